/*
 * Tests of the start measured from the data (vpSelfCalibMeasuredStart.cpp): eMc and a self-calibrated
 * focal length from the camera's and the robot's motions, whatever the model's eMc guess and the
 * focal guess.
 */
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <visp3/selfcalib/vpBoardDetector.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibRenderer.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "../testCommon.h"
#include "startGuesses.h"
#include "core/vpSelfCalibMath.h"
#include "pipeline/vpSelfCalibPipelines.h"

using namespace selfcalib_test;
using RSC = vpRobotSelfCalibration;

namespace
{
//! The first n views with their true end-effector poses set (has_fMe).
std::vector<vpSelfCalibDataset::View> withTrueFMe(const vpSelfCalibSimulator &sim, const vpSelfCalibDataset &ds)
{
  std::vector<vpSelfCalibDataset::View> views = ds.views;
  for (auto &v : views) {
    v.fMe = sim.getTrueChain().get_fMe(v.q);
    v.has_fMe = true;
  }
  return views;
}

//! The ChArUco board of simulate --target charuco (7 x 5 squares of 2 cm).
const char *const kCharuco = "charuco:7x5:0.02:0.015:DICT_6X6_250";

/*
  The views of simulate --images --target charuco (getting-started's block) without the images:
  the reference scenario's robot and poses (seed), its board's inner corners (the renderer's
  placement) through the true camera with `sd` px of noise, the board's first row the yardstick.
*/
vpSelfCalibDataset charucoPlane(const vpSelfCalibSimulator &sim, unsigned int n, double sd)
{
  vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(n));
  vpSelfCalibRenderer::Options ro;
  ro.scene = vpSelfCalibRenderer::CHARUCO;
  const vpHomogeneousMatrix fMb = vpSelfCalibRenderer(sim, ro).getBoardPose();
  const vpBoardDetector board(vpBoardDetector::parse(kCharuco));
  const vpSelfCalib::CameraModel lens = vpSelfCalib::CameraModel::fromVisp(sim.getCamera());
  vpSelfCalib::Random rng(sim.getOptions().seed, 77);
  for (auto &v : ds.views) {
    v.points.clear();
    const vpSelfCalib::Rigid cMb = vpSelfCalib::rigidFromVisp(sim.getTrueChain().get_fMc(v.q).inverse() * fMb);
    for (const auto &e : board.getLayout()) {
      const Eigen::Vector2d uv = lens.project(cMb * vpSelfCalib::vec3(e.second));
      vpSelfCalibDataset::Observation o;
      o.id = e.first;
      o.ip = vpImagePoint(uv(1) + rng.normal(sd), uv(0) + rng.normal(sd));
      v.points.push_back(o);
    }
  }
  ds.yardstick = board.getYardstick();
  return ds;
}
} // namespace

// Noise-free views and the true end-effector poses: the focal length where the camera's and the
// robot's rotation angles agree is the true one, and eMc follows exactly, from the two-view motions
// and from a target of known points (the scene points, frame f) alike; the lens's focal length
// (here 3 times the truth) is not read.
TEST(MeasuredStart, NoiseFreeMotionsGiveTheTrueFocalAndEMc)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 7, 0.0);
  const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(10));
  const std::vector<vpSelfCalibDataset::View> views = withTrueFMe(sim, ds);
  const double f_true = sim.getCamera().get_px();
  vpCameraParameters wrong;
  wrong.initPersProjWithoutDistortion(3 * f_true, 3 * f_true, ds.cam.get_u0(), ds.cam.get_v0());
  const vpSelfCalib::CameraModel lens = vpSelfCalib::CameraModel::fromVisp(wrong);
  const vpHomogeneousMatrix eMc_true = sim.getTrueChain().get_eMc_corrected();
  const std::map<int, vpColVector> layout = sim.getScenePointsById();
  for (bool known : {false, true}) {
    const vpSelfCalibPipeline::MeasuredStart m = vpSelfCalibPipeline::measuredStart(
        views, lens, 640, known ? layout : std::map<int, vpColVector>(), false, 1.0);
    ASSERT_TRUE(m.has_eMc && m.has_fx) << m.how;
    EXPECT_NEAR(m.fx, f_true, 1e-4 * f_true) << m.how;
    EXPECT_LT(vpSelfCalib::rotationDistance(vpSelfCalib::toVisp(m.eMc), eMc_true), 1e-5) << m.how;
    EXPECT_LT(vpSelfCalib::translationDistance(vpSelfCalib::toVisp(m.eMc), eMc_true), 1e-5) << m.how;
  }
}

// A plane of unknown layout (the ChArUco board's corners, noise-free): each pair's motion is the
// homography's decomposition whose plane normal the other pairs share (the five-point solutions
// fit the points of a plane but not the motion), and the focal length and eMc follow exactly.
TEST(MeasuredStart, APlaneOfUnknownLayoutGivesTheTrueFocalAndEMc)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 1, 0.0);
  const vpSelfCalibDataset ds = charucoPlane(sim, 12, 0.0);
  std::vector<vpSelfCalibDataset::View> views = ds.views;
  for (auto &v : views) {
    v.fMe = sim.getTrueChain().get_fMe(v.q);
    v.has_fMe = true;
  }
  const vpSelfCalib::CameraModel lens = vpSelfCalib::CameraModel::fromVisp(sim.getCamera());
  const vpHomogeneousMatrix eMc_true = sim.getTrueChain().get_eMc_corrected();
  for (bool known : {false, true}) {
    const vpSelfCalibPipeline::MeasuredStart m = vpSelfCalibPipeline::measuredStart(views, lens, 640, {}, known, 1.0);
    ASSERT_TRUE(m.has_eMc) << m.how;
    EXPECT_NE(m.how.find(" pairs with view 0 (11 on a plane"), std::string::npos) << m.how;
    EXPECT_NEAR(m.fx, lens.px(), 1e-4 * lens.px()) << m.how;
    EXPECT_LT(vpSelfCalib::rotationDistance(vpSelfCalib::toVisp(m.eMc), eMc_true), 1e-5) << m.how;
    EXPECT_LT(vpSelfCalib::translationDistance(vpSelfCalib::toVisp(m.eMc), eMc_true), 2e-5) << m.how;
  }
}

// The ChArUco plane of getting-started (f self-calibrated, 0.2 px): with the board's layout as its
// spec describes it (target_layout, PnP) or without (the plane's motions), the run starts from the
// measured eMc (no emc-start-guess), ends ok with eMc within 3 sd of the truth, and gives the same
// focal length and eMc within 0.1 sd from the focal guesses 0.5x, 1x, 2x and an eMc guess 90 deg off.
TEST(MeasuredStart, ACharucoPlaneCalibratesFromTheMeasuredStartWhateverTheGuesses)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 1, 0.2);
  const vpSelfCalibDataset ds = charucoPlane(sim, 15, 0.2);
  const double f_true = sim.getCamera().get_px();
  const vpPoseVector truth(sim.getTrueChain().get_eMc_corrected());
  for (bool layout : {true, false}) {
    RSC::Options o;
    if (layout)
      o.target_layout = vpBoardDetector(vpBoardDetector::parse(kCharuco)).getLayout();
    const RSC::Result ref = RSC::run(sim.getNominalChain(), withGuess(ds, f_true), o);
    for (const auto &run : {std::make_pair(1.0, false), std::make_pair(0.5, true), std::make_pair(2.0, true)}) {
      const RSC::Result r = run.first == 1.0 ? ref
                                             : RSC::run(run.second ? turned90(sim.getNominalChain()) : sim.getNominalChain(),
                                                        withGuess(ds, run.first * f_true), o);
      const std::string what = std::string(layout ? "layout" : "no layout") + " " + std::to_string(run.first);
      ASSERT_TRUE(r.status == RSC::OK || r.status == RSC::DOUBTFUL) << what << ": " << r.message;
      EXPECT_NE(r.message.find(layout ? "eMc started from the target's poses" : "eMc started from the camera's motions"),
                std::string::npos)
          << what << ": " << r.message;
      for (const auto &f : r.findings)
        EXPECT_NE(f.code, "emc-start-guess") << what << ": " << f.message;
      EXPECT_LT(std::fabs(r.fx - f_true), 3 * r.fx_sd) << what;
      EXPECT_LT(std::fabs(r.fx - ref.fx), 0.1 * ref.fx_sd) << what;
      for (unsigned int i = 0; i < 6; ++i) {
        EXPECT_LT(std::fabs(r.eMc[i] - truth[i]), 3 * r.eMc_sd[i]) << what << " " << i;
        EXPECT_LT(std::fabs(r.eMc[i] - ref.eMc[i]), 0.1 * ref.eMc_sd[i]) << what << " " << i;
      }
    }
  }
}

// The bundle method with f self-calibrated, started from 1x (the reference), 0.5x and 2x the true
// focal length, with the right eMc guess or one turned by 90 deg, on 0.2 px noise: every run gives
// the same focal length and eMc within 0.1 of their sd, f within 3 sd of the truth, and only the
// turned guess is said to be far (emc-guess-far).
TEST(MeasuredStart, AnswerDependsOnNeitherTheFocalNorTheEMcGuess)
{
  for (uint64_t seed : {11, 12}) {
    const vpSelfCalibSimulator sim = makeSim("viper850", seed, 0.2);
    const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(12));
    const double f_true = sim.getCamera().get_px();
    RSC::Options o;
    o.num_calibration_poses = 12;
    // The assessment may call a run doubtful against a nominal model already close (these 12 views
    // cannot make it reliably better): the answer is what is compared.
    const RSC::Result ref = RSC::run(sim.getNominalChain(), withGuess(ds, f_true), o);
    ASSERT_TRUE(ref.status == RSC::OK || ref.status == RSC::DOUBTFUL) << seed << ": " << ref.message;
    EXPECT_NE(ref.message.find("eMc started from the camera's motions"), std::string::npos) << ref.message;
    EXPECT_LT(std::fabs(ref.fx - f_true), 3 * ref.fx_sd) << seed;
    for (const auto &f : ref.findings)
      EXPECT_NE(f.code, "emc-guess-far") << f.message;
    for (const auto &run : {std::make_pair(0.5, true), std::make_pair(2.0, true), std::make_pair(2.0, false)}) {
        const double k = run.first;
        const bool turn = run.second;
        const RSC::Result r =
            RSC::run(turn ? turned90(sim.getNominalChain()) : sim.getNominalChain(), withGuess(ds, k * f_true), o);
        ASSERT_TRUE(r.status == RSC::OK || r.status == RSC::DOUBTFUL) << seed << " " << k << " " << turn << ": " << r.message;
        EXPECT_LT(std::fabs(r.fx - ref.fx), 0.1 * ref.fx_sd) << seed << " " << k << " " << turn;
        for (unsigned int i = 0; i < 6; ++i)
          EXPECT_LT(std::fabs(r.eMc[i] - ref.eMc[i]), 0.1 * ref.eMc_sd[i]) << seed << " " << k << " " << turn << " " << i;
        bool far = false;
        for (const auto &f : r.findings)
          far = far || f.code == "emc-guess-far";
        EXPECT_EQ(far, turn) << seed << " " << k;
      }
  }
}

// A part of eMc the caller fixes (--fix eMc.tz) keeps the model's guess where the run measures eMc
// from the data: the guess 5 mm off the truth in z, the fixed run ends with no z correction from the
// guess, while the free run moves it (1.8 mm here); the fixed part kept the measured start's value
// before, a value the user did not state.
TEST(MeasuredStart, AFixedPartOfEMcKeepsTheGuess)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 13, 0.2);
  const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(10));
  vpKinematicChain guess = sim.getNominalChain();
  vpHomogeneousMatrix dz;
  dz.buildFrom(0, 0, 0.005, 0, 0, 0);
  guess.set_eMc(vpPoseVector(guess.get_eMc() * dz));
  const unsigned int tz = guess.getNumParameters() - vpKinematicChain::kBlockSize + 2;
  RSC::Options o;
  o.num_calibration_poses = 10;
  o.trust_robot = true; // the simulated joints are exact; the start is the subject
  const RSC::Result free_run = RSC::run(guess, ds, o);
  o.bundle.fixed = {"eMc.tz"};
  const RSC::Result fixed_run = RSC::run(guess, ds, o);
  for (const RSC::Result *r : {&free_run, &fixed_run}) {
    ASSERT_TRUE(r->status == RSC::OK || r->status == RSC::DOUBTFUL) << r->message;
    EXPECT_NE(r->message.find("eMc started from the camera's motions"), std::string::npos) << r->message;
  }
  EXPECT_GT(std::fabs(free_run.calibrated.getParameters()[tz]), 0.001);
  EXPECT_LT(std::fabs(fixed_run.calibrated.getParameters()[tz]), 1e-4);
}

// Hand-eye from controller poses off by 1 mm / 1 mrad: the eMc guess turned by 90 deg and the focal
// guess at 0.5x give the answer of the right guesses.
TEST(MeasuredStart, HandEyeFromControllerPosesDoesNotDependOnTheGuesses)
{
  const uint64_t seed = 21;
  const vpSelfCalibSimulator sim = makeSim("viper850", seed, 0.2);
  vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(10));
  toControllerPoses(sim, ds, 1e-3, 1e-3, seed, 98);
  const double f_true = sim.getCamera().get_px();
  RSC::Options o;
  o.method = RSC::HAND_EYE;
  o.num_calibration_poses = 10;
  const RSC::Result ref = RSC::run(sim.getNominalChain(), withGuess(ds, f_true), o);
  const RSC::Result r = RSC::run(turned90(sim.getNominalChain()), withGuess(ds, 0.5 * f_true), o);
  ASSERT_EQ(ref.status, RSC::OK) << ref.message;
  ASSERT_EQ(r.status, RSC::OK) << r.message;
  EXPECT_LT(std::fabs(r.fx - ref.fx), 0.1 * ref.fx_sd);
  for (unsigned int i = 0; i < 6; ++i)
    EXPECT_LT(std::fabs(r.eMc[i] - ref.eMc[i]), 0.1 * ref.eMc_sd[i]) << i;
  const vpPoseVector truth(sim.getTrueChain().get_eMc_corrected());
  for (unsigned int i = 0; i < 6; ++i)
    EXPECT_LT(std::fabs(r.eMc[i] - truth[i]), 4 * r.eMc_sd[i]) << i;
}

// No view shares 15 points with 3 others (each view keeps 12): eMc starts from the model's guess,
// and the run says so (emc-start-guess); the focal length from the rays of the model's camera poses.
TEST(MeasuredStart, TooFewSharedPointsFallsBackToTheGuessAndSaysSo)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 5, 0.2);
  vpSelfCalibDataset ds = withGuess(sim.makeDataset(sim.generateConfigurations(8)), 1000);
  for (auto &v : ds.views)
    v.points.resize(std::min<size_t>(v.points.size(), 12));
  RSC::Options o;
  o.num_calibration_poses = 8;
  const vpSelfCalibPipeline::DataStart s = vpSelfCalibPipeline::startFromData(sim.getNominalChain(), ds, 8, o);
  EXPECT_FALSE(s.eMc_from_data);
  ASSERT_EQ(s.findings.size(), 1u);
  EXPECT_EQ(s.findings[0].code, "emc-start-guess");
  EXPECT_NE(s.findings[0].message.find("no view shares 15 points with 3 others"), std::string::npos)
      << s.findings[0].message;
  EXPECT_LT(vpSelfCalib::rotationDistance(s.model.get_eMc_corrected(), sim.getNominalChain().get_eMc_corrected()),
            1e-12);
  EXPECT_NE(s.message.find("eMc started from the model's guess"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("where the rays of the model's camera poses meet best"), std::string::npos) << s.message;
}

// A first view that sees little of the scene (12 points): the pairs are taken with the view that
// shares enough points with the most others, and eMc is still measured, exactly on noise-free views.
TEST(MeasuredStart, AFirstViewSeeingLittleDoesNotLeaveTheStartToTheGuess)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 7, 0.0);
  const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(8));
  std::vector<vpSelfCalibDataset::View> views = withTrueFMe(sim, ds);
  views[0].points.resize(12);
  const vpSelfCalibPipeline::MeasuredStart m =
      vpSelfCalibPipeline::measuredStart(views, vpSelfCalib::CameraModel::fromVisp(sim.getCamera()), 640, {}, true, 1.0);
  ASSERT_TRUE(m.has_eMc) << m.how;
  EXPECT_EQ(m.how.find("pairs with view 0 "), std::string::npos) << m.how;
  EXPECT_NE(m.how.find("the camera's motions of 6 pairs with view "), std::string::npos) << m.how;
  const vpHomogeneousMatrix eMc_true = sim.getTrueChain().get_eMc_corrected();
  EXPECT_LT(vpSelfCalib::rotationDistance(vpSelfCalib::toVisp(m.eMc), eMc_true), 1e-5) << m.how;
  EXPECT_LT(vpSelfCalib::translationDistance(vpSelfCalib::toVisp(m.eMc), eMc_true), 1e-5) << m.how;
}

// A view without its end-effector pose is a caller mistake.
TEST(MeasuredStart, AViewWithoutItsEndEffectorPoseThrows)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 5, 0.2);
  const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(4));
  try {
    vpSelfCalibPipeline::measuredStart(ds.views, vpSelfCalib::CameraModel::fromVisp(ds.cam), 640, {}, false, 1.0);
    FAIL() << "no exception";
  } catch (const vpSelfCalibException &e) {
    EXPECT_NE(e.getStringMessage().find("every view needs its end-effector pose"), std::string::npos)
        << e.getStringMessage();
  }
}
