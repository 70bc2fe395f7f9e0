/*
 * ViSP SelfCalib: the measure-and-run-again step of every method. A level of the noise model to be
 * measured (measure_pixel_sd, measure_pose_sd) is measured from the residuals of a run, and the run is made again at the
 * measured level when it differs from the one used (vpSelfCalibPipelines.h).
 */
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "vpSelfCalibPipelines.h"

namespace vpSelfCalibPipeline
{
namespace
{
std::string mm(double v)
{
  std::ostringstream m;
  m << std::fixed << std::setprecision(1) << 1e3 * v;
  return m.str();
}

void note(std::vector<vpSelfCalibDataCheck::Finding> &findings, const std::string &text)
{
  findings.push_back({vpSelfCalibDataCheck::WARNING, "robot-error-not-settled", text});
}

//! The run that stands: the noise it used, the one its residuals measure, and whether it is ok.
struct State {
  vpSelfCalibNoiseModel used, measured;
  bool ok;
};

constexpr int kMaxPoseRounds = 5;      //!< runs again at the measured robot pose error, at most
constexpr double kPoseSettled = 0.1;   //!< relative change of both parts below which the level has settled
/*!
  m and rad: a measured part below this is taken at this level, and when both are below it the
  poses are exact to what matters. It is a serial arm's repeatability (ISO 9283 figures: 0.02 to
  0.1 mm): no arm's poses are known better, and a level this small moves no estimate. Without the
  floor, variance components on poses without error shrink the level by a factor each round and it
  never settles.
*/
constexpr double kPoseFloor = 2e-5;

//! The run again with exact poses, the measured error being below the floor in both parts.
void settleExact(State &st, const NoiseAttemptFunction &attempt, std::vector<vpSelfCalibDataCheck::Finding> &findings)
{
  const vpSelfCalibNoiseModel next = st.used.withPoseError(0, 0, vpSelfCalibNoiseModel::MEASURED);
  const NoiseAttempt a = attempt(next, true);
  if (!a.ok) {
    note(findings, "the robot pose error measures below " + mm(kPoseFloor) + " mm / " + mm(kPoseFloor) +
                       " mrad, and the run with exact poses ended " + a.failure + ": the result is the one at " +
                       mm(st.used.pose_sd_translation) + " mm / " + mm(st.used.pose_sd_rotation) + " mrad");
    return;
  }
  st.used = next;
  st.measured = a.measured;
}

/*
  The controller poses' error measured: rounds at the measured level until it settles (or falls
  below the floor in both parts: exact poses); a warning when it does not, cannot be measured, or
  the run at the measured level is not ok (the standing run is then the last ok one).
*/
void measurePoseError(State &st, const NoiseAttemptFunction &attempt, std::vector<vpSelfCalibDataCheck::Finding> &findings)
{
  for (int round = 0;; ++round) {
    const double tm = st.measured.pose_sd_translation, rm = st.measured.pose_sd_rotation;
    const double t0 = st.used.pose_sd_translation, r0 = st.used.pose_sd_rotation;
    const bool at_floor = t0 <= kPoseFloor && r0 <= kPoseFloor;
    if (!(tm > 0 || rm > 0) && !at_floor) {
      note(findings, "the robot pose error could not be measured (the views do not separate the pose corrections from "
                     "the rest, or no covariance): the stated " + mm(t0) + " mm / " + mm(r0) + " mrad is used");
      return;
    }
    // Below the floor, or not measured at it (the prior, not the images, holds the corrections).
    if (tm < kPoseFloor && rm < kPoseFloor)
      return settleExact(st, attempt, findings);
    const double t = std::max(tm, kPoseFloor), r = std::max(rm, kPoseFloor);
    if (std::fabs(t / t0 - 1) <= kPoseSettled && std::fabs(r / r0 - 1) <= kPoseSettled) {
      st.used.pose_sd_origin = vpSelfCalibNoiseModel::MEASURED; // the measurement agrees with it
      return;
    }
    if (round == kMaxPoseRounds) {
      note(findings, "the robot pose error did not settle in 5 rounds: the corrections measure " + mm(tm) + " mm / " +
                         mm(rm) + " mrad where " + mm(t0) + " mm / " + mm(r0) + " mrad was used");
      return;
    }
    vpSelfCalibNoiseModel next = st.used.withPoseError(t, r, vpSelfCalibNoiseModel::MEASURED);
    if (st.used.measure_pixel_sd &&
        measuredNoiseDiffers(next.pixel_sd, st.measured.pixel_sd))
      next = next.withPixelNoise(st.measured.pixel_sd, vpSelfCalibNoiseModel::MEASURED);
    const NoiseAttempt a = attempt(next, true);
    if (!a.ok) {
      // Said, not hidden: the result stands at the level used, which the corrections contradict.
      note(findings, "the robot pose error the corrections measure (" + mm(tm) + " mm / " + mm(rm) +
                         " mrad) is not the one used (" + mm(t0) + " mm / " + mm(r0) +
                         " mrad), and the run at the measured level ended " + a.failure +
                         ": the result is the one at the level used; these views may not determine the pose "
                         "error (add views)");
      return;
    }
    st.used = next;
    st.measured = a.measured;
  }
}
} // namespace

vpSelfCalibNoiseModel measureNoise(const vpSelfCalibNoiseModel &start, const vpSelfCalibNoiseModel &measured,
                                   bool ok, bool usable, bool pose_rounds, const NoiseAttemptFunction &attempt,
                                   std::vector<vpSelfCalibDataCheck::Finding> &findings)
{
  State st{start, measured, ok};
  // The image noise measured: once more at the level the residuals give, when it differs.
  if (start.measure_pixel_sd && usable && !measuredNoiseDiffers(start.pixel_sd, measured.pixel_sd))
    st.used.pixel_sd_origin = vpSelfCalibNoiseModel::MEASURED; // the measurement agrees with it
  if (start.measure_pixel_sd && usable && measuredNoiseDiffers(start.pixel_sd, measured.pixel_sd)) {
    const vpSelfCalibNoiseModel next = start.withPixelNoise(measured.pixel_sd, vpSelfCalibNoiseModel::MEASURED);
    const NoiseAttempt a = attempt(next, false);
    if (a.ok) {
      st.used = next;
      st.measured = a.measured;
      st.ok = true;
    }
  }
  // The controller poses' error measured, from a run that stands.
  if (pose_rounds && st.ok && start.measure_pose_sd && start.hasPoseError())
    measurePoseError(st, attempt, findings);
  return st.used;
}
} // namespace vpSelfCalibPipeline
