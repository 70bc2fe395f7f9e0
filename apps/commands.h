/*
 * visp-selfcalib: the commands of the tool (one file each, COMMANDCommand.cpp) and what they share.
 * Each command has its arguments (a struct the CLI11 options fill), an add function that declares
 * it on the application and a function that runs it and returns the exit code: 0 success, 1 bad
 * input (message on stderr), 3 the command's work failed (message on stderr); usage errors (2) are
 * CLI11's. The acquire command is in acquireCommand.h.
 */
#ifndef VISP_SELFCALIB_COMMANDS_H
#define VISP_SELFCALIB_COMMANDS_H

#include <algorithm>
#include <filesystem>
#include <initializer_list>
#include <istream>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>

#include <visp3/core/vpColVector.h>
#include <visp3/selfcalib/vpKinematicBundleAdjustment.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

// ---------------------------------------------------------------------------------------------
// Shared by the commands (commandCommon.cpp)

extern const char *const kProgram;  //!< the program's name, in messages
//! The presets' names, from the code ("puma560, viper850, ..."), for the help.
std::string presetList();
//! The help of a MODEL argument (the presets from the code).
std::string modelHelp();

/*!
  Joint vectors of `n` values, one per line (rad, spaces or commas, '#' comments), from `file` (""
  or "-": standard input), `what` naming it in messages ("joints file"). A file is read whole by
  vpSelfCalibTextFile::read() (at most 64 MiB, a FIFO without a writer refused); then, as standard
  input, with bounds counted while reading (a line of at most 64 KiB, at most 100000 vectors,
  values within 1000 rad): an input without end (/dev/zero) is refused at once. Throws
  vpSelfCalibException with the file, the line and the reason.
*/
std::vector<vpColVector> readJoints(const std::string &file, const std::string &what, unsigned int n);
//! Canonical path of an existing file or directory, or "" when it does not exist.
std::string canonical(const std::string &p);
//! The same view: the same image file, or the same joints (or, without joints, controller pose) to 1e-12.
bool sameView(const vpSelfCalibDataset::View &a, const vpSelfCalibDataset::View &b);
//! Whether every view gives a controller pose and none its joints (the hand-eye method then uses no kinematics).
bool controllerPosesOnly(const vpSelfCalibDataset &ds);
/*!
  True, with the error on stderr, when `out` may not be written: a device node, a FIFO or a socket
  (or a link to one) or a directory, --force or not; or an existing file without `force`.
*/
bool outputRefused(const std::string &out, bool force);
//! Creates a directory unless it exists; false when that fails.
bool makeDirectory(const std::filesystem::path &dir);
//! The names of focal modes, as the command lines spell them.
std::vector<std::string> focalNames(std::initializer_list<vpRobotSelfCalibration::FocalMode> modes);
//! --robot NAME: a preset or a robot-model file (YAML or URDF).
CLI::Option *addRobotOption(CLI::App &app, std::string &robot);
/*!
  The MODEL of export, verify and predict: vpKinematicChain::fromPresetOrFile(), and a model.yaml
  that an eye-to-hand calibrate wrote before the model file had `camera_mount` (bMc under the key
  eMc: its results.yaml beside it has a bMc block) refused with how to convert it, so that a bMc is
  never used as an eMc. Throws vpSelfCalibException.
*/
vpKinematicChain readModelArgument(const std::string &model);

// ---------------------------------------------------------------------------------------------
// info, predict, verify: a model, and a joints file or a dataset

struct ModelArgs {
  std::string model, second; //!< predict: the joints file; verify: the dataset
};
void addInfo(CLI::App &app, ModelArgs &a);
int info(const ModelArgs &a);
void addPredict(CLI::App &app, ModelArgs &a);
int predict(const ModelArgs &a);
void addVerify(CLI::App &app, ModelArgs &a);
int verify(const ModelArgs &a);

//! compare RESULT_DIR TRUTH.yaml: a result against the truth of a simulation.
struct CompareArgs {
  std::string result, truth, joints, yaml;
  unsigned int pairs = 1000;
  bool force = false;
};
void addCompare(CLI::App &app, CompareArgs &a);
int compare(const CompareArgs &a);

// ---------------------------------------------------------------------------------------------
// plan, simulate

struct PlanArgs {
  std::string out, robot = "viper850", method = "observability";
  vpSelfCalibSimulator::Options so;
  unsigned int poses = 0, held_out = 10; //!< poses 0: not given (15 planned; with --from, as many as needed)
  bool force = false;
  bool out_given = false;               //!< OUT.txt on the command line (even empty)
  std::string from, out_file;           //!< --from DATASET, --out FILE
  std::vector<double> tolerance;        //!< --tolerance (with --from)
};
void addPlan(CLI::App &app, PlanArgs &a);
int plan(const PlanArgs &a);
//! plan --from DATASET: the poses to add to a dataset's views (planFromCommand.cpp).
int planFrom(const PlanArgs &a);

struct SimulateArgs {
  std::string out, robot = "viper850", focal = "known", target = "textured", joints_file, camera_mount = "effector";
  vpSelfCalibSimulator::Options so;
  double pose_sd = 0; //!< eye-to-hand: the controller poses' error (m and rad)
  bool with_joints = false; //!< eye-to-hand: the target carried by --robot's arm, joint readings written
  double joint_sd = 0;      //!< eye-to-hand with joints: the joint readings' error (rad)
  unsigned int poses = 25;
  bool force = false, controller = false, images = false;
};
void addSimulate(CLI::App &app, SimulateArgs &a);
int simulate(const SimulateArgs &a);

// ---------------------------------------------------------------------------------------------
// import, export

struct ImportArgs {
  std::string path, out, robot, intrinsics;
  bool force = false;
};
void addImport(CLI::App &app, ImportArgs &a);
int importData(const ImportArgs &a);

struct ExportArgs {
  std::string model, urdf, dh, mdh;
  bool force = false;
};
void addExport(CLI::App &app, ExportArgs &a);
int exportModel(const ExportArgs &a);

// ---------------------------------------------------------------------------------------------
// calibrate (calibrateOptions.cpp, calibrateCommand.cpp, calibrateOutput.cpp)

struct CalibrateArgs {
  std::string dataset, out, method, focal = "auto";
  unsigned int calibration = 0;
  std::string pixel_sd = "auto";
  std::vector<double> tolerance; //!< links (m, rad), then optionally eMc (m, rad)
  unsigned int holdout = 0;       //!< --holdout N: the last N views verify (0: none)
  unsigned int folds = 5;         //!< --folds K: k-fold cross-validation (0: none)
  bool folds_given = false;
  std::string heldout;            //!< --heldout FILE: a second dataset to verify on
  std::vector<std::string> pose_sd; //!< robot pose error (m, rad) of controller poses, or "auto"; empty: exact
  std::vector<double> joint_sd; //!< joint-reading noise (rad), one or one per joint; empty: exact or measured
  bool joint_sd_auto = false;   //!< --joint-sd auto: measured (the default)
  std::vector<std::string> estimate; //!< intrinsics estimated beside f: aspect, pp, distortion
  std::vector<std::string> fix, free; //!< kinematic parameters (names or glob patterns) kept nominal / freed
  std::string kinematic_prior;  //!< off, tolerance, tolerance/K or K (the prior's sd: the tolerance / K); empty: not said
  int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::vector<std::string> dot_grids;
  bool no_features = false;
  std::string board;
  bool board_geometry = false; //!< the board's layout as a prior on its points
  double board_sd = vpKinematicBundleAdjustment::Options().known_points_sd; //!< m, each board point's placement
  bool with_features = false;
  bool mask_board = false;     //!< the board only masked out: natural features alone
  std::string mask;            //!< an image: where its pixels are 0, no feature is looked for
  bool force = false; //!< replace an earlier run's results in --out
};
void addCalibrate(CLI::App &app, CalibrateArgs &a);
int calibrate(const CalibrateArgs &a);

#endif
