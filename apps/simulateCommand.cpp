/*
 * visp-selfcalib simulate: a dataset of the reference scenario (observations, or rendered images).
 */
#include "commands.h"

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>
#include <visp3/selfcalib/vpSelfCalibFileWriter.h>
#include <visp3/selfcalib/vpSelfCalibRenderer.h>

#include "selfcalibCli.h"

namespace fs = std::filesystem;

namespace
{
//! simulate --poses: more would take hours (each pose is searched for by inverse kinematics).
constexpr unsigned long long kMaxSimulatedPoses = 10000;
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
              "render the images (OUT's directory/images/) and write no points: calibrate\n"
              "then runs the image front end");
  c->add_option("--target", a.target,
                "textured (default: photographs on two planes, natural features) or dots (the\n"
                "paper's experiment: dot grids 4x5 and 4x9 on the two planes; needs --images;\n"
                "calibrate with --dot-grids 4x5,4x9 --no-features)")
      ->type_name("T")
      ->check(CLI::IsMember({"textured", "dots"}));
  c->add_option("--camera-mount", a.camera_mount,
                 "effector (default: the reference scenario) or world: a camera fixed in the world and a\n"
                 "6 x 5 board (2 cm, the layout of --board chessboard:5x6:0.02, rows x cols) on the tool, points data\n"
                 "(calibrate --method hand-eye --board chessboard:5x6:0.02 --board-geometry)")
      ->type_name("MOUNT")
      ->check(CLI::IsMember({"effector", "world"}));
  c->add_option("--pose-sd", a.pose_sd, "with --camera-mount world: the controller poses' error sd (m and rad, default 0)")
      ->type_name("SD")
      ->check(CLI::Range(0.0, 0.1));
  c->add_flag("--force", a.force, "replace an existing OUT.yaml");
  c->final_callback([&a] {
    if (a.target == "dots" && !a.images)
      throw CLI::ValidationError("--target", "dots renders images: add --images");
  });
}

int simulate(const SimulateArgs &a)
{
  const std::string &out = a.out;
  const vpSelfCalibSimulator::Options &so = a.so;
  unsigned int poses = a.poses;
  if (!a.force && !canonical(out).empty()) {
    std::cerr << "error: '" << out << "' exists; use --force to replace it\n";
    return 1;
  }
  if (a.camera_mount == "world") {
    if (a.images || !a.joints_file.empty() || a.controller)
      throw CLI::ValidationError("--camera-mount", "world simulates points data of its own poses: no --images, "
                                                   "--joints or --controller-poses");
    vpSelfCalibSimulator::EyeToHandOptions eo;
    eo.seed = so.seed;
    eo.num_views = poses;
    eo.pixel_noise_sd = so.pixel_noise_sd;
    eo.pose_sd_translation = eo.pose_sd_rotation = a.pose_sd;
    vpSelfCalibSimulator::EyeToHandTruth truth;
    vpSelfCalibDataset ds = vpSelfCalibSimulator::simulateEyeToHand(eo, truth);
    ds.saveYaml(out);
    std::cerr << "true bMc " << vpPoseVector(truth.bMc).t() << "\ntrue eMo " << vpPoseVector(truth.eMo).t() << "\n";
    std::cout << "wrote " << out << ": " << ds.views.size() << " views (camera in the world)\n";
    return 0;
  }
  const vpSelfCalibSimulator sim(vpKinematicChain::fromPresetOrFile(a.robot), so);
  std::vector<vpColVector> configurations;
  if (!a.joints_file.empty()) {
    // The given configurations (a plan), each checked for joint limits and visibility.
    std::ifstream in(a.joints_file);
    if (!in) {
      std::cerr << "error: cannot open joints file '" << a.joints_file << "'\n";
      return 1;
    }
    if (!readJoints(in, a.joints_file, sim.getNominalChain().getNumJoints(), configurations))
      return 1;
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
    configurations = sim.generateConfigurations(poses, [](unsigned int d, unsigned int n) {
      std::cerr << "configurations " << d << "/" << n << "\r" << std::flush;
    });
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
  if (a.images) {
    // Rendered acquisition: images beside the dataset, no points (the front end finds them), the
    // yardstick's length only (its dots are found in the images).
    const fs::path parent = fs::path(out).parent_path();
    const fs::path img_dir = (parent.empty() ? fs::path(".") : parent) / "images";
    if (!makeDirectory(img_dir)) {
      std::cerr << "error: cannot create '" << img_dir.string() << "'\n";
      return 1;
    }
    vpSelfCalibRenderer::Options ro;
    ro.seed = so.seed;
    ro.scene = a.target == "dots" ? vpSelfCalibRenderer::DOTS : vpSelfCalibRenderer::TEXTURED;
    const vpSelfCalibRenderer renderer(sim, ro);
    for (size_t k = 0; k < ds.views.size(); ++k) {
      std::ostringstream name;
      name << std::setw(4) << std::setfill('0') << k + 1 << ".png";
      const std::string file = (img_dir / name.str()).string();
      // Encoded in memory and written atomically, every write checked (a full disk is an error
      // naming the file and the reason, and the dataset that would point at it is not written).
      try {
        vpSelfCalibFileWriter::writeImage(file, renderer.render(qs[k], static_cast<unsigned int>(k)));
      } catch (...) {
        std::cerr << "\n"; // after the progress line
        throw;
      }
      ds.views[k].image = file;
      ds.views[k].points.clear();
      std::cerr << "rendered " << k + 1 << "/" << ds.views.size() << "\r" << std::flush;
    }
    std::cerr << "\n";
    ds.yardstick.length = renderer.getYardstickLength();
    ds.yardstick.id_a = ds.yardstick.id_b = -1;
  }
  ds.saveYaml(out);
  if (a.images)
    std::cout << "wrote " << out << ": " << poses << " poses of " << a.robot << ", rendered images in the images/ "
              << "directory beside it\n";
  else
    std::cout << "wrote " << out << ": " << poses << " poses of " << a.robot << ", " << sim.getScenePoints().size()
              << " scene points, noise " << so.pixel_noise_sd << " px\n";
  return 0;
}
