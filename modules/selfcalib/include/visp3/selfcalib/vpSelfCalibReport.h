/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpSelfCalibReport.h
  \brief The report of a calibration run: a folder with report.md and PNG figures drawn by gnuplot
  (Debian package gnuplot-nox) from data files kept beside them (plots.gp redraws them).
*/
#ifndef VP_SELFCALIB_REPORT_H
#define VP_SELFCALIB_REPORT_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <string>
#include <vector>

#include <visp3/selfcalib/vpFeatureFrontEnd.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibCrossValidation.h>
#include <visp3/selfcalib/vpSelfCalibPoseStudy.h>
#include <visp3/selfcalib/vpSelfCalibProtocol.h>

/*!
  \class vpSelfCalibReport
  \ingroup group_selfcalib_io
  \brief The report of a calibration run: a folder with report.md and PNG figures drawn by gnuplot
  (Debian package gnuplot-nox) from data files kept beside them (plots.gp redraws them).

  report.md: the run (method, views, f, scale, stage times), the front end (features per image,
  tracks, track-length histogram, the yardstick's views) when there is one, the estimated
  parameters with their standard deviations, those left out and why, the reprojection residuals
  and the verification on the held-out views.
  Figures: trajectory.png (camera positions of every view in 3-D, calibration and held-out),
  position_norms.png (|t_i| of c_i M c_1, the paper's Figures 4-5), residuals.png (histogram of
  the reprojection residuals on the calibration views), verification.png (reprojection RMS of
  each held-out view), errors_vs_poses.png (3-D yardstick error on the held-out views against
  the number of calibration poses, the paper's Figure 6, from a vpSelfCalibPoseStudy result; its
  data file is empty without one), view_residuals.png (reprojection RMS of each calibration view,
  calibrated beside nominal: the view to suspect first). With a front-end result, matches.png (the
  verified matches of every image pair as a matrix image: which views are tied to which) and
  track_lengths.png (the track-length histogram).
  With a vpSelfCalibCrossValidation result, a section "Cross-validation" with the figure and a
  per-fold table (held-out views, status, reprojection RMS and median calibrated and nominal, the
  yardstick error when the fold verified it); with a vpSelfCalibCrossValidation::HeldOut, a section
  "Held-out dataset". A figure without data (no held-out view: every view calibrates) is neither
  drawn nor linked: report.md says why in its place.
  Without gnuplot the data files and report.md are still written and the result says so. gnuplot
  runs without a shell (posix_spawnp with an argument vector, in the report's directory), so no
  path is ever parsed as a command; the message tells apart gnuplot missing, gnuplot failing, a
  figure without data (not drawn) and a figure that did not write completely.

  Writing a report presents results and computes nothing long: it never runs a calibration.
*/
class VISP_SELFCALIB_EXPORT vpSelfCalibReport
{
public:
  //! Settings of vpSelfCalibReport (the defaults are the member initialisers).
  struct Options {
    std::string gnuplot = "gnuplot"; //!< the program (found in PATH); empty: no figures
  };
  //! The result of vpSelfCalibReport: what it computed, and what the caller needs to judge it.
  struct Result {
    bool figures = false; //!< the PNG files were drawn
    std::string message;
    std::vector<std::string> files; //!< everything written
    //! What the report finds in the data that the caller should show (calibration views the
    //! calibrated model does not explain, named), also in report.md.
    std::vector<std::string> warnings;
  };
  /*!
    The record of a run that a report presents: the nominal model, the dataset, the options and the
    result of the calibration, and what was computed beside it (each may be null): the front end's
    result, the errors against the number of poses (vpSelfCalibPoseStudy::run() on the same dataset
    and options), the cross-validation and the held-out dataset's verification (computed apart:
    writing a report never calibrates). The record refers to these objects: they must outlive it.
  */
  struct Record {
    //! A calibration alone.
    Record(const vpKinematicChain &nominal, const vpSelfCalibDataset &dataset,
           const vpRobotSelfCalibration::Options &options, const vpRobotSelfCalibration::Result &result);
    //! A protocol's run: its options, its calibration (with the verdicts), cross-validation and held-out dataset.
    Record(const vpKinematicChain &nominal, const vpSelfCalibDataset &dataset, const vpSelfCalibProtocol::Result &protocol);
    const vpKinematicChain &nominal;
    const vpSelfCalibDataset &dataset;
    const vpRobotSelfCalibration::Options &options;
    const vpRobotSelfCalibration::Result &result;
    const vpFeatureFrontEnd::Result *front_end = nullptr;
    const vpSelfCalibPoseStudy::Result *errors_vs_poses = nullptr;
    const vpSelfCalibCrossValidation::Result *cross_validation = nullptr;
    const vpSelfCalibCrossValidation::HeldOut *held_out = nullptr;
  };
  /*!
    Writes the report of `run` into `directory` (created if missing). Throws vpSelfCalibException
    when the directory cannot be written; a missing or failing gnuplot is reported in the result.
  */
  static Result write(const std::string &directory, const Record &run, const Options &report_options);
};

#endif
