/*
 * ViSP SelfCalib: kinematic bundle adjustment, the covariance of the corrections and intrinsics, and
 * its propagation to a relative camera pose.
 */
#include "vpKinematicBundleAdjustmentProblem.h"

#include <visp3/selfcalib/vpSelfCalibException.h>

#include <algorithm>
#include <set>

#include "../core/vpSelfCalibGeometry.h"
#include "../core/vpSelfCalibRange.h"

using namespace vpSelfCalib;

namespace vpKinematicBundle
{
namespace
{
/*
  The full mode's robot error measured by variance component estimation, as the controller poses'
  in hand-eye mode: per part (the joint readings, the model residual's translations, its
  rotations), the sum of the squared whitened corrections over their redundancy, sum (1 - posterior
  variance / prior variance), the posterior variances from `full` (the covariance at the stated
  weights, the dq blocks from row `first`). The joints share one factor (the stated per-joint ratios
  kept). A part whose redundancy is below 1 (the images do not separate its corrections from the
  rest, or its prior is below what they can see) is not measured: it stays 0 in res.measured.
*/
void measureFullModeError(const Adjustment &a, const Eigen::MatrixXd &full, int first, KBA::Result &res)
{
  if (a.state.dq.empty())
    return;
  const int nj = a.state.n_joint, size = static_cast<int>(a.state.dq[0].size());
  double sum[3] = {0, 0, 0}, redundancy[3] = {0, 0, 0};
  for (size_t k = 0; k < a.state.dq.size(); ++k)
    for (int i = 0; i < size; ++i) {
      const int part = i < nj ? 0 : (i < nj + 3 ? 1 : 2), r = first + size * static_cast<int>(k) + i;
      const double prior = a.joint_sd[i] * a.joint_sd[i];
      sum[part] += a.state.dq[k][i] * a.state.dq[k][i] / prior;
      redundancy[part] += 1.0 - full(r, r) / prior;
    }
  if (nj > 0 && redundancy[0] >= 1) {
    const double factor = std::sqrt(sum[0] / redundancy[0]);
    res.measured.joint_sd.assign(a.joint_sd.begin(), a.joint_sd.begin() + nj);
    for (double &sd : res.measured.joint_sd)
      sd *= factor;
  }
  // The model residual's parts apart: a part whose redundancy is below 1 while the other's is not
  // is one its prior holds, not the images (a level the images cannot see): measured 0.
  if (a.state.camera_delta && (redundancy[1] >= 1 || redundancy[2] >= 1)) {
    if (redundancy[1] >= 1)
      res.measured.model_sd_translation = a.noise.model_sd_translation * std::sqrt(sum[1] / redundancy[1]);
    if (redundancy[2] >= 1)
      res.measured.model_sd_rotation = a.noise.model_sd_rotation * std::sqrt(sum[2] / redundancy[2]);
  }
}
} // namespace

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
  // The a posteriori variance factor: the stated noise is too small for the residuals.
  // With robot pose corrections the pose priors take up what the pixels do not: a sigma0 below 1
  // then says the priors were loose, not that the estimate is better, and is not used to shrink.
  const double s2 = res.sigma0 * res.sigma0;
  const bool pose_priors = !a.state.delta.empty() || !a.state.dq.empty();
  const double factor =
      a.scale_covariance_chi2 && !pose_priors ? (res.sigma0 < res.sigma0_low || res.sigma0 > res.sigma0_high ? s2 : 1.0)
      : (a.scale_covariance || a.scale_covariance_chi2) && res.sigma0 > 1 ? s2
                                                                          : 1.0;
  res.covariance_scaled = factor != 1.0;
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
