/*
 * ViSP SelfCalib: private helpers shared by the module's sources (not installed).
 * Small rigid-body algebra on Eigen types, and conversions at the ViSP boundary.
 */
#ifndef VP_SELFCALIB_MATH_H
#define VP_SELFCALIB_MATH_H

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <visp3/core/vpColVector.h>
#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/core/vpMatrix.h>
#include <visp3/core/vpPoseVector.h>

namespace vpSelfCalib
{
//! A rigid transform aMb: x_a = R x_b + t.
struct Rigid {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();

  Rigid operator*(const Rigid &o) const
  {
    Rigid r;
    r.R = R * o.R;
    r.t = R * o.t + t;
    return r;
  }
  Eigen::Vector3d operator*(const Eigen::Vector3d &x) const { return R * x + t; }
  Rigid inverse() const
  {
    Rigid r;
    r.R = R.transpose();
    r.t = -(r.R * t);
    return r;
  }
};

inline Eigen::Matrix3d skew(const Eigen::Vector3d &v)
{
  Eigen::Matrix3d S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}

//! Rotation exp([r]x) of a theta-u vector.
inline Eigen::Matrix3d expSO3(const Eigen::Vector3d &r)
{
  const double theta = r.norm();
  if (theta == 0.0)
    return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(theta, r / theta).toRotationMatrix();
}

//! Theta-u vector of a rotation (log map), through Eigen's angle-axis.
inline Eigen::Vector3d logSO3(const Eigen::Matrix3d &R)
{
  Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

/*!
  Left Jacobian of SO(3): exp([r + dr]x) = exp([J_l(r) dr]x) exp([r]x) to first order.
  J_l = I + (1 - cos t) / t^2 K + (t - sin t) / t^3 K^2, K = [r]x, t = |r|; series below 1e-4.
*/
inline Eigen::Matrix3d leftJacobianSO3(const Eigen::Vector3d &r)
{
  const double t2 = r.squaredNorm();
  const Eigen::Matrix3d K = skew(r);
  double a, b;
  if (t2 < 1e-8) {
    a = 0.5 - t2 / 24.0;
    b = 1.0 / 6.0 - t2 / 120.0;
  } else {
    const double t = std::sqrt(t2);
    a = (1.0 - std::cos(t)) / t2;
    b = (t - std::sin(t)) / (t2 * t);
  }
  return Eigen::Matrix3d::Identity() + a * K + b * K * K;
}

//! [exp([r]x) | t] from a 6-vector (tx ty tz rx ry rz).
inline Rigid rigidFromVector(const double *v)
{
  Rigid m;
  m.t = Eigen::Vector3d(v[0], v[1], v[2]);
  m.R = expSO3(Eigen::Vector3d(v[3], v[4], v[5]));
  return m;
}

inline Rigid rigidFromPose(const vpPoseVector &p)
{
  double v[6];
  for (unsigned int i = 0; i < 6; ++i)
    v[i] = p[i];
  return rigidFromVector(v);
}

inline Rigid rigidFromVisp(const vpHomogeneousMatrix &M)
{
  Rigid m;
  for (unsigned int i = 0; i < 3; ++i) {
    for (unsigned int j = 0; j < 3; ++j)
      m.R(i, j) = M[i][j];
    m.t(i) = M[i][3];
  }
  return m;
}

inline vpHomogeneousMatrix toVisp(const Rigid &m)
{
  vpHomogeneousMatrix M;
  for (unsigned int i = 0; i < 3; ++i) {
    for (unsigned int j = 0; j < 3; ++j)
      M[i][j] = m.R(i, j);
    M[i][3] = m.t(i);
  }
  return M;
}

//! Elementary transforms of the DH conventions.
inline Rigid rotZ(double a)
{
  Rigid m;
  m.R = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return m;
}
inline Rigid rotX(double a)
{
  Rigid m;
  m.R = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()).toRotationMatrix();
  return m;
}
inline Rigid trans(double x, double y, double z)
{
  Rigid m;
  m.t = Eigen::Vector3d(x, y, z);
  return m;
}

//! Rotation angle (rad) between two rotations and distance (m) between two positions.
inline double rotationDistance(const vpHomogeneousMatrix &A, const vpHomogeneousMatrix &B)
{
  return logSO3(rigidFromVisp(A).R.transpose() * rigidFromVisp(B).R).norm();
}
inline double translationDistance(const vpHomogeneousMatrix &A, const vpHomogeneousMatrix &B)
{
  return (rigidFromVisp(A).t - rigidFromVisp(B).t).norm();
}

//! The first three values of a vpColVector (a 3-D point) as an Eigen vector.
inline Eigen::Vector3d vec3(const vpColVector &v) { return Eigen::Vector3d(v[0], v[1], v[2]); }

inline Eigen::Matrix3d toEigen3(const vpMatrix &M)
{
  Eigen::Matrix3d E;
  for (unsigned int i = 0; i < 3; ++i)
    for (unsigned int j = 0; j < 3; ++j)
      E(i, j) = M[i][j];
  return E;
}

inline vpMatrix toVispMatrix(const Eigen::Matrix3d &E)
{
  vpMatrix M(3, 3);
  for (unsigned int i = 0; i < 3; ++i)
    for (unsigned int j = 0; j < 3; ++j)
      M[i][j] = E(i, j);
  return M;
}

inline bool allFinite(const vpColVector &v)
{
  for (unsigned int i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i]))
      return false;
  return true;
}
/*!
  The noise sd measured robustly from absolute residuals (one per pixel coordinate): 1.4826 times
  their median, times sqrt(values / dof) for the degrees of freedom the fit took (inflate). The
  values are reordered. 0 when there are none.
*/
inline double robustNoiseSd(std::vector<double> &abs_residuals, double inflate)
{
  if (abs_residuals.empty())
    return 0;
  const auto mid = abs_residuals.begin() + static_cast<std::ptrdiff_t>(abs_residuals.size() / 2);
  std::nth_element(abs_residuals.begin(), mid, abs_residuals.end());
  return 1.4826 * *mid * inflate;
}

/*!
  The two-sided 99.9 % interval [low, high] of sigma0 = sqrt(chi2 / dof) for dof degrees of freedom
  (chi2 quantiles by the Wilson-Hilferty approximation, z = 3.29; within 1 % of the exact quantiles
  from dof = 10 on). A sigma0 outside it says that the stated noise and the residuals disagree.
*/
inline void sigma0Interval(double dof, double &low, double &high)
{
  const double z = 3.2905, c = 2.0 / (9.0 * dof);
  const auto q = [&](double zz) { return std::pow(std::max(0.0, 1.0 - c + zz * std::sqrt(c)), 1.5); };
  low = q(-z);
  high = q(z);
}
} // namespace vpSelfCalib

#endif
