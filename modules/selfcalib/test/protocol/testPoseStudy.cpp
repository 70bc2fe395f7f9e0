/*
 * Tests of vpSelfCalibPoseStudy: errors against the number of calibration poses (Figure 6).
 */
#include <gtest/gtest.h>

#include <cmath>

#include <visp3/selfcalib/vpCalibrationVerifier.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibPoseStudy.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "../testCommon.h"

using namespace selfcalib_test;

// 15 views, 12 calibrating: one point per number of poses from min_poses (11) to 12, the last one the
// very run vpRobotSelfCalibration makes with the same options (bit for bit), the reference line the
// nominal model's error on the held-out views; progress goes from 0 to the number of runs.
TEST(PoseStudy, OnePointPerNumberOfPosesTheLastIsTheCalibration)
{
  // From 11 poses: fewer can leave the model's error over the joint limits above the nominal
  // model's (workspace-worse-than-nominal), a doubtful run the curve does not plot. This scenario's
  // first 9 and 10 views do (9.2 and 11.4 mm against the nominal model's 7.5 on the camera's motions
  // against the truth); 11 and 12 views 1.4 and 1.1 mm.
  const vpSelfCalibSimulator sim = makeSim("viper850", 14, 0.2);
  const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(15));
  vpRobotSelfCalibration::Options o;
  o.num_calibration_poses = 12;
  o.trust_robot = true; // exact joints; the study's curve is the subject, not the robot's error
  vpSelfCalibPoseStudy::Options so;
  so.min_poses = 11;
  std::vector<std::pair<unsigned int, unsigned int>> calls;
  const vpSelfCalibPoseStudy::Result s = vpSelfCalibPoseStudy::run(
      sim.getNominalChain(), ds, o, so, [&](unsigned int done, unsigned int total) { calls.push_back({done, total}); });
  ASSERT_EQ(s.status, vpSelfCalibPoseStudy::OK) << s.message;
  EXPECT_EQ(s.runs, 2u);
  ASSERT_EQ(s.points.size(), 2u) << s.message;
  EXPECT_EQ(s.points[0].poses, 11u);
  EXPECT_EQ(s.points[1].poses, 12u);
  for (const auto &p : s.points)
    EXPECT_TRUE(std::isfinite(p.yardstick_error) && p.yardstick_error >= 0);
  const auto r = vpRobotSelfCalibration::run(sim.getNominalChain(), ds, o);
  ASSERT_EQ(r.status, vpRobotSelfCalibration::OK) << r.message;
  ASSERT_TRUE(r.verified);
  EXPECT_EQ(s.points[1].yardstick_error, r.after.yardstick_error);
  EXPECT_EQ(s.nominal_error, r.before.yardstick_error);
  EXPECT_GT(s.nominal_error, s.points[1].yardstick_error);
  const std::vector<std::pair<unsigned int, unsigned int>> expected = {{0, 2}, {1, 2}, {2, 2}};
  EXPECT_EQ(calls, expected);
}

// The calibrations run in parallel: 1 or 3 threads give the same curve, bit for bit; the caller's own
// run on all the poses is the last point and is not run again.
TEST(PoseStudy, ThreadsAndTheCallersRunDoNotChangeTheCurve)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 16, 0.2);
  const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(15));
  vpRobotSelfCalibration::Options o;
  o.num_calibration_poses = 12;
  o.trust_robot = true; // exact joints; the study's curve is the subject, not the robot's error
  vpSelfCalibPoseStudy::Options so;
  so.min_poses = 9; // fewer views can be doubtful (not plotted): the curve is the subject here
  so.threads = 1;
  const auto one = vpSelfCalibPoseStudy::run(sim.getNominalChain(), ds, o, so);
  so.threads = 3;
  const auto three = vpSelfCalibPoseStudy::run(sim.getNominalChain(), ds, o, so);
  const auto r = vpRobotSelfCalibration::run(sim.getNominalChain(), ds, o);
  ASSERT_EQ(r.status, vpRobotSelfCalibration::OK) << r.message;
  so.threads = 2;
  unsigned int calls = 0, last_done = 0;
  const auto reused = vpSelfCalibPoseStudy::run(
      sim.getNominalChain(), ds, o, so,
      [&](unsigned int done, unsigned int) {
        ++calls;
        last_done = done;
      },
      &r);
  ASSERT_EQ(one.status, vpSelfCalibPoseStudy::OK) << one.message;
  ASSERT_EQ(one.points.size(), 4u) << one.message; // 9, 10, 11 and 12 poses
  for (const auto *s : {&three, &reused}) {
    EXPECT_EQ(s->runs, 4u);
    ASSERT_EQ(s->points.size(), one.points.size());
    for (size_t k = 0; k < one.points.size(); ++k) {
      EXPECT_EQ(s->points[k].poses, one.points[k].poses);
      EXPECT_EQ(s->points[k].yardstick_error, one.points[k].yardstick_error) << "n = " << one.points[k].poses;
    }
  }
  EXPECT_EQ(reused.points.back().yardstick_error, r.after.yardstick_error);
  // The study's own run on all the poses is the caller's run, bit for bit; none when given.
  ASSERT_TRUE(one.full.has_value());
  EXPECT_EQ(one.full->calibrated.getParameters(), r.calibrated.getParameters());
  EXPECT_EQ(one.full->message, r.message);
  EXPECT_FALSE(reused.full.has_value());
  EXPECT_EQ(calls, 5u); // 0, the 3 calibrations run, and the caller's
  EXPECT_EQ(last_done, 4u);
}

// step 2 on 9 poses: n = 5, 7, 9, each the same calibration as with step 1 (bit for bit); step 0 throws.
TEST(PoseStudy, StepKeepsEveryStepthNumberOfPoses)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 16, 0.2);
  const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(12));
  vpRobotSelfCalibration::Options o;
  o.num_calibration_poses = 9;
  o.trust_robot = true; // exact joints; the study's curve is the subject, not the robot's error
  vpSelfCalibPoseStudy::Options so;
  so.min_poses = 5;
  const auto every = vpSelfCalibPoseStudy::run(sim.getNominalChain(), ds, o, so);
  so.step = 2;
  const auto some = vpSelfCalibPoseStudy::run(sim.getNominalChain(), ds, o, so);
  ASSERT_EQ(some.status, vpSelfCalibPoseStudy::OK) << some.message;
  EXPECT_EQ(every.runs, 5u);
  EXPECT_EQ(some.runs, 3u);
  std::vector<unsigned int> ns;
  for (const auto &p : some.points) {
    ns.push_back(p.poses);
    bool found = false;
    for (const auto &q : every.points)
      if (q.poses == p.poses) {
        found = true;
        EXPECT_EQ(q.yardstick_error, p.yardstick_error) << "n = " << p.poses;
      }
    EXPECT_TRUE(found) << "n = " << p.poses;
  }
  for (unsigned int n : ns)
    EXPECT_TRUE(n == 5 || n == 7 || n == 9) << n;
  EXPECT_FALSE(some.points.empty());
  EXPECT_EQ(some.points.back().poses, 9u);
  so.step = 0;
  EXPECT_THROW(vpSelfCalibPoseStudy::run(sim.getNominalChain(), ds, o, so), vpSelfCalibException);
}

// Nothing to verify on (fewer than 2 held-out views) or no yardstick: a status, no calibration run.
// Study options that cannot make a calibration throw.
TEST(PoseStudy, NotApplicableAndBadOptions)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 15, 0.2);
  const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(10));
  vpRobotSelfCalibration::Options o;
  o.num_calibration_poses = 9;
  o.trust_robot = true; // exact joints; the study's curve is the subject, not the robot's error
  auto s = vpSelfCalibPoseStudy::run(sim.getNominalChain(), ds, o);
  EXPECT_EQ(s.status, vpSelfCalibPoseStudy::NO_HELD_OUT_VIEWS);
  EXPECT_EQ(s.runs, 0u);
  EXPECT_TRUE(s.points.empty());
  EXPECT_NE(s.message.find("held-out"), std::string::npos) << s.message;
  vpSelfCalibDataset no_yardstick = ds;
  no_yardstick.yardstick = vpSelfCalibDataset::Yardstick();
  o.num_calibration_poses = 7;
  s = vpSelfCalibPoseStudy::run(sim.getNominalChain(), no_yardstick, o);
  EXPECT_EQ(s.status, vpSelfCalibPoseStudy::NO_YARDSTICK);
  EXPECT_EQ(s.runs, 0u);
  EXPECT_STREQ(vpSelfCalibPoseStudy::statusName(s.status), "no yardstick");
  vpSelfCalibPoseStudy::Options bad;
  bad.min_poses = 2;
  EXPECT_THROW(vpSelfCalibPoseStudy::run(sim.getNominalChain(), ds, o, bad), vpSelfCalibException);
}
