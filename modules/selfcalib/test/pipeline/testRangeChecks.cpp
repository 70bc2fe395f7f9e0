/*
 * Tests of the library's range checks (issue 23 item 4): a camera or a kinematic chain built in
 * code with absurd numbers (a focal length of 1e200 px, inf, nan, negative, a principal point
 * beyond 1e6 px, a link of 1e308 m) is a caller's mistake: every public entry point that takes one
 * throws vpSelfCalibException naming the value, instead of letting the solvers overflow (Ceres
 * aborts the process on a CHECK). The data are the reference scenario's, valid but for the value
 * under test, so that without the check each call would reach its solver.
 */
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>

#include <visp3/selfcalib/vpCalibrationVerifier.h>
#include <visp3/selfcalib/vpKinematicBundleAdjustment.h>
#include <visp3/selfcalib/vpKinematicIdentification.h>
#include <visp3/selfcalib/vpMeasurementPlanner.h>
#include <visp3/selfcalib/vpMultiViewReconstruction.h>
#include <visp3/selfcalib/vpPoseScale.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>
#include <visp3/selfcalib/vpTwoViewEstimator.h>

#include "../testCommon.h"

using namespace selfcalib_test;

namespace
{
// The message of the vpSelfCalibException f throws, "" when it throws none (any other exception
// fails the test).
std::string thrown(const std::function<void()> &f)
{
  try {
    f();
  } catch (const vpSelfCalibException &e) {
    return e.getStringMessage();
  }
  return "";
}

const double kInf = std::numeric_limits<double>::infinity();
const double kNan = std::numeric_limits<double>::quiet_NaN();

struct Absurd {
  double px, py, u0, v0;
  const char *named; // what the message must name
};
const Absurd kAbsurd[] = {{1e200, 1e200, 320, 240, "px"}, {kInf, kInf, 320, 240, "px"}, {kNan, kNan, 320, 240, "px"},
                          {-800, -800, 320, 240, "px"},   {2e7, 2e7, 320, 240, "px"},   {800, 1e200, 320, 240, "py"},
                          {800, 800, 1e200, 240, "u0"},   {800, 800, 320, -2e7, "v0"},  {800, 800, 320, kNan, "v0"}};

vpCameraParameters camera(const Absurd &a)
{
  vpCameraParameters c;
  c.initPersProjWithoutDistortion(a.px, a.py, a.u0, a.v0);
  return c;
}

struct Scenario {
  vpSelfCalibSimulator sim = makeSim("viper850", 1);
  vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(8));
};
const Scenario &scenario()
{
  static const Scenario s;
  return s;
}
} // namespace

TEST(RangeChecks, RobotSelfCalibrationRejectsAnAbsurdCameraSetInCode)
{
  const Scenario &s = scenario();
  for (const Absurd &a : kAbsurd) {
    vpSelfCalibDataset ds = s.ds;
    ds.cam = camera(a);
    for (bool known : {true, false}) {
      ds.focal_known = known;
      const std::string m = thrown([&] { vpRobotSelfCalibration::run(s.sim.getNominalChain(), ds, {}); });
      EXPECT_NE(m.find(std::string("the dataset's camera: the ") + (a.named[0] == 'p' ? "focal length " : "principal point ") + a.named), std::string::npos)
          << a.px << " " << a.py << " " << a.u0 << " " << a.v0 << ": '" << m << "'";
    }
  }
  // The bounds themselves are accepted (a 1e6 px focal length is implausible, not a mistake).
  vpTwoViewEstimator::Options to;
  to.fx = 1e6;
  to.u0 = -1e6;
  to.v0 = 1e6;
  EXPECT_EQ(thrown([&] { to.check(); }), "");
}

TEST(RangeChecks, KinematicChainRejectsAbsurdLengthsBuiltInCode)
{
  const vpKinematicChain p = vpKinematicChain::preset("viper850");
  std::vector<vpKinematicChain::Joint> joints = p.getJoints();
  joints[1].a = 1e308;
  EXPECT_NE(thrown([&] { vpKinematicChain("bad", p.getConvention(), joints, p.get_fMb_pose(), p.get_nMe_pose(),
                                          p.get_eMc_pose()); })
                .find("joint 2's a is 1e+308"),
            std::string::npos);
  joints = p.getJoints();
  joints[3].d = -2e4;
  EXPECT_NE(thrown([&] { vpKinematicChain("bad", p.getConvention(), joints); }).find("joint 4's d"), std::string::npos);

  // Values changed after construction (setters, corrections) are caught at the entry points.
  const Scenario &s = scenario();
  vpKinematicChain eMc = s.sim.getNominalChain();
  vpPoseVector e = eMc.get_eMc_pose();
  e[2] = 1e308;
  eMc.set_eMc(e);
  EXPECT_NE(thrown([&] { vpRobotSelfCalibration::run(eMc, s.ds, {}); }).find("the hand-eye pose eMc tz is 1e+308"),
            std::string::npos);
  vpKinematicChain corr = s.sim.getNominalChain();
  corr.setParameter("j2.tx", 1e308);
  EXPECT_NE(thrown([&] { vpRobotSelfCalibration::run(corr, s.ds, {}); }).find("the correction j2.tx"),
            std::string::npos);
  corr.setParameter("j2.tx", 0);
  corr.setParameter("j3.rz", 1e300); // (setParameter itself refuses a non-finite value)
  const std::string m = thrown([&] { vpRobotSelfCalibration::run(corr, s.ds, {}); });
  EXPECT_NE(m.find("the correction j3.rz"), std::string::npos) << m;

  // The other entry points that take a chain.
  const vpKinematicBundleAdjustment::Options bo;
  EXPECT_NE(thrown([&] {
              vpKinematicBundleAdjustment::adjust(corr, s.ds.cam, s.ds.views, s.ds.yardstick, {}, bo, vpSelfCalibNoiseModel());
            }).find("vpKinematicBundleAdjustment: the model"),
            std::string::npos);
  std::vector<vpKinematicIdentification::Measurement> ms(1);
  ms[0].q = s.ds.views[0].q;
  ms[0].M = corr.nominal().get_fMc(ms[0].q);
  EXPECT_NE(thrown([&] { vpKinematicIdentification::identify(corr, ms, {}); }).find("the correction j3.rz"),
            std::string::npos);
  EXPECT_NE(thrown([&] { vpCalibrationVerifier::verify(corr, s.ds.cam, s.ds.views, s.ds.yardstick); })
                .find("vpCalibrationVerifier::verify: the model"),
            std::string::npos);
  EXPECT_NE(thrown([&] { vpMeasurementPlanner(corr, s.sim.getPlannerScene()); }).find("vpMeasurementPlanner: the nominal"),
            std::string::npos);
}

TEST(RangeChecks, EveryEntryPointTakingACameraRejectsAbsurdIntrinsics)
{
  const Scenario &s = scenario();
  const vpKinematicChain &chain = s.sim.getNominalChain();
  std::vector<vpImagePoint> p1, p2;
  for (size_t i = 0; i < s.ds.views[0].points.size() && i < s.ds.views[1].points.size(); ++i) {
    p1.push_back(s.ds.views[0].points[i].ip);
    p2.push_back(s.ds.views[1].points[i].ip);
  }
  for (const Absurd &a : kAbsurd) {
    const std::string what = std::string(a.named[0] == 'p' ? "focal length " : "principal point ") + a.named;
    const vpCameraParameters cam = camera(a);
    EXPECT_NE(thrown([&] {
                vpKinematicBundleAdjustment::adjust(chain, cam, s.ds.views, s.ds.yardstick, {},
                                                    vpKinematicBundleAdjustment::Options(), vpSelfCalibNoiseModel());
              }).find("vpKinematicBundleAdjustment: the camera: the " + what),
              std::string::npos);
    EXPECT_NE(thrown([&] {
                vpKinematicBundleAdjustment::information(chain, cam, s.ds.views, s.ds.yardstick, {},
                                                         vpKinematicBundleAdjustment::Options(), vpSelfCalibNoiseModel());
              }).find("the camera: the " + what),
              std::string::npos);
    EXPECT_NE(thrown([&] { vpCalibrationVerifier::triangulate(chain, cam, s.ds.views); }).find("the " + what),
              std::string::npos);
    vpPlannerScene scene = s.sim.getPlannerScene();
    scene.cam = cam;
    EXPECT_NE(thrown([&] { vpMeasurementPlanner(chain, scene); }).find("the scene's camera: the " + what),
              std::string::npos);
    // Two-view and multi-view: the camera is fx, mu = py / px, u0, v0 in their options.
    vpTwoViewEstimator::Options to;
    to.focal_mode = vpRefinedFactorMethod::KNOWN;
    to.fx = a.px;
    to.mu = a.py / a.px;
    to.u0 = a.u0;
    to.v0 = a.v0;
    const std::string m2 = thrown([&] { vpTwoViewEstimator::estimate(p1, p2, to); });
    EXPECT_NE(m2.find("vpTwoViewEstimator"), std::string::npos) << m2;
    vpMultiViewReconstruction::Options mo;
    mo.twoview = to;
    const std::string mm = thrown([&] { vpMultiViewReconstruction::reconstruct(s.ds.views, s.ds.yardstick, mo, vpSelfCalibNoiseModel()); });
    EXPECT_TRUE(mm.find("vpMultiViewReconstruction") != std::string::npos ||
                mm.find("vpTwoViewEstimator") != std::string::npos)
        << mm;
    if (std::isfinite(to.mu) && to.mu > 0) {
      const std::string ms = thrown([&] { vpPoseScale::yardstick({}, 0.1, a.px, a.u0, a.v0, to.mu, vpPoseScale::YardstickOptions(), vpSelfCalibNoiseModel()); });
      EXPECT_NE(ms.find("vpPoseScale::yardstick"), std::string::npos) << ms;
    }
  }
}
