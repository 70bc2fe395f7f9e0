/*
 * ViSP SelfCalib: the levels of the robot's error a run measures, and the rules that take a
 * measurement to the next level (not installed). Shared by the kinematic bundle adjustment, which
 * measures the full kinematics' joint readings and model residual inside one adjustment, and the
 * pipeline's rounds, which measure the controller poses' error run by run.
 */
#ifndef VP_SELFCALIB_ROBOT_ERROR_LEVELS_H
#define VP_SELFCALIB_ROBOT_ERROR_LEVELS_H

#include <algorithm>
#include <cmath>
#include <vector>

#include <visp3/selfcalib/vpSelfCalibNoiseModel.h>

namespace vpSelfCalib
{
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
//! Relative change of every part below which the controller poses' error has settled.
constexpr double kPoseSettled = 0.1;
/*!
  The same for the full kinematics' joint readings and model residual, which the images separate
  from each other only weakly (both move every camera): their variance components have few degrees
  of freedom (a relative sd of 1 / sqrt(2 x redundancy), 15 to 25 % on 15 views), and a tighter test
  re-weighs for changes below what the data can measure.
*/
constexpr double kFullModeSettled = 0.25;

/*!
  The forms of the robot's error, each one group of levels measured together and dropped together:
  the controller poses' (hand-eye: translation, rotation), the joint readings' (full kinematics: one
  factor on every joint's sd), the kinematic model's residual (full kinematics: translation,
  rotation).
*/
enum RobotErrorForm { POSE_ERROR, JOINT_ERROR, MODEL_ERROR, ROBOT_ERROR_FORMS };

//! A form's levels (m, rad; JOINT_ERROR: the largest joint sd, rad, in both) and whether it is modelled.
struct RobotErrorLevels {
  double t = 0, r = 0;
  bool modelled() const { return t > 0 || r > 0; }
};

inline RobotErrorLevels levelsOf(const vpSelfCalibNoiseModel &n, RobotErrorForm f)
{
  if (f == POSE_ERROR)
    return {n.pose_sd_translation, n.pose_sd_rotation};
  if (f == MODEL_ERROR)
    return {n.model_sd_translation, n.model_sd_rotation};
  const double j = n.joint_sd.empty() ? 0 : *std::max_element(n.joint_sd.begin(), n.joint_sd.end());
  return {j, j};
}

//! The form is to be measured (the noise model's measure_* request) and is modelled.
inline bool measuredForm(const vpSelfCalibNoiseModel &n, RobotErrorForm f)
{
  const bool asked = f == POSE_ERROR ? n.measure_pose_sd : (f == MODEL_ERROR ? n.measure_model_sd : n.measure_joint_sd);
  return asked && levelsOf(n, f).modelled();
}

/*!
  rad, and m / rad: what a well-built arm's joint readings (encoders and gear play: 1e-4 to 1e-3 rad)
  and its model's residual after a kinematic calibration (a few 0.1 mm and mrad; 1 mm and 1 mrad,
  the hand-eye method's controller pose prior, which holds the kinematic errors too) stay within.
  The variance components measure whatever the corrections take. A model residual beyond its bound
  is a misfit the model cannot explain; a joint level beyond its bound is questioned, not condemned:
  a low-cost arm's backlash (0.1 to 0.2 deg, 2 to 3.5 mrad) is beyond it and is reading noise. The
  pipeline judges it by the corrections' structure (vpSelfCalibRobotErrorStructure.h: reading noise
  is independent per joint and per view, with mean 0; a parameter held at a wrong value puts an
  offset on a joint, a rendering or a loose camera a per-view 6-D displacement).
*/
constexpr double kJointErrorPlausible = 1e-3, kModelErrorPlausible = 1e-3;
/*!
  rad: joint readings off by more than this (0.57 deg) are no arm's, whatever their structure (a
  hobby servo's dead band is about this): a misfit, or joints paired with another view's images.
*/
constexpr double kJointErrorImpossible = 1e-2;

/*!
  The full kinematics' robot error is yet to be measured: a joint readings' or model residual's
  level asked to be measured and not measured yet (the prior's, a guess). A set of estimated
  parameters decided at it is decided again at the level the run measures (dropped: as a trusted
  run's), and the run made again on that set when it differs: at the prior's 3e-4 rad a simulated
  Viper850 with exact joints leaves j4.tx and j5.tx out, which its trusted run estimates; at no
  robot error a planar board's 8 views estimate eMc.tz and j3.tx, which the corrections at the
  prior's level leave undetermined.
*/
inline bool robotLevelGuessed(const vpSelfCalibNoiseModel &n)
{
  return (n.measure_joint_sd && !n.joint_sd.empty() && n.joint_sd_origin != vpSelfCalibNoiseModel::MEASURED) ||
         (n.measure_model_sd && n.hasModelError() && n.model_sd_origin != vpSelfCalibNoiseModel::MEASURED);
}

/*!
  n without its guessed levels (robotLevelGuessed()): those forms exact, their origin STATED and
  their measure_* request kept, the state of a robot error asked to be measured that could not be
  (the corrections at the prior's level leave the estimate undetermined), which the assessment says.
*/
inline vpSelfCalibNoiseModel withoutGuessedLevels(const vpSelfCalibNoiseModel &n)
{
  vpSelfCalibNoiseModel k = n;
  if (n.measure_joint_sd && !n.joint_sd.empty() && n.joint_sd_origin != vpSelfCalibNoiseModel::MEASURED)
    k = k.withJointError({}, vpSelfCalibNoiseModel::STATED);
  if (n.measure_model_sd && n.hasModelError() && n.model_sd_origin != vpSelfCalibNoiseModel::MEASURED)
    k = k.withModelError(0, 0, vpSelfCalibNoiseModel::STATED);
  return k;
}

/*!
  The joint readings' error asked to be measured that could not be (withoutGuessedLevels()): no
  other run leaves it asked, exact and STATED (dropped, it is MEASURED; the model residual, asked
  with the joints' by --joint-sd auto, is left unmodelled and STATED when the dataset states the
  joints' level alone).
*/
inline bool robotErrorNotMeasured(const vpSelfCalibNoiseModel &n)
{
  return n.measure_joint_sd && n.joint_sd.empty() && n.joint_sd_origin == vpSelfCalibNoiseModel::STATED;
}

//! The form's level held is the one the residuals measure (they agreed with it).
inline void markMeasured(vpSelfCalibNoiseModel &n, RobotErrorForm f)
{
  (f == POSE_ERROR ? n.pose_sd_origin : (f == MODEL_ERROR ? n.model_sd_origin : n.joint_sd_origin)) =
      vpSelfCalibNoiseModel::MEASURED;
}

//! What a measurement makes of a form: the next level, dropped (exact), or not measured (kept).
enum RobotErrorStep { NEXT_LEVEL, DROP_LEVEL, UNMEASURED_LEVEL };

/*!
  The next level of a form from what a run measured, into next: dropped (exact) when every part
  measures below kRobotDrop (or is not measured while the level used is already at the drop level:
  the prior, not the images, holds the corrections), kept when not measured, else the measured one,
  each part at least kRobotFloor. The origin of a changed level is MEASURED.
*/
inline RobotErrorStep nextLevel(const vpSelfCalibNoiseModel &used, const vpSelfCalibNoiseModel &measured,
                                RobotErrorForm f, vpSelfCalibNoiseModel &next)
{
  const RobotErrorLevels u = levelsOf(used, f), m = levelsOf(measured, f);
  const bool at_floor = u.t <= kRobotDrop && u.r <= kRobotDrop;
  if (!m.modelled() && !at_floor)
    return UNMEASURED_LEVEL;
  const vpSelfCalibNoiseModel::Origin o = vpSelfCalibNoiseModel::MEASURED;
  if (m.t < kRobotDrop && m.r < kRobotDrop) {
    next = f == POSE_ERROR    ? next.withPoseError(0, 0, o)
           : f == MODEL_ERROR ? next.withModelError(0, 0, o)
                              : next.withJointError({}, o);
    return DROP_LEVEL;
  }
  if (f == POSE_ERROR)
    next = next.withPoseError(std::max(m.t, kRobotFloor), std::max(m.r, kRobotFloor), o);
  else if (f == MODEL_ERROR)
    next = next.withModelError(std::max(m.t, kRobotFloor), std::max(m.r, kRobotFloor), o);
  else {
    std::vector<double> sd = measured.joint_sd;
    for (double &v : sd)
      v = std::max(v, kRobotFloor);
    next = next.withJointError(sd, o);
  }
  return NEXT_LEVEL;
}

//! Every part of the form moved by at most its settle tolerance (kPoseSettled, kFullModeSettled).
inline bool settled(const RobotErrorLevels &from, const RobotErrorLevels &to, RobotErrorForm f)
{
  const double tol = f == POSE_ERROR ? kPoseSettled : kFullModeSettled;
  return std::fabs(to.t / from.t - 1) <= tol && std::fabs(to.r / from.r - 1) <= tol;
}
} // namespace vpSelfCalib

#endif
