/*
 * Tests of the noise model every estimator is given (core layer).
 */
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibNoiseModel.h>

TEST(NoiseModel, DefaultsAreAStatedImageNoiseAndAnExactRobot)
{
  const vpSelfCalibNoiseModel n;
  EXPECT_NO_THROW(n.check());
  EXPECT_EQ(n.pixel_sd, 0.2);
  EXPECT_EQ(n.pixel_sd_origin, vpSelfCalibNoiseModel::STATED);
  EXPECT_FALSE(n.measure_pixel_sd);
  EXPECT_FALSE(n.measure_pose_sd);
  EXPECT_EQ(n.loss, vpSelfCalibNoiseModel::LOSS_CAUCHY);
  EXPECT_DOUBLE_EQ(n.lossScalePixels(), 0.6);
  EXPECT_FALSE(n.hasRobotError());
  EXPECT_FALSE(n.hasPoseError());
  EXPECT_FALSE(n.hasModelError());
}

TEST(NoiseModel, LevelsChangeWithTheirOrigin)
{
  const vpSelfCalibNoiseModel n;
  const vpSelfCalibNoiseModel p = n.withPixelNoise(0.5, vpSelfCalibNoiseModel::MEASURED);
  EXPECT_EQ(p.pixel_sd, 0.5);
  EXPECT_EQ(p.pixel_sd_origin, vpSelfCalibNoiseModel::MEASURED);
  EXPECT_EQ(n.pixel_sd, 0.2); // a copy: the original stays
  const vpSelfCalibNoiseModel r = p.withPoseError(2e-3, 3e-3, vpSelfCalibNoiseModel::MEASURED);
  EXPECT_TRUE(r.hasPoseError());
  EXPECT_TRUE(r.hasRobotError());
  EXPECT_EQ(r.pose_sd_origin, vpSelfCalibNoiseModel::MEASURED);
  EXPECT_EQ(r.pixel_sd, 0.5);
  EXPECT_NO_THROW(r.check());
  const vpSelfCalibNoiseModel u = vpSelfCalibNoiseModel::unmeasured();
  EXPECT_EQ(u.pixel_sd, 0);
  EXPECT_EQ(u.pixel_sd_origin, vpSelfCalibNoiseModel::MEASURED);
  EXPECT_FALSE(u.measure_pixel_sd || u.measure_pose_sd); // a measurement asks for none
  EXPECT_THROW(u.check(), vpSelfCalibException);
  vpSelfCalibNoiseModel j;
  j.joint_sd = {1e-4};
  EXPECT_TRUE(j.hasRobotError());
  // The full mode's forms, each with its own origin.
  const vpSelfCalibNoiseModel f = n.withJointError({3e-4, 2e-4, 2e-4, 1e-4, 1e-4, 1e-4}, vpSelfCalibNoiseModel::MEASURED)
                                      .withModelError(2e-4, 3e-4, vpSelfCalibNoiseModel::MEASURED);
  EXPECT_EQ(f.joint_sd.size(), 6u);
  EXPECT_EQ(f.joint_sd_origin, vpSelfCalibNoiseModel::MEASURED);
  EXPECT_TRUE(f.hasModelError());
  EXPECT_EQ(f.model_sd_rotation, 3e-4);
  EXPECT_EQ(f.model_sd_origin, vpSelfCalibNoiseModel::MEASURED);
  EXPECT_EQ(f.pose_sd_origin, vpSelfCalibNoiseModel::STATED); // the others untouched
  EXPECT_NO_THROW(f.check());
  const vpSelfCalibNoiseModel exact = f.withJointError({}, vpSelfCalibNoiseModel::MEASURED)
                                          .withModelError(0, 0, vpSelfCalibNoiseModel::MEASURED);
  EXPECT_FALSE(exact.hasRobotError());
  EXPECT_EQ(u.joint_sd_origin, vpSelfCalibNoiseModel::MEASURED);
  EXPECT_EQ(u.model_sd_origin, vpSelfCalibNoiseModel::MEASURED);
}

// What a run does with a level and where the level comes from are two fields: a level to measure
// keeps its request through the copies that set a measured value, and a stated level never
// becomes a request.
TEST(NoiseModel, TheRequestToMeasureAndTheOriginAreSeparate)
{
  vpSelfCalibNoiseModel n;
  n.measure_pixel_sd = true;
  const vpSelfCalibNoiseModel m = n.withPixelNoise(0.4, vpSelfCalibNoiseModel::MEASURED);
  EXPECT_TRUE(m.measure_pixel_sd);
  EXPECT_EQ(m.pixel_sd_origin, vpSelfCalibNoiseModel::MEASURED);
  const vpSelfCalibNoiseModel s = vpSelfCalibNoiseModel().withPixelNoise(0.4, vpSelfCalibNoiseModel::MEASURED);
  EXPECT_FALSE(s.measure_pixel_sd); // a measured level given: used as it is
  vpSelfCalibNoiseModel p;
  p.measure_pose_sd = true;
  const vpSelfCalibNoiseModel q = p.withPoseError(1e-3, 1e-3, vpSelfCalibNoiseModel::STATED);
  EXPECT_TRUE(q.measure_pose_sd);
  EXPECT_EQ(q.pose_sd_origin, vpSelfCalibNoiseModel::STATED);
  EXPECT_FALSE(q.measure_pixel_sd);
}

TEST(NoiseModel, NonsenseIsRefusedWithTheCallersName)
{
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (double v : {0.0, -1.0, nan, inf}) {
    vpSelfCalibNoiseModel n;
    n.pixel_sd = v;
    EXPECT_THROW(n.check(), vpSelfCalibException) << v;
    n = vpSelfCalibNoiseModel();
    n.loss_scale = v;
    EXPECT_THROW(n.check(), vpSelfCalibException) << v;
  }
  vpSelfCalibNoiseModel n;
  n.outlier_threshold = 0; // keeps every observation
  EXPECT_NO_THROW(n.check());
  n.outlier_threshold = -1;
  EXPECT_THROW(n.check(), vpSelfCalibException);
  n = vpSelfCalibNoiseModel();
  n.pose_sd_translation = 1e-3; // one part of the pair
  EXPECT_THROW(n.check(), vpSelfCalibException);
  n.pose_sd_rotation = nan;
  EXPECT_THROW(n.check(), vpSelfCalibException);
  n = vpSelfCalibNoiseModel();
  n.model_sd_rotation = 1e-3;
  EXPECT_THROW(n.check(), vpSelfCalibException);
  n = vpSelfCalibNoiseModel();
  for (double v : {0.0, -1e-3, 1.0, nan}) {
    n.joint_sd = {1e-4, v};
    EXPECT_THROW(n.check(), vpSelfCalibException) << v;
  }
  n = vpSelfCalibNoiseModel();
  n.loss = static_cast<vpSelfCalibNoiseModel::Loss>(7);
  EXPECT_THROW(n.check(), vpSelfCalibException);
  n = vpSelfCalibNoiseModel();
  n.joint_sd_origin = static_cast<vpSelfCalibNoiseModel::Origin>(5);
  EXPECT_THROW(n.check(), vpSelfCalibException);
  n = vpSelfCalibNoiseModel();
  n.model_sd_origin = static_cast<vpSelfCalibNoiseModel::Origin>(5);
  EXPECT_THROW(n.check(), vpSelfCalibException);
  try {
    vpSelfCalibNoiseModel m;
    m.pixel_sd = -1;
    m.check("vpSomeEstimator");
    FAIL() << "no exception";
  } catch (const vpSelfCalibException &e) {
    EXPECT_NE(e.getStringMessage().find("vpSomeEstimator"), std::string::npos) << e.getStringMessage();
  }
}

TEST(NoiseModel, LossNamesRoundTrip)
{
  for (auto l : {vpSelfCalibNoiseModel::LOSS_NONE, vpSelfCalibNoiseModel::LOSS_HUBER, vpSelfCalibNoiseModel::LOSS_CAUCHY})
    EXPECT_EQ(vpSelfCalibNoiseModel::lossFromName(vpSelfCalibNoiseModel::lossName(l)), l);
  EXPECT_THROW(vpSelfCalibNoiseModel::lossFromName("l1"), vpSelfCalibException);
  EXPECT_STREQ(vpSelfCalibNoiseModel::originName(vpSelfCalibNoiseModel::MEASURED), "measured");
  EXPECT_STREQ(vpSelfCalibNoiseModel::originName(vpSelfCalibNoiseModel::STATED), "stated");
}
