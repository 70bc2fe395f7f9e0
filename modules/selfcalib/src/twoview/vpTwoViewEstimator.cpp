/*
 * ViSP SelfCalib: two-view pose measurement (paper Section 3.1).
 */
#include <visp3/selfcalib/vpFactorMethod.h>
#include <visp3/selfcalib/vpFocalFromFundamental.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpTwoViewEstimator.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include <Eigen/SVD>
#include <opencv2/calib3d.hpp>

#include "../core/vpSelfCalibGeometry.h"
#include "../core/vpSelfCalibMath.h"
#include "../core/vpSelfCalibRandom.h"
#include "../core/vpSelfCalibRange.h"

using namespace vpSelfCalib;

namespace
{
std::vector<Eigen::Vector2d> toEigen(const std::vector<vpImagePoint> &p)
{
  std::vector<Eigen::Vector2d> e;
  for (const vpImagePoint &x : p)
    e.emplace_back(x.get_u(), x.get_v());
  return e;
}

std::vector<cv::Point2d> toCv(const std::vector<vpImagePoint> &p)
{
  std::vector<cv::Point2d> out;
  for (const vpImagePoint &ip : p)
    out.emplace_back(ip.get_u(), ip.get_v());
  return out;
}

void select(const std::vector<vpImagePoint> &p1, const std::vector<vpImagePoint> &p2, const std::vector<bool> &mask,
            std::vector<vpImagePoint> &a, std::vector<vpImagePoint> &b)
{
  a.clear();
  b.clear();
  for (size_t i = 0; i < p1.size(); ++i)
    if (mask[i]) {
      a.push_back(p1[i]);
      b.push_back(p2[i]);
    }
}

/*
  Homography test. Returns true when H explains the F inliers; then sets pure_rotation and, for a
  rotation, R (nearest rotation to A^-1 H A scaled to unit determinant).
*/
bool homographyExplains(const std::vector<vpImagePoint> &p1, const std::vector<vpImagePoint> &p2,
                        unsigned int f_inliers, const vpTwoViewEstimator::Options &o, bool &pure_rotation,
                        Eigen::Matrix3d &R, std::vector<bool> &h_inliers)
{
  if (p1.size() < 8)
    return false;
  // Only a homography that keeps at least planar_ratio * f_inliers points matters. If one exists,
  // a 4-point sample is all-inlier with probability w^4, w = planar_ratio * f_inliers / n, so
  // log(1 - confidence) / log(1 - w^4) samples find it with the RANSAC confidence. On a general
  // scene no homography reaches that, and OpenCV's adaptive count would run to its maximum (2000
  // samples, about 13 ms for 80 points: most of the pair's time).
  int iterations = 2000;
  if (f_inliers > 0) {
    const double w = std::min(1.0, o.planar_ratio * f_inliers / static_cast<double>(p1.size()));
    const double w4 = w * w * w * w;
    if (w4 >= 1)
      iterations = 1;
    else
      iterations = static_cast<int>(std::min(2000.0, std::ceil(std::log(1 - o.ransac.confidence) / std::log(1 - w4))));
    iterations = std::max(iterations, 1);
  }
  Eigen::Matrix3d He;
  if (!fitHomography(toEigen(p1), toEigen(p2), o.ransac.inlier_threshold, iterations, o.ransac.confidence, He,
                     h_inliers))
    return false;
  const unsigned int nh = static_cast<unsigned int>(std::count(h_inliers.begin(), h_inliers.end(), true));
  // The homography explains the data when it keeps (nearly) as many points as the fundamental
  // matrix; with a plane the 8-point system is rank-deficient and F may not exist at all.
  if (nh < 8 || nh < o.planar_ratio * f_inliers)
    return false;
  const Eigen::Matrix3d A = toEigen3(vpFactorMethod::intrinsicMatrix(o.fx, o.u0, o.v0, o.mu));
  Eigen::Matrix3d M = A.inverse() * He * A;
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d s = svd.singularValues() / svd.singularValues()(1);
  pure_rotation = std::fabs(s(0) - 1) < o.rotation_tolerance && std::fabs(s(2) - 1) < o.rotation_tolerance;
  R = svd.matrixU() * svd.matrixV().transpose();
  if (R.determinant() < 0)
    R = -R;
  return true;
}

/*
  Planar scene, known intrinsics: the five-point solver (valid for planes), then the refinement with
  f fixed. Classic RANSAC, not USAC: OpenCV 4.6's USAC essential matrix on this planar scene returns a
  wrong pose (0.1-0.3 rad of rotation error on TwoView.PlanarSceneIsReported..., with or without
  local optimisation: its final least-squares polish of E on all inliers is rank-deficient on a
  plane), where the classic five-point RANSAC recovers it to 1e-6. So this call takes no seed: it is
  deterministic with OpenCV's fixed seed (the classic RANSAC draws from RNG((uint64)-1) created in
  each call, calib3d's ptsetreg.cpp) and thread-safe. False (message set) when the solver fails.
*/
bool fivePointPose(const std::vector<vpImagePoint> &a, const std::vector<vpImagePoint> &b,
                   const vpTwoViewEstimator::Options &o, vpTwoViewEstimator::Result &res)
{
  const cv::Mat K = (cv::Mat_<double>(3, 3) << o.fx, 0, o.u0, 0, o.mu * o.fx, o.v0, 0, 0, 1);
  cv::Mat mask, R, t;
  const cv::Mat E = cv::findEssentialMat(toCv(a), toCv(b), K, cv::RANSAC, o.ransac.confidence,
                                         o.ransac.inlier_threshold, mask);
  if (E.empty() || E.rows != 3 || cv::recoverPose(E(cv::Rect(0, 0, 3, 3)), toCv(a), toCv(b), K, R, t, mask) == 0) {
    res.message = "planar scene and the five-point solver failed";
    return false;
  }
  Rigid M;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j)
      M.R(i, j) = R.at<double>(i, j);
    M.t(i) = t.at<double>(i);
  }
  res.c2Mc1 = toVisp(M);
  res.fx = o.fx;
  res.message = "the scene is (nearly) planar: pose from the five-point solver with the known focal length";
  return true;
}

/*
  General scene: the focal length (given, or from F) and the factor method's pose. False (status
  FOCAL_UNOBSERVABLE) when F does not give the focal length.
*/
bool factorPose(const vpMatrix &F, const std::vector<vpImagePoint> &a, const std::vector<vpImagePoint> &b,
                const vpTwoViewEstimator::Options &o, bool known, vpTwoViewEstimator::Result &res)
{
  double f = o.fx;
  if (!known) {
    const vpFocalFromFundamental::Result fo =
        vpFocalFromFundamental::estimate(F, o.u0, o.v0, o.mu, o.fx, o.min_coplanarity);
    if (fo.status != vpFocalFromFundamental::OK) {
      // Report it, with the pose computed from the initial guess so that a caller can still use it
      // (for example as the start of a shared-focal estimate).
      const vpFactorMethod::Result fm = vpFactorMethod::estimate(F, o.fx, o.u0, o.v0, o.mu, a, b);
      res.c2Mc1 = fm.c2Mc1;
      res.fx = 0;
      res.status = vpTwoViewEstimator::FOCAL_UNOBSERVABLE;
      res.message = fo.message + "; the pose was computed with the initial guess fx = " + std::to_string(o.fx);
      return false;
    }
    f = fo.fx;
  }
  const vpFactorMethod::Result fm = vpFactorMethod::estimate(F, f, o.u0, o.v0, o.mu, a, b);
  res.c2Mc1 = fm.c2Mc1;
  res.fx = f;
  res.status = vpTwoViewEstimator::OK;
  res.message = "ok";
  return true;
}

/*
  The refined factor method from the pose found (f fixed when known); a focal length it does not
  determine is FOCAL_UNOBSERVABLE. False (status NO_CONVERGENCE) when it does not converge.
*/
bool refinePose(const std::vector<vpImagePoint> &a, const std::vector<vpImagePoint> &b,
                const vpTwoViewEstimator::Options &o, bool known, vpTwoViewEstimator::Result &res)
{
  vpRefinedFactorMethod::Options ro;
  ro.focal_mode = known ? vpRefinedFactorMethod::KNOWN : vpRefinedFactorMethod::PER_PAIR;
  ro.u0 = o.u0;
  ro.v0 = o.v0;
  ro.mu = o.mu;
  ro.huber = o.huber;
  vpRefinedFactorMethod::Pair pair{a, b, res.c2Mc1};
  const vpRefinedFactorMethod::Result rr = vpRefinedFactorMethod::refine({pair}, res.fx, ro);
  if (!rr.converged) {
    res.status = vpTwoViewEstimator::NO_CONVERGENCE;
    res.message = "refined factor method: " + rr.message;
    return false;
  }
  res.c2Mc1 = rr.c2Mc1[0];
  res.fx = rr.fx;
  res.fx_sd = rr.fx_sd;
  if (!known && !(res.fx_sd <= o.max_fx_relative_sd * res.fx)) {
    res.status = vpTwoViewEstimator::FOCAL_UNOBSERVABLE;
    std::ostringstream os;
    os << "f_x = " << res.fx << " px with standard deviation " << res.fx_sd
       << " px: this pair does not determine the focal length (optical axes nearly meet); "
          "use a known or shared focal length";
    res.message = os.str();
  }
  return true;
}
} // namespace

const char *vpTwoViewEstimator::statusName(Status s)
{
  switch (s) {
  case OK:
    return "ok";
  case TOO_FEW_POINTS:
    return "too few points";
  case PURE_ROTATION:
    return "pure rotation";
  case PLANAR:
    return "planar";
  case FOCAL_UNOBSERVABLE:
    return "focal unobservable";
  case NO_CONVERGENCE:
    return "no convergence";
  }
  return "?";
}

void vpTwoViewEstimator::Settings::check() const
{
  ransac.check();
  if (!(planar_ratio > 0 && planar_ratio <= 1) || !(min_coplanarity >= 0) || !(rotation_tolerance > 0) ||
      !(huber >= 0 && std::isfinite(huber)) || !(max_fx_relative_sd > 0))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpTwoViewEstimator: planar_ratio in (0, 1], min_coplanarity >= 0, "
                               "rotation_tolerance > 0, huber >= 0, max_fx_relative_sd > 0");
}

void vpTwoViewEstimator::Options::check() const
{
  if (focal_mode == vpRefinedFactorMethod::SHARED)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpTwoViewEstimator: use estimateShared() for a focal length shared by many pairs");
  if (!(std::isfinite(fx) && fx > 0 && std::isfinite(mu) && mu > 0 && std::isfinite(u0) && std::isfinite(v0)))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpTwoViewEstimator: fx and mu must be positive, u0 and v0 finite");
  vpSelfCalib::checkIntrinsics(fx, mu * fx, u0, v0, "vpTwoViewEstimator: the camera (fx, mu fx, u0, v0)");
  Settings::check();
}

vpTwoViewEstimator::Result vpTwoViewEstimator::estimate(const std::vector<vpImagePoint> &p1,
                                                        const std::vector<vpImagePoint> &p2, const Options &o)
{
  o.check();
  vpFundamentalMatrix::checkCorrespondences(p1, p2, "vpTwoViewEstimator::estimate");
  Result res;
  res.inliers.assign(p1.size(), false);
  const unsigned int distinct = vpFundamentalMatrix::countDistinct(p1, p2);
  if (distinct < 8) {
    res.status = TOO_FEW_POINTS;
    res.message = std::to_string(distinct) + " distinct correspondences; at least 8 are needed";
    return res;
  }
  const vpFundamentalMatrix::Result fr = vpFundamentalMatrix::estimate(p1, p2, o.ransac);
  const unsigned int nf = fr.status == vpFundamentalMatrix::OK ? fr.num_inliers : 0;
  const bool known = o.focal_mode == vpRefinedFactorMethod::KNOWN;
  std::vector<vpImagePoint> a, b;

  bool pure_rotation = false;
  Eigen::Matrix3d Rh;
  std::vector<bool> h_inliers;
  if (homographyExplains(p1, p2, nf, o, pure_rotation, Rh, h_inliers)) {
    res.inliers = h_inliers;
    res.num_inliers = static_cast<unsigned int>(std::count(h_inliers.begin(), h_inliers.end(), true));
    select(p1, p2, h_inliers, a, b);
    if (pure_rotation) {
      Rigid M;
      M.R = Rh;
      M.t.setZero();
      res.c2Mc1 = toVisp(M);
      res.fx = o.fx;
      res.status = PURE_ROTATION;
      res.message = "the two views differ by a pure rotation: no translation, no epipolar geometry";
      return res;
    }
    res.status = PLANAR;
    if (!known) {
      res.message = "the scene is (nearly) planar: a homography explains the correspondences; the focal length "
                    "cannot be self-calibrated from this pair (give it, or use a non-planar scene)";
      return res;
    }
    if (!fivePointPose(a, b, o, res))
      return res;
  } else {
    if (fr.status != vpFundamentalMatrix::OK) {
      res.status = TOO_FEW_POINTS;
      res.message = fr.message;
      return res;
    }
    res.F = fr.F;
    res.inliers = fr.inliers;
    res.num_inliers = fr.num_inliers;
    select(p1, p2, fr.inliers, a, b);
    if (!factorPose(fr.F, a, b, o, known, res))
      return res;
  }
  if (o.refine && !refinePose(a, b, o, known, res))
    return res;
  res.rms = vpRefinedFactorMethod::rmsSymmetricEpipolarDistance(res.c2Mc1, res.fx, o.u0, o.v0, o.mu, a, b);
  return res;
}

vpTwoViewEstimator::SharedResult vpTwoViewEstimator::estimateShared(const std::vector<std::vector<vpImagePoint>> &p1,
                                                                    const std::vector<std::vector<vpImagePoint>> &p2,
                                                                    const Options &options)
{
  options.check();
  if (p1.size() != p2.size() || p1.empty())
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               "vpTwoViewEstimator::estimateShared: expected the same, non-zero number of pairs");
  SharedResult out;
  // Per pair, without refinement: F, the closed-form focal and a first pose.
  Options per = options;
  per.refine = false;
  per.focal_mode = vpRefinedFactorMethod::PER_PAIR;
  std::vector<double> focals;
  for (size_t k = 0; k < p1.size(); ++k) {
    out.pairs.push_back(estimate(p1[k], p2[k], per));
    if (out.pairs.back().status == OK)
      focals.push_back(out.pairs.back().fx);
  }
  double f0 = options.fx;
  if (!focals.empty()) {
    std::nth_element(focals.begin(), focals.begin() + focals.size() / 2, focals.end());
    f0 = focals[focals.size() / 2];
  }
  // First poses with the common initial focal length (factor method), then the joint refinement.
  std::vector<vpRefinedFactorMethod::Pair> pairs;
  std::vector<size_t> used;
  for (size_t k = 0; k < p1.size(); ++k) {
    Result &r = out.pairs[k];
    if (r.status != OK && r.status != FOCAL_UNOBSERVABLE)
      continue;
    vpRefinedFactorMethod::Pair pr;
    select(p1[k], p2[k], r.inliers, pr.p1, pr.p2);
    pr.c2Mc1 = vpFactorMethod::estimate(r.F, f0, options.u0, options.v0, options.mu, pr.p1, pr.p2).c2Mc1;
    pairs.push_back(pr);
    used.push_back(k);
  }
  if (pairs.empty()) {
    out.message = "no pair could be initialized";
    return out;
  }
  vpRefinedFactorMethod::Options ro;
  ro.focal_mode = vpRefinedFactorMethod::SHARED;
  ro.u0 = options.u0;
  ro.v0 = options.v0;
  ro.mu = options.mu;
  ro.huber = options.huber;
  const vpRefinedFactorMethod::Result rr = vpRefinedFactorMethod::refine(pairs, f0, ro);
  out.converged = rr.converged;
  out.message = rr.message;
  out.fx = rr.fx;
  out.fx_sd = rr.fx_sd;
  for (size_t j = 0; j < used.size(); ++j) {
    Result &r = out.pairs[used[j]];
    r.c2Mc1 = rr.c2Mc1[j];
    r.fx = rr.fx;
    r.fx_sd = rr.fx_sd;
    r.rms = rr.rms[j];
    r.status = rr.converged ? OK : NO_CONVERGENCE;
    r.message = rr.converged ? "ok (shared focal length)" : "shared refinement: " + rr.message;
  }
  return out;
}
