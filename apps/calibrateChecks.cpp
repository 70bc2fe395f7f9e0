/*
 * visp-selfcalib calibrate: the checks of its options against the dataset and the method (the
 * options of one method refused with another, the robot's error stated, --fix / --free names) and
 * of --heldout, see calibrate.h (the dataset's own checks: calibrateDataChecks.cpp).
 */
#include "calibrate.h"

#include <algorithm>
#include <iostream>
#include <set>
#include <sstream>

#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpKinematicIdentification.h>

//! How many of the board's points (known_points' ids) the dataset's views observe.
size_t boardPointsObserved(const std::map<int, vpColVector> &layout, const vpSelfCalibDataset &ds)
{
  std::set<int> seen;
  for (const auto &v : ds.views)
    for (const auto &o : v.points)
      if (layout.count(o.id))
        seen.insert(o.id);
  return seen.size();
}

//! The options of the full kinematic calibration only, refused with the hand-eye method (exit 2).
void refuseBundleOptions(const CalibrateArgs &a)
{
  if (!a.joint_sd.empty() || a.joint_sd_auto)
    throw CLI::ValidationError("--joint-sd", "the joint readings' error is the full kinematic calibration's (--method "
                                             "bundle); the hand-eye method models the controller poses' error: give "
                                             "--pose-sd T,R (m, rad) instead");
  if (!a.free.empty())
    throw CLI::ValidationError("--free", "the hand-eye method estimates every part of eMc (bMc with the camera in "
                                         "the world) whatever the tolerance; --free frees the kinematic parameters of "
                                         "--method bundle (--fix keeps a part of eMc at its nominal value)");
}

/*
  --pose-sd T,R and --joint-sd into the noise model of po's method: the controller poses' error
  (hand-eye), the kinematic model's residual and the joint readings' error (bundle; the joints' with
  hand-eye is refused by the run); none for the paper's method, which models no robot error (the
  options are not used).
*/
void stateRobotError(const CalibrateArgs &a, vpRobotSelfCalibration::Options &po)
{
  // A stated robot error: the sd are widened by sigma0 when the residuals say the noise is larger.
  // --joint-sd 0 and --pose-sd 0 come alone: exact, nothing stated.
  const bool joints_stated = !a.joint_sd.empty() && a.joint_sd[0] > 0;
  bool pose_stated = a.pose_sd.size() == 2 && std::stod(a.pose_sd[0]) > 0;
  // Below an arm's repeatability (ISO 9283: 0.02 to 0.1 mm; the floor of the measured robot error)
  // a stated error only freezes the poses, unchecked: taken as exact, whose checks then apply.
  constexpr double kArmFloor = 2e-5;
  if (pose_stated && std::stod(a.pose_sd[0]) < kArmFloor && std::stod(a.pose_sd[1]) < kArmFloor) {
    std::cerr << "warning: --pose-sd " << a.pose_sd[0] << "," << a.pose_sd[1]
              << ": below the 0.02 mm / 0.02 mrad no arm repeats better than: the poses are taken as exact, as "
                 "with --pose-sd 0 (whose checks then apply)\n";
    pose_stated = false;
    po.trust_robot = true;
  }
  if (joints_stated || pose_stated)
    po.bundle.scale_covariance = true;
  if (joints_stated && po.method != vpRobotSelfCalibration::PAPER)
    po.noise.joint_sd = a.joint_sd;
  if (!pose_stated)
    return;
  // The controller poses' error (hand-eye), or the kinematic model's residual (bundle); the
  // paper's method models neither.
  const double t = std::stod(a.pose_sd[0]), r = std::stod(a.pose_sd[1]);
  if (po.method == vpRobotSelfCalibration::HAND_EYE) {
    po.noise.pose_sd_translation = t;
    po.noise.pose_sd_rotation = r;
  } else if (po.method == vpRobotSelfCalibration::BUNDLE_ADJUSTMENT) {
    po.noise.model_sd_translation = t;
    po.noise.model_sd_rotation = r;
  }
}

/*
  --fix / --free and the dataset's fix: / free: against the model's parameter names: a pattern that
  matches nothing is a usage error (exit 2) naming it and listing the valid names; so is a parameter
  both fixed and freed.
*/
void checkParameterLists(const vpKinematicChain &nominal, const vpSelfCalibDataset &ds,
                         const vpRobotSelfCalibration::Options &po, bool hand_eye, bool intrinsics_estimated)
{
  const std::pair<const char *, std::vector<std::string>> lists[4] = {
      {"--fix", po.bundle.fixed}, {"--free", po.bundle.free}, {"the dataset's fix", ds.fix}, {"the dataset's free", ds.free}};
  std::vector<std::string> fixed, freed;
  for (const auto &l : lists) {
    std::vector<std::string> names;
    try {
      names = vpKinematicIdentification::matchParameters(nominal, l.second, l.first);
    } catch (const vpException &e) {
      throw CLI::ValidationError(e.getStringMessage()); // the message names the option
    }
    std::vector<std::string> &into = std::string(l.first).find("fix") != std::string::npos ? fixed : freed;
    into.insert(into.end(), names.begin(), names.end());
  }
  for (const std::string &f : freed)
    if (std::find(fixed.begin(), fixed.end(), f) != fixed.end())
      throw CLI::ValidationError("--free", "'" + f + "' is both fixed and freed: choose one");
  // Every parameter the method estimates fixed (eMc's six with hand-eye): nothing is left to
  // calibrate, or only the intrinsics, which the adjustment estimates with the robot's parameters only.
  if (fixed.empty())
    return;
  const std::vector<std::string> names = nominal.getParameterNames();
  const size_t estimated = static_cast<size_t>(std::count_if(names.begin(), names.end(), [&](const std::string &n) {
    return (!hand_eye || n.rfind("eMc.", 0) == 0) && std::find(fixed.begin(), fixed.end(), n) == fixed.end();
  }));
  if (estimated > 0)
    return;
  const std::string what = "every parameter the " + std::string(hand_eye ? "hand-eye" : "bundle") +
                           " method estimates is fixed (" +
                           (hand_eye ? std::string("the six of eMc, bMc with the camera in the world")
                                     : std::to_string(names.size()) + " parameters") + ")";
  const std::string fewer = std::string("fix fewer parameters (") + (hand_eye ? "e.g. --fix eMc.tz" : "e.g. --fix 'j1.*'") + ")";
  if (intrinsics_estimated)
    throw CLI::ValidationError("--fix", what + ": only the intrinsics (--estimate, --focal shared) would be left, "
                                               "and this tool calibrates them with the robot's parameters, not alone; " +
                                            fewer + ", or calibrate the camera alone with a camera calibration (a "
                                                    "board seen in several views)");
  throw CLI::ValidationError("--fix", what + " and the intrinsics are known: nothing is left to calibrate; " + fewer);
}

/*
  A doubt of misfit (residuals, corrections, predictions) on a run whose user fixed parameters: a
  fixed value that is wrong cannot be corrected and its error goes into the residuals and the other
  estimates, which the misfit checks then name as a wrong model, unmodelled joint error or the like.
  The fixed parameters lead: a doubt naming them goes first (in the output, the status line and
  results.yaml).
*/
void leadWithFixedParameters(vpRobotSelfCalibration::Result &r)
{
  if (r.status != vpRobotSelfCalibration::DOUBTFUL)
    return;
  static const std::set<std::string> misfit = {
      "residuals-too-large",          "robot-error-unmodelled",      "correction-beyond-tolerance",
      "fit-worse-than-nominal",       "held-out-worse-than-nominal", "cross-validation-worse-than-nominal",
      "yardstick-not-reproduced",     "robot-corrections-stand-in",  "expected-worse-than-nominal"};
  const bool misfits = std::any_of(r.findings.begin(), r.findings.end(), [](const vpSelfCalibDataCheck::Finding &f) {
    return f.severity == vpSelfCalibDataCheck::DOUBT && misfit.count(f.code);
  });
  std::vector<std::string> fixed;
  for (const auto &u : r.identifiability.unidentifiable)
    if (u.cause == vpKinematicIdentification::CAUSE_FIXED)
      fixed.push_back(u.name);
  if (!misfits || fixed.empty())
    return;
  std::string names;
  for (size_t i = 0; i < fixed.size() && i < 6; ++i)
    names += (i ? ", " : "") + fixed[i];
  if (fixed.size() > 6)
    names += " and " + std::to_string(fixed.size() - 6) + " more";
  r.findings.insert(r.findings.begin(),
                    {vpSelfCalibDataCheck::DOUBT, "fixed-parameters-misfit",
                     "the model does not fit the data with " + std::to_string(fixed.size()) + " parameter" +
                         (fixed.size() > 1 ? "s" : "") + " fixed at their nominal values by --fix or the dataset's "
                         "fix: (" + names + "): a fixed value that is wrong is not corrected and its error goes "
                         "into the residuals and the other estimates; run without fixing them (or fix fewer) "
                         "before reading the doubts below"});
}

int checkHeldout(const std::string &dataset, const vpSelfCalibDataset &ds, const std::string &heldout)
{
  if (heldout.empty())
    return 0;
  if (!canonical(heldout).empty() && canonical(heldout) == canonical(dataset)) {
    std::cerr << "error: --heldout " << heldout << " is the calibration dataset itself: a check on the views "
              << "calibrated on is not independent; give a dataset of other poses\n";
    return 1;
  }
  const vpSelfCalibDataset h = vpSelfCalibDataset::loadYaml(heldout);
  if (h.camera_mount != ds.camera_mount) {
    std::cerr << "error: --heldout " << heldout << ": camera_mount: "
              << vpSelfCalibDataset::cameraMountName(h.camera_mount) << ", the calibration dataset's is "
              << vpSelfCalibDataset::cameraMountName(ds.camera_mount)
              << ": a check on another set-up says nothing of this calibration; give views of this one\n";
    return 1;
  }
  if (h.robot != ds.robot) {
    // Another robot model's views say nothing of this calibration (their joints move another arm).
    const vpKinematicChain mine = vpKinematicChain::fromPresetOrFile(ds.robot);
    const vpKinematicChain theirs = vpKinematicChain::fromPresetOrFile(h.robot);
    // The same arm: the same flange pose at the held-out views' joints (a copy of the model file is).
    bool same = mine.getNumJoints() == theirs.getNumJoints();
    for (size_t k = 0; same && k < h.views.size(); ++k)
      if (h.views[k].q.size() == mine.getNumJoints()) {
        const vpHomogeneousMatrix d = mine.get_fMe(h.views[k].q).inverse() * theirs.get_fMe(h.views[k].q);
        same = d.getTranslationVector().frobeniusNorm() < 1e-9 && vpThetaUVector(d).getTheta() < 1e-9;
      }
    if (!same) {
      std::cerr << "error: --heldout " << heldout << ": robot " << h.robot << ", the calibration dataset's is "
                << ds.robot << ": a check on another robot's views says nothing of this calibration; give views of "
                << "this robot\n";
      return 1;
    }
  }
  std::vector<size_t> shared;
  for (size_t k = 0; k < h.views.size(); ++k)
    for (const vpSelfCalibDataset::View &v : ds.views)
      if (sameView(h.views[k], v)) {
        shared.push_back(k);
        break;
      }
  if (shared.empty())
    return 0;
  std::ostringstream list;
  for (size_t i = 0; i < shared.size() && i < 10; ++i)
    list << (i ? ", " : "") << shared[i];
  if (shared.size() > 10)
    list << "...";
  std::cerr << "error: --heldout " << heldout << ": " << shared.size() << " of its " << h.views.size()
            << " views (" << list.str() << ") are views of the calibration dataset too (the same joints or "
            << "image): a check on them is not independent; give views not used to calibrate\n";
  return 1;
}
