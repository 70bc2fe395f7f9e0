/*
 * ViSP SelfCalib: focal length from the fundamental matrix (see the header for the equations).
 */
#include <visp3/selfcalib/vpFocalFromFundamental.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <cmath>
#include <sstream>

#include <Eigen/SVD>

#include "../core/vpSelfCalibMath.h"

using namespace vpSelfCalib;

vpFocalFromFundamental::Result vpFocalFromFundamental::estimate(const vpMatrix &F, double u0, double v0, double mu,
                                                                double scale, double min_coplanarity)
{
  if (F.getRows() != 3 || F.getCols() != 3)
    throw vpSelfCalibException(vpSelfCalibException::dimensionError, "vpFocalFromFundamental: F must be 3 x 3");
  if (!(std::isfinite(u0) && std::isfinite(v0) && mu > 0 && std::isfinite(mu) && scale > 0 && std::isfinite(scale)))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpFocalFromFundamental: u0, v0 must be finite, mu and scale positive");
  // Pixels to the square, centred, scaled frame: x = N m with N = [[1/s, 0, -u0/s], [0, 1/(mu s), -v0/(mu s)], [0, 0, 1]].
  Eigen::Matrix3d N;
  N << 1 / scale, 0, -u0 / scale, 0, 1 / (mu * scale), -v0 / (mu * scale), 0, 0, 1;
  const Eigen::Matrix3d Ni = N.inverse();
  Eigen::Matrix3d Fn = Ni.transpose() * toEigen3(F) * Ni;
  Fn /= Fn.norm();
  Result res;
  res.axes_coplanarity = std::fabs(Fn(2, 2));
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(Fn, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const double a = svd.singularValues()(0), b = svd.singularValues()(1);
  const Eigen::Matrix3d U = svd.matrixU(), V = svd.matrixV();
  const double u13 = U(2, 0), u23 = U(2, 1), v13 = V(2, 0), v23 = V(2, 1);
  const double c1 = a * a * u13 * u23 * (1 - v13 * v13) + a * b * v13 * v23 * (1 - u23 * u23);
  const double d1 = a * a * u13 * u23 * v13 * v13 + a * b * v13 * v23 * u23 * u23;
  const double c2 = a * b * v13 * v23 * (1 - u13 * u13) + b * b * u13 * u23 * (1 - v23 * v23);
  const double d2 = a * b * v13 * v23 * u13 * u13 + b * b * u13 * u23 * v23 * v23;
  const double den = c1 * c1 + c2 * c2;
  std::ostringstream os;
  if (res.axes_coplanarity < min_coplanarity || !(den > 0)) {
    res.status = UNOBSERVABLE;
    os << "the optical axes of the two views (nearly) meet (|F33| = " << res.axes_coplanarity
       << " in the normalized frame): the focal length is not observable from this pair";
    res.message = os.str();
    return res;
  }
  const double w = -(c1 * d1 + c2 * d2) / den;
  if (!(w > 0) || !std::isfinite(w)) {
    res.status = NEGATIVE;
    os << "the Kruppa equations give f^2 = " << w * scale * scale
       << " <= 0 (noise or a wrong principal point / aspect ratio)";
    res.message = os.str();
    return res;
  }
  res.fx = scale * std::sqrt(w);
  res.status = OK;
  res.message = "ok";
  return res;
}
