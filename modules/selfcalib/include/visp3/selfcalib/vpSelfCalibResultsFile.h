/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpSelfCalibResultsFile.h
  \brief results.yaml, the machine-readable record of a calibrate run: its writer and its reader.
*/
#ifndef VP_SELFCALIB_RESULTS_FILE_H
#define VP_SELFCALIB_RESULTS_FILE_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibProtocol.h>

/*!
  \class vpSelfCalibResultsFile
  \ingroup group_selfcalib_io
  \brief results.yaml, the machine-readable record of a calibrate run: what the run found, without
  wall times (the same dataset gives the same file, byte for byte). Its writer and its reader.

  The schema (version kSchemaVersion; lengths in m, angles in rad, image quantities in px; numbers
  written with 17 significant digits, so that they read back exactly). Keys in this order, those
  marked (opt.) only when they apply:
  - `schema_version`: the integer kSchemaVersion; the reader refuses a file without it or with
    another version.
  - `dataset`: the dataset file as given; `method`, `status` (vpRobotSelfCalibration's names);
    `message` (the run's message, double-quoted).
  - `findings`: a list of `{code, severity, message}` (vpSelfCalibDataCheck's severity names).
  - `camera`: `{px, py, u0, v0, px_sd, distortion}`: `distortion` (opt.) OpenCV's k1 k2 p1 p2 k3.
  - `intrinsics_estimated` (opt., bundle adjustment with a covariance): per intrinsic, `[value, sd]`.
  - `eMc` (opt.): `{pose: [tx, ty, tz, tux, tuy, tuz], sd: [6 values]}`.
  - `bMc`, `eMo` (opt., camera_mount world): the camera in the robot's base frame and the target in
    the end-effector frame, in the form of `eMc`.
  - `bundle_adjustment` (opt., methods bundle and hand-eye): `{observations, dropped, rms_px,
    sigma0, scale_from}`, `scale_sd` (no yardstick: the relative sd of the nominal scale held, counted in every sd), then with robot pose corrections `robot_pose_rms_m`, `robot_pose_rms_rad`,
    `robot_pose_sd: [T, R]` and, when measured, `robot_pose_sd_measured: [T, R]` (hand-eye: the
    controller poses' error; bundle: the kinematic model's residual); with joint corrections
    `joint_correction_rms_rad`, `joint_sd: [rad...]` (used) and, when measured, `joint_sd_measured`;
    with a robot error modelled `robot_error: measured` (the rounds measured the level used) or
    `stated`; with re-posed views `reposed_rms_px`, `repose_f`,
    `repose_f_limit`; `sd_scaled_by_sigma0: true` when the covariance was scaled.
  - `noise` (opt., not the paper's method): `{pixel_sd, measured}`; `fit` (same): `{nominal,
    calibrated}`, the reprojection RMS of the calibration views.
  - `estimated`: per estimated parameter (chain order), `[value, sd]`; `not_estimated`: per other
    parameter, the reason.
  - `estimated_set` (opt.): `{rule, count, order: [names], new_direction: {name: value},
    fixed_by_user: [names], left_by_data: {name: {reason, needs}}}`, the new-direction figures
    written with 3 significant digits; fixed_by_user and left_by_data are written when not empty
    (the parameters the user fixed, and those the data do not determine, kept at nominal with the
    reason and what would determine them); with the bundle adjustment's kinematic prior (its
    default; absent when it is off) `kinematic_prior: K` (the prior's sd: the tolerance / K) and, when not empty,
    `held_by_prior: {name: {reason, needs}}` (estimated, but determined by the prior, not the data).
  - `verification` (opt., a split with held-out views): `yardstick_error_nominal`,
    `yardstick_error_calibrated`, `reprojection_rms_nominal`, `reprojection_rms_calibrated`.
  - `protocol`: `{calibration_views, held_out_views, folds}`.
  - `cross_validation` (opt.): `folds`, `views`, `measured`, `failed`, `rms_px` and `median_px`
    (each `calibrated` and `nominal`: `{mean, sd, min, max}`), `per_fold`: a list of `{held_out:
    [indices], status, fx, rms_calibrated, median_calibrated (when the fold's status is ok) or
    message (otherwise), rms_nominal, median_nominal, observations, yardstick_error_calibrated,
    yardstick_error_nominal (when the fold verified the yardstick)}`.
  - `heldout_dataset` (opt.): `{file, views, rms_px: {calibrated, nominal}, median_px: {calibrated,
    nominal}, observations, yardstick_error_nominal, yardstick_error_calibrated (with a yardstick)}`.

  Contents holds every value of the file; fromRun() fills it from a run, toYaml() writes it,
  fromYaml() and read() give it back: fromYaml(toYaml(c)) writes the same text again.
*/
class VISP_SELFCALIB_EXPORT vpSelfCalibResultsFile
{
public:
  //! The version of the schema above, written as `schema_version`.
  static constexpr int kSchemaVersion = 1;

  //! A value and its standard deviation.
  struct Estimate {
    std::string name;
    double value = 0, sd = 0;
  };
  //! One finding: its severity, a stable code, and a message that says what is wrong and what to do.
  struct Finding {
    std::string code, severity, message;
  };
  //! The `camera` block of results.yaml.
  struct Camera {
    double px = 0, py = 0, u0 = 0, v0 = 0, px_sd = 0;
    std::vector<double> distortion; //!< OpenCV's k1 k2 p1 p2 k3; empty: not written
  };
  //! The `eMc` block of results.yaml: the pose vector and its sd.
  struct HandEye {
    std::vector<double> pose, sd; //!< 6 values each
  };
  //! The `bundle_adjustment` block of results.yaml.
  struct BundleAdjustment {
    unsigned int observations = 0, dropped = 0;
    double rms_px = 0, sigma0 = 0;
    std::string scale_from;
    //! Without a yardstick: the relative sd of the nominal scale held, counted in the sd (`scale_sd`; 0: absent).
    double scale_sd = 0;
    bool has_robot_pose = false; //!< robot pose corrections: the four values below
    double robot_pose_rms_m = 0, robot_pose_rms_rad = 0;
    double robot_pose_sd_m = 0, robot_pose_sd_rad = 0;
    bool has_robot_pose_sd_measured = false;
    double robot_pose_sd_measured_m = 0, robot_pose_sd_measured_rad = 0;
    bool has_joint_corrections = false;
    double joint_correction_rms_rad = 0;
    std::vector<double> joint_sd, joint_sd_measured; //!< rad, with joint corrections: used, measured (empty: not)
    std::string robot_error; //!< "measured" or "stated" (the origin of the robot error used); empty: none modelled
    bool has_repose = false;
    double reposed_rms_px = 0, repose_f = 0, repose_f_limit = 0;
    bool sd_scaled_by_sigma0 = false;
  };
  //! The `noise` and `fit` blocks of results.yaml.
  struct NoiseAndFit {
    double image_noise_px = 0, image_noise_measured_px = 0; //!< the noise model's pixel_sd used, and measured
    double fit_nominal = 0, fit_calibrated = 0;
  };
  /*!
    The `workspace` and `workspace_full_range` blocks of results.yaml (m, rad): the calibrated model's predicted RMS error on the
    relative camera motions between configurations over the joint limits and its 90 % bound, the
    nominal model's there as its misfit on the calibration views measures it, and the chance that
    the calibrated model is the worse (vpRobotSelfCalibration::WorkspaceError).
  */
  struct Workspace {
    double calibrated_t = 0, calibrated_r = 0, bound_t = 0, bound_r = 0, nominal_t = 0, nominal_r = 0;
    double worse_t = 0, worse_r = 0;
    bool scale_left_out = false; //!< the nominal scale's error (no yardstick), common to both, left out
    //! The joints that barely move in the views, drawn within their range there: name, low, high (rad).
    std::vector<std::pair<std::string, std::pair<double, double>>> joints_within;
  };
  //! The `estimated_set` block of results.yaml.
  struct EstimatedSet {
    std::string rule;
    unsigned int count = 0;
    std::vector<std::string> order;
    std::vector<std::pair<std::string, double>> new_direction; //!< written with 3 significant digits
    std::vector<std::string> fixed_by_user;                    //!< fixed by the caller (--fix, the dataset's fix:)
    //! Left at nominal because the data do not determine them: name, reason, what would determine it.
    struct LeftByData {
      std::string name, reason, needs;
    };
    std::vector<LeftByData> left_by_data;
    //! The bundle adjustment's kinematic prior, K (the prior's sd: the tolerance / K); 0: none.
    double kinematic_prior = 0;
    //! With the prior: the parameters the data alone do not determine, estimated and held near nominal by the prior.
    std::vector<LeftByData> held_by_prior;
  };
  //! The `verification` block of results.yaml.
  struct Verification {
    double yardstick_error_nominal = 0, yardstick_error_calibrated = 0;
    double reprojection_rms_nominal = 0, reprojection_rms_calibrated = 0;
  };
  //! Mean, sd, min and max of a figure over the folds.
  struct Spread {
    double mean = 0, sd = 0, min = 0, max = 0;
  };
  //! One entry of `cross_validation.per_fold` in results.yaml.
  struct Fold {
    std::vector<unsigned int> held_out;
    std::string status;
    bool calibrated = false; //!< fx and the calibrated figures are written (status ok), else message
    double fx = 0, rms_calibrated = 0, median_calibrated = 0;
    std::string message;
    double rms_nominal = 0, median_nominal = 0;
    unsigned int observations = 0;
    bool verified = false; //!< the yardstick errors are written
    double yardstick_error_calibrated = 0, yardstick_error_nominal = 0;
  };
  //! The `cross_validation` block of results.yaml.
  struct CrossValidation {
    unsigned int folds = 0, views = 0, measured = 0, failed = 0;
    Spread rms_calibrated, rms_nominal, median_calibrated, median_nominal;
    std::vector<Fold> per_fold;
  };
  //! The `heldout_dataset` block of results.yaml.
  struct HeldOutDataset {
    std::string file;
    unsigned int views = 0;
    double rms_calibrated = 0, rms_nominal = 0, median_calibrated = 0, median_nominal = 0;
    unsigned int observations = 0;
    bool has_yardstick = false;
    double yardstick_error_nominal = 0, yardstick_error_calibrated = 0;
  };
  //! Every value of a results.yaml; the optional blocks are those of the schema.
  struct Contents {
    int schema_version = kSchemaVersion;
    std::string dataset, method, status, message;
    std::vector<Finding> findings;
    Camera camera;
    std::vector<Estimate> intrinsics_estimated; //!< empty: not written
    std::optional<HandEye> eMc;
    std::optional<HandEye> bMc, eMo; //!< eye-to-hand: the camera in the base frame, the target in the effector frame
    std::optional<BundleAdjustment> bundle_adjustment;
    std::optional<NoiseAndFit> noise;
    std::optional<Workspace> workspace;
    std::optional<Workspace> workspace_full_range; //!< with joints_within: every joint over its limits
    std::vector<Estimate> estimated;
    std::vector<std::pair<std::string, std::string>> not_estimated; //!< name, reason
    std::optional<EstimatedSet> estimated_set;
    std::optional<Verification> verification;
    unsigned int calibration_views = 0, held_out_views = 0, folds = 0;
    std::optional<CrossValidation> cross_validation;
    std::optional<HeldOutDataset> heldout_dataset;
  };

  /*!
    The contents of a run's results.yaml: the calibration `result` (the protocol's, with its
    verdicts) of the `nominal` model on the dataset file `dataset`, and the protocol's split,
    cross-validation and held-out dataset.
  */
  static Contents fromRun(const vpRobotSelfCalibration::Result &result, const vpKinematicChain &nominal,
                          const std::string &dataset, const vpSelfCalibProtocol::Result &protocol);
  //! The text of results.yaml (ending with a newline).
  static std::string toYaml(const Contents &contents);
  //! Writes results.yaml atomically (vpSelfCalibFileWriter); throws vpSelfCalibException when it cannot.
  static void write(const std::string &filename, const Contents &contents);
  /*!
    Reads the text of a results.yaml back; `source` names it in the messages. Throws
    vpSelfCalibException (parseError) on a malformed file, a missing key or a schema_version other
    than kSchemaVersion.
  */
  static Contents fromYaml(const std::string &text, const std::string &source = "<text>");
  //! Reads a results.yaml file (fromYaml()); throws vpSelfCalibException when it cannot be read.
  static Contents read(const std::string &filename);
};

#endif
