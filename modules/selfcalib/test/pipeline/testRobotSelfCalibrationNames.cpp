/*
 * Tests of vpRobotSelfCalibration's names (methods, focal modes), as command lines spell them.
 */
#include <gtest/gtest.h>

#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

TEST(RobotSelfCalibrationNames, FocalModesRoundTrip)
{
  for (vpRobotSelfCalibration::FocalMode m :
       {vpRobotSelfCalibration::FOCAL_AUTO, vpRobotSelfCalibration::FOCAL_PER_PAIR,
        vpRobotSelfCalibration::FOCAL_SHARED, vpRobotSelfCalibration::FOCAL_KNOWN})
    EXPECT_EQ(vpRobotSelfCalibration::focalModeFromName(vpRobotSelfCalibration::focalModeName(m)), m);
  EXPECT_STREQ(vpRobotSelfCalibration::focalModeName(vpRobotSelfCalibration::FOCAL_PER_PAIR), "per-pair");
  EXPECT_THROW(vpRobotSelfCalibration::focalModeFromName("zoom"), vpSelfCalibException);
  EXPECT_THROW(vpRobotSelfCalibration::focalModeFromName("Known"), vpSelfCalibException);
}

TEST(RobotSelfCalibrationNames, MethodsRoundTrip)
{
  for (vpRobotSelfCalibration::Method m :
       {vpRobotSelfCalibration::BUNDLE_ADJUSTMENT, vpRobotSelfCalibration::PAPER, vpRobotSelfCalibration::HAND_EYE})
    EXPECT_EQ(vpRobotSelfCalibration::methodFromName(vpRobotSelfCalibration::methodName(m)), m);
  EXPECT_THROW(vpRobotSelfCalibration::methodFromName("magic"), vpSelfCalibException);
}
