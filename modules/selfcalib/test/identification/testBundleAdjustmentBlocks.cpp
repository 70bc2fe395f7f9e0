/*
 * ViSP SelfCalib: the kinematic bundle adjustment's estimated-set decision and its covariance see
 * the same problem: the information of the corrections the decision walks is the inverse of the
 * covariance the adjustment reports at the same state (every robot-error correction eliminated in
 * both), in the hand-eye mode (controller pose corrections) and the full mode (joint and
 * model-residual corrections).
 */
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <memory>
#include <vector>

#include <Eigen/Dense>

#include <visp3/selfcalib/vpKinematicBundleAdjustment.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "../testCommon.h"
#include "identification/vpKinematicBundleAdjustmentProblem.h"

using namespace selfcalib_test;
using KBA = vpKinematicBundleAdjustment;

namespace
{
/*
  The decision's information of the corrections (vpKinematicBundle::correctionInformation) for the
  simulator's true state, built as the adjustment builds it: the views' joints or controller poses,
  the true points, the rule's set, a robot-error correction per view when `robot_error`.
*/
Eigen::MatrixXd decisionInformation(const vpSelfCalibSimulator &sim, const vpSelfCalibDataset &ds, const KBA::Options &o,
                                    const vpSelfCalibNoiseModel &noise, bool robot_error)
{
  using namespace vpKinematicBundle;
  const vpKinematicChain &start = sim.getTrueChain();
  std::vector<vpColVector> q;
  std::vector<vpSelfCalib::Rigid> fMe;
  std::map<int, unsigned int> seen;
  collectViews(start, ds.views, o, q, fMe, seen);
  const std::map<int, Eigen::Vector3d> X0 = startPoints(sim.getScenePointsById(), seen);
  const vpKinematicIdentification::Identifiability set = estimatedSet(start, q, o);
  std::vector<double> sd;
  if (robot_error && !o.hand_eye_only) {
    sd.assign(start.getNumJoints(), noise.joint_sd[0]);
    for (int i = 0; i < 6; ++i)
      sd.push_back(i < 3 ? noise.model_sd_translation : noise.model_sd_rotation);
  }
  Adjustment a(X0, start, set.identified, q, fMe, robot_error && o.hand_eye_only, sd,
               robot_error && !o.hand_eye_only ? static_cast<int>(start.getNumJoints()) : 0,
               robot_error && !o.hand_eye_only);
  a.noise = noise;
  a.P = static_cast<int>(set.identified.size());
  for (unsigned int k = 0; k < ds.views.size(); ++k)
    for (const auto &ob : ds.views[k].points)
      if (a.X.count(ob.id))
        a.obs.push_back({k, ob.id, ob.ip.get_u(), ob.ip.get_v()});
  a.state.model = lensModel(o);
  a.free_in = estimatedIntrinsics(sim.getCamera(), o, a.in);
  if (!a.free_in.empty() && a.free_in.size() < kIntrinsics) { // the other intrinsics held, as the adjustment holds them
    std::vector<int> constant;
    for (int i = 0; i < kIntrinsics; ++i)
      if (std::find(a.free_in.begin(), a.free_in.end(), i) == a.free_in.end())
        constant.push_back(i);
    a.subset.reset(new ceres::SubsetManifold(kIntrinsics, constant));
  }
  a.state.update(true);
  a.rho0 = a.state.rho;
  a.has_yardstick = ds.yardstick.isSet() && a.X.count(ds.yardstick.id_a) && a.X.count(ds.yardstick.id_b);
  a.keepVisible();
  std::shared_ptr<ceres::ParameterBlockOrdering> order;
  KBA::ScaleSource source;
  const std::unique_ptr<ceres::Problem> problem = buildProblem(a, ds.yardstick, o, 0, order, source, false);
  if (!problem)
    return Eigen::MatrixXd();
  return correctionInformation(a, *problem, ds.yardstick);
}

//! The corrections' block of the covariance information() reports at the true state.
Eigen::MatrixXd reportedCovariance(const vpSelfCalibSimulator &sim, const vpSelfCalibDataset &ds, const KBA::Options &o,
                                   const vpSelfCalibNoiseModel &noise, unsigned int &P)
{
  const KBA::Result r = KBA::information(sim.getTrueChain(), sim.getCamera(), ds.views, ds.yardstick,
                                         sim.getScenePointsById(), o, noise);
  P = static_cast<unsigned int>(r.identifiability.identified.size());
  Eigen::MatrixXd C(P, P);
  for (unsigned int i = 0; i < P; ++i)
    for (unsigned int j = 0; j < P; ++j)
      C(i, j) = r.covariance[i][j];
  return C;
}

//! max |A - B| / max |B|.
double relativeDifference(const Eigen::MatrixXd &A, const Eigen::MatrixXd &B)
{
  return (A - B).cwiseAbs().maxCoeff() / B.cwiseAbs().maxCoeff();
}
} // namespace

/*
  Hand-eye mode with the controller poses' error (a 6-D correction per view): the decision's
  information is the inverse of the reported covariance. Holding the pose corrections instead of
  eliminating them (the listing without them) overstates the information: its inverse is well
  below the reported covariance.
*/
TEST(KinematicBundleAdjustmentBlocks, TheSetDecisionEliminatesThePoseCorrections)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 61, 0.2);
  vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(12));
  toControllerPoses(sim, ds, 0, 0, 61, 98);
  KBA::Options o;
  o.hand_eye_only = true;
  o.intrinsics = 0;
  vpSelfCalibNoiseModel noise;
  noise.pose_sd_translation = noise.pose_sd_rotation = 1e-3;
  unsigned int P = 0;
  const Eigen::MatrixXd C = reportedCovariance(sim, ds, o, noise, P);
  ASSERT_EQ(P, 6u);
  const Eigen::MatrixXd M = decisionInformation(sim, ds, o, noise, true);
  ASSERT_EQ(M.rows(), 6);
  EXPECT_LT(relativeDifference(M.inverse(), C), 1e-6);
  const Eigen::MatrixXd held = decisionInformation(sim, ds, o, noise, false);
  ASSERT_EQ(held.rows(), 6);
  EXPECT_LT(held.inverse().trace(), 0.5 * C.trace());
}

/*
  Full kinematic mode with the joint readings' error and the model's residual (a joint and a 6-D
  camera correction per view), f estimated, the yardstick's scale: the decision's information is the
  inverse of the corrections' block of the reported covariance; without the corrections it is larger.
*/
TEST(KinematicBundleAdjustmentBlocks, TheSetDecisionEliminatesTheJointAndModelCorrections)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 62, 0.2);
  const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(15));
  KBA::Options o;
  o.set_from_information = false; // the rule's set in both
  o.kinematic_prior = KBA::KINEMATIC_PRIOR_OFF; // the decision's information is the data's alone
  vpSelfCalibNoiseModel noise;
  noise.joint_sd = {3e-4};
  noise.model_sd_translation = noise.model_sd_rotation = 2e-4;
  unsigned int P = 0;
  const Eigen::MatrixXd C = reportedCovariance(sim, ds, o, noise, P);
  ASSERT_GT(P, 6u);
  const Eigen::MatrixXd M = decisionInformation(sim, ds, o, noise, true);
  ASSERT_EQ(M.rows(), static_cast<Eigen::Index>(P));
  EXPECT_LT(relativeDifference(M.inverse(), C), 1e-5);
  const Eigen::MatrixXd held = decisionInformation(sim, ds, o, noise, false);
  ASSERT_EQ(held.rows(), static_cast<Eigen::Index>(P));
  EXPECT_LT(held.inverse().trace(), 0.9 * C.trace());
}
