/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpSelfCalibNoiseModel.h
  \brief The noise of a calibration's data: the image noise and how residuals are weighed, tested and
  rejected, and the robot's error (controller poses, joint readings, the kinematic model's residual).
*/
#ifndef VP_SELFCALIB_NOISE_MODEL_H
#define VP_SELFCALIB_NOISE_MODEL_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <string>
#include <vector>

/*!
  \class vpSelfCalibNoiseModel
  \ingroup group_selfcalib_core
  \brief The noise of a calibration's data, held once and passed to every estimator that weighs,
  tests or rejects a residual.

  Real data bring two noises, not one:
  - the image noise: pixel_sd (px, per image coordinate) weighs every reprojection residual; the
    robust loss (loss, loss_scale in units of pixel_sd) and the outlier rule (outlier_threshold in
    noise sds) follow it;
  - the robot's error, in the form the data give it:
    - controller poses fMe (hand-eye): pose_sd_translation (m) and pose_sd_rotation (rad), the error
      of each recorded flange pose, corrected in the end-effector frame;
    - joint readings (full kinematics): joint_sd (rad; one value for every joint, or one per joint),
      the error of the encoder readings;
    - the kinematic model's own residual (full kinematics): model_sd_translation (m) and
      model_sd_rotation (rad), what no parameter of the error model explains (link deflection, gear
      eccentricity), a correction of each camera pose in its own frame.
    Zero (empty for joint_sd) means exact: no correction is estimated.

  Two things are said of the image noise and of the controller poses' error, each by its own field:
  - what a run does with the level (measure_pixel_sd, measure_pose_sd): true asks the run to
    measure it from the residuals (a robust spread for the image noise, variance components for the
    poses' error) and to run again at the measured level, the value given being the start; false
    uses it as given. Copies made by withPixelNoise() and withPoseError() keep it.
  - where the level held comes from (pixel_sd_origin, pose_sd_origin): STATED, given by the caller
    or the dataset (or the start of a measurement not made); MEASURED, the residuals of a run gave
    it (the measured value, or the value used when the measurement agreed with it).
  In the options of a run the caller sets the first; the noise a run used (its result) says both.
  An estimator that measures the noise returns its measurement in a noise model of its own
  (unmeasured() filled with what was measured; a level left at 0 was not measured, and its loss and
  outlier fields carry no meaning), so the level used and the level measured are never confused.
*/
class VISP_SELFCALIB_EXPORT vpSelfCalibNoiseModel
{
public:
  //! The robust loss on whitened residuals.
  enum Loss { LOSS_NONE, LOSS_HUBER, LOSS_CAUCHY };
  //! "none", "huber" or "cauchy".
  static const char *lossName(Loss loss);
  //! "none", "huber" or "cauchy"; throws vpSelfCalibException otherwise.
  static Loss lossFromName(const std::string &name);

  //! Where a level held comes from (not what a run does with it: the measure_* fields).
  enum Origin {
    STATED,  //!< given by the caller or the dataset
    MEASURED //!< measured from the residuals of a run
  };
  //! "stated" or "measured".
  static const char *originName(Origin origin);

  double pixel_sd = 0.2;            //!< px, the image noise sd per image coordinate
  Origin pixel_sd_origin = STATED;  //!< where pixel_sd comes from
  //! A run measures the image noise from its residuals and runs again at it (pixel_sd the start).
  bool measure_pixel_sd = false;
  Loss loss = LOSS_CAUCHY;          //!< the robust loss of the robust stages
  double loss_scale = 3;            //!< in units of pixel_sd
  //! In noise sds (pixel_sd, or the residuals' robust sd when larger): an observation beyond it is
  //! rejected after the robust stage; 0 keeps every observation.
  double outlier_threshold = 5;

  double pose_sd_translation = 0;   //!< m, controller pose error (hand-eye); 0: exact poses
  double pose_sd_rotation = 0;      //!< rad, controller pose error (hand-eye); 0: exact poses
  Origin pose_sd_origin = STATED;   //!< where pose_sd_* come from
  //! A run (hand-eye) measures the controller poses' error and runs again at it (pose_sd_* the start).
  bool measure_pose_sd = false;
  //! rad, joint reading error (full kinematics), one value for every joint or one per joint; empty: exact.
  std::vector<double> joint_sd;
  Origin joint_sd_origin = STATED;  //!< where joint_sd comes from
  //! A run (full kinematics) measures the joint reading error and runs again at it (joint_sd the start).
  bool measure_joint_sd = false;
  double model_sd_translation = 0;  //!< m, the kinematic model's residual (full kinematics); 0: none
  double model_sd_rotation = 0;     //!< rad, the kinematic model's residual (full kinematics); 0: none
  Origin model_sd_origin = STATED;  //!< where model_sd_* come from
  //! A run (full kinematics) measures the model's residual and runs again at it (model_sd_* the start).
  bool measure_model_sd = false;

  //! A model for measurements not made yet: every level 0, origin MEASURED, nothing to measure
  //! (check() refuses it).
  static vpSelfCalibNoiseModel unmeasured();

  //! px, the robust loss's scale: loss_scale * pixel_sd.
  double lossScalePixels() const { return loss_scale * pixel_sd; }
  //! True when the controller poses carry an error (both parts positive).
  bool hasPoseError() const { return pose_sd_translation > 0 && pose_sd_rotation > 0; }
  //! True when the kinematic model's residual is modelled (both parts positive).
  bool hasModelError() const { return model_sd_translation > 0 && model_sd_rotation > 0; }
  //! True when any robot error is modelled (controller poses, joint readings or the model's residual).
  bool hasRobotError() const { return hasPoseError() || hasModelError() || !joint_sd.empty(); }

  //! This model with the image noise `sd`, its origin `origin` (measure_pixel_sd kept).
  vpSelfCalibNoiseModel withPixelNoise(double sd, Origin origin) const;
  //! This model with the controller pose error (t m, r rad), its origin `origin` (measure_pose_sd kept).
  vpSelfCalibNoiseModel withPoseError(double t, double r, Origin origin) const;
  //! This model with the joint reading error `sd` (rad; empty: exact readings), its origin `origin`
  //! (measure_joint_sd kept).
  vpSelfCalibNoiseModel withJointError(const std::vector<double> &sd, Origin origin) const;
  //! This model with the kinematic model's residual (t m, r rad; both 0: none), its origin `origin`
  //! (measure_model_sd kept).
  vpSelfCalibNoiseModel withModelError(double t, double r, Origin origin) const;

  /*!
    Throws vpSelfCalibException on nonsense: pixel_sd or loss_scale not positive or not finite, a
    negative or non-finite outlier_threshold, an unknown loss or origin, a pose or model error with
    one part 0 and the other not (both positive or both 0), a negative or non-finite level, a
    joint_sd entry outside (0, 1) rad. Every part is checked, also by the estimators that use only
    the image part. `who` starts the message (the estimator that was given it).
  */
  void check(const std::string &who = "vpSelfCalibNoiseModel") const;
};

#endif
