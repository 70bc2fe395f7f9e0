/*
 * visp-selfcalib acquire: a dataset acquired through a robot (vpRobot) and a grabber
 * (vpFrameGrabber) with vpSelfCalibAcquisition. Here the robot is ViSP's simulated Viper850 and
 * the grabber renders what its camera sees; on a real set-up these two objects are replaced.
 */
#ifndef VISP_SELFCALIB_ACQUIRE_COMMAND_H
#define VISP_SELFCALIB_ACQUIRE_COMMAND_H

#include <string>

#include <CLI/CLI.hpp>

struct AcquireArgs {
  std::string out, plan, focal = "known";
  unsigned long long seed = 1;
  unsigned int calibration = 0, fail_at = 0; // calibration 0: not given (15, or the whole plan when shorter)
  double settle = 0;
};

//! Declares the acquire command and its options.
void addAcquire(CLI::App &app, AcquireArgs &a);
//! Runs it: 0 done, 1 bad input or a robot / image failure (the dataset so far kept).
int acquire(const AcquireArgs &a);

#endif
