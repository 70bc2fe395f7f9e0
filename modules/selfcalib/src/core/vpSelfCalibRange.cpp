/*
 * ViSP SelfCalib: plausibility ranges of cameras and robot models.
 */
#include "vpSelfCalibRange.h"

#include <cmath>
#include <sstream>

#include <visp3/selfcalib/vpSelfCalibException.h>

namespace vpSelfCalib
{
namespace
{
[[noreturn]] void fail(const std::string &where, const std::string &name, double value, const std::string &expected)
{
  std::ostringstream os;
  os.precision(17);
  os << where << ": " << name << " is " << value << "; expected " << expected;
  throw vpSelfCalibException(vpSelfCalibException::badValue, os.str());
}
std::string bound(double b, const char *unit)
{
  std::ostringstream os;
  os << b << " " << unit;
  return os.str();
}
} // namespace

void checkIntrinsics(double px, double py, double u0, double v0, const std::string &where)
{
  const std::string range = "a finite value in (0, " + bound(kMaxPixels, "px]");
  if (!(std::isfinite(px) && px > 0 && px <= kMaxPixels))
    fail(where, "the focal length px", px, range);
  if (!(std::isfinite(py) && py > 0 && py <= kMaxPixels))
    fail(where, "the focal length py", py, range);
  const std::string pp = "a finite value of magnitude at most " + bound(kMaxPixels, "px");
  if (!(std::isfinite(u0) && std::fabs(u0) <= kMaxPixels))
    fail(where, "the principal point u0", u0, pp);
  if (!(std::isfinite(v0) && std::fabs(v0) <= kMaxPixels))
    fail(where, "the principal point v0", v0, pp);
}

void checkCamera(const vpCameraParameters &cam, const std::string &where)
{
  checkIntrinsics(cam.get_px(), cam.get_py(), cam.get_u0(), cam.get_v0(), where);
  if (cam.get_projModel() == vpCameraParameters::perspectiveProjWithDistortion) {
    const std::string k = "a finite value of magnitude at most 1e6";
    if (!(std::isfinite(cam.get_kud()) && std::fabs(cam.get_kud()) <= 1e6))
      fail(where, "the distortion kud", cam.get_kud(), k);
    if (!(std::isfinite(cam.get_kdu()) && std::fabs(cam.get_kdu()) <= 1e6))
      fail(where, "the distortion kdu", cam.get_kdu(), k);
  }
}

void checkLength(double value, const std::string &name, const std::string &where)
{
  if (!(std::isfinite(value) && std::fabs(value) <= kMaxLength))
    fail(where, name, value, "a finite length of magnitude at most " + bound(kMaxLength, "m"));
}

void checkAngle(double value, const std::string &name, const std::string &where)
{
  if (!(std::isfinite(value) && std::fabs(value) <= kMaxAngle))
    fail(where, name, value, "a finite angle of magnitude at most " + bound(kMaxAngle, "rad"));
}

void checkPose(const vpPoseVector &p, const std::string &name, const std::string &where)
{
  static const char *c[6] = {"tx", "ty", "tz", "tux", "tuy", "tuz"};
  for (unsigned int k = 0; k < 6; ++k) {
    if (k < 3)
      checkLength(p[k], name + " " + c[k], where);
    else
      checkAngle(p[k], name + " " + c[k], where);
  }
}
} // namespace vpSelfCalib
