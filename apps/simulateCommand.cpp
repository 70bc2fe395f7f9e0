/*
 * visp-selfcalib simulate: a dataset of the reference scenario (observations, or rendered images).
 */
#include "commands.h"

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
#include <visp3/selfcalib/vpSelfCalibEyeToHandRenderer.h>
#include <visp3/selfcalib/vpSelfCalibFileWriter.h>
#include <visp3/selfcalib/vpSelfCalibRenderer.h>

#include "selfcalibCli.h"

#include <yaml-cpp/yaml.h>

namespace fs = std::filesystem;

namespace
{
//! simulate --poses: more would take hours (each pose is searched for by inverse kinematics).
constexpr unsigned long long kMaxSimulatedPoses = 10000;
//! 8 hex digits, new in every run (the name of a run's image directory).
std::string runName()
{
  std::random_device rd;
  std::ostringstream os;
  os << std::hex << std::setw(8) << std::setfill('0') << (rd() & 0xffffffffu);
  return os.str();
}

//! Whether `name` is STEM-images-XXXXXXXX (8 lower-case hex digits): a run's image directory.
bool isRunImageDirectory(const std::string &name, const std::string &stem)
{
  const std::string prefix = stem + "-images-";
  if (name.size() != prefix.size() + 8 || name.compare(0, prefix.size(), prefix) != 0)
    return false;
  return std::all_of(name.begin() + static_cast<long>(prefix.size()), name.end(),
                     [](char c) { return std::isdigit(static_cast<unsigned char>(c)) || (c >= 'a' && c <= 'f'); });
}

//! Whether `dir` holds only rendered images (NNNN.png files), as a run's image directory does.
bool holdsOnlyRenderedImages(const fs::path &dir)
{
  std::error_code ec;
  for (const fs::directory_entry &e : fs::directory_iterator(dir, ec)) {
    const std::string n = e.path().filename().string();
    if (e.is_symlink(ec) || !e.is_regular_file(ec) || n.size() != 8 || n.compare(4, 4, ".png") != 0 ||
        !std::all_of(n.begin(), n.begin() + 4, [](char c) { return std::isdigit(static_cast<unsigned char>(c)); }))
      return false;
  }
  return !ec;
}

/*
  Removes the image directories beside the dataset at `out` that no dataset points at: a run killed
  between its images' commit and its dataset's rename leaves one. Only those named like a run's
  (STEM-images-XXXXXXXX) that hold rendered images only, not the one `keep` names, and not one a
  live run holds (its lock is taken first).
*/
void removeOrphanImageDirectories(const fs::path &parent, const std::string &stem, const std::string &keep)
{
  std::error_code ec;
  std::vector<fs::path> orphans;
  for (const fs::directory_entry &e : fs::directory_iterator(parent, ec))
    if (isRunImageDirectory(e.path().filename().string(), stem) && e.path().string() != keep &&
        e.is_directory(ec) && !e.is_symlink(ec) && holdsOnlyRenderedImages(e.path()))
      orphans.push_back(e.path());
  for (const fs::path &d : orphans)
    try {
      const vpSelfCalibOutputDirectory held(d.string()); // refused while a live run holds it
      fs::remove_all(d, ec);
    } catch (const vpException &) {
      // a live run's
    }
}

/*
  The image directories to remove once the new dataset is in place: the one of the dataset at
  `out` that an earlier simulate --images wrote (one of ours, beside it, every image in it). Also
  removes what killed runs left: their hidden staging directories (each opened as an output set,
  which removes the leftovers of its name unless a live run holds it) and, when the dataset at
  `out` is absent or one of ours, the image directories no dataset points at.
*/
std::vector<std::string> earlierImageDirectories(const std::string &out)
{
  const fs::path parent = fs::absolute(out).lexically_normal().parent_path();
  const std::string stem = fs::path(out).stem().string();
  std::error_code ec;
  for (const fs::directory_entry &e : fs::directory_iterator(parent, ec)) {
    const std::string n = e.path().filename().string();
    const size_t tmp = n.find(".tmp-");
    if (n.size() > 1 && n[0] == '.' && tmp != std::string::npos && isRunImageDirectory(n.substr(1, tmp - 1), stem))
      try {
        const vpSelfCalibOutputDirectory leftovers((parent / n.substr(1, tmp - 1)).string());
      } catch (const vpException &) {
        // a live run's, or not ours to remove
      }
  }
  if (canonical(out).empty()) {
    removeOrphanImageDirectories(parent, stem, "");
    return {};
  }
  std::string dir;
  try {
    for (const vpSelfCalibDataset::View &v : vpSelfCalibDataset::loadYaml(out).views) {
      const fs::path d = fs::absolute(v.image).lexically_normal().parent_path();
      if (v.image.empty() || d.parent_path() != parent || !isRunImageDirectory(d.filename().string(), stem) ||
          (!dir.empty() && dir != d.string()))
        return {};
      dir = d.string();
    }
  } catch (const vpException &) {
    return {}; // not a dataset: its images, if any, are not ours to remove
  }
  removeOrphanImageDirectories(parent, stem, dir);
  if (dir.empty())
    return {};
  return {dir};
}

//! simulate --target apriltags: the bundle's description (vpBoardDetector's apriltag-bundle file) beside the dataset.
void writeTagBundle(const fs::path &dir, const vpSelfCalibRenderer::Options &ro)
{
  std::ostringstream yaml;
  yaml << "family: " << ro.tag_family << "\ntags:\n";
  for (const auto &t : vpSelfCalibRenderer::getTagBundle(ro))
    yaml << "  - {id: " << t.first << ", size: " << ro.tag_size << ", pose: [" << t.second[0] << ", " << t.second[1]
         << ", 0, 0, 0, 0]}\n";
  const std::string file = ((dir.empty() ? fs::path(".") : dir) / "tags.yaml").string();
  vpSelfCalibFileWriter::write(file, yaml.str(), "tag bundle");
}

//! The renderer's options of simulate --target.
vpSelfCalibRenderer::Options rendererOptions(const SimulateArgs &a)
{
  vpSelfCalibRenderer::Options ro;
  ro.seed = a.so.seed;
  ro.scene = a.target == "dots"        ? vpSelfCalibRenderer::DOTS
             : a.target == "charuco"   ? vpSelfCalibRenderer::CHARUCO
             : a.target == "apriltags" ? vpSelfCalibRenderer::APRILTAGS
                                       : vpSelfCalibRenderer::TEXTURED;
  return ro;
}

/*
  Writes image k = render(k) of every view into a directory of this run's own beside the dataset
  (STEM-images-XXXXXXXX), written as a set (vpSelfCalibOutputDirectory: staged, then renamed into
  place) before the dataset that points at them: a run killed at any moment leaves the earlier
  dataset with its own images (and, killed between the two, an image directory no dataset points
  at, which the next run removes). The set is returned with its lock, to be released once the
  dataset is in place.
*/
std::unique_ptr<vpSelfCalibOutputDirectory>
writeImages(const std::function<vpImage<unsigned char>(unsigned int)> &render, const std::string &out,
            vpSelfCalibDataset &ds)
{
  const fs::path parent = fs::path(out).parent_path(); // as given: the dataset then holds relative paths
  const fs::path img_dir = (parent.empty() ? fs::path(".") : parent) / (fs::path(out).stem().string() + "-images-" + runName());
  auto owned = std::make_unique<vpSelfCalibOutputDirectory>(img_dir.string());
  vpSelfCalibOutputDirectory &set = *owned;
  for (size_t k = 0; k < ds.views.size(); ++k) {
    std::ostringstream name;
    name << std::setw(4) << std::setfill('0') << k + 1 << ".png";
    // Encoded in memory and written atomically, every write checked (a full disk is an error
    // naming the file and the reason, and the dataset that would point at it is not written).
    try {
      vpSelfCalibFileWriter::writeImage((fs::path(set.staging()) / name.str()).string(),
                                        render(static_cast<unsigned int>(k)));
    } catch (...) {
      std::cerr << "\n"; // after the progress line
      throw;
    }
    ds.views[k].image = (img_dir / name.str()).string();
    ds.views[k].points.clear();
    std::cerr << "rendered " << k + 1 << "/" << ds.views.size() << "\r" << std::flush;
  }
  std::cerr << "\n";
  set.commit();
  return owned; // its lock held until the dataset points at it: no other run takes it for an orphan
}

//! The rendered images of the reference scenario's views at joints qs (see writeImages()).
std::unique_ptr<vpSelfCalibOutputDirectory> renderImages(const vpSelfCalibSimulator &sim, const SimulateArgs &a, const std::vector<vpColVector> &qs,
                  const std::string &out, vpSelfCalibDataset &ds)
{
  const vpSelfCalibRenderer::Options ro = rendererOptions(a);
  const vpSelfCalibRenderer renderer(sim, ro);
  if (ro.scene == vpSelfCalibRenderer::APRILTAGS)
    writeTagBundle(fs::path(out).parent_path(), ro);
  auto images = writeImages([&](unsigned int k) { return renderer.render(qs[k], k); }, out, ds);
  ds.yardstick.length = renderer.getYardstickLength(); // 0 for the boards: their first row is the yardstick
  ds.yardstick.id_a = ds.yardstick.id_b = -1;
  return images;
}

/*
  simulate --camera-mount world --images: a camera fixed in the world (1280 x 720, f 1000 px) sees
  the board of --target (charuco or apriltags) on the tool, the tool's textured parts around it
  (vpSelfCalibEyeToHandRenderer), at controller poses of vpSelfCalibSimulator::simulateEyeToHand
  (the whole board in every image; --pose-sd their error).
*/
int simulateEyeToHandImages(const SimulateArgs &a)
{
  if (a.target != "charuco" && a.target != "apriltags")
    throw CLI::ValidationError("--target", "--camera-mount world --images renders a board on the tool: --target "
                                           "charuco or apriltags");
  if (!a.joints_file.empty() || a.controller)
    throw CLI::ValidationError("--camera-mount", "world simulates controller poses of its own: no --joints or "
                                                 "--controller-poses");
  const vpSelfCalibRenderer::Options ro = rendererOptions(a);
  vpSelfCalibSimulator::EyeToHandOptions eo = vpSelfCalibEyeToHandRenderer::simulation(ro);
  eo.seed = a.so.seed;
  eo.num_views = a.poses;
  eo.pose_sd_translation = eo.pose_sd_rotation = a.pose_sd;
  vpSelfCalibSimulator::EyeToHandTruth truth;
  vpSelfCalibDataset ds = vpSelfCalibSimulator::simulateEyeToHand(eo, truth);
  const vpSelfCalibEyeToHandRenderer renderer(ro, ds.cam, eo.width, eo.height, truth.bMc, truth.eMo);
  const std::vector<std::string> earlier_images = earlierImageDirectories(a.out);
  if (ro.scene == vpSelfCalibRenderer::APRILTAGS)
    writeTagBundle(fs::path(a.out).parent_path(), ro);
  auto images = writeImages([&](unsigned int k) { return renderer.render(truth.bMe[k], k); }, a.out, ds);
  ds.saveYaml(a.out);
  images.reset();
  for (const std::string &dir : earlier_images) {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  std::cerr << "true bMc " << vpPoseVector(truth.bMc).t() << "\ntrue eMo " << vpPoseVector(truth.eMo).t() << "\n";
  std::cout << "wrote " << a.out << ": " << ds.views.size() << " views (camera in the world), rendered images in "
            << fs::path(ds.views[0].image).parent_path().filename().string() << "/ beside it\n";
  return 0;
}

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

/*
  Eye-to-hand: the truth beside the dataset (STEM-truth.yaml): the camera, bMc and eMo (pose vectors,
  m and rad), the target's layout (id, x, y, z in o), and with joints the true and nominal robot
  models (the true model's hand-eye slot is the nominal's: the camera is bMc). Returns the file's name.
*/
std::string writeEyeToHandTruth(const vpSelfCalibSimulator::EyeToHandTruth &t, const std::string &out,
                                const vpSelfCalibDataset &ds)
{
  const fs::path file = fs::path(out).parent_path() / (fs::path(out).stem().string() + "-truth.yaml");
  YAML::Emitter y;
  y << YAML::Comment("The truth " + std::string(kProgram) + " simulate used for " + fs::path(out).filename().string() +
                     " (camera in the world, target on the tool)");
  y << YAML::BeginMap << YAML::Key << "truth_of" << YAML::Value << fs::path(out).filename().string();
  y << YAML::Key << "camera" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "width" << YAML::Value
    << ds.width << YAML::Key << "height" << YAML::Value << ds.height << YAML::Key << "px" << YAML::Value
    << ds.cam.get_px() << YAML::Key << "py" << YAML::Value << ds.cam.get_py() << YAML::Key << "u0" << YAML::Value
    << ds.cam.get_u0() << YAML::Key << "v0" << YAML::Value << ds.cam.get_v0() << YAML::EndMap;
  for (const auto &m : {std::make_pair("bMc", t.bMc), std::make_pair("eMo", t.eMo)}) {
    const vpPoseVector p(m.second);
    y << YAML::Key << m.first << YAML::Value << YAML::Flow << YAML::BeginSeq;
    for (unsigned int i = 0; i < 6; ++i)
      y << p[i];
    y << YAML::EndSeq;
  }
  if (!t.q.empty()) {
    y << YAML::Key << "true_model" << YAML::Value << YAML::Literal << t.chain.toYamlString();
    y << YAML::Key << "nominal_model" << YAML::Value << YAML::Literal << t.chain.nominal().toYamlString();
  }
  y << YAML::Key << "points" << YAML::Value << YAML::BeginSeq;
  for (const auto &pt : t.layout)
    y << YAML::Flow << YAML::BeginSeq << pt.first << pt.second[0] << pt.second[1] << pt.second[2] << YAML::EndSeq;
  y << YAML::EndSeq << YAML::EndMap;
  vpSelfCalibFileWriter::write(file.string(), std::string(y.c_str()) + "\n", "truth");
  return file.string();
}

//! simulate --camera-mount world: points data of a board on the tool seen by a fixed camera, and its truth.
int simulateEyeToHand(const SimulateArgs &a)
{
  if (a.images || !a.joints_file.empty() || a.controller || a.focal == "shared")
    throw CLI::ValidationError("--camera-mount", "world simulates points data of its own poses with the focal length "
                                                 "known: no --images, --joints, --controller-poses or --focal shared");
  if (a.joint_sd > 0 && !a.with_joints)
    throw CLI::ValidationError("--joint-sd", "the joint readings' error needs --with-joints");
  if (a.pose_sd > 0 && a.with_joints)
    throw CLI::ValidationError("--pose-sd", "the controller poses' error, and --with-joints writes joint readings "
                                            "instead of controller poses: give their error with --joint-sd");
  vpSelfCalibSimulator::EyeToHandOptions eo;
  eo.seed = static_cast<unsigned int>(a.so.seed);
  eo.num_views = a.poses;
  eo.pixel_noise_sd = a.so.pixel_noise_sd;
  eo.pose_sd_translation = eo.pose_sd_rotation = a.pose_sd;
  if (a.with_joints) {
    eo.robot = a.robot;
    eo.joint_sd = a.joint_sd;
  }
  vpSelfCalibSimulator::EyeToHandTruth truth;
  vpSelfCalibDataset ds = vpSelfCalibSimulator::simulateEyeToHand(eo, truth);
  for (auto &v : ds.views) // a view has joints or a controller pose: the joints with --with-joints
    v.has_fMe = v.has_fMe && v.q.size() == 0;
  ds.saveYaml(a.out);
  const std::string file = writeEyeToHandTruth(truth, a.out, ds);
  std::cout << "wrote " << a.out << ": " << ds.views.size() << " views (camera in the world"
            << (a.with_joints ? ", joint readings of " + a.robot : std::string()) << ")\n";
  std::cout << "wrote " << file << ": the truth simulated (bMc, eMo, the target's layout"
            << (a.with_joints ? ", true and nominal models" : "") << ")\n";
  return 0;
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
              "with --camera-mount world: the board is carried by --robot's simulated arm (seeded\n"
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
