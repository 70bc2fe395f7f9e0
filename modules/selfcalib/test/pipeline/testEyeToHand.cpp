/*
 * Tests of the eye-to-hand set-up (camera fixed in the world, target on the tool): exact recovery of
 * bMc and eMo on noise-free data, honest sd with the controller poses' error, the inverted pose
 * correction's Jacobian against finite differences, and the refusal of the other methods.
 */
#include <gtest/gtest.h>

#include <cmath>

#include <visp3/selfcalib/vpKinematicBundleAdjustment.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "core/vpSelfCalibRandom.h"
#include "identification/vpKinematicBundleAdjustmentCosts.h"
#include "../testCommon.h"

namespace
{
using RSC = vpRobotSelfCalibration;
using selfcalib_test::poseError;

RSC::Result calibrate(const vpSelfCalibDataset &ds, const std::map<int, vpColVector> &layout, double pixel_sd,
                      bool tight = false)
{
  RSC::Options o;
  o.method = RSC::HAND_EYE;
  o.bundle.known_points = layout;
  o.bundle.tight = tight;
  o.noise.pixel_sd = pixel_sd;
  return RSC::run(vpKinematicChain::preset("viper850"), ds, o);
}

} // namespace

TEST(EyeToHand, NoiseFreeBoardIsRecoveredExactly)
{
  vpSelfCalibSimulator::EyeToHandOptions so;
  so.pixel_noise_sd = 0;
  vpSelfCalibSimulator::EyeToHandTruth truth;
  const vpSelfCalibDataset ds = vpSelfCalibSimulator::simulateEyeToHand(so, truth);
  const RSC::Result r = calibrate(ds, truth.layout, 0.2, true);
  ASSERT_EQ(r.status, RSC::OK) << r.message;
  ASSERT_TRUE(r.has_bMc);
  ASSERT_TRUE(r.has_eMo);
  EXPECT_FALSE(r.has_eMc);
  EXPECT_EQ(r.camera_mount, vpSelfCalibDataset::CAMERA_IN_WORLD);
  const vpColVector eb = poseError(r.bMc, truth.bMc), eo = poseError(r.eMo, truth.eMo);
  for (unsigned int i = 0; i < 6; ++i) {
    EXPECT_LT(std::fabs(eb[i]), 1e-7) << "bMc axis " << i;
    EXPECT_LT(std::fabs(eo[i]), 1e-7) << "eMo axis " << i;
  }
  // The calibrated model's hand-eye slot is bMc, and the model says so (its file: camera_mount:
  // world, key bMc); it reads back as the same bMc.
  EXPECT_TRUE(r.calibrated.isCameraInWorld());
  const vpKinematicChain back = vpKinematicChain::fromYamlString(r.calibrated.toYamlString());
  EXPECT_TRUE(back.isCameraInWorld());
  const vpColVector eback = poseError(vpPoseVector(back.get_eMc_corrected()), truth.bMc);
  for (unsigned int i = 0; i < 6; ++i)
    EXPECT_LT(std::fabs(eback[i]), 1e-7) << "model file's bMc axis " << i;
}

// A model whose camera is fixed in the world (its hand-eye slot bMc) on a dataset whose camera is
// on the end-effector: refused, so that a bMc is never calibrated as an eMc.
TEST(EyeToHand, CameraInWorldModelOnEyeInHandDataIsRefused)
{
  vpSelfCalibSimulator::EyeToHandOptions so;
  so.robot = "viper850";
  vpSelfCalibSimulator::EyeToHandTruth truth;
  vpSelfCalibDataset ds = vpSelfCalibSimulator::simulateEyeToHand(so, truth);
  ds.camera_mount = vpSelfCalibDataset::CAMERA_ON_EFFECTOR;
  vpKinematicChain model = vpKinematicChain::preset("viper850");
  model.setCameraInWorld(true);
  RSC::Options o;
  o.method = RSC::HAND_EYE;
  try {
    RSC::run(model, ds, o);
    ADD_FAILURE() << "a camera-in-the-world model ran on an eye-in-hand dataset";
  } catch (const vpSelfCalibException &e) {
    EXPECT_NE(e.getStringMessage().find("has the camera fixed in the world (camera_mount: world, its hand-eye slot is "
                                        "bMc) and the dataset has it on the end-effector"),
              std::string::npos)
        << e.getStringMessage();
  }
}

// With 2 mm / 2 mrad of controller pose error and 0.2 px: the errors stay within 3.5 reported sd on
// every axis, for bMc and eMo, over 4 seeds (the full statistics are bench-eye-to-hand's).
TEST(EyeToHand, PoseErrorIsModelledAndSdAreHonest)
{
  for (unsigned int seed = 1; seed <= 4; ++seed) {
    vpSelfCalibSimulator::EyeToHandOptions so;
    so.seed = seed;
    so.pose_sd_translation = 0.002;
    so.pose_sd_rotation = 0.002;
    vpSelfCalibSimulator::EyeToHandTruth truth;
    const vpSelfCalibDataset ds = vpSelfCalibSimulator::simulateEyeToHand(so, truth);
    const RSC::Result r = calibrate(ds, truth.layout, 0.2);
    ASSERT_TRUE(r.status == RSC::OK || r.status == RSC::DOUBTFUL) << r.message;
    ASSERT_TRUE(r.has_bMc && r.has_eMo);
    EXPECT_GT(r.noise.pose_sd_translation, 0);
    const vpColVector eb = poseError(r.bMc, truth.bMc), eo = poseError(r.eMo, truth.eMo);
    for (unsigned int i = 0; i < 6; ++i) {
      EXPECT_GT(r.bMc_sd[i], 0);
      EXPECT_LT(std::fabs(eb[i]), 3.5 * r.bMc_sd[i]) << "seed " << seed << " bMc axis " << i;
      EXPECT_LT(std::fabs(eo[i]), 3.5 * r.eMo_sd[i]) << "seed " << seed << " eMo axis " << i;
    }
  }
}

/*
  Residuals below the image noise a measurement is believed at (0.01 px: rendered corners, exact
  data) do not shrink the covariance: on noise-free data with 0.2 px stated, the reported sd of bMc
  and eMo are those of 0.2 px, the Cramér-Rao bound of the same views at the truth
  (vpKinematicBundleAdjustment::information), not sigma0 (about 1e-9 here) times them. They were
  scaled by sigma0^2, and rendered ChArUco corners (0.006 px of residuals, sigma0 0.03) put bMc 4-5
  of those sd off the truth.
*/
TEST(EyeToHand, ResidualsBelowTheNoiseFloorShrinkTheSdToTheFloorOnly)
{
  for (unsigned int seed = 1; seed <= 2; ++seed) {
    vpSelfCalibSimulator::EyeToHandOptions so;
    so.seed = seed;
    so.pixel_noise_sd = 0;
    vpSelfCalibSimulator::EyeToHandTruth truth;
    const vpSelfCalibDataset ds = vpSelfCalibSimulator::simulateEyeToHand(so, truth);
    const RSC::Result r = calibrate(ds, truth.layout, 0.2, true);
    ASSERT_EQ(r.status, RSC::OK) << r.message;
    ASSERT_TRUE(r.has_bMc && r.has_eMo);
    EXPECT_LT(r.bundle.sigma0, 1e-3) << "seed " << seed;
    EXPECT_TRUE(r.bundle.covariance_scaled) << "seed " << seed;
    // The bound at the stated 0.2 px scaled to the floor's noise (0.01 px: residuals below it do not
    // measure the observations' error), not below: the hand-eye problem on the inverted controller
    // poses at the estimate (the truth),
    // bMc in the hand-eye slot as the run's model holds it: the sd of its corrections compared.
    vpKinematicChain chain = r.calibrated;
    chain.setCameraInWorld(false);
    vpSelfCalibDataset inverted = ds;
    std::map<int, vpColVector> points;
    for (auto &v : inverted.views)
      v.fMe = v.fMe.inverse();
    for (const auto &l : truth.layout) {
      const vpColVector X = truth.eMo * vpColVector({l.second[0], l.second[1], l.second[2], 1.0});
      points[l.first] = vpColVector({X[0], X[1], X[2]});
    }
    vpKinematicBundleAdjustment::Options ko;
    ko.hand_eye_only = true;
    ko.controller_poses_inverted = true;
    ko.known_points = truth.layout;
    ko.intrinsics = 0;
    vpSelfCalibNoiseModel noise;
    noise.pixel_sd = 0.2;
    const vpKinematicBundleAdjustment::Result b = vpKinematicBundleAdjustment::information(
        chain, ds.cam, inverted.views, vpSelfCalibDataset::Yardstick(), points, ko, noise);
    ASSERT_TRUE(b.has_covariance && b.has_object);
    const unsigned int first = chain.getNumParameters() - vpKinematicChain::kBlockSize;
    for (unsigned int i = 0; i < 6; ++i) {
      const double floor = 0.01 / 0.2;
      EXPECT_NEAR(r.bundle.sd[first + i] / b.sd[first + i] / floor, 1.0, 0.05) << "seed " << seed << " bMc axis " << i;
      EXPECT_NEAR(r.eMo_sd[i] / b.object_sd[i] / floor, 1.0, 0.05) << "seed " << seed << " eMo axis " << i;
    }
  }
}

namespace
{
std::map<int, vpColVector> scaled(const std::map<int, vpColVector> &layout, double k)
{
  std::map<int, vpColVector> out;
  for (const auto &e : layout)
    out[e.first] = k * e.second;
  return out;
}

bool hasFinding(const RSC::Result &r, const std::string &code)
{
  for (const auto &f : r.findings)
    if (f.code == code)
      return true;
  return false;
}
} // namespace

// The board declared at its size: the layout's scale measured 1; declared 25 % too large: measured
// 0.8 (the true size over the declared one), exactly on noise-free data, and the run is doubtful.
TEST(EyeToHand, NoiseFreeBoardSizeIsMeasured)
{
  vpSelfCalibSimulator::EyeToHandOptions so;
  so.pixel_noise_sd = 0;
  vpSelfCalibSimulator::EyeToHandTruth truth;
  const vpSelfCalibDataset ds = vpSelfCalibSimulator::simulateEyeToHand(so, truth);
  const RSC::Result right = calibrate(ds, truth.layout, 0.2, true);
  ASSERT_EQ(right.status, RSC::OK) << right.message;
  ASSERT_TRUE(right.bundle.has_layout_scale);
  EXPECT_NEAR(right.bundle.layout_scale, 1.0, 1e-7);
  EXPECT_FALSE(hasFinding(right, "board-size-mismatch"));
  const RSC::Result wrong = calibrate(ds, scaled(truth.layout, 1.25), 0.2);
  ASSERT_TRUE(wrong.bundle.has_layout_scale) << wrong.message;
  EXPECT_NEAR(wrong.bundle.layout_scale, 0.8, 1e-6);
  EXPECT_EQ(wrong.status, RSC::DOUBTFUL) << wrong.message;
  EXPECT_TRUE(hasFinding(wrong, "board-size-mismatch")) << wrong.message;
}

// 2 mm / 2 mrad of pose error, 0.2 px, 4 seeds: the right size measured within 3.5 sd of 1 and not
// doubted; 20 % too small a declared size doubted on every seed, the measure within 3.5 sd of 1.25.
TEST(EyeToHand, BoardSizeDoubtHoldsOverSeeds)
{
  for (unsigned int seed = 1; seed <= 4; ++seed) {
    vpSelfCalibSimulator::EyeToHandOptions so;
    so.seed = seed;
    so.pose_sd_translation = 0.002;
    so.pose_sd_rotation = 0.002;
    vpSelfCalibSimulator::EyeToHandTruth truth;
    const vpSelfCalibDataset ds = vpSelfCalibSimulator::simulateEyeToHand(so, truth);
    const RSC::Result right = calibrate(ds, truth.layout, 0.2);
    ASSERT_TRUE(right.bundle.has_layout_scale) << right.message;
    EXPECT_LT(std::fabs(right.bundle.layout_scale - 1), 3.5 * right.bundle.layout_scale_sd) << "seed " << seed;
    EXPECT_FALSE(hasFinding(right, "board-size-mismatch")) << "seed " << seed << ": " << right.message;
    const RSC::Result wrong = calibrate(ds, scaled(truth.layout, 0.8), 0.2);
    ASSERT_TRUE(wrong.bundle.has_layout_scale) << wrong.message;
    EXPECT_LT(std::fabs(wrong.bundle.layout_scale - 1.25), 3.5 * wrong.bundle.layout_scale_sd) << "seed " << seed;
    EXPECT_TRUE(hasFinding(wrong, "board-size-mismatch")) << "seed " << seed << ": " << wrong.message;
  }
}

// The scaled layout residual: at s = 1 the plain one, and its s derivative (automatic) against a
// central difference.
TEST(EyeToHand, ScaledKnownPointCostMatchesAndItsScaleDerivativeIsRight)
{
  const vpColVector L({0.03, -0.02, 0.001});
  const double o[6] = {0.1, -0.2, 0.5, 0.3, -0.1, 0.2}, X[3] = {0.12, -0.25, 0.49};
  double r0[3], r1[3], rp[3], rm[3];
  const double one = 1, s = 0.9, h = 1e-6, sp = s + h, sm = s - h;
  vpKinematicBundle::KnownPointCost(L, 1e-3)(o, X, r0);
  vpKinematicBundle::ScaledKnownPointCost(L, 1e-3)(o, &one, X, r1);
  for (int i = 0; i < 3; ++i)
    EXPECT_DOUBLE_EQ(r0[i], r1[i]);
  ceres::AutoDiffCostFunction<vpKinematicBundle::ScaledKnownPointCost, 3, 6, 1, 3> f(
      new vpKinematicBundle::ScaledKnownPointCost(L, 1e-3));
  const double *params[3] = {o, &s, X};
  double r[3], J0[18], J1[3], J2[9];
  double *J[3] = {J0, J1, J2};
  ASSERT_TRUE(f.Evaluate(params, r, J));
  vpKinematicBundle::ScaledKnownPointCost(L, 1e-3)(o, &sp, X, rp);
  vpKinematicBundle::ScaledKnownPointCost(L, 1e-3)(o, &sm, X, rm);
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(J1[i], (rp[i] - rm[i]) / (2 * h), 1e-6 * (1 + std::fabs(J1[i])));
}

// The paper's method needs a moving camera; the bundle method needs the target's layout.
TEST(EyeToHand, PaperAndBundleWithoutLayoutAreRefused)
{
  vpSelfCalibSimulator::EyeToHandOptions so;
  so.robot = "viper850";
  vpSelfCalibSimulator::EyeToHandTruth truth;
  const vpSelfCalibDataset ds = vpSelfCalibSimulator::simulateEyeToHand(so, truth);
  const std::pair<RSC::Method, std::string> cases[] = {
      {RSC::PAPER, "camera_mount: world is calibrated with --method bundle or hand-eye; the paper method measures"},
      {RSC::BUNDLE_ADJUSTMENT, "camera_mount: world with the bundle method needs the layout of the target on the tool"}};
  for (const auto &c : cases) {
    RSC::Options o;
    o.method = c.first;
    try {
      RSC::run(vpKinematicChain::preset("viper850"), ds, o);
      ADD_FAILURE() << "method " << RSC::methodName(c.first) << " ran on camera_mount world";
    } catch (const vpSelfCalibException &e) {
      EXPECT_NE(e.getStringMessage().find(c.second), std::string::npos) << e.getStringMessage();
    }
  }
}

// The view of E(delta)^-1 fMe and its derivatives with respect to delta against central differences
// of the camera pose (origin, and the rotation as a left perturbation).
TEST(EyeToHand, InvertedPoseCorrectionJacobian)
{
  using namespace vpKinematicBundle;
  vpKinematicChain chain = vpKinematicChain::preset("viper850");
  chain.set_eMc(vpPoseVector(0.9, -0.1, 0.5, 1.1, -1.0, 0.4));
  const Rigid G = rigidFromVisp(vpHomogeneousMatrix(vpPoseVector(-0.2, 0.3, 0.6, 0.4, 0.2, -0.9)));
  const double delta[6] = {0.003, -0.002, 0.001, 0.01, -0.02, 0.015};
  ViewState v;
  computeInvertedPoseNoiseView(chain, {}, G, delta, true, v);
  // Ad = R^T dp/ddelta, Cd = R^T dphi/ddelta: compare R Ad and R Cd with differences.
  const Eigen::Matrix3d R = v.RT.transpose();
  const double h = 1e-6;
  for (int i = 0; i < 6; ++i) {
    double a[6], b[6];
    std::copy(delta, delta + 6, a);
    std::copy(delta, delta + 6, b);
    a[i] += h;
    b[i] -= h;
    ViewState va, vb;
    computeInvertedPoseNoiseView(chain, {}, G, a, false, va);
    computeInvertedPoseNoiseView(chain, {}, G, b, false, vb);
    const Eigen::Vector3d dp = (va.tf - vb.tf) / (2 * h);
    const Eigen::Matrix3d dR = va.RT.transpose() * vb.RT; // exp([dphi]x) to first order
    const Eigen::Vector3d dphi = Eigen::Vector3d(dR(2, 1) - dR(1, 2), dR(0, 2) - dR(2, 0), dR(1, 0) - dR(0, 1)) / (4 * h);
    EXPECT_LT((R * v.Ad.col(i) - dp).norm(), 1e-6) << "column " << i;
    EXPECT_LT((R * v.Cd.col(i) - dphi).norm(), 1e-6) << "column " << i;
  }
}

// A target that stays still in the images while the end-effector moves is not on the tool: the
// data check refuses it (DEGENERATE_DATA, target-does-not-move).
TEST(EyeToHand, TargetThatDoesNotMoveIsRefused)
{
  vpSelfCalibSimulator::EyeToHandOptions so;
  vpSelfCalibSimulator::EyeToHandTruth truth;
  vpSelfCalibDataset ds = vpSelfCalibSimulator::simulateEyeToHand(so, truth);
  for (size_t k = 1; k < ds.views.size(); ++k)
    ds.views[k].points = ds.views[0].points;
  const RSC::Result r = calibrate(ds, truth.layout, 0.2);
  EXPECT_EQ(r.status, RSC::DEGENERATE_DATA) << r.message;
  bool found = false;
  for (const auto &f : r.findings)
    found = found || f.code == "target-does-not-move";
  EXPECT_TRUE(found);
}

namespace
{
// The camera pose of the eye-to-hand view (fMe(q)^-1 bMc) and its derivatives against central
// differences: the chain's corrections (every block), then the joint corrections.
void expectEyeToHandColumns(const vpKinematicChain &chain, const vpColVector &q)
{
  using namespace vpKinematicBundle;
  std::vector<unsigned int> id(chain.getNumParameters());
  for (unsigned int i = 0; i < id.size(); ++i)
    id[i] = i;
  const unsigned int n = chain.getNumJoints();
  const std::vector<double> dq0(n, 0.01);
  ViewState v, w;
  computeEyeToHandView(chain, id, q, true, v);
  computeNoisyView(chain, id, q, dq0.data(), static_cast<int>(n), false, true, w, true);
  const double h = 1e-6;
  auto expectColumn = [&](const ViewState &a, const ViewState &b, const Eigen::Matrix3d &R, const Eigen::Vector3d &jt,
                          const Eigen::Vector3d &jr, const std::string &what) {
    const Eigen::Vector3d dp = (a.tf - b.tf) / (2 * h);
    const Eigen::Matrix3d dR = a.RT.transpose() * b.RT;
    const Eigen::Vector3d dphi = Eigen::Vector3d(dR(2, 1) - dR(1, 2), dR(0, 2) - dR(2, 0), dR(1, 0) - dR(0, 1)) / (4 * h);
    EXPECT_LT((R * jt - dp).norm(), 1e-6 * std::max(1.0, dp.norm())) << what;
    EXPECT_LT((R * jr - dphi).norm(), 1e-6 * std::max(1.0, dphi.norm())) << what;
  };
  for (unsigned int i = 0; i < id.size(); ++i) {
    vpKinematicChain a = chain, b = chain;
    vpColVector pa = chain.getParameters(), pb = pa;
    pa[i] += h;
    pb[i] -= h;
    a.setParameters(pa);
    b.setParameters(pb);
    ViewState va, vb;
    computeEyeToHandView(a, id, q, false, va);
    computeEyeToHandView(b, id, q, false, vb);
    expectColumn(va, vb, v.RT.transpose(), v.A.col(i), v.C.col(i), chain.getParameterNames()[i]);
  }
  for (unsigned int j = 0; j < n; ++j) {
    std::vector<double> a = dq0, b = dq0;
    a[j] += h;
    b[j] -= h;
    ViewState va, vb;
    computeNoisyView(chain, id, q, a.data(), static_cast<int>(n), false, false, va, true);
    computeNoisyView(chain, id, q, b.data(), static_cast<int>(n), false, false, vb, true);
    expectColumn(va, vb, w.RT.transpose(), w.Ad.col(j), w.Cd.col(j), "joint " + std::to_string(j + 1));
  }
}
} // namespace

TEST(EyeToHandBundle, ViewJacobianMatchesFiniteDifferences)
{
  for (const std::string robot : {"ur5", "panda"}) {
    vpKinematicChain chain = vpKinematicChain::preset(robot);
    chain.set_eMc(vpPoseVector(0.9, -0.1, 0.5, 1.1, -1.0, 0.4)); // the hand-eye slot holds bMc
    vpColVector p(chain.getNumParameters());
    for (unsigned int i = 0; i < p.size(); ++i)
      p[i] = 0.003 * std::sin(1.7 * i + 0.3);
    chain.setParameters(p);
    vpColVector q(chain.getNumJoints());
    for (unsigned int j = 0; j < q.size(); ++j)
      q[j] = 0.5 * (chain.getJointMin()[j] + chain.getJointMax()[j]) + 0.3 * std::cos(2.1 * j);
    SCOPED_TRACE(robot);
    expectEyeToHandColumns(chain, q);
  }
}

namespace
{
vpSelfCalibDataset::View projectView(const vpKinematicChain &chain, const vpHomogeneousMatrix &bMc,
                                     const vpHomogeneousMatrix &eMo, const std::map<int, vpColVector> &layout,
                                     const vpCameraParameters &cam, const vpColVector &q)
{
  const vpHomogeneousMatrix cMo = bMc.inverse() * chain.get_fMe(q) * eMo;
  vpSelfCalibDataset::View v;
  v.q = q;
  for (const auto &l : layout) {
    vpColVector X = cMo * vpColVector({l.second[0], l.second[1], l.second[2], 1.0});
    v.points.push_back({l.first, vpImagePoint(cam.get_v0() + cam.get_py() * X[1] / X[2],
                                              cam.get_u0() + cam.get_px() * X[0] / X[2])});
  }
  return v;
}

RSC::Result calibrateBundle(const vpSelfCalibDataset &ds, const std::string &robot,
                            const std::map<int, vpColVector> &layout, bool tight)
{
  RSC::Options o;
  o.method = RSC::BUNDLE_ADJUSTMENT;
  o.bundle.known_points = layout;
  o.bundle.tight = tight;
  if (tight) // noise-free exact recovery: without the kinematic prior, whose pull toward nominal is not exact
    o.bundle.kinematic_prior = vpKinematicBundleAdjustment::KINEMATIC_PRIOR_OFF;
  o.noise.pixel_sd = 0.2;
  return RSC::run(vpKinematicChain::preset(robot), ds, o);
}
} // namespace

/*
  Noise-free joints and pixels, a 6-axis and a 7-axis arm carrying a board, a fixed 1280 x 720
  camera. (1) With the true robot's errors everywhere, the calibrated model predicts the target's
  image pose cMo = bMc^-1 fMe(q) eMo of new configurations exactly (what is left out is the same
  as a change of bMc or eMo). (2) With the truth's errors only on the parameters estimated, bMc, eMo
  and every estimated correction are the truth's, and the others stay nominal.
*/
TEST(EyeToHandBundle, NoiseFreeExactRecoveryOfBmcEmoAndTheChain)
{
  for (const std::string robot : {"ur5", "panda"}) {
    SCOPED_TRACE(robot);
    vpSelfCalibSimulator::EyeToHandOptions so = vpSelfCalibSimulator::eyeToHandHd();
    so.robot = robot;
    so.num_views = 20;
    so.board_cols = 8;
    so.board_rows = 6;
    so.pixel_noise_sd = 0;
    so.joint_spread = 0.5;
    vpSelfCalibSimulator::EyeToHandTruth truth;
    vpSelfCalibDataset ds = vpSelfCalibSimulator::simulateEyeToHand(so, truth);
    for (auto &v : ds.views)
      v.has_fMe = false;
    RSC::Result r = calibrateBundle(ds, robot, truth.layout, true);
    ASSERT_EQ(r.status, RSC::OK) << r.message;
    ASSERT_TRUE(r.has_bMc && r.has_eMo);
    EXPECT_EQ(r.bundle.scale_source, vpKinematicBundleAdjustment::SCALE_KNOWN_POINTS);
    EXPECT_GE(r.identifiability.identified.size(), 20u);
    // (1) New configurations.
    const vpHomogeneousMatrix bMc(r.bMc), eMo(r.eMo);
    vpSelfCalib::Random rng(7, 1);
    for (int k = 0; k < 10; ++k) {
      vpColVector q = truth.q[0];
      for (unsigned int j = 0; j < q.size(); ++j)
        q[j] += rng.uniform(-0.4, 0.4);
      const vpHomogeneousMatrix t = bMc.inverse() * r.calibrated.get_fMe(q) * eMo;
      const vpHomogeneousMatrix u = truth.bMc.inverse() * truth.chain.get_fMe(q) * truth.eMo;
      const vpColVector e = poseError(vpPoseVector(t), u);
      for (unsigned int i = 0; i < 6; ++i)
        EXPECT_LT(std::fabs(e[i]), 1e-7) << "configuration " << k << " axis " << i;
    }
    // (2) The truth restricted to the estimated set, the same configurations.
    vpKinematicChain restricted = truth.chain;
    vpColVector p(restricted.getNumParameters(), 0.0);
    for (unsigned int i : r.identifiability.identified)
      if (i + vpKinematicChain::kBlockSize < p.size()) // the hand-eye slot is bMc here
        p[i] = truth.chain.getParameters()[i];
    restricted.setParameters(p);
    for (size_t k = 0; k < ds.views.size(); ++k)
      ds.views[k] = projectView(restricted, truth.bMc, truth.eMo, truth.layout, ds.cam, truth.q[k]);
    r = calibrateBundle(ds, robot, truth.layout, true);
    ASSERT_EQ(r.status, RSC::OK) << r.message;
    const vpColVector eb = poseError(r.bMc, truth.bMc), eo = poseError(r.eMo, truth.eMo);
    for (unsigned int i = 0; i < 6; ++i) {
      EXPECT_LT(std::fabs(eb[i]), 1e-7) << "bMc axis " << i;
      EXPECT_LT(std::fabs(eo[i]), 1e-7) << "eMo axis " << i;
    }
    const vpColVector est = r.calibrated.getParameters();
    for (unsigned int i = 0; i + vpKinematicChain::kBlockSize < p.size(); ++i)
      EXPECT_NEAR(est[i], p[i], 1e-8) << restricted.getParameterNames()[i];
  }
}

// The rule's reasons in this set-up: the base and joint 1's placement go with bMc, the last joint's
// offset with the target's pose eMo.
TEST(EyeToHandBundle, LeftOutParametersSayWhyInThisSetUp)
{
  vpSelfCalibSimulator::EyeToHandOptions so;
  so.robot = "ur5";
  so.num_views = 15;
  so.pixel_noise_sd = 0;
  vpSelfCalibSimulator::EyeToHandTruth truth;
  const vpSelfCalibDataset ds = vpSelfCalibSimulator::simulateEyeToHand(so, truth);
  const RSC::Result r = calibrateBundle(ds, "ur5", truth.layout, false);
  ASSERT_TRUE(r.status == RSC::OK || r.status == RSC::DOUBTFUL) << r.message;
  std::map<std::string, std::string> why;
  for (const auto &u : r.identifiability.unidentifiable)
    why[u.name] = u.reason;
  ASSERT_TRUE(why.count("base.tx") && why.count("j1.rz") && why.count("j6.rz"));
  EXPECT_NE(why["base.tx"].find("a change of bMc"), std::string::npos) << why["base.tx"];
  EXPECT_NE(why["j1.rz"].find("a change of bMc"), std::string::npos) << why["j1.rz"];
  EXPECT_NE(why["j6.rz"].find("eMo."), std::string::npos) << why["j6.rz"];
}
