/*
 * ViSP SelfCalib: eq. 21 scale propagation and yardstick scale (paper Section 3.2).
 */
#include <visp3/selfcalib/vpPoseScale.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <cmath>

#include <ceres/ceres.h>
#include <opencv2/calib3d.hpp>

#include "../core/vpSelfCalibCeres.h"
#include "../core/vpSelfCalibMath.h"

using namespace vpSelfCalib;

namespace
{
// L = scale * ratio * l: one residual per yardstick view (m).
struct YardstickResidual {
  double ratio_length, length;
  template <typename T> bool operator()(const T *scale, T *r) const
  {
    r[0] = scale[0] * T(ratio_length) - T(length);
    return true;
  }
};
} // namespace

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

vpPoseScale::Result vpPoseScale::yardstick(const std::vector<YardstickView> &views, double length, double fx,
                                           double u0, double v0, double mu)
{
  if (!(length > 0 && std::isfinite(length)) || !(fx > 0 && std::isfinite(fx)) || !(mu > 0) || !std::isfinite(u0) ||
      !std::isfinite(v0))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpPoseScale::yardstick: length, fx and mu must be positive, u0 and v0 finite");
  Result res;
  if (views.empty()) {
    res.message = "no pair of images sees both yardstick ends; two views of the yardstick are needed";
    return res;
  }
  double scale0 = 0;
  ceres::Problem problem;
  double scale = 0;
  for (size_t j = 0; j < views.size(); ++j) {
    const YardstickView &v = views[j];
    for (const vpImagePoint *p : {&v.a1, &v.b1, &v.a2, &v.b2})
      if (!std::isfinite(p->get_u()) || !std::isfinite(p->get_v()))
        throw vpSelfCalibException(vpSelfCalibException::badValue, "vpPoseScale::yardstick: non-finite pixel");
    if (!(v.ratio > 0 && std::isfinite(v.ratio)))
      throw vpSelfCalibException(vpSelfCalibException::badValue, "vpPoseScale::yardstick: ratios must be positive");
    // Normalized coordinates; P1 = [I 0], P2 = [R t] with |t| = 1.
    auto norm = [&](const vpImagePoint &p) { return cv::Point2d((p.get_u() - u0) / fx, (p.get_v() - v0) / (mu * fx)); };
    const std::vector<cv::Point2d> x1 = {norm(v.a1), norm(v.b1)}, x2 = {norm(v.a2), norm(v.b2)};
    cv::Mat P1 = cv::Mat::eye(3, 4, CV_64F), P2(3, 4, CV_64F), X;
    const Rigid M = rigidFromVisp(v.c2Mc1);
    const double tn = M.t.norm();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c)
        P2.at<double>(r, c) = M.R(r, c);
      P2.at<double>(r, 3) = M.t(r) / tn;
    }
    cv::triangulatePoints(P1, P2, x1, x2, X);
    Eigen::Vector3d E[2];
    bool front = true;
    for (int k = 0; k < 2; ++k) {
      const double w = X.at<double>(3, k);
      E[k] = Eigen::Vector3d(X.at<double>(0, k), X.at<double>(1, k), X.at<double>(2, k)) / w;
      const Eigen::Vector3d in2 = M.R * E[k] + M.t / tn;
      front = front && std::isfinite(E[k].z()) && E[k].z() > 0 && in2.z() > 0;
    }
    if (!front) {
      res.status = DEGENERATE;
      res.message = "yardstick view " + std::to_string(j) + ": the ends do not triangulate in front of both cameras";
      return res;
    }
    const double l = (E[0] - E[1]).norm();
    res.lengths.push_back(l);
    scale0 += length / (v.ratio * l);
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<YardstickResidual, 1, 1>(
                                 new YardstickResidual{v.ratio * l, length}),
                             nullptr, &scale);
  }
  scale = scale0 / views.size();
  const ceres::Solver::Options so = solverOptions(50, true);
  ceres::Solver::Summary summary;
  vpSelfCalib::solve(so, &problem, &summary);
  res.scale = scale;
  if (views.size() > 1) {
    // sd of the least-squares scale: sigma^2 (a^T a)^-1 with sigma^2 from the residuals.
    double aa = 0;
    for (size_t j = 0; j < views.size(); ++j)
      aa += std::pow(views[j].ratio * res.lengths[j], 2);
    const double s2 = 2 * summary.final_cost / (views.size() - 1);
    res.sd = std::sqrt(s2 / aa);
  }
  res.status = OK;
  res.message = "ok";
  return res;
}
