/*
 * visp-selfcalib verify: the paper's 3-D yardstick error of a model on a dataset's views.
 */
#include "commands.h"

#include <algorithm>
#include <iomanip>
#include <filesystem>
#include <iostream>

#include <visp3/selfcalib/vpCalibrationVerifier.h>
#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpSelfCalibDataCheck.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibImageCorrespondences.h>
#include <visp3/selfcalib/vpSelfCalibResultsFile.h>

void addVerify(CLI::App &app, ModelArgs &a)
{
  CLI::App *c = app.add_subcommand("verify", "the paper's 3-D yardstick error of a model");
  c->footer("Prints the paper's 3-D yardstick error of MODEL on the dataset's views. A dataset of images\n"
            "without points goes through the image front end first, as in calibrate (the yardstick's ends\n"
            "are found in the images).");
  c->add_option("MODEL", a.model, modelHelp())->type_name("NAME|FILE")->required();
  c->add_option("DATASET", a.second, "a dataset YAML file")->type_name("FILE")->required();
}

namespace
{
namespace fs = std::filesystem;

//! The views of ds that are views of cal too (sameView()).
size_t sharedViews(const vpSelfCalibDataset &ds, const vpSelfCalibDataset &cal)
{
  size_t shared = 0;
  for (const auto &v : ds.views)
    shared += std::any_of(cal.views.begin(), cal.views.end(), [&](const auto &c) { return sameView(v, c); });
  return shared;
}

/*
  The dataset a model was calibrated on (results.yaml beside the model names it) checks little: its
  yardstick set the calibration's scale on the views calibrated on. A note for stdout's figure line
  when the views verified are that dataset's (all, or some: a warning on stderr says which),
  empty otherwise. Not a refusal: with --holdout the same file holds the held-out views too.
*/
std::string calibrationDataNote(const std::string &model, const std::string &dataset, const vpSelfCalibDataset &ds)
{
  std::error_code ec;
  const fs::path results = fs::path(model).parent_path() / "results.yaml";
  if (!fs::is_regular_file(model, ec) || !fs::is_regular_file(results, ec))
    return "";
  vpSelfCalibResultsFile::Contents r;
  try {
    r = vpSelfCalibResultsFile::read(results.string());
  } catch (const vpSelfCalibException &) {
    return ""; // a results.yaml that does not read says nothing about this model
  }
  // Written as calibrate was given it: relative to where calibrate ran, the directory above --out as a rule.
  for (const fs::path &c : {fs::path(r.dataset), fs::absolute(model, ec).parent_path().parent_path() / r.dataset}) {
    if (r.dataset.empty() || !fs::is_regular_file(c, ec))
      continue;
    size_t shared = fs::equivalent(c, dataset, ec) ? ds.views.size() : 0;
    if (shared == 0) {
      try {
        shared = sharedViews(ds, vpSelfCalibDataset::loadYaml(c.string()));
      } catch (const vpSelfCalibException &) {
        continue;
      }
    }
    if (shared == 0)
      return "";
    std::cerr << "warning: " << shared << " of the " << ds.views.size() << " views of '" << dataset << "' are views of "
              << "the dataset " << model << " was calibrated on (" << results.string() << ": " << r.dataset << ", "
              << r.calibration_views << " views calibrated on): where the yardstick set the calibration's "
              << "scale, its 3-D error is not an independent check; verify on a dataset of other poses (calibrate "
              << "--heldout FILE reports one too)\n";
    return " (on views of the calibration dataset: not an independent check)";
  }
  return "";
}
} // namespace

int verify(const ModelArgs &a)
{
  const std::string &dataset = a.second;
  std::error_code ec;
  if (std::filesystem::is_directory(a.model, ec)) {
    const std::filesystem::path m = std::filesystem::path(a.model) / "model.yaml";
    std::cerr << "error: '" << a.model << "' is a directory: give the model file"
              << (std::filesystem::exists(m, ec) ? " (" + m.string() + ", the model calibrate wrote there)" : "")
              << "\n";
    return 1;
  }
  const vpKinematicChain model = readModelArgument(a.model);
  if (model.isCameraInWorld()) {
    std::cerr << "error: " << a.model << ": the camera is fixed in the world (camera_mount: world); verify "
              << "triangulates a yardstick through a camera on the end-effector: read an eye-to-hand model's "
              << "cross-validation in results.yaml, or compare a simulated one with its truth (compare)\n";
    return 1;
  }
  vpSelfCalibDataset ds = vpSelfCalibDataset::loadYaml(dataset);
  const std::string note = calibrationDataNote(a.model, dataset, ds);
  if (ds.camera_mount == vpSelfCalibDataset::CAMERA_IN_WORLD) {
    std::cerr << "error: dataset '" << dataset << "': camera_mount: world; verify triangulates the scene through a "
              << "camera on the flange (camera_mount: effector), which this dataset does not have\n";
    return 1;
  }
  if (vpSelfCalibImageCorrespondences::needsFrontEnd(ds)) {
    // Images without points (simulate --images, an acquisition): the front end finds the points
    // and the yardstick's ends as calibrate's does, guided by the model verified.
    std::cerr << "... image front end (" << ds.views.size() << " images)\n";
    vpSelfCalibImageCorrespondences::Options co;
    co.prior = model;
    const vpSelfCalibImageCorrespondences::Result cr = vpSelfCalibImageCorrespondences::fromDatasetImages(ds, co);
    for (const std::string &w : cr.warnings)
      std::cerr << "warning: " << w << "\n";
    for (const auto &d : cr.dropped)
      std::cerr << "warning: view " << d.index << " (" << d.image << "): no correspondence found; left out\n";
  }
  if (!ds.yardstick.isSet()) {
    std::cerr << "error: dataset '" << dataset << "' has no yardstick to verify against\n";
    return 1;
  }
  // The same check of the inputs as calibrate's: joints of another robot, or outside the model's
  // limits, are refused (its findings on the data's geometry are calibrate's business).
  vpSelfCalibDataCheck::check(model, ds, static_cast<unsigned int>(ds.views.size()), true,
                              vpSelfCalibDataCheck::Options(), vpSelfCalibNoiseModel());
  const vpCalibrationVerifier::Result v = vpCalibrationVerifier::verify(model, ds.cam, ds.views, ds.yardstick);
  if (!v.has_yardstick) {
    std::cerr << "error: the yardstick's ends are not seen in two views of '" << dataset << "'\n";
    return 1;
  }
  std::cout << std::setprecision(6) << "yardstick length " << v.yardstick_length << " m (true " << ds.yardstick.length
            << "), 3-D error " << 1e3 * v.yardstick_error << " mm, " << v.points.size() << " points triangulated" << note << "\n";
  return 0;
}
