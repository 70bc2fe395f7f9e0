/*
 * ViSP SelfCalib: the refined nonlinear factor method (paper eqs. 12-13) with Ceres.
 */
#include <visp3/selfcalib/vpRefinedFactorMethod.h>
#include <visp3/selfcalib/vpFactorMethod.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <cmath>
#include <limits>

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include "../core/vpSelfCalibCeres.h"
#include "../core/vpSelfCalibMath.h"

using namespace vpSelfCalib;

namespace
{
/*
  Residual of eq. 13 for one correspondence: e sqrt(1/|l2|^2 + 1/|l1|^2), e = n2^T [t]x R n1,
  n = A^-1 m (normalized coordinates); l2 = A^-T E n1 and l1 = A^-T E^T n2 are the epipolar lines
  in pixels, of which only the first two components enter the point-line distance.
  Parameters: f_x (1), quaternion (w, x, y, z) of R (4), t (3, unit).
*/
struct SymmetricEpipolarResidual {
  SymmetricEpipolarResidual(const vpImagePoint &a, const vpImagePoint &b, double u0, double v0, double mu)
    : u1(a.get_u() - u0), v1(a.get_v() - v0), u2(b.get_u() - u0), v2(b.get_v() - v0), mu(mu)
  {
  }

  template <typename T> bool operator()(const T *f, const T *q, const T *t, T *r) const
  {
    const T n1[3] = {T(u1) / f[0], T(v1) / (T(mu) * f[0]), T(1)};
    const T n2[3] = {T(u2) / f[0], T(v2) / (T(mu) * f[0]), T(1)};
    T Rn1[3];
    ceres::UnitQuaternionRotatePoint(q, n1, Rn1);
    // E n1 = t x (R n1)
    T En1[3];
    ceres::CrossProduct(t, Rn1, En1);
    // E^T n2 = R^T [t]x^T n2 = R^T (n2 x t)
    T n2xt[3];
    ceres::CrossProduct(n2, t, n2xt);
    const T qc[4] = {q[0], -q[1], -q[2], -q[3]};
    T Etn2[3];
    ceres::UnitQuaternionRotatePoint(qc, n2xt, Etn2);
    const T e = n2[0] * En1[0] + n2[1] * En1[1] + n2[2] * En1[2];
    const T a2 = (En1[0] / f[0]) * (En1[0] / f[0]) + (En1[1] / (T(mu) * f[0])) * (En1[1] / (T(mu) * f[0]));
    const T b2 = (Etn2[0] / f[0]) * (Etn2[0] / f[0]) + (Etn2[1] / (T(mu) * f[0])) * (Etn2[1] / (T(mu) * f[0]));
    r[0] = e * sqrt(T(1) / a2 + T(1) / b2);
    return true;
  }

  double u1, v1, u2, v2, mu;
};

struct PairParams {
  double q[4];
  double t[3];
};

PairParams toParams(const vpHomogeneousMatrix &M)
{
  const Rigid R = rigidFromVisp(M);
  const Eigen::Quaterniond q(R.R);
  PairParams p{{q.w(), q.x(), q.y(), q.z()}, {R.t(0), R.t(1), R.t(2)}};
  const double n = std::sqrt(p.t[0] * p.t[0] + p.t[1] * p.t[1] + p.t[2] * p.t[2]);
  for (double &x : p.t)
    x /= n;
  return p;
}

vpHomogeneousMatrix fromParams(const PairParams &p)
{
  Rigid M;
  M.R = Eigen::Quaterniond(p.q[0], p.q[1], p.q[2], p.q[3]).normalized().toRotationMatrix();
  M.t = Eigen::Vector3d(p.t[0], p.t[1], p.t[2]).normalized();
  return toVisp(M);
}
unsigned int inFront(const vpHomogeneousMatrix &c2Mc1, double f, const vpRefinedFactorMethod::Options &opt,
                     const vpRefinedFactorMethod::Pair &pair)
{
  unsigned int n = 0;
  for (size_t i = 0; i < pair.p1.size(); ++i) {
    const double x1[2] = {(pair.p1[i].get_u() - opt.u0) / f, (pair.p1[i].get_v() - opt.v0) / (opt.mu * f)};
    const double x2[2] = {(pair.p2[i].get_u() - opt.u0) / f, (pair.p2[i].get_v() - opt.v0) / (opt.mu * f)};
    double z1, z2;
    vpFactorMethod::triangulateDepths(c2Mc1, x1, x2, z1, z2);
    n += z1 > 0 && z2 > 0;
  }
  return n;
}

vpHomogeneousMatrix keepCheirality(const vpHomogeneousMatrix &c2Mc1, double f, const vpRefinedFactorMethod::Options &opt,
                                   const vpRefinedFactorMethod::Pair &pair)
{
  vpHomogeneousMatrix flipped = c2Mc1;
  for (unsigned int i = 0; i < 3; ++i)
    flipped[i][3] = -c2Mc1[i][3];
  return inFront(flipped, f, opt, pair) > inFront(c2Mc1, f, opt, pair) ? flipped : c2Mc1;
}
} // namespace

void vpRefinedFactorMethod::Options::check() const
{
  if (!(std::isfinite(u0) && std::isfinite(v0) && std::isfinite(mu) && mu > 0))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpRefinedFactorMethod: u0, v0 must be finite and mu positive");
  if (!(std::isfinite(huber) && huber >= 0))
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpRefinedFactorMethod: huber must be >= 0");
  if (max_iterations < 1)
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpRefinedFactorMethod: max_iterations must be >= 1");
}

double vpRefinedFactorMethod::symmetricEpipolarDistance(const vpHomogeneousMatrix &c2Mc1, double fx, double u0,
                                                        double v0, double mu, const vpImagePoint &p1,
                                                        const vpImagePoint &p2)
{
  const PairParams p = toParams(c2Mc1);
  const SymmetricEpipolarResidual r(p1, p2, u0, v0, mu);
  double out;
  r(&fx, p.q, p.t, &out);
  return std::fabs(out);
}

double vpRefinedFactorMethod::rmsSymmetricEpipolarDistance(const vpHomogeneousMatrix &c2Mc1, double fx, double u0,
                                                           double v0, double mu, const std::vector<vpImagePoint> &p1,
                                                           const std::vector<vpImagePoint> &p2)
{
  double ss = 0;
  for (size_t i = 0; i < p1.size(); ++i) {
    const double d = symmetricEpipolarDistance(c2Mc1, fx, u0, v0, mu, p1[i], p2[i]);
    ss += d * d;
  }
  return p1.empty() ? 0 : std::sqrt(ss / p1.size());
}

vpRefinedFactorMethod::Result vpRefinedFactorMethod::refine(const std::vector<Pair> &pairs, double fx,
                                                            const Options &opt)
{
  opt.check();
  if (pairs.empty() || (opt.focal_mode != SHARED && pairs.size() != 1))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpRefinedFactorMethod::refine: PER_PAIR and KNOWN take one pair, SHARED one or more");
  if (!(std::isfinite(fx) && fx > 0))
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpRefinedFactorMethod::refine: fx must be positive");
  double f = fx;
  std::vector<PairParams> params;
  for (const Pair &p : pairs) {
    if (p.p1.size() != p.p2.size())
      throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                                 "vpRefinedFactorMethod::refine: point lists differ in size");
    params.push_back(toParams(p.c2Mc1));
  }
  ceres::Problem::Options po;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  ceres::QuaternionManifold quat; // Ceres order (w, x, y, z), as used by UnitQuaternionRotatePoint
  ceres::SphereManifold<3> sphere;
  for (size_t k = 0; k < pairs.size(); ++k) {
    for (size_t i = 0; i < pairs[k].p1.size(); ++i) {
      auto *cost = new ceres::AutoDiffCostFunction<SymmetricEpipolarResidual, 1, 1, 4, 3>(
          new SymmetricEpipolarResidual(pairs[k].p1[i], pairs[k].p2[i], opt.u0, opt.v0, opt.mu));
      problem.AddResidualBlock(cost, opt.huber > 0 ? new ceres::HuberLoss(opt.huber) : nullptr, &f, params[k].q,
                               params[k].t);
    }
    if (problem.HasParameterBlock(params[k].q)) {
      problem.SetManifold(params[k].q, &quat);
      problem.SetManifold(params[k].t, &sphere);
    }
  }
  Result res;
  if (!problem.HasParameterBlock(&f)) {
    res.message = "no correspondences";
    return res;
  }
  if (opt.focal_mode == KNOWN)
    problem.SetParameterBlockConstant(&f);
  const ceres::Solver::Options so =
      solverOptions(opt.max_iterations, opt.tight, pairs.size() > 1 ? ceres::DENSE_SCHUR : ceres::DENSE_QR);
  ceres::Solver::Summary summary;
  vpSelfCalib::solve(so, &problem, &summary);
  res.iterations = static_cast<unsigned int>(summary.iterations.size());
  res.converged = summary.termination_type == ceres::CONVERGENCE && std::isfinite(f) && f > 0;
  res.message = summary.message;
  res.fx = f;
  for (size_t k = 0; k < pairs.size(); ++k) {
    // The epipolar distance is even in t (E and -E give the same lines), so the minimizer may end
    // at -t even when it started at the factor method's cheirality-checked t. Cheirality again:
    // keep the sign that puts more correspondences in front of both cameras.
    res.c2Mc1.push_back(fromParams(params[k]));
    res.c2Mc1.back() = keepCheirality(res.c2Mc1.back(), f, opt, pairs[k]);
    res.rms.push_back(rmsSymmetricEpipolarDistance(res.c2Mc1[k], f, opt.u0, opt.v0, opt.mu, pairs[k].p1, pairs[k].p2));
  }
  if (opt.focal_mode != KNOWN && res.converged) {
    // Standard deviation of f_x: covariance of the f block, scaled by the residual variance
    // (sigma^2 = 2 cost / (m - dof)). The manifolds leave no gauge freedom, so the full inverse is
    // taken (covarianceOptions()): on a near-degenerate pair f lies in the near-null direction.
    // When the normal matrix is singular to working precision, fx_sd is infinite.
    ceres::Covariance cov(covarianceOptions());
    std::vector<std::pair<const double *, const double *>> blocks = {{&f, &f}};
    res.fx_sd = std::numeric_limits<double>::infinity();
    if (computeCovariance(cov, blocks, &problem)) {
      double c = 0;
      cov.GetCovarianceBlock(&f, &f, &c);
      const int dof = summary.num_residuals - summary.num_effective_parameters;
      const double s2 = dof > 0 ? 2.0 * summary.final_cost / dof : 0.0;
      if (std::isfinite(c) && c >= 0)
        res.fx_sd = std::sqrt(c * s2);
    }
  }
  return res;
}
