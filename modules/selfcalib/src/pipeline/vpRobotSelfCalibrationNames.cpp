/*
 * ViSP SelfCalib: names of vpRobotSelfCalibration's focal-length modes, as the command lines and
 * files spell them.
 */
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

const char *vpRobotSelfCalibration::focalModeName(FocalMode m)
{
  switch (m) {
  case FOCAL_AUTO:
    return "auto";
  case FOCAL_PER_PAIR:
    return "per-pair";
  case FOCAL_SHARED:
    return "shared";
  case FOCAL_KNOWN:
    return "known";
  }
  return "unknown";
}

vpRobotSelfCalibration::FocalMode vpRobotSelfCalibration::focalModeFromName(const std::string &name)
{
  for (FocalMode m : {FOCAL_AUTO, FOCAL_PER_PAIR, FOCAL_SHARED, FOCAL_KNOWN})
    if (name == focalModeName(m))
      return m;
  throw vpSelfCalibException(vpSelfCalibException::badValue,
                             "focal mode '" + name + "': use auto, known, shared or per-pair");
}
