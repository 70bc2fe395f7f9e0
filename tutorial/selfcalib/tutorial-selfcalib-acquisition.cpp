/*!
  \example tutorial-selfcalib-acquisition.cpp

  From a robot to a calibrated model: plan -> acquire -> calibrate -> export, on ViSP's simulated
  Viper850 (vpSimulatorViper850, headless) with a grabber that renders what its camera sees.

  On a real arm, exactly two objects change (marked "SWAP" below):
    1. the robot: vpSelfCalibSimulatorViper850 -> your vpRobot (vpRobotViper850, vpRobotFranka,
       vpRobotUniversalRobots, ...), with its nominal model (a preset, a robot-model YAML or its
       URDF: vpKinematicChain::fromPresetOrFile("robot.urdf"));
    2. the grabber: vpSelfCalibSimulatedGrabber -> your camera's vpFrameGrabber (vp1394TwoGrabber,
       vpV4l2Grabber, vpRealSense2 through a callback...).
  Everything else (the acquisition, the dataset file, the calibration, the export) is the same.

    tutorial-selfcalib-acquisition [--dir DIR] [--seed N] [--poses N] [--held-out N]

  The same steps with the command-line tool:
    visp-selfcalib plan plan.txt
    visp-selfcalib acquire run/dataset.yaml --plan plan.txt     # run again to resume after an interruption
    visp-selfcalib calibrate run/dataset.yaml --out result
    visp-selfcalib export result/model.yaml --urdf robot.urdf
*/
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <string>
#include <vector>

#include <visp3/selfcalib/vpCalibrationVerifier.h>
#include <visp3/selfcalib/vpMeasurementPlanner.h>
#include <visp3/selfcalib/vpModelExport.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibAcquisition.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibImageCorrespondences.h>
#include <visp3/selfcalib/vpSelfCalibRenderer.h>
#include <visp3/selfcalib/vpSelfCalibResultsFile.h>
#include <visp3/selfcalib/vpSelfCalibSimulatedGrabber.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>
#include <visp3/selfcalib/vpSelfCalibSimulatorViper850.h>

#include "selfcalibCli.h"

namespace fs = std::filesystem;

int main(int argc, char **argv)
{
  std::string dir = "selfcalib-acquisition";
  unsigned long long seed = 1;
  unsigned int poses = 15, held_out = 10;
  CLI::App app("plan -> acquire -> calibrate -> export on ViSP's simulated Viper850 (the robot and the grabber are\n"
               "the two classes a real set-up replaces).",
               "tutorial-selfcalib-acquisition");
  app.add_option("--dir", dir, "output directory (default selfcalib-acquisition; an acquisition there is resumed)")
      ->type_name("DIR");
  app.add_option("--seed", seed, "scenario seed (default 1)")->type_name("N")->check(selfcalibCli::wholeNumber());
  app.add_option("--poses", poses, "calibration poses (default 15)")->type_name("N")->check(selfcalibCli::wholeNumber(6));
  app.add_option("--held-out", held_out, "held-out poses (default 10)")->type_name("N")->check(selfcalibCli::wholeNumber(2));
  const int parsed = selfcalibCli::parse(app, argc, argv);
  if (parsed >= 0)
    return parsed;
  try {
    // SWAP 1: the robot. Any vpRobot that moves in vpRobot::ARTICULAR_FRAME and reads its joints back.
    vpSelfCalibSimulatorViper850 robot;
    const vpKinematicChain nominal = robot.getNominalChain();

    // The simulated world (true robot with seeded errors, the scene): on a real set-up, the world.
    vpSelfCalibSimulator::Options so;
    so.seed = seed;
    const vpSelfCalibSimulator sim(nominal, so);
    vpSelfCalibRenderer::Options ro;
    ro.seed = seed;
    const vpSelfCalibRenderer renderer(sim, ro);

    // SWAP 2: the grabber. Any vpFrameGrabber (or a callback filling a vpImage<unsigned char>).
    vpSelfCalibSimulatedGrabber grabber(robot, renderer);

    // 1. Plan: the observability-optimal calibration poses from a pool of feasible ones, then random
    //    held-out poses (here the pool comes from the simulated scene; on a real set-up from the
    //    scene's rough position in front of the robot, as visp-selfcalib plan does).
    const std::vector<vpColVector> pool = sim.generateConfigurations(poses + held_out + 60);
    std::vector<vpColVector> candidates(pool.begin(), pool.begin() + poses);
    candidates.insert(candidates.end(), pool.begin() + poses + held_out, pool.end());
    const vpMeasurementPlanner planner(nominal, sim.getPlannerScene());
    const vpMeasurementPlanner::Result pr = planner.selectObservable(candidates, poses);
    if (pr.status != vpMeasurementPlanner::OK) {
      std::cerr << "planning failed: " << pr.message << "\n";
      return 3;
    }
    std::vector<vpColVector> plan = pr.configurations;
    plan.insert(plan.end(), pool.begin() + poses, pool.begin() + poses + held_out);
    std::cout << "== Plan: " << poses << " calibration poses (O1 " << std::setprecision(4) << pr.observability_before.O1
              << " -> " << pr.observability_after.O1 << "), " << held_out << " held-out poses\n";

    // 2. Acquire: visit the plan, record the joints reached and the images, write the dataset as it
    //    goes (run again after an interruption: it resumes).
    fs::create_directories(dir);
    const std::string robot_file = (fs::absolute(dir) / "robot.yaml").string();
    nominal.saveYaml(robot_file);
    vpSelfCalibAcquisition::Options ao;
    ao.dataset_file = (fs::path(dir) / "dataset.yaml").string();
    ao.header = sim.makeDataset({}); // the camera: its intrinsics (camera XML on a real set-up)
    ao.header.robot = robot_file;
    ao.header.yardstick.length = renderer.getYardstickLength(); // its two dots are found in the images
    ao.header.yardstick.id_a = ao.header.yardstick.id_b = -1;
    ao.calibration_poses = poses;
    ao.settle_time = 0; // a real arm: the time it takes to stop vibrating, e.g. 0.5 s
    vpSelfCalibAcquisition acquisition(robot, nominal, grabber, ao);
    const vpSelfCalibAcquisition::Result ar =
        acquisition.run(plan, [](unsigned int done, unsigned int total, const std::string &) {
          std::cerr << "   ... acquired " << done << "/" << total << "\r" << std::flush;
        });
    std::cerr << "\n";
    if (ar.status != vpSelfCalibAcquisition::OK) {
      std::cerr << "acquisition stopped: " << ar.message << " (run again to resume)\n";
      return EXIT_FAILURE;
    }
    std::cout << "== Acquisition: " << ar.total << " poses in " << ao.dataset_file << " (" << ar.resumed
              << " resumed), joint travel " << std::setprecision(3) << ar.travel << " rad instead of "
              << ar.travel_plan_order << " in plan order\n";

    // 3. Calibrate the dataset file (what visp-selfcalib calibrate does): image front end, then the
    //    default pipeline on the calibration poses.
    vpSelfCalibDataset ds = vpSelfCalibDataset::loadYaml(ao.dataset_file);
    const vpKinematicChain model = vpKinematicChain::fromPresetOrFile(ds.robot);
    const std::vector<vpSelfCalibDataset::View> acquired = ds.views;
    vpSelfCalibImageCorrespondences::Options co;
    const vpSelfCalibImageCorrespondences::Result cr = vpSelfCalibImageCorrespondences::fromDatasetImages(ds, co);
    if (!cr.dropped.empty()) {
      std::cerr << "some views had no correspondence: this tutorial expects all of them\n";
      return EXIT_FAILURE;
    }
    vpRobotSelfCalibration::Options po;
    po.method = cr.method;
    po.num_calibration_poses = poses;
    const vpRobotSelfCalibration::Result r = vpRobotSelfCalibration::run(model, ds, po);
    // The run's results.yaml, in the schema visp-selfcalib calibrate writes (the split: the first
    // poses calibrate, the others verify).
    vpSelfCalibProtocol::Result split;
    split.plan.calibration = poses;
    split.plan.held_out = static_cast<unsigned int>(ds.views.size()) - poses;
    vpSelfCalibResultsFile::write((fs::path(dir) / "results.yaml").string(),
                                  vpSelfCalibResultsFile::fromRun(r, model, ao.dataset_file, split));
    std::cout << "== Calibration: " << vpRobotSelfCalibration::statusName(r.status) << ", "
              << r.identifiability.identified.size() << " of " << model.getNumParameters() << " parameters, "
              << cr.front_end.num_tracks << " tracks\n";
    if (r.status != vpRobotSelfCalibration::OK) {
      std::cerr << r.message << "\n";
      return 3;
    }

    // Held-out check against the simulated truth (on a real set-up: visp-selfcalib verify, the
    // yardstick's 3-D error on held-out views).
    const std::vector<vpSelfCalibDataset::View> ver(acquired.begin() + poses, acquired.end());
    const std::vector<vpSelfCalibDataset::View> ver_data(ds.views.begin() + poses, ds.views.end());
    const std::vector<vpHomogeneousMatrix> true_fMc = sim.getTrueCameraPoses(ver);
    const auto before = vpCalibrationVerifier::verify(model, ds.cam, ver_data, ds.yardstick, {}, true_fMc);
    const auto after = vpCalibrationVerifier::verify(r.calibrated, r.camera, ver_data, ds.yardstick, {}, true_fMc);
    std::cout << "== Verification on " << ver.size() << " held-out poses     nominal   calibrated\n"
              << std::fixed << std::setprecision(3) << "   yardstick 3-D error [mm]        " << std::setw(10)
              << 1e3 * before.yardstick_error << std::setw(12) << 1e3 * after.yardstick_error << "\n"
              << "   relative pose error, mean [mm]  " << std::setw(10) << 1e3 * before.position_error_mean
              << std::setw(12) << 1e3 * after.position_error_mean << "\n"
              << "   relative pose error, mean [mrad]" << std::setw(10) << 1e3 * before.rotation_error_mean
              << std::setw(12) << 1e3 * after.rotation_error_mean << "\n";

    // 4. Export: the calibrated model as robot-model YAML and as URDF joint origins.
    r.calibrated.saveYaml((fs::path(dir) / "model.yaml").string());
    vpModelExport::saveURDF(r.calibrated, (fs::path(dir) / "model.urdf").string());
    std::cout << "== Export: " << dir << "/model.yaml, " << dir << "/model.urdf\n";
    return EXIT_SUCCESS;
  } catch (const vpException &e) {
    std::cerr << "error: " << e.getStringMessage() << "\n";
    return EXIT_FAILURE;
  }
}
