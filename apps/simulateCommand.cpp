/*
 * visp-selfcalib simulate: a dataset of the reference scenario (observations, or rendered images) and
 * the truth it was simulated from (see simulate.h).
 */
#include "simulate.h"

#include <unistd.h>

#include <algorithm>
#include <functional>
#include <fstream>
#include <iomanip>
#include <memory>
#include <iostream>
#include <random>
#include <sstream>

#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>
#include <visp3/selfcalib/vpSelfCalibFileWriter.h>
#include <visp3/selfcalib/vpSelfCalibRenderer.h>

#include "selfcalibCli.h"

#include <yaml-cpp/yaml.h>

namespace fs = std::filesystem;

namespace
{
//! simulate --poses: more would take hours (each pose is searched for by inverse kinematics).
constexpr unsigned long long kMaxSimulatedPoses = 10000;
/*
  The truth the dataset was simulated from, beside it (STEM-truth.yaml): the true and the nominal
  robot models (robot-model YAML, as text), the true camera and the scene points (id, x, y, z in
  f, m). Read by `compare`. Returns the file's name.
*/
std::string writeTruth(const vpSelfCalibSimulator &sim, const std::string &out, const vpSelfCalibDataset &ds)
{
  const fs::path file = fs::path(out).parent_path() / (fs::path(out).stem().string() + "-truth.yaml");
  const vpCameraParameters cam = sim.getCamera();
  YAML::Emitter y;
  y << YAML::Comment("The truth " + std::string(kProgram) + " simulate used for " + fs::path(out).filename().string() +
                     " (read by " + kProgram + " compare)");
  y << YAML::BeginMap << YAML::Key << "truth_of" << YAML::Value << fs::path(out).filename().string();
  y << YAML::Key << "camera" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "width" << YAML::Value
    << ds.width << YAML::Key << "height" << YAML::Value << ds.height << YAML::Key << "px" << YAML::Value
    << cam.get_px() << YAML::Key << "py" << YAML::Value << cam.get_py() << YAML::Key << "u0" << YAML::Value
    << cam.get_u0() << YAML::Key << "v0" << YAML::Value << cam.get_v0() << YAML::EndMap;
  y << YAML::Key << "true_model" << YAML::Value << YAML::Literal << sim.getTrueChain().toYamlString();
  y << YAML::Key << "nominal_model" << YAML::Value << YAML::Literal << sim.getNominalChain().toYamlString();
  y << YAML::Key << "points" << YAML::Value << YAML::BeginSeq;
  for (const auto &pt : sim.getScenePointsById())
    y << YAML::Flow << YAML::BeginSeq << pt.first << pt.second[0] << pt.second[1] << pt.second[2] << YAML::EndSeq;
  y << YAML::EndSeq << YAML::EndMap;
  vpSelfCalibFileWriter::write(file.string(), std::string(y.c_str()) + "\n", "truth");
  return file.string();
}

} // namespace

void addSimulate(CLI::App &app, SimulateArgs &a)
{
  CLI::App *c = app.add_subcommand("simulate", "a dataset of the reference scenario (observations or images)");
  c->footer("Writes a dataset of the reference scenario (simulated robot with seeded errors, scene, yardstick).");
  c->add_option("OUT.yaml", a.out, "the dataset file to write")->type_name("FILE")->required();
  addRobotOption(*c, a.robot);
  c->add_option("--seed", a.so.seed, "scenario seed (default 1)")->type_name("N")->check(selfcalibCli::wholeNumber());
  CLI::Option *poses = c->add_option("--poses", a.poses, "random feasible poses, 3 to 10000 (default 25)")
                           ->type_name("N")
                           ->check(selfcalibCli::wholeNumber(3, kMaxSimulatedPoses));
  c->add_option("--joints", a.joints_file, "the poses of a plan (visp-selfcalib plan) instead of random ones")
      ->type_name("FILE")
      ->excludes(poses);
  c->add_option("--noise", a.so.pixel_noise_sd, "image noise sd (default 0.2)")
      ->type_name("PX")
      ->check(selfcalibCli::number(0, false, 100));
  c->add_option("--focal", a.focal, "known (default: px, py in the file) or shared (f to be self-calibrated)")
      ->type_name("MODE")
      ->check(CLI::IsMember(focalNames({vpRobotSelfCalibration::FOCAL_KNOWN, vpRobotSelfCalibration::FOCAL_SHARED})));
  c->add_flag("--controller-poses", a.controller,
              "the true end-effector poses fMe instead of joints (hand-eye datasets)");
  c->add_flag("--images", a.images,
              "render the images and write no points (calibrate then runs the image front\n"
              "end): they go to a directory of the run's own beside OUT.yaml, OUT-images-XXXXXXXX/,\n"
              "written before the dataset that points at them (a run stopped at any moment leaves\n"
              "the earlier dataset and its images as they were); the earlier run's images are\n"
              "removed once the new dataset is in place");
  c->add_option("--target", a.target,
                "textured (default: photographs on two planes, natural features), dots (the\n"
                "paper's experiment: dot grids 4x5 and 4x9 on the two planes; calibrate with\n"
                "--dot-grids 4x5,4x9 --no-features), charuco (a ChArUco board of 7 x 5 squares\n"
                "of 2 cm, markers 1.5 cm, DICT_6X6_250, facing the home view; calibrate with\n"
                "--board charuco:7x5:0.02:0.015:DICT_6X6_250) or apriltags (tags 0-3 of 36h11,\n"
                "4 cm, 6 cm apart; OUT's directory/tags.yaml describes them: calibrate with\n"
                "--board apriltag-bundle:DIR/tags.yaml). All but textured need --images")
      ->type_name("T")
      ->check(CLI::IsMember({"textured", "dots", "charuco", "apriltags"}));
  c->add_option("--camera-mount", a.camera_mount,
                 "effector (default: the reference scenario) or world: a camera fixed in the world and a\n"
                 "6 x 5 board (2 cm, the layout of --board chessboard:5x6:0.02, rows x cols) on the tool, points data\n"
                 "(calibrate --method hand-eye --board chessboard:5x6:0.02 --board-geometry); with --images\n"
                 "--target charuco|apriltags: that board on the tool, its plate and last link textured, seen\n"
                 "by a 1280 x 720 camera (calibrate --method hand-eye --board ... --board-geometry)")
      ->type_name("MOUNT")
      ->check(CLI::IsMember({"effector", "world"}));
  c->add_option("--pose-sd", a.pose_sd, "with --camera-mount world: the controller poses' error sd (m and rad, default 0)")
      ->type_name("SD")
      ->check(CLI::Range(0.0, 0.1));
  c->add_flag("--with-joints", a.with_joints,
              "with --camera-mount world, points data: the board is carried by --robot's simulated arm (seeded\n"
              "errors), each view has its joint readings (data for --method bundle or hand-eye)");
  c->add_option("--joint-sd", a.joint_sd, "with --with-joints: the joint readings' error sd (rad, default 0)")
      ->type_name("RAD")
      ->check(CLI::Range(0.0, 0.1));
  c->add_flag("--force", a.force, "replace an existing OUT.yaml");
  c->final_callback([&a] {
    if (a.target != "textured" && !a.images)
      throw CLI::ValidationError("--target", a.target + " renders images: add --images");
  });
}

int simulate(const SimulateArgs &a)
{
  const std::string &out = a.out;
  const vpSelfCalibSimulator::Options &so = a.so;
  unsigned int poses = a.poses;
  if (outputRefused(out, a.force))
    return 1;
  std::error_code ec;
  const fs::path out_dir = fs::path(out).parent_path();
  if (!out_dir.empty() && !fs::is_directory(out_dir, ec)) {
    std::cerr << "error: '" << out << "': its directory '" << out_dir.string() << "' is not there\n";
    return 1;
  }
  // One run per dataset at a time (a lock beside it, released when the run ends, killed or not):
  // two runs into one stem would pair one run's dataset with the other's truth.
  std::unique_ptr<vpSelfCalibOutputDirectory> run_lock;
  try {
    run_lock = std::make_unique<vpSelfCalibOutputDirectory>(
        (out_dir / (fs::path(out).stem().string() + "-simulate")).string());
  } catch (const vpException &e) {
    if (e.getStringMessage().find("is being written by another run") == std::string::npos)
      throw;
    std::cerr << "error: '" << out << "' is being written by another simulate run: wait for it to end, or "
              << "write elsewhere\n";
    return 1;
  }
  if (a.camera_mount != "world" && (a.with_joints || a.joint_sd > 0))
    throw CLI::ValidationError(a.with_joints ? "--with-joints" : "--joint-sd",
                               "joint readings with a board on the tool are simulated with --camera-mount world only "
                               "(an eye-in-hand dataset always has its joints, exact)");
  if (a.camera_mount != "world" && a.pose_sd > 0)
    throw CLI::ValidationError("--pose-sd", "the controller poses' error is simulated with --camera-mount world only "
                                            "(a camera on the effector: the robot's errors are in its true model)");
  if (a.camera_mount == "world" && a.images)
    return simulateEyeToHandImages(a);
  if (a.camera_mount == "world")
    return simulateEyeToHand(a);
  const vpSelfCalibSimulator sim(vpKinematicChain::fromPresetOrFile(a.robot), so);
  std::vector<vpColVector> configurations;
  if (!a.joints_file.empty()) {
    // The given configurations (a plan), each checked for joint limits and visibility.
    configurations = readJoints(a.joints_file, "joints file", sim.getNominalChain().getNumJoints());
    for (size_t k = 0; k < configurations.size(); ++k)
      if (!sim.getNominalChain().isInJointLimits(configurations[k]) || !sim.isVisible(configurations[k])) {
        std::cerr << "error: " << a.joints_file << ": configuration " << k + 1
                  << " is outside the joint limits or does not see the whole scene\n";
        return 1;
      }
    if (configurations.size() < 3) {
      std::cerr << "error: " << a.joints_file << ": at least 3 configurations are needed\n";
      return 1;
    }
    poses = static_cast<unsigned int>(configurations.size());
  } else {
    // Progress on a terminal only, rewritten in place; nothing in a pipe or a log.
    const bool tty = ::isatty(STDERR_FILENO) != 0;
    configurations = sim.generateConfigurations(poses, [tty](unsigned int d, unsigned int n) {
      if (tty)
        std::cerr << "\r\033[Kconfigurations " << d << "/" << n << std::flush;
    });
    if (tty)
      std::cerr << "\n";
  }
  vpSelfCalibDataset ds = sim.makeDataset(configurations);
  const std::vector<std::string> presets = vpKinematicChain::presetNames(); // a file: written relative to the dataset
  ds.robot = std::count(presets.begin(), presets.end(), a.robot)
                 ? a.robot
                 : fs::relative(fs::absolute(a.robot), fs::absolute(out).parent_path()).string();
  std::vector<vpColVector> qs;
  for (const auto &v : ds.views)
    qs.push_back(v.q);
  if (a.controller)
    // What a controller reports: the (true) end-effector pose, no joints.
    for (auto &v : ds.views) {
      v.has_fMe = true;
      v.fMe = sim.getTrueChain().get_fMe(v.q);
      v.q = vpColVector();
    }
  if (a.focal == "shared") {
    ds.focal_known = false;
    ds.cam.initPersProjWithoutDistortion(0.93 * so.px, 0.93 * so.py, so.u0, so.v0);
  }
  std::vector<std::string> earlier_images;
  std::unique_ptr<vpSelfCalibOutputDirectory> images;
  if (a.images) {
    // Rendered acquisition: images beside the dataset, no points (the front end finds them), the
    // yardstick's length only (its dots are found in the images).
    earlier_images = earlierImageDirectories(out);
    images = renderImages(sim, a, qs, out, ds);
  }
  // The truth first: a dataset in place always has its truth beside it.
  const std::string truth = writeTruth(sim, out, ds);
  // The one step from the earlier run to this one: the dataset renamed into place (its images,
  // in a directory of their own, are already there). Then the earlier runs' images go.
  ds.saveYaml(out);
  images.reset();
  for (const std::string &dir : earlier_images) {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  if (a.images)
    std::cout << "wrote " << out << ": " << poses << " poses of " << a.robot << ", rendered images in "
              << fs::path(ds.views[0].image).parent_path().filename().string() << "/ beside it\n";
  else
    std::cout << "wrote " << out << ": " << poses << " poses of " << a.robot << ", " << sim.getScenePoints().size()
              << " scene points, noise " << so.pixel_noise_sd << " px\n";
  std::cout << "wrote " << truth << ": the truth simulated (true model, camera, scene points); " << kProgram
            << " compare RESULT_DIR " << truth << " measures a result against it\n";
  return 0;
}
