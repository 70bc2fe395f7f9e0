/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpKinematicBundleAdjustment.h
  \brief Kinematic bundle adjustment (beyond the paper): the robot's kinematic parameters, the camera
  intrinsics and the scene points estimated jointly from every image observation.
*/
#ifndef VP_KINEMATIC_BUNDLE_ADJUSTMENT_H
#define VP_KINEMATIC_BUNDLE_ADJUSTMENT_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpColVector.h>
#include <visp3/core/vpMatrix.h>
#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpKinematicIdentification.h>
#include <visp3/selfcalib/vpMultiViewReconstruction.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>
#include <visp3/selfcalib/vpSelfCalibNoiseModel.h>

/*!
  \class vpKinematicBundleAdjustment
  \ingroup group_selfcalib_identification
  \brief Kinematic bundle adjustment (beyond the paper): the robot's kinematic parameters, the
  camera intrinsics and the scene points estimated jointly from every image observation.

  Unknowns: the identifiable corrections rho of the vpKinematicChain, the requested intrinsics
  (f_x by default; on request the aspect ratio mu = p_y / p_x, the principal point and ViSP's radial
  distortion coefficient k_ud) and every scene point X_j in the reference frame f.

  Residual of the observation (u, v) of point j in view k, divided by the pixel noise sd:
      X_c = fMc(q_k; rho)^-1 X_j,  x = X_c,x / X_c,z,  y = X_c,y / X_c,z,  g = 1 + k_ud (x^2 + y^2)
      r = ( u0 + p_x x g - u,  v0 + mu p_x y g - v ) / pixel_sd
  (ViSP's perspective projection with distortion, vpMeterPixelConversion). The paper calibrates
  distortion in a separate step; here it is folded into the same estimate. The Jacobian is analytic:
  dX_c/drho = -R^T J_t + [X_c]x R^T J_phi with the chain's identification Jacobian
  (vpKinematicChain::getJacobian()); poses and Jacobians are computed once per view and evaluation
  point (a Ceres EvaluationCallback), not once per observation.

  Gauge, fixed explicitly:
  - the base frame: moving every point with the base leaves the images unchanged, so the base
    correction and the joint-1 placement are not estimated (they cancel as in relative pose
    measurements). The estimated set is the one vpKinematicIdentification::analyseConfigurations()
    selects for the relative poses c_kMc_0 of the views' joint configurations at the NOMINAL model
    (the start's corrections, the images and the noise play no part: the same robot and poses give
    the same set; 24 for a 6-joint arm), minus Options::fixed; the others stay at their start values
    and are listed with the reason. Hand-eye-only mode: eMc's six minus Options::fixed, whatever the
    motion (a degenerate motion is RANK_DEFICIENT, not a smaller set).
  <b>The estimated set from the data</b> (full kinematic mode, Options::set_from_information): the
  candidates are the rule's set above; the adjustment's own Jacobian at the start values (the start
  chain, camera and points, the STATED noise: pixel_sd and the robot's error; never the residuals,
  so noise draws of the same geometry give the same set) gives the information of the corrections
  with the scene points, intrinsics, robot-error corrections and the known object's pose eliminated
  (Schur complement: the marginal information of the corrections). Walked in the preference order
  (Options::free first), a candidate is estimated when, with it added, (1) its information
  conditional on those kept before it is at least separation_tolerance of its own (else the data
  cannot separate it from them), and (2) the predicted sd of it and of every one kept before it stays
  within the nominal model's tolerance (Options::tolerance_*; the scale direction held when it is,
  as in the solve). Otherwise it is listed with cause CAUSE_DATA, the reason and what would
  determine it, and, with the kinematic prior (Settings::kinematic_prior, the default), estimated
  nonetheless, held by the prior (Identifiability::held_by_prior); without it (KINEMATIC_PRIOR_OFF,
  the set rule) it stays at its start value (the nominal one in the pipeline). What would determine
  it: the joint between its placement and the next one (the smaller range of the two in the views),
  the range it moves, and about how far it would have to move (the sd shrinks as the inverse of that
  range), or more views when that joint already moves widely. A freed parameter skips (2).

  - the scale: scaling every length of the robot and the scene leaves the images unchanged. With a
    yardstick (both ends observed) the residual (|X_a - X_b| - L) / yardstick_sd fixes it
    (SCALE_YARDSTICK). Without, the component of rho along the scale direction (the least-squares
    combination of corrections that scales every camera position about a point of the first joint
    axis) is held at its start value (SCALE_NOMINAL: the start model's scale, the nominal one in
    the pipeline), and the result says so. With the kinematic prior (Settings::kinematic_prior, the
    default) the prior holds it instead: no separate gauge, the prior's weight on the scale direction the nominal
    lengths' own.

  Noise (vpSelfCalibNoiseModel, passed to adjust() and information()): pixel_sd weighs the
  reprojection residuals, loss and loss_scale make the robust stages, outlier_threshold the rejection.
  The robot's error adds a correction per view with a prior residual (correction / sd) beside the
  pixel residuals, so that the estimate weighs pixel noise and robot error together and its
  covariance accounts for both:
  - hand-eye-only mode, the controller poses (pose_sd_*): each view k gets delta_k = (t, theta u)
    in its end-effector frame, fMe_k' = fMe_k [exp([theta u]x) | t];
  - full kinematic mode, the kinematic model's residual (model_sd_*): a correction of each view's
    camera pose in the camera frame, fMc_k' = fMc(q_k; rho) [exp([theta u]x) | t]; and the joint
    readings (joint_sd): joint corrections dq_k, the pose fMc(q_k + dq_k; rho).
  A robot error of the other mode (pose_sd in full mode, model_sd or joint_sd in hand-eye mode) is a
  caller mistake.

  Solver: Ceres Levenberg-Marquardt with the Schur complement (points eliminated, DENSE_SCHUR on the
  small reduced system), robust loss on the whitened residuals (Cauchy by default), then the
  observations above outlier_threshold sd are dropped and the problem is solved again with plain
  least squares, so the covariance is the Gauss-Newton one: (J^T J)^-1 of the identified parameters
  and intrinsics, the points marginalized (Ceres Covariance, sparse QR). At the true state and with
  the true noise sd, information() gives the Cramér-Rao bound of the same problem.
*/
class VISP_SELFCALIB_EXPORT vpKinematicBundleAdjustment
{
public:
  //! Intrinsics that can be estimated (bitwise or).
  /*!
    Intrinsics that can be estimated (bitwise or). DISTORTION: ViSP's k_ud, or with the OpenCV model
    k1, k2, p1, p2 (k3 held at its start value unless DISTORTION_K3 is added too: it is poorly
    determined by most data, as in OpenCV's CALIB_FIX_K3 practice).
  */
  enum Intrinsic : unsigned int { FX = 1, ASPECT = 2, PRINCIPAL_POINT = 4, DISTORTION = 8, DISTORTION_K3 = 16 };
  //! Lens distortion model of the estimate.
  enum DistortionModel { DISTORTION_VISP, DISTORTION_OPENCV };
  //! The kinematic prior's k when neither the caller nor the dataset gives one (Settings::kinematic_prior).
  static constexpr double DEFAULT_KINEMATIC_PRIOR = 3;
  //! Settings::kinematic_prior's value for no prior: the set from the data alone (the set rule).
  static constexpr double KINEMATIC_PRIOR_OFF = 0;

  /*!
    The caller's settings of vpKinematicBundleAdjustment (the defaults are the member initialisers).
    vpRobotSelfCalibration::Options holds these; the mode (hand_eye_only), which follows from the
    method, is added by vpRobotSelfCalibration::bundleOptions(), which also sets the FX flag of
    intrinsics from the focal mode.
  */
  struct Settings {
    unsigned int intrinsics = FX;      //!< estimated intrinsics; 0: the camera is known
    /*!
      DISTORTION_VISP (default): the camera's own model (vpCameraParameters' k_ud, or none).
      DISTORTION_OPENCV: OpenCV's (k1, k2, p1, p2, k3) model, starting from (or, without DISTORTION,
      held at) opencv_distortion; the camera passed must then have no ViSP distortion.
    */
    DistortionModel distortion_model = DISTORTION_VISP;
    std::vector<double> opencv_distortion; //!< (k1, k2, p1, p2, k3); empty: all 0
    //! Kinematic parameters kept at their start value by the caller: names or glob patterns
    //! ("j3.*"; vpKinematicIdentification::matchParameters()).
    std::vector<std::string> fixed;
    /*!
      Full kinematic mode: kinematic parameters (names or glob patterns) estimated whatever their
      predicted sd, walked before the others of the preference order (see "The estimated set from
      the data" above). A freed parameter that the model's rule leaves out (a redundancy) is
      refused: status RANK_DEFICIENT naming it and the reason; so is, without the kinematic prior
      (kinematic_prior KINEMATIC_PRIOR_OFF), one the data cannot separate from those estimated
      before it (with the prior it is estimated, held by the prior). Also fixed: a caller mistake.
    */
    std::vector<std::string> free;
    /*!
      Full kinematic mode: decide the estimated set from the information of this adjustment (true,
      default; see "The estimated set from the data" above), or estimate the whole set of the rule
      on the joints (false: the set of vpKinematicIdentification::analyseConfigurations()).
    */
    bool set_from_information = true;
    /*!
      The nominal model's tolerance, the largest error expected of a joint placement (m, rad) and of
      the hand-eye transform eMc, a guess (m, rad): a parameter whose predicted sd would exceed it is
      left at its nominal value (vpRobotSelfCalibration's tolerance_* give them in the pipeline).
    */
    double tolerance_translation = 0.01;
    double tolerance_rotation = 0.05;
    double tolerance_hand_eye_translation = 0.1;
    double tolerance_hand_eye_rotation = 0.5;
    /*!
      A parameter whose information conditional on the parameters estimated before it is below this
      fraction of its own (1 / its variance inflation) is not separable from them (1e-8: an sd 10^4
      times the one it would have alone).
    */
    double separation_tolerance = 1e-8;
    /*!
      Full kinematic mode: a prior on every estimated correction (but the hand-eye ones of a
      measured eMc: Options::eMc_measured), k. Empty (not said): the default,
      DEFAULT_KINEMATIC_PRIOR (3); KINEMATIC_PRIOR_OFF (0): no prior (the set from the data alone,
      the parameters it does not determine left at their start value). Each correction gets the
      residual (rho_i - rho_ref,i) / (tol_i / k) beside the pixels, tol_i its tolerance
      (tolerance_*) and rho_ref the model whose scale is held (scale_reference, else the start's):
      the nominal model in the pipeline. k = 1: the tolerance is one sd of the nominal model's
      error; 3: it is three. With the prior every candidate of the rule is estimated: those the data
      alone do not determine (the set from the data would leave them at nominal) are estimated too,
      held near nominal by the prior, and listed in Result::identifiability.held_by_prior with the
      reason and what would determine them; a freed one (free) the data do not determine is held by
      the prior too instead of refused. The prior also holds the scale without a yardstick (no
      separate gauge: its weight on the scale direction is the nominal lengths' own). The covariance
      and the sd are the posterior ones, (J^T J + P)^-1 with P = diag((k / tol_i)^2): the Cramér-Rao
      bound of the estimate with that prior (information() gives it at any state). The prior pulls
      every estimate toward rho_ref by its weight: on noise-free data the recovery is exact only
      without it. The vpRobotSelfCalibration pipeline passes the caller's value, else the dataset's
      (vpSelfCalibDataset::kinematic_prior), else leaves it empty.
    */
    std::optional<double> kinematic_prior;
    //! The k used (kinematicPrior(): kinematic_prior, DEFAULT_KINEMATIC_PRIOR when empty; 0: none).
    double kinematicPrior() const;
    /*!
      Without a yardstick (SCALE_NOMINAL), the corrections of the model whose scale is held (all of
      the chain's, vpKinematicChain::getParameters(), the start's DH table): the gauge holds the
      component of the corrections along the scale direction at this model's value. Empty: the
      start model's (the pipeline gives the nominal model, so that a start identification that
      drifted in scale does not carry its drift into every length).
    */
    std::vector<double> scale_reference;
    /*!
      The estimated set decided by the caller (estimatedSet(), before a start identification that
      must estimate the same set): when its `identified` list is not empty it is used as it is (its
      reasons kept), else the set is decided by the adjustment itself.
    */
    vpKinematicIdentification::Identifiability estimated_set;
    double yardstick_sd = 1e-5;        //!< m, uncertainty of the yardstick's length
    double rank_tolerance = 1e-6;      //!< estimated-set threshold (vpKinematicIdentification::Options)
    unsigned int max_iterations = 100;
    bool tight = false;                //!< tolerances 1e-15 (exact recovery on noise-free data)
    bool covariance = true;            //!< compute the covariance
    /*!
      Hand-eye-only mode, eye-to-hand: each view's fMe is the inverse of a controller pose bMe (the
      effector frame plays f, the camera's base pose bMc plays eMc, the target's points are in the
      effector frame). The controller pose's error stays modelled where it is made, on bMe's right:
      the view's pose is (bMe E(delta))^-1 = E(delta)^-1 fMe, delta's prior the noise model's pose_sd.
    */
    bool controller_poses_inverted = false;
    /*!
      Full kinematic mode, eye-to-hand: the camera is fixed in the world and the points (a target
      carried by the tool) are fixed in the end-effector frame e, which plays f for the points and
      the known object (whose pose is then eMo). The chain's hand-eye slot (its nominal eMc and
      correction eMc.*) holds bMc, the camera in the chain's reference frame; view k's camera pose
      in e is fMe(q_k; rho)^-1 bMc, the joint-reading corrections dq_k on q_k as in eye-in-hand.
      The estimated set mirrors the eye-in-hand one: the base and the placement of joint 1 act as a
      change of bMc (estimated in their place), and the components of the last joint's placement
      that commute with its rotation (its offset rz and slide tz) act as a change of the target's
      pose eMo; both are left out with that reason. With known points the target's layout fixes the
      scale (SCALE_KNOWN_POINTS). Not with hand_eye_only (controller_poses_inverted is that mode's
      eye-to-hand).
    */
    bool eye_to_hand = false;
    /*!
      Scale the covariance by sigma0^2 when sigma0 > 1: the residuals say the stated noise (pixel
      and robot) is too small, and the standard deviations are widened accordingly (the a
      posteriori variance factor). Off by default.
    */
    bool scale_covariance = false;
    /*!
      Scale the covariance by sigma0^2 whenever sigma0 is outside the two-sided 99.9 % interval of
      sqrt(chi2(dof) / dof): the residuals contradict the stated noise in either direction (too
      small a pixel_sd gives too small standard deviations, too large a pixel_sd too large ones).
      With robot error modelled (the noise model's pose, joint or model sd) only a sigma0 above 1 scales (as
      scale_covariance): their priors absorb what the pixels leave, and a sigma0 below 1 then says
      the priors were loose, not that the estimate is better. Takes precedence over
      scale_covariance. Off by default.
    */
    bool scale_covariance_chi2 = false;
    /*!
      Scene points of known geometry (a calibration board's layout): id -> coordinates (3-vector, m)
      in the object's own frame. The object's pose in f (6 parameters) is estimated with the rest,
      and each of these points observed gets the prior residual (X_j - fMo L_j) / known_points_sd.
      At least 3 of them must be observed. Empty (default): the whole scene is unknown.
    */
    std::map<int, vpColVector> known_points;
    /*!
      sd of each known point's placement on its object (m). The default, 10 um, is a printed or
      machined board's dot placement, and it is what makes the layout known: a point seen N times
      at depth Z through a focal length f is located by the images alone to about
      pixel_sd Z / (f sqrt(N)) (0.2 px, 0.5 m, 540 px, 12 views: 53 um). A prior looser than that
      lets the points take the board's shape from the images (and the focal length with it).
    */
    double known_points_sd = 1e-5;
    /*!
      With known points in hand-eye-only mode (the robot's metric motion fixes the scale; in the full
      mode a wrong size scales the kinematic corrections instead): after the solve, measure the scale
      of the declared layout. One more
      adjustment from the solution frees a factor s on the layout (every known point s L_j), and
      Result::layout_scale and its sd come from its covariance; the estimate is not changed. A
      layout declared at the wrong size (a board's spacing mistyped) gives s away from 1 when the
      views determine it; poses on a sphere about the board leave it undetermined (a large sd).
      Without known points, a yardstick (both ends observed) is measured the same way: its
      declared length times s, s the length the views measure over the declared one (a board's
      first row taken as the yardstick at a mistyped spacing). On by default.
    */
    bool measure_layout_scale = true;
    unsigned int num_threads = 1;       //!< more is faster on large problems, but not bit-reproducible
    void check() const; //!< throws vpSelfCalibException on a setting out of range
  };

  //! What vpKinematicBundleAdjustment runs with: the settings and the mode.
  struct Options : Settings {
    /*!
      Hand-eye-only mode: the robot's kinematics are trusted and only the hand-eye correction
      eMc.* (minus `fixed`) and the intrinsics are estimated, with each view's end-effector pose
      fMe (View::fMe when has_fMe, else the chain's forward kinematics at View::q). The metric
      end-effector motion fixes the scale (SCALE_ROBOT_MOTION); a yardstick seen in two views adds
      its residual. Rotations about a single axis leave part of eMc unobservable: RANK_DEFICIENT.
    */
    bool hand_eye_only = false;
    /*!
      The start chain's eMc was measured from these data, not stated (the pipeline's measured
      start): the kinematic prior (Settings::kinematic_prior) then leaves out the hand-eye
      corrections the data determine. A prior around the measured eMc would count the data twice, and
      along the directions the data leave free (a stuck joint's offsets against eMc) it would share
      them between the joints and eMc around a value that is no one's statement: from a focal length
      started far off, tens of millimetres from the truth. The hand-eye corrections the data alone
      do not determine keep the prior (nothing else holds them).
    */
    bool eMc_measured = false;
    //! Settings::check(), then the mode against the settings (eye_to_hand is the full mode's).
    void check() const;
  };

  /*!
    What fixes the scale: the yardstick, the start model's scale held (no yardstick), the robot's
    metric motion (hand-eye-only mode), or the target's known layout (eye-to-hand, known points).
  */
  enum ScaleSource { SCALE_YARDSTICK, SCALE_NOMINAL, SCALE_ROBOT_MOTION, SCALE_KNOWN_POINTS };
  static const char *scaleSourceName(ScaleSource s);
  enum Status { OK, TOO_FEW_OBSERVATIONS, RANK_DEFICIENT, NO_CONVERGENCE };
  static const char *statusName(Status s);

  //! The result of vpKinematicBundleAdjustment: what it computed, and what the caller needs to judge it.
  struct Result {
    Status status = TOO_FEW_OBSERVATIONS;
    std::string message;
    vpKinematicChain chain;                  //!< the start chain with the estimated corrections
    vpCameraParameters camera;               //!< estimated intrinsics (with k_ud when that model is estimated)
    //! OpenCV model: its (k1, k2, p1, p2, k3) at the estimate (camera then has no distortion); else empty.
    std::vector<double> opencv_distortion;
    vpKinematicIdentification::Identifiability identifiability; //!< estimated and left-out parameters
    ScaleSource scale_source = SCALE_NOMINAL;
    std::map<int, vpColVector> points;       //!< scene points in f (3-vectors), by id
    /*!
      With known points (Options::known_points): the object's pose fMo (t, theta u), and with the
      covariance its 6 x 6 covariance (t in m, theta u in rad; the points marginalized, scaled as
      the rest) and its sd.
    */
    bool has_object = false;
    vpPoseVector object_pose;
    vpMatrix object_covariance;
    vpColVector object_sd;
    /*!
      Settings::measure_layout_scale with known points (or a yardstick) and a covariance: the
      layout's (the yardstick's) scale s the views measure (1: the declared size), its sd (scaled
      as the covariance; infinite when the views do not determine it), and whether it was measured
      (false: neither known points nor a yardstick, not hand-eye-only mode, or the solve failed).
    */
    /*!
      SCALE_NOMINAL, full kinematic mode, adjust(): the relative sd of the scale held (the nominal
      lengths' own error: the estimated corrections' tolerances, tolerance_*, projected on the scale
      direction s, sigma^2 = sum_i (s_i tol_i)^2 / |s|^4). The covariance counts it: sigma^2 s s^T
      added to the corrections' block, so that the sd of every length (eMc's translation, the link
      lengths) and what is propagated from them include the scale's error. With the kinematic
      prior, which holds the scale itself: the prior's sd along the scale direction,
      1 / sqrt(s^T P s), already in the posterior covariance (nothing added). 0 otherwise.
    */
    double nominal_scale_sd = 0;
    //! The k of the kinematic prior the corrections were estimated with (Settings::kinematic_prior; 0: none).
    double kinematic_prior = 0;
    /*!
      With the kinematic prior and a covariance: whether the data agree with the prior, per group of
      corrections of one tolerance (joint translations, joint rotations, hand-eye translations, hand-eye
      rotations; the base's with the joints'). chi2: the sum of the squared prior residuals
      ((rho - rho_ref) / sd)^2 at the estimate; redundancy: their expected sum when the corrections are
      drawn with the prior's sd (the trace of I - S C S over the group, C the posterior covariance at the
      stated weights, S = diag(1 / sd)), the number of corrections the data rather than the prior
      determine; quantile: chi2's 99.9 % quantile then (the eigenvalues of that block as weights of a sum
      of chi-squares). chi2 above the quantile: the data put the corrections beyond what the prior's sd
      allow (the arm's errors larger than its stated tolerances / k), and the sd, which the prior
      narrows, understate the error. sqrt(chi2 / redundancy) is the factor the prior's sd are off by.
    */
    struct PriorGroup {
      std::string name;
      double chi2 = 0, redundancy = 0, quantile = 0;
    };
    std::vector<PriorGroup> prior_groups;
    bool has_layout_scale = false;
    double layout_scale = 1;
    double layout_scale_sd = 0;
    vpColVector sd;                          //!< per chain parameter (0 for those not estimated)
    //! Estimated intrinsics: "fx", "mu", "u0", "v0", then "kud" or OpenCV's "k1", "k2", "p1", "p2", "k3".
    std::vector<std::string> intrinsic_names;
    vpColVector intrinsics, intrinsics_sd;   //!< their values and sd
    double fx_sd = 0;                        //!< px (0 when f is not estimated)
    vpMatrix covariance;                     //!< identified parameters then estimated intrinsics
    std::vector<std::string> covariance_names;
    bool has_covariance = false;
    /*!
      RANK_DEFICIENT: the estimated parameters (corrections and intrinsics) along the direction the
      data do not determine, the most involved first (also named in the message).
    */
    std::vector<std::string> undetermined;
    unsigned int num_observations = 0, num_outliers = 0;
    double rms = 0;                          //!< px, reprojection RMS over the kept observations
    double sigma0 = 0;                       //!< sqrt(2 cost / dof): about 1 when pixel_sd is right
    bool covariance_scaled = false;          //!< the covariance was multiplied by sigma0^2 (scale_covariance)
    //! The factor the covariance was multiplied by after the solve (sigma0^2, or the floor's; 1 when not
    //! scaled): the solve weighed the data at the stated noise, the covariance says the measured one.
    double covariance_factor = 1;
    /*!
      The noise the residuals measure (origin MEASURED; a level not measured is 0):
      - pixel_sd (px), robustly: 1.4826 x the median absolute residual coordinate over every
        observation that projects (the rejected ones included, so that a too small pixel_sd does
        not hide the noise), times sqrt(observations / dof) for the estimated unknowns. Independent
        of the stated pixel_sd; 0 without observations.
      - pose_sd_translation (m) and pose_sd_rotation (rad), hand-eye mode (hand_eye_only) with the
        controller pose error modelled and a covariance, by variance component estimation: for the
        translations, then the rotations, the sum of the squared corrections over their redundancy,
        sum (1 - posterior variance / stated variance), the posterior variances from the covariance
        at the stated weights. A stated sd that is right gives about itself back; 0 without pose
        corrections, without covariance, or when the corrections' redundancy is below 1 (the images
        do not separate them from the rest).
      - joint_sd (rad, one per joint) and model_sd_translation (m), model_sd_rotation (rad), full
        mode with the joint readings' error or the model's residual modelled and a covariance, by
        Helmert's variance component estimation over the pixels, the joints (one factor on their
        stated sds), the model residual's translations and its rotations: the factors solve
        H theta = q, where q holds each group's sum of squared whitened residuals and H the traces
        of the products of their blocks of the residuals' cofactor (unbiased whatever the weights
        used, where the diagonal estimate q / redundancy gives each of the joints and the model
        residual what both explain). A part whose redundancy is below 1 is 0; a part measured with
        no error (a factor at or below 0) is 1e-6 of the level used (below any drop level).
    */
    vpSelfCalibNoiseModel measured = vpSelfCalibNoiseModel::unmeasured();
    /*!
      The standard deviation of measured.joint_sd's largest value (rad), from the variance
      components' covariance (twice the inverse of H, Gaussian residuals): how well the views
      determine the joints' level. 0 when the joints' level was not measured.
    */
    double measured_joint_level_sd = 0;
    /*!
      The noise the estimate stands at: the one given, except in full mode for the joint readings'
      error and the model's residual when the noise model asks to measure them (measure_joint_sd,
      measure_model_sd). Those are measured in the neighbourhood of the solution: the levels the
      variance components give (`measured`, each part at least a serial arm's repeatability, 2e-5 m
      and rad), and the image noise's factor (pixel_factor), weigh the priors and the pixels again
      and the adjustment is solved again from its solution (the kept observations, plain least
      squares, the tight tolerances), until every part changes by 25 % or less and the pixels'
      factor by 10 % or less (its origin then MEASURED). Both asked on an arm of 6 joints or more,
      the joints alone take the robot's error (robot_error_confounded). A form measured below 4e-5 in every part is dropped: its corrections
      are no longer estimated (exact readings, or no model residual). The estimate, covariance and
      statistics are those of the last solve.
    */
    vpSelfCalibNoiseModel noise;
    //! The solves again of that measurement (0: the first solve's levels agreed, or nothing measured).
    unsigned int robot_rounds = 0;
    /*!
      With the robot's error measured in full mode: the image noise's sd the pixels were weighed at
      in the last solve, over noise.pixel_sd. Its variance component is measured in the same rounds
      as the robot's (a stated pixel_sd too small is then measured as such rather than taken up by
      the robot's corrections), and the covariance is that of the measured weights, not scaled by
      sigma0 again. 1 otherwise.
    */
    double pixel_factor = 1;
    /*!
      The joint corrections and the model residual move the cameras the same way (on a 6-joint arm
      both span each view's 6-D displacement): the images cannot split the robot's error between
      them. One level was measured, taken by the joint readings, and the model residual dropped.
    */
    bool robot_error_confounded = false;
    /*!
      Empty when the robot's error measured settled (or nothing was measured); else what did not:
      a form that could not be measured (redundancy below 1), levels still moving after the last
      round, or a solve again that failed (the estimate is then the last one that succeeded).
    */
    std::string robot_error_unsettled;
    //! The two-sided 99.9 % interval of sigma0 for the degrees of freedom of the solution.
    double sigma0_low = 0, sigma0_high = 0;
    /*!
      With a per-view pose correction modelled (the noise model's pose_sd in hand-eye mode, model_sd
      in full mode): the estimated correction delta_k of each view's
      controller pose (hand-eye) or camera pose (full mode) (t, theta u; empty otherwise), and the RMS
      of their translation (m) and rotation (rad) parts: the robot part of the residuals, beside rms
      (the pixel part).
    */
    std::vector<vpColVector> pose_corrections;
    double pose_rms_translation = 0, pose_rms_rotation = 0;
    //! With joint-reading noise modelled (the noise model's joint_sd): each view's estimated joint corrections (rad) and their RMS.
    std::vector<vpColVector> joint_corrections;
    double joint_rms = 0;
    /*!
      With robot error modelled: the robot part of the chi-square, the sum of the squared whitened
      corrections (each pose or joint correction over its stated sd), and their number. The
      corrections are estimates, shrunk towards 0 by the pixels: their chi-square stays below its
      number when the stated robot error is right, and far above it when the corrections absorb more
      (a model or eMc that is off, or a robot error larger than stated). 0 without robot error.
    */
    double robot_chi2 = 0;
    unsigned int robot_dof = 0;
    /*!
      The largest ratio of a part of the robot corrections' RMS to its stated sd (the pose
      translations, the pose rotations, the joints): 3 or more says they stand in for something the
      model does not explain rather than for the stated robot error. 0 without robot error.
    */
    double robot_rms_ratio = 0;
    /*!
      Without robot error modelled (vpSelfCalibNoiseModel::hasRobotError() false): each view's camera re-posed alone on
      its kept observations, the points and intrinsics held (a rigid correction per view, 6 values).
      reposed_rms: the reprojection RMS then (px, over the views with 4 kept observations or more;
      0 when not computed), over reposed_views views; repose_rms_translation (m) and
      repose_rms_rotation (rad): the RMS of the corrections, camera frame. repose_f: the F statistic
      of the fit gained, ((S0 - S1) / 6K) / (S1 / (dof - 6K)) with S0, S1 the sums of squares before
      and after over those views and dof the solution's: about 1 when the residuals are image noise;
      repose_f_limit: its 99.9 % quantile (approximate). Far above it, with reposed_rms well below
      rms, the residuals are mostly each view's own camera displacement (a robot pose error the model
      does not have), not noise, and the sd computed as if they were noise are too small.
    */
    double reposed_rms = 0;
    double repose_rms_before = 0; //!< px, the RMS over the same views before re-posing
    unsigned int reposed_views = 0;
    double repose_rms_translation = 0, repose_rms_rotation = 0;
    double repose_f = 0, repose_f_limit = 0;
    unsigned int iterations = 0;
    double seconds_solve = 0, seconds_covariance = 0;
  };

  /*!
    Bundle adjustment from the start chain and camera, with initial scene points in f (every point
    observed in two or more views needs one; others are ignored). Views need joint vectors of the
    chain's size. Throws vpSelfCalibException on caller mistakes (sizes, non-finite values, an
    unknown fixed name, nonsense options or noise model, a robot error of the other mode); too few
    observations, rank deficiency and no convergence are statuses.
  */
  static Result adjust(const vpKinematicChain &start, const vpCameraParameters &camera,
                       const std::vector<vpSelfCalibDataset::View> &views,
                       const vpSelfCalibDataset::Yardstick &yardstick, const std::map<int, vpColVector> &points,
                       const Options &options, const vpSelfCalibNoiseModel &noise);

  /*!
    The estimated set adjust() decides for these data (see "The estimated set from the data"), at the
    start values given, without solving: to give a start identification the same set
    (Options::estimated_set). With Settings::kinematic_prior, adjust() given this set estimates in
    addition the parameters it leaves at nominal by the data (cause CAUSE_DATA), held by the prior
    (Identifiability::held_by_prior). Throws as adjust().
  */
  static vpKinematicIdentification::Identifiability estimatedSet(const vpKinematicChain &start,
                                                                 const vpCameraParameters &camera,
                                                                 const std::vector<vpSelfCalibDataset::View> &views,
                                                                 const vpSelfCalibDataset::Yardstick &yardstick,
                                                                 const std::map<int, vpColVector> &points,
                                                                 const Options &options,
                                                                 const vpSelfCalibNoiseModel &noise);

  /*!
    The predicted sd (m, rad) of the corrections `parameters` (chain indices, among the candidates of
    the model's rule for these views: vpKinematicIdentification's set at the nominal model) estimated
    together, the other corrections held at their start values: the test estimatedSet() applies to a
    subset (the information of the adjustment at the start values, the points, intrinsics and robot
    error marginalized, the scale direction held without a yardstick). Infinite when the data do not
    determine them. Full kinematic mode only. Throws as adjust(), and on a parameter that is not a
    candidate.
  */
  static vpColVector predictedSd(const vpKinematicChain &start, const vpCameraParameters &camera,
                                 const std::vector<vpSelfCalibDataset::View> &views,
                                 const vpSelfCalibDataset::Yardstick &yardstick, const std::map<int, vpColVector> &points,
                                 const std::vector<unsigned int> &parameters, const Options &options,
                                 const vpSelfCalibNoiseModel &noise = vpSelfCalibNoiseModel());

  /*!
    The covariance of the same problem at the given state, without solving and without robust loss
    or outlier rejection. At the true chain, camera and points with the true noise this is the
    Cramér-Rao bound of the kinematic parameters and intrinsics.
  */
  static Result information(const vpKinematicChain &state, const vpCameraParameters &camera,
                            const std::vector<vpSelfCalibDataset::View> &views,
                            const vpSelfCalibDataset::Yardstick &yardstick, const std::map<int, vpColVector> &points,
                            const Options &options, const vpSelfCalibNoiseModel &noise);

  /*!
    First-order covariance (6 x 6: position in m, then rotation in rad, both in the frame of c_ref)
    of the relative pose c_ref M c(q) predicted by the chain, from the covariance of the parameters
    `parameters` (chain indices, the first rows/columns of `covariance`).
  */
  static vpMatrix relativePoseCovariance(const vpKinematicChain &chain, const std::vector<unsigned int> &parameters,
                                         const vpMatrix &covariance, const vpColVector &q_ref, const vpColVector &q);

  /*!
    Projection (u, v) of the f-frame point X seen at joints q, and its analytic Jacobian
    (2 x (|parameters| + 5 + 3)) with respect to the chain corrections `parameters`, the intrinsics
    (p_x, mu, u0, v0, k_ud) and X (not divided by the noise sd). Exposed for tests.
  */
  static vpMatrix observationJacobian(const vpKinematicChain &chain, const std::vector<unsigned int> &parameters,
                                      const vpCameraParameters &camera, const vpColVector &q, const vpColVector &X,
                                      vpColVector &uv);
};

#endif
