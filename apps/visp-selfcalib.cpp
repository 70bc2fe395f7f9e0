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
 * wrong value), 3 the calibration failed (its status and message on stderr). Outputs are written
 * atomically and never over an input.
 */
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <opencv2/core.hpp>
#include <yaml-cpp/yaml.h>

#include <visp3/core/vpPoseVector.h>
#include <visp3/core/vpXmlParserCamera.h>
#include <visp3/io/vpImageIo.h>
#include <visp3/selfcalib/vpBoardDetector.h>
#include <visp3/selfcalib/vpCalibrationVerifier.h>
#include <visp3/selfcalib/vpFeatureFrontEnd.h>
#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpMeasurementPlanner.h>
#include <visp3/selfcalib/vpModelExport.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibCrossValidation.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibFileWriter.h>
#include <visp3/selfcalib/vpSelfCalibImageCorrespondences.h>
#include <visp3/selfcalib/vpSelfCalibImporter.h>
#include <visp3/selfcalib/vpSelfCalibRenderer.h>
#include <visp3/selfcalib/vpSelfCalibReport.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "acquireCommand.h"
#include "selfcalibCli.h"

namespace fs = std::filesystem;

namespace
{
const char *const kProgram = "visp-selfcalib";
const char *const kModelHelp = "a preset (puma560, viper850, panda, ur5), a robot-model YAML or a URDF file";
//! simulate --poses: more would take hours (each pose is searched for by inverse kinematics).
constexpr unsigned long long kMaxSimulatedPoses = 10000;

int info(const vpKinematicChain &c)
{
  std::cout << "name: " << c.getName() << "\nconvention: " << (c.getConvention() == vpKinematicChain::DH ? "dh" : "mdh")
            << "\njoints: " << c.getNumJoints() << "\nerror-model parameters: " << c.getNumParameters() << "\n";
  const std::vector<std::string> names = c.getParameterNames();
  for (unsigned int i = 0; i < names.size(); ++i)
    if (c.getParameters()[i] != 0)
      std::cout << "  " << names[i] << " = " << std::setprecision(17) << c.getParameters()[i] << "\n";
  return 0;
}

//! Joint vectors, one per line (rad, spaces or commas, '#' comments); false with a message on error.
bool readJoints(std::istream &in, const std::string &source, unsigned int n, std::vector<vpColVector> &out)
{
  std::string line;
  unsigned int lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    const size_t hash = line.find('#');
    if (hash != std::string::npos)
      line.resize(hash);
    for (char &ch : line)
      if (ch == ',')
        ch = ' ';
    std::istringstream ls(line);
    std::vector<double> v;
    std::string tok;
    while (ls >> tok) {
      try {
        size_t used = 0;
        v.push_back(std::stod(tok, &used));
        if (used != tok.size() || !std::isfinite(v.back()))
          throw std::invalid_argument(tok);
      } catch (const std::exception &) {
        std::cerr << source << ":" << lineno << ": '" << tok << "' is not a number\n";
        return false;
      }
    }
    if (v.empty())
      continue;
    if (v.size() != n) {
      std::cerr << source << ":" << lineno << ": expected " << n << " joint values, got " << v.size() << "\n";
      return false;
    }
    out.push_back(vpColVector(v));
  }
  return true;
}

int predict(const vpKinematicChain &c, std::istream &in, const std::string &source)
{
  std::vector<vpColVector> qs;
  if (!readJoints(in, source, c.getNumJoints(), qs))
    return 1;
  std::cout << std::setprecision(17);
  for (const vpColVector &q : qs) {
    if (!c.isInJointLimits(q))
      std::cerr << source << ": warning: joints outside the model's limits\n";
    const vpPoseVector p(c.get_fMc(q));
    for (unsigned int k = 0; k < 6; ++k)
      std::cout << p[k] << (k < 5 ? " " : "\n");
  }
  return 0;
}

//! Canonical path of an existing file or directory, or "" when it does not exist.
std::string canonical(const std::string &p)
{
  std::error_code ec;
  const fs::path c = fs::canonical(p, ec);
  return ec ? std::string() : c.string();
}

//! Creates a directory unless it exists; false when that fails.
bool makeDirectory(const fs::path &dir)
{
  std::error_code ec;
  return fs::is_directory(dir, ec) || fs::create_directory(dir, ec);
}

//! The names of focal modes, as the command lines spell them.
std::vector<std::string> focalNames(std::initializer_list<vpRobotSelfCalibration::FocalMode> modes)
{
  std::vector<std::string> names;
  for (vpRobotSelfCalibration::FocalMode m : modes)
    names.push_back(vpRobotSelfCalibration::focalModeName(m));
  return names;
}

//! --robot NAME: a preset or a robot-model file (YAML or URDF).
CLI::Option *addRobotOption(CLI::App &app, std::string &robot)
{
  return app.add_option("--robot", robot, "the robot: viper850 (default), another preset, or a robot-model YAML or URDF file")
      ->type_name("NAME")
      ->check(CLI::IsMember(vpKinematicChain::presetNames()) | CLI::ExistingFile);
}

// ---------------------------------------------------------------------------------------------
// simulate

struct SimulateArgs {
  std::string out, robot = "viper850", focal = "known", target = "textured", joints_file;
  vpSelfCalibSimulator::Options so;
  unsigned int poses = 25;
  bool force = false, controller = false, images = false;
};

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

// ---------------------------------------------------------------------------------------------
// calibrate

/*!
  The protocol of a calibrate run (README "calibrate"): by default every view calibrates and a k-fold
  cross-validation measures the model on views it was not calibrated on; --holdout N (or
  --calibration) keeps the paper's split, the last views verifying; --heldout FILE verifies the
  model on a second dataset.
*/
struct Protocol {
  unsigned int calibration = 0, held_out = 0; //!< views calibrating, views after them verifying
  unsigned int folds = 0;                     //!< 0: no cross-validation
  std::string note;                           //!< why there is no cross-validation, when it was not asked for
  std::string heldout_file;
  vpSelfCalibDataset heldout;                 //!< --heldout's dataset (views empty without)
  std::optional<vpSelfCalibCrossValidation::Result> cv;
  std::optional<vpSelfCalibCrossValidation::HeldOut> verified;
};

//! The protocol's part of results.yaml: the split, the cross_validation block, the held-out dataset.
void protocolYaml(YAML::Emitter &out, const Protocol &p)
{
  using CV = vpSelfCalibCrossValidation;
  out << YAML::Key << "protocol" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "calibration_views"
      << YAML::Value << p.calibration << YAML::Key << "held_out_views" << YAML::Value << p.held_out << YAML::Key
      << "folds" << YAML::Value << p.folds << YAML::EndMap;
  auto spread = [&out](const char *key, const CV::Spread &s) {
    out << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "mean" << YAML::Value
        << s.mean << YAML::Key << "sd" << YAML::Value << s.sd << YAML::Key << "min" << YAML::Value << s.min
        << YAML::Key << "max" << YAML::Value << s.max << YAML::EndMap;
  };
  if (p.cv) {
    const CV::Result &cv = *p.cv;
    out << YAML::Key << "cross_validation"
        << YAML::Comment("held-out views' reprojection error (px), scene from the training views; view i in fold i mod k")
        << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "folds" << YAML::Value << cv.folds << YAML::Key << "views" << YAML::Value << cv.views
        << YAML::Key << "measured" << YAML::Value << cv.num_ok << YAML::Key << "failed" << YAML::Value
        << cv.num_failed;
    out << YAML::Key << "rms_px" << YAML::Value << YAML::BeginMap;
    spread("calibrated", cv.calibrated_rms);
    spread("nominal", cv.nominal_rms);
    out << YAML::EndMap << YAML::Key << "median_px" << YAML::Value << YAML::BeginMap;
    spread("calibrated", cv.calibrated_median);
    spread("nominal", cv.nominal_median);
    out << YAML::EndMap << YAML::Key << "per_fold" << YAML::Value << YAML::BeginSeq;
    for (const CV::Fold &f : cv.fold) {
      out << YAML::Flow << YAML::BeginMap << YAML::Key << "held_out" << YAML::Value << YAML::Flow << f.held_out
          << YAML::Key << "status" << YAML::Value << vpRobotSelfCalibration::statusName(f.status);
      if (f.status == vpRobotSelfCalibration::OK)
        out << YAML::Key << "fx" << YAML::Value << f.fx << YAML::Key << "rms_calibrated" << YAML::Value
            << f.calibrated.rms << YAML::Key << "median_calibrated" << YAML::Value << f.calibrated.median;
      else
        out << YAML::Key << "message" << YAML::Value << YAML::DoubleQuoted << f.message;
      out << YAML::Key << "rms_nominal" << YAML::Value << f.nominal.rms << YAML::Key << "median_nominal"
          << YAML::Value << f.nominal.median << YAML::Key << "observations" << YAML::Value << f.nominal.observations;
      if (f.verified)
        out << YAML::Key << "yardstick_error_calibrated" << YAML::Value << f.yardstick_error_calibrated << YAML::Key
            << "yardstick_error_nominal" << YAML::Value << f.yardstick_error_nominal;
      out << YAML::EndMap;
    }
    out << YAML::EndSeq << YAML::EndMap;
  }
  if (p.verified) {
    const CV::HeldOut &h = *p.verified;
    out << YAML::Key << "heldout_dataset"
        << YAML::Comment("the calibrated model on a second dataset: its views' reprojection error (px), scene "
                         "from these views; yardstick 3-D error (m)")
        << YAML::Value << YAML::BeginMap << YAML::Key << "file" << YAML::Value << p.heldout_file << YAML::Key
        << "views" << YAML::Value << h.views << YAML::Key << "rms_px" << YAML::Value << YAML::Flow << YAML::BeginMap
        << YAML::Key << "calibrated" << YAML::Value << h.calibrated.rms << YAML::Key << "nominal" << YAML::Value
        << h.nominal.rms << YAML::EndMap << YAML::Key << "median_px" << YAML::Value << YAML::Flow << YAML::BeginMap
        << YAML::Key << "calibrated" << YAML::Value << h.calibrated.median << YAML::Key << "nominal" << YAML::Value
        << h.nominal.median << YAML::EndMap << YAML::Key << "observations" << YAML::Value << h.calibrated.observations;
    if (h.has_yardstick)
      out << YAML::Key << "yardstick_error_nominal" << YAML::Value << h.yardstick_error_nominal << YAML::Key
          << "yardstick_error_calibrated" << YAML::Value << h.yardstick_error_calibrated;
    out << YAML::EndMap;
  }
}

//! results.yaml: what the run found, without wall times (the same dataset gives the same file).
std::string resultsYaml(const vpRobotSelfCalibration::Result &r, const vpKinematicChain &nominal,
                        const std::string &dataset, const Protocol &protocol)
{
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap;
  out << YAML::Key << "dataset" << YAML::Value << dataset;
  out << YAML::Key << "method" << YAML::Value << vpRobotSelfCalibration::methodName(r.method);
  out << YAML::Key << "status" << YAML::Value << vpRobotSelfCalibration::statusName(r.status);
  out << YAML::Key << "message" << YAML::Value << YAML::DoubleQuoted << r.message;
  const char *findings_comment = "what the data check found, and what to do";
  out << YAML::Key << "findings";
  if (r.findings.empty())
    out << YAML::Value << YAML::Flow << YAML::BeginSeq << YAML::EndSeq << YAML::Comment(findings_comment);
  else
    out << YAML::Comment(findings_comment) << YAML::Value << YAML::BeginSeq;
  for (const auto &f : r.findings)
    out << YAML::Flow << YAML::BeginMap << YAML::Key << "code" << YAML::Value << f.code << YAML::Key << "severity"
        << YAML::Value << vpSelfCalibDataCheck::severityName(f.severity) << YAML::Key
        << "message" << YAML::Value << YAML::DoubleQuoted << f.message << YAML::EndMap;
  if (!r.findings.empty())
    out << YAML::EndSeq;
  out << YAML::Key << "camera" << YAML::Value << YAML::Flow << YAML::BeginMap;
  out << YAML::Key << "px" << YAML::Value << r.camera.get_px() << YAML::Key << "py" << YAML::Value << r.camera.get_py()
      << YAML::Key << "u0" << YAML::Value << r.camera.get_u0() << YAML::Key << "v0" << YAML::Value << r.camera.get_v0()
      << YAML::Key << "px_sd" << YAML::Value << r.fx_sd;
  if (!r.bundle.opencv_distortion.empty()) {
    out << YAML::Key << "distortion" << YAML::Comment("OpenCV: k1 k2 p1 p2 k3") << YAML::Value << YAML::BeginSeq;
    for (double k : r.bundle.opencv_distortion)
      out << k;
    out << YAML::EndSeq;
  }
  out << YAML::EndMap;
  if (r.bundle.intrinsic_names.size() == r.bundle.intrinsics_sd.size() && !r.bundle.intrinsic_names.empty() &&
      r.bundle.has_covariance) {
    out << YAML::Key << "intrinsics_estimated" << YAML::Comment("value and sd (px; mu and distortion unitless)")
        << YAML::Value << YAML::Flow << YAML::BeginMap;
    for (unsigned int i = 0; i < r.bundle.intrinsics.size(); ++i)
      out << YAML::Key << r.bundle.intrinsic_names[i] << YAML::Value << YAML::BeginSeq << r.bundle.intrinsics[i]
          << r.bundle.intrinsics_sd[i] << YAML::EndSeq;
    out << YAML::EndMap;
  }
  if (r.has_eMc) {
    out << YAML::Key << "eMc" << YAML::Comment("calibrated hand-eye pose vector (tx ty tz tux tuy tuz; m, rad) and sd")
        << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "pose" << YAML::Value << YAML::BeginSeq;
    for (unsigned int k = 0; k < 6; ++k)
      out << r.eMc[k];
    out << YAML::EndSeq << YAML::Key << "sd" << YAML::Value << YAML::BeginSeq;
    for (unsigned int k = 0; k < 6; ++k)
      out << r.eMc_sd[k];
    out << YAML::EndSeq << YAML::EndMap;
  }
  if (r.method == vpRobotSelfCalibration::BUNDLE_ADJUSTMENT || r.method == vpRobotSelfCalibration::HAND_EYE) {
    out << YAML::Key << "bundle_adjustment" << YAML::Value << YAML::Flow << YAML::BeginMap;
    out << YAML::Key << "observations" << YAML::Value << r.bundle.num_observations << YAML::Key << "dropped"
        << YAML::Value << r.bundle.num_outliers << YAML::Key << "rms_px" << YAML::Value << r.bundle.rms << YAML::Key
        << "sigma0" << YAML::Value << r.bundle.sigma0 << YAML::Key << "scale_from" << YAML::Value << YAML::DoubleQuoted
        << vpKinematicBundleAdjustment::scaleSourceName(r.bundle.scale_source);
    if (!r.bundle.pose_corrections.empty()) {
      out << YAML::Key << "robot_pose_rms_m" << YAML::Value << r.bundle.pose_rms_translation << YAML::Key
          << "robot_pose_rms_rad" << YAML::Value << r.bundle.pose_rms_rotation;
      // The pose error (m, rad) the corrections were weighed with (hand-eye: the controller poses';
      // bundle: the kinematic model's residual), and the one they measure.
      const bool controller = r.noise.hasPoseError();
      out << YAML::Key << "robot_pose_sd" << YAML::Value << YAML::Flow << YAML::BeginSeq
          << (controller ? r.noise.pose_sd_translation : r.noise.model_sd_translation)
          << (controller ? r.noise.pose_sd_rotation : r.noise.model_sd_rotation) << YAML::EndSeq;
      if (r.bundle.measured.pose_sd_translation > 0)
        out << YAML::Key << "robot_pose_sd_measured" << YAML::Value << YAML::Flow << YAML::BeginSeq
            << r.bundle.measured.pose_sd_translation << r.bundle.measured.pose_sd_rotation << YAML::EndSeq;
    }
    if (!r.bundle.joint_corrections.empty())
      out << YAML::Key << "joint_correction_rms_rad" << YAML::Value << r.bundle.joint_rms;
    if (r.bundle.reposed_views > 0) // robot error not modelled: each camera re-posed alone
      out << YAML::Key << "reposed_rms_px" << YAML::Value << r.bundle.reposed_rms << YAML::Key << "repose_f"
          << YAML::Value << r.bundle.repose_f << YAML::Key << "repose_f_limit" << YAML::Value
          << r.bundle.repose_f_limit;
    if (r.bundle.covariance_scaled)
      out << YAML::Key << "sd_scaled_by_sigma0" << YAML::Value << true;
    out << YAML::EndMap;
  }
  if (r.method != vpRobotSelfCalibration::PAPER) {
    out << YAML::Key << "noise" << YAML::Comment("px: image noise sd used, and measured by the residuals (robust)")
        << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "pixel_sd" << YAML::Value << r.noise.pixel_sd
        << YAML::Key << "measured" << YAML::Value << r.measured.pixel_sd << YAML::EndMap;
    out << YAML::Key << "fit" << YAML::Comment("px: reprojection RMS on the calibration views, nominal and calibrated model")
        << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "nominal" << YAML::Value << r.fit_nominal_rms
        << YAML::Key << "calibrated" << YAML::Value << r.fit_calibrated_rms << YAML::EndMap;
  }
  const std::vector<std::string> names = nominal.getParameterNames();
  out << YAML::Key << "estimated" << YAML::Comment("per parameter: value and sd (m or rad)") << YAML::Value
      << YAML::BeginMap;
  for (unsigned int k : r.identifiability.identified)
    out << YAML::Key << names[k] << YAML::Value << YAML::Flow << YAML::BeginSeq << r.calibrated.getParameters()[k]
        << (k < r.parameter_sd.size() ? r.parameter_sd[k] : 0.0) << YAML::EndSeq;
  out << YAML::EndMap;
  out << YAML::Key << "not_estimated" << YAML::Value << YAML::BeginMap;
  for (const auto &u : r.identifiability.unidentifiable)
    out << YAML::Key << u.name << YAML::Value << YAML::DoubleQuoted << u.reason;
  out << YAML::EndMap;
  // How the set was chosen (vpKinematicIdentification): the same robot and poses give the same set.
  const auto &ident = r.identifiability;
  if (!ident.order.empty()) {
    out << YAML::Key << "estimated_set"
        << YAML::Comment("fixed preference order at the nominal model and the calibration joints (README, "
                         "\"The estimated set\")")
        << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "rule" << YAML::Value << YAML::DoubleQuoted
        << "walk the order; estimate a parameter when its column of the relative-pose Jacobian (nominal model, "
           "joints only, 1 m = 1 rad) adds a new direction above the threshold";
    out << YAML::Key << "count" << YAML::Value << ident.identified.size();
    out << YAML::Key << "order" << YAML::Value << YAML::Flow << YAML::BeginSeq;
    for (unsigned int k : ident.order)
      out << names[k];
    out << YAML::EndSeq;
    out << YAML::Key << "new_direction" << YAML::Comment("of each estimated parameter, in the order") << YAML::Value
        << YAML::Flow << YAML::BeginMap;
    for (unsigned int k : ident.order)
      if (std::binary_search(ident.identified.begin(), ident.identified.end(), k) && k < ident.new_direction.size())
      {
        std::ostringstream v;
        v << std::setprecision(3) << ident.new_direction[k];
        out << YAML::Key << names[k] << YAML::Value << v.str();
      }
    out << YAML::EndMap << YAML::EndMap;
  }
  if (r.verified) {
    out << YAML::Key << "verification" << YAML::Comment("the paper's 3-D yardstick error on the held-out views (m)")
        << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "yardstick_error_nominal" << YAML::Value << r.before.yardstick_error;
    out << YAML::Key << "yardstick_error_calibrated" << YAML::Value << r.after.yardstick_error;
    out << YAML::Key << "reprojection_rms_nominal" << YAML::Comment("px, points triangulated from these views")
        << YAML::Value << r.before.reprojection_rms;
    out << YAML::Key << "reprojection_rms_calibrated" << YAML::Value << r.after.reprojection_rms;
    out << YAML::EndMap;
  }
  protocolYaml(out, protocol);
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

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
  std::vector<double> joint_sd; //!< joint-reading noise (rad), one or one per joint; empty: exact
  std::vector<std::string> estimate; //!< intrinsics estimated beside f: aspect, pp, distortion
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

//! "CxR": C columns, R rows of an asymmetric circle grid; false when it is not that.
bool parseDotGrid(const std::string &item, vpFeatureFrontEnd::DotGrid &g)
{
  const size_t x = item.find('x');
  const std::string digits = "0123456789";
  if (x == std::string::npos || x == 0 || x + 1 == item.size() ||
      item.substr(0, x).find_first_not_of(digits) != std::string::npos ||
      item.substr(x + 1).find_first_not_of(digits) != std::string::npos || item.size() > 12)
    return false;
  const unsigned long cols = std::stoul(item.substr(0, x)), rows = std::stoul(item.substr(x + 1));
  if (cols == 0 || rows == 0 || cols > 1000 || rows > 1000)
    return false;
  g.cols = static_cast<unsigned int>(cols);
  g.rows = static_cast<unsigned int>(rows);
  return true;
}

void addCalibrate(CLI::App &app, CalibrateArgs &a)
{
  CLI::App *c = app.add_subcommand("calibrate", "calibrated model, camera and results in DIR");
  c->add_option("DATASET", a.dataset, "the dataset file (README: Data formats)")->type_name("FILE")->required();
  c->add_option("--out", a.out, "the output directory (created when missing)")->type_name("DIR")->required();
  std::vector<std::string> methods;
  for (vpRobotSelfCalibration::Method m :
       {vpRobotSelfCalibration::BUNDLE_ADJUSTMENT, vpRobotSelfCalibration::PAPER, vpRobotSelfCalibration::HAND_EYE})
    methods.push_back(vpRobotSelfCalibration::methodName(m));
  c->add_option("--method", a.method,
                "bundle (default; hand-eye when the poses have fMe and no joints): multi-view\n"
                "reconstruction + kinematic bundle adjustment; paper: the paper's procedure;\n"
                "hand-eye: kinematics trusted, eMc, f and points estimated")
      ->type_name("M")
      ->check(CLI::IsMember(methods));
  c->add_option("--calibration", a.calibration,
                "the paper's split: the first N views calibrate, the others verify (3-D yardstick\n"
                "error); at least 3 (default: every view calibrates)")
      ->type_name("N")
      ->check(selfcalibCli::wholeNumber(3, 100000));
  c->add_option("--holdout", a.holdout,
                "the paper's split counted from the end: the last N views verify, the others\n"
                "calibrate; 2 to 100000 (the yardstick error needs two views; with --calibration,\n"
                "the two must add up to the views)")
      ->type_name("N")
      ->check(selfcalibCli::wholeNumber(2, 100000));
  CLI::Option *folds =
      c->add_option("--folds", a.folds,
                    "K-fold cross-validation (view i held out in fold i mod K), 0 or 2 to 100: the\n"
                    "held-out views' reprojection error through the calibrated model vs the nominal\n"
                    "one, the figure to trust on real data (default 5 when every view calibrates,\n"
                    "skipped with a note under 6 views; with --holdout / --calibration none unless\n"
                    "given: then over the calibration views); 0: none")
          ->type_name("K")
          ->check(selfcalibCli::zeroOrWholeNumber(2, 100));
  folds->each([&a](const std::string &) { a.folds_given = true; });
  c->add_option("--heldout", a.heldout,
                "a second dataset of the same robot and camera, not used to calibrate: the model is\n"
                "verified on it (3-D yardstick error when it has one; its views' reprojection error,\n"
                "calibrated vs nominal, the scene triangulated from them)")
      ->type_name("FILE");
  c->add_option("--focal", a.focal, "auto (default: known when the dataset gives px, py), known, shared, per-pair")
      ->type_name("MODE")
      ->check(
          CLI::IsMember(focalNames({vpRobotSelfCalibration::FOCAL_AUTO, vpRobotSelfCalibration::FOCAL_KNOWN,
                                    vpRobotSelfCalibration::FOCAL_SHARED, vpRobotSelfCalibration::FOCAL_PER_PAIR})));
  c->add_option("--pixel-sd", a.pixel_sd,
                "image noise sd (px): auto (default) measures it from the residuals (a second run\n"
                "with the measured value when it differs from 0.2 px by more than 25 %); a number is\n"
                "used as stated, and the sd are scaled when the residuals contradict it")
      ->type_name("auto|PX")
      ->check(selfcalibCli::wordOrNumber("auto", 0, true, 1000));
  c->add_option("--tolerance", a.tolerance,
                "the nominal model's tolerance: largest error of a joint placement (m, rad), then\n"
                "optionally of eMc (m, rad); a correction or an sd beyond it makes the run doubtful\n"
                "(default 0.01,0.05,0.1,0.5; hand-eye does not check eMc)")
      ->type_name("T,R[,TE,RE]")
      ->delimiter(',')
      ->expected(2, 4)
      ->check(selfcalibCli::number(0, true, 100));
  c->add_option("--pose-sd", a.pose_sd,
                "hand-eye: the controller poses' error, translation (m) and rotation (rad) sd,\n"
                "e.g. 0.002,0.002: each pose gets a correction with that prior, and the sd are\n"
                "widened by sigma0 when the residuals say the noise is larger (default: the dataset's\n"
                "robot_error, else exact poses); bundle-adjustment: the kinematic model's own residual\n"
                "(each camera pose corrected in its own frame with that prior; default: none);\n"
                "auto: measured from the corrections (variance components), from the dataset's\n"
                "robot_error or 2 mm / 2 mrad, runs again until it settles within 10 % (the default\n"
                "when the dataset states a robot_error)")
      ->type_name("T,R|auto")
      ->delimiter(',')
      ->expected(1, 2)
      ->check(selfcalibCli::wordOrNumber("auto", 0, true, 10));
  c->add_option("--joint-sd", a.joint_sd,
                "bundle-adjustment: the joint readings' error (rad), one value for every joint or one\n"
                "per joint, e.g. 1e-4: each view gets joint corrections with that prior, and the sd are\n"
                "widened by sigma0 when the residuals say the noise is larger (default: the dataset's\n"
                "robot_error, else exact readings)")
      ->type_name("RAD[,RAD...]")
      ->delimiter(',')
      ->check(selfcalibCli::number(0, true, 1));
  c->add_option("--estimate", a.estimate,
                "intrinsics estimated with the calibration besides f (--focal): aspect (p_y / p_x),\n"
                "pp (principal point), distortion (OpenCV's k1, k2, p1, p2), k3 (and OpenCV's k3),\n"
                "kud (ViSP's one radial coefficient instead); for nominal intrinsics")
      ->type_name("WHAT[,WHAT...]")
      ->delimiter(',')
      ->check(CLI::IsMember({"aspect", "pp", "distortion", "k3", "kud"}));
  c->add_option("--threads", a.threads,
                "threads of the image front end (default: all cores); the results do not depend on it")
      ->type_name("N")
      ->check(selfcalibCli::wholeNumber(1, 1024));
  c->add_option("--dot-grids", a.dot_grids,
                "dot targets for the front end: asymmetric circle grids, C columns x R rows (R odd),\n"
                "grid g numbered from 1000000 + 1000 g; their dots must differ in size")
      ->type_name("CxR[,CxR...]")
      ->delimiter(',')
      ->check(CLI::Validator(
          [](std::string &item) -> std::string {
            vpFeatureFrontEnd::DotGrid g;
            return parseDotGrid(item, g) ? std::string() : "expected COLSxROWS[,COLSxROWS...], got '" + item + "'";
          },
          std::string()));
  CLI::Option *no_features = c->add_flag("--no-features", a.no_features, "no natural features (dot targets only)");
  CLI::Option *board =
      c->add_option("--board", a.board,
                    "a calibration board whose points are the observations (their ids from\n"
                    "2000000 + row * cols + col): chessboard:ROWSxCOLS:SPACING (inner corners),\n"
                    "circles:, acircles: or modified-circles:ROWSxCOLS:SPACING (dots), spacing in m,\n"
                    "e.g. chessboard:9x6:0.0236, modified-circles:10x10:0.0254; ':upright' accepts a\n"
                    "board that looks the same turned. Without a yardstick in the dataset, the ends\n"
                    "of the board's first row are the yardstick")
          ->type_name("SPEC")
          ->check(CLI::Validator(
              [](std::string &spec) -> std::string {
                try {
                  vpBoardDetector::parse(spec);
                  return std::string();
                } catch (const vpSelfCalibException &e) {
                  return e.getStringMessage();
                }
              },
              std::string()));
  c->add_flag("--with-features", a.with_features, "with --board: natural features too")->needs(board)->excludes(no_features);
  CLI::Option *mask_board = c->add_flag("--mask-board", a.mask_board,
              "with --board: the board is found only to be masked out (its region, 15 px beyond its\n"
              "outer points); the calibration uses the natural features around it, target-free")
      ->needs(board)
      ->excludes(no_features);
  c->add_option("--mask", a.mask,
                "an image of the camera's size: where it is black (0) no natural feature is looked\n"
                "for in any view (the robot's own parts, a drawn overlay, a moving background)")
      ->type_name("PNG")
      ->check(CLI::ExistingFile);
  CLI::Option *board_geometry =
      c->add_flag("--board-geometry", a.board_geometry,
                  "with --board: its layout is known (a prior of --board-sd on each point, the\n"
                  "board's pose estimated); without it the board's points are unknown scene points")
          ->needs(board)
          ->excludes(mask_board);
  c->add_option("--board-sd", a.board_sd,
                "with --board-geometry: sd (m) of each point's placement on the board (default 1e-5,\n"
                "10 um: a printed or machined board's accuracy; the layout then holds the points)")
      ->type_name("SD")
      ->check(selfcalibCli::number(0, true, 0.01))
      ->needs(board_geometry);
  c->add_flag("--force", a.force, "replace the results of an earlier run in DIR");
  c->footer("Self-calibrates on every view and cross-validates (--folds), or on the first views and\n"
            "verifies on the last ones (--holdout, --calibration). Writes DIR/model.yaml,\n"
            "DIR/model.urdf, DIR/camera.xml, DIR/results.yaml and DIR/report/ (report.md, gnuplot figures)\n"
            "as one set: written beside DIR, then moved into place at once, under a lock on DIR (a second run\n"
            "into the same DIR is refused). DIR must not hold an input or files that are not results; an\n"
            "earlier run's results are replaced only with --force. The data check's findings are printed\n"
            "as warnings.\n"
            "Exit codes: 0 calibrated, 1 bad input, 2 bad usage, 3 failed or degenerate data (message on stderr).");
}

//! The files a calibration reads: the dataset, its robot model file, camera XML and images.
std::vector<std::string> calibrationInputs(const std::string &dataset, const vpSelfCalibDataset &ds)
{
  std::vector<std::string> in = {dataset};
  const std::vector<std::string> presets = vpKinematicChain::presetNames();
  if (std::find(presets.begin(), presets.end(), ds.robot) == presets.end())
    in.push_back(ds.robot);
  for (const auto &v : ds.views)
    if (!v.image.empty())
      in.push_back(v.image);
  // The camera XML's path is not kept in the dataset: read it from the file (already parsed once).
  try {
    const YAML::Node root = YAML::LoadFile(dataset);
    if (root["camera_xml"] && root["camera_xml"]["file"]) {
      fs::path xml = root["camera_xml"]["file"].as<std::string>();
      if (xml.is_relative())
        xml = fs::path(dataset).parent_path() / xml;
      in.push_back(xml.string());
    }
  } catch (const YAML::Exception &) {
  }
  return in;
}

/*!
  Refuses an output directory that holds an input of the run, files that are not an earlier run's
  results (they would be lost with the earlier set), or an earlier run's results without --force.
  Returns 0 when the run may go on, else the exit code (1) after the message.
*/
int checkOutputDirectory(const vpSelfCalibOutputDirectory &outdir, const std::string &out,
                         const std::vector<std::string> &inputs, bool force)
{
  const std::string target = canonical(outdir.target());
  if (!target.empty())
    for (const std::string &in : inputs) {
      const std::string c = canonical(in);
      if (!c.empty() && (c == target || c.rfind(target + "/", 0) == 0)) {
        std::cerr << "error: '" << in << "' is an input of this run and lies in the output directory '" << out
                  << "', whose content is replaced: choose another --out\n";
        return 1;
      }
    }
  const std::vector<std::string> entries = outdir.existingEntries();
  if (entries.empty())
    return 0;
  const std::vector<std::string> ours = {"model.yaml", "model.urdf", "camera.xml", "results.yaml", "report"};
  std::string foreign;
  for (const std::string &e : entries)
    if (std::find(ours.begin(), ours.end(), e) == ours.end())
      foreign += (foreign.empty() ? "'" : ", '") + e + "'";
  if (!foreign.empty()) {
    std::cerr << "error: the output directory '" << out << "' holds files that are not results of calibrate ("
              << foreign << "); they would be lost: choose a new or empty --out\n";
    return 1;
  }
  if (!force) {
    std::cerr << "error: '" << out << "' holds the results of an earlier run; use --force to replace them\n";
    return 1;
  }
  return 0;
}

/*!
  The split of the m views (po.num_calibration_poses) and the folds from --calibration, --holdout and
  --folds, and --heldout's dataset read (its front end runs after the calibration). Returns 0, or the
  exit code (1) after the message.
*/
int prepareProtocol(const CalibrateArgs &a, unsigned int m, vpRobotSelfCalibration::Options &po, Protocol &p)
{
  if (a.calibration > m) {
    std::cerr << "error: --calibration " << a.calibration << ": the dataset has " << m
              << " views (the calibration uses the first N, the others verify)\n";
    return 1;
  }
  if (a.holdout && a.calibration && a.calibration + a.holdout != m) {
    std::cerr << "error: --calibration " << a.calibration << " and --holdout " << a.holdout << " disagree: the dataset has "
              << m << " views, not " << a.calibration + a.holdout << "; give one of them\n";
    return 1;
  }
  if (a.holdout && (a.holdout >= m || m - a.holdout < 3)) {
    std::cerr << "error: --holdout " << a.holdout << ": the dataset has " << m
              << " views; at least 3 must remain to calibrate\n";
    return 1;
  }
  const bool split = a.calibration || a.holdout;
  p.calibration = a.calibration ? a.calibration : m - a.holdout;
  p.held_out = m - p.calibration;
  po.num_calibration_poses = std::max(3u, p.calibration);
  // Cross-validation: by default when every view calibrates, over the calibration views otherwise.
  p.folds = split && !a.folds_given ? 0 : a.folds;
  if (p.folds && !a.folds_given && p.calibration < 6) {
    p.note = "cross-validation skipped: " + std::to_string(p.calibration) +
             " views, fewer than 6 (each fold would calibrate on 4 views or fewer); --folds K asks for it";
    p.folds = 0;
  }
  if (p.folds) {
    try {
      vpSelfCalibCrossValidation::folds(p.calibration, p.folds);
    } catch (const vpSelfCalibException &e) {
      std::cerr << "error: --folds " << p.folds << ": " << e.getStringMessage() << "\n";
      return 1;
    }
  }
  if (!a.heldout.empty()) {
    p.heldout_file = a.heldout;
    p.heldout = vpSelfCalibDataset::loadYaml(a.heldout);
    if (p.heldout.views.size() < 2) {
      std::cerr << "error: --heldout " << a.heldout << ": " << p.heldout.views.size()
                << " view(s); at least 2 are needed to verify on\n";
      return 1;
    }
  }
  return 0;
}

/*!
  After a calibration: the k-fold cross-validation over the calibration views and the verification on
  --heldout's dataset (the front end run on its images with the calibration's options).
*/
void runProtocol(const vpKinematicChain &nominal, const vpSelfCalibDataset &ds, const vpRobotSelfCalibration::Options &po,
                 const vpRobotSelfCalibration::Result &r, const vpSelfCalibImageCorrespondences::Options &co,
                 int threads, Protocol &p)
{
  if (!p.note.empty())
    std::cerr << "note: " << p.note << "\n";
  if (p.folds) {
    vpSelfCalibDataset cal = ds;
    cal.views.resize(p.calibration);
    vpSelfCalibCrossValidation::Options cvo;
    cvo.folds = p.folds;
    p.cv = vpSelfCalibCrossValidation::run(nominal, cal, po, cvo,
                                           [](const std::string &stage, unsigned int, unsigned int) {
                                             std::cerr << "... " << stage << "\n";
                                           });
    for (size_t f = 0; f < p.cv->fold.size(); ++f)
      if (p.cv->fold[f].status != vpRobotSelfCalibration::OK && p.cv->fold[f].status != vpRobotSelfCalibration::DOUBTFUL)
        std::cerr << "warning: cross-validation fold " << f + 1 << " failed: "
                  << vpRobotSelfCalibration::statusName(p.cv->fold[f].status) << ": " << p.cv->fold[f].message << "\n";
  }
  if (!p.heldout_file.empty()) {
    if (p.heldout.robot != ds.robot || p.heldout.width != ds.width || p.heldout.height != ds.height)
      std::cerr << "warning: --heldout " << p.heldout_file << ": its robot (" << p.heldout.robot << ") or image size ("
                << p.heldout.width << " x " << p.heldout.height << ") is not the dataset's (" << ds.robot << ", "
                << ds.width << " x " << ds.height << "): the verification assumes the same robot and camera\n";
    if (vpSelfCalibImageCorrespondences::needsFrontEnd(p.heldout)) {
      std::cerr << "... image front end of the held-out dataset (" << p.heldout.views.size() << " images)\n";
      cv::setNumThreads(threads);
      vpSelfCalibImageCorrespondences::fromDatasetImages(p.heldout, co);
      cv::setNumThreads(1);
    }
    p.verified = vpSelfCalibCrossValidation::verifyHeldOut(nominal, ds, po, r, p.heldout);
  }
}

//! A DOUBT finding of the protocol: into the findings, the status DOUBTFUL, the message.
void addDoubt(vpRobotSelfCalibration::Result &r, const std::string &code, const std::string &message)
{
  vpSelfCalibDataCheck::Finding f;
  f.severity = vpSelfCalibDataCheck::DOUBT;
  f.code = code;
  f.message = message;
  r.findings.push_back(f);
  r.status = vpRobotSelfCalibration::DOUBTFUL;
  r.message += "; doubtful: " + message;
}

/*!
  The cross-validation's word on the model: when the calibrated model predicts the held-out views
  worse than the nominal model in most folds and by 5 % or more on average, the calibration does not
  generalise (too many parameters for the views, or a wrong input): a DOUBT finding, status DOUBTFUL.
  The same when most folds fail: the calibration does not survive leaving a few views out.
*/
void crossValidationCheck(const Protocol &p, vpRobotSelfCalibration::Result &r)
{
  if (!p.cv)
    return;
  // Most folds failed: the calibration stands only on all the views together, and a few views less
  // (one fold) lose it; the answer depends on which views are used.
  unsigned int failed = 0;
  for (const auto &f : p.cv->fold)
    failed += f.status != vpRobotSelfCalibration::OK && f.status != vpRobotSelfCalibration::DOUBTFUL;
  if (p.cv->fold.size() >= 2 && 2 * failed > p.cv->fold.size() &&
      (r.status == vpRobotSelfCalibration::OK || r.status == vpRobotSelfCalibration::DOUBTFUL)) {
    std::ostringstream os;
    os << failed << " of " << p.cv->fold.size()
       << " cross-validation folds failed (each leaves out a few views): the calibration stands only on all the "
          "views together and depends on which views are used; add views, or check the correspondences";
    addDoubt(r, "cross-validation-folds-failed", os.str());
  }
  if (p.cv->num_ok < 2)
    return;
  unsigned int worse = 0, compared = 0;
  for (const auto &f : p.cv->fold)
    if (f.calibrated.observations > 0 && f.nominal.observations > 0) {
      ++compared;
      worse += f.calibrated.rms > f.nominal.rms;
    }
  if (2 * worse <= compared || !(p.cv->calibrated_rms.mean > 1.05 * p.cv->nominal_rms.mean))
    return;
  std::ostringstream os;
  os << std::setprecision(3) << "the cross-validation's calibrated models predict the held-out views worse than the "
     << "nominal model (reprojection RMS " << p.cv->calibrated_rms.mean << " px against " << p.cv->nominal_rms.mean
     << " px; worse in " << worse << " of " << compared
     << " folds): the calibration does not generalise; add views or estimate fewer parameters";
  addDoubt(r, "cross-validation-worse-than-nominal", os.str());
}

//! The protocol's figures on stdout, one line each.
void printProtocol(const Protocol &p)
{
  if (p.cv)
    std::cout << "cross-validation (" << p.cv->folds << " folds of " << p.cv->views << " views): " << p.cv->message
              << "\n";
  if (p.verified) {
    const vpSelfCalibCrossValidation::HeldOut &h = *p.verified;
    std::cout << std::setprecision(3) << "held-out dataset " << p.heldout_file << " (" << h.views
              << " views): reprojection RMS " << h.calibrated.rms << " px calibrated vs " << h.nominal.rms
              << " px nominal";
    if (h.has_yardstick)
      std::cout << ", yardstick 3-D error " << 1e3 * h.yardstick_error_nominal << " mm (nominal) -> "
                << 1e3 * h.yardstick_error_calibrated << " mm";
    std::cout << std::defaultfloat << "\n";
  }
}

//! calibrate's summary on stdout: what was estimated, eMc with its sd, the residuals, the intrinsics.
void printSummary(const vpRobotSelfCalibration::Result &r, unsigned int num_calibration)
{
  std::cout << "calibrated " << r.identifiability.identified.size() << " parameters on " << num_calibration
            << " views (" << vpRobotSelfCalibration::methodName(r.method) << "), f_x " << std::setprecision(6)
            << r.camera.get_px() << " px";
  if (r.verified)
    std::cout << "; yardstick 3-D error on the held-out views " << std::setprecision(3)
              << 1e3 * r.before.yardstick_error << " mm (nominal) -> " << 1e3 * r.after.yardstick_error << " mm";
  if (r.has_eMc) {
    std::cout << "\neMc: t = (" << std::fixed << std::setprecision(2);
    for (unsigned int k = 0; k < 3; ++k)
      std::cout << (k ? ", " : "") << 1e3 * r.eMc[k] << " +- " << 1e3 * r.eMc_sd[k];
    std::cout << ") mm, theta-u = (";
    for (unsigned int k = 3; k < 6; ++k)
      std::cout << (k > 3 ? ", " : "") << 1e3 * r.eMc[k] << " +- " << 1e3 * r.eMc_sd[k];
    std::cout << ") mrad";
    if (r.method != vpRobotSelfCalibration::PAPER) {
      std::cout << "; pixel rms " << std::setprecision(3) << r.bundle.rms << " px";
      if (!r.bundle.pose_corrections.empty())
        std::cout << ", robot pose corrections rms " << 1e3 * r.bundle.pose_rms_translation << " mm / "
                  << 1e3 * r.bundle.pose_rms_rotation << " mrad";
      std::cout << ", sigma0 " << std::setprecision(2) << r.bundle.sigma0;
    }
    std::cout << std::defaultfloat;
  }
  if (!r.bundle.joint_corrections.empty())
    std::cout << "\njoint corrections rms " << std::setprecision(3) << 1e3 * r.bundle.joint_rms << " mrad, sigma0 "
              << std::setprecision(2) << r.bundle.sigma0 << std::defaultfloat;
  if (r.bundle.has_covariance && r.bundle.intrinsic_names.size() > 1) {
    std::cout << "\nintrinsics:";
    for (unsigned int i = 0; i < r.bundle.intrinsics.size(); ++i)
      std::cout << " " << r.bundle.intrinsic_names[i] << " " << std::setprecision(5) << r.bundle.intrinsics[i]
                << " +- " << std::setprecision(2) << r.bundle.intrinsics_sd[i];
    std::cout << std::defaultfloat;
  }
}

int calibrate(const CalibrateArgs &a)
{
  const std::string &dataset = a.dataset, &out = a.out;
  vpSelfCalibImageCorrespondences::Options co;
  // A board alone unless natural features are asked for too.
  co.front_end.features = a.board.empty() ? !a.no_features : (a.with_features || a.mask_board);
  if (!a.board.empty())
    co.board = vpBoardDetector::parse(a.board);
  co.mask_board = a.mask_board;
  if (!a.mask.empty()) {
    vpImage<unsigned char> mask;
    try {
      vpImageIo::read(mask, a.mask);
    } catch (const vpException &e) {
      throw vpSelfCalibException(vpSelfCalibException::ioError,
                                 "--mask: cannot read the image '" + a.mask + "': " + e.getStringMessage());
    }
    co.front_end.masks.push_back(mask);
  }
  // C x R; grid g numbered from 1000000 + 1000 g (as simulate --target dots).
  for (const std::string &item : a.dot_grids) {
    vpFeatureFrontEnd::DotGrid g;
    parseDotGrid(item, g);
    g.first_id = vpDotGrid::kDefaultFirstId + 1000 * static_cast<int>(co.front_end.dot_grids.size());
    co.front_end.dot_grids.push_back(g);
  }
  if (!a.method.empty())
    co.method = vpRobotSelfCalibration::methodFromName(a.method);
  vpRobotSelfCalibration::Options po;
  po.focal_mode = vpRobotSelfCalibration::focalModeFromName(a.focal);
  if (a.pixel_sd == "auto")
    po.noise.pixel_sd_origin = vpSelfCalibNoiseModel::MEASURED; // from 0.2 px
  else
    po.noise.pixel_sd = std::stod(a.pixel_sd);
  if (a.tolerance.size() == 3)
    throw CLI::ValidationError("--tolerance", "give 2 values (joint placements) or 4 (and eMc), not 3");
  if (a.tolerance.size() >= 2) {
    po.tolerance_translation = a.tolerance[0];
    po.tolerance_rotation = a.tolerance[1];
  }
  if (a.tolerance.size() == 4) {
    po.tolerance_hand_eye_translation = a.tolerance[2];
    po.tolerance_hand_eye_rotation = a.tolerance[3];
  }
  if (a.board_geometry) {
    po.bundle.known_points = vpBoardDetector(*co.board).getLayout();
    po.bundle.known_points_sd = a.board_sd;
  }
  for (const std::string &e : a.estimate) {
    using KBA = vpKinematicBundleAdjustment;
    po.bundle.intrinsics |= e == "aspect" ? KBA::ASPECT
                            : e == "pp"   ? KBA::PRINCIPAL_POINT
                            : e == "k3"   ? KBA::DISTORTION | KBA::DISTORTION_K3
                                          : KBA::DISTORTION;
    if (e == "distortion" || e == "k3")
      po.bundle.distortion_model = KBA::DISTORTION_OPENCV;
  }
  if (std::count(a.estimate.begin(), a.estimate.end(), "kud") && po.bundle.distortion_model != 0)
    throw CLI::ValidationError("--estimate", "kud (ViSP's model) and distortion / k3 (OpenCV's) exclude each other");
  const bool pose_auto = std::count(a.pose_sd.begin(), a.pose_sd.end(), "auto") > 0;
  if (pose_auto && a.pose_sd.size() != 1)
    throw CLI::ValidationError("--pose-sd", "give T,R (two numbers) or auto, not both");
  if (pose_auto && !a.method.empty() && co.method != vpRobotSelfCalibration::HAND_EYE)
    throw CLI::ValidationError("--pose-sd", "auto measures the controller poses' error: it needs --method hand-eye "
                                            "(the joint readings' error is stated with --joint-sd)");
  if (!pose_auto && a.pose_sd.size() == 1)
    throw CLI::ValidationError("--pose-sd", "give two values, T,R (m, rad), or auto");
  // Measured by default from the dataset's robot_error when it states one (below, once it is read).
  if (pose_auto || a.pose_sd.empty())
    po.noise.pose_sd_origin = vpSelfCalibNoiseModel::MEASURED;
  if (a.pose_sd.size() == 2)
    po.bundle.scale_covariance = true; // set in the noise model once the method is known (below)
  if (!a.joint_sd.empty()) {
    po.noise.joint_sd = a.joint_sd;
    po.bundle.scale_covariance = true;
  }

  // The image front end runs on `threads` OpenCV threads: its results do not depend on them (test
  // app-deterministic). Everything after it runs on one thread, OpenMP included (OpenCV's
  // setNumThreads sets OpenMP's count, which CHOLMOD/SPQR in the covariance use, and their sums
  // change with it); Ceres's multi-threaded Schur elimination also sums in a scheduling-dependent
  // order. The result files must be bit-reproducible.
  cv::setNumThreads(a.threads);
  vpSelfCalibDataset ds = vpSelfCalibDataset::loadYaml(dataset);
  const vpKinematicChain nominal = vpKinematicChain::fromPresetOrFile(ds.robot);
  co.prior = nominal; // the front end's matching is guided by the nominal kinematics
  // Outputs: a set written in a private directory beside --out, moved into place at once, under
  // a lock on --out; never over an input, never over files that are not an earlier run's results.
  vpSelfCalibOutputDirectory outdir(out);
  if (const int refused = checkOutputDirectory(outdir, out, calibrationInputs(dataset, ds), a.force))
    return refused;
  const size_t num_images = ds.views.size();
  if (vpSelfCalibImageCorrespondences::needsFrontEnd(ds))
    std::cerr << "... image front end (" << num_images << " images)\n";
  else if (co.board)
    std::cerr << "warning: --board: the dataset's views come with their points; the board is not looked for\n";
  const vpSelfCalibImageCorrespondences::Result cr = vpSelfCalibImageCorrespondences::fromDatasetImages(ds, co);
  if (cr.front_end_ran) {
    if (!co.front_end.dot_grids.empty())
      std::cerr << "... dot grids found " << cr.grids_found << " times in " << num_images << " images\n";
    std::cerr << "... " << cr.front_end.num_tracks << " tracks, yardstick in " << cr.yardstick_images << " images, "
              << std::setprecision(2) << cr.front_end.seconds << " s\n";
  }
  if (cr.board_ran) {
    std::cerr << "... board " << vpBoardDetector::toString(*co.board) << " found in " << cr.board_images << " of "
              << num_images << " images\n";
    if (cr.board_yardstick)
      std::cerr << "... yardstick: the ends of the board's first row (ids " << ds.yardstick.id_a << ", "
                << ds.yardstick.id_b << "), " << std::setprecision(6) << ds.yardstick.length << " m\n";
  }
  for (const std::string &w : cr.warnings)
    std::cerr << "warning: " << w << "\n";
  if (cr.front_end_ran || cr.board_ran) {
    for (auto d = cr.dropped.rbegin(); d != cr.dropped.rend(); ++d)
      std::cerr << "warning: view " << d->index << " (" << d->image << "): no correspondence found; left out\n";
  }
  cv::setNumThreads(1);
  po.method = cr.method;
  if (pose_auto && po.method != vpRobotSelfCalibration::HAND_EYE)
    std::cerr << "warning: --pose-sd auto measures the controller poses' error (hand-eye); the method is "
              << vpRobotSelfCalibration::methodName(po.method) << ", so it is not used\n";
  else if (pose_auto && !(ds.pose_sd_translation > 0)) { // no robot_error to start from: a serial arm's accuracy
    po.noise.pose_sd_translation = po.noise.pose_sd_rotation = 2e-3;
    po.bundle.scale_covariance = true;
  }
  if (a.pose_sd.size() == 2) {
    // The controller poses' error (hand-eye), or the kinematic model's residual (bundle); the
    // paper's method models neither.
    const double t = std::stod(a.pose_sd[0]), r = std::stod(a.pose_sd[1]);
    if (po.method == vpRobotSelfCalibration::HAND_EYE) {
      po.noise.pose_sd_translation = t;
      po.noise.pose_sd_rotation = r;
    } else if (po.method == vpRobotSelfCalibration::BUNDLE_ADJUSTMENT) {
      po.noise.model_sd_translation = t;
      po.noise.model_sd_rotation = r;
    }
  }
  Protocol protocol;
  if (const int bad = prepareProtocol(a, static_cast<unsigned int>(ds.views.size()), po, protocol))
    return bad;

  vpRobotSelfCalibration::Result r =
      vpRobotSelfCalibration::run(nominal, ds, po, [](const std::string &stage, unsigned int, unsigned int) {
        std::cerr << "... " << stage << "\n";
      });
  if (r.status != vpRobotSelfCalibration::OK && r.status != vpRobotSelfCalibration::DOUBTFUL) {
    std::cerr << "calibration failed: " << vpRobotSelfCalibration::statusName(r.status) << ": " << r.message << "\n";
    return 3;
  }
  runProtocol(nominal, ds, po, r, co, a.threads, protocol);
  const vpRobotSelfCalibration::Result run_result = r; // the run itself, the last point of Figure 6
  crossValidationCheck(protocol, r);
  for (const auto &f : r.findings)
    std::cerr << vpSelfCalibDataCheck::severityName(f.severity) << ": " << f.message << "\n";
  // A doubtful model is written all the same, marked so (its name, results.yaml's status, the report).
  const bool doubtful = r.status == vpRobotSelfCalibration::DOUBTFUL;
  const fs::path stage = outdir.staging();
  vpKinematicChain model = r.calibrated;
  model.setName(nominal.getName() + (doubtful ? "-calibrated-DOUBTFUL" : "-calibrated"));
  model.saveYaml((stage / "model.yaml").string());
  vpModelExport::saveURDF(model, (stage / "model.urdf").string());
  vpSelfCalibFileWriter::writeCameraXml((stage / "camera.xml").string(), r.camera, "Camera", ds.width, ds.height,
                                        "self-calibrated by visp-selfcalib");
  vpSelfCalibFileWriter::write((stage / "results.yaml").string(), resultsYaml(r, nominal, dataset, protocol), "results");
  std::cerr << "... report\n";
  const vpSelfCalibPoseStudy::Result study = // Figure 6
      vpSelfCalibPoseStudy::run(nominal, ds, po, vpSelfCalibPoseStudy::Options(), {}, &run_result);
  const vpSelfCalibReport::Result rep =
      vpSelfCalibReport::write((stage / "report").string(), nominal, ds, po, r,
                               cr.front_end_ran ? &cr.front_end : nullptr, &study, vpSelfCalibReport::Options(),
                               protocol.cv ? &*protocol.cv : nullptr, protocol.verified ? &*protocol.verified : nullptr);
  outdir.commit();

  const std::string files[4] = {(fs::path(out) / "model.yaml").string(), (fs::path(out) / "camera.xml").string(),
                                (fs::path(out) / "results.yaml").string(), (fs::path(out) / "model.urdf").string()};
  printSummary(r, po.num_calibration_poses);
  std::cout << "\n";
  printProtocol(protocol);
  std::cout << "wrote " << files[0] << ", " << files[1] << ", " << files[2] << ", " << files[3] << "\n";
  std::cout << "report: " << (fs::path(out) / "report").string() << "/report.md (" << rep.message << ")\n";
  if (doubtful) {
    std::cerr << "calibration doubtful: the model is written (marked so) but failed the checks above; "
                 "see results.yaml's findings of severity doubt\n";
    return 3;
  }
  return 0;
}

int verify(const std::string &model_name, const std::string &dataset)
{
  const vpKinematicChain model = vpKinematicChain::fromPresetOrFile(model_name);
  const vpSelfCalibDataset ds = vpSelfCalibDataset::loadYaml(dataset);
  if (!ds.yardstick.isSet()) {
    std::cerr << "error: dataset '" << dataset << "' has no yardstick to verify against\n";
    return 1;
  }
  const vpCalibrationVerifier::Result v = vpCalibrationVerifier::verify(model, ds.cam, ds.views, ds.yardstick);
  if (!v.has_yardstick) {
    std::cerr << "error: the yardstick's ends are not seen in two views of '" << dataset << "'\n";
    return 1;
  }
  std::cout << std::setprecision(6) << "yardstick length " << v.yardstick_length << " m (true " << ds.yardstick.length
            << "), 3-D error " << 1e3 * v.yardstick_error << " mm, " << v.points.size() << " points triangulated\n";
  return 0;
}
// ---------------------------------------------------------------------------------------------
// plan

struct PlanArgs {
  std::string out, robot = "viper850", method = "observability";
  vpSelfCalibSimulator::Options so;
  unsigned int poses = 15, held_out = 10;
  bool force = false;
};

void addPlan(CLI::App &app, PlanArgs &a)
{
  CLI::App *c = app.add_subcommand("plan", "planned calibration poses of the reference scenario");
  c->footer("Writes calibration poses planned on the reference scenario's nominal model, then random held-out\n"
            "poses, one joint vector per line.");
  c->add_option("OUT.txt", a.out, "the file to write")->type_name("FILE")->required();
  addRobotOption(*c, a.robot);
  c->add_option("--seed", a.so.seed, "scenario seed (default 1)")->type_name("N")->check(selfcalibCli::wholeNumber());
  c->add_option("--poses", a.poses, "calibration poses, 6 to 1000 (default 15)")
      ->type_name("N")
      ->check(selfcalibCli::wholeNumber(6, 1000));
  c->add_option("--held-out", a.held_out, "held-out poses after them, at most 10000 (default 10)")
      ->type_name("N")
      ->check(selfcalibCli::wholeNumber(0, 10000));
  c->add_option("--method", a.method,
                "observability (default): O1-optimal choice from a pool; paper: the paper's\n"
                "optimal trajectory (eqs. 22-39)")
      ->type_name("M")
      ->check(CLI::IsMember({"observability", "paper"}));
  c->add_flag("--force", a.force, "replace an existing OUT.txt");
}

int plan(const PlanArgs &a)
{
  const std::string &out = a.out, &robot = a.robot, &method = a.method;
  const vpSelfCalibSimulator::Options &so = a.so;
  const unsigned int poses = a.poses, held_out = a.held_out;
  if (!a.force && !canonical(out).empty()) {
    std::cerr << "error: '" << out << "' exists; use --force to replace it\n";
    return 1;
  }
  const vpSelfCalibSimulator sim(vpKinematicChain::fromPresetOrFile(robot), so);
  const unsigned int pool = method == "observability" ? 60 : 0;
  std::cerr << "... random feasible configurations\n";
  const std::vector<vpColVector> q = sim.generateConfigurations(poses + held_out + pool);
  const std::vector<vpColVector> initial(q.begin(), q.begin() + poses);
  const vpMeasurementPlanner planner(sim.getNominalChain(), sim.getPlannerScene());
  vpMeasurementPlanner::Result pr;
  if (method == "paper") {
    vpMeasurementPlanner::TrajectoryOptions to;
    to.seed = so.seed;
    pr = planner.planTrajectory(initial, to, [](const std::string &stage, unsigned int d, unsigned int n) {
      std::cerr << "... " << stage << " " << d + 1 << "/" << n << "\n";
    });
  } else {
    std::vector<vpColVector> candidates = initial;
    candidates.insert(candidates.end(), q.begin() + poses + held_out, q.end());
    pr = planner.selectObservable(candidates, poses);
  }
  if (pr.status != vpMeasurementPlanner::OK) {
    std::cerr << "planning failed: " << vpMeasurementPlanner::statusName(pr.status) << ": " << pr.message << "\n";
    return 3;
  }
  std::ostringstream os;
  os << std::setprecision(17) << "# " << robot << ", seed " << so.seed << ": " << poses << " planned (" << method
     << ") calibration poses, then " << held_out << " random held-out poses; rad\n";
  std::vector<vpColVector> all = pr.configurations;
  all.insert(all.end(), q.begin() + poses, q.begin() + poses + held_out);
  for (const vpColVector &c : all) {
    for (unsigned int i = 0; i < c.size(); ++i)
      os << c[i] << (i + 1 < c.size() ? " " : "\n");
  }
  vpSelfCalibFileWriter::write(out, os.str(), "plan");
  std::cout << "wrote " << out << ": " << poses << " planned + " << held_out << " held-out configurations; "
            << std::setprecision(3) << "cond(J) " << pr.before.condition << " -> " << pr.after.condition << ", O1 "
            << pr.observability_before.O1 << " -> " << pr.observability_after.O1 << ", " << std::setprecision(2)
            << pr.seconds << " s\n";
  return 0;
}

// ---------------------------------------------------------------------------------------------
// import

struct ImportArgs {
  std::string path, out, robot, intrinsics;
  bool force = false;
};

void addImport(CLI::App &app, ImportArgs &a)
{
  CLI::App *c =
      app.add_subcommand("import", "a dataset from a ViSP hand-eye folder or an industrial_calibration cal_data.yaml");
  c->footer("Reads PATH: a ViSP hand-eye folder (<prefix>_pose_rPe_N.yaml or _fPe_N.yaml, <prefix>_image-N.png,\n"
            "a camera XML), or industrial_calibration's cal_data.yaml (the file or its folder), and writes a\n"
            "dataset of controller poses fMe and images (calibrate runs the front end on them). Pose files:\n"
            "ViSP pose vectors, x y z qx qy qz qw, or 4 x 4 matrices. Prints what it found and what it could not\n"
            "use. A robot model, when one is needed (an eMc guess in the data, or no --robot for a robot without\n"
            "a preset), is written beside OUT.yaml as OUT-robot.yaml. Refuses to replace an existing file\n"
            "without --force, and never writes over an input.\n"
            "Exit codes: 0 imported, 1 bad input (message on stderr), 2 bad usage.");
  c->add_option("PATH", a.path, "the folder, or the cal_data.yaml file")->type_name("PATH")->required();
  c->add_option("--out", a.out, "the dataset file to write")->type_name("OUT.yaml")->required();
  std::string presets;
  for (const std::string &p : vpKinematicChain::presetNames())
    presets += (presets.empty() ? "" : ", ") + p;
  c->add_option("--robot", a.robot,
                "a preset (" + presets +
                    ") or a robot-model file (default: panda for ViSP\n"
                    "franka_ folders, else a generic hand-eye model: the hand-eye calibration uses only\n"
                    "its eMc guess)")
      ->type_name("NAME|FILE");
  c->add_option("--intrinsics", a.intrinsics,
                "known: the focal length is fixed; guess: it is self-calibrated from the given one\n"
                "(default: known for a ViSP camera XML, guess for cal_data.yaml's nominal intrinsics)")
      ->type_name("known|guess")
      ->check(CLI::IsMember({"known", "guess"}));
  c->add_flag("--force", a.force, "replace an existing OUT.yaml (and OUT-robot.yaml)");
}

int importData(const ImportArgs &a)
{
  if (!a.force && !canonical(a.out).empty()) {
    std::cerr << "error: '" << a.out << "' exists; use --force to replace it\n";
    return 1;
  }
  vpSelfCalibImporter::Options io;
  io.robot = a.robot;
  io.intrinsics = a.intrinsics.empty() ? vpSelfCalibImporter::INTRINSICS_DEFAULT
                                       : (a.intrinsics == "known" ? vpSelfCalibImporter::INTRINSICS_KNOWN
                                                                  : vpSelfCalibImporter::INTRINSICS_GUESS);
  const vpSelfCalibImporter::Result res = vpSelfCalibImporter::import(a.path, io);
  std::vector<std::string> outputs = {a.out};
  if (res.has_robot_model)
    outputs.push_back(vpSelfCalibImporter::robotModelFileFor(a.out));
  for (const std::string &f : outputs) {
    const std::string c = canonical(f);
    if (c.empty())
      continue;
    for (const std::string &in : res.inputs)
      if (c == canonical(in)) {
        std::cerr << "error: '" << f << "' is an input of this import; choose another --out\n";
        return 1;
      }
    if (!a.force) {
      std::cerr << "error: '" << f << "' exists; use --force to replace it\n";
      return 1;
    }
  }
  res.save(a.out);
  const vpSelfCalibImporter::Report &r = res.report;
  std::cout << "found " << vpSelfCalibImporter::layoutName(r.layout) << " " << r.source << "\n"
            << "  poses:  " << r.num_pose_files << " pose files, " << r.num_images << " images: " << r.num_views
            << " views; " << r.pose_format << "\n"
            << "  camera: " << r.camera << "\n"
            << "  robot:  " << r.robot << "\n"
            << "  board:  " << (r.board.empty() ? "none described" : r.board)
            << (r.board.empty() ? "" : "; used only with calibrate --board TYPE:RxC:SPACING (else natural features)")
            << "\n"
            << "  robot error: " << r.robot_error << "\n";
  if (!r.unused.empty()) {
    std::cout << "not used:\n";
    for (const vpSelfCalibImporter::Unused &u : r.unused)
      std::cout << "  " << u.what << ": " << u.reason << "\n";
  }
  std::cout << "wrote " << a.out;
  if (res.has_robot_model)
    std::cout << " and " << vpSelfCalibImporter::robotModelFileFor(a.out);
  std::cout << ": " << r.num_views << " views\nnext: " << kProgram << " calibrate " << a.out << " --out DIR\n";
  return 0;
}

// ---------------------------------------------------------------------------------------------
// export

struct ExportArgs {
  std::string model, urdf, dh, mdh;
  bool force = false;
};

void addExport(CLI::App &app, ExportArgs &a)
{
  CLI::App *c = app.add_subcommand("export", "URDF joint origins, or a corrected (modified) DH table");
  c->footer("Writes the model as URDF joint origins (exact), or as a DH / modified-DH robot-model file without\n"
            "corrections when one reproduces it (exit 3 when none does; a warning when it is ill-conditioned).");
  c->add_option("MODEL", a.model, kModelHelp)->type_name("NAME|FILE")->required();
  CLI::Option_group *g = c->add_option_group("output", "the file to write");
  g->add_option("--urdf", a.urdf, "URDF joint origins")->type_name("OUT.urdf");
  g->add_option("--dh", a.dh, "a DH robot-model file")->type_name("OUT.yaml");
  g->add_option("--mdh", a.mdh, "a modified-DH robot-model file")->type_name("OUT.yaml");
  g->require_option(1);
  c->add_flag("--force", a.force, "replace an existing output file");
}

int exportModel(const ExportArgs &a)
{
  const std::string &model_name = a.model;
  const std::string &out = !a.urdf.empty() ? a.urdf : (!a.dh.empty() ? a.dh : a.mdh);
  const vpKinematicChain model = vpKinematicChain::fromPresetOrFile(model_name);
  if (!canonical(out).empty() && canonical(out) == canonical(model_name)) {
    std::cerr << "error: '" << out << "' is the input model\n";
    return 1;
  }
  if (!a.force && !canonical(out).empty()) {
    std::cerr << "error: '" << out << "' exists; use --force to replace it\n";
    return 1;
  }
  if (!a.urdf.empty()) {
    vpModelExport::saveURDF(model, out);
    std::cout << "wrote " << out << "\n";
    return 0;
  }
  const vpModelExport::DHFit fit =
      vpModelExport::fitDH(model, !a.dh.empty() ? vpKinematicChain::DH : vpKinematicChain::MDH);
  std::cerr << fit.message << "\n";
  if (!fit.representable)
    return 3;
  fit.table.saveYaml(out);
  std::cout << "wrote " << out << (fit.well_conditioned ? "" : " (ill-conditioned, see above)") << "\n";
  return 0;
}

// ---------------------------------------------------------------------------------------------
// info, predict, verify

struct ModelArgs {
  std::string model, second; //!< predict: the joints file; verify: the dataset
};

int run(int argc, char **argv)
{
  CLI::App app("Self-calibration of a camera-equipped robot arm (ViSP SelfCalib): plan the poses, simulate or\n"
               "import a dataset, calibrate, verify, predict camera poses and export the calibrated model.",
               kProgram);
  app.require_subcommand(1);
  app.footer("MODEL: a preset (puma560, viper850) or a robot-model YAML file. DATASET: a dataset YAML file (README).\n"
             "'visp-selfcalib COMMAND --help' describes a command and its options.\n"
             "Exit codes: 0 success, 1 bad input (message on stderr), 2 bad usage, 3 the calibration failed.");
  ModelArgs info_args, predict_args, verify_args;
  CLI::App *info_cmd = app.add_subcommand("info", "robot model summary and error-model parameters");
  info_cmd->footer("Prints the robot model: convention, joints, number of error-model parameters, the corrections\n"
                   "that are not zero.");
  info_cmd->add_option("MODEL", info_args.model, kModelHelp)->type_name("NAME|FILE")->required();
  CLI::App *predict_cmd = app.add_subcommand("predict", "fMc for each joint vector (one per line, rad)");
  predict_cmd->footer(
      "Reads one joint vector per line (rad, separated by spaces or commas; '#' starts a comment) from\n"
      "JOINTS_FILE or standard input and prints the camera pose fMc as 'tx ty tz tux tuy tuz' (m, rad)\n"
      "per line.");
  predict_cmd->add_option("MODEL", predict_args.model, kModelHelp)->type_name("NAME|FILE")->required();
  predict_cmd->add_option("JOINTS_FILE", predict_args.second, "joint vectors (default: standard input)")
      ->type_name("FILE");
  PlanArgs plan_args;
  addPlan(app, plan_args);
  SimulateArgs simulate_args;
  addSimulate(app, simulate_args);
  AcquireArgs acquire_args;
  addAcquire(app, acquire_args);
  ImportArgs import_args;
  addImport(app, import_args);
  CalibrateArgs calibrate_args;
  addCalibrate(app, calibrate_args);
  CLI::App *verify_cmd = app.add_subcommand("verify", "the paper's 3-D yardstick error of a model");
  verify_cmd->footer("Prints the paper's 3-D yardstick error of MODEL on the dataset's views.");
  verify_cmd->add_option("MODEL", verify_args.model, kModelHelp)->type_name("NAME|FILE")->required();
  verify_cmd->add_option("DATASET", verify_args.second, "a dataset YAML file")->type_name("FILE")->required();
  ExportArgs export_args;
  addExport(app, export_args);

  if (argc == 2 && std::string(argv[1]) == "help") {
    std::cout << app.help();
    return 0;
  }
  if (argc >= 2 && argv[1][0] != '-') {
    // CLI11 would only say that a command is required.
    std::string names;
    bool known = false;
    for (const CLI::App *sub : app.get_subcommands({})) {
      names += (names.empty() ? "" : ", ") + sub->get_name();
      known = known || sub->get_name() == argv[1];
    }
    if (!known) {
      std::cerr << "error: unknown command '" << argv[1] << "' (" << names << ")\n'" << kProgram
                << " --help' lists the commands.\n";
      return selfcalibCli::kUsageError;
    }
  }
  const int parsed = selfcalibCli::parse(app, argc, argv);
  if (parsed >= 0)
    return parsed;
  if (app.got_subcommand("simulate"))
    return simulate(simulate_args);
  if (app.got_subcommand("acquire"))
    return acquire(acquire_args);
  if (app.got_subcommand("import"))
    return importData(import_args);
  if (app.got_subcommand("calibrate"))
    return calibrate(calibrate_args);
  if (app.got_subcommand("export"))
    return exportModel(export_args);
  if (app.got_subcommand("plan"))
    return plan(plan_args);
  if (app.got_subcommand("verify"))
    return verify(verify_args.model, verify_args.second);
  if (app.got_subcommand("info"))
    return info(vpKinematicChain::fromPresetOrFile(info_args.model));
  const vpKinematicChain chain = vpKinematicChain::fromPresetOrFile(predict_args.model);
  if (!predict_args.second.empty()) {
    std::ifstream in(predict_args.second);
    if (!in) {
      std::cerr << "error: cannot open joints file '" << predict_args.second << "'\n";
      return 1;
    }
    return predict(chain, in, predict_args.second);
  }
  return predict(chain, std::cin, "<stdin>");
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
