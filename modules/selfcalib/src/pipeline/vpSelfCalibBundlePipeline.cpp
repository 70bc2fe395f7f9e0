/*
 * ViSP SelfCalib: the default pipeline, multi-view reconstruction then kinematic bundle adjustment
 * (beyond the paper).
 */
#include "vpSelfCalibPipelines.h"
#include "vpSelfCalibRobotErrorStructure.h"

#include <algorithm>
#include <cmath>

#include "../core/vpSelfCalibMath.h"
#include "../core/vpSelfCalibRobotErrorLevels.h"

using namespace vpSelfCalib;

namespace vpSelfCalibPipeline
{
namespace
{
/*
  The model the estimated set is decided at: values no noise draw moves. eMc measured from the data
  (startFromData()) moves with the draw, by centimetres where the views barely turn about a joint,
  and the information at it, and a decision near a margin, with it. The caller's model when the
  measured eMc is within the hand-eye tolerance of its guess (the guess is as good a start for the
  decision as any within the tolerance); otherwise the guess corrected by the measured eMc rounded
  to that tolerance in the guess's frame (guess^-1 measured: its translation to multiples of the
  translation tolerance, its theta-u vector to multiples of the rotation tolerance), so that draws a
  fraction of the tolerance apart decide at the same values unless the correction lies near half a
  step (a guess off by a turn of the axes, the common mistake, is corrected by whole steps).
*/
vpKinematicChain decisionModel(const Context &c)
{
  if (!c.eMc_from_data)
    return c.nominal;
  const double tt = c.options.tolerance_hand_eye_translation, tr = c.options.tolerance_hand_eye_rotation;
  const vpHomogeneousMatrix guess = c.guess.get_eMc_corrected(), measured = c.nominal.get_eMc_corrected();
  if (translationDistance(guess, measured) <= tt && rotationDistance(guess, measured) <= tr)
    return c.guess;
  vpPoseVector d(guess.inverse() * measured);
  for (unsigned int i = 0; i < 6; ++i) {
    const double step = i < 3 ? tt : tr;
    d[i] = step * std::round(d[i] / step);
  }
  vpKinematicChain out = c.nominal;
  out.set_eMc(vpPoseVector(guess * vpHomogeneousMatrix(d))); // the measured start's eMc corrections are zero
  return out;
}

//! Where the estimated set is decided: the model (decisionModel()), the points, the unit and f.
struct SetDecision {
  vpKinematicChain at;
  std::map<int, vpColVector> points;
  double s, fx;
};

/*
  The set the bundle adjustment estimates, decided from what its data determine at the nominal
  model (decisionModel(): not at the eMc measured from this draw), so that the start identification
  estimates within it and a parameter the data leave out stays nominal instead of taking the start's
  value. With f known, the points are triangulated through that model's camera poses: their scale
  is the model's, where the multi-view points' scale (one noisy baseline) moves every predicted sd
  by several percent from one noise draw to the next, and a decision near the tolerance with it.
  At the robot error `noise`.
*/
vpKinematicIdentification::Identifiability decideSet(const Context &c, const SetDecision &d,
                                                     const vpSelfCalibNoiseModel &noise)
{
  return vpKinematicBundleAdjustment::estimatedSet(d.at, startCamera(c, d.fx), c.calibration, c.dataset.yardstick,
                                                   d.points, c.bundle, noise);
}

/*
  The kinematic prior's centre (Settings::kinematic_prior, through scale_reference): the caller's
  model, its eMc the caller's guess, whose error the hand-eye tolerance states, not the eMc this run
  started from (startFromData(): the nominal model's eMc replaced by the one the camera's motions
  measure, its corrections then zero). That start is data, not a prior: its translation can be
  decimetres off before the adjustment corrects it (the hand-eye closed form from small rotations),
  and a prior centred there is contradicted by the data. The guess expressed as corrections of the
  start's eMc; empty without the prior or without a measured eMc (bundleFrom() then centres it on
  the nominal model's own parameters).
*/
std::vector<double> priorCentre(const Context &c)
{
  if (!c.eMc_from_data || c.bundle.hand_eye_only || !(c.bundle.kinematicPrior() > 0) ||
      c.guess.getNumParameters() != c.nominal.getNumParameters())
    return {};
  const vpColVector p = c.nominal.getParameters();
  std::vector<double> centre(p.data, p.data + p.size());
  const Rigid D = rigidFromPose(c.nominal.get_eMc_pose()).inverse() * rigidFromVisp(c.guess.get_eMc_corrected());
  const Eigen::Vector3d r = logSO3(D.R);
  const size_t first = centre.size() - vpKinematicChain::kBlockSize;
  for (size_t i = 0; i < 3; ++i) {
    centre[first + i] = D.t(static_cast<Eigen::Index>(i));
    centre[first + 3 + i] = r(static_cast<Eigen::Index>(i));
  }
  return centre;
}

/*
  The start identification from the multi-view poses (res.measurements) on the set, then the
  kinematic bundle adjustment (at c's noise) from its model; false when the adjustment fails.
*/
bool identifyAndAdjust(const Context &c, const SetDecision &d, const vpKinematicIdentification::Identifiability &set,
                       Result &res, std::chrono::steady_clock::time_point ts)
{
  vpKinematicBundleAdjustment::Options bo = c.bundle;
  bo.estimated_set = set;
  if (bo.scale_reference.empty())
    bo.scale_reference = priorCentre(c);
  // The start identification estimates exactly that set (fixing the others instead would let the
  // rule take a redundant twin of each in its place, which the bundle adjustment would then keep at
  // the start's value); when the posed views do not determine it, the start is the nominal model.
  vpKinematicIdentification::Options io = c.options.identification;
  for (const std::string &f : vpKinematicIdentification::matchParameters(c.nominal, c.bundle.fixed, "fixed"))
    if (std::find(io.fixed.begin(), io.fixed.end(), f) == io.fixed.end())
      io.fixed.push_back(f);
  res.identification = bo.estimated_set.identified.empty()
                           ? vpKinematicIdentification::identify(c.nominal, res.measurements, io)
                           : vpKinematicIdentification::identify(c.nominal, res.measurements, io, bo.estimated_set);
  const vpKinematicChain start =
      res.identification.status == vpKinematicIdentification::OK ? res.identification.chain : c.nominal;
  res.stage_seconds.push_back({"identification", seconds(ts)});
  // Kinematic bundle adjustment, points moved to f through the start model. It estimates the set
  // selected from every calibration view's joints at the nominal model; the identification above
  // (same rule, its posed views only) estimated a subset of it, the rest being still nominal.
  return bundle(c, start, start.get_fMc(c.calibration[0].q), d.s, c.calibration, bo, "kinematic bundle adjustment",
                res);
}
/*
  The identification and the bundle adjustment again on `set` at c's noise from res's
  measurements; res replaced when the adjustment succeeds (its stage times appended), kept
  otherwise. True when replaced.
*/
bool adjustAgain(const Context &c, const SetDecision &d, const vpKinematicIdentification::Identifiability &set,
                 Result &res)
{
  Result next = res;
  next.stage_seconds.clear();
  if (!identifyAndAdjust(c, d, set, next, std::chrono::steady_clock::now()))
    return false;
  next.stage_seconds.insert(next.stage_seconds.begin(), res.stage_seconds.begin(), res.stage_seconds.end());
  res = next;
  return true;
}
} // namespace

void runBundle(const Context &c, Result &res)
{
  if (c.bundle.eye_to_hand) {
    runBundleEyeToHand(c, res);
    return;
  }
  auto ts = std::chrono::steady_clock::now();
  const unsigned int N = c.num_calibration;
  const std::vector<View> &cal = c.calibration;

  // 1. Scale-consistent poses and points of the calibration views, one focal length.
  if (!multiView(c, res)) {
    // No two-view geometry (a plane seen with f self-calibrated, too few matches per pair): the
    // points triangulated from the camera poses the nominal model predicts, at the dataset's focal
    // length (run() measured it where these rays meet best when f is self-calibrated); the bundle
    // adjustment from there (its information decides).
    const Result failed = res;
    std::vector<Rigid> fMc;
    for (const View &v : cal)
      fMc.push_back(rigidFromVisp(c.nominal.get_fMc(v.q)));
    const PredictedStart p =
        predictedStart(cal, fMc, lensOf(c.dataset), true); // the dataset's f: measured by run() when self-calibrated
    res.stage_seconds.push_back({"start from the nominal model's poses", seconds(ts)});
    if (!p.ok)
      return;
    vpKinematicBundleAdjustment::Options bo = c.bundle;
    if (bo.scale_reference.empty())
      bo.scale_reference = priorCentre(c);
    if (bundleFrom(c, c.nominal, p.points, p.fx, cal, bo, "kinematic bundle adjustment", res))
      res.message = "start from the nominal model's poses (" + failed.message + "); " + res.message;
    else
      res.message = failed.message + "; from the nominal model's poses: " + res.message;
    return;
  }
  res.fx = res.multiview.fx;
  res.fx_sd = res.multiview.fx_sd;
  ts = std::chrono::steady_clock::now();

  // Without the yardstick, the unit is the reference pair's baseline: give it the nominal length.
  double s = 1;
  if (!res.multiview.metric) {
    const unsigned int r = res.multiview.reference_view;
    const double nominal_baseline =
        (c.nominal.get_fMc(cal[r].q).inverse() * c.nominal.get_fMc(cal[0].q)).getTranslationVector().frobeniusNorm();
    s = nominal_baseline / res.multiview.cMc0[r].getTranslationVector().frobeniusNorm();
  }

  // 2. Pose-based identification from the multi-view poses: the start of the bundle adjustment.
  for (unsigned int k = 1; k < N; ++k) {
    if (!res.multiview.posed[k])
      continue;
    Rigid M = rigidFromVisp(res.multiview.cMc0[k]);
    M.t *= s;
    res.measurements.push_back(poseMeasurement(cal[k].q, cal[0].q, toVisp(M), M.t.norm(), c.options));
  }
  c.report("identification from the multi-view poses", 0, 1);
  const vpKinematicChain at = decisionModel(c);
  std::map<int, vpColVector> set_points = pointsInF(res, at.get_fMc(cal[0].q), s);
  if (c.mode == vpRobotSelfCalibration::FOCAL_KNOWN) {
    std::vector<Rigid> fMc;
    for (const View &v : cal)
      fMc.push_back(rigidFromVisp(at.get_fMc(v.q)));
    PredictedStart p = predictedStart(cal, fMc, lensOf(c.dataset), true);
    if (p.ok)
      set_points = std::move(p.points);
  }
  const SetDecision d{at, set_points, s, res.multiview.fx};
  // The robot's error yet to be measured (the prior's level, a guess: robotLevelGuessed()): the
  // set decided again at the level the adjustment measured (dropped: a trusted run's), and when it
  // differs the adjustment runs again on it from that level.
  const vpKinematicIdentification::Identifiability first = decideSet(c, d, c.noise);
  if (!identifyAndAdjust(c, d, first, res, ts) || !robotLevelGuessed(c.noise))
    return;
  // Measured beyond a real arm's, or not measured (the corrections at the prior's level leave the
  // estimate undetermined): vpRobotSelfCalibration::run() makes the trusted run instead
  // (robot-error-taken-exact, robot-error-not-measured), from the top.
  if (robotErrorNotMeasured(res.bundle.noise) ||
      robotErrorImplausible(res.bundle.noise, res.bundle, cal, &res.joint_error_structure))
    return;
  const vpKinematicIdentification::Identifiability again = decideSet(c, d, res.bundle.noise);
  // The model residual merged into the joints (robot_error_confounded) stays merged from that level.
  const bool confounded = res.bundle.robot_error_confounded;
  if (again.identified != first.identified && adjustAgain(Context(c, res.bundle.noise, false), d, again, res))
    res.bundle.robot_error_confounded = res.bundle.robot_error_confounded || confounded;
}
} // namespace vpSelfCalibPipeline
