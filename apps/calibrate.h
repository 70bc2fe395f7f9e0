/*
 * visp-selfcalib calibrate: the pieces its files share (calibrateOptions.cpp: the command line and
 * the library options it gives, calibrateFrontEnd.cpp: its front-end part; calibrateChecks.cpp: the
 * options checked against the dataset and the method; calibrateDataChecks.cpp: the dataset checked
 * against the robot and the method; calibrateCommand.cpp: the run;
 * calibrateOutput.cpp: the output directory and what is printed).
 */
#ifndef VISP_SELFCALIB_CALIBRATE_H
#define VISP_SELFCALIB_CALIBRATE_H

#include <map>
#include <string>
#include <vector>

#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>
#include <visp3/selfcalib/vpSelfCalibFileWriter.h>
#include <visp3/selfcalib/vpSelfCalibImageCorrespondences.h>
#include <visp3/selfcalib/vpSelfCalibProtocol.h>

#include "commands.h"

//! calibrate's front-end options (dot grids, natural features, a board, a mask): calibrateFrontEnd.cpp.
void addFrontEndOptions(CLI::App *c, CalibrateArgs &a);
//! The front end's options from the command line (throws on a bad --mask image).
vpSelfCalibImageCorrespondences::Options frontEndOptions(const CalibrateArgs &a);
//! The calibration's options from the command line; CLI::ValidationError for options that disagree.
vpRobotSelfCalibration::Options calibrationOptions(const CalibrateArgs &a,
                                                   const vpSelfCalibImageCorrespondences::Options &co);

//! How many of the board's points (known_points' ids) the dataset's views observe (calibrateChecks.cpp).
size_t boardPointsObserved(const std::map<int, vpColVector> &layout, const vpSelfCalibDataset &ds);
//! The options of the full kinematic calibration only, refused with the hand-eye method (CLI::ValidationError).
void refuseBundleOptions(const CalibrateArgs &a);
//! --pose-sd T,R and --joint-sd into the noise model once the method is known.
void stateRobotError(const CalibrateArgs &a, vpRobotSelfCalibration::Options &po);
//! A misfit doubt on a run with fixed parameters: a doubt naming them put first (calibrateChecks.cpp).
void leadWithFixedParameters(vpRobotSelfCalibration::Result &r);
//! --fix / --free and the dataset's fix: / free: against the model's parameter names (usage errors).
void checkParameterLists(const vpKinematicChain &nominal, const vpSelfCalibDataset &ds,
                         const vpRobotSelfCalibration::Options &po, bool hand_eye, bool intrinsics_estimated);

//! The files a calibration reads: the dataset, its robot model file, camera XML and images.
std::vector<std::string> calibrationInputs(const std::string &dataset, const vpSelfCalibDataset &ds);
/*!
  Refuses an output directory that holds an input of the run, files that are not an earlier run's
  results (they would be lost with the earlier set), or an earlier run's results without --force.
  Returns 0 when the run may go on, else the exit code (1) after the message.
*/
int checkOutputDirectory(const vpSelfCalibOutputDirectory &outdir, const std::string &out,
                         const std::vector<std::string> &inputs, bool force);
/*!
  Refuses a --heldout dataset that is the calibration dataset or shares views with it (the same
  image, joints or controller pose): the check would not be independent. 0, or 1 after the message.
*/
int checkHeldout(const std::string &dataset, const vpSelfCalibDataset &ds, const std::string &heldout);
//! Refuses controller poses (fMe) beyond any robot's reach (units other than m): 0, or 1 after the message.
int checkControllerPoses(const std::string &dataset, const vpSelfCalibDataset &ds);
//! The flange's farthest distance from the base over the views (m; fMe, or the nominal model at the joints).
double armReach(const vpSelfCalibDataset &ds, const vpKinematicChain &nominal);
/*!
  Refuses a yardstick over ten times the arm's reach (armReach) or under a thousandth of it: a
  length in other units than m, which the adjustment would otherwise end on without naming it. 0,
  or 1 after the message.
*/
int checkYardstick(const std::string &dataset, const vpSelfCalibDataset &ds, const vpKinematicChain &nominal);
//! A note when the hand-eye method on controller poses uses none of the robot model's kinematics.
void noteRobotModel(const vpSelfCalibDataset &ds, vpRobotSelfCalibration::Method method);
/*!
  On a failed or doubtful run, or one whose yardstick was rejected: a note when the yardstick is longer than the arm's reach (a unit
  slip?), or when corrections beyond the tolerance may be its length's error (the scale it sets).
*/
void noteYardstickLength(const vpSelfCalibDataset &ds, const vpKinematicChain &nominal,
                         const std::vector<vpSelfCalibDataCheck::Finding> &findings);
//! Refuses a method that needs joints (bundle, paper) on views that give controller poses: 0, or 1 after the message.
int checkMethodData(vpRobotSelfCalibration::Method method, const vpSelfCalibDataset &ds);
/*!
  calibrate's last line on stdout: "status: ok" (", with N warnings (CODES): ..." when there are
  warnings), "status: doubtful: WHY (and N more checks failed); ... what to do" or "status:
  refused: STATUS: WHY" (the message says what to do).
*/
void printStatus(const vpRobotSelfCalibration::Result &r, bool calibrated, size_t report_warnings = 0);
//! The protocol's figures on stdout, one line each.
void printProtocol(const vpSelfCalibProtocol::Result &p);
//! calibrate's summary on stdout: what was estimated, eMc with its sd, the residuals, the intrinsics.
void printSummary(const vpRobotSelfCalibration::Result &r, unsigned int num_calibration);
//! When the data left parameters at nominal: the plan --from command that proposes the poses to add.
void printAddPoses(const vpRobotSelfCalibration::Result &r, const std::string &dataset);

#endif
