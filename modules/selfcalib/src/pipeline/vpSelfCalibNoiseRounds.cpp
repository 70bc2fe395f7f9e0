/*
 * ViSP SelfCalib: the measure-and-run-again step of every method. A level of the noise model to be
 * measured (its measure_* field) is measured from the residuals of a run, and the run is made again
 * at the measured level when it differs from the one used (vpSelfCalibPipelines.h).
 */
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "../core/vpSelfCalibRobotErrorLevels.h"
#include "vpSelfCalibPipelines.h"

namespace vpSelfCalibPipeline
{
namespace
{
std::string mm(double v, int digits = 1)
{
  std::ostringstream m;
  m << std::fixed << std::setprecision(digits) << 1e3 * v;
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

constexpr int kMaxRobotRounds = 5; //!< runs again at the measured robot error, at most

std::string text(const vpSelfCalib::RobotErrorLevels &l)
{
  return mm(l.t) + " mm / " + mm(l.r) + " mrad";
}

/*
  The controller poses' error measured (measure_pose_sd): rounds at the measured levels until they
  settle; measured below the drop level in every part, it is dropped (exact). A warning when it does
  not settle, cannot be measured, or the run at the measured levels is not ok (the standing run is
  then the last ok one). The full kinematics' joint readings and model residual are measured inside
  the bundle adjustment (vpKinematicBundleAdjustment::Result::noise), not here.
*/
void measurePoseError(State &st, const NoiseAttemptFunction &attempt, std::vector<vpSelfCalibDataCheck::Finding> &findings)
{
  using namespace vpSelfCalib;
  const RobotErrorForm form = POSE_ERROR;
  for (int round = 0; measuredForm(st.used, form); ++round) {
    vpSelfCalibNoiseModel next = st.used;
    const RobotErrorStep step = nextLevel(st.used, st.measured, form, next);
    const std::string used = text(levelsOf(st.used, form));
    if (step == UNMEASURED_LEVEL) {
      note(findings, "the robot's error could not be measured (the views do not separate its corrections from the "
                     "rest, or no covariance): the controller pose error (the stated " + used + " is used)");
      return;
    }
    if (step == NEXT_LEVEL && settled(levelsOf(st.used, form), levelsOf(next, form), form)) {
      markMeasured(st.used, form);
      return;
    }
    const std::string change = "the controller pose error " + text(levelsOf(st.measured, form)) + " where " + used + " was used";
    if (round == kMaxRobotRounds) {
      note(findings, "the robot's error did not settle in 5 rounds: the corrections measure " + change);
      return;
    }
    if (st.used.measure_pixel_sd && measuredNoiseDiffers(next.pixel_sd, st.measured.pixel_sd))
      next = next.withPixelNoise(st.measured.pixel_sd, vpSelfCalibNoiseModel::MEASURED);
    const NoiseAttempt a = attempt(next, true);
    if (!a.ok) {
      // Said, not hidden: the result stands at the level used, which the corrections contradict.
      note(findings, "the robot's error the corrections measure is not the one used (" + change +
                         "), and the run at the measured level ended " + a.failure +
                         ": the result is the one at the level used; these views may not determine the robot's "
                         "error (add views)");
      return;
    }
    st.used = next;
    st.measured = a.measured;
    if (step == DROP_LEVEL)
      return;
  }
}
} // namespace

vpSelfCalibNoiseModel measureNoise(const vpSelfCalibNoiseModel &start, const vpSelfCalibNoiseModel &measured,
                                   bool ok, bool usable, bool robot_rounds, const NoiseAttemptFunction &attempt,
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
  // The robot's error measured, from a run that stands.
  if (robot_rounds && st.ok)
    measurePoseError(st, attempt, findings);
  return st.used;
}
} // namespace vpSelfCalibPipeline
