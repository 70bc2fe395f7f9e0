/*
 * ViSP SelfCalib: whether the joint corrections of a full-kinematics bundle adjustment look like a
 * real arm's reading noise.
 */
#include "vpSelfCalibRobotErrorStructure.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Dense>

#include "../core/vpSelfCalibFormat.h"
#include "../core/vpSelfCalibRobotErrorLevels.h"

namespace vpSelfCalibPipeline
{
namespace
{
//! The standard normal deviate exceeded with probability p (0 < p < 0.5), by bisection on erfc.
double normalUpper(double p)
{
  double lo = 0, hi = 40;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (0.5 * std::erfc(mid / std::sqrt(2.0)) > p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

//! Student's t deviate for nu degrees of freedom at the normal deviate z (Cornish-Fisher, two terms).
double studentUpper(double z, double nu)
{
  const double z3 = z * z * z, z5 = z3 * z * z;
  return z + (z3 + z) / (4 * nu) + (5 * z5 + 16 * z3 + 3 * z) / (96 * nu * nu);
}

using vpSelfCalib::fixed;
} // namespace

} // namespace vpSelfCalibPipeline

// The structure carried in the run's result (vpRobotSelfCalibration.h), judged by jointErrorStructure().
bool vpRobotSelfCalibration::JointErrorStructure::readingNoise() const
{
  using namespace vpSelfCalibPipeline;
  return judged && !offset && pose_compared && pose_bic_gain < -kPoseLikeBic;
}

std::string vpRobotSelfCalibration::JointErrorStructure::describe() const
{
  using namespace vpSelfCalibPipeline;
  std::string s;
  if (offset)
    s = "a constant offset on " + offset_joint + " (its corrections' mean is " + fixed(offset_t, 1) +
        " times its standard error, the 0.1 % bound " + fixed(offset_bound, 1) + ")";
  if (pose_like)
    s += std::string(s.empty() ? "" : " and ") +
         "a per-view displacement of the camera rather than reading noise (the per-view pose error explains the "
         "corrections better: information criterion " +
         fixed(pose_bic_gain, 0) + " lower)";
  if (s.empty() && readingNoise())
    s = "independent noise on each joint and view";
  else if (s.empty() && pose_compared)
    s = "no clear structure: reading noise explains them no better than a per-view displacement of the camera "
        "(information criteria " + fixed(-pose_bic_gain, 0) + " apart, " + fixed(kPoseLikeBic, 0) +
        " needed: too few views, or views that leave much of each displacement to the prior)";
  else if (s.empty())
    s = "no structure that tells reading noise from a misfit (fewer than 6 joints)";
  return s;
}

namespace vpSelfCalibPipeline
{
JointErrorStructure jointErrorStructure(const vpKinematicBundleAdjustment::Result &b, const vpSelfCalibNoiseModel &noise,
                                        const std::vector<vpSelfCalibDataset::View> &views)
{
  JointErrorStructure s;
  const size_t K = b.joint_corrections.size();
  if (K < 3 || K != views.size() || noise.joint_sd.empty())
    return s;
  const int n = static_cast<int>(b.joint_corrections[0].size());
  if (n == 0 || static_cast<int>(b.chain.getNumJoints()) != n)
    return s;
  s.judged = true;

  // A joint's mean correction against its spread (Student's t, K - 1 degrees of freedom).
  const double z = normalUpper(0.0005 / n);
  s.offset_bound = studentUpper(z, static_cast<double>(K - 1));
  for (int i = 0; i < n; ++i) {
    double mean = 0, ss = 0;
    for (const vpColVector &d : b.joint_corrections)
      mean += d[static_cast<unsigned int>(i)];
    mean /= static_cast<double>(K);
    for (const vpColVector &d : b.joint_corrections)
      ss += (d[static_cast<unsigned int>(i)] - mean) * (d[static_cast<unsigned int>(i)] - mean);
    const double se = std::sqrt(ss / static_cast<double>(K - 1) / static_cast<double>(K));
    const double t = se > 0 ? std::fabs(mean) / se : 0;
    if (t > s.offset_t) {
      s.offset_t = t;
      s.offset_joint = "joint " + std::to_string(i + 1);
    }
  }
  s.offset = s.offset_t > s.offset_bound;

  // Reading noise against a per-view pose error, on the camera displacements e_k = J_k dq_k.
  if (n < 6)
    return s;
  Eigen::VectorXd ratio2(n);
  const double top = *std::max_element(noise.joint_sd.begin(), noise.joint_sd.end());
  for (int i = 0; i < n; ++i) {
    const double sd = noise.joint_sd.size() == static_cast<size_t>(n) ? noise.joint_sd[static_cast<size_t>(i)] : top;
    ratio2[i] = (sd / top) * (sd / top);
  }
  const std::vector<unsigned int> &id = b.identifiability.identified;
  const int m6 = 6 * static_cast<int>(K), P = static_cast<int>(id.size());
  Eigen::VectorXd e(m6);
  Eigen::MatrixXd G(m6, P), joint_cov = Eigen::MatrixXd::Zero(m6, m6);
  for (size_t k = 0; k < K; ++k) {
    const int r0 = 6 * static_cast<int>(k);
    const vpMatrix Jv = b.chain.getJointJacobian(views[k].q), Gv = b.chain.getJacobian(views[k].q);
    Eigen::MatrixXd J(6, n);
    Eigen::VectorXd dq(n);
    for (int r = 0; r < 6; ++r) {
      for (int c = 0; c < n; ++c)
        J(r, c) = Jv[static_cast<unsigned int>(r)][static_cast<unsigned int>(c)];
      for (int c = 0; c < P; ++c)
        G(r0 + r, c) = Gv[static_cast<unsigned int>(r)][id[static_cast<size_t>(c)]];
    }
    for (int c = 0; c < n; ++c)
      dq[c] = b.joint_corrections[k][static_cast<unsigned int>(c)];
    e.segment<6>(r0) = J * dq;
    joint_cov.block<6, 6>(r0, r0) = J * ratio2.asDiagonal() * J.transpose();
  }
  // The contrasts the estimated parameters do not move (L^T G = 0, L orthonormal): the corrections
  // are a residual of the adjustment, whose contrasts are the displacements' own (restricted
  // likelihood: the parameters take the rest, under either model).
  Eigen::MatrixXd L = Eigen::MatrixXd::Identity(m6, m6);
  if (P > 0) {
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(G, Eigen::ComputeFullU);
    int rank = 0;
    const Eigen::VectorXd &sv = svd.singularValues();
    for (int i = 0; i < sv.size(); ++i)
      rank += sv[i] > 1e-9 * sv[0];
    L = svd.matrixU().rightCols(m6 - rank);
  }
  const int m = static_cast<int>(L.cols());
  if (m < 6)
    return s;
  const Eigen::VectorXd w = L.transpose() * e;
  // -2 log of the restricted likelihood of w ~ N(0, v A) (A = L^T C L) at the maximum likelihood v,
  // up to a constant common to both models (m (1 + log 2 pi)); infinite when A is singular.
  const auto m2ll = [&](const Eigen::MatrixXd &A) {
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(A);
    const Eigen::VectorXd d = ldlt.vectorD();
    if (ldlt.info() != Eigen::Success || !(d.minCoeff() > 0))
      return std::numeric_limits<double>::infinity();
    const double q = w.dot(ldlt.solve(w));
    return q > 0 ? m * std::log(q / m) + d.array().log().sum() : std::numeric_limits<double>::infinity();
  };
  const double joint = m2ll(L.transpose() * joint_cov * L);
  // The pose model: translation variance v, rotation variance lambda v (lambda in rad^2 / m^2, on a
  // log grid from 1e-4 to 1e6, then refined by golden section around the best): A = At + lambda Ar.
  Eigen::MatrixXd Lt(3 * K, m), Lr(3 * K, m);
  for (size_t k = 0; k < K; ++k) {
    Lt.middleRows(3 * k, 3) = L.middleRows(6 * k, 3);
    Lr.middleRows(3 * k, 3) = L.middleRows(6 * k + 3, 3);
  }
  const Eigen::MatrixXd At = Lt.transpose() * Lt, Ar = Lr.transpose() * Lr;
  const auto pose = [&](double log_lambda) { return m2ll(At + std::pow(10.0, log_lambda) * Ar); };
  double best = 0, best_value = std::numeric_limits<double>::infinity();
  for (double x = -4; x <= 6; x += 0.5) {
    const double v = pose(x);
    if (v < best_value) {
      best_value = v;
      best = x;
    }
  }
  double lo = best - 0.5, hi = best + 0.5;
  const double g = 0.5 * (std::sqrt(5.0) - 1);
  for (int i = 0; i < 20; ++i) {
    const double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
    if (pose(x1) < pose(x2))
      hi = x2;
    else
      lo = x1;
  }
  best_value = std::min(best_value, pose(0.5 * (lo + hi)));
  if (!std::isfinite(joint) || !std::isfinite(best_value))
    return s;
  s.pose_compared = true;
  // Bayesian information criteria: one level for the joints, two for the pose error.
  s.pose_bic_gain = (joint + std::log(static_cast<double>(m))) - (best_value + 2 * std::log(static_cast<double>(m)));
  s.pose_like = s.pose_bic_gain > kPoseLikeBic;
  return s;
}

bool robotErrorImplausible(const vpSelfCalibNoiseModel &noise, const vpKinematicBundleAdjustment::Result &b,
                           const std::vector<vpSelfCalibDataset::View> &views, JointErrorStructure *structure)
{
  using namespace vpSelfCalib;
  const bool model = noise.model_sd_origin == vpSelfCalibNoiseModel::MEASURED &&
                     (noise.model_sd_translation > kModelErrorPlausible || noise.model_sd_rotation > kModelErrorPlausible);
  const bool joints_measured = noise.joint_sd_origin == vpSelfCalibNoiseModel::MEASURED && !noise.joint_sd.empty();
  const double level = joints_measured ? *std::max_element(noise.joint_sd.begin(), noise.joint_sd.end()) : 0;
  bool joints = false;
  if (level > kJointErrorPlausible) {
    JointErrorStructure judged;
    JointErrorStructure &s = structure ? *structure : judged;
    if (!s.judged)
      s = jointErrorStructure(b, noise, views);
    joints = level > kJointErrorImpossible || !s.readingNoise();
  }
  return model || joints;
}
vpSelfCalibDataCheck::Finding robotErrorNotMeasuredFinding(double guessed)
{
  return vpSelfCalibDataCheck::Finding{
      vpSelfCalibDataCheck::WARNING, "robot-error-not-measured",
      "the robot's error could not be measured: with the joint corrections at the level it was measured from (" +
          fixed(1e3 * guessed, 2) +
          " mrad) these views do not determine the estimate, so the joint readings and the model are taken as exact "
          "(as calibrate --joint-sd 0) and the standard deviations leave their error out. State the readings' level "
          "if known (calibrate --joint-sd RAD, or the dataset's robot_error), or add views (more varied "
          "configurations, a scene not all on one plane)"};
}
} // namespace vpSelfCalibPipeline
