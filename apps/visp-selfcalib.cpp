/*
 * visp-selfcalib: command-line tool of ViSP SelfCalib.
 *
 *   visp-selfcalib info      MODEL                 robot model summary and error-model parameters
 *   visp-selfcalib predict   MODEL [JOINTS_FILE]   fMc for each joint vector (one per line, rad;
 *                                                  from the file or standard input), printed as
 *                                                  one pose vector per line: tx ty tz tux tuy tuz
 *   visp-selfcalib plan      OUT.txt [options]     planned calibration poses of the reference scenario
 *   visp-selfcalib simulate  OUT.yaml [options]    a dataset of the reference scenario (observations)
 *   visp-selfcalib import    PATH --out OUT.yaml [options]
 *                                                  a dataset from a ViSP hand-eye folder or an
 *                                                  industrial_calibration cal_data.yaml
 *   visp-selfcalib calibrate DATASET --out DIR [options]
 *                                                  calibrated model, camera and results in DIR
 *   visp-selfcalib verify    MODEL DATASET         the paper's 3-D yardstick error of a model
 *   visp-selfcalib export    MODEL (--urdf OUT | --dh OUT | --mdh OUT)
 *                                                  URDF joint origins, or a corrected (modified) DH table
 * MODEL is a preset name (puma560, viper850) or a robot-model YAML file. The command lines are
 * CLI11's: 'visp-selfcalib COMMAND --help' lists a command's options.
 * Exit codes: 0 success, 1 bad input (message on stderr), 2 bad usage (unknown option, missing or
 * wrong value), 3 no trustworthy calibration (refused, failed or doubtful: calibrate's last line on stdout). Outputs are written
 * atomically and never over an input.
 *
 * This file declares the commands and dispatches to them; each command is in its own file
 * (commands.h).
 */
#include <iostream>
#include <new>
#include <string>

#include <visp3/core/vpConfig.h>
#include <visp3/core/vpException.h>

#include "acquireCommand.h"
#include "commands.h"
#include "selfcalibCli.h"

namespace
{
//! Every command's arguments, filled by the command line.
struct Args {
  ModelArgs info, predict, verify;
  PlanArgs plan;
  SimulateArgs simulate;
  AcquireArgs acquire;
  ImportArgs import;
  CalibrateArgs calibrate;
  ExportArgs exportArgs;
  CompareArgs compare;
};

//! The commands, in the order the help lists them.
void addCommands(CLI::App &app, Args &a)
{
  addInfo(app, a.info);
  addPredict(app, a.predict);
  addPlan(app, a.plan);
  addSimulate(app, a.simulate);
  addAcquire(app, a.acquire);
  addImport(app, a.import);
  addCalibrate(app, a.calibrate);
  addVerify(app, a.verify);
  addCompare(app, a.compare);
  addExport(app, a.exportArgs);
}

//! An unknown command: CLI11 would only say that a command is required. Returns true when it is one.
bool unknownCommand(const CLI::App &app, const std::string &name)
{
  std::string names;
  bool known = false;
  for (const CLI::App *sub : app.get_subcommands({})) {
    names += (names.empty() ? "" : ", ") + sub->get_name();
    known = known || sub->get_name() == name;
  }
  if (!known)
    std::cerr << "error: unknown command '" << name << "' (" << names << ")\n'" << kProgram
              << " --help' lists the commands.\n";
  return !known;
}

//! Runs the command the command line named.
int dispatch(const CLI::App &app, const Args &a)
{
  if (app.got_subcommand("simulate"))
    return simulate(a.simulate);
  if (app.got_subcommand("acquire"))
    return acquire(a.acquire);
  if (app.got_subcommand("import"))
    return importData(a.import);
  if (app.got_subcommand("calibrate"))
    return calibrate(a.calibrate);
  if (app.got_subcommand("export"))
    return exportModel(a.exportArgs);
  if (app.got_subcommand("plan"))
    return plan(a.plan);
  if (app.got_subcommand("verify"))
    return verify(a.verify);
  if (app.got_subcommand("compare"))
    return compare(a.compare);
  if (app.got_subcommand("info"))
    return info(a.info);
  return predict(a.predict);
}

int run(int argc, char **argv)
{
  CLI::App app("Self-calibration of a camera-equipped robot arm (ViSP SelfCalib): plan the poses, simulate or\n"
               "import a dataset, calibrate, verify, predict camera poses and export the calibrated model.",
               kProgram);
  app.require_subcommand(1);
  const std::string version = std::string(kProgram) + " " + VISP_SELFCALIB_VERSION_STRING + " (ViSP " +
                              std::to_string(VISP_VERSION_MAJOR) + "." + std::to_string(VISP_VERSION_MINOR) + "." +
                              std::to_string(VISP_VERSION_PATCH) + ")";
  app.set_version_flag("--version", version, "print the version and exit");
  app.footer("MODEL: " + modelHelp() + ". DATASET: a dataset YAML file (doc/formats.md).\n"
             "'visp-selfcalib COMMAND --help' describes a command and its options.\n"
             "Exit codes: 0 success, 1 bad input (message on stderr), 2 bad usage, 3 no trustworthy\n"
             "calibration: refused (data that cannot determine it) or doubtful (the model, written and marked,\n"
             "fails its checks); calibrate's last line says which and what to do.");
  Args args;
  addCommands(app, args);
  // 'COMMAND --version' prints the version too, before any required argument is asked for.
  for (CLI::App *sub : app.get_subcommands([](CLI::App *) { return true; }))
    sub->set_version_flag("--version", version, "print the version and exit");
  if (argc == 2 && std::string(argv[1]) == "help") {
    std::cout << app.help();
    return 0;
  }
  if (argc >= 2 && argv[1][0] != '-' && unknownCommand(app, argv[1]))
    return selfcalibCli::kUsageError;
  const int parsed = selfcalibCli::parse(app, argc, argv);
  if (parsed >= 0)
    return parsed;
  return dispatch(app, args);
}
} // namespace

int main(int argc, char **argv)
{
  try {
    return run(argc, argv);
  } catch (const vpException &e) {
    std::cerr << "error: " << e.getStringMessage() << "\n";
    return 1;
  } catch (const std::bad_alloc &) {
    std::cerr << "error: out of memory (an input too large for this machine?)\n";
    return 1;
  } catch (const CLI::ValidationError &e) {
    // Options that are valid one by one but not together, found after parsing: a usage error.
    std::cerr << "error: " << e.what() << "\n'visp-selfcalib COMMAND --help' lists the options.\n";
    return 2;
  } catch (const std::exception &e) {
    // Not one of the module's errors: a case its checks missed (please report it with the input).
    std::cerr << "error: unexpected failure: " << e.what() << "\n";
    return 1;
  }
}
