/*
 * ViSP SelfCalib: observability indices O1-O5 and the condition number (paper eq. 7).
 */
#include <visp3/selfcalib/vpObservabilityIndices.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include <Eigen/SVD>

#include "../core/vpSelfCalibMath.h"

vpObservabilityIndices vpObservabilityIndices::fromSingularValues(std::vector<double> sigma, unsigned int m)
{
  if (sigma.empty() || m == 0)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpObservabilityIndices: need at least one singular value and one configuration");
  for (double s : sigma)
    if (!(std::isfinite(s) && s >= 0))
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpObservabilityIndices: singular values must be finite and non-negative");
  std::sort(sigma.begin(), sigma.end(), std::greater<double>());
  const double s1 = sigma.front(), sL = sigma.back();
  const double L = static_cast<double>(sigma.size());
  vpObservabilityIndices o;
  double log_sum = 0, inv_sum = 0;
  for (double s : sigma) {
    log_sum += std::log(s); // -inf when s = 0: O1 = 0
    inv_sum += 1.0 / s;     // inf when s = 0: O5 = 0
  }
  o.O1 = std::exp(log_sum / L) / std::sqrt(static_cast<double>(m));
  o.O2 = s1 > 0 ? sL / s1 : 0;
  o.O3 = sL;
  o.O4 = s1 > 0 ? sL * sL / s1 : 0;
  o.O5 = 1.0 / inv_sum;
  o.condition_number = sL > 0 ? s1 / sL : std::numeric_limits<double>::infinity();
  return o;
}

vpObservabilityIndices vpObservabilityIndices::fromJacobian(const vpMatrix &J, unsigned int m)
{
  if (J.getCols() == 0 || J.getRows() < J.getCols())
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               "vpObservabilityIndices: J must have at least as many rows as columns");
  const Eigen::MatrixXd Je = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      J.data, J.getRows(), J.getCols());
  const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(Je).singularValues();
  return fromSingularValues(std::vector<double>(s.data(), s.data() + s.size()), m);
}
