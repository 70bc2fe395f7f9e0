/*
 * ViSP SelfCalib: eq. 21 scale propagation and yardstick scale (paper Section 3.2).
 */
#include <visp3/selfcalib/vpPoseScale.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <array>
#include <cmath>
#include <functional>

#include <Eigen/Eigenvalues>

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include "../core/vpSelfCalibCeres.h"
#include "../core/vpSelfCalibGeometry.h"
#include "../core/vpSelfCalibMath.h"
#include "../core/vpSelfCalibRange.h"

using namespace vpSelfCalib;

namespace
{
// Weighted: (scale ratio l / L - 1) / sqrt(v), the relative misfit of one view in units of its sd.
// Unweighted (the paper): scale ratio l - L (m).
struct YardstickResidual {
  double ratio_length, length, weight;
  bool relative;
  template <typename T> bool operator()(const T *scale, T *r) const
  {
    if (relative)
      r[0] = (scale[0] * T(ratio_length / length) - T(1)) * T(weight);
    else
      r[0] = scale[0] * T(ratio_length) - T(length);
    return true;
  }
};

// Joint yardstick (beyond the paper): the ends in every view at once. The reference view sees
// A = M + (L/2) u and B = M - (L/2) u (c_1 frame, metres); view j has the pose (exp([w]x) R_j,
// scale ratio_j exp(rho_j) normalize(t_j + a e1 + b e2)) with its 5 corrections (w, a, b) and the log
// ratio correction rho_j held by priors. Residuals in units of the pixel sd.
template <typename T> void projectEnds(const T *M, const T *u, double half, const T *R9, const T *t, double fx,
                                       double u0, double v0, double mu, T *uv)
{
  for (int e = 0; e < 2; ++e) {
    const T s = T(e == 0 ? half : -half);
    const T X[3] = {M[0] + s * u[0], M[1] + s * u[1], M[2] + s * u[2]};
    T Y[3];
    for (int r = 0; r < 3; ++r)
      Y[r] = R9[3 * r] * X[0] + R9[3 * r + 1] * X[1] + R9[3 * r + 2] * X[2] + t[r];
    uv[2 * e] = T(fx) * Y[0] / Y[2] + T(u0);
    uv[2 * e + 1] = T(mu * fx) * Y[1] / Y[2] + T(v0);
  }
}

struct ReferenceEndsResidual {
  double half, fx, u0, v0, mu, sd;
  double obs[4];
  template <typename T> bool operator()(const T *M, const T *u, T *r) const
  {
    const T I[9] = {T(1), T(0), T(0), T(0), T(1), T(0), T(0), T(0), T(1)};
    const T z[3] = {T(0), T(0), T(0)};
    T uv[4];
    projectEnds(M, u, half, I, z, fx, u0, v0, mu, uv);
    for (int c = 0; c < 4; ++c)
      r[c] = (uv[c] - T(obs[c])) / T(sd);
    return true;
  }
};

struct ViewEndsResidual {
  double half, fx, u0, v0, mu, sd, ratio;
  double R0[9], t0[3], e1[3], e2[3];
  double obs[4];
  template <typename T> bool operator()(const T *scale, const T *M, const T *u, const T *d, const T *rho, T *r) const
  {
    // R = exp([w]x) R0, column by column.
    T R9[9];
    for (int c = 0; c < 3; ++c) {
      const T col[3] = {T(R0[c]), T(R0[3 + c]), T(R0[6 + c])};
      T out[3];
      ceres::AngleAxisRotatePoint(d, col, out);
      for (int k = 0; k < 3; ++k)
        R9[3 * k + c] = out[k];
    }
    T t[3];
    T n2 = T(0);
    for (int k = 0; k < 3; ++k) {
      t[k] = T(t0[k]) + d[3] * T(e1[k]) + d[4] * T(e2[k]);
      n2 += t[k] * t[k];
    }
    const T g = scale[0] * T(ratio) * exp(rho[0]) / sqrt(n2);
    for (int k = 0; k < 3; ++k)
      t[k] *= g;
    T uv[4];
    projectEnds(M, u, half, R9, t, fx, u0, v0, mu, uv);
    for (int c = 0; c < 4; ++c)
      r[c] = (uv[c] - T(obs[c])) / T(sd);
    return true;
  }
};

// Prior U d (U^T U = C^-1) on a pose's 5 corrections, or rho / sd on the log ratio.
struct PriorResidual {
  Eigen::Matrix<double, 5, 5> U;
  template <typename T> bool operator()(const T *d, T *r) const
  {
    for (int i = 0; i < 5; ++i) {
      r[i] = T(0);
      for (int j = 0; j < 5; ++j)
        r[i] += T(U(i, j)) * d[j];
    }
    return true;
  }
};
struct LogRatioPrior {
  double sd;
  template <typename T> bool operator()(const T *rho, T *r) const
  {
    r[0] = rho[0] / T(sd);
    return true;
  }
};

// The pose moved by the 5 local coordinates (w, a, b): R <- exp([w]x) R, t <- normalize(t + a e1 + b e2).
void perturbPose(const Rigid &M, const double *d, Eigen::Matrix3d &R, Eigen::Vector3d &t)
{
  const Eigen::Vector3d t0 = M.t.normalized(), e1 = t0.unitOrthogonal(), e2 = t0.cross(e1);
  const Eigen::Vector3d w(d[0], d[1], d[2]);
  R = (w.norm() > 0 ? Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix() : Eigen::Matrix3d::Identity()) *
      M.R;
  t = (t0 + d[3] * e1 + d[4] * e2).normalized();
}

struct Intrinsics {
  double fx, u0, v0, mu;
  Eigen::Matrix3d Kinv() const
  {
    Eigen::Matrix3d K;
    K << fx, 0, u0, 0, mu * fx, v0, 0, 0, 1;
    return K.inverse();
  }
};

// Yardstick length with the unit translation, from ends (u, v) x 4 = a1, b1, a2, b2, each end
// triangulated by the linear DLT of the two views (camera 2 at x2 = R x1 + t); false when the ends
// do not triangulate in front of both cameras. l and ends are set in any case.
bool unitLength(const Eigen::Matrix3d &R, const Eigen::Vector3d &t, const double *px, const Intrinsics &k, double &l,
                Eigen::Vector3d *ends = nullptr)
{
  const double in[4] = {k.fx, k.mu, k.u0, k.v0};
  const CameraModel camera(Distortion::NONE, in);
  Rigid c2Mc1;
  c2Mc1.R = R;
  c2Mc1.t = t;
  Eigen::Vector3d E[2];
  bool front = true;
  for (int e = 0; e < 2; ++e) {
    PointViews views;
    views.cMf = {Rigid(), c2Mc1};
    views.uv = {Eigen::Vector2d(px[2 * e], px[2 * e + 1]), Eigen::Vector2d(px[4 + 2 * e], px[5 + 2 * e])};
    const bool ok = triangulate(camera, views, Triangulation::LINEAR_DLT, E[e]);
    front = front && ok;
  }
  l = (E[0] - E[1]).norm();
  if (ends) {
    ends[0] = E[0];
    ends[1] = E[1];
  }
  return front && std::isfinite(l);
}

// The 8 end pixels of a view: a1, b1, a2, b2.
struct YardstickViewPixels {
  double v[8];
  explicit YardstickViewPixels(const vpPoseScale::YardstickView &y)
      : v{y.a1.get_u(), y.a1.get_v(), y.b1.get_u(), y.b1.get_v(), y.a2.get_u(), y.a2.get_v(), y.b2.get_u(), y.b2.get_v()}
  {
  }
};

// True when every view's first image is the same one (the same ends a1, b1): the pairs (0, j).
bool sharedReference(const std::vector<vpPoseScale::YardstickView> &views)
{
  for (const auto &v : views)
    if (v.a1 != views[0].a1 || v.b1 != views[0].b1)
      return false;
  return true;
}

struct JointScale {
  bool ok = false;
  double scale = 0, predicted_sd = 0, chi2 = 0;
  int dof = 0;
};

/*
  The scale from the yardstick ends in every view jointly (all views share the reference image: its
  ends are one observation, not one per pair), the two-view poses held by their covariance and the
  ratios by their sd. start: a scale to start from; best: the view whose triangulation starts the
  ends.
*/
JointScale jointScale(const std::vector<vpPoseScale::YardstickView> &views, double length, const Intrinsics &K,
                      double pixel_sd, double start, size_t best)
{
  JointScale out;
  const size_t n = views.size();
  const double half = 0.5 * length;
  // Start: the ends of the best view, in metres.
  Eigen::Vector3d E[2];
  {
    const Rigid M0 = rigidFromVisp(views[best].c2Mc1);
    const double zero[5] = {0, 0, 0, 0, 0};
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
    perturbPose(M0, zero, R, t);
    const YardstickViewPixels px(views[best]);
    double l = 0;
    if (!unitLength(R, t, px.v, K, l, E))
      return out;
  }
  const double s0 = start * views[best].ratio;
  double scale = start;
  Eigen::Vector3d M = 0.5 * s0 * (E[0] + E[1]), u = (E[0] - E[1]).normalized();
  std::vector<std::array<double, 5>> d(n, std::array<double, 5>{0, 0, 0, 0, 0});
  std::vector<double> rho(n, 0.0);
  ceres::Problem problem;
  {
    auto *r = new ReferenceEndsResidual{half, K.fx, K.u0, K.v0, K.mu, pixel_sd, {}};
    const vpImagePoint &a = views[0].a1, &b = views[0].b1;
    r->obs[0] = a.get_u(), r->obs[1] = a.get_v(), r->obs[2] = b.get_u(), r->obs[3] = b.get_v();
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<ReferenceEndsResidual, 4, 3, 3>(r), nullptr, M.data(),
                             u.data());
  }
  int residuals = 4;
  for (size_t j = 0; j < n; ++j) {
    const vpPoseScale::YardstickView &v = views[j];
    const Rigid Mj = rigidFromVisp(v.c2Mc1);
    auto *r = new ViewEndsResidual{half, K.fx, K.u0, K.v0, K.mu, pixel_sd, v.ratio, {}, {}, {}, {}, {}};
    const Eigen::Vector3d t0 = Mj.t.normalized(), e1 = t0.unitOrthogonal(), e2 = t0.cross(e1);
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b)
        r->R0[3 * a + b] = Mj.R(a, b);
      r->t0[a] = t0(a), r->e1[a] = e1(a), r->e2[a] = e2(a);
    }
    r->obs[0] = v.a2.get_u(), r->obs[1] = v.a2.get_v(), r->obs[2] = v.b2.get_u(), r->obs[3] = v.b2.get_v();
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<ViewEndsResidual, 4, 1, 3, 3, 5, 1>(r), nullptr, &scale,
                             M.data(), u.data(), d[j].data(), &rho[j]);
    residuals += 4;
    const vpMatrix C = vpPoseScale::twoViewCovariance(v.c2Mc1, v.p1, v.p2, K.fx, K.u0, K.v0, K.mu, pixel_sd);
    if (C.getRows() == 5) {
      Eigen::Matrix<double, 5, 5> Ce;
      for (unsigned int a = 0; a < 5; ++a)
        for (unsigned int b = 0; b < 5; ++b)
          Ce(a, b) = C[a][b];
      const Eigen::Matrix<double, 5, 5> info = Ce.inverse();
      Eigen::LLT<Eigen::Matrix<double, 5, 5>> llt(info);
      if (llt.info() != Eigen::Success) {
        problem.SetParameterBlockConstant(d[j].data());
      } else {
        const Eigen::Matrix<double, 5, 5> U = llt.matrixU();
        problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PriorResidual, 5, 5>(new PriorResidual{U}), nullptr,
                                 d[j].data());
      }
    } else
      problem.SetParameterBlockConstant(d[j].data());
    if (v.ratio_sd > 0)
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<LogRatioPrior, 1, 1>(new LogRatioPrior{v.ratio_sd}),
                               nullptr, &rho[j]);
    else
      problem.SetParameterBlockConstant(&rho[j]);
  }
  problem.SetManifold(u.data(), new ceres::SphereManifold<3>());
  ceres::Solver::Summary summary;
  vpSelfCalib::solve(solverOptions(100, true), &problem, &summary);
  if (!summary.IsSolutionUsable() || !(scale > 0) || !std::isfinite(scale))
    return out;
  ceres::Covariance cov(covarianceOptions());
  const std::vector<std::pair<const double *, const double *>> blocks = {{&scale, &scale}};
  double var = 0;
  if (!computeCovariance(cov, blocks, &problem) || !cov.GetCovarianceBlock(&scale, &scale, &var) || !(var > 0))
    return out;
  out.ok = true;
  out.scale = scale;
  out.predicted_sd = std::sqrt(var);
  out.chi2 = 2 * summary.final_cost;
  // The ends' residuals against the ends' unknowns (6, less the length: 5) and the scale (1); the
  // priors' residuals match their unknowns.
  out.dof = residuals - 6;
  return out;
}
} // namespace

void vpPoseScale::YardstickOptions::check() const
{
  if (!(fx_sd >= 0 && std::isfinite(fx_sd)))
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpPoseScale::YardstickOptions: fx_sd must be >= 0");
}

std::vector<double> vpPoseScale::nominalRatioSd(const vpKinematicChain &model, const std::vector<vpColVector> &q)
{
  return nominalRatioSd(model, q, ModelTolerance());
}

namespace
{
// |t_i| of c_iMc_0, i = 1..m-1.
std::vector<double> norms(const vpKinematicChain &model, const std::vector<vpColVector> &q)
{
  const vpHomogeneousMatrix fMc0 = model.get_fMc(q[0]);
  std::vector<double> n;
  for (size_t i = 1; i < q.size(); ++i)
    n.push_back((model.get_fMc(q[i]).inverse() * fMc0).getTranslationVector().frobeniusNorm());
  return n;
}

// First-order sd of log f_i(model) under the tolerance (central differences over the parameters).
std::vector<double> logSd(const vpKinematicChain &model, const vpPoseScale::ModelTolerance &tol,
                          const std::function<std::vector<double>(const vpKinematicChain &)> &f)
{
  vpKinematicChain chain = model.nominal();
  const std::vector<double> r0 = f(chain);
  std::vector<double> var(r0.size(), 0.0);
  const unsigned int np = chain.getNumParameters(), nblocks = np / 6;
  const double h = 1e-6;
  for (unsigned int k = 0; k < np; ++k) {
    const unsigned int b = k / 6;
    const bool eye = b == nblocks - 1, rot = k % 6 >= 3;
    const double sd = rot ? (eye ? tol.hand_eye_rotation : tol.rotation)
                          : (eye ? tol.hand_eye_translation : tol.translation);
    if (sd == 0)
      continue;
    vpColVector p(np, 0.0);
    p[k] = h;
    chain.setParameters(p);
    const std::vector<double> rp = f(chain);
    p[k] = -h;
    chain.setParameters(p);
    const std::vector<double> rm = f(chain);
    for (size_t i = 0; i < r0.size(); ++i) {
      const double d = (std::log(rp[i]) - std::log(rm[i])) / (2 * h);
      var[i] += sd * sd * d * d;
    }
  }
  std::vector<double> sd;
  for (double v : var)
    sd.push_back(std::sqrt(v));
  return sd;
}
} // namespace

std::vector<double> vpPoseScale::nominalRatioSd(const vpKinematicChain &model, const std::vector<vpColVector> &q,
                                                const ModelTolerance &tol)
{
  nominalRatios(model, q); // argument checks
  return logSd(model, tol, [&](const vpKinematicChain &c) { return nominalRatios(c, q); });
}

std::vector<double> vpPoseScale::nominalNormSd(const vpKinematicChain &model, const std::vector<vpColVector> &q,
                                               const ModelTolerance &tol)
{
  nominalRatios(model, q); // argument checks
  return logSd(model, tol, [&](const vpKinematicChain &c) { return norms(c, q); });
}

vpMatrix vpPoseScale::twoViewCovariance(const vpHomogeneousMatrix &c2Mc1, const std::vector<vpImagePoint> &p1,
                                        const std::vector<vpImagePoint> &p2, double fx, double u0, double v0,
                                        double mu, double pixel_sd)
{
  if (p1.size() != p2.size())
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               "vpPoseScale::twoViewCovariance: p1 and p2 must have the same size");
  if (!(fx > 0 && mu > 0 && pixel_sd > 0))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpPoseScale::twoViewCovariance: fx, mu and pixel_sd must be positive");
  if (p1.size() < 5)
    return vpMatrix();
  const Rigid M = rigidFromVisp(c2Mc1);
  const Eigen::Matrix3d Kinv = Intrinsics{fx, u0, v0, mu}.Kinv();
  // Sampson distance (px) of every correspondence at the pose moved by d.
  auto sampson = [&](const double *d, Eigen::VectorXd &r) {
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
    perturbPose(M, d, R, t);
    const Eigen::Matrix3d F = Kinv.transpose() * skew(t) * R * Kinv;
    r.resize(static_cast<Eigen::Index>(p1.size()));
    for (size_t i = 0; i < p1.size(); ++i) {
      const Eigen::Vector3d m1(p1[i].get_u(), p1[i].get_v(), 1), m2(p2[i].get_u(), p2[i].get_v(), 1);
      const Eigen::Vector3d l2 = F * m1, l1 = F.transpose() * m2;
      const double den = std::sqrt(l2(0) * l2(0) + l2(1) * l2(1) + l1(0) * l1(0) + l1(1) * l1(1));
      r(static_cast<Eigen::Index>(i)) = den > 0 ? m2.dot(l2) / den : 0;
    }
  };
  const double h = 1e-7;
  Eigen::MatrixXd J(static_cast<Eigen::Index>(p1.size()), 5);
  for (int c = 0; c < 5; ++c) {
    double dp[5] = {0, 0, 0, 0, 0}, dm[5] = {0, 0, 0, 0, 0};
    dp[c] = h;
    dm[c] = -h;
    Eigen::VectorXd rp, rm;
    sampson(dp, rp);
    sampson(dm, rm);
    J.col(c) = (rp - rm) / (2 * h);
  }
  const Eigen::Matrix<double, 5, 5> A = J.transpose() * J;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 5, 5>> es(A);
  if (!(es.eigenvalues()(0) > 1e-12 * es.eigenvalues()(4)))
    return vpMatrix();
  const Eigen::Matrix<double, 5, 5> C = pixel_sd * pixel_sd * A.inverse();
  vpMatrix out(5, 5);
  for (unsigned int r = 0; r < 5; ++r)
    for (unsigned int c = 0; c < 5; ++c)
      out[r][c] = C(r, c);
  return out;
}

std::vector<double> vpPoseScale::nominalRatios(const vpKinematicChain &model, const std::vector<vpColVector> &q)
{
  if (q.size() < 2)
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpPoseScale::nominalRatios: need at least 2 configurations");
  const vpHomogeneousMatrix fMc0 = model.get_fMc(q[0]);
  std::vector<double> norms;
  for (size_t i = 1; i < q.size(); ++i)
    norms.push_back((model.get_fMc(q[i]).inverse() * fMc0).getTranslationVector().frobeniusNorm());
  if (!(norms[0] > 0))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpPoseScale::nominalRatios: configuration 1 puts the camera where configuration 0 does");
  std::vector<double> r;
  for (double n : norms)
    r.push_back(n / norms[0]);
  return r;
}

namespace
{
using YardstickView = vpPoseScale::YardstickView;

//! The caller mistakes of a yardstick view (non-finite pixels, ratios, p1 and p2 sizes).
void checkYardstickView(const YardstickView &v)
{
  for (const vpImagePoint *p : {&v.a1, &v.b1, &v.a2, &v.b2})
    if (!std::isfinite(p->get_u()) || !std::isfinite(p->get_v()))
      throw vpSelfCalibException(vpSelfCalibException::badValue, "vpPoseScale::yardstick: non-finite pixel");
  if (!(v.ratio > 0 && std::isfinite(v.ratio)) || !(v.ratio_sd >= 0 && std::isfinite(v.ratio_sd)))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpPoseScale::yardstick: ratios must be positive and their sd >= 0");
  if (v.p1.size() != v.p2.size())
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               "vpPoseScale::yardstick: p1 and p2 of a view must have the same size");
}

/*
  Expected variance of a view's unit length l (to first order): the ends' pixel noise (central
  differences over the 8 end coordinates px) and the pose's two-view covariance (over its 5 degrees
  of freedom).
*/
double unitLengthVariance(const YardstickView &v, const Rigid &M, const Eigen::Matrix3d &R, const Eigen::Vector3d &t,
                          double px[8], const Intrinsics &K, double l, double pixel_sd)
{
  double var = 0;
  const double hp = 1e-3; // px
  for (int c = 0; c < 8; ++c) {
    double lp = 0, lm = 0;
    const double keep = px[c];
    px[c] = keep + hp;
    const bool okp = unitLength(R, t, px, K, lp);
    px[c] = keep - hp;
    const bool okm = unitLength(R, t, px, K, lm);
    px[c] = keep;
    if (okp && okm)
      var += std::pow(pixel_sd * (lp - lm) / (2 * hp), 2);
  }
  const vpMatrix C = vpPoseScale::twoViewCovariance(v.c2Mc1, v.p1, v.p2, K.fx, K.u0, K.v0, K.mu, pixel_sd);
  if (C.getRows() == 5) {
    Eigen::Matrix<double, 5, 1> g;
    const double hq = 1e-7;
    for (int c = 0; c < 5; ++c) {
      double dp[5] = {0, 0, 0, 0, 0}, dm[5] = {0, 0, 0, 0, 0};
      dp[c] = hq;
      dm[c] = -hq;
      Eigen::Matrix3d Rp, Rm;
      Eigen::Vector3d tp, tm;
      perturbPose(M, dp, Rp, tp);
      perturbPose(M, dm, Rm, tm);
      double lp = l, lm = l;
      unitLength(Rp, tp, px, K, lp);
      unitLength(Rm, tm, px, K, lm);
      g(c) = (lp - lm) / (2 * hq);
    }
    Eigen::Matrix<double, 5, 5> Ce;
    for (int r = 0; r < 5; ++r)
      for (int c = 0; c < 5; ++c)
        Ce(r, c) = C[static_cast<unsigned int>(r)][static_cast<unsigned int>(c)];
    var += g.dot(Ce * g);
  }
  return var;
}

//! What the views give before the scale is fitted: their unit lengths, expected relative variances
//! and sensitivities d log l / d fx (the last two when weighted).
struct ViewLengths {
  std::vector<double> rel_var, dlogl_df;
};

/*
  Each view's unit length into res.lengths (and, weighted, its expected relative sd into
  res.relative_sd). False (res DEGENERATE) when a view's ends do not triangulate in front of both
  cameras.
*/
bool unitLengths(const std::vector<YardstickView> &views, const Intrinsics &K, const vpPoseScale::YardstickOptions &options,
                 double pixel_sd, vpPoseScale::Result &res, ViewLengths &out)
{
  for (size_t j = 0; j < views.size(); ++j) {
    const YardstickView &v = views[j];
    checkYardstickView(v);
    const Rigid M = rigidFromVisp(v.c2Mc1);
    const double zero[5] = {0, 0, 0, 0, 0};
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
    perturbPose(M, zero, R, t);
    double px[8] = {v.a1.get_u(), v.a1.get_v(), v.b1.get_u(), v.b1.get_v(),
                    v.a2.get_u(), v.a2.get_v(), v.b2.get_u(), v.b2.get_v()};
    double l = 0;
    if (!unitLength(R, t, px, K, l)) {
      res.status = vpPoseScale::DEGENERATE;
      res.message = "yardstick view " + std::to_string(j) + ": the ends do not triangulate in front of both cameras";
      return false;
    }
    res.lengths.push_back(l);
    if (!options.weighted)
      continue;
    const double var = unitLengthVariance(v, M, R, t, px, K, l, pixel_sd);
    // Sensitivity to the focal length (pose fixed): the common error of a self-calibrated f.
    {
      const double hf = 1e-3 * K.fx;
      double lp = l, lm = l;
      unitLength(R, t, px, Intrinsics{K.fx + hf, K.u0, K.v0, K.mu}, lp);
      unitLength(R, t, px, Intrinsics{K.fx - hf, K.u0, K.v0, K.mu}, lm);
      out.dlogl_df.push_back((std::log(lp) - std::log(lm)) / (2 * hf));
    }
    out.rel_var.push_back(var / (l * l) + v.ratio_sd * v.ratio_sd);
    res.relative_sd.push_back(std::sqrt(out.rel_var.back()));
  }
  return true;
}

/*
  The joint fit of the ends in every image (the views sharing their first image): res's scale and
  sd from it, the focal length's common error added. False when it fails (the per-pair combination
  stands).
*/
bool jointYardstick(const std::vector<YardstickView> &views, double length, const Intrinsics &K,
                    const vpPoseScale::YardstickOptions &options, double pixel_sd, double scale,
                    const std::vector<double> &rel_var, vpPoseScale::Result &res)
{
  size_t best = 0;
  for (size_t j = 1; j < views.size(); ++j)
    if (rel_var[j] < rel_var[best])
      best = j;
  const JointScale js = jointScale(views, length, K, pixel_sd, scale, best);
  if (!js.ok)
    return false;
  res.scale = js.scale;
  res.predicted_sd = js.predicted_sd;
  const double factor = js.dof > 0 ? std::sqrt(js.chi2 / js.dof) : 1.0;
  res.sd = res.predicted_sd * std::max(1.0, factor);
  if (options.fx_sd > 0) {
    // The focal length's common error: d scale / d fx by solving again at fx + hf.
    const double hf = 1e-3 * K.fx;
    const JointScale jf = jointScale(views, length, Intrinsics{K.fx + hf, K.u0, K.v0, K.mu}, pixel_sd, js.scale, best);
    if (jf.ok) {
      const double f_part = (jf.scale - js.scale) / hf * options.fx_sd;
      res.predicted_sd = std::sqrt(res.predicted_sd * res.predicted_sd + f_part * f_part);
      res.sd = std::sqrt(res.sd * res.sd + f_part * f_part);
    }
  }
  return true;
}

/*
  The sd of the per-pair combination: weighted, from the expected accuracies (widened by the
  residuals, the focal length's common error added); plain, from the residuals of the paper's least
  squares. final_cost: the combination's Ceres cost.
*/
void combinationSd(const std::vector<YardstickView> &views, const vpPoseScale::YardstickOptions &options,
                   const ViewLengths &vl, double scale, double final_cost, vpPoseScale::Result &res)
{
  const size_t n = views.size();
  if (options.weighted) {
    double info = 0;
    for (double v : vl.rel_var)
      info += 1 / std::max(v, 1e-30);
    res.predicted_sd = scale / std::sqrt(info);
    const double factor = n > 1 ? std::sqrt(2 * final_cost / (n - 1)) : 1.0;
    res.sd = res.predicted_sd * std::max(1.0, factor);
    if (options.fx_sd > 0) {
      double g = 0;
      for (size_t j = 0; j < n; ++j)
        g += vl.dlogl_df[j] / std::max(vl.rel_var[j], 1e-30);
      g /= info;
      const double f_part = scale * g * options.fx_sd;
      res.predicted_sd = std::sqrt(res.predicted_sd * res.predicted_sd + f_part * f_part);
      res.sd = std::sqrt(res.sd * res.sd + f_part * f_part);
    }
  } else if (n > 1) {
    // sd of the least-squares scale: sigma^2 (a^T a)^-1 with sigma^2 from the residuals.
    double aa = 0;
    for (size_t j = 0; j < n; ++j)
      aa += std::pow(views[j].ratio * res.lengths[j], 2);
    const double s2 = 2 * final_cost / (n - 1);
    res.sd = std::sqrt(s2 / aa);
  }
}
} // namespace

vpPoseScale::Result vpPoseScale::yardstick(const std::vector<YardstickView> &views, double length, double fx,
                                           double u0, double v0, double mu, const YardstickOptions &options,
                                           const vpSelfCalibNoiseModel &noise)
{
  if (!(length > 0 && std::isfinite(length)) || !(fx > 0 && std::isfinite(fx)) || !(mu > 0) || !std::isfinite(u0) ||
      !std::isfinite(v0))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpPoseScale::yardstick: length, fx and mu must be positive, u0 and v0 finite");
  vpSelfCalib::checkIntrinsics(fx, mu * fx, u0, v0, "vpPoseScale::yardstick: the camera (fx, mu fx, u0, v0)");
  vpSelfCalib::checkLength(length, "the yardstick's length", "vpPoseScale::yardstick");
  options.check();
  noise.check("vpPoseScale::yardstick");
  Result res;
  if (views.empty()) {
    res.message = "no pair of images sees both yardstick ends; two views of the yardstick are needed";
    return res;
  }
  const Intrinsics K{fx, u0, v0, mu};
  ViewLengths vl;
  if (!unitLengths(views, K, options, noise.pixel_sd, res, vl))
    return res;
  const std::vector<double> &rel_var = vl.rel_var;
  // Start: the weighted (or plain) mean of the per-view scales.
  double num = 0, den = 0;
  for (size_t j = 0; j < views.size(); ++j) {
    const double w = options.weighted ? 1 / std::max(rel_var[j], 1e-30) : 1;
    num += w * length / (views[j].ratio * res.lengths[j]);
    den += w;
  }
  double scale = num / den;
  ceres::Problem problem;
  for (size_t j = 0; j < views.size(); ++j)
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<YardstickResidual, 1, 1>(new YardstickResidual{
                                 views[j].ratio * res.lengths[j], length,
                                 options.weighted ? 1 / std::sqrt(std::max(rel_var[j], 1e-30)) : 1.0,
                                 options.weighted}),
                             nullptr, &scale);
  const ceres::Solver::Options so = solverOptions(50, true);
  ceres::Solver::Summary summary;
  vpSelfCalib::solve(so, &problem, &summary);
  res.scale = scale;
  res.status = OK;
  res.message = "ok";
  if (options.weighted && options.joint && sharedReference(views) &&
      jointYardstick(views, length, K, options, noise.pixel_sd, scale, rel_var, res))
    return res;
  combinationSd(views, options, vl, scale, summary.final_cost, res);
  return res;
}
