/*
 * ViSP SelfCalib: the quantile and the tail of a weighted sum of chi-squares (the distribution of a predicted
 * error's mean square given its covariance).
 */
#ifndef VP_SELFCALIB_CHI_SQUARE_H
#define VP_SELFCALIB_CHI_SQUARE_H

#include <algorithm>
#include <cmath>

#include <Eigen/Core>

namespace vpSelfCalib
{
//! Pearson's three-moment fit of a weighted sum of chi-squares (see weightedChi2Quantile()).
struct WeightedChi2Fit {
  double c1 = 0, c2 = 0, nu = 0, c = 0; //!< sum lambda, sum lambda^2, the chi-square's nu, 2 / (9 nu)
  bool spread = false;                  //!< false: Q has no spread (every weight 0)
};

//! The three-moment fit of Q = sum_k lambda_k z_k^2 (weightedChi2Quantile()).
inline WeightedChi2Fit weightedChi2Fit(const Eigen::VectorXd &lambda)
{
  const Eigen::ArrayXd l = lambda.array().max(0.0);
  WeightedChi2Fit f;
  f.c1 = l.sum();
  f.c2 = l.square().sum();
  const double c3 = l.cube().sum();
  f.spread = f.c1 > 0 && f.c2 > 0 && c3 > 0;
  if (f.spread) {
    f.nu = f.c2 * f.c2 * f.c2 / (c3 * c3);
    f.c = 2.0 / (9.0 * f.nu);
  }
  return f;
}

/*!
  The quantile of Q = sum_k lambda_k z_k^2 (z_k independent N(0, 1), lambda_k >= 0) at the one-sided
  normal deviate z (3.0902: 99.9 %, 1.6449: 95 %): Pearson's three-moment fit, Q ~ mean + sd
  (chi2_nu - nu) / sqrt(2 nu) with the same mean (sum lambda), variance (2 sum lambda^2) and skewness
  (nu = (sum lambda^2)^3 / (sum lambda^3)^2), the chi-square quantile by Wilson-Hilferty (11.1 for
  nu = 1 at 99.9 % where the exact is 10.8). Exact in shape for one weight (the one-dimensional bound
  z^2 lambda) and for equal weights; within 3 % of drawn quantiles for spread weights, where matching
  two moments only (Satterthwaite) is 7-12 % low.
*/
inline double weightedChi2Quantile(const Eigen::VectorXd &lambda, double z)
{
  const WeightedChi2Fit f = weightedChi2Fit(lambda);
  if (!f.spread)
    return 0;
  const double chi2 = f.nu * std::pow(std::max(0.0, 1.0 - f.c + z * std::sqrt(f.c)), 3.0);
  return f.c1 + std::sqrt(2.0 * f.c2) * (chi2 - f.nu) / std::sqrt(2.0 * f.nu);
}

//! The 99.9 % quantile of a weighted sum of chi-squares (weightedChi2Quantile()).
inline double weightedChi2Quantile999(const Eigen::VectorXd &lambda) { return weightedChi2Quantile(lambda, 3.0902); }

/*!
  The probability that Q = sum_k lambda_k z_k^2 exceeds y: the inverse of weightedChi2Quantile() (the
  same three-moment fit and Wilson-Hilferty transform), 1 where Q has no spread above y <= 0.
*/
inline double weightedChi2Survival(const Eigen::VectorXd &lambda, double y)
{
  const WeightedChi2Fit f = weightedChi2Fit(lambda);
  if (!f.spread)
    return y < 0 ? 1.0 : 0.0;
  const double chi2 = std::max(0.0, f.nu + (y - f.c1) * std::sqrt(2.0 * f.nu) / std::sqrt(2.0 * f.c2));
  const double z = (std::cbrt(chi2 / f.nu) - 1.0 + f.c) / std::sqrt(f.c);
  return 0.5 * std::erfc(z / std::sqrt(2.0));
}
} // namespace vpSelfCalib

#endif
