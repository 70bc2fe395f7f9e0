/*
 * ViSP SelfCalib: the paper's 3-D verification (Section 4.1, step 5) and held-out pose errors.
 */
#include <visp3/selfcalib/vpCalibrationVerifier.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <cmath>

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

std::map<int, vpColVector> vpCalibrationVerifier::triangulate(const vpKinematicChain &model,
                                                              const vpCameraParameters &cam,
                                                              const std::vector<vpSelfCalibDataset::View> &views)
{
  vpSelfCalib::checkCamera(cam, "vpCalibrationVerifier::triangulate: the camera");
  vpSelfCalib::checkChain(model, "vpCalibrationVerifier::triangulate: the model '" + model.getName() + "'");
  // Each point: the midpoint of its rays through the camera model (distortion included), refined on
  // its reprojection error; a point the rays place behind a camera is left out.
  const CameraModel camera = CameraModel::fromVisp(cam);
  struct Seen {
    std::vector<Ray> rays;
    std::vector<Rigid> cMf;
    std::vector<Eigen::Vector2d> uv;
  };
  std::map<int, Seen> seen;
  for (size_t k = 0; k < views.size(); ++k) {
    if (views[k].q.size() != model.getNumJoints() && !views[k].has_fMe)
      throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                                 "vpCalibrationVerifier: view " + std::to_string(k) + " has no joint vector of size " +
                                     std::to_string(model.getNumJoints()) + " and no fMe");
    const Rigid fMc = rigidFromVisp(cameraPose(model, views[k]));
    for (const auto &o : views[k].points) {
      Seen &s = seen[o.id];
      s.uv.emplace_back(o.ip.get_u(), o.ip.get_v());
      s.rays.push_back(rayThrough(fMc, camera, s.uv.back()));
      s.cMf.push_back(fMc.inverse());
    }
  }
  std::map<int, vpColVector> out;
  for (const auto &kv : seen) {
    Eigen::Vector3d X;
    if (triangulateMidpoint(kv.second.rays, X) && refineTriangulation(camera, kv.second.cMf, kv.second.uv, X))
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
  vpSelfCalib::checkCamera(cam, "vpCalibrationVerifier::verify: the camera");
  vpSelfCalib::checkChain(model, "vpCalibrationVerifier::verify: the model '" + model.getName() + "'");
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
