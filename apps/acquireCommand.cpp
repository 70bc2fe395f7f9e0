/*
 * visp-selfcalib acquire (see acquireCommand.h).
 */
#include "acquireCommand.h"
#include "commands.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <vector>

#include <visp3/selfcalib/vpSelfCalibAcquisition.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibRenderer.h>
#include <visp3/selfcalib/vpSelfCalibSimulatedGrabber.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>
#include <visp3/selfcalib/vpSelfCalibSimulatorViper850.h>

#include "selfcalibCli.h"

namespace fs = std::filesystem;

namespace
{
// The simulated Viper850; --fail-at makes its controller fail at one move (to see the error path).
class SimulatedViper : public vpSelfCalibSimulatorViper850
{
public:
  unsigned int fail_at = 0, moves = 0;
  using vpSelfCalibSimulatorViper850::setPosition;
  void setPosition(const vpRobot::vpControlFrameType frame, const vpColVector &q) override
  {
    if (++moves == fail_at)
      throw vpRobotException(vpRobotException::communicationError,
                             "simulated controller fault at move " + std::to_string(moves));
    vpSelfCalibSimulatorViper850::setPosition(frame, q);
  }
};

// Joint vectors, one per line ('#' comments, spaces or commas), as `visp-selfcalib plan` writes them.
std::vector<vpColVector> readPlan(const std::string &file, unsigned int n)
{
  const std::vector<vpColVector> out = readJoints(file, "plan", n);
  if (out.empty())
    throw vpSelfCalibException(vpSelfCalibException::badValue, "plan '" + file + "' has no configuration");
  return out;
}
//! acquire --settle: beyond ten minutes a move's wait is a mistake (1e9 s would wait for decades).
constexpr double kMaxSettleSeconds = 600;
} // namespace

void addAcquire(CLI::App &app, AcquireArgs &a)
{
  CLI::App *c = app.add_subcommand("acquire", "a dataset acquired through a robot and a camera (simulated Viper850)");
  c->footer("Drives ViSP's simulated Viper850 (vpSimulatorViper850, headless) through the plan's configurations in a\n"
            "short-travel order (calibration poses first), reads its joints back and grabs what its camera sees\n"
            "(rendered scene of the reference scenario), writing OUT.yaml, robot.yaml and images/ beside it after\n"
            "every pose. Run again after an interruption: it resumes where it stopped. Then: calibrate OUT.yaml.");
  c->add_option("OUT.yaml", a.out, "the dataset file (resumed when it exists)")->type_name("FILE")->required();
  c->add_option("--plan", a.plan, "joint configurations, one per line (visp-selfcalib plan)")
      ->type_name("FILE")
      ->required();
  c->add_option("--seed", a.seed, "scenario seed: the true robot's errors, the scene (default 1)")
      ->type_name("N")
      ->check(selfcalibCli::wholeNumber());
  c->add_option("--calibration", a.calibration,
                "the plan's first N poses are calibration poses, visited before the others, 1 to the\n"
                "plan's size (default 15, or the whole plan when it is shorter)")
      ->type_name("N")
      ->check(selfcalibCli::wholeNumber(1, 100000));
  c->add_option("--focal", a.focal, "known (default: px, py in the dataset) or shared (f to be self-calibrated)")
      ->type_name("MODE")
      ->check(CLI::IsMember({"known", "shared"}));
  c->add_option("--settle", a.settle, "seconds to wait after each move, at most 600 (default 0)")
      ->type_name("S")
      ->check(selfcalibCli::number(0, false, kMaxSettleSeconds));
  c->add_option("--fail-at", a.fail_at, "make the simulated controller fail at move N (tests the error path)")
      ->type_name("N")
      ->check(selfcalibCli::wholeNumber(1));
}

int acquire(const AcquireArgs &a)
{
  // 1. The robot: ViSP's simulated Viper850. On a real arm: the robot's vpRobot (vpRobotViper850,
  //    vpRobotFranka, vpRobotUniversalRobots...) and its nominal model (a preset, YAML or URDF).
  SimulatedViper robot;
  robot.fail_at = a.fail_at;
  const vpKinematicChain nominal = robot.getNominalChain();
  // The simulated world: the true robot (nominal + seeded errors) and the scene the camera sees.
  vpSelfCalibSimulator::Options so;
  so.seed = a.seed;
  const vpSelfCalibSimulator sim(nominal, so);
  vpSelfCalibRenderer::Options ro;
  ro.seed = a.seed;
  const vpSelfCalibRenderer renderer(sim, ro);
  // 2. The grabber: renders what the camera sees. On a real arm: the camera's vpFrameGrabber.
  vpSelfCalibSimulatedGrabber grabber(robot, renderer);

  const std::vector<vpColVector> plan = readPlan(a.plan, nominal.getNumJoints());
  const unsigned int calibration =
      a.calibration ? a.calibration : std::min(15u, static_cast<unsigned int>(plan.size()));
  if (calibration > plan.size()) {
    std::cerr << "error: --calibration " << a.calibration << ": the plan '" << a.plan << "' has " << plan.size()
              << " poses; give at most " << plan.size() << "\n";
    return 1;
  }
  const fs::path parent = fs::path(a.out).parent_path();
  const fs::path dir = parent.empty() ? fs::path(".") : parent;
  std::error_code ec;
  fs::create_directories(dir, ec);
  const fs::path robot_file = dir / "robot.yaml";
  nominal.saveYaml(robot_file.string());

  vpSelfCalibAcquisition::Options o;
  o.dataset_file = a.out;
  o.header = sim.makeDataset({});
  o.header.robot = fs::absolute(robot_file).lexically_normal().string();
  o.header.yardstick.length = renderer.getYardstickLength(); // its dots are found in the images
  o.header.yardstick.id_a = o.header.yardstick.id_b = -1;
  if (a.focal == "shared") {
    o.header.focal_known = false;
    o.header.cam.initPersProjWithoutDistortion(0.93 * so.px, 0.93 * so.py, so.u0, so.v0);
  }
  o.calibration_poses = calibration;
  o.settle_time = a.settle;
  vpSelfCalibAcquisition acquisition(robot, nominal, grabber, o);
  const vpSelfCalibAcquisition::Result r =
      acquisition.run(plan, [](unsigned int done, unsigned int total, const std::string &what) {
        std::cerr << done << "/" << total << ": " << what << "\n";
      });
  if (r.status != vpSelfCalibAcquisition::OK) {
    std::cerr << "error: " << vpSelfCalibAcquisition::statusName(r.status) << ": " << r.message
              << "\n(run the same command again to resume)\n";
    return 1;
  }
  std::cout << "wrote " << a.out << ": " << r.total << " poses (" << r.resumed << " resumed, " << r.acquired
            << " acquired), joint travel " << r.travel << " rad (plan order " << r.travel_plan_order << " rad)\n";
  return 0;
}
