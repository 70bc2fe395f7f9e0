/*
 * Tests of vpSelfCalibResultsFile: every block of the schema written and read back (the reader
 * gives back what the writer wrote), the schema_version key written first and checked, and the
 * record of a real run.
 */
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibResultsFile.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "../testCommon.h"

using namespace selfcalib_test;
using RF = vpSelfCalibResultsFile;

namespace
{
//! Contents with every optional block, and values that need all 17 digits.
RF::Contents everything()
{
  RF::Contents c;
  c.dataset = "data/ds.yaml";
  c.method = "bundle";
  c.status = "doubtful";
  c.message = "calibrated; doubtful: \"quoted\" words";
  c.findings = {{"code-a", "warning", "first: a message"}, {"code-b", "doubt", "second"}};
  c.camera = {1500.1234567890123, 1499.5, 320.25, 240.125, 0.1 / 3, {0.01, -0.02, 1e-4, -2e-4, 0.003}};
  c.intrinsics_estimated = {{"px", 1500.5, 0.25}, {"k1", 0.01, 1e-3}};
  c.eMc = RF::HandEye{{0.1, 0.2, 0.3, 0.01, 0.02, 1.5}, {1e-3, 2e-3, 3e-3, 1e-4, 2e-4, 3e-4}};
  RF::BundleAdjustment b;
  b.observations = 1234;
  b.dropped = 5;
  b.rms_px = 0.2 / 7;
  b.sigma0 = 1.01;
  b.scale_from = "yardstick";
  b.has_robot_pose = b.has_robot_pose_sd_measured = b.has_joint_corrections = b.has_repose = true;
  b.robot_pose_rms_m = 1e-3;
  b.robot_pose_rms_rad = 2e-3;
  b.robot_pose_sd_m = b.robot_pose_sd_rad = 2e-3;
  b.robot_pose_sd_measured_m = 3.5e-3;
  b.robot_pose_sd_measured_rad = 4.25e-3;
  b.joint_correction_rms_rad = 1e-4;
  b.joint_sd = {3e-4, 2.5e-4, 2.5e-4, 1e-4, 1e-4, 1e-4};
  b.joint_sd_measured = {2.75e-4, 2.5e-4, 2.5e-4, 1e-4, 1e-4, 1e-4};
  b.robot_error = "measured";
  b.reposed_rms_px = 0.5;
  b.repose_f = 3.25;
  b.repose_f_limit = 1.75;
  b.sd_scaled_by_sigma0 = true;
  c.bundle_adjustment = b;
  c.noise = RF::NoiseAndFit{0.2, 0.21, 12.5, 0.25};
  c.workspace = RF::Workspace{2.5e-3, 1.25e-3, 3.75e-3, 2e-3, 8e-3, 9.5e-3, 0.0625, 0.125, true, {{"j3", {0.25, 0.5}}}};
  c.workspace_full_range = RF::Workspace{7.5e-3, 5e-3, 1e-2, 6e-3, 8e-3, 9.5e-3, 0.75, 0.5, false, {}};
  c.estimated = {{"eMc.tx", 0.1, 1e-4}, {"j2.rz", -1e-3 / 3, 2e-5}};
  c.not_estimated = {{"base.tx", "the same as eMc's"}, {"j1.rz", "no motion: \"fixed\""}};
  c.estimated_set = RF::EstimatedSet{"the rule", 2, {"eMc.tx", "base.tx", "j2.rz"}, {{"eMc.tx", 1}, {"j2.rz", 0.125}}};
  c.verification = RF::Verification{1e-3, 1e-5, 3.5, 0.25};
  c.calibration_views = 10;
  c.held_out_views = 2;
  c.folds = 2;
  RF::CrossValidation cv;
  cv.folds = 2;
  cv.views = 10;
  cv.measured = 1;
  cv.failed = 1;
  cv.rms_calibrated = {0.3, 0, 0.3, 0.3};
  cv.rms_nominal = {5, 0, 5, 5};
  cv.median_calibrated = {0.25, 0, 0.25, 0.25};
  cv.median_nominal = {4, 0, 4, 4};
  RF::Fold ok;
  ok.held_out = {0, 2, 4, 6, 8};
  ok.status = "ok";
  ok.calibrated = ok.verified = true;
  ok.fx = 1500.25;
  ok.rms_calibrated = 0.3;
  ok.median_calibrated = 0.25;
  ok.rms_nominal = 5;
  ok.median_nominal = 4;
  ok.observations = 410;
  ok.yardstick_error_calibrated = 1e-5;
  ok.yardstick_error_nominal = 1e-3;
  RF::Fold failed;
  failed.held_out = {1, 3, 5, 7, 9};
  failed.status = "degenerate-data";
  failed.message = "too few views";
  cv.per_fold = {ok, failed};
  c.cross_validation = cv;
  c.heldout_dataset = RF::HeldOutDataset{"held.yaml", 4, 0.3, 5, 0.25, 4, 328, true, 1e-3, 1e-5};
  return c;
}
} // namespace

// Every block read back as written: the same values, and the same text written again.
TEST(ResultsFile, ReaderGivesBackWhatTheWriterWrote)
{
  const RF::Contents c = everything();
  const std::string text = RF::toYaml(c);
  EXPECT_EQ(text.rfind("schema_version: 1\n", 0), 0u) << text;
  const RF::Contents back = RF::fromYaml(text);
  EXPECT_EQ(RF::toYaml(back), text);
  EXPECT_EQ(back.schema_version, RF::kSchemaVersion);
  EXPECT_EQ(back.message, c.message);
  EXPECT_EQ(back.camera.px, c.camera.px);
  EXPECT_EQ(back.camera.px_sd, c.camera.px_sd);
  EXPECT_EQ(back.camera.distortion, c.camera.distortion);
  ASSERT_EQ(back.findings.size(), 2u);
  EXPECT_EQ(back.findings[1].severity, "doubt");
  ASSERT_TRUE(back.bundle_adjustment.has_value());
  EXPECT_EQ(back.bundle_adjustment->rms_px, c.bundle_adjustment->rms_px);
  EXPECT_TRUE(back.bundle_adjustment->has_repose);
  EXPECT_EQ(back.bundle_adjustment->robot_pose_sd_measured_rad, 4.25e-3);
  EXPECT_EQ(back.bundle_adjustment->joint_sd, c.bundle_adjustment->joint_sd);
  EXPECT_EQ(back.bundle_adjustment->joint_sd_measured, c.bundle_adjustment->joint_sd_measured);
  EXPECT_EQ(back.bundle_adjustment->robot_error, "measured");
  ASSERT_TRUE(back.workspace.has_value());
  EXPECT_EQ(back.workspace->bound_t, 3.75e-3);
  EXPECT_EQ(back.workspace->nominal_r, 9.5e-3);
  EXPECT_EQ(back.workspace->worse_r, 0.125);
  EXPECT_TRUE(back.workspace->scale_left_out);
  EXPECT_EQ(back.workspace->joints_within, c.workspace->joints_within);
  ASSERT_TRUE(back.workspace_full_range.has_value());
  EXPECT_EQ(back.workspace_full_range->worse_t, 0.75);
  EXPECT_TRUE(back.workspace_full_range->joints_within.empty());
  ASSERT_EQ(back.estimated.size(), 2u);
  EXPECT_EQ(back.estimated[1].name, "j2.rz");
  EXPECT_EQ(back.estimated[1].value, c.estimated[1].value);
  EXPECT_EQ(back.not_estimated, c.not_estimated);
  ASSERT_TRUE(back.estimated_set.has_value());
  EXPECT_EQ(back.estimated_set->order, c.estimated_set->order);
  EXPECT_EQ(back.estimated_set->new_direction, c.estimated_set->new_direction);
  ASSERT_TRUE(back.cross_validation.has_value());
  ASSERT_EQ(back.cross_validation->per_fold.size(), 2u);
  EXPECT_EQ(back.cross_validation->per_fold[0].held_out, c.cross_validation->per_fold[0].held_out);
  EXPECT_TRUE(back.cross_validation->per_fold[0].verified);
  EXPECT_FALSE(back.cross_validation->per_fold[1].calibrated);
  EXPECT_EQ(back.cross_validation->per_fold[1].message, "too few views");
  ASSERT_TRUE(back.heldout_dataset.has_value());
  EXPECT_EQ(back.heldout_dataset->observations, 328u);
  EXPECT_EQ(back.heldout_dataset->yardstick_error_calibrated, 1e-5);
}

// The optional blocks left out are left out when read back; a file round-trips through disk.
TEST(ResultsFile, OptionalBlocksAndFiles)
{
  RF::Contents c = everything();
  c.findings.clear();
  c.camera.distortion.clear();
  c.intrinsics_estimated.clear();
  c.eMc.reset();
  c.bundle_adjustment.reset();
  c.noise.reset();
  c.workspace.reset();
  c.workspace_full_range.reset();
  c.estimated_set.reset();
  c.verification.reset();
  c.cross_validation.reset();
  c.heldout_dataset.reset();
  const std::string text = RF::toYaml(c);
  EXPECT_NE(text.find("findings: []"), std::string::npos) << text;
  const std::string file = (std::filesystem::temp_directory_path() / "testResultsFile-results.yaml").string();
  RF::write(file, c);
  const RF::Contents back = RF::read(file);
  std::remove(file.c_str());
  EXPECT_EQ(RF::toYaml(back), text);
  EXPECT_FALSE(back.eMc || back.bundle_adjustment || back.noise || back.workspace || back.workspace_full_range || back.estimated_set || back.verification ||
               back.cross_validation || back.heldout_dataset);
  EXPECT_TRUE(back.findings.empty());
}

// A file without schema_version, or of another version, is refused with a message naming the key.
TEST(ResultsFile, SchemaVersionIsChecked)
{
  std::string text = RF::toYaml(everything());
  const std::string other = "schema_version: 2" + text.substr(text.find('\n'));
  EXPECT_THROW(RF::fromYaml(other), vpSelfCalibException);
  const std::string none = text.substr(text.find('\n') + 1);
  try {
    RF::fromYaml(none, "old.yaml");
    FAIL() << "a file without schema_version was read";
  } catch (const vpSelfCalibException &e) {
    EXPECT_NE(e.getStringMessage().find("old.yaml: key 'schema_version'"), std::string::npos) << e.getStringMessage();
  }
  EXPECT_THROW(RF::fromYaml("[1, 2"), vpSelfCalibException);
  EXPECT_THROW(RF::read("/nonexistent/results.yaml"), vpSelfCalibException);
}

// The record of a real run (calibration, cross-validation) reads back to the same text.
TEST(ResultsFile, RecordOfARunRoundTrips)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 32, 0.2);
  const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(10));
  vpSelfCalibProtocol::Options o;
  o.holdout = 2;
  o.folds = 2;
  o.folds_given = true;
  const vpSelfCalibProtocol::Result p =
      vpSelfCalibProtocol::run(sim.getNominalChain(), ds, vpRobotSelfCalibration::Options(),
                               vpSelfCalibProtocol::plan(o, 10), o);
  ASSERT_TRUE(p.calibrated()) << p.run.message;
  const RF::Contents c = RF::fromRun(p.calibration, sim.getNominalChain(), "ds.yaml", p);
  EXPECT_EQ(c.method, "bundle");
  EXPECT_EQ(c.calibration_views, 8u);
  EXPECT_EQ(c.held_out_views, 2u);
  ASSERT_TRUE(c.cross_validation.has_value());
  EXPECT_EQ(c.cross_validation->per_fold.size(), 2u);
  EXPECT_TRUE(c.verification.has_value());
  EXPECT_EQ(c.estimated.size(), p.calibration.identifiability.identified.size());
  const std::string text = RF::toYaml(c);
  EXPECT_EQ(RF::toYaml(RF::fromYaml(text)), text);
}

// Eye-to-hand: the bMc and eMo blocks in the form of eMc, read back as written; eMc absent.
TEST(ResultsFile, EyeToHandBlocks)
{
  RF::Contents c;
  c.dataset = "e2h.yaml";
  c.method = "hand-eye";
  c.status = "ok";
  c.bMc = RF::HandEye{{0.95, -0.05, 0.47, -1.1, -1.1, 1.3}, {1e-3, 2e-3, 3e-3, 1e-3, 2e-3, 3e-3}};
  c.eMo = RF::HandEye{{0.023, -0.005, -0.056, 0.01, 0.02, 0.03}, {4e-4, 5e-4, 6e-4, 4e-3, 5e-3, 6e-3}};
  const std::string text = RF::toYaml(c);
  EXPECT_NE(text.find("bMc:  # the camera in the robot's base frame"), std::string::npos) << text;
  EXPECT_NE(text.find("{pose: [0.94999999999999996, -0.050000000000000003"), std::string::npos) << text;
  EXPECT_NE(text.find("eMo:  # the target in the end-effector frame"), std::string::npos) << text;
  EXPECT_EQ(text.find("eMc:"), std::string::npos) << text;
  const RF::Contents back = RF::fromYaml(text);
  ASSERT_TRUE(back.bMc && back.eMo);
  EXPECT_FALSE(back.eMc);
  EXPECT_EQ(back.bMc->pose, c.bMc->pose);
  EXPECT_EQ(back.bMc->sd, c.bMc->sd);
  EXPECT_EQ(back.eMo->pose, c.eMo->pose);
  EXPECT_EQ(back.eMo->sd, c.eMo->sd);
  EXPECT_EQ(RF::toYaml(back), text);
}
