/*
 * ViSP SelfCalib: the paper's self-calibration procedure (Section 4.1, steps 2-5).
 */
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <sstream>

#include "../core/vpSelfCalibMath.h"
#include "../core/vpSelfCalibRandom.h"

#include <opencv2/calib3d.hpp>

using namespace vpSelfCalib;

namespace
{
// Correspondences of two views by scene id.
void correspondences(const vpSelfCalibDataset::View &a, const vpSelfCalibDataset::View &b,
                     std::vector<vpImagePoint> &pa, std::vector<vpImagePoint> &pb)
{
  std::map<int, vpImagePoint> second;
  for (const auto &o : b.points)
    second[o.id] = o.ip;
  pa.clear();
  pb.clear();
  for (const auto &o : a.points) {
    auto it = second.find(o.id);
    if (it != second.end()) {
      pa.push_back(o.ip);
      pb.push_back(it->second);
    }
  }
}

bool findPoint(const vpSelfCalibDataset::View &v, int id, vpImagePoint &ip)
{
  for (const auto &o : v.points)
    if (o.id == id) {
      ip = o.ip;
      return true;
    }
  return false;
}
double seconds(const std::chrono::steady_clock::time_point &since)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

/*
  A field that a builder derives from another setting: accepted when the caller left it at its
  default or set it to the derived value (a builder's output put back), a conflict otherwise.
  Returns the derived value.
*/
template <typename T>
T derived(const T &set, const T &default_value, const T &value, const char *field, const char *source)
{
  if (set == default_value || set == value)
    return value;
  std::ostringstream os;
  os << std::boolalpha << "vpRobotSelfCalibration: " << field << " (" << set << ") is derived from " << source
     << " (" << value << ") and not read: set " << source << " instead, or leave " << field << " at its default";
  throw vpSelfCalibException(vpSelfCalibException::badValue, os.str());
}

// Every field of two two-view options equal.
bool same(const vpTwoViewEstimator::Options &a, const vpTwoViewEstimator::Options &b)
{
  return a.focal_mode == b.focal_mode && a.fx == b.fx && a.u0 == b.u0 && a.v0 == b.v0 && a.mu == b.mu &&
         a.ransac.inlier_threshold == b.ransac.inlier_threshold && a.ransac.confidence == b.ransac.confidence &&
         a.ransac.max_iterations == b.ransac.max_iterations && a.ransac.seed == b.ransac.seed &&
         a.refine == b.refine && a.huber == b.huber && a.planar_ratio == b.planar_ratio &&
         a.min_coplanarity == b.min_coplanarity && a.rotation_tolerance == b.rotation_tolerance &&
         a.max_fx_relative_sd == b.max_fx_relative_sd;
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
  if (!(pixel_sd > 0))
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpRobotSelfCalibration: pixel_sd must be positive");
  if (num_calibration_poses < 3)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpRobotSelfCalibration: num_calibration_poses must be at least 3");
  if (!(pose_sd_rotation > 0 && pose_sd_direction > 0))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpRobotSelfCalibration: pose_sd_rotation and pose_sd_direction must be positive");
  if (!(outlier_warning > 0 && outlier_warning <= 1 && min_posed_fraction >= 0 && min_posed_fraction <= 1 &&
        max_outlier_fraction > 0 && max_outlier_fraction <= 1))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpRobotSelfCalibration: outlier_warning, min_posed_fraction and max_outlier_fraction "
                               "must be fractions in (0, 1]");
  identification.check();
  bundle.check();
  data_check.check();
  // The derived fields that conflict whatever the dataset (the builders find the others).
  derived(data_check.pixel_sd, vpSelfCalibDataCheck::Options().pixel_sd, pixel_sd, "data_check.pixel_sd", "pixel_sd");
  derived(multiview.pixel_sd, vpMultiViewReconstruction::Options().pixel_sd, pixel_sd, "multiview.pixel_sd",
          "pixel_sd");
  const vpKinematicBundleAdjustment::Options bundle_default;
  derived(bundle.pixel_sd, bundle_default.pixel_sd, pixel_sd, "bundle.pixel_sd", "pixel_sd");
  derived(bundle.hand_eye_only, bundle_default.hand_eye_only, method == HAND_EYE, "bundle.hand_eye_only", "method");
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
  const vpTwoViewEstimator::Options def;
  const char *camera = "the dataset's camera";
  vpTwoViewEstimator::Options to = opt.twoview;
  to.fx = derived(opt.twoview.fx, def.fx, ds.cam.get_px(), "twoview.fx", camera);
  to.u0 = derived(opt.twoview.u0, def.u0, ds.cam.get_u0(), "twoview.u0", camera);
  to.v0 = derived(opt.twoview.v0, def.v0, ds.cam.get_v0(), "twoview.v0", camera);
  to.mu = derived(opt.twoview.mu, def.mu, ds.cam.get_py() / ds.cam.get_px(), "twoview.mu", camera);
  to.focal_mode = derived(opt.twoview.focal_mode, def.focal_mode,
                          known ? vpRefinedFactorMethod::KNOWN : vpRefinedFactorMethod::PER_PAIR,
                          "twoview.focal_mode", "focal_mode");
  return to;
}

vpMultiViewReconstruction::Options vpRobotSelfCalibration::multiViewOptions(const Options &opt,
                                                                             const vpSelfCalibDataset &ds)
{
  const vpMultiViewReconstruction::Options def;
  vpMultiViewReconstruction::Options mo = opt.multiview;
  mo.twoview = twoViewOptions(opt, ds);
  if (!same(opt.multiview.twoview, def.twoview) && !same(opt.multiview.twoview, mo.twoview))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpRobotSelfCalibration: multiview.twoview is derived from twoview and the dataset "
                               "(twoViewOptions()) and not read: set twoview instead, or leave multiview.twoview "
                               "at its default");
  mo.focal_known = derived(opt.multiview.focal_known, def.focal_known, resolveFocalMode(opt, ds) == FOCAL_KNOWN,
                           "multiview.focal_known", "focal_mode");
  mo.pixel_sd = derived(opt.multiview.pixel_sd, def.pixel_sd, opt.pixel_sd, "multiview.pixel_sd", "pixel_sd");
  return mo;
}

vpKinematicBundleAdjustment::Options vpRobotSelfCalibration::bundleOptions(const Options &opt,
                                                                            const vpSelfCalibDataset &ds)
{
  const unsigned int FX = vpKinematicBundleAdjustment::FX;
  const vpKinematicBundleAdjustment::Options def;
  vpKinematicBundleAdjustment::Options bo = opt.bundle;
  bo.pixel_sd = derived(opt.bundle.pixel_sd, def.pixel_sd, opt.pixel_sd, "bundle.pixel_sd", "pixel_sd");
  const bool fx = derived((opt.bundle.intrinsics & FX) != 0, (def.intrinsics & FX) != 0,
                          resolveFocalMode(opt, ds) != FOCAL_KNOWN, "the FX flag of bundle.intrinsics", "focal_mode");
  if (fx)
    bo.intrinsics |= FX;
  else
    bo.intrinsics &= ~FX;
  bo.hand_eye_only =
      derived(opt.bundle.hand_eye_only, def.hand_eye_only, opt.method == HAND_EYE, "bundle.hand_eye_only", "method");
  return bo;
}

vpSelfCalibDataCheck::Options vpRobotSelfCalibration::dataCheckOptions(const Options &opt)
{
  vpSelfCalibDataCheck::Options co = opt.data_check;
  co.pixel_sd = derived(opt.data_check.pixel_sd, vpSelfCalibDataCheck::Options().pixel_sd, opt.pixel_sd,
                        "data_check.pixel_sd", "pixel_sd");
  return co;
}

vpRobotSelfCalibration::Result vpRobotSelfCalibration::run(const vpKinematicChain &nominal,
                                                           const vpSelfCalibDataset &ds, const Options &opt,
                                                           const Progress &progress)
{
  const auto t0 = std::chrono::steady_clock::now();
  opt.check();
  const unsigned int N = std::min<unsigned int>(opt.num_calibration_poses, static_cast<unsigned int>(ds.views.size()));
  if (N < 3)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpRobotSelfCalibration: the dataset has " + std::to_string(ds.views.size()) +
                                   " views; at least 3 calibration views are needed");
  for (size_t k = 0; k < ds.views.size(); ++k) {
    if (opt.method == HAND_EYE && ds.views[k].has_fMe && ds.views[k].q.size() == 0) {
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
  if (opt.method == PAPER && !ds.yardstick.isSet())
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpRobotSelfCalibration: the dataset has no yardstick (length and two end ids); "
                               "the scale cannot be fixed without it");
  const FocalMode mode = resolveFocalMode(opt, ds);
  // The remaining caller mistakes (derived options set against their source) throw before any work.
  twoViewOptions(opt, ds);
  multiViewOptions(opt, ds);
  bundleOptions(opt, ds);

  Result res;
  res.method = opt.method;
  res.calibrated = nominal;
  res.camera = ds.cam;
  res.findings = vpSelfCalibDataCheck::check(nominal, ds, N, opt.method == HAND_EYE, dataCheckOptions(opt));
  if (vpSelfCalibDataCheck::degenerate(res.findings)) {
    res.status = DEGENERATE_DATA;
    for (const auto &f : res.findings)
      if (f.severity == vpSelfCalibDataCheck::DEGENERATE)
        res.message += (res.message.empty() ? "" : "; ") + f.message;
    res.seconds = seconds(t0);
    return res;
  }
  if (opt.method == BUNDLE_ADJUSTMENT)
    runBundle(nominal, ds, opt, N, progress, res);
  else if (opt.method == HAND_EYE)
    runHandEye(nominal, ds, opt, N, progress, res);
  else
    runPaper(nominal, ds, opt, mode, N, progress, res);
  checkResult(nominal, ds, opt, N, res);
  if (res.status != OK) {
    // What the checks found often explains the failure: say it with the failure.
    for (const auto &f : res.findings)
      res.message += "; " + f.message;
    res.seconds = seconds(t0);
    return res;
  }

  // Step 5: verification on the remaining views.
  if (ds.views.size() >= N + 2) {
    if (progress)
      progress("verification", 0, 1);
    const auto tv = std::chrono::steady_clock::now();
    const std::vector<vpSelfCalibDataset::View> ver(ds.views.begin() + N, ds.views.end());
    res.before = vpCalibrationVerifier::verify(nominal, ds.cam, ver, ds.yardstick);
    res.after = vpCalibrationVerifier::verify(res.calibrated, res.camera, ver, ds.yardstick);
    res.verified = true;
    res.stage_seconds.push_back({"verification", seconds(tv)});
  }
  res.seconds = seconds(t0);
  return res;
}

void vpRobotSelfCalibration::checkResult(const vpKinematicChain &nominal, const vpSelfCalibDataset &ds,
                                         const Options &opt, unsigned int N, Result &res)
{
  using Finding = vpSelfCalibDataCheck::Finding;
  // Data left unused: observations rejected as wrong matches, or on points the reconstruction could
  // not place. Many of them mean a poor front end.
  unsigned int total = 0;
  for (unsigned int k = 0; k < N; ++k)
    total += static_cast<unsigned int>(ds.views[k].points.size());
  const unsigned int kept = res.bundle.num_observations;
  if (opt.method != PAPER && kept > 0 && total > kept && total - kept > opt.outlier_warning * total) {
    std::ostringstream os;
    os << total - kept << " of " << total << " observations of the calibration poses ("
       << static_cast<int>(std::lround(100.0 * (total - kept) / total))
       << "%) were not used: rejected as wrong matches, or on points the reconstruction could not place; check the "
          "correspondences (ratio test, geometric verification, the dot detection) and that every pose's joints "
          "belong to its image";
    res.findings.push_back(Finding{vpSelfCalibDataCheck::WARNING, "outliers", os.str()});
  }
  // A yardstick in the data that the bundle adjustment could not use.
  const bool unseen = std::any_of(res.findings.begin(), res.findings.end(),
                                  [](const Finding &f) { return f.code == "yardstick-unseen"; });
  if (res.status == OK && opt.method == BUNDLE_ADJUSTMENT && ds.yardstick.isSet() && !unseen &&
      res.bundle.scale_source == vpKinematicBundleAdjustment::SCALE_NOMINAL)
    res.findings.push_back(Finding{vpSelfCalibDataCheck::WARNING, "yardstick-unused",
                                   "the yardstick is in the data but its points were rejected (wrong matches, or "
                                   "not placed by the reconstruction): the scale is the nominal model's; check the "
                                   "yardstick's observations"});
  if (res.status != OK || opt.method == HAND_EYE)
    return;
  // Parameters that poses spread over the joint ranges identify but these poses do not.
  vpSelfCalib::Random rng(0x5e1fca1b, 1);
  std::vector<vpKinematicIdentification::Measurement> rich;
  vpColVector q0(nominal.getNumJoints());
  for (unsigned int k = 0; k <= 4 * nominal.getNumJoints() + 6; ++k) {
    vpColVector q(nominal.getNumJoints());
    for (unsigned int j = 0; j < q.size(); ++j)
      q[j] = rng.uniform(nominal.getJoints()[j].min, nominal.getJoints()[j].max);
    if (k == 0) {
      q0 = q;
      continue;
    }
    vpKinematicIdentification::Measurement m;
    m.q = q;
    m.q_ref = q0;
    m.M = nominal.get_fMc(q).inverse() * nominal.get_fMc(q0);
    rich.push_back(m);
  }
  vpKinematicIdentification::Options io = opt.identification;
  for (const std::string &f : opt.bundle.fixed)
    io.fixed.push_back(f);
  const auto best = vpKinematicIdentification::analyse(nominal, rich, io);
  std::vector<std::string> lost;
  for (unsigned int i : best.identified)
    if (std::find(res.identifiability.identified.begin(), res.identifiability.identified.end(), i) ==
        res.identifiability.identified.end())
      lost.push_back(nominal.getParameterNames()[i]);
  if (res.identifiability.identified.size() < best.identified.size()) {
    std::ostringstream os;
    os << "these " << N << " poses identify " << res.identifiability.identified.size()
       << " parameters, poses spread over the joint ranges " << best.identified.size() << " (not identified here:";
    for (size_t k = 0; k < lost.size() && k < 6; ++k)
      os << " " << lost[k];
    os << (lost.size() > 6 ? " ...)" : ")") << ": add poses that move every joint, with rotations of 10 deg or more";
    res.findings.push_back(Finding{vpSelfCalibDataCheck::WARNING, "identifiability-lost", os.str()});
  }
}

void vpRobotSelfCalibration::runPaper(const vpKinematicChain &nominal, const vpSelfCalibDataset &ds, const Options &opt,
                                      FocalMode mode, unsigned int N, const Progress &progress, Result &res)
{
  auto ts = std::chrono::steady_clock::now();

  // Step 2: pose measurements on the pairs (1, i).
  const vpTwoViewEstimator::Options to = twoViewOptions(opt, ds);
  std::vector<std::vector<vpImagePoint>> p1(N - 1), p2(N - 1);
  for (unsigned int i = 1; i < N; ++i)
    correspondences(ds.views[0], ds.views[i], p1[i - 1], p2[i - 1]);
  if (mode == FOCAL_SHARED) {
    if (progress)
      progress("pose measurements (shared focal length)", 0, N - 1);
    const vpTwoViewEstimator::SharedResult sr = vpTwoViewEstimator::estimateShared(p1, p2, to);
    res.pairs = sr.pairs;
    if (!sr.converged) {
      res.status = TWO_VIEW_FAILED;
      res.message = "shared focal length: " + sr.message;
      return;
    }
    res.fx = sr.fx;
    res.fx_sd = sr.fx_sd;
  } else {
    std::vector<double> focals;
    for (unsigned int i = 1; i < N; ++i) {
      if (progress)
        progress("pose measurements", i - 1, N - 1);
      res.pairs.push_back(vpTwoViewEstimator::estimate(p1[i - 1], p2[i - 1], to));
      if (res.pairs.back().status == vpTwoViewEstimator::OK)
        focals.push_back(res.pairs.back().fx);
    }
    if (mode == FOCAL_KNOWN)
      res.fx = ds.cam.get_px();
    else if (!focals.empty()) {
      std::nth_element(focals.begin(), focals.begin() + focals.size() / 2, focals.end());
      res.fx = focals[focals.size() / 2];
    }
  }
  if (res.fx > 0)
    res.camera.initPersProjWithoutDistortion(res.fx, res.fx * to.mu, to.u0, to.v0);

  res.stage_seconds.push_back({"two-view poses", seconds(ts)});
  ts = std::chrono::steady_clock::now();

  // Step 3: eq. 21 ratios from the nominal model.
  std::vector<vpColVector> qcal;
  for (unsigned int i = 0; i < N; ++i)
    qcal.push_back(ds.views[i].q);
  res.ratios = vpPoseScale::nominalRatios(nominal, qcal);

  // Step 4: the global scale from the yardstick seen in the pairs with a pose.
  std::vector<vpPoseScale::YardstickView> yv;
  vpImagePoint a1, b1;
  const bool in_first = findPoint(ds.views[0], ds.yardstick.id_a, a1) && findPoint(ds.views[0], ds.yardstick.id_b, b1);
  for (unsigned int i = 1; i < N && in_first; ++i) {
    const vpTwoViewEstimator::Result &r = res.pairs[i - 1];
    vpPoseScale::YardstickView v;
    if (r.status != vpTwoViewEstimator::OK || !findPoint(ds.views[i], ds.yardstick.id_a, v.a2) ||
        !findPoint(ds.views[i], ds.yardstick.id_b, v.b2))
      continue;
    v.c2Mc1 = r.c2Mc1;
    v.ratio = res.ratios[i - 1];
    v.a1 = a1;
    v.b1 = b1;
    yv.push_back(v);
  }
  if (res.fx > 0) {
    res.scale = vpPoseScale::yardstick(yv, ds.yardstick.length, res.fx, to.u0, to.v0, to.mu);
  }
  if (res.scale.status != vpPoseScale::OK) {
    res.status = SCALE_FAILED;
    res.message = yv.empty() ? "the yardstick is not seen in both images of any pair with a pose measurement "
                               "(it must be seen in the first view and at least one other)"
                             : "yardstick: " + res.scale.message;
    return;
  }

  // Scaled pose measurements (paper: c_iMc_1 with |T_i| = ratio_i |k_1|).
  for (unsigned int i = 1; i < N; ++i) {
    const vpTwoViewEstimator::Result &r = res.pairs[i - 1];
    if (r.status != vpTwoViewEstimator::OK)
      continue;
    Rigid M = rigidFromVisp(r.c2Mc1);
    const double norm = res.ratios[i - 1] * res.scale.scale;
    M.t = M.t.normalized() * norm;
    vpKinematicIdentification::Measurement m;
    m.q = ds.views[i].q;
    m.q_ref = ds.views[0].q;
    m.M = toVisp(M);
    m.sd_rotation = opt.pose_sd_rotation;
    m.sd_position = std::max(1e-6, norm * opt.pose_sd_direction);
    res.measurements.push_back(m);
  }
  if (res.measurements.empty()) {
    res.status = TWO_VIEW_FAILED;
    res.message = "no pair gave a pose measurement";
    return;
  }

  res.stage_seconds.push_back({"scale", seconds(ts)});
  ts = std::chrono::steady_clock::now();

  // Identification from the nominal model.
  if (progress)
    progress("identification", 0, 1);
  res.identification = vpKinematicIdentification::identify(nominal, res.measurements, opt.identification);
  res.calibrated = res.identification.chain;
  if (res.identification.status != vpKinematicIdentification::OK) {
    res.stage_seconds.push_back({"identification", seconds(ts)});
    res.status = IDENTIFICATION_FAILED;
    res.message = res.identification.message;
    return;
  }

  res.stage_seconds.push_back({"identification", seconds(ts)});
  res.identifiability = res.identification.identifiability;
  res.parameter_sd = res.identification.sd;
  res.status = OK;
  std::ostringstream os;
  os << "ok: " << res.measurements.size() << " pose measurements, " << res.identification.identifiability.identified.size()
     << " parameters identified";
  res.message = os.str();
}

void vpRobotSelfCalibration::runBundle(const vpKinematicChain &nominal, const vpSelfCalibDataset &ds, const Options &opt,
                                       unsigned int N, const Progress &progress, Result &res)
{
  auto ts = std::chrono::steady_clock::now();
  const std::vector<vpSelfCalibDataset::View> cal(ds.views.begin(), ds.views.begin() + N);

  // 1. Scale-consistent poses and points of the calibration views, one focal length.
  if (!multiView(ds, cal, opt, progress, res))
    return;
  res.fx = res.multiview.fx;
  res.fx_sd = res.multiview.fx_sd;
  ts = std::chrono::steady_clock::now();

  // Without the yardstick, the unit is the reference pair's baseline: give it the nominal length.
  double s = 1;
  if (!res.multiview.metric) {
    const unsigned int r = res.multiview.reference_view;
    const double nominal_baseline =
        (nominal.get_fMc(cal[r].q).inverse() * nominal.get_fMc(cal[0].q)).getTranslationVector().frobeniusNorm();
    s = nominal_baseline / res.multiview.cMc0[r].getTranslationVector().frobeniusNorm();
  }

  // 2. Pose-based identification from the multi-view poses: the start of the bundle adjustment.
  for (unsigned int k = 1; k < N; ++k) {
    if (!res.multiview.posed[k])
      continue;
    Rigid M = rigidFromVisp(res.multiview.cMc0[k]);
    M.t *= s;
    vpKinematicIdentification::Measurement me;
    me.q = cal[k].q;
    me.q_ref = cal[0].q;
    me.M = toVisp(M);
    me.sd_rotation = opt.pose_sd_rotation;
    me.sd_position = std::max(1e-6, M.t.norm() * opt.pose_sd_direction);
    res.measurements.push_back(me);
  }
  if (progress)
    progress("identification from the multi-view poses", 0, 1);
  res.identification = vpKinematicIdentification::identify(nominal, res.measurements, opt.identification);
  const vpKinematicChain start =
      res.identification.status == vpKinematicIdentification::OK ? res.identification.chain : nominal;
  res.stage_seconds.push_back({"identification", seconds(ts)});

  // 3. Kinematic bundle adjustment, points moved to f through the start model.
  vpKinematicBundleAdjustment::Options bo = bundleOptions(opt, ds);
  // The same estimated set as the identification that gave the start (the others are still at the
  // nominal values); QR pivoting at the start model could pick another, equivalent set, and the
  // parameters left out would then keep the identification's values.
  if (res.identification.status == vpKinematicIdentification::OK)
    for (const auto &u : res.identification.identifiability.unidentifiable)
      if (std::find(bo.fixed.begin(), bo.fixed.end(), u.name) == bo.fixed.end())
        bo.fixed.push_back(u.name);
  if (!bundle(start, start.get_fMc(cal[0].q), s, cal, ds, opt, bo, "kinematic bundle adjustment", progress, res))
    return;
  // The parameters fixed above because the identification found them dependent keep its reason.
  for (auto &u : res.identifiability.unidentifiable)
    for (const auto &v : res.identification.identifiability.unidentifiable)
      if (u.name == v.name && std::find(opt.bundle.fixed.begin(), opt.bundle.fixed.end(), u.name) == opt.bundle.fixed.end())
        u.reason = v.reason;
}

bool vpRobotSelfCalibration::bundle(const vpKinematicChain &start, const vpHomogeneousMatrix &fMc0_, double s,
                                    const std::vector<vpSelfCalibDataset::View> &views, const vpSelfCalibDataset &ds,
                                    const Options &opt, const vpKinematicBundleAdjustment::Options &bo,
                                    const std::string &label, const Progress &progress, Result &res)
{
  if (progress)
    progress(label, 0, 1);
  const Rigid fMc0 = rigidFromVisp(fMc0_);
  std::map<int, vpColVector> points;
  for (const auto &e : res.multiview.points) {
    const Eigen::Vector3d x = fMc0 * (s * vec3(e.second));
    vpColVector v(3);
    for (unsigned int a = 0; a < 3; ++a)
      v[a] = x(a);
    points[e.first] = v;
  }
  vpCameraParameters cam0 = ds.cam;
  cam0.initPersProjWithoutDistortion(res.multiview.fx, res.multiview.fx * ds.cam.get_py() / ds.cam.get_px(),
                                     ds.cam.get_u0(), ds.cam.get_v0());
  res.bundle = vpKinematicBundleAdjustment::adjust(start, cam0, views, ds.yardstick, points, bo);
  res.stage_seconds.push_back({label, res.bundle.seconds_solve});
  res.stage_seconds.push_back({"covariance", res.bundle.seconds_covariance});
  res.calibrated = res.bundle.chain;
  res.camera = res.bundle.camera;
  res.identifiability = res.bundle.identifiability;
  res.parameter_sd = res.bundle.sd;
  if (res.bundle.status != vpKinematicBundleAdjustment::OK) {
    res.status = IDENTIFICATION_FAILED;
    res.message = label + ": " + res.bundle.message;
    return false;
  }
  unsigned int total = 0;
  for (const auto &v : views)
    total += static_cast<unsigned int>(v.points.size());
  if (total > res.bundle.num_observations && total - res.bundle.num_observations > opt.max_outlier_fraction * total) {
    std::ostringstream os;
    os << label << ": " << total - res.bundle.num_observations << " of " << total
       << " observations were not used (rejected as wrong matches, or on points the reconstruction could not "
          "place), more than "
       << std::lround(100 * opt.max_outlier_fraction) << "%: a model resting on the rest is not trusted";
    res.status = IDENTIFICATION_FAILED;
    res.message = os.str();
    return false;
  }
  res.fx = res.camera.get_px();
  res.fx_sd = res.bundle.fx_sd;
  res.status = OK;
  res.message = "multi-view " + res.multiview.message + "; " + label + " " + res.bundle.message;
  return true;
}

bool vpRobotSelfCalibration::multiView(const vpSelfCalibDataset &ds, const std::vector<vpSelfCalibDataset::View> &cal,
                                       const Options &opt, const Progress &progress, Result &res)
{
  if (progress)
    progress("multi-view reconstruction", 0, 1);
  res.multiview = vpMultiViewReconstruction::reconstruct(cal, ds.yardstick, multiViewOptions(opt, ds));
  res.pairs = res.multiview.pairs;
  res.stage_seconds.push_back({"two-view poses", res.multiview.seconds_twoview});
  res.stage_seconds.push_back({"multi-view bundle adjustment", res.multiview.seconds_bundle});
  if (res.multiview.status != vpMultiViewReconstruction::OK) {
    res.status = TWO_VIEW_FAILED;
    res.message = std::string("multi-view reconstruction: ") + res.multiview.message;
    return false;
  }
  const unsigned int posed =
      static_cast<unsigned int>(std::count(res.multiview.posed.begin(), res.multiview.posed.end(), true));
  const unsigned int needed = std::max<unsigned int>(
      3, static_cast<unsigned int>(std::ceil(opt.min_posed_fraction * static_cast<double>(cal.size()))));
  if (posed < needed) {
    res.status = TWO_VIEW_FAILED;
    res.message = "multi-view reconstruction: only " + std::to_string(posed) + " of " + std::to_string(cal.size()) +
                  " calibration views could be placed (" + std::to_string(needed) +
                  " needed): too many wrong matches, or too little overlap between the views";
    return false;
  }
  res.fx = res.multiview.fx;
  res.fx_sd = res.multiview.fx_sd;
  return true;
}

void vpRobotSelfCalibration::runHandEye(const vpKinematicChain &nominal, const vpSelfCalibDataset &ds, const Options &opt,
                                        unsigned int N, const Progress &progress, Result &res)
{
  const std::vector<vpSelfCalibDataset::View> cal(ds.views.begin(), ds.views.begin() + N);
  if (!multiView(ds, cal, opt, progress, res))
    return;
  auto ts = std::chrono::steady_clock::now();
  std::vector<Rigid> fMe;
  for (const auto &v : cal)
    fMe.push_back(rigidFromVisp(v.has_fMe ? v.fMe : nominal.get_fMe(v.q)));

  // Metric unit: the yardstick, else the end-effector baseline of the reference pair with the model's eMc.
  const Rigid eMc0 = rigidFromVisp(nominal.get_eMc_corrected());
  double s = 1;
  if (!res.multiview.metric) {
    const unsigned int r = res.multiview.reference_view;
    const double baseline = ((fMe[r] * eMc0).inverse() * (fMe[0] * eMc0)).t.norm();
    s = baseline / res.multiview.cMc0[r].getTranslationVector().frobeniusNorm();
  }
  // First eMc: Tsai's closed form (OpenCV) from the end-effector and scene-to-camera poses.
  vpKinematicChain start = nominal;
  std::vector<cv::Mat> Rg, tg, Rt, tt;
  for (unsigned int k = 0; k < N; ++k) {
    if (!res.multiview.posed[k])
      continue;
    const Rigid c = rigidFromVisp(res.multiview.cMc0[k]);
    cv::Mat a(3, 3, CV_64F), b(3, 1, CV_64F), c3(3, 3, CV_64F), d(3, 1, CV_64F);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        a.at<double>(i, j) = fMe[k].R(i, j);
        c3.at<double>(i, j) = c.R(i, j);
      }
      b.at<double>(i) = fMe[k].t(i);
      d.at<double>(i) = s * c.t(i);
    }
    Rg.push_back(a);
    tg.push_back(b);
    Rt.push_back(c3);
    tt.push_back(d);
  }
  if (Rg.size() >= 3) {
    cv::Mat R, t;
    cv::calibrateHandEye(Rg, tg, Rt, tt, R, t, cv::CALIB_HAND_EYE_TSAI);
    Rigid eMc;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j)
        eMc.R(i, j) = R.at<double>(i, j);
      eMc.t(i) = t.at<double>(i);
    }
    // As a correction of the model's eMc: eMc_nominal D = eMc.
    const Rigid D = rigidFromPose(nominal.get_eMc_pose()).inverse() * eMc;
    const Eigen::Vector3d r = logSO3(D.R);
    const unsigned int first = nominal.getNumParameters() - vpKinematicChain::kBlockSize;
    vpColVector p = nominal.getParameters();
    for (unsigned int i = 0; i < 3; ++i) {
      p[first + i] = D.t(i);
      p[first + 3 + i] = r(i);
    }
    if (D.t.allFinite() && r.allFinite() && D.t.norm() < 1.0)
      start.setParameters(p);
  }
  res.stage_seconds.push_back({"hand-eye closed form", seconds(ts)});

  // Kinematic bundle adjustment in hand-eye-only mode (bundleOptions), points moved to f through the first eMc.
  std::vector<vpSelfCalibDataset::View> views = cal;
  for (unsigned int k = 0; k < N; ++k)
    if (!views[k].has_fMe) {
      views[k].has_fMe = true;
      views[k].fMe = toVisp(fMe[k]);
    }
  bundle(start, toVisp(fMe[0]) * start.get_eMc_corrected(), s, views, ds, opt, bundleOptions(opt, ds),
         "hand-eye bundle adjustment", progress, res);
}
