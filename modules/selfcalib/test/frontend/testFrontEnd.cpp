/*
 * Tests of the image front end on rendered images of the reference scenario, end to end.
 */
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <iostream>

#include <visp3/selfcalib/vpCalibrationVerifier.h>
#include <visp3/selfcalib/vpFeatureFrontEnd.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibRenderer.h>

#include "core/vpSelfCalibMath.h"
#include "core/vpSelfCalibRandom.h"

using namespace vpSelfCalib;

namespace
{
// Mean held-out position error (m) of the default pipeline on the first C views, verified on the rest.
double heldOut(const vpSelfCalibSimulator &sim, const vpSelfCalibDataset &ds, unsigned int C, double *rms = nullptr)
{
  vpRobotSelfCalibration::Options o;
  o.num_calibration_poses = C;
  o.trust_robot = true; // exact joints: the front end's points are the subject, not the robot's error
  const auto r = vpRobotSelfCalibration::run(sim.getNominalChain(), ds, o);
  EXPECT_EQ(r.status, vpRobotSelfCalibration::OK) << r.message;
  if (rms)
    *rms = r.bundle.rms;
  const std::vector<vpSelfCalibDataset::View> ver(ds.views.begin() + C, ds.views.end());
  return vpCalibrationVerifier::verify(r.calibrated, r.camera, ver, ds.yardstick, {}, sim.getTrueCameraPoses(ver))
      .position_error_mean;
}
// The same observations, replaced by the exact projections of their true points (truth(id), in f)
// through the true cameras T, plus Gaussian noise of sd `sd` (stream 5 of `seed`).
vpSelfCalibDataset exactProjections(vpSelfCalibDataset ds, const std::vector<vpHomogeneousMatrix> &T,
                                    const std::function<const vpColVector &(int)> &truth, double sd, uint64_t seed)
{
  Random rng(seed, 5);
  for (size_t k = 0; k < ds.views.size(); ++k)
    for (auto &o : ds.views[k].points) {
      const Eigen::Vector3d c = rigidFromVisp(T[k]).inverse() * vec3(truth(o.id));
      o.ip = vpImagePoint(240 + 1500 * c(1) / c(2) + rng.normal(sd), 320 + 1500 * c(0) / c(2) + rng.normal(sd));
    }
  return ds;
}

// The simulator's dataset with the front end's observations and yardstick ends in place of its points.
vpSelfCalibDataset withFrontEnd(vpSelfCalibDataset ds, const vpFeatureFrontEnd::Result &fe,
                                const vpSelfCalibRenderer &renderer)
{
  for (size_t k = 0; k < ds.views.size(); ++k)
    ds.views[k].points = fe.observations[k];
  ds.yardstick.length = renderer.getYardstickLength();
  ds.yardstick.id_a = fe.yardstick_a;
  ds.yardstick.id_b = fe.yardstick_b;
  return ds;
}
} // namespace

// 12 rendered poses (8 calibrating, 4 held out): the tracks are right (they triangulate through the
// true cameras within a pixel), the yardstick's dots are found and located, and the calibration on
// the front end's correspondences is within 2x of the same run on exact correspondences of the same
// points with the same pixel noise.
TEST(FrontEnd, RenderedImagesEndToEnd)
{
  const unsigned int N = 12, C = 8;
  vpSelfCalibSimulator::Options so;
  so.seed = 91;
  const vpSelfCalibSimulator sim(vpKinematicChain::preset("viper850"), so);
  const vpSelfCalibRenderer renderer(sim, vpSelfCalibRenderer::Options());
  const std::vector<vpColVector> q = sim.generateConfigurations(N);
  std::vector<vpImage<unsigned char>> images;
  for (unsigned int k = 0; k < N; ++k)
    images.push_back(renderer.render(q[k], k));
  // Rendered on several threads: the same images, pixel for pixel.
  for (unsigned int threads : {1u, 3u}) {
    std::vector<vpImage<unsigned char>> parallel = renderer.render(q, threads); // vpImage::operator== is not const
    ASSERT_EQ(parallel.size(), images.size());
    for (unsigned int k = 0; k < N; ++k)
      ASSERT_TRUE(parallel[k] == images[k]) << "image " << k << ", " << threads << " threads";
  }
  const vpFeatureFrontEnd::Result fe = vpFeatureFrontEnd::process(images, vpFeatureFrontEnd::Options());
  ASSERT_GT(fe.num_tracks, 300u);
  ASSERT_GE(fe.yardstick_a, 0) << "yardstick not found";
  unsigned int seen = 0;
  for (bool b : fe.yardstick_seen)
    seen += b;
  EXPECT_GE(seen, 3u);

  const vpSelfCalibDataset ds = withFrontEnd(sim.makeDataset(q), fe, renderer);

  // Tracks through the true cameras: triangulated, reprojected.
  const std::map<int, vpColVector> X = vpCalibrationVerifier::triangulate(sim.getTrueChain(), ds.cam, ds.views);
  const std::vector<vpHomogeneousMatrix> T = sim.getTrueCameraPoses(ds.views);
  unsigned int good = 0, total = 0;
  for (unsigned int k = 0; k < N; ++k)
    for (const auto &o : ds.views[k].points) {
      const Eigen::Vector3d c = rigidFromVisp(T[k]).inverse() * vec3(X.at(o.id));
      const double du = 320 + 1500 * c(0) / c(2) - o.ip.get_u(), dv = 240 + 1500 * c(1) / c(2) - o.ip.get_v();
      good += std::hypot(du, dv) < 1.0;
      ++total;
    }
  EXPECT_GT(good, 0.95 * total);
  // The dots: their centroids against the projections of the true ends.
  for (unsigned int k = 0; k < N; ++k)
    for (const auto &o : ds.views[k].points)
      if (o.id == fe.yardstick_a || o.id == fe.yardstick_b) {
        const vpColVector &E = o.id == fe.yardstick_a ? renderer.getYardstickEndA() : renderer.getYardstickEndB();
        const Eigen::Vector3d c = rigidFromVisp(T[k]).inverse() * vec3(E);
        EXPECT_NEAR(320 + 1500 * c(0) / c(2), o.ip.get_u(), 0.2) << "view " << k;
        EXPECT_NEAR(240 + 1500 * c(1) / c(2), o.ip.get_v(), 0.2) << "view " << k;
      }

  double rms = 0;
  const double rendered = heldOut(sim, ds, C, &rms);
  // The same points (triangulated through the true cameras; the yardstick's true ends), projected
  // exactly, with Gaussian noise of the rendered run's residual RMS.
  const double reference = heldOut(sim, exactProjections(ds, T, [&](int id) -> const vpColVector & {
    return id == fe.yardstick_a ? renderer.getYardstickEndA()
                                : (id == fe.yardstick_b ? renderer.getYardstickEndB() : X.at(id));
  }, rms, 91), C);
  EXPECT_LT(rendered, 2 * reference) << "rendered " << rendered << " m, exact correspondences " << reference << " m";
}

// The paper's experiment: a dot pattern on a non-planar object (two asymmetric circle grids on the
// two planes), 12 rendered poses, dots only (no natural features). Every dot found gets the id of
// its place in its grid, the same in every view (checked against the true dot centres, within
// 0.5 px), and the calibration is within 2x of the same run on the true dot projections with the
// same pixel noise.
TEST(FrontEnd, DotTargetEndToEnd)
{
  const unsigned int N = 12, C = 8;
  vpSelfCalibSimulator::Options so;
  so.seed = 92;
  const vpSelfCalibSimulator sim(vpKinematicChain::preset("viper850"), so);
  vpSelfCalibRenderer::Options ro;
  ro.scene = vpSelfCalibRenderer::DOTS;
  const vpSelfCalibRenderer renderer(sim, ro);
  const std::vector<vpColVector> q = sim.generateConfigurations(N);
  std::vector<vpImage<unsigned char>> images;
  for (unsigned int k = 0; k < N; ++k)
    images.push_back(renderer.render(q[k], k));
  vpFeatureFrontEnd::Options fo;
  fo.features = false;
  fo.dot_grids = renderer.getDotGrids();
  const vpFeatureFrontEnd::Result fe = vpFeatureFrontEnd::process(images, fo);
  EXPECT_EQ(fe.num_tracks, 0u);
  ASSERT_EQ(fe.grid_seen.size(), 2u);
  unsigned int grids = 0, yardsticks = 0;
  for (unsigned int k = 0; k < N; ++k) {
    grids += fe.grid_seen[0][k] + fe.grid_seen[1][k];
    yardsticks += fe.yardstick_seen[k];
  }
  EXPECT_GE(grids, 2 * N - 2) << "grids found in " << grids << " of " << 2 * N << " images";
  EXPECT_GE(yardsticks, N - 2);

  const vpSelfCalibDataset ds = withFrontEnd(sim.makeDataset(q), fe, renderer);
  const std::vector<vpHomogeneousMatrix> T = sim.getTrueCameraPoses(ds.views);
  auto truth = [&](int id) -> const vpColVector & {
    return id == fe.yardstick_a ? renderer.getYardstickEndA()
                                : (id == fe.yardstick_b ? renderer.getYardstickEndB() : renderer.getDotCentres().at(id));
  };
  for (unsigned int k = 0; k < N; ++k)
    for (const auto &o : ds.views[k].points) {
      ASSERT_TRUE(o.id == fe.yardstick_a || o.id == fe.yardstick_b || renderer.getDotCentres().count(o.id)) << o.id;
      const Eigen::Vector3d c = rigidFromVisp(T[k]).inverse() * vec3(truth(o.id));
      EXPECT_LT(std::hypot(320 + 1500 * c(0) / c(2) - o.ip.get_u(), 240 + 1500 * c(1) / c(2) - o.ip.get_v()), 0.5)
          << "view " << k << ", dot " << o.id;
    }

  double rms = 0;
  const double rendered = heldOut(sim, ds, C, &rms);
  const double reference = heldOut(sim, exactProjections(ds, T, truth, rms, 92), C);
  std::cout << "dot target, held-out position error: " << 1e3 * rendered << " mm on the rendered images, "
            << 1e3 * reference << " mm on exact projections with the same noise (" << rms << " px)\n";
  EXPECT_LT(rendered, 2 * reference) << "rendered " << rendered << " m, exact correspondences " << reference << " m";
}

TEST(FrontEnd, BadInput)
{
  vpImage<unsigned char> a(480, 640, 128), b(240, 320, 128);
  EXPECT_THROW(vpFeatureFrontEnd::process({a}, vpFeatureFrontEnd::Options()), vpSelfCalibException);
  EXPECT_THROW(vpFeatureFrontEnd::process({a, b}, vpFeatureFrontEnd::Options()), vpSelfCalibException);
  vpFeatureFrontEnd::Options o;
  o.ratio = 2;
  EXPECT_THROW(o.check(), vpSelfCalibException);
  EXPECT_THROW(vpFeatureFrontEnd::detectorFromName("surf"), vpSelfCalibException);
  o = vpFeatureFrontEnd::Options();
  o.features = false;
  EXPECT_THROW(o.check(), vpSelfCalibException); // nothing to find
  o.dot_grids.resize(2);                           // the same ids
  EXPECT_THROW(o.check(), vpSelfCalibException);
  o.dot_grids[1].first_id = 1001000;               // two grids of 4 x 5 dots: indistinguishable
  EXPECT_THROW(o.check(), vpSelfCalibException);
  o.dot_grids[1].rows = 9;
  EXPECT_NO_THROW(o.check());
  o.dot_grids[1].first_id = 1;                     // the yardstick takes ids 0 and 1 here
  EXPECT_THROW(vpFeatureFrontEnd::process({a, a}, o), vpSelfCalibException);
  // Featureless images: no tracks, no yardstick, no crash.
  const auto r = vpFeatureFrontEnd::process({a, a, a}, vpFeatureFrontEnd::Options());
  EXPECT_EQ(r.num_tracks, 0u);
  EXPECT_EQ(r.yardstick_a, -1);
  vpSelfCalibRenderer::Options ro;
  ro.texture_dir = "/nonexistent";
  vpSelfCalibSimulator::Options so;
  const vpSelfCalibSimulator sim(vpKinematicChain::preset("viper850"), so);
  EXPECT_THROW(vpSelfCalibRenderer(sim, ro), vpSelfCalibException);
}

// The dot grid description: OpenCV's asymmetric layout, odd rows shifted by half a step; the
// renderer's DOTS scene describes its two grids with it, as the front end looks for them.
TEST(FrontEnd, DotGridLayout)
{
  vpDotGrid g;
  g.cols = 4;
  g.rows = 3;
  EXPECT_EQ(g.size(), 12u);
  const unsigned int x[12] = {0, 2, 4, 6, 1, 3, 5, 7, 0, 2, 4, 6}, y[12] = {0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2};
  for (unsigned int k = 0; k < 12; ++k) {
    EXPECT_EQ(g.x(k), x[k]) << k;
    EXPECT_EQ(g.y(k), y[k]) << k;
  }
  vpSelfCalibSimulator::Options so;
  const vpSelfCalibSimulator sim(vpKinematicChain::preset("viper850"), so);
  vpSelfCalibRenderer::Options ro;
  EXPECT_TRUE(vpSelfCalibRenderer(sim, ro).getDotGrids().empty());
  ro.scene = vpSelfCalibRenderer::DOTS;
  const vpSelfCalibRenderer renderer(sim, ro);
  ASSERT_EQ(renderer.getDotGrids().size(), 2u);
  vpFeatureFrontEnd::Options fo;
  fo.features = false;
  fo.dot_grids = renderer.getDotGrids();
  EXPECT_NO_THROW(fo.check());
  EXPECT_EQ(renderer.getDotCentres().size(), fo.dot_grids[0].size() + fo.dot_grids[1].size());
  for (const vpDotGrid &d : fo.dot_grids)
    for (unsigned int k = 0; k < d.size(); ++k)
      EXPECT_EQ(renderer.getDotCentres().count(d.first_id + static_cast<int>(k)), 1u);
}
