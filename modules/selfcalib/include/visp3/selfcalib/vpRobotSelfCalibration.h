/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpRobotSelfCalibration.h
  \brief Self-calibration of a camera-equipped arm from a dataset, by one of three methods run on the
  same data (one pipeline each behind run()).
*/
#ifndef VP_ROBOT_SELF_CALIBRATION_H
#define VP_ROBOT_SELF_CALIBRATION_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <functional>
#include <map>
#include <string>
#include <vector>

#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpPoseVector.h>
#include <visp3/selfcalib/vpCalibrationVerifier.h>
#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpKinematicBundleAdjustment.h>
#include <visp3/selfcalib/vpKinematicIdentification.h>
#include <visp3/selfcalib/vpMultiViewReconstruction.h>
#include <visp3/selfcalib/vpPoseScale.h>
#include <visp3/selfcalib/vpSelfCalibDataCheck.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>
#include <visp3/selfcalib/vpTwoViewEstimator.h>

/*!
  \class vpRobotSelfCalibration
  \ingroup group_selfcalib_pipeline
  \brief Self-calibration of a camera-equipped arm from a dataset, by one of three methods run on the
  same data (one pipeline each behind run()).

  <b>BUNDLE_ADJUSTMENT (the default, beyond the paper).</b>
  1. vpMultiViewReconstruction of the calibration views: scale-consistent poses c_kMc_0 and points
     with one focal length (known, or self-calibrated for FOCAL_SHARED and FOCAL_PER_PAIR alike),
     robust loss; metric through the yardstick when its ends are seen, otherwise scaled so that the
     reference pair's baseline is the nominal model's;
  2. vpKinematicIdentification from these poses (a start close to the solution);
  3. vpKinematicBundleAdjustment from there: corrections, f_x (unless known; more intrinsics through
     Options::bundle.intrinsics) and points on every observation, scale from the yardstick, or the
     nominal scale without one (said in the result); covariance;
  4. verification on the remaining views, as below.

  <b>HAND_EYE (target-less hand-eye calibration).</b> The robot's kinematics are trusted: views
  give the controller pose fMe (or joints, through the model). The multi-view reconstruction as
  above; a first eMc from its metric poses by OpenCV's calibrateHandEye (Tsai), or the model's eMc
  when the reconstruction has no metric scale; then vpKinematicBundleAdjustment in hand-eye-only
  mode (eMc, f_x unless known, points; scale from the metric end-effector motion).

  <b>PAPER: the paper's procedure</b> (Section 4.1, steps 2 to 5):

  2. pose measurements: the refined nonlinear factor method on the image pairs (pose 1, pose i) of
     the calibration views, i = 2..N (vpTwoViewEstimator), with the focal length per pair (the
     paper), shared by all pairs (by default from every view jointly, then known to the pairs:
     Options::paper_focal_all_views), or known;
  3. scale: eq. 21 ratios from the nominal model times one global scale (vpPoseScale);
  4. the global scale from the yardstick seen in the pairs (least squares). The paper identifies with
     scale 1 and fixes the scale afterwards; the two orders give the same model because the scale
     multiplies every measured translation, so here the scale is applied first and identification
     runs once on metric measurements;
  3'. identification of the kinematic parameters from the nominal model (vpKinematicIdentification);
  5. verification on the remaining views: the paper's 3-D error of the yardstick before (nominal)
     and after calibration (vpCalibrationVerifier).

  Views are used in dataset order: the first num_calibration_poses for calibration, the rest for
  verification.

  <b>Options of the steps.</b> Each setting has one source: Options::noise is THE noise of the data
  (image noise, robust loss, outlier rule, robot error; vpSelfCalibNoiseModel), passed as it is to
  every step that weighs a residual (noiseModel() gives the one a run starts from); the dataset's
  camera gives the camera (the known focal length, or the first guess of a self-calibrated one),
  focal_mode and method give the flags that follow from them; the nested structs (twoview,
  multiview, bundle, data_check) carry the caller's other settings of each step: they are the
  steps' Settings types, without the camera, the focal mode or the mode the run gives them. The
  options each step runs with are built from these by twoViewOptions(), multiViewOptions(),
  bundleOptions() and dataCheckOptions(), public so that a caller can see exactly what will run;
  run() uses them and never changes the caller's Options. A builder's output put back into
  Options keeps its settings (the assignment takes the Settings part).
*/
class VISP_SELFCALIB_EXPORT vpRobotSelfCalibration
{
public:
  enum FocalMode {
    FOCAL_AUTO,     //!< KNOWN when the dataset says the focal length is known, else SHARED
    FOCAL_PER_PAIR, //!< the paper: f self-calibrated with each pair, the median of the pairs kept
    FOCAL_SHARED,   //!< one f estimated jointly over all pairs
    FOCAL_KNOWN     //!< the dataset's px
  };

  enum Method {
    BUNDLE_ADJUSTMENT, //!< multi-view reconstruction + kinematic bundle adjustment (default)
    PAPER,             //!< the paper's two-view measurements, eq. 21 scale, pose-based identification
    HAND_EYE           //!< kinematics trusted: eMc, intrinsics and points from views with fMe (or joints)
  };
  static const char *methodName(Method m);
  //! "bundle", "paper" or "hand-eye"; throws vpSelfCalibException otherwise.
  static Method methodFromName(const std::string &name);
  //! "auto", "per-pair", "shared" or "known".
  static const char *focalModeName(FocalMode m);
  //! "auto", "per-pair", "shared" or "known"; throws vpSelfCalibException otherwise.
  static FocalMode focalModeFromName(const std::string &name);

  //! Settings of vpRobotSelfCalibration (the defaults are the member initialisers).
  struct Options {
    Method method = BUNDLE_ADJUSTMENT;
    unsigned int num_calibration_poses = 15; //!< the paper's 15 of 25
    FocalMode focal_mode = FOCAL_AUTO;
    //! The two-view step of every method (PAPER's pairs, the multi-view step's pairs); the camera
    //! and the focal mode are the dataset's and focal_mode above (twoViewOptions()).
    vpTwoViewEstimator::Settings twoview;
    //! PAPER: the expected error of a two-view pose measurement (rad), rotation and translation
    //! direction: the weights of its pose-based identification (not the robot's error, which is in noise).
    double twoview_rotation_sd = 5e-3;
    double twoview_direction_sd = 5e-3;
    vpKinematicIdentification::Options identification;
    //! BUNDLE_ADJUSTMENT, HAND_EYE, and PAPER's shared focal length (paper_focal_all_views); its
    //! two-view options are twoview above with the camera, its focal mode focal_mode's (multiViewOptions()).
    vpMultiViewReconstruction::Settings multiview;
    /*!
      PAPER with FOCAL_SHARED (beyond the paper): true (default) takes the focal length from every
      calibration view jointly (vpMultiViewReconstruction's bundle adjustment, its points shared by
      all views, started from the pairs' shared estimate) and measures the pairs again with it known;
      false keeps vpTwoViewEstimator::estimateShared's (one f over the pairs (1, i), each pair with
      its own points): points shared by every view fix the focal length, and the yardstick scale
      with it, better than the pairs' (bench-paper measures both: doc/benchmarks.md). When the
      reconstruction fails, the pairs' estimate is kept (Result::multiview says why).
    */
    bool paper_focal_all_views = true;
    //! BUNDLE_ADJUSTMENT, HAND_EYE (`fixed` also counts in the identifiability finding of every method).
    //! The mode is the method's; whether the focal length is estimated is focal_mode's, and the FX
    //! flag of intrinsics is not read (the other flags are); see bundleOptions().
    vpKinematicBundleAdjustment::Settings bundle;
    /*!
      THE noise of the data, passed to every step (residual weights, robust loss, outlier tests, the
      data check's homography threshold, the robot's error in the bundle adjustment). Its robot
      part as the method uses it: HAND_EYE the controller poses' error (pose_sd_*), BUNDLE_ADJUSTMENT
      the joint readings' (joint_sd) and the kinematic model's residual (model_sd_*); a part the
      method does not use is a caller mistake. A robot error left at 0 is taken from the dataset's
      robot_error when it states one (noiseModel()).

      A level whose origin is MEASURED is measured, not assumed, starting from the value given:
      - pixel_sd (calibrate's default, --pixel-sd auto). BUNDLE_ADJUSTMENT and HAND_EYE: after the
        method's run, when the noise level its residuals measure (robust) differs from pixel_sd by
        more than 25 % and is at least 0.01 px (below, the data are exact to the level that
        matters), the method runs again with that value: outlier thresholds, robust loss and weights
        follow the real noise. PAPER: only its focal length from every view (f shared,
        paper_focal_all_views) has pixel residuals; that reconstruction runs again at the measured
        level, the rest of the method has none. In every mode the covariance (PAPER: f's sd) is
        scaled by sigma0 when sigma0 is outside its 99.9 % chi-square interval, with a
        "noise-mismatch" finding naming both values.
      - the robot's error: pose_sd_* (HAND_EYE, calibrate --pose-sd auto), joint_sd and
        model_sd_* (BUNDLE_ADJUSTMENT, calibrate's default without --joint-sd / --pose-sd), each
        with its own origin field. After the run, when the error its corrections measure
        (variance component estimation; the joints with one factor on every joint's sd) differs
        from the one used by more than 10 % in a part (25 % for the joint readings and the model
        residual, which the images separate only weakly), the method runs again with the measured
        values (and the measured image noise when pixel_sd is measured too), up to 5 times; a form
        measured below 4e-5 m and rad (twice a serial arm's repeatability) in every part is dropped
        (exact). A run that is not ok ends the rounds and the last ok one stands, with the warning
        "robot-error-not-settled" (also when the level does not settle in 5 rounds or cannot be
        measured). The start: the stated level, else the dataset's robot_error, else (trust_robot
        false, the default) the prior robotErrorPrior() measured from there. PAPER: no effect.
      Result::noise says which levels were used.
    */
    vpSelfCalibNoiseModel noise;
    /*!
      HAND_EYE and BUNDLE_ADJUSTMENT: whether the robot is exact when neither noise nor the dataset
      states its error (HAND_EYE: the controller poses; BUNDLE_ADJUSTMENT: the joint readings and
      the kinematic model's residual). false (default): every real arm is off by a fraction of a
      millimetre to millimetres, so the error is modelled from robotErrorPrior() and measured
      (variance components, then the method runs again at the measured level; data without that
      error measure it near 0 and end as if exact). true: the robot is trusted, no error modelled
      (calibrate --pose-sd 0 or --joint-sd 0). A stated error (noise or the dataset's robot_error)
      is used whatever this says. PAPER: not read.
    */
    bool trust_robot = false;
    //! The checks run before calibrating (its noise: the noise above).
    vpSelfCalibDataCheck::Options data_check;
    /*!
      A start taken from an earlier run on the same views or a superset of them (the folds of
      vpSelfCalibCrossValidation start from the run on every view). HAND_EYE with the camera on the
      effector, when `set`: the method's start steps (the points triangulated from the controller
      poses, the multi-view reconstruction and the closed form, the focal length where the
      predicted rays meet best) are not run; one hand-eye bundle adjustment starts from `model`'s
      eMc, the scene `points` (frame f, by id; ids the views do not observe are ignored) and the
      focal length `fx` (px). The noise rounds, checks and assessment run as without it. Other
      methods and set-ups: not read.
    */
    struct Start {
      bool set = false;
      vpKinematicChain model;
      std::map<int, vpColVector> points;
      double fx = 0;
    };
    Start start;
    /*!
      The target's layout as its description gives it (a board's spec: id -> point in the target's
      frame, m), used only for the start of eMc and of a self-calibrated focal length (each view's
      target pose by PnP, then the hand-eye closed form), where the camera's motions between views
      of a plane are ambiguous. The bundle adjustment does not take it as known (that is
      bundle.known_points, which the start uses first when given): a description only roughly
      right (a board printed at another scale, not quite flat) still gives a start, and the data
      decide the rest. Empty: the start measures the camera's motions.
    */
    std::map<int, vpColVector> target_layout;
    //! After a run: a warning when more than this fraction of the calibration observations was not
    //! used (rejected as wrong matches, or on points the reconstruction could not place).
    double outlier_warning = 0.25;
    //! Acceptance (BUNDLE_ADJUSTMENT, HAND_EYE): a run fails, rather than return a model built on a
    //! small remnant of the data, when the multi-view step places fewer than this fraction of the
    //! calibration views (and at least 3), or when the bundle adjustment uses less than
    //! 1 - max_outlier_fraction of the calibration observations.
    double min_posed_fraction = 0.5;
    double max_outlier_fraction = 0.5;
    /*!
      The nominal model's stated tolerance: the largest error expected of a joint placement or the
      base (m, rad), and of the hand-eye transform eMc (a guess, often rough). An estimated
      correction beyond it, or an sd above it (the views determine the parameter worse than the
      nominal model knows it), makes the run DOUBTFUL. HAND_EYE does not check eMc (it is what is
      calibrated, from any start).
    */
    double tolerance_translation = 0.01;
    double tolerance_rotation = 0.05;
    double tolerance_hand_eye_translation = 0.1;
    double tolerance_hand_eye_rotation = 0.5;
    //! px: a calibration whose residuals measure more image noise than this does not explain its images (DOUBTFUL).
    double max_pixel_noise = 3.0;
    //! Throws vpSelfCalibException on nonsense values (the noise model's included, and a robot
    //! error the method does not use).
    void check() const;
  };

  enum Status {
    OK,
    TWO_VIEW_FAILED,
    SCALE_FAILED,
    IDENTIFICATION_FAILED,
    DEGENERATE_DATA, //!< the data check found data that cannot determine the calibration (message: what to do)
    /*!
      A model was estimated but fails a check of its own word (findings of severity DOUBT: what is
      wrong and what to do): corrections or sds beyond the nominal model's tolerance, a predicted
      error above the nominal model's misfit, the
      calibrated model explaining its calibration views or the held-out views no better than the
      nominal one, the yardstick not reproduced on the held-out views, residuals far above any
      plausible image noise. Every field is filled as for OK; use the model with care.
    */
    DOUBTFUL
  };
  static const char *statusName(Status s);

  /*!
    What the joint corrections of a BUNDLE_ADJUSTMENT run (Result::bundle's joint_corrections, one per
    calibration view) look like against reading noise, which is independent from view to view and
    from joint to joint, with mean 0. Judged when the joint readings' level measured is beyond a
    well-built arm's (1 mrad): the level stands only when they look like reading noise
    (readingNoise()); otherwise the readings are taken as exact (robot-error-taken-exact) or the
    level is doubted (robot-error-implausible).
    - offset: a joint's corrections have a mean far from 0 against their spread (Student's t over
      the views, two-sided 0.1 % with Bonferroni over the joints): a parameter held at a wrong value;
    - pose_like: on arms of 6 joints or more, the per-view camera displacements the corrections make
      are explained very strongly better (Bayesian information criteria more than 10 apart) by a
      per-view 6-D pose error (a rendering's, a loose camera's) than by reading noise.
    judged false: not judged (no joint level measured beyond 1 mrad, or fewer than 3 views).
  */
  struct VISP_SELFCALIB_EXPORT JointErrorStructure {
    bool judged = false;
    double offset_t = 0, offset_bound = 0; //!< the largest |t| of a joint's mean, and the 0.1 % bound
    std::string offset_joint;              //!< the joint of offset_t ("joint 3")
    bool offset = false;
    bool pose_compared = false; //!< the per-view pose model was compared (6 joints or more)
    double pose_bic_gain = 0;   //!< BIC of reading noise minus BIC of a per-view pose error
    bool pose_like = false;
    //! Judged, no offset, and reading noise very strongly preferred to a per-view pose error.
    bool readingNoise() const;
    //! What the corrections look like, for a finding ("a constant offset on joint 3 (t = 9.1)...").
    std::string describe() const;
  };

  /*!
    The calibrated model's predicted error on the workspace's motions (the camera's relative motions
    between configurations drawn over the joint limits; with the camera in the world, the target's),
    against the nominal model's error there as its misfit on the calibration views measures it: the
    workspace-worse-than-nominal check's figures (BUNDLE_ADJUSTMENT, PAPER, with joint readings).
    RMS over the pairs, m and rad. A joint that barely moves in the calibration views is drawn within
    the range they cover (joints_within).
  */
  struct VISP_SELFCALIB_EXPORT WorkspaceError {
    //! A joint held to the range the calibration views cover (rad).
    struct JointRange {
      std::string joint; //!< "j3"
      double lo = 0, hi = 0;
      unsigned int index = 0; //!< the joint's index in the chain (0-based)
    };
    bool computed = false;
    double calibrated_t = 0, calibrated_r = 0; //!< predicted RMS (its covariance and the parameters held)
    double bound_t = 0, bound_r = 0;           //!< its 90 % bound
    double nominal_t = 0, nominal_r = 0;       //!< the nominal model's, estimated from its misfit
    double worse_t = 0, worse_r = 0;           //!< the chance that the calibrated model is the worse
    bool scale_left_out = false;               //!< the nominal scale's error, common to both, left out
    std::vector<JointRange> joints_within;     //!< the joints drawn within the views' range
  };

  //! The result of vpRobotSelfCalibration: what it computed, and what the caller needs to judge it.
  struct Result {
    Status status = TWO_VIEW_FAILED;
    std::string message;
    Method method = BUNDLE_ADJUSTMENT;
    /*!
      What the data check found before calibrating (vpSelfCalibDataCheck), then, after the run:
      "outliers" (many observations not used), "yardstick-unused" (in the data, but rejected: the scale
      is the nominal model's) and "identifiability-lost" (parameters that a richer set of poses
      identifies, missing here), each with what to do.
    */
    std::vector<vpSelfCalibDataCheck::Finding> findings;
    //! The final estimate, either method: parameters estimated (and left out, with the reason) and
    //! their sd (per chain parameter, 0 for those not estimated).
    vpKinematicIdentification::Identifiability identifiability;
    vpColVector parameter_sd;
    /*!
      The calibrated hand-eye transform eMc (every method; PAPER from its identification's covariance) as a pose vector
      (tx, ty, tz, theta u) and its sd, propagated to first order from the covariance of the eMc
      corrections (a correction that is not estimated contributes no variance); has_eMc false
      otherwise.
    */
    bool has_eMc = false;
    vpPoseVector eMc;
    vpColVector eMc_sd;
    /*!
      Eye-to-hand (dataset camera_mount world, HAND_EYE): the camera in the robot's base frame bMc
      and the target in the end-effector frame eMo (a board's pose; has_eMo false for natural
      features, whose points in the effector frame are bundle.points), each a pose vector with its
      sd from the covariance (the controller poses' error modelled). has_eMc is then false.
    */
    vpSelfCalibDataset::CameraMount camera_mount = vpSelfCalibDataset::CAMERA_ON_EFFECTOR;
    bool has_bMc = false, has_eMo = false;
    vpPoseVector bMc, eMo;
    vpColVector bMc_sd, eMo_sd;
    vpKinematicChain calibrated;           //!< the nominal model with the identified corrections
    vpCameraParameters camera;             //!< with the focal length used
    /*!
      The noise the final run used (Options::noise, with the dataset's robot error where the options
      left it at 0, and the measured levels where they are measured; a robot error of 0: none
      modelled), and the one its residuals measure (pixel_sd; PAPER: that of its focal length from
      every view, 0 without; HAND_EYE with the controller poses' error modelled: pose_sd_*).
    */
    vpSelfCalibNoiseModel noise = vpSelfCalibNoiseModel::unmeasured();
    vpSelfCalibNoiseModel measured = vpSelfCalibNoiseModel::unmeasured();
    /*!
      How well each model explains the calibration views (BUNDLE_ADJUSTMENT, HAND_EYE): the
      reprojection RMS (px) of the points triangulated from these views through the nominal model
      (the dataset's camera) and through the calibrated one (its camera), the same rule for both
      (vpCalibrationVerifier). 0 when not computed.
    */
    double fit_nominal_rms = 0, fit_calibrated_rms = 0;
    /*!
      px, the calibrated model's own predicted error on new views (BUNDLE_ADJUSTMENT, PAPER): its
      covariance propagated to the relative camera poses of the calibration views (c_0 M c_k), then
      to the pixels of the points each view sees (first order, the pose's 6 x 6 covariance whole),
      each point triangulated again from its views (the part of the displacement a shift of the
      point explains removed, as fit_nominal_rms triangulates the nominal model's points), RMS per
      coordinate. When the 99.9 % quantile of that error (a weighted sum of chi-squares) exceeds
      twice fit_nominal_rms, the model's own uncertainty leaves more than a 0.1 % chance that it
      does worse than twice the nominal model on new views (DOUBTFUL, expected-worse-than-nominal).
      0 when not computed.
    */
    double predicted_rms = 0;
    WorkspaceError workspace; //!< the calibrated and the nominal model over the workspace
    //! With joints that barely move (workspace.joints_within): the same over every joint's whole range.
    WorkspaceError workspace_full_range;
    double fx = 0, fx_sd = 0;
    std::vector<vpTwoViewEstimator::Result> pairs;      //!< pair (1, i + 2) at index i
    std::vector<double> ratios;                         //!< PAPER: eq. 21 ratios, one per pair
    vpPoseScale::Result scale;                          //!< PAPER
    //! The pose measurements c_iMc_1: PAPER the scaled two-view poses, BUNDLE_ADJUSTMENT the
    //! multi-view ones (the start of the bundle adjustment)
    std::vector<vpKinematicIdentification::Measurement> measurements;
    vpKinematicIdentification::Result identification;   //!< pose-based identification from measurements
    //! BUNDLE_ADJUSTMENT, HAND_EYE; PAPER: the shared focal length's (Options::paper_focal_all_views)
    vpMultiViewReconstruction::Result multiview;
    vpKinematicBundleAdjustment::Result bundle;         //!< BUNDLE_ADJUSTMENT
    //! BUNDLE_ADJUSTMENT: the structure of bundle's joint corrections, judged once for them when
    //! their level measured is beyond 1 mrad (judged false otherwise)
    JointErrorStructure joint_error_structure;
    std::vector<std::pair<std::string, double>> stage_seconds; //!< wall time of each stage
    bool verified = false;                 //!< true when there were 2 or more verification views
    vpCalibrationVerifier::Result before, after; //!< yardstick 3-D error with the nominal and calibrated models
    double seconds = 0;
  };

  //! Progress of a run: stage name, done, total.
  using Progress = std::function<void(const std::string &, unsigned int, unsigned int)>;

  /*!
    Throws vpSelfCalibException on caller mistakes: fewer than 3 calibration views, a view without
    joints of the model's size or without any image point, non-finite values, joints outside the
    model's limits, no yardstick in the dataset (PAPER only: the bundle adjustment then keeps the
    nominal scale), an unknown focal length with FOCAL_KNOWN; all before any work.
    Degenerate data is DEGENERATE_DATA or a finding; numerical failures are statuses. The method's
    pipeline runs with the options the builders make; `options` is not changed.
  */
  static Result run(const vpKinematicChain &nominal, const vpSelfCalibDataset &dataset, const Options &options,
                    const Progress &progress = Progress());

  /*!
    The focal mode a run uses: options.focal_mode, FOCAL_AUTO resolved to FOCAL_KNOWN when
    dataset.focal_known, else FOCAL_SHARED. Throws vpSelfCalibException when it is FOCAL_KNOWN and
    the dataset's camera has no px.
  */
  static FocalMode resolveFocalMode(const Options &options, const vpSelfCalibDataset &dataset);

  /*!
    The two-view options a run uses (PAPER's pairs; BUNDLE_ADJUSTMENT's and HAND_EYE's through
    multiViewOptions()): the settings options.twoview with the run's inputs,
    - fx, u0, v0 the dataset camera's px, u0, v0 (fx: the known focal length, or the first guess
      when it is self-calibrated) and mu = py / px;
    - focal_mode KNOWN when resolveFocalMode() is FOCAL_KNOWN, else PER_PAIR (FOCAL_SHARED runs
      vpTwoViewEstimator::estimateShared, which sets its own).

    Throws vpSelfCalibException as resolveFocalMode().
  */
  static vpTwoViewEstimator::Options twoViewOptions(const Options &options, const vpSelfCalibDataset &dataset);

  /*!
    The noise model a run starts from: options.noise with, where it leaves the robot's error at 0,
    the dataset's robot_error in the method's form (HAND_EYE: the controller poses' pose_sd_*;
    BUNDLE_ADJUSTMENT: joint_sd), else robotErrorPrior() (HAND_EYE, BUNDLE_ADJUSTMENT) unless
    options.trust_robot. Throws vpSelfCalibException on a robot error the method does not
    use (pose_sd_* with BUNDLE_ADJUSTMENT, model_sd_* or joint_sd with HAND_EYE, any with PAPER).
  */
  static vpSelfCalibNoiseModel noiseModel(const Options &options, const vpSelfCalibDataset &dataset);

  /*!
    The robot's error a run starts from when nothing states it (Options::trust_robot false), every
    level MEASURED. BUNDLE_ADJUSTMENT: the joint readings' kJointErrorPrior and the model residual's
    kModelErrorPrior (both parts). HAND_EYE: the controller poses' error, 1 mm and 1 mrad. Between a serial arm's repeatability (0.02 to 0.1 mm) and its
    absolute accuracy (1 to 5 mm, a few mrad): loose enough that the images, not the prior, decide
    where the poses are wrong, tight enough that the first run is not an unconstrained per-view
    fit. It is a start, not a claim: the run measures the level and runs again at it.
  */
  static vpSelfCalibNoiseModel robotErrorPrior(const vpSelfCalibNoiseModel &noise, Method method = HAND_EYE);
  /*!
    rad: the joint reading error a BUNDLE_ADJUSTMENT run starts from when nothing states it, 3e-4
    rad (0.017 deg). A 17 to 20 bit encoder reads a joint to 1e-5 rad, but what the model sees is
    the joint's angle at the link, after the gear's lost motion and the joint's compliance under
    the arm's own weight: 1e-4 to 1e-3 rad on serial arms (harmonic drives: about 1 arc-minute,
    3e-4 rad). It is a start, not a claim: the run measures the level and runs again at it.
  */
  static constexpr double kJointErrorPrior = 3e-4;
  /*!
    m and rad: the kinematic model's residual a BUNDLE_ADJUSTMENT run starts from when nothing
    states the robot's error, 0.2 mm and 0.2 mrad per view: what a geometric model leaves on a
    serial arm after calibration (link and gear compliance, gear eccentricity: 0.1 to 0.5 mm),
    above its repeatability (0.02 to 0.1 mm). Measured from there, as kJointErrorPrior.
  */
  static constexpr double kModelErrorPrior = 2e-4;

  /*!
    The multi-view reconstruction options a run uses (BUNDLE_ADJUSTMENT, HAND_EYE): the settings
    options.multiview with the run's inputs,
    - focal_known true when resolveFocalMode() is FOCAL_KNOWN;
    - twoview = twoViewOptions(options, dataset).

    Throws vpSelfCalibException as twoViewOptions().
  */
  static vpMultiViewReconstruction::Options multiViewOptions(const Options &options, const vpSelfCalibDataset &dataset);

  /*!
    The kinematic bundle adjustment options a run uses (BUNDLE_ADJUSTMENT, HAND_EYE): the settings
    options.bundle with the run's inputs,
    - the FX flag of intrinsics cleared when resolveFocalMode() is FOCAL_KNOWN, set otherwise (the
      other flags are the caller's);
    - hand_eye_only true for HAND_EYE;
    - the tolerances (tolerance_translation ... tolerance_hand_eye_rotation) the options' own;
    - the dataset's fix and free lists added to the caller's fixed and free, and its kinematic_prior
      (off included) where the caller's is empty (not for HAND_EYE); both empty: left empty, the
      bundle adjustment's default prior (vpKinematicBundleAdjustment::DEFAULT_KINEMATIC_PRIOR).

    Every method estimates the set vpKinematicIdentification::analyseConfigurations() selects from the
    calibration views' joint configurations at the nominal model (PAPER passes it to its
    identification; BUNDLE_ADJUSTMENT's start identification estimates a subset of it, the bundle
    adjustment all of it), so it does not depend on the noise. Throws vpSelfCalibException as
    resolveFocalMode().
  */
  static vpKinematicBundleAdjustment::Options bundleOptions(const Options &options, const vpSelfCalibDataset &dataset);

  //! The data check options a run uses: options.data_check (its noise: noiseModel()).
  static vpSelfCalibDataCheck::Options dataCheckOptions(const Options &options);

private:
  //! run() once the camera's mount is resolved: the eye-in-hand problem (eye-to-hand: inverted poses).
  static Result runMounted(const vpKinematicChain &nominal, const vpSelfCalibDataset &dataset, const Options &options,
                           const Progress &progress);
};

#endif
