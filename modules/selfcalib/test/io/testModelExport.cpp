/*
 * Tests of vpModelExport: the URDF reproduces the model exactly; a DH table is fitted when one exists
 * and the fit says so when it does not.
 */
#include <gtest/gtest.h>

#include <cmath>
#include <regex>

#include <visp3/core/vpRotationMatrix.h>
#include <visp3/core/vpRxyzVector.h>
#include <visp3/selfcalib/vpDHTableFit.h>
#include <visp3/selfcalib/vpKinematicIdentification.h>
#include <visp3/selfcalib/vpModelExport.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "../testCommon.h"
#include "core/vpSelfCalibMath.h"
#include "core/vpSelfCalibRandom.h"

using namespace selfcalib_test;

using namespace vpSelfCalib;

namespace
{
// The origins of the URDF's joints, in order, as transforms (xyz, rpy with R = Rz(y) Ry(p) Rx(r)).
std::vector<vpHomogeneousMatrix> origins(const std::string &urdf)
{
  std::vector<vpHomogeneousMatrix> out;
  const std::regex re("<origin xyz=\"([^ ]+) ([^ ]+) ([^\"]+)\" rpy=\"([^ ]+) ([^ ]+) ([^\"]+)\"/>");
  for (auto it = std::sregex_iterator(urdf.begin(), urdf.end(), re); it != std::sregex_iterator(); ++it) {
    double v[6];
    for (int k = 0; k < 6; ++k)
      v[k] = std::stod((*it)[k + 1]);
    const Eigen::Matrix3d R = (Eigen::AngleAxisd(v[5], Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(v[4], Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(v[3], Eigen::Vector3d::UnitX()))
                                  .toRotationMatrix();
    Rigid T;
    T.R = R;
    T.t = Eigen::Vector3d(v[0], v[1], v[2]);
    out.push_back(toVisp(T));
  }
  return out;
}
} // namespace

// Composing the URDF's origins with the joint rotations gives the model's fMc, corrections included.
TEST(ModelExport, UrdfReproducesTheModel)
{
  for (const std::string robot : {"puma560", "viper850"}) {
    const vpSelfCalibSimulator sim = makeSim(robot, 81);
    const vpKinematicChain &model = sim.getTrueChain();
    const std::string urdf = vpModelExport::toURDF(model, "test");
    EXPECT_NE(urdf.find("<robot name=\"test\">"), std::string::npos);
    const std::vector<vpHomogeneousMatrix> O = origins(urdf);
    ASSERT_EQ(O.size(), model.getNumJoints() + 2);
    Random rng(81, 2);
    for (int s = 0; s < 5; ++s) {
      vpColVector q(model.getNumJoints());
      for (unsigned int i = 0; i < q.size(); ++i)
        q[i] = rng.uniform(model.getJoints()[i].min, model.getJoints()[i].max);
      vpHomogeneousMatrix T;
      for (unsigned int i = 0; i < q.size(); ++i)
        T = T * O[i] * vpHomogeneousMatrix(0, 0, 0, 0, 0, q[i]);
      T = T * O[q.size()] * O[q.size() + 1];
      EXPECT_LT(translationDistance(T, model.get_fMc(q)), 1e-12) << robot;
      EXPECT_LT(rotationDistance(T, model.get_fMc(q)), 1e-12) << robot;
    }
  }
}

// A model whose errors are DH errors (a, d, twists, offsets, base, tool), given as identified 6-D
// corrections: the fitted DH table reproduces it and is declared representable.
TEST(ModelExport, DhTableOfADhRepresentableModel)
{
  const vpKinematicChain nominal = vpKinematicChain::preset("puma560");
  std::vector<vpKinematicChain::Joint> rows = nominal.getJoints();
  Random rng(82, 1);
  for (size_t i = 0; i < rows.size(); ++i) {
    rows[i].a += rng.normal(1e-3);
    rows[i].d += rng.normal(1e-3);
    rows[i].theta_offset += rng.normal(2e-3);
    if (i != 1) // joints 2 and 3 stay parallel: a DH table exists
      rows[i].alpha += rng.normal(2e-3);
  }
  const vpKinematicChain truth("puma560", vpKinematicChain::DH, rows, vpPoseVector(0.01, -0.02, 0.005, 0.01, 0, 0.02),
                               nominal.get_nMe_pose(), vpPoseVector(0.001, 0.061, 0.079, 0.003, -0.002, 0.001));
  // The calibrated form: the nominal table with 6-D corrections from exact absolute poses.
  std::vector<vpKinematicIdentification::Measurement> ms;
  for (int s = 0; s < 20; ++s) {
    vpKinematicIdentification::Measurement m;
    m.q.resize(6);
    for (unsigned int i = 0; i < 6; ++i)
      m.q[i] = rng.uniform(rows[i].min, rows[i].max);
    m.M = truth.get_fMc(m.q);
    ms.push_back(m);
  }
  const auto id = vpKinematicIdentification::identify(nominal, ms, vpKinematicIdentification::Options());
  ASSERT_EQ(id.status, vpKinematicIdentification::OK) << id.message;
  const vpDHTableFit::Result fit = vpDHTableFit::fit(id.chain, vpKinematicChain::DH);
  EXPECT_TRUE(fit.representable) << fit.message;
  EXPECT_TRUE(fit.well_conditioned) << fit.message;
  EXPECT_LT(fit.max_position_error, 1e-9);
  EXPECT_EQ(fit.table.getParameters().frobeniusNorm(), 0.0);
  for (const auto &m : ms)
    EXPECT_LT(translationDistance(fit.table.get_fMc(m.q), m.M), 1e-8);
}

// The simulated arms' errors tilt the parallel axes 2 and 3: a table exists but with a common
// normal far away; the fit must say so (and say whether it reproduces the model, consistently with
// its errors).
TEST(ModelExport, DhFitReportsHonestly)
{
  for (const std::string robot : {"puma560", "viper850"}) {
    const vpSelfCalibSimulator sim = makeSim(robot, 83);
    for (auto conv : {vpKinematicChain::DH, vpKinematicChain::MDH}) {
      vpDHTableFit::Options o;
      o.samples = 40;
      const vpDHTableFit::Result fit = vpDHTableFit::fit(sim.getTrueChain(), conv, o);
      EXPECT_EQ(fit.representable, fit.max_position_error <= 1e-9 && fit.max_rotation_error <= 1e-9) << fit.message;
      if (fit.representable) {
        EXPECT_FALSE(fit.well_conditioned) << fit.message;
        EXPECT_NE(fit.message.find("ill-conditioned"), std::string::npos) << fit.message;
      } else
        EXPECT_NE(fit.message.find("parallel"), std::string::npos) << fit.message;
    }
  }
  vpDHTableFit::Options bad;
  bad.samples = 1;
  EXPECT_THROW(vpDHTableFit::fit(vpKinematicChain::preset("puma560"), vpKinematicChain::DH, bad),
               vpSelfCalibException);
}

// Eye-to-hand: the camera joint hangs from base_link with bMc, the target from the flange with eMo.
TEST(ModelExport, EyeToHandCameraIsALinkOfTheWorld)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 82);
  const vpKinematicChain &model = sim.getTrueChain();
  const vpHomogeneousMatrix bMc(vpPoseVector(0.95, -0.05, 0.47, -1.1, -1.1, 1.3));
  const vpHomogeneousMatrix eMo(vpPoseVector(0.02, -0.005, -0.056, 0.1, 0.2, 0.3));
  const std::string urdf = vpModelExport::toURDF(model, "test", &bMc, &eMo);
  const std::vector<vpHomogeneousMatrix> O = origins(urdf);
  ASSERT_EQ(O.size(), model.getNumJoints() + 3);
  EXPECT_NE(urdf.find("<joint name=\"camera_joint\" type=\"fixed\">\n    <parent link=\"base_link\"/>"), std::string::npos)
      << urdf;
  EXPECT_NE(urdf.find("<joint name=\"target_joint\" type=\"fixed\">\n    <parent link=\"flange\"/>"), std::string::npos);
  EXPECT_LT(translationDistance(O[model.getNumJoints() + 1], bMc), 1e-12);
  EXPECT_LT(rotationDistance(O[model.getNumJoints() + 1], bMc), 1e-12);
  // The target through the chain: fMe(q) eMo.
  const vpColVector q = vpSelfCalibSimulator::homeConfiguration(model);
  vpHomogeneousMatrix T;
  for (unsigned int i = 0; i < q.size(); ++i)
    T = T * O[i] * vpHomogeneousMatrix(0, 0, 0, 0, 0, q[i]);
  T = T * O[q.size()] * O[q.size() + 2];
  EXPECT_LT(translationDistance(T, model.get_fMe(q) * eMo), 1e-12);
  EXPECT_LT(rotationDistance(T, model.get_fMe(q) * eMo), 1e-12);
}
