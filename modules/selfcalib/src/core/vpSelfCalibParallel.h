/*
 * ViSP SelfCalib: private parallel loop (not installed).
 *
 * Independent work items on a few threads, with results that do not depend on the thread count:
 * each item writes only to its own slots, and the caller combines them in index order.
 */
#ifndef VP_SELFCALIB_PARALLEL_H
#define VP_SELFCALIB_PARALLEL_H

#include <algorithm>
#include <atomic>
#include <exception>
#include <thread>
#include <vector>

namespace vpSelfCalib
{
//! Threads for `requested` (0: the machine's hardware threads, at least 1).
inline unsigned int threadCount(unsigned int requested)
{
  return requested ? requested : std::max(1u, std::thread::hardware_concurrency());
}

/*!
  Runs fn(0), ..., fn(n - 1) on `threads` threads (the calling one included), each index once; the
  first exception thrown is rethrown after every thread has stopped. fn must write only to its own
  index's slots.
*/
template <class Fn> void parallelFor(size_t n, unsigned int threads, const Fn &fn)
{
  threads = static_cast<unsigned int>(std::min<size_t>(std::max(1u, threads), n));
  if (threads <= 1) {
    for (size_t k = 0; k < n; ++k)
      fn(k);
    return;
  }
  std::atomic<size_t> next(0);
  std::vector<std::exception_ptr> errors(threads);
  auto work = [&](unsigned int t) {
    try {
      for (size_t k; (k = next++) < n;)
        fn(k);
    } catch (...) {
      errors[t] = std::current_exception();
      next = n;
    }
  };
  std::vector<std::thread> pool;
  for (unsigned int t = 1; t < threads; ++t)
    pool.emplace_back(work, t);
  work(0);
  for (std::thread &th : pool)
    th.join();
  for (const std::exception_ptr &e : errors)
    if (e)
      std::rethrow_exception(e);
}
} // namespace vpSelfCalib

#endif
