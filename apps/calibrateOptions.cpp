/*
 * visp-selfcalib calibrate: its command line, and the library options it gives (see calibrate.h).
 */
#include "calibrate.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include <visp3/core/vpException.h>
#include <visp3/selfcalib/vpBoardDetector.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include "selfcalibCli.h"

namespace
{
//! The protocol: the method, the split of the views, the folds, a held-out dataset.
void addProtocolOptions(CLI::App *c, CalibrateArgs &a)
{
  std::vector<std::string> methods;
  for (vpRobotSelfCalibration::Method m :
       {vpRobotSelfCalibration::BUNDLE_ADJUSTMENT, vpRobotSelfCalibration::PAPER, vpRobotSelfCalibration::HAND_EYE})
    methods.push_back(vpRobotSelfCalibration::methodName(m));
  c->add_option("--method", a.method,
                "bundle (default; hand-eye when the poses have fMe and no joints): multi-view\n"
                "reconstruction + kinematic bundle adjustment; paper: the paper's procedure;\n"
                "hand-eye: kinematics trusted, eMc, f and points estimated")
      ->type_name("M")
      ->check(CLI::IsMember(methods));
  c->add_option("--calibration", a.calibration,
                "the paper's split: the first N views calibrate, the others verify (3-D yardstick\n"
                "error); at least 3 (default: every view calibrates)")
      ->type_name("N")
      ->check(selfcalibCli::wholeNumber(3, 100000));
  c->add_option("--holdout", a.holdout,
                "the paper's split counted from the end: the last N views verify, the others\n"
                "calibrate; 2 to 100000 (the yardstick error needs two views; with --calibration,\n"
                "the two must add up to the views)")
      ->type_name("N")
      ->check(selfcalibCli::wholeNumber(2, 100000));
  CLI::Option *folds =
      c->add_option("--folds", a.folds,
                    "K-fold cross-validation (view i held out in fold i mod K), 0 or 2 to 100: the\n"
                    "held-out views' reprojection error through the calibrated model vs the nominal\n"
                    "one, the figure to trust on real data (default 5 when every view calibrates,\n"
                    "skipped with a note under 6 views; with --holdout / --calibration none unless\n"
                    "given: then over the calibration views); 0: none")
          ->type_name("K")
          ->check(selfcalibCli::zeroOrWholeNumber(2, 100));
  folds->each([&a](const std::string &) { a.folds_given = true; });
  c->add_option("--heldout", a.heldout,
                "a second dataset of the same robot and camera, not used to calibrate: the model is\n"
                "verified on it (3-D yardstick error when it has one; its views' reprojection error,\n"
                "calibrated vs nominal, the scene triangulated from them)")
      ->type_name("FILE");
}

//! --kinematic-prior's K (the prior's sd: the tolerance / K): off 0, tolerance 1, tolerance/K or K; -1 when not one of them.
double priorDivisor(const std::string &v)
{
  if (v == "off")
    return vpKinematicBundleAdjustment::KINEMATIC_PRIOR_OFF;
  const std::string k = v == "tolerance" ? "1" : v.rfind("tolerance/", 0) == 0 ? v.substr(10) : v;
  char *end = nullptr;
  const double d = std::strtod(k.c_str(), &end);
  return !k.empty() && end == k.c_str() + k.size() && std::isfinite(d) && d > 0 && d <= 1e3 ? d : -1;
}

//! K as the help prints it (3, 2.5).
std::string priorText(double k)
{
  std::ostringstream os;
  os << k;
  return os.str();
}

//! The model: the focal length, the noise, the tolerance, the robot's error, the intrinsics.
void addModelOptions(CLI::App *c, CalibrateArgs &a)
{
  c->add_option("--focal", a.focal, "auto (default: known when the dataset gives px, py), known, shared, per-pair")
      ->type_name("MODE")
      ->check(
          CLI::IsMember(focalNames({vpRobotSelfCalibration::FOCAL_AUTO, vpRobotSelfCalibration::FOCAL_KNOWN,
                                    vpRobotSelfCalibration::FOCAL_SHARED, vpRobotSelfCalibration::FOCAL_PER_PAIR})));
  c->add_option("--pixel-sd", a.pixel_sd,
                "image noise sd (px): auto (default) measures it from the residuals (a second run\n"
                "with the measured value when it differs from 0.2 px by more than 25 %); a number is\n"
                "used as stated (0.001 to 1000), and the sd are scaled when the residuals contradict it")
      ->type_name("auto|PX")
      ->check(selfcalibCli::wordOrNumber("auto", 0.001, false, 1000)); // below 0.001 px: a mistake
  c->add_option("--tolerance", a.tolerance,
                "the nominal model's tolerance: largest error of a joint placement (m, rad), then\n"
                "optionally of eMc (m, rad); a correction or an sd beyond it makes the run doubtful\n"
                "(default 0.01,0.05,0.1,0.5; hand-eye does not check eMc)")
      ->type_name("T,R[,TE,RE]")
      ->delimiter(',')
      ->expected(1, 4) // 1 or 3 refused below; (2, 4) would print "x 2" in the help
      ->check(selfcalibCli::number(0, true, 100));
  c->add_option("--pose-sd", a.pose_sd,
                "hand-eye: the controller poses' error, translation (m) and rotation (rad) sd,\n"
                "e.g. 0.002,0.002: each pose gets a correction with that prior, and the sd are\n"
                "widened by sigma0 when the residuals say the noise is larger; bundle-adjustment: the\n"
                "kinematic model's own residual (each camera pose corrected in its own frame with that\n"
                "prior; stated, or by default measured with the joints' on arms of fewer than 6 joints);\n"
                "auto (hand-eye's default): measured from\n"
                "the corrections (variance components), from the dataset's robot_error or 1 mm /\n"
                "1 mrad, runs again until it settles within 10 %; 0: the robot is exact (no error\n"
                "modelled: the controller poses, or the joint readings and the model)")
      ->type_name("T,R|auto|0")
      ->delimiter(',')
      ->expected(1, 2)
      ->check(selfcalibCli::wordOrNumber("auto", 0, false, 10));
  c->add_option_function<std::vector<std::string>>(
       "--joint-sd",
       [&a](const std::vector<std::string> &values) {
         for (const std::string &v : values)
           if (v == "auto" && values.size() > 1) // auto,auto or auto,1e-4: one or the other
             throw CLI::ValidationError("--joint-sd", "auto (measured) comes alone, once; or give the error (rad), "
                                                      "one value for every joint or one per joint, or 0");
           else if (v == "auto")
             a.joint_sd_auto = true;
           else
             a.joint_sd.push_back(std::stod(v));
       },
       "bundle-adjustment: the joint readings' error (rad). auto: measured (variance\n"
       "components inside the bundle adjustment, with the image noise's own factor, the\n"
       "priors re-weighed until they settle within 25 %) from the dataset's robot_error, else\n"
       "from 3e-4 rad; on arms of fewer than 6 joints the model's residual too, from 0.2 mm /\n"
       "0.2 mrad (on 6 or more the joints take the whole error: the images cannot split it);\n"
       "a level below 4e-5 is dropped (exact). S: stated,\n"
       "one value for every joint or one per joint, e.g. 1e-4: each view gets joint\n"
       "corrections with that prior, and the sd are widened by sigma0 when the residuals say\n"
       "the noise is larger. 0: the joint readings and the model are exact (no error\n"
       "modelled, whatever the dataset's robot_error says). Default: the dataset's\n"
       "robot_error, stated, else measured as with auto (from 3e-4 rad; the estimated set\n"
       "decided again at the level measured; a model residual measured above 1 mm / 1 mrad, or\n"
       "a joint error above 1e-3 rad whose corrections do not look like reading noise, is a\n"
       "misfit, not noise: the result is then the run with --joint-sd 0, and the warning\n"
       "robot-error-taken-exact says so)")
      ->type_name("auto|RAD[,RAD...]|0")
      ->delimiter(',')
      ->check(selfcalibCli::wordOrNumber("auto", 0, false, 0.999));
  c->add_option("--fix", a.fix,
                "kinematic parameters kept at their nominal value, names or glob patterns as the\n"
                "model names them (j2.tx, eMc.ry, 'j3.*,base.*'); added to the dataset's fix: list.\n"
                "A part of eMc keeps the model's guess also where the run measures eMc from the\n"
                "data (the other parts start from the measured eMc)")
      ->type_name("NAMES")
      ->delimiter(',');
  c->add_option("--free", a.free,
                "bundle-adjustment: kinematic parameters estimated even when their predicted sd exceeds\n"
                "the tolerance (--tolerance), walked first; added to the dataset's free: list. One the\n"
                "model folds into another is refused (exit 3); so is, with --kinematic-prior off, one\n"
                "the data cannot separate from the others (with the prior it is estimated, held by the\n"
                "prior: results.yaml held_by_prior)")
      ->type_name("NAMES")
      ->delimiter(',');
  c->add_option("--kinematic-prior", a.kinematic_prior,
                "bundle-adjustment: a prior on every kinematic correction, its sd the tolerance\n"
                "(--tolerance) / K: the parameters the data alone do not determine are estimated too,\n"
                "held near nominal (results.yaml: held_by_prior), and the sd include the prior.\n"
                "tolerance (K = 1), tolerance/K or K (above 0, at most 1000); off: no prior, the\n"
                "parameters the data do not determine are left at nominal (results.yaml:\n"
                "left_by_data). Default: the dataset's kinematic_prior, else tolerance/" +
                    priorText(vpKinematicBundleAdjustment::DEFAULT_KINEMATIC_PRIOR))
      ->type_name("off|tolerance|tolerance/K|K")
      ->check(CLI::Validator(
          [](std::string &v) {
            return priorDivisor(v) < 0 ? "expected off, tolerance, tolerance/K or K (K above 0, at most 1000), got '" + v + "'"
                                       : std::string();
          },
          std::string()));
  c->add_option("--estimate", a.estimate,
                "intrinsics estimated with the calibration besides f (--focal): aspect (p_y / p_x),\n"
                "pp (principal point), distortion (OpenCV's k1, k2, p1, p2), k3 (and OpenCV's k3),\n"
                "kud (ViSP's one radial coefficient instead); for nominal intrinsics")
      ->type_name("WHAT[,WHAT...]")
      ->delimiter(',')
      ->check(CLI::IsMember({"aspect", "pp", "distortion", "k3", "kud"}));
  c->add_option("--threads", a.threads,
                "threads of the image front end (default: all cores); the results do not depend on it")
      ->type_name("N")
      ->check(selfcalibCli::wholeNumber(1, 1024));
}

} // namespace

void addCalibrate(CLI::App &app, CalibrateArgs &a)
{
  CLI::App *c = app.add_subcommand("calibrate", "calibrated model, camera and results in DIR");
  c->add_option("DATASET", a.dataset, "the dataset file (doc/formats.md)")->type_name("FILE")->required();
  c->add_option("--out", a.out, "the output directory (created when missing)")->type_name("DIR")->required();
  addProtocolOptions(c, a);
  addModelOptions(c, a);
  addFrontEndOptions(c, a);
  c->add_flag("--force", a.force, "replace the results of an earlier run in DIR");
  c->footer("Self-calibrates on every view and cross-validates (--folds), or on the first views and\n"
            "verifies on the last ones (--holdout, --calibration). Writes DIR/model.yaml,\n"
            "DIR/model.urdf, DIR/camera.xml, DIR/results.yaml and DIR/report/ (report.md, gnuplot figures)\n"
            "as one set: written beside DIR, then moved into place at once, under a lock on DIR (a second run\n"
            "into the same DIR is refused). DIR must not hold an input or files that are not results; an\n"
            "earlier run's results are replaced only with --force. The data check's findings are printed\n"
            "as warnings.\n"
            "Exit codes: 0 calibrated, 1 bad input, 2 bad usage, 3 no trustworthy calibration: refused (data\n"
            "that cannot determine it), failed, or doubtful (model written, marked); the last line on stdout\n"
            "('status: ...') says which and what to do.");
}

vpRobotSelfCalibration::Options calibrationOptions(const CalibrateArgs &a,
                                                   const vpSelfCalibImageCorrespondences::Options &co)
{
  vpRobotSelfCalibration::Options po;
  po.focal_mode = vpRobotSelfCalibration::focalModeFromName(a.focal);
  if (a.pixel_sd == "auto")
    po.noise.measure_pixel_sd = true; // from 0.2 px
  else
    po.noise.pixel_sd = std::stod(a.pixel_sd);
  if (a.tolerance.size() == 1 || a.tolerance.size() == 3)
    throw CLI::ValidationError("--tolerance", "give 2 values (joint placements) or 4 (and eMc), not " +
                                                  std::to_string(a.tolerance.size()));
  if (a.tolerance.size() >= 2) {
    po.tolerance_translation = a.tolerance[0];
    po.tolerance_rotation = a.tolerance[1];
  }
  if (a.tolerance.size() == 4) {
    po.tolerance_hand_eye_translation = a.tolerance[2];
    po.tolerance_hand_eye_rotation = a.tolerance[3];
  }
  po.bundle.fixed = a.fix;
  po.bundle.free = a.free;
  if (!a.kinematic_prior.empty()) // else not said: the dataset's, else the bundle adjustment's default
    po.bundle.kinematic_prior = priorDivisor(a.kinematic_prior);
  // The board's layout as its spec describes it measures the start (PnP) even when the bundle
  // adjustment does not take it as known; several single tags have none, a masked board gives no points.
  if (co.board && !co.mask_board) {
    try {
      po.target_layout = vpBoardDetector(*co.board).getLayout();
    } catch (const vpSelfCalibException &) {
    }
  }
  if (a.board_geometry) {
    try {
      po.bundle.known_points = vpBoardDetector(*co.board).getLayout();
    } catch (const vpSelfCalibException &e) { // several single tags: no layout (a usage error)
      throw CLI::ValidationError("--board-geometry", e.getStringMessage());
    }
    po.bundle.known_points_sd = a.board_sd;
  }
  for (const std::string &e : a.estimate) {
    using KBA = vpKinematicBundleAdjustment;
    po.bundle.intrinsics |= e == "aspect" ? KBA::ASPECT
                            : e == "pp"   ? KBA::PRINCIPAL_POINT
                            : e == "k3"   ? KBA::DISTORTION | KBA::DISTORTION_K3
                                          : KBA::DISTORTION;
    if (e == "distortion" || e == "k3")
      po.bundle.distortion_model = KBA::DISTORTION_OPENCV;
  }
  if (std::count(a.estimate.begin(), a.estimate.end(), "kud") && po.bundle.distortion_model != 0)
    throw CLI::ValidationError("--estimate", "kud (ViSP's model) and distortion / k3 (OpenCV's) exclude each other");
  const bool pose_auto = std::count(a.pose_sd.begin(), a.pose_sd.end(), "auto") > 0;
  if (pose_auto && a.pose_sd.size() != 1)
    throw CLI::ValidationError("--pose-sd", "give T,R (two numbers) or auto, not both");
  if (pose_auto && !a.method.empty() && co.method != vpRobotSelfCalibration::HAND_EYE)
    throw CLI::ValidationError("--pose-sd", "auto measures the controller poses' error: it needs --method hand-eye "
                                            "(the joint readings' error is stated with --joint-sd)");
  const bool trusted = std::all_of(a.pose_sd.begin(), a.pose_sd.end(), [](const std::string &v) { return v != "auto" && std::stod(v) == 0; });
  if (!pose_auto && a.pose_sd.size() == 1 && !trusted)
    throw CLI::ValidationError("--pose-sd", "give two values, T,R (m, rad), or auto, or 0 (exact poses)");
  if (a.pose_sd.size() == 2 && !trusted && (std::stod(a.pose_sd[0]) == 0 || std::stod(a.pose_sd[1]) == 0))
    throw CLI::ValidationError("--pose-sd", "T and R are both positive (the error modelled) or both 0 (exact poses)");
  // A robot's pose error, or its model's residual, is millimetres and milliradians: beyond 0.1 m or
  // 0.5 rad the values are in other units (mm typed as m), and the adjustment would fail unexplained.
  if (a.pose_sd.size() == 2 && !trusted && (std::stod(a.pose_sd[0]) > 0.1 || std::stod(a.pose_sd[1]) > 0.5))
    throw CLI::ValidationError("--pose-sd", a.pose_sd[0] + "," + a.pose_sd[1] + " is no robot's error: T is in metres "
                                            "(at most 0.1) and R in radians (at most 0.5); 2 mm and 2 mrad are "
                                            "0.002,0.002");
  if (a.joint_sd_auto && !a.joint_sd.empty())
    throw CLI::ValidationError("--joint-sd", "auto (measured) comes alone; or give the error (rad), one value for every "
                                             "joint or one per joint, or 0 (exact readings)");
  const bool joints_exact = std::count(a.joint_sd.begin(), a.joint_sd.end(), 0.0) > 0;
  if (joints_exact && a.joint_sd.size() != 1)
    throw CLI::ValidationError("--joint-sd", "0 (exact readings) comes alone; give positive values (rad), one for "
                                             "every joint or one per joint");
  if (joints_exact && !a.method.empty() && co.method != vpRobotSelfCalibration::BUNDLE_ADJUSTMENT)
    throw CLI::ValidationError("--joint-sd", "the joint readings' error is the bundle method's (--method bundle); "
                                             "hand-eye trusts the robot with --pose-sd 0");
  po.trust_robot = (trusted && !a.pose_sd.empty()) || joints_exact;
  // Measured by default from the dataset's robot_error when it states one (below, once it is read).
  if (pose_auto || a.pose_sd.empty())
    po.noise.measure_pose_sd = true;
  if (a.joint_sd_auto)
    po.noise.measure_joint_sd = po.noise.measure_model_sd = true; // the dataset's robot_error measured too
  // Without --joint-sd, the bundle method models the robot's error from robotErrorPrior() and
  // measures it when the dataset states none (the library's default, trust_robot false).
  // --pose-sd T,R and --joint-sd go to the noise model once the method is known (stateRobotError).
  return po;
}
