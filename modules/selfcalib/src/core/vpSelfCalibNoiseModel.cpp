/*
 * ViSP SelfCalib: vpSelfCalibNoiseModel, the noise of a calibration's data.
 */
#include <visp3/selfcalib/vpSelfCalibNoiseModel.h>

#include <visp3/selfcalib/vpSelfCalibException.h>

#include <cmath>

const char *vpSelfCalibNoiseModel::lossName(Loss loss)
{
  switch (loss) {
  case LOSS_NONE:
    return "none";
  case LOSS_HUBER:
    return "huber";
  case LOSS_CAUCHY:
    return "cauchy";
  }
  return "unknown";
}

vpSelfCalibNoiseModel::Loss vpSelfCalibNoiseModel::lossFromName(const std::string &name)
{
  for (Loss l : {LOSS_NONE, LOSS_HUBER, LOSS_CAUCHY})
    if (name == lossName(l))
      return l;
  throw vpSelfCalibException(vpSelfCalibException::badValue, "robust loss '" + name + "': use none, huber or cauchy");
}

const char *vpSelfCalibNoiseModel::originName(Origin origin) { return origin == MEASURED ? "measured" : "stated"; }

vpSelfCalibNoiseModel vpSelfCalibNoiseModel::unmeasured()
{
  vpSelfCalibNoiseModel n;
  n.pixel_sd = 0;
  n.pixel_sd_origin = n.pose_sd_origin = n.joint_sd_origin = n.model_sd_origin = MEASURED;
  return n;
}

namespace
{
using Noise = vpSelfCalibNoiseModel;

//! A copy of `n` holding the level `value` in `field`, and `origin` in `origin_field` (where it comes from).
template <typename T>
Noise withLevel(Noise n, T Noise::*field, const T &value, Noise::Origin Noise::*origin_field, Noise::Origin origin)
{
  n.*field = value;
  n.*origin_field = origin;
  return n;
}

// Both parts positive (the error modelled) or both 0 (exact), each finite.
bool pairValid(double t, double r)
{
  return t >= 0 && r >= 0 && std::isfinite(t) && std::isfinite(r) && ((t > 0) == (r > 0));
}
} // namespace

vpSelfCalibNoiseModel vpSelfCalibNoiseModel::withPixelNoise(double sd, Origin origin) const
{
  return withLevel(*this, &Noise::pixel_sd, sd, &Noise::pixel_sd_origin, origin);
}

vpSelfCalibNoiseModel vpSelfCalibNoiseModel::withPoseError(double t, double r, Origin origin) const
{
  Noise n = withLevel(*this, &Noise::pose_sd_translation, t, &Noise::pose_sd_origin, origin);
  n.pose_sd_rotation = r;
  return n;
}

vpSelfCalibNoiseModel vpSelfCalibNoiseModel::withJointError(const std::vector<double> &sd, Origin origin) const
{
  return withLevel(*this, &Noise::joint_sd, sd, &Noise::joint_sd_origin, origin);
}

vpSelfCalibNoiseModel vpSelfCalibNoiseModel::withModelError(double t, double r, Origin origin) const
{
  Noise n = withLevel(*this, &Noise::model_sd_translation, t, &Noise::model_sd_origin, origin);
  n.model_sd_rotation = r;
  return n;
}

void vpSelfCalibNoiseModel::check(const std::string &who) const
{
  if (!(pixel_sd > 0) || !std::isfinite(pixel_sd) || !(loss_scale > 0) || !std::isfinite(loss_scale) ||
      !(outlier_threshold >= 0) || !std::isfinite(outlier_threshold))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               who + ": the noise model's pixel_sd and loss_scale must be positive and finite, "
                                     "outlier_threshold non-negative and finite");
  if (loss != LOSS_NONE && loss != LOSS_HUBER && loss != LOSS_CAUCHY)
    throw vpSelfCalibException(vpSelfCalibException::badValue, who + ": the noise model's loss is unknown");
  for (Origin o : {pixel_sd_origin, pose_sd_origin, joint_sd_origin, model_sd_origin})
    if (o != STATED && o != MEASURED)
      throw vpSelfCalibException(vpSelfCalibException::badValue, who + ": the noise model's origin is unknown");
  if (!pairValid(pose_sd_translation, pose_sd_rotation))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               who + ": pose_sd_translation and pose_sd_rotation must be both positive (robot pose "
                                     "error modelled) or both 0 (exact poses)");
  if (!pairValid(model_sd_translation, model_sd_rotation))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               who + ": model_sd_translation and model_sd_rotation must be both positive (the "
                                     "kinematic model's residual modelled) or both 0 (none)");
  for (double sd : joint_sd)
    if (!(sd > 0) || !(sd < 1))
      throw vpSelfCalibException(vpSelfCalibException::badValue, who + ": joint_sd values must be in (0, 1) rad");
}
