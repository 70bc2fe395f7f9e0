/*
 * visp-selfcalib compare, a camera fixed in the world: an eye-to-hand result (bMc, eMo) measured
 * against the truth simulate --camera-mount world wrote (see compare.h).
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

namespace fs = std::filesystem;

namespace
{
//! The error of an estimated transform against the truth: distance, angle, and the largest component error in sd.
struct PoseError {
  double t = 0, r = 0, max_sd = 0;
};

vpHomogeneousMatrix poseOf(const YAML::Node &n, const std::string &key, const std::string &file)
{
  try {
    const std::vector<double> v = n.as<std::vector<double>>();
    if (v.size() == 6)
      return vpHomogeneousMatrix(vpPoseVector(v[0], v[1], v[2], v[3], v[4], v[5]));
  } catch (const YAML::Exception &) {
  }
  throw vpSelfCalibException(vpSelfCalibException::parseError,
                             "truth '" + file + "': key '" + key + "': expected a pose vector [tx, ty, tz, tux, tuy, tuz]");
}

/*
  est against truth: |t_est - t_true|, the angle of R_true^T R_est, and the largest |p_est,i -
  p_true,i| / sd_i over the six pose-vector components (the sd the result reports).
*/
PoseError poseError(const vpSelfCalibResultsFile::HandEye &est, const vpHomogeneousMatrix &truth)
{
  const vpHomogeneousMatrix M(vpPoseVector(est.pose[0], est.pose[1], est.pose[2], est.pose[3], est.pose[4], est.pose[5]));
  const vpHomogeneousMatrix d = truth.inverse() * M;
  PoseError e;
  e.t = (M.getTranslationVector() - truth.getTranslationVector()).frobeniusNorm();
  e.r = vpThetaUVector(d.getRotationMatrix()).getTheta();
  const vpPoseVector p(truth);
  for (unsigned int i = 0; i < 6 && i < est.sd.size(); ++i)
    if (est.sd[i] > 0)
      e.max_sd = std::max(e.max_sd, std::fabs(est.pose[i] - p[i]) / est.sd[i]);
  return e;
}

//! RMS and largest error (m, rad) of the camera's view of the target cMo(q) = bMc^-1 fMe(q) eMo.
struct ViewError {
  double rms_t = 0, rms_r = 0, max_t = 0, max_r = 0;
};

/*
  With joint readings: the calibrated model's cMo(q) (model.yaml's kinematics, results.yaml's bMc
  and eMo) against the true one over `n` configurations drawn uniformly within the joint limits
  (seeded), or over given configurations: what the camera would see of the target, the base frame
  included (a fixed camera observes it).
*/
std::vector<vpColVector> randomConfigurations(const vpKinematicChain &truth, unsigned int n)
{
  std::mt19937_64 rng(1);
  std::vector<vpColVector> qs;
  for (unsigned int k = 0; k < n; ++k) {
    vpColVector q(truth.getNumJoints());
    for (unsigned int j = 0; j < q.size(); ++j)
      q[j] = std::uniform_real_distribution<double>(truth.getJoints()[j].min, truth.getJoints()[j].max)(rng);
    qs.push_back(q);
  }
  return qs;
}

ViewError viewError(const vpKinematicChain &model, const vpHomogeneousMatrix &bMc, const vpHomogeneousMatrix &eMo,
                    const vpKinematicChain &truth, const vpHomogeneousMatrix &bMc_true,
                    const vpHomogeneousMatrix &eMo_true, const std::vector<vpColVector> &qs)
{
  ViewError e;
  const double n = static_cast<double>(qs.size());
  for (const vpColVector &q : qs) {
    const vpHomogeneousMatrix m = bMc.inverse() * model.get_fMe(q) * eMo,
                              t = bMc_true.inverse() * truth.get_fMe(q) * eMo_true, d = t.inverse() * m;
    const double et = d.getTranslationVector().frobeniusNorm(), er = vpThetaUVector(d.getRotationMatrix()).getTheta();
    e.rms_t += et * et / n;
    e.rms_r += er * er / n;
    e.max_t = std::max(e.max_t, et);
    e.max_r = std::max(e.max_r, er);
  }
  e.rms_t = std::sqrt(e.rms_t);
  e.rms_r = std::sqrt(e.rms_r);
  return e;
}

std::ostream &operator<<(std::ostream &os, const PoseError &e)
{
  return os << std::fixed << std::setprecision(3) << 1e3 * e.t << " mm / " << 1e3 * e.r << " mrad (largest component "
            << std::setprecision(2) << e.max_sd << " sd)";
}

std::ostream &operator<<(std::ostream &os, const ViewError &e)
{
  return os << std::fixed << std::setprecision(3) << 1e3 * e.rms_t << " mm / " << 1e3 * e.rms_r << " mrad RMS (largest "
            << 1e3 * e.max_t << " mm / " << 1e3 * e.max_r << " mrad)";
}

void emitView(YAML::Emitter &y, const char *key, const ViewError &e)
{
  y << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "rms_m" << YAML::Value << e.rms_t
    << YAML::Key << "rms_rad" << YAML::Value << e.rms_r << YAML::Key << "max_m" << YAML::Value << e.max_t << YAML::Key
    << "max_rad" << YAML::Value << e.max_r << YAML::EndMap;
}

void emit(YAML::Emitter &y, const char *key, const PoseError &e)
{
  y << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "t_m" << YAML::Value << e.t
    << YAML::Key << "r_rad" << YAML::Value << e.r << YAML::Key << "max_sd" << YAML::Value << e.max_sd << YAML::EndMap;
}

//! model.yaml of a result with joint readings, checked against the truth's nominal model.
vpKinematicChain resultModel(const fs::path &dir, const vpKinematicChain &nominal)
{
  const vpKinematicChain model = vpKinematicChain::loadYaml((dir / "model.yaml").string());
  bool same = model.getNumJoints() == nominal.getNumJoints() && model.getConvention() == nominal.getConvention();
  for (unsigned int j = 0; same && j < model.getNumJoints(); ++j) {
    const vpKinematicChain::Joint &m = model.getJoints()[j], &n = nominal.getJoints()[j];
    same = std::max({std::fabs(m.a - n.a), std::fabs(m.d - n.d), std::fabs(m.alpha - n.alpha),
                     std::fabs(m.theta_offset - n.theta_offset)}) <= 1e-9;
  }
  if (!same)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               (dir / "model.yaml").string() + ": its nominal table is not the truth's nominal model ('" +
                                   nominal.getName() + "'): not a result of this simulation's robot");
  return model;
}
} // namespace

int compareEyeToHand(const CompareArgs &a, const YAML::Node &root)
{
  const vpHomogeneousMatrix bMc_true = poseOf(root["bMc"], "bMc", a.truth), eMo_true = poseOf(root["eMo"], "eMo", a.truth);
  const fs::path dir(a.result);
  const vpSelfCalibResultsFile::Contents res = vpSelfCalibResultsFile::read((dir / "results.yaml").string());
  if (res.bMc && res.bMc->pose.size() == 6 && (!res.eMo || res.eMo->pose.size() != 6)) {
    std::cerr << "error: " << (dir / "results.yaml").string() << " has bMc but no eMo (the target's pose on the "
              << "tool): calibrate estimates it from the target's layout only (--board SPEC --board-geometry), and "
              << "compare measures the camera's view of the target with both; calibrate again with the layout\n";
    return 1;
  }
  if (!res.bMc || !res.eMo || res.bMc->pose.size() != 6 || res.eMo->pose.size() != 6) {
    std::cerr << "error: " << (dir / "results.yaml").string() << " has no bMc and eMo: the truth '" << a.truth
              << "' is of a camera fixed in the world; compare a result of calibrate on that simulation's dataset\n";
    return 1;
  }
  const bool joints = root["true_model"] && root["nominal_model"];
  ViewError views, nominal;
  std::string configurations;
  if (joints) {
    const vpKinematicChain truth = vpKinematicChain::fromYamlString(root["true_model"].as<std::string>(), a.truth + ": true_model");
    const vpKinematicChain model = resultModel(
        dir, vpKinematicChain::fromYamlString(root["nominal_model"].as<std::string>(), a.truth + ": nominal_model"));
    const auto pose = [](const std::vector<double> &p) { return vpHomogeneousMatrix(vpPoseVector(p[0], p[1], p[2], p[3], p[4], p[5])); };
    const std::vector<vpColVector> qs = a.joints.empty() ? randomConfigurations(truth, a.pairs)
                                                         : readJoints(a.joints, "joints file", truth.getNumJoints());
    configurations = a.joints.empty() ? std::to_string(a.pairs) + " random configurations"
                                      : std::to_string(qs.size()) + " configurations of " + a.joints;
    views = viewError(model, pose(res.bMc->pose), pose(res.eMo->pose), truth, bMc_true, eMo_true, qs);
    nominal = viewError(truth.nominal(), bMc_true, eMo_true, truth, bMc_true, eMo_true, qs);
  }
  if (!a.yaml.empty() && outputRefused(a.yaml, a.force))
    return 1;
  const PoseError e_bMc = poseError(*res.bMc, bMc_true), e_eMo = poseError(*res.eMo, eMo_true);
  std::cout << "camera in the world: bMc " << e_bMc << " off the truth; eMo " << e_eMo << "\n";
  // The full kinematics method: also against the truth in the model's own frames (compare.h).
  PoseError f_bMc, f_eMo;
  bool frames = false;
  if (joints && res.method == "bundle") {
    std::map<int, vpColVector> layout;
    for (const YAML::Node &p : root["points"])
      if (p.IsSequence() && p.size() == 4)
        layout[p[0].as<int>()] = vpColVector({p[1].as<double>(), p[2].as<double>(), p[3].as<double>()});
    std::vector<std::string> estimated;
    for (const auto &e : res.estimated)
      estimated.push_back(e.name);
    const std::string of = root["truth_of"] ? root["truth_of"].as<std::string>() : std::string();
    const YAML::Node cam = root["camera"];
    const vpCameraParameters c(cam["px"].as<double>(), cam["py"].as<double>(), cam["u0"].as<double>(), cam["v0"].as<double>());
    vpHomogeneousMatrix bMc_f, eMo_f;
    const std::string of_path = (fs::path(a.truth).parent_path() / of).string();
    frames = !of.empty() && truthInModelFrames(
        vpKinematicChain::fromYamlString(root["true_model"].as<std::string>(), a.truth + ": true_model"),
        vpKinematicChain::fromYamlString(root["nominal_model"].as<std::string>(), a.truth + ": nominal_model"), bMc_true,
        eMo_true, layout, c, of_path, estimated, bMc_f, eMo_f);
    if (!frames)
      std::cout << "bMc and eMo in the calibrated model's frames: not computed ("
                << (of.empty() ? a.truth + " names no dataset (truth_of)"
                               : of_path + " is missing or unreadable, or its joint readings do not fit the truth") << ")\n";
    if (frames) {
      f_bMc = poseError(*res.bMc, bMc_f);
      f_eMo = poseError(*res.eMo, eMo_f);
      std::cout << "in the calibrated model's frames (the true robot's base, joint 1 and last joint's offset taken "
                   "into bMc and eMo, as the model takes them): bMc "
                << f_bMc << " off; eMo " << f_eMo << "\n";
    }
  }
  if (joints)
    std::cout << "the camera's view of the target cMo(q), " << configurations << ": calibrated " << views
              << "; the nominal kinematics with the true bMc and eMo " << nominal << "\n";
  if (a.yaml.empty())
    return 0;
  YAML::Emitter y;
  y << YAML::BeginMap << YAML::Key << "result" << YAML::Value << a.result << YAML::Key << "truth" << YAML::Value
    << a.truth << YAML::Key << "camera_mount" << YAML::Value << "world";
  emit(y, "bMc_error", e_bMc);
  emit(y, "eMo_error", e_eMo);
  if (frames) {
    emit(y, "bMc_error_model_frames", f_bMc);
    emit(y, "eMo_error_model_frames", f_eMo);
  }
  if (joints) {
    y << YAML::Key << "view_error" << YAML::Value << YAML::BeginMap << YAML::Key << "configurations" << YAML::Value
      << configurations;
    emitView(y, "calibrated", views);
    emitView(y, "nominal_kinematics", nominal);
    y << YAML::EndMap;
  }
  y << YAML::EndMap;
  vpSelfCalibFileWriter::write(a.yaml, std::string(y.c_str()) + "\n", "comparison");
  std::cout << "wrote " << a.yaml << "\n";
  return 0;
}
