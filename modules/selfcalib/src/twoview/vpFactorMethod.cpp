/*
 * ViSP SelfCalib: the factor method (paper Theorem 1).
 */
#include <visp3/selfcalib/vpFactorMethod.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <Eigen/SVD>

#include "../core/vpSelfCalibMath.h"

using namespace vpSelfCalib;

vpMatrix vpFactorMethod::intrinsicMatrix(double fx, double u0, double v0, double mu)
{
  Eigen::Matrix3d A;
  A << fx, 0, u0, 0, mu * fx, v0, 0, 0, 1;
  return toVispMatrix(A);
}

/*
  Midpoint triangulation of rays x1 (camera 1) and x2 (camera 2), normalized coordinates:
  z1 X1dir = R^T (z2 x2dir - t)  <=>  z1 x1 - z2 R^T x2 = -R^T t, least squares in (z1, z2).
*/
void vpFactorMethod::triangulateDepths(const vpHomogeneousMatrix &c2Mc1, const double x1[2], const double x2[2],
                                       double &z1, double &z2)
{
  const Rigid M = rigidFromVisp(c2Mc1);
  const Eigen::Vector3d a(x1[0], x1[1], 1);
  const Eigen::Vector3d b = M.R.transpose() * Eigen::Vector3d(x2[0], x2[1], 1);
  const Eigen::Vector3d c = -(M.R.transpose() * M.t);
  Eigen::Matrix<double, 3, 2> Am;
  Am.col(0) = a;
  Am.col(1) = -b;
  const Eigen::Vector2d z = Am.colPivHouseholderQr().solve(c);
  z1 = z(0);
  z2 = z(1);
}

vpFactorMethod::Result vpFactorMethod::estimate(const vpMatrix &F, double fx, double u0, double v0, double mu,
                                                const std::vector<vpImagePoint> &p1, const std::vector<vpImagePoint> &p2)
{
  if (!(fx > 0 && mu > 0 && std::isfinite(fx) && std::isfinite(mu)))
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpFactorMethod: fx and mu must be positive");
  if (p1.size() != p2.size())
    throw vpSelfCalibException(vpSelfCalibException::dimensionError, "vpFactorMethod: point lists differ in size");
  const Eigen::Matrix3d A = toEigen3(intrinsicMatrix(fx, u0, v0, mu));
  const Eigen::Matrix3d E = A.transpose() * toEigen3(F) * A;
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(E, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d U = svd.matrixU(), V = svd.matrixV();
  if (U.determinant() < 0)
    U = -U;
  if (V.determinant() < 0)
    V = -V;
  Eigen::Matrix3d W; // the paper's E of Theorem 1
  W << 0, 1, 0, -1, 0, 0, 0, 0, 1;
  const Eigen::Matrix3d Ainv = A.inverse();
  std::vector<std::array<double, 4>> x(p1.size());
  for (size_t i = 0; i < p1.size(); ++i) {
    const Eigen::Vector3d a = Ainv * Eigen::Vector3d(p1[i].get_u(), p1[i].get_v(), 1);
    const Eigen::Vector3d b = Ainv * Eigen::Vector3d(p2[i].get_u(), p2[i].get_v(), 1);
    x[i] = {a(0), a(1), b(0), b(1)};
  }
  Result best;
  bool first = true;
  for (int r = 0; r < 2; ++r) {
    const Eigen::Matrix3d R = U * (r == 0 ? W : Eigen::Matrix3d(W.transpose())) * V.transpose();
    for (int s = 0; s < 2; ++s) {
      Rigid M;
      M.R = R;
      M.t = (s == 0 ? 1.0 : -1.0) * U.col(2);
      const vpHomogeneousMatrix c2Mc1 = toVisp(M);
      unsigned int in_front = 0;
      for (const auto &xi : x) {
        double z1, z2;
        triangulateDepths(c2Mc1, &xi[0], &xi[2], z1, z2);
        in_front += (z1 > 0 && z2 > 0);
      }
      if (first || in_front > best.num_in_front) {
        best.c2Mc1 = c2Mc1;
        best.num_in_front = in_front;
        first = false;
      }
    }
  }
  return best;
}
