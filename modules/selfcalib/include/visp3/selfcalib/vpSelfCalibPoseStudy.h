/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpSelfCalibPoseStudy.h
  \brief The paper's Figure 6: the 3-D yardstick error on the held-out views against the number of
  calibration poses.
*/
#ifndef VP_SELFCALIB_POSE_STUDY_H
#define VP_SELFCALIB_POSE_STUDY_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>

/*!
  \class vpSelfCalibPoseStudy
  \ingroup group_selfcalib_protocol
  \brief The paper's Figure 6: the 3-D yardstick error on the held-out views against the number of
  calibration poses.

  With N = min(options.num_calibration_poses, number of views) and the held-out views those after
  the first N (as vpRobotSelfCalibration uses them), the calibration is run again on the first n
  views for n = N, N - step, ... down to min(min_poses, N), each time verified on the same held-out views; the
  calibrated model's yardstick error (vpCalibrationVerifier, the paper's 3-D error) is kept for
  every n whose run is OK and verified. The nominal model's error on the same views is the
  reference line. The last point (n = N) is the run vpRobotSelfCalibration::run() makes with the
  same options.

  The calibrations run in parallel (Options::threads); the curve is the same for any thread count.
  It runs the calibration once per n: the figure of a report (vpSelfCalibReport::write() takes the
  result), computed apart from the report so that writing a report never calibrates.
*/
class VISP_SELFCALIB_EXPORT vpSelfCalibPoseStudy
{
public:
  //! Settings of vpSelfCalibPoseStudy (the defaults are the member initialisers).
  struct Options {
    unsigned int min_poses = 6; //!< fewest calibration poses of the curve (the paper's Figure 6 starts at 6)
    //! Every step-th n from N down to min_poses (1: every n; 3 with N = 15: 6, 9, 12, 15).
    unsigned int step = 1;
    //! Calibrations run at once, each on its own thread (0: the machine's hardware threads). The
    //! curve does not depend on it: every calibration is single-threaded and deterministic.
    unsigned int threads = 0;
    //! Throws vpSelfCalibException when min_poses < 3 (a calibration needs 3 views) or step is 0.
    void check() const;
  };

  enum Status {
    OK,
    NO_HELD_OUT_VIEWS, //!< fewer than 2 views after the calibration views: nothing to verify on
    NO_YARDSTICK       //!< the dataset has no yardstick: no 3-D error to measure
  };
  static const char *statusName(Status s);

  //! One point of the curve.
  struct Point {
    unsigned int poses = 0;      //!< n, calibration poses
    double yardstick_error = 0;  //!< m, calibrated on the first n views, on the held-out views
  };

  //! The result of vpSelfCalibPoseStudy: what it computed, and what the caller needs to judge it.
  struct Result {
    Status status = NO_HELD_OUT_VIEWS;
    std::string message;
    double nominal_error = 0;  //!< m, the nominal model's yardstick error on the held-out views
    std::vector<Point> points; //!< n increasing; a failed or unverified run leaves no point
    unsigned int runs = 0;     //!< calibrations run
    double seconds = 0;
    /*!
      The run on all N poses (the curve's last point) when the study ran it (no `full` given to
      run()): exactly vpRobotSelfCalibration::run(nominal, dataset, options), for a caller that wants
      both and runs the study first so that this run shares the cores with the others.
    */
    std::optional<vpRobotSelfCalibration::Result> full;
  };

  //! Progress: calibrations done, total. Called from the worker threads, one call at a time.
  using Progress = std::function<void(unsigned int, unsigned int)>;

  /*!
    The study on `dataset` with the calibration `options`. Throws vpSelfCalibException on bad
    study options and, through vpRobotSelfCalibration::run(), on caller mistakes in the dataset
    (fewer than 3 calibration views...). Runs nothing when the status is not OK. `full`, when
    given, is vpRobotSelfCalibration::run(nominal, dataset, options), which the caller has already
    run: it is the last point of the curve and is not run again (a result of other options or
    another dataset would give a wrong last point).
  */
  static Result run(const vpKinematicChain &nominal, const vpSelfCalibDataset &dataset,
                    const vpRobotSelfCalibration::Options &options, const Options &study_options,
                    const Progress &progress = Progress(), const vpRobotSelfCalibration::Result *full = nullptr);
  //! The study with the default study options.
  static Result run(const vpKinematicChain &nominal, const vpSelfCalibDataset &dataset,
                    const vpRobotSelfCalibration::Options &options);
};

#endif
