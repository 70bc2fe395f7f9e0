/*
 * Tests of vpSelfCalibProtocol: the split and the folds from the options (and the caller mistakes
 * refused with their messages), the cross-validation's verdicts, and a run that calibrates,
 * cross-validates and reports through its callback.
 */
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibProtocol.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "../testCommon.h"

using namespace selfcalib_test;
using P = vpSelfCalibProtocol;
using CV = vpSelfCalibCrossValidation;

namespace
{
//! The message of the vpSelfCalibException that plan() throws, or "" when it does not.
std::string planError(const P::Options &o, unsigned int views)
{
  try {
    P::plan(o, views);
  } catch (const vpSelfCalibException &e) {
    return e.getStringMessage();
  }
  return std::string();
}

//! A cross-validation result of folds with the given statuses and RMS (calibrated, nominal).
CV::Result folds(const std::vector<vpRobotSelfCalibration::Status> &status, const std::vector<double> &calibrated,
                 const std::vector<double> &nominal)
{
  CV::Result cv;
  for (size_t k = 0; k < status.size(); ++k) {
    CV::Fold f;
    f.status = status[k];
    f.calibrated.rms = calibrated[k];
    f.nominal.rms = nominal[k];
    f.calibrated.observations = f.nominal.observations = f.status == vpRobotSelfCalibration::OK ? 10 : 0;
    cv.fold.push_back(f);
    cv.num_ok += f.status == vpRobotSelfCalibration::OK;
    cv.num_failed += f.status != vpRobotSelfCalibration::OK;
  }
  double sc = 0, sn = 0;
  for (size_t k = 0; k < status.size(); ++k) {
    sc += calibrated[k];
    sn += nominal[k];
  }
  cv.calibrated_rms.mean = sc / status.size();
  cv.nominal_rms.mean = sn / status.size();
  return cv;
}

vpRobotSelfCalibration::Result okRun()
{
  vpRobotSelfCalibration::Result r;
  r.status = vpRobotSelfCalibration::OK;
  r.message = "calibrated";
  return r;
}
} // namespace

// Every view calibrates with 5 folds by default; a split turns the folds off unless asked for;
// too few views skip them with a note.
TEST(Protocol, PlanSplitsTheViewsAndChoosesTheFolds)
{
  P::Options o;
  P::Plan p = P::plan(o, 12);
  EXPECT_EQ(p.calibration, 12u);
  EXPECT_EQ(p.held_out, 0u);
  EXPECT_EQ(p.folds, 5u);
  EXPECT_TRUE(p.note.empty());
  o.holdout = 4;
  p = P::plan(o, 12);
  EXPECT_EQ(p.calibration, 8u);
  EXPECT_EQ(p.held_out, 4u);
  EXPECT_EQ(p.folds, 0u);
  o.folds = 2;
  o.folds_given = true;
  EXPECT_EQ(P::plan(o, 12).folds, 2u);
  o = P::Options();
  o.calibration = 7;
  p = P::plan(o, 9);
  EXPECT_EQ(p.calibration, 7u);
  EXPECT_EQ(p.held_out, 2u);
  EXPECT_EQ(p.folds, 0u);
  p = P::plan(P::Options(), 5);
  EXPECT_EQ(p.folds, 0u);
  EXPECT_EQ(p.note, "cross-validation skipped: 5 views, fewer than 6 (each fold would calibrate on 4 views or "
                    "fewer); --folds K asks for it");
}

// Options that contradict each other or the dataset throw, naming the option.
TEST(Protocol, PlanRefusesContradictions)
{
  P::Options o;
  o.calibration = 13;
  EXPECT_EQ(planError(o, 12), "--calibration 13: the dataset has 12 views (the calibration uses the first N, the "
                              "others verify)");
  o.calibration = 8;
  o.holdout = 3;
  EXPECT_EQ(planError(o, 12), "--calibration 8 and --holdout 3 disagree: the dataset has 12 views, not 11; give one "
                              "of them");
  o = P::Options();
  o.holdout = 10;
  EXPECT_EQ(planError(o, 12), "--holdout 10: the dataset has 12 views; at least 3 must remain to calibrate");
  o = P::Options();
  o.folds = 2;
  o.folds_given = true;
  EXPECT_EQ(planError(o, 4).rfind("--folds 2: ", 0), 0u) << planError(o, 4);
  o = P::Options();
  o.heldout = "/nonexistent/held.yaml";
  EXPECT_FALSE(planError(o, 12).empty());
}

// Most folds failed, or the calibrated models predict worse than the nominal one: DOUBTFUL with a
// finding each; folds that predict better leave the run as it is.
TEST(Protocol, JudgeMakesARunDoubtful)
{
  using S = vpRobotSelfCalibration::Status;
  const S ok = vpRobotSelfCalibration::OK, bad = vpRobotSelfCalibration::DEGENERATE_DATA;
  vpRobotSelfCalibration::Result r = okRun();
  P::judge(folds({ok, ok, ok}, {1, 1, 1}, {5, 5, 5}), r);
  EXPECT_EQ(r.status, vpRobotSelfCalibration::OK);
  EXPECT_TRUE(r.findings.empty());

  r = okRun();
  P::judge(folds({ok, bad, bad}, {1, 0, 0}, {5, 0, 0}), r);
  EXPECT_EQ(r.status, vpRobotSelfCalibration::DOUBTFUL);
  ASSERT_EQ(r.findings.size(), 1u);
  EXPECT_EQ(r.findings[0].code, "cross-validation-folds-failed");
  EXPECT_EQ(r.findings[0].severity, vpSelfCalibDataCheck::DOUBT);
  EXPECT_EQ(r.message.rfind("calibrated; doubtful: 2 of 3 cross-validation folds failed", 0), 0u) << r.message;

  r = okRun();
  P::judge(folds({ok, ok, ok}, {6, 6, 4}, {5, 5, 5}), r);
  EXPECT_EQ(r.status, vpRobotSelfCalibration::DOUBTFUL);
  ASSERT_EQ(r.findings.size(), 1u);
  EXPECT_EQ(r.findings[0].code, "cross-validation-worse-than-nominal");
  EXPECT_NE(r.findings[0].message.find("reprojection RMS 5.33 px against 5 px; worse in 2 of 3 folds"),
            std::string::npos)
      << r.findings[0].message;

  // Worse in most folds but not by 5 % on average: no verdict.
  r = okRun();
  P::judge(folds({ok, ok, ok}, {5.1, 5.1, 4.9}, {5, 5, 5}), r);
  EXPECT_EQ(r.status, vpRobotSelfCalibration::OK);
}

// A run calibrates, cross-validates over the calibration views and tells its stages to the
// callback; the verdicts are on `calibration`, the run itself is kept apart.
TEST(Protocol, RunCalibratesAndCrossValidates)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 31, 0.0);
  const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(10));
  P::Options o;
  o.holdout = 2;
  o.folds = 2;
  o.folds_given = true;
  const P::Plan plan = P::plan(o, 10);
  unsigned int progress = 0, warnings = 0;
  // Without the kinematic prior: on noise-free views its pull toward nominal leaves residuals that
  // the robot-error check takes for each camera's own displacement (doubtful), not the subject here.
  vpRobotSelfCalibration::Options ro;
  ro.bundle.kinematic_prior = vpKinematicBundleAdjustment::KINEMATIC_PRIOR_OFF;
  const P::Result r = P::run(sim.getNominalChain(), ds, ro, plan, o,
                             [&](P::EventKind kind, const std::string &) {
                               progress += kind == P::PROGRESS;
                               warnings += kind == P::WARNING;
                             });
  ASSERT_TRUE(r.calibrated()) << r.run.message;
  EXPECT_EQ(r.options.num_calibration_poses, 8u);
  EXPECT_TRUE(r.run.verified);
  ASSERT_TRUE(r.cv.has_value());
  EXPECT_EQ(r.cv->views, 8u);
  EXPECT_EQ(r.cv->fold.size(), 2u);
  EXPECT_FALSE(r.verified.has_value());
  EXPECT_GT(progress, 3u);
  EXPECT_EQ(warnings, 0u);
  // The run itself is kept as it was; the verdicts (2 folds of 4 training views: worse than
  // nominal) are on `calibration` only.
  EXPECT_EQ(r.run.status, vpRobotSelfCalibration::OK);
  vpRobotSelfCalibration::Result judged = r.run;
  P::judge(*r.cv, judged);
  EXPECT_EQ(r.calibration.status, judged.status);
  EXPECT_EQ(r.calibration.message, judged.message);
  EXPECT_EQ(r.calibration.findings.size(), judged.findings.size());
}
