/*
 * Tests of vpMultiViewReconstruction: exact recovery, robustness to wrong matches, bad input.
 */
#include <gtest/gtest.h>

#include <cmath>

#include <visp3/selfcalib/vpMultiViewReconstruction.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "../testCommon.h"
#include "../testPlaneDraws.h"
#include "core/vpSelfCalibMath.h"
#include "core/vpSelfCalibRandom.h"

using namespace selfcalib_test;

using namespace vpSelfCalib;

namespace
{
vpMultiViewReconstruction::Options options(const vpSelfCalibSimulator &sim, bool focal_known)
{
  vpMultiViewReconstruction::Options o;
  const vpCameraParameters c = sim.getCamera();
  o.focal_known = focal_known;
  o.twoview.fx = focal_known ? c.get_px() : 0.93 * c.get_px();
  o.twoview.u0 = c.get_u0();
  o.twoview.v0 = c.get_v0();
  o.twoview.mu = c.get_py() / c.get_px();
  return o;
}

//! The noise model of the simulated data: its pixel noise, at least 0.2 px.
vpSelfCalibNoiseModel noiseOf(const vpSelfCalibSimulator &sim)
{
  vpSelfCalibNoiseModel n;
  n.pixel_sd = std::max(0.2, sim.getOptions().pixel_noise_sd);
  return n;
}

// Mean translation-direction error (rad) of the poses against the truth.
double directionError(const vpMultiViewReconstruction::Result &r, const std::vector<vpHomogeneousMatrix> &truth)
{
  double s = 0;
  unsigned int n = 0;
  for (size_t k = 1; k < truth.size(); ++k) {
    if (!r.posed[k])
      continue;
    const Eigen::Vector3d a = rigidFromVisp(r.cMc0[k]).t, b = rigidFromVisp(truth[k].inverse() * truth[0]).t;
    s += std::acos(std::min(1.0, a.normalized().dot(b.normalized())));
    ++n;
  }
  return n ? s / n : M_PI;
}
} // namespace

// Noise-free images, f unknown: the poses are the true c_kMc_0 with the yardstick's metric scale,
// the points the true ones in the first camera frame, f the true one.
TEST(MultiViewReconstruction, NoiseFreeExactRecoveryWithSelfCalibratedFocal)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 21, 0.0);
  const std::vector<vpColVector> q = sim.generateConfigurations(10);
  const vpSelfCalibDataset ds = sim.makeDataset(q);
  vpMultiViewReconstruction::Options o = options(sim, false);
  o.tight = true;
  const vpMultiViewReconstruction::Result r = vpMultiViewReconstruction::reconstruct(ds.views, ds.yardstick, o, noiseOf(sim));
  ASSERT_EQ(r.status, vpMultiViewReconstruction::OK) << r.message;
  EXPECT_TRUE(r.metric);
  EXPECT_EQ(r.num_outliers, 0u);
  EXPECT_NEAR(r.fx, sim.getCamera().get_px(), 1e-5);
  const std::vector<vpHomogeneousMatrix> T = sim.getTrueCameraPoses(ds.views);
  for (size_t k = 1; k < q.size(); ++k) {
    ASSERT_TRUE(r.posed[k]);
    const vpHomogeneousMatrix truth = T[k].inverse() * T[0];
    EXPECT_LT(translationDistance(r.cMc0[k], truth), 1e-9) << k;
    EXPECT_LT(rotationDistance(r.cMc0[k], truth), 1e-9) << k;
  }
  const Rigid c0Mf = rigidFromVisp(T[0]).inverse();
  for (const auto &e : sim.getScenePointsById()) {
    ASSERT_TRUE(r.points.count(e.first));
    EXPECT_LT((vec3(r.points.at(e.first)) - c0Mf * vec3(e.second)).norm(), 1e-9);
  }
}

// Without the yardstick the result is in the unit of the reference pair's baseline.
TEST(MultiViewReconstruction, WithoutYardstickTheReferenceBaselineIsTheUnit)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 22, 0.0);
  const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(6));
  const vpMultiViewReconstruction::Result r =
      vpMultiViewReconstruction::reconstruct(ds.views, vpSelfCalibDataset::Yardstick(), options(sim, true), noiseOf(sim));
  ASSERT_EQ(r.status, vpMultiViewReconstruction::OK) << r.message;
  EXPECT_FALSE(r.metric);
  ASSERT_GT(r.reference_view, 0u);
  EXPECT_NEAR(r.cMc0[r.reference_view].getTranslationVector().frobeniusNorm(), 1.0, 1e-12);
}

// 20% of the observations replaced by random pixels: the robust default finds them all.
TEST(MultiViewReconstruction, WrongMatchesAreRejected)
{
  double robust = 0, removed = 0, plain_error = 0;
  for (uint64_t seed : {31, 32, 33}) {
    const vpSelfCalibSimulator sim = makeSim("viper850", seed, 0.2);
    const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(12));
    vpSelfCalibDataset bad = ds;
    corrupt(bad, 0.2, seed, 77);
    vpMultiViewReconstruction::Options o = options(sim, false);
    o.tight = true; // both solves to the bottom of a flat valley, so that they can be compared
    const auto rb = vpMultiViewReconstruction::reconstruct(bad.views, bad.yardstick, o, noiseOf(sim));
    ASSERT_EQ(rb.status, vpMultiViewReconstruction::OK) << rb.message;
    EXPECT_TRUE(rb.metric);
    // Every wrong match is rejected (but the odd one that lands within a pixel of the right place);
    // at most 3% of the right ones are lost with them.
    vpSelfCalibDataset kept = bad;
    unsigned int wrong_kept = 0, wrong_total = 0, right = 0, right_lost = 0;
    for (size_t k = 0; k < ds.views.size(); ++k) {
      kept.views[k].points.clear();
      for (size_t j = 0; j < ds.views[k].points.size(); ++j) {
        const bool wrong = !(bad.views[k].points[j].ip == ds.views[k].points[j].ip);
        wrong_kept += wrong && rb.inliers[k][j];
        wrong_total += wrong;
        right += !wrong;
        right_lost += !wrong && !rb.inliers[k][j];
        if (rb.inliers[k][j])
          kept.views[k].points.push_back(bad.views[k].points[j]);
      }
    }
    EXPECT_LE(wrong_kept, 0.02 * wrong_total) << seed;
    EXPECT_LT(right_lost, 0.03 * right) << seed;
    // Accuracy: the reconstruction alone is not held to the error without wrong matches: images
    // of a small, distant scene leave a flat cost with separate minima, and the robust solve can
    // stop in another one (seed 33: 4% higher RMS than least squares on the same kept
    // observations from the clean start). The pipeline's kinematic bundle adjustment is (test-bundle).
    // Plain least squares on the corrupted data is far worse than either.
    vpSelfCalibNoiseModel plain = noiseOf(sim);
    plain.loss = vpSelfCalibNoiseModel::LOSS_NONE;
    plain.outlier_threshold = 0;
    const auto rr = vpMultiViewReconstruction::reconstruct(kept.views, kept.yardstick, o, plain);
    const auto rp = vpMultiViewReconstruction::reconstruct(bad.views, bad.yardstick, o, plain);
    ASSERT_EQ(rr.status, vpMultiViewReconstruction::OK) << rr.message;
    const std::vector<vpHomogeneousMatrix> T = sim.getTrueCameraPoses(ds.views);
    robust += directionError(rb, T);
    removed += directionError(rr, T);
    plain_error += rp.status == vpMultiViewReconstruction::OK ? directionError(rp, T) : M_PI;
  }
  EXPECT_LT(robust, 4 * removed);
  EXPECT_GT(plain_error, 3 * robust);
}

TEST(MultiViewReconstruction, BadInputThrowsAndUselessDataGivesAStatus)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 23, 0.2);
  const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(4));
  const vpMultiViewReconstruction::Options o = options(sim, true);
  EXPECT_THROW(vpMultiViewReconstruction::reconstruct({ds.views[0]}, ds.yardstick, o, noiseOf(sim)), vpSelfCalibException);
  vpSelfCalibDataset bad = ds;
  bad.views[1].points.push_back(bad.views[1].points[0]);
  EXPECT_THROW(vpMultiViewReconstruction::reconstruct(bad.views, ds.yardstick, o, noiseOf(sim)), vpSelfCalibException);
  bad = ds;
  bad.views[2].points[3].ip.set_u(std::nan(""));
  EXPECT_THROW(vpMultiViewReconstruction::reconstruct(bad.views, ds.yardstick, o, noiseOf(sim)), vpSelfCalibException);
  vpSelfCalibNoiseModel bn;
  bn.pixel_sd = 0;
  EXPECT_THROW(vpMultiViewReconstruction::reconstruct(ds.views, ds.yardstick, o, bn), vpSelfCalibException);
  bn.pixel_sd = 0.2;
  bn.loss_scale = -1;
  EXPECT_THROW(vpMultiViewReconstruction::reconstruct(ds.views, ds.yardstick, o, bn), vpSelfCalibException);
  EXPECT_THROW(vpSelfCalibNoiseModel::lossFromName("l1"), vpSelfCalibException);
  // Views sharing 4 points: no pair can be estimated.
  bad = ds;
  for (size_t k = 1; k < bad.views.size(); ++k)
    bad.views[k].points.resize(4);
  const auto r = vpMultiViewReconstruction::reconstruct(bad.views, ds.yardstick, o, noiseOf(sim));
  EXPECT_EQ(r.status, vpMultiViewReconstruction::TWO_VIEW_FAILED);
  EXPECT_FALSE(r.message.empty());
}

// Noise-free images, most points left out of the bundle adjustment: they are triangulated from the
// adjusted poses (midpoint of their rays) as exactly as the bundled ones are recovered.
TEST(MultiViewReconstruction, PointsLeftOutOfTheBundleAreTriangulatedExactly)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 24, 0.0);
  const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(8));
  vpMultiViewReconstruction::Options o = options(sim, true);
  o.tight = true;
  o.max_bundle_points = 12;
  const vpMultiViewReconstruction::Result r = vpMultiViewReconstruction::reconstruct(ds.views, ds.yardstick, o, noiseOf(sim));
  ASSERT_EQ(r.status, vpMultiViewReconstruction::OK) << r.message;
  EXPECT_TRUE(r.metric);
  EXPECT_EQ(r.num_outliers, 0u);
  const std::vector<vpHomogeneousMatrix> T = sim.getTrueCameraPoses(ds.views);
  const Rigid c0Mf = rigidFromVisp(T[0]).inverse();
  const std::map<int, vpColVector> truth = sim.getScenePointsById();
  ASSERT_EQ(r.points.size(), truth.size());
  for (const auto &e : truth) {
    ASSERT_TRUE(r.points.count(e.first));
    EXPECT_LT((vec3(r.points.at(e.first)) - c0Mf * vec3(e.second)).norm(), 1e-9) << e.first;
  }
}

// f's standard deviation (the points marginalized) is positive, covers the error, and is the same
// to the last digit from run to run; 0 when f is known.
TEST(MultiViewReconstruction, FocalStandardDeviationIsReproducible)
{
  for (uint64_t seed : {41, 42, 43}) {
    const vpSelfCalibSimulator sim = makeSim("viper850", seed, 0.2);
    const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(12));
    const vpMultiViewReconstruction::Options o = options(sim, false);
    const auto a = vpMultiViewReconstruction::reconstruct(ds.views, ds.yardstick, o, noiseOf(sim));
    const auto b = vpMultiViewReconstruction::reconstruct(ds.views, ds.yardstick, o, noiseOf(sim));
    ASSERT_EQ(a.status, vpMultiViewReconstruction::OK) << a.message;
    EXPECT_GT(a.fx_sd, 0.0) << seed;
    EXPECT_TRUE(std::isfinite(a.fx_sd)) << seed;
    EXPECT_LT(std::fabs(a.fx - sim.getCamera().get_px()), 4 * a.fx_sd) << seed << ": f " << a.fx << " sd " << a.fx_sd;
    EXPECT_EQ(a.fx_sd, b.fx_sd) << seed;
    EXPECT_EQ(a.fx, b.fx) << seed;
    const auto k = vpMultiViewReconstruction::reconstruct(ds.views, ds.yardstick, options(sim, true), noiseOf(sim));
    ASSERT_EQ(k.status, vpMultiViewReconstruction::OK) << k.message;
    EXPECT_EQ(k.fx_sd, 0.0);
  }
}

// The estimate is the optimum: the default options give the f that the whole schedule run to
// tolerances of 1e-15 gives, to 1 % of its sd (the last solve stopped at Ceres' default relative
// cost change used to leave it further).
TEST(MultiViewReconstruction, TheFocalLengthIsTheConvergedOptimum)
{
  for (uint64_t seed : {41, 42, 43, 44}) {
    const vpSelfCalibSimulator sim = makeSim("viper850", seed, 0.5);
    const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(15));
    vpMultiViewReconstruction::Options o = options(sim, false), tight = o;
    tight.tight = true;
    const auto r = vpMultiViewReconstruction::reconstruct(ds.views, ds.yardstick, o, noiseOf(sim));
    const auto c = vpMultiViewReconstruction::reconstruct(ds.views, ds.yardstick, tight, noiseOf(sim));
    ASSERT_EQ(r.status, vpMultiViewReconstruction::OK) << r.message;
    ASSERT_EQ(c.status, vpMultiViewReconstruction::OK) << c.message;
    ASSERT_GT(c.fx_sd, 0.0);
    EXPECT_LT(std::fabs(r.fx - c.fx), 0.01 * c.fx_sd) << seed << ": f " << r.fx << " against " << c.fx;
  }
}

// Cheirality: the pinhole formula projects a point and its mirror image through the camera centre
// to the same pixel, so a point behind a camera can fit that camera's observation exactly. Six
// views (f known) of a scene 1.5-2.5 m deep, plus one point 0.3 m in front of view 0 that is 0.2 m
// behind view 2, observed in view 2 at the pixel the formula gives for it: that observation is
// rejected (the point stays, from the views it is in front of), everything else is kept.
TEST(MultiViewReconstruction, PointsBehindACameraAreRejected)
{
  const double f = 500, u0 = 320, v0 = 240;
  // c0Mck: camera k in the frame of camera 0 (view 2 0.5 m ahead of view 0, on its axis).
  const std::vector<vpHomogeneousMatrix> c0Mc = {
      vpHomogeneousMatrix(0, 0, 0, 0, 0, 0),          vpHomogeneousMatrix(0.2, 0, 0, 0, -0.05, 0),
      vpHomogeneousMatrix(0, 0, 0.5, 0.02, 0, 0),     vpHomogeneousMatrix(-0.15, 0.1, 0.1, -0.04, 0.06, 0.02),
      vpHomogeneousMatrix(0.1, -0.15, 0.2, 0.05, 0.03, -0.03), vpHomogeneousMatrix(0.05, 0.12, -0.1, -0.03, -0.02, 0.05)};
  const size_t m = c0Mc.size();
  std::vector<vpSelfCalibDataset::View> views(m);
  Random rng(31, 0);
  const auto project = [&](size_t k, const Eigen::Vector3d &X, double &u, double &v) {
    const Eigen::Vector3d Xc = rigidFromVisp(c0Mc[k].inverse()) * X;
    u = u0 + f * Xc.x() / Xc.z();
    v = v0 + f * Xc.y() / Xc.z();
    return Xc.z();
  };
  const auto add = [&](size_t k, int id, double u, double v) {
    vpSelfCalibDataset::Observation o;
    o.id = id;
    o.ip.set_uv(u, v);
    views[k].points.push_back(o);
  };
  for (int id = 0; id < 80; ++id) {
    const Eigen::Vector3d X(rng.uniform(-0.6, 0.6), rng.uniform(-0.45, 0.45), rng.uniform(1.5, 2.5));
    for (size_t k = 0; k < m; ++k) {
      double u, v;
      if (project(k, X, u, v) > 0 && u > 0 && u < 640 && v > 0 && v < 480)
        add(k, id, u, v);
    }
  }
  const int behind_id = 1000;
  const Eigen::Vector3d B(0.1, 0.01, 0.3);
  std::vector<size_t> in_front;
  for (size_t k = 0; k < m; ++k) {
    double u, v;
    const double z = project(k, B, u, v);
    const bool in_image = u > 0 && u < 640 && v > 0 && v < 480;
    if (k == 2) {
      ASSERT_LT(z, -0.1); // behind view 2, its formula pixel inside the image
      ASSERT_TRUE(in_image) << u << " " << v;
      add(k, behind_id, u, v);
    } else if (z > 0 && in_image) {
      add(k, behind_id, u, v);
      in_front.push_back(k);
    }
  }
  ASSERT_GE(in_front.size(), 2u);

  vpMultiViewReconstruction::Options o;
  o.focal_known = true;
  o.twoview.focal_mode = vpRefinedFactorMethod::KNOWN;
  o.twoview.fx = f;
  o.twoview.u0 = u0;
  o.twoview.v0 = v0;
  const vpMultiViewReconstruction::Result r =
      vpMultiViewReconstruction::reconstruct(views, vpSelfCalibDataset::Yardstick(), o, vpSelfCalibNoiseModel());
  ASSERT_EQ(r.status, vpMultiViewReconstruction::OK) << r.message;
  for (size_t k = 0; k < m; ++k) {
    ASSERT_TRUE(r.posed[k]) << k;
    for (size_t j = 0; j < views[k].points.size(); ++j) {
      const int id = views[k].points[j].id;
      EXPECT_EQ(r.inliers[k][j], !(id == behind_id && k == 2)) << "view " << k << " point " << id;
      // Every inlier is in front of its camera, with the reconstructed geometry.
      if (r.inliers[k][j] && r.points.count(id))
        EXPECT_GT((rigidFromVisp(r.cMc0[k]) * vec3(r.points.at(id))).z(), 0) << "view " << k << " point " << id;
    }
  }
  ASSERT_TRUE(r.points.count(behind_id));
  // The point itself, from the views it is in front of: 0.3 m in front of view 0 (unit: the
  // reference baseline, so compared as a direction and a depth ratio with another point).
  const Eigen::Vector3d Xb = vec3(r.points.at(behind_id));
  EXPECT_GT(Xb.z(), 0);
  EXPECT_LT(std::acos(std::min(1.0, Xb.normalized().dot(B.normalized()))), 1e-6);
}

// A small planar board (ChArUco 7 x 5, 24 corners), its layout unknown, seen from 14 poses of the
// Viper850 with 0.2 px of noise. On a plane a pair's two-view motion is ambiguous (a homography
// decomposes into two motions), and on this geometry a view of every draw took the wrong one: it
// still explained about half of the corners, so it stayed posed 30 to 45 deg off, with 11 to 25 of
// its observations trimmed as outliers. The views that leave an observation unexplained are
// resected from the points the others place: every view right, no observation lost, the fit at the
// noise (sigma0 within its 99 % interval). The right poses are within 5 deg of the truth (c_kMc_0
// carries view 0's own error against the weakly tilted plane); the wrong motion is 20 deg or more off.
TEST(MultiViewReconstruction, PlanarBoardEveryViewTakesTheRightOfItsTwoMotions)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 10, 0.0);
  const std::vector<vpColVector> all = sim.generateConfigurations(20);
  const std::vector<vpColVector> q(all.begin(), all.begin() + 14);
  vpSelfCalibNoiseModel noise;
  noise.pixel_sd = 0.2;
  for (uint64_t draw = 0; draw < 5; ++draw) {
    std::map<int, vpColVector> truth;
    const vpSelfCalibDataset ds = charucoBoardViews(sim, q, 0.2, 10, draw, truth);
    const vpMultiViewReconstruction::Result r =
        vpMultiViewReconstruction::reconstruct(ds.views, ds.yardstick, options(sim, true), noise);
    ASSERT_EQ(r.status, vpMultiViewReconstruction::OK) << draw << ": " << r.message;
    EXPECT_EQ(r.num_outliers, 0u) << draw << ": " << r.message;
    EXPECT_TRUE(r.metric) << draw;
    EXPECT_EQ(r.points.size(), truth.size()) << draw;
    EXPECT_GE(r.sigma0, r.sigma0_low) << draw;
    EXPECT_LE(r.sigma0, r.sigma0_high) << draw;
    const vpHomogeneousMatrix fMc0 = sim.getTrueChain().get_fMc(q[0]);
    for (size_t k = 1; k < q.size(); ++k) {
      ASSERT_TRUE(r.posed[k]) << draw << ": view " << k;
      const vpHomogeneousMatrix E = (sim.getTrueChain().get_fMc(q[k]).inverse() * fMc0).inverse() * r.cMc0[k];
      const vpThetaUVector tu(E.getRotationMatrix());
      EXPECT_LT(std::sqrt(tu.sumSquare()), 5 * M_PI / 180) << draw << ": view " << k;
    }
  }
}

// The draws of a flat board of unknown layout (24 corners as points, 0.2 px, f known) whose
// reconstruction from its two-view start alone ended bent (13 views 19-41 deg off, sigma0 2.1-2.4,
// 10-21 good observations rejected): the plane's start (the homographies' motions with the shared
// normal) ends at the noise: every view posed within 5 deg of the truth (c_kMc_0 carries view 0's
// own error against the plane; the wrong motion is 19 deg or more off), no observation rejected,
// sigma0 within its 99.9 % interval.
TEST(MultiViewReconstruction, PlaneOfUnknownLayoutTheDrawsThatEndedBent)
{
  vpSelfCalibNoiseModel noise;
  noise.pixel_sd = 0.2;
  for (const auto &d : kBentDraws) {
    const PlaneDraw p(d.first, d.second, 0.2);
    const vpMultiViewReconstruction::Result r =
        vpMultiViewReconstruction::reconstruct(p.ds.views, p.ds.yardstick, options(p.sim, true), noise);
    ASSERT_EQ(r.status, vpMultiViewReconstruction::OK) << d.first << "/" << d.second << ": " << r.message;
    EXPECT_EQ(std::count(r.posed.begin(), r.posed.end(), true), 14) << d.first << "/" << d.second;
    EXPECT_EQ(r.num_outliers, 0u) << d.first << "/" << d.second << ": " << r.message;
    EXPECT_GE(r.sigma0, r.sigma0_low) << d.first << "/" << d.second;
    EXPECT_LE(r.sigma0, r.sigma0_high) << d.first << "/" << d.second;
    EXPECT_LT(p.worstRotation(r), 5 * M_PI / 180) << d.first << "/" << d.second;
  }
}
