/*
 * ViSP SelfCalib: kinematic bundle adjustment, the covariance of the corrections and intrinsics, and
 * its propagation to a relative camera pose.
 */
#include "vpKinematicBundleAdjustmentProblem.h"

#include <visp3/selfcalib/vpSelfCalibException.h>

#include <algorithm>
#include <cmath>
#include <set>

#include <Eigen/Eigenvalues>

#include "../core/vpSelfCalibChiSquare.h"
#include "../core/vpSelfCalibGeometry.h"
#include "../core/vpSelfCalibRange.h"

using namespace vpSelfCalib;

namespace vpKinematicBundle
{
namespace
{
/*
  The variance components of the full mode (Helmert's estimation; Koch, Parameter Estimation and
  Hypothesis Testing in Linear Models, 3.6): the groups are the pixels (0), the joint corrections
  (1), the model residual's translations (2) and rotations (3). With the whitened posterior
  covariance of the corrections B (their covariance at the weights used over their prior sds) and
  M = I - B, H(k, j) is the sum of M's squared entries between groups k and j, r(k) the trace of
  M's block k (its redundancy) and q(k) the sum of the squared whitened corrections. The pixels'
  row follows from those of the corrections (the rows of H sum to r; the redundancies sum to the
  degrees of freedom), so only the corrections' covariance is needed. H theta = q gives each
  group's variance factor on the weight it was used at, unbiased whatever that weight, where the
  diagonal estimate (q(k) / r(k)) gives to each group what the groups that move the cameras the
  same way (the joints and the model residual) explain together.
*/
struct Components {
  Eigen::Matrix4d H = Eigen::Matrix4d::Zero();
  Eigen::Vector4d r = Eigen::Vector4d::Zero(), q = Eigen::Vector4d::Zero();
  bool present[4] = {true, false, false, false};
};

Components components(const Adjustment &a, const Eigen::MatrixXd &full, int first, const KBA::Result &res)
{
  Components c;
  const int nj = a.state.n_joint, size = static_cast<int>(a.state.dq[0].size());
  const int n = size * static_cast<int>(a.state.dq.size());
  auto group = [nj](int i) { return i < nj ? 1 : (i < nj + 3 ? 2 : 3); };
  for (int i = 0; i < size; ++i)
    c.present[group(i)] = true;
  for (int x = 0; x < n; ++x) {
    const int ix = x % size, gx = group(ix);
    const double sx = a.joint_sd[ix], d = a.state.dq[x / size][ix] / sx;
    c.q[gx] += d * d;
    for (int y = 0; y < n; ++y) {
      const int iy = y % size;
      const double m = (x == y ? 1.0 : 0.0) - full(first + x, first + y) / (sx * a.joint_sd[iy]);
      c.H(gx, group(iy)) += m * m;
      if (x == y)
        c.r[gx] += m;
    }
  }
  const double dof = 2.0 * res.num_observations - static_cast<double>(a.P + a.free_in.size() + 3 * res.points.size());
  const double pixel_sd = a.noise.pixel_sd * a.pixel_factor;
  c.r[0] = dof - c.r.tail<3>().sum();
  for (int j = 1; j < 4; ++j)
    c.H(0, j) = c.H(j, 0) = c.r[j] - c.H.row(j).tail<3>().sum();
  c.H(0, 0) = c.r[0] - c.H.row(0).tail<3>().sum();
  c.q[0] = 2.0 * res.num_observations * res.rms * res.rms / (pixel_sd * pixel_sd);
  return c;
}

/*
  H theta = q over the groups `active` (the others held at `fixed`), a group of the robot's error
  whose factor comes out negative held at 0 (no such error) and the rest solved again.
*/
Eigen::Vector4d solveComponents(const Components &c, std::vector<int> active, const Eigen::Vector4d &fixed)
{
  Eigen::Vector4d theta = fixed;
  for (;;) {
    const int m = static_cast<int>(active.size());
    Eigen::MatrixXd H(m, m);
    Eigen::VectorXd q(m);
    for (int k = 0; k < m; ++k) {
      q[k] = c.q[active[k]];
      for (int j = 0; j < 4; ++j)
        if (std::find(active.begin(), active.end(), j) == active.end())
          q[k] -= c.H(active[k], j) * theta[j];
      for (int j = 0; j < m; ++j)
        H(k, j) = c.H(active[k], active[j]);
    }
    const Eigen::VectorXd t = H.colPivHouseholderQr().solve(q);
    int negative = -1;
    for (int k = 0; k < m; ++k) {
      theta[active[k]] = t[k];
      if (active[k] > 0 && t[k] <= 0 && (negative < 0 || t[k] < theta[negative]))
        negative = active[k];
    }
    if (negative < 0)
      return theta;
    theta[negative] = 0;
    active.erase(std::find(active.begin(), active.end(), negative));
  }
}

/*
  The full mode's robot error measured (Result::measured: joint_sd, model_sd_*; the image noise's
  factor into a.pixel_factor_measured) from the variance components. A group whose redundancy is
  below 1 (the images do not separate its corrections from the rest, or its prior is below what
  they can see) is not measured: it stays 0 in res.measured, its factor held at 1. The joints share
  one factor (the stated per-joint ratios kept). When the joints and the model residual move the
  cameras the same way (a 6-joint arm: both span each view's 6-D displacement), their factors are
  correlated beyond kConfounded: one level is measured for both, taken by the joints, and the model
  residual is dropped (Result::robot_error_confounded).
*/
constexpr double kConfounded = 0.9;
constexpr double kNoError = 1e-12; //!< the variance factor of a group measured at 0

void measureFullModeError(Adjustment &a, const Eigen::MatrixXd &full, int first, KBA::Result &res)
{
  a.pixel_factor_measured = 0;
  if (a.state.dq.empty())
    return;
  Components c = components(a, full, first, res);
  std::vector<int> active;
  Eigen::Vector4d fixed = Eigen::Vector4d::Ones();
  for (int k = 0; k < 4; ++k)
    if (c.present[k] && c.r[k] >= 1)
      active.push_back(k);
  if (active.empty() || active[0] != 0)
    return;
  const bool split = c.present[1] && (c.present[2] || c.present[3]) && active.size() > 2 && active[1] == 1;
  if (split) {
    // H^-1 is the factors' covariance up to 2 (Gaussian residuals): a model part whose factor's sd
    // is above 1 (its level not told from none or from twice it) or correlated with the joints'
    // beyond kConfounded is not separated from the joints by these views.
    const int m = static_cast<int>(active.size());
    Eigen::MatrixXd H(m, m);
    for (int k = 0; k < m; ++k)
      for (int j = 0; j < m; ++j)
        H(k, j) = c.H(active[k], active[j]);
    const Eigen::MatrixXd C = H.inverse();
    for (int k = 2; k < m; ++k)
      res.robot_error_confounded = res.robot_error_confounded || !(2 * C(k, k) <= 1) ||
                                   std::fabs(C(1, k)) > kConfounded * std::sqrt(C(1, 1) * C(k, k));
  }
  if (res.robot_error_confounded) {
    // One group: the model's rows and columns added into the joints'.
    for (int k = 2; k < 4; ++k) {
      c.H.row(1) += c.H.row(k);
      c.H.col(1) += c.H.col(k);
      c.H.row(k).setZero();
      c.H.col(k).setZero();
      c.q[1] += c.q[k];
      c.q[k] = 0;
      fixed[k] = 0;
    }
    active = {0, 1};
  }
  const Eigen::Vector4d theta = solveComponents(c, active, fixed);
  res.measured_joint_level_sd = 0;
  if (c.present[1] && active.size() > 1 && active[1] == 1 && theta[1] > 0) {
    // The joints' factor's variance 2 (H^-1)(1, 1) over the groups measured; the level's sd by the delta method.
    const int m = static_cast<int>(active.size());
    Eigen::MatrixXd H(m, m);
    for (int k = 0; k < m; ++k)
      for (int j = 0; j < m; ++j)
        H(k, j) = c.H(active[k], active[j]);
    const double var = 2 * H.inverse()(1, 1);
    const double top = *std::max_element(a.joint_sd.begin(), a.joint_sd.begin() + a.state.n_joint);
    if (var > 0)
      res.measured_joint_level_sd = top * std::sqrt(var) / (2 * std::sqrt(theta[1]));
  }
  if (theta[0] > 0)
    a.pixel_factor_measured = a.pixel_factor * std::sqrt(theta[0]);
  const int nj = a.state.n_joint;
  auto measured = [&](int k) { return std::find(active.begin(), active.end(), k) != active.end(); };
  // A factor of 0 (no such error) is measured as 1e-6 of the level used: below any drop level, and
  // told from a part not measured (0).
  auto sd_factor = [&](int k) { return std::sqrt(std::max(kNoError, theta[k])); };
  if (nj > 0 && measured(1)) {
    res.measured.joint_sd.assign(a.joint_sd.begin(), a.joint_sd.begin() + nj);
    for (double &sd : res.measured.joint_sd)
      sd *= sd_factor(1);
  }
  if (a.state.camera_delta && res.robot_error_confounded) {
    // Taken by the joints: the model residual measured as none (dropped).
    res.measured.model_sd_translation = a.noise.model_sd_translation * std::sqrt(kNoError);
    res.measured.model_sd_rotation = a.noise.model_sd_rotation * std::sqrt(kNoError);
  } else if (a.state.camera_delta) {
    if (measured(2))
      res.measured.model_sd_translation = a.noise.model_sd_translation * sd_factor(2);
    if (measured(3))
      res.measured.model_sd_rotation = a.noise.model_sd_rotation * sd_factor(3);
  }
}
} // namespace

/*
  Without a yardstick the solve holds the scale at the reference model's (the nominal one in the
  pipeline), whose lengths are known to their tolerance only: the scale as one more parameter with
  that prior (scaleGauge(): the relative variance of the scale held). An error e of the scale moves
  the corrections by e s (s: the corrections that scale every camera position by 1 + e, per unit
  e: scaleDirection()), which the images do not see: var(e) s s^T is added to their covariance.
*/
void addNominalScale(const Adjustment &a, KBA::Result &res)
{
  const int P = a.P;
  if (!a.prior_sd.empty() && res.scale_source == KBA::SCALE_NOMINAL && a.scale_dir.size() == P && P > 0) {
    // The kinematic prior holds the scale: its information on it, s^T P s, is the nominal lengths'
    // own, and the posterior covariance already counts it (nothing added; the sd is reported).
    double information = 0;
    for (int r = 0; r < P; ++r)
      if (std::isfinite(a.prior_sd[static_cast<size_t>(r)]))
        information += std::pow(a.scale_dir(r) / a.prior_sd[static_cast<size_t>(r)], 2);
    if (information > 0)
      res.nominal_scale_sd = 1 / std::sqrt(information);
    return;
  }
  if (!a.scale_prior || res.scale_source != KBA::SCALE_NOMINAL || a.scale_dir.size() != P || P == 0 ||
      !(a.scale_variance > 0))
    return;
  for (int r = 0; r < P; ++r)
    for (int c = 0; c < P; ++c)
      res.covariance[r][c] += a.scale_variance * a.scale_dir(r) * a.scale_dir(c);
  res.nominal_scale_sd = std::sqrt(a.scale_variance);
}

/*
  The kinematic prior against the data (Result::prior_groups): per tolerance group, the squared prior
  residuals at the estimate, their expected sum if the corrections were drawn with the prior's sd (the
  trace of I - S C S, C the posterior covariance at the stated weights, before any sigma0 scaling) and
  its 99.9 % quantile (the block's eigenvalues as weights). The corrections lead the kept blocks.
*/
void measurePriorAgreement(const Adjustment &a, const Eigen::MatrixXd &full, KBA::Result &res)
{
  res.prior_groups.clear();
  const int P = a.P;
  if (a.prior_sd.size() != static_cast<size_t>(P) || P == 0 || full.rows() < P)
    return;
  const unsigned int n = a.state.chain.getNumJoints();
  const char *names[4] = {"joint translations", "joint rotations", "hand-eye translations", "hand-eye rotations"};
  for (int g = 0; g < 4; ++g) {
    std::vector<int> rows;
    for (int r = 0; r < P; ++r) {
      const unsigned int i = a.state.id[static_cast<size_t>(r)];
      const bool eMc = i / vpKinematicChain::kBlockSize == n + 1, t = i % vpKinematicChain::kBlockSize < 3;
      if (2 * eMc + !t == g && std::isfinite(a.prior_sd[static_cast<size_t>(r)]))
        rows.push_back(r);
    }
    if (rows.empty())
      continue;
    const Eigen::Index m = static_cast<Eigen::Index>(rows.size());
    Eigen::MatrixXd R(m, m);
    KBA::Result::PriorGroup pg;
    pg.name = names[g];
    for (Eigen::Index u = 0; u < m; ++u) {
      const int r = rows[static_cast<size_t>(u)];
      const double z = (a.state.rho[static_cast<size_t>(r)] - a.rho0[static_cast<size_t>(r)]) / a.prior_sd[static_cast<size_t>(r)];
      pg.chi2 += z * z;
      for (Eigen::Index v = 0; v < m; ++v) {
        const int c = rows[static_cast<size_t>(v)];
        R(u, v) = (u == v ? 1.0 : 0.0) - full(r, c) / (a.prior_sd[static_cast<size_t>(r)] * a.prior_sd[static_cast<size_t>(c)]);
      }
    }
    pg.redundancy = R.trace();
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (R + R.transpose()), Eigen::EigenvaluesOnly);
    pg.quantile = vpSelfCalib::weightedChi2Quantile999(eig.eigenvalues());
    res.prior_groups.push_back(pg);
  }
}

/*
  Stage 6, the covariance of the corrections and the estimated intrinsics with the points
  marginalized (core marginalCovariance); the yardstick's ends, linked by their residual, stay in
  the complement as in the solve. False when the information is singular.
*/
bool fillCovariance(Adjustment &a, ceres::Problem &problem, const vpSelfCalibDataset::Yardstick &yardstick,
                    const std::vector<std::string> &names, KBA::Result &res)
{
  const std::vector<unsigned int> &id = res.identifiability.identified;
  const MarginalBlocks blocks = marginalBlocks(a, problem, yardstick);
  const int P = a.P, N = P + static_cast<int>(a.free_in.size());
  Eigen::MatrixXd full;
  Eigen::MatrixXd undetermined;
  if (!marginalCovariance(problem, blocks.kept, blocks.eliminated, full, &undetermined)) {
    // Name the estimated parameters in the undetermined directions (a component of 0.3 or more in
    // one of them; the pose corrections and the yardstick's ends, also kept, are not named).
    std::vector<std::pair<double, std::string>> named;
    for (int r = 0; r < std::min<int>(N, static_cast<int>(undetermined.rows())); ++r) {
      const double c = undetermined.row(r).cwiseAbs().maxCoeff();
      if (c >= 0.3)
        named.push_back({-c, r < P ? names[id[r]] : intrinsicName(a.state.model, a.free_in[r - P])});
    }
    std::sort(named.begin(), named.end());
    for (const auto &e : named)
      res.undetermined.push_back(e.second);
    return false;
  }
  // The robot pose error measured (variance component estimation): each correction's redundancy is
  // 1 - its posterior variance over its prior one, at the stated weights (the covariance before any
  // sigma0 scaling); the corrections follow the kept blocks before them.
  const double stated_pose_sd[2] = {a.noise.pose_sd_translation, a.noise.pose_sd_rotation};
  if (!a.state.delta.empty() && stated_pose_sd[0] > 0 && stated_pose_sd[1] > 0) {
    const int first = N + 3 * blocks.num_ends;
    double sum[2] = {0, 0}, redundancy[2] = {0, 0};
    for (size_t k = 0; k < a.state.delta.size(); ++k)
      for (int i = 0; i < 6; ++i) {
        const int part = i < 3 ? 0 : 1, r = first + 6 * static_cast<int>(k) + i;
        const double prior = stated_pose_sd[part] * stated_pose_sd[part];
        sum[part] += a.state.delta[k][i] * a.state.delta[k][i];
        redundancy[part] += 1.0 - full(r, r) / prior;
      }
    if (redundancy[0] >= 1 && redundancy[1] >= 1) {
      res.measured.pose_sd_translation = std::sqrt(sum[0] / redundancy[0]);
      res.measured.pose_sd_rotation = std::sqrt(sum[1] / redundancy[1]);
    }
  }
  measureFullModeError(a, full, N + 3 * blocks.num_ends + 6 * static_cast<int>(a.state.delta.size()), res);
  measurePriorAgreement(a, full, res);
  // The a posteriori variance factor: the stated noise is too small for the residuals.
  // With robot pose corrections the pose priors take up what the pixels do not: a sigma0 below 1
  // then says the priors were loose, not that the estimate is better, and is not used to shrink.
  // Nor below vpSelfCalib::kPixelSdFloor of image noise: residuals that small do not measure the
  // observations' error (rendered ChArUco corners on a camera fixed in the world: sigma0 0.03-0.04 at
  // 0.2 px stated, the covariance shrunk 600-fold, bMc 4-5 of those sd off the truth), and the noise
  // rounds make no run at such a level: the covariance is scaled to the floor (a stated level below
  // it stands). Scaled to the stated 0.2 px instead, rendered ChArUco corners eye-in-hand (8 views,
  // 0.005 px of residual) predicted 12 mm on the camera's motions for a model 0.5 mm off the truth.
  const double stated = a.noise.pixel_sd * a.pixel_factor;
  const double floor_ratio = stated > 0 ? std::min(1.0, vpSelfCalib::kPixelSdFloor / stated) : 1.0;
  const double s2 = std::max(res.sigma0 * res.sigma0, floor_ratio * floor_ratio);
  const bool pose_priors = !a.state.delta.empty() || !a.state.dq.empty();
  const bool chi2_scaled = res.sigma0 < res.sigma0_low || res.sigma0 > res.sigma0_high;
  const double factor = a.components_measured                                                  ? 1.0
                        : a.scale_covariance_chi2 && !pose_priors                               ? (chi2_scaled ? s2 : 1.0)
                        : (a.scale_covariance || a.scale_covariance_chi2) && res.sigma0 > 1 ? s2
                                                                                            : 1.0;
  res.covariance_scaled = factor != 1.0 || a.pixel_factor != 1.0;
  res.covariance_factor = factor;
  res.pixel_factor = a.pixel_factor;
  res.covariance.resize(N, N);
  for (int r = 0; r < N; ++r)
    for (int c = 0; c < N; ++c)
      res.covariance[r][c] = factor * full(r, c);
  if (a.has_object && problem.HasParameterBlock(a.object.data())) {
    // The object's block is the last one kept.
    const int o = static_cast<int>(full.rows()) - 6;
    res.object_covariance.resize(6, 6);
    res.object_sd.resize(6);
    for (int r = 0; r < 6; ++r) {
      for (int c = 0; c < 6; ++c)
        res.object_covariance[r][c] = factor * full(o + r, o + c);
      res.object_sd[r] = std::sqrt(std::max(0.0, res.object_covariance[r][r]));
    }
  }
  addNominalScale(a, res);
  for (int r = 0; r < P; ++r)
    res.sd[id[r]] = std::sqrt(std::max(0.0, res.covariance[r][r]));
  for (size_t r = 0; r < a.free_in.size(); ++r) {
    res.intrinsics_sd[static_cast<unsigned int>(r)] = std::sqrt(std::max(0.0, res.covariance[P + r][P + r]));
    if (a.free_in[r] == 0)
      res.fx_sd = res.intrinsics_sd[static_cast<unsigned int>(r)];
  }
  for (int r = 0; r < P; ++r)
    res.covariance_names.push_back(names[id[r]]);
  for (int i : a.free_in)
    res.covariance_names.push_back(intrinsicName(a.state.model, i));
  res.has_covariance = true;
  return true;
}

} // namespace vpKinematicBundle

vpMatrix vpKinematicBundleAdjustment::relativePoseCovariance(const vpKinematicChain &chain,
                                                             const std::vector<unsigned int> &parameters,
                                                             const vpMatrix &covariance, const vpColVector &q_ref,
                                                             const vpColVector &q)
{
  vpSelfCalib::checkChain(chain, "vpKinematicBundleAdjustment::relativePoseCovariance: the model");
  const unsigned int P = static_cast<unsigned int>(parameters.size());
  if (covariance.getRows() < P || covariance.getCols() < P)
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               "vpKinematicBundleAdjustment::relativePoseCovariance: the covariance is smaller than "
                               "the parameter list");
  for (unsigned int i : parameters)
    if (i >= chain.getNumParameters())
      throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                                 "vpKinematicBundleAdjustment::relativePoseCovariance: parameter index out of range");
  const Rigid A = rigidFromVisp(chain.get_fMc(q_ref)), B = rigidFromVisp(chain.get_fMc(q));
  const vpMatrix JA = chain.getJacobian(q_ref), JB = chain.getJacobian(q);
  Eigen::MatrixXd JAs(6, P), JBs(6, P), S(P, P);
  for (unsigned int c = 0; c < P; ++c) {
    for (unsigned int a = 0; a < 6; ++a) {
      JAs(a, c) = JA[a][parameters[c]];
      JBs(a, c) = JB[a][parameters[c]];
    }
    for (unsigned int d = 0; d < P; ++d)
      S(c, d) = covariance[c][d];
  }
  // c_ref M c = A^-1 B (core relativePoseJacobian), then G S G^T.
  Eigen::MatrixXd Jt, Jr, G(6, P);
  relativePoseJacobian(A, JAs, B, JBs, Jt, Jr);
  G.topRows(3) = Jt;
  G.bottomRows(3) = Jr;
  const Eigen::MatrixXd C = G * S * G.transpose();
  vpMatrix out(6, 6);
  for (unsigned int a = 0; a < 6; ++a)
    for (unsigned int b = 0; b < 6; ++b)
      out[a][b] = C(a, b);
  return out;
}
