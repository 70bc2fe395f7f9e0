/*
 * ViSP SelfCalib: private Ceres settings shared by the module's solvers (not installed).
 */
#ifndef VP_SELFCALIB_CERES_H
#define VP_SELFCALIB_CERES_H

#include <ceres/ceres.h>
#include <glog/logging.h>

#include <mutex>
#include <utility>
#include <vector>

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
  logging_type SILENT, and the module never prints. While at least one QuietCeres is alive, glog's
  minimum level is FATAL; when the last one ends, the level the caller had before the first one is
  restored. glog's level is one global flag: the count and the saved level are guarded by a mutex,
  so concurrent calibrations in several threads neither race on it nor leave it at FATAL (each
  saving and restoring the flag on its own would, when their lifetimes interleave). The outcome of
  those events reaches the caller as a status.
*/
class QuietCeres
{
public:
  QuietCeres()
  {
    std::lock_guard<std::mutex> lock(state().mutex);
    if (state().count++ == 0) {
      state().saved = FLAGS_minloglevel;
      FLAGS_minloglevel = google::GLOG_FATAL;
    }
  }
  ~QuietCeres()
  {
    std::lock_guard<std::mutex> lock(state().mutex);
    if (--state().count == 0)
      FLAGS_minloglevel = state().saved;
  }
  QuietCeres(const QuietCeres &) = delete;
  QuietCeres &operator=(const QuietCeres &) = delete;

private:
  struct State {
    std::mutex mutex;
    unsigned int count = 0;
    int saved = 0;
  };
  //! One state for the whole program (an inline function's static: one instance across translation units).
  static State &state()
  {
    static State s;
    return s;
  }
};

//! ceres::Solve under QuietCeres: every solve of the module goes through here (the module never prints).
inline void solve(const ceres::Solver::Options &options, ceres::Problem *problem, ceres::Solver::Summary *summary)
{
  const QuietCeres quiet;
  ceres::Solve(options, problem, summary);
}

//! Covariance::Compute under QuietCeres: a rank-deficient covariance is otherwise a glog error line
//! on stderr (the caller gets false).
inline bool computeCovariance(ceres::Covariance &covariance,
                              const std::vector<std::pair<const double *, const double *>> &blocks,
                              ceres::Problem *problem)
{
  const QuietCeres quiet;
  return covariance.Compute(blocks, problem);
}
} // namespace vpSelfCalib

#endif
