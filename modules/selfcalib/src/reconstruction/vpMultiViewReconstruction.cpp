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

#include "../core/vpSelfCalibCamera.h"
#include "../core/vpSelfCalibCeres.h"
#include "../core/vpSelfCalibMath.h"
#include "../core/vpSelfCalibGeometry.h"
#include "../core/vpSelfCalibObservations.h"

using namespace vpSelfCalib;

static_assert(static_cast<int>(RobustLoss::NONE) == vpSelfCalibNoiseModel::LOSS_NONE &&
                  static_cast<int>(RobustLoss::HUBER) == vpSelfCalibNoiseModel::LOSS_HUBER &&
                  static_cast<int>(RobustLoss::CAUCHY) == vpSelfCalibNoiseModel::LOSS_CAUCHY,
              "the core robust losses and vpSelfCalibNoiseModel::Loss must agree");

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
    Xc = R(q) X + t,  r = (projectPoint(NONE, (f, mu, u0, v0), Xc) - (u, v)) / sd,
  the core camera model without distortion: u = u0 + f Xc_x / Xc_z, v = v0 + mu f Xc_y / Xc_z.
  q is an Eigen quaternion (x, y, z, w). View 0 uses the identity (no pose blocks).
*/
struct Reprojection {
  Reprojection(double u, double v, double u0, double v0, double mu, double sd)
    : u_(u), v_(v), u0_(u0), v0_(v0), mu_(mu), w_(1.0 / sd)
  {
  }
  template <typename T> bool project(const T *Xc, const T *f, T *r) const
  {
    const T in[4] = {f[0], T(mu_), T(u0_), T(v0_)};
    T uv[2];
    projectPoint(Distortion::NONE, in, Xc, uv);
    r[0] = (uv[0] - T(u_)) * T(w_);
    r[1] = (uv[1] - T(v_)) * T(w_);
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

void vpMultiViewReconstruction::Settings::check() const
{
  if (!(init_tolerance > 0))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpMultiViewReconstruction: init_tolerance must be positive");
  if (min_points < 5 || max_iterations == 0 || num_threads == 0 || (max_pair_points > 0 && max_pair_points < 8))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpMultiViewReconstruction: min_points must be at least 5, max_pair_points 0 or at least "
                               "8, max_iterations and num_threads at least 1");
}

void vpMultiViewReconstruction::Options::check() const
{
  Settings::check();
  if (!(twoview.fx > 0) || !(twoview.mu > 0))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpMultiViewReconstruction: twoview.fx and twoview.mu must be positive");
  twoview.check();
}

namespace
{
using Options = vpMultiViewReconstruction::Options;
using Result = vpMultiViewReconstruction::Result;

/*
  What the stages of reconstruct() share. The observations of the bundle adjustment (obs, with
  their inlier flags) are collected once; the points left out of it are appended at the end.
*/
struct State {
  State(const std::vector<vpSelfCalibDataset::View> &views_, const vpSelfCalibDataset::Yardstick &yardstick_,
        const Options &opt_, const vpSelfCalibNoiseModel &noise_)
    : views(views_), yardstick(yardstick_), opt(opt_), noise(noise_), m(static_cast<unsigned int>(views_.size())),
      u0(opt_.twoview.u0), v0(opt_.twoview.v0), mu(opt_.twoview.mu), t0(std::chrono::steady_clock::now())
  {
  }
  const std::vector<vpSelfCalibDataset::View> &views;
  const vpSelfCalibDataset::Yardstick &yardstick;
  const Options &opt;
  const vpSelfCalibNoiseModel &noise;
  const unsigned int m;
  const double u0, v0, mu;
  const std::chrono::steady_clock::time_point t0;
  Result res;

  std::vector<std::map<int, vpImagePoint>> byId; //!< per view: id -> pixel
  // Pairs (0, k) at index k - 1: common ids (at index k), their pixels in views 0 and k, and the
  // position of each in the two-view subset (or -1).
  std::vector<std::vector<int>> ids;
  std::vector<std::vector<vpImagePoint>> p0, pk;
  std::vector<std::vector<int>> sub;
  std::vector<std::map<int, Eigen::Vector3d>> tri; //!< per view k: unit-baseline triangulations, frame 0
  std::vector<double> scale;                       //!< per view k: scale of its pair relative to the reference
  std::map<int, Eigen::Vector3d> Xinit;            //!< initial points, frame 0

  // The bundle adjustment: points, the ids left out of it, observations, poses and f.
  std::unique_ptr<PointStore> X;
  std::set<int> later;
  std::vector<Observation> obs;
  std::vector<bool> inlier;
  std::vector<Eigen::Vector4d> quat;
  std::vector<Eigen::Vector3d> trans;
  double f = 0;
  //! The outlier test's noise in stated sds: 1, or the measured noise over the stated one when
  //! larger (trimOutliers).
  double noise_factor = 1;
  ceres::Solver::Summary summary;                  //!< of the last solve
  ceres::EigenQuaternionManifold quaternion;       //!< the manifolds of every solve (problems do not own them)
  ceres::SphereManifold<3> sphere;
};

//! The camera of the reconstruction at focal length f: (f, mu, u0, v0), no distortion.
CameraModel pinhole(const State &s, double f)
{
  const double in[4] = {f, s.mu, s.u0, s.v0};
  return CameraModel(Distortion::NONE, in);
}

//! (u, v) of an image point.
Eigen::Vector2d pixel(const vpImagePoint &ip) { return Eigen::Vector2d(ip.get_u(), ip.get_v()); }

//! The Reprojection residual (weight 1 / sd) of observation o against point X with the current poses and f.
Eigen::Vector2d residual(const State &s, const Observation &o, const Eigen::Vector3d &X, double sd)
{
  Eigen::Vector2d r;
  if (o.view == 0)
    ReprojectionReference(o.u, o.v, s.u0, s.v0, s.mu, sd).project(X.data(), &s.f, r.data());
  else
    ReprojectionPosed(o.u, o.v, s.u0, s.v0, s.mu, sd)(s.quat[o.view].data(), s.trans[o.view].data(), X.data(), &s.f,
                                                      r.data());
  return r;
}

//! Depth of point X (frame of view 0) in the camera of observation o's view, current pose.
double depthInView(const State &s, const Observation &o, const Eigen::Vector3d &X)
{
  if (o.view == 0)
    return X.z();
  const Eigen::Vector4d &q = s.quat[o.view];
  return (Eigen::Quaterniond(q(3), q(0), q(1), q(2)) * X + s.trans[o.view]).z();
}

/*
  Whitened reprojection error (in noise sd) of observation o against point X; infinite when X is
  not in front of o's camera (cheirality): the pinhole formula projects X and its mirror image -X
  through the centre to the same pixel, so the reprojection error alone cannot see a point behind
  a camera, and such an observation is never an inlier.
*/
double whitened(const State &s, const Observation &o, const Eigen::Vector3d &X)
{
  if (!(depthInView(s, o, X) > 0))
    return std::numeric_limits<double>::infinity();
  const Eigen::Vector2d r = residual(s, o, X, s.noise.pixel_sd);
  return std::hypot(r(0), r(1));
}

//! Whitened error of bundle observation n against its current point.
double whitened(State &s, size_t n) { return whitened(s, s.obs[n], (*s.X)[s.obs[n].id]); }

//! Input checks and the observations by id, per view.
void collectObservations(State &s)
{
  if (s.m < 2)
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpMultiViewReconstruction: at least 2 views are needed");
  s.byId.resize(s.m);
  for (unsigned int k = 0; k < s.m; ++k)
    for (const auto &o : s.views[k].points) {
      if (!std::isfinite(o.ip.get_u()) || !std::isfinite(o.ip.get_v()))
        throw vpSelfCalibException(vpSelfCalibException::badValue, "vpMultiViewReconstruction: view " +
                                                                       std::to_string(k) + " has a non-finite pixel");
      if (!s.byId[k].emplace(o.id, o.ip).second)
        throw vpSelfCalibException(vpSelfCalibException::badValue, "vpMultiViewReconstruction: view " +
                                                                       std::to_string(k) + " has point id " +
                                                                       std::to_string(o.id) + " twice");
    }
  s.res.cMc0.assign(s.m, vpHomogeneousMatrix());
  s.res.posed.assign(s.m, false);
  s.res.posed[0] = true;
}

//! 1. Two-view poses of the pairs (0, k).
void twoViewPoses(State &s)
{
  const unsigned int m = s.m;
  const Options &opt = s.opt;
  Result &res = s.res;
  s.ids.resize(m);
  s.p0.resize(m - 1);
  s.pk.resize(m - 1);
  for (unsigned int k = 1; k < m; ++k)
    for (const auto &e : s.byId[0]) {
      auto it = s.byId[k].find(e.first);
      if (it != s.byId[k].end()) {
        s.ids[k].push_back(e.first);
        s.p0[k - 1].push_back(e.second);
        s.pk[k - 1].push_back(it->second);
      }
    }
  // The two-view estimates on at most max_pair_points correspondences per pair, evenly spread over
  // the list (the bundle adjustment below uses them all); sub[k - 1][j] is the position of
  // correspondence j in the subset, or -1.
  std::vector<std::vector<vpImagePoint>> s0(m - 1), sk(m - 1);
  s.sub.resize(m - 1);
  for (unsigned int k = 1; k < m; ++k) {
    const size_t n = s.p0[k - 1].size();
    const size_t keep = opt.max_pair_points > 0 ? std::min<size_t>(n, opt.max_pair_points) : n;
    s.sub[k - 1].assign(n, -1);
    for (size_t i = 0; i < keep; ++i) {
      const size_t j = i * n / keep;
      s.sub[k - 1][j] = static_cast<int>(s0[k - 1].size());
      s0[k - 1].push_back(s.p0[k - 1][j]);
      sk[k - 1].push_back(s.pk[k - 1][j]);
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
  res.seconds_twoview = std::chrono::duration<double>(std::chrono::steady_clock::now() - s.t0).count();
}

/*
  2. Unit-baseline triangulations of the inliers of each pair in the frame of view 0, and the
  reference pair (smallest median depth). False (status TWO_VIEW_FAILED) when no pair is usable.
*/
bool triangulatePairs(State &s)
{
  const Options &opt = s.opt;
  Result &res = s.res;
  const CameraModel camera = pinhole(s, res.fx);
  s.tri.resize(s.m);
  unsigned int ref = 0;
  double best_depth = std::numeric_limits<double>::infinity();
  for (unsigned int k = 1; k < s.m; ++k) {
    const vpTwoViewEstimator::Result &r = res.pairs[k - 1];
    if (r.status != vpTwoViewEstimator::OK)
      continue;
    const std::vector<vpImagePoint> &p0 = s.p0[k - 1], &pk = s.pk[k - 1];
    std::vector<double> depths;
    for (size_t j = 0; j < s.ids[k].size(); ++j) {
      // Inlier of the pair: by its RANSAC when in the subset, else by the Sampson distance to its F.
      const int si = s.sub[k - 1][j];
      if (si >= 0 ? (!r.inliers.empty() && !r.inliers[si])
                  : (r.F.getRows() != 3 ||
                     vpFundamentalMatrix::sampsonDistance(r.F, p0[j], pk[j]) > opt.twoview.ransac.inlier_threshold))
        continue;
      const Eigen::Vector2d x0 = camera.unproject(pixel(p0[j])), xk = camera.unproject(pixel(pk[j]));
      double z0 = 0, zk = 0;
      vpFactorMethod::triangulateDepths(r.c2Mc1, x0.data(), xk.data(), z0, zk);
      if (!(z0 > 0 && zk > 0) || !std::isfinite(z0))
        continue;
      s.tri[k][s.ids[k][j]] = z0 * Eigen::Vector3d(x0(0), x0(1), 1);
      depths.push_back(z0);
    }
    if (depths.size() < opt.min_points) {
      s.tri[k].clear();
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
    for (unsigned int k = 1; k < s.m; ++k)
      most = std::max(most, s.p0[k - 1].size());
    res.status = vpMultiViewReconstruction::TWO_VIEW_FAILED;
    res.message = most < 8 ? "the views share too few points with view 0 (at most " + std::to_string(most) +
                                 "): every view needs 8 or more points also seen in view 0"
                           : "no pair (0, k) gave a pose with enough triangulated points (at most " +
                                 std::to_string(most) + " common points; see the pairs' statuses)";
    return false;
  }
  res.reference_view = ref;
  return true;
}

/*
  Scale chaining: the scale of each pair relative to the reference (median ratio of the distances
  of the points both triangulated), its pose, and the initial points (coordinate-wise median of
  the scaled triangulations).
*/
void chainScales(State &s)
{
  Result &res = s.res;
  const unsigned int ref = res.reference_view;
  s.scale.assign(s.m, 0);
  for (unsigned int k = 1; k < s.m; ++k) {
    std::vector<double> ratios;
    for (const auto &e : s.tri[k]) {
      auto it = s.tri[ref].find(e.first);
      if (it != s.tri[ref].end())
        ratios.push_back(it->second.norm() / e.second.norm());
    }
    if (ratios.size() < s.opt.min_points)
      continue;
    s.scale[k] = median(ratios);
    Rigid M = rigidFromVisp(res.pairs[k - 1].c2Mc1);
    M.t = M.t.normalized() * (k == ref ? 1.0 : s.scale[k]);
    res.cMc0[k] = toVisp(M);
    res.posed[k] = true;
  }
  std::map<int, std::vector<Eigen::Vector3d>> cand;
  for (unsigned int k = 1; k < s.m; ++k)
    if (res.posed[k])
      for (const auto &e : s.tri[k])
        cand[e.first].push_back(s.scale[k] * e.second);
  for (const auto &c : cand) {
    Eigen::Vector3d x;
    for (int a = 0; a < 3; ++a) {
      std::vector<double> v;
      for (const auto &p : c.second)
        v.push_back(p(a));
      x(a) = median(v);
    }
    s.Xinit[c.first] = x;
  }
}

/*
  Points without a triangulation from view 0 (not seen there, or a wrong match there): the pair of
  posed views whose triangulation most other views agree with (within init_tolerance px), when at
  least three agree.
*/
void initializePointsNotSeenFromView0(State &s)
{
  const Options &opt = s.opt;
  const Result &res = s.res;
  const double tol = std::max(opt.init_tolerance, s.noise.outlier_threshold * s.noise.pixel_sd);
  std::map<int, std::vector<unsigned int>> seen_in;
  for (unsigned int k = 1; k < s.m; ++k)
    if (res.posed[k])
      for (const auto &e : s.byId[k])
        if (!s.Xinit.count(e.first))
          seen_in[e.first].push_back(k);
  const CameraModel camera = pinhole(s, res.fx);
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
        const Eigen::Vector2d xa = camera.unproject(pixel(s.byId[vk[a]].at(e.first)));
        const Eigen::Vector2d xb = camera.unproject(pixel(s.byId[vk[b]].at(e.first)));
        double za = 0, zb = 0;
        vpFactorMethod::triangulateDepths(toVisp(B * A.inverse()), xa.data(), xb.data(), za, zb);
        if (!(za > 0 && zb > 0) || !std::isfinite(za))
          continue;
        const Eigen::Vector3d Xc0 = A.inverse() * (za * Eigen::Vector3d(xa(0), xa(1), 1));
        unsigned int count = 0;
        double err = 0;
        for (unsigned int k : vk) {
          const vpImagePoint &ip = s.byId[k].at(e.first);
          Eigen::Vector2d uv;
          const double d = camera.project(rigidFromVisp(res.cMc0[k]) * Xc0, uv, nullptr, nullptr)
                               ? std::hypot(uv(0) - ip.get_u(), uv(1) - ip.get_v())
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
      s.Xinit[e.first] = best_X;
  }
}

/*
  3. The bundle adjustment's start: at most max_bundle_points points (evenly spread over the ids,
  the yardstick ends always in; the others, `later`, are triangulated afterwards with the adjusted
  poses), their observations (inliers: those of posed views), the poses as quaternions and f.
*/
void setUpBundle(State &s)
{
  s.X = std::make_unique<PointStore>(s.Xinit);
  const size_t n = s.X->size();
  const size_t keep = s.opt.max_bundle_points > 0 ? std::min<size_t>(n, s.opt.max_bundle_points) : n;
  std::vector<int> all;
  for (const auto &e : s.X->index())
    all.push_back(e.first);
  std::set<int> bundled;
  for (size_t i = 0; i < keep; ++i)
    bundled.insert(all[i * n / keep]);
  for (int id : {s.yardstick.id_a, s.yardstick.id_b})
    if (s.X->count(id))
      bundled.insert(id);
  for (int id : all)
    if (!bundled.count(id))
      s.later.insert(id);
  for (unsigned int k = 0; k < s.m; ++k)
    for (const auto &e : s.byId[k])
      if (bundled.count(e.first))
        s.obs.push_back({k, e.first, e.second.get_u(), e.second.get_v()});
  s.quat.resize(s.m);
  s.trans.resize(s.m);
  for (unsigned int k = 0; k < s.m; ++k) {
    const Rigid M = rigidFromVisp(s.res.cMc0[k]);
    const Eigen::Quaterniond q(M.R);
    s.quat[k] = Eigen::Vector4d(q.x(), q.y(), q.z(), q.w());
    s.trans[k] = M.t;
  }
  s.f = s.res.fx;
  s.inlier.resize(s.obs.size());
  for (size_t i = 0; i < s.obs.size(); ++i)
    s.inlier[i] = s.res.posed[s.obs[i].view];
}

//! Pose c_kMc_0 of a view from its quaternion and translation.
Rigid viewPose(const State &s, unsigned int k)
{
  Rigid M;
  M.R = Eigen::Quaterniond(s.quat[k](3), s.quat[k](0), s.quat[k](1), s.quat[k](2)).normalized().toRotationMatrix();
  M.t = s.trans[k];
  return M;
}

/*
  One solve of the bundle adjustment on the inlier observations, with the robust loss of the given
  scale (0: plain least squares), to the tight tolerances when `converge` (the solve that gives the
  estimate) or opt.tight. The problem is returned for the covariance; nullptr when no observation
  is left.
*/
std::unique_ptr<ceres::Problem> solveBundle(State &s, double loss_scale, bool converge)
{
  const Options &opt = s.opt;
  const bool robust = loss_scale > 0;
  ceres::Problem::Options po;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  auto problem = std::make_unique<ceres::Problem>(po);
  auto order = std::make_shared<ceres::ParameterBlockOrdering>();
  for (size_t n = 0; n < s.obs.size(); ++n) {
    if (!s.inlier[n])
      continue;
    const Observation &o = s.obs[n];
    double *Xp = (*s.X)[o.id].data();
    ceres::LossFunction *loss = robust ? makeLoss(static_cast<RobustLoss>(s.noise.loss), loss_scale) : nullptr;
    if (o.view == 0)
      problem->AddResidualBlock(new ceres::AutoDiffCostFunction<ReprojectionReference, 2, 3, 1>(
                                    new ReprojectionReference(o.u, o.v, s.u0, s.v0, s.mu, s.noise.pixel_sd)),
                                loss, Xp, &s.f);
    else
      problem->AddResidualBlock(new ceres::AutoDiffCostFunction<ReprojectionPosed, 2, 4, 3, 3, 1>(
                                    new ReprojectionPosed(o.u, o.v, s.u0, s.v0, s.mu, s.noise.pixel_sd)),
                                loss, s.quat[o.view].data(), s.trans[o.view].data(), Xp, &s.f);
    order->AddElementToGroup(Xp, 0);
  }
  for (unsigned int k = 1; k < s.m; ++k)
    if (s.res.posed[k] && problem->HasParameterBlock(s.quat[k].data())) {
      problem->SetManifold(s.quat[k].data(), &s.quaternion);
      if (k == s.res.reference_view)
        problem->SetManifold(s.trans[k].data(), &s.sphere);
      // One group per block, in view order: within a group Ceres orders blocks by address, which
      // changes from run to run for separately allocated blocks (and so would the last digits).
      order->AddElementToGroup(s.quat[k].data(), static_cast<int>(2 * k - 1));
      order->AddElementToGroup(s.trans[k].data(), static_cast<int>(2 * k));
    }
  if (!problem->HasParameterBlock(&s.f))
    return nullptr;
  order->AddElementToGroup(&s.f, static_cast<int>(2 * s.m));
  if (opt.focal_known)
    problem->SetParameterBlockConstant(&s.f);
  ceres::Solver::Options so =
      solverOptions(opt.max_iterations, opt.tight || converge, s.m > 60 ? ceres::SPARSE_SCHUR : ceres::DENSE_SCHUR);
  so.linear_solver_ordering = order;
  so.num_threads = static_cast<int>(opt.num_threads);
  vpSelfCalib::solve(so, problem.get(), &s.summary);
  return problem;
}

/*
  Resection of the views the robust solve could not fully explain (a wrong two-view pose, or no
  pose): a view with an observation beyond the outlier threshold gets the pose OpenCV's PnP RANSAC
  finds from the current points, when that explains more of them; a view that still explains
  fewer than half of its observations (or min_points) is left out (posed = false). Not the
  reference view, whose baseline is the unit. True when a pose changed or a view was left out.
  Every view with an unexplained observation is tried, not only those that explain less than half:
  on a plane the two-view motion is ambiguous (a homography decomposes into two motions), and the
  wrong one of a view, after the robust solve has bent the points a little towards it, still
  explains about half of a small board's corners; the other views place the points well enough
  for PnP to find the right pose, which explains them all.
*/
bool resectUnexplainedViews(State &s)
{
  const Options &opt = s.opt;
  bool changed = false;
  const double thr = std::max(4.0, s.noise.outlier_threshold * s.noise.pixel_sd);
  for (unsigned int k = 1; k < s.m; ++k) {
    if (k == s.res.reference_view)
      continue;
    std::vector<size_t> idx;
    unsigned int good = 0;
    for (size_t n = 0; n < s.obs.size(); ++n)
      if (s.obs[n].view == k) {
        idx.push_back(n);
        good += s.res.posed[k] && whitened(s, n) * s.noise.pixel_sd <= thr;
      }
    const unsigned int needed = std::max<unsigned int>(opt.min_points, static_cast<unsigned int>(idx.size() / 2));
    if (s.res.posed[k] && good == idx.size())
      continue;
    std::vector<Eigen::Vector3d> P3;
    std::vector<Eigen::Vector2d> P2;
    for (size_t n : idx) {
      P3.push_back((*s.X)[s.obs[n].id]);
      P2.emplace_back(s.obs[n].u, s.obs[n].v);
    }
    // OpenCV's USAC PnP (core fitPoseRansac), seeded from twoview.ransac.seed with the view's own
    // stream, sequential: the same seed gives the same poses whatever the thread count.
    Rigid ckMc0;
    std::vector<int> pnp_inliers;
    const bool ok = fitPoseRansac(P3, P2, s.f, s.u0, s.v0, s.mu, thr, 200, s.opt.twoview.ransac.seed, 1000 + k, ckMc0,
                                  pnp_inliers);
    const bool was_posed = s.res.posed[k];
    if (ok && pnp_inliers.size() >= needed && pnp_inliers.size() > good) {
      const Eigen::Quaterniond qk(ckMc0.R);
      s.quat[k] = Eigen::Vector4d(qk.x(), qk.y(), qk.z(), qk.w());
      s.trans[k] = ckMc0.t;
      s.res.posed[k] = true;
      changed = true;
    } else if (good < needed) {
      s.res.posed[k] = false;
      changed = changed || was_posed;
    }
    for (size_t n : idx)
      s.inlier[n] = s.res.posed[k];
  }
  return changed;
}

/*
  Outliers: whitened error above the threshold, tested on every observation so that one wrongly
  dropped in the robust pass can come back; then the points left with fewer than two observations.
  The threshold is in noise sds: the stated one or, when larger, the one the residuals of every
  observation of a posed view measure (robustNoiseSd: the median holds up to half of them wrong).
  A stated sd 2.5x too small would otherwise drop about 13 % of the good observations at 5 stated
  sd, and no sigma0 scaling afterwards repairs the truncated residuals.
*/
void trimOutliers(State &s)
{
  std::vector<double> abs_residuals;
  for (size_t n = 0; n < s.obs.size(); ++n) {
    const Observation &o = s.obs[n];
    const Eigen::Vector3d &X = (*s.X)[o.id];
    if (s.res.posed[o.view] && depthInView(s, o, X) > 0) {
      const Eigen::Vector2d r = residual(s, o, X, 1.0);
      abs_residuals.push_back(std::fabs(r(0)));
      abs_residuals.push_back(std::fabs(r(1)));
    }
  }
  s.noise_factor = std::max(1.0, vpSelfCalib::robustNoiseSd(abs_residuals, 1.0) / s.noise.pixel_sd);
  for (size_t n = 0; n < s.obs.size(); ++n)
    s.inlier[n] = s.res.posed[s.obs[n].view] && whitened(s, n) <= s.noise.outlier_threshold * s.noise_factor;
  dropPoorlyObservedPoints(s.obs, s.inlier);
}

/*
  Standard deviation (px) of f after the final solve: the square root of f's entry of (J^T J)^-1,
  J the Jacobian of the whitened residuals over the poses (tangent coordinates), f and the points,
  with the points marginalized (core marginalCovariance: their Schur complement, the same digits
  from run to run). Infinite when the information is singular.
*/
double focalSd(ceres::Problem &problem, State &s)
{
  std::vector<double *> kept, eliminated;
  for (unsigned int k = 1; k < s.m; ++k)
    if (problem.HasParameterBlock(s.quat[k].data())) {
      kept.push_back(s.quat[k].data());
      kept.push_back(s.trans[k].data());
    }
  kept.push_back(&s.f);
  for (const auto &e : s.X->index()) {
    double *Xp = (*s.X)[e.first].data();
    if (problem.HasParameterBlock(Xp))
      eliminated.push_back(Xp);
  }
  Eigen::MatrixXd cov;
  if (!marginalCovariance(problem, kept, eliminated, cov))
    return std::numeric_limits<double>::infinity();
  return std::sqrt(cov(cov.rows() - 1, cov.cols() - 1));
}

/*
  The robust solve schedule (robustSchedule): after each robust solve, the views it could not
  explain are resected and, when that changed a view, that solve is run again (a view wrongly
  posed may only show once the wide loss of the first solve has narrowed); the outliers are
  trimmed after the solve the schedule says; the last solve (plain least squares)
  gives f's standard deviation. Status OK, TOO_FEW_VIEWS (no observation left) or NO_CONVERGENCE.
*/
vpMultiViewReconstruction::Status robustSolve(State &s)
{
  const Options &opt = s.opt;
  Result &res = s.res;
  const auto tb = std::chrono::steady_clock::now();
  std::vector<double> start_errors;
  for (size_t n = 0; n < s.obs.size(); ++n)
    if (s.inlier[n])
      start_errors.push_back(whitened(s, n));
  const RobustSchedule schedule =
      robustSchedule(s.noise.loss != vpSelfCalibNoiseModel::LOSS_NONE, s.noise.loss_scale, s.noise.outlier_threshold,
                     start_errors);
  const size_t last = schedule.scales.size() - 1;
  for (size_t stage = 0; stage <= last; ++stage) {
    const double loss_scale = schedule.scales[stage];
    // The last solve gives f and its sd: converged whatever opt.tight (see solveBundle).
    std::unique_ptr<ceres::Problem> problem = solveBundle(s, loss_scale, stage == last);
    if (problem && s.summary.IsSolutionUsable() && loss_scale > 0 && resectUnexplainedViews(s))
      problem = solveBundle(s, loss_scale, stage == last);
    if (!problem) {
      res.message = "no observation left";
      return vpMultiViewReconstruction::TOO_FEW_VIEWS;
    }
    if (!s.summary.IsSolutionUsable())
      break;
    if (static_cast<int>(stage) == schedule.trim_after)
      trimOutliers(s);
    if (stage == last && !opt.focal_known)
      res.fx_sd = focalSd(*problem, s);
  }
  res.seconds_bundle = std::chrono::duration<double>(std::chrono::steady_clock::now() - tb).count();
  if (!s.summary.IsSolutionUsable()) {
    res.message = s.summary.BriefReport();
    return vpMultiViewReconstruction::NO_CONVERGENCE;
  }
  res.fx = s.f;
  return vpMultiViewReconstruction::OK;
}

/*
  The plane's start. On a plane each pair's two-view motion is ambiguous: its homography decomposes
  into two motions that explain the pair's points alike, and the two-view step keeps one of them per
  pair. A start whose pairs took different ones is bent, and the robust solve can end in a local
  minimum (most views 5-35 deg off, sigma0 about 2, some of the good observations trimmed as
  outliers). The plane's normal in view 0 is the same in every pair (view 0 and the plane are
  shared), the other motion's is not: here every pair (0, k) whose homography explains planar_ratio
  of its points or more (the two-view step's rule) gives its motions (core homographyMotions); the
  normal nearest to a motion of the most pairs (the smallest median angle) is the plane's, and each
  pair takes the motion with that normal when it is less than half as far from it as the pair's
  other motions. The translations t / d share the plane's distance d from camera 0, so they are
  consistent without scale chaining, and the points are the rays of the view that sees them first
  met with the plane n . X = d.
*/

//! Per view k: the motions of pair (0, k)'s homography at focal length fx when it explains the pair.
std::vector<std::vector<PlaneMotion>> planarPairs(const State &s, double fx)
{
  std::vector<std::vector<PlaneMotion>> motions(s.m);
  const CameraModel camera = pinhole(s, fx);
  const double threshold =
      std::max(s.opt.twoview.ransac.inlier_threshold, s.noise.outlier_threshold * s.noise.pixel_sd);
  for (unsigned int k = 1; k < s.m; ++k) {
    std::vector<Eigen::Vector2d> a, b, xa, xb;
    for (size_t j = 0; j < s.p0[k - 1].size(); ++j) {
      a.push_back(pixel(s.p0[k - 1][j]));
      b.push_back(pixel(s.pk[k - 1][j]));
    }
    Eigen::Matrix3d H;
    std::vector<bool> in;
    if (a.size() < 8 || !fitHomography(a, b, threshold, 2000, 0.999, H, in))
      continue;
    for (size_t j = 0; j < a.size(); ++j)
      if (in[j]) {
        xa.push_back(camera.unproject(a[j]));
        xb.push_back(camera.unproject(b[j]));
      }
    if (xa.size() >= 8 && xa.size() >= s.opt.twoview.planar_ratio * a.size())
      motions[k] = homographyMotions(H, fx, s.u0, s.v0, s.mu, xa, xb);
  }
  return motions;
}

//! The angle (rad) from n to the nearest normal of `motions`, and its index (infinite when empty).
double angleToNearest(const std::vector<PlaneMotion> &motions, const Eigen::Vector3d &n, size_t &which)
{
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < motions.size(); ++i) {
    const double a = std::acos(std::clamp(motions[i].normal.dot(n), -1.0, 1.0));
    if (a < best) {
      best = a;
      which = i;
    }
  }
  return best;
}

/*
  The plane's motion of each pair (c_kMc_0, translation over d; posed false for the others) and its
  normal; false when fewer than 3 pairs are planar or fewer than 3 take a motion.
*/
bool choosePlaneMotions(const std::vector<std::vector<PlaneMotion>> &motions, std::vector<Rigid> &ckMc0,
                        std::vector<bool> &posed, Eigen::Vector3d &normal)
{
  std::vector<size_t> planar;
  for (size_t k = 0; k < motions.size(); ++k)
    if (!motions[k].empty())
      planar.push_back(k);
  if (planar.size() < 3)
    return false;
  double best = std::numeric_limits<double>::infinity();
  for (size_t k : planar)
    for (const PlaneMotion &c : motions[k]) {
      std::vector<double> angles;
      size_t which = 0;
      for (size_t l : planar)
        if (l != k)
          angles.push_back(angleToNearest(motions[l], c.normal, which));
      const double a = median(angles);
      if (a < best) {
        best = a;
        normal = c.normal;
      }
    }
  ckMc0.assign(motions.size(), Rigid());
  posed.assign(motions.size(), false);
  unsigned int count = 0;
  for (size_t k : planar) {
    size_t which = 0;
    const double d = angleToNearest(motions[k], normal, which);
    double other = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < motions[k].size(); ++i)
      if (i != which)
        other = std::min(other, std::acos(std::clamp(motions[k][i].normal.dot(normal), -1.0, 1.0)));
    if (d < 0.5 * other) {
      ckMc0[k] = motions[k][which].bMa;
      posed[k] = true;
      ++count;
    }
  }
  return count >= 3;
}

/*
  The plane's start in p (collected, the pairs and the two-view f of s) at focal length fx: the poses
  of choosePlaneMotions, the reference view the one farthest from view 0 (its baseline the unit), the
  points on the plane. False when the data do not say plane.
*/
bool planeStart(const State &s, State &p, double fx)
{
  std::vector<Rigid> ckMc0;
  std::vector<bool> posed;
  Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
  if (!choosePlaneMotions(planarPairs(s, fx), ckMc0, posed, n))
    return false;
  collectObservations(p);
  p.ids = s.ids;
  p.p0 = s.p0;
  p.pk = s.pk;
  p.res.pairs = s.res.pairs;
  p.res.fx = fx;
  p.res.seconds_twoview = s.res.seconds_twoview;
  unsigned int ref = 0;
  for (unsigned int k = 1; k < p.m; ++k)
    if (posed[k] && (ref == 0 || ckMc0[k].t.norm() > ckMc0[ref].t.norm()))
      ref = k;
  const double unit = ckMc0[ref].t.norm();
  if (!(unit > 0))
    return false;
  p.res.reference_view = ref;
  std::vector<Rigid> c0Mc(p.m); // camera k in frame 0, the plane's distance d from camera 0 the unit
  for (unsigned int k = 0; k < p.m; ++k)
    if (k == 0 || posed[k]) {
      p.res.posed[k] = true;
      Rigid M = ckMc0[k];
      c0Mc[k] = M.inverse();
      M.t /= unit;
      p.res.cMc0[k] = toVisp(M);
    }
  const CameraModel camera = pinhole(p, fx);
  for (unsigned int k = 0; k < p.m; ++k)
    for (const auto &e : p.byId[k]) {
      if (!p.res.posed[k] || p.Xinit.count(e.first))
        continue;
      // The ray C + lambda D (frame 0) meets n . X = 1 at lambda = (1 - n . C) / (n . D), in front.
      const Eigen::Vector3d C = c0Mc[k].t, D = c0Mc[k].R * camera.ray(pixel(e.second));
      const double lambda = (1 - n.dot(C)) / n.dot(D);
      if (lambda > 0 && std::isfinite(lambda))
        p.Xinit[e.first] = (C + lambda * D) / unit;
    }
  return true;
}

/*
  The truncated quadratic (MSAC) cost of a reconstruction over every input observation of the
  points it adjusted: min(e^2, T^2), e its whitened error and T the outlier threshold (stated sds);
  T^2 for an observation of a view left out or of a point not placed. The lower of two starts is kept.
*/
double startScore(State &s)
{
  const double T2 = s.noise.outlier_threshold * s.noise.outlier_threshold;
  double score = 0;
  for (unsigned int k = 0; k < s.m; ++k)
    for (const auto &e : s.byId[k]) {
      if (s.later.count(e.first))
        continue;
      const Observation o{k, e.first, e.second.get_u(), e.second.get_v()};
      const double w = s.res.posed[k] && s.X->count(e.first) ? whitened(s, o, (*s.X)[e.first])
                                                               : std::numeric_limits<double>::infinity();
      score += std::min(w * w, T2);
    }
  return score;
}

/*
  Points left out of the bundle adjustment: the midpoint of their rays from the posed views
  (triangulateMidpoint), in three rounds; after each, the views whose whitened error against the
  midpoint exceeds max(outlier_threshold, 20 / (round + 1)) are left out of the next (the threshold
  in the noise sds of trimOutliers). A point is kept when two views or more remain, with its
  observations within the outlier threshold as inliers; it is left out when its rays are (nearly) parallel or meet behind one of the cameras.
*/
void triangulateLeftOutPoints(State &s)
{
  const double threshold = s.noise.outlier_threshold * s.noise_factor;
  const CameraModel camera = pinhole(s, s.f);
  std::vector<Rigid> c0Mc(s.m);
  for (unsigned int k = 0; k < s.m; ++k)
    if (s.res.posed[k])
      c0Mc[k] = viewPose(s, k).inverse();
  for (int id : s.later) {
    std::vector<Observation> po;
    for (unsigned int k = 0; k < s.m; ++k) {
      auto it = s.byId[k].find(id);
      if (s.res.posed[k] && it != s.byId[k].end())
        po.push_back({k, id, it->second.get_u(), it->second.get_v()});
    }
    std::vector<bool> use(po.size(), true);
    Eigen::Vector3d x;
    bool triangulated = true;
    for (int round = 0; round < 3 && triangulated; ++round) {
      std::vector<Ray> rays;
      for (size_t i = 0; i < po.size(); ++i)
        if (use[i])
          rays.push_back(rayThrough(c0Mc[po[i].view], camera, Eigen::Vector2d(po[i].u, po[i].v)));
      triangulated = triangulateMidpoint(rays, x);
      for (size_t i = 0; i < po.size() && triangulated; ++i)
        use[i] = whitened(s, po[i], x) <= std::max(threshold, 20.0 / (round + 1));
    }
    if (!triangulated || std::count(use.begin(), use.end(), true) < 2)
      continue;
    (*s.X)[id] = x;
    for (size_t i = 0; i < po.size(); ++i) {
      s.obs.push_back(po[i]);
      s.inlier.push_back(use[i] && whitened(s, po[i], x) <= threshold);
    }
  }
}

/*
  Statistics over the kept observations (inlier flags per input point, counts, RMS in px) and the
  ids of the points with at least one kept observation (the others are dropped).
*/
std::set<int> statistics(State &s)
{
  Result &res = s.res;
  res.inliers.resize(s.m);
  for (unsigned int k = 0; k < s.m; ++k)
    res.inliers[k].assign(s.views[k].points.size(), false);
  std::vector<std::map<int, size_t>> index(s.m);
  for (unsigned int k = 0; k < s.m; ++k)
    for (size_t j = 0; j < s.views[k].points.size(); ++j)
      index[k][s.views[k].points[j].id] = j;
  std::set<int> kept;
  double sum = 0;
  std::vector<double> abs_residuals; // every observation of a posed view, the outliers too
  for (size_t n = 0; n < s.obs.size(); ++n) {
    const Observation &o = s.obs[n];
    const bool posed = o.view < res.posed.size() && res.posed[o.view];
    Eigen::Vector2d r(0, 0);
    if (posed && s.X->count(o.id)) {
      r = residual(s, o, (*s.X)[o.id], 1.0);
      if (r.allFinite()) {
        abs_residuals.push_back(std::fabs(r(0)));
        abs_residuals.push_back(std::fabs(r(1)));
      }
    }
    if (!s.inlier[n]) {
      ++res.num_outliers;
      continue;
    }
    sum += r(0) * r(0) + r(1) * r(1);
    ++res.num_observations;
    res.inliers[o.view][index[o.view][o.id]] = true;
    kept.insert(o.id);
  }
  res.rms = res.num_observations ? std::sqrt(sum / (2.0 * res.num_observations)) : 0;
  // The noise against the stated one: sigma0 over the inliers, and the noise measured robustly over
  // every observation (the median absolute residual), so that a stated sd too small, which rejects
  // good observations as outliers, is still measured right. Unknowns: the posed views but the first
  // (the reference baseline's length fixed), the kept points, f.
  unsigned int posed = 0;
  for (bool p : res.posed)
    posed += p ? 1u : 0u;
  const double unknowns = 6.0 * (posed > 0 ? posed - 1 : 0) - 1.0 + 3.0 * static_cast<double>(kept.size()) +
                          (s.opt.focal_known ? 0.0 : 1.0);
  const double dof = 2.0 * res.num_observations - unknowns;
  if (dof > 0 && res.num_observations > 0) {
    const double inflate = std::sqrt(2.0 * res.num_observations / dof);
    res.sigma0 = res.rms / s.noise.pixel_sd * inflate;
    vpSelfCalib::sigma0Interval(dof, res.sigma0_low, res.sigma0_high);
    res.measured.pixel_sd = vpSelfCalib::robustNoiseSd(abs_residuals, inflate);
  }
  return kept;
}

//! 4. Scale by the yardstick when both ends are kept; the poses and kept points of the result.
void scaleAndExport(State &s, const std::set<int> &kept)
{
  Result &res = s.res;
  const vpSelfCalibDataset::Yardstick &yardstick = s.yardstick;
  double scale = 1;
  if (yardstick.isSet() && kept.count(yardstick.id_a) && kept.count(yardstick.id_b)) {
    res.yardstick_unit_length = ((*s.X)[yardstick.id_a] - (*s.X)[yardstick.id_b]).norm();
    if (res.yardstick_unit_length > 0) {
      scale = yardstick.length / res.yardstick_unit_length;
      res.metric = true;
    }
  }
  for (unsigned int k = 1; k < s.m; ++k)
    if (res.posed[k]) {
      Rigid M = viewPose(s, k);
      M.t = scale * s.trans[k];
      res.cMc0[k] = toVisp(M);
    }
  for (int id : kept) {
    const Eigen::Vector3d x = scale * (*s.X)[id];
    vpColVector v(3);
    for (unsigned int a = 0; a < 3; ++a)
      v[a] = x(a);
    res.points[id] = v;
  }
  const unsigned int num_posed = static_cast<unsigned int>(std::count(res.posed.begin(), res.posed.end(), true));
  res.status = vpMultiViewReconstruction::OK;
  res.message = "ok: " + std::to_string(num_posed) + " of " + std::to_string(s.m) + " views, " +
                std::to_string(res.points.size()) + " points, " + std::to_string(res.num_outliers) + " outliers, rms " +
                std::to_string(res.rms) + " px" + (res.metric ? ", metric" : ", unit reference baseline");
}
} // namespace

vpMultiViewReconstruction::Result vpMultiViewReconstruction::reconstruct(const std::vector<vpSelfCalibDataset::View> &views,
                                                                         const vpSelfCalibDataset::Yardstick &yardstick,
                                                                         const Options &opt,
                                                                         const vpSelfCalibNoiseModel &noise)
{
  opt.check();
  noise.check("vpMultiViewReconstruction");
  const QuietCeres quiet;
  auto start = std::make_unique<State>(views, yardstick, opt, noise);
  collectObservations(*start);
  twoViewPoses(*start);
  if (!triangulatePairs(*start))
    return std::move(start->res);
  chainScales(*start);
  initializePointsNotSeenFromView0(*start);
  setUpBundle(*start);
  const double fx_start = start->res.fx;
  const Status status = robustSolve(*start);
  if (status != OK) {
    start->res.status = status;
    return std::move(start->res);
  }
  // On a plane, the start from the plane's homographies too; the lower cost is kept.
  auto plane = std::make_unique<State>(views, yardstick, opt, noise);
  if (planeStart(*start, *plane, fx_start)) {
    setUpBundle(*plane);
    if (robustSolve(*plane) == OK && startScore(*plane) < startScore(*start)) {
      plane->res.seconds_bundle += start->res.seconds_bundle;
      start = std::move(plane);
    }
  }
  State &s = *start;
  // Cheirality after the last solve: an observation of a point behind its camera is an outlier
  // (the points left with fewer than two observations are dropped).
  for (size_t n = 0; n < s.obs.size(); ++n)
    if (s.inlier[n] && !(depthInView(s, s.obs[n], (*s.X)[s.obs[n].id]) > 0))
      s.inlier[n] = false;
  dropPoorlyObservedPoints(s.obs, s.inlier);
  triangulateLeftOutPoints(s);
  scaleAndExport(s, statistics(s));
  return std::move(s.res);
}
