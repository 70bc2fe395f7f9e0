/*
 * ViSP SelfCalib: pose-based kinematic identification (paper eq. 6) with Ceres, the estimated set
 * (a fixed preference order at the nominal model), covariance and observability.
 */
#include <visp3/selfcalib/vpKinematicIdentification.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <algorithm>
#include <fnmatch.h>
#include <cmath>
#include <memory>
#include <sstream>

#include <Eigen/QR>
#include <Eigen/Householder>
#include <ceres/ceres.h>

#include "../core/vpSelfCalibCeres.h"
#include "../core/vpSelfCalibGeometry.h"
#include "../core/vpSelfCalibMath.h"
#include "../core/vpSelfCalibRandom.h"
#include "../core/vpSelfCalibRange.h"

using namespace vpSelfCalib;

namespace
{
using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

Eigen::MatrixXd toEigen(const vpMatrix &M)
{
  return Eigen::Map<const RowMajor>(M.data, M.getRows(), M.getCols());
}

/*
  Weighted residual (6) of one measurement and, if J is given, its derivative with respect to all
  chain parameters (6 x N). See the class description for the formulas; with A = fMc(q),
  B = fMc(q_ref), M = A^-1 B, and the chain Jacobian giving (dp, dphi) in f:
      dt_M     = R_A^T (dp_B - dp_A + [p_B - p_A]x dphi_A)
      dtheta_M = R_A^T (dphi_B - dphi_A)      (left perturbation of R_M, in c_i)
      de_r     = J_l(e_r)^-1 dtheta_M.
*/
void evaluate(const vpKinematicChain &chain, const vpKinematicIdentification::Measurement &m, double r[6],
              Eigen::MatrixXd *J, bool at_zero_residual = false)
{
  const Rigid meas = rigidFromVisp(m.M);
  Rigid pred;
  Eigen::MatrixXd JA, JB;
  const Rigid A = rigidFromVisp(chain.get_fMc(m.q));
  if (J)
    JA = toEigen(chain.getJacobian(m.q));
  Rigid B;
  if (m.isRelative()) {
    B = rigidFromVisp(chain.get_fMc(m.q_ref));
    if (J)
      JB = toEigen(chain.getJacobian(m.q_ref));
    pred = A.inverse() * B;
  } else
    pred = A;
  const Eigen::Vector3d et = pred.t - meas.t;
  const Eigen::Vector3d er = logSO3(pred.R * meas.R.transpose());
  for (int i = 0; i < 3; ++i) {
    r[i] = et(i) / m.sd_position;
    r[3 + i] = er(i) / m.sd_rotation;
  }
  if (!J)
    return;
  // at_zero_residual: the Jacobian of the prediction only (J_l = I), which does not depend on the
  // measured values; the identifiability analysis uses it so that noise cannot change the
  // parameter set chosen among exactly dependent columns.
  const Eigen::Matrix3d JlInv = at_zero_residual ? Eigen::Matrix3d::Identity() : Eigen::Matrix3d(leftJacobianSO3(er).inverse());
  J->resize(6, JA.cols());
  if (m.isRelative()) {
    Eigen::MatrixXd Jt, Jr;
    relativePoseJacobian(A, JA, B, JB, Jt, Jr);
    J->topRows(3) = Jt;
    J->bottomRows(3) = JlInv * Jr;
  } else {
    J->topRows(3) = JA.topRows(3);
    J->bottomRows(3) = JlInv * JA.bottomRows(3);
  }
  J->topRows(3) /= m.sd_position;
  J->bottomRows(3) /= m.sd_rotation;
}

// Ceres cost of one measurement over the identified parameters (one block).
class MeasurementCost : public ceres::CostFunction
{
public:
  MeasurementCost(const vpKinematicChain &start, const std::vector<unsigned int> &identified,
                  const vpKinematicIdentification::Measurement &m)
    : m_chain(start), m_identified(identified), m_m(m)
  {
    set_num_residuals(6);
    mutable_parameter_block_sizes()->push_back(static_cast<int>(identified.size()));
  }

  bool Evaluate(double const *const *x, double *residuals, double **jacobians) const override
  {
    vpKinematicChain chain = m_chain;
    vpColVector p = chain.getParameters();
    for (size_t k = 0; k < m_identified.size(); ++k)
      p[m_identified[k]] = x[0][k];
    chain.setParameters(p);
    Eigen::MatrixXd J;
    evaluate(chain, m_m, residuals, jacobians && jacobians[0] ? &J : nullptr);
    if (jacobians && jacobians[0]) {
      const size_t n = m_identified.size();
      for (int i = 0; i < 6; ++i)
        for (size_t k = 0; k < n; ++k)
          jacobians[0][i * n + k] = J(i, m_identified[k]);
    }
    for (int i = 0; i < 6; ++i)
      if (!std::isfinite(residuals[i]))
        return false;
    return true;
  }

private:
  vpKinematicChain m_chain;
  std::vector<unsigned int> m_identified;
  vpKinematicIdentification::Measurement m_m;
};

void checkMeasurements(const vpKinematicChain &chain, const std::vector<vpKinematicIdentification::Measurement> &ms)
{
  const unsigned int n = chain.getNumJoints();
  for (size_t i = 0; i < ms.size(); ++i) {
    const auto &m = ms[i];
    auto finite = [](const vpColVector &v) {
      for (unsigned int k = 0; k < v.size(); ++k)
        if (!std::isfinite(v[k]))
          return false;
      return true;
    };
    bool M_finite = true;
    for (unsigned int r = 0; r < 4; ++r)
      for (unsigned int c = 0; c < 4; ++c)
        M_finite = M_finite && std::isfinite(m.M[r][c]);
    std::ostringstream where;
    where << "vpKinematicIdentification: measurement " << i << ": ";
    if (m.q.size() != n || (m.isRelative() && m.q_ref.size() != n))
      throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                                 where.str() + "joint vectors must have " + std::to_string(n) + " values");
    if (!finite(m.q) || !finite(m.q_ref) || !M_finite)
      throw vpSelfCalibException(vpSelfCalibException::badValue, where.str() + "non-finite joints or pose");
    if (!(m.sd_position > 0 && m.sd_rotation > 0 && std::isfinite(m.sd_position) && std::isfinite(m.sd_rotation)))
      throw vpSelfCalibException(vpSelfCalibException::badValue, where.str() + "standard deviations must be positive");
  }
}

bool allConfigurationsEqual(const std::vector<vpKinematicIdentification::Measurement> &ms)
{
  auto same = [](const vpColVector &a, const vpColVector &b) {
    if (a.size() != b.size())
      return false;
    for (unsigned int k = 0; k < a.size(); ++k)
      if (std::fabs(a[k] - b[k]) > 1e-12)
        return false;
    return true;
  };
  for (const auto &m : ms) {
    if (!same(m.q, ms[0].q))
      return false;
    if (m.isRelative() && !same(m.q_ref, m.q))
      return false;
  }
  return true;
}
} // namespace

const char *vpKinematicIdentification::statusName(Status s)
{
  switch (s) {
  case OK:
    return "ok";
  case TOO_FEW_MEASUREMENTS:
    return "too few measurements";
  case RANK_DEFICIENT:
    return "rank deficient";
  case NO_CONVERGENCE:
    return "no convergence";
  }
  return "unknown";
}

void vpKinematicIdentification::Options::check() const
{
  if (!(rank_tolerance > 0 && rank_tolerance < 1))
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpKinematicIdentification: rank_tolerance in (0, 1)");
  if (!(correlation_threshold > 0 && correlation_threshold <= 1))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicIdentification: correlation_threshold in (0, 1]");
  if (max_iterations < 1)
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpKinematicIdentification: max_iterations >= 1");
}

vpColVector vpKinematicIdentification::residual(const vpKinematicChain &chain, const Measurement &m)
{
  checkMeasurements(chain, {m});
  double r[6];
  evaluate(chain, m, r, nullptr);
  vpColVector out(6);
  for (unsigned int i = 0; i < 6; ++i)
    out[i] = r[i];
  return out;
}

namespace
{
vpMatrix fullJacobian(const vpKinematicChain &chain, const std::vector<vpKinematicIdentification::Measurement> &ms,
                      bool at_zero_residual)
{
  checkMeasurements(chain, ms);
  vpMatrix J(static_cast<unsigned int>(6 * ms.size()), chain.getNumParameters());
  for (size_t i = 0; i < ms.size(); ++i) {
    double r[6];
    Eigen::MatrixXd Ji;
    evaluate(chain, ms[i], r, &Ji, at_zero_residual);
    for (int a = 0; a < 6; ++a)
      for (int b = 0; b < Ji.cols(); ++b)
        J[static_cast<unsigned int>(6 * i + a)][b] = Ji(a, b);
  }
  return J;
}
} // namespace

vpMatrix vpKinematicIdentification::jacobian(const vpKinematicChain &chain, const std::vector<Measurement> &ms)
{
  return fullJacobian(chain, ms, false);
}

vpKinematicIdentification::Identifiability
vpKinematicIdentification::analyseConfigurations(const vpKinematicChain &chain, const std::vector<vpColVector> &q,
                                                 const Options &options)
{
  if (q.size() < 2)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicIdentification::analyseConfigurations: at least 2 configurations are needed");
  std::vector<Measurement> rel;
  const vpHomogeneousMatrix fMc0 = chain.get_fMc(q[0]);
  for (size_t k = 1; k < q.size(); ++k) {
    Measurement m;
    m.q = q[k];
    m.q_ref = q[0];
    m.M = chain.get_fMc(q[k]).inverse() * fMc0;
    rel.push_back(m);
  }
  return analyse(chain, rel, options);
}

std::vector<vpColVector> vpKinematicIdentification::randomConfigurations(const vpKinematicChain &chain,
                                                                         unsigned int count, uint64_t rng_seed,
                                                                         uint64_t rng_stream)
{
  Random rng(rng_seed, rng_stream);
  const vpColVector qmin = chain.getJointMin(), qmax = chain.getJointMax();
  std::vector<vpColVector> q(count, vpColVector(chain.getNumJoints()));
  for (vpColVector &c : q)
    for (unsigned int j = 0; j < c.size(); ++j)
      c[j] = rng.uniform(qmin[j], qmax[j]);
  return q;
}

std::vector<std::string> vpKinematicIdentification::matchParameters(const vpKinematicChain &chain,
                                                                   const std::vector<std::string> &patterns,
                                                                   const std::string &what)
{
  const std::vector<std::string> names = chain.getParameterNames();
  std::vector<bool> hit(names.size(), false);
  for (const std::string &p : patterns) {
    bool any = false;
    for (size_t i = 0; i < names.size(); ++i)
      if (fnmatch(p.c_str(), names[i].c_str(), 0) == 0)
        any = hit[i] = true;
    if (!any) {
      std::string valid;
      for (size_t i = 0; i < names.size(); ++i)
        valid += (i ? ", " : "") + names[i];
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 what + ": '" + p + "' matches no parameter of the model '" + chain.getName() +
                                     "'; valid names (glob patterns such as 'j3.*' allowed): " + valid);
    }
  }
  std::vector<std::string> out;
  for (size_t i = 0; i < names.size(); ++i)
    if (hit[i])
      out.push_back(names[i]);
  return out;
}

std::vector<unsigned int> vpKinematicIdentification::preferenceOrder(const vpKinematicChain &chain)
{
  // See the class description for why this order. Components inside a block: tx ty tz rx ry rz = 0..5.
  const unsigned int B = vpKinematicChain::kBlockSize, n = chain.getNumJoints();
  const unsigned int eMc = B * (n + 1);
  std::vector<unsigned int> order;
  for (unsigned int k = 0; k < B; ++k)
    order.push_back(eMc + k);
  for (unsigned int k = 0; k < B; ++k)
    order.push_back(k);
  const unsigned int joint_order[6] = {5, 2, 0, 3, 4, 1}; // rz tz tx rx ry ty
  for (unsigned int j = 1; j <= n; ++j)
    for (unsigned int k : joint_order)
      order.push_back(B * j + k);
  return order;
}

vpKinematicIdentification::Identifiability vpKinematicIdentification::analyse(const vpKinematicChain &chain,
                                                                              const std::vector<Measurement> &ms,
                                                                              const Options &opt)
{
  opt.check();
  vpSelfCalib::checkChain(chain, "vpKinematicIdentification::analyse: the model '" + chain.getName() + "'");
  if (ms.empty())
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpKinematicIdentification: no measurement");
  checkMeasurements(chain, ms);
  const std::vector<std::string> names = chain.getParameterNames();
  const unsigned int N = chain.getNumParameters();
  std::vector<bool> fixed(N, false);
  for (const std::string &f : matchParameters(chain, opt.fixed, "the fixed parameters"))
    fixed[chain.getParameterIndex(f)] = true;

  // The design Jacobian: predictions at the NOMINAL model and the measurements' joints only, rows in
  // SI units unweighted (sd 1 m and 1 rad), at zero residual (the measured values play no part).
  const vpKinematicChain nominal = chain.nominal();
  std::vector<Measurement> design = ms;
  for (Measurement &m : design) {
    m.M = m.isRelative() ? nominal.get_fMc(m.q).inverse() * nominal.get_fMc(m.q_ref) : nominal.get_fMc(m.q);
    m.sd_position = 1;
    m.sd_rotation = 1;
  }
  const Eigen::MatrixXd J = toEigen(fullJacobian(nominal, design, true));
  const bool relative = ms[0].isRelative();

  Identifiability out;
  out.order = preferenceOrder(chain);
  out.new_direction.assign(N, 0.0);
  const Eigen::VectorXd norms = J.colwise().norm();
  const double max_norm = norms.maxCoeff();
  std::vector<std::string> reason(N);
  std::vector<unsigned int> kept; // in preference order
  Eigen::MatrixXd A(J.rows(), 0); // the kept columns, unit norm
  for (unsigned int c : out.order) {
    if (fixed[c]) {
      reason[c] = "fixed by the caller";
      continue;
    }
    if (!(max_norm > 0) || !(norms(c) > 1e-10 * max_norm)) {
      reason[c] = relative ? "no effect on relative poses: it moves the whole arm rigidly (a base motion, or one "
                             "along or about joint 1's axis), which cancels in c_i M c_ref"
                           : "no effect on the measured poses";
      continue;
    }
    const Eigen::VectorXd a = J.col(c) / norms(c);
    // ||(I - P) a|| for unit a: |R_kk| of the QR of [A a] (Eigen's Householder QR, no pivoting).
    Eigen::MatrixXd Aa(J.rows(), A.cols() + 1);
    Aa << A, a;
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(Aa);
    const double d = A.cols() < J.rows() ? std::fabs(qr.matrixQR()(A.cols(), A.cols())) : 0.0;
    out.new_direction[c] = d;
    if (d > opt.rank_tolerance) {
      kept.push_back(c);
      A = Aa;
      continue;
    }
    // Dependent: the estimated parameters whose columns combine into this one (SI coefficients:
    // a change of this parameter acts as coefficient times that change of each of them).
    const Eigen::VectorXd x = A.householderQr().solve(a);
    std::vector<std::pair<double, size_t>> terms;
    for (Eigen::Index k = 0; k < x.size(); ++k)
      if (std::fabs(x(k)) > 1e-3)
        terms.push_back({std::fabs(x(k)), static_cast<size_t>(k)});
    std::sort(terms.rbegin(), terms.rend());
    std::ostringstream os;
    os.precision(3);
    os << "depends on parameters estimated before it in the preference order (new direction " << d << " <= "
       << opt.rank_tolerance << "): acts on the measurements as";
    for (size_t t = 0; t < terms.size() && t < 4; ++t) {
      const unsigned int k = kept[terms[t].second];
      os << (t ? "," : "") << " " << names[k] << " (" << x(terms[t].second) * norms(c) / norms(k) << ")";
    }
    if (terms.size() > 4)
      os << ", ...";
    reason[c] = os.str();
  }
  out.rank = static_cast<unsigned int>(kept.size());
  out.identified = kept;
  std::sort(out.identified.begin(), out.identified.end());
  for (unsigned int c = 0; c < N; ++c)
    if (!reason[c].empty())
      out.unidentifiable.push_back({c, names[c], reason[c], fixed[c] ? CAUSE_FIXED : CAUSE_MODEL, ""});
  return out;
}

vpKinematicIdentification::Result vpKinematicIdentification::identify(const vpKinematicChain &start,
                                                                      const std::vector<Measurement> &ms,
                                                                      const Options &opt)
{
  opt.check();
  vpSelfCalib::checkChain(start, "vpKinematicIdentification::identify: the model '" + start.getName() + "'");
  if (ms.empty())
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpKinematicIdentification: no measurement");
  checkMeasurements(start, ms);
  Result res;
  res.chain = start;
  res.sd.resize(start.getNumParameters());
  if (allConfigurationsEqual(ms)) {
    res.status = RANK_DEFICIENT;
    res.message = "all measurement configurations are equal: no kinematic parameter can be identified";
    return res;
  }
  return identify(start, ms, opt, analyse(start, ms, opt));
}

namespace
{
using Identifiability = vpKinematicIdentification::Identifiability;
using Measurement = vpKinematicIdentification::Measurement;

/*
  Do these measurements determine every parameter of the estimated set? The same rule restricted to
  it; missing: the parameters of the set it leaves out, when not.
*/
bool determinesSet(const vpKinematicChain &start, const std::vector<Measurement> &ms,
                   const vpKinematicIdentification::Options &opt, const Identifiability &estimated, std::string &missing)
{
  const unsigned int N = start.getNumParameters();
  vpKinematicIdentification::Options only = opt;
  only.fixed.clear();
  const std::vector<std::string> names = start.getParameterNames();
  for (unsigned int i = 0; i < N; ++i)
    if (!std::binary_search(estimated.identified.begin(), estimated.identified.end(), i))
      only.fixed.push_back(names[i]);
  const Identifiability here = vpKinematicIdentification::analyse(start, ms, only);
  if (here.identified != estimated.identified) {
    for (unsigned int i : estimated.identified)
      if (!std::binary_search(here.identified.begin(), here.identified.end(), i))
        missing += (missing.empty() ? "" : ", ") + names[i];
    return false;
  }
  return true;
}

//! Residual RMS, Jacobian of the identified parameters, observability, at res.chain.
void fillFit(const std::vector<Measurement> &ms, vpKinematicIdentification::Result &res)
{
  const std::vector<unsigned int> &id = res.identifiability.identified;
  const size_t p = id.size();
  const vpMatrix Jall = vpKinematicIdentification::jacobian(res.chain, ms);
  vpMatrix Jid(Jall.getRows(), static_cast<unsigned int>(p));
  for (unsigned int i = 0; i < Jall.getRows(); ++i)
    for (size_t k = 0; k < p; ++k)
      Jid[i][static_cast<unsigned int>(k)] = Jall[i][id[k]];
  res.observability = vpObservabilityIndices::fromJacobian(Jid, static_cast<unsigned int>(ms.size()));
  double sp = 0, sr = 0;
  for (const Measurement &m : ms) {
    double r[6];
    evaluate(res.chain, m, r, nullptr);
    for (int i = 0; i < 3; ++i) {
      sp += std::pow(r[i] * m.sd_position, 2);
      sr += std::pow(r[3 + i] * m.sd_rotation, 2);
    }
  }
  res.rms_position = std::sqrt(sp / (3 * ms.size()));
  res.rms_rotation = std::sqrt(sr / (3 * ms.size()));
}

//! Covariance (J^T J)^-1 of the identified parameters x from Ceres at the solution, their sds and
//! strong correlations; false when singular.
bool fillCovariance(ceres::Problem &problem, std::vector<double> &x, const std::vector<std::string> &names,
                    const vpKinematicIdentification::Options &opt, vpKinematicIdentification::Result &res)
{
  const std::vector<unsigned int> &id = res.identifiability.identified;
  const size_t p = id.size();
  ceres::Covariance cov(covarianceOptions());
  std::vector<std::pair<const double *, const double *>> blocks = {{x.data(), x.data()}};
  if (!computeCovariance(cov, blocks, &problem))
    return false;
  std::vector<double> C(p * p);
  cov.GetCovarianceBlock(x.data(), x.data(), C.data());
  res.covariance.resize(static_cast<unsigned int>(p), static_cast<unsigned int>(p));
  for (size_t a = 0; a < p; ++a) {
    for (size_t b = 0; b < p; ++b)
      res.covariance[static_cast<unsigned int>(a)][static_cast<unsigned int>(b)] = C[a * p + b];
    res.sd[id[a]] = std::sqrt(std::max(0.0, C[a * p + a]));
  }
  for (size_t a = 0; a < p; ++a)
    for (size_t b = a + 1; b < p; ++b) {
      const double rho = C[a * p + b] / std::sqrt(C[a * p + a] * C[b * p + b]);
      if (std::fabs(rho) > opt.correlation_threshold)
        res.correlations.push_back({names[id[a]], names[id[b]], rho});
    }
  return true;
}
} // namespace

vpKinematicIdentification::Result vpKinematicIdentification::identify(const vpKinematicChain &start,
                                                                      const std::vector<Measurement> &ms,
                                                                      const Options &opt,
                                                                      const Identifiability &estimated)
{
  opt.check();
  if (ms.empty())
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpKinematicIdentification: no measurement");
  checkMeasurements(start, ms);
  const unsigned int N = start.getNumParameters();
  for (size_t k = 0; k < estimated.identified.size(); ++k)
    if (estimated.identified[k] >= N || (k > 0 && estimated.identified[k] <= estimated.identified[k - 1]))
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpKinematicIdentification::identify: the estimated set must hold increasing indices "
                                 "below " + std::to_string(N));
  Result res;
  res.chain = start;
  res.sd.resize(N);
  if (allConfigurationsEqual(ms)) {
    res.status = RANK_DEFICIENT;
    res.message = "all measurement configurations are equal: no kinematic parameter can be identified";
    return res;
  }
  res.identifiability = estimated;
  std::string missing;
  if (!determinesSet(start, ms, opt, estimated, missing)) {
    res.status = RANK_DEFICIENT;
    res.message = "these " + std::to_string(ms.size()) + " measurements do not determine " + missing +
                  " of the estimated set (pose measurements lost?)";
    return res;
  }
  const std::vector<unsigned int> &id = res.identifiability.identified;
  const size_t p = id.size();
  if (p == 0) {
    res.status = RANK_DEFICIENT;
    res.message = "no parameter has an effect on the measurements";
    return res;
  }
  if (6 * ms.size() <= p) {
    res.status = TOO_FEW_MEASUREMENTS;
    res.message = std::to_string(ms.size()) + " measurements give " + std::to_string(6 * ms.size()) +
                  " equations for " + std::to_string(p) + " identifiable parameters; 6 m > n is needed (paper, Section 4.2)";
    return res;
  }
  std::vector<double> x(p);
  for (size_t k = 0; k < p; ++k)
    x[k] = start.getParameters()[id[k]];
  ceres::Problem problem;
  for (const Measurement &m : ms)
    problem.AddResidualBlock(new MeasurementCost(start, id, m), nullptr, x.data());
  const ceres::Solver::Options so = solverOptions(opt.max_iterations, opt.tight);
  ceres::Solver::Summary summary;
  vpSelfCalib::solve(so, &problem, &summary);
  res.iterations = static_cast<unsigned int>(summary.iterations.size());
  vpColVector params = start.getParameters();
  for (size_t k = 0; k < p; ++k)
    params[id[k]] = x[k];
  res.chain.setParameters(params);
  if (summary.termination_type != ceres::CONVERGENCE) {
    res.status = NO_CONVERGENCE;
    res.message = summary.message;
    return res;
  }
  res.status = OK;
  res.message = "ok";
  const double dof = static_cast<double>(6 * ms.size() - p);
  res.sigma0 = std::sqrt(2 * summary.final_cost / dof);

  fillFit(ms, res);
  if (!fillCovariance(problem, x, start.getParameterNames(), opt, res)) {
    res.status = RANK_DEFICIENT;
    res.message = "the normal matrix of the identified parameters is singular at the solution";
  }
  return res;
}
