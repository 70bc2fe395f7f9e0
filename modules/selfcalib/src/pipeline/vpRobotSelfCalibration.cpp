/*
 * ViSP SelfCalib: vpRobotSelfCalibration, the entry point: checks the inputs, builds the options of
 * every step from the caller's Options and dispatches to the method's pipeline
 * (vpSelfCalibPaperPipeline.cpp, vpSelfCalibBundlePipeline.cpp, vpSelfCalibHandEyePipeline.cpp).
 */
#include <visp3/selfcalib/vpRobotSelfCalibration.h>

#include <visp3/selfcalib/vpSelfCalibException.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <iomanip>
#include <optional>
#include <sstream>

#include "../core/vpSelfCalibRange.h"
#include "../core/vpSelfCalibRobotErrorLevels.h"
#include "vpSelfCalibPipelines.h"
#include "vpSelfCalibRobotErrorStructure.h"

namespace
{
/*
  The options' noise model with, where it leaves the robot's error at 0, the dataset's robot_error
  in the method's form: controller poses (hand-eye) or joint readings (full kinematics).
*/
vpSelfCalibNoiseModel withDatasetRobotError(const vpRobotSelfCalibration::Options &opt, const vpSelfCalibDataset &ds)
{
  vpSelfCalibNoiseModel noise = opt.noise;
  if (opt.method == vpRobotSelfCalibration::HAND_EYE && !noise.hasPoseError() && ds.pose_sd_translation > 0) {
    noise.pose_sd_translation = ds.pose_sd_translation;
    noise.pose_sd_rotation = ds.pose_sd_rotation;
  }
  if (opt.method == vpRobotSelfCalibration::BUNDLE_ADJUSTMENT && noise.joint_sd.empty() && !ds.joint_sd.empty())
    noise.joint_sd = ds.joint_sd;
  // Nothing states the robot's error: a real arm has one, so it is modelled from the prior and
  // measured (hand-eye: the controller poses; bundle: the joint readings and the model's residual,
  // measured inside its bundle adjustment). trust_robot takes the robot as exact.
  if ((opt.method == vpRobotSelfCalibration::HAND_EYE || opt.method == vpRobotSelfCalibration::BUNDLE_ADJUSTMENT) &&
      !noise.hasRobotError() && !opt.trust_robot)
    noise = vpRobotSelfCalibration::robotErrorPrior(noise, opt.method);
  return noise;
}
} // namespace

const char *vpRobotSelfCalibration::statusName(Status s)
{
  switch (s) {
  case OK:
    return "ok";
  case TWO_VIEW_FAILED:
    return "two-view pose measurement failed";
  case SCALE_FAILED:
    return "scale failed";
  case IDENTIFICATION_FAILED:
    return "identification failed";
  case DEGENERATE_DATA:
    return "degenerate data";
  case DOUBTFUL:
    return "doubtful";
  }
  return "unknown";
}

const char *vpRobotSelfCalibration::methodName(Method m)
{
  return m == PAPER ? "paper" : (m == HAND_EYE ? "hand-eye" : "bundle");
}

vpRobotSelfCalibration::Method vpRobotSelfCalibration::methodFromName(const std::string &name)
{
  if (name == "bundle")
    return BUNDLE_ADJUSTMENT;
  if (name == "paper")
    return PAPER;
  if (name == "hand-eye")
    return HAND_EYE;
  throw vpSelfCalibException(vpSelfCalibException::badValue, "method '" + name + "': use bundle, paper or hand-eye");
}

void vpRobotSelfCalibration::Options::check() const
{
  noise.check("vpRobotSelfCalibration");
  if (method == BUNDLE_ADJUSTMENT && noise.hasPoseError())
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpRobotSelfCalibration: noise.pose_sd_* is the controller poses' error (HAND_EYE); "
                               "the bundle method's per-view camera correction is noise.model_sd_*");
  if (method == HAND_EYE && (noise.hasModelError() || !noise.joint_sd.empty()))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpRobotSelfCalibration: noise.model_sd_* and noise.joint_sd are the full kinematic "
                               "model's (BUNDLE_ADJUSTMENT); HAND_EYE takes the controller poses' error, noise.pose_sd_*");
  if (method == PAPER && noise.hasRobotError())
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpRobotSelfCalibration: PAPER does not model the robot's error (noise.pose_sd_*, "
                               "model_sd_*, joint_sd): use BUNDLE_ADJUSTMENT or HAND_EYE");
  if (num_calibration_poses < 3)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpRobotSelfCalibration: num_calibration_poses must be at least 3");
  if (!(twoview_rotation_sd > 0 && twoview_direction_sd > 0))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpRobotSelfCalibration: twoview_rotation_sd and twoview_direction_sd must be positive");
  if (!(outlier_warning > 0 && outlier_warning <= 1 && min_posed_fraction >= 0 && min_posed_fraction <= 1 &&
        max_outlier_fraction > 0 && max_outlier_fraction <= 1))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpRobotSelfCalibration: outlier_warning, min_posed_fraction and max_outlier_fraction "
                               "must be fractions in (0, 1]");
  const double tolerances[] = {tolerance_translation, tolerance_rotation, tolerance_hand_eye_translation,
                               tolerance_hand_eye_rotation, max_pixel_noise};
  for (double t : tolerances)
    if (!(t > 0) || !std::isfinite(t))
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpRobotSelfCalibration: the tolerances and max_pixel_noise must be positive and finite");
  identification.check();
  bundle.check();
  data_check.check();
}

vpRobotSelfCalibration::FocalMode vpRobotSelfCalibration::resolveFocalMode(const Options &opt,
                                                                           const vpSelfCalibDataset &ds)
{
  FocalMode mode = opt.focal_mode;
  if (mode == FOCAL_AUTO)
    mode = ds.focal_known ? FOCAL_KNOWN : FOCAL_SHARED;
  if (mode == FOCAL_KNOWN && !(ds.cam.get_px() > 0))
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpRobotSelfCalibration: FOCAL_KNOWN without px");
  return mode;
}

vpTwoViewEstimator::Options vpRobotSelfCalibration::twoViewOptions(const Options &opt, const vpSelfCalibDataset &ds)
{
  const bool known = resolveFocalMode(opt, ds) == FOCAL_KNOWN;
  vpTwoViewEstimator::Options to;
  static_cast<vpTwoViewEstimator::Settings &>(to) = opt.twoview;
  to.fx = ds.cam.get_px();
  to.u0 = ds.cam.get_u0();
  to.v0 = ds.cam.get_v0();
  to.mu = ds.cam.get_py() / ds.cam.get_px();
  to.focal_mode = known ? vpRefinedFactorMethod::KNOWN : vpRefinedFactorMethod::PER_PAIR;
  return to;
}

vpMultiViewReconstruction::Options vpRobotSelfCalibration::multiViewOptions(const Options &opt,
                                                                             const vpSelfCalibDataset &ds)
{
  vpMultiViewReconstruction::Options mo;
  static_cast<vpMultiViewReconstruction::Settings &>(mo) = opt.multiview;
  mo.twoview = twoViewOptions(opt, ds);
  mo.focal_known = resolveFocalMode(opt, ds) == FOCAL_KNOWN;
  return mo;
}

vpKinematicBundleAdjustment::Options vpRobotSelfCalibration::bundleOptions(const Options &opt,
                                                                            const vpSelfCalibDataset &ds)
{
  const unsigned int FX = vpKinematicBundleAdjustment::FX;
  vpKinematicBundleAdjustment::Options bo;
  static_cast<vpKinematicBundleAdjustment::Settings &>(bo) = opt.bundle;
  if (resolveFocalMode(opt, ds) != FOCAL_KNOWN)
    bo.intrinsics |= FX;
  else
    bo.intrinsics &= ~FX;
  bo.hand_eye_only = opt.method == HAND_EYE;
  // The nominal model's tolerance the estimated set and the kinematic prior are decided with: the run's.
  bo.tolerance_translation = opt.tolerance_translation;
  bo.tolerance_rotation = opt.tolerance_rotation;
  bo.tolerance_hand_eye_translation = opt.tolerance_hand_eye_translation;
  bo.tolerance_hand_eye_rotation = opt.tolerance_hand_eye_rotation;
  // The dataset's estimated-set settings: its fix / free lists added to the caller's, its kinematic
  // prior (off included) when the caller says nothing; neither: left empty, the bundle adjustment's
  // default (vpKinematicBundleAdjustment::DEFAULT_KINEMATIC_PRIOR).
  for (const std::string &f : ds.fix)
    if (std::find(bo.fixed.begin(), bo.fixed.end(), f) == bo.fixed.end())
      bo.fixed.push_back(f);
  for (const std::string &f : ds.free)
    if (std::find(bo.free.begin(), bo.free.end(), f) == bo.free.end())
      bo.free.push_back(f);
  if (!bo.kinematic_prior && !bo.hand_eye_only)
    bo.kinematic_prior = ds.kinematic_prior;
  // The standard deviations follow the residuals when they contradict the stated noise (either way).
  bo.scale_covariance_chi2 = true;
  // The robot's error as the dataset states it (noiseModel()), with the sd widened by sigma0 when
  // the residuals say the noise is larger.
  const vpSelfCalibNoiseModel noise = withDatasetRobotError(opt, ds);
  if (noise.hasPoseError() != opt.noise.hasPoseError() || noise.joint_sd != opt.noise.joint_sd ||
      noise.hasModelError() != opt.noise.hasModelError())
    bo.scale_covariance = true;
  // The dataset's OpenCV lens model: the model of the estimate, its coefficients the start (unless
  // the caller gives other start coefficients).
  if (!ds.opencv_distortion.empty()) {
    bo.distortion_model = vpKinematicBundleAdjustment::DISTORTION_OPENCV;
    if (bo.opencv_distortion.empty())
      bo.opencv_distortion = ds.opencv_distortion;
  }
  return bo;
}

vpSelfCalibNoiseModel vpRobotSelfCalibration::robotErrorPrior(const vpSelfCalibNoiseModel &noise, Method method)
{
  const vpSelfCalibNoiseModel::Origin stated = vpSelfCalibNoiseModel::STATED;
  vpSelfCalibNoiseModel prior;
  if (method == BUNDLE_ADJUSTMENT) {
    prior = noise.withJointError({kJointErrorPrior}, stated).withModelError(kModelErrorPrior, kModelErrorPrior, stated);
    prior.measure_joint_sd = prior.measure_model_sd = true;
    return prior;
  }
  if (method != HAND_EYE)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpRobotSelfCalibration::robotErrorPrior: PAPER models no robot error");
  prior = noise.withPoseError(1e-3, 1e-3, stated);
  prior.measure_pose_sd = true;
  return prior;
}

vpSelfCalibDataCheck::Options vpRobotSelfCalibration::dataCheckOptions(const Options &opt) { return opt.data_check; }

vpSelfCalibNoiseModel vpRobotSelfCalibration::noiseModel(const Options &opt, const vpSelfCalibDataset &ds)
{
  opt.check();
  return withDatasetRobotError(opt, ds);
}

namespace
{
// The method's pipeline; the noise it used and the one its residuals measure.
void runMethod(const vpSelfCalibPipeline::Context &c, vpRobotSelfCalibration::Result &res)
{
  if (c.options.method == vpRobotSelfCalibration::BUNDLE_ADJUSTMENT)
    vpSelfCalibPipeline::runBundle(c, res);
  else if (c.options.method == vpRobotSelfCalibration::HAND_EYE)
    vpSelfCalibPipeline::runHandEye(c, res);
  else
    vpSelfCalibPipeline::runPaper(c, res);
  if (c.options.method != vpRobotSelfCalibration::PAPER) {
    // The bundle method's joint and model levels as its adjustment measured them.
    const bool adjusted = res.bundle.status == vpKinematicBundleAdjustment::OK;
    res.noise = adjusted ? res.bundle.noise : c.noise;
    res.measured = res.bundle.measured;
    if (adjusted && !res.bundle.robot_error_unsettled.empty())
      res.findings.push_back({vpSelfCalibDataCheck::WARNING, "robot-error-not-settled", res.bundle.robot_error_unsettled});
  } else {
    // The paper's pixel residuals are those of its focal length from every view (f shared), if any;
    // the pipeline says the noise it used there.
    if (!(res.noise.pixel_sd > 0))
      res.noise = c.noise;
    res.measured = vpSelfCalibNoiseModel::unmeasured();
    if (res.multiview.status == vpMultiViewReconstruction::OK)
      res.measured.pixel_sd = res.multiview.measured.pixel_sd;
  }
}

//! Why a run's robot error is dropped for the trusted run's (robotErrorDropped()), or kept.
enum Dropped { KEPT, TAKEN_EXACT, NOT_MEASURED };

/*
  The bundle method's robot error, measured from a guessed level (the prior's, or the dataset's with
  --joint-sd auto: robotLevelGuessed()), is dropped: run() makes the trusted run instead.
  TAKEN_EXACT: measured beyond a real arm's (robotErrorImplausible(): a model residual beyond a
  calibrated model's, or a joint level beyond a well-built arm's whose corrections are no reading
  noise): a misfit or views that do not separate the corrections from the rest. NOT_MEASURED: the
  corrections at the guessed level leave the estimate undetermined (the adjustment measured nothing:
  robotErrorNotMeasured()). What the joint corrections look like is judged once for res's
  adjustment, into res.joint_error_structure.
*/
Dropped robotErrorDropped(const vpSelfCalibPipeline::Context &c, vpRobotSelfCalibration::Result &res)
{
  if (c.options.method != vpRobotSelfCalibration::BUNDLE_ADJUSTMENT || c.options.trust_robot ||
      !vpSelfCalib::robotLevelGuessed(c.noise))
    return KEPT;
  if (res.bundle.status == vpKinematicBundleAdjustment::OK && vpSelfCalib::robotErrorNotMeasured(res.bundle.noise))
    return NOT_MEASURED;
  return vpSelfCalibPipeline::robotErrorImplausible(res.noise, res.bundle, c.calibration, &res.joint_error_structure)
             ? TAKEN_EXACT
             : KEPT;
}

//! The options of the trusted run (calibrate --joint-sd 0): the joint readings and the model exact.
vpRobotSelfCalibration::Options trustedOptions(const vpRobotSelfCalibration::Options &opt)
{
  vpRobotSelfCalibration::Options o = opt;
  o.trust_robot = true;
  o.noise = o.noise.withJointError({}, vpSelfCalibNoiseModel::STATED).withModelError(0, 0, vpSelfCalibNoiseModel::STATED);
  o.noise.measure_joint_sd = o.noise.measure_model_sd = false;
  return o;
}

//! Why the result is the trusted run's: the levels the measured run found (measured) and the joints' structure.
vpSelfCalibDataCheck::Finding takenExactFinding(const vpSelfCalibNoiseModel &measured,
                                                const vpSelfCalibPipeline::JointErrorStructure &structure)
{
  using namespace vpSelfCalib;
  std::ostringstream level;
  const double joints = levelsOf(measured, JOINT_ERROR).r;
  level << std::setprecision(3) << "joint readings " << 1e3 * joints << " mrad";
  if (measured.hasModelError())
    level << ", model residual " << 1e3 * measured.model_sd_translation << " mm / " << 1e3 * measured.model_sd_rotation
          << " mrad";
  std::string why;
  if (structure.judged && joints > kJointErrorPlausible && joints <= kJointErrorImpossible)
    why = "; the joint corrections show " + structure.describe();
  return vpSelfCalibDataCheck::Finding{vpSelfCalibDataCheck::WARNING, "robot-error-taken-exact",
          "the robot's error measured from the corrections is beyond a real arm's (" + level.str() + why +
              "): no reading noise, but a misfit the model cannot explain (a "
              "parameter held at a wrong value, a wrong robot model or eMc guess, joints paired with another view's "
              "images, a camera that moves on the flange) or views that do not separate the corrections from the rest. "
              "The result is the trusted run's, "
              "the readings and the model taken as exact (as calibrate --joint-sd 0), and the checks below judge the "
              "fit; if the readings really are that noisy, state their level (calibrate --joint-sd RAD)"};
}

/*
  Known OpenCV distortion with every intrinsic known: applied once to every pixel, the steps see a
  pinhole camera (the dataset returned without its lens). When an intrinsic is estimated (the focal
  length included) undistorting needs it: the lens stays in the bundle adjustment's model (its
  coefficients estimated or held), and an empty dataset is returned (ds is used as it is).
*/
vpSelfCalibDataset pinholeData(const vpSelfCalibDataset &ds, const vpRobotSelfCalibration::Options &opt)
{
  const unsigned int others = vpKinematicBundleAdjustment::ASPECT | vpKinematicBundleAdjustment::PRINCIPAL_POINT |
                              vpKinematicBundleAdjustment::DISTORTION | vpKinematicBundleAdjustment::DISTORTION_K3;
  const bool lens_in_bundle =
      opt.method != vpRobotSelfCalibration::PAPER &&
      ((opt.bundle.intrinsics & others) != 0 ||
       vpRobotSelfCalibration::resolveFocalMode(opt, ds) != vpRobotSelfCalibration::FOCAL_KNOWN);
  vpSelfCalibDataset pinhole;
  if (!ds.opencv_distortion.empty() && !lens_in_bundle) {
    pinhole = ds;
    pinhole.views = vpSelfCalibPipeline::undistorted(ds.views, vpSelfCalibPipeline::lensOf(ds));
    pinhole.opencv_distortion.clear();
  }
  return pinhole;
}

// The caller mistakes of run() (see its documentation); returns the number of calibration views.
unsigned int checkInputs(const vpKinematicChain &nominal, const vpSelfCalibDataset &ds,
                         const vpRobotSelfCalibration::Options &opt)
{
  opt.check();
  if (ds.camera_mount == vpSelfCalibDataset::CAMERA_IN_WORLD && opt.method == vpRobotSelfCalibration::PAPER)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpRobotSelfCalibration: camera_mount: world is calibrated with --method bundle or "
                               "hand-eye; the paper method measures the camera's motion between views of a scene "
                               "fixed in the base frame (two-view geometry, eq. 21's scale), and a fixed camera does "
                               "not move");
  if (ds.camera_mount == vpSelfCalibDataset::CAMERA_IN_WORLD && opt.method == vpRobotSelfCalibration::BUNDLE_ADJUSTMENT &&
      opt.bundle.known_points.size() < 4)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpRobotSelfCalibration: camera_mount: world with the bundle method needs the layout of "
                               "the target on the tool (a board: calibrate --board, or bundle.known_points, 4 points "
                               "or more): the target's start pose and the scale come from it");
  // A camera or a model built in code is held to the files' plausibility bounds (beyond them the
  // solvers overflow and Ceres aborts on a CHECK instead of returning).
  vpSelfCalib::checkCamera(ds.cam, "vpRobotSelfCalibration: the dataset's camera");
  vpSelfCalib::checkChain(nominal, "vpRobotSelfCalibration: the nominal model '" + nominal.getName() + "'");
  const unsigned int N = std::min<unsigned int>(opt.num_calibration_poses, static_cast<unsigned int>(ds.views.size()));
  if (N < 3)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpRobotSelfCalibration: the dataset has " + std::to_string(ds.views.size()) +
                                   " views; at least 3 calibration views are needed");
  for (size_t k = 0; k < ds.views.size(); ++k) {
    if (opt.method == vpRobotSelfCalibration::HAND_EYE && ds.views[k].has_fMe && ds.views[k].q.size() == 0) {
      // Hand-eye: a controller pose in place of joints.
    } else if (ds.views[k].q.size() != nominal.getNumJoints())
      throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                                 "vpRobotSelfCalibration: view " + std::to_string(k) + " has " +
                                     std::to_string(ds.views[k].q.size()) + " joint values, the model has " +
                                     std::to_string(nominal.getNumJoints()) + " joints");
    if (ds.views[k].points.empty())
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpRobotSelfCalibration: view " + std::to_string(k) + " has no image point");
  }
  if (opt.method == vpRobotSelfCalibration::PAPER && !ds.yardstick.isSet())
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpRobotSelfCalibration: the dataset has no yardstick (length and two end ids); "
                               "the scale cannot be fixed without it");
  return N;
}
} // namespace

vpRobotSelfCalibration::Result vpRobotSelfCalibration::run(const vpKinematicChain &input_model,
                                                           const vpSelfCalibDataset &input, const Options &opt,
                                                           const Progress &progress)
{
  using vpSelfCalibPipeline::seconds;
  const auto t0 = std::chrono::steady_clock::now();
  const unsigned int N = checkInputs(input_model, input, opt);
  if (input_model.isCameraInWorld() && input.camera_mount != vpSelfCalibDataset::CAMERA_IN_WORLD)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpRobotSelfCalibration: the model '" + input_model.getName() +
                                   "' has the camera fixed in the world (camera_mount: world, its hand-eye slot is "
                                   "bMc) and the dataset has it on the end-effector: give the dataset "
                                   "camera_mount: world, or a model of the arm with the camera's eMc");
  if (input.camera_mount == vpSelfCalibDataset::CAMERA_IN_WORLD) {
    // Eye-to-hand: the eye-in-hand problem of the inverted controller poses, its eMc (bMc here)
    // started where the target's known points say (else at the identity), the result renamed.
    // The bundle method: the joints' kinematics are calibrated (the controller poses are not used).
    const bool joints = opt.method == BUNDLE_ADJUSTMENT;
    const vpSelfCalibDataset inverted = vpSelfCalibPipeline::eyeToHandAsEyeInHand(
        input_model, joints ? vpSelfCalibPipeline::eyeToHandJointsOnly(input, input_model.getNumJoints()) : input);
    vpKinematicChain model = input_model;
    vpHomogeneousMatrix bMc, eMo;
    double median_px = 0;
    if (!(opt.bundle.known_points.size() >= 4 &&
          vpSelfCalibPipeline::eyeToHandStart(inverted, N, opt.bundle.known_points, bMc, eMo, median_px)))
      bMc.eye();
    model.set_eMc(vpPoseVector(bMc));
    vpColVector p = model.getParameters();
    for (unsigned int i = p.size() - vpKinematicChain::kBlockSize; i < p.size(); ++i)
      p[i] = 0;
    model.setParameters(p);
    Options o = opt;
    o.bundle.controller_poses_inverted = !joints;
    o.bundle.eye_to_hand = joints;
    Result res = runMounted(model, joints ? input : inverted, o, progress);
    vpSelfCalibPipeline::eyeToHandResult(res);
    // Hand-eye on joint readings: its pipeline saw the poses the nominal kinematics give them.
    const auto joints_only = [](const vpSelfCalibDataset::View &v) { return v.q.size() > 0 && !v.has_fMe; };
    if (!joints && (res.status == OK || res.status == DOUBTFUL) &&
        std::any_of(input.views.begin(), input.views.end(), joints_only))
      vpSelfCalibPipeline::handEyeOnJoints(true, res);
    if (opt.bundle.known_points.size() < 4)
      vpSelfCalibPipeline::eyeToHandWithoutLayout(res);
    std::ostringstream start;
    start << "eye-to-hand, bMc started "
          << (median_px > 0 ? "from the target's poses (PnP and closed forms, median " : "at the identity (no target of known points)");
    if (median_px > 0)
      start << std::setprecision(3) << median_px << " px)";
    res.message = start.str() + "; " + res.message;
    res.seconds = seconds(t0);
    return res;
  }
  return runMounted(input_model, input, opt, progress);
}

vpRobotSelfCalibration::Result vpRobotSelfCalibration::runMounted(const vpKinematicChain &nominal,
                                                                  const vpSelfCalibDataset &ds, const Options &opt,
                                                                  const Progress &progress)
{
  using vpSelfCalibPipeline::seconds;
  const auto t0 = std::chrono::steady_clock::now();
  const unsigned int N = checkInputs(nominal, ds, opt);
  const vpSelfCalibDataset pinhole = pinholeData(ds, opt);
  const vpSelfCalibDataset &data0 = pinhole.views.empty() ? ds : pinhole;
  // eMc and a self-calibrated focal length started from what the data measure, not from the guesses
  // (below); a hand-eye run started from an earlier run's model, points and f (opt.start: a
  // cross-validation fold) starts from those.
  // The robot's error dropped (robotErrorDropped(): measured beyond a real arm's, or not measured):
  // the trusted run (calibrate --joint-sd 0) from the same start, whose checks judge the fit, with
  // the finding that says why; null when the trusted run fails (the measured run then goes on from
  // where it stopped, its level judged: robot-error-implausible).
  std::function<Result(const vpSelfCalibPipeline::DataStart &, const Options &, bool)> runFrom;
  const auto trustedInstead = [&](const vpSelfCalibPipeline::DataStart &start, const Result &measured,
                                  Dropped why, double guessed) -> std::optional<Result> {
    vpSelfCalibPipeline::DataStart exact_start = start;
    exact_start.dataset.joint_sd.clear();
    Result trusted = runFrom(exact_start, trustedOptions(opt), false);
    if (trusted.status != OK && trusted.status != DOUBTFUL)
      return std::nullopt;
    trusted.findings.push_back(why == TAKEN_EXACT ? takenExactFinding(measured.noise, measured.joint_error_structure)
                                                  : vpSelfCalibPipeline::robotErrorNotMeasuredFinding(guessed));
    return trusted;
  };
  // may_drop: the run stops where its robot error is dropped, and is the trusted run instead.
  runFrom = [&](const vpSelfCalibPipeline::DataStart &start, const Options &run_opt, bool may_drop) -> Result {
    const vpSelfCalibDataset &data = start.dataset;
    const vpKinematicChain &model = start.model;
    // Resolves the focal mode and builds every step's options: the remaining caller mistakes throw here.
    const vpSelfCalibPipeline::Context context(model, data, run_opt, N, progress, &nominal, start.eMc_from_data);
    bool tried = false; // the trusted run is made once: when it fails, the measured run goes on
    const auto stopped = [&](Result &r) {
      const Dropped why = may_drop && !tried ? robotErrorDropped(context, r) : KEPT;
      if (why == KEPT)
        return false;
      tried = true;
      std::optional<Result> trusted =
          trustedInstead(start, r, why, vpSelfCalib::levelsOf(noiseModel(run_opt, data), vpSelfCalib::JOINT_ERROR).r);
      if (!trusted)
        return false;
      r = std::move(*trusted);
      r.seconds = seconds(t0);
      return true;
    };

    Result res;
    res.method = run_opt.method;
    res.calibrated = model;
    res.camera = data.cam;
    if (!vpSelfCalibPipeline::checkData(context, res)) {
      res.seconds = seconds(t0);
      return res;
    }
    res.findings.insert(res.findings.end(), start.findings.begin(), start.findings.end());
    const std::vector<vpSelfCalibDataCheck::Finding> data_findings = res.findings;
    runMethod(context, res);
    if (stopped(res))
      return res;
    // Later runs at the measured noise levels; `current` is the context of the run that stands.
    std::optional<vpSelfCalibPipeline::Context> current;
    const auto attempt = [&](const vpSelfCalibNoiseModel &noise, bool robot_round) {
      const vpSelfCalibPipeline::Context c(context, noise, robot_round);
      Result next;
      next.method = run_opt.method;
      next.calibrated = model;
      next.camera = data.cam;
      next.findings = data_findings;
      runMethod(c, next);
      if (next.status != OK)
        return vpSelfCalibPipeline::NoiseAttempt{false, statusName(next.status), vpSelfCalibNoiseModel::unmeasured()};
      next.stage_seconds.insert(next.stage_seconds.begin(), res.stage_seconds.begin(), res.stage_seconds.end());
      res = next;
      current.emplace(c);
      return vpSelfCalibPipeline::NoiseAttempt{true, std::string(), res.measured};
    };
    if (run_opt.method != PAPER) {
      // A run that failed on too many rejected observations is the one a too small pixel_sd breaks:
      // it runs again too when its residuals measured the noise.
      // The attempts replace res: what the first run measured is copied first, and the notes of the
      // rounds join the findings of the run that stands at the end.
      const bool usable = res.status == OK || res.status == IDENTIFICATION_FAILED;
      const vpSelfCalibNoiseModel first_measured = res.measured;
      std::vector<vpSelfCalibDataCheck::Finding> notes;
      vpSelfCalibPipeline::measureNoise(res.noise, first_measured, res.status == OK, usable, true, attempt, notes);
      res.findings.insert(res.findings.end(), notes.begin(), notes.end());
      // The checks below at the robot error the adjustment measured (its sds then follow sigma0).
      if (res.bundle.robot_rounds > 0) {
        const vpSelfCalibPipeline::Context base = current ? *current : context;
        current.emplace(base, res.noise, true);
      }
      if (stopped(res))
        return res;
    }
    const vpSelfCalibPipeline::Context &used = current ? *current : context;
    if (!start.message.empty())
      res.message = start.message + "; " + res.message;
    if (start.eMc_from_data && res.status == OK)
      vpSelfCalibPipeline::findGuessFar(nominal, run_opt, res);

    vpSelfCalibPipeline::checkResult(used, res);
    if (res.status != OK) {
      // What the checks found often explains the failure: say it with the failure.
      for (const auto &f : res.findings)
        res.message += "; " + f.message;
      res.seconds = seconds(t0);
      return res;
    }
    vpSelfCalibPipeline::verify(used, res);
    vpSelfCalibPipeline::assess(used, res);
    if (start.eMc_from_data)
      vpSelfCalibPipeline::expressInGuess(nominal, res);
    res.seconds = seconds(t0);
    return res;
  };
  const vpSelfCalibPipeline::DataStart start = opt.method == HAND_EYE && opt.start.set
                                                   ? vpSelfCalibPipeline::DataStart{nominal, data0, {}, std::string()}
                                                   : vpSelfCalibPipeline::startFromData(nominal, data0, N, opt);
  return runFrom(start, opt, true);
}
