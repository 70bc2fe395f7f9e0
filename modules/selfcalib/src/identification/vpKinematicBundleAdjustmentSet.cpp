/*
 * ViSP SelfCalib: kinematic bundle adjustment, the estimated set from what the data determine (the
 * marginal information of the corrections at the start values, walked in the preference order).
 */
#include "vpKinematicBundleAdjustmentProblem.h"

#include <visp3/selfcalib/vpSelfCalibException.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iomanip>
#include <limits>
#include <set>
#include <sstream>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include "../core/vpSelfCalibGeometry.h"

using namespace vpSelfCalib;

namespace vpKinematicBundle
{
using Ident = vpKinematicIdentification;

Eigen::MatrixXd correctionInformation(Adjustment &a, ceres::Problem &problem, const vpSelfCalibDataset::Yardstick &y)
{
  const MarginalBlocks blocks = marginalBlocks(a, problem, y);
  const std::vector<double *> &kept = blocks.kept, &eliminated = blocks.eliminated;
  Eigen::MatrixXd H;
  Eigen::VectorXd own;
  if (!marginalInformation(problem, kept, eliminated, H, own))
    return Eigen::MatrixXd();
  const int P = a.P, Q = static_cast<int>(H.rows()) - P;
  if (Q == 0)
    return H;
  const Eigen::MatrixXd Hnn = H.bottomRightCorner(Q, Q);
  Eigen::VectorXd s = Hnn.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(s.asDiagonal() * Hnn * s.asDiagonal());
  Eigen::VectorXd inv = eig.eigenvalues();
  const double top = inv.maxCoeff();
  for (Eigen::Index i = 0; i < inv.size(); ++i)
    inv(i) = inv(i) > 1e-12 * top ? 1.0 / inv(i) : 0.0;
  const Eigen::MatrixXd Hnn_pinv =
      s.asDiagonal() * eig.eigenvectors() * inv.asDiagonal() * eig.eigenvectors().transpose() * s.asDiagonal();
  const Eigen::MatrixXd Hpn = H.topRightCorner(P, Q);
  return H.topLeftCorner(P, P) - Hpn * Hnn_pinv * Hpn.transpose();
}

namespace
{

//! The walk's test of one subset: the sds (m, rad) and the fraction of each one's own information left.
struct Trial {
  bool finite = false;
  Eigen::VectorXd sd, fraction;
};

/*
  The covariance of the corrections `cols` (columns of M) alone, the others held: with the scale
  gauge (no yardstick) the direction the solve holds (scaleDirection of these columns) is removed,
  as the ScaleCost does.
*/
Trial trial(const Eigen::MatrixXd &M, const std::vector<int> &cols, const Adjustment &a, bool gauge)
{
  const int n = static_cast<int>(cols.size());
  Eigen::MatrixXd S(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      S(i, j) = M(cols[i], cols[j]);
  Trial t;
  const Eigen::VectorXd d = S.diagonal();
  if (!(d.minCoeff() > 0))
    return t;
  const Eigen::VectorXd D = d.cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd Ms = D.asDiagonal() * S * D.asDiagonal();
  Eigen::MatrixXd Z = Eigen::MatrixXd::Identity(n, n);
  if (gauge) {
    // In the scaled coordinates y (x = D y) the constraint s^T x = 0 is (D s)^T y = 0.
    const Eigen::VectorXd ds = (D.asDiagonal() * scaleDirection(a.state, cols)).eval();
    if (ds.norm() > 0 && n > 1) {
      const Eigen::HouseholderQR<Eigen::MatrixXd> qr(ds / ds.norm());
      Z = (qr.householderQ() * Eigen::MatrixXd::Identity(n, n)).rightCols(n - 1);
    }
  }
  const Eigen::MatrixXd R = Z.transpose() * Ms * Z;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (R + R.transpose()));
  if (eig.info() != Eigen::Success || !(eig.eigenvalues().minCoeff() > 1e-14))
    return t;
  const Eigen::MatrixXd Cs =
      Z * eig.eigenvectors() * eig.eigenvalues().cwiseInverse().asDiagonal() * eig.eigenvectors().transpose() * Z.transpose();
  t.finite = Cs.allFinite();
  t.sd = (D.array() * Cs.diagonal().cwiseMax(0).cwiseSqrt().array()).matrix();
  t.fraction = Cs.diagonal().cwiseMax(1e-300).cwiseInverse();
  return t;
}

/*
  The set's bias: how the estimated corrections (out.identified) absorb an error of 1 in each one the
  data left at nominal, -M_ee^-1 M_el (the scale direction held, as trial() does); columns in
  out.unidentifiable's order, 0 for the entries of another cause.
*/
vpMatrix setBias(const Eigen::MatrixXd &M, const vpKinematicIdentification::Identifiability &out,
                 const std::function<int(unsigned int)> &column, const Adjustment &a, bool gauge)
{
  const int e = static_cast<int>(out.identified.size()), l = static_cast<int>(out.unidentifiable.size());
  vpMatrix bias(static_cast<unsigned int>(e), static_cast<unsigned int>(l), 0.0);
  if (e == 0 || l == 0)
    return bias;
  std::vector<int> cols;
  for (unsigned int i : out.identified)
    cols.push_back(column(i));
  Eigen::MatrixXd See(e, e);
  for (int i = 0; i < e; ++i)
    for (int j = 0; j < e; ++j)
      See(i, j) = M(cols[i], cols[j]);
  const Eigen::VectorXd D = See.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
  Eigen::MatrixXd Z = Eigen::MatrixXd::Identity(e, e);
  if (gauge && e > 1) {
    const Eigen::VectorXd ds = (D.asDiagonal() * scaleDirection(a.state, cols)).eval();
    if (ds.norm() > 0) {
      const Eigen::HouseholderQR<Eigen::MatrixXd> qr(ds / ds.norm());
      Z = (qr.householderQ() * Eigen::MatrixXd::Identity(e, e)).rightCols(e - 1);
    }
  }
  const Eigen::MatrixXd R = Z.transpose() * D.asDiagonal() * See * D.asDiagonal() * Z;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(0.5 * (R + R.transpose()));
  if (ldlt.info() != Eigen::Success)
    return bias;
  for (int k = 0; k < l; ++k) {
    const vpKinematicIdentification::Unidentifiable &u = out.unidentifiable[k];
    if (u.cause != vpKinematicIdentification::CAUSE_DATA)
      continue;
    const int c = column(u.index);
    if (c >= M.cols())
      continue;
    Eigen::VectorXd m(e);
    for (int i = 0; i < e; ++i)
      m(i) = M(cols[i], c);
    const Eigen::VectorXd b = -(D.asDiagonal() * Z * ldlt.solve(Z.transpose() * (D.asDiagonal() * m))).eval();
    for (int i = 0; i < e; ++i)
      bias[i][k] = std::isfinite(b(i)) ? b(i) : 0.0;
  }
  return bias;
}

std::string withUnit(double v, unsigned int index)
{
  std::ostringstream os;
  os << std::setprecision(2);
  if (index % vpKinematicChain::kBlockSize < 3)
    os << 1e3 * v << " mm";
  else
    os << v * 180.0 / M_PI << " deg";
  return os.str();
}

/*
  What would determine a parameter the data leave out: a joint that barely moves in the views, else
  the joint between its placement and the next one (its own joint and the one before it; eMc: the
  last), the one that moves least in the views;
  the sd shrinks as the inverse of that joint's range, so about ratio times the range (within its
  limits); a joint already moving 20 deg or more asks for more views or less noise.
*/
std::string needs(const vpKinematicChain &chain, const std::vector<vpColVector> &q, unsigned int index, double ratio)
{
  const unsigned int n = chain.getNumJoints(), block = index / vpKinematicChain::kBlockSize;
  if (q.empty() || n == 0)
    return "more views";
  std::vector<double> range(n, 0.0);
  for (unsigned int j = 0; j < n; ++j) {
    double lo = q[0][j], hi = q[0][j];
    for (const vpColVector &v : q) {
      lo = std::min(lo, v[j]);
      hi = std::max(hi, v[j]);
    }
    range[j] = hi - lo;
  }
  // A joint that barely moves (under a tenth of the median range) leaves the placements near it
  // undetermined, directly or through the axes it keeps aligned: it is the one to move. Else the
  // joint between this placement and the next (its own and the one before; eMc: the last).
  std::vector<double> sorted = range;
  std::sort(sorted.begin(), sorted.end());
  const unsigned int least = static_cast<unsigned int>(std::min_element(range.begin(), range.end()) - range.begin());
  std::vector<unsigned int> joints; // 0-based
  if (range[least] < 0.1 * sorted[n / 2])
    joints.push_back(least);
  else if (block == n + 1)
    joints.push_back(n - 1);
  else if (block >= 1) {
    if (block >= 2)
      joints.push_back(block - 2);
    joints.push_back(block - 1);
  }
  if (joints.empty())
    return "more views";
  unsigned int best = joints[0];
  double best_range = 1e300;
  for (unsigned int j : joints)
    if (range[j] < best_range) {
      best_range = range[j];
      best = j;
    }
  const double deg = 180.0 / M_PI, span = chain.getJoints()[best].max - chain.getJoints()[best].min;
  std::ostringstream os;
  os << std::fixed << std::setprecision(best_range * deg < 10 ? 2 : 0);
  const std::string name = "j" + std::to_string(best + 1);
  if (best_range * deg >= 20) {
    os << "more views or less image noise (" << name << " already moves " << best_range * deg
       << " deg; its sd is " << std::setprecision(1) << ratio << " times what it needs)";
    return os.str();
  }
  const double want = std::min(span, std::max(10.0 / deg, best_range * std::max(ratio, 2.0)));
  os << name << " moves " << best_range * deg << " deg in the views; it needs " << name << " to move about "
     << std::setprecision(0) << std::ceil(want * deg) << " deg";
  if (want >= span)
    os << " (its whole range)";
  return os.str();
}
} // namespace

vpKinematicIdentification::Identifiability decideSet(Adjustment &a, const vpKinematicChain &start,
                                                     const vpKinematicIdentification::Identifiability &candidates,
                                                     const std::vector<vpColVector> &q,
                                                     const vpSelfCalibDataset::Yardstick &yardstick, const KBA::Options &opt)
{
  const std::vector<std::string> names = start.getParameterNames();
  const std::vector<std::string> freed =
      vpKinematicIdentification::matchParameters(start, opt.free, "vpKinematicBundleAdjustment: the freed parameters");
  std::shared_ptr<ceres::ParameterBlockOrdering> order;
  KBA::ScaleSource source;
  const std::unique_ptr<ceres::Problem> problem = buildProblem(a, yardstick, opt, 0, order, source, false);
  Ident::Identifiability out = candidates;
  if (!problem)
    return out;
  const Eigen::MatrixXd M = correctionInformation(a, *problem, yardstick);
  if (M.rows() != a.P || !M.allFinite())
    return out;
  const bool gauge = source == KBA::SCALE_NOMINAL;
  // The walk: the freed candidates first, then the others, each in the preference order.
  const std::vector<unsigned int> &id = candidates.identified; // chain order = rho's order
  auto column = [&](unsigned int index) {
    return static_cast<int>(std::lower_bound(id.begin(), id.end(), index) - id.begin());
  };
  auto isFreed = [&](unsigned int index) {
    return std::find(freed.begin(), freed.end(), names[index]) != freed.end();
  };
  std::vector<unsigned int> walk;
  for (int pass = 0; pass < 2; ++pass)
    for (unsigned int c : candidates.order)
      if (std::binary_search(id.begin(), id.end(), c) && isFreed(c) == (pass == 0))
        walk.push_back(c);
  std::vector<int> kept;
  std::vector<unsigned int> kept_index;
  const unsigned int n = start.getNumJoints();
  for (unsigned int c : walk) {
    std::vector<int> cols = kept;
    cols.push_back(column(c));
    const Trial t = trial(M, cols, a, gauge);
    std::ostringstream why;
    why << std::setprecision(2);
    double ratio = 0;
    const int last = static_cast<int>(cols.size()) - 1;
    if (!t.finite || t.fraction(last) < opt.separation_tolerance) {
      // Name the kept parameters it is most correlated with (in the information).
      std::vector<std::pair<double, unsigned int>> mix;
      for (size_t k = 0; k < kept.size(); ++k) {
        const double r = M(kept[k], column(c)) / std::sqrt(M(kept[k], kept[k]) * M(column(c), column(c)));
        mix.push_back({-std::fabs(r), kept_index[k]});
      }
      std::sort(mix.begin(), mix.end());
      why << "the data cannot separate it from the parameters estimated before it (";
      if (t.finite)
        why << "its information given them is " << t.fraction(last) << " of its own";
      else
        why << "no information once they are estimated";
      why << ")";
      for (size_t k = 0; k < mix.size() && k < 3; ++k)
        why << (k ? ", " : ": mostly ") << names[mix[k].second];
      ratio = t.finite ? t.sd(last) / toleranceOf(c, n, opt) : 1e9;
    } else {
      // Its sd, and every kept one's, within the tolerance (a freed one: its own is not checked).
      for (int k = 0; k <= last; ++k) {
        const unsigned int index = k == last ? c : kept_index[k];
        const double tol = toleranceOf(index, n, opt), r = t.sd(k) / tol;
        if (r > 1 && !isFreed(index) && r > ratio) {
          ratio = r;
          why.str("");
          if (index == c)
            why << "its predicted sd would be " << withUnit(t.sd(k), index) << ", beyond the nominal model's tolerance of "
                << withUnit(tol, index);
          else
            why << "estimating it would raise the sd of " << names[index] << " to " << withUnit(t.sd(k), index)
                << ", beyond the nominal model's tolerance of " << withUnit(tol, index);
        }
      }
      if (ratio == 0) {
        kept = cols;
        kept_index.push_back(c);
        continue;
      }
    }
    out.unidentifiable.push_back({c, names[c], why.str(), Ident::CAUSE_DATA, needs(start, q, c, ratio)});
  }
  out.identified = kept_index;
  std::sort(out.identified.begin(), out.identified.end());
  out.rank = static_cast<unsigned int>(out.identified.size());
  std::sort(out.unidentifiable.begin(), out.unidentifiable.end(),
            [](const Ident::Unidentifiable &x, const Ident::Unidentifiable &y) { return x.index < y.index; });
  out.bias = setBias(M, out, column, a, gauge);
  return out;
}

Eigen::VectorXd predictedSd(Adjustment &a, const std::vector<int> &columns, const vpSelfCalibDataset::Yardstick &yardstick,
                            const KBA::Options &opt)
{
  Eigen::VectorXd sd = Eigen::VectorXd::Constant(static_cast<Eigen::Index>(columns.size()),
                                                 std::numeric_limits<double>::infinity());
  std::shared_ptr<ceres::ParameterBlockOrdering> order;
  KBA::ScaleSource source;
  const std::unique_ptr<ceres::Problem> problem = buildProblem(a, yardstick, opt, 0, order, source, false);
  if (!problem)
    return sd;
  const Eigen::MatrixXd M = correctionInformation(a, *problem, yardstick);
  if (M.rows() != a.P || !M.allFinite())
    return sd;
  const Trial t = trial(M, columns, a, source == KBA::SCALE_NOMINAL);
  return t.finite ? t.sd : sd;
}
} // namespace vpKinematicBundle
