/*
 * ViSP SelfCalib: private interface of the pipelines behind vpRobotSelfCalibration (not installed).
 * vpRobotSelfCalibration::run checks the inputs, builds a Context and dispatches to one pipeline per
 * method (vpSelfCalibPaperPipeline.cpp, vpSelfCalibBundlePipeline.cpp, vpSelfCalibHandEyePipeline.cpp);
 * the steps they share are in vpSelfCalibPipelineSteps.cpp.
 */
#ifndef VP_SELFCALIB_PIPELINES_H
#define VP_SELFCALIB_PIPELINES_H

#include <chrono>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <visp3/selfcalib/vpRobotSelfCalibration.h>

#include "../core/vpSelfCalibCamera.h"
#include "../core/vpSelfCalibMath.h"

namespace vpSelfCalibPipeline
{
using Result = vpRobotSelfCalibration::Result;
using View = vpSelfCalibDataset::View;

/*!
  What a run works on: its inputs, the focal mode resolved, the views split (the first
  num_calibration for calibration, the rest for verification) and the options of every step, built
  once from the caller's Options by vpRobotSelfCalibration's builders, and the noise model every
  step is given. The pipelines read the steps' options and the noise from here, never from
  options.twoview, .multiview, .bundle, .data_check or .noise. A context owns its options; the
  nominal model, the dataset and the progress callback are the caller's (they outlive the run).
*/
struct Context {
  Context(const vpKinematicChain &nominal, const vpSelfCalibDataset &dataset,
          const vpRobotSelfCalibration::Options &options, unsigned int num_calibration,
          const vpRobotSelfCalibration::Progress &progress, const vpKinematicChain *guess = nullptr,
          bool eMc_from_data = false);
  /*!
    The same run at another noise model (measured levels). robot_round: the robot's error was
    measured, and the covariance is scaled by sigma0 when the residuals say the noise is larger.
  */
  Context(const Context &base, const vpSelfCalibNoiseModel &noise, bool robot_round);

  const vpKinematicChain &nominal;
  const vpSelfCalibDataset &dataset;
  const vpRobotSelfCalibration::Options options;
  const vpRobotSelfCalibration::Progress &progress;
  const unsigned int num_calibration;
  const vpRobotSelfCalibration::FocalMode mode;
  const std::vector<View> calibration, verification;
  const vpTwoViewEstimator::Options twoview;
  const vpMultiViewReconstruction::Options multiview;
  const vpKinematicBundleAdjustment::Options bundle;
  const vpSelfCalibDataCheck::Options data_check;
  const vpSelfCalibNoiseModel noise; //!< the noise of every step (vpRobotSelfCalibration::noiseModel())
  //! The caller's model (nominal, unless the run started from another: startFromData()): the
  //! reference of the assessment's and the verification's "nominal" figures.
  const vpKinematicChain &guess;
  //! The nominal model's eMc is the one the data measure (startFromData()), not the caller's guess.
  const bool eMc_from_data;

  //! Reports progress when the caller gave a callback.
  void report(const std::string &stage, unsigned int done, unsigned int total) const;
};

// The pipelines, one per method: each fills result (status, message, model, statistics).
void runPaper(const Context &context, Result &result);
void runBundle(const Context &context, Result &result);
void runHandEye(const Context &context, Result &result);

// Steps shared by the pipelines.

//! The dataset's camera with its lens model (ViSP's k_ud in cam, or OpenCV's coefficients).
vpSelfCalib::CameraModel lensOf(const vpSelfCalibDataset &dataset);
//! A pinhole camera with OpenCV's coefficients (empty: the camera's own model).
vpSelfCalib::CameraModel lensOf(const vpCameraParameters &cam, const std::vector<double> &opencv_distortion);
//! The views with their pixels through the inverse of the lens distortion (the views themselves without).
std::vector<View> undistorted(const std::vector<View> &views, const vpSelfCalib::CameraModel &lens);

/*!
  The estimated set of every method but HAND_EYE: vpKinematicIdentification::analyseConfigurations()
  on the calibration views' joint configurations at the nominal model, minus the caller's fixed
  parameters (options.identification.fixed and options.bundle.fixed). Depends on no measured value.
*/
vpKinematicIdentification::Identifiability estimatedSet(const Context &context);

//! Wall time since a point (s).
double seconds(const std::chrono::steady_clock::time_point &since);
//! Observations (image points) of views.
unsigned int countObservations(const std::vector<View> &views);
//! A pose measurement c_iMc_ref with its weights: position sd from the length of its translation.
vpKinematicIdentification::Measurement poseMeasurement(const vpColVector &q, const vpColVector &q_ref,
                                                       const vpHomogeneousMatrix &M, double translation_norm,
                                                       const vpRobotSelfCalibration::Options &options);
//! The data check before calibrating: findings into the result; false (DEGENERATE_DATA) when the
//! data cannot determine the calibration.
bool checkData(const Context &context, Result &result);
//! The multi-view reconstruction of the calibration views; false (TWO_VIEW_FAILED) when it fails or
//! places too few views.
bool multiView(const Context &context, Result &result);
//! The multi-view points moved to f by fMc0 (a model's pose of view 0) and scaled by s.
std::map<int, vpColVector> pointsInF(const Result &result, const vpHomogeneousMatrix &fMc0, double s);
//! The bundle adjustment's start camera: the dataset's (its distortion included) with focal length fx0.
vpCameraParameters startCamera(const Context &context, double fx0);
/*!
  The kinematic bundle adjustment from a start model, the multi-view points moved to f by fMc0 (the
  start's pose of view 0) and scaled by s; fills the result. False (IDENTIFICATION_FAILED) when it
  fails or leaves too many observations unused.
*/
bool bundle(const Context &context, const vpKinematicChain &start, const vpHomogeneousMatrix &fMc0, double s,
            const std::vector<View> &views, const vpKinematicBundleAdjustment::Options &bundle_options,
            const std::string &label, Result &result);
//! The same from start points in f and a start focal length.
bool bundleFrom(const Context &context, const vpKinematicChain &start, const std::map<int, vpColVector> &points,
                double fx0, const std::vector<View> &views, const vpKinematicBundleAdjustment::Options &bundle_options,
                const std::string &label, Result &result);

/*!
  A focal length's score for scanFocal(): score(f, bound) is the score at f (px), or any value above
  `bound` once the score is known to be above it (the scan does not choose that f then, whatever
  its score): a score that is a median over pairs can stop when most of them are above it. A score
  that does not bound itself ignores `bound`.
*/
using FocalScore = std::function<double(double f, double bound)>;
/*!
  The focal length (px) that minimises score(f): a ladder of rungs from 0.3x to 4x `center` (steps
  of 2^(1/4); the lowest score, the shortest focal length of equal ones), then a golden-section
  search on log f between the best rung's neighbours; 0 when no rung has a finite score.
  `rung_score`, when given, scores the rungs instead (a cheaper score that ranks the rungs as score
  does: most rungs are far from the optimum).
*/
double scanFocal(const FocalScore &score, double center, const FocalScore &rung_score = {});

//! A start from the camera poses the robot predicts (see predictedStart()).
struct PredictedStart {
  bool ok = false;
  double fx = 0;                         //!< px
  double median_error = 0;               //!< px, median reprojection error of the triangulated points
  std::map<int, vpColVector> points;     //!< in f
};
/*!
  Every point seen twice triangulated from the cameras the robot predicts (fMc: nominal kinematics
  or controller poses with the nominal eMc) through the lens; with the focal length not known, the
  focal length that makes these rays meet best (lowest median reprojection error over a ladder of
  candidates from 0.3x to 4x the lens's, scanFocal()). Needs no two-view geometry:
  it works on planar scenes and from any focal guess. ok false when fewer than 10 observations
  triangulate.
*/
PredictedStart predictedStart(const std::vector<View> &views, const std::vector<vpSelfCalib::Rigid> &fMc,
                              const vpSelfCalib::CameraModel &lens, bool focal_known);

/*!
  result.eMc and result.eMc_sd from the calibrated chain and a covariance of its parameters (rows
  named by covariance_names; eMc components not among them are held, no variance).
*/
void handEyeWithSd(Result &result, const vpMatrix &covariance, const std::vector<std::string> &covariance_names);

/*!
  Every id seen in two or more of the views triangulated from cameras at fMc (one per view, frame f)
  through camera, its lens included: the multi-ray midpoint, refined on its reprojection error
  (Ceres); an id whose rays do not meet in front of every camera is left out. The one triangulation
  of vpCalibrationVerifier and vpSelfCalibCrossValidation.
*/
std::map<int, Eigen::Vector3d> triangulateViews(const std::vector<View> &views, const std::vector<vpSelfCalib::Rigid> &fMc,
                                                const vpSelfCalib::CameraModel &camera);

//! Findings after a run: many outliers, an unused yardstick, parameters a richer trajectory would identify.
void checkResult(const Context &context, Result &result);
//! Step 5: the yardstick 3-D error on the verification views, nominal and calibrated (2 views or more).
void verify(const Context &context, Result &result);
//! True when a measured image noise (px, 0.01 or more) differs from the stated one by more than 25 %.
bool measuredNoiseDiffers(double stated, double measured);

//! A run made at a noise model: whether it is ok (else the status's name), and what its residuals measure.
struct NoiseAttempt {
  bool ok = false;
  std::string failure;
  vpSelfCalibNoiseModel measured;
};
//! Runs the method (or step) at a noise model; robot_round: the robot's error is the measured one.
//! An ok run stands (the caller keeps it); a failed one is discarded.
using NoiseAttemptFunction = std::function<NoiseAttempt(const vpSelfCalibNoiseModel &noise, bool robot_round)>;
/*!
  The measure-and-run-again step of every method. After a first run at `start` whose residuals
  measure `measured` (ok: it stands and is OK; usable: its residuals can be trusted for the image
  noise, an OK run or one that failed on rejected observations):
  - start.pixel_sd to be measured (measure_pixel_sd): one more run at the measured image noise when it
    differs by more than 25 % (measuredNoiseDiffers());
  - robot_rounds and the controller poses' error measured (pose_sd_*, measure_pose_sd): from a run
    that stands, rounds at the measured levels (and image noise) until every part settles within
    10 %, 5 at most, no part below the floor (2e-5 m and rad, a serial arm's repeatability); measured
    below twice the floor in every part it is dropped (exact); a warning "robot-error-not-settled" in
    findings when it does not settle, cannot be measured, or a round is not ok (the last ok run
    stands). The full kinematics' joint readings and model residual are measured inside the bundle
    adjustment (vpKinematicBundleAdjustment::Result::noise, the same rules), not by runs again.
  Returns the noise model of the run that stands.
*/
vpSelfCalibNoiseModel measureNoise(const vpSelfCalibNoiseModel &start, const vpSelfCalibNoiseModel &measured,
                                   bool ok, bool usable, bool robot_rounds, const NoiseAttemptFunction &attempt,
                                   std::vector<vpSelfCalibDataCheck::Finding> &findings);
/*!
  The 99.9 % bound of the robot corrections' chi-square (bundle.robot_chi2) for their number, and
  whether the corrections stay within it (true without robot error modelled).
*/
double robotChi2Bound(const vpKinematicBundleAdjustment::Result &bundle);
bool robotCorrectionsWithinStated(const vpKinematicBundleAdjustment::Result &bundle);
/*!
  True when the robot corrections exceed that bound and one part of them (translations, rotations,
  joints) averages 3 times its stated sd or more: they stand in for what the model does not explain.
*/
bool robotCorrectionsStandIn(const vpKinematicBundleAdjustment::Result &bundle);
/*!
  The checks of an OK run's own word (vpSelfCalibAssessment.cpp): corrections and sds against the
  nominal model's tolerance, the calibration views and the held-out views explained better than by
  the nominal model, the yardstick reproduced on the held-out views, the measured image noise.
  Findings of severity DOUBT make the status DOUBTFUL; a noise mismatch is a warning.
*/
void assess(const Context &context, Result &result);
/*!
  The hand-eye method on joint readings (`joints`: some view has joints and no controller pose): the
  warning hand-eye-kinematics-nominal (the kinematics' error goes into eMc, or bMc and the target's
  pose with the camera in the world). assess() adds it; the camera in the world, whose pipeline sees
  the poses computed from the joints, adds it from the caller's dataset.
*/
void handEyeOnJoints(bool world, Result &result);
/*!
  Eye-to-hand (vpSelfCalibEyeToHand.cpp): the dataset with every view's controller pose bMe (or the
  nominal model's at its joints) replaced by its inverse, so that the hand-eye method's eye-in-hand
  problem is the eye-to-hand one (eMc -> bMc, scene points -> the target in the effector frame).
*/
vpSelfCalibDataset eyeToHandAsEyeInHand(const vpKinematicChain &nominal, const vpSelfCalibDataset &ds);
/*!
  eMc and the target's pose fMo from its known points (layout, its frame o) in views whose fMe is
  set (has_fMe; pixels of a pinhole camera `cam`): each view's target pose by PnP, then OpenCV's
  closed forms (Tsai, Park, Horaud, Andreff, Daniilidis); with each, fMo from every view; the pair
  that reprojects the known points with the lowest median error (median_px) over every view is kept
  (on small motions of a small target the closed forms disagree by metres, and which one is right
  differs between data sets). num_posed: the views PnP posed. False with fewer than 3 posed.
*/
bool handEyeFromKnownPoints(const std::vector<View> &views, const std::map<int, vpColVector> &layout,
                            const vpCameraParameters &cam, vpSelfCalib::Rigid &eMc, vpSelfCalib::Rigid &fMo,
                            double &median_px, unsigned int &num_posed);
/*!
  A start bMc and eMo from the target's known points (layout, its frame o) in the first num_views
  views of an inverted dataset: per-view PnP and OpenCV's hand-eye closed forms, the pair with the
  lowest median reprojection error (median_px) kept. False with fewer than 3 views posed.
*/
bool eyeToHandStart(const vpSelfCalibDataset &inverted, unsigned int num_views, const std::map<int, vpColVector> &layout,
                    vpHomogeneousMatrix &bMc, vpHomogeneousMatrix &eMo, double &median_px);
//! The result in eye-to-hand terms: eMc -> bMc, the known object's pose -> eMo (has_eMc false).
void eyeToHandResult(Result &result);
//! Eye-to-hand without the target's layout: the finding target-layout-unknown (with a board: --board-geometry),
//! said in the message of a run that is not ok.
void eyeToHandWithoutLayout(Result &res);
/*!
  The dataset's views for their joints where they have them (their controller poses dropped), so
  that eyeToHandAsEyeInHand() inverts the model's end-effector poses: the full kinematics method's.
*/
vpSelfCalibDataset eyeToHandJointsOnly(const vpSelfCalibDataset &ds, unsigned int num_joints);
/*!
  Eye-to-hand with joints (Options::eye_to_hand of the bundle adjustment): every view as a controller
  pose view, fMe = model.fMe(q)^-1 (q cleared), so that the model's hand-eye slot (bMc) gives the
  camera pose in the effector frame where an eye-in-hand check expects fMc (vpCalibrationVerifier).
*/
std::vector<View> eyeToHandViews(const vpKinematicChain &model, const std::vector<View> &views);
/*!
  The full kinematics method with the camera in the world (the context's bundle options
  eye_to_hand, its nominal model's hand-eye slot the start bMc): the target's start pose eMo from
  the same start as run(), its known points placed in e through it, then the kinematic bundle
  adjustment of the chain, bMc, eMo and the intrinsics.
*/
void runBundleEyeToHand(const Context &context, Result &result);

//! A start for eMc and the focal length measured from the data (vpSelfCalibMeasuredStart.cpp).
struct MeasuredStart {
  bool has_eMc = false;  //!< eMc measured
  bool has_fx = false;   //!< the focal length measured (not when it is known)
  double fx = 0;         //!< px
  vpSelfCalib::Rigid eMc;
  std::string how;       //!< what measured them, or why they could not be
};
/*!
  eMc and, when focal_known is false, the focal length measured from views whose fMe is set (has_fMe;
  their pixels a pinhole camera's at lens's principal point and aspect ratio, whatever lens's focal
  length): with a target of 4 known points or more (layout), handEyeFromKnownPoints(), its focal
  length the one whose median reprojection error through the robot is lowest (scanFocal() around the
  image width); else the two-view motions of the pairs (view r, view k) sharing 15 points or more, r
  the view with the most such pairs (OpenCV's five-point RANSAC, threshold_px), the focal length the one at which their rotation angles
  agree best with the end-effector's (median), eMc's rotation by OpenCV's closed forms and its
  translation with the pairs' scales by linear least squares. Depends on neither the model's eMc nor
  lens's focal length. has_eMc false (how says why) when too few views are posed. Throws
  vpSelfCalibException when a view has no fMe.
*/
MeasuredStart measuredStart(const std::vector<View> &views, const vpSelfCalib::CameraModel &lens, unsigned int width,
                            const std::map<int, vpColVector> &layout, bool focal_known, double threshold_px);

//! What a run starts from (startFromData()).
struct DataStart {
  vpKinematicChain model;                             //!< the nominal model, eMc measured when it could be
  vpSelfCalibDataset dataset;                         //!< the dataset, its focal length measured when self-calibrated
  std::vector<vpSelfCalibDataCheck::Finding> findings; //!< eMc not measured
  std::string message;                                //!< how eMc and f were started
  bool eMc_from_data = false;                         //!< model's eMc is the measured one
};
/*!
  The start of the bundle and hand-eye methods (the paper's: the inputs unchanged): measuredStart()
  on the first N views (end-effector poses: the controller's with HAND_EYE, else the nominal
  kinematics at the joints); the model's eMc replaced by the measured one (its eMc correction
  zeroed); when eMc cannot be measured, the guess, and the warning "emc-start-guess". A self-calibrated focal
  length measured with it, else where the rays of the model's camera poses meet best
  (predictedStart()). Eye-to-hand (bundle.controller_poses_inverted or bundle.eye_to_hand: run()
  started bMc): the focal length only, from the rays.
*/
DataStart startFromData(const vpKinematicChain &nominal, const vpSelfCalibDataset &data, unsigned int N,
                        const vpRobotSelfCalibration::Options &opt);

//! The model with eMc set to `eMc` and no eMc correction (eye-to-hand: the target's pose in the hand-eye slot).
vpKinematicChain withNominalEMc(const vpKinematicChain &model, const vpPoseVector &eMc);

/*!
  The calibrated model of a run started from the data's eMc expressed against the caller's model:
  its eMc the guess's, its eMc correction D such that guess D = the calibrated eMc (the corrections
  read against the caller's model, as without the start); the translation's sd turned with it, the
  rotation's left as estimated (the same when the guess's rotation is the start's).
*/
void expressInGuess(const vpKinematicChain &guess, Result &res);
//! A warning "emc-guess-far" when the calibrated eMc is beyond the caller's hand-eye tolerance of its guess.
void findGuessFar(const vpKinematicChain &guess, const vpRobotSelfCalibration::Options &opt, Result &res);
} // namespace vpSelfCalibPipeline

#endif
