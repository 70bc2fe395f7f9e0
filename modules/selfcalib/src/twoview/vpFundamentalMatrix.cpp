/*
 * ViSP SelfCalib: normalized 8-point fundamental matrix and its RANSAC estimator.
 */
#include <visp3/selfcalib/vpFundamentalMatrix.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/SVD>

#include <opencv2/calib3d.hpp>

#include "../core/vpSelfCalibMath.h"
#include "../core/vpSelfCalibRansac.h"

using namespace vpSelfCalib;

namespace
{
// Hartley normalization: centroid to the origin, mean distance sqrt(2). False if all points coincide.
bool normalization(const std::vector<vpImagePoint> &p, Eigen::Matrix3d &T)
{
  double cu = 0, cv = 0;
  for (const vpImagePoint &ip : p) {
    cu += ip.get_u();
    cv += ip.get_v();
  }
  cu /= p.size();
  cv /= p.size();
  double d = 0;
  for (const vpImagePoint &ip : p)
    d += std::hypot(ip.get_u() - cu, ip.get_v() - cv);
  d /= p.size();
  if (!(d > 1e-9))
    return false;
  const double s = std::sqrt(2.0) / d;
  T << s, 0, -s * cu, 0, s, -s * cv, 0, 0, 1;
  return true;
}

//! The pixels as OpenCV's float points.
std::vector<cv::Point2f> toCvPoints(const std::vector<vpImagePoint> &p)
{
  std::vector<cv::Point2f> out;
  out.reserve(p.size());
  for (const vpImagePoint &ip : p)
    out.emplace_back(static_cast<float>(ip.get_u()), static_cast<float>(ip.get_v()));
  return out;
}

//! A 3 x 3 OpenCV matrix of doubles as a vpMatrix; false when it is not 3 x 3.
bool fromCvMatrix(const cv::Mat &M, vpMatrix &F)
{
  if (M.rows != 3 || M.cols != 3)
    return false;
  F.resize(3, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x)
      F[static_cast<unsigned int>(y)][static_cast<unsigned int>(x)] = M.at<double>(y, x);
  return true;
}

//! estimate() with Method USAC_MSAC (see there).
vpFundamentalMatrix::Result estimateUsac(const std::vector<vpImagePoint> &p1, const std::vector<vpImagePoint> &p2,
                                         const vpFundamentalMatrix::Options &opt)
{
  vpFundamentalMatrix::Result res;
  res.inliers.assign(p1.size(), false);
  if (p1.size() < 8) {
    res.status = vpFundamentalMatrix::TOO_FEW_POINTS;
    res.message = std::to_string(p1.size()) + " correspondences; USAC needs 8";
    return res;
  }
  cv::UsacParams p;
  p.threshold = opt.inlier_threshold;
  p.confidence = opt.confidence;
  p.maxIterations = static_cast<int>(opt.max_iterations);
  p.randomGeneratorState = static_cast<int>(opt.seed & 0x7fffffffULL);
  p.isParallel = false;
  std::vector<unsigned char> inl;
  cv::Mat Fcv;
  try {
    Fcv = cv::findFundamentalMat(toCvPoints(p1), toCvPoints(p2), inl, p);
  } catch (const cv::Exception &) {
    Fcv = cv::Mat(); // a degenerate configuration: no model
  }
  if (Fcv.empty() || inl.size() != p1.size() || !fromCvMatrix(Fcv, res.F)) {
    res.status = vpFundamentalMatrix::DEGENERATE;
    res.message = "USAC found no fundamental matrix";
    return res;
  }
  double ss = 0;
  for (size_t i = 0; i < p1.size(); ++i)
    if (inl[i]) {
      res.inliers[i] = true;
      ++res.num_inliers;
      const double d = vpFundamentalMatrix::sampsonDistance(res.F, p1[i], p2[i]);
      ss += d * d;
    }
  res.rms_sampson = std::sqrt(ss / std::max(1u, res.num_inliers));
  res.status = vpFundamentalMatrix::OK;
  res.message = "ok";
  return res;
}
} // namespace

void vpFundamentalMatrix::Options::check() const
{
  if (!(std::isfinite(inlier_threshold) && inlier_threshold > 0))
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpFundamentalMatrix: inlier_threshold must be > 0");
  if (!(confidence > 0 && confidence < 1))
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpFundamentalMatrix: confidence must be in (0, 1)");
  if (method != RANSAC_8POINT && method != USAC_MSAC)
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpFundamentalMatrix: unknown method");
  if (max_iterations < 1)
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpFundamentalMatrix: max_iterations must be >= 1");
}

void vpFundamentalMatrix::checkCorrespondences(const std::vector<vpImagePoint> &p1, const std::vector<vpImagePoint> &p2,
                                               const char *where)
{
  if (p1.size() != p2.size())
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               std::string(where) + ": the two point lists differ in size (" +
                                   std::to_string(p1.size()) + " and " + std::to_string(p2.size()) + ")");
  for (size_t i = 0; i < p1.size(); ++i)
    if (!std::isfinite(p1[i].get_u()) || !std::isfinite(p1[i].get_v()) || !std::isfinite(p2[i].get_u()) ||
        !std::isfinite(p2[i].get_v()))
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 std::string(where) + ": correspondence " + std::to_string(i) +
                                     " has a non-finite pixel coordinate");
}

unsigned int vpFundamentalMatrix::countDistinct(const std::vector<vpImagePoint> &p1, const std::vector<vpImagePoint> &p2)
{
  unsigned int n = 0;
  for (size_t i = 0; i < p1.size(); ++i) {
    bool dup = false;
    for (size_t j = 0; j < i && !dup; ++j)
      dup = (std::hypot(p1[i].get_u() - p1[j].get_u(), p1[i].get_v() - p1[j].get_v()) < 1e-9) ||
            (std::hypot(p2[i].get_u() - p2[j].get_u(), p2[i].get_v() - p2[j].get_v()) < 1e-9);
    n += !dup;
  }
  return n;
}

bool vpFundamentalMatrix::eightPoint(const std::vector<vpImagePoint> &p1, const std::vector<vpImagePoint> &p2,
                                     vpMatrix &F)
{
  if (p1.size() < 8 || p1.size() != p2.size())
    return false;
  Eigen::Matrix3d T1, T2;
  if (!normalization(p1, T1) || !normalization(p2, T2))
    return false;
  // Each row: m2^T F m1 = 0 as a linear form in the 9 entries of F (row-major).
  Eigen::Matrix<double, Eigen::Dynamic, 9> A(p1.size(), 9);
  for (size_t i = 0; i < p1.size(); ++i) {
    const Eigen::Vector3d a = T1 * Eigen::Vector3d(p1[i].get_u(), p1[i].get_v(), 1);
    const Eigen::Vector3d b = T2 * Eigen::Vector3d(p2[i].get_u(), p2[i].get_v(), 1);
    A.row(i) << b(0) * a(0), b(0) * a(1), b(0), b(1) * a(0), b(1) * a(1), b(1), a(0), a(1), 1;
  }
  Eigen::JacobiSVD<Eigen::Matrix<double, Eigen::Dynamic, 9>> svd(A, Eigen::ComputeFullV);
  // The null space must be one-dimensional: the 8th singular value clearly above zero.
  const Eigen::VectorXd sv = svd.singularValues();
  if (sv.size() < 8 || !(sv(7) > 1e-10 * sv(0)))
    return false;
  const Eigen::Matrix<double, 9, 1> f = svd.matrixV().col(8);
  Eigen::Matrix3d Fn;
  Fn << f(0), f(1), f(2), f(3), f(4), f(5), f(6), f(7), f(8);
  // Rank 2: zero the smallest singular value.
  Eigen::JacobiSVD<Eigen::Matrix3d> s3(Fn, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Vector3d d = s3.singularValues();
  d(2) = 0;
  Fn = s3.matrixU() * d.asDiagonal() * s3.matrixV().transpose();
  Eigen::Matrix3d Fp = T2.transpose() * Fn * T1;
  const double norm = Fp.norm();
  if (!(norm > 0) || !Fp.allFinite())
    return false;
  Fp /= norm;
  // Fix the sign so that results are reproducible: largest entry positive.
  Eigen::Index r, c;
  Fp.cwiseAbs().maxCoeff(&r, &c);
  if (Fp(r, c) < 0)
    Fp = -Fp;
  F = toVispMatrix(Fp);
  return true;
}

bool vpFundamentalMatrix::eightPointOpenCV(const std::vector<vpImagePoint> &p1, const std::vector<vpImagePoint> &p2,
                                           vpMatrix &F)
{
  if (p1.size() < 8 || p1.size() != p2.size())
    return false;
  cv::Mat Fcv;
  try {
    Fcv = cv::findFundamentalMat(toCvPoints(p1), toCvPoints(p2), cv::FM_8POINT);
  } catch (const cv::Exception &) {
    return false;
  }
  return fromCvMatrix(Fcv, F);
}

double vpFundamentalMatrix::sampsonDistance(const vpMatrix &F, const vpImagePoint &p1, const vpImagePoint &p2)
{
  const Eigen::Matrix3d E = toEigen3(F);
  const Eigen::Vector3d a(p1.get_u(), p1.get_v(), 1), b(p2.get_u(), p2.get_v(), 1);
  const Eigen::Vector3d Fa = E * a, Ftb = E.transpose() * b;
  const double e = b.dot(Fa);
  const double den = Fa(0) * Fa(0) + Fa(1) * Fa(1) + Ftb(0) * Ftb(0) + Ftb(1) * Ftb(1);
  return den > 0 ? std::fabs(e) / std::sqrt(den) : std::numeric_limits<double>::infinity();
}

vpFundamentalMatrix::Result vpFundamentalMatrix::estimate(const std::vector<vpImagePoint> &p1,
                                                          const std::vector<vpImagePoint> &p2, const Options &opt)
{
  opt.check();
  checkCorrespondences(p1, p2, "vpFundamentalMatrix::estimate");
  if (opt.method == USAC_MSAC)
    return estimateUsac(p1, p2, opt);
  Result res;
  res.inliers.assign(p1.size(), false);
  const unsigned int distinct = countDistinct(p1, p2);
  if (distinct < 8) {
    res.status = TOO_FEW_POINTS;
    res.message = std::to_string(distinct) + " distinct correspondences; the 8-point algorithm needs 8";
    return res;
  }
  Random rng(opt.seed, 0xF);
  const auto fit = [&](const std::vector<unsigned int> &idx, vpMatrix &F) {
    std::vector<vpImagePoint> a, b;
    for (unsigned int i : idx) {
      a.push_back(p1[i]);
      b.push_back(p2[i]);
    }
    return eightPoint(a, b, F);
  };
  const auto inlier = [&](const vpMatrix &F, unsigned int i) {
    return sampsonDistance(F, p1[i], p2[i]) < opt.inlier_threshold;
  };
  RansacResult<vpMatrix> r = ransac<vpMatrix>(static_cast<unsigned int>(p1.size()), 8, fit, inlier, opt.confidence,
                                              opt.max_iterations, rng);
  res.iterations = r.iterations;
  if (!r.found || r.num_inliers < 8) {
    res.status = DEGENERATE;
    res.message = "RANSAC found no fundamental matrix supported by 8 correspondences";
    return res;
  }
  // Re-estimate on all inliers, twice (the inlier set can grow with the better model).
  vpMatrix F = r.model;
  std::vector<bool> mask = r.inliers;
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<unsigned int> idx;
    for (unsigned int i = 0; i < p1.size(); ++i)
      if (mask[i])
        idx.push_back(i);
    vpMatrix Fr;
    if (!fit(idx, Fr))
      break;
    std::vector<bool> m2(p1.size());
    unsigned int n2 = 0;
    for (unsigned int i = 0; i < p1.size(); ++i)
      n2 += (m2[i] = inlier(Fr, i));
    if (n2 < 8)
      break;
    F = Fr;
    mask = m2;
  }
  res.F = F;
  res.inliers = mask;
  double ss = 0;
  for (unsigned int i = 0; i < p1.size(); ++i)
    if (mask[i]) {
      ++res.num_inliers;
      const double d = sampsonDistance(F, p1[i], p2[i]);
      ss += d * d;
    }
  res.rms_sampson = std::sqrt(ss / std::max(1u, res.num_inliers));
  res.status = OK;
  res.message = "ok";
  return res;
}
