/*
 * Tests of the module's one camera model and shared geometry (core layer).
 */
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <ceres/ceres.h>
#include <opencv2/calib3d.hpp>
#include <visp3/core/vpMeterPixelConversion.h>
#include <visp3/core/vpPixelMeterConversion.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include "core/vpSelfCalibCamera.h"
#include "core/vpSelfCalibGeometry.h"
#include "core/vpSelfCalibMath.h"
#include "core/vpSelfCalibRandom.h"

using namespace vpSelfCalib;

namespace
{
CameraModel opencvCamera()
{
  // A wide lens with every OpenCV coefficient non-zero.
  const double in[9] = {541.3, 1.0028, 322.6, 215.2, 0.02, 0.109, 1.5e-3, -2e-3, -0.05};
  return CameraModel(Distortion::OPENCV, in);
}
CameraModel vispCamera()
{
  const double in[5] = {600, 1.01, 330, 238, 0.2};
  return CameraModel(Distortion::VISP, in);
}
//! A linear residual over a 2-vector k and a 3-vector p (the marginal covariance test).
struct LinearCost {
  double a[5], y;
  template <typename T> bool operator()(const T *k, const T *p, T *r) const
  {
    r[0] = T(a[0]) * k[0] + T(a[1]) * k[1] + T(a[2]) * p[0] + T(a[3]) * p[1] + T(a[4]) * p[2] - T(y);
    return true;
  }
};
std::vector<Eigen::Vector3d> pointsInView(uint64_t seed)
{
  Random rng(seed, 0);
  std::vector<Eigen::Vector3d> X;
  for (int i = 0; i < 50; ++i)
    X.emplace_back(rng.uniform(-0.35, 0.35), rng.uniform(-0.3, 0.3), rng.uniform(0.5, 1.5));
  return X;
}
} // namespace

// The VISP model is ViSP's own perspectiveProjWithDistortion (meter -> pixel).
TEST(Camera, VispModelMatchesViSP)
{
  const CameraModel cam = vispCamera();
  const vpCameraParameters vc = cam.toVisp();
  for (const Eigen::Vector3d &X : pointsInView(1)) {
    double u, v;
    vpMeterPixelConversion::convertPoint(vc, X(0) / X(2), X(1) / X(2), u, v);
    const Eigen::Vector2d uv = cam.project(X);
    EXPECT_NEAR(uv(0), u, 1e-9);
    EXPECT_NEAR(uv(1), v, 1e-9);
  }
  const CameraModel back = CameraModel::fromVisp(vc);
  EXPECT_EQ(back.distortion(), Distortion::VISP);
  for (int i = 0; i < 5; ++i)
    EXPECT_NEAR(back.intrinsics()[i], cam.intrinsics()[i], 1e-12);
}

// The OPENCV model is cv::projectPoints' with (k1, k2, p1, p2, k3).
TEST(Camera, OpencvModelMatchesOpenCV)
{
  const CameraModel cam = opencvCamera();
  const double *in = cam.intrinsics();
  const cv::Matx33d K(in[0], 0, in[2], 0, in[1] * in[0], in[3], 0, 0, 1);
  const std::vector<double> dist = {in[4], in[5], in[6], in[7], in[8]};
  std::vector<cv::Point3d> P;
  const std::vector<Eigen::Vector3d> X = pointsInView(2);
  for (const auto &x : X)
    P.emplace_back(x(0), x(1), x(2));
  std::vector<cv::Point2d> p;
  cv::projectPoints(P, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, dist, p);
  for (size_t i = 0; i < X.size(); ++i) {
    const Eigen::Vector2d uv = cam.project(X[i]);
    EXPECT_NEAR(uv(0), p[i].x, 1e-9);
    EXPECT_NEAR(uv(1), p[i].y, 1e-9);
  }
  EXPECT_THROW(cam.toVisp(), vpSelfCalibException);
}

// Analytic Jacobians against central differences, every model.
TEST(Camera, JacobiansMatchFiniteDifferences)
{
  const double pin[4] = {800, 0.98, 310, 250};
  for (const CameraModel &cam : {CameraModel(Distortion::NONE, pin), vispCamera(), opencvCamera()}) {
    const int n = cam.size();
    for (const Eigen::Vector3d &X : pointsInView(3)) {
      Eigen::Vector2d uv;
      Eigen::Matrix<double, 2, 3> JX;
      std::vector<double> Jin(2 * n);
      ASSERT_TRUE(cam.project(X, uv, &JX, Jin.data()));
      for (int c = 0; c < 3; ++c) {
        const double h = 1e-6;
        Eigen::Vector3d a = X, b = X;
        a(c) += h;
        b(c) -= h;
        const Eigen::Vector2d d = (cam.project(a) - cam.project(b)) / (2 * h);
        EXPECT_NEAR(JX(0, c), d(0), 1e-5 * (1 + std::fabs(d(0))));
        EXPECT_NEAR(JX(1, c), d(1), 1e-5 * (1 + std::fabs(d(1))));
      }
      for (int c = 0; c < n; ++c) {
        const double h = 1e-6 * std::max(1.0, std::fabs(cam.intrinsics()[c]));
        CameraModel a = cam, b = cam;
        a.intrinsics()[c] += h;
        b.intrinsics()[c] -= h;
        const Eigen::Vector2d d = (a.project(X) - b.project(X)) / (2 * h);
        EXPECT_NEAR(Jin[c], d(0), 1e-5 * (1 + std::fabs(d(0))));
        EXPECT_NEAR(Jin[n + c], d(1), 1e-5 * (1 + std::fabs(d(1))));
      }
    }
  }
}

// Unprojection inverts projection, distortion included; a point behind the camera is refused.
TEST(Camera, UnprojectInvertsProjectAndCheiralityHolds)
{
  for (const CameraModel &cam : {vispCamera(), opencvCamera()}) {
    for (const Eigen::Vector3d &X : pointsInView(4)) {
      Eigen::Vector2d xy;
      ASSERT_TRUE(cam.unproject(cam.project(X), xy));
      EXPECT_NEAR(xy(0), X(0) / X(2), 1e-12);
      EXPECT_NEAR(xy(1), X(1) / X(2), 1e-12);
      EXPECT_NEAR((cam.ray(cam.project(X)) - X.normalized()).norm(), 0, 1e-12);
    }
    Eigen::Vector2d uv;
    EXPECT_FALSE(cam.project(Eigen::Vector3d(0.1, 0.1, -1), uv, nullptr, nullptr));
  }
}

// Multi-ray triangulation: exact on exact rays, through a distorted camera; a point behind a
// camera or parallel rays are refused.
TEST(Geometry, TriangulationExactWithDistortionAndCheirality)
{
  const CameraModel cam = opencvCamera();
  Random rng(5, 0);
  std::vector<Rigid> fMc;
  for (int k = 0; k < 4; ++k) {
    double v[6] = {rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2), rng.uniform(-0.1, 0.1),
                   rng.uniform(-0.1, 0.1), rng.uniform(-0.1, 0.1), rng.uniform(-0.1, 0.1)};
    fMc.push_back(rigidFromVector(v));
  }
  for (const Eigen::Vector3d &Xf : pointsInView(6)) {
    std::vector<Ray> rays;
    std::vector<Rigid> cMf;
    std::vector<Eigen::Vector2d> uv;
    for (const Rigid &M : fMc) {
      cMf.push_back(M.inverse());
      uv.push_back(cam.project(cMf.back() * Xf));
      rays.push_back(rayThrough(M, cam, uv.back()));
    }
    Eigen::Vector3d X;
    ASSERT_TRUE(triangulateMidpoint(rays, X));
    EXPECT_LT((X - Xf).norm(), 1e-9);
    X += Eigen::Vector3d(0.01, -0.02, 0.03);
    ASSERT_TRUE(refineTriangulation(cam, cMf, uv, X));
    EXPECT_LT((X - Xf).norm(), 1e-9);
    // The same rays pointing away: the point would be behind every camera.
    for (Ray &r : rays)
      r.direction = -r.direction;
    EXPECT_FALSE(triangulateMidpoint(rays, X));
  }
  const std::vector<Ray> parallel = {{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 0, 1)},
                                     {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 0, 1)}};
  Eigen::Vector3d X;
  EXPECT_FALSE(triangulateMidpoint(parallel, X));
  EXPECT_FALSE(triangulateMidpoint({parallel[0]}, X));
}

// One camera re-posed on its observations alone: a displacement of a few mm and mrad (the order of
// a robot's pose error) recovered exactly through a distorted camera; fewer than 4 observations
// are refused.
TEST(Geometry, ReposeCameraRecoversTheDisplacement)
{
  const CameraModel cam = opencvCamera();
  const double d[6] = {2e-3, -1e-3, 3e-3, 5e-3, -3e-3, 2e-3};
  const Rigid M = rigidFromVector(d);
  std::vector<Eigen::Vector3d> Xc = pointsInView(20);
  std::vector<Eigen::Vector2d> uv;
  for (const Eigen::Vector3d &X : Xc)
    uv.push_back(cam.project(M * X));
  Eigen::Matrix<double, 6, 1> c;
  double cost = -1;
  ASSERT_TRUE(reposeCamera(cam, Xc, uv, c, cost));
  for (int i = 0; i < 6; ++i)
    EXPECT_NEAR(c(i), d[i], 1e-9) << i;
  EXPECT_LT(cost, 1e-16);
  // Unmoved: nothing to correct.
  std::vector<Eigen::Vector2d> still;
  for (const Eigen::Vector3d &X : Xc)
    still.push_back(cam.project(X));
  ASSERT_TRUE(reposeCamera(cam, Xc, still, c, cost));
  EXPECT_LT(c.norm(), 1e-12);
  Xc.resize(3);
  uv.resize(3);
  EXPECT_FALSE(reposeCamera(cam, Xc, uv, c, cost));
}

// The relative-pose Jacobian against finite differences of A(rho)^-1 B(rho).
TEST(Geometry, RelativePoseJacobianMatchesFiniteDifferences)
{
  Random rng(7, 0);
  const int P = 5;
  Eigen::MatrixXd JA = Eigen::MatrixXd::Zero(6, P), JB = Eigen::MatrixXd::Zero(6, P);
  for (int i = 0; i < 6; ++i)
    for (int c = 0; c < P; ++c) {
      JA(i, c) = rng.uniform(-1, 1);
      JB(i, c) = rng.uniform(-1, 1);
    }
  double va[6] = {0.3, -0.1, 0.5, 0.2, -0.4, 0.1}, vb[6] = {-0.2, 0.4, 0.7, -0.3, 0.1, 0.5};
  const Rigid A = rigidFromVector(va), B = rigidFromVector(vb);
  // Absolute poses moved as getJacobian describes: t + J_t d, exp([J_phi d]x) R.
  auto moved = [](const Rigid &M, const Eigen::MatrixXd &J, const Eigen::VectorXd &d) {
    Rigid r;
    r.t = M.t + J.topRows(3) * d;
    r.R = expSO3(J.bottomRows(3) * d) * M.R;
    return r;
  };
  Eigen::MatrixXd Jt, Jr;
  relativePoseJacobian(A, JA, B, JB, Jt, Jr);
  const Rigid rel0 = A.inverse() * B;
  for (int c = 0; c < P; ++c) {
    const double h = 1e-6;
    Eigen::VectorXd d = Eigen::VectorXd::Zero(P);
    d(c) = h;
    const Rigid plus = moved(A, JA, d).inverse() * moved(B, JB, d);
    const Rigid minus = moved(A, JA, -d).inverse() * moved(B, JB, -d);
    const Eigen::Vector3d dt = (plus.t - minus.t) / (2 * h);
    const Eigen::Vector3d dphi = (logSO3(plus.R * rel0.R.transpose()) - logSO3(minus.R * rel0.R.transpose())) / (2 * h);
    EXPECT_LT((Jt.col(c) - dt).norm(), 1e-6);
    EXPECT_LT((Jr.col(c) - dphi).norm(), 1e-6);
  }
}

// The marginal covariance equals the inverse of the full information's kept block.
TEST(Geometry, MarginalCovarianceIsTheInverseOfTheFullInformation)
{
  Random rng(9, 0);
  double k[2] = {0, 0};
  std::vector<Eigen::Vector3d> pts(4, Eigen::Vector3d::Zero());
  ceres::Problem problem;
  Eigen::MatrixXd Jfull = Eigen::MatrixXd::Zero(40, 2 + 12);
  for (int r = 0; r < 40; ++r) {
    LinearCost c;
    for (double &x : c.a)
      x = rng.uniform(-1, 1);
    c.y = rng.uniform(-1, 1);
    const int i = r % 4;
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<LinearCost, 1, 2, 3>(new LinearCost(c)), nullptr, k, pts[i].data());
    Jfull(r, 0) = c.a[0];
    Jfull(r, 1) = c.a[1];
    for (int j = 0; j < 3; ++j)
      Jfull(r, 2 + 3 * i + j) = c.a[2 + j];
  }
  std::vector<double *> eliminated;
  for (auto &p : pts)
    eliminated.push_back(p.data());
  Eigen::MatrixXd cov;
  ASSERT_TRUE(marginalCovariance(problem, {k}, eliminated, cov));
  const Eigen::MatrixXd full = (Jfull.transpose() * Jfull).inverse();
  EXPECT_LT((cov - full.topLeftCorner(2, 2)).norm(), 1e-10 * full.topLeftCorner(2, 2).norm());

  // A fifth point with two residuals only (3 unknowns: not determined by its own observations, as a
  // point seen along one ray) is left out with its residuals: the same covariance, counted; the
  // kept blocks are still determined by the four others. It made the whole covariance fail before.
  Eigen::Vector3d lone = Eigen::Vector3d::Zero();
  for (int r = 0; r < 2; ++r) {
    LinearCost c;
    for (double &x : c.a)
      x = rng.uniform(-1, 1);
    c.y = rng.uniform(-1, 1);
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<LinearCost, 1, 2, 3>(new LinearCost(c)), nullptr, k,
                             lone.data());
  }
  eliminated.push_back(lone.data());
  Eigen::MatrixXd cov5;
  int left_out = -1;
  ASSERT_TRUE(marginalCovariance(problem, {k}, eliminated, cov5, nullptr, &left_out));
  EXPECT_EQ(left_out, 1);
  EXPECT_LT((cov5 - cov).norm(), 1e-12 * cov.norm());
}

// The homography fit: a plane's matches are all explained; a general scene's are not.
TEST(Geometry, HomographyExplainsAPlaneOnly)
{
  const CameraModel cam = vispCamera().withoutDistortion();
  double v[6] = {0.1, 0.02, 0.0, 0.02, 0.15, -0.05};
  const Rigid c2Mc1 = rigidFromVector(v);
  Random rng(11, 0);
  for (bool planar : {true, false}) {
    std::vector<Eigen::Vector2d> a, b;
    for (int i = 0; i < 60; ++i) {
      const Eigen::Vector3d X(rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), planar ? 1.0 : rng.uniform(0.6, 1.6));
      a.push_back(cam.project(X));
      b.push_back(cam.project(c2Mc1 * X));
    }
    Eigen::Matrix3d H;
    std::vector<bool> inl;
    ASSERT_TRUE(fitHomography(a, b, 1.0, 2000, 0.999, H, inl));
    size_t n = 0;
    for (bool x : inl)
      n += x;
    if (planar)
      EXPECT_EQ(n, a.size());
    else
      EXPECT_LT(n, a.size() / 2);
  }
  Eigen::Matrix3d H;
  std::vector<bool> inl;
  EXPECT_FALSE(fitHomography({Eigen::Vector2d(0, 0)}, {Eigen::Vector2d(1, 1)}, 1.0, 100, 0.99, H, inl));
}

// The homography's RANSAC is OpenCV's classic one (USAC changed the two-view verdicts of the main
// job: see fitHomography): it takes no seed, and is deterministic by itself: the same homography bit
// for bit from call to call, whatever OpenCV's thread count and the global cv::theRNG state (which
// cv::setRNGSeed sets, and which that RANSAC does not use); on a plane contaminated by 40 % of
// outliers it finds the true inliers.
TEST(Geometry, HomographyRansacIsDeterministicWithoutASeed)
{
  const CameraModel cam = vispCamera().withoutDistortion();
  double v[6] = {0.1, 0.02, 0.0, 0.02, 0.15, -0.05};
  const Rigid c2Mc1 = rigidFromVector(v);
  Random rng(12, 0);
  std::vector<Eigen::Vector2d> a, b;
  std::vector<bool> truth;
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d X(rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), 1.0);
    a.push_back(cam.project(X) + Eigen::Vector2d(rng.normal(0.2), rng.normal(0.2)));
    const bool outlier = i % 5 < 2;
    b.push_back(outlier ? Eigen::Vector2d(rng.uniform(0, 640), rng.uniform(0, 480))
                        : Eigen::Vector2d(cam.project(c2Mc1 * X) + Eigen::Vector2d(rng.normal(0.2), rng.normal(0.2))));
    truth.push_back(!outlier);
  }
  Eigen::Matrix3d H1;
  std::vector<bool> in1;
  ASSERT_TRUE(fitHomography(a, b, 2.0, 2000, 0.999, H1, in1));
  unsigned int wrong = 0;
  for (size_t i = 0; i < a.size(); ++i)
    wrong += in1[i] != truth[i];
  // A random pixel lands within 2 px of the true transfer with probability ~4e-5 per point.
  EXPECT_LE(wrong, 1u);
  const int threads = cv::getNumThreads();
  for (int t : {1, 4}) {
    cv::setNumThreads(t);
    cv::setRNGSeed(1000 + t);
    Eigen::Matrix3d H;
    std::vector<bool> inl;
    ASSERT_TRUE(fitHomography(a, b, 2.0, 2000, 0.999, H, inl));
    EXPECT_TRUE(H == H1) << t << " threads: another homography";
    EXPECT_EQ(inl, in1);
  }
  cv::setNumThreads(threads);
}

// The PnP RANSAC (OpenCV USAC; the multi-view reconstruction's resection) is seeded: the same seed
// gives the same pose bit for bit whatever OpenCV's thread count; ten other seeds all find the true
// inliers of a set with 40 % of wrong pixels and the true pose; with one sample per call, the seeds
// draw different samples (different poses).
TEST(Geometry, PoseRansacIsSeeded)
{
  const double fx = 800, u0 = 320, v0 = 240, mu = 1.02;
  double v[6] = {0.05, -0.03, 0.1, 0.1, -0.2, 0.05};
  const Rigid cMw = rigidFromVector(v);
  Random rng(13, 0);
  std::vector<Eigen::Vector3d> X;
  std::vector<Eigen::Vector2d> uv;
  std::vector<bool> truth;
  for (int i = 0; i < 80; ++i) {
    const Eigen::Vector3d P(rng.uniform(-0.4, 0.4), rng.uniform(-0.3, 0.3), rng.uniform(1.5, 2.5));
    const Eigen::Vector3d Xc = cMw * P;
    const bool outlier = i % 5 < 2;
    X.push_back(P);
    uv.push_back(outlier ? Eigen::Vector2d(rng.uniform(0, 640), rng.uniform(0, 480))
                         : Eigen::Vector2d(u0 + fx * Xc.x() / Xc.z() + rng.normal(0.2),
                                           v0 + mu * fx * Xc.y() / Xc.z() + rng.normal(0.2)));
    truth.push_back(!outlier);
  }
  const auto same = [](const Rigid &a, const Rigid &b) { return a.R == b.R && a.t == b.t; };
  Rigid M1, M1b;
  std::vector<int> in1, in1b;
  ASSERT_TRUE(fitPoseRansac(X, uv, fx, u0, v0, mu, 2.0, 2000, 7, 3, M1, in1));
  const int threads = cv::getNumThreads();
  cv::setNumThreads(1);
  ASSERT_TRUE(fitPoseRansac(X, uv, fx, u0, v0, mu, 2.0, 2000, 7, 3, M1b, in1b));
  cv::setNumThreads(threads);
  EXPECT_TRUE(same(M1, M1b)) << "same seed, other thread count: another pose";
  EXPECT_EQ(in1, in1b);
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    Rigid M, again;
    std::vector<int> inl, inl2;
    ASSERT_TRUE(fitPoseRansac(X, uv, fx, u0, v0, mu, 2.0, 2000, seed, 0, M, inl)) << "seed " << seed;
    std::vector<bool> is_in(X.size(), false);
    for (int i : inl)
      is_in[static_cast<size_t>(i)] = true;
    unsigned int wrong = 0;
    for (size_t i = 0; i < X.size(); ++i)
      wrong += is_in[i] != truth[i];
    EXPECT_LE(wrong, 1u) << "seed " << seed;
    EXPECT_LT(logSO3(M.R.transpose() * cMw.R).norm(), 1e-3) << "seed " << seed;
    EXPECT_LT((M.t - cMw.t).norm(), 5e-3) << "seed " << seed;
    ASSERT_TRUE(fitPoseRansac(X, uv, fx, u0, v0, mu, 2.0, 2000, seed, 0, again, inl2));
    EXPECT_TRUE(same(M, again)) << "seed " << seed << ": not reproducible";
  }
  std::vector<Rigid> single;
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    Rigid M;
    std::vector<int> inl;
    if (fitPoseRansac(X, uv, fx, u0, v0, mu, 2.0, 1, seed, 0, M, inl))
      single.push_back(M);
  }
  ASSERT_GE(single.size(), 2u);
  unsigned int distinct = 0;
  for (size_t i = 1; i < single.size(); ++i)
    distinct += !same(single[i], single[0]);
  EXPECT_GE(distinct, 1u) << "every seed drew the same sample";
}
