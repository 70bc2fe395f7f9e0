/*
 * visp-selfcalib compare: a calibration result measured against the truth a simulation wrote.
 */
#include "compare.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <random>

#include <visp3/core/vpThetaUVector.h>
#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibFileWriter.h>
#include <visp3/selfcalib/vpSelfCalibResultsFile.h>
#include <visp3/selfcalib/vpSelfCalibTextFile.h>
#include <yaml-cpp/yaml.h>

#include "selfcalibCli.h"

namespace fs = std::filesystem;

namespace
{
//! The truth file's models and camera (what compare uses of it).
struct Truth {
  vpKinematicChain true_model, nominal;
  double px = 0, py = 0, u0 = 0, v0 = 0;
};

//! The truth file's YAML (a regular text file, read whole, then parsed).
YAML::Node readTruthFile(const std::string &file)
{
  const auto fail = [&file](const std::string &why) -> void {
    throw vpSelfCalibException(vpSelfCalibException::parseError,
                               "truth '" + file + "': " + why + " (a file " + kProgram + " simulate writes, STEM-truth.yaml)");
  };
  // Read as the module reads its own files: bounded while reading, no NUL byte, no blocking FIFO.
  const std::string text = vpSelfCalibTextFile::read(file, "truth", size_t(64) << 20);
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception &e) {
    fail("not YAML: " + e.msg);
  }
  return root;
}

Truth readTruth(const YAML::Node &root, const std::string &file)
{
  const auto fail = [&file](const std::string &why) -> void {
    throw vpSelfCalibException(vpSelfCalibException::parseError,
                               "truth '" + file + "': " + why + " (a file " + kProgram + " simulate writes, STEM-truth.yaml)");
  };
  if (!root.IsMap() || !root["true_model"] || !root["nominal_model"] || !root["camera"] || !root["camera"].IsMap())
    fail("expected the keys true_model, nominal_model and camera (or bMc and eMo: a camera fixed in the world)");
  Truth t{vpKinematicChain::fromYamlString(root["true_model"].as<std::string>(), file + ": true_model"),
          vpKinematicChain::fromYamlString(root["nominal_model"].as<std::string>(), file + ": nominal_model")};
  try {
    const YAML::Node c = root["camera"];
    t.px = c["px"].as<double>();
    t.py = c["py"].as<double>();
    t.u0 = c["u0"].as<double>();
    t.v0 = c["v0"].as<double>();
  } catch (const YAML::Exception &) {
    fail("camera: expected px, py, u0 and v0");
  }
  return t;
}

//! RMS and largest translation (m) and rotation (rad) errors of a model's relative camera motions.
struct MotionError {
  double rms_t = 0, rms_r = 0, max_t = 0, max_r = 0;
};

/*
  The error of `model`'s relative camera motions c_iMc_j against the true model's, over `pairs`
  pairs of configurations drawn uniformly within the true model's joint limits (seeded): free of
  the base frame, which self-calibration does not determine.
*/
MotionError motionError(const vpKinematicChain &model, const vpKinematicChain &truth, unsigned int pairs)
{
  std::mt19937_64 rng(1);
  const auto draw = [&]() {
    vpColVector q(truth.getNumJoints());
    for (unsigned int j = 0; j < q.size(); ++j)
      q[j] = std::uniform_real_distribution<double>(truth.getJoints()[j].min, truth.getJoints()[j].max)(rng);
    return q;
  };
  MotionError e;
  for (unsigned int k = 0; k < pairs; ++k) {
    const vpColVector qi = draw(), qj = draw();
    const vpHomogeneousMatrix m = model.get_fMc(qi).inverse() * model.get_fMc(qj),
                              t = truth.get_fMc(qi).inverse() * truth.get_fMc(qj), d = t.inverse() * m;
    const double et = d.getTranslationVector().frobeniusNorm(), er = vpThetaUVector(d.getRotationMatrix()).getTheta();
    e.rms_t += et * et;
    e.rms_r += er * er;
    e.max_t = std::max(e.max_t, et);
    e.max_r = std::max(e.max_r, er);
  }
  e.rms_t = std::sqrt(e.rms_t / pairs);
  e.rms_r = std::sqrt(e.rms_r / pairs);
  return e;
}

/*
  The main job's held-out pose error (vpCalibrationVerifier): the error of `model`'s relative camera
  motions c_0 M c_k between the first configuration and each other, against the true model's;
  the means over the k (m, rad).
*/
MotionError fromFirstError(const vpKinematicChain &model, const vpKinematicChain &truth, const std::vector<vpColVector> &qs)
{
  MotionError e;
  for (size_t k = 1; k < qs.size(); ++k) {
    const vpHomogeneousMatrix m = model.get_fMc(qs[0]).inverse() * model.get_fMc(qs[k]),
                              t = truth.get_fMc(qs[0]).inverse() * truth.get_fMc(qs[k]), d = t.inverse() * m;
    const double et = d.getTranslationVector().frobeniusNorm(), er = vpThetaUVector(d.getRotationMatrix()).getTheta();
    e.rms_t += et / static_cast<double>(qs.size() - 1); // the mean, in the fields of the RMS
    e.rms_r += er / static_cast<double>(qs.size() - 1);
    e.max_t = std::max(e.max_t, et);
    e.max_r = std::max(e.max_r, er);
  }
  return e;
}

void emitError(YAML::Emitter &y, const char *key, const MotionError &e, const char *mean_or_rms)
{
  y << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << (std::string(mean_or_rms) + "_m")
    << YAML::Value << e.rms_t << YAML::Key << (std::string(mean_or_rms) + "_rad") << YAML::Value << e.rms_r
    << YAML::Key << "max_m" << YAML::Value << e.max_t << YAML::Key << "max_rad" << YAML::Value << e.max_r
    << YAML::EndMap;
}

std::ostream &operator<<(std::ostream &os, const MotionError &e)
{
  return os << std::fixed << std::setprecision(3) << 1e3 * e.rms_t << " mm / " << 1e3 * e.rms_r << " mrad (largest "
            << 1e3 * e.max_t << " mm / " << 1e3 * e.max_r << " mrad)";
}
} // namespace

void addCompare(CLI::App &app, CompareArgs &a)
{
  CLI::App *c = app.add_subcommand("compare", "a calibration result against the truth of a simulation");
  c->footer("Measures RESULT_DIR (calibrate's --out: model.yaml, results.yaml) against TRUTH.yaml (written by\n"
            "simulate beside its dataset, STEM-truth.yaml): the error of the relative camera motions between\n"
            "pairs of random configurations within the joint limits (free of the base frame, which\n"
            "self-calibration does not determine), for the calibrated and the nominal model, and the error of\n"
            "the intrinsics. A truth of a camera fixed in the world (simulate --camera-mount world): the\n"
            "errors of bMc and eMo (distance, angle, and the largest component error in the result's sd),\n"
            "a --method bundle result's also against the truth in its model's frames (the true base, joint\n"
            "1 and last joint's offset, which a fixed camera does not tell from bMc and eMo, taken into\n"
            "them); with joint readings, of the camera's view of the target cMo(q) over --pairs random\n"
            "configurations (of --joints when given), the calibrated model's and the nominal kinematics'.");
  c->add_option("RESULT_DIR", a.result, "a directory calibrate wrote")->type_name("DIR")->required();
  c->add_option("TRUTH", a.truth, "the truth file simulate wrote")->type_name("FILE")->required();
  c->add_option("--pairs", a.pairs, "pairs of configurations drawn (default 1000)")
      ->type_name("N")
      ->check(selfcalibCli::wholeNumber(1, 1000000));
  c->add_option("--joints", a.joints,
                "configurations (one joint vector per line, as plan writes; e.g. its held-out poses):\n"
                "also the error of the relative camera motions from the first to each other, mean\n"
                "(the main job's 'relative pose error' on its held-out poses)")
      ->type_name("FILE");
  c->add_option("--yaml", a.yaml, "write the figures to OUT.yaml too (m, rad, px)")->type_name("OUT.yaml");
  c->add_flag("--force", a.force, "replace an existing --yaml file");
}

namespace
{
//! A truth simulated for another dataset (truth_of) than the result's (results.yaml): a warning (files get renamed).
void warnOtherSimulation(const CompareArgs &a, const YAML::Node &root)
{
  if (!root.IsMap() || !root["truth_of"] || !root["truth_of"].IsScalar())
    return;
  std::string calibrated;
  try {
    calibrated = vpSelfCalibResultsFile::read((fs::path(a.result) / "results.yaml").string()).dataset;
  } catch (const vpSelfCalibException &) {
    return; // the checks below say what is wrong with the result
  }
  const std::string truth_of = root["truth_of"].as<std::string>();
  if (!calibrated.empty() && fs::path(calibrated).filename() != fs::path(truth_of).filename())
    std::cerr << "warning: " << a.result << " was calibrated on " << calibrated << " (its results.yaml), and " << a.truth
              << " is the truth simulated for " << truth_of << ": unless one was renamed, the errors below measure "
              << "this result against another simulation's robot\n";
}
} // namespace

int compare(const CompareArgs &a)
{
  const YAML::Node root = readTruthFile(a.truth);
  const fs::path dir(a.result);
  std::error_code ec;
  if (!fs::is_directory(dir, ec) || !fs::exists(dir / "model.yaml", ec) || !fs::exists(dir / "results.yaml", ec)) {
    std::cerr << "error: '" << a.result << "' is not a directory calibrate wrote (its --out: model.yaml and "
              << "results.yaml): " << (fs::is_directory(dir, ec) ? "model.yaml or results.yaml is missing" : fs::exists(dir, ec) ? "not a directory" : "it is not there")
              << "\n";
    return 1;
  }
  warnOtherSimulation(a, root);
  if (root.IsMap() && root["bMc"] && root["eMo"]) // a camera fixed in the world
    return compareEyeToHand(a, root);
  const Truth t = readTruth(root, a.truth);
  const vpKinematicChain model = vpKinematicChain::loadYaml((dir / "model.yaml").string());
  const vpSelfCalibResultsFile::Contents res = vpSelfCalibResultsFile::read((dir / "results.yaml").string());
  if (res.bMc) {
    std::cerr << "error: '" << a.result << "' is an eye-to-hand result (bMc, eMo: the camera in the world): compare "
              << "measures the relative motions of a camera on the flange, which this result does not model\n";
    return 1;
  }
  if (model.getNumJoints() != t.true_model.getNumJoints()) {
    std::cerr << "error: " << (dir / "model.yaml").string() << " has " << model.getNumJoints() << " joints, the truth "
              << t.true_model.getNumJoints() << ": not a result of this simulation's robot\n";
    return 1;
  }
  // A result of this robot starts from the truth's nominal model: the same nominal table.
  for (unsigned int j = 0; j < model.getNumJoints(); ++j) {
    const vpKinematicChain::Joint &m = model.getJoints()[j], &n = t.nominal.getJoints()[j];
    const double diff = std::max({std::fabs(m.a - n.a), std::fabs(m.d - n.d), std::fabs(m.alpha - n.alpha),
                                  std::fabs(m.theta_offset - n.theta_offset)});
    if (diff > 1e-9 || model.getConvention() != t.nominal.getConvention()) {
      std::cerr << "error: " << (dir / "model.yaml").string() << ": joint " << j + 1
                << "'s nominal row differs from the truth's nominal model ('" << t.nominal.getName()
                << "'): not a result of this simulation's robot\n";
      return 1;
    }
  }
  std::vector<vpColVector> qs;
  if (!a.joints.empty()) {
    qs = readJoints(a.joints, "joints file", t.true_model.getNumJoints());
    if (qs.size() < 2) {
      std::cerr << "error: " << a.joints << ": at least 2 configurations are needed (the first and one other)\n";
      return 1;
    }
    // Configurations the arm cannot reach measure nothing it does (calibrate and verify refuse them too).
    for (size_t k = 0; k < qs.size(); ++k)
      for (unsigned int j = 0; j < qs[k].size(); ++j) {
        const vpKinematicChain::Joint &l = t.true_model.getJoints()[j];
        if (qs[k][j] < l.min || qs[k][j] > l.max) {
          std::cerr << "error: " << a.joints << ":" << k + 1 << ": joint " << j + 1 << " = " << qs[k][j]
                    << " rad is outside the model's limits [" << l.min << ", " << l.max << "]\n";
          return 1;
        }
      }
  }
  if (!a.yaml.empty() && outputRefused(a.yaml, a.force))
    return 1;
  const MotionError cal = motionError(model, t.true_model, a.pairs), nom = motionError(t.nominal, t.true_model, a.pairs);
  std::cout << "relative camera motions, " << a.pairs << " pairs of random configurations: calibrated " << cal
            << "; nominal " << nom << "\n";
  MotionError cal_q, nom_q;
  if (!qs.empty()) {
    cal_q = fromFirstError(model, t.true_model, qs);
    nom_q = fromFirstError(t.nominal, t.true_model, qs);
    std::cout << "relative camera motions from the first of the " << qs.size() << " configurations of " << a.joints
              << " to each other, mean: calibrated " << cal_q << "; nominal " << nom_q << "\n";
  }
  std::cout << std::fixed << std::setprecision(3) << "intrinsics: px " << res.camera.px - t.px << ", py "
            << res.camera.py - t.py << ", u0 " << res.camera.u0 - t.u0 << ", v0 " << res.camera.v0 - t.v0
            << " px off the truth (px " << t.px << ", py " << t.py << ", u0 " << t.u0 << ", v0 " << t.v0 << ")\n";
  if (a.yaml.empty())
    return 0;
  YAML::Emitter y;
  y << YAML::BeginMap << YAML::Key << "result" << YAML::Value << a.result << YAML::Key << "truth" << YAML::Value
    << a.truth << YAML::Key << "random_pairs" << YAML::Value << YAML::BeginMap << YAML::Key << "pairs" << YAML::Value
    << a.pairs;
  emitError(y, "calibrated", cal, "rms");
  emitError(y, "nominal", nom, "rms");
  y << YAML::EndMap;
  if (!qs.empty()) {
    y << YAML::Key << "from_first" << YAML::Value << YAML::BeginMap << YAML::Key << "joints" << YAML::Value << a.joints
      << YAML::Key << "configurations" << YAML::Value << qs.size();
    emitError(y, "calibrated", cal_q, "mean");
    emitError(y, "nominal", nom_q, "mean");
    y << YAML::EndMap;
  }
  y << YAML::Key << "intrinsics_error" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "px"
    << YAML::Value << res.camera.px - t.px << YAML::Key << "py" << YAML::Value << res.camera.py - t.py << YAML::Key
    << "u0" << YAML::Value << res.camera.u0 - t.u0 << YAML::Key << "v0" << YAML::Value << res.camera.v0 - t.v0
    << YAML::EndMap << YAML::EndMap;
  vpSelfCalibFileWriter::write(a.yaml, std::string(y.c_str()) + "\n", "comparison");
  std::cout << "wrote " << a.yaml << "\n";
  return 0;
}
