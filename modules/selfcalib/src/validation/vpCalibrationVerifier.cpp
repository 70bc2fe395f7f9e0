/*
 * ViSP SelfCalib: the paper's 3-D verification (Section 4.1, step 5) and held-out pose errors.
 */
#include <visp3/selfcalib/vpCalibrationVerifier.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include "../core/vpSelfCalibGeometry.h"
#include "../core/vpSelfCalibMath.h"
#include "../core/vpSelfCalibRange.h"

using namespace vpSelfCalib;

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

namespace
{
// A point's views, and the dataset's view of each.
struct Seen : PointViews {
  std::vector<size_t> view;
};

// The point of the rays: midpoint, then reprojection error minimized; false behind a camera.
bool pointOf(const CameraModel &camera, const Seen &s, Eigen::Vector3d &X)
{
  return triangulate(camera, s, Triangulation::MIDPOINT_REFINED, X);
}

// Largest coordinate error of each observation of a point.
std::vector<double> errorsOf(const CameraModel &camera, const Seen &s, const Eigen::Vector3d &X)
{
  std::vector<double> e;
  for (size_t k = 0; k < s.uv.size(); ++k) {
    Eigen::Vector2d uv;
    // A point outside the lens model's valid region is not seen (as one behind the camera).
    const Eigen::Vector3d Xc = s.cMf[k] * X;
    e.push_back(camera.sees(Xc) && camera.project(Xc, uv, nullptr, nullptr) ? (uv - s.uv[k]).cwiseAbs().maxCoeff()
                                                                            : std::numeric_limits<double>::infinity());
  }
  return e;
}

/*
  Every point seen in two or more views, triangulated; then, robustly against wrong matches among
  the views, an observation whose error exceeds 5 times the robust sd of all errors (1.4826 x their
  median) is left out of a point seen three times or more, and the point triangulated again.
  rejected: (view, id) of the observations left out.
*/
std::map<int, vpColVector> robustTriangulation(const vpKinematicChain &model, const vpCameraParameters &cam,
                                               const std::vector<vpSelfCalibDataset::View> &views,
                                               std::set<std::pair<size_t, int>> &rejected)
{
  vpSelfCalib::checkCamera(cam, "vpCalibrationVerifier::triangulate: the camera");
  vpSelfCalib::checkChain(model, "vpCalibrationVerifier::triangulate: the model '" + model.getName() + "'");
  const CameraModel camera = CameraModel::fromVisp(cam);
  std::map<int, Seen> seen;
  for (size_t k = 0; k < views.size(); ++k) {
    if (views[k].q.size() != model.getNumJoints() && !views[k].has_fMe)
      throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                                 "vpCalibrationVerifier: view " + std::to_string(k) + " has no joint vector of size " +
                                     std::to_string(model.getNumJoints()) + " and no fMe");
    const Rigid fMc = rigidFromVisp(vpCalibrationVerifier::cameraPose(model, views[k]));
    for (const auto &o : views[k].points) {
      Seen &s = seen[o.id];
      s.add(fMc, camera, Eigen::Vector2d(o.ip.get_u(), o.ip.get_v()));
      s.view.push_back(k);
    }
  }
  std::map<int, Eigen::Vector3d> X;
  std::vector<double> all;
  for (const auto &kv : seen) {
    Eigen::Vector3d P;
    if (!pointOf(camera, kv.second, P))
      continue;
    X[kv.first] = P;
    for (double e : errorsOf(camera, kv.second, P))
      if (std::isfinite(e))
        all.push_back(e);
  }
  if (!all.empty()) {
    const auto mid = all.begin() + static_cast<std::ptrdiff_t>(all.size() / 2);
    std::nth_element(all.begin(), mid, all.end());
    // The median of the largest coordinate error of 2 Gaussian coordinates is about 1.0 sd.
    const double threshold = std::max(5.0 * *mid, 0.01); // px: below, no match is wrong
    for (auto &kv : X) {
      const Seen &s = seen[kv.first];
      if (s.uv.size() < 3)
        continue;
      const std::vector<double> e = errorsOf(camera, s, kv.second);
      Seen kept;
      for (size_t k = 0; k < e.size(); ++k) {
        if (e[k] <= threshold) {
          kept.rays.push_back(s.rays[k]);
          kept.cMf.push_back(s.cMf[k]);
          kept.uv.push_back(s.uv[k]);
          kept.view.push_back(s.view[k]);
        } else
          rejected.insert({s.view[k], kv.first});
      }
      if (kept.uv.size() < s.uv.size() && kept.uv.size() >= 2)
        pointOf(camera, kept, kv.second);
    }
  }
  std::map<int, vpColVector> out;
  for (const auto &kv : X)
    out[kv.first] = vpColVector({kv.second.x(), kv.second.y(), kv.second.z()});
  return out;
}
} // namespace

std::map<int, vpColVector> vpCalibrationVerifier::triangulate(const vpKinematicChain &model,
                                                              const vpCameraParameters &cam,
                                                              const std::vector<vpSelfCalibDataset::View> &views)
{
  std::set<std::pair<size_t, int>> rejected;
  return robustTriangulation(model, cam, views, rejected);
}

vpCalibrationVerifier::Result vpCalibrationVerifier::verify(const vpKinematicChain &model, const vpCameraParameters &cam,
                                                            const std::vector<vpSelfCalibDataset::View> &views,
                                                            const vpSelfCalibDataset::Yardstick &yardstick,
                                                            const std::map<int, vpColVector> &true_points,
                                                            const std::vector<vpHomogeneousMatrix> &true_fMc)
{
  vpSelfCalib::checkCamera(cam, "vpCalibrationVerifier::verify: the camera");
  vpSelfCalib::checkChain(model, "vpCalibrationVerifier::verify: the model '" + model.getName() + "'");
  if (views.size() < 2)
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpCalibrationVerifier: at least 2 views are needed");
  if (!true_fMc.empty() && true_fMc.size() != views.size())
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               "vpCalibrationVerifier: true_fMc must have one pose per view");
  Result res;
  std::set<std::pair<size_t, int>> rejected;
  res.points = robustTriangulation(model, cam, views, rejected);
  res.num_rejected = static_cast<unsigned int>(rejected.size());
  auto pa = res.points.find(yardstick.id_a), pb = res.points.find(yardstick.id_b);
  if (yardstick.isSet() && pa != res.points.end() && pb != res.points.end()) {
    res.has_yardstick = true;
    res.yardstick_length = (pa->second - pb->second).frobeniusNorm();
    res.yardstick_error = std::fabs(res.yardstick_length - yardstick.length);
  }
  const CameraModel camera = CameraModel::fromVisp(cam);
  double sum = 0;
  for (size_t k = 0; k < views.size(); ++k) {
    const Rigid cMf = rigidFromVisp(cameraPose(model, views[k])).inverse();
    for (const auto &o : views[k].points) {
      const auto X = res.points.find(o.id);
      if (X == res.points.end() || rejected.count({k, o.id}))
        continue;
      const Eigen::Vector3d Xc = cMf * Eigen::Vector3d(X->second[0], X->second[1], X->second[2]);
      Eigen::Vector2d uv;
      if (!camera.sees(Xc) || !camera.project(Xc, uv, nullptr, nullptr))
        continue; // behind the camera, or outside its lens model's valid region: not seen
      sum += (uv - Eigen::Vector2d(o.ip.get_u(), o.ip.get_v())).squaredNorm();
      ++res.num_observations;
    }
  }
  if (res.num_observations) {
    res.reprojection_rms = std::sqrt(sum / (2.0 * res.num_observations));
    res.reprojection_dof = 2.0 * res.num_observations - 3.0 * static_cast<double>(res.points.size());
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
