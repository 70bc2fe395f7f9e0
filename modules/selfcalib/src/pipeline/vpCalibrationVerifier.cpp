/*
 * ViSP SelfCalib: the paper's 3-D verification (Section 4.1, step 5) and held-out pose errors.
 */
#include <visp3/selfcalib/vpCalibrationVerifier.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <cmath>

#include <ceres/ceres.h>

#include "../core/vpSelfCalibCeres.h"
#include "../core/vpSelfCalibMath.h"

using namespace vpSelfCalib;

namespace
{
// Reprojection of a point X (f frame) in a camera cMf with intrinsics; pixels.
struct PointReprojection {
  Rigid cMf;
  double px, py, u0, v0, u, v;
  template <typename T> bool operator()(const T *X, T *r) const
  {
    T p[3];
    for (int i = 0; i < 3; ++i)
      p[i] = T(cMf.R(i, 0)) * X[0] + T(cMf.R(i, 1)) * X[1] + T(cMf.R(i, 2)) * X[2] + T(cMf.t(i));
    r[0] = T(px) * p[0] / p[2] + T(u0) - T(u);
    r[1] = T(py) * p[1] / p[2] + T(v0) - T(v);
    return true;
  }
};

} // namespace

vpHomogeneousMatrix vpCalibrationVerifier::cameraPose(const vpKinematicChain &model, const vpSelfCalibDataset::View &v)
{
  if (v.q.size() == model.getNumJoints())
    return model.get_fMc(v.q);
  if (!v.has_fMe)
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               "vpCalibrationVerifier: a view has no joint vector of size " +
                                   std::to_string(model.getNumJoints()) + " and no fMe");
  return v.fMe * model.get_eMc_corrected();
}

std::map<int, vpColVector> vpCalibrationVerifier::triangulate(const vpKinematicChain &model,
                                                              const vpCameraParameters &cam,
                                                              const std::vector<vpSelfCalibDataset::View> &views)
{
  struct Ray {
    Rigid fMc;
    double u, v;
  };
  std::map<int, std::vector<Ray>> rays;
  for (size_t k = 0; k < views.size(); ++k) {
    if (views[k].q.size() != model.getNumJoints() && !views[k].has_fMe)
      throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                                 "vpCalibrationVerifier: view " + std::to_string(k) + " has no joint vector of size " +
                                     std::to_string(model.getNumJoints()) + " and no fMe");
    const Rigid fMc = rigidFromVisp(cameraPose(model, views[k]));
    for (const auto &o : views[k].points)
      rays[o.id].push_back({fMc, o.ip.get_u(), o.ip.get_v()});
  }
  std::map<int, vpColVector> out;
  for (const auto &kv : rays) {
    if (kv.second.size() < 2)
      continue;
    // Linear start: the point closest to all rays, sum (I - d d^T) (X - c) = 0.
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    for (const Ray &r : kv.second) {
      const Eigen::Vector3d dc((r.u - cam.get_u0()) / cam.get_px(), (r.v - cam.get_v0()) / cam.get_py(), 1.0);
      const Eigen::Vector3d d = (r.fMc.R * dc).normalized();
      const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - d * d.transpose();
      A += P;
      b += P * r.fMc.t;
    }
    Eigen::Vector3d X = A.ldlt().solve(b);
    ceres::Problem problem;
    for (const Ray &r : kv.second)
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PointReprojection, 2, 3>(new PointReprojection{
                                   r.fMc.inverse(), cam.get_px(), cam.get_py(), cam.get_u0(), cam.get_v0(), r.u, r.v}),
                               nullptr, X.data());
    const ceres::Solver::Options so = solverOptions(50, true);
    ceres::Solver::Summary summary;
    vpSelfCalib::solve(so, &problem, &summary);
    if (X.allFinite())
      out[kv.first] = vpColVector({X.x(), X.y(), X.z()});
  }
  return out;
}

vpCalibrationVerifier::Result vpCalibrationVerifier::verify(const vpKinematicChain &model, const vpCameraParameters &cam,
                                                            const std::vector<vpSelfCalibDataset::View> &views,
                                                            const vpSelfCalibDataset::Yardstick &yardstick,
                                                            const std::map<int, vpColVector> &true_points,
                                                            const std::vector<vpHomogeneousMatrix> &true_fMc)
{
  if (views.size() < 2)
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpCalibrationVerifier: at least 2 views are needed");
  if (!true_fMc.empty() && true_fMc.size() != views.size())
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               "vpCalibrationVerifier: true_fMc must have one pose per view");
  Result res;
  res.points = triangulate(model, cam, views);
  auto pa = res.points.find(yardstick.id_a), pb = res.points.find(yardstick.id_b);
  if (yardstick.isSet() && pa != res.points.end() && pb != res.points.end()) {
    res.has_yardstick = true;
    res.yardstick_length = (pa->second - pb->second).frobeniusNorm();
    res.yardstick_error = std::fabs(res.yardstick_length - yardstick.length);
  }
  if (!true_points.empty()) {
    std::vector<std::pair<vpColVector, vpColVector>> both;
    for (const auto &kv : res.points) {
      auto t = true_points.find(kv.first);
      if (t != true_points.end())
        both.push_back({kv.second, t->second});
    }
    double s = 0, ss = 0;
    for (size_t i = 0; i < both.size(); ++i)
      for (size_t j = i + 1; j < both.size(); ++j) {
        const double e = std::fabs((both[i].first - both[j].first).frobeniusNorm() -
                                   (both[i].second - both[j].second).frobeniusNorm());
        s += e;
        ss += e * e;
        res.distance_error_max = std::max(res.distance_error_max, e);
        ++res.num_pairs;
      }
    if (res.num_pairs) {
      res.distance_error_mean = s / res.num_pairs;
      res.distance_error_rms = std::sqrt(ss / res.num_pairs);
    }
  }
  if (!true_fMc.empty()) {
    const Rigid m0 = rigidFromVisp(cameraPose(model, views[0])), t0 = rigidFromVisp(true_fMc[0]);
    for (size_t k = 1; k < views.size(); ++k) {
      const Rigid pred = m0.inverse() * rigidFromVisp(cameraPose(model, views[k]));
      const Rigid truth = t0.inverse() * rigidFromVisp(true_fMc[k]);
      res.position_errors.push_back((pred.t - truth.t).norm());
      res.rotation_errors.push_back(logSO3(pred.R * truth.R.transpose()).norm());
      res.position_error_mean += res.position_errors.back() / (views.size() - 1);
      res.rotation_error_mean += res.rotation_errors.back() / (views.size() - 1);
    }
  }
  return res;
}
