/*
 * visp-selfcalib import: a dataset from a ViSP hand-eye folder or an industrial_calibration cal_data.yaml.
 */
#include "commands.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>

#include <visp3/selfcalib/vpBoardDetector.h>
#include <visp3/selfcalib/vpFeatureFrontEnd.h>
#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpSelfCalibImporter.h>

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

namespace
{
//! Whether `file` is a regular file whose whole content is `text`.
bool holdsText(const std::string &file, const std::string &text)
{
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec) || std::filesystem::file_size(file, ec) != text.size() || ec)
    return false;
  std::ifstream in(file, std::ios::binary);
  std::string content(text.size(), '\0');
  return in.read(&content[0], static_cast<std::streamsize>(content.size())) && content == text;
}

/*
  An AprilTag of any id (the tag description gives the family and the side, not the id): the ids
  the views show, and in how many views each. calibrate's board of any id takes tag 0's corners as
  the yardstick and cannot use the tag's layout; with the id, both are the tag's.
*/
std::map<int, unsigned int> tagsSeen(const vpSelfCalibDataset &ds, const std::string &board_option)
{
  std::map<int, unsigned int> seen;
  if (board_option.rfind("apriltag:", 0) != 0 || std::count(board_option.begin(), board_option.end(), ':') != 2)
    return seen;
  const vpBoardDetector detector(vpBoardDetector::parse(board_option));
  const int offset = detector.getOptions().id_offset;
  for (size_t k = 0; k < ds.views.size(); ++k) {
    if (ds.views[k].image.empty())
      continue;
    std::set<int> tags;
    for (const auto &c : detector.detect(vpFeatureFrontEnd::readImage(ds.views[k].image, "view " + std::to_string(k))).corners)
      tags.insert((c.id - offset) / 4);
    for (int t : tags)
      ++seen[t];
  }
  return seen;
}

//! import's last lines: the calibrate command that fits what it found ("next: ...").
void printNext(const ImportArgs &a, const vpSelfCalibImporter::Result &res, bool nominal_intrinsics)
{
  const vpSelfCalibImporter::Report &r = res.report;
  const std::map<int, unsigned int> tags = tagsSeen(res.dataset, r.board_option);
  // One tag, in two views or more: its id makes the tag's corners the yardstick and its layout eMo's start.
  const bool one_tag = tags.size() == 1 && tags.begin()->second >= 2;
  const std::string board =
      one_tag ? r.board_option + ":" + std::to_string(tags.begin()->first) + " --board-geometry" : r.board_option;
  std::cout << "next: " << kProgram << " calibrate " << a.out << " --out DIR"
            << (board.empty() ? "" : " --method hand-eye --board " + board)
            << (nominal_intrinsics ? " --estimate pp,distortion" : "") << "\n";
  if (one_tag)
    std::cout << "  (tag " << tags.begin()->first << " is seen in " << tags.begin()->second << " of the "
              << res.dataset.views.size() << " images: its id makes its corners the yardstick, and its layout "
              << "(--board-geometry) gives the tag's pose eMo)\n";
  else if (r.board_option.rfind("apriltag:", 0) == 0) {
    std::cout << "  (the tag's pose eMo too: give its id and its geometry, --board " << r.board_option
              << ":ID --board-geometry";
    for (auto it = tags.begin(); it != tags.end(); ++it)
      std::cout << (it == tags.begin() ? "; tags seen: " : ", ") << it->first << " in " << it->second << " images";
    std::cout << ")\n";
  }
}
} // namespace

int importData(const ImportArgs &a)
{
  const std::vector<std::string> presets = vpKinematicChain::presetNames();
  std::error_code ec;
  if (!a.robot.empty() && std::find(presets.begin(), presets.end(), a.robot) == presets.end() &&
      !std::filesystem::exists(a.robot, ec)) {
    std::string names;
    for (const std::string &p : presets)
      names += (names.empty() ? "" : ", ") + p;
    throw CLI::ValidationError("--robot", "'" + a.robot + "' is neither a preset (" + names +
                                              ") nor a robot-model file (DH/MDH YAML or URDF)");
  }
  if (outputRefused(a.out, a.force))
    return 1;
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
    // A model identical to the one to write is no conflict (an import stopped between the model and
    // the dataset left it, or an import of the same folder): nothing is lost by writing it again.
    if (!a.force && !(f != a.out && holdsText(f, res.robot_model.toYamlString()))) {
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
            << (controllerPosesOnly(res.dataset) ? "          (the views are controller poses: calibrate --method hand-eye "
                                                  "takes them as they are and uses none of this model's kinematics, "
                                                  "only its eMc guess; the model is the bundle method's, on joint "
                                                  "readings)\n" : "")
            << "  board:  " << (r.board.empty() ? "none described" : r.board)
            << (r.board.empty()            ? ""
                : r.board_option.empty() ? "; used only with calibrate --board TYPE:RxC:SPACING (else natural features)"
                                         : "; used with calibrate --board " + r.board_option + " (else natural features)")
            << "\n"
            << "  robot error: " << r.robot_error << "\n";
  if (!r.unused.empty()) {
    std::cout << "not used:\n";
    for (const vpSelfCalibImporter::Unused &u : r.unused)
      std::cout << "  " << u.what << ": " << u.reason << "\n";
  }
  // cal_data.yaml's intrinsics are nominal values (fx = fy, the image centre, no distortion): with
  // them a guess, the principal point and the distortion are estimated too.
  const bool nominal_intrinsics =
      r.layout == vpSelfCalibImporter::INDUSTRIAL_CALIBRATION && !res.dataset.focal_known;
  std::cout << "wrote " << a.out;
  if (res.has_robot_model)
    std::cout << " and " << vpSelfCalibImporter::robotModelFileFor(a.out);
  std::cout << ": " << r.num_views << " views\n";
  printNext(a, res, nominal_intrinsics);
  return 0;
}
