/*
 * Tests of bad input and degenerate data through vpRobotSelfCalibration (the README's catalogue):
 * each case gets a clear error, a DEGENERATE_DATA status, or a warning that says what to do, and
 * good data gets none.
 */
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include <visp3/selfcalib/vpCalibrationVerifier.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibDataCheck.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "../testCommon.h"

using namespace selfcalib_test;

namespace
{
using Result = vpRobotSelfCalibration::Result;

Result calibrate(const vpSelfCalibSimulator &sim, const vpSelfCalibDataset &ds,
                 vpRobotSelfCalibration::Method method = vpRobotSelfCalibration::BUNDLE_ADJUSTMENT)
{
  vpRobotSelfCalibration::Options o;
  o.method = method;
  o.trust_robot = true; // exact joints: the data check's findings are the subject, not the robot's error
  return vpRobotSelfCalibration::run(sim.getNominalChain(), ds, o);
}

const vpSelfCalibDataCheck::Finding *finding(const Result &r, const std::string &code)
{
  for (const auto &f : r.findings)
    if (f.code == code)
      return &f;
  return nullptr;
}

std::string codes(const Result &r)
{
  std::string s;
  for (const auto &f : r.findings)
    s += f.code + ": " + f.message + "\n";
  return s;
}

std::string thrown(const vpSelfCalibSimulator &sim, const vpSelfCalibDataset &ds)
{
  try {
    calibrate(sim, ds);
  } catch (const vpSelfCalibException &e) {
    return e.getStringMessage();
  }
  return "";
}

// Joints reaching a camera pose, by Gauss-Newton on the nominal model from q0.
bool solveIK(const vpKinematicChain &chain, const vpHomogeneousMatrix &target, const vpColVector &q0, vpColVector &q)
{
  q = q0;
  for (int it = 0; it < 50; ++it) {
    const vpHomogeneousMatrix M = chain.get_fMc(q);
    const vpTranslationVector dt = target.getTranslationVector() - M.getTranslationVector();
    const vpThetaUVector tu(target.getRotationMatrix() * M.getRotationMatrix().t());
    vpColVector e(6);
    for (unsigned int i = 0; i < 3; ++i) {
      e[i] = dt[i];
      e[3 + i] = tu[i];
    }
    if (e.frobeniusNorm() < 1e-12)
      return true;
    q += chain.getJointJacobian(q).pseudoInverse() * e;
  }
  return false;
}

// Configurations whose nominal camera poses are fMc(q_ref) * motion(k), kept when visible.
std::vector<vpColVector> around(const vpSelfCalibSimulator &sim, const vpColVector &q_ref,
                                const std::function<vpHomogeneousMatrix(int)> &motion, unsigned int wanted)
{
  std::vector<vpColVector> qs;
  const vpHomogeneousMatrix M0 = sim.getNominalChain().get_fMc(q_ref);
  vpColVector q;
  for (int k = 0; k < 200 && qs.size() < wanted; ++k)
    if (solveIK(sim.getNominalChain(), M0 * motion(k), q_ref, q) && sim.isVisible(q))
      qs.push_back(q);
  return qs;
}
// Visible configurations around the home one, joint j moved uniformly within +-spread[j].
std::vector<vpColVector> jitteredHome(const vpSelfCalibSimulator &sim, uint64_t seed, const std::vector<double> &spread,
                                      unsigned int wanted)
{
  const vpColVector h = vpSelfCalibSimulator::homeConfiguration(sim.getNominalChain());
  vpSelfCalib::Random rng(seed, 3);
  std::vector<vpColVector> qs;
  for (int k = 0; k < 400 && qs.size() < wanted; ++k) {
    vpColVector q = h;
    for (unsigned int j = 0; j < q.size(); ++j)
      q[j] += rng.uniform(-spread[j], spread[j]);
    if (sim.isVisible(q))
      qs.push_back(q);
  }
  return qs;
}
} // namespace

// Good data raises no finding: the reference scenario, both robots, several seeds.
TEST(DataCheck, ReferenceScenarioHasNoFinding)
{
  for (const std::string robot : {"viper850", "puma560"})
    for (uint64_t seed : {1, 2, 3}) {
      const vpSelfCalibSimulator sim = makeSim(robot, seed);
      const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(25));
      EXPECT_TRUE(vpSelfCalibDataCheck::check(sim.getNominalChain(), ds, 15, false, vpSelfCalibDataCheck::Options(), vpSelfCalibNoiseModel())
                      .empty())
          << robot << " seed " << seed;
    }
  // The default run (the robot's error measured: exact readings drop it) raises none either.
  const vpSelfCalibSimulator sim = makeSim("viper850", 4);
  const Result r = vpRobotSelfCalibration::run(sim.getNominalChain(), sim.makeDataset(sim.generateConfigurations(25)),
                                              vpRobotSelfCalibration::Options());
  EXPECT_EQ(r.status, vpRobotSelfCalibration::OK);
  EXPECT_TRUE(r.findings.empty()) << codes(r);
}

TEST(DataCheck, CallerMistakesThrowWithWhatToFix)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 5);
  const vpSelfCalibDataset good = sim.makeDataset(sim.generateConfigurations(16));
  const double max2 = sim.getNominalChain().getJoints()[1].max;

  vpSelfCalibDataset ds = good;
  ds.views[3].q[1] = max2 + 0.2;
  std::string msg = thrown(sim, ds);
  EXPECT_NE(msg.find("pose 3: joint 2"), std::string::npos) << msg;
  EXPECT_NE(msg.find("outside the model's limits"), std::string::npos) << msg;
  // Within the tolerance (encoder noise at a limit): accepted.
  ds.views[3].q[1] = max2 + 1e-4;
  EXPECT_EQ(vpSelfCalibDataCheck::check(sim.getNominalChain(), ds, 15, false, vpSelfCalibDataCheck::Options(), vpSelfCalibNoiseModel()).size(),
            0u);

  ds = good;
  ds.views[14].q[4] = std::numeric_limits<double>::quiet_NaN();
  msg = thrown(sim, ds);
  EXPECT_NE(msg.find("pose 14: joint 5 is not a finite number"), std::string::npos) << msg;

  ds = good;
  ds.views[2].points[7].ip.set_u(std::numeric_limits<double>::infinity());
  msg = thrown(sim, ds);
  EXPECT_NE(msg.find("pose 2: point"), std::string::npos) << msg;

  ds = good;
  ds.views[1].q.resize(5, true);
  EXPECT_NE(thrown(sim, ds), "");
}

TEST(DataCheck, IdenticalPosesAreDegenerateRepeatedOnesAWarning)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 6);
  const vpSelfCalibDataset good = sim.makeDataset(sim.generateConfigurations(20));
  vpSelfCalibDataset ds = good;
  for (unsigned int k = 1; k < 15; ++k)
    ds.views[k] = ds.views[0];
  Result r = calibrate(sim, ds);
  EXPECT_EQ(r.status, vpRobotSelfCalibration::DEGENERATE_DATA);
  EXPECT_NE(r.message.find("same robot configuration"), std::string::npos) << r.message;

  ds = good;
  ds.views[9] = ds.views[4];
  r = calibrate(sim, ds);
  EXPECT_EQ(r.status, vpRobotSelfCalibration::OK);
  ASSERT_NE(finding(r, "repeated-poses"), nullptr) << codes(r);
  EXPECT_NE(finding(r, "repeated-poses")->message.find("poses 4 and 9"), std::string::npos);
}

TEST(DataCheck, ViewWithTooFewPointsWarnsAndTheRestCalibrates)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 7);
  vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(20));
  ds.views[5].points.resize(3);
  const Result r = calibrate(sim, ds);
  EXPECT_EQ(r.status, vpRobotSelfCalibration::OK) << r.message;
  ASSERT_NE(finding(r, "few-points"), nullptr) << codes(r);
  EXPECT_NE(finding(r, "few-points")->message.find("5 (3)"), std::string::npos);
}

// The camera turns about its own centre: no parallax, nothing to triangulate.
TEST(DataCheck, PureRotationsAreDegenerate)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 8);
  const vpColVector q0 = sim.generateConfigurations(1)[0];
  const std::vector<vpColVector> qs = around(
      sim, q0,
      [](int k) { return vpHomogeneousMatrix(0, 0, 0, 0.03 * (k % 5 - 2), 0.03 * (k / 5 % 5 - 2), 0.1 * (k % 3 - 1)); },
      15);
  ASSERT_GE(qs.size(), 10u);
  const Result r = calibrate(sim, sim.makeDataset(qs));
  EXPECT_EQ(r.status, vpRobotSelfCalibration::DEGENERATE_DATA);
  EXPECT_NE(r.message.find("the camera only rotates"), std::string::npos) << r.message;
}

// The camera translates without rotating: calibration runs, with a warning; with f unknown it is
// still estimated (the robot's motion is metric), and the poorly determined parameters have large sd.
TEST(DataCheck, PureTranslationsWarn)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 9);
  const vpColVector q0 = sim.generateConfigurations(1)[0];
  const std::vector<vpColVector> qs = around(
      sim, q0,
      [](int k) {
        return vpHomogeneousMatrix(0.03 * (k % 5 - 2), 0.03 * (k / 5 % 5 - 2), 0.05 * ((3 * k) % 5 - 2), 0, 0, 0);
      },
      15);
  ASSERT_GE(qs.size(), 10u);
  const Result r = calibrate(sim, sim.makeDataset(qs));
  ASSERT_NE(finding(r, "barely-rotates"), nullptr) << codes(r);
  EXPECT_NE(finding(r, "barely-rotates")->message.find("add poses rotated"), std::string::npos);
  if (r.status == vpRobotSelfCalibration::OK)
    EXPECT_GT(r.parameter_sd.getMaxValue(), 0.01) << "an honest sd: some parameter is poorly determined";
}

// The simulator's views of a scene facing the camera (a plane x = const through the scene centre,
// with the given relief along x), observed through the true robot with 0.2 px noise.
vpSelfCalibDataset facingScene(const vpSelfCalibSimulator &sim, const std::vector<vpColVector> &qs, double relief,
                               uint64_t seed)
{
  vpSelfCalibDataset ds = sim.makeDataset(qs);
  vpSelfCalib::Random rng(seed, 5);
  const vpColVector c = sim.getSceneCentre();
  std::vector<vpColVector> X;
  for (int i = 0; i < 80; ++i) {
    vpColVector x = c;
    x[0] += relief * rng.uniform(-0.5, 0.5);
    x[1] += 0.18 * rng.uniform(-0.5, 0.5);
    x[2] += 0.14 * rng.uniform(-0.5, 0.5);
    X.push_back(x);
  }
  for (double side : {-0.05, 0.05}) { // the yardstick, ids 80 and 81
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
      vpSelfCalibDataset::Observation o;
      o.id = static_cast<int>(i);
      o.ip = vpImagePoint(cam.get_v0() + cam.get_py() * p[1] / p[2] + 0.2 * rng.normal(),
                          cam.get_u0() + cam.get_px() * p[0] / p[2] + 0.2 * rng.normal());
      if (o.ip.get_u() >= 0 && o.ip.get_v() >= 0 && o.ip.get_u() < ds.width && o.ip.get_v() < ds.height)
        v.points.push_back(o);
    }
  }
  return ds;
}

// Every point on one plane facing the camera, f known: a homography explains every pair, which is
// a warning (planar-scene), not a refusal; the full kinematic calibration goes on and the held-out
// poses are predicted as well as from a scene with relief (within 2x of the 1 cm relief run, and far
// better than the nominal model).
TEST(DataCheck, PlanarSceneWithFocalKnownCalibrates)
{
  for (uint64_t seed : {10, 11}) {
    const vpSelfCalibSimulator sim = makeSim("viper850", seed);
    const std::vector<vpColVector> qs = sim.generateConfigurations(20);
    const vpSelfCalibDataset plane = facingScene(sim, qs, 0.0, seed), relief = facingScene(sim, qs, 0.01, seed);
    const Result r = calibrate(sim, plane);
    ASSERT_EQ(r.status, vpRobotSelfCalibration::OK) << "seed " << seed << ": " << r.message;
    ASSERT_NE(finding(r, "planar-scene"), nullptr) << codes(r);
    EXPECT_NE(finding(r, "planar-scene")->message.find("the scene is a plane"), std::string::npos);
    const Result rr = calibrate(sim, relief);
    ASSERT_EQ(rr.status, vpRobotSelfCalibration::OK) << rr.message;
    const std::vector<vpSelfCalibDataset::View> held(plane.views.begin() + 15, plane.views.end());
    const std::vector<vpHomogeneousMatrix> truth = sim.getTrueCameraPoses(held);
    const double e_plane = vpCalibrationVerifier::verify(r.calibrated, r.camera, held, plane.yardstick, {}, truth)
                               .position_error_mean;
    const double e_relief = vpCalibrationVerifier::verify(rr.calibrated, rr.camera, held, plane.yardstick, {}, truth)
                                .position_error_mean;
    const double e_nominal =
        vpCalibrationVerifier::verify(sim.getNominalChain(), plane.cam, held, plane.yardstick, {}, truth)
            .position_error_mean;
    EXPECT_LT(e_plane, 2 * e_relief + 1e-4) << "seed " << seed;
    EXPECT_LT(e_plane, 0.5 * e_nominal) << "seed " << seed;
    // 1 cm of relief at 0.7 m: no finding at all.
    const auto f = vpSelfCalibDataCheck::check(sim.getNominalChain(), relief, 15, false, vpSelfCalibDataCheck::Options(), vpSelfCalibNoiseModel());
    EXPECT_TRUE(f.empty()) << (f.empty() ? "" : f[0].message);
  }
}

// The example: the wrist joints barely move.
TEST(DataCheck, StillWristWarnsWithTheJointsToMove)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 11);
  const std::vector<vpColVector> qs = jitteredHome(sim, 11, {0.08, 0.08, 0.08, 1e-3, 1e-3, 1e-3}, 20);
  ASSERT_EQ(qs.size(), 20u);
  const Result r = calibrate(sim, sim.makeDataset(qs));
  ASSERT_NE(finding(r, "joints-barely-move"), nullptr) << codes(r);
  const std::string &m = finding(r, "joints-barely-move")->message;
  EXPECT_EQ(m.find("joints 4-6 barely move"), 0u) << m;
  EXPECT_NE(m.find("add poses with larger joints 4-6 rotations"), std::string::npos) << m;
}

// Joints 2, 3 and 5 only (parallel axes): the parameters that need joints 1, 4, 6 are lost, and the
// result says which; in hand-eye mode, the rotations all share one axis direction.
TEST(DataCheck, ParallelAxesWarnAndSayWhatIsLost)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 12);
  const std::vector<vpColVector> qs = jitteredHome(sim, 12, {0, 0.1, 0.1, 0, 0.15, 0}, 18);
  ASSERT_EQ(qs.size(), 18u);
  vpSelfCalibDataset ds = sim.makeDataset(qs);
  Result r = calibrate(sim, ds);
  ASSERT_NE(finding(r, "joints-barely-move"), nullptr) << codes(r);
  EXPECT_EQ(finding(r, "joints-barely-move")->message.find("joints 1, 4 and 6 barely move"), 0u);
  // The estimated set (the fixed preference order, eMc first) holds eMc.tx, whose axis lies within
  // 1.4% of the common joint axis here: 99% of its effect is a rigid motion of the whole arm, and the
  // bundle adjustment's information keeps 5e-11 of it, below its 1e-10 test. The run fails naming the
  // undetermined parameter, or is doubtful naming the poorly determined ones (or the correction of
  // eMc.tx beyond its tolerance: its predicted sd is within the tolerance, so the estimated set from
  // the data keeps it, and the data then pull it far; or that the model is worse than the nominal one
  // away from the views: 532 mm against 8 on the camera's motions against the truth), or is ok saying
  // what is lost.
  if (r.status == vpRobotSelfCalibration::IDENTIFICATION_FAILED)
    EXPECT_NE(r.message.find("not determined: eMc.tx"), std::string::npos) << r.message;
  else if (r.status == vpRobotSelfCalibration::DOUBTFUL)
    ASSERT_TRUE(finding(r, "poorly-determined") != nullptr || finding(r, "correction-beyond-tolerance") != nullptr ||
                finding(r, "workspace-worse-than-nominal") != nullptr)
        << codes(r);
  else {
    EXPECT_EQ(r.status, vpRobotSelfCalibration::OK) << r.message;
    ASSERT_NE(finding(r, "identifiability-lost"), nullptr) << codes(r);
  }

  for (auto &v : ds.views) {
    v.has_fMe = true;
    v.fMe = sim.getTrueChain().get_fMe(v.q);
    v.q = vpColVector();
  }
  r = calibrate(sim, ds, vpRobotSelfCalibration::HAND_EYE);
  ASSERT_NE(finding(r, "parallel-rotation-axes"), nullptr) << codes(r);
  // Not a confident answer: the translation along the common axis has a large sd.
  if (r.status == vpRobotSelfCalibration::OK)
    EXPECT_GT(r.parameter_sd.getMaxValue(), 0.01);
}

TEST(DataCheck, YardstickSeenOnceCannotSetTheScale)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 13);
  vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(20));
  for (size_t k = 1; k < ds.views.size(); ++k) {
    auto &p = ds.views[k].points;
    p.erase(std::remove_if(p.begin(), p.end(),
                           [&](const vpSelfCalibDataset::Observation &o) {
                             return o.id == ds.yardstick.id_a || o.id == ds.yardstick.id_b;
                           }),
            p.end());
  }
  const Result r = calibrate(sim, ds);
  EXPECT_EQ(r.status, vpRobotSelfCalibration::OK) << r.message;
  ASSERT_NE(finding(r, "yardstick-unseen"), nullptr) << codes(r);
  EXPECT_NE(finding(r, "yardstick-unseen")->message.find("seen in 1 calibration pose"), std::string::npos);
  EXPECT_EQ(r.bundle.scale_source, vpKinematicBundleAdjustment::SCALE_NOMINAL);
  // The paper's method needs the yardstick in the pairs: a status, never a made-up scale.
  vpRobotSelfCalibration::Options o;
  o.method = vpRobotSelfCalibration::PAPER;
  EXPECT_NE(vpRobotSelfCalibration::run(sim.getNominalChain(), ds, o).status, vpRobotSelfCalibration::OK);
}

// Half of the observations replaced by random pixels (three quarters of the pair correspondences
// wrong): the run fails and says why, rather than return a model built on what is left. 30%: it
// calibrates and says how much data it did not use, or (when the reconstruction keeps less than half
// of the data) fails and says why.
TEST(DataCheck, HalfTheObservationsWrongFailsClearly)
{
  unsigned int calibrated = 0;
  for (uint64_t seed : {14, 15}) {
    const vpSelfCalibSimulator sim = makeSim("viper850", seed);
    const vpSelfCalibDataset good = sim.makeDataset(sim.generateConfigurations(20));
    vpSelfCalibDataset ds = good;
    corrupt(ds, 0.5, seed, 99);
    Result r = calibrate(sim, ds);
    EXPECT_NE(r.status, vpRobotSelfCalibration::OK) << "seed " << seed;
    EXPECT_NE(r.message.find("wrong matches"), std::string::npos) << r.message;

    ds = good;
    corrupt(ds, 0.3, seed, 99);
    r = calibrate(sim, ds);
    if (r.status == vpRobotSelfCalibration::OK) {
      ++calibrated;
      ASSERT_NE(finding(r, "outliers"), nullptr) << codes(r);
      EXPECT_NE(finding(r, "outliers")->message.find("were not used"), std::string::npos);
    } else
      EXPECT_NE(r.message.find("wrong matches"), std::string::npos) << r.message;
  }
  EXPECT_GE(calibrated, 1u);
}

TEST(DataCheck, PointsOutsideTheImageWarn)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 16);
  vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(16));
  ds.width = 320; // the camera says 320 x 480, the observations span 640 columns
  const auto f = vpSelfCalibDataCheck::check(sim.getNominalChain(), ds, 15, false, vpSelfCalibDataCheck::Options(), vpSelfCalibNoiseModel());
  ASSERT_FALSE(f.empty());
  EXPECT_EQ(f[0].code, "points-outside-image");
  EXPECT_NE(f[0].message.find("check that the camera size matches the images"), std::string::npos);
}

// The same data in one process gives the same result, bit for bit (Ceres orders blocks of a group
// by address: every block has its own group).
TEST(DataCheck, SecondRunInTheSameProcessIsBitIdentical)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 17);
  const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(12));
  const Result a = calibrate(sim, ds);
  std::vector<double> garbage(12345, 1.0); // moves the heap between the two runs
  const Result b = calibrate(sim, ds);
  ASSERT_EQ(a.status, vpRobotSelfCalibration::OK);
  const vpColVector pa = a.calibrated.getParameters(), pb = b.calibrated.getParameters();
  for (unsigned int i = 0; i < pa.size(); ++i)
    EXPECT_EQ(pa[i], pb[i]) << i;
  EXPECT_EQ(a.bundle.rms, b.bundle.rms);
  EXPECT_EQ(a.multiview.fx, b.multiview.fx);
  EXPECT_GT(garbage.size(), 0u);
}

// Few random correspondences (images of pure noise, a front end that found almost nothing) are not
// "a plane": a homography fitted to a handful of matches explains them by construction. The finding
// is about the correspondences; with many random matches there is no planar finding either; a
// plane seen through only 10 points per pair is not called a plane (too little support), through
// all of its points it is.
TEST(DataCheck, FewRandomMatchesAreNotAPlane)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 10);
  const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(15));
  const auto check = [&](const vpSelfCalibDataset &d) {
    return vpSelfCalibDataCheck::check(sim.getNominalChain(), d, 15, false, vpSelfCalibDataCheck::Options(), vpSelfCalibNoiseModel());
  };
  const auto has = [](const std::vector<vpSelfCalibDataCheck::Finding> &f, const std::string &code) {
    return std::any_of(f.begin(), f.end(), [&](const vpSelfCalibDataCheck::Finding &x) { return x.code == code; });
  };
  for (uint64_t seed : {1, 2, 3, 4, 5}) {
    for (unsigned int n : {8u, 10u, 14u, 40u}) {
      vpSelfCalibDataset noise = ds;
      vpSelfCalib::Random rng(seed, n);
      for (auto &v : noise.views) {
        v.points.clear();
        for (unsigned int id = 0; id < n; ++id) {
          vpSelfCalibDataset::Observation o;
          o.id = static_cast<int>(id);
          o.ip.set_uv(rng.uniform(0, 640), rng.uniform(0, 480));
          v.points.push_back(o);
        }
      }
      const std::vector<vpSelfCalibDataCheck::Finding> f = check(noise);
      EXPECT_FALSE(has(f, "planar-scene")) << "seed " << seed << ", " << n << " random matches";
      EXPECT_FALSE(has(f, "no-parallax")) << "seed " << seed << ", " << n << " random matches";
      EXPECT_EQ(has(f, "few-correspondences"), n < 15) << "seed " << seed << ", " << n << " random matches";
    }
  }
  // A true plane: with 10 of its points per view the verdict lacks support; with all it is a plane.
  const std::vector<vpColVector> qs = sim.generateConfigurations(20);
  const vpSelfCalibDataset plane = facingScene(sim, qs, 0.0, 10);
  EXPECT_TRUE(has(check(plane), "planar-scene"));
  vpSelfCalibDataset ten = plane;
  for (auto &v : ten.views) {
    std::vector<vpSelfCalibDataset::Observation> kept;
    for (const auto &o : v.points)
      if (o.id < 10)
        kept.push_back(o);
    v.points = kept;
  }
  const std::vector<vpSelfCalibDataCheck::Finding> f = check(ten);
  EXPECT_FALSE(has(f, "planar-scene"));
  EXPECT_TRUE(has(f, "few-correspondences"));
}

// One small tag of a known layout (4 corners per view, as ViSP's eye-to-hand set): PnP places each
// view from its 4 coplanar points and the layout gives their depth, so neither "fewer than 6 image
// points" nor "no view shares 15 points" is said; without the layout (unknown scene points) both
// are. A view with 3 of the tag's corners is named with PnP's minimum, 4. Through
// vpRobotSelfCalibration the bundle adjustment's known_points are the layout.
TEST(DataCheck, OneSmallTagOfAKnownLayoutIsEnough)
{
  vpSelfCalibSimulator::EyeToHandOptions so;
  so.board_cols = so.board_rows = 2;
  so.board_spacing = 0.048;
  so.num_views = 8;
  vpSelfCalibSimulator::EyeToHandTruth truth;
  vpSelfCalibDataset ds = vpSelfCalibSimulator::simulateEyeToHand(so, truth);
  const vpKinematicChain nominal = vpKinematicChain::preset("viper850");
  const auto has = [](const std::vector<vpSelfCalibDataCheck::Finding> &f, const std::string &code) {
    return std::any_of(f.begin(), f.end(), [&](const vpSelfCalibDataCheck::Finding &x) { return x.code == code; });
  };
  vpSelfCalibDataCheck::Options known;
  known.known_points = truth.layout;
  std::vector<vpSelfCalibDataCheck::Finding> f = vpSelfCalibDataCheck::check(nominal, ds, 8, true, known, vpSelfCalibNoiseModel());
  EXPECT_FALSE(has(f, "few-points"));
  EXPECT_FALSE(has(f, "few-correspondences"));
  f = vpSelfCalibDataCheck::check(nominal, ds, 8, true, vpSelfCalibDataCheck::Options(), vpSelfCalibNoiseModel());
  EXPECT_TRUE(has(f, "few-points"));
  EXPECT_TRUE(has(f, "few-correspondences"));

  vpRobotSelfCalibration::Options o;
  o.method = vpRobotSelfCalibration::HAND_EYE;
  o.bundle.known_points = truth.layout;
  const Result r = vpRobotSelfCalibration::run(nominal, ds, o);
  EXPECT_EQ(finding(r, "few-points"), nullptr) << codes(r);
  EXPECT_EQ(finding(r, "few-correspondences"), nullptr) << codes(r);

  ds.views[2].points.pop_back();
  f = vpSelfCalibDataCheck::check(nominal, ds, 8, true, known, vpSelfCalibNoiseModel());
  const auto it = std::find_if(f.begin(), f.end(), [](const vpSelfCalibDataCheck::Finding &x) { return x.code == "few-points"; });
  ASSERT_NE(it, f.end());
  EXPECT_EQ(it->message, "calibration poses with fewer than 4 points of the known layout: 2 (3); PnP needs 4 to place "
                         "such a pose: aim the camera so that it sees more of the board");
}
