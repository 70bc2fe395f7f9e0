/*
 * ViSP SelfCalib: private Ceres settings shared by the module's solvers (not installed).
 */
#ifndef VP_SELFCALIB_CERES_H
#define VP_SELFCALIB_CERES_H

#include <ceres/ceres.h>
#include <glog/logging.h>

namespace vpSelfCalib
{
/*!
  Silent, single-threaded solver options. tight: tolerances 1e-15, so that noise-free data are
  recovered to 1e-9 and better (Ceres' defaults stop near 1e-8 relative accuracy).
*/
inline ceres::Solver::Options solverOptions(unsigned int max_iterations, bool tight,
                                            ceres::LinearSolverType linear_solver = ceres::DENSE_QR)
{
  ceres::Solver::Options so;
  so.linear_solver_type = linear_solver;
  so.max_num_iterations = static_cast<int>(max_iterations);
  if (tight) {
    so.function_tolerance = 1e-15;
    so.gradient_tolerance = 1e-15;
    so.parameter_tolerance = 1e-15;
  }
  so.logging_type = ceres::SILENT;
  so.num_threads = 1;
  return so;
}

/*!
  Covariance options for problems without gauge freedom (manifolds or fixed blocks remove it): the
  full inverse (null_space_rank 0). A pseudo-inverse would silently drop the near-null direction of a
  nearly degenerate problem, exactly the one whose variance matters, and report it as tiny; here a
  singular normal matrix makes Compute() fail instead.
*/
inline ceres::Covariance::Options covarianceOptions()
{
  ceres::Covariance::Options co;
  co.algorithm_type = ceres::DENSE_SVD;
  co.null_space_rank = 0;
  co.min_reciprocal_condition_number = 1e-300;
  return co;
}
/*!
  Ceres reports recoverable events (a rejected Levenberg-Marquardt step whose Cholesky factorization
  failed under a robust loss, a rank-deficient covariance) through glog warnings on stderr even with
  logging_type SILENT, and the module never prints. While alive, this raises glog's minimum level to
  FATAL and restores the caller's level afterwards. The outcome of those events reaches the caller
  as a status.
*/
class QuietCeres
{
public:
  QuietCeres() : m_saved(FLAGS_minloglevel) { FLAGS_minloglevel = google::GLOG_FATAL; }
  ~QuietCeres() { FLAGS_minloglevel = m_saved; }
  QuietCeres(const QuietCeres &) = delete;
  QuietCeres &operator=(const QuietCeres &) = delete;

private:
  int m_saved;
};

//! ceres::Solve under QuietCeres: every solve of the module goes through here (the module never prints).
inline void solve(const ceres::Solver::Options &options, ceres::Problem *problem, ceres::Solver::Summary *summary)
{
  const QuietCeres quiet;
  ceres::Solve(options, problem, summary);
}
} // namespace vpSelfCalib

#endif
