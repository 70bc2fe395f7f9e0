/*
 * ViSP SelfCalib: kinematic bundle adjustment (beyond the paper). See the header for the model.
 * The run: the robust solve schedule, the estimate and the status. The cost functions are in
 * vpKinematicBundleAdjustmentCosts.h/.cpp, the problem in vpKinematicBundleAdjustmentProblem.h/.cpp,
 * the covariance in vpKinematicBundleAdjustmentCovariance.cpp.
 */
#include <visp3/selfcalib/vpKinematicBundleAdjustment.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <algorithm>
#include <limits>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <memory>
#include <set>
#include <sstream>

#include "../core/vpSelfCalibCamera.h"
#include "../core/vpSelfCalibCeres.h"
#include "../core/vpSelfCalibGeometry.h"
#include "../core/vpSelfCalibMath.h"
#include "../core/vpSelfCalibRange.h"
#include "../core/vpSelfCalibRobotErrorLevels.h"
#include "vpKinematicBundleAdjustmentProblem.h"

using namespace vpSelfCalib;
using namespace vpKinematicBundle;

namespace
{
/*
  Stage 4, the robust solve schedule (robustSchedule: a wide loss when the start is far off, the
  narrow robust loss, trimming, plain least squares). Returns the last problem (for the covariance),
  or null when every observation was rejected; summary: the last solve's.
*/
std::unique_ptr<ceres::Problem> solveSchedule(Adjustment &a, const vpSelfCalibDataset::Yardstick &yardstick,
                                              const KBA::Options &opt, bool solve, ceres::Solver::Summary &summary,
                                              KBA::Result &res)
{
  RobustSchedule schedule;
  if (solve)
    schedule = robustSchedule(a.noise.loss != vpSelfCalibNoiseModel::LOSS_NONE, a.noise.loss_scale,
                              a.noise.outlier_threshold, a.startErrors(a.noise.pixel_sd));
  else
    schedule.scales = {0};
  std::unique_ptr<ceres::Problem> problem;
  for (size_t stage = 0; stage < schedule.scales.size(); ++stage) {
    std::shared_ptr<ceres::ParameterBlockOrdering> order;
    problem = buildProblem(a, yardstick, opt, schedule.scales[stage], order, res.scale_source);
    if (!problem || !solve)
      return problem;
    // The last solve gives the estimate: converged to the tight tolerances whatever opt.tight (the
    // default ones stopped it at a relative cost change of 1e-6 while f still moved by up to 0.3
    // of its sd, bench-trust's PUMA); the robust stages before it only give it a start and the
    // outliers, and keep the default tolerances.
    const bool last = stage + 1 == schedule.scales.size();
    ceres::Solver::Options so = solverOptions(opt.max_iterations, opt.tight || last, ceres::DENSE_SCHUR);
    so.linear_solver_ordering = order;
    so.num_threads = static_cast<int>(opt.num_threads);
    vpSelfCalib::solve(so, problem.get(), &summary);
    res.iterations += static_cast<unsigned int>(summary.iterations.size());
    a.state.update(true); // the callback last saw the final trial point, not necessarily the solution
    if (!summary.IsSolutionUsable())
      break;
    if (static_cast<int>(stage) == schedule.trim_after)
      a.trim(a.noise.outlier_threshold, a.noise.pixel_sd);
  }
  return problem;
}

/*
  Without robot error modelled: each view's camera re-posed alone on its kept observations
  (reposeCamera), the F statistic of the fit gained against the residuals left (Result::repose_f).
  Its 99.9 % quantile: the chi-square quantile of the numerator's degrees of freedom (Wilson-Hilferty,
  z = 3.09) over them, widened by the denominator's own spread (z sqrt(2 / its dof)).
*/
void reposeViews(Adjustment &a, KBA::Result &res)
{
  const CameraModel camera(a.state.model, a.in);
  std::vector<std::vector<Eigen::Vector3d>> Xc(a.state.views.size());
  std::vector<std::vector<Eigen::Vector2d>> uv(a.state.views.size());
  std::set<int> kept;
  for (size_t n = 0; n < a.obs.size(); ++n) {
    if (!a.inlier[n])
      continue;
    kept.insert(a.obs[n].id);
    const ViewState &v = a.state.views[a.obs[n].view];
    Xc[a.obs[n].view].push_back(v.RT * (a.X[a.obs[n].id] - v.tf));
    uv[a.obs[n].view].emplace_back(a.obs[n].u, a.obs[n].v);
  }
  double before = 0, after = 0, st = 0, sr = 0, used = 0;
  unsigned int views = 0;
  for (size_t k = 0; k < Xc.size(); ++k) {
    Eigen::Matrix<double, 6, 1> c;
    double cost = 0;
    if (!reposeCamera(camera, Xc[k], uv[k], c, cost))
      continue;
    for (size_t i = 0; i < Xc[k].size(); ++i) {
      Eigen::Vector2d p;
      if (camera.project(Xc[k][i], p, nullptr, nullptr))
        before += (p - uv[k][i]).squaredNorm();
    }
    after += cost;
    used += static_cast<double>(Xc[k].size());
    st += c.head<3>().squaredNorm();
    sr += c.tail<3>().squaredNorm();
    ++views;
  }
  // The solution's degrees of freedom over the views used: its share of the whole.
  const double unknowns = static_cast<double>(a.P + a.free_in.size()) + 3.0 * static_cast<double>(kept.size());
  const double dof = 2.0 * used - unknowns * used / std::max(1.0, static_cast<double>(res.num_observations)) - 6.0 * views;
  if (views == 0 || !(dof > 0) || !(after > 0))
    return;
  res.reposed_views = views;
  res.reposed_rms = std::sqrt(after / (2.0 * used));
  res.repose_rms_before = std::sqrt(before / (2.0 * used));
  res.repose_rms_translation = std::sqrt(st / (3.0 * views));
  res.repose_rms_rotation = std::sqrt(sr / (3.0 * views));
  const double nu = 6.0 * views;
  res.repose_f = (std::max(0.0, before - after) / nu) / (after / dof);
  const double z = 3.09, h = 2.0 / (9.0 * nu);
  res.repose_f_limit = std::pow(1.0 - h + z * std::sqrt(h), 3) * (1.0 + z * std::sqrt(2.0 / dof));
}

//! Stage 5, the estimate at the final state: chain, camera, points, rms and sigma0, intrinsics.
void fillEstimate(Adjustment &a, bool distortion, KBA::Result &res)
{
  res.chain = a.state.chain;
  res.camera = cameraFrom(a.in, a.state.model, distortion);
  if (a.state.model == Distortion::OPENCV)
    res.opencv_distortion.assign(a.in + 4, a.in + 9);
  std::set<int> kept;
  double sum = 0;
  std::vector<double> abs_residuals; // every observation that projects, for the robust noise level
  for (size_t n = 0; n < a.obs.size(); ++n) {
    double uv[2];
    const bool projects = a.reproject(n, uv);
    if (projects) {
      abs_residuals.push_back(std::fabs(uv[0] - a.obs[n].u));
      abs_residuals.push_back(std::fabs(uv[1] - a.obs[n].v));
    }
    if (!a.inlier[n] || !projects) {
      a.inlier[n] = false;
      ++res.num_outliers;
      continue;
    }
    sum += std::pow(uv[0] - a.obs[n].u, 2) + std::pow(uv[1] - a.obs[n].v, 2);
    ++res.num_observations;
    kept.insert(a.obs[n].id);
  }
  res.rms = res.num_observations ? std::sqrt(sum / (2.0 * res.num_observations)) : 0;
  // The pose priors add as many residuals as unknowns: the degrees of freedom are the pixels'.
  const double dof = 2.0 * res.num_observations - static_cast<double>(a.P + a.free_in.size() + 3 * kept.size());
  res.sigma0 = dof > 0 ? res.rms / a.noise.pixel_sd * std::sqrt(2.0 * res.num_observations / dof) : 0;
  if (dof > 0 && !abs_residuals.empty()) {
    res.measured.pixel_sd = vpSelfCalib::robustNoiseSd(abs_residuals, std::sqrt(2.0 * res.num_observations / dof));
    vpSelfCalib::sigma0Interval(dof, res.sigma0_low, res.sigma0_high);
  }
  if (!a.state.delta.empty()) {
    double chi2 = sum / (a.noise.pixel_sd * a.noise.pixel_sd), st = 0, sr = 0;
    for (const auto &d : a.state.delta) {
      const double t2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2], r2 = d[3] * d[3] + d[4] * d[4] + d[5] * d[5];
      st += t2;
      sr += r2;
      const double robot = t2 / (a.noise.pose_sd_translation * a.noise.pose_sd_translation) +
                           r2 / (a.noise.pose_sd_rotation * a.noise.pose_sd_rotation);
      chi2 += robot;
      res.robot_chi2 += robot;
      res.robot_dof += 6;
      res.pose_corrections.push_back(vpColVector({d[0], d[1], d[2], d[3], d[4], d[5]}));
    }
    const double views = static_cast<double>(a.state.delta.size());
    res.pose_rms_translation = std::sqrt(st / (3 * views));
    res.pose_rms_rotation = std::sqrt(sr / (3 * views));
    res.robot_rms_ratio = std::max(res.pose_rms_translation / a.noise.pose_sd_translation,
                                   res.pose_rms_rotation / a.noise.pose_sd_rotation);
    res.sigma0 = dof > 0 ? std::sqrt(chi2 / dof) : 0;
  }
  if (!a.state.dq.empty()) {
    double chi2 = sum / (a.noise.pixel_sd * a.noise.pixel_sd), sq = 0, st = 0, sr = 0;
    double part[3] = {0, 0, 0}; // whitened squares: joints, camera translation, camera rotation
    const int nj = a.state.n_joint;
    for (const auto &d : a.state.dq) {
      for (size_t i = 0; i < d.size(); ++i) {
        const double robot = d[i] * d[i] / (a.joint_sd[i] * a.joint_sd[i]);
        chi2 += robot;
        res.robot_chi2 += robot;
        ++res.robot_dof;
        part[static_cast<int>(i) < nj ? 0 : (static_cast<int>(i) < nj + 3 ? 1 : 2)] += robot;
      }
      if (nj > 0) {
        vpColVector c(static_cast<unsigned int>(nj));
        for (int i = 0; i < nj; ++i) {
          c[static_cast<unsigned int>(i)] = d[i];
          sq += d[i] * d[i];
        }
        res.joint_corrections.push_back(c);
      }
      if (a.state.camera_delta) {
        res.pose_corrections.push_back(
            vpColVector({d[nj], d[nj + 1], d[nj + 2], d[nj + 3], d[nj + 4], d[nj + 5]}));
        for (int i = 0; i < 3; ++i) {
          st += d[nj + i] * d[nj + i];
          sr += d[nj + 3 + i] * d[nj + 3 + i];
        }
      }
    }
    const double views = static_cast<double>(a.state.dq.size());
    if (nj > 0)
      res.joint_rms = std::sqrt(sq / (views * nj));
    if (a.state.camera_delta) {
      res.pose_rms_translation = std::sqrt(st / (3 * views));
      res.pose_rms_rotation = std::sqrt(sr / (3 * views));
    }
    if (nj > 0)
      res.robot_rms_ratio = std::sqrt(part[0] / (views * nj));
    if (a.state.camera_delta)
      res.robot_rms_ratio =
          std::max(res.robot_rms_ratio, std::sqrt(std::max(part[1], part[2]) / (3 * views)));
    res.sigma0 = dof > 0 ? std::sqrt(chi2 / dof) : 0;
  }
  if (a.has_object) {
    res.has_object = true;
    for (unsigned int i = 0; i < 6; ++i)
      res.object_pose[i] = a.object[i];
  }
  for (int idp : kept) {
    vpColVector v(3);
    for (unsigned int c = 0; c < 3; ++c)
      v[c] = a.X[idp](c);
    res.points[idp] = v;
  }
  for (int i : a.free_in)
    res.intrinsic_names.push_back(intrinsicName(a.state.model, i));
  res.intrinsics.resize(static_cast<unsigned int>(a.free_in.size()));
  res.intrinsics_sd.resize(static_cast<unsigned int>(a.free_in.size()));
  for (size_t i = 0; i < a.free_in.size(); ++i)
    res.intrinsics[static_cast<unsigned int>(i)] = a.in[a.free_in[i]];
}

/*
  Stage 7, Settings::measure_layout_scale (hand-eye-only mode: the robot's metric motion is the scale's
  reference; in the full mode a wrong size scales the kinematic corrections, beyond their tolerance):
  from the solution, one more plain least-squares solve with the known layout's scale free (without a
  layout, the yardstick's: its declared length times the scale), and its sd from the covariance with
  every other block kept as in stage 6 (scaled as res's covariance). The estimate in res is not changed. A singular information
  (the views do not determine the scale) gives an infinite sd.
*/
void measureLayoutScale(Adjustment &a, const vpSelfCalibDataset::Yardstick &yardstick, const KBA::Options &opt,
                        KBA::Result &res)
{
  a.free_layout_scale = true;
  a.layout_scale[0] = 1;
  std::shared_ptr<ceres::ParameterBlockOrdering> order;
  KBA::ScaleSource source = res.scale_source;
  std::unique_ptr<ceres::Problem> problem = buildProblem(a, yardstick, opt, 0, order, source);
  if (!problem || !problem->HasParameterBlock(a.layout_scale.data()))
    return;
  ceres::Solver::Options so = solverOptions(opt.max_iterations, true, ceres::DENSE_SCHUR);
  so.linear_solver_ordering = order;
  so.num_threads = static_cast<int>(opt.num_threads);
  ceres::Solver::Summary summary;
  vpSelfCalib::solve(so, problem.get(), &summary);
  a.state.update(true);
  if (!summary.IsSolutionUsable() || !std::isfinite(a.layout_scale[0]))
    return;
  res.has_layout_scale = true;
  res.layout_scale = a.layout_scale[0];
  const MarginalBlocks blocks = marginalBlocks(a, *problem, yardstick);
  Eigen::MatrixXd full;
  if (!marginalCovariance(*problem, blocks.kept, blocks.eliminated, full, nullptr)) {
    res.layout_scale_sd = std::numeric_limits<double>::infinity();
    return;
  }
  const double factor = res.covariance_scaled ? res.sigma0 * res.sigma0 : 1.0;
  const Eigen::Index last = full.rows() - 1;
  res.layout_scale_sd = std::sqrt(std::max(0.0, factor * full(last, last)));
}

/*
  The robot's error of a full-mode noise model put in the adjustment: the priors' sds (a.joint_sd)
  and, for a form dropped (joint readings exact, or no model residual), its part of every view's
  correction removed. Only forms already modelled are kept.
*/
void applyRobotLevels(Adjustment &a, const vpSelfCalibNoiseModel &noise)
{
  const int nj = a.state.n_joint;
  const bool joints = nj > 0 && !noise.joint_sd.empty(), model = a.state.camera_delta && noise.hasModelError();
  std::vector<double> sd;
  for (int i = 0; joints && i < nj; ++i)
    sd.push_back(noise.joint_sd.size() == 1 ? noise.joint_sd[0] : noise.joint_sd[static_cast<size_t>(i)]);
  for (int i = 0; model && i < 6; ++i)
    sd.push_back(i < 3 ? noise.model_sd_translation : noise.model_sd_rotation);
  for (auto &d : a.state.dq) {
    std::vector<double> kept;
    if (joints)
      kept.insert(kept.end(), d.begin(), d.begin() + nj);
    if (model)
      kept.insert(kept.end(), d.begin() + nj, d.end());
    d = kept;
  }
  if (sd.empty())
    a.state.dq.clear();
  a.state.n_joint = joints ? nj : 0;
  a.state.camera_delta = model;
  a.joint_sd = sd;
  a.noise = noise;
  a.state.update(true);
}

/*
  One solve again at the robot error `noise` from the adjustment's state: the kept observations,
  plain least squares (the schedule's last stage), then the estimate and covariance into res from
  `solved` (the result before the estimate), the pixels weighed at pixel_factor times the stated
  sd. Converged to the tight tolerances: any solve may be the one that stands (a solve to Ceres's
  default ones, then a tight one once the levels agree, cost one solve more on every run). False,
  res untouched, when it fails.
*/
bool solveAgain(Adjustment &a, const vpSelfCalibNoiseModel &noise, double pixel_factor,
                const vpSelfCalibDataset::Yardstick &yardstick, const KBA::Options &opt, bool distortion,
                const std::vector<std::string> &names, const KBA::Result &solved, KBA::Result &res)
{
  applyRobotLevels(a, noise);
  // The weights are the variance components measured: the covariance at them stands as it is.
  // Every robot error dropped (measured exact): the problem is a trusted run's, weighed and its
  // covariance scaled as that run's (the stated image noise, sigma0 outside its interval), so
  // exact readings end as the trusted run would.
  const bool trusted = !noise.hasRobotError();
  a.pixel_factor = trusted ? 1.0 : pixel_factor;
  a.components_measured = !trusted;
  KBA::Result r = solved;
  std::shared_ptr<ceres::ParameterBlockOrdering> order;
  const std::unique_ptr<ceres::Problem> problem = buildProblem(a, yardstick, opt, 0, order, r.scale_source);
  if (!problem)
    return false;
  ceres::Solver::Options so = solverOptions(opt.max_iterations, true, ceres::DENSE_SCHUR);
  so.linear_solver_ordering = order;
  so.num_threads = static_cast<int>(opt.num_threads);
  ceres::Solver::Summary summary;
  vpSelfCalib::solve(so, problem.get(), &summary);
  r.iterations = res.iterations + static_cast<unsigned int>(summary.iterations.size());
  a.state.update(true);
  if (!summary.IsSolutionUsable())
    return false;
  fillEstimate(a, distortion, r);
  if (a.state.delta.empty() && a.state.dq.empty())
    reposeViews(a, r);
  if (!fillCovariance(a, *problem, yardstick, names, r))
    return false;
  r.noise = noise;
  r.robot_rounds = res.robot_rounds + 1;
  res = r;
  return true;
}

std::string levelText(const vpSelfCalibNoiseModel &n, RobotErrorForm f)
{
  const RobotErrorLevels l = levelsOf(n, f);
  std::ostringstream os;
  os << std::fixed << std::setprecision(f == JOINT_ERROR ? 3 : 1) << 1e3 * l.t;
  if (f == MODEL_ERROR)
    os << " mm / " << 1e3 * l.r;
  os << " mrad";
  return os.str();
}

constexpr int kMaxRobotRounds = 8; //!< solves again at the measured robot error, at most

/*
  Full mode, the robot's error measured (the noise's measure_joint_sd, measure_model_sd; see
  Result::noise): variance components in the solution's neighbourhood. res holds a converged solve
  with its covariance; `solved` is the result before its estimate.
*/
void settleRobotError(Adjustment &a, const vpSelfCalibDataset::Yardstick &yardstick, const KBA::Options &opt,
                      bool distortion, const std::vector<std::string> &names, const KBA::Result &solved,
                      KBA::Result &res)
{
  const char *const form_name[] = {"", "the joint reading error", "the model residual"};
  bool confounded = false;
  for (;;) {
    confounded = confounded || res.robot_error_confounded;
    vpSelfCalibNoiseModel next = res.noise;
    std::vector<RobotErrorForm> agreed;
    std::string change, unmeasured;
    for (RobotErrorForm f : {JOINT_ERROR, MODEL_ERROR}) {
      if (!measuredForm(res.noise, f))
        continue;
      const RobotErrorStep step = nextLevel(res.noise, res.measured, f, next);
      if (step == UNMEASURED_LEVEL)
        unmeasured += (unmeasured.empty() ? "" : ", ") + std::string(form_name[f]) + " (the stated " +
                      levelText(res.noise, f) + " is used)";
      else if (step == NEXT_LEVEL && settled(levelsOf(res.noise, f), levelsOf(next, f), f))
        agreed.push_back(f);
      else
        change += (change.empty() ? "" : ", ") + std::string(form_name[f]) + " " + levelText(res.measured, f) +
                  " where " + levelText(res.noise, f) + " was used";
    }
    // The image noise's component, measured with the robot's (its redundancy is large: the tight test).
    const double pixel_factor = a.pixel_factor_measured > 0 ? a.pixel_factor_measured : a.pixel_factor;
    if (std::fabs(pixel_factor / a.pixel_factor - 1) > kPoseSettled) {
      std::ostringstream os;
      os << std::setprecision(3) << "the image noise " << a.noise.pixel_sd * pixel_factor << " px where "
         << a.noise.pixel_sd * a.pixel_factor << " px was used";
      change += (change.empty() ? "" : ", ") + os.str();
    }
    res.robot_error_confounded = confounded;
    if (!unmeasured.empty() && (change.empty() || static_cast<int>(res.robot_rounds) == kMaxRobotRounds))
      res.robot_error_unsettled = "the robot's error could not be measured (the views do not separate its corrections "
                                  "from the rest, or no covariance): " + unmeasured;
    if (change.empty()) {
      // The levels agree with the solution's (converged to the tight tolerances, as every solve).
      res.robot_error_confounded = confounded;
      for (RobotErrorForm f : agreed)
        markMeasured(res.noise, f);
      return;
    }
    if (static_cast<int>(res.robot_rounds) == kMaxRobotRounds) {
      res.robot_error_unsettled = "the robot's error did not settle in " + std::to_string(kMaxRobotRounds) +
                                  " rounds: the corrections measure " + change;
      return;
    }
    // Every form dropped or no longer measured: the next solve is the last one.
    const bool last = !measuredForm(next, JOINT_ERROR) && !measuredForm(next, MODEL_ERROR);
    if (!solveAgain(a, next, pixel_factor, yardstick, opt, distortion, names, solved, res)) {
      res.robot_error_unsettled = "the robot's error the corrections measure is not the one used (" + change +
                                  "), and the solve at the measured level failed: the result is the one at the level "
                                  "used; these views may not determine the robot's error (add views)";
      return;
    }
    if (last) {
      res.robot_error_confounded = confounded;
      return;
    }
  }
}

//! The checks of the views and the camera that need more than Options::check.
void checkViewsAndCamera(const vpCameraParameters &camera, unsigned int m, const KBA::Options &opt)
{
  if (m < 2)
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpKinematicBundleAdjustment: at least 2 views are needed");
  if (!(camera.get_px() > 0) || !(camera.get_py() > 0))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment: the camera needs positive px and py");
  if (opt.distortion_model == KBA::DISTORTION_OPENCV && CameraModel::fromVisp(camera).distortion() != Distortion::NONE)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment: with the OpenCV distortion model the camera must have no "
                               "ViSP distortion (k_ud): give the start coefficients in opencv_distortion");
}

/*
  The robot's error of the noise model, as the mode takes it: hand-eye-only the controller poses'
  (pose_sd_*), full kinematics the joint readings' (joint_sd: 1 or one per joint) and the model's
  residual (model_sd_*). A part of the other mode is a caller mistake (checked here rather than in
  check(): the pipeline sets hand_eye_only from its method).
*/
void checkRobotError(const vpKinematicChain &start, const KBA::Options &opt, const vpSelfCalibNoiseModel &noise)
{
  if (opt.hand_eye_only && !noise.joint_sd.empty())
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment: joint_sd (joint-reading noise) is for the full kinematic "
                               "mode; in hand-eye-only mode give the controller pose error (pose_sd_*)");
  if (opt.hand_eye_only && noise.hasModelError())
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment: model_sd_* (the kinematic model's residual) is for the "
                               "full kinematic mode; in hand-eye-only mode give the controller pose error (pose_sd_*)");
  if (!opt.hand_eye_only && noise.hasPoseError())
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment: pose_sd_* (the controller poses' error) is for the "
                               "hand-eye-only mode; in the full kinematic mode the camera pose correction is model_sd_*");
  if (!noise.joint_sd.empty() && noise.joint_sd.size() != 1 && noise.joint_sd.size() != start.getNumJoints())
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               "vpKinematicBundleAdjustment: joint_sd needs 1 or " +
                                   std::to_string(start.getNumJoints()) + " values, got " +
                                   std::to_string(noise.joint_sd.size()));
}

/*
  Full mode, the joint readings' error and the model residual both to be measured on an arm of 6
  joints or more: each view's joint corrections already span its camera's 6-D displacement, so the
  images cannot split the robot's error between them (the model residual differs only by its
  prior's shape). The joints alone take it (Result::robot_error_confounded); a residual stated, or
  measured without the joints', is kept.
*/
bool jointsTakeTheModelResidual(const vpKinematicChain &start, const KBA::Options &opt, const vpSelfCalibNoiseModel &noise)
{
  return !opt.hand_eye_only && noise.measure_joint_sd && noise.measure_model_sd && !noise.joint_sd.empty() &&
         noise.hasModelError() && start.getNumJoints() >= 6;
}

//! Full mode: the sd of each view's correction, the joints (the noise model's joint_sd, one value
//! for all or one per joint) then, with the model's residual, the camera pose (t m, r rad); empty
//! without robot error.
std::vector<double> fullModeSd(const vpKinematicChain &start, const KBA::Options &opt, const vpSelfCalibNoiseModel &noise,
                               int &n_joint, bool &camera_delta)
{
  std::vector<double> joint_sd;
  if (!noise.joint_sd.empty()) {
    joint_sd.assign(start.getNumJoints(), noise.joint_sd[0]);
    if (noise.joint_sd.size() > 1)
      joint_sd = noise.joint_sd;
  }
  // The camera pose error the model leaves (model_sd_*), after the joint corrections.
  camera_delta = !opt.hand_eye_only && noise.hasModelError();
  n_joint = static_cast<int>(joint_sd.size());
  if (camera_delta)
    for (int i = 0; i < 6; ++i)
      joint_sd.push_back(i < 3 ? noise.model_sd_translation : noise.model_sd_rotation);
  return joint_sd;
}

//! Stage 2, the observations of the reconstructed points, the intrinsics and the options the
//! adjustment keeps.
void fillAdjustment(Adjustment &a, const std::vector<vpSelfCalibDataset::View> &views, const vpCameraParameters &camera,
                    const KBA::Options &opt)
{
  const unsigned int m = static_cast<unsigned int>(views.size());
  for (unsigned int k = 0; k < m; ++k)
    for (const auto &o : views[k].points)
      if (a.X.count(o.id))
        a.obs.push_back({k, o.id, o.ip.get_u(), o.ip.get_v()});
  a.state.model = lensModel(opt);
  a.free_in = estimatedIntrinsics(camera, opt, a.in);
  a.scale_covariance = opt.scale_covariance;
  a.scale_covariance_chi2 = opt.scale_covariance_chi2;
}

/*
  Stage 2, the start: the views at the start model, the gauge (the yardstick, or the scale direction
  held; none in hand-eye-only mode), the observations that project, the known object's pose and the
  intrinsics held constant.
*/
void prepareStart(Adjustment &a, const vpSelfCalibDataset::Yardstick &yardstick, const KBA::Options &opt)
{
  a.state.update(true);
  a.rho0 = a.state.rho;
  if (!opt.scale_reference.empty())
    for (size_t i = 0; i < a.rho0.size(); ++i)
      a.rho0[i] = opt.scale_reference[a.state.id[i]];
  a.has_yardstick = yardstick.isSet() && a.X.count(yardstick.id_a) && a.X.count(yardstick.id_b);
  // Hand-eye-only: the metric end-effector motion fixes the scale; no gauge constraint.
  if (!opt.hand_eye_only)
  {
    a.scale_dir = scaleDirection(a.state);
    a.scale_gauge = scaleGauge(a.state, a.scale_dir, opt, a.scale_variance);
  }
  a.keepVisible();
  if (!opt.known_points.empty())
    startObject(opt.known_points, a);
  if (!a.free_in.empty() && a.free_in.size() < kIntrinsics) {
    std::vector<int> constant;
    for (int i = 0; i < kIntrinsics; ++i)
      if (std::find(a.free_in.begin(), a.free_in.end(), i) == a.free_in.end())
        constant.push_back(i);
    a.subset.reset(new ceres::SubsetManifold(kIntrinsics, constant));
  }
}

/*
  Stage 2, the estimated set: the rule's (estimatedSet), in full mode cut to what the data determine
  (decideSet, at the start values) unless the caller decided it (Options::estimated_set) or asks for
  the rule's whole set. refused: the freed parameters left out, with their reason.
*/
vpKinematicIdentification::Identifiability setOf(const vpKinematicChain &start, const vpCameraParameters &camera,
                                                 const std::vector<vpSelfCalibDataset::View> &views,
                                                 const vpSelfCalibDataset::Yardstick &yardstick,
                                                 const std::map<int, Eigen::Vector3d> &X0, const std::vector<vpColVector> &q,
                                                 const std::vector<Rigid> &fMe, const KBA::Options &opt,
                                                 const vpSelfCalibNoiseModel &noise, std::string &refused)
{
  const std::vector<std::string> freed =
      vpKinematicIdentification::matchParameters(start, opt.free, "vpKinematicBundleAdjustment: the freed parameters");
  const std::vector<std::string> fixed =
      vpKinematicIdentification::matchParameters(start, opt.fixed, "vpKinematicBundleAdjustment: the fixed parameters");
  if (opt.hand_eye_only && !freed.empty())
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment: free is for the full kinematic mode; hand-eye-only mode "
                               "estimates eMc (minus fixed) whatever the data");
  for (const std::string &f : freed)
    if (std::find(fixed.begin(), fixed.end(), f) != fixed.end())
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpKinematicBundleAdjustment: '" + f + "' is both fixed and freed: choose one");
  vpKinematicIdentification::Identifiability set = estimatedSet(start, q, opt);
  if (!opt.hand_eye_only && !opt.estimated_set.identified.empty()) {
    for (unsigned int i : opt.estimated_set.identified)
      if (i >= start.getNumParameters())
        throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                                   "vpKinematicBundleAdjustment: estimated_set is of another model (index out of range)");
    set = opt.estimated_set;
  } else if (!opt.hand_eye_only && opt.set_from_information) {
    int n_joint = 0;
    bool camera_delta = false;
    const std::vector<double> joint_sd = fullModeSd(start, opt, noise, n_joint, camera_delta);
    Adjustment a(X0, start, set.identified, q, fMe, false, joint_sd, n_joint, camera_delta);
    a.noise = noise;
    a.state.eye_to_hand = opt.eye_to_hand;
    a.P = static_cast<int>(set.identified.size());
    fillAdjustment(a, views, camera, opt);
    if (a.P > 0 && 2 * a.obs.size() > a.P + a.free_in.size() + 3 * a.X.size()) {
      prepareStart(a, yardstick, opt);
      set = decideSet(a, start, set, q, yardstick, opt);
    }
  }
  refused.clear();
  // With the kinematic prior a freed parameter the data do not determine is held by it (holdByPrior).
  const bool prior = opt.kinematicPrior() > 0 && !opt.hand_eye_only;
  for (const std::string &f : freed) {
    const unsigned int i = start.getParameterIndex(f);
    if (std::binary_search(set.identified.begin(), set.identified.end(), i))
      continue;
    for (const auto &u : set.unidentifiable)
      if (u.index == i && !(prior && u.cause == vpKinematicIdentification::CAUSE_DATA))
        refused += (refused.empty() ? "" : "; ") + f + ": " + u.reason + (u.needs.empty() ? "" : " (" + u.needs + ")");
  }
  if (!refused.empty())
    refused = "freed parameters the data do not determine, refused: " + refused;
  return set;
}

/*
  The kinematic prior (Settings::kinematic_prior): the parameters the data alone leave at nominal
  (cause DATA) are estimated too, held by the prior; they move from `unidentifiable` to `identified`
  and are listed in held_by_prior. The set's bias (columns the parameters left) is then 0.
*/
void holdByPrior(vpKinematicIdentification::Identifiability &set)
{
  std::vector<vpKinematicIdentification::Unidentifiable> left;
  for (const auto &u : set.unidentifiable)
    if (u.cause == vpKinematicIdentification::CAUSE_DATA) {
      set.held_by_prior.push_back(u);
      set.identified.push_back(u.index);
    } else
      left.push_back(u);
  if (set.held_by_prior.empty())
    return;
  set.unidentifiable = left;
  std::sort(set.identified.begin(), set.identified.end());
  set.identified.erase(std::unique(set.identified.begin(), set.identified.end()), set.identified.end());
  set.rank = static_cast<unsigned int>(set.identified.size());
  set.bias = vpMatrix(static_cast<unsigned int>(set.identified.size()), static_cast<unsigned int>(left.size()), 0.0);
}

/*
  The kinematic prior's sd of each estimated correction, its tolerance / K; infinite (no prior) for
  the hand-eye corrections of a measured eMc (Options::eMc_measured) that the data determine.
*/
std::vector<double> priorSds(const vpKinematicIdentification::Identifiability &set, unsigned int n_joints,
                             const KBA::Options &opt)
{
  const unsigned int eMc_first = (n_joints + 1) * vpKinematicChain::kBlockSize;
  std::vector<double> sd;
  for (unsigned int i : set.identified)
    sd.push_back(opt.eMc_measured && i >= eMc_first && !set.heldByPrior(i) ? std::numeric_limits<double>::infinity()
                                                                : toleranceOf(i, n_joints, opt) / opt.kinematicPrior());
  return sd;
}

/*
  The message of a singular information matrix: every cause that makes it singular named, the
  observations kept first (after many rejected matches the few left are the likelier cause than the
  poses' geometry), then the parameters not determined.
*/
std::string rankDeficientMessage(const KBA::Result &res, const KBA::Options &opt)
{
  const std::string kept_text = std::to_string(res.num_observations) + " observations kept of " +
                                std::to_string(res.num_observations + res.num_outliers);
  std::string message = opt.hand_eye_only
                    ? "the information matrix of the hand-eye correction and intrinsics is singular (" +
                          kept_text +
                          "): the observations kept do not determine eMc and the intrinsics: too few points "
                          "or views left, end-effector rotations all about parallel axes, or intrinsics a "
                          "planar scene cannot fix; add views, poses rotating about another axis, or fix the "
                          "intrinsics"
                    : "the information matrix of the corrections and intrinsics is singular (" + kept_text +
                          "): the views do not determine them (too few or too similar configurations, or too "
                          "few observations left)";
  if (!res.undetermined.empty()) {
    std::string list;
    for (const std::string &n : res.undetermined)
      list += (list.empty() ? "" : ", ") + n;
    message += "; not determined: " + list;
  }
  return message;
}

//! What run() and estimatedSet() start from: each view's joints and end-effector pose, the points
//! the views see, and their start values.
struct Inputs {
  std::vector<vpColVector> q;
  std::vector<Rigid> fMe;
  std::map<int, unsigned int> seen;
  std::map<int, Eigen::Vector3d> X0;
};

//! The caller's inputs checked (options, noise, camera, model, views, robot error), then Inputs;
//! `where` names the function in the messages.
Inputs checkedInputs(const vpKinematicChain &start, const vpCameraParameters &camera,
                     const std::vector<vpSelfCalibDataset::View> &views, const std::map<int, vpColVector> &points0,
                     const KBA::Options &opt, const vpSelfCalibNoiseModel &noise,
                     const std::string &where = "vpKinematicBundleAdjustment")
{
  opt.check();
  noise.check(where);
  vpSelfCalib::checkCamera(camera, where + ": the camera");
  vpSelfCalib::checkChain(start, where + ": the model '" + start.getName() + "'");
  checkViewsAndCamera(camera, static_cast<unsigned int>(views.size()), opt);
  Inputs in;
  collectViews(start, views, opt, in.q, in.fMe, in.seen);
  in.X0 = startPoints(points0, in.seen);
  checkRobotError(start, opt, noise);
  return in;
}

//! The adjustment (solve) or only its information at the start state (!solve); see the header.
vpKinematicBundleAdjustment::Result run(const vpKinematicChain &start, const vpCameraParameters &camera,
                                        const std::vector<vpSelfCalibDataset::View> &views,
                                        const vpSelfCalibDataset::Yardstick &yardstick,
                                        const std::map<int, vpColVector> &points0,
                                        const vpKinematicBundleAdjustment::Options &opt,
                                        const vpSelfCalibNoiseModel &given, bool solve)
{
  const QuietCeres quiet;
  const auto t0 = std::chrono::steady_clock::now();
  const Inputs in = checkedInputs(start, camera, views, points0, opt, given);
  if (!opt.scale_reference.empty() && opt.scale_reference.size() != start.getNumParameters())
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               "vpKinematicBundleAdjustment: scale_reference has " +
                                   std::to_string(opt.scale_reference.size()) + " values, the start model " +
                                   std::to_string(start.getNumParameters()) +
                                   " parameters: give the reference model's getParameters() (same robot), or leave it "
                                   "empty for the start model");
  const bool confounded = solve && jointsTakeTheModelResidual(start, opt, given);
  const vpSelfCalibNoiseModel noise =
      confounded ? given.withModelError(0, 0, vpSelfCalibNoiseModel::MEASURED) : given;
  const std::vector<vpColVector> &q = in.q;
  const std::vector<Rigid> &fMe = in.fMe;
  const std::map<int, Eigen::Vector3d> &X0 = in.X0;

  KBA::Result res;
  res.chain = start;
  res.camera = camera;
  res.noise = noise;
  res.sd.resize(start.getNumParameters());
  res.robot_error_confounded = confounded;
  std::string refused;
  // A robot error yet to be measured: the set decided again at the level measured (robotLevelGuessed()).
  const bool decided_here = !opt.hand_eye_only && opt.estimated_set.identified.empty() && opt.set_from_information;
  res.identifiability = setOf(start, camera, views, yardstick, X0, q, fMe, opt, noise, refused);
  if (!refused.empty()) {
    res.status = KBA::RANK_DEFICIENT;
    res.message = refused;
    return res;
  }
  const bool prior = opt.kinematicPrior() > 0 && !opt.hand_eye_only;
  if (prior)
    holdByPrior(res.identifiability);
  int n_joint = 0;
  bool camera_delta = false;
  const std::vector<double> joint_sd = fullModeSd(start, opt, noise, n_joint, camera_delta);
  Adjustment a(X0, start, res.identifiability.identified, q, fMe, opt.hand_eye_only && noise.hasPoseError(), joint_sd,
               n_joint, camera_delta);
  a.noise = noise;
  a.scale_prior = solve && !opt.hand_eye_only && !prior;
  if (prior) {
    res.kinematic_prior = opt.kinematicPrior();
    a.prior_sd = priorSds(res.identifiability, start.getNumJoints(), opt);
  }
  a.state.inverted = opt.hand_eye_only && opt.controller_poses_inverted;
  a.state.eye_to_hand = opt.eye_to_hand;
  a.P = static_cast<int>(res.identifiability.identified.size());
  fillAdjustment(a, views, camera, opt);
  const bool distortion = (opt.intrinsics & KBA::DISTORTION) || a.in[4] != 0;
  const size_t unknowns = a.P + a.free_in.size() + 3 * a.X.size();
  if (a.P == 0 || 2 * a.obs.size() <= unknowns) {
    res.status = KBA::TOO_FEW_OBSERVATIONS;
    res.message = std::to_string(a.obs.size()) + " observations of points seen twice for " +
                  std::to_string(unknowns) + " unknowns";
    return res;
  }
  prepareStart(a, yardstick, opt);

  ceres::Solver::Summary summary;
  const std::unique_ptr<ceres::Problem> problem = solveSchedule(a, yardstick, opt, solve, summary, res);
  if (!problem) {
    res.status = KBA::TOO_FEW_OBSERVATIONS;
    res.message = "every observation was rejected as an outlier";
    res.chain = a.state.chain;
    return res;
  }
  res.seconds_solve = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const KBA::Result solved = res;
  fillEstimate(a, distortion, res);
  if (solve && a.state.delta.empty() && a.state.dq.empty())
    reposeViews(a, res);
  if (solve && !summary.IsSolutionUsable()) {
    res.status = KBA::NO_CONVERGENCE;
    res.message = summary.message.empty() ? summary.BriefReport() : summary.message;
    return res;
  }
  if (opt.covariance) {
    const auto tc = std::chrono::steady_clock::now();
    fillCovariance(a, *problem, yardstick, start.getParameterNames(), res);
    if (!res.has_covariance && solve && robotLevelGuessed(given))
      // The corrections at the guessed level leave the estimate undetermined: the robot's error
      // is not measured, its readings taken as exact (robotErrorNotMeasured(), said by the caller).
      return run(start, camera, views, yardstick, points0, opt, withoutGuessedLevels(given), solve);
    if (!res.has_covariance) {
      res.seconds_covariance = std::chrono::duration<double>(std::chrono::steady_clock::now() - tc).count();
      res.status = KBA::RANK_DEFICIENT;
      res.message = rankDeficientMessage(res, opt);
      return res;
    }
    if (solve && !opt.hand_eye_only && (noise.measure_joint_sd || noise.measure_model_sd))
      settleRobotError(a, yardstick, opt, distortion, start.getParameterNames(), solved, res);
    if (solve && decided_here && robotLevelGuessed(noise)) {
      KBA::Options again = opt;
      again.estimated_set = setOf(start, camera, views, yardstick, X0, q, fMe, opt, res.noise, refused);
      if (prior)
        holdByPrior(again.estimated_set);
      if (refused.empty() && again.estimated_set.identified != res.identifiability.identified) {
        KBA::Result r = run(start, camera, views, yardstick, points0, again, res.noise, solve);
        r.robot_error_confounded = r.robot_error_confounded || res.robot_error_confounded; // stays merged
        return r;
      }
    }
    res.seconds_covariance = std::chrono::duration<double>(std::chrono::steady_clock::now() - tc).count();
    if (solve && opt.measure_layout_scale && opt.hand_eye_only && (a.has_object || a.has_yardstick))
      measureLayoutScale(a, yardstick, opt, res);
  }
  res.status = KBA::OK;
  std::ostringstream os;
  os << "ok: " << a.P << " corrections, " << a.free_in.size() << " intrinsics, " << res.points.size() << " points, "
     << res.num_observations << " observations (" << res.num_outliers << " dropped), rms " << res.rms
     << " px, scale from " << KBA::scaleSourceName(res.scale_source);
  res.message = os.str();
  return res;
}
} // namespace

const char *vpKinematicBundleAdjustment::scaleSourceName(ScaleSource s)
{
  switch (s) {
  case SCALE_YARDSTICK:
    return "the yardstick";
  case SCALE_ROBOT_MOTION:
    return "the robot's metric motion (and the yardstick when seen)";
  case SCALE_KNOWN_POINTS:
    return "the target's known layout";
  default:
    return "the start model (nominal scale: no yardstick)";
  }
}

const char *vpKinematicBundleAdjustment::statusName(Status s)
{
  switch (s) {
  case OK:
    return "ok";
  case TOO_FEW_OBSERVATIONS:
    return "too few observations";
  case RANK_DEFICIENT:
    return "rank deficient";
  case NO_CONVERGENCE:
    return "no convergence";
  }
  return "unknown";
}

void vpKinematicBundleAdjustment::Settings::check() const
{
  if (intrinsics > (FX | ASPECT | PRINCIPAL_POINT | DISTORTION | DISTORTION_K3))
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpKinematicBundleAdjustment: unknown intrinsics flag");
  if (distortion_model != DISTORTION_VISP && distortion_model != DISTORTION_OPENCV)
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpKinematicBundleAdjustment: unknown distortion model");
  if (distortion_model == DISTORTION_VISP ? !opencv_distortion.empty()
                                          : !(opencv_distortion.empty() || opencv_distortion.size() == 5))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment: opencv_distortion is (k1, k2, p1, p2, k3), with "
                               "distortion_model DISTORTION_OPENCV only (empty: all 0)");
  for (double k : opencv_distortion)
    if (!std::isfinite(k) || std::abs(k) > 1e3)
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpKinematicBundleAdjustment: opencv_distortion coefficients must be finite, |k| <= 1000");
  if ((intrinsics & DISTORTION_K3) && !(intrinsics & DISTORTION))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment: DISTORTION_K3 goes with DISTORTION");
  if (!(yardstick_sd > 0) || !(rank_tolerance > 0 && rank_tolerance < 1))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment: yardstick_sd must be positive, rank_tolerance in (0, 1)");
  if (!(tolerance_translation > 0) || !(tolerance_rotation > 0) || !(tolerance_hand_eye_translation > 0) ||
      !(tolerance_hand_eye_rotation > 0) || !(separation_tolerance > 0 && separation_tolerance < 1))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment: the tolerances must be positive, separation_tolerance in (0, 1)");
  if (kinematic_prior && (!(*kinematic_prior >= 0) || !std::isfinite(*kinematic_prior)))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment: kinematic_prior must be finite and positive (the prior's sd "
                               "is the tolerance over it), 0 (KINEMATIC_PRIOR_OFF) for no prior, or empty for the "
                               "default");
  if (!(known_points_sd > 0) || !std::isfinite(known_points_sd))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment: known_points_sd must be positive and finite");
  if (max_iterations == 0 || num_threads == 0)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment: max_iterations and num_threads must be at least 1");
}

double vpKinematicBundleAdjustment::Settings::kinematicPrior() const
{
  return kinematic_prior ? *kinematic_prior : DEFAULT_KINEMATIC_PRIOR;
}

void vpKinematicBundleAdjustment::Options::check() const
{
  Settings::check();
  for (double v : scale_reference)
    if (!std::isfinite(v))
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpKinematicBundleAdjustment: scale_reference holds a value that is not finite; give "
                                 "the reference model's getParameters(), or leave it empty for the start model");
  if (eye_to_hand && hand_eye_only)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment: eye_to_hand is the full kinematic mode's camera in the "
                               "world; in hand-eye-only mode the eye-to-hand set-up is controller_poses_inverted");
}

vpKinematicBundleAdjustment::Result vpKinematicBundleAdjustment::adjust(const vpKinematicChain &start,
                                                                       const vpCameraParameters &camera,
                                                                       const std::vector<vpSelfCalibDataset::View> &views,
                                                                       const vpSelfCalibDataset::Yardstick &yardstick,
                                                                       const std::map<int, vpColVector> &points,
                                                                       const Options &options,
                                                                       const vpSelfCalibNoiseModel &noise)
{
  return run(start, camera, views, yardstick, points, options, noise, true);
}

vpKinematicIdentification::Identifiability vpKinematicBundleAdjustment::estimatedSet(
    const vpKinematicChain &start, const vpCameraParameters &camera, const std::vector<vpSelfCalibDataset::View> &views,
    const vpSelfCalibDataset::Yardstick &yardstick, const std::map<int, vpColVector> &points, const Options &options,
    const vpSelfCalibNoiseModel &noise)
{
  const QuietCeres quiet;
  const Inputs in = checkedInputs(start, camera, views, points, options, noise);
  std::string refused;
  return setOf(start, camera, views, yardstick, in.X0, in.q, in.fMe, options, noise, refused);
}

vpColVector vpKinematicBundleAdjustment::predictedSd(const vpKinematicChain &start, const vpCameraParameters &camera,
                                                     const std::vector<vpSelfCalibDataset::View> &views,
                                                     const vpSelfCalibDataset::Yardstick &yardstick,
                                                     const std::map<int, vpColVector> &points,
                                                     const std::vector<unsigned int> &parameters, const Options &options,
                                                     const vpSelfCalibNoiseModel &noise)
{
  const QuietCeres quiet;
  const Inputs in = checkedInputs(start, camera, views, points, options, noise, "vpKinematicBundleAdjustment::predictedSd");
  const std::vector<vpColVector> &q = in.q;
  if (options.hand_eye_only)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment::predictedSd: for the full kinematic mode (hand_eye_only "
                               "estimates eMc whatever the data)");
  const vpKinematicIdentification::Identifiability set = vpKinematicBundle::estimatedSet(start, q, options);
  std::vector<int> columns;
  for (unsigned int i : parameters) {
    const auto it = std::lower_bound(set.identified.begin(), set.identified.end(), i);
    if (it == set.identified.end() || *it != i)
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpKinematicBundleAdjustment::predictedSd: parameter " + std::to_string(i) +
                                     " is not among the candidates of the model's rule for these views "
                                     "(a redundant twin of another, or fixed); ask for the rule's set only");
    columns.push_back(static_cast<int>(it - set.identified.begin()));
  }
  vpColVector out(static_cast<unsigned int>(parameters.size()), std::numeric_limits<double>::infinity());
  int n_joint = 0;
  bool camera_delta = false;
  const std::vector<double> joint_sd = fullModeSd(start, options, noise, n_joint, camera_delta);
  Adjustment a(in.X0, start, set.identified, q, in.fMe, false, joint_sd, n_joint, camera_delta);
  a.noise = noise;
  a.P = static_cast<int>(set.identified.size());
  fillAdjustment(a, views, camera, options);
  if (columns.empty() || !(2 * a.obs.size() > a.P + a.free_in.size() + 3 * a.X.size()))
    return out;
  prepareStart(a, yardstick, options);
  const Eigen::VectorXd sd = vpKinematicBundle::predictedSd(a, columns, yardstick, options);
  for (unsigned int k = 0; k < out.size(); ++k)
    out[k] = sd(k);
  return out;
}

vpKinematicBundleAdjustment::Result vpKinematicBundleAdjustment::information(
    const vpKinematicChain &state, const vpCameraParameters &camera, const std::vector<vpSelfCalibDataset::View> &views,
    const vpSelfCalibDataset::Yardstick &yardstick, const std::map<int, vpColVector> &points, const Options &options,
    const vpSelfCalibNoiseModel &noise)
{
  Options o = options;
  o.covariance = true;
  return run(state, camera, views, yardstick, points, o, noise, false);
}


vpMatrix vpKinematicBundleAdjustment::observationJacobian(const vpKinematicChain &chain,
                                                          const std::vector<unsigned int> &parameters,
                                                          const vpCameraParameters &camera, const vpColVector &q,
                                                          const vpColVector &X, vpColVector &uv)
{
  vpSelfCalib::checkCamera(camera, "vpKinematicBundleAdjustment::observationJacobian: the camera");
  vpSelfCalib::checkChain(chain, "vpKinematicBundleAdjustment::observationJacobian: the model");
  if (X.size() != 3)
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               "vpKinematicBundleAdjustment::observationJacobian: X must be a 3-vector");
  for (unsigned int i : parameters)
    if (i >= chain.getNumParameters())
      throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                                 "vpKinematicBundleAdjustment::observationJacobian: parameter index out of range");
  ViewState v;
  computeView(chain, parameters, q, true, v);
  double in[kIntrinsics];
  intrinsicsFrom(camera, Options(), in);
  constexpr int kVisp = 5; // p_x, mu, u0, v0, k_ud
  const int P = static_cast<int>(parameters.size());
  std::vector<double> Jr(2 * P), Ji(2 * kIntrinsics), JX(6);
  double Xp[3] = {X[0], X[1], X[2]}, p[2];
  uv.resize(2);
  vpMatrix J(2, P + kVisp + 3);
  if (!project(Distortion::VISP, v, in, Xp, p, Jr.data(), Ji.data(), JX.data(), P))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment::observationJacobian: the point is behind the camera");
  uv[0] = p[0];
  uv[1] = p[1];
  for (unsigned int r = 0; r < 2; ++r) {
    for (int c = 0; c < P; ++c)
      J[r][c] = Jr[r * P + c];
    for (int c = 0; c < kVisp; ++c)
      J[r][P + c] = Ji[r * kIntrinsics + c];
    for (int c = 0; c < 3; ++c)
      J[r][P + kVisp + c] = JX[r * 3 + c];
  }
  return J;
}
