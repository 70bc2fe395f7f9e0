/*
 * ViSP SelfCalib: the steps the self-calibration pipelines share (data check, view split,
 * multi-view reconstruction, kinematic bundle adjustment, result check, verification).
 */
#include "vpSelfCalibPipelines.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "../core/vpSelfCalibMath.h"
#include "../core/vpSelfCalibCamera.h"
#include "../core/vpSelfCalibGeometry.h"

using namespace vpSelfCalib;

namespace vpSelfCalibPipeline
{
namespace
{
using Finding = vpSelfCalibDataCheck::Finding;

// Data left unused: observations rejected as wrong matches, or on points the reconstruction could
// not place. Many of them mean a poor front end.
void findOutliers(const Context &c, Result &res)
{
  const unsigned int total = countObservations(c.calibration);
  const unsigned int kept = res.bundle.num_observations;
  if (c.options.method != vpRobotSelfCalibration::PAPER && kept > 0 && total > kept &&
      total - kept > c.options.outlier_warning * total) {
    std::ostringstream os;
    os << total - kept << " of " << total << " observations of the calibration poses ("
       << static_cast<int>(std::lround(100.0 * (total - kept) / total))
       << "%) were not used: rejected as wrong matches, or on points the reconstruction could not place; check the "
          "correspondences (ratio test, geometric verification, the dot detection) and that every pose's joints "
          "belong to its image";
    res.findings.push_back(Finding{vpSelfCalibDataCheck::WARNING, "outliers", os.str()});
  }
}

// No yardstick in the data: the bundle method keeps the nominal model's scale, known to its lengths'
// tolerances; the sd count it (vpKinematicBundleAdjustment::Result::nominal_scale_sd).
void findScaleNominal(const Context &c, Result &res)
{
  if (res.status != vpRobotSelfCalibration::OK || c.options.method != vpRobotSelfCalibration::BUNDLE_ADJUSTMENT ||
      c.dataset.yardstick.isSet() || res.bundle.scale_source != vpKinematicBundleAdjustment::SCALE_NOMINAL)
    return;
  std::ostringstream os;
  os << "no yardstick in the data: the scale is the nominal model's, known to ";
  if (res.bundle.nominal_scale_sd > 0) {
    os.setf(std::ios::fixed);
    os.precision(2);
    os << 100.0 * res.bundle.nominal_scale_sd << " % (1 sd, from its lengths' tolerances: a camera motion of 0.5 m "
       << "to +- " << 500.0 * res.bundle.nominal_scale_sd << " mm)";
  } else
    os << "its lengths' tolerances";
  os << "; every length calibrated (link lengths, eMc's translation, the scene) carries that error, which the "
        "reported sd count; show a yardstick (two points a known distance apart, or a board with --board) in two "
        "views or more to measure lengths better than the nominal model";
  res.findings.push_back(Finding{vpSelfCalibDataCheck::WARNING, "scale-nominal", os.str()});
}

// A yardstick in the data that the bundle adjustment could not use.
void findYardstickUnused(const Context &c, Result &res)
{
  const bool unseen = std::any_of(res.findings.begin(), res.findings.end(),
                                  [](const Finding &f) { return f.code == "yardstick-unseen"; });
  if (res.status == vpRobotSelfCalibration::OK && c.options.method == vpRobotSelfCalibration::BUNDLE_ADJUSTMENT &&
      c.dataset.yardstick.isSet() && !unseen && res.bundle.scale_source == vpKinematicBundleAdjustment::SCALE_NOMINAL)
    res.findings.push_back(Finding{vpSelfCalibDataCheck::WARNING, "yardstick-unused",
                                   "the yardstick is in the data but its points were rejected (wrong matches, or "
                                   "not placed by the reconstruction): the scale is the nominal model's; check the "
                                   "yardstick's observations"});
  // Hand-eye, the camera on the flange: the robot's motion sets the scale and the yardstick is measured
  // against it (no known layout); ends whose observations contradict the robot at the declared length
  // are rejected.
  if (res.status == vpRobotSelfCalibration::OK && c.options.method == vpRobotSelfCalibration::HAND_EYE &&
      c.dataset.camera_mount == vpSelfCalibDataset::CAMERA_ON_EFFECTOR && c.dataset.yardstick.isSet() && !unseen && c.options.bundle.measure_layout_scale &&
      c.bundle.known_points.empty() && res.bundle.has_covariance && !res.bundle.has_layout_scale) {
    std::ostringstream length;
    length << c.dataset.yardstick.length;
    res.findings.push_back(Finding{vpSelfCalibDataCheck::WARNING, "yardstick-unused",
                                   "the yardstick is in the data but not measured: its ends' observations were "
                                   "rejected, or are not in the adjustment (at its declared length of " +
                                       length.str() +
                                       " m they may contradict the robot's motion, which sets the scale here): "
                                       "check the yardstick's length and end ids"});
  }
}

// Parameters that poses spread over the joint ranges identify but these poses do not.
void findIdentifiabilityLost(const Context &c, Result &res)
{
  const vpKinematicChain &nominal = c.nominal;
  const std::vector<vpColVector> rich =
      vpKinematicIdentification::randomConfigurations(nominal, 4 * nominal.getNumJoints() + 7, 0x5e1fca1b, 1);
  vpKinematicIdentification::Options io = c.options.identification;
  for (const std::string &f : c.bundle.fixed)
    io.fixed.push_back(f);
  const auto best = vpKinematicIdentification::analyseConfigurations(nominal, rich, io);
  std::vector<std::string> lost;
  for (unsigned int i : best.identified)
    if (std::find(res.identifiability.identified.begin(), res.identifiability.identified.end(), i) ==
        res.identifiability.identified.end())
      lost.push_back(nominal.getParameterNames()[i]);
  if (res.identifiability.identified.size() < best.identified.size()) {
    std::ostringstream os;
    os << "these " << c.num_calibration << " poses identify " << res.identifiability.identified.size()
       << " parameters, poses spread over the joint ranges " << best.identified.size() << " (not identified here:";
    for (size_t k = 0; k < lost.size() && k < 6; ++k)
      os << " " << lost[k];
    os << (lost.size() > 6 ? " ...)" : ")") << ": add poses that move every joint, with rotations of 10 deg or more";
    res.findings.push_back(Finding{vpSelfCalibDataCheck::WARNING, "identifiability-lost", os.str()});
  }
}
} // namespace

Context::Context(const vpKinematicChain &nominal_, const vpSelfCalibDataset &dataset_,
                 const vpRobotSelfCalibration::Options &options_, unsigned int num_calibration_,
                 const vpRobotSelfCalibration::Progress &progress_, const vpKinematicChain *guess_,
                 bool eMc_from_data_)
  : nominal(nominal_), dataset(dataset_), options(options_), progress(progress_), num_calibration(num_calibration_),
    mode(vpRobotSelfCalibration::resolveFocalMode(options_, dataset_)),
    calibration(dataset_.views.begin(), dataset_.views.begin() + num_calibration_),
    verification(dataset_.views.begin() + num_calibration_, dataset_.views.end()),
    twoview(vpRobotSelfCalibration::twoViewOptions(options_, dataset_)),
    multiview(vpRobotSelfCalibration::multiViewOptions(options_, dataset_)),
    bundle(vpRobotSelfCalibration::bundleOptions(options_, dataset_)),
    data_check(vpRobotSelfCalibration::dataCheckOptions(options_)),
    noise(vpRobotSelfCalibration::noiseModel(options_, dataset_)), guess(guess_ ? *guess_ : nominal_),
    eMc_from_data(eMc_from_data_)
{
}

namespace
{
//! The bundle adjustment's options of a run whose robot error was measured: sds scaled by sigma0 above 1.
vpKinematicBundleAdjustment::Options withScaledCovariance(vpKinematicBundleAdjustment::Options o, bool robot_round)
{
  if (robot_round)
    o.scale_covariance = true;
  return o;
}
} // namespace

Context::Context(const Context &base, const vpSelfCalibNoiseModel &noise_, bool robot_round)
  : nominal(base.nominal), dataset(base.dataset), options(base.options), progress(base.progress),
    num_calibration(base.num_calibration), mode(base.mode), calibration(base.calibration),
    verification(base.verification), twoview(base.twoview), multiview(base.multiview),
    bundle(withScaledCovariance(base.bundle, robot_round)), data_check(base.data_check), noise(noise_),
    guess(base.guess), eMc_from_data(base.eMc_from_data)
{
}

void Context::report(const std::string &stage, unsigned int done, unsigned int total) const
{
  if (progress)
    progress(stage, done, total);
}

vpKinematicIdentification::Identifiability estimatedSet(const Context &c)
{
  std::vector<vpColVector> q;
  for (const View &v : c.calibration)
    q.push_back(v.q);
  vpKinematicIdentification::Options io = c.options.identification;
  for (const std::string &f : c.bundle.fixed)
    if (std::find(io.fixed.begin(), io.fixed.end(), f) == io.fixed.end())
      io.fixed.push_back(f);
  return vpKinematicIdentification::analyseConfigurations(c.nominal, q, io);
}

double seconds(const std::chrono::steady_clock::time_point &since)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

unsigned int countObservations(const std::vector<View> &views)
{
  unsigned int total = 0;
  for (const auto &v : views)
    total += static_cast<unsigned int>(v.points.size());
  return total;
}

vpKinematicIdentification::Measurement poseMeasurement(const vpColVector &q, const vpColVector &q_ref,
                                                       const vpHomogeneousMatrix &M, double translation_norm,
                                                       const vpRobotSelfCalibration::Options &options)
{
  vpKinematicIdentification::Measurement m;
  m.q = q;
  m.q_ref = q_ref;
  m.M = M;
  m.sd_rotation = options.twoview_rotation_sd;
  m.sd_position = std::max(1e-6, translation_norm * options.twoview_direction_sd);
  return m;
}

bool checkData(const Context &c, Result &res)
{
  vpSelfCalibDataCheck::Options check = c.data_check;
  if (check.known_points.empty())
    check.known_points = c.options.bundle.known_points;
  res.findings = vpSelfCalibDataCheck::check(c.nominal, c.dataset, c.num_calibration,
                                             c.options.method == vpRobotSelfCalibration::HAND_EYE, check, c.noise);
  if (!vpSelfCalibDataCheck::degenerate(res.findings))
    return true;
  res.status = vpRobotSelfCalibration::DEGENERATE_DATA;
  for (const auto &f : res.findings)
    if (f.severity == vpSelfCalibDataCheck::DEGENERATE)
      res.message += (res.message.empty() ? "" : "; ") + f.message;
  return false;
}

CameraModel lensOf(const vpSelfCalibDataset &ds)
{
  if (ds.opencv_distortion.empty())
    return CameraModel::fromVisp(ds.cam);
  return lensOf(ds.cam, ds.opencv_distortion);
}

CameraModel lensOf(const vpCameraParameters &cam, const std::vector<double> &opencv_distortion)
{
  if (opencv_distortion.empty())
    return CameraModel::fromVisp(cam);
  const CameraModel pin = CameraModel::fromVisp(cam);
  double in[kMaxIntrinsics] = {pin.px(), pin.mu(), pin.u0(), pin.v0(), 0, 0, 0, 0, 0};
  for (size_t i = 0; i < opencv_distortion.size() && i < 5; ++i)
    in[4 + i] = opencv_distortion[i];
  return CameraModel(Distortion::OPENCV, in);
}

/*
  The views with their pixels moved through the inverse of the camera's distortion (pinhole pixels
  of the same camera), for the steps that model a pinhole camera (the multi-view reconstruction);
  the views themselves when the camera has no distortion.
*/
std::vector<View> undistorted(const std::vector<View> &views, const CameraModel &camera)
{
  if (camera.distortion() == Distortion::NONE)
    return views;
  std::vector<View> out = views;
  for (View &v : out)
    for (auto &o : v.points) {
      const Eigen::Vector2d uv = camera.undistortPixel(Eigen::Vector2d(o.ip.get_u(), o.ip.get_v()));
      o.ip = vpImagePoint(uv(1), uv(0));
    }
  return out;
}

/*
  res.eMc and res.eMc_sd from the calibrated chain and the bundle adjustment's covariance: the
  Jacobian of the pose vector of eMc with respect to the six eMc corrections by central differences
  (1e-7), times their covariance (rows and columns of the estimated ones; the others are held).
*/
void handEyeWithSd(Result &res, const vpMatrix &covariance, const std::vector<std::string> &covariance_names)
{
  const vpKinematicChain &chain = res.calibrated;
  const unsigned int first = chain.getNumParameters() - vpKinematicChain::kBlockSize;
  const std::vector<std::string> names = chain.getParameterNames();
  Eigen::Matrix<double, 6, 6> S = Eigen::Matrix<double, 6, 6>::Zero();
  std::vector<int> row(6, -1);
  for (size_t r = 0; r < covariance_names.size() && r < covariance.getRows(); ++r)
    for (unsigned int i = 0; i < 6; ++i)
      if (covariance_names[r] == names[first + i])
        row[i] = static_cast<int>(r);
  for (unsigned int i = 0; i < 6; ++i)
    for (unsigned int j = 0; j < 6; ++j)
      if (row[i] >= 0 && row[j] >= 0)
        S(i, j) = covariance[static_cast<unsigned int>(row[i])][static_cast<unsigned int>(row[j])];
  Eigen::Matrix<double, 6, 6> J;
  const double h = 1e-7;
  for (unsigned int i = 0; i < 6; ++i) {
    vpKinematicChain a = chain, b = chain;
    vpColVector pa = chain.getParameters(), pb = pa;
    pa[first + i] += h;
    pb[first + i] -= h;
    a.setParameters(pa);
    b.setParameters(pb);
    const vpPoseVector A(a.get_eMc_corrected()), B(b.get_eMc_corrected());
    for (unsigned int k = 0; k < 6; ++k)
      J(k, i) = (A[k] - B[k]) / (2 * h);
  }
  const Eigen::Matrix<double, 6, 6> C = J * S * J.transpose();
  res.eMc = vpPoseVector(chain.get_eMc_corrected());
  res.eMc_sd.resize(6);
  for (unsigned int k = 0; k < 6; ++k)
    res.eMc_sd[k] = std::sqrt(std::max(0.0, C(k, k)));
  res.has_eMc = true;
}

bool multiView(const Context &c, Result &res)
{
  c.report("multi-view reconstruction", 0, 1);
  res.multiview = vpMultiViewReconstruction::reconstruct(undistorted(c.calibration, lensOf(c.dataset)),
                                                         c.dataset.yardstick, c.multiview, c.noise);
  res.pairs = res.multiview.pairs;
  res.stage_seconds.push_back({"two-view poses", res.multiview.seconds_twoview});
  res.stage_seconds.push_back({"multi-view bundle adjustment", res.multiview.seconds_bundle});
  if (res.multiview.status != vpMultiViewReconstruction::OK) {
    res.status = vpRobotSelfCalibration::TWO_VIEW_FAILED;
    res.message = std::string("multi-view reconstruction: ") + res.multiview.message;
    return false;
  }
  const size_t num_views = c.calibration.size();
  const unsigned int posed =
      static_cast<unsigned int>(std::count(res.multiview.posed.begin(), res.multiview.posed.end(), true));
  const unsigned int needed = std::max<unsigned int>(
      3, static_cast<unsigned int>(std::ceil(c.options.min_posed_fraction * static_cast<double>(num_views))));
  if (posed < needed) {
    res.status = vpRobotSelfCalibration::TWO_VIEW_FAILED;
    res.message = "multi-view reconstruction: only " + std::to_string(posed) + " of " + std::to_string(num_views) +
                  " calibration views could be placed (" + std::to_string(needed) +
                  " needed): too many wrong matches, or too little overlap between the views";
    return false;
  }
  if (!(res.multiview.fx > 0) || !std::isfinite(res.multiview.fx)) {
    // A failure of the data, not a camera to start from (with plain least squares on wrong matches
    // the focal length can end up negative).
    std::ostringstream os;
    os << "multi-view reconstruction: its focal length (" << res.multiview.fx
       << " px) is not a camera's: too many wrong matches for a non-robust loss, or too little overlap";
    res.status = vpRobotSelfCalibration::TWO_VIEW_FAILED;
    res.message = os.str();
    return false;
  }
  res.fx = res.multiview.fx;
  res.fx_sd = res.multiview.fx_sd;
  return true;
}

std::map<int, vpColVector> pointsInF(const Result &res, const vpHomogeneousMatrix &fMc0_, double s)
{
  const Rigid fMc0 = rigidFromVisp(fMc0_);
  std::map<int, vpColVector> points;
  for (const auto &e : res.multiview.points) {
    const Eigen::Vector3d x = fMc0 * (s * vec3(e.second));
    vpColVector v(3);
    for (unsigned int a = 0; a < 3; ++a)
      v[a] = x(a);
    points[e.first] = v;
  }
  return points;
}

vpCameraParameters startCamera(const Context &c, double fx0)
{
  // The dataset's camera (its distortion included) with the multi-view focal length.
  CameraModel start_camera = CameraModel::fromVisp(c.dataset.cam);
  start_camera.intrinsics()[0] = fx0;
  return start_camera.toVisp();
}

bool bundle(const Context &c, const vpKinematicChain &start, const vpHomogeneousMatrix &fMc0, double s,
            const std::vector<View> &views, const vpKinematicBundleAdjustment::Options &bo, const std::string &label,
            Result &res)
{
  return bundleFrom(c, start, pointsInF(res, fMc0, s), res.multiview.fx, views, bo, label, res);
}

bool bundleFrom(const Context &c, const vpKinematicChain &start, const std::map<int, vpColVector> &points, double fx0,
                const std::vector<View> &views, const vpKinematicBundleAdjustment::Options &bo,
                const std::string &label, Result &res)
{
  c.report(label, 0, 1);
  const vpSelfCalibDataset &ds = c.dataset;
  const vpCameraParameters cam0 = startCamera(c, fx0);
  // Without a yardstick the scale held is the nominal model's, not the start identification's (whose
  // scale follows one reconstruction's, and drifts with it).
  vpKinematicBundleAdjustment::Options o = bo;
  o.eMc_measured = c.eMc_from_data;
  if (o.scale_reference.empty() && !o.hand_eye_only && start.getNumParameters() == c.nominal.getNumParameters()) {
    const vpColVector p = c.nominal.getParameters();
    o.scale_reference.assign(p.data, p.data + p.size());
  }
  res.bundle = vpKinematicBundleAdjustment::adjust(start, cam0, views, ds.yardstick, points, o, c.noise);
  res.joint_error_structure = {}; // judged again for these corrections (robotErrorImplausible())
  res.stage_seconds.push_back({label, res.bundle.seconds_solve});
  res.stage_seconds.push_back({"covariance", res.bundle.seconds_covariance});
  res.calibrated = res.bundle.chain;
  res.camera = res.bundle.camera;
  res.identifiability = res.bundle.identifiability;
  res.parameter_sd = res.bundle.sd;
  if (res.bundle.has_covariance)
    handEyeWithSd(res, res.bundle.covariance, res.bundle.covariance_names);
  if (res.bundle.status != vpKinematicBundleAdjustment::OK) {
    res.status = vpRobotSelfCalibration::IDENTIFICATION_FAILED;
    res.message = label + ": " + res.bundle.message;
    // A camera fixed in the world, declared on the flange: the target moves with the tool, and no
    // rigid scene fits the views.
    if (res.bundle.status == vpKinematicBundleAdjustment::RANK_DEFICIENT &&
        c.dataset.camera_mount != vpSelfCalibDataset::CAMERA_IN_WORLD && !bo.eye_to_hand && !bo.controller_poses_inverted)
      res.message += "; or the dataset's camera_mount is wrong: it says effector (a camera on the flange seeing a "
                     "scene fixed in the world); a camera fixed in the world seeing a target on the tool is "
                     "camera_mount: world";
    return false;
  }
  const unsigned int total = countObservations(views);
  const double max_outlier_fraction = c.options.max_outlier_fraction;
  if (total > res.bundle.num_observations && total - res.bundle.num_observations > max_outlier_fraction * total) {
    std::ostringstream os;
    os << label << ": " << total - res.bundle.num_observations << " of " << total
       << " observations were not used (rejected as wrong matches, or on points the reconstruction could not "
          "place), more than "
       << std::lround(100 * max_outlier_fraction) << "%: a model resting on the rest is not trusted";
    res.status = vpRobotSelfCalibration::IDENTIFICATION_FAILED;
    res.message = os.str();
    return false;
  }
  res.fx = res.camera.get_px();
  res.fx_sd = res.bundle.fx_sd;
  res.status = vpRobotSelfCalibration::OK;
  res.message = "multi-view " + res.multiview.message + "; " + label + " " + res.bundle.message;
  return true;
}

namespace
{
/*
  Points triangulated (multi-ray midpoint, cheirality) from cameras at fMc through camera, and the
  median reprojection error (px) of their observations; ids seen in fewer than 2 views, or that do
  not triangulate, are left out.
*/
double triangulateAll(const std::vector<View> &views, const std::vector<Rigid> &fMc, const CameraModel &camera,
                      std::map<int, Eigen::Vector3d> &X)
{
  std::map<int, std::vector<std::pair<size_t, Eigen::Vector2d>>> seen;
  for (size_t k = 0; k < views.size(); ++k)
    for (const auto &o : views[k].points)
      seen[o.id].push_back({k, Eigen::Vector2d(o.ip.get_u(), o.ip.get_v())});
  X.clear();
  std::vector<double> errors;
  for (const auto &e : seen) {
    if (e.second.size() < 2)
      continue;
    std::vector<Ray> rays;
    for (const auto &ob : e.second)
      rays.push_back(rayThrough(fMc[ob.first], camera, ob.second));
    Eigen::Vector3d x;
    if (!triangulateMidpoint(rays, x))
      continue;
    X[e.first] = x;
    for (const auto &ob : e.second) {
      const Eigen::Vector3d xc = fMc[ob.first].inverse() * x;
      errors.push_back(inFront(xc) ? (camera.project(xc) - ob.second).norm() : 1e6);
    }
  }
  if (errors.size() < 10)
    return std::numeric_limits<double>::infinity();
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  return errors[errors.size() / 2];
}
} // namespace

double scanFocal(const FocalScore &score, double center, const FocalScore &rung_score)
{
  // A ladder of focal lengths from 0.3x to 4x center (steps of 2^(1/4)), then golden-section
  // search on log f between the best rung's neighbours. The rungs are scored from the longest focal
  // length down (where the two-view scores are cheap) and the lowest score taken, the shortest focal
  // length of equal ones; each score is bounded by the one it must beat: a rung or a point of the
  // search known to score higher is not chosen, whatever its exact score.
  const FocalScore &rung = rung_score ? rung_score : score;
  const double inf = std::numeric_limits<double>::infinity();
  double best = inf;
  int best_k = 0;
  for (int k = 8; k >= -7; --k) {
    const double e = rung(center * std::pow(2.0, k / 4.0), best);
    if (e <= best && std::isfinite(e)) {
      best = e;
      best_k = k;
    }
  }
  if (!std::isfinite(best))
    return 0;
  double a = std::log(center) + (best_k - 1) * std::log(2.0) / 4, b = a + std::log(2.0) / 2;
  const double g = (std::sqrt(5.0) - 1) / 2;
  double x1 = b - g * (b - a), x2 = a + g * (b - a), e1 = score(std::exp(x1), inf), e2 = score(std::exp(x2), e1);
  // The last step's point is not compared with anything: the bracket it narrows is the answer.
  for (int it = 0; it < 20; ++it) {
    const bool last = it == 19;
    if (e1 < e2) {
      b = x2;
      x2 = x1;
      e2 = e1;
      x1 = b - g * (b - a);
      e1 = last ? inf : score(std::exp(x1), e2);
    } else {
      a = x1;
      x1 = x2;
      e1 = e2;
      x2 = a + g * (b - a);
      e2 = last ? inf : score(std::exp(x2), e1);
    }
  }
  return std::exp(0.5 * (a + b));
}

PredictedStart predictedStart(const std::vector<View> &views, const std::vector<Rigid> &fMc, const CameraModel &lens,
                              bool focal_known)
{
  PredictedStart out;
  std::map<int, Eigen::Vector3d> X;
  CameraModel camera = lens;
  double f0 = lens.px();
  if (!focal_known) {
    f0 = scanFocal(
        [&](double f, double) {
          camera.intrinsics()[0] = f;
          return triangulateAll(views, fMc, camera, X);
        },
        lens.px());
    if (!(f0 > 0))
      return out;
  }
  camera.intrinsics()[0] = f0;
  out.median_error = triangulateAll(views, fMc, camera, X);
  if (!std::isfinite(out.median_error))
    return out;
  out.fx = f0;
  for (const auto &e : X)
    out.points[e.first] = vpColVector({e.second(0), e.second(1), e.second(2)});
  out.ok = true;
  return out;
}

std::map<int, Eigen::Vector3d> triangulateViews(const std::vector<View> &views, const std::vector<Rigid> &fMc,
                                                const CameraModel &camera)
{
  std::map<int, PointViews> seen;
  for (size_t k = 0; k < views.size(); ++k)
    for (const auto &o : views[k].points)
      seen[o.id].add(fMc[k], camera, Eigen::Vector2d(o.ip.get_u(), o.ip.get_v()));
  std::map<int, Eigen::Vector3d> out;
  for (const auto &kv : seen) {
    Eigen::Vector3d X;
    if (triangulate(camera, kv.second, Triangulation::MIDPOINT_REFINED, X))
      out[kv.first] = X;
  }
  return out;
}

void checkResult(const Context &c, Result &res)
{
  findOutliers(c, res);
  findYardstickUnused(c, res);
  findScaleNominal(c, res);
  if (res.status != vpRobotSelfCalibration::OK || c.options.method == vpRobotSelfCalibration::HAND_EYE)
    return;
  findIdentifiabilityLost(c, res);
}

void verify(const Context &c, Result &res)
{
  if (c.verification.size() < 2)
    return;
  c.report("verification", 0, 1);
  const auto tv = std::chrono::steady_clock::now();
  // An estimated OpenCV lens model (which vpCameraParameters cannot hold): the held-out pixels
  // through the inverse of the start one (before) and of the estimated one (after).
  const bool opencv = !res.bundle.opencv_distortion.empty();
  // Eye-to-hand with joints: each model's views as camera poses in the effector frame.
  const std::vector<View> before = opencv ? undistorted(c.verification, lensOf(c.dataset)) : c.verification;
  const std::vector<View> after =
      opencv ? undistorted(c.verification, lensOf(res.camera, res.bundle.opencv_distortion)) : c.verification;
  res.before = vpCalibrationVerifier::verify(c.guess, c.dataset.cam,
                                             c.bundle.eye_to_hand ? eyeToHandViews(c.guess, before) : before,
                                             c.dataset.yardstick);
  res.after = vpCalibrationVerifier::verify(res.calibrated, res.camera,
                                            c.bundle.eye_to_hand ? eyeToHandViews(res.calibrated, after) : after,
                                            c.dataset.yardstick);
  res.verified = true;
  res.stage_seconds.push_back({"verification", seconds(tv)});
}
} // namespace vpSelfCalibPipeline
