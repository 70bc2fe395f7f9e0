/*
 * Tests of the pipeline layer: the paper's 3-D verification and vpRobotSelfCalibration.
 */
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <iterator>
#include <sstream>
#include <cmath>
#include <string>
#include <type_traits>
#include <vector>

#include <visp3/selfcalib/vpCalibrationVerifier.h>
#include <visp3/selfcalib/vpKinematicIdentification.h>
#include <visp3/selfcalib/vpMultiViewReconstruction.h>
#include <visp3/selfcalib/vpPoseScale.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibReport.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include <fstream>
#include <sys/stat.h>

#include "../testCommon.h"

using namespace selfcalib_test;


// Noise-free: with the model identified from exact relative poses (oracle scale), the paper's 3-D
// errors and the held-out pose errors vanish (1e-6 mm); with the nominal model they do not.
TEST(Verifier, NoiseFreeIdentifiedModelVerifiesExactly)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 11, 0.0);
  const std::vector<vpColVector> q = sim.generateConfigurations(25);
  const vpSelfCalibDataset ds = sim.makeDataset(q);
  std::vector<vpKinematicIdentification::Measurement> ms;
  for (size_t i = 1; i < 15; ++i) {
    vpKinematicIdentification::Measurement m;
    m.q = q[i];
    m.q_ref = q[0];
    m.M = sim.getTrueChain().get_fMc(q[i]).inverse() * sim.getTrueChain().get_fMc(q[0]);
    ms.push_back(m);
  }
  const auto id = vpKinematicIdentification::identify(sim.getNominalChain(), ms, vpKinematicIdentification::Options());
  ASSERT_EQ(id.status, vpKinematicIdentification::OK);
  const std::vector<vpSelfCalibDataset::View> ver(ds.views.begin() + 15, ds.views.end());
  const std::vector<vpHomogeneousMatrix> true_fMc = sim.getTrueCameraPoses(ver);
  const auto after = vpCalibrationVerifier::verify(id.chain, ds.cam, ver, ds.yardstick, sim.getScenePointsById(), true_fMc);
  ASSERT_TRUE(after.has_yardstick);
  EXPECT_NEAR(after.yardstick_length, ds.yardstick.length, 1e-9);
  EXPECT_LT(after.yardstick_error, 1e-9);
  EXPECT_EQ(after.num_pairs, 82u * 81u / 2u);
  EXPECT_LT(after.distance_error_max, 1e-9);
  ASSERT_EQ(after.position_errors.size(), 9u);
  EXPECT_LT(after.position_error_mean, 1e-9);
  EXPECT_LT(after.rotation_error_mean, 1e-9);
  const auto before = vpCalibrationVerifier::verify(sim.getNominalChain(), ds.cam, ver, ds.yardstick, sim.getScenePointsById(), true_fMc);
  EXPECT_GT(before.position_error_mean, 1e-4);
  EXPECT_GT(before.distance_error_mean, 1e-5);
  // Bad input.
  EXPECT_THROW(vpCalibrationVerifier::verify(id.chain, ds.cam, {ver[0]}, ds.yardstick), vpSelfCalibException);
  EXPECT_THROW(vpCalibrationVerifier::verify(id.chain, ds.cam, ver, ds.yardstick, {}, {true_fMc[0]}), vpSelfCalibException);
}

// The paper's procedure on noise-free images with f known: the only error left is the eq. 21
// approximation of the scale ratios by the nominal model, so the calibrated model must beat the
// nominal one on held-out poses, and the yardstick scale is within a few percent.
TEST(RobotSelfCalibration, PaperPipelineOnNoiseFreeImagesImprovesTheModel)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 12, 0.0);
  const std::vector<vpColVector> q = sim.generateConfigurations(25);
  const vpSelfCalibDataset ds = sim.makeDataset(q);
  vpRobotSelfCalibration::Options o;
  o.method = vpRobotSelfCalibration::PAPER;
  const vpRobotSelfCalibration::Result r = vpRobotSelfCalibration::run(sim.getNominalChain(), ds, o);
  // Over the joint limits this model is not better than the nominal one in position (8.45 mm against
  // 8.12 on the camera's motions against the truth; 4.7 mrad against 7.8): doubtful by the workspace
  // check, and by it alone; the held-out poses near the calibration views are the subject here.
  const auto workspace_doubt_only = [](const vpRobotSelfCalibration::Result &x) {
      return x.status == vpRobotSelfCalibration::DOUBTFUL &&
             std::all_of(x.findings.begin(), x.findings.end(), [](const auto &f) {
               return f.severity != vpSelfCalibDataCheck::DOUBT || f.code == "workspace-worse-than-nominal";
             });
    };
  ASSERT_TRUE(workspace_doubt_only(r)) << r.message;
  EXPECT_EQ(r.measurements.size(), 14u);
  EXPECT_EQ(r.identification.identifiability.identified.size(), 24u);
  EXPECT_TRUE(r.verified);
  const double T1 = (sim.getTrueChain().get_fMc(q[1]).inverse() * sim.getTrueChain().get_fMc(q[0]))
                        .getTranslationVector()
                        .frobeniusNorm();
  EXPECT_NEAR(r.scale.scale / T1, 1.0, 0.05);
  const std::vector<vpSelfCalibDataset::View> ver(ds.views.begin() + 15, ds.views.end());
  const std::vector<vpHomogeneousMatrix> true_fMc = sim.getTrueCameraPoses(ver);
  const auto before = vpCalibrationVerifier::verify(sim.getNominalChain(), ds.cam, ver, ds.yardstick, {}, true_fMc);
  const auto after = vpCalibrationVerifier::verify(r.calibrated, r.camera, ver, ds.yardstick, {}, true_fMc);
  EXPECT_LT(after.position_error_mean, before.position_error_mean);
  EXPECT_LT(after.rotation_error_mean, before.rotation_error_mean);
  // The paper method gives eMc with its sd too: the calibrated chain's, with a positive sd for
  // every estimated component and none for those held.
  ASSERT_TRUE(r.has_eMc);
  const vpPoseVector e(r.calibrated.get_eMc_corrected());
  const std::vector<std::string> names = r.calibrated.getParameterNames();
  const unsigned int first = r.calibrated.getNumParameters() - vpKinematicChain::kBlockSize;
  bool any_estimated = false;
  for (unsigned int k = 0; k < 6; ++k) {
    EXPECT_EQ(r.eMc[k], e[k]);
    any_estimated = any_estimated || r.parameter_sd[first + k] > 0;
  }
  ASSERT_EQ(r.eMc_sd.size(), 6u);
  if (any_estimated)
    EXPECT_GT(r.eMc_sd.frobeniusNorm(), 0.0);
}

// The paper's method with one focal length for all pairs, taken from every view jointly (the
// default, beyond the paper) or from the pairs alone: without noise the former is exact; at 0.2 px on
// the paper scene it is several times closer to the truth, the yardstick scale (which inherits the
// focal length's error about 2.5 times) with it, and the scale's reported sd is honest. Each scale
// error is against the same method on the noise-free images of the same poses (the eq. 21 bias
// left out, as in bench-paper). 10 seeds of the PUMA 560 (measured: focal length error RMS 0.10
// against 0.48 px, scale 0.24 against 0.47 %, error/sd RMS 1.2).
TEST(RobotSelfCalibration, PaperSharedFocalFromEveryViewIsExactAndBeatsThePairs)
{
  double f2[2] = {0, 0}, s2[2] = {0, 0}, z2 = 0;
  unsigned int n = 0;
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    vpSelfCalibSimulator::Options so = vpSelfCalibSimulator::sceneOptions("paper");
    so.seed = seed;
    const vpSelfCalibSimulator sim(vpKinematicChain::preset("puma560"), so);
    const std::vector<vpColVector> q = sim.generateConfigurations(15);
    const vpSelfCalibDataset noisy = sim.makeDataset(q);
    vpSelfCalibDataset exact = noisy;
    for (unsigned int k = 0; k < q.size(); ++k)
      exact.views[k].points = sim.observe(q[k], k, 0.0);
    const double f_true = sim.getCamera().get_px();
    vpRobotSelfCalibration::Result r0[2], r[2];
    for (int all = 0; all < 2; ++all) {
      vpRobotSelfCalibration::Options o;
      o.method = vpRobotSelfCalibration::PAPER;
      o.focal_mode = vpRobotSelfCalibration::FOCAL_SHARED;
      o.num_calibration_poses = static_cast<unsigned int>(q.size());
      o.paper_focal_all_views = all == 1;
      r0[all] = vpRobotSelfCalibration::run(sim.getNominalChain(), exact, o);
      // A model on the exact images; the paper's model itself is not exact (its eq. 21 and
      // small-motion approximations): with seed 1 it is worse than the nominal model over the joint
      // limits (8.2 mm RMS on the camera's motions against 6.9) and with seed 2 about as good (7.7
      // against 8.0), and the workspace check says so. No other doubt.
      ASSERT_TRUE(r0[all].status == vpRobotSelfCalibration::OK || r0[all].status == vpRobotSelfCalibration::DOUBTFUL)
          << "seed " << seed << ": " << r0[all].message;
      for (const auto &f : r0[all].findings)
        EXPECT_TRUE(f.severity != vpSelfCalibDataCheck::DOUBT || f.code == "workspace-worse-than-nominal")
            << "seed " << seed << ": " << f.code << ": " << f.message;
      r[all] = vpRobotSelfCalibration::run(sim.getNominalChain(), noisy, o);
    }
    ASSERT_EQ(r0[1].multiview.status, vpMultiViewReconstruction::OK) << r0[1].multiview.message;
    EXPECT_NEAR(r0[1].fx, f_true, 1e-6 * f_true) << "seed " << seed;
    // The pairs' shared focal length, which both start from, may not converge on noisy images (a
    // status: TWO_VIEW_FAILED); such a draw says nothing of the comparison.
    if (r[0].scale.status != vpPoseScale::OK || r[1].scale.status != vpPoseScale::OK)
      continue;
    for (int all = 0; all < 2; ++all) {
      const double e = r[all].scale.scale / r0[all].scale.scale - 1;
      f2[all] += (r[all].fx - f_true) * (r[all].fx - f_true);
      s2[all] += e * e;
      if (all == 1) {
        ASSERT_GT(r[all].scale.sd, 0.0);
        z2 += std::pow(e * r[all].scale.scale / r[all].scale.sd, 2);
      }
    }
    ++n;
  }
  ASSERT_GE(n, 7u) << "too few draws where the pairs' shared focal length converged";
  const double f_all = std::sqrt(f2[1] / n), f_pairs = std::sqrt(f2[0] / n);
  EXPECT_LT(f_all, 0.5 * f_pairs) << "focal length error RMS (px), every view " << f_all << ", pairs " << f_pairs;
  EXPECT_LT(std::sqrt(s2[1] / n), 0.7 * std::sqrt(s2[0] / n)) << "scale error RMS";
  // error / sd over n >= 7 draws: its RMS is 1 for an honest sd; 0.35-1.75 holds with more than
  // 99 % chance (chi-square with 7 degrees of freedom).
  const double z = std::sqrt(z2 / n);
  EXPECT_GT(z, 0.35);
  EXPECT_LT(z, 1.75);
}

// The paper's focal length from every view against a wrong stated pixel sd (0.3 px noise stated as
// 1.2 or 0.075 px). Measured (the noise model's pixel_sd of origin MEASURED): the reconstruction runs again at the measured
// level, so f and its sd are those of the right statement. Used as stated: the sd is scaled by
// sigma0, with a finding (unscaled it was 4x the right one). A right statement gives no finding.
TEST(RobotSelfCalibration, PaperFocalSdFollowsTheImageNoiseNotTheStatedOne)
{
  vpSelfCalibSimulator::Options so = vpSelfCalibSimulator::sceneOptions("paper");
  so.seed = 4;
  so.pixel_noise_sd = 0.3;
  const vpSelfCalibSimulator sim(vpKinematicChain::preset("puma560"), so);
  const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(15));
  const auto run = [&](double factor, bool measure) {
    vpRobotSelfCalibration::Options o;
    o.method = vpRobotSelfCalibration::PAPER;
    o.focal_mode = vpRobotSelfCalibration::FOCAL_SHARED;
    o.num_calibration_poses = 15;
    o.noise.pixel_sd = factor * so.pixel_noise_sd;
    if (measure)
      o.noise.measure_pixel_sd = true;
    return vpRobotSelfCalibration::run(sim.getNominalChain(), ds, o);
  };
  const auto imageNoiseFinding = [](const vpRobotSelfCalibration::Result &r) {
    for (const auto &f : r.findings)
      if (f.code == "noise-mismatch" && f.message.find("image residuals") != std::string::npos)
        return true;
    return false;
  };
  const vpRobotSelfCalibration::Result right = run(1.0, false);
  ASSERT_EQ(right.multiview.status, vpMultiViewReconstruction::OK) << right.multiview.message;
  ASSERT_GT(right.fx_sd, 0.0);
  EXPECT_FALSE(imageNoiseFinding(right));
  EXPECT_NEAR(right.measured.pixel_sd, so.pixel_noise_sd, 0.1 * so.pixel_noise_sd);
  for (const double factor : {4.0, 0.25}) {
    const vpRobotSelfCalibration::Result r = run(factor, true);
    ASSERT_EQ(r.multiview.status, vpMultiViewReconstruction::OK) << r.multiview.message;
    EXPECT_NEAR(r.noise.pixel_sd, so.pixel_noise_sd, 0.1 * so.pixel_noise_sd) << "stated x" << factor;
    EXPECT_EQ(r.multiview.num_outliers, right.multiview.num_outliers) << "stated x" << factor;
    EXPECT_NEAR(r.fx, right.fx, 0.05 * right.fx_sd) << "stated x" << factor;
    EXPECT_NEAR(r.fx_sd / right.fx_sd, 1.0, 0.1) << "stated x" << factor;
    EXPECT_FALSE(imageNoiseFinding(r)) << "stated x" << factor;
  }
  const vpRobotSelfCalibration::Result stated = run(4.0, false);
  EXPECT_TRUE(imageNoiseFinding(stated));
  EXPECT_NEAR(stated.fx_sd / right.fx_sd, 1.0, 0.1);
}

TEST(RobotSelfCalibration, BadInputsGiveAStatusOrAnError)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 13, 0.2);
  const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(18));
  vpRobotSelfCalibration::Options o;
  o.method = vpRobotSelfCalibration::PAPER;
  // A pose with no correspondences.
  vpSelfCalibDataset bad = ds;
  bad.views[4].points.clear();
  EXPECT_THROW(vpRobotSelfCalibration::run(sim.getNominalChain(), bad, o), vpSelfCalibException);
  // No yardstick at all.
  bad = ds;
  bad.yardstick = vpSelfCalibDataset::Yardstick();
  EXPECT_THROW(vpRobotSelfCalibration::run(sim.getNominalChain(), bad, o), vpSelfCalibException);
  // The yardstick seen in one view only (the first): no pair can measure it.
  bad = ds;
  for (size_t k = 1; k < bad.views.size(); ++k) {
    auto &pts = bad.views[k].points;
    pts.erase(std::remove_if(pts.begin(), pts.end(),
                             [&](const vpSelfCalibDataset::Observation &ob) {
                               return ob.id == ds.yardstick.id_a || ob.id == ds.yardstick.id_b;
                             }),
              pts.end());
  }
  const auto r = vpRobotSelfCalibration::run(sim.getNominalChain(), bad, o);
  EXPECT_EQ(r.status, vpRobotSelfCalibration::SCALE_FAILED);
  EXPECT_NE(r.message.find("yardstick"), std::string::npos);
  // Too few views, and joints of the wrong size.
  bad = ds;
  bad.views.resize(2);
  EXPECT_THROW(vpRobotSelfCalibration::run(sim.getNominalChain(), bad, o), vpSelfCalibException);
  bad = ds;
  bad.views[3].q.resize(4);
  EXPECT_THROW(vpRobotSelfCalibration::run(sim.getNominalChain(), bad, o), vpSelfCalibException);
}

// The options of the steps come from the top-level Options and the dataset, by the builders: the noise
// from the top level, the camera from the dataset, the flags from the focal mode and the method; the
// caller's other settings of each step are kept.
TEST(RobotSelfCalibration, StepOptionsAreBuiltFromTheTopLevelOptionsAndTheDataset)
{
  using RSC = vpRobotSelfCalibration;
  const vpSelfCalibSimulator sim = makeSim("viper850", 15, 0.2);
  vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(6));
  ds.focal_known = false;
  ds.cam.initPersProjWithoutDistortion(1390, 1410, 318, 243); // a guess: f self-calibrated
  RSC::Options o;
  o.noise.pixel_sd = 0.7;
  o.twoview.ransac.inlier_threshold = 2;
  o.multiview.max_pair_points = 123;
  o.bundle.intrinsics |= vpKinematicBundleAdjustment::ASPECT;
  o.bundle.fixed = {"j2.tx"};
  o.data_check.min_points = 9;
  ASSERT_NO_THROW(o.check());
  EXPECT_EQ(RSC::resolveFocalMode(o, ds), RSC::FOCAL_SHARED);

  const vpMultiViewReconstruction::Options mo = RSC::multiViewOptions(o, ds);
  EXPECT_FALSE(mo.focal_known);
  EXPECT_EQ(mo.max_pair_points, 123u);
  EXPECT_EQ(mo.twoview.fx, 1390);
  EXPECT_EQ(mo.twoview.u0, 318);
  EXPECT_EQ(mo.twoview.v0, 243);
  EXPECT_EQ(mo.twoview.mu, 1410.0 / 1390.0);
  EXPECT_EQ(mo.twoview.focal_mode, vpRefinedFactorMethod::PER_PAIR);
  EXPECT_EQ(mo.twoview.ransac.inlier_threshold, 2);
  const vpTwoViewEstimator::Options to = RSC::twoViewOptions(o, ds);
  EXPECT_EQ(to.fx, mo.twoview.fx);
  EXPECT_EQ(to.mu, mo.twoview.mu);
  const vpKinematicBundleAdjustment::Options bo = RSC::bundleOptions(o, ds);
  EXPECT_EQ(bo.intrinsics, vpKinematicBundleAdjustment::FX | vpKinematicBundleAdjustment::ASPECT);
  EXPECT_FALSE(bo.hand_eye_only);
  EXPECT_EQ(bo.fixed, std::vector<std::string>{"j2.tx"});
  // The run's tolerances, not the bundle adjustment's own defaults (the estimated set, the planner, the prior).
  RSC::Options tight = o;
  tight.tolerance_translation = 0.003;
  tight.tolerance_rotation = 0.005;
  tight.tolerance_hand_eye_translation = 0.004;
  tight.tolerance_hand_eye_rotation = 0.02;
  const vpKinematicBundleAdjustment::Options bt = RSC::bundleOptions(tight, ds);
  EXPECT_EQ(bt.tolerance_translation, 0.003);
  EXPECT_EQ(bt.tolerance_rotation, 0.005);
  EXPECT_EQ(bt.tolerance_hand_eye_translation, 0.004);
  EXPECT_EQ(bt.tolerance_hand_eye_rotation, 0.02);
  // The dataset's fix / free lists added to the caller's (plan --from plans with them), its kinematic
  // prior where the caller sets none.
  vpSelfCalibDataset with_sets = ds;
  with_sets.fix = {"j3.*", "j2.tx"};
  with_sets.free = {"j4.tz"};
  with_sets.kinematic_prior = 3;
  const vpKinematicBundleAdjustment::Options bs = RSC::bundleOptions(o, with_sets);
  EXPECT_EQ(bs.fixed, (std::vector<std::string>{"j2.tx", "j3.*"}));
  EXPECT_EQ(bs.free, std::vector<std::string>{"j4.tz"});
  EXPECT_EQ(bs.kinematic_prior, 3.0);
  RSC::Options own_prior = o;
  own_prior.bundle.kinematic_prior = 1;
  EXPECT_EQ(RSC::bundleOptions(own_prior, with_sets).kinematic_prior, 1.0);
  // Off is said (the caller's over the dataset's prior, the dataset's over the default); neither the
  // caller nor the dataset: left empty, the bundle adjustment's default, tolerance / 3.
  own_prior.bundle.kinematic_prior = vpKinematicBundleAdjustment::KINEMATIC_PRIOR_OFF;
  EXPECT_EQ(RSC::bundleOptions(own_prior, with_sets).kinematicPrior(), 0.0);
  with_sets.kinematic_prior = vpKinematicBundleAdjustment::KINEMATIC_PRIOR_OFF;
  EXPECT_EQ(RSC::bundleOptions(o, with_sets).kinematicPrior(), 0.0);
  EXPECT_FALSE(RSC::bundleOptions(o, ds).kinematic_prior.has_value());
  EXPECT_EQ(RSC::bundleOptions(o, ds).kinematicPrior(), 3.0);
  EXPECT_EQ(vpKinematicBundleAdjustment::DEFAULT_KINEMATIC_PRIOR, 3.0);
  const vpSelfCalibDataCheck::Options co = RSC::dataCheckOptions(o);
  EXPECT_EQ(co.min_points, 9u);
  EXPECT_EQ(RSC::noiseModel(o, ds).pixel_sd, 0.7);

  // A builder's output put back into the Options (its settings) builds the same.
  RSC::Options back = o;
  back.twoview = to;
  back.multiview = mo;
  back.bundle = bo;
  back.data_check = co;
  ASSERT_NO_THROW(back.check());
  EXPECT_EQ(RSC::multiViewOptions(back, ds).twoview.fx, 1390);
  EXPECT_EQ(RSC::bundleOptions(back, ds).intrinsics, bo.intrinsics);

  // The focal length known: KNOWN everywhere, FX no longer estimated (the caller's ASPECT kept).
  ds.focal_known = true;
  EXPECT_EQ(RSC::resolveFocalMode(o, ds), RSC::FOCAL_KNOWN);
  EXPECT_TRUE(RSC::multiViewOptions(o, ds).focal_known);
  EXPECT_EQ(RSC::twoViewOptions(o, ds).focal_mode, vpRefinedFactorMethod::KNOWN);
  EXPECT_EQ(RSC::bundleOptions(o, ds).intrinsics, static_cast<unsigned int>(vpKinematicBundleAdjustment::ASPECT));
  o.method = RSC::HAND_EYE;
  EXPECT_TRUE(RSC::bundleOptions(o, ds).hand_eye_only);
}

// The run's inputs (the camera, the focal mode, the method's mode) are not among the caller's
// settings: Options holds the steps' Settings types, and the builders add the inputs from the
// dataset, focal_mode and method whatever the settings were built from.
TEST(RobotSelfCalibration, StepInputsComeFromTheDatasetTheFocalModeAndTheMethod)
{
  using RSC = vpRobotSelfCalibration;
  static_assert(std::is_same<decltype(RSC::Options::twoview), vpTwoViewEstimator::Settings>::value,
                "Options::twoview holds no camera");
  static_assert(std::is_same<decltype(RSC::Options::multiview), vpMultiViewReconstruction::Settings>::value,
                "Options::multiview holds no camera and no focal mode");
  static_assert(std::is_same<decltype(RSC::Options::bundle), vpKinematicBundleAdjustment::Settings>::value,
                "Options::bundle holds no mode");
  const vpSelfCalibSimulator sim = makeSim("viper850", 16, 0.2);
  vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(6));
  ds.focal_known = false;
  ds.cam.initPersProjWithoutDistortion(1390, 1410, 318, 243);
  // Settings taken from a builder's output made on another camera and focal mode: the run's
  // inputs are this dataset's and this focal mode's.
  vpTwoViewEstimator::Options other;
  other.fx = 500;
  other.u0 = 10;
  other.focal_mode = vpRefinedFactorMethod::KNOWN;
  other.huber = 1.5;
  RSC::Options o;
  o.twoview = other;
  o.bundle.intrinsics = vpKinematicBundleAdjustment::PRINCIPAL_POINT; // FX: focal_mode's
  const vpTwoViewEstimator::Options to = RSC::twoViewOptions(o, ds);
  EXPECT_EQ(to.fx, 1390);
  EXPECT_EQ(to.u0, 318);
  EXPECT_EQ(to.focal_mode, vpRefinedFactorMethod::PER_PAIR);
  EXPECT_EQ(to.huber, 1.5);
  EXPECT_EQ(RSC::multiViewOptions(o, ds).twoview.fx, 1390);
  EXPECT_EQ(RSC::bundleOptions(o, ds).intrinsics,
            vpKinematicBundleAdjustment::FX | vpKinematicBundleAdjustment::PRINCIPAL_POINT);
  o.focal_mode = RSC::FOCAL_KNOWN;
  EXPECT_EQ(RSC::twoViewOptions(o, ds).focal_mode, vpRefinedFactorMethod::KNOWN);
  EXPECT_TRUE(RSC::multiViewOptions(o, ds).focal_known);
  EXPECT_EQ(RSC::bundleOptions(o, ds).intrinsics,
            static_cast<unsigned int>(vpKinematicBundleAdjustment::PRINCIPAL_POINT));
  EXPECT_FALSE(RSC::bundleOptions(o, ds).hand_eye_only);
  o.method = RSC::HAND_EYE;
  EXPECT_TRUE(RSC::bundleOptions(o, ds).hand_eye_only);
}

// The noise model is the method's: a robot error the method does not model is a caller mistake, and
// the dataset's robot_error fills the part the method uses when the caller leaves it at 0.
TEST(RobotSelfCalibration, TheNoiseModelIsTheMethods)
{
  using RSC = vpRobotSelfCalibration;
  const vpSelfCalibSimulator sim = makeSim("viper850", 16, 0.2);
  vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(6));
  RSC::Options o;
  o.noise.pose_sd_translation = o.noise.pose_sd_rotation = 1e-3;
  EXPECT_THROW(o.check(), vpSelfCalibException); // controller poses with the full kinematics
  EXPECT_THROW(RSC::run(sim.getNominalChain(), ds, o), vpSelfCalibException);
  o.method = RSC::HAND_EYE;
  EXPECT_NO_THROW(o.check());
  o.noise.joint_sd = {1e-4};
  EXPECT_THROW(o.check(), vpSelfCalibException); // joint readings with hand-eye
  o = RSC::Options();
  o.noise.model_sd_translation = 1e-3;
  EXPECT_THROW(o.check(), vpSelfCalibException); // one part of a pair
  o.noise.model_sd_rotation = 1e-3;
  EXPECT_NO_THROW(o.check());
  o.method = RSC::PAPER;
  EXPECT_THROW(o.check(), vpSelfCalibException); // the paper models no robot error
  o = RSC::Options();
  o.noise.pixel_sd = 0;
  EXPECT_THROW(o.check(), vpSelfCalibException);
  // The dataset's robot_error, in the method's form.
  ds.pose_sd_translation = 2e-3;
  ds.pose_sd_rotation = 3e-3;
  ds.joint_sd = {1e-4};
  o = RSC::Options();
  EXPECT_TRUE(RSC::noiseModel(o, ds).joint_sd == std::vector<double>{1e-4});
  EXPECT_FALSE(RSC::noiseModel(o, ds).hasPoseError());
  EXPECT_TRUE(RSC::bundleOptions(o, ds).scale_covariance);
  o.method = RSC::HAND_EYE;
  EXPECT_EQ(RSC::noiseModel(o, ds).pose_sd_translation, 2e-3);
  EXPECT_EQ(RSC::noiseModel(o, ds).pose_sd_rotation, 3e-3);
  EXPECT_TRUE(RSC::noiseModel(o, ds).joint_sd.empty());
  o.noise.pose_sd_translation = o.noise.pose_sd_rotation = 1e-3; // the caller's stands
  EXPECT_EQ(RSC::noiseModel(o, ds).pose_sd_translation, 1e-3);
  EXPECT_FALSE(RSC::bundleOptions(o, ds).scale_covariance);
}

// run() builds what it needs from the caller's Options and leaves them as they were: a second run
// with the same Options gives the same result.
TEST(RobotSelfCalibration, RunLeavesTheOptionsUnchanged)
{
  using RSC = vpRobotSelfCalibration;
  const vpSelfCalibSimulator sim = makeSim("viper850", 17, 0.2);
  const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(12));
  RSC::Options o;
  o.num_calibration_poses = 9;
  o.noise.pixel_sd = 0.3;
  o.bundle.fixed = {"j1.tz"};
  const RSC::Options copy = o;
  const RSC::Result a = RSC::run(sim.getNominalChain(), ds, o);
  ASSERT_EQ(a.status, RSC::OK) << a.message;
  EXPECT_EQ(o.noise.pixel_sd, copy.noise.pixel_sd);
  EXPECT_EQ(o.multiview.max_pair_points, copy.multiview.max_pair_points);
  EXPECT_EQ(o.twoview.ransac.seed, copy.twoview.ransac.seed);
  EXPECT_EQ(o.bundle.intrinsics, copy.bundle.intrinsics);
  EXPECT_EQ(o.bundle.fixed, copy.bundle.fixed); // the run's extra fixed parameters stay in the run
  const RSC::Result b = RSC::run(sim.getNominalChain(), ds, o);
  ASSERT_EQ(b.status, RSC::OK) << b.message;
  EXPECT_EQ(a.fx, b.fx);
  EXPECT_EQ(a.message, b.message);
  EXPECT_EQ(a.calibrated.getParameters(), b.calibrated.getParameters());
}

// The report without gnuplot: data files and report.md written, figures reported as not drawn.
TEST(Report, WithoutGnuplotTheDataAndTheTextAreStillWritten)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 14, 0.2);
  const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(15));
  vpRobotSelfCalibration::Options o;
  o.num_calibration_poses = 12;
  o.trust_robot = true; // exact joints; the report's files are the subject, not the robot's error
  const auto r = vpRobotSelfCalibration::run(sim.getNominalChain(), ds, o);
  ASSERT_EQ(r.status, vpRobotSelfCalibration::OK) << r.message;
  char dir[] = "/tmp/selfcalib-report-XXXXXX";
  ASSERT_NE(mkdtemp(dir), nullptr);
  vpSelfCalibReport::Options ro;
  ro.gnuplot = "/nonexistent/gnuplot";
  vpSelfCalibPoseStudy::Options so;
  so.min_poses = 11; // fewer views can be doubtful (workspace-worse-than-nominal: 9 and 10 here) and are not plotted
  const vpSelfCalibPoseStudy::Result study = vpSelfCalibPoseStudy::run(sim.getNominalChain(), ds, o, so);
  vpSelfCalibReport::Record run(sim.getNominalChain(), ds, o, r);
  run.errors_vs_poses = &study;
  const auto rep = vpSelfCalibReport::write(dir, run, ro);
  EXPECT_FALSE(rep.figures);
  EXPECT_NE(rep.message.find("gnuplot-nox"), std::string::npos);
  std::ifstream md(std::string(dir) + "/report.md");
  const std::string text((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("| j2.tx |"), std::string::npos);
  EXPECT_NE(text.find("Not estimated"), std::string::npos);
  std::ifstream curve(std::string(dir) + "/errors_vs_poses.dat");
  std::string line;
  unsigned int rows = 0;
  while (std::getline(curve, line))
    rows += !line.empty() && line[0] != '#';
  EXPECT_EQ(rows, 2u); // 11 and 12 calibration poses
  // No front end: no match matrix, no track-length figure.
  EXPECT_FALSE(std::filesystem::exists(std::string(dir) + "/matches.dat"));
  EXPECT_FALSE(std::filesystem::exists(std::string(dir) + "/track_lengths.dat"));
  // Per calibration view: the calibrated model explains every view at the noise level, the nominal
  // model (errors of millimetres) does not.
  std::ifstream per_view(std::string(dir) + "/view_residuals.dat");
  rows = 0;
  while (std::getline(per_view, line)) {
    if (line.empty() || line[0] == '#')
      continue;
    std::istringstream in(line);
    unsigned int view = 0;
    double calibrated = 0, nom = 0;
    ASSERT_TRUE(in >> view >> calibrated >> nom) << line;
    EXPECT_EQ(view, ++rows);
    EXPECT_LT(calibrated, 1.0) << line;  // 0.2 px noise
    EXPECT_GT(nom, 2 * calibrated) << line;
  }
  EXPECT_EQ(rows, 12u); // one row per calibration view

  // With a front end: the match matrix symmetric, one row per image, and the track-length histogram.
  vpFeatureFrontEnd::Result fe;
  fe.features = {100, 120, 90};
  fe.yardstick_seen = {false, false, false};
  fe.matches = {{0, 40, 0}, {0, 0, 25}, {0, 0, 0}};
  fe.track_lengths = {0, 0, 30, 5};
  fe.num_tracks = 35;
  char dir2[] = "/tmp/selfcalib-report-XXXXXX";
  ASSERT_NE(mkdtemp(dir2), nullptr);
  run.front_end = &fe;
  vpSelfCalibReport::write(dir2, run, ro);
  std::ifstream mm(std::string(dir2) + "/matches.dat");
  std::vector<std::vector<unsigned int>> matrix;
  while (std::getline(mm, line))
    if (!line.empty() && line[0] != '#') {
      std::istringstream in(line);
      matrix.emplace_back(std::istream_iterator<unsigned int>(in), std::istream_iterator<unsigned int>());
    }
  const std::vector<std::vector<unsigned int>> expected = {{0, 40, 0}, {40, 0, 25}, {0, 25, 0}};
  EXPECT_EQ(matrix, expected);
  std::ifstream tl(std::string(dir2) + "/track_lengths.dat");
  std::vector<std::string> hist;
  while (std::getline(tl, line))
    if (!line.empty() && line[0] != '#')
      hist.push_back(line);
  EXPECT_EQ(hist, (std::vector<std::string>{"2 30", "3 5"}));
  std::ifstream md2(std::string(dir2) + "/report.md");
  const std::string text2((std::istreambuf_iterator<char>(md2)), std::istreambuf_iterator<char>());
  EXPECT_NE(text2.find("(figure matches.png not drawn: figures not drawn: '/nonexistent/gnuplot'"), std::string::npos);
  std::filesystem::remove_all(dir2);
  run.front_end = nullptr;
  EXPECT_THROW(vpSelfCalibReport::write("/nonexistent/dir/report", run, ro), vpSelfCalibException);
}


/*
  Hand-eye models the controller poses' error by default and measures it: poses without error
  measure it below a serial arm's repeatability and the run ends at exact poses (the trusted run's
  estimate); poses off by 2 mm / 2 mrad measure about that, the sd of eMc covering its error. A
  stated error (the options', the dataset's) is used as stated; trust_robot keeps exact poses.
*/
TEST(RobotSelfCalibration, HandEyeMeasuresTheRobotErrorByDefault)
{
  using RSC = vpRobotSelfCalibration;
  for (uint64_t seed : {31, 32}) {
    const vpSelfCalibSimulator sim = makeSim("viper850", seed, 0.2);
    RSC::Options o;
    o.method = RSC::HAND_EYE;
    o.num_calibration_poses = 12;
    vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(12));
    toControllerPoses(sim, ds, 0, 0, seed, 98);
    const vpSelfCalibNoiseModel start = RSC::noiseModel(o, ds);
    EXPECT_EQ(start.pose_sd_translation, 1e-3);
    EXPECT_EQ(start.pose_sd_rotation, 1e-3);
    EXPECT_TRUE(start.measure_pose_sd); // a start, to be measured
    EXPECT_EQ(start.pose_sd_origin, vpSelfCalibNoiseModel::STATED);
    const RSC::Result r = RSC::run(sim.getNominalChain(), ds, o);
    ASSERT_EQ(r.status, RSC::OK) << seed << ": " << r.message;
    EXPECT_FALSE(r.noise.hasPoseError()) << seed << ": " << r.noise.pose_sd_translation;
    EXPECT_EQ(r.noise.pose_sd_origin, vpSelfCalibNoiseModel::MEASURED); // the run measured it
    for (const auto &f : r.findings)
      EXPECT_NE(f.code, "robot-error-not-settled") << seed << ": " << f.message;
    RSC::Options trusted = o;
    trusted.trust_robot = true;
    EXPECT_FALSE(RSC::noiseModel(trusted, ds).hasPoseError());
    const RSC::Result t = RSC::run(sim.getNominalChain(), ds, trusted);
    ASSERT_EQ(t.status, RSC::OK) << seed << ": " << t.message;
    for (unsigned int i = 0; i < t.calibrated.getNumParameters(); ++i)
      EXPECT_NEAR(r.calibrated.getParameters()[i], t.calibrated.getParameters()[i], 1e-9) << seed << " " << i;

    // 2 mm / 2 mrad of pose error: measured, and eMc within 3 of its sd of the truth.
    ds = sim.makeDataset(sim.generateConfigurations(12));
    toControllerPoses(sim, ds, 2e-3, 2e-3, seed, 98);
    const RSC::Result e = RSC::run(sim.getNominalChain(), ds, o);
    ASSERT_EQ(e.status, RSC::OK) << seed << ": " << e.message;
    EXPECT_GT(e.noise.pose_sd_translation, 1.2e-3) << seed;
    EXPECT_LT(e.noise.pose_sd_translation, 3e-3) << seed;
    EXPECT_GT(e.noise.pose_sd_rotation, 1.2e-3) << seed;
    EXPECT_LT(e.noise.pose_sd_rotation, 3e-3) << seed;
    const unsigned int first = sim.getTrueChain().getNumParameters() - vpKinematicChain::kBlockSize;
    for (unsigned int i = first; i < first + 6; ++i)
      EXPECT_LT(std::fabs(e.calibrated.getParameters()[i] - sim.getTrueChain().getParameters()[i]),
                3 * e.parameter_sd[i])
          << seed << " " << i;

    // Stated errors are used as stated.
    ds.pose_sd_translation = 5e-3;
    ds.pose_sd_rotation = 4e-3;
    EXPECT_EQ(RSC::noiseModel(o, ds).pose_sd_translation, 5e-3);
    EXPECT_EQ(RSC::noiseModel(trusted, ds).pose_sd_rotation, 4e-3);
    o.noise.pose_sd_translation = o.noise.pose_sd_rotation = 3e-3;
    EXPECT_EQ(RSC::noiseModel(o, ds).pose_sd_translation, 3e-3);
  }
}

namespace
{
//! Joint readings off by sd (rad) on every joint of every view: the images stay those of the true joints.
void offsetReadings(vpSelfCalibDataset &ds, double sd, uint64_t seed, uint64_t stream)
{
  vpSelfCalib::Random rng(seed, stream);
  for (auto &v : ds.views)
    for (unsigned int i = 0; i < v.q.size(); ++i)
      v.q[i] += rng.normal(sd);
}
} // namespace

/*
  The bundle method, nothing stating the robot's error (the default Options, no robot_error in the
  dataset), models it from robotErrorPrior() (joint readings and the model's residual) and measures it: joint readings off by 0.03 deg measure about that back
  on every seed (variance components inside the bundle adjustment, the priors re-weighed until they
  settle; the method runs once), the origin MEASURED,
  the mean over the seeds within 20 % of the truth. trust_robot (calibrate --joint-sd 0) models no
  robot error: no joint corrections, the readings taken as exact.
*/
TEST(RobotSelfCalibration, BundleMeasuresTheJointReadingErrorByDefault)
{
  using RSC = vpRobotSelfCalibration;
  const double joint_sd = 0.03 * M_PI / 180.0;
  double sum = 0;
  const uint64_t seeds[] = {51, 52, 53};
  for (uint64_t seed : seeds) {
    const vpSelfCalibSimulator sim = makeSim("viper850", seed, 0.2);
    RSC::Options o;
    o.num_calibration_poses = 15; // nothing states the robot's error: the default models and measures it
    vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(15));
    offsetReadings(ds, joint_sd, seed, 97);
    const vpSelfCalibNoiseModel start = RSC::noiseModel(o, ds);
    EXPECT_TRUE(start.joint_sd == std::vector<double>{RSC::kJointErrorPrior});
    EXPECT_TRUE(start.measure_joint_sd && start.measure_model_sd); // a start, to be measured
    EXPECT_EQ(start.joint_sd_origin, vpSelfCalibNoiseModel::STATED);
    EXPECT_EQ(start.model_sd_translation, RSC::kModelErrorPrior);
    unsigned int method_runs = 0;
    const RSC::Result r = RSC::run(sim.getNominalChain(), ds, o, [&](const std::string &stage, unsigned int, unsigned int) {
      method_runs += stage == "identification from the multi-view poses";
    });
    ASSERT_EQ(r.status, RSC::OK) << seed << ": " << r.message;
    EXPECT_EQ(method_runs, 1u) << seed; // measured inside the bundle adjustment, not by runs again
    // A 6-joint arm: the joints alone take the robot's error (the model residual is not split from
    // them); the level settles after one or two solves again.
    EXPECT_TRUE(r.bundle.robot_error_confounded) << seed;
    EXPECT_FALSE(r.noise.hasModelError()) << seed;
    EXPECT_GE(r.bundle.robot_rounds, 1u) << seed;
    EXPECT_LE(r.bundle.robot_rounds, 2u) << seed;
    ASSERT_EQ(r.noise.joint_sd.size(), 6u) << seed; // one measured factor on the prior's one value for every joint
    EXPECT_EQ(r.noise.joint_sd.front(), r.noise.joint_sd.back());
    EXPECT_EQ(r.noise.joint_sd_origin, vpSelfCalibNoiseModel::MEASURED);
    EXPECT_EQ(r.bundle.joint_corrections.size(), 15u);
    const double ratio = r.noise.joint_sd[0] / joint_sd;
    EXPECT_GT(ratio, 0.7) << seed;
    EXPECT_LT(ratio, 1.4) << seed;
    sum += ratio;
    for (const auto &f : r.findings)
      EXPECT_NE(f.code, "robot-error-not-settled") << seed << ": " << f.message;

    RSC::Options trusted = o;
    trusted.trust_robot = true;
    EXPECT_FALSE(RSC::noiseModel(trusted, ds).hasRobotError());
    const RSC::Result t = RSC::run(sim.getNominalChain(), ds, trusted);
    EXPECT_FALSE(t.noise.hasRobotError()) << seed;
    EXPECT_TRUE(t.bundle.joint_corrections.empty()) << seed;
    EXPECT_TRUE(t.bundle.pose_corrections.empty()) << seed;
  }
  EXPECT_NEAR(sum / std::size(seeds), 1.0, 0.2);
}

/*
  Exact joint readings and model: the default's robot error measures below a serial arm's
  repeatability and is dropped, the run ending with no robot error modelled and the trusted run's
  estimate (the default costs runs, not accuracy).
*/
TEST(RobotSelfCalibration, BundleDropsTheRobotErrorOnExactReadings)
{
  using RSC = vpRobotSelfCalibration;
  const vpSelfCalibSimulator sim = makeSim("viper850", 54, 0.2);
  RSC::Options o;
  o.num_calibration_poses = 15; // nothing states the robot's error: the default models and measures it
  const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(15));
  unsigned int method_runs = 0;
  const RSC::Result r = RSC::run(sim.getNominalChain(), ds, o, [&](const std::string &stage, unsigned int, unsigned int) {
    method_runs += stage == "identification from the multi-view poses";
  });
  ASSERT_EQ(r.status, RSC::OK) << r.message;
  EXPECT_FALSE(r.noise.hasRobotError()) << r.noise.joint_sd.size() << " " << r.noise.model_sd_translation;
  // Measured inside the one bundle adjustment: the method runs once, the variance components measure
  // the joints' factor near 0 from the first solve or the next (Helmert's estimate is unbiased
  // whatever the prior, where the diagonal one shrank the level by 1.5 to 4 a round: 3 to 5
  // rounds), and one solve without the dropped corrections ends it.
  EXPECT_EQ(method_runs, 1u);
  EXPECT_GE(r.bundle.robot_rounds, 1u);
  EXPECT_LE(r.bundle.robot_rounds, 2u);
  for (const auto &f : r.findings)
    EXPECT_NE(f.code, "robot-error-not-settled") << f.message;
  RSC::Options trusted = o;
  trusted.trust_robot = true;
  const RSC::Result t = RSC::run(sim.getNominalChain(), ds, trusted);
  ASSERT_EQ(t.status, RSC::OK) << t.message;
  for (unsigned int i = 0; i < t.calibrated.getNumParameters(); ++i)
    EXPECT_NEAR(r.calibrated.getParameters()[i], t.calibrated.getParameters()[i], 1e-9) << i;
  // The same sd and the same findings: the dropped run's last solve is the trusted run's problem,
  // weighed and scaled as it is (no measured image noise factor left over: no noise-mismatch).
  ASSERT_EQ(r.parameter_sd.size(), t.parameter_sd.size());
  for (unsigned int i = 0; i < t.parameter_sd.size(); ++i)
    EXPECT_NEAR(r.parameter_sd[i], t.parameter_sd[i], 1e-3 * t.parameter_sd[i] + 1e-12) << i;
  EXPECT_EQ(r.bundle.covariance_scaled, t.bundle.covariance_scaled);
  EXPECT_EQ(r.findings.size(), t.findings.size());
  // The set decided again at the level measured (dropped): the trusted run's, not the one the
  // prior's 3e-4 rad allows.
  EXPECT_EQ(r.identifiability.identified, t.identifiability.identified);
}

namespace
{
/*
  r, a default run whose robot error was dropped (measured beyond a real arm's, or not measured), is
  the trusted run t (calibrate --joint-sd 0 on the same data) with one more finding, `code`
  (robot-error-taken-exact, robot-error-not-measured), naming the joint readings: the same set
  estimated, the same values (1e-9 relative), sd, sigma0, noise model and findings.
*/
void expectTrustedRun(const vpRobotSelfCalibration::Result &r, const vpRobotSelfCalibration::Result &t,
                      const std::string &what, const std::string &code = "robot-error-taken-exact")
{
  ASSERT_EQ(r.status, t.status) << what << ": " << r.message;
  EXPECT_EQ(r.identifiability.identified, t.identifiability.identified) << what;
  const vpColVector pr = r.calibrated.getParameters(), pt = t.calibrated.getParameters();
  ASSERT_EQ(pr.size(), pt.size());
  for (unsigned int i = 0; i < pt.size(); ++i)
    EXPECT_NEAR(pr[i], pt[i], 1e-9 * std::max(1.0, std::fabs(pt[i]))) << what << " " << i;
  ASSERT_EQ(r.parameter_sd.size(), t.parameter_sd.size());
  for (unsigned int i = 0; i < t.parameter_sd.size(); ++i)
    EXPECT_NEAR(r.parameter_sd[i], t.parameter_sd[i], 1e-9 * t.parameter_sd[i] + 1e-15) << what << " " << i;
  EXPECT_NEAR(r.bundle.sigma0, t.bundle.sigma0, 1e-9 * t.bundle.sigma0) << what;
  EXPECT_FALSE(r.noise.hasRobotError()) << what;
  EXPECT_EQ(r.noise.pixel_sd, t.noise.pixel_sd) << what;
  ASSERT_EQ(r.findings.size(), t.findings.size() + 1) << what << ": " << r.message;
  for (size_t i = 0; i < t.findings.size(); ++i)
    EXPECT_EQ(r.findings[i].code, t.findings[i].code) << what;
  EXPECT_EQ(r.findings.back().code, code) << what;
  EXPECT_NE(r.findings.back().message.find("joint readings"), std::string::npos) << what;
}

/*
  The views' images taken from the true camera displaced by a 6-D error (t m, r rad, in the camera
  frame, drawn per view) that no kinematic parameter explains; 0.2 px noise, joint readings exact
  (a rendering's per-view displacement, or a model residual beyond a real arm's).
*/
void displaceCameras(const vpSelfCalibSimulator &sim, vpSelfCalibDataset &ds, double t, double r, uint64_t seed)
{
  vpSelfCalib::Random rng(seed, 43);
  const vpCameraParameters cam = sim.getCamera();
  const std::vector<vpColVector> &X = sim.getScenePoints();
  for (auto &v : ds.views) {
    const vpHomogeneousMatrix delta(rng.normal(t), rng.normal(t), rng.normal(t), rng.normal(r), rng.normal(r),
                                    rng.normal(r));
    const vpHomogeneousMatrix cMf = (sim.getTrueChain().get_fMc(v.q) * delta).inverse();
    for (auto &o : v.points) {
      const vpColVector x = cMf * vpColVector({X[o.id][0], X[o.id][1], X[o.id][2], 1.0});
      o.ip.set_uv(cam.get_u0() + cam.get_px() * x[0] / x[2] + rng.normal(0.2),
                  cam.get_v0() + cam.get_py() * x[1] / x[2] + rng.normal(0.2));
    }
  }
}
} // namespace

/*
  A misfit the model cannot explain, measured by default as joint error: every joint's parameters
  held (fixed) at the nominal values, which the simulated true robot is a few mm and mrad off, on
  exact readings (calibrate --fix 'j*' on a robot that needs its kinematics calibrated). The variance
  components put milliradians on the joints, beyond any real arm's encoders: the run takes the
  readings as exact (robot-error-taken-exact), and is the trusted run (expectTrustedRun()), whose
  checks make it doubtful. Real reading noise at a real arm's level is measured as such
  (BundleMeasuresTheJointReadingErrorByDefault, FiveJointArmMeasuresTheModelResidualWithTheJoints,
  app-default-joint-error).
*/
TEST(RobotSelfCalibration, BundleDoubtsAJointErrorBeyondARealArms)
{
  using RSC = vpRobotSelfCalibration;
  const vpSelfCalibSimulator sim = makeSim("viper850", 81, 0.2);
  const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(15));
  RSC::Options o;
  o.num_calibration_poses = 15;
  o.bundle.fixed = {"j*"}; // held at the nominal values, a few mm and mrad off the true robot's
  const RSC::Result r = RSC::run(sim.getNominalChain(), ds, o);
  ASSERT_EQ(r.status, RSC::DOUBTFUL) << r.message;
  RSC::Options trusted = o;
  trusted.trust_robot = true;
  expectTrustedRun(r, RSC::run(sim.getNominalChain(), ds, trusted), "fixed joints");
}

/*
  Exact joint readings, each view's camera displaced by 1 mm / 1 mrad (as rendered images are, by
  about half that, in app-images): the joint corrections take the displacement, measured beyond a
  real arm's. Taken as exact, the result is the trusted run's from the top, not a run again from the
  measured run's state (which estimated fewer parameters, its sigma0 against an image noise measured
  on the way): the same set, values, sd and sigma0 as trust_robot (calibrate --joint-sd 0).
*/
TEST(RobotSelfCalibration, BundleTakenExactIsTheTrustedRun)
{
  using RSC = vpRobotSelfCalibration;
  const vpSelfCalibSimulator sim = makeSim("viper850", 83, 0.0);
  vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(10));
  displaceCameras(sim, ds, 1e-3, 1e-3, 83);
  RSC::Options o;
  o.num_calibration_poses = 10;
  const RSC::Result r = RSC::run(sim.getNominalChain(), ds, o);
  RSC::Options trusted = o;
  trusted.trust_robot = true;
  expectTrustedRun(r, RSC::run(sim.getNominalChain(), ds, trusted), "displaced cameras");
}

/*
  The robot's error asked to be measured from a guessed level that leaves the estimate undetermined:
  the dataset's robot_error states 0.9 rad on the joints, measured (calibrate --joint-sd auto). On a
  6-joint arm each view's joint corrections span its camera's 6-D motion, so at that level the
  kinematic corrections are held by the joints' prior alone: the smallest fraction of their own
  information left falls as the level grows (on this scenario 3e-9 at 0.1 rad, 8e-11 at 0.3 rad,
  2e-11 at 0.9 rad) and the covariance's singularity test (1e-10: marginalCovariance()) finds it
  singular. The level is not measured (robot-error-not-measured) and the result is the
  trusted run's from the top: calibrate --joint-sd 0 on the same data, the dataset's level cleared
  (expectTrustedRun()); images with 0.2 px noise, 10 views, two seeds. (The default prior,
  3e-4 rad, leaves far more: no data of the reference scenario reach the test from it.)
*/
TEST(RobotSelfCalibration, BundleNotMeasuredIsTheTrustedRun)
{
  using RSC = vpRobotSelfCalibration;
  for (uint64_t seed : {1u, 2u}) {
    const vpSelfCalibSimulator sim = makeSim("viper850", seed, 0.2);
    vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(10));
    ds.joint_sd = {0.9};
    RSC::Options o;
    o.num_calibration_poses = 10;
    o.noise.measure_joint_sd = o.noise.measure_model_sd = true; // calibrate --joint-sd auto
    const RSC::Result r = RSC::run(sim.getNominalChain(), ds, o);
    RSC::Options trusted = o; // calibrate --joint-sd 0
    trusted.trust_robot = true;
    trusted.noise.measure_joint_sd = trusted.noise.measure_model_sd = false;
    vpSelfCalibDataset exact = ds;
    exact.joint_sd.clear(); // --joint-sd 0: exact readings, whatever the dataset's robot_error says
    expectTrustedRun(r, RSC::run(sim.getNominalChain(), exact, trusted), "seed " + std::to_string(seed),
                     "robot-error-not-measured");
    ASSERT_FALSE(r.findings.empty());
    EXPECT_NE(r.findings.back().message.find("(900.00 mrad)"), std::string::npos) << r.findings.back().message;
  }
}

namespace
{
//! RMS over the held-out pairs (q[0], q[k]) of the error of model's relative camera position against the truth's (m).
double heldOutError(const vpKinematicChain &model, const vpKinematicChain &truth, const std::vector<vpColVector> &q)
{
  double sum = 0;
  for (size_t k = 1; k < q.size(); ++k) {
    const vpHomogeneousMatrix a = model.get_fMc(q[0]).inverse() * model.get_fMc(q[k]);
    const vpHomogeneousMatrix b = truth.get_fMc(q[0]).inverse() * truth.get_fMc(q[k]);
    sum += (a.getTranslationVector() - b.getTranslationVector()).sumSquare();
  }
  return std::sqrt(sum / static_cast<double>(q.size() - 1));
}
} // namespace

/*
  A low-cost arm: joint readings off by 0.15 deg (2.6 mrad, a low-cost arm's backlash), beyond a
  well-built arm's 1 mrad. The corrections look like reading noise (no offset, no per-view
  displacement: vpSelfCalibRobotErrorStructure.h), so the default measures the level (within
  0.7-1.4x the truth, its own sd below a third of it) instead of taking the readings as exact, and
  its held-out error is within 1.3x that of a run told the true level (calibrate --joint-sd TRUE);
  two seeds.
*/
TEST(RobotSelfCalibration, BundleMeasuresALowCostArmsJointError)
{
  using RSC = vpRobotSelfCalibration;
  const double joint_sd = 0.15 * M_PI / 180.0;
  for (uint64_t seed : {71u, 72u}) {
    const vpSelfCalibSimulator sim = makeSim("viper850", seed, 0.2);
    const std::vector<vpColVector> q = sim.generateConfigurations(25);
    vpSelfCalibDataset ds = sim.makeDataset(std::vector<vpColVector>(q.begin(), q.begin() + 15));
    offsetReadings(ds, joint_sd, seed, 99);
    RSC::Options o;
    o.num_calibration_poses = 15;
    const RSC::Result r = RSC::run(sim.getNominalChain(), ds, o);
    ASSERT_TRUE(r.status == RSC::OK || r.status == RSC::DOUBTFUL) << seed << ": " << r.message;
    for (const auto &f : r.findings) {
      EXPECT_NE(f.code, "robot-error-taken-exact") << seed << ": " << f.message;
      EXPECT_NE(f.code, "robot-error-implausible") << seed << ": " << f.message;
    }
    ASSERT_FALSE(r.noise.joint_sd.empty()) << seed;
    EXPECT_EQ(r.noise.joint_sd_origin, vpSelfCalibNoiseModel::MEASURED) << seed;
    EXPECT_GT(r.noise.joint_sd[0] / joint_sd, 0.7) << seed;
    EXPECT_LT(r.noise.joint_sd[0] / joint_sd, 1.4) << seed;
    EXPECT_GT(r.bundle.measured_joint_level_sd, 0) << seed;
    EXPECT_LT(r.bundle.measured_joint_level_sd, r.noise.joint_sd[0] / 3) << seed;
    // The result carries what the corrections were judged to be: reading noise.
    EXPECT_TRUE(r.joint_error_structure.judged && r.joint_error_structure.readingNoise())
        << seed << ": " << r.joint_error_structure.describe();

    RSC::Options told = o;
    told.noise.joint_sd = {joint_sd};
    told.bundle.scale_covariance = true;
    const RSC::Result t = RSC::run(sim.getNominalChain(), ds, told);
    ASSERT_TRUE(t.status == RSC::OK || t.status == RSC::DOUBTFUL) << seed << ": " << t.message;
    const std::vector<vpColVector> held(q.begin() + 15, q.end());
    const double e = heldOutError(r.calibrated, sim.getTrueChain(), held);
    const double et = heldOutError(t.calibrated, sim.getTrueChain(), held);
    EXPECT_LT(e, 1.3 * et) << seed << ": default " << 1e3 * e << " mm, told " << 1e3 * et << " mm";
    std::cout << "seed " << seed << ": joint level " << 1e3 * r.noise.joint_sd[0] << " mrad (sd "
              << 1e3 * r.bundle.measured_joint_level_sd << "), held-out " << 1e3 * e << " mm, told " << 1e3 * et
              << " mm\n";
  }
}

/*
  The image noise's variance component measured with the robot's: pixel noise 0.5 px stated as
  0.2 px, joint readings off by 0.03 deg, the robot's error measured. The pixels' factor comes out
  near 2.5 (the pixels' redundancy is about 2000: its relative sd is about 2 %, 10 % allowed for
  the robot corrections' share) and the joint level near the truth (not inflated by the pixel
  residual the corrections would otherwise take up), on three seeds; the covariance is that of the
  measured weights.
*/
TEST(RobotSelfCalibration, BundleMeasuresAnUnderstatedPixelNoiseWithTheRobotError)
{
  using RSC = vpRobotSelfCalibration;
  const double joint_sd = 0.03 * M_PI / 180.0;
  for (uint64_t seed : {61u, 62u, 63u}) {
    const vpSelfCalibSimulator sim = makeSim("viper850", seed, 0.5);
    RSC::Options o;
    o.num_calibration_poses = 15;
    o.noise.pixel_sd = 0.2;
    o.noise.measure_joint_sd = o.noise.measure_model_sd = true;
    vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(15));
    offsetReadings(ds, joint_sd, seed, 98);
    const RSC::Result r = RSC::run(sim.getNominalChain(), ds, o);
    ASSERT_TRUE(r.status == RSC::OK || r.status == RSC::DOUBTFUL) << seed << ": " << r.message;
    EXPECT_NEAR(r.bundle.pixel_factor, 2.5, 0.25) << seed;
    EXPECT_TRUE(r.bundle.covariance_scaled) << seed;
    EXPECT_DOUBLE_EQ(r.noise.pixel_sd, 0.2) << seed; // stated: kept, its factor measured
    ASSERT_FALSE(r.noise.joint_sd.empty()) << seed;
    EXPECT_GT(r.noise.joint_sd[0] / joint_sd, 0.6) << seed;
    EXPECT_LT(r.noise.joint_sd[0] / joint_sd, 1.5) << seed;
  }
}

namespace
{
/*
  A 5-joint arm (base yaw, shoulder, elbow, wrist pitch and roll; joint limits whose middles are an
  arm reaching forward) and its views of a scene 0.4 m deep: joints drawn within +-10 deg of home
  whose camera sees 40 scene points and the yardstick (a 600 px lens: a 5-joint arm cannot follow
  the reference scenario's look-at poses). Each view's image is taken from the
  true camera displaced by a 6-D model residual (model_t m, model_r rad, in the camera frame) that
  no kinematic parameter explains, with 0.2 px noise; its joint readings are off by joint_sd (rad).
*/
vpSelfCalibSimulator fiveJointSim(uint64_t seed)
{
  std::vector<vpKinematicChain::Joint> joints(5);
  joints[0].d = 0.35;
  joints[0].alpha = -M_PI / 2;
  joints[1].a = 0.4;
  joints[1].min = -1.6, joints[1].max = 0.2;
  joints[2].a = 0.35;
  joints[2].min = 0.2, joints[2].max = 2.0;
  joints[3].alpha = -M_PI / 2;
  joints[3].min = -1.0, joints[3].max = 1.4;
  joints[4].d = 0.1;
  const vpKinematicChain arm("arm5", vpKinematicChain::DH, joints, vpPoseVector(), vpPoseVector(),
                             vpPoseVector(0, 0.05, 0.05, 0, 0, 0));
  vpSelfCalibSimulator::Options so;
  so.seed = seed;
  so.px = so.py = 600;
  so.min_visible_points = 40;
  so.box_x = so.box_y = so.box_z = 0.4; // points 0.4 m deep: a camera's translation told from its rotation
  return vpSelfCalibSimulator(arm, so);
}

vpSelfCalibDataset fiveJointDataset(const vpSelfCalibSimulator &sim, unsigned int m, double joint_sd, double model_t,
                                    double model_r, uint64_t seed)
{
  vpSelfCalib::Random rng(seed, 41);
  const vpColVector home = vpSelfCalibSimulator::homeConfiguration(sim.getNominalChain());
  std::vector<vpColVector> qs;
  for (unsigned int attempt = 0; qs.size() < m && attempt < 100000; ++attempt) {
    vpColVector q = home;
    for (unsigned int i = 0; i < q.size(); ++i)
      q[i] += rng.uniform(-1, 1) * 10 * M_PI / 180;
    if (sim.getNominalChain().isInJointLimits(q) && sim.isVisible(q))
      qs.push_back(q);
  }
  EXPECT_EQ(qs.size(), m);
  vpSelfCalibDataset ds = sim.makeDataset(qs);
  const vpCameraParameters cam = sim.getCamera();
  const std::vector<vpColVector> &X = sim.getScenePoints();
  const vpSelfCalibSimulator::Options &so = sim.getOptions();
  for (auto &v : ds.views) {
    const vpHomogeneousMatrix delta(rng.normal(model_t), rng.normal(model_t), rng.normal(model_t),
                                    rng.normal(model_r), rng.normal(model_r), rng.normal(model_r));
    const vpHomogeneousMatrix cMf = (sim.getTrueChain().get_fMc(v.q) * delta).inverse();
    v.points.clear();
    for (size_t i = 0; i < X.size(); ++i) {
      const vpColVector x = cMf * vpColVector({X[i][0], X[i][1], X[i][2], 1.0});
      const double u = cam.get_u0() + cam.get_px() * x[0] / x[2] + rng.normal(so.pixel_noise_sd);
      const double w = cam.get_v0() + cam.get_py() * x[1] / x[2] + rng.normal(so.pixel_noise_sd);
      if (x[2] > 0 && u >= 0 && w >= 0 && u <= so.width - 1 && w <= so.height - 1) {
        vpSelfCalibDataset::Observation o;
        o.id = static_cast<int>(i);
        o.ip.set_uv(u, w);
        v.points.push_back(o);
      }
    }
    for (unsigned int i = 0; i < v.q.size(); ++i)
      v.q[i] += rng.normal(joint_sd);
  }
  return ds;
}
} // namespace

/*
  The model's residual on an arm of fewer than 6 joints: each view's 5 joint corrections leave one
  direction of its camera's displacement to the model residual, so the images can tell the two
  apart and both are measured (the variance components' factors with an sd below 1 and correlated
  below 0.9: not merged into the joints). The default run on a 5-joint arm, readings off by
  0.03 deg and a model residual of 0.2 mm / 0.2 mrad per view, 20 views: ok, neither level merged
  nor dropped, each measured within 0.5-2x of the truth per seed and within 40 % on average over 3
  seeds (measured: joints 0.81-0.92, model translation 0.95-1.15, rotation 1.21-1.50). With 5
  views the model's factors are not told from the joints' (sd above 1 or correlated beyond 0.9):
  merged (robot_error_confounded), the model residual not modelled, the joints taking the error.
*/
TEST(RobotSelfCalibration, FiveJointArmMeasuresTheModelResidualWithTheJoints)
{
  using RSC = vpRobotSelfCalibration;
  const double joint_sd = 0.03 * M_PI / 180.0, model_t = 2e-4, model_r = 2e-4;
  const unsigned int nv = 20;
  double joint_ratio = 0, model_t_ratio = 0, model_r_ratio = 0;
  const uint64_t seeds[] = {71, 72, 73};
  for (uint64_t seed : seeds) {
    const vpSelfCalibSimulator sim = fiveJointSim(seed);
    const vpSelfCalibDataset ds = fiveJointDataset(sim, nv, joint_sd, model_t, model_r, seed);
    RSC::Options o;
    o.num_calibration_poses = nv;
    const RSC::Result r = RSC::run(sim.getNominalChain(), ds, o);
    // Seed 73 is better than the nominal model over the joint limits (6.7 mm / 7.0 mrad against 7.8 /
    // 14.2 against the truth) but its predicted error leaves a 15 % chance of the contrary: doubtful
    // by the workspace check alone, which is not the subject here.
    const auto workspace_doubt_only = [](const vpRobotSelfCalibration::Result &x) {
        return x.status == vpRobotSelfCalibration::DOUBTFUL &&
               std::all_of(x.findings.begin(), x.findings.end(), [](const auto &f) {
                 return f.severity != vpSelfCalibDataCheck::DOUBT || f.code == "workspace-worse-than-nominal";
               });
      };
    ASSERT_TRUE(r.status == RSC::OK || workspace_doubt_only(r)) << seed << ": " << r.message;
    EXPECT_FALSE(r.bundle.robot_error_confounded) << seed;
    ASSERT_EQ(r.noise.joint_sd.size(), sim.getNominalChain().getNumJoints()) << seed;
    ASSERT_TRUE(r.noise.hasModelError()) << seed;
    EXPECT_EQ(r.noise.joint_sd_origin, vpSelfCalibNoiseModel::MEASURED) << seed;
    EXPECT_EQ(r.noise.model_sd_origin, vpSelfCalibNoiseModel::MEASURED) << seed;
    const double ratios[3] = {r.noise.joint_sd[0] / joint_sd, r.noise.model_sd_translation / model_t,
                              r.noise.model_sd_rotation / model_r};
    for (double ratio : ratios) {
      EXPECT_GT(ratio, 0.5) << seed;
      EXPECT_LT(ratio, 2.0) << seed;
    }
    joint_ratio += ratios[0] / std::size(seeds);
    model_t_ratio += ratios[1] / std::size(seeds);
    model_r_ratio += ratios[2] / std::size(seeds);
  }
  EXPECT_NEAR(joint_ratio, 1.0, 0.4);
  EXPECT_NEAR(model_t_ratio, 1.0, 0.4);
  EXPECT_NEAR(model_r_ratio, 1.0, 0.4);

  const vpSelfCalibSimulator sim = fiveJointSim(74);
  const vpSelfCalibDataset few = fiveJointDataset(sim, 5, joint_sd, model_t, model_r, 74);
  RSC::Options o;
  o.num_calibration_poses = 5;
  const RSC::Result r = RSC::run(sim.getNominalChain(), few, o);
  // 5 views may leave the model worse than the nominal one away from them (a doubt); the subject
  // here is the residual's confounding with the joints, which the adjustment reports either way.
  const bool workspace_doubt = std::any_of(r.findings.begin(), r.findings.end(),
                                           [](const auto &f) { return f.code == "workspace-worse-than-nominal"; });
  ASSERT_TRUE(r.status == RSC::OK || (r.status == RSC::DOUBTFUL && workspace_doubt)) << r.message;
  EXPECT_TRUE(r.bundle.robot_error_confounded);
  EXPECT_FALSE(r.noise.hasModelError());
  ASSERT_EQ(r.noise.joint_sd.size(), 5u);
  EXPECT_EQ(r.noise.joint_sd_origin, vpSelfCalibNoiseModel::MEASURED);
  EXPECT_GT(r.noise.joint_sd[0] / joint_sd, 0.5); // the joints take the whole error
  EXPECT_LT(r.noise.joint_sd[0] / joint_sd, 3.0);
}
