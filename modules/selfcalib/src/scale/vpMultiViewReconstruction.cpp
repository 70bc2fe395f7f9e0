/*
 * ViSP SelfCalib: scale-consistent multi-view reconstruction (beyond the paper).
 */
#include <visp3/selfcalib/vpMultiViewReconstruction.h>
#include <visp3/selfcalib/vpFactorMethod.h>
#include <visp3/selfcalib/vpFundamentalMatrix.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <set>

#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <opencv2/calib3d.hpp>

#include "../core/vpSelfCalibCeres.h"
#include "../core/vpSelfCalibMath.h"
#include "../core/vpSelfCalibGeometry.h"
#include "../core/vpSelfCalibObservations.h"

using namespace vpSelfCalib;

static_assert(static_cast<int>(RobustLoss::NONE) == vpMultiViewReconstruction::LOSS_NONE &&
                  static_cast<int>(RobustLoss::HUBER) == vpMultiViewReconstruction::LOSS_HUBER &&
                  static_cast<int>(RobustLoss::CAUCHY) == vpMultiViewReconstruction::LOSS_CAUCHY,
              "the core robust losses and vpMultiViewReconstruction::Loss must agree");

namespace
{
double median(std::vector<double> v)
{
  const size_t h = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + h, v.end());
  return v[h];
}

/*
  Reprojection error of point X (frame of view 0) in view k, divided by the noise sd:
    Xc = R(q) X + t,  u = u0 + f Xc_x / Xc_z,  v = v0 + mu f Xc_y / Xc_z.
  q is an Eigen quaternion (x, y, z, w). View 0 uses the identity (no pose blocks).
*/
struct Reprojection {
  Reprojection(double u, double v, double u0, double v0, double mu, double sd)
    : u_(u), v_(v), u0_(u0), v0_(v0), mu_(mu), w_(1.0 / sd)
  {
  }
  template <typename T> bool project(const T *Xc, const T *f, T *r) const
  {
    r[0] = (T(u0_) + f[0] * Xc[0] / Xc[2] - T(u_)) * T(w_);
    r[1] = (T(v0_) + T(mu_) * f[0] * Xc[1] / Xc[2] - T(v_)) * T(w_);
    return true;
  }
  double u_, v_, u0_, v0_, mu_, w_;
};

struct ReprojectionPosed : Reprojection {
  using Reprojection::Reprojection;
  template <typename T> bool operator()(const T *q, const T *t, const T *X, const T *f, T *r) const
  {
    const Eigen::Quaternion<T> Q(q[3], q[0], q[1], q[2]);
    const Eigen::Matrix<T, 3, 1> Xc = Q * Eigen::Map<const Eigen::Matrix<T, 3, 1>>(X) +
                                      Eigen::Map<const Eigen::Matrix<T, 3, 1>>(t);
    return project(Xc.data(), f, r);
  }
};

struct ReprojectionReference : Reprojection {
  using Reprojection::Reprojection;
  template <typename T> bool operator()(const T *X, const T *f, T *r) const { return project(X, f, r); }
};

struct Observation {
  unsigned int view;
  int id;
  double u, v;
};

} // namespace

const char *vpMultiViewReconstruction::lossName(Loss loss)
{
  switch (loss) {
  case LOSS_NONE:
    return "none";
  case LOSS_HUBER:
    return "huber";
  case LOSS_CAUCHY:
    return "cauchy";
  }
  return "unknown";
}

vpMultiViewReconstruction::Loss vpMultiViewReconstruction::lossFromName(const std::string &name)
{
  for (Loss l : {LOSS_NONE, LOSS_HUBER, LOSS_CAUCHY})
    if (name == lossName(l))
      return l;
  throw vpSelfCalibException(vpSelfCalibException::badValue,
                             "robust loss '" + name + "': use none, huber or cauchy");
}

const char *vpMultiViewReconstruction::statusName(Status s)
{
  switch (s) {
  case OK:
    return "ok";
  case TOO_FEW_VIEWS:
    return "too few views with a pose";
  case TWO_VIEW_FAILED:
    return "two-view poses failed";
  case NO_CONVERGENCE:
    return "bundle adjustment did not converge";
  }
  return "unknown";
}

void vpMultiViewReconstruction::Options::check() const
{
  if (!(pixel_sd > 0) || !(loss_scale > 0) || !(init_tolerance > 0) || !(outlier_threshold >= 0) || !std::isfinite(outlier_threshold))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpMultiViewReconstruction: pixel_sd, loss_scale and init_tolerance must be positive, "
                               "outlier_threshold non-negative");
  if (min_points < 5 || max_iterations == 0 || num_threads == 0 || (max_pair_points > 0 && max_pair_points < 8))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpMultiViewReconstruction: min_points must be at least 5, max_pair_points 0 or at least "
                               "8, max_iterations and num_threads at least 1");
  if (!(twoview.fx > 0) || !(twoview.mu > 0))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpMultiViewReconstruction: twoview.fx and twoview.mu must be positive");
  twoview.check();
}

vpMultiViewReconstruction::Result vpMultiViewReconstruction::reconstruct(const std::vector<vpSelfCalibDataset::View> &views,
                                                                         const vpSelfCalibDataset::Yardstick &yardstick,
                                                                         const Options &opt)
{
  opt.check();
  const QuietCeres quiet;
  const auto t0 = std::chrono::steady_clock::now();
  const unsigned int m = static_cast<unsigned int>(views.size());
  if (m < 2)
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpMultiViewReconstruction: at least 2 views are needed");
  std::vector<std::map<int, vpImagePoint>> byId(m);
  for (unsigned int k = 0; k < m; ++k)
    for (const auto &o : views[k].points) {
      if (!std::isfinite(o.ip.get_u()) || !std::isfinite(o.ip.get_v()))
        throw vpSelfCalibException(vpSelfCalibException::badValue, "vpMultiViewReconstruction: view " +
                                                                       std::to_string(k) + " has a non-finite pixel");
      if (!byId[k].emplace(o.id, o.ip).second)
        throw vpSelfCalibException(vpSelfCalibException::badValue, "vpMultiViewReconstruction: view " +
                                                                       std::to_string(k) + " has point id " +
                                                                       std::to_string(o.id) + " twice");
    }

  const double u0 = opt.twoview.u0, v0 = opt.twoview.v0, mu = opt.twoview.mu;
  Result res;
  res.cMc0.assign(m, vpHomogeneousMatrix());
  res.posed.assign(m, false);
  res.posed[0] = true;

  // 1. Two-view poses of the pairs (0, k).
  std::vector<std::vector<int>> ids(m);
  std::vector<std::vector<vpImagePoint>> p0(m - 1), pk(m - 1);
  for (unsigned int k = 1; k < m; ++k)
    for (const auto &e : byId[0]) {
      auto it = byId[k].find(e.first);
      if (it != byId[k].end()) {
        ids[k].push_back(e.first);
        p0[k - 1].push_back(e.second);
        pk[k - 1].push_back(it->second);
      }
    }
  // The two-view estimates on at most max_pair_points correspondences per pair, evenly spread over
  // the list (the bundle adjustment below uses them all); sub[k - 1][j] is the position of
  // correspondence j in the subset, or -1.
  std::vector<std::vector<vpImagePoint>> s0(m - 1), sk(m - 1);
  std::vector<std::vector<int>> sub(m - 1);
  for (unsigned int k = 1; k < m; ++k) {
    const size_t n = p0[k - 1].size();
    const size_t keep = opt.max_pair_points > 0 ? std::min<size_t>(n, opt.max_pair_points) : n;
    sub[k - 1].assign(n, -1);
    for (size_t i = 0; i < keep; ++i) {
      const size_t j = i * n / keep;
      sub[k - 1][j] = static_cast<int>(s0[k - 1].size());
      s0[k - 1].push_back(p0[k - 1][j]);
      sk[k - 1].push_back(pk[k - 1][j]);
    }
  }
  vpTwoViewEstimator::Options to = opt.twoview;
  to.focal_mode = vpRefinedFactorMethod::KNOWN;
  res.fx = opt.twoview.fx;
  if (opt.focal_known) {
    for (unsigned int k = 1; k < m; ++k)
      res.pairs.push_back(vpTwoViewEstimator::estimate(s0[k - 1], sk[k - 1], to));
  } else {
    const vpTwoViewEstimator::SharedResult sr = vpTwoViewEstimator::estimateShared(s0, sk, to);
    res.pairs = sr.pairs;
    if (sr.converged && sr.fx > 0.5 * opt.twoview.fx && sr.fx < 2 * opt.twoview.fx)
      res.fx = sr.fx;
    else
      // The joint two-view refinement failed (wrong matches can drag it away): poses with the
      // guessed f instead; the bundle adjustment below estimates f.
      for (unsigned int k = 1; k < m; ++k)
        res.pairs[k - 1] = vpTwoViewEstimator::estimate(s0[k - 1], sk[k - 1], to);
  }
  res.seconds_twoview = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  // 2. Unit-baseline triangulations in the frame of view 0, reference pair, scale chaining.
  std::vector<std::map<int, Eigen::Vector3d>> tri(m);
  unsigned int ref = 0;
  double best_depth = std::numeric_limits<double>::infinity();
  for (unsigned int k = 1; k < m; ++k) {
    const vpTwoViewEstimator::Result &r = res.pairs[k - 1];
    if (r.status != vpTwoViewEstimator::OK)
      continue;
    std::vector<double> depths;
    for (size_t j = 0; j < ids[k].size(); ++j) {
      // Inlier of the pair: by its RANSAC when in the subset, else by the Sampson distance to its F.
      const int si = sub[k - 1][j];
      if (si >= 0 ? (!r.inliers.empty() && !r.inliers[si])
                  : (r.F.getRows() != 3 || vpFundamentalMatrix::sampsonDistance(r.F, p0[k - 1][j], pk[k - 1][j]) >
                                               opt.twoview.ransac.inlier_threshold))
        continue;
      const double x0[2] = {(p0[k - 1][j].get_u() - u0) / res.fx, (p0[k - 1][j].get_v() - v0) / (mu * res.fx)};
      const double xk[2] = {(pk[k - 1][j].get_u() - u0) / res.fx, (pk[k - 1][j].get_v() - v0) / (mu * res.fx)};
      double z0 = 0, zk = 0;
      vpFactorMethod::triangulateDepths(r.c2Mc1, x0, xk, z0, zk);
      if (!(z0 > 0 && zk > 0) || !std::isfinite(z0))
        continue;
      tri[k][ids[k][j]] = z0 * Eigen::Vector3d(x0[0], x0[1], 1);
      depths.push_back(z0);
    }
    if (depths.size() < opt.min_points) {
      tri[k].clear();
      continue;
    }
    const double d = median(depths);
    if (d < best_depth) {
      best_depth = d;
      ref = k;
    }
  }
  if (ref == 0) {
    size_t most = 0;
    for (unsigned int k = 1; k < m; ++k)
      most = std::max(most, p0[k - 1].size());
    res.status = TWO_VIEW_FAILED;
    res.message = most < 8 ? "the views share too few points with view 0 (at most " + std::to_string(most) +
                                 "): every view needs 8 or more points also seen in view 0"
                           : "no pair (0, k) gave a pose with enough triangulated points (at most " +
                                 std::to_string(most) + " common points; see the pairs' statuses)";
    return res;
  }
  res.reference_view = ref;
  std::vector<double> scale(m, 0);
  for (unsigned int k = 1; k < m; ++k) {
    std::vector<double> ratios;
    for (const auto &e : tri[k]) {
      auto it = tri[ref].find(e.first);
      if (it != tri[ref].end())
        ratios.push_back(it->second.norm() / e.second.norm());
    }
    if (ratios.size() < opt.min_points)
      continue;
    scale[k] = median(ratios);
    Rigid M = rigidFromVisp(res.pairs[k - 1].c2Mc1);
    M.t = M.t.normalized() * (k == ref ? 1.0 : scale[k]);
    res.cMc0[k] = toVisp(M);
    res.posed[k] = true;
  }
  unsigned int num_posed = 0;
  for (bool p : res.posed)
    num_posed += p;

  std::map<int, Eigen::Vector3d> Xinit;
  {
    std::map<int, std::vector<Eigen::Vector3d>> cand;
    for (unsigned int k = 1; k < m; ++k)
      if (res.posed[k])
        for (const auto &e : tri[k])
          cand[e.first].push_back(scale[k] * e.second);
    for (const auto &c : cand) {
      Eigen::Vector3d x;
      for (int a = 0; a < 3; ++a) {
        std::vector<double> v;
        for (const auto &p : c.second)
          v.push_back(p(a));
        x(a) = median(v);
      }
      Xinit[c.first] = x;
    }
  }

  // Points without a triangulation from view 0 (not seen there, or a wrong match there): the pair
  // of posed views whose triangulation most other views agree with (within init_tolerance px).
  {
    const double tol = std::max(opt.init_tolerance, opt.outlier_threshold * opt.pixel_sd);
    std::map<int, std::vector<unsigned int>> seen_in;
    for (unsigned int k = 1; k < m; ++k)
      if (res.posed[k])
        for (const auto &e : byId[k])
          if (!Xinit.count(e.first))
            seen_in[e.first].push_back(k);
    auto normalized = [&](const vpImagePoint &ip, double x[2]) {
      x[0] = (ip.get_u() - u0) / res.fx;
      x[1] = (ip.get_v() - v0) / (mu * res.fx);
    };
    for (const auto &e : seen_in) {
      const std::vector<unsigned int> &vk = e.second;
      if (vk.size() < 3)
        continue;
      const size_t n = std::min<size_t>(vk.size(), 12);
      unsigned int best = 0;
      double best_err = 0;
      Eigen::Vector3d best_X;
      for (size_t a = 0; a < n; ++a)
        for (size_t b = a + 1; b < n; ++b) {
          const Rigid A = rigidFromVisp(res.cMc0[vk[a]]), B = rigidFromVisp(res.cMc0[vk[b]]);
          double xa[2], xb[2], za = 0, zb = 0;
          normalized(byId[vk[a]].at(e.first), xa);
          normalized(byId[vk[b]].at(e.first), xb);
          vpFactorMethod::triangulateDepths(toVisp(B * A.inverse()), xa, xb, za, zb);
          if (!(za > 0 && zb > 0) || !std::isfinite(za))
            continue;
          const Eigen::Vector3d Xc0 = A.inverse() * (za * Eigen::Vector3d(xa[0], xa[1], 1));
          unsigned int count = 0;
          double err = 0;
          for (unsigned int k : vk) {
            const Eigen::Vector3d c = rigidFromVisp(res.cMc0[k]) * Xc0;
            const vpImagePoint &ip = byId[k].at(e.first);
            const double d = c(2) > 0 ? std::hypot(u0 + res.fx * c(0) / c(2) - ip.get_u(),
                                                   v0 + mu * res.fx * c(1) / c(2) - ip.get_v())
                                      : std::numeric_limits<double>::infinity();
            if (d < tol) {
              ++count;
              err += d;
            }
          }
          if (count > best || (count == best && err < best_err)) {
            best = count;
            best_err = err;
            best_X = Xc0;
          }
        }
      if (best >= 3)
        Xinit[e.first] = best_X;
    }
  }

  // 3. Bundle adjustment, on at most max_bundle_points points (evenly spread over the ids, the
  // yardstick ends always in); the others are triangulated afterwards with the adjusted poses.
  PointStore X(Xinit);
  std::set<int> bundled, later;
  {
    const size_t n = X.size();
    const size_t keep = opt.max_bundle_points > 0 ? std::min<size_t>(n, opt.max_bundle_points) : n;
    std::vector<int> all;
    for (const auto &e : X.index())
      all.push_back(e.first);
    for (size_t i = 0; i < keep; ++i)
      bundled.insert(all[i * n / keep]);
    for (int id : {yardstick.id_a, yardstick.id_b})
      if (X.count(id))
        bundled.insert(id);
    for (int id : all)
      if (!bundled.count(id))
        later.insert(id);
  }
  std::vector<Observation> obs;
  for (unsigned int k = 0; k < m; ++k)
    for (const auto &e : byId[k])
      if (bundled.count(e.first))
        obs.push_back({k, e.first, e.second.get_u(), e.second.get_v()});
  std::vector<Eigen::Vector4d> quat(m);
  std::vector<Eigen::Vector3d> trans(m);
  for (unsigned int k = 0; k < m; ++k) {
    const Rigid M = rigidFromVisp(res.cMc0[k]);
    const Eigen::Quaterniond q(M.R);
    quat[k] = Eigen::Vector4d(q.x(), q.y(), q.z(), q.w());
    trans[k] = M.t;
  }
  double f = res.fx;
  std::vector<bool> inlier(obs.size());
  for (size_t n = 0; n < obs.size(); ++n)
    inlier[n] = res.posed[obs[n].view];
  const auto tb = std::chrono::steady_clock::now();
  ceres::Solver::Summary summary;
  auto whitened = [&](size_t n) {
    const Observation &o = obs[n];
    double r[2];
    if (o.view == 0)
      ReprojectionReference(o.u, o.v, u0, v0, mu, opt.pixel_sd).project(X[o.id].data(), &f, r);
    else
      ReprojectionPosed(o.u, o.v, u0, v0, mu, opt.pixel_sd)(quat[o.view].data(), trans[o.view].data(), X[o.id].data(),
                                                            &f, r);
    return std::hypot(r[0], r[1]);
  };
  std::vector<double> start_errors;
  for (size_t n = 0; n < obs.size(); ++n)
    if (inlier[n])
      start_errors.push_back(whitened(n));
  /*
    Resection of the views the robust solve could not explain (a wrong two-view pose, or no pose):
    a view with fewer than half of its observations (or min_points) within the outlier threshold
    gets the pose OpenCV's PnP RANSAC finds from the current points, when that explains more of
    them; a view that still explains too few is left out (posed = false). Not the reference view,
    whose baseline is the unit.
  */
  auto resection = [&]() {
    bool changed = false;
    const double thr = std::max(4.0, opt.outlier_threshold * opt.pixel_sd);
    for (unsigned int k = 1; k < m; ++k) {
      if (k == ref)
        continue;
      std::vector<size_t> idx;
      unsigned int good = 0;
      for (size_t n = 0; n < obs.size(); ++n)
        if (obs[n].view == k) {
          idx.push_back(n);
          good += res.posed[k] && whitened(n) * opt.pixel_sd <= thr;
        }
      const unsigned int needed = std::max<unsigned int>(opt.min_points, static_cast<unsigned int>(idx.size() / 2));
      if (res.posed[k] && good >= needed)
        continue;
      std::vector<cv::Point3d> P3;
      std::vector<cv::Point2d> P2;
      for (size_t n : idx) {
        const Eigen::Vector3d &x = X[obs[n].id];
        P3.emplace_back(x(0), x(1), x(2));
        P2.emplace_back(obs[n].u, obs[n].v);
      }
      cv::Mat rvec, tvec;
      std::vector<int> pnp_inliers;
      const cv::Matx33d K(f, 0, u0, 0, mu * f, v0, 0, 0, 1);
      const bool ok = P3.size() >= 6 && cv::solvePnPRansac(P3, P2, K, cv::noArray(), rvec, tvec, false, 200, thr, 0.999,
                                                           pnp_inliers, cv::SOLVEPNP_EPNP);
      const bool was_posed = res.posed[k];
      if (ok && pnp_inliers.size() >= needed && pnp_inliers.size() > good) {
        const Eigen::Vector3d r(rvec.at<double>(0), rvec.at<double>(1), rvec.at<double>(2));
        const Eigen::Quaterniond qk(expSO3(r));
        quat[k] = Eigen::Vector4d(qk.x(), qk.y(), qk.z(), qk.w());
        trans[k] = Eigen::Vector3d(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
        res.posed[k] = true;
        changed = true;
      } else if (good < needed) {
        res.posed[k] = false;
        changed = changed || was_posed;
      }
      for (size_t n : idx)
        inlier[n] = res.posed[k];
    }
    return changed;
  };
  bool resected = false;
  const RobustSchedule schedule = robustSchedule(opt.loss != LOSS_NONE, opt.loss_scale, opt.outlier_threshold, start_errors);
  for (int stage = 0; stage < static_cast<int>(schedule.scales.size()); ++stage) {
    const double loss_scale = schedule.scales[stage];
    const bool robust = loss_scale > 0;
    ceres::Problem::Options po;
    po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(po);
    ceres::EigenQuaternionManifold quaternion;
    ceres::SphereManifold<3> sphere;
    auto order = std::make_shared<ceres::ParameterBlockOrdering>();
    for (size_t n = 0; n < obs.size(); ++n) {
      if (!inlier[n])
        continue;
      const Observation &o = obs[n];
      double *Xp = X[o.id].data();
      ceres::LossFunction *loss = robust ? makeLoss(static_cast<RobustLoss>(opt.loss), loss_scale) : nullptr;
      if (o.view == 0)
        problem.AddResidualBlock(new ceres::AutoDiffCostFunction<ReprojectionReference, 2, 3, 1>(
                                     new ReprojectionReference(o.u, o.v, u0, v0, mu, opt.pixel_sd)),
                                 loss, Xp, &f);
      else
        problem.AddResidualBlock(new ceres::AutoDiffCostFunction<ReprojectionPosed, 2, 4, 3, 3, 1>(
                                     new ReprojectionPosed(o.u, o.v, u0, v0, mu, opt.pixel_sd)),
                                 loss, quat[o.view].data(), trans[o.view].data(), Xp, &f);
      order->AddElementToGroup(Xp, 0);
    }
    for (unsigned int k = 1; k < m; ++k)
      if (res.posed[k] && problem.HasParameterBlock(quat[k].data())) {
        problem.SetManifold(quat[k].data(), &quaternion);
        if (k == ref)
          problem.SetManifold(trans[k].data(), &sphere);
        // One group per block, in view order: within a group Ceres orders blocks by address, which
        // changes from run to run for separately allocated blocks (and so would the last digits).
        order->AddElementToGroup(quat[k].data(), static_cast<int>(2 * k - 1));
        order->AddElementToGroup(trans[k].data(), static_cast<int>(2 * k));
      }
    if (!problem.HasParameterBlock(&f)) {
      res.status = TOO_FEW_VIEWS;
      res.message = "no observation left";
      return res;
    }
    order->AddElementToGroup(&f, static_cast<int>(2 * m));
    if (opt.focal_known)
      problem.SetParameterBlockConstant(&f);
    ceres::Solver::Options so = solverOptions(opt.max_iterations, opt.tight,
                                              m > 60 ? ceres::SPARSE_SCHUR : ceres::DENSE_SCHUR);
    so.linear_solver_ordering = order;
    so.num_threads = static_cast<int>(opt.num_threads);
    vpSelfCalib::solve(so, &problem, &summary);
    if (!summary.IsSolutionUsable())
      break;
    if (stage == 0 && robust && !resected) {
      resected = true;
      if (resection()) {
        stage = -1; // the robust solve again, with the resected views
        continue;
      }
    }
    // Outliers: whitened error above the threshold, tested on every observation so that one
    // wrongly dropped in the robust pass can come back.
    if (stage == schedule.trim_after) {
      for (size_t n = 0; n < obs.size(); ++n)
        inlier[n] = res.posed[obs[n].view] && whitened(n) <= opt.outlier_threshold;
      dropPoorlyObservedPoints(obs, inlier);
    }
    if (stage + 1 == static_cast<int>(schedule.scales.size()) && !opt.focal_known) {
      ceres::Covariance::Options co = covarianceOptions();
      co.algorithm_type = ceres::SPARSE_QR;
      co.num_threads = static_cast<int>(opt.num_threads);
      ceres::Covariance cov(co);
      std::vector<std::pair<const double *, const double *>> blocks = {{&f, &f}};
      double c = 0;
      if (cov.Compute(blocks, &problem) && cov.GetCovarianceBlock(&f, &f, &c))
        res.fx_sd = std::sqrt(c);
      else
        res.fx_sd = std::numeric_limits<double>::infinity();
    }
  }
  res.seconds_bundle = std::chrono::duration<double>(std::chrono::steady_clock::now() - tb).count();
  if (!summary.IsSolutionUsable()) {
    res.status = NO_CONVERGENCE;
    res.message = summary.BriefReport();
    return res;
  }
  res.fx = f;

  // Points left out of the bundle adjustment: midpoint of their rays from the posed views, the views
  // whose reprojection error exceeds the outlier threshold left out (twice), kept with two views.
  for (int id : later) {
    std::vector<Observation> po;
    for (unsigned int k = 0; k < m; ++k) {
      auto it = byId[k].find(id);
      if (res.posed[k] && it != byId[k].end())
        po.push_back({k, id, it->second.get_u(), it->second.get_v()});
    }
    std::vector<bool> use(po.size(), true);
    Eigen::Vector3d x = X[id];
    for (int round = 0; round < 3; ++round) {
      Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
      Eigen::Vector3d b = Eigen::Vector3d::Zero();
      unsigned int n = 0;
      for (size_t i = 0; i < po.size(); ++i) {
        if (!use[i])
          continue;
        const Eigen::Quaterniond Q(quat[po[i].view](3), quat[po[i].view](0), quat[po[i].view](1), quat[po[i].view](2));
        const Eigen::Matrix3d Rt = Q.normalized().toRotationMatrix().transpose();
        const Eigen::Vector3d o = -Rt * trans[po[i].view];
        const Eigen::Vector3d d =
            (Rt * Eigen::Vector3d((po[i].u - u0) / f, (po[i].v - v0) / (mu * f), 1)).normalized();
        const Eigen::Matrix3d Pd = Eigen::Matrix3d::Identity() - d * d.transpose();
        A += Pd;
        b += Pd * o;
        ++n;
      }
      if (n < 2)
        break;
      x = A.ldlt().solve(b);
      for (size_t i = 0; i < po.size(); ++i) {
        X[id] = x;
        obs.push_back(po[i]);
        use[i] = whitened(obs.size() - 1) <= std::max(opt.outlier_threshold, 20.0 / (round + 1));
        obs.pop_back();
      }
    }
    unsigned int n = 0;
    for (bool u : use)
      n += u;
    if (n < 2 || !x.allFinite())
      continue;
    X[id] = x;
    for (size_t i = 0; i < po.size(); ++i) {
      obs.push_back(po[i]);
      inlier.push_back(use[i] && whitened(obs.size() - 1) <= opt.outlier_threshold);
    }
  }

  // Statistics over the kept observations; points without any kept observation are dropped.
  res.inliers.resize(m);
  for (unsigned int k = 0; k < m; ++k)
    res.inliers[k].assign(views[k].points.size(), false);
  std::vector<std::map<int, size_t>> index(m);
  for (unsigned int k = 0; k < m; ++k)
    for (size_t j = 0; j < views[k].points.size(); ++j)
      index[k][views[k].points[j].id] = j;
  std::set<int> kept;
  double sum = 0;
  for (size_t n = 0; n < obs.size(); ++n) {
    if (!inlier[n]) {
      ++res.num_outliers;
      continue;
    }
    const Observation &o = obs[n];
    double r[2];
    if (o.view == 0)
      ReprojectionReference(o.u, o.v, u0, v0, mu, 1.0).project(X[o.id].data(), &f, r);
    else
      ReprojectionPosed(o.u, o.v, u0, v0, mu, 1.0)(quat[o.view].data(), trans[o.view].data(), X[o.id].data(), &f, r);
    sum += r[0] * r[0] + r[1] * r[1];
    ++res.num_observations;
    res.inliers[o.view][index[o.view][o.id]] = true;
    kept.insert(o.id);
  }
  res.rms = res.num_observations ? std::sqrt(sum / (2.0 * res.num_observations)) : 0;

  // 4. Scale by the yardstick when both ends are there.
  double s = 1;
  if (yardstick.isSet() && kept.count(yardstick.id_a) && kept.count(yardstick.id_b)) {
    res.yardstick_unit_length = (X[yardstick.id_a] - X[yardstick.id_b]).norm();
    if (res.yardstick_unit_length > 0) {
      s = yardstick.length / res.yardstick_unit_length;
      res.metric = true;
    }
  }
  for (unsigned int k = 1; k < m; ++k)
    if (res.posed[k]) {
      Rigid M;
      M.R = Eigen::Quaterniond(quat[k](3), quat[k](0), quat[k](1), quat[k](2)).normalized().toRotationMatrix();
      M.t = s * trans[k];
      res.cMc0[k] = toVisp(M);
    }
  for (int id : kept) {
    const Eigen::Vector3d x = s * X[id];
    vpColVector v(3);
    for (unsigned int a = 0; a < 3; ++a)
      v[a] = x(a);
    res.points[id] = v;
  }
  num_posed = 0;
  for (bool p : res.posed)
    num_posed += p;
  res.status = OK;
  res.message = "ok: " + std::to_string(num_posed) + " of " + std::to_string(m) + " views, " +
                std::to_string(res.points.size()) + " points, " + std::to_string(res.num_outliers) + " outliers, rms " +
                std::to_string(res.rms) + " px" + (res.metric ? ", metric" : ", unit reference baseline");
  return res;
}
