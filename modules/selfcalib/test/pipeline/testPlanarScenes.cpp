/*
 * Planar scenes through the whole pipeline (hand-eye method): one plane seen at several tilts
 * determines eMc and f (as in Zhang's calibration), with a real lens (OpenCV's distortion) known or
 * estimated; the errors stay within the Cramér-Rao bound of the same data over several seeds.
 */
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <visp3/selfcalib/vpCalibrationVerifier.h>
#include <visp3/selfcalib/vpKinematicBundleAdjustment.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "../testCommon.h"
#include "../testPlaneDraws.h"
#include "core/vpSelfCalibCamera.h"
#include "core/vpSelfCalibMath.h"
#include "core/vpSelfCalibRandom.h"
#include "pipeline/vpSelfCalibMultiViewFit.h"

using namespace selfcalib_test;
using namespace vpSelfCalib;

namespace
{
const double kLens[9] = {800, 1.0, 330, 236, -0.21, 0.09, 0.0012, -0.0015, 0};

struct PlaneData {
  vpSelfCalibDataset ds;
  std::map<int, vpColVector> X; //!< the plane's points (f)
};

/*
  A 11 x 11 grid (6 cm pitch) on the plane z = 1 m of f, seen by the true camera from 12 tilted
  poses; hand-eye data (controller poses exact), pixels through the lens with `sd` px of noise. The
  yardstick is the grid's first row ends (0.6 m).
*/
PlaneData tiltedPlane(const vpSelfCalibSimulator &sim, const CameraModel &lens, double sd, uint64_t seed)
{
  PlaneData p;
  for (int i = 0; i < 11; ++i)
    for (int j = 0; j < 11; ++j)
      p.X[11 * i + j] = vpColVector({-0.3 + 0.06 * i, -0.3 + 0.06 * j, 1.0});
  Random rng(seed, 3);
  const vpHomogeneousMatrix cMe = sim.getTrueChain().get_eMc_corrected().inverse();
  p.ds.width = 640;
  p.ds.height = 480;
  p.ds.cam.initPersProjWithoutDistortion(lens.px(), lens.py(), lens.u0(), lens.v0());
  p.ds.robot = "viper850";
  for (int k = 0; k < 12; ++k) {
    const vpHomogeneousMatrix fMc(0.04 * (k % 3 - 1), 0.04 * ((k / 3) % 3 - 1), 0.08 * (k % 2), 0.3 * ((k % 3) - 1),
                                  0.3 * ((k / 3) % 3 - 1) + 0.1 * (k % 2), 0.45 * k);
    vpSelfCalibDataset::View v;
    v.has_fMe = true;
    v.fMe = fMc * cMe;
    const Rigid cMf = rigidFromVisp(fMc).inverse();
    for (const auto &e : p.X) {
      const Eigen::Vector2d uv = lens.project(cMf * vec3(e.second));
      const double u = uv(0) + rng.normal(sd), w = uv(1) + rng.normal(sd);
      if (u > 0 && u < 640 && w > 0 && w < 480)
        v.points.push_back({e.first, vpImagePoint(w, u)});
    }
    p.ds.views.push_back(v);
  }
  p.ds.yardstick.length = 0.6;
  p.ds.yardstick.id_a = 0;
  p.ds.yardstick.id_b = 10;
  return p;
}

vpRobotSelfCalibration::Options handEye(bool focal_known)
{
  vpRobotSelfCalibration::Options o;
  o.method = vpRobotSelfCalibration::HAND_EYE;
  o.num_calibration_poses = 12;
  o.trust_robot = true; // the controller poses are exact: the intrinsics are the subject
  o.focal_mode = focal_known ? vpRobotSelfCalibration::FOCAL_KNOWN : vpRobotSelfCalibration::FOCAL_SHARED;
  return o;
}

//! The eMc correction of the estimate minus the truth's, and its reported sd.
void eMcError(const vpSelfCalibSimulator &sim, const vpRobotSelfCalibration::Result &r, double e[6], double sd[6])
{
  const unsigned int first = r.calibrated.getNumParameters() - vpKinematicChain::kBlockSize;
  for (unsigned int i = 0; i < 6; ++i) {
    e[i] = r.calibrated.getParameters()[first + i] - sim.getTrueChain().getParameters()[first + i];
    sd[i] = r.parameter_sd[first + i];
  }
}
} // namespace

/*
  f self-calibrated from a tilted plane, OpenCV lens known (the dataset's coefficients, pixels as
  measured): over 6 seeds at 0.2 px, f and the 6 eMc components within 3.5 of the Cramér-Rao sd
  (information() at the truth), and the normalized error (RMS of error / CRB sd) below 1.5.
  Noise-free: exact.
*/
TEST(PlanarScene, HandEyeFocalSelfCalibratedWithAKnownLensWithinItsBound)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 91, 0.0);
  const CameraModel lens(Distortion::OPENCV, kLens);
  const std::vector<double> k(kLens + 4, kLens + 9);
  {
    PlaneData p = tiltedPlane(sim, lens, 0.0, 90);
    p.ds.opencv_distortion = k;
    p.ds.focal_known = false;
    vpRobotSelfCalibration::Options o = handEye(false);
    o.bundle.tight = true;
    const auto r = vpRobotSelfCalibration::run(sim.getNominalChain(), p.ds, o);
    ASSERT_EQ(r.status, vpRobotSelfCalibration::OK) << r.message;
    EXPECT_NEAR(r.camera.get_px(), kLens[0], 1e-6);
    double e[6], sd[6];
    eMcError(sim, r, e, sd);
    for (int i = 0; i < 6; ++i)
      EXPECT_NEAR(e[i], 0, 1e-8) << i;
  }
  // The bound: information() at the truth, on the undistorted noise-free pixels (the lens known).
  PlaneData clean = tiltedPlane(sim, lens.withoutDistortion(), 0.0, 90);
  vpKinematicBundleAdjustment::Options bo;
  bo.hand_eye_only = true;
  bo.intrinsics = vpKinematicBundleAdjustment::FX;
  const auto crb = vpKinematicBundleAdjustment::information(sim.getTrueChain(), clean.ds.cam, clean.ds.views,
                                                            clean.ds.yardstick, clean.X, bo, vpSelfCalibNoiseModel());
  ASSERT_TRUE(crb.has_covariance) << crb.message;
  const unsigned int first = sim.getTrueChain().getNumParameters() - vpKinematicChain::kBlockSize;
  double nsq = 0;
  int n = 0;
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    PlaneData p = tiltedPlane(sim, lens, 0.2, seed);
    p.ds.opencv_distortion = k;
    p.ds.focal_known = false;
    // A first guess twice the truth (as the image width is for a wide lens): the start comes from
    // where the predicted rays meet, not from the guess.
    p.ds.cam.initPersProjWithoutDistortion(2 * kLens[0], 2 * kLens[0], kLens[2], kLens[3]);
    const auto r = vpRobotSelfCalibration::run(sim.getNominalChain(), p.ds, handEye(false));
    ASSERT_EQ(r.status, vpRobotSelfCalibration::OK) << seed << ": " << r.message;
    const double ef = (r.camera.get_px() - kLens[0]) / crb.fx_sd;
    EXPECT_LT(std::abs(ef), 3.5) << seed;
    nsq += ef * ef;
    ++n;
    double e[6], sd[6];
    eMcError(sim, r, e, sd);
    for (unsigned int i = 0; i < 6; ++i) {
      const double z = e[i] / crb.sd[first + i];
      EXPECT_LT(std::abs(z), 3.5) << seed << " eMc component " << i;
      nsq += z * z;
      ++n;
    }
  }
  EXPECT_LT(std::sqrt(nsq / n), 1.5);
}

/*
  Nominal intrinsics (f 6 % off, principal point 12 px off, no distortion): f, the principal point
  and OpenCV's k1, k2, p1, p2 estimated with eMc from the tilted plane. Noise-free: exact. At 0.2 px
  over 4 seeds: each within 3.5 of its reported sd, and the reported sd of the principal point and of
  k1 are given (written as intrinsics with their sd).
*/
TEST(PlanarScene, HandEyeNominalIntrinsicsLensAndPrincipalPointEstimated)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 92, 0.0);
  const CameraModel lens(Distortion::OPENCV, kLens);
  vpRobotSelfCalibration::Options o = handEye(false);
  o.bundle.intrinsics = vpKinematicBundleAdjustment::FX | vpKinematicBundleAdjustment::PRINCIPAL_POINT |
                       vpKinematicBundleAdjustment::DISTORTION;
  o.bundle.distortion_model = vpKinematicBundleAdjustment::DISTORTION_OPENCV;
  for (uint64_t seed = 0; seed <= 4; ++seed) {
    PlaneData p = tiltedPlane(sim, lens, seed == 0 ? 0.0 : 0.2, seed + 20);
    p.ds.focal_known = false;
    p.ds.cam.initPersProjWithoutDistortion(0.94 * kLens[0], 0.94 * kLens[0], 320, 248);
    vpRobotSelfCalibration::Options oo = o;
    oo.bundle.tight = seed == 0;
    const auto r = vpRobotSelfCalibration::run(sim.getNominalChain(), p.ds, oo);
    ASSERT_EQ(r.status, vpRobotSelfCalibration::OK) << seed << ": " << r.message;
    const auto &b = r.bundle;
    ASSERT_EQ(b.intrinsic_names, (std::vector<std::string>{"fx", "u0", "v0", "k1", "k2", "p1", "p2"}));
    const double truth[7] = {kLens[0], kLens[2], kLens[3], kLens[4], kLens[5], kLens[6], kLens[7]};
    for (unsigned int i = 0; i < 7; ++i) {
      if (seed == 0)
        EXPECT_NEAR(b.intrinsics[i], truth[i], 1e-6 * std::max(1.0, std::abs(truth[i]))) << b.intrinsic_names[i];
      else
        EXPECT_LT(std::abs(b.intrinsics[i] - truth[i]), 3.5 * b.intrinsics_sd[i]) << seed << " " << b.intrinsic_names[i];
    }
    ASSERT_EQ(b.opencv_distortion.size(), 5u);
  }
}

/*
  Full kinematics on a plane (every point on one plane facing the robot's home view, the yardstick's
  ends on it; the configurations tilt the camera), f self-calibrated from a guess twice the truth.
  Over 3 seeds at 0.2 px: f within 3.5 of its reported sd, and the held-out relative camera
  positions' RMS error within 3x what the covariance predicts. (Without a yardstick the scale is the
  nominal one, an error the covariance does not hold: the held-out errors then exceed the
  prediction up to 46x on these seeds.)
*/
TEST(PlanarScene, FullKinematicsFocalSelfCalibratedOnAPlane)
{
  for (uint64_t seed : {31, 32, 33}) {
    const vpSelfCalibSimulator sim = makeSim("viper850", seed, 0.0);
    const std::vector<vpColVector> qs = sim.generateConfigurations(25);
    vpSelfCalibDataset ds = sim.makeDataset(qs);
    Random rng(seed, 5);
    const vpColVector c = sim.getSceneCentre();
    std::vector<vpColVector> X;
    for (int i = 0; i < 100; ++i) {
      vpColVector x = c;
      x[1] += 0.25 * rng.uniform(-0.5, 0.5);
      x[2] += 0.2 * rng.uniform(-0.5, 0.5);
      X.push_back(x);
    }
    for (double side : {-0.06, 0.06}) { // the yardstick's ends, on the plane: ids 100, 101
      vpColVector x = c;
      x[1] += side;
      X.push_back(x);
    }
    const vpCameraParameters cam = sim.getCamera();
    for (auto &v : ds.views) {
      const vpHomogeneousMatrix cMf = sim.getTrueChain().get_fMc(v.q).inverse();
      v.points.clear();
      for (size_t i = 0; i < X.size(); ++i) {
        const vpColVector p = cMf * vpColVector({X[i][0], X[i][1], X[i][2], 1.0});
        const double u = cam.get_u0() + cam.get_px() * p[0] / p[2] + rng.normal(0.2),
                     w = cam.get_v0() + cam.get_py() * p[1] / p[2] + rng.normal(0.2);
        if (p[2] > 0 && u >= 0 && w >= 0 && u < ds.width && w < ds.height)
          v.points.push_back({static_cast<int>(i), vpImagePoint(w, u)});
      }
    }
    ds.yardstick.length = 0.12;
    ds.yardstick.id_a = 100;
    ds.yardstick.id_b = 101;
    ds.focal_known = false;
    ds.cam.initPersProjWithoutDistortion(2 * cam.get_px(), 2 * cam.get_py(), cam.get_u0(), cam.get_v0());
    vpRobotSelfCalibration::Options o;
    o.method = vpRobotSelfCalibration::BUNDLE_ADJUSTMENT;
    o.focal_mode = vpRobotSelfCalibration::FOCAL_SHARED;
    o.trust_robot = true; // exact joints: the plane and f are the subject
    const auto r = vpRobotSelfCalibration::run(sim.getNominalChain(), ds, o);
    ASSERT_EQ(r.status, vpRobotSelfCalibration::OK) << seed << ": " << r.message;
    EXPECT_LT(std::abs(r.camera.get_px() - cam.get_px()), 3.5 * r.fx_sd) << seed << ": " << r.camera.get_px();
    // The held-out relative positions: their errors against what the covariance predicts (a plane
    // with f free and no yardstick determines the kinematics weakly; the sd must say so).
    const std::vector<vpSelfCalibDataset::View> held(ds.views.begin() + 15, ds.views.end());
    const std::vector<vpHomogeneousMatrix> truth = sim.getTrueCameraPoses(held);
    const auto v = vpCalibrationVerifier::verify(r.calibrated, r.camera, held, ds.yardstick, {}, truth);
    double e2 = 0, p2 = 0;
    for (size_t k = 1; k < held.size(); ++k) {
      const vpMatrix C = vpKinematicBundleAdjustment::relativePoseCovariance(
          r.calibrated, r.identifiability.identified, r.bundle.covariance, held[0].q, held[k].q);
      p2 += C[0][0] + C[1][1] + C[2][2];
      e2 += v.position_errors[k - 1] * v.position_errors[k - 1];
    }
    EXPECT_LT(std::sqrt(e2 / p2), 3.0) << seed << ": held-out rms " << std::sqrt(e2 / (held.size() - 1))
                                       << " m against a predicted " << std::sqrt(p2 / (held.size() - 1));
  }
}

/*
  The bundle method on a small planar board (ChArUco 7 x 5, 24 corners), its layout unknown: the
  Viper850 of seed 10, 14 calibration and 6 held-out poses. With 0.2 px of noise (the draw whose
  multi-view reconstruction kept a view on the wrong one of a plane's two motions: its start
  identification put eMc 1 m off and the bundle adjustment failed, rank deficient): ok, no
  observation dropped, the held-out relative positions within what the covariance predicts (RMS of
  error / predicted sd below 3). Noise-free (two-view motions undetermined on an exact plane: the
  start from the nominal model's poses): exact.
*/
TEST(PlanarScene, BundleMethodOnABoardWithItsLayoutUnknown)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 10, 0.0);
  const std::vector<vpColVector> q = sim.generateConfigurations(20);
  for (double sd : {0.0, 0.2}) {
    std::map<int, vpColVector> truth;
    const vpSelfCalibDataset ds = charucoBoardViews(sim, q, sd, 10, 4, truth);
    vpSelfCalibDataset cal = ds;
    cal.views.resize(14);
    vpRobotSelfCalibration::Options o;
    o.num_calibration_poses = 14;
    o.noise.pixel_sd = sd > 0 ? sd : 0.01;
    o.trust_robot = true; // exact joints: the board is the subject
    // Without the kinematic prior: noise-free, its pull toward nominal leaves residuals the robot-error
    // check takes for each camera's own displacement.
    o.bundle.kinematic_prior = vpKinematicBundleAdjustment::KINEMATIC_PRIOR_OFF;
    const vpRobotSelfCalibration::Result r = vpRobotSelfCalibration::run(sim.getNominalChain(), cal, o);
    ASSERT_EQ(r.status, vpRobotSelfCalibration::OK) << sd << ": " << r.message;
    EXPECT_EQ(r.bundle.num_outliers, 0u) << sd << ": " << r.message;
    double e2 = 0, p2 = 0;
    const vpColVector &h0 = ds.views[14].q;
    for (size_t k = 15; k < ds.views.size(); ++k) {
      const vpColVector &hk = ds.views[k].q;
      const vpHomogeneousMatrix m = r.calibrated.get_fMc(h0).inverse() * r.calibrated.get_fMc(hk);
      const vpHomogeneousMatrix t = sim.getTrueChain().get_fMc(h0).inverse() * sim.getTrueChain().get_fMc(hk);
      e2 += (m.getTranslationVector() - t.getTranslationVector()).sumSquare();
      const vpMatrix C = vpKinematicBundleAdjustment::relativePoseCovariance(
          r.calibrated, r.identifiability.identified, r.bundle.covariance, h0, hk);
      p2 += C[0][0] + C[1][1] + C[2][2];
    }
    if (sd == 0)
      EXPECT_LT(std::sqrt(e2 / 5), 1e-6) << "noise-free held-out rms (m)";
    else
      EXPECT_LT(std::sqrt(e2 / p2), 3.0) << "held-out rms " << std::sqrt(e2 / 5) << " m against a predicted "
                                         << std::sqrt(p2 / 5);
  }
}

/*
  A yardstick declared at the wrong length (a board's first row at a mistyped spacing, no layout
  given): the hand-eye method measures it against the robot's metric motion. Poses with 2 mm / 2 mrad
  of stated error, 0.2 px, 3 seeds: the right length (0.36 m) measures within 3.5 sd of 1 and is not
  doubted; 0.288 m (20 % too short) measures within 3.5 sd of 1.25 and is doubted
  (board-size-mismatch).
*/
TEST(PlanarScene, HandEyeMeasuresTheYardsticksLength)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 93, 0.0);
  const CameraModel lens = CameraModel(Distortion::OPENCV, kLens).withoutDistortion();
  auto hasFinding = [](const vpRobotSelfCalibration::Result &r, const std::string &code) {
    for (const auto &f : r.findings)
      if (f.code == code)
        return true;
    return false;
  };
  vpRobotSelfCalibration::Options o = handEye(true);
  o.noise.pose_sd_translation = o.noise.pose_sd_rotation = 0.002;
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    PlaneData p = tiltedPlane(sim, lens, 0.2, seed + 40);
    p.ds.yardstick = {0.36, 24, 30}; // inside the grid, seen in every view
    const auto right = vpRobotSelfCalibration::run(sim.getNominalChain(), p.ds, o);
    ASSERT_EQ(right.status, vpRobotSelfCalibration::OK) << seed << ": " << right.message;
    ASSERT_TRUE(right.bundle.has_layout_scale) << right.message;
    EXPECT_LT(std::fabs(right.bundle.layout_scale - 1), 3.5 * right.bundle.layout_scale_sd) << seed;
    EXPECT_FALSE(hasFinding(right, "board-size-mismatch")) << seed << ": " << right.message;
    p.ds.yardstick.length = 0.288;
    const auto wrong = vpRobotSelfCalibration::run(sim.getNominalChain(), p.ds, o);
    ASSERT_TRUE(wrong.bundle.has_layout_scale) << seed << ": " << wrong.message;
    EXPECT_LT(std::fabs(wrong.bundle.layout_scale - 1.25), 3.5 * wrong.bundle.layout_scale_sd) << seed;
    EXPECT_EQ(wrong.status, vpRobotSelfCalibration::DOUBTFUL) << seed << ": " << wrong.message;
    EXPECT_TRUE(hasFinding(wrong, "board-size-mismatch")) << seed << ": " << wrong.message;
  }
}

namespace
{
//! The largest |error| / sd of eMc's components (translation, theta-u) against the truth.
double eMcErrorInSd(const vpRobotSelfCalibration::Result &r, const vpSelfCalibSimulator &sim)
{
  const vpPoseVector t(sim.getTrueChain().get_eMc_corrected());
  double worst = 0;
  for (unsigned int i = 0; i < 6; ++i)
    worst = std::max(worst, std::fabs(r.eMc[i] - t[i]) / r.eMc_sd[i]);
  return worst;
}
} // namespace

/*
  The bundle method on a flat board of unknown layout given as points (24 ChArUco corners, 0.2 px,
  f known; bench-plane-scan's draws): the draws whose multi-view step ended bent from its two-view
  start, which then ended "ok" with eMc 180-230 sd off, and five other geometries. Every run ok,
  no "multiview-misfit", eMc within 4 sd of the truth in every component (the largest of six
  components: 3 sd is passed by chance in about one draw of sixty) and the held-out relative
  positions within 3 predicted sd (RMS).
*/
TEST(PlanarScene, BundleMethodOnAFlatBoardOfUnknownLayoutStaysRight)
{
  std::vector<std::pair<uint64_t, uint64_t>> draws = kBentDraws;
  for (uint64_t seed : {4, 5, 7, 8, 11})
    draws.emplace_back(seed, 0);
  for (const auto &d : draws) {
    const PlaneDraw p(d.first, d.second, 0.2);
    vpRobotSelfCalibration::Options o;
    o.num_calibration_poses = 14;
    o.noise.pixel_sd = 0.2;
    o.trust_robot = true; // exact joints: the board is the subject
    const vpRobotSelfCalibration::Result r = vpRobotSelfCalibration::run(p.sim.getNominalChain(), p.ds, o);
    const std::string draw = std::to_string(d.first) + "/" + std::to_string(d.second);
    // Draw 1/3 is better than the nominal model over the joint limits by little (5.1 mm / 7.9 mrad
    // against 6.6 / 8.6 against the truth), and what its views show leaves a chance of the contrary
    // above 10 %: doubtful by the workspace check alone, which is not the subject here.
    const auto workspace_doubt_only = [](const vpRobotSelfCalibration::Result &x) {
        return x.status == vpRobotSelfCalibration::DOUBTFUL &&
               std::all_of(x.findings.begin(), x.findings.end(), [](const auto &f) {
                 return f.severity != vpSelfCalibDataCheck::DOUBT || f.code == "workspace-worse-than-nominal";
               });
      };
    ASSERT_TRUE(r.status == vpRobotSelfCalibration::OK || workspace_doubt_only(r)) << draw << ": " << r.message;
    EXPECT_FALSE(vpSelfCalibPipeline::multiViewMisfit(r.multiview)) << draw;
    ASSERT_TRUE(r.has_eMc) << draw;
    EXPECT_LT(eMcErrorInSd(r, p.sim), 4.0) << draw;
    double e2 = 0, p2 = 0;
    for (size_t k = 1; k < p.held.size(); ++k) {
      const vpHomogeneousMatrix m = r.calibrated.get_fMc(p.held[0]).inverse() * r.calibrated.get_fMc(p.held[k]);
      const vpHomogeneousMatrix t =
          p.sim.getTrueChain().get_fMc(p.held[0]).inverse() * p.sim.getTrueChain().get_fMc(p.held[k]);
      e2 += (m.getTranslationVector() - t.getTranslationVector()).sumSquare();
      const vpMatrix C = vpKinematicBundleAdjustment::relativePoseCovariance(
          r.calibrated, r.identifiability.identified, r.bundle.covariance, p.held[0], p.held[k]);
      p2 += C[0][0] + C[1][1] + C[2][2];
    }
    EXPECT_LT(std::sqrt(e2 / p2), 3.0) << draw;
  }
}

/*
  The workspace doubt against the truth on the flat board of unknown layout (bench-plane-scan's draws,
  calibrate's defaults, 14 views, 0.2 px; seeds 1, 2 and 5, six draws each): every model worse than
  the nominal one over the joint limits (the camera's motions, position or rotation) is doubtful,
  and at most 2 doubtful ones are clearly better (both errors within two thirds of the nominal
  model's). Judged from the two models' errors apart, the chance of the calibrated model being the
  worse counted twice what both share: 16 of the 18 runs were doubtful, 11 of them clearly better,
  and a model worse in rotation (11.5 against 10.3 mrad) passed.
*/
TEST(PlanarScene, TheWorkspaceDoubtFollowsTheTruthOnAFlatBoard)
{
  unsigned int worse = 0, worse_passed = 0, clear_doubted = 0;
  for (uint64_t seed : {1, 2, 5})
    for (uint64_t d = 0; d < 6; ++d) {
      const PlaneDraw p(seed, d, 0.2);
      vpRobotSelfCalibration::Options o;
      o.num_calibration_poses = 14;
      o.noise.pixel_sd = 0.2;
      const vpRobotSelfCalibration::Result r = vpRobotSelfCalibration::run(p.sim.getNominalChain(), p.ds, o);
      const std::string draw = std::to_string(seed) + "/" + std::to_string(d);
      ASSERT_TRUE(r.status == vpRobotSelfCalibration::OK || r.status == vpRobotSelfCalibration::DOUBTFUL)
          << draw << ": " << r.message;
      ASSERT_TRUE(r.workspace.computed) << draw;
      const bool doubt = std::any_of(r.findings.begin(), r.findings.end(),
                                     [](const auto &f) { return f.code == "workspace-worse-than-nominal"; });
      const MotionRms cal = workspaceMotionError(r.calibrated, p.sim.getTrueChain());
      const MotionRms nom = workspaceMotionError(p.sim.getNominalChain(), p.sim.getTrueChain());
      const bool is_worse = cal.t > nom.t || cal.r > nom.r;
      worse += is_worse;
      EXPECT_TRUE(doubt || !is_worse) << draw << ": passed, worse than nominal: " << 1e3 * cal.t << " mm / "
                                      << 1e3 * cal.r << " mrad against " << 1e3 * nom.t << " / " << 1e3 * nom.r;
      worse_passed += is_worse && !doubt;
      clear_doubted += doubt && cal.t < 2.0 / 3 * nom.t && cal.r < 2.0 / 3 * nom.r;
    }
  EXPECT_GE(worse, 1u); // the draws hold a model worse than nominal: the check has something to catch
  EXPECT_EQ(worse_passed, 0u);
  EXPECT_LE(clear_doubted, 2u);
}

/*
  The assessment's multi-view misfit (a doubt, "multiview-misfit") needs both marks a reconstruction
  in a local minimum leaves, sigma0 far above its interval and observations rejected; each alone has
  an innocent cause that it must not doubt: a noise stated 3x too small (sigma0 about 3, nothing
  rejected: the outlier test runs at the measured noise) and 20 % wrong matches on a scene with depth
  at the stated noise (rejected, sigma0 within its interval). On the flat board with 10 % wrong
  matches (2-3 of each view's 24 corners) the reconstruction ends in a local minimum (views 14-26 deg
  off, sigma0 2.5-3.8 with 44-65 of 336 observations rejected over three corruptions): a misfit, and
  the calibration on it is not "ok".
*/
TEST(PlanarScene, MultiViewMisfitNeedsBothMarks)
{
  vpSelfCalibNoiseModel noise;
  noise.pixel_sd = 0.2;
  const auto reconstruct = [&](const vpSelfCalibDataset &ds) {
    return vpMultiViewReconstruction::reconstruct(ds.views, ds.yardstick,
                                                  vpRobotSelfCalibration::multiViewOptions({}, ds), noise);
  };
  const PlaneDraw right(4, 0, 0.2), noisy(4, 0, 0.6);
  const vpMultiViewReconstruction::Result r = reconstruct(right.ds);
  ASSERT_EQ(r.status, vpMultiViewReconstruction::OK) << r.message;
  EXPECT_FALSE(vpSelfCalibPipeline::multiViewMisfit(r));

  const vpMultiViewReconstruction::Result understated = reconstruct(noisy.ds);
  ASSERT_EQ(understated.status, vpMultiViewReconstruction::OK) << understated.message;
  EXPECT_GT(understated.sigma0, vpSelfCalibPipeline::kMultiViewSigma0Factor * understated.sigma0_high);
  EXPECT_FALSE(vpSelfCalibPipeline::multiViewMisfit(understated)) << understated.message;

  const vpSelfCalibSimulator sim = makeSim("viper850", 4, 0.2);
  vpSelfCalibDataset depth = sim.makeDataset(sim.generateConfigurations(10));
  corrupt(depth, 0.2, 4, 77);
  const vpMultiViewReconstruction::Result matches = reconstruct(depth);
  ASSERT_EQ(matches.status, vpMultiViewReconstruction::OK) << matches.message;
  EXPECT_GT(matches.num_outliers, vpSelfCalibPipeline::kMultiViewRejected * (matches.num_observations + matches.num_outliers));
  EXPECT_LE(matches.sigma0, matches.sigma0_high);
  EXPECT_FALSE(vpSelfCalibPipeline::multiViewMisfit(matches)) << matches.message;

  vpSelfCalibDataset wrong = right.ds;
  corrupt(wrong, 0.1, 4, 11);
  const vpMultiViewReconstruction::Result bent = reconstruct(wrong);
  ASSERT_EQ(bent.status, vpMultiViewReconstruction::OK) << bent.message;
  EXPECT_GT(right.worstRotation(bent), 5 * M_PI / 180);
  EXPECT_TRUE(vpSelfCalibPipeline::multiViewMisfit(bent)) << bent.message;
  vpRobotSelfCalibration::Options o;
  o.num_calibration_poses = 14;
  o.noise.pixel_sd = 0.2;
  const vpRobotSelfCalibration::Result run = vpRobotSelfCalibration::run(right.sim.getNominalChain(), wrong, o);
  EXPECT_NE(run.status, vpRobotSelfCalibration::OK) << run.message;
  if (run.status == vpRobotSelfCalibration::DOUBTFUL)
    EXPECT_TRUE(std::any_of(run.findings.begin(), run.findings.end(),
                            [](const vpSelfCalibDataCheck::Finding &f) { return f.code == "multiview-misfit"; }))
        << run.message;
}
