/*
 * Tests of the rendered eye-to-hand set-up (vpSelfCalibEyeToHandRenderer, simulate --camera-mount
 * world --images): the board on the tool is drawn where the truth says, and the hand-eye method on
 * the board found in the images recovers bMc and eMo within a bound over several seeds.
 */
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include <visp3/core/vpMeterPixelConversion.h>
#include <visp3/selfcalib/vpBoardDetector.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibEyeToHandRenderer.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibImageCorrespondences.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "../testCommon.h"

namespace
{
using RSC = vpRobotSelfCalibration;
using E2H = vpSelfCalibEyeToHandRenderer;
using selfcalib_test::poseError;

//! The board of `scene` as simulate --camera-mount world --images draws it, and its detector.
vpSelfCalibRenderer::Options boardOptions(vpSelfCalibRenderer::Scene scene, unsigned int seed)
{
  vpSelfCalibRenderer::Options ro;
  ro.scene = scene;
  ro.seed = seed;
  return ro;
}

vpBoardDetector::Options detectorOptions(const vpSelfCalibRenderer::Options &ro)
{
  return ro.scene == vpSelfCalibRenderer::CHARUCO ? vpBoardDetector::parse("charuco:7x5:0.02:0.015:DICT_6X6_250")
                                                  : selfcalib_test::tagBundleDetector(ro);
}

//! The eye-to-hand simulation of the rendered path (simulate --camera-mount world --images).
vpSelfCalibDataset simulate(const vpSelfCalibRenderer::Options &ro, unsigned int seed, unsigned int views,
                            double pose_sd, vpSelfCalibSimulator::EyeToHandTruth &truth)
{
  vpSelfCalibSimulator::EyeToHandOptions eo = E2H::simulation(ro);
  eo.seed = seed;
  eo.num_views = views;
  eo.pose_sd_translation = eo.pose_sd_rotation = pose_sd;
  return vpSelfCalibSimulator::simulateEyeToHand(eo, truth);
}

std::vector<vpImage<unsigned char>> render(const vpSelfCalibRenderer::Options &ro, const vpSelfCalibDataset &ds,
                                           const vpSelfCalibSimulator::EyeToHandTruth &truth)
{
  const E2H renderer(ro, ds.cam, ds.width, ds.height, truth.bMc, truth.eMo);
  std::vector<vpImage<unsigned char>> images;
  for (size_t k = 0; k < truth.bMe.size(); ++k)
    images.push_back(renderer.render(truth.bMe[k], static_cast<unsigned int>(k)));
  return images;
}

} // namespace

// The board on the tool is drawn where the truth says: every point of the ChArUco board and of the
// tag bundle is found in 4 views, within 0.1 px of the true projection of its layout point through
// bMc^-1 bMe eMo, the tool's textured parts behind it notwithstanding.
TEST(EyeToHandImages, RenderedBoardIsWhereTheTruthSays)
{
  for (vpSelfCalibRenderer::Scene scene : {vpSelfCalibRenderer::CHARUCO, vpSelfCalibRenderer::APRILTAGS}) {
    const vpSelfCalibRenderer::Options ro = boardOptions(scene, 3);
    vpSelfCalibSimulator::EyeToHandTruth truth;
    const vpSelfCalibDataset ds = simulate(ro, 3, 4, 0, truth);
    const std::vector<vpImage<unsigned char>> images = render(ro, ds, truth);
    const vpBoardDetector det(detectorOptions(ro));
    const std::map<int, vpColVector> layout = det.getLayout();
    double worst = 0;
    size_t points = 0;
    for (size_t k = 0; k < images.size(); ++k) {
      ASSERT_EQ(images[k].getWidth(), 1280u);
      ASSERT_EQ(images[k].getHeight(), 720u);
      const vpBoardDetector::Result r = det.detect(images[k]);
      ASSERT_TRUE(r.found) << "view " << k << ": " << r.message;
      const vpHomogeneousMatrix cMo = truth.bMc.inverse() * truth.bMe[k] * truth.eMo;
      for (const vpSelfCalibDataset::Observation &ob : r.corners) {
        const vpColVector &P = layout.at(ob.id);
        const vpColVector X = cMo * vpColVector({P[0], P[1], P[2], 1.0});
        vpImagePoint ip;
        vpMeterPixelConversion::convertPoint(ds.cam, X[0] / X[2], X[1] / X[2], ip);
        worst = std::max(worst, vpImagePoint::distance(ip, ob.ip));
        ++points;
      }
    }
    std::cout << "[ e2h      ] " << vpBoardDetector::toString(det.getOptions()) << ": " << points
              << " points in 4 views, largest error " << worst << " px\n";
    EXPECT_EQ(points, scene == vpSelfCalibRenderer::CHARUCO ? 4u * 24 : 4u * 16);
    EXPECT_LT(worst, 0.1);
  }
}

// calibrate --method hand-eye --board ... --board-geometry on rendered images: over 4 seeds (the
// ChArUco board on 3, the tags on 1), 8 views with 1 mm / 1 mrad of controller pose error (the
// default: the pose error measured), bMc and eMo within 4 reported sd of the truth on every axis,
// the sd themselves under 5 mm / 10 mrad (a bound that holds because the sd are, not because
// they are wide).
TEST(EyeToHandImages, HandEyeOnRenderedBoardsRecoversTheTruth)
{
  for (unsigned int seed = 1; seed <= 4; ++seed) {
    const vpSelfCalibRenderer::Scene scene = seed <= 3 ? vpSelfCalibRenderer::CHARUCO : vpSelfCalibRenderer::APRILTAGS;
    const vpSelfCalibRenderer::Options ro = boardOptions(scene, seed);
    vpSelfCalibSimulator::EyeToHandTruth truth;
    vpSelfCalibDataset ds = simulate(ro, seed, 8, 0.001, truth);
    ds.pose_sd_translation = ds.pose_sd_rotation = 0; // nothing stated: measured
    vpSelfCalibImageCorrespondences::Options co;
    co.front_end.features = false;
    co.board = detectorOptions(ro);
    co.method = RSC::HAND_EYE;
    const vpSelfCalibImageCorrespondences::Result cr =
        vpSelfCalibImageCorrespondences::fromImages(ds, render(ro, ds, truth), co);
    ASSERT_EQ(cr.board_images, 8u);
    RSC::Options o;
    o.method = RSC::HAND_EYE;
    o.bundle.known_points = vpBoardDetector(*co.board).getLayout();
    const RSC::Result r = RSC::run(vpKinematicChain::preset("viper850"), ds, o);
    ASSERT_TRUE(r.status == RSC::OK || r.status == RSC::DOUBTFUL) << r.message;
    ASSERT_TRUE(r.has_bMc && r.has_eMo);
    const vpColVector eb = poseError(r.bMc, truth.bMc), eo = poseError(r.eMo, truth.eMo);
    std::cout << "[ e2h      ] seed " << seed << " " << vpBoardDetector::toString(*co.board) << ": bMc error "
              << 1e3 * eb.extract(0, 3).frobeniusNorm() << " mm, " << 1e3 * eb.extract(3, 3).frobeniusNorm()
              << " mrad; eMo " << 1e3 * eo.extract(0, 3).frobeniusNorm() << " mm, "
              << 1e3 * eo.extract(3, 3).frobeniusNorm() << " mrad; measured pose sd "
              << 1e3 * r.noise.pose_sd_translation << " mm, " << 1e3 * r.noise.pose_sd_rotation << " mrad\n";
    for (unsigned int i = 0; i < 6; ++i) {
      EXPECT_LT(std::fabs(eb[i]), 4 * r.bMc_sd[i]) << "seed " << seed << " bMc axis " << i;
      EXPECT_LT(std::fabs(eo[i]), 4 * r.eMo_sd[i]) << "seed " << seed << " eMo axis " << i;
      const double sd_max = i < 3 ? 0.005 : 0.010;
      EXPECT_LT(r.bMc_sd[i], sd_max) << "seed " << seed << " bMc axis " << i;
      EXPECT_LT(r.eMo_sd[i], sd_max) << "seed " << seed << " eMo axis " << i;
    }
  }
}

TEST(EyeToHandImages, OnlyBoardScenesAreRendered)
{
  vpSelfCalibRenderer::Options ro;
  ro.scene = vpSelfCalibRenderer::TEXTURED;
  try {
    E2H(ro, vpCameraParameters(1000, 1000, 640, 360), 1280, 720, vpHomogeneousMatrix(), vpHomogeneousMatrix());
    ADD_FAILURE() << "a textured scene was accepted";
  } catch (const vpSelfCalibException &e) {
    EXPECT_EQ(e.getStringMessage(),
              "vpSelfCalibEyeToHandRenderer: the tool carries a board: scene CHARUCO or APRILTAGS");
  }
}
