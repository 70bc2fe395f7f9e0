/*
 * ViSP SelfCalib: the measure-and-run-again step of every method. A level of the noise model to be
 * measured (its measure_* field) is measured from the residuals of a run, and the run is made again
 * at the measured level when it differs from the one used (vpSelfCalibPipelines.h).
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

constexpr int kMaxRobotRounds = 5;     //!< runs again at the measured robot error, at most
/*!
  Relative change of every part below which a level has settled: 10 % for the controller poses'
  error; 25 % for the full mode's joint readings and model residual, which the images separate from
  each other only weakly (both move every camera): their variance components have few degrees of
  freedom (a relative sd of 1 / sqrt(2 x redundancy), 15 to 25 % on 15 views), converge slowly from
  round to round, and a tighter test runs the method again for changes below what it can measure.
*/
constexpr double kPoseSettled = 0.1;
constexpr double kFullModeSettled = 0.25;
/*!
  m and rad: a measured part below this is taken at this level, and when every part of a form of
  the robot's error is below it, that form is dropped (exact). It is a serial arm's repeatability
  (ISO 9283 figures: 0.02 to 0.1 mm; a joint reading 2e-5 rad off moves a camera 0.5 m out by
  10 um): no arm is known better, and a level this small moves no estimate. Without the floor,
  variance components on data without that error shrink the level by a factor each round and it
  never settles.
*/
constexpr double kRobotFloor = 2e-5;
/*!
  A form measured below this in every part is dropped (exact): twice the floor. Near the floor the
  measurement is mostly the image noise leaking into the corrections, and it jumps from round to
  round (below the floor in one part, above it in the other) instead of settling.
*/
constexpr double kRobotDrop = 2 * kRobotFloor;

/*!
  The forms of the robot's error, each one group of levels measured together and dropped together:
  the controller poses' (hand-eye: translation, rotation), the joint readings' (full kinematics: one
  factor on every joint's sd), the kinematic model's residual (full kinematics: translation,
  rotation).
*/
enum Form { POSE, JOINTS, MODEL, FORMS };
const char *const kFormName[FORMS] = {"the controller pose error", "the joint reading error", "the model residual"};

//! A form's levels (m, rad; JOINTS: the largest joint sd, rad, in both) and whether it is modelled.
struct Levels {
  double t = 0, r = 0;
  bool modelled() const { return t > 0 || r > 0; }
};
Levels levelsOf(const vpSelfCalibNoiseModel &n, Form f)
{
  if (f == POSE)
    return {n.pose_sd_translation, n.pose_sd_rotation};
  if (f == MODEL)
    return {n.model_sd_translation, n.model_sd_rotation};
  const double j = n.joint_sd.empty() ? 0 : *std::max_element(n.joint_sd.begin(), n.joint_sd.end());
  return {j, j};
}
//! The form is to be measured (the noise model's measure_* request) and is modelled.
bool measuredForm(const vpSelfCalibNoiseModel &n, Form f)
{
  const bool asked = f == POSE ? n.measure_pose_sd : (f == MODEL ? n.measure_model_sd : n.measure_joint_sd);
  return asked && levelsOf(n, f).modelled();
}
//! The form's level held is the one the residuals measure (they agreed with it).
void markMeasured(vpSelfCalibNoiseModel &n, Form f)
{
  (f == POSE ? n.pose_sd_origin : (f == MODEL ? n.model_sd_origin : n.joint_sd_origin)) = vpSelfCalibNoiseModel::MEASURED;
}
std::string text(const Levels &l, Form f)
{
  return f == JOINTS ? mm(l.t, 3) + " mrad" : mm(l.t) + " mm / " + mm(l.r) + " mrad";
}

//! The next level of a form from what the run measured: dropped (exact), kept (not measured) or the
//! measured one, each part at least the floor.
enum Step { NEXT, DROP, UNMEASURED };
Step nextLevel(const vpSelfCalibNoiseModel &used, const vpSelfCalibNoiseModel &measured, Form f,
               vpSelfCalibNoiseModel &next)
{
  const Levels u = levelsOf(used, f), m = levelsOf(measured, f);
  const bool at_floor = u.t <= kRobotDrop && u.r <= kRobotDrop;
  if (!m.modelled() && !at_floor)
    return UNMEASURED;
  // Below the drop level, or not measured near it (the prior, not the images, holds the corrections).
  const vpSelfCalibNoiseModel::Origin o = vpSelfCalibNoiseModel::MEASURED;
  if (m.t < kRobotDrop && m.r < kRobotDrop) {
    next = f == POSE ? next.withPoseError(0, 0, o) : (f == MODEL ? next.withModelError(0, 0, o) : next.withJointError({}, o));
    return DROP;
  }
  if (f == POSE)
    next = next.withPoseError(std::max(m.t, kRobotFloor), std::max(m.r, kRobotFloor), o);
  else if (f == MODEL)
    next = next.withModelError(std::max(m.t, kRobotFloor), std::max(m.r, kRobotFloor), o);
  else {
    std::vector<double> sd = measured.joint_sd;
    for (double &v : sd)
      v = std::max(v, kRobotFloor);
    next = next.withJointError(sd, o);
  }
  return NEXT;
}

bool settled(const Levels &from, const Levels &to, Form f)
{
  const double tol = f == POSE ? kPoseSettled : kFullModeSettled;
  return std::fabs(to.t / from.t - 1) <= tol && std::fabs(to.r / from.r - 1) <= tol;
}

/*
  The robot's error measured, every form to be measured (measure_pose_sd, measure_joint_sd, measure_model_sd): rounds at the measured levels
  until they settle; a form measured below the floor in every part is dropped (exact). A warning when
  a form does not settle, cannot be measured, or the run at the measured levels is not ok (the
  standing run is then the last ok one).
*/
void measureRobotError(State &st, const NoiseAttemptFunction &attempt, std::vector<vpSelfCalibDataCheck::Finding> &findings)
{
  for (int round = 0;; ++round) {
    vpSelfCalibNoiseModel next = st.used;
    bool changed = false, any = false;
    std::vector<Form> agreed;
    std::string unmeasured, change;
    for (int f = 0; f < FORMS; ++f) {
      const Form form = static_cast<Form>(f);
      if (!measuredForm(st.used, form))
        continue;
      any = true;
      const Step step = nextLevel(st.used, st.measured, form, next);
      if (step == UNMEASURED)
        unmeasured += (unmeasured.empty() ? "" : ", ") + std::string(kFormName[f]) + " (the stated " +
                      text(levelsOf(st.used, form), form) + " is used)";
      if (step == NEXT && settled(levelsOf(st.used, form), levelsOf(next, form), form))
        agreed.push_back(form);
      if (step == DROP || (step == NEXT && !settled(levelsOf(st.used, form), levelsOf(next, form), form))) {
        changed = true;
        change += (change.empty() ? "" : ", ") + std::string(kFormName[f]) + " " + text(levelsOf(st.measured, form), form) +
                  " where " + text(levelsOf(st.used, form), form) + " was used";
      }
    }
    if (!unmeasured.empty() && (!changed || round == kMaxRobotRounds))
      note(findings, "the robot's error could not be measured (the views do not separate its corrections from the "
                     "rest, or no covariance): " + unmeasured);
    if (!any || !changed) {
      for (Form form : agreed)
        markMeasured(st.used, form);
      return;
    }
    if (round == kMaxRobotRounds) {
      note(findings, "the robot's error did not settle in 5 rounds: the corrections measure " + change);
      return;
    }
    if (st.used.measure_pixel_sd &&
        measuredNoiseDiffers(next.pixel_sd, st.measured.pixel_sd))
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
    measureRobotError(st, attempt, findings);
  return st.used;
}
} // namespace vpSelfCalibPipeline
