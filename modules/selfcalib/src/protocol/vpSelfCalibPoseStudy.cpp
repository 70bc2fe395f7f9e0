/*
 * ViSP SelfCalib: errors against the number of calibration poses (the paper's Figure 6).
 */
#include <visp3/selfcalib/vpCalibrationVerifier.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibPoseStudy.h>

#include <algorithm>
#include <chrono>
#include <mutex>

#include "../core/vpSelfCalibParallel.h"

void vpSelfCalibPoseStudy::Options::check() const
{
  if (min_poses < 3)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpSelfCalibPoseStudy: min_poses must be at least 3 (a calibration needs 3 views), "
                               "got " + std::to_string(min_poses));
  if (step == 0)
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpSelfCalibPoseStudy: step must be at least 1");
}

const char *vpSelfCalibPoseStudy::statusName(Status s)
{
  switch (s) {
  case OK:
    return "ok";
  case NO_HELD_OUT_VIEWS:
    return "no held-out views";
  case NO_YARDSTICK:
    return "no yardstick";
  }
  return "unknown";
}

vpSelfCalibPoseStudy::Result vpSelfCalibPoseStudy::run(const vpKinematicChain &nominal,
                                                       const vpSelfCalibDataset &dataset,
                                                       const vpRobotSelfCalibration::Options &options)
{
  return run(nominal, dataset, options, Options());
}

vpSelfCalibPoseStudy::Result vpSelfCalibPoseStudy::run(const vpKinematicChain &nominal,
                                                       const vpSelfCalibDataset &ds,
                                                       const vpRobotSelfCalibration::Options &po,
                                                       const Options &so, const Progress &progress,
                                                       const vpRobotSelfCalibration::Result *full)
{
  const auto t0 = std::chrono::steady_clock::now();
  so.check();
  Result res;
  const unsigned int N = std::min<unsigned int>(po.num_calibration_poses, static_cast<unsigned int>(ds.views.size()));
  const std::vector<vpSelfCalibDataset::View> cal(ds.views.begin(), ds.views.begin() + N),
      ver(ds.views.begin() + N, ds.views.end());
  if (ver.size() < 2) {
    res.status = NO_HELD_OUT_VIEWS;
    res.message = std::to_string(ver.size()) + " held-out view(s), the views after the first " + std::to_string(N) +
                  ": 2 are needed to verify on";
  } else if (!ds.yardstick.isSet()) {
    res.status = NO_YARDSTICK;
    res.message = "the dataset has no yardstick: no 3-D error to measure";
  } else {
    res.status = OK;
    res.nominal_error = vpCalibrationVerifier::verify(nominal, ds.cam, ver, ds.yardstick).yardstick_error;
    const unsigned int first = std::min(so.min_poses, N);
    std::vector<unsigned int> ns; // the n of the curve, ascending, the last N
    for (unsigned int back = 0; back + first <= N; back += so.step)
      ns.insert(ns.begin(), N - back);
    const unsigned int total = static_cast<unsigned int>(ns.size());
    // One calibration per n, independent of the others: run on so.threads threads, each writing
    // only its own slot, the curve assembled in n order (the same whatever the thread count).
    // The run on all N poses is the caller's when given (the same options and dataset).
    const bool reuse_full = full != nullptr;
    std::vector<vpRobotSelfCalibration::Result> runs(total);
    std::mutex progress_mutex;
    unsigned int done = 0;
    if (progress)
      progress(0, total);
    // The largest calibrations first: the threads then finish together (longest-first scheduling);
    // each run writes its own slot, so the order does not change the result.
    const size_t count = reuse_full ? total - 1 : total;
    vpSelfCalib::parallelFor(count, vpSelfCalib::threadCount(so.threads), [&](size_t k) {
      const size_t i = count - 1 - k;
      const unsigned int n = ns[i];
      std::vector<vpSelfCalibDataset::View> views(cal.begin(), cal.begin() + n);
      views.insert(views.end(), ver.begin(), ver.end());
      vpSelfCalibDataset sub = ds;
      sub.views = views;
      vpRobotSelfCalibration::Options o = po;
      o.num_calibration_poses = n;
      runs[i] = vpRobotSelfCalibration::run(nominal, sub, o);
      if (progress) {
        std::lock_guard<std::mutex> lock(progress_mutex);
        progress(++done, total);
      }
    });
    if (reuse_full) {
      runs.back() = *full;
      if (progress)
        progress(total, total);
    } else
      res.full = runs.back();
    res.runs = total;
    for (unsigned int i = 0; i < total; ++i)
      if (runs[i].status == vpRobotSelfCalibration::OK && runs[i].verified)
        res.points.push_back({ns[i], runs[i].after.yardstick_error});
    res.message = std::to_string(res.points.size()) + " of " + std::to_string(res.runs) + " calibrations (" +
                  std::to_string(ns.front()) + " to " + std::to_string(N) + " poses" +
                  (so.step > 1 ? ", every " + std::to_string(so.step) + "th" : std::string()) +
                  ") verified on " + std::to_string(ver.size()) + " held-out views";
  }
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}
