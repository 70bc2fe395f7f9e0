/*
 * Tests of the eye-to-hand set-up (camera fixed in the world, target on the tool): exact recovery of
 * bMc and eMo on noise-free data, honest sd with the controller poses' error, the inverted pose
 * correction's Jacobian against finite differences, and the refusal of the other methods.
 */
#include <gtest/gtest.h>

#include <cmath>

#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

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

TEST(EyeToHand, OtherMethodsAreRefused)
{
  vpSelfCalibSimulator::EyeToHandOptions so;
  vpSelfCalibSimulator::EyeToHandTruth truth;
  const vpSelfCalibDataset ds = vpSelfCalibSimulator::simulateEyeToHand(so, truth);
  for (RSC::Method m : {RSC::BUNDLE_ADJUSTMENT, RSC::PAPER}) {
    RSC::Options o;
    o.method = m;
    try {
      RSC::run(vpKinematicChain::preset("viper850"), ds, o);
      ADD_FAILURE() << "method " << RSC::methodName(m) << " ran on camera_mount world";
    } catch (const vpSelfCalibException &e) {
      EXPECT_NE(e.getStringMessage().find("camera_mount: world is calibrated with --method hand-eye"), std::string::npos)
          << e.getStringMessage();
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
