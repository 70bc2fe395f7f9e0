/*
 * Tests of the reference simulator and of the instantly moved Viper850.
 */
#include <gtest/gtest.h>

#include <cmath>

#include <visp3/core/vpMeterPixelConversion.h>
#include <visp3/core/vpPoint.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>
#include <visp3/selfcalib/vpSelfCalibSimulatorViper850.h>

namespace
{
vpSelfCalibSimulator makeSim(const std::string &robot, uint64_t seed)
{
  vpSelfCalibSimulator::Options o;
  o.seed = seed;
  return vpSelfCalibSimulator(vpKinematicChain::preset(robot), o);
}

void expectSameObservations(const std::vector<vpSelfCalibDataset::Observation> &a,
                            const std::vector<vpSelfCalibDataset::Observation> &b)
{
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].id, b[i].id);
    EXPECT_EQ(a[i].ip.get_u(), b[i].ip.get_u());
    EXPECT_EQ(a[i].ip.get_v(), b[i].ip.get_v());
  }
}
} // namespace

TEST(Simulator, OptionsCheckRejectsNonsense)
{
  auto bad = [](auto mutate) {
    vpSelfCalibSimulator::Options o;
    mutate(o);
    EXPECT_THROW(o.check(), vpSelfCalibException);
  };
  bad([](auto &o) { o.joint_translation_sd = -1; });
  bad([](auto &o) { o.hand_eye_rotation_sd = std::nan(""); });
  bad([](auto &o) { o.width = 0; });
  bad([](auto &o) { o.px = 0; });
  bad([](auto &o) { o.num_points = 0; });
  bad([](auto &o) { o.distance_min = 0.9; });
  bad([](auto &o) { o.yardstick_length = 0.5; });
  bad([](auto &o) { o.image_margin = 300; });
  bad([](auto &o) { o.pixel_noise_sd = -0.1; });
  bad([](auto &o) { o.view_cone = 3; });
  vpSelfCalibSimulator::Options ok;
  EXPECT_NO_THROW(ok.check());
  vpSelfCalibSimulator::Options home;
  home.home = vpColVector(5, 0.0);
  EXPECT_THROW(vpSelfCalibSimulator(vpKinematicChain::preset("viper850"), home), vpSelfCalibException);
}

TEST(Simulator, SameSeedSameDataBitForBit)
{
  const vpSelfCalibSimulator a = makeSim("viper850", 7), b = makeSim("viper850", 7), c = makeSim("viper850", 8);
  for (unsigned int i = 0; i < a.getTrueChain().getNumParameters(); ++i)
    EXPECT_EQ(a.getTrueChain().getParameters()[i], b.getTrueChain().getParameters()[i]);
  EXPECT_NE(a.getTrueChain().getParameters()[6], c.getTrueChain().getParameters()[6]);
  for (size_t i = 0; i < a.getScenePoints().size(); ++i)
    for (unsigned int k = 0; k < 3; ++k)
      EXPECT_EQ(a.getScenePoints()[i][k], b.getScenePoints()[i][k]);
  const std::vector<vpColVector> qa = a.generateConfigurations(5), qb = b.generateConfigurations(5);
  ASSERT_EQ(qa.size(), 5u);
  for (size_t k = 0; k < qa.size(); ++k)
    for (unsigned int i = 0; i < 6; ++i)
      EXPECT_EQ(qa[k][i], qb[k][i]);
  // Noise of view k does not depend on the order of the calls.
  const auto o3 = a.observe(qa[3], 3);
  a.observe(qa[1], 1);
  expectSameObservations(o3, b.observe(qa[3], 3));
}

TEST(Simulator, TrueRobotErrorsHaveTheRequestedSpread)
{
  // Over 40 seeds, the sample sd of each kind of error is within 15% of the option (n = 40 * 18 draws
  // for joints: relative sd of the estimate about 4%).
  double jt = 0, jr = 0, ht = 0, hr = 0;
  unsigned int njt = 0, nht = 0;
  for (uint64_t s = 0; s < 40; ++s) {
    const vpSelfCalibSimulator sim = makeSim("puma560", s);
    const vpColVector p = sim.getTrueChain().getParameters();
    for (unsigned int b = 1; b <= 6; ++b)
      for (unsigned int k = 0; k < 3; ++k, ++njt) {
        jt += p[6 * b + k] * p[6 * b + k];
        jr += p[6 * b + 3 + k] * p[6 * b + 3 + k];
      }
    for (unsigned int k = 0; k < 3; ++k, ++nht) {
      ht += p[42 + k] * p[42 + k];
      hr += p[45 + k] * p[45 + k];
    }
  }
  const vpSelfCalibSimulator::Options o;
  EXPECT_NEAR(std::sqrt(jt / njt) / o.joint_translation_sd, 1.0, 0.15);
  EXPECT_NEAR(std::sqrt(jr / njt) / o.joint_rotation_sd, 1.0, 0.15);
  EXPECT_NEAR(std::sqrt(ht / nht) / o.hand_eye_translation_sd, 1.0, 0.3);
  EXPECT_NEAR(std::sqrt(hr / nht) / o.hand_eye_rotation_sd, 1.0, 0.3);
}

TEST(Simulator, ConfigurationsAreInLimitsAndSeeTheWholeScene)
{
  for (const char *robot : {"viper850", "puma560"}) {
    const vpSelfCalibSimulator sim = makeSim(robot, 3);
    const std::vector<vpColVector> q = sim.generateConfigurations(25);
    ASSERT_EQ(q.size(), 25u);
    const vpSelfCalibDataset ds = sim.makeDataset(q);
    const vpSelfCalibSimulator::Options &o = sim.getOptions();
    for (size_t k = 0; k < q.size(); ++k) {
      EXPECT_TRUE(sim.getNominalChain().isInJointLimits(q[k])) << robot;
      EXPECT_TRUE(sim.isVisible(q[k]));
      EXPECT_EQ(ds.views[k].points.size(), o.num_points + 2) << robot << " view " << k;
      // The nominal camera looks at the scene centre from the requested distance.
      const vpHomogeneousMatrix cMf = sim.getNominalChain().get_fMc(q[k]).inverse();
      const vpColVector c = sim.getSceneCentre();
      const vpTranslationVector cc = cMf * vpTranslationVector(c[0], c[1], c[2]);
      EXPECT_NEAR(cc[0], 0, 1e-8);
      EXPECT_NEAR(cc[1], 0, 1e-8);
      EXPECT_GE(cc[2], o.distance_min - 1e-8);
      EXPECT_LE(cc[2], o.distance_max + 1e-8);
      for (size_t j = 0; j < k; ++j)
        EXPECT_GT((q[k] - q[j]).frobeniusNorm(), 1e-3) << "configurations " << j << " and " << k << " coincide";
    }
  }
}

// Partial views (the paper scene): every configuration sees both yardstick ends and at least N
// points through the true robot, the dataset has exactly the points in the image, and the views are
// indeed partial. The reference scene is the default options.
TEST(Simulator, PaperSceneHasPartialViewsWithTheYardstick)
{
  const vpSelfCalibSimulator::Options ref = vpSelfCalibSimulator::sceneOptions("reference"), def;
  EXPECT_EQ(ref.px, def.px);
  EXPECT_EQ(ref.num_points, def.num_points);
  EXPECT_EQ(ref.min_visible_points, 0u);
  EXPECT_EQ(ref.view_cone, def.view_cone);
  EXPECT_THROW(vpSelfCalibSimulator::sceneOptions("nope"), vpSelfCalibException);
  for (const char *robot : {"viper850", "puma560"}) {
    vpSelfCalibSimulator::Options o = vpSelfCalibSimulator::sceneOptions("paper");
    o.seed = 2;
    const vpSelfCalibSimulator sim(vpKinematicChain::preset(robot), o);
    const std::vector<vpColVector> q = sim.generateConfigurations(10);
    const vpSelfCalibDataset ds = sim.makeDataset(q);
    const vpSelfCalibDataset::Yardstick y = sim.getYardstick();
    unsigned int partial = 0;
    for (size_t k = 0; k < q.size(); ++k) {
      EXPECT_TRUE(sim.isVisible(q[k]));
      EXPECT_GE(sim.countVisible(q[k]), o.min_visible_points) << robot << " view " << k;
      bool a = false, b = false;
      for (const auto &ob : ds.views[k].points) {
        a = a || ob.id == y.id_a;
        b = b || ob.id == y.id_b;
        EXPECT_GE(ob.ip.get_u(), 0);
        EXPECT_LE(ob.ip.get_u(), o.width - 1);
      }
      EXPECT_TRUE(a && b) << robot << " view " << k << ": the yardstick";
      if (ds.views[k].points.size() < o.num_points + 2)
        ++partial;
    }
    EXPECT_GT(partial, 0u) << robot << ": the views should be partial";
    // The planner's scene carries the same rule.
    EXPECT_EQ(sim.getPlannerScene().min_visible, o.min_visible_points);
    ASSERT_EQ(sim.getPlannerScene().required.size(), 2u);
    EXPECT_EQ(sim.getPlannerScene().required[0], static_cast<unsigned int>(y.id_a));
  }
  vpSelfCalibSimulator::Options bad = vpSelfCalibSimulator::sceneOptions("paper");
  bad.min_visible_points = bad.num_points + 3;
  EXPECT_THROW(bad.check(), vpSelfCalibException);
}

// The layers that consume simulated views take partial ones: both pipelines calibrate on the paper
// scene without noise and leave a smaller 3-D error than the nominal model.
TEST(Simulator, PipelinesCalibrateOnPartialViews)
{
  const vpSelfCalibSimulator sim(vpKinematicChain::preset("viper850"), vpSelfCalibSimulator::sceneOptions("paper"));
  const std::vector<vpColVector> q = sim.generateConfigurations(14);
  vpSelfCalibDataset ds = sim.makeDataset(q);
  for (auto &v : ds.views)
    v.points = sim.observe(v.q, static_cast<unsigned int>(&v - &ds.views[0]), 0.0);
  for (auto method : {vpRobotSelfCalibration::PAPER, vpRobotSelfCalibration::BUNDLE_ADJUSTMENT}) {
    vpRobotSelfCalibration::Options o;
    o.method = method;
    o.num_calibration_poses = 10;
    o.trust_robot = true; // exact joints (PAPER does not read it): the partial views are the subject
    const vpRobotSelfCalibration::Result r = vpRobotSelfCalibration::run(sim.getNominalChain(), ds, o);
    ASSERT_EQ(r.status, vpRobotSelfCalibration::OK) << vpRobotSelfCalibration::methodName(method) << ": " << r.message;
    ASSERT_TRUE(r.verified);
    EXPECT_LT(r.after.yardstick_error, r.before.yardstick_error) << vpRobotSelfCalibration::methodName(method);
  }
}

TEST(Simulator, ObservationsAreTheTrueProjectionPlusNoiseOfTheRequestedSd)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 5);
  const std::vector<vpColVector> q = sim.generateConfigurations(6);
  const vpCameraParameters cam = sim.getCamera();
  double ss = 0, sum = 0;
  unsigned int n = 0;
  for (unsigned int k = 0; k < q.size(); ++k) {
    const auto exact = sim.observe(q[k], k, 0.0);
    const auto noisy = sim.observe(q[k], k);
    ASSERT_EQ(exact.size(), noisy.size());
    const vpHomogeneousMatrix cMf = sim.getTrueChain().get_fMc(q[k]).inverse();
    for (size_t i = 0; i < exact.size(); ++i) {
      // Independent projection with ViSP.
      const vpColVector &X = sim.getScenePoints()[exact[i].id];
      vpPoint P(X[0], X[1], X[2]);
      P.track(cMf);
      double u, v;
      vpMeterPixelConversion::convertPoint(cam, P.get_x(), P.get_y(), u, v);
      EXPECT_NEAR(exact[i].ip.get_u(), u, 1e-9);
      EXPECT_NEAR(exact[i].ip.get_v(), v, 1e-9);
      for (double d : {noisy[i].ip.get_u() - u, noisy[i].ip.get_v() - v}) {
        ss += d * d;
        sum += d;
        ++n;
      }
    }
  }
  // n = 6 * 82 * 2 = 984 draws: the sd estimate is within 7% (about 3 sigma), the mean within 0.03 px.
  EXPECT_NEAR(std::sqrt(ss / n), 0.2, 0.2 * 0.07);
  EXPECT_NEAR(sum / n, 0.0, 0.03);
}

TEST(Simulator, YardstickEndsAreSceneIdsAtTheKnownDistance)
{
  const vpSelfCalibSimulator sim = makeSim("puma560", 2);
  const vpSelfCalibDataset::Yardstick y = sim.getYardstick();
  ASSERT_TRUE(y.isSet());
  const vpColVector d = sim.getScenePoints()[y.id_a] - sim.getScenePoints()[y.id_b];
  EXPECT_NEAR(d.frobeniusNorm(), 0.1, 1e-12);
}

TEST(Simulator, ZeroErrorsGiveTheNominalRobot)
{
  vpSelfCalibSimulator::Options o;
  o.joint_translation_sd = o.joint_rotation_sd = o.base_translation_sd = o.base_rotation_sd = 0;
  o.hand_eye_translation_sd = o.hand_eye_rotation_sd = 0;
  const vpSelfCalibSimulator sim(vpKinematicChain::preset("viper850"), o);
  EXPECT_EQ(sim.getTrueChain().getParameters().frobeniusNorm(), 0.0);
}

TEST(Simulator, UnreachableSceneIsAClearError)
{
  vpSelfCalibSimulator::Options o;
  o.distance_min = 3.0;
  o.distance_max = 3.5;
  o.max_attempts = 5;
  const vpSelfCalibSimulator sim(vpKinematicChain::preset("viper850"), o);
  try {
    sim.generateConfigurations(3);
    FAIL();
  } catch (const vpSelfCalibException &e) {
    EXPECT_NE(e.getStringMessage().find("no configuration found"), std::string::npos);
  }
}

// The Viper850 through ViSP's simulator, as acquisition code sees it: moves are instant and exact,
// ViSP's own forward kinematics agree with the nominal chain, and the dataset acquired through
// vpRobot equals the one made directly.
TEST(Simulator, AcquisitionThroughTheViSPViper850Simulator)
{
  vpSelfCalibSimulatorViper850 robot;
  const vpKinematicChain nominal = robot.getNominalChain();
  for (unsigned int i = 0; i < 6; ++i)
    EXPECT_EQ(nominal.getJointMax()[i], robot.getJointMax()[i]);
  vpSelfCalibSimulator::Options o;
  o.seed = 4;
  const vpSelfCalibSimulator sim(nominal, o);
  const std::vector<vpColVector> q = sim.generateConfigurations(8);
  const vpSelfCalibDataset direct = sim.makeDataset(q);
  const vpSelfCalibDataset acquired = sim.acquire(robot, q);
  ASSERT_EQ(acquired.views.size(), q.size());
  for (size_t k = 0; k < q.size(); ++k) {
    for (unsigned int i = 0; i < 6; ++i)
      EXPECT_EQ(acquired.views[k].q[i], q[k][i]);
    expectSameObservations(acquired.views[k].points, direct.views[k].points);
    vpHomogeneousMatrix fMc;
    robot.get_fMc(acquired.views[k].q, fMc);
    const vpHomogeneousMatrix diff = fMc.inverse() * nominal.get_fMc(q[k]);
    EXPECT_LT(diff.getTranslationVector().frobeniusNorm(), 1e-12);
    EXPECT_LT(diff.getThetaUVector().getTheta(), 1e-12);
  }
  EXPECT_THROW(robot.setPosition(vpRobot::ARTICULAR_FRAME, vpColVector(6, 10.0)), vpSelfCalibException);
  EXPECT_THROW(robot.setPosition(vpRobot::CAMERA_FRAME, q[0]), vpSelfCalibException);
}
