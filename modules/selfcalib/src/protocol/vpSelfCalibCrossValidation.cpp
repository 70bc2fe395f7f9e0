/*
 * ViSP SelfCalib: k-fold cross-validation of a self-calibration (the held-out views' reprojection
 * error, calibrated against nominal) and the verification of a calibration on a second dataset.
 */
#include <visp3/selfcalib/vpCalibrationVerifier.h>
#include <visp3/selfcalib/vpSelfCalibCrossValidation.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <iomanip>
#include <sstream>

#include "../core/vpSelfCalibCamera.h"
#include "../core/vpSelfCalibMath.h"
#include "../pipeline/vpSelfCalibPipelines.h"

using namespace vpSelfCalib;

namespace
{
using View = vpSelfCalibDataset::View;

// A view's camera pose through a model (see reprojection()).
Rigid predictedCamera(const vpKinematicChain &model, const View &v, bool controller_poses, size_t index)
{
  if (controller_poses && v.has_fMe)
    return rigidFromVisp(v.fMe * model.get_eMc_corrected());
  if (v.q.size() == model.getNumJoints())
    return rigidFromVisp(model.get_fMc(v.q));
  if (v.has_fMe)
    return rigidFromVisp(v.fMe * model.get_eMc_corrected());
  throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                             "vpSelfCalibCrossValidation: view " + std::to_string(index) +
                                 " has no joint vector of size " + std::to_string(model.getNumJoints()) +
                                 " and no fMe");
}

/*
  The reprojection error of test views on a scene triangulated from scene views, each view's camera
  given in the frame the scene is fixed in (fMc): see vpSelfCalibCrossValidation::reprojection().
*/
vpSelfCalibCrossValidation::Reprojection reprojectionThrough(const CameraModel &camera, const std::vector<View> &scene_views,
                                                             const std::vector<Rigid> &fMc,
                                                             const std::vector<View> &test_views,
                                                             const std::vector<Rigid> &test_fMc)
{
  std::vector<Rigid> cMf;
  for (const Rigid &M : test_fMc)
    cMf.push_back(M.inverse());
  const std::map<int, Eigen::Vector3d> X = vpSelfCalibPipeline::triangulateViews(scene_views, fMc, camera);
  vpSelfCalibCrossValidation::Reprojection r;
  r.points = static_cast<unsigned int>(X.size());
  std::vector<double> errors;
  for (size_t k = 0; k < test_views.size(); ++k)
    for (const auto &o : test_views[k].points) {
      const auto it = X.find(o.id);
      if (it == X.end())
        continue;
      const Eigen::Vector3d Xc = cMf[k] * it->second;
      if (!inFront(Xc)) {
        ++r.behind;
        continue;
      }
      // Outside the lens model's valid region (its polynomial's monotonic range, the image and its
      // margin) the polynomial's pixel is no prediction: not seen.
      if (!camera.sees(Xc)) {
        ++r.outside;
        continue;
      }
      errors.push_back((camera.project(Xc) - Eigen::Vector2d(o.ip.get_u(), o.ip.get_v())).norm());
    }
  r.observations = static_cast<unsigned int>(errors.size());
  if (errors.empty())
    return r;
  double sum2 = 0;
  for (double e : errors)
    sum2 += e * e;
  r.rms = std::sqrt(sum2 / errors.size());
  std::sort(errors.begin(), errors.end());
  const size_t m = errors.size();
  r.median = m % 2 ? errors[m / 2] : 0.5 * (errors[m / 2 - 1] + errors[m / 2]);
  return r;
}

/*
  A camera fixed in the world: view k's camera in the target's frame o, oMc = (bMe eMo)^-1 bMc,
  bMe the view's controller pose (HAND_EYE) or the kinematics at its joints. The target (a board,
  tags, or the tool's natural features, whose frame is e: eMo the identity) is the scene that
  stays fixed from view to view in this frame.
*/
Rigid cameraInTarget(const vpKinematicChain &kinematics, const View &v, bool controller_poses,
                     const vpHomogeneousMatrix &bMc, const vpHomogeneousMatrix &eMo, size_t index)
{
  vpHomogeneousMatrix bMe;
  if (controller_poses && v.has_fMe)
    bMe = v.fMe;
  else if (v.q.size() == kinematics.getNumJoints())
    bMe = kinematics.get_fMe(v.q);
  else if (v.has_fMe)
    bMe = v.fMe;
  else
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               "vpSelfCalibCrossValidation: view " + std::to_string(index) +
                                   " has no joint vector of size " + std::to_string(kinematics.getNumJoints()) +
                                   " and no fMe");
  return rigidFromVisp((bMe * eMo).inverse() * bMc);
}

/*
  The held-out reprojection with the camera fixed in the world: the target's points triangulated in
  its frame from the training views' cameras oMc, projected into the held-out views' (the same
  rule as reprojection()). The fold's bMc and eMo with the given kinematics and camera: the
  calibrated model's, or the nominal kinematics and the dataset's camera (the reference: what the
  calibrated bMc and eMo predict without the calibrated kinematics; HAND_EYE calibrates none, and
  the two differ only by the camera).
*/
vpSelfCalibCrossValidation::Reprojection worldReprojection(const vpKinematicChain &kinematics,
                                                           const vpRobotSelfCalibration::Result &r,
                                                           const vpCameraParameters &cam,
                                                           const std::vector<double> &opencv_distortion,
                                                           bool controller_poses, const std::vector<View> &scene_views,
                                                           const std::vector<View> &test_views, unsigned int width,
                                                           unsigned int height)
{
  if (!r.has_bMc) // no camera pose to place: nothing compared
    return vpSelfCalibCrossValidation::Reprojection();
  const vpHomogeneousMatrix bMc(r.bMc), eMo = r.has_eMo ? vpHomogeneousMatrix(r.eMo) : vpHomogeneousMatrix();
  std::vector<Rigid> oMc, test_oMc;
  for (size_t k = 0; k < scene_views.size(); ++k)
    oMc.push_back(cameraInTarget(kinematics, scene_views[k], controller_poses, bMc, eMo, k));
  for (size_t k = 0; k < test_views.size(); ++k)
    test_oMc.push_back(cameraInTarget(kinematics, test_views[k], controller_poses, bMc, eMo, k));
  return reprojectionThrough(vpSelfCalibPipeline::lensOf(cam, opencv_distortion).withImage(width, height), scene_views,
                             oMc, test_views, test_oMc);
}

vpSelfCalibCrossValidation::Spread spread(const std::vector<double> &x)
{
  vpSelfCalibCrossValidation::Spread s;
  s.count = static_cast<unsigned int>(x.size());
  if (x.empty())
    return s;
  double sum = 0;
  for (double v : x)
    sum += v;
  s.mean = sum / x.size();
  double ss = 0;
  for (double v : x)
    ss += (v - s.mean) * (v - s.mean);
  s.sd = x.size() > 1 ? std::sqrt(ss / (x.size() - 1)) : 0.0;
  s.min = *std::min_element(x.begin(), x.end());
  s.max = *std::max_element(x.begin(), x.end());
  return s;
}
} // namespace

void vpSelfCalibCrossValidation::Options::check() const
{
  if (folds < 2)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpSelfCalibCrossValidation: folds must be at least 2, got " + std::to_string(folds));
}

std::vector<std::vector<unsigned int>> vpSelfCalibCrossValidation::folds(unsigned int n, unsigned int k)
{
  Options o;
  o.folds = k;
  o.check();
  if (k > n)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpSelfCalibCrossValidation: " + std::to_string(k) + " folds of " + std::to_string(n) +
                                   " views: at most one fold per view");
  const unsigned int largest = (n + k - 1) / k;
  if (n - largest < 3)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpSelfCalibCrossValidation: " + std::to_string(k) + " folds of " + std::to_string(n) +
                                   " views hold out up to " + std::to_string(largest) + " views, leaving " +
                                   std::to_string(n - largest) +
                                   " to calibrate: at least 3 are needed (more views, or more folds)");
  std::vector<std::vector<unsigned int>> out(k);
  for (unsigned int i = 0; i < n; ++i)
    out[i % k].push_back(i);
  return out;
}

vpSelfCalibCrossValidation::Reprojection
vpSelfCalibCrossValidation::reprojection(const vpKinematicChain &model, const vpCameraParameters &cam,
                                         const std::vector<double> &opencv_distortion, bool controller_poses,
                                         const std::vector<View> &scene_views, const std::vector<View> &test_views,
                                         unsigned int width, unsigned int height)
{
  const CameraModel camera = vpSelfCalibPipeline::lensOf(cam, opencv_distortion).withImage(width, height);
  std::vector<Rigid> fMc, test_fMc;
  for (size_t k = 0; k < scene_views.size(); ++k)
    fMc.push_back(predictedCamera(model, scene_views[k], controller_poses, k));
  for (size_t k = 0; k < test_views.size(); ++k)
    test_fMc.push_back(predictedCamera(model, test_views[k], controller_poses, k));
  return reprojectionThrough(camera, scene_views, fMc, test_views, test_fMc);
}

std::vector<double> vpSelfCalibCrossValidation::calibratedDistortion(const vpRobotSelfCalibration::Result &result,
                                                                     const vpSelfCalibDataset &dataset)
{
  return result.bundle.opencv_distortion.empty() ? dataset.opencv_distortion : result.bundle.opencv_distortion;
}

namespace
{
//! One fold's calibration: the fold's dataset (training views first), its options, its progress.
using FoldCalibration = std::function<vpRobotSelfCalibration::Result(
    const vpSelfCalibDataset &, const vpRobotSelfCalibration::Options &, const vpRobotSelfCalibration::Progress &)>;

bool gaveModel(const vpRobotSelfCalibration::Result &r)
{
  return r.status == vpRobotSelfCalibration::OK || r.status == vpRobotSelfCalibration::DOUBTFUL;
}

/*
  A bundle adjustment's residuals contradict the noise it was given: sigma0 above its 99.9 %
  interval (the pixels noisier than stated), or the robot corrections beyond their chi-square bound.
*/
bool contradictsNoise(const vpKinematicBundleAdjustment::Result &b)
{
  return b.sigma0 > b.sigma0_high || !vpSelfCalibPipeline::robotCorrectionsWithinStated(b);
}

/*
  A fold started from the run on every view (vpSelfCalibCrossValidation::run with `full`): its eMc,
  points and focal length the start (Options::start), its noise held (the levels it measured, not
  measured again); the fold measures them again, as full did, only when its residuals contradict
  them while full's did not.
*/
vpRobotSelfCalibration::Result warmFold(const vpKinematicChain &nominal, const vpSelfCalibDataset &sub,
                                        vpRobotSelfCalibration::Options o, const vpRobotSelfCalibration::Result &full,
                                        const vpRobotSelfCalibration::Progress &progress)
{
  o.start.set = true;
  o.start.model = full.calibrated;
  o.start.points = full.bundle.points;
  o.start.fx = full.camera.get_px();
  if (!full.bundle.opencv_distortion.empty())
    o.bundle.opencv_distortion = full.bundle.opencv_distortion;
  vpSelfCalibDataset data = sub;
  if (!full.noise.hasRobotError()) {
    // full measured the robot exact (or trusted it): so does the fold, not the prior again.
    o.trust_robot = true;
    data.pose_sd_translation = data.pose_sd_rotation = 0;
  }
  o.noise = full.noise;
  o.noise.measure_pixel_sd = o.noise.measure_pose_sd = o.noise.measure_joint_sd = o.noise.measure_model_sd = false;
  const vpRobotSelfCalibration::Result r = vpRobotSelfCalibration::run(nominal, data, o, progress);
  if (!gaveModel(r) || !contradictsNoise(r.bundle) || contradictsNoise(full.bundle))
    return r;
  o.noise = full.noise; // measured again from the held levels
  return vpRobotSelfCalibration::run(nominal, data, o, progress);
}

vpSelfCalibCrossValidation::Result runFolds(const vpKinematicChain &nominal, const vpSelfCalibDataset &ds,
                                            const vpRobotSelfCalibration::Options &options,
                                            const vpSelfCalibCrossValidation::Options &cv,
                                            const vpSelfCalibCrossValidation::Progress &progress,
                                            const FoldCalibration &calibrate)
{
  using CV = vpSelfCalibCrossValidation;
  using Result = CV::Result;
  using Fold = CV::Fold;
  const auto t0 = std::chrono::steady_clock::now();
  cv.check();
  const unsigned int n = static_cast<unsigned int>(ds.views.size());
  const std::vector<std::vector<unsigned int>> held = CV::folds(n, cv.folds);
  const bool controller_poses = options.method == vpRobotSelfCalibration::HAND_EYE;
  Result res;
  res.views = n;
  res.folds = cv.folds;
  std::vector<double> cal_rms, nom_rms, cal_median, nom_median;
  for (unsigned int f = 0; f < cv.folds; ++f) {
    const auto tf = std::chrono::steady_clock::now();
    const std::string label = "cross-validation fold " + std::to_string(f + 1) + " of " + std::to_string(cv.folds);
    if (progress)
      progress(label, f, cv.folds);
    // The training views first (calibration), then the held-out ones (run()'s verification).
    std::vector<View> train, test;
    for (unsigned int i = 0; i < n; ++i)
      (std::find(held[f].begin(), held[f].end(), i) == held[f].end() ? train : test).push_back(ds.views[i]);
    vpSelfCalibDataset sub = ds;
    sub.views = train;
    sub.views.insert(sub.views.end(), test.begin(), test.end());
    vpRobotSelfCalibration::Options o = options;
    o.num_calibration_poses = static_cast<unsigned int>(train.size());
    const vpRobotSelfCalibration::Progress inner =
        progress ? vpRobotSelfCalibration::Progress([&](const std::string &stage, unsigned int, unsigned int) {
          progress(label + ": " + stage, f, cv.folds);
        })
                 : vpRobotSelfCalibration::Progress();
    const vpRobotSelfCalibration::Result r = calibrate(sub, o, inner);
    Fold fold;
    fold.held_out = held[f];
    fold.status = r.status;
    fold.message = r.message;
    // A camera fixed in the world: the target's frame is the one the scene is fixed in (worldReprojection()).
    const bool world = ds.camera_mount == vpSelfCalibDataset::CAMERA_IN_WORLD;
    if (!world)
      fold.nominal = CV::reprojection(nominal, ds.cam, ds.opencv_distortion, controller_poses, train, test,
                                      ds.width, ds.height);
    // A doubtful fold has a model (the one calibrate would write, marked): it is cross-validated too.
    if (r.status == vpRobotSelfCalibration::OK || r.status == vpRobotSelfCalibration::DOUBTFUL) {
      fold.fx = r.camera.get_px();
      if (world)
        fold.nominal = worldReprojection(nominal, r, ds.cam, ds.opencv_distortion, controller_poses, train, test,
                                         ds.width, ds.height);
      fold.calibrated =
          world ? worldReprojection(r.calibrated, r, r.camera, CV::calibratedDistortion(r, ds), controller_poses, train,
                                    test, ds.width, ds.height)
                : CV::reprojection(r.calibrated, r.camera, CV::calibratedDistortion(r, ds), controller_poses, train, test,
                                   ds.width, ds.height);
      if (r.verified && r.before.has_yardstick && r.after.has_yardstick) {
        fold.verified = true;
        fold.yardstick_error_nominal = r.before.yardstick_error;
        fold.yardstick_error_calibrated = r.after.yardstick_error;
      }
      if (fold.calibrated.observations > 0 && fold.nominal.observations > 0) {
        ++res.num_ok;
        cal_rms.push_back(fold.calibrated.rms);
        nom_rms.push_back(fold.nominal.rms);
        cal_median.push_back(fold.calibrated.median);
        nom_median.push_back(fold.nominal.median);
      } else
        fold.message += "; no held-out observation of a point the training views triangulate";
    } else
      ++res.num_failed;
    fold.seconds = vpSelfCalibPipeline::seconds(tf);
    res.fold.push_back(fold);
  }
  if (progress)
    progress("cross-validation", cv.folds, cv.folds);
  res.calibrated_rms = spread(cal_rms);
  res.nominal_rms = spread(nom_rms);
  res.calibrated_median = spread(cal_median);
  res.nominal_median = spread(nom_median);
  std::ostringstream os;
  os << std::setprecision(3);
  if (res.num_ok == 0 && res.num_failed == 0)
    os << "no fold measured (every fold calibrated, but no held-out view observes a point its training views "
          "triangulate: too few points shared between views, e.g. one small tag)";
  else if (res.num_ok == 0)
    os << "no fold measured (" << res.num_failed << " of " << cv.folds << " calibrations failed)";
  else {
    os << "held-out reprojection RMS " << res.calibrated_rms.mean << " px (sd " << res.calibrated_rms.sd << ", "
       << res.calibrated_rms.min << " to " << res.calibrated_rms.max << ") calibrated vs " << res.nominal_rms.mean
       << " px (sd " << res.nominal_rms.sd << ") nominal, median " << res.calibrated_median.mean << " vs "
       << res.nominal_median.mean << " px; " << res.num_ok << " of " << cv.folds << " folds measured";
    if (res.num_failed)
      os << ", " << res.num_failed << " failed";
  }
  res.message = os.str();
  res.seconds = vpSelfCalibPipeline::seconds(t0);
  return res;
}
} // namespace

vpSelfCalibCrossValidation::Result vpSelfCalibCrossValidation::run(const vpKinematicChain &nominal,
                                                                   const vpSelfCalibDataset &ds,
                                                                   const vpRobotSelfCalibration::Options &options,
                                                                   const Options &cv, const Progress &progress)
{
  return runFolds(nominal, ds, options, cv, progress,
                  [&nominal](const vpSelfCalibDataset &sub, const vpRobotSelfCalibration::Options &o,
                             const vpRobotSelfCalibration::Progress &inner) {
                    return vpRobotSelfCalibration::run(nominal, sub, o, inner);
                  });
}

vpSelfCalibCrossValidation::Result vpSelfCalibCrossValidation::run(const vpKinematicChain &nominal,
                                                                   const vpSelfCalibDataset &ds,
                                                                   const vpRobotSelfCalibration::Options &options,
                                                                   const Options &cv,
                                                                   const vpRobotSelfCalibration::Result &full,
                                                                   const Progress &progress)
{
  const bool warm = options.method == vpRobotSelfCalibration::HAND_EYE &&
                    ds.camera_mount == vpSelfCalibDataset::CAMERA_ON_EFFECTOR && gaveModel(full) &&
                    !full.bundle.points.empty() && full.camera.get_px() > 0;
  if (!warm && options.method == vpRobotSelfCalibration::BUNDLE_ADJUSTMENT && gaveModel(full) &&
      !full.noise.hasRobotError() && !options.trust_robot) {
    // The bundle method's robot error measured exact (dropped) on every view: the folds, on fewer
    // views of the same robot, take it as exact too rather than measure it again from the prior.
    vpRobotSelfCalibration::Options exact = options;
    exact.trust_robot = true;
    return run(nominal, ds, exact, cv, progress);
  }
  if (!warm)
    return run(nominal, ds, options, cv, progress);
  return runFolds(nominal, ds, options, cv, progress,
                  [&nominal, &full](const vpSelfCalibDataset &sub, const vpRobotSelfCalibration::Options &o,
                                    const vpRobotSelfCalibration::Progress &inner) {
                    return warmFold(nominal, sub, o, full, inner);
                  });
}

vpSelfCalibCrossValidation::HeldOut vpSelfCalibCrossValidation::verifyHeldOut(
    const vpKinematicChain &nominal, const vpSelfCalibDataset &ds, const vpRobotSelfCalibration::Options &options,
    const vpRobotSelfCalibration::Result &r, const vpSelfCalibDataset &h)
{
  if (h.views.size() < 2)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpSelfCalibCrossValidation: the held-out dataset has " +
                                   std::to_string(h.views.size()) + " views; at least 2 are needed to verify on");
  const bool controller_poses = options.method == vpRobotSelfCalibration::HAND_EYE;
  HeldOut out;
  out.views = static_cast<unsigned int>(h.views.size());
  const std::vector<double> lens = calibratedDistortion(r, ds);
  out.calibrated = reprojection(r.calibrated, r.camera, lens, controller_poses, h.views, h.views, h.width, h.height);
  out.nominal =
      reprojection(nominal, h.cam, h.opencv_distortion, controller_poses, h.views, h.views, h.width, h.height);
  if (h.yardstick.isSet()) {
    // vpCalibrationVerifier's camera holds no OpenCV lens: the pixels through its inverse first.
    auto pinhole = [&h](const vpCameraParameters &cam, const std::vector<double> &opencv) {
      return opencv.empty() ? h.views : vpSelfCalibPipeline::undistorted(h.views, vpSelfCalibPipeline::lensOf(cam, opencv));
    };
    const auto before =
        vpCalibrationVerifier::verify(nominal, h.cam, pinhole(h.cam, h.opencv_distortion), h.yardstick);
    const auto after = vpCalibrationVerifier::verify(r.calibrated, r.camera, pinhole(r.camera, lens), h.yardstick);
    if (before.has_yardstick && after.has_yardstick) {
      out.has_yardstick = true;
      out.yardstick_error_nominal = before.yardstick_error;
      out.yardstick_error_calibrated = after.yardstick_error;
    }
  }
  return out;
}
