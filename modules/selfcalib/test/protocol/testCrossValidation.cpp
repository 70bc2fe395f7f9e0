/*
 * Tests of vpSelfCalibCrossValidation: the folds, exact recovery of the held-out views on
 * noise-free data (bundle adjustment and hand-eye), a statistical bound at 0.2 px over seeds,
 * failed folds counted, a second dataset verified, bad inputs, the report's section; a camera fixed
 * in the world (exact on noise-free data, the noise level on noisy data).
 */
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <set>
#include <sstream>
#include <vector>

#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibCrossValidation.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibReport.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "../testCommon.h"
#include "core/vpSelfCalibCamera.h"
#include "core/vpSelfCalibMath.h"
#include "core/vpSelfCalibRandom.h"

using namespace selfcalib_test;
using CV = vpSelfCalibCrossValidation;

namespace
{
// A simulated dataset of the reference scenario: m views, the given noise (px).
vpSelfCalibDataset simulated(const vpSelfCalibSimulator &sim, unsigned int m)
{
  return sim.makeDataset(sim.generateConfigurations(m));
}

// The same views with controller poses (the true flange pose) and no joints.
vpSelfCalibDataset withControllerPoses(const vpSelfCalibSimulator &sim, vpSelfCalibDataset ds)
{
  for (auto &v : ds.views) {
    v.has_fMe = true;
    v.fMe = sim.getTrueChain().get_fMe(v.q);
    v.q = vpColVector();
  }
  return ds;
}

// A view whose camera is at fMc (its controller pose fMc eMc^-1) seeing `scene` through `camera`, 0.2 px of noise.
vpSelfCalibDataset::View lensView(const vpHomogeneousMatrix &fMc, const vpHomogeneousMatrix &eMc,
                                  const std::vector<Eigen::Vector3d> &scene, const vpSelfCalib::CameraModel &camera,
                                  vpSelfCalib::Random &rng)
{
  vpSelfCalibDataset::View v;
  v.has_fMe = true;
  v.fMe = fMc * eMc.inverse();
  const vpSelfCalib::Rigid cMf = vpSelfCalib::rigidFromVisp(fMc).inverse();
  for (size_t p = 0; p < scene.size(); ++p) {
    const Eigen::Vector2d uv = camera.project(cMf * scene[p]);
    v.points.push_back({static_cast<int>(p), vpImagePoint(uv(1) + rng.normal(0.2), uv(0) + rng.normal(0.2))});
  }
  return v;
}
} // namespace

// View i in fold i mod k: every view held out exactly once, the same folds every call, the
// bounds of k and of the training sets enforced.
TEST(CrossValidation, FoldsAreInterleavedDeterministicAndBounded)
{
  const auto f = CV::folds(10, 3);
  ASSERT_EQ(f.size(), 3u);
  EXPECT_EQ(f[0], (std::vector<unsigned int>{0, 3, 6, 9}));
  EXPECT_EQ(f[1], (std::vector<unsigned int>{1, 4, 7}));
  EXPECT_EQ(f[2], (std::vector<unsigned int>{2, 5, 8}));
  EXPECT_EQ(CV::folds(10, 3), f);
  for (unsigned int n : {4u, 7u, 12u, 25u})
    for (unsigned int k = 2; k <= n; ++k) {
      if (n - (n + k - 1) / k < 3) {
        EXPECT_THROW(CV::folds(n, k), vpSelfCalibException) << n << " views, " << k << " folds";
        continue;
      }
      std::multiset<unsigned int> all;
      for (const auto &fold : CV::folds(n, k)) {
        EXPECT_FALSE(fold.empty());
        all.insert(fold.begin(), fold.end());
      }
      ASSERT_EQ(all.size(), n);
      for (unsigned int i = 0; i < n; ++i)
        EXPECT_EQ(all.count(i), 1u);
    }
  EXPECT_THROW(CV::folds(10, 1), vpSelfCalibException);
  EXPECT_THROW(CV::folds(10, 0), vpSelfCalibException);
  EXPECT_THROW(CV::folds(4, 5), vpSelfCalibException);
  EXPECT_THROW(CV::folds(5, 2), vpSelfCalibException); // holds out 3, leaves 2
  EXPECT_NO_THROW(CV::folds(4, 4));                    // holds out 1, leaves 3
  CV::Options o;
  o.folds = 1;
  EXPECT_THROW(o.check(), vpSelfCalibException);
}

// Noise-free, f known, without the kinematic prior (its pull toward nominal is not exact): each
// fold recovers the true robot from its training views, so the held-out views are predicted exactly
// (below 1e-6 px), while the nominal model misses them by pixels. The yardstick 3-D error of run()'s
// verification on the held-out views vanishes too.
TEST(CrossValidation, NoiseFreeBundleAdjustmentPredictsTheHeldOutViewsExactly)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 21, 0.0);
  const vpSelfCalibDataset ds = simulated(sim, 15);
  unsigned int stages = 0;
  CV::Options cvo;
  cvo.folds = 3;
  vpRobotSelfCalibration::Options exact;
  exact.trust_robot = true; // noise-free joints; the folds' exactness is the subject
  exact.bundle.kinematic_prior = vpKinematicBundleAdjustment::KINEMATIC_PRIOR_OFF;
  const CV::Result r = CV::run(sim.getNominalChain(), ds, exact, cvo,
                               [&](const std::string &, unsigned int, unsigned int) { ++stages; });
  EXPECT_GT(stages, 3u);
  ASSERT_EQ(r.fold.size(), 3u);
  EXPECT_EQ(r.views, 15u);
  EXPECT_EQ(r.num_ok, 3u);
  EXPECT_EQ(r.num_failed, 0u);
  for (const auto &f : r.fold) {
    ASSERT_EQ(f.status, vpRobotSelfCalibration::OK) << f.message;
    EXPECT_EQ(f.held_out.size(), 5u);
    // Every held-out observation compared: all 82 points are seen in every view.
    EXPECT_EQ(f.calibrated.observations, 5u * 82u);
    EXPECT_EQ(f.nominal.observations, 5u * 82u);
    EXPECT_LT(f.calibrated.rms, 1e-6);
    EXPECT_GT(f.nominal.rms, 1.0);
    EXPECT_TRUE(f.verified);
    EXPECT_LT(f.yardstick_error_calibrated, 1e-9);
  }
  EXPECT_LT(r.calibrated_rms.max, 1e-6);
  EXPECT_GT(r.nominal_rms.min, 1.0);
  EXPECT_EQ(r.calibrated_rms.count, 3u);
  EXPECT_LE(r.calibrated_rms.min, r.calibrated_rms.mean);
  EXPECT_GE(r.calibrated_rms.max, r.calibrated_rms.mean);
}

// Hand-eye on controller poses, noise-free, f self-calibrated: the predicted cameras are
// fMe eMc with the calibrated eMc and f, exact; the nominal eMc is 1 mm and 0.2 deg off.
TEST(CrossValidation, NoiseFreeHandEyePredictsTheHeldOutViewsExactly)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 22, 0.0);
  vpSelfCalibDataset ds = withControllerPoses(sim, simulated(sim, 10));
  ds.focal_known = false;
  vpRobotSelfCalibration::Options o;
  o.method = vpRobotSelfCalibration::HAND_EYE;
  CV::Options cvo;
  cvo.folds = 2;
  const CV::Result r = CV::run(sim.getNominalChain(), ds, o, cvo);
  ASSERT_EQ(r.num_ok, 2u) << r.message << " / " << r.fold[0].message << " / " << r.fold[1].message;
  for (const auto &f : r.fold) {
    EXPECT_NEAR(f.fx, 1500, 1e-6);
    EXPECT_LT(f.calibrated.rms, 1e-6);
    EXPECT_GT(f.nominal.rms, 1.0);
  }
}

/*
  0.2 px of noise per coordinate, three seeds, 25 views in 5 folds (20 training views). A held-out
  pixel's error is its own noise (2-D RMS sqrt(2) 0.2 = 0.283 px) plus the error of its point,
  triangulated from 20 training views (its projection about sqrt(2) 0.2 / sqrt(20): RMS factor
  sqrt(1 + 1/20), 0.290 px), plus the calibrated model's error on views it did not see. The true
  robot on the same folds (the oracle) measures the first two: the calibrated model may add little
  to it, at most 10 % (a model error of 0.46 times the rest would fail). Over 5 x 82 observations
  per fold the RMS has a relative sd of about 1 / sqrt(2 x 410) = 3.5 %: the calibrated RMS lies
  between 0.9 and 1.2 times the noise's 0.283 px, its sd over folds below 10 % of it; the median of
  a 2-D Gaussian error's norm is sqrt(2 ln 2) 0.2 = 0.235 px: between 0.85 and 1.2 times that. The
  nominal model is pixels off: the calibrated RMS is below half of it. (With 10 training views the
  model's own error shows: 0.32-0.39 px.)
*/
TEST(CrossValidation, NoisyHeldOutErrorIsTheNoiseLevel)
{
  const double sigma = 0.2, rms_noise = std::sqrt(2.0) * sigma, median_noise = std::sqrt(2 * std::log(2.0)) * sigma;
  const unsigned int m = 25, k = 5;
  for (uint64_t seed : {31u, 32u, 33u}) {
    const vpSelfCalibSimulator sim = makeSim("viper850", seed, sigma);
    const vpSelfCalibDataset ds = simulated(sim, m);
    CV::Options cvo;
    cvo.folds = k;
    vpRobotSelfCalibration::Options o;
    o.trust_robot = true; // exact joints: the held-out image error is the subject
    const CV::Result r = CV::run(sim.getNominalChain(), ds, o, cvo);
    ASSERT_EQ(r.num_ok, k) << "seed " << seed << ": " << r.message;
    for (unsigned int f = 0; f < k; ++f) {
      const CV::Fold &fold = r.fold[f];
      std::vector<vpSelfCalibDataset::View> train, test;
      for (unsigned int i = 0; i < m; ++i)
        (i % k == f ? test : train).push_back(ds.views[i]);
      const CV::Reprojection oracle = CV::reprojection(sim.getTrueChain(), ds.cam, {}, false, train, test);
      EXPECT_GT(fold.calibrated.rms, 0.9 * rms_noise) << "seed " << seed;
      EXPECT_LT(fold.calibrated.rms, 1.2 * rms_noise) << "seed " << seed;
      EXPECT_LT(fold.calibrated.rms, 1.1 * oracle.rms) << "seed " << seed;
      EXPECT_GT(fold.calibrated.median, 0.85 * median_noise) << "seed " << seed;
      EXPECT_LT(fold.calibrated.median, 1.2 * median_noise) << "seed " << seed;
      EXPECT_LT(fold.calibrated.rms, 0.5 * fold.nominal.rms) << "seed " << seed;
    }
    EXPECT_GT(r.calibrated_rms.sd, 0.0);
    EXPECT_LT(r.calibrated_rms.sd, 0.1 * rms_noise);
  }
}

// The paper's procedure in every fold, noise-free with f known: its only error is the eq. 21
// approximation of the scale ratios (and 10 training views), so the held-out views are not exact,
// but every fold is closer than the nominal model, and on average by more than half.
TEST(CrossValidation, PaperMethodBeatsTheNominalModel)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 26, 0.0);
  const vpSelfCalibDataset ds = simulated(sim, 15);
  vpRobotSelfCalibration::Options o;
  o.method = vpRobotSelfCalibration::PAPER;
  CV::Options cvo;
  cvo.folds = 3;
  const CV::Result r = CV::run(sim.getNominalChain(), ds, o, cvo);
  ASSERT_EQ(r.num_ok, 3u) << r.message;
  for (const auto &f : r.fold)
    EXPECT_LT(f.calibrated.rms, f.nominal.rms);
  // Measured: 1.1 to 5.1 px against 9 to 12 px.
  EXPECT_LT(r.calibrated_rms.mean, 0.5 * r.nominal_rms.mean) << r.message;
}

// Folds that cannot calibrate (every pose the same: degenerate data) are counted with their
// status, not hidden, and no figure is made from them.
TEST(CrossValidation, FailedFoldsAreCountedWithTheirStatus)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 23, 0.2);
  vpSelfCalibDataset ds = simulated(sim, 8);
  for (auto &v : ds.views)
    v.q = ds.views[0].q;
  CV::Options cvo;
  cvo.folds = 2;
  const CV::Result r = CV::run(sim.getNominalChain(), ds, vpRobotSelfCalibration::Options(), cvo);
  ASSERT_EQ(r.fold.size(), 2u);
  EXPECT_EQ(r.num_failed, 2u);
  EXPECT_EQ(r.num_ok, 0u);
  EXPECT_EQ(r.calibrated_rms.count, 0u);
  for (const auto &f : r.fold) {
    EXPECT_EQ(f.status, vpRobotSelfCalibration::DEGENERATE_DATA);
    EXPECT_FALSE(f.message.empty());
  }
  EXPECT_NE(r.message.find("2 of 2 calibrations failed"), std::string::npos) << r.message;
}

// A calibration checked on a second dataset of the same robot: exact with the calibrated model
// (noise-free, without the kinematic prior), not with the nominal one; the yardstick 3-D error vanishes.
TEST(CrossValidation, SecondDatasetVerifiesTheCalibration)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 24, 0.0);
  const std::vector<vpColVector> q = sim.generateConfigurations(16);
  const vpSelfCalibDataset all = sim.makeDataset(q);
  vpSelfCalibDataset cal = all, held = all;
  cal.views.assign(all.views.begin(), all.views.begin() + 12);
  held.views.assign(all.views.begin() + 12, all.views.end());
  vpRobotSelfCalibration::Options o;
  o.num_calibration_poses = 12;
  o.bundle.kinematic_prior = vpKinematicBundleAdjustment::KINEMATIC_PRIOR_OFF;
  const auto r = vpRobotSelfCalibration::run(sim.getNominalChain(), cal, o);
  ASSERT_EQ(r.status, vpRobotSelfCalibration::OK) << r.message;
  const CV::HeldOut h = CV::verifyHeldOut(sim.getNominalChain(), cal, o, r, held);
  EXPECT_EQ(h.views, 4u);
  EXPECT_EQ(h.calibrated.observations, 4u * 82u);
  EXPECT_LT(h.calibrated.rms, 1e-6);
  EXPECT_GT(h.nominal.rms, 0.01);
  ASSERT_TRUE(h.has_yardstick);
  EXPECT_LT(h.yardstick_error_calibrated, 1e-9);
  EXPECT_GT(h.yardstick_error_nominal, 1e-6);
  held.views.resize(1);
  EXPECT_THROW(CV::verifyHeldOut(sim.getNominalChain(), cal, o, r, held), vpSelfCalibException);
}

// Caller mistakes throw before any work: too few views for k, a view the model cannot place.
TEST(CrossValidation, BadInputsThrow)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 25, 0.2);
  vpSelfCalibDataset ds = simulated(sim, 6);
  CV::Options cvo;
  cvo.folds = 7;
  EXPECT_THROW(CV::run(sim.getNominalChain(), ds, vpRobotSelfCalibration::Options(), cvo), vpSelfCalibException);
  cvo.folds = 1;
  EXPECT_THROW(CV::run(sim.getNominalChain(), ds, vpRobotSelfCalibration::Options(), cvo), vpSelfCalibException);
  vpSelfCalibDataset bad = ds;
  bad.views[2].q = vpColVector(3);
  EXPECT_THROW(CV::reprojection(sim.getNominalChain(), ds.cam, {}, false, bad.views, ds.views), vpSelfCalibException);
  cvo.folds = 2;
  EXPECT_THROW(CV::run(sim.getNominalChain(), bad, vpRobotSelfCalibration::Options(), cvo), vpSelfCalibException);
}

// The report of a run on every view with its cross-validation: no held-out view, so no figure of
// the held-out views is linked and report.md says why; the cross-validation section has one row
// per fold with the figures of the result.
TEST(CrossValidation, ReportHasTheFoldsAndNoEmptyFigure)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 27, 0.2);
  const vpSelfCalibDataset ds = simulated(sim, 9);
  vpRobotSelfCalibration::Options o;
  o.num_calibration_poses = 9;
  o.trust_robot = true; // exact joints; the report's sections are the subject, not the robot's error
  const auto r = vpRobotSelfCalibration::run(sim.getNominalChain(), ds, o);
  ASSERT_EQ(r.status, vpRobotSelfCalibration::OK) << r.message;
  CV::Options cvo;
  cvo.folds = 3;
  const CV::Result cv = CV::run(sim.getNominalChain(), ds, o, cvo);
  ASSERT_EQ(cv.num_ok, 3u) << cv.message;
  char dir[] = "/tmp/selfcalib-cv-report-XXXXXX";
  ASSERT_NE(mkdtemp(dir), nullptr);
  vpSelfCalibReport::Options ro;
  ro.gnuplot = "/nonexistent/gnuplot";
  vpSelfCalibReport::Record run(sim.getNominalChain(), ds, o, r);
  run.cross_validation = &cv;
  vpSelfCalibReport::write(dir, run, ro);
  std::ifstream md(std::string(dir) + "/report.md");
  const std::string text((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("No view was held out: all 9 views calibrate"), std::string::npos) << text;
  EXPECT_EQ(text.find("](verification.png)"), std::string::npos);
  EXPECT_EQ(text.find("](errors_vs_poses.png)"), std::string::npos);
  EXPECT_NE(text.find("## Cross-validation"), std::string::npos);
  // Each fold's row has its figures, a doubtful fold's too (6 views of these 9 can be: their
  // figures are in the means; a doubtful fold's status is followed by its message).
  for (unsigned int f = 0; f < 3; ++f) {
    ASSERT_TRUE(cv.fold[f].status == vpRobotSelfCalibration::OK || cv.fold[f].status == vpRobotSelfCalibration::DOUBTFUL);
    std::ostringstream head, figures;
    head << "| " << f + 1 << " | " << f + 1 << " " << f + 4 << " " << f + 7 << " | "
         << vpRobotSelfCalibration::statusName(cv.fold[f].status);
    figures << " | " << std::fixed << std::setprecision(3) << cv.fold[f].fx << " | " << cv.fold[f].calibrated.rms
            << " | " << cv.fold[f].nominal.rms << " |";
    const size_t at = text.find(head.str());
    ASSERT_NE(at, std::string::npos) << head.str() << "\n" << text;
    const size_t end = text.find('\n', at);
    EXPECT_NE(text.substr(at, end - at).find(figures.str()), std::string::npos) << figures.str() << "\n" << text;
  }
}

/*
  A real lens (k1 = -0.3: its distortion polynomial folds back beyond r^2 = 1 / 0.9) and scene points
  the predicted camera has far outside its image (a wrong match, or a wrong nominal model's
  triangulation): they are not seen (counted in `outside`), and the held-out figure stays the one of
  the points in the image instead of the polynomial's value there (4e5 px at r = 5.6).
*/
TEST(CrossValidation, PointsOutsideTheLensModelAreNotSeen)
{
  const vpKinematicChain model = vpKinematicChain::fromPresetOrFile("viper850");
  const vpHomogeneousMatrix eMc = model.get_eMc_corrected();
  const std::vector<double> lens = {-0.3, 0, 0, 0, 0};
  const vpCameraParameters cam(800, 800, 640, 360); // 1280 x 720
  const double in[9] = {800, 1, 640, 360, -0.3, 0, 0, 0, 0};
  const vpSelfCalib::CameraModel camera(vpSelfCalib::Distortion::OPENCV, in);
  EXPECT_NEAR(camera.validRadius2(), 1 / 0.9, 1e-9);
  EXPECT_TRUE(std::isinf(vpSelfCalib::CameraModel::pinhole(800, 800, 640, 360).validRadius2()));
  const double positive[9] = {800, 1, 640, 360, 0.1, 0.05, 0, 0, 0};
  EXPECT_TRUE(std::isinf(vpSelfCalib::CameraModel(vpSelfCalib::Distortion::OPENCV, positive).validRadius2()));

  vpSelfCalib::Random rng(7, 1);
  // A view whose camera is at fMc, seeing the grid on the plane z = 2 through the lens (0.2 px noise).
  std::vector<Eigen::Vector3d> scene;
  for (int i = -4; i <= 4; ++i)
    for (int j = -3; j <= 3; ++j)
      scene.emplace_back(0.1 * i, 0.1 * j, 2.0);
  const auto view = [&](const vpHomogeneousMatrix &fMc) { return lensView(fMc, eMc, scene, camera, rng); };
  const std::vector<vpSelfCalibDataset::View> train = {view(vpHomogeneousMatrix(-0.2, 0, 0, 0, 0, 0)),
                                                       view(vpHomogeneousMatrix(0.2, 0, 0, 0, 0, 0)),
                                                       view(vpHomogeneousMatrix(0, 0.2, 0, 0, 0, 0))};
  const vpSelfCalibDataset::View inside = view(vpHomogeneousMatrix(0.05, 0.03, 0, 0, 0, 0));
  const CV::Reprojection seen = CV::reprojection(model, cam, lens, true, train, {inside});
  ASSERT_EQ(seen.observations, scene.size());
  EXPECT_EQ(seen.outside, 0u);
  EXPECT_LT(seen.rms, 0.5);
  // A camera turned 80 degrees: the grid in front of it at r up to 6, observed (wrongly) in its image.
  vpSelfCalibDataset::View turned = inside;
  turned.fMe = vpHomogeneousMatrix(0, 0, 0, 0, 80 * M_PI / 180, 0) * eMc.inverse();
  for (auto &o : turned.points)
    o.ip = vpImagePoint(rng.uniform(0, 720), rng.uniform(0, 1280));
  const CV::Reprojection both = CV::reprojection(model, cam, lens, true, train, {inside, turned});
  EXPECT_GT(both.outside, scene.size() / 2);
  EXPECT_EQ(both.observations + both.outside + both.behind, 2 * scene.size());
  ASSERT_TRUE(std::isfinite(both.rms));
  EXPECT_LT(both.rms, 2 * seen.rms);
  EXPECT_LT(both.median, 2 * seen.median);

  // As the folds call it (the image's size given, so its margin applies too), through the model
  // and through one whose eMc is 1 mm and 0.2 deg off (a nominal model): both figures finite and
  // within 2x of their in-image figures.
  vpKinematicChain off = model;
  off.set_eMc(vpPoseVector(eMc * vpHomogeneousMatrix(1e-3, 0, 0, 0, 0.2 * M_PI / 180, 0)));
  for (const vpKinematicChain *m : std::vector<const vpKinematicChain *>{&model, &off}) {
    const CV::Reprojection in_image = CV::reprojection(*m, cam, lens, true, train, {inside}, 1280, 720);
    const CV::Reprojection with_far = CV::reprojection(*m, cam, lens, true, train, {inside, turned}, 1280, 720);
    ASSERT_GT(in_image.observations, 0u);
    EXPECT_GT(with_far.outside, scene.size() / 2);
    ASSERT_TRUE(std::isfinite(with_far.rms) && std::isfinite(with_far.median));
    EXPECT_LT(with_far.rms, 2 * in_image.rms) << (m == &off ? "nominal" : "calibrated");
    EXPECT_LT(with_far.median, 2 * in_image.median) << (m == &off ? "nominal" : "calibrated");
  }
}

// The image and its margin (k1 = -0.3, 1280 x 720, p_x 1600): a point inside the polynomial's
// monotonic range (r^2 < 1 / 0.9) whose undistorted pixel lies more than the margin outside the
// image is not seen once the camera is told its image; a pinhole camera still sees it (its model
// holds everywhere). In the cross-validation, exactly the held-out observations whose predicted
// undistorted pixel lies beyond the image and its margin are counted outside, not compared.
TEST(CrossValidation, PointsOutsideTheImageAndItsMarginAreNotSeen)
{
  const double in[9] = {1600, 1, 640, 360, -0.3, 0, 0, 0, 0};
  const vpSelfCalib::CameraModel lens(vpSelfCalib::Distortion::OPENCV, in);
  const vpSelfCalib::CameraModel framed = lens.withImage(1280, 720); // margin 320 px
  ASSERT_NEAR(lens.validRadius2(), 1 / 0.9, 1e-9);
  const Eigen::Vector3d near_edge(0.59, 0.42, 1), beyond_u(0.61, 0, 1), beyond_v(0, 0.43, 1), left(-0.61, 0, 1);
  for (const Eigen::Vector3d &X : {near_edge, beyond_u, beyond_v, left})
    EXPECT_TRUE(lens.sees(X)); // inside the polynomial's range: the old rule sees them all
  EXPECT_TRUE(framed.sees(near_edge)); // u = 1584, v = 1032: within 1600 and 1040
  EXPECT_FALSE(framed.sees(beyond_u)); // u = 1616
  EXPECT_FALSE(framed.sees(beyond_v)); // v = 1048
  EXPECT_FALSE(framed.sees(left));     // u = -336
  EXPECT_FALSE(framed.sees(Eigen::Vector3d(0.1, 0, -1))); // behind
  const vpSelfCalib::CameraModel tight = lens.withImage(1280, 720, 0);
  EXPECT_TRUE(tight.sees(Eigen::Vector3d(0.39, 0, 1)));  // u = 1264
  EXPECT_FALSE(tight.sees(Eigen::Vector3d(0.41, 0, 1))); // u = 1296
  const vpSelfCalib::CameraModel pin = vpSelfCalib::CameraModel::pinhole(1600, 1600, 640, 360).withImage(1280, 720);
  EXPECT_TRUE(pin.sees(Eigen::Vector3d(5, 3, 1)));

  const vpKinematicChain model = vpKinematicChain::fromPresetOrFile("viper850");
  const vpHomogeneousMatrix eMc = model.get_eMc_corrected();
  const std::vector<double> coefficients = {-0.3, 0, 0, 0, 0};
  const vpCameraParameters cam(1600, 1600, 640, 360);
  std::vector<Eigen::Vector3d> scene;
  for (int i = -4; i <= 4; ++i)
    for (int j = -3; j <= 3; ++j)
      scene.emplace_back(0.05 * i, 0.05 * j, 2.0);
  vpSelfCalib::Random rng(11, 1);
  const auto view = [&](const vpHomogeneousMatrix &fMc) { return lensView(fMc, eMc, scene, lens, rng); };
  const std::vector<vpSelfCalibDataset::View> train = {view(vpHomogeneousMatrix(-0.2, 0, 0, 0, 0, 0)),
                                                       view(vpHomogeneousMatrix(0.2, 0, 0, 0, 0, 0)),
                                                       view(vpHomogeneousMatrix(0, 0.2, 0, 0, 0, 0))};
  // A camera turned 28 degrees about y: the grid at |x / z| from about 0.43 to 0.65, part of it
  // beyond u = 1600; its pixels observed wrongly (anywhere in the image).
  const vpHomogeneousMatrix fMc_turned(0, 0, 0, 0, -28 * M_PI / 180, 0);
  vpSelfCalibDataset::View turned = view(fMc_turned);
  for (auto &o : turned.points)
    o.ip = vpImagePoint(rng.uniform(0, 720), rng.uniform(0, 1280));
  const vpSelfCalib::Rigid cMf = vpSelfCalib::rigidFromVisp(fMc_turned).inverse();
  unsigned int beyond = 0;
  for (const Eigen::Vector3d &X : scene) {
    const Eigen::Vector3d Xc = cMf * X;
    const double u = 640 + 1600 * Xc(0) / Xc(2), v = 360 + 1600 * Xc(1) / Xc(2);
    ASSERT_LT(Xc.head<2>().squaredNorm() / (Xc(2) * Xc(2)), 1 / 0.9);
    beyond += u < -320 || u > 1600 || v < -320 || v > 1040;
  }
  ASSERT_GT(beyond, 5u);
  ASSERT_LT(beyond, scene.size() - 5);
  const CV::Reprojection unframed = CV::reprojection(model, cam, coefficients, true, train, {turned});
  const CV::Reprojection image = CV::reprojection(model, cam, coefficients, true, train, {turned}, 1280, 720);
  EXPECT_EQ(unframed.outside, 0u);
  EXPECT_EQ(image.outside, beyond);
  EXPECT_EQ(image.observations + beyond, unframed.observations);
  // Without distortion the image's size changes nothing.
  const CV::Reprojection pinhole = CV::reprojection(model, cam, {}, true, train, {turned}, 1280, 720);
  EXPECT_EQ(pinhole.outside, 0u);
  EXPECT_EQ(pinhole.observations, scene.size());
}

// A camera fixed in the world (eye-to-hand), the hand-eye method, noise-free: the target's points
// triangulated in its frame from the training views' cameras oMc = (bMe eMo)^-1 bMc reproject into
// every held-out view exactly; the nominal figure (the fold's bMc and eMo, the dataset's camera)
// is the calibrated one, hand-eye calibrating no kinematics and the focal length known.
TEST(CrossValidation, EyeToHandNoiseFreeHandEyePredictsTheHeldOutViewsExactly)
{
  vpSelfCalibSimulator::EyeToHandOptions so;
  so.num_views = 10;
  so.pixel_noise_sd = 0;
  vpSelfCalibSimulator::EyeToHandTruth truth;
  const vpSelfCalibDataset ds = vpSelfCalibSimulator::simulateEyeToHand(so, truth);
  vpRobotSelfCalibration::Options o;
  o.method = vpRobotSelfCalibration::HAND_EYE;
  o.trust_robot = true;
  o.bundle.known_points = truth.layout;
  const CV::Result r = CV::run(vpKinematicChain::preset("viper850"), ds, o, CV::Options());
  ASSERT_EQ(r.num_ok, 5u) << r.message;
  for (const CV::Fold &f : r.fold) {
    EXPECT_EQ(f.calibrated.observations, 2 * truth.layout.size()) << f.message;
    EXPECT_LT(f.calibrated.rms, 1e-5);
    EXPECT_NEAR(f.nominal.rms, f.calibrated.rms, 1e-9);
  }
}

/*
  A camera fixed in the world, the full kinematics method: a UR5 with errors of 3 mm / 3 mrad on every
  joint placement (an arm never calibrated) carries the board, exact joint readings, 0.2 px of image noise, 20 views. Each fold's
  held-out RMS is the noise's sqrt(2) sigma plus the fold model's own error (16 training views):
  from 0.9 to 1.6 times the noise; the nominal kinematics (with the fold's bMc and eMo) miss by the
  robot's errors: 3 times the calibrated figure or more, on every fold of 2 seeds.
*/
TEST(CrossValidation, EyeToHandHeldOutErrorIsTheNoiseLevel)
{
  const double sigma = 0.2, rms_noise = std::sqrt(2.0) * sigma;
  for (unsigned int seed : {3u, 4u}) {
    vpSelfCalibSimulator::EyeToHandOptions so;
    so.seed = seed;
    so.robot = "ur5";
    so.home = vpColVector({0, -1.0, 1.2, -0.2, 1.2, 0});
    so.num_views = 20;
    so.pixel_noise_sd = sigma;
    so.robot_translation_sd = so.robot_rotation_sd = 3e-3;
    vpSelfCalibSimulator::EyeToHandTruth truth;
    vpSelfCalibDataset ds = vpSelfCalibSimulator::simulateEyeToHand(so, truth);
    for (auto &v : ds.views)
      v.has_fMe = false;
    vpRobotSelfCalibration::Options o;
    o.method = vpRobotSelfCalibration::BUNDLE_ADJUSTMENT;
    o.bundle.known_points = truth.layout;
    o.noise.pixel_sd = sigma;
    const CV::Result r = CV::run(vpKinematicChain::preset("ur5"), ds, o, CV::Options());
    ASSERT_EQ(r.num_ok, 5u) << "seed " << seed << ": " << r.message;
    for (const CV::Fold &f : r.fold) {
      EXPECT_GT(f.calibrated.rms, 0.9 * rms_noise) << "seed " << seed;
      EXPECT_LT(f.calibrated.rms, 1.6 * rms_noise) << "seed " << seed;
      EXPECT_GT(f.nominal.rms, 3 * f.calibrated.rms) << "seed " << seed;
    }
  }
}

/*
  Folds started from the run on every view (its eMc, points, focal length and measured noise) give
  the folds from scratch: noise-free, the held-out views exactly; at 0.2 px with 0.5 mm / 0.5 mrad
  of controller pose error, over two seeds, every fold's held-out RMS within 3 of its own sampling
  sd (RMS / sqrt(2 x observations)) of the fold from scratch and its focal length within 3 of the
  full run's sd of it; each fold says it started from the earlier run.
*/
TEST(CrossValidation, FoldsFromTheFullRunGiveTheFoldsFromScratch)
{
  vpRobotSelfCalibration::Options o;
  o.method = vpRobotSelfCalibration::HAND_EYE;
  CV::Options cvo;
  cvo.folds = 3;
  {
    const vpSelfCalibSimulator sim = makeSim("viper850", 22, 0.0);
    vpSelfCalibDataset ds = withControllerPoses(sim, simulated(sim, 9));
    ds.focal_known = false;
    vpRobotSelfCalibration::Options all = o;
    all.num_calibration_poses = 9;
    const vpRobotSelfCalibration::Result full = vpRobotSelfCalibration::run(sim.getNominalChain(), ds, all);
    ASSERT_EQ(full.status, vpRobotSelfCalibration::OK) << full.message;
    const CV::Result warm = CV::run(sim.getNominalChain(), ds, o, cvo, full);
    ASSERT_EQ(warm.num_ok, 3u) << warm.message;
    for (const auto &f : warm.fold) {
      EXPECT_NE(f.message.find("start from an earlier run"), std::string::npos) << f.message;
      EXPECT_NEAR(f.fx, 1500, 1e-6);
      EXPECT_LT(f.calibrated.rms, 1e-6);
      EXPECT_GT(f.nominal.rms, 0.5); // the nominal eMc: 1 mm and 0.2 deg off
    }
  }
  for (uint64_t seed : {41u, 42u}) {
    const vpSelfCalibSimulator sim = makeSim("viper850", seed, 0.2);
    vpSelfCalibDataset ds = simulated(sim, 12);
    toControllerPoses(sim, ds, 5e-4, 5e-4, seed, 7);
    ds.focal_known = false;
    vpRobotSelfCalibration::Options all = o;
    all.num_calibration_poses = 12;
    const vpRobotSelfCalibration::Result full = vpRobotSelfCalibration::run(sim.getNominalChain(), ds, all);
    ASSERT_EQ(full.status, vpRobotSelfCalibration::OK) << full.message;
    const CV::Result scratch = CV::run(sim.getNominalChain(), ds, o, cvo);
    const CV::Result warm = CV::run(sim.getNominalChain(), ds, o, cvo, full);
    ASSERT_EQ(scratch.num_ok, 3u) << "seed " << seed << ": " << scratch.message;
    ASSERT_EQ(warm.num_ok, 3u) << "seed " << seed << ": " << warm.message;
    for (unsigned int f = 0; f < 3; ++f) {
      const CV::Fold &a = warm.fold[f], &b = scratch.fold[f];
      EXPECT_NE(a.message.find("start from an earlier run"), std::string::npos) << a.message;
      EXPECT_EQ(a.calibrated.observations + a.calibrated.behind + a.calibrated.outside,
                b.calibrated.observations + b.calibrated.behind + b.calibrated.outside);
      const double sampling = b.calibrated.rms / std::sqrt(2.0 * b.calibrated.observations);
      EXPECT_LE(std::abs(a.calibrated.rms - b.calibrated.rms), 3 * sampling)
          << "seed " << seed << ", fold " << f << ": " << a.calibrated.rms << " vs " << b.calibrated.rms;
      EXPECT_EQ(a.nominal.rms, b.nominal.rms);
      EXPECT_LE(std::abs(a.fx - full.fx), 3 * full.fx_sd) << "seed " << seed << ", fold " << f;
    }
  }
}
