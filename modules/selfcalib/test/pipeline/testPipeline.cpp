/*
 * Tests of the pipeline layer: the paper's 3-D verification and vpRobotSelfCalibration.
 */
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <visp3/selfcalib/vpCalibrationVerifier.h>
#include <visp3/selfcalib/vpKinematicIdentification.h>
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
  ASSERT_EQ(r.status, vpRobotSelfCalibration::OK) << r.message;
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

// The report without gnuplot: data files and report.md written, figures reported as not drawn.
TEST(Report, WithoutGnuplotTheDataAndTheTextAreStillWritten)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 14, 0.2);
  const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(12));
  vpRobotSelfCalibration::Options o;
  o.num_calibration_poses = 9;
  const auto r = vpRobotSelfCalibration::run(sim.getNominalChain(), ds, o);
  ASSERT_EQ(r.status, vpRobotSelfCalibration::OK) << r.message;
  char dir[] = "/tmp/selfcalib-report-XXXXXX";
  ASSERT_NE(mkdtemp(dir), nullptr);
  vpSelfCalibReport::Options ro;
  ro.gnuplot = "/nonexistent/gnuplot";
  const vpSelfCalibPoseStudy::Result study = vpSelfCalibPoseStudy::run(sim.getNominalChain(), ds, o);
  const auto rep = vpSelfCalibReport::write(dir, sim.getNominalChain(), ds, o, r, nullptr, &study, ro);
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
  EXPECT_EQ(rows, 4u); // 6, 7, 8 and 9 calibration poses
  EXPECT_THROW(
      vpSelfCalibReport::write("/nonexistent/dir/report", sim.getNominalChain(), ds, o, r, nullptr, &study, ro),
      vpSelfCalibException);
}
