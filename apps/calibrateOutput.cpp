/*
 * visp-selfcalib calibrate: its output directory's checks and what it prints (see calibrate.h).
 */
#include "calibrate.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <filesystem>
#include <iomanip>
#include <set>
#include <iostream>

#include <yaml-cpp/yaml.h>

#include <visp3/selfcalib/vpKinematicChain.h>

namespace fs = std::filesystem;

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

void printProtocol(const vpSelfCalibProtocol::Result &p)
{
  if (p.cv)
    std::cout << "cross-validation (" << p.cv->folds << " folds of " << p.cv->views << " views): " << p.cv->message
              << "\n";
  if (p.verified) {
    const vpSelfCalibCrossValidation::HeldOut &h = *p.verified;
    std::cout << std::setprecision(3) << "held-out dataset " << p.plan.heldout_file << " (" << h.views
              << " views): reprojection RMS " << h.calibrated.rms << " px calibrated vs " << h.nominal.rms
              << " px nominal";
    if (h.has_yardstick)
      std::cout << ", yardstick 3-D error " << 1e3 * h.yardstick_error_nominal << " mm (nominal) -> "
                << 1e3 * h.yardstick_error_calibrated << " mm";
    std::cout << std::defaultfloat << "\n";
  }
}

/*
  One line when the data left parameters at nominal: the command that proposes the poses to add. N is
  a first guess, one pose per joint the reasons ask to move (at least 2, at most 6); plan --from
  says what each pose adds.
*/
void printAddPoses(const vpRobotSelfCalibration::Result &r, const std::string &dataset)
{
  std::set<std::string> joints;
  bool any = false;
  auto need = [&](const vpKinematicIdentification::Unidentifiable &u) {
    any = true;
    const size_t at = u.needs.find(" moves ");
    if (at != std::string::npos && u.needs[0] == 'j')
      joints.insert(u.needs.substr(0, at));
  };
  for (const auto &u : r.identifiability.unidentifiable)
    if (u.cause == vpKinematicIdentification::CAUSE_DATA)
      need(u);
  for (const auto &u : r.identifiability.held_by_prior)
    need(u);
  if (!any)
    return;
  const size_t n = std::min<size_t>(6, std::max<size_t>(2, joints.size()));
  std::cout << "add these " << n << " poses: visp-selfcalib plan --from " << dataset << " --poses " << n
            << (r.identifiability.held_by_prior.empty() ? " (they determine the parameters left at nominal)\n"
                                                        : " (they determine the parameters the kinematic prior holds)\n");
}

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
  // The estimated set: what the user fixed, and what the data leave at nominal (results.yaml and the report say why).
  std::string fixed, by_data, needs;
  for (const auto &u : r.identifiability.unidentifiable)
    if (u.cause == vpKinematicIdentification::CAUSE_FIXED)
      fixed += (fixed.empty() ? "" : ", ") + u.name;
    else if (u.cause == vpKinematicIdentification::CAUSE_DATA) {
      by_data += (by_data.empty() ? "" : ", ") + u.name;
      if (needs.empty())
        needs = u.needs;
    }
  if (!fixed.empty())
    std::cout << "\nfixed by the user: " << fixed;
  if (!by_data.empty())
    std::cout << "\nleft at nominal (the data do not determine them): " << by_data << " (" << needs
              << "; results.yaml estimated_set.left_by_data)";
  std::string held;
  for (const auto &u : r.identifiability.held_by_prior)
    held += (held.empty() ? "" : ", ") + u.name;
  if (!held.empty())
    std::cout << "\nheld by the kinematic prior (the data alone do not determine them): " << held
              << " (results.yaml estimated_set.held_by_prior)";
  if (r.workspace.computed) {
    const auto line = [](const vpRobotSelfCalibration::WorkspaceError &w) {
      std::ostringstream os;
      os << std::fixed << std::setprecision(2) << 1e3 * w.calibrated_t << " mm / " << 1e3 * w.calibrated_r
         << " mrad RMS (90 % bound " << 1e3 * w.bound_t << " / " << 1e3 * w.bound_r << "), the nominal model "
         << 1e3 * w.nominal_t << " mm / " << 1e3 * w.nominal_r << " mrad";
      return os.str();
    };
    std::string within;
    for (const auto &j : r.workspace.joints_within)
      within += (within.empty() ? " (" : ", ") + j.joint + " as in the views";
    std::cout << "\npredicted error on " << (r.has_bMc ? "the target's motions in the camera" : "the camera's motions")
              << " over the joint limits" << (within.empty() ? "" : within + ")")
              << ": " << line(r.workspace);
    if (r.workspace_full_range.computed)
      std::cout << "; with every joint over its limits: " << line(r.workspace_full_range);
  }
  if (r.bundle.has_covariance && r.bundle.intrinsic_names.size() > 1) {
    std::cout << "\nintrinsics:";
    for (unsigned int i = 0; i < r.bundle.intrinsics.size(); ++i)
      std::cout << " " << r.bundle.intrinsic_names[i] << " " << std::setprecision(5) << r.bundle.intrinsics[i]
                << " +- " << std::setprecision(2) << r.bundle.intrinsics_sd[i];
    std::cout << std::defaultfloat;
  }
}

namespace
{
//! The first sentence of a message (to its first ". "), at most about 300 characters.
std::string firstSentence(const std::string &m)
{
  std::string s = m.substr(0, m.find(". "));
  if (s.size() > 300)
    s = s.substr(0, 297) + "...";
  return s;
}
} // namespace

void printStatus(const vpRobotSelfCalibration::Result &r, bool calibrated, size_t report_warnings)
{
  if (!calibrated) {
    std::cout << "status: " << (r.status == vpRobotSelfCalibration::DEGENERATE_DATA ? "refused: " : "failed: ")
              << vpRobotSelfCalibration::statusName(r.status) << ": " << r.message << "\n";
    return;
  }
  std::vector<const vpSelfCalibDataCheck::Finding *> doubts;
  for (const auto &f : r.findings)
    if (f.severity == vpSelfCalibDataCheck::DOUBT)
      doubts.push_back(&f);
  if (r.status != vpRobotSelfCalibration::DOUBTFUL || doubts.empty()) {
    if (r.status == vpRobotSelfCalibration::DOUBTFUL) {
      std::cout << "status: doubtful: see results.yaml's findings\n";
      return;
    }
    // ok, and the warnings named: a reader of the last line alone learns that there are some.
    // The report's own warnings (views the model does not explain) first: they name views dropped.
    std::string codes = report_warnings > 0 ? "views-unexplained" : "";
    size_t warnings = report_warnings > 0 ? 1 : 0;
    for (const auto &f : r.findings)
      if (f.severity == vpSelfCalibDataCheck::WARNING && warnings++ < 4)
        codes += (codes.empty() ? "" : ", ") + f.code;
    std::cout << "status: ok";
    if (warnings > 0)
      std::cout << ", with " << warnings << " warning" << (warnings > 1 ? "s" : "") << " (" << codes
                << (warnings > 4 ? ", ..." : "") << "): the 'warning' lines above say what each costs";
    std::cout << "\n";
    return;
  }
  std::cout << "status: doubtful: " << firstSentence(doubts[0]->message);
  if (doubts.size() > 1)
    std::cout << " (and " << doubts.size() - 1 << " more check" << (doubts.size() > 2 ? "s" : "") << " failed)";
  std::cout << "; the model is written, marked doubtful: the 'doubt' lines above and results.yaml's findings say "
               "what to do\n";
}
