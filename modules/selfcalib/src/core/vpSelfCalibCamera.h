/*
 * ViSP SelfCalib: the one camera model of the module (private, not installed).
 */
#ifndef VP_SELFCALIB_CAMERA_H
#define VP_SELFCALIB_CAMERA_H

#include <array>
#include <limits>

#include <Eigen/Core>

#include <visp3/core/vpCameraParameters.h>

namespace vpSelfCalib
{
/*!
  Lens distortion models. A point of normalized (undistorted) coordinates x = X/Z, y = Y/Z,
  r^2 = x^2 + y^2, is moved to (x_d, y_d), then u = u0 + p_x x_d, v = v0 + mu p_x y_d.
  - NONE: x_d = x, y_d = y.
  - VISP: ViSP's perspectiveProjWithDistortion (vpCameraParameters k_ud, the undistorted-to-distorted
    coefficient): x_d = x (1 + k_ud r^2), y_d = y (1 + k_ud r^2). One coefficient.
  - OPENCV: OpenCV's (Brown-Conrady) model with coefficients (k1, k2, p1, p2, k3):
    g = 1 + k1 r^2 + k2 r^4 + k3 r^6,
    x_d = x g + 2 p1 x y + p2 (r^2 + 2 x^2),  y_d = y g + p1 (r^2 + 2 y^2) + 2 p2 x y.
  The numeric values are the numbers of coefficients.
*/
enum class Distortion { NONE = 0, VISP = 1, OPENCV = 5 };

inline constexpr int numDistortionCoefficients(Distortion d) { return static_cast<int>(d); }

//! Largest intrinsics vector: p_x, mu, u0, v0 and five distortion coefficients.
constexpr int kMaxIntrinsics = 9;

/*!
  Distortion of normalized coordinates (x, y) -> (xd, yd) with coefficients k (see Distortion).
  Templated so that autodiff cost functors and analytic code share it.
*/
template <typename T> void distort(Distortion model, const T *k, const T &x, const T &y, T &xd, T &yd)
{
  xd = x;
  yd = y;
  switch (model) {
  case Distortion::NONE:
    return;
  case Distortion::VISP: {
    const T g = T(1) + k[0] * (x * x + y * y);
    xd = x * g;
    yd = y * g;
    return;
  }
  case Distortion::OPENCV: {
    const T r2 = x * x + y * y;
    const T g = T(1) + r2 * (k[0] + r2 * (k[1] + r2 * k[4]));
    xd = x * g + T(2) * k[2] * x * y + k[3] * (r2 + T(2) * x * x);
    yd = y * g + k[2] * (r2 + T(2) * y * y) + T(2) * k[3] * x * y;
    return;
  }
  }
}

/*!
  Pixel of a point Xc in the camera frame through intrinsics in = (p_x, mu, u0, v0, k...):
  u = u0 + p_x x_d, v = v0 + mu p_x y_d. No cheirality test (see inFront()).
*/
template <typename T> void projectPoint(Distortion model, const T *in, const T *Xc, T *uv)
{
  const T x = Xc[0] / Xc[2], y = Xc[1] / Xc[2];
  T xd = x, yd = y;
  distort(model, in + 4, x, y, xd, yd);
  uv[0] = in[2] + in[0] * xd;
  uv[1] = in[3] + in[1] * in[0] * yd;
}

//! A point the camera can see: in front of it by more than 1e-9 (of the scene's unit).
inline bool inFront(const Eigen::Vector3d &Xc) { return Xc(2) > 1e-9; }

/*!
  \brief The camera model every layer uses: pinhole + one of the distortion models above, with
  analytic Jacobians and the inverse (unprojection).

  Intrinsics vector in = (p_x, mu, u0, v0, k_1 .. k_n), n = numDistortionCoefficients(distortion);
  p_y = mu p_x. At the ViSP boundary: fromVisp() / toVisp() (perspectiveProjWithDistortion is the
  VISP model with k_ud; ViSP's inverse coefficient k_du is not used: unprojection is solved).
*/
class CameraModel
{
public:
  CameraModel() { m_in.fill(0.0); }
  CameraModel(Distortion distortion, const double *in);

  static CameraModel fromVisp(const vpCameraParameters &cam);
  static CameraModel pinhole(double px, double py, double u0, double v0);
  /*!
    The vpCameraParameters of this model: without distortion, or ViSP's k_ud model with k_du = -k_ud
    (its first-order inverse). Throws vpSelfCalibException for the OPENCV model, which ViSP 3.5's
    vpCameraParameters cannot hold.
  */
  vpCameraParameters toVisp() const;

  Distortion distortion() const { return m_distortion; }
  int size() const { return 4 + numDistortionCoefficients(m_distortion); }
  const double *intrinsics() const { return m_in.data(); }
  double *intrinsics() { return m_in.data(); }
  double px() const { return m_in[0]; }
  double py() const { return m_in[1] * m_in[0]; }
  double mu() const { return m_in[1]; }
  double u0() const { return m_in[2]; }
  double v0() const { return m_in[3]; }
  //! The model without its distortion (same p_x, mu, u0, v0).
  CameraModel withoutDistortion() const;

  //! Pixel of Xc (camera frame); no cheirality test.
  Eigen::Vector2d project(const Eigen::Vector3d &Xc) const;
  /*!
    The largest r^2 = x^2 + y^2 (normalized undistorted coordinates) where the model's radial
    distortion is valid: where the distorted radius r g(r^2) still grows with r (d/dr > 0: 1 + 3 k1 r^2
    + 5 k2 r^4 + 7 k3 r^6 > 0 for OPENCV, 1 + 3 k_ud r^2 > 0 for VISP). Beyond it the polynomial
    folds back and then diverges (a point at r = 10 through k1 = -0.3 lands 4e5 px away): a lens
    model fitted on the image says nothing there. Infinity without distortion, or when the radius
    grows up to r = 100 (a field of view beyond any lens).
  */
  double validRadius2() const;
  //! The image margin of withImage() by default, as a fraction of the image's larger side.
  static constexpr double kImageMarginFraction = 0.25;
  /*!
    The same model, told the image it was fitted on (width x height px): a lens model with
    distortion then also sees only the points whose undistorted pinhole pixel (u0 + p_x x,
    v0 + p_y y) lies in the image widened by `margin` px on every side (negative: the default,
    kImageMarginFraction of the larger side). A distortion polynomial is measured inside the image;
    beyond it, even where validRadius2() still holds, its value is an extrapolation that no
    observation supported. Without distortion the pinhole is exact everywhere and nothing changes.
  */
  CameraModel withImage(unsigned int width, unsigned int height, double margin = -1) const;
  /*!
    Whether the camera sees Xc through its model: in front (inFront()), inside validRadius2() and,
    after withImage() with distortion, within the image and its margin. A point outside is not
    seen: a figure over projected points leaves it out, never counts the polynomial's value there.
  */
  bool sees(const Eigen::Vector3d &Xc) const;
  /*!
    Pixel of Xc and, on request, d uv / d Xc (2 x 3) and d uv / d in (2 x size(), row-major array).
    False (and nothing written) when Xc is not in front of the camera.
  */
  bool project(const Eigen::Vector3d &Xc, Eigen::Vector2d &uv, Eigen::Matrix<double, 2, 3> *J_X,
               double *J_in) const;
  //! Pixel of normalized undistorted coordinates (x, y).
  Eigen::Vector2d pixel(const Eigen::Vector2d &xy) const;
  /*!
    Normalized undistorted coordinates (x, y) of a pixel: the inverse of pixel(), by Newton's method
    on the distortion (exact without distortion). Converges for the distortions of real lenses
    inside the image; where it does not (the distortion folds over), the last iterate is returned
    and converged() of the overload below says so.
  */
  Eigen::Vector2d unproject(const Eigen::Vector2d &uv) const;
  bool unproject(const Eigen::Vector2d &uv, Eigen::Vector2d &xy) const;
  //! The pixel where the same camera without distortion would see what it sees at uv.
  Eigen::Vector2d undistortPixel(const Eigen::Vector2d &uv) const { return withoutDistortion().pixel(unproject(uv)); }
  //! The unit ray (camera frame) through a pixel.
  Eigen::Vector3d ray(const Eigen::Vector2d &uv) const;

  //! Jacobian (2 x 2) of (x_d, y_d) with respect to (x, y), and on request (2 x n, row-major) to k.
  static Eigen::Matrix2d distortionJacobian(Distortion model, const double *k, double x, double y, double *J_k);

private:
  Distortion m_distortion = Distortion::NONE;
  std::array<double, kMaxIntrinsics> m_in;
  //! withImage(): the undistorted pixels seen, [u_min, u_max] x [v_min, v_max] (none by default).
  double m_u_min = -std::numeric_limits<double>::infinity(), m_u_max = std::numeric_limits<double>::infinity();
  double m_v_min = -std::numeric_limits<double>::infinity(), m_v_max = std::numeric_limits<double>::infinity();
};
} // namespace vpSelfCalib

#endif
