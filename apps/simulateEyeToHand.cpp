/*
 * visp-selfcalib simulate --camera-mount world: a camera fixed in the world and a target on the tool,
 * as points data (with its truth) or rendered images (see simulate.h).
 */
#include "simulate.h"

#include <iostream>
#include <sstream>

#include <visp3/selfcalib/vpBoardDetector.h>
#include <visp3/selfcalib/vpSelfCalibEyeToHandRenderer.h>
#include <visp3/selfcalib/vpSelfCalibFileWriter.h>

#include "selfcalibCli.h"

#include <yaml-cpp/yaml.h>

namespace fs = std::filesystem;

namespace
{
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

/*
  The board of --target as calibrate reads it from the images (vpBoardDetector's layout, in the
  frame the renderer prints it in, the frame of eMo): its spec and its corners by id.
*/
std::string boardSpec(const vpSelfCalibRenderer::Options &ro, const std::string &out)
{
  if (ro.scene == vpSelfCalibRenderer::APRILTAGS)
    return "apriltag-bundle:" + ((fs::path(out).parent_path().empty() ? fs::path(".") : fs::path(out).parent_path()) /
                                 "tags.yaml").string();
  std::ostringstream spec;
  spec << "charuco:" << ro.charuco_cols << "x" << ro.charuco_rows << ":" << ro.charuco_square << ":"
       << ro.charuco_marker << ":" << ro.charuco_dictionary;
  return spec.str();
}

} // namespace

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
  if (a.with_joints || a.joint_sd > 0)
    throw CLI::ValidationError(a.with_joints ? "--with-joints" : "--joint-sd",
                               "rendered images of a camera in the world are simulated with controller poses only "
                               "(joint readings: points data, without --images)");
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
  // The truth's layout is the board's as calibrate finds it in the images (the simulation's is its outline).
  const std::string spec = boardSpec(ro, a.out);
  truth.layout = vpBoardDetector(vpBoardDetector::parse(spec)).getLayout();
  const std::string file = writeEyeToHandTruth(truth, a.out, ds);
  images.reset();
  for (const std::string &dir : earlier_images) {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  std::cout << "wrote " << a.out << ": " << ds.views.size() << " views (camera in the world), rendered images in "
            << fs::path(ds.views[0].image).parent_path().filename().string() << "/ beside it\n";
  std::cout << "wrote " << file << ": the truth simulated (bMc, eMo, the layout of --board " << spec << ")\n";
  return 0;
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
