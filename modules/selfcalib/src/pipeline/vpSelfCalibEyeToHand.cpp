/*
 * ViSP SelfCalib: the eye-to-hand set-up (a camera fixed in the world, the target on the tool) as
 * the hand-eye method's eye-in-hand problem with the controller poses inverted.
 *
 * Eye-in-hand observes proj(eMc^-1 fMe_i^-1 fP), eye-to-hand proj(bMc^-1 bMe_i eP): the same with
 * fMe_i -> bMe_i^-1, eMc -> bMc and the scene points -> the target's points in the effector frame.
 * The controller pose's error is kept where it is made, bMe_i E(delta) (the bundle adjustment's
 * controller_poses_inverted), so the stated and measured pose sd mean the same in both set-ups.
 */
#include "vpSelfCalibPipelines.h"

#include <visp3/selfcalib/vpSelfCalibException.h>

#include <algorithm>
#include <limits>

#include <opencv2/calib3d.hpp>

using namespace vpSelfCalib;

namespace vpSelfCalibPipeline
{
namespace
{
cv::Mat toCv(const Eigen::Matrix3d &R)
{
  cv::Mat m(3, 3, CV_64F);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      m.at<double>(i, j) = R(i, j);
  return m;
}

cv::Mat toCv(const Eigen::Vector3d &t) { return (cv::Mat_<double>(3, 1) << t(0), t(1), t(2)); }

Rigid fromCv(const cv::Mat &R, const cv::Mat &t)
{
  Rigid M;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j)
      M.R(i, j) = R.at<double>(i, j);
    M.t(i) = t.at<double>(i);
  }
  return M;
}

/*
  The target's pose cMo in one view from its known points (OpenCV's solvePnP on the undistorted
  pixels, iterative from a homography or DLT start); false with fewer than 4 known points seen or
  a failed solve.
*/
bool viewPose(const View &v, const std::map<int, vpColVector> &layout, const vpCameraParameters &cam, Rigid &cMo)
{
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  for (const auto &o : v.points) {
    const auto it = layout.find(o.id);
    if (it == layout.end())
      continue;
    object.emplace_back(it->second[0], it->second[1], it->second[2]);
    image.emplace_back(o.ip.get_u(), o.ip.get_v());
  }
  if (object.size() < 4)
    return false;
  const cv::Mat K = (cv::Mat_<double>(3, 3) << cam.get_px(), 0, cam.get_u0(), 0, cam.get_py(), cam.get_v0(), 0, 0, 1);
  cv::Mat r, t, R;
  if (!cv::solvePnP(object, image, K, cv::Mat(), r, t, false, cv::SOLVEPNP_ITERATIVE))
    return false;
  cv::Rodrigues(r, R);
  cMo = fromCv(R, t);
  if (!cMo.t.allFinite() || !cMo.R.allFinite())
    return false;
  // In front of the camera: the points' median depth (a layout's origin may lie anywhere).
  std::vector<double> z;
  for (const cv::Point3d &X : object)
    z.push_back((cMo * Eigen::Vector3d(X.x, X.y, X.z))(2));
  std::nth_element(z.begin(), z.begin() + static_cast<long>(z.size() / 2), z.end());
  return z[z.size() / 2] > 0;
}

//! Median reprojection error (px) of the known points through bMc and eMo over the views (G = fMe = eMb).
double medianError(const std::vector<View> &views, const std::vector<Rigid> &G, const Rigid &X, const Rigid &eMo,
                   const std::map<int, vpColVector> &layout, const vpCameraParameters &cam)
{
  std::vector<double> e;
  for (size_t k = 0; k < views.size(); ++k) {
    const Rigid cMo = X.inverse() * G[k].inverse() * eMo;
    for (const auto &o : views[k].points) {
      const auto it = layout.find(o.id);
      if (it == layout.end())
        continue;
      const Eigen::Vector3d p = cMo.R * Eigen::Vector3d(it->second[0], it->second[1], it->second[2]) + cMo.t;
      if (!(p(2) > 0)) {
        e.push_back(std::numeric_limits<double>::infinity());
        continue;
      }
      const double u = cam.get_u0() + cam.get_px() * p(0) / p(2), w = cam.get_v0() + cam.get_py() * p(1) / p(2);
      e.push_back(std::hypot(u - o.ip.get_u(), w - o.ip.get_v()));
    }
  }
  if (e.empty())
    return std::numeric_limits<double>::infinity();
  std::nth_element(e.begin(), e.begin() + static_cast<long>(e.size() / 2), e.end());
  return e[e.size() / 2];
}
} // namespace

vpSelfCalibDataset eyeToHandAsEyeInHand(const vpKinematicChain &nominal, const vpSelfCalibDataset &ds)
{
  vpSelfCalibDataset inv = ds;
  for (View &v : inv.views) {
    const vpHomogeneousMatrix bMe = v.has_fMe ? v.fMe : nominal.get_fMe(v.q);
    v.fMe = bMe.inverse();
    v.has_fMe = true;
    v.q = vpColVector();
  }
  return inv;
}

bool handEyeFromKnownPoints(const std::vector<View> &views, const std::map<int, vpColVector> &layout,
                            const vpCameraParameters &cam, Rigid &eMc, Rigid &fMo, double &median_px,
                            unsigned int &num_posed)
{
  std::vector<Rigid> G, cMo;
  std::vector<View> posed;
  std::vector<cv::Mat> Rg, tg, Rt, tt;
  for (const View &v : views) {
    Rigid c;
    if (!v.has_fMe || !viewPose(v, layout, cam, c))
      continue;
    G.push_back(rigidFromVisp(v.fMe));
    cMo.push_back(c);
    posed.push_back(v);
    Rg.push_back(toCv(G.back().R));
    tg.push_back(toCv(G.back().t));
    Rt.push_back(toCv(c.R));
    tt.push_back(toCv(c.t));
  }
  num_posed = static_cast<unsigned int>(G.size());
  if (G.size() < 3)
    return false;
  median_px = std::numeric_limits<double>::infinity();
  for (cv::HandEyeCalibrationMethod m : {cv::CALIB_HAND_EYE_TSAI, cv::CALIB_HAND_EYE_PARK, cv::CALIB_HAND_EYE_HORAUD,
                                         cv::CALIB_HAND_EYE_ANDREFF, cv::CALIB_HAND_EYE_DANIILIDIS}) {
    cv::Mat R, t;
    try {
      cv::calibrateHandEye(Rg, tg, Rt, tt, R, t, m);
    } catch (const cv::Exception &) {
      continue;
    }
    const Rigid X = fromCv(R, t);
    if (!X.t.allFinite() || !X.R.allFinite())
      continue;
    for (size_t k = 0; k < G.size(); ++k) {
      const Rigid o = G[k] * X * cMo[k];
      const double e = medianError(posed, G, X, o, layout, cam);
      if (e < median_px) {
        median_px = e;
        eMc = X;
        fMo = o;
      }
    }
  }
  return std::isfinite(median_px);
}

/*
  The start bMc of an eye-to-hand set-up with a target of known points: handEyeFromKnownPoints() on
  the inverted controller poses (bMc in place of eMc, eMo in place of fMo).
*/
bool eyeToHandStart(const vpSelfCalibDataset &inv, unsigned int num_views, const std::map<int, vpColVector> &layout,
                    vpHomogeneousMatrix &bMc, vpHomogeneousMatrix &eMo, double &median_px)
{
  const std::vector<View> views =
      undistorted(std::vector<View>(inv.views.begin(), inv.views.begin() + num_views), lensOf(inv));
  Rigid X, o;
  unsigned int posed = 0;
  if (!handEyeFromKnownPoints(views, layout, inv.cam, X, o, median_px, posed))
    return false;
  bMc = toVisp(X);
  eMo = toVisp(o);
  return true;
}

vpSelfCalibDataset eyeToHandJointsOnly(const vpSelfCalibDataset &ds, unsigned int num_joints)
{
  vpSelfCalibDataset out = ds;
  for (View &v : out.views)
    if (v.q.size() == num_joints)
      v.has_fMe = false;
  return out;
}

std::vector<View> eyeToHandViews(const vpKinematicChain &model, const std::vector<View> &views)
{
  std::vector<View> out = views;
  for (View &v : out) {
    if (v.q.size() != model.getNumJoints())
      continue;
    v.fMe = model.get_fMe(v.q).inverse();
    v.has_fMe = true;
    v.q = vpColVector();
  }
  return out;
}

void runBundleEyeToHand(const Context &c, Result &res)
{
  const auto ts = std::chrono::steady_clock::now();
  const std::string label = "kinematic bundle adjustment (eye-to-hand)";
  const vpSelfCalibDataset inv =
      eyeToHandAsEyeInHand(c.nominal, eyeToHandJointsOnly(c.dataset, c.nominal.getNumJoints()));
  vpHomogeneousMatrix bMc, eMo;
  double median_px = 0;
  if (c.bundle.known_points.size() < 4 || !eyeToHandStart(inv, c.num_calibration, c.bundle.known_points, bMc, eMo, median_px)) {
    res.status = vpRobotSelfCalibration::IDENTIFICATION_FAILED;
    res.message = label + ": no start pose of the target: fewer than 3 views show 4 of its known points with a "
                          "pose OpenCV's PnP and hand-eye closed forms can solve";
    return;
  }
  const Rigid E = rigidFromVisp(eMo);
  std::map<int, vpColVector> points;
  for (const auto &l : c.bundle.known_points) {
    const Eigen::Vector3d x = E * Eigen::Vector3d(l.second[0], l.second[1], l.second[2]);
    points[l.first] = vpColVector({x(0), x(1), x(2)});
  }
  res.stage_seconds.push_back({"eye-to-hand start", seconds(ts)});
  if (!bundleFrom(c, c.nominal, points, c.dataset.cam.get_px(), c.calibration, c.bundle, label, res))
    return;
  res.message = label + " " + res.bundle.message;
}

void eyeToHandResult(Result &res)
{
  res.camera_mount = vpSelfCalibDataset::CAMERA_IN_WORLD;
  res.calibrated.setCameraInWorld(true); // its hand-eye slot is bMc: its model file says so
  res.has_bMc = res.has_eMc;
  res.bMc = res.eMc;
  res.bMc_sd = res.eMc_sd;
  res.has_eMc = false;
  res.has_eMo = res.bundle.has_object;
  if (res.has_eMo) {
    res.eMo = res.bundle.object_pose;
    res.eMo_sd = res.bundle.object_sd.size() == 6 ? res.bundle.object_sd : vpColVector(6, 0.0);
  }
}

void eyeToHandWithoutLayout(Result &res)
{
  const std::string text =
      "the camera is fixed in the world and the target's layout is not given: bMc started at the identity and "
      "the target's points were reconstructed from the images alone; with a board on the tool, give it "
      "(calibrate --board SPEC --board-geometry): its layout starts bMc where the board's poses put it and fixes "
      "the target's shape";
  res.findings.push_back({vpSelfCalibDataCheck::WARNING, "target-layout-unknown", text});
  if (res.status != vpRobotSelfCalibration::OK)
    res.message += "; " + text;
}
} // namespace vpSelfCalibPipeline
