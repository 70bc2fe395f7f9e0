/*
 * Tests of the poses to add (vpMeasurementPlanner::planAdditions): on a PUMA 560 whose wrist joint 5
 * barely moves, the poses proposed determine what the views leave at nominal, by the planner's own
 * prediction and by the estimated set of the true robot's views at those poses.
 */
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <visp3/selfcalib/vpKinematicBundleAdjustment.h>
#include <visp3/selfcalib/vpMeasurementPlanner.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "../testCommon.h"

namespace
{
// The simulator's views of a PUMA 560 with joint 5 held within +-0.25 deg of its home value (about
// 0.5 deg of range, as bench-estset's stuck joint): 15 views, f known, no pixel noise.
struct Stuck : selfcalib_test::StuckWrist {
  explicit Stuck(uint64_t seed, double range_deg = 0.5) : StuckWrist(seed, 15, range_deg) {}
  vpMeasurementPlanner planner() const { return vpMeasurementPlanner(sim.getNominalChain(), sim.getPlannerScene()); }
};

vpKinematicBundleAdjustment::Options bundleOptions()
{
  vpKinematicBundleAdjustment::Options bo;
  bo.intrinsics = 0;
  bo.tolerance_translation = 3e-3;
  bo.tolerance_rotation = 5e-3;
  return bo;
}

vpSelfCalibNoiseModel noiseOf(double pixel_sd)
{
  vpSelfCalibNoiseModel n;
  n.pixel_sd = pixel_sd;
  return n;
}

using selfcalib_test::leftByData;
} // namespace

/*
  The poses proposed: within the joint limits, the scene in view, and with them the predicted sd of
  every parameter left falls below its tolerance (it was above); the true robot's views at those
  poses (the simulator's, through the true model) make the estimated set keep none at nominal. Two
  geometries.
*/
TEST(PlanAdditions, ProposedPosesDetermineWhatAStuckWristLeaves)
{
  for (uint64_t seed : {3u}) {
    const Stuck w(seed);
    const vpKinematicBundleAdjustment::Options bo = bundleOptions();
    const vpSelfCalibNoiseModel noise = noiseOf(0.2);
    const vpMeasurementPlanner planner = w.planner();
    vpMeasurementPlanner::AdditionOptions o;
    o.seed = seed;
    const auto r = planner.planAdditions(w.ds.views, w.ds.cam, w.sim.getScenePointsById(), w.ds.yardstick, bo, noise, o);
    ASSERT_FALSE(r.left.empty()) << "seed " << seed << ": the stuck wrist must leave parameters at nominal";
    EXPECT_EQ(r.status, vpMeasurementPlanner::OK) << r.message;
    ASSERT_FALSE(r.additions.empty()) << r.message;
    EXPECT_LE(r.additions.size(), o.max_poses);
    EXPECT_GT(*std::max_element(r.ratio_before.begin(), r.ratio_before.end()), 1.0) << r.message;
    const vpKinematicChain &nominal = w.sim.getNominalChain();
    std::vector<vpColVector> q;
    for (const vpSelfCalibDataset::View &v : w.ds.views)
      q.push_back(v.q);
    for (const auto &a : r.additions) {
      EXPECT_TRUE(nominal.isInJointLimits(a.q, 1e-9));
      EXPECT_GE(a.visible, 6u);
      q.push_back(a.q);
    }
    for (size_t l = 0; l < r.left.size(); ++l)
      EXPECT_LE(r.additions.back().ratio[l], 1.0) << r.left[l] << ": " << r.message;
    EXPECT_TRUE(r.still_left.empty()) << r.message;
    // Ground truth: the true robot's views at the proposed poses.
    const vpSelfCalibDataset more = w.sim.makeDataset(q);
    ASSERT_EQ(more.views.size(), q.size());
    const auto set = vpKinematicBundleAdjustment::estimatedSet(nominal, more.cam, more.views, more.yardstick,
                                                               w.sim.getScenePointsById(), bo, noise);
    EXPECT_TRUE(leftByData(set).empty()) << "seed " << seed << ": " << leftByData(set).size() << " still left";
  }
}

// Views that determine every parameter: nothing to add, said so, no pose proposed.
TEST(PlanAdditions, NothingToAddWhenTheViewsDetermineEverything)
{
  const Stuck w(4, 0);
  const auto r = w.planner().planAdditions(w.ds.views, w.ds.cam, w.sim.getScenePointsById(), w.ds.yardstick,
                                           bundleOptions(), noiseOf(0.2), vpMeasurementPlanner::AdditionOptions());
  EXPECT_EQ(r.status, vpMeasurementPlanner::OK);
  EXPECT_TRUE(r.left.empty());
  EXPECT_TRUE(r.additions.empty());
  EXPECT_NE(r.message.find("no pose to add"), std::string::npos) << r.message;
}

// Caller mistakes: a view without joints, hand-eye-only options, nonsense options.
TEST(PlanAdditions, BadInputsThrowWithWhatIsWrong)
{
  const Stuck w(3);
  const vpMeasurementPlanner planner = w.planner();
  std::vector<vpSelfCalibDataset::View> views = w.ds.views;
  views[2].q = vpColVector();
  views[2].has_fMe = true;
  const auto X = w.sim.getScenePointsById();
  const vpMeasurementPlanner::AdditionOptions o;
  try {
    planner.planAdditions(views, w.ds.cam, X, w.ds.yardstick, bundleOptions(), noiseOf(0.2), o);
    FAIL() << "a view without joints must throw";
  } catch (const vpSelfCalibException &e) {
    EXPECT_NE(e.getStringMessage().find("view 2 has 0 joint values"), std::string::npos) << e.getStringMessage();
  }
  vpKinematicBundleAdjustment::Options he = bundleOptions();
  he.hand_eye_only = true;
  EXPECT_THROW(planner.planAdditions(w.ds.views, w.ds.cam, X, w.ds.yardstick, he, noiseOf(0.2), o), vpSelfCalibException);
  vpMeasurementPlanner::AdditionOptions bad;
  bad.max_poses = 0;
  EXPECT_THROW(planner.planAdditions(w.ds.views, w.ds.cam, X, w.ds.yardstick, bundleOptions(), noiseOf(0.2), bad),
               vpSelfCalibException);
}
