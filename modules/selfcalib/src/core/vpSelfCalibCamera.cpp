/*
 * ViSP SelfCalib: the one camera model of the module. See vpSelfCalibCamera.h.
 */
#include "vpSelfCalibCamera.h"

#include <limits>

#include <algorithm>
#include <cmath>

#include <Eigen/LU>

#include <visp3/selfcalib/vpSelfCalibException.h>

namespace vpSelfCalib
{
CameraModel::CameraModel(Distortion distortion, const double *in) : m_distortion(distortion)
{
  m_in.fill(0.0);
  for (int i = 0; i < size(); ++i)
    m_in[i] = in[i];
}

CameraModel CameraModel::fromVisp(const vpCameraParameters &cam)
{
  const double in[5] = {cam.get_px(), cam.get_py() / cam.get_px(), cam.get_u0(), cam.get_v0(),
                        cam.get_projModel() == vpCameraParameters::perspectiveProjWithDistortion ? cam.get_kud()
                                                                                                  : 0.0};
  const bool distorted = cam.get_projModel() == vpCameraParameters::perspectiveProjWithDistortion;
  return CameraModel(distorted ? Distortion::VISP : Distortion::NONE, in);
}

CameraModel CameraModel::pinhole(double px, double py, double u0, double v0)
{
  const double in[4] = {px, py / px, u0, v0};
  return CameraModel(Distortion::NONE, in);
}

vpCameraParameters CameraModel::toVisp() const
{
  vpCameraParameters c;
  switch (m_distortion) {
  case Distortion::NONE:
    c.initPersProjWithoutDistortion(m_in[0], m_in[1] * m_in[0], m_in[2], m_in[3]);
    break;
  case Distortion::VISP:
    // ViSP also stores the inverse model k_du; its first-order value is -k_ud.
    c.initPersProjWithDistortion(m_in[0], m_in[1] * m_in[0], m_in[2], m_in[3], m_in[4], -m_in[4]);
    break;
  case Distortion::OPENCV:
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "CameraModel::toVisp: ViSP's vpCameraParameters cannot hold OpenCV's distortion model");
  }
  return c;
}

CameraModel CameraModel::withoutDistortion() const { return CameraModel(Distortion::NONE, m_in.data()); }

Eigen::Vector2d CameraModel::project(const Eigen::Vector3d &Xc) const
{
  Eigen::Vector2d uv;
  projectPoint(m_distortion, m_in.data(), Xc.data(), uv.data());
  return uv;
}

double CameraModel::validRadius2() const
{
  const double *k = m_in.data() + 4;
  // d(r g(r^2))/dr as a polynomial of s = r^2.
  const auto slope = [&](double s) {
    if (m_distortion == Distortion::VISP)
      return 1 + 3 * k[0] * s;
    return 1 + s * (3 * k[0] + s * (5 * k[1] + s * 7 * k[4]));
  };
  constexpr double kLargest = 1e4; // r = 100
  if (m_distortion == Distortion::NONE)
    return std::numeric_limits<double>::infinity();
  // The first sign change on a geometric scan of s, then bisection (the slope is 1 at s = 0).
  double lo = 0;
  for (double s = 1e-4; s <= kLargest; s *= 1.25) {
    if (slope(s) <= 0) {
      double hi = s;
      for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        (slope(mid) > 0 ? lo : hi) = mid;
      }
      return lo;
    }
    lo = s;
  }
  return std::numeric_limits<double>::infinity();
}

CameraModel CameraModel::withImage(unsigned int width, unsigned int height, double margin) const
{
  CameraModel c = *this;
  if (m_distortion == Distortion::NONE || width == 0 || height == 0)
    return c;
  const double m = margin < 0 ? kImageMarginFraction * std::max(width, height) : margin;
  c.m_u_min = -m;
  c.m_v_min = -m;
  c.m_u_max = width + m;
  c.m_v_max = height + m;
  return c;
}

bool CameraModel::sees(const Eigen::Vector3d &Xc) const
{
  if (!inFront(Xc))
    return false;
  const double x = Xc(0) / Xc(2), y = Xc(1) / Xc(2);
  if (!(x * x + y * y < validRadius2()))
    return false;
  const double u = u0() + px() * x, v = v0() + py() * y;
  return u >= m_u_min && u <= m_u_max && v >= m_v_min && v <= m_v_max;
}

Eigen::Matrix2d CameraModel::distortionJacobian(Distortion model, const double *k, double x, double y, double *J_k)
{
  Eigen::Matrix2d D = Eigen::Matrix2d::Identity();
  const double r2 = x * x + y * y;
  switch (model) {
  case Distortion::NONE:
    break;
  case Distortion::VISP: {
    const double g = 1 + k[0] * r2;
    D << g + 2 * k[0] * x * x, 2 * k[0] * x * y, 2 * k[0] * x * y, g + 2 * k[0] * y * y;
    if (J_k) {
      J_k[0] = x * r2;
      J_k[1] = y * r2;
    }
    break;
  }
  case Distortion::OPENCV: {
    const double k1 = k[0], k2 = k[1], p1 = k[2], p2 = k[3], k3 = k[4];
    const double g = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
    const double dg = k1 + r2 * (2 * k2 + 3 * k3 * r2); // d g / d r^2
    D << g + 2 * x * x * dg + 2 * p1 * y + 6 * p2 * x, 2 * x * y * dg + 2 * p1 * x + 2 * p2 * y,
        2 * x * y * dg + 2 * p1 * x + 2 * p2 * y, g + 2 * y * y * dg + 6 * p1 * y + 2 * p2 * x;
    if (J_k) {
      // Row-major 2 x 5 over (k1, k2, p1, p2, k3).
      const double r4 = r2 * r2, r6 = r4 * r2;
      const double row0[5] = {x * r2, x * r4, 2 * x * y, r2 + 2 * x * x, x * r6};
      const double row1[5] = {y * r2, y * r4, r2 + 2 * y * y, 2 * x * y, y * r6};
      for (int i = 0; i < 5; ++i) {
        J_k[i] = row0[i];
        J_k[5 + i] = row1[i];
      }
    }
    break;
  }
  }
  return D;
}

bool CameraModel::project(const Eigen::Vector3d &Xc, Eigen::Vector2d &uv, Eigen::Matrix<double, 2, 3> *J_X,
                          double *J_in) const
{
  if (!inFront(Xc))
    return false;
  projectPoint(m_distortion, m_in.data(), Xc.data(), uv.data());
  if (!J_X && !J_in)
    return true;
  const int n = numDistortionCoefficients(m_distortion);
  const double fx = m_in[0], mu = m_in[1];
  const double x = Xc(0) / Xc(2), y = Xc(1) / Xc(2);
  double Jk[10];
  const Eigen::Matrix2d Dd = distortionJacobian(m_distortion, m_in.data() + 4, x, y, n ? Jk : nullptr);
  if (J_X) {
    Eigen::Matrix<double, 2, 3> Dc;
    Dc << 1 / Xc(2), 0, -x / Xc(2), 0, 1 / Xc(2), -y / Xc(2);
    Eigen::Matrix2d S;
    S << fx, 0, 0, mu * fx;
    *J_X = S * Dd * Dc;
  }
  if (J_in) {
    double xd = 0, yd = 0;
    distort(m_distortion, m_in.data() + 4, x, y, xd, yd);
    const int w = size();
    double *r0 = J_in, *r1 = J_in + w;
    r0[0] = xd, r0[1] = 0, r0[2] = 1, r0[3] = 0;
    r1[0] = mu * yd, r1[1] = fx * yd, r1[2] = 0, r1[3] = 1;
    for (int j = 0; j < n; ++j) {
      r0[4 + j] = fx * Jk[j];
      r1[4 + j] = mu * fx * Jk[n + j];
    }
  }
  return true;
}

Eigen::Vector2d CameraModel::pixel(const Eigen::Vector2d &xy) const
{
  double xd = 0, yd = 0;
  distort(m_distortion, m_in.data() + 4, xy(0), xy(1), xd, yd);
  return Eigen::Vector2d(m_in[2] + m_in[0] * xd, m_in[3] + m_in[1] * m_in[0] * yd);
}

bool CameraModel::unproject(const Eigen::Vector2d &uv, Eigen::Vector2d &xy) const
{
  const Eigen::Vector2d target((uv(0) - m_in[2]) / m_in[0], (uv(1) - m_in[3]) / (m_in[1] * m_in[0]));
  xy = target;
  if (m_distortion == Distortion::NONE)
    return true;
  // Newton's method on distort(x, y) = target, from the distorted coordinates.
  for (int it = 0; it < 50; ++it) {
    double xd = 0, yd = 0;
    distort(m_distortion, m_in.data() + 4, xy(0), xy(1), xd, yd);
    const Eigen::Vector2d r = target - Eigen::Vector2d(xd, yd);
    if (r.norm() <= 1e-15 * (1 + target.norm()))
      return true;
    const Eigen::Matrix2d D = distortionJacobian(m_distortion, m_in.data() + 4, xy(0), xy(1), nullptr);
    const double det = D.determinant();
    if (!(std::fabs(det) > 1e-12))
      return false;
    const Eigen::Vector2d step = D.inverse() * r;
    xy += step;
    if (!xy.allFinite())
      return false;
    if (step.norm() <= 1e-16 * (1 + xy.norm()))
      return true;
  }
  double xd = 0, yd = 0;
  distort(m_distortion, m_in.data() + 4, xy(0), xy(1), xd, yd);
  return (target - Eigen::Vector2d(xd, yd)).norm() <= 1e-10 * (1 + target.norm());
}

Eigen::Vector2d CameraModel::unproject(const Eigen::Vector2d &uv) const
{
  Eigen::Vector2d xy;
  unproject(uv, xy);
  return xy;
}

Eigen::Vector3d CameraModel::ray(const Eigen::Vector2d &uv) const
{
  const Eigen::Vector2d xy = unproject(uv);
  return Eigen::Vector3d(xy(0), xy(1), 1).normalized();
}
} // namespace vpSelfCalib
