/*
 * ViSP SelfCalib: plausibility ranges of cameras and robot models (not installed).
 *
 * One place for the bounds beyond which a number is a caller's mistake (and the solvers overflow:
 * a focal length of 1e200 px squared in a residual is inf, and Ceres aborts on a CHECK rather than
 * returning). The files' readers (io) and the library's entry points (a camera or a kinematic
 * chain built in code) apply the same bounds, and throw vpSelfCalibException naming the value.
 */
#ifndef VP_SELFCALIB_RANGE_H
#define VP_SELFCALIB_RANGE_H

#include <string>

#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpPoseVector.h>

namespace vpSelfCalib
{
constexpr double kMaxLength = 1e4; //!< m: links, offsets, translations (a DH fit can need 150 m)
constexpr double kMaxAngle = 1e3;  //!< rad: joint values, limits and angles of a model
constexpr double kMaxPixels = 1e6; //!< px: focal lengths, principal point, image coordinates
/*!
  px: the image noise below which a measurement is not believed: residuals that small say the data
  are exact to the level that matters, not that the observations are that accurate (a detector's
  systematic error, e.g. of rendered or printed corners, fits into the estimate and leaves no
  residual). No run is made again at a level measured below it, and no covariance is scaled down
  below it (a level stated below it stands).
*/
constexpr double kPixelSdFloor = 0.01;

/*!
  Intrinsics of a pinhole camera: px, py in (0, kMaxPixels], |u0|, |v0| <= kMaxPixels, all finite.
  Throws vpSelfCalibException (badValue) "<where>: <which value> ... expected ...".
*/
void checkIntrinsics(double px, double py, double u0, double v0, const std::string &where);
//! checkIntrinsics() on a ViSP camera, and its ViSP distortion coefficients finite, |k| <= 1e6.
void checkCamera(const vpCameraParameters &cam, const std::string &where);
//! A length (m): finite, |value| <= kMaxLength. name: what it is ("joint 2's a").
void checkLength(double value, const std::string &name, const std::string &where);
//! An angle (rad): finite, |value| <= kMaxAngle.
void checkAngle(double value, const std::string &name, const std::string &where);
//! A pose vector (tx ty tz tux tuy tuz): its translation by checkLength, its rotation by checkAngle.
void checkPose(const vpPoseVector &p, const std::string &name, const std::string &where);

/*!
  A kinematic chain (vpKinematicChain; a template so that the core layer does not depend on the
  kinematics layer): every joint's a, d (lengths), alpha, theta_offset and limits (angles), the
  base, flange and hand-eye poses, and every correction (tx ty tz: lengths, rx ry rz: angles).
*/
template <class Chain> void checkChain(const Chain &chain, const std::string &where)
{
  const auto &joints = chain.getJoints();
  for (size_t i = 0; i < joints.size(); ++i) {
    const std::string j = "joint " + std::to_string(i + 1) + "'s ";
    checkLength(joints[i].a, j + "a", where);
    checkLength(joints[i].d, j + "d", where);
    checkAngle(joints[i].alpha, j + "alpha", where);
    checkAngle(joints[i].theta_offset, j + "theta_offset", where);
    checkAngle(joints[i].min, j + "lower limit", where);
    checkAngle(joints[i].max, j + "upper limit", where);
  }
  checkPose(chain.get_fMb_pose(), "the base pose fMb", where);
  checkPose(chain.get_nMe_pose(), "the flange pose nMe", where);
  checkPose(chain.get_eMc_pose(), "the hand-eye pose eMc", where);
  const std::vector<std::string> names = chain.getParameterNames();
  const auto &p = chain.getParameters();
  for (unsigned int k = 0; k < p.size() && k < names.size(); ++k) {
    if (k % 6 < 3)
      checkLength(p[k], "the correction " + names[k], where);
    else
      checkAngle(p[k], "the correction " + names[k], where);
  }
}
} // namespace vpSelfCalib

#endif
