/*
 * ViSP SelfCalib: a start for eMc and the focal length measured from the data, so that a run does
 * not depend on the model's eMc guess (a preset's can be 90 deg off the real camera) nor on the
 * focal guess (f_guess, or the image width).
 *
 * The camera's motions between views are measured from the images, the end-effector's from the
 * controller poses (or the nominal kinematics at the joints), and the two are tied by
 * fMe_k eMc c_kMo = fMo for every view k (AX = XB):
 * - a target of known points: each view's target pose by PnP, eMc by OpenCV's closed forms;
 * - a scene of unknown points: the two-view motion c_kMc_r of each pair (view r, view k), r the view
 *   that shares enough points with the most others, by
 *   OpenCV's five-point solver (on a plane, which a homography explains: the homography's
 *   decomposition whose plane normal in view r the pairs share), the rotation of eMc by OpenCV's
 *   closed forms, its translation and each pair's unknown scale by linear least squares.
 * A self-calibrated focal length is the one at which the two agree best, scanned over 0.3x to 4x the
 * image width: the median reprojection error of the target's points through the robot, or the
 * median difference between the rotation angle of each camera motion and the end-effector's (the
 * angle of a rotation is the same in both frames, whatever eMc is).
 */
#include "vpSelfCalibPipelines.h"

#include <visp3/selfcalib/vpSelfCalibException.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <set>
#include <sstream>

#include <Eigen/QR>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "../core/vpSelfCalibGeometry.h"
#include "../core/vpSelfCalibMath.h"

using namespace vpSelfCalib;

namespace vpSelfCalibPipeline
{
namespace
{
//! Pairs (view r, view k) with fewer common points are not measured.
const unsigned int kMinPairPoints = 15;
//! Pairs whose end-effector rotates less (rad) carry little on the focal length.
const double kMinPairRotation = 0.035;
/*!
  The five-point RANSAC's iterations at a rung of the focal scan: enough for half of a pair's points
  off at 0.999 confidence (218). At a focal length far from the camera's few points fit and the
  RANSAC would run to OpenCV's 1000; the search about the best rung and the final motions keep 1000.
*/
const int kRungIterations = 250;
const int kIterations = 1000;

double angleOf(const Eigen::Matrix3d &R) { return logSO3(R).norm(); }

double median(std::vector<double> v)
{
  if (v.empty())
    return std::numeric_limits<double>::infinity();
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

//! A rotation or a translation as an OpenCV matrix (CV_64F).
cv::Mat toCvMat(const Eigen::Matrix3d &m)
{
  cv::Mat out;
  cv::eigen2cv(m, out);
  return out;
}

cv::Mat toCvMat(const Eigen::Vector3d &v)
{
  cv::Mat out;
  cv::eigen2cv(v, out);
  return out;
}

//! The pair (view r, view k): common pixels, the end-effector's rotation angle, the camera's motion.
struct Pair {
  unsigned int k = 0;
  std::vector<cv::Point2d> p0, pk; //!< in view r, in view k
  double robot_angle = 0;
  bool posed = false;
  Rigid ckMc0; //!< c_kMc_r, translation of unit length
  cv::Mat H;                            //!< the homography r -> k when it explains the points (a plane)
  std::vector<cv::Point2d> h_inliers0, h_inliersk; //!< its inliers
  bool planar = false;                  //!< ckMc0 is one of the plane's motions below
  std::vector<Rigid> plane_motions;     //!< the homography's motions that keep the points in front
  std::vector<Eigen::Vector3d> normals; //!< the plane's normal in view r of each
};

//! The number of ids views a and b share.
size_t sharedIds(const View &a, const View &b)
{
  std::set<int> ids;
  for (const auto &o : a.points)
    ids.insert(o.id);
  return static_cast<size_t>(
      std::count_if(b.points.begin(), b.points.end(), [&](const vpSelfCalibDataset::Observation &o) { return ids.count(o.id) > 0; }));
}

/*
  The reference view of the pairs: the one that shares kMinPairPoints ids or more with the most
  other views (the first of those when several do), so that a first view that sees little of the
  scene does not leave the start to the guess.
*/
unsigned int referenceView(const std::vector<View> &views)
{
  unsigned int best = 0;
  size_t best_count = 0;
  for (unsigned int r = 0; r < views.size(); ++r) {
    size_t count = 0;
    for (unsigned int k = 0; k < views.size(); ++k)
      count += k != r && sharedIds(views[r], views[k]) >= kMinPairPoints;
    if (count > best_count) {
      best = r;
      best_count = count;
    }
  }
  return best;
}

//! The pairs (view r, view k) with kMinPairPoints common ids or more.
std::vector<Pair> pairsWithView(const std::vector<View> &views, const std::vector<Rigid> &fMe, unsigned int r)
{
  std::map<int, vpImagePoint> first;
  for (const auto &o : views[r].points)
    first[o.id] = o.ip;
  std::vector<Pair> pairs;
  for (unsigned int k = 0; k < views.size(); ++k) {
    if (k == r)
      continue;
    Pair p;
    p.k = k;
    for (const auto &o : views[k].points) {
      const auto it = first.find(o.id);
      if (it == first.end())
        continue;
      p.p0.emplace_back(it->second.get_u(), it->second.get_v());
      p.pk.emplace_back(o.ip.get_u(), o.ip.get_v());
    }
    p.robot_angle = angleOf((fMe[k].inverse() * fMe[r]).R);
    if (p.p0.size() >= kMinPairPoints)
      pairs.push_back(p);
  }
  return pairs;
}

/*
  The pairs whose points a homography explains (its inliers planar_ratio times the fundamental
  matrix's or more, vpTwoViewEstimator's rule) keep it: the scene is a plane, where the five-point
  solutions fit the points but not the motion. Independent of the focal length: found once.
*/
void findPlanes(std::vector<Pair> &pairs, double threshold_px)
{
  for (Pair &p : pairs) {
    cv::Mat h_mask, f_mask;
    const cv::Mat H = cv::findHomography(p.p0, p.pk, cv::RANSAC, threshold_px, h_mask);
    const cv::Mat F = cv::findFundamentalMat(p.p0, p.pk, cv::FM_RANSAC, threshold_px, 0.99, f_mask);
    const int nh = H.empty() ? 0 : cv::countNonZero(h_mask);
    const int nf = F.empty() ? 0 : cv::countNonZero(f_mask);
    if (nh < 8 || nh < vpTwoViewEstimator::Settings().planar_ratio * nf)
      continue;
    p.H = H;
    for (size_t i = 0; i < p.p0.size(); ++i)
      if (h_mask.at<uchar>(static_cast<int>(i))) {
        p.h_inliers0.push_back(p.p0[i]);
        p.h_inliersk.push_back(p.pk[i]);
      }
  }
}

/*
  A plane's pair at the camera (f, the lens's u0, v0, mu): the homography's motions that keep its
  inliers in front of both cameras (core homographyMotions), with the plane's normal in view r of
  each and the translation's direction; choosePlaneMotions() keeps one.
*/
void planeMotions(Pair &p, double f, const CameraModel &lens)
{
  p.plane_motions.clear();
  p.normals.clear();
  Eigen::Matrix3d H;
  cv::cv2eigen(p.H, H);
  const double fy = lens.mu() * f;
  std::vector<Eigen::Vector2d> a, b; // normalized coordinates of the inliers
  for (size_t i = 0; i < p.h_inliers0.size(); ++i) {
    a.emplace_back((p.h_inliers0[i].x - lens.u0()) / f, (p.h_inliers0[i].y - lens.v0()) / fy);
    b.emplace_back((p.h_inliersk[i].x - lens.u0()) / f, (p.h_inliersk[i].y - lens.v0()) / fy);
  }
  for (PlaneMotion &m : homographyMotions(H, f, lens.u0(), lens.v0(), lens.mu(), a, b))
    if (m.bMa.t.norm() > 0) {
      m.bMa.t.normalize();
      p.plane_motions.push_back(m.bMa);
      p.normals.push_back(m.normal);
    }
}

/*
  The plane's two decompositions differ in their normal, and only the true one is the same in every
  pair with view r (the plane's normal in view r): the normal that is nearest to some candidate of
  the most other planar pairs (the smallest median angle) is taken, and each planar pair's motion
  is its candidate with the nearest normal, when that one is less than half as far from it as the
  pair's other candidates (a pair that sees another plane, e.g. the other side of a ridge, is left
  out rather than given a motion at random). Needs 3 planar pairs or more.
*/
void choosePlaneMotions(std::vector<Pair> &pairs)
{
  std::vector<Pair *> planar;
  for (Pair &p : pairs)
    if (!p.plane_motions.empty())
      planar.push_back(&p);
  if (planar.size() < 3)
    return;
  const auto nearest = [](const Pair &p, const Eigen::Vector3d &n, size_t &which) {
    double best = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < p.normals.size(); ++i) {
      const double a = std::acos(std::clamp(p.normals[i].dot(n), -1.0, 1.0));
      if (a < best) {
        best = a;
        which = i;
      }
    }
    return best;
  };
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  double best = std::numeric_limits<double>::infinity();
  for (const Pair *p : planar)
    for (const Eigen::Vector3d &n : p->normals) {
      std::vector<double> angles;
      size_t which = 0;
      for (const Pair *q : planar)
        if (q != p)
          angles.push_back(nearest(*q, n, which));
      const double m = median(angles);
      if (m < best) {
        best = m;
        normal = n;
      }
    }
  for (Pair *p : planar) {
    size_t which = 0;
    const double d = nearest(*p, normal, which);
    double other = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < p->normals.size(); ++i)
      if (i != which)
        other = std::min(other, std::acos(std::clamp(p->normals[i].dot(normal), -1.0, 1.0)));
    if (!(d < 0.5 * other))
      continue;
    p->ckMc0 = p->plane_motions[which];
    p->planar = p->posed = true;
  }
}

//! A posed pair's disagreement (rad): the camera's rotation angle against the end-effector's.
double pairError(const Pair &p) { return std::abs(angleOf(p.ckMc0.R) - p.robot_angle); }

/*
  True when the median over the posed pairs that rotate kMinPairRotation or more is known to be
  above `bound` while `left` of them are still to be posed: 3 or more are posed (the median is
  theirs whatever the others give), and it stays above bound even when every pair left is posed
  below it (the median of n values is the (n/2)-th smallest, counted from 0, as median() takes).
*/
bool scoreAbove(const std::vector<Pair> &pairs, double bound, size_t left)
{
  size_t posed = 0, above = 0;
  for (const Pair &p : pairs)
    if (p.posed && p.robot_angle >= kMinPairRotation) {
      ++posed;
      above += pairError(p) > bound;
    }
  return posed >= 3 && (posed - above) + left <= (posed + left) / 2;
}

/*
  Each pair's camera motion c_kMc_0 at the pinhole camera (f, mu f, u0, v0) by OpenCV's five-point
  RANSAC (classic: deterministic, valid on planes; at most `iterations`) and recoverPose; the median over the pairs of
  |angle(c_kMc_0) - angle(e_kMe_0)| (those that rotate kMinPairRotation or more, all when fewer than
  3 do). Infinite when fewer than 3 pairs are posed, or as soon as the median is known to be above
  `bound` (scoreAbove(): the pairs left are not posed; FocalScore's contract). The plane's pairs are
  posed first (their motions are chosen together), the others one by one.
*/
double motionScore(std::vector<Pair> &pairs, const CameraModel &lens, double f, double threshold_px,
                   int iterations = kIterations, double bound = std::numeric_limits<double>::infinity())
{
  const cv::Mat K = (cv::Mat_<double>(3, 3) << f, 0, lens.u0(), 0, lens.mu() * f, lens.v0(), 0, 0, 1);
  size_t left = 0; // rotating pairs still to pose by the five-point solver
  for (Pair &p : pairs) {
    p.posed = p.planar = false;
    p.plane_motions.clear();
    if (!p.H.empty())
      planeMotions(p, f, lens);
    else
      left += p.robot_angle >= kMinPairRotation;
  }
  choosePlaneMotions(pairs);
  for (Pair &p : pairs) {
    if (!p.H.empty())
      continue;
    if (scoreAbove(pairs, bound, left))
      return std::numeric_limits<double>::infinity();
    left -= p.robot_angle >= kMinPairRotation;
    cv::Mat mask, R, t;
    const cv::Mat E = cv::findEssentialMat(p.p0, p.pk, K, cv::RANSAC, 0.999, threshold_px, iterations, mask);
    if (E.empty() || E.rows != 3 || cv::recoverPose(E(cv::Rect(0, 0, 3, 3)), p.p0, p.pk, K, R, t, mask) == 0)
      continue;
    cv::cv2eigen(R, p.ckMc0.R);
    cv::cv2eigen(t, p.ckMc0.t);
    p.posed = p.ckMc0.R.allFinite() && p.ckMc0.t.allFinite();
  }
  std::vector<double> all, rotating;
  for (const Pair &p : pairs) {
    if (!p.posed)
      continue;
    all.push_back(pairError(p));
    if (p.robot_angle >= kMinPairRotation)
      rotating.push_back(all.back());
  }
  if (all.size() < 3)
    return std::numeric_limits<double>::infinity();
  return median(rotating.size() >= 3 ? rotating : all);
}

/*
  The posed pairs' motions refined at the focal length f (vpTwoViewEstimator, f known: RANSAC, then
  the refined factor method on the inliers): the five-point RANSAC keeps a minimal sample's motion,
  whose rotation axis is off by milliradians on a small, distant scene even without noise. A pair
  the estimator cannot pose keeps its five-point motion.
*/
void refinePairs(std::vector<Pair> &pairs, const CameraModel &lens, double f, double threshold_px)
{
  vpTwoViewEstimator::Options o;
  o.focal_mode = vpRefinedFactorMethod::KNOWN;
  o.fx = f;
  o.u0 = lens.u0();
  o.v0 = lens.v0();
  o.mu = lens.mu();
  o.ransac.inlier_threshold = threshold_px;
  for (Pair &p : pairs) {
    if (!p.posed || p.planar) // a plane's fundamental matrix is not determined
      continue;
    std::vector<vpImagePoint> a, b;
    for (size_t i = 0; i < p.p0.size(); ++i) {
      a.emplace_back(p.p0[i].y, p.p0[i].x);
      b.emplace_back(p.pk[i].y, p.pk[i].x);
    }
    const vpTwoViewEstimator::Result r = vpTwoViewEstimator::estimate(a, b, o);
    const Rigid M = rigidFromVisp(r.c2Mc1);
    if (r.hasPose() && M.t.norm() > 0.5 && M.R.allFinite() && M.t.allFinite())
      p.ckMc0 = M;
  }
}

/*
  eMc from the posed pairs: its rotation by OpenCV's rotation closed forms (Tsai, Park, Horaud; the
  one whose rotations R_e_k R_X R_c_k = R_e_r R_X agree best, median angle), then its translation t
  and each pair's scale s_k by linear least squares on fMe_k eMc c_kMc_r = fMe_r eMc:
  (R_e_k - R_e_r) t + s_k R_e_k R_X u_k = t_e_r - t_e_k (u_k: the pair's unit translation).
  False with fewer than 3 posed pairs, a rank-deficient system or a negative scale in the majority.
*/
bool handEyeFromMotions(const std::vector<Pair> &pairs, const std::vector<Rigid> &fMe, unsigned int r, Rigid &eMc)
{
  std::vector<const Pair *> posed;
  std::vector<cv::Mat> Rg{toCvMat(fMe[r].R)}, tg{toCvMat(fMe[r].t)}, Rt{toCvMat(Eigen::Matrix3d(Eigen::Matrix3d::Identity()))},
      tt{toCvMat(Eigen::Vector3d(Eigen::Vector3d::Zero()))};
  for (const Pair &p : pairs) {
    if (!p.posed)
      continue;
    posed.push_back(&p);
    Rg.push_back(toCvMat(fMe[p.k].R));
    tg.push_back(toCvMat(fMe[p.k].t));
    Rt.push_back(toCvMat(p.ckMc0.R));
    tt.push_back(toCvMat(p.ckMc0.t));
  }
  if (posed.size() < 3)
    return false;
  double best = std::numeric_limits<double>::infinity();
  for (cv::HandEyeCalibrationMethod m : {cv::CALIB_HAND_EYE_TSAI, cv::CALIB_HAND_EYE_PARK, cv::CALIB_HAND_EYE_HORAUD}) {
    cv::Mat R, t;
    try {
      cv::calibrateHandEye(Rg, tg, Rt, tt, R, t, m);
    } catch (const cv::Exception &) {
      continue;
    }
    Eigen::Matrix3d X;
    cv::cv2eigen(R, X);
    if (!X.allFinite())
      continue;
    std::vector<double> e;
    for (const Pair *p : posed)
      e.push_back(angleOf((fMe[p->k].R * X * p->ckMc0.R).transpose() * fMe[r].R * X));
    const double m_e = median(e);
    if (m_e < best) {
      best = m_e;
      eMc.R = X;
    }
  }
  if (!std::isfinite(best))
    return false;
  const Eigen::Index n = static_cast<Eigen::Index>(posed.size());
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(3 * n, 3 + n);
  Eigen::VectorXd b(3 * n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Rigid &Ek = fMe[posed[static_cast<size_t>(i)]->k];
    A.block<3, 3>(3 * i, 0) = Ek.R - fMe[r].R;
    A.block<3, 1>(3 * i, 3 + i) = Ek.R * eMc.R * posed[static_cast<size_t>(i)]->ckMc0.t;
    b.segment<3>(3 * i) = fMe[r].t - Ek.t;
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  if (qr.rank() < 3 + n)
    return false;
  const Eigen::VectorXd x = qr.solve(b);
  eMc.t = x.head<3>();
  const long negative = std::count_if(x.data() + 3, x.data() + x.size(), [](double s) { return !(s > 0); });
  return eMc.t.allFinite() && 2 * negative < n;
}

/*
  True when two of the end-effector's motions from view 0 rotate kMinPairRotation or more about
  axes 3 deg apart or more: without, AX = XB leaves eMc's rotation (and the focal length's scan)
  undetermined.
*/
bool rotatesAboutTwoAxes(const std::vector<Rigid> &fMe)
{
  std::vector<Eigen::Vector3d> axes;
  for (size_t k = 1; k < fMe.size(); ++k) {
    const Eigen::Vector3d r = logSO3((fMe[k].inverse() * fMe[0]).R);
    if (r.allFinite() && r.norm() >= kMinPairRotation)
      axes.push_back(r.normalized());
  }
  for (size_t i = 0; i < axes.size(); ++i)
    for (size_t j = i + 1; j < axes.size(); ++j)
      if (axes[i].cross(axes[j]).norm() >= std::sin(3 * M_PI / 180))
        return true;
  return false;
}

//! True when every pixel and end-effector pose of the views is finite (else the data check says what is wrong).
bool allFinite(const std::vector<View> &views)
{
  for (const View &v : views) {
    if (!rigidFromVisp(v.fMe).R.allFinite() || !rigidFromVisp(v.fMe).t.allFinite())
      return false;
    for (const auto &o : v.points)
      if (!std::isfinite(o.ip.get_u()) || !std::isfinite(o.ip.get_v()))
        return false;
  }
  return true;
}

//! The pinhole camera (f, mu f) of the lens's principal point, no distortion.
vpCameraParameters pinholeAt(const CameraModel &lens, double f)
{
  vpCameraParameters cam;
  cam.initPersProjWithoutDistortion(f, lens.mu() * f, lens.u0(), lens.v0());
  return cam;
}
} // namespace

MeasuredStart measuredStart(const std::vector<View> &views, const CameraModel &lens, unsigned int width,
                            const std::map<int, vpColVector> &layout, bool focal_known, double threshold_px)
{
  MeasuredStart out;
  std::vector<Rigid> fMe;
  for (const View &v : views) {
    if (!v.has_fMe)
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "measuredStart: every view needs its end-effector pose (has_fMe)");
    fMe.push_back(rigidFromVisp(v.fMe));
  }
  const double center = width > 0 ? width : 2 * lens.u0();
  if (!rotatesAboutTwoAxes(fMe)) {
    out.how = "the end-effector does not rotate about two different axes";
    return out;
  }
  // A target of known points: the reprojection error through the robot.
  if (layout.size() >= 4) {
    Rigid fMo;
    double px = 0;
    unsigned int posed = 0;
    const auto score = [&](double f, double) {
      double e = 0;
      return handEyeFromKnownPoints(views, layout, pinholeAt(lens, f), out.eMc, fMo, e, posed)
                 ? e
                 : std::numeric_limits<double>::infinity();
    };
    const double f = focal_known ? lens.px() : scanFocal(score, center);
    if (f > 0 && handEyeFromKnownPoints(views, layout, pinholeAt(lens, f), out.eMc, fMo, px, posed)) {
      std::ostringstream os;
      os << "the target's poses in " << posed << " views (PnP, hand-eye closed form, median " << std::setprecision(3)
         << px << " px through the robot)";
      out.how = os.str();
      out.has_eMc = true;
      out.has_fx = !focal_known;
      out.fx = f;
      return out;
    }
  }
  // Unknown points: the camera's motions from the reference view.
  const unsigned int r = referenceView(views);
  std::vector<Pair> pairs = pairsWithView(views, fMe, r);
  if (pairs.size() < 3) {
    out.how = "no view shares " + std::to_string(kMinPairPoints) + " points with 3 others";
    return out;
  }
  findPlanes(pairs, threshold_px);
  const double f =
      focal_known ? lens.px()
                  : scanFocal([&](double x, double bound) { return motionScore(pairs, lens, x, threshold_px, kIterations, bound); },
                              center,
                              [&](double x, double bound) {
                                return motionScore(pairs, lens, x, threshold_px, kRungIterations, bound);
                              });
  const double score = f > 0 ? motionScore(pairs, lens, f, threshold_px) : std::numeric_limits<double>::infinity();
  if (std::isfinite(score))
    refinePairs(pairs, lens, f, threshold_px);
  if (!std::isfinite(score) || !handEyeFromMotions(pairs, fMe, r, out.eMc)) {
    out.how = "the two-view motions of fewer than 3 pairs with view " + std::to_string(r) + " agree with the robot's";
    return out;
  }
  const long posed = std::count_if(pairs.begin(), pairs.end(), [](const Pair &p) { return p.posed; });
  const long planar = std::count_if(pairs.begin(), pairs.end(), [](const Pair &p) { return p.planar; });
  std::ostringstream os;
  os << "the camera's motions of " << posed << " pairs with view " << r;
  if (planar > 0)
    os << " (" << planar << " on a plane: the homography's motion whose normal the pairs share)";
  os << " (five-point, hand-eye closed form, median " << std::setprecision(3) << score * 180 / M_PI
     << " deg from the robot's rotation angles)";
  out.how = os.str();
  out.has_eMc = true;
  out.has_fx = !focal_known;
  out.fx = f;
  return out;
}
} // namespace vpSelfCalibPipeline

namespace vpSelfCalibPipeline
{
namespace
{
/*
  The eMc a run starts from: the one measured from the data, but for the parts the caller fixed
  (--fix eMc.tz: a value the user knows, from a drawing or a measurement), which keep the guess's.
  The parts are the corrections' components from the guess, in the guess's frame, as results.yaml
  gives them (expressInGuess()): the fixed correction stays 0 through the adjustment, so the fixed
  part ends at the guess's value (to the free parts' coupling through the start's rotation).
*/
Rigid withFixedPartsOfGuess(const vpKinematicChain &guess, const Rigid &measured, const std::vector<std::string> &fixed)
{
  if (fixed.empty())
    return measured;
  const std::vector<std::string> names = vpKinematicIdentification::matchParameters(guess, fixed, "fixed");
  const Rigid G = rigidFromPose(guess.get_eMc_pose());
  Rigid D = G.inverse() * measured;
  Eigen::Vector3d r = logSO3(D.R);
  const char *parts[] = {"eMc.tx", "eMc.ty", "eMc.tz", "eMc.rx", "eMc.ry", "eMc.rz"};
  bool any = false;
  for (int i = 0; i < 6; ++i) {
    if (std::find(names.begin(), names.end(), parts[i]) == names.end())
      continue;
    any = true;
    if (i < 3)
      D.t(i) = 0;
    else
      r(i - 3) = 0;
  }
  if (!any)
    return measured;
  D.R = expSO3(r);
  return G * D;
}

//! The dataset with the pinhole focal length f (mu and the principal point kept, the lens too).
vpSelfCalibDataset withFocal(const vpSelfCalibDataset &data, double f)
{
  vpSelfCalibDataset out = data;
  const double mu = data.cam.get_py() / data.cam.get_px();
  out.cam.initPersProjWithoutDistortion(f, mu * f, data.cam.get_u0(), data.cam.get_v0());
  if (data.cam.get_projModel() == vpCameraParameters::perspectiveProjWithDistortion)
    out.cam.initPersProjWithDistortion(f, mu * f, data.cam.get_u0(), data.cam.get_v0(), data.cam.get_kud(),
                                       data.cam.get_kdu());
  return out;
}

/*
  The focal length where the rays of the model's predicted camera poses meet best (predictedStart()),
  0 when they do not triangulate: the start when the data do not measure eMc.
*/
double focalFromModel(const vpKinematicChain &model, const std::vector<View> &cal, const vpSelfCalibDataset &data)
{
  std::vector<Rigid> fMc;
  const Rigid eMc = rigidFromVisp(model.get_eMc_corrected());
  for (const View &v : cal)
    fMc.push_back(rigidFromVisp(v.fMe) * eMc);
  const PredictedStart p = predictedStart(cal, fMc, lensOf(data), false);
  return p.ok ? p.fx : 0;
}

} // namespace

DataStart startFromData(const vpKinematicChain &nominal, const vpSelfCalibDataset &data, unsigned int N,
                        const vpRobotSelfCalibration::Options &opt)
{
  DataStart start{nominal, data, {}, std::string()};
  if (opt.method == vpRobotSelfCalibration::PAPER)
    return start;
  const bool focal_known = vpRobotSelfCalibration::resolveFocalMode(opt, data) == vpRobotSelfCalibration::FOCAL_KNOWN;
  const bool eye_to_hand = opt.bundle.controller_poses_inverted || opt.bundle.eye_to_hand;
  std::vector<View> cal(data.views.begin(), data.views.begin() + N);
  for (View &v : cal) {
    if (v.has_fMe && opt.method == vpRobotSelfCalibration::HAND_EYE)
      continue;
    if (!vpSelfCalib::allFinite(v.q))
      return start; // the data check says which joint
    // Eye-to-hand with joints: the camera (the hand-eye slot, bMc) seen from the effector frame.
    v.fMe = opt.bundle.eye_to_hand ? nominal.get_fMe(v.q).inverse() : nominal.get_fMe(v.q);
    v.has_fMe = true;
  }
  if (!allFinite(cal))
    return start;
  std::ostringstream os;
  if (eye_to_hand) {
    // Eye-to-hand: run() started bMc from the target; the focal length from the rays it predicts.
    const double f = focal_known ? 0 : focalFromModel(nominal, cal, data);
    if (f > 0)
      start.dataset = withFocal(data, f);
    return start;
  }
  const CameraModel lens = lensOf(data);
  // A known focal length: the pixels through the lens; a self-calibrated one: the lens is not known
  // yet, the pixels are taken as a pinhole camera's.
  const std::vector<View> pixels = focal_known ? undistorted(cal, lens) : cal;
  const double threshold = std::max(1.0, 3 * opt.noise.pixel_sd);
  // The known points, else the target's described layout (PnP), else the camera's motions.
  const std::map<int, vpColVector> &layout = opt.bundle.known_points.empty() ? opt.target_layout : opt.bundle.known_points;
  const MeasuredStart m = measuredStart(pixels, lens, data.width, layout, focal_known, threshold);
  if (m.has_eMc) {
    start.model = withNominalEMc(nominal, vpPoseVector(toVisp(withFixedPartsOfGuess(nominal, m.eMc, opt.bundle.fixed))));
    start.eMc_from_data = true;
    os << "eMc started from " << m.how;
  } else {
    os << "eMc started from the model's guess (" << m.how << ")";
    start.findings.push_back(vpSelfCalibDataCheck::Finding{
        vpSelfCalibDataCheck::WARNING, "emc-start-guess",
        "eMc could not be measured from the data (" + m.how +
            "): the run started from the model's eMc guess; if it is far off, give a closer one or more views that "
            "share points with each other"});
  }
  if (!focal_known) {
    const double f = m.has_fx ? m.fx : focalFromModel(start.model, cal, data);
    if (f > 0) {
      start.dataset = withFocal(data, f);
      os << std::setprecision(5) << "; f started at " << f << " px"
         << (m.has_fx ? " (where the camera's and the robot's motions agree best)"
                      : " (where the rays of the model's camera poses meet best)");
    }
  }
  start.message = os.str();
  return start;
}
} // namespace vpSelfCalibPipeline

namespace vpSelfCalibPipeline
{
void findGuessFar(const vpKinematicChain &guess, const vpRobotSelfCalibration::Options &opt, Result &res)
{
  const vpHomogeneousMatrix g = guess.get_eMc_corrected(), c = res.calibrated.get_eMc_corrected();
  const double dt = translationDistance(g, c), dr = rotationDistance(g, c);
  if (dt <= opt.tolerance_hand_eye_translation && dr <= opt.tolerance_hand_eye_rotation)
    return;
  std::ostringstream os;
  os << std::setprecision(3) << "the model's eMc guess is " << dt * 1000 << " mm and " << dr * 180 / M_PI
     << " deg from the calibrated one (tolerance " << opt.tolerance_hand_eye_translation * 1000 << " mm, "
     << opt.tolerance_hand_eye_rotation * 180 / M_PI
     << " deg); the run started from the eMc the data measure: correct the guess (the calibrated model has it)";
  res.findings.push_back(vpSelfCalibDataCheck::Finding{vpSelfCalibDataCheck::WARNING, "emc-guess-far", os.str()});
}
} // namespace vpSelfCalibPipeline

namespace vpSelfCalibPipeline
{
vpKinematicChain withNominalEMc(const vpKinematicChain &model, const vpPoseVector &eMc)
{
  vpKinematicChain out = model;
  out.set_eMc(eMc);
  vpColVector p = out.getParameters();
  for (unsigned int i = p.size() - vpKinematicChain::kBlockSize; i < p.size(); ++i)
    p[i] = 0;
  out.setParameters(p);
  return out;
}

void expressInGuess(const vpKinematicChain &guess, Result &res)
{
  const Rigid G = rigidFromPose(guess.get_eMc_pose()), S = rigidFromPose(res.calibrated.get_eMc_pose());
  const Rigid D = G.inverse() * rigidFromVisp(res.calibrated.get_eMc_corrected());
  const Eigen::Vector3d r = logSO3(D.R);
  const unsigned int first = res.calibrated.getNumParameters() - vpKinematicChain::kBlockSize;
  vpColVector p = res.calibrated.getParameters();
  // sd of the translation through d(D.t)/d(correction.t) = G.R^T S.R (correlations left out).
  const Eigen::Matrix3d M = G.R.transpose() * S.R;
  if (res.parameter_sd.size() == p.size()) {
    Eigen::Vector3d sd;
    for (int i = 0; i < 3; ++i)
      sd(i) = res.parameter_sd[first + static_cast<unsigned int>(i)];
    for (int i = 0; i < 3; ++i)
      res.parameter_sd[first + static_cast<unsigned int>(i)] = std::sqrt(M.row(i).cwiseAbs2().dot(sd.cwiseAbs2()));
  }
  for (unsigned int i = 0; i < 3; ++i) {
    p[first + i] = D.t(i);
    p[first + 3 + i] = r(i);
  }
  res.calibrated.set_eMc(guess.get_eMc_pose());
  res.calibrated.setParameters(p);
}
} // namespace vpSelfCalibPipeline
