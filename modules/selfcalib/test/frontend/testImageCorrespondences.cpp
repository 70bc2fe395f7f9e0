/*
 * Tests of vpSelfCalibImageCorrespondences: front end, views left out, method choice.
 */
#include <gtest/gtest.h>

#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibImageCorrespondences.h>
#include <visp3/selfcalib/vpSelfCalibRenderer.h>

#include "../testCommon.h"

// Rendered images, one of them blank: its view is left out, the others get the front end's points
// and the yardstick its ends; the method is the one asked for, bundle adjustment by default.
TEST(ImageCorrespondences, FromImagesLeavesOutEmptyViews)
{
  const vpSelfCalibSimulator sim = selfcalib_test::makeSim("viper850", 7);
  const vpSelfCalibRenderer renderer(sim, vpSelfCalibRenderer::Options());
  const std::vector<vpColVector> q = sim.generateConfigurations(5);
  vpSelfCalibDataset ds = sim.makeDataset(q);
  std::vector<vpImage<unsigned char>> images;
  for (unsigned int k = 0; k < q.size(); ++k)
    images.push_back(renderer.render(q[k], k));
  images[2] = vpImage<unsigned char>(images[0].getHeight(), images[0].getWidth(), 255);

  vpSelfCalibImageCorrespondences::Options o;
  vpSelfCalibDataset data = ds;
  const vpSelfCalibImageCorrespondences::Result r = vpSelfCalibImageCorrespondences::fromImages(data, images, o);
  EXPECT_TRUE(r.front_end_ran);
  ASSERT_EQ(r.dropped.size(), 1u);
  EXPECT_EQ(r.dropped[0].index, 2u);
  ASSERT_EQ(data.views.size(), 4u);
  for (size_t k = 0; k < data.views.size(); ++k) {
    EXPECT_FALSE(data.views[k].points.empty());
    const size_t original = k < 2 ? k : k + 1;
    EXPECT_EQ(data.views[k].points.size(), r.front_end.observations[original].size());
    EXPECT_EQ(data.views[k].q, ds.views[original].q);
  }
  EXPECT_EQ(data.yardstick.id_a, r.front_end.yardstick_a);
  EXPECT_EQ(data.yardstick.id_b, r.front_end.yardstick_b);
  unsigned int seen = 0;
  for (bool b : r.front_end.yardstick_seen)
    seen += b;
  EXPECT_EQ(r.yardstick_images, seen);
  EXPECT_GT(seen, 0u);
  EXPECT_EQ(r.method, vpRobotSelfCalibration::BUNDLE_ADJUSTMENT);
  // A dataset that declares no yardstick: its dots are not looked for (the same images).
  data = ds;
  data.yardstick = vpSelfCalibDataset::Yardstick();
  const vpSelfCalibImageCorrespondences::Result none = vpSelfCalibImageCorrespondences::fromImages(data, images, o);
  EXPECT_EQ(none.yardstick_images, 0u);
  EXPECT_FALSE(data.yardstick.isSet());

  o.method = vpRobotSelfCalibration::PAPER;
  data = ds;
  EXPECT_EQ(vpSelfCalibImageCorrespondences::fromImages(data, images, o).method, vpRobotSelfCalibration::PAPER);
  images.pop_back();
  data = ds;
  EXPECT_THROW(vpSelfCalibImageCorrespondences::fromImages(data, images, o), vpSelfCalibException);
}

// A dataset with its points needs no front end: its views are kept; controller poses without joints
// choose the hand-eye method unless a method is given.
TEST(ImageCorrespondences, FromDatasetWithPoints)
{
  const vpSelfCalibSimulator sim = selfcalib_test::makeSim("puma560", 3);
  vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(4));
  ds.views[1].points.clear(); // no image either: left to the calibration's checks
  EXPECT_FALSE(vpSelfCalibImageCorrespondences::needsFrontEnd(ds));
  vpSelfCalibImageCorrespondences::Options o;
  vpSelfCalibDataset data = ds;
  vpSelfCalibImageCorrespondences::Result r = vpSelfCalibImageCorrespondences::fromDatasetImages(data, o);
  EXPECT_FALSE(r.front_end_ran);
  EXPECT_TRUE(r.dropped.empty());
  EXPECT_EQ(data.views.size(), ds.views.size());
  EXPECT_EQ(r.method, vpRobotSelfCalibration::BUNDLE_ADJUSTMENT);

  for (auto &v : ds.views) {
    v.has_fMe = true;
    v.fMe = sim.getTrueChain().get_fMe(v.q);
    v.q = vpColVector();
  }
  data = ds;
  EXPECT_EQ(vpSelfCalibImageCorrespondences::fromDatasetImages(data, o).method, vpRobotSelfCalibration::HAND_EYE);
  o.method = vpRobotSelfCalibration::BUNDLE_ADJUSTMENT;
  data = ds;
  EXPECT_EQ(vpSelfCalibImageCorrespondences::fromDatasetImages(data, o).method,
            vpRobotSelfCalibration::BUNDLE_ADJUSTMENT);

  ds.views[0].image = "/nonexistent/0001.png"; // a view with an image and no points: the front end runs
  ds.views[0].points.clear();
  EXPECT_TRUE(vpSelfCalibImageCorrespondences::needsFrontEnd(ds));
  EXPECT_THROW(vpSelfCalibImageCorrespondences::fromDatasetImages(ds, o), vpSelfCalibException);
}
