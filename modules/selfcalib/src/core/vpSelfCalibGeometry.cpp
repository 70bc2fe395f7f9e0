/*
 * ViSP SelfCalib: the geometry every layer shares. See vpSelfCalibGeometry.h.
 */
#include "vpSelfCalibGeometry.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <ceres/tiny_solver.h>
#include <ceres/tiny_solver_autodiff_function.h>
#include <opencv2/calib3d.hpp>

#include "vpSelfCalibCeres.h"
#include "vpSelfCalibRandom.h"

namespace vpSelfCalib
{
namespace
{
//! Reprojection errors (px) of a point X (frame f) in the cameras cMf[i] that saw it at uv[i], for
//! TinySolver (the number of residuals known at run time).
struct PointReprojections {
  const CameraModel &camera;
  const std::vector<Rigid> &cMf;
  const std::vector<Eigen::Vector2d> &uv;
  int NumResiduals() const { return static_cast<int>(2 * uv.size()); }
  template <typename T> bool operator()(const T *X, T *r) const
  {
    T in[kMaxIntrinsics];
    for (int k = 0; k < camera.size(); ++k)
      in[k] = T(camera.intrinsics()[k]);
    for (size_t i = 0; i < uv.size(); ++i) {
      T Xc[3], p[2];
      for (int k = 0; k < 3; ++k)
        Xc[k] = T(cMf[i].R(k, 0)) * X[0] + T(cMf[i].R(k, 1)) * X[1] + T(cMf[i].R(k, 2)) * X[2] + T(cMf[i].t(k));
      projectPoint(camera.distortion(), in, Xc, p);
      r[2 * i] = p[0] - T(uv[i](0));
      r[2 * i + 1] = p[1] - T(uv[i](1));
    }
    return true;
  }
};

//! Reprojection errors (px) of points Xc (camera frame) seen at uv, the camera moved by (t, w):
//! Xc' = R(w) Xc + t.
struct CameraCorrection {
  const CameraModel &camera;
  const std::vector<Eigen::Vector3d> &Xc;
  const std::vector<Eigen::Vector2d> &uv;
  int NumResiduals() const { return static_cast<int>(2 * uv.size()); }
  template <typename T> bool operator()(const T *c, T *r) const
  {
    T in[kMaxIntrinsics];
    for (int k = 0; k < camera.size(); ++k)
      in[k] = T(camera.intrinsics()[k]);
    for (size_t i = 0; i < uv.size(); ++i) {
      const T X[3] = {T(Xc[i](0)), T(Xc[i](1)), T(Xc[i](2))};
      T Y[3], p[2];
      ceres::AngleAxisRotatePoint(c + 3, X, Y);
      for (int k = 0; k < 3; ++k)
        Y[k] += c[k];
      projectPoint(camera.distortion(), in, Y, p);
      r[2 * i] = p[0] - T(uv[i](0));
      r[2 * i + 1] = p[1] - T(uv[i](1));
    }
    return true;
  }
};
} // namespace

Ray rayThrough(const Rigid &fMc, const CameraModel &camera, const Eigen::Vector2d &uv)
{
  const Eigen::Vector2d xy = camera.unproject(uv);
  return {fMc.t, (fMc.R * Eigen::Vector3d(xy(0), xy(1), 1.0)).normalized()};
}

bool triangulateMidpoint(const std::vector<Ray> &rays, Eigen::Vector3d &X)
{
  if (rays.size() < 2)
    return false;
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (const Ray &r : rays) {
    const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - r.direction * r.direction.transpose();
    A += P;
    b += P * r.origin;
  }
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(A);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().cwiseAbs().minCoeff() > 1e-12 * A.trace()))
    return false;
  X = ldlt.solve(b);
  if (!X.allFinite())
    return false;
  for (const Ray &r : rays)
    if (!(r.direction.dot(X - r.origin) > 0))
      return false;
  return true;
}

void PointViews::add(const Rigid &fMc, const CameraModel &camera, const Eigen::Vector2d &pixel)
{
  uv.push_back(pixel);
  rays.push_back(rayThrough(fMc, camera, pixel));
  cMf.push_back(fMc.inverse());
}

namespace
{
// Triangulation::LINEAR_DLT (see there).
bool triangulateLinear(const CameraModel &camera, const PointViews &views, Eigen::Vector3d &X)
{
  if (views.cMf.size() != 2 || views.uv.size() != 2)
    return false;
  cv::Mat P[2];
  std::vector<cv::Point2d> x[2];
  for (int k = 0; k < 2; ++k) {
    P[k].create(3, 4, CV_64F);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c)
        P[k].at<double>(r, c) = views.cMf[static_cast<size_t>(k)].R(r, c);
      P[k].at<double>(r, 3) = views.cMf[static_cast<size_t>(k)].t(r);
    }
    const Eigen::Vector2d xy = camera.unproject(views.uv[static_cast<size_t>(k)]);
    x[k].emplace_back(xy(0), xy(1));
  }
  cv::Mat H;
  cv::triangulatePoints(P[0], P[1], x[0], x[1], H);
  const double w = H.at<double>(3, 0);
  X = Eigen::Vector3d(H.at<double>(0, 0), H.at<double>(1, 0), H.at<double>(2, 0)) / w;
  if (!X.allFinite())
    return false;
  for (const Rigid &cMf : views.cMf)
    if (!((cMf * X).z() > 0))
      return false;
  return true;
}
} // namespace

bool triangulate(const CameraModel &camera, const PointViews &views, Triangulation method, Eigen::Vector3d &X)
{
  switch (method) {
  case Triangulation::MIDPOINT:
    return triangulateMidpoint(views.rays, X);
  case Triangulation::MIDPOINT_REFINED:
    return triangulateMidpoint(views.rays, X) && refineTriangulation(camera, views.cMf, views.uv, X);
  case Triangulation::LINEAR_DLT:
    return triangulateLinear(camera, views, X);
  }
  return false;
}

/*
  Ceres' TinySolver (dense Levenberg-Marquardt, no problem or program to build) on the residuals
  of `Residuals` over N unknowns x, as solverOptions(50, true): converged to the last digits (the
  cost change is absolute here). False when the solve is not usable or x is not finite; sum_squares:
  the final sum of squared residuals (TinySolver's cost is half of it).
*/
template <class Residuals, int N>
bool solveTiny(const Residuals &residuals, Eigen::Matrix<double, N, 1> &x, double *sum_squares = nullptr)
{
  using Function = ceres::TinySolverAutoDiffFunction<Residuals, Eigen::Dynamic, N>;
  const Function f(residuals);
  ceres::TinySolver<Function> solver;
  solver.options.max_num_iterations = 50;
  solver.options.gradient_tolerance = 1e-14;
  solver.options.parameter_tolerance = 1e-14;
  solver.options.function_tolerance = 0;
  Eigen::Matrix<double, N, 1> y = x;
#pragma GCC diagnostic push // TinySolver's cost_ is set by its first evaluation, which cannot fail here
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
  solver.Solve(f, &y);
#pragma GCC diagnostic pop
  if (!y.allFinite() || !(solver.summary.final_cost <= solver.summary.initial_cost))
    return false;
  x = y;
  if (sum_squares)
    *sum_squares = 2 * solver.summary.final_cost;
  return true;
}

bool refineTriangulation(const CameraModel &camera, const std::vector<Rigid> &cMf,
                         const std::vector<Eigen::Vector2d> &uv, Eigen::Vector3d &X)
{
  if (cMf.size() != uv.size() || cMf.empty())
    return false;
  // Three unknowns and a few dozen residuals, solved for every point of every view set (tens of
  // thousands of times per calibration): TinySolver instead of a ceres::Solve per point.
  Eigen::Vector3d x = X;
  if (!solveTiny(PointReprojections{camera, cMf, uv}, x))
    return false;
  X = x;
  for (const Rigid &M : cMf)
    if (!inFront(M * X))
      return false;
  return true;
}

bool reposeCamera(const CameraModel &camera, const std::vector<Eigen::Vector3d> &Xc,
                  const std::vector<Eigen::Vector2d> &uv, Eigen::Matrix<double, 6, 1> &correction, double &cost)
{
  if (Xc.size() != uv.size() || uv.size() < 4)
    return false;
  Eigen::Matrix<double, 6, 1> c = Eigen::Matrix<double, 6, 1>::Zero();
  if (!solveTiny(CameraCorrection{camera, Xc, uv}, c, &cost))
    return false;
  correction = c;
  return true;
}

void relativePoseJacobian(const Rigid &A, const Eigen::MatrixXd &JA, const Rigid &B, const Eigen::MatrixXd &JB,
                          Eigen::MatrixXd &Jt, Eigen::MatrixXd &Jr)
{
  const Eigen::Matrix3d RAt = A.R.transpose();
  Jt = RAt * (JB.topRows(3) - JA.topRows(3) + skew(B.t - A.t) * JA.bottomRows(3));
  Jr = RAt * (JB.bottomRows(3) - JA.bottomRows(3));
}

bool fitHomography(const std::vector<Eigen::Vector2d> &a, const std::vector<Eigen::Vector2d> &b,
                   double ransac_threshold, int max_iterations, double confidence, Eigen::Matrix3d &H,
                   std::vector<bool> &inliers)
{
  if (a.size() != b.size() || a.size() < 4)
    return false;
  std::vector<cv::Point2d> ca, cb;
  for (size_t i = 0; i < a.size(); ++i) {
    ca.emplace_back(a[i](0), a[i](1));
    cb.emplace_back(b[i](0), b[i](1));
  }
  // Classic RANSAC, not USAC: see the header.
  cv::Mat mask, Hc;
  try {
    Hc = cv::findHomography(ca, cb, cv::RANSAC, ransac_threshold, mask, std::max(1, max_iterations), confidence);
  } catch (const cv::Exception &) {
    return false; // degenerate sample set: no model
  }
  if (Hc.empty() || mask.total() != a.size())
    return false;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      H(i, j) = Hc.at<double>(i, j);
  inliers.assign(a.size(), false);
  for (size_t i = 0; i < a.size(); ++i)
    inliers[i] = mask.at<uchar>(static_cast<int>(i)) != 0;
  return true;
}

std::vector<PlaneMotion> homographyMotions(const Eigen::Matrix3d &H, double fx, double u0, double v0, double mu,
                                           const std::vector<Eigen::Vector2d> &xa,
                                           const std::vector<Eigen::Vector2d> &xb)
{
  std::vector<PlaneMotion> out;
  const cv::Matx33d K(fx, 0, u0, 0, mu * fx, v0, 0, 0, 1);
  cv::Matx33d Hc;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      Hc(i, j) = H(i, j);
  std::vector<cv::Mat> Rs, ts, ns;
  std::vector<cv::Point2f> pa, pb;
  for (size_t i = 0; i < xa.size() && i < xb.size(); ++i) {
    pa.emplace_back(static_cast<float>(xa[i](0)), static_cast<float>(xa[i](1)));
    pb.emplace_back(static_cast<float>(xb[i](0)), static_cast<float>(xb[i](1)));
  }
  std::vector<int> visible;
  try {
    cv::decomposeHomographyMat(Hc, K, Rs, ts, ns);
    cv::filterHomographyDecompByVisibleRefpoints(Rs, ns, pa, pb, visible);
  } catch (const cv::Exception &) {
    return out; // a degenerate homography: no motion
  }
  for (int v : visible) {
    const size_t i = static_cast<size_t>(v);
    PlaneMotion m;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c)
        m.bMa.R(r, c) = Rs[i].at<double>(r, c);
      m.bMa.t(r) = ts[i].at<double>(r);
      m.normal(r) = ns[i].at<double>(r);
    }
    if (m.bMa.R.allFinite() && m.bMa.t.allFinite() && m.normal.allFinite() && m.normal.norm() > 0) {
      m.normal.normalize();
      out.push_back(m);
    }
  }
  return out;
}

bool fitPoseRansac(const std::vector<Eigen::Vector3d> &X, const std::vector<Eigen::Vector2d> &uv, double fx, double u0,
                   double v0, double mu, double threshold, int max_iterations, uint64_t seed, uint64_t stream,
                   Rigid &cMw, std::vector<int> &inliers)
{
  inliers.clear();
  if (X.size() != uv.size() || X.size() < 6)
    return false;
  std::vector<cv::Point3d> P3;
  std::vector<cv::Point2d> P2;
  for (size_t i = 0; i < X.size(); ++i) {
    P3.emplace_back(X[i](0), X[i](1), X[i](2));
    P2.emplace_back(uv[i](0), uv[i](1));
  }
  cv::UsacParams up;
  up.threshold = threshold;
  up.confidence = 0.999;
  up.maxIterations = std::max(1, max_iterations);
  up.randomGeneratorState = usacSeed(seed, stream);
  up.isParallel = false;
  cv::Mat K = (cv::Mat_<double>(3, 3) << fx, 0, u0, 0, mu * fx, v0, 0, 0, 1), rvec, tvec;
  bool ok = false;
  try {
    ok = cv::solvePnPRansac(P3, P2, K, cv::noArray(), rvec, tvec, inliers, up);
  } catch (const cv::Exception &) {
    ok = false;
  }
  if (!ok || rvec.total() != 3 || tvec.total() != 3)
    return false;
  rvec.convertTo(rvec, CV_64F);
  tvec.convertTo(tvec, CV_64F);
  const Eigen::Vector3d r(rvec.at<double>(0), rvec.at<double>(1), rvec.at<double>(2));
  cMw.R = expSO3(r);
  cMw.t = Eigen::Vector3d(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
  return cMw.R.allFinite() && cMw.t.allFinite();
}

bool marginalInformation(ceres::Problem &problem, const std::vector<double *> &kept,
                         const std::vector<double *> &eliminated, Eigen::MatrixXd &H, Eigen::VectorXd &own,
                         int *points_left_out)
{
  if (points_left_out)
    *points_left_out = 0;
  ceres::Problem::EvaluateOptions eo;
  eo.parameter_blocks = kept;
  eo.parameter_blocks.insert(eo.parameter_blocks.end(), eliminated.begin(), eliminated.end());
  eo.num_threads = 1;
  ceres::CRSMatrix J;
  if (!problem.Evaluate(eo, nullptr, nullptr, nullptr, &J))
    return false;
  const int nA = J.num_cols - 3 * static_cast<int>(eliminated.size());
  if (nA <= 0)
    return false;
  // Each row's eliminated point (or -1) and each point's 3 x 3 information; a row on two points is not this
  // problem's structure.
  std::vector<int> row_point(J.num_rows, -1);
  std::vector<Eigen::Matrix3d> C(eliminated.size(), Eigen::Matrix3d::Zero());
  for (int r = 0; r < J.num_rows; ++r) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (int k = J.rows[r]; k < J.rows[r + 1]; ++k) {
      const int c = J.cols[k];
      if (c < nA)
        continue;
      const int i = (c - nA) / 3;
      if (row_point[r] >= 0 && row_point[r] != i)
        return false;
      row_point[r] = i;
      p((c - nA) % 3) = J.values[k];
    }
    if (row_point[r] >= 0)
      C[row_point[r]] += p * p.transpose();
  }
  // A point its own observations do not determine (seen along one ray only, or so near a camera
  // or so far away that its information is rounding error: a 3 x 3 block with an eigenvalue below
  // 1e-12 of its largest) tells the kept parameters nothing reliable: it is left out with its rows.
  // (Exactly, its rows' information is J_a^T (I - P_p) J_a, P_p the projector on its Jacobian's
  // range; along a near-null direction that is the difference of two rounding errors.)
  std::vector<char> determined(eliminated.size(), 1);
  std::vector<Eigen::Matrix3d> L(eliminated.size(), Eigen::Matrix3d::Zero()); // L L^T = C^-1
  for (size_t i = 0; i < C.size(); ++i) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> e(C[i]);
    const Eigen::Vector3d ev = e.eigenvalues(); // increasing
    determined[i] = e.info() == Eigen::Success && ev(2) > 0 && std::isfinite(ev(2)) && ev(0) > 1e-12 * ev(2);
    if (determined[i])
      L[i] = e.eigenvectors() * ev.cwiseSqrt().cwiseInverse().asDiagonal();
    else if (points_left_out)
      ++*points_left_out;
  }
  // Normal equations [H B; B^T C] over the rows kept: H over the kept blocks, B per eliminated point.
  H = Eigen::MatrixXd::Zero(nA, nA);
  std::vector<Eigen::Matrix<double, Eigen::Dynamic, 3>> B(eliminated.size(),
                                                          Eigen::Matrix<double, Eigen::Dynamic, 3>::Zero(nA, 3));
  std::vector<std::pair<int, double>> a;
  for (int r = 0; r < J.num_rows; ++r) {
    const int point = row_point[r];
    if (point >= 0 && !determined[point])
      continue;
    a.clear();
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (int k = J.rows[r]; k < J.rows[r + 1]; ++k) {
      const int c = J.cols[k];
      if (c < nA)
        a.push_back({c, J.values[k]});
      else
        p((c - nA) % 3) = J.values[k];
    }
    for (const auto &x : a)
      for (const auto &y : a)
        H(x.first, y.first) += x.second * y.second;
    if (point >= 0)
      for (const auto &x : a)
        B[point].row(x.first) += x.second * p.transpose();
  }
  // The kept parameters' own information, before the points are marginalized: the scale of the test
  // below. Scaling by the complement's diagonal instead would blow a direction the points take all
  // the information from (its diagonal is then pure cancellation) up to order 1.
  own = H.diagonal();
  // The points' Schur complements B_i C_i^-1 B_i^T in one symmetric rank update, H -= S S^T with
  // S = [B_i L_i]: one product instead of one per point (with a per-view
  // robot correction the kept blocks number hundreds, and a product per point dominated the run).
  std::vector<size_t> used;
  for (size_t i = 0; i < C.size(); ++i)
    if (determined[i])
      used.push_back(i);
  Eigen::MatrixXd S(nA, 3 * static_cast<Eigen::Index>(used.size()));
  for (size_t u = 0; u < used.size(); ++u)
    S.middleCols<3>(3 * static_cast<Eigen::Index>(u)) = B[used[u]] * L[used[u]];
  H.selfadjointView<Eigen::Lower>().rankUpdate(S, -1.0);
  H.triangularView<Eigen::StrictlyUpper>() = H.transpose();
  return true;
}

bool marginalCovariance(ceres::Problem &problem, const std::vector<double *> &kept,
                        const std::vector<double *> &eliminated, Eigen::MatrixXd &cov, Eigen::MatrixXd *undetermined,
                        int *points_left_out)
{
  Eigen::MatrixXd H;
  Eigen::VectorXd d;
  if (!marginalInformation(problem, kept, eliminated, H, d, points_left_out))
    return false;
  if (!(d.minCoeff() > 0)) {
    if (undetermined) {
      Eigen::Index i = 0;
      d.minCoeff(&i);
      *undetermined = Eigen::VectorXd::Unit(d.size(), i);
    }
    return false;
  }
  const Eigen::VectorXd scale = d.cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd Hs = scale.asDiagonal() * H * scale.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (Hs + Hs.transpose()));
  // Hs's eigenvalues are the fractions of the parameters' own information left once the points are
  // marginalized (at most the number of parameters); a direction the data do not determine keeps only
  // rounding errors, far below 1e-10.
  if (eig.info() != Eigen::Success || !(eig.eigenvalues().minCoeff() > 1e-10)) {
    if (undetermined && eig.info() == Eigen::Success) {
      Eigen::Index k = 0; // eigenvalues in increasing order
      while (k < eig.eigenvalues().size() && !(eig.eigenvalues()(k) > 1e-10))
        ++k;
      *undetermined = eig.eigenvectors().leftCols(std::max<Eigen::Index>(k, 1));
    }
    return false;
  }
  cov = scale.asDiagonal() *
        (eig.eigenvectors() * eig.eigenvalues().cwiseInverse().asDiagonal() * eig.eigenvectors().transpose()) *
        scale.asDiagonal();
  return cov.allFinite();
}

ceres::LossFunction *makeLoss(RobustLoss loss, double scale)
{
  switch (loss) {
  case RobustLoss::HUBER:
    return new ceres::HuberLoss(scale);
  case RobustLoss::CAUCHY:
    return new ceres::CauchyLoss(scale);
  default:
    return nullptr;
  }
}
} // namespace vpSelfCalib
