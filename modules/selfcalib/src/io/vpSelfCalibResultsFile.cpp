/*
 * ViSP SelfCalib: results.yaml, the record of a calibrate run (writer and reader).
 */
#include <visp3/selfcalib/vpSelfCalibResultsFile.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibFileWriter.h>

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "../core/vpSelfCalibFiles.h" // readTextFileBounded

namespace
{
using RF = vpSelfCalibResultsFile;
using CV = vpSelfCalibCrossValidation;

const char *const kRule = "walk the order; estimate a parameter when its column of the relative-pose Jacobian (nominal "
                          "model, joints only, 1 m = 1 rad) adds a new direction above the threshold";
const char *const kDataRule = "walk the order; estimate a parameter when its column of the relative-pose Jacobian (nominal "
                              "model, joints only, 1 m = 1 rad) adds a new direction above the threshold and the "
                              "bundle adjustment's information at the start values (stated noise, points, intrinsics "
                              "and robot error eliminated) separates it and keeps every sd within the tolerance";

// ---------------------------------------------------------------------------------------------
// From a run

RF::Camera cameraOf(const vpRobotSelfCalibration::Result &r)
{
  RF::Camera c;
  c.px = r.camera.get_px();
  c.py = r.camera.get_py();
  c.u0 = r.camera.get_u0();
  c.v0 = r.camera.get_v0();
  c.px_sd = r.fx_sd;
  c.distortion = r.bundle.opencv_distortion;
  return c;
}

RF::BundleAdjustment bundleOf(const vpRobotSelfCalibration::Result &r)
{
  const vpKinematicBundleAdjustment::Result &b = r.bundle;
  RF::BundleAdjustment a;
  a.observations = b.num_observations;
  a.dropped = b.num_outliers;
  a.rms_px = b.rms;
  a.sigma0 = b.sigma0;
  a.scale_from = vpKinematicBundleAdjustment::scaleSourceName(b.scale_source);
  a.scale_sd = b.nominal_scale_sd;
  a.has_robot_pose = !b.pose_corrections.empty();
  a.robot_pose_rms_m = b.pose_rms_translation;
  a.robot_pose_rms_rad = b.pose_rms_rotation;
  // The pose error (m, rad) the corrections were weighed with (hand-eye: the controller poses';
  // bundle: the kinematic model's residual), and the one they measure.
  const bool controller = r.method == vpRobotSelfCalibration::HAND_EYE;
  a.robot_pose_sd_m = controller ? r.noise.pose_sd_translation : r.noise.model_sd_translation;
  a.robot_pose_sd_rad = controller ? r.noise.pose_sd_rotation : r.noise.model_sd_rotation;
  a.robot_pose_sd_measured_m = controller ? b.measured.pose_sd_translation : b.measured.model_sd_translation;
  a.robot_pose_sd_measured_rad = controller ? b.measured.pose_sd_rotation : b.measured.model_sd_rotation;
  a.has_robot_pose_sd_measured = a.robot_pose_sd_measured_m > 0;
  a.has_joint_corrections = !b.joint_corrections.empty();
  a.joint_correction_rms_rad = b.joint_rms;
  if (a.has_joint_corrections) {
    a.joint_sd = r.noise.joint_sd;
    a.joint_sd_measured = b.measured.joint_sd;
  }
  // Where the robot's error used comes from: measured by the run's rounds, or stated.
  const vpSelfCalibNoiseModel::Origin origin =
      controller ? r.noise.pose_sd_origin
                 : (r.noise.joint_sd.empty() ? r.noise.model_sd_origin : r.noise.joint_sd_origin);
  if (r.noise.hasRobotError())
    a.robot_error = vpSelfCalibNoiseModel::originName(origin);
  a.has_repose = b.reposed_views > 0; // robot error not modelled: each camera re-posed alone
  a.reposed_rms_px = b.reposed_rms;
  a.repose_f = b.repose_f;
  a.repose_f_limit = b.repose_f_limit;
  a.sd_scaled_by_sigma0 = b.covariance_scaled;
  return a;
}

//! How the set was chosen (vpKinematicIdentification): the same robot and poses give the same set.
RF::EstimatedSet estimatedSetOf(const vpKinematicIdentification::Identifiability &ident,
                                const std::vector<std::string> &names, double kinematic_prior)
{
  RF::EstimatedSet s;
  s.rule = kRule;
  s.kinematic_prior = kinematic_prior;
  for (const auto &u : ident.held_by_prior) {
    s.held_by_prior.push_back({u.name, u.reason, u.needs});
    s.rule = kDataRule;
  }
  for (const auto &u : ident.unidentifiable)
    if (u.cause == vpKinematicIdentification::CAUSE_FIXED)
      s.fixed_by_user.push_back(u.name);
    else if (u.cause == vpKinematicIdentification::CAUSE_DATA) {
      s.left_by_data.push_back({u.name, u.reason, u.needs});
      s.rule = kDataRule;
    }
  s.count = static_cast<unsigned int>(ident.identified.size());
  for (unsigned int k : ident.order)
    s.order.push_back(names[k]);
  for (unsigned int k : ident.order)
    if (std::binary_search(ident.identified.begin(), ident.identified.end(), k) && k < ident.new_direction.size())
      s.new_direction.emplace_back(names[k], ident.new_direction[k]);
  return s;
}

RF::Spread spreadOf(const CV::Spread &s) { return {s.mean, s.sd, s.min, s.max}; }

RF::CrossValidation crossValidationOf(const CV::Result &cv)
{
  RF::CrossValidation c;
  c.folds = cv.folds;
  c.views = cv.views;
  c.measured = cv.num_ok;
  c.failed = cv.num_failed;
  c.rms_calibrated = spreadOf(cv.calibrated_rms);
  c.rms_nominal = spreadOf(cv.nominal_rms);
  c.median_calibrated = spreadOf(cv.calibrated_median);
  c.median_nominal = spreadOf(cv.nominal_median);
  for (const CV::Fold &f : cv.fold) {
    RF::Fold o;
    o.held_out = f.held_out;
    o.status = vpRobotSelfCalibration::statusName(f.status);
    o.calibrated = f.status == vpRobotSelfCalibration::OK;
    o.fx = f.fx;
    o.rms_calibrated = f.calibrated.rms;
    o.median_calibrated = f.calibrated.median;
    o.message = f.message;
    o.rms_nominal = f.nominal.rms;
    o.median_nominal = f.nominal.median;
    o.observations = f.nominal.observations;
    o.verified = f.verified;
    o.yardstick_error_calibrated = f.yardstick_error_calibrated;
    o.yardstick_error_nominal = f.yardstick_error_nominal;
    c.per_fold.push_back(o);
  }
  return c;
}

RF::HeldOutDataset heldOutOf(const CV::HeldOut &h, const std::string &file)
{
  RF::HeldOutDataset d;
  d.file = file;
  d.views = h.views;
  d.rms_calibrated = h.calibrated.rms;
  d.rms_nominal = h.nominal.rms;
  d.median_calibrated = h.calibrated.median;
  d.median_nominal = h.nominal.median;
  d.observations = h.calibrated.observations;
  d.has_yardstick = h.has_yardstick;
  d.yardstick_error_nominal = h.yardstick_error_nominal;
  d.yardstick_error_calibrated = h.yardstick_error_calibrated;
  return d;
}

//! The protocol's part: the split, the cross-validation, the held-out dataset.
void protocolOf(const vpSelfCalibProtocol::Result &p, RF::Contents &c)
{
  c.calibration_views = p.plan.calibration;
  c.held_out_views = p.plan.held_out;
  c.folds = p.plan.folds;
  if (p.cv)
    c.cross_validation = crossValidationOf(*p.cv);
  if (p.verified)
    c.heldout_dataset = heldOutOf(*p.verified, p.plan.heldout_file);
}

// ---------------------------------------------------------------------------------------------
// Writer

void emitEstimates(YAML::Emitter &out, const std::vector<RF::Estimate> &estimates)
{
  for (const RF::Estimate &e : estimates)
    out << YAML::Key << e.name << YAML::Value << YAML::BeginSeq << e.value << e.sd << YAML::EndSeq;
}

void emitHead(YAML::Emitter &out, const RF::Contents &c)
{
  out << YAML::Key << "schema_version" << YAML::Value << c.schema_version;
  out << YAML::Key << "dataset" << YAML::Value << c.dataset;
  out << YAML::Key << "method" << YAML::Value << c.method;
  out << YAML::Key << "status" << YAML::Value << c.status;
  out << YAML::Key << "message" << YAML::Value << YAML::DoubleQuoted << c.message;
  const char *findings_comment = "what the data check found, and what to do";
  out << YAML::Key << "findings";
  if (c.findings.empty())
    out << YAML::Value << YAML::Flow << YAML::BeginSeq << YAML::EndSeq << YAML::Comment(findings_comment);
  else
    out << YAML::Comment(findings_comment) << YAML::Value << YAML::BeginSeq;
  for (const auto &f : c.findings)
    out << YAML::Flow << YAML::BeginMap << YAML::Key << "code" << YAML::Value << f.code << YAML::Key << "severity"
        << YAML::Value << f.severity << YAML::Key << "message" << YAML::Value << YAML::DoubleQuoted << f.message
        << YAML::EndMap;
  if (!c.findings.empty())
    out << YAML::EndSeq;
  const RF::Camera &cam = c.camera;
  out << YAML::Key << "camera" << YAML::Value << YAML::Flow << YAML::BeginMap;
  out << YAML::Key << "px" << YAML::Value << cam.px << YAML::Key << "py" << YAML::Value << cam.py << YAML::Key << "u0"
      << YAML::Value << cam.u0 << YAML::Key << "v0" << YAML::Value << cam.v0 << YAML::Key << "px_sd" << YAML::Value
      << cam.px_sd;
  if (!cam.distortion.empty()) {
    out << YAML::Key << "distortion" << YAML::Comment("OpenCV: k1 k2 p1 p2 k3") << YAML::Value << YAML::BeginSeq;
    for (double k : cam.distortion)
      out << k;
    out << YAML::EndSeq;
  }
  out << YAML::EndMap;
  if (!c.intrinsics_estimated.empty()) {
    out << YAML::Key << "intrinsics_estimated" << YAML::Comment("value and sd (px; mu and distortion unitless)")
        << YAML::Value << YAML::Flow << YAML::BeginMap;
    emitEstimates(out, c.intrinsics_estimated);
    out << YAML::EndMap;
  }
  const std::pair<const char *, const std::optional<RF::HandEye> *> poses[] = {{"eMc", &c.eMc}, {"bMc", &c.bMc}, {"eMo", &c.eMo}};
  const char *comments[] = {"calibrated hand-eye pose vector (tx ty tz tux tuy tuz; m, rad) and sd",
                            "the camera in the robot's base frame (tx ty tz tux tuy tuz; m, rad) and sd",
                            "the target in the end-effector frame (tx ty tz tux tuy tuz; m, rad) and sd"};
  for (int i = 0; i < 3; ++i) {
    const std::optional<RF::HandEye> &e = *poses[i].second;
    if (!e)
      continue;
    out << YAML::Key << poses[i].first << YAML::Comment(comments[i]) << YAML::Value << YAML::Flow << YAML::BeginMap
        << YAML::Key << "pose" << YAML::Value << YAML::BeginSeq;
    for (double v : e->pose)
      out << v;
    out << YAML::EndSeq << YAML::Key << "sd" << YAML::Value << YAML::BeginSeq;
    for (double v : e->sd)
      out << v;
    out << YAML::EndSeq << YAML::EndMap;
  }
}

void emitBundle(YAML::Emitter &out, const RF::BundleAdjustment &b)
{
  out << YAML::Key << "bundle_adjustment" << YAML::Value << YAML::Flow << YAML::BeginMap;
  out << YAML::Key << "observations" << YAML::Value << b.observations << YAML::Key << "dropped" << YAML::Value
      << b.dropped << YAML::Key << "rms_px" << YAML::Value << b.rms_px << YAML::Key << "sigma0" << YAML::Value
      << b.sigma0 << YAML::Key << "scale_from" << YAML::Value << YAML::DoubleQuoted << b.scale_from;
  if (b.scale_sd > 0)
    out << YAML::Key << "scale_sd" << YAML::Value << b.scale_sd;
  if (b.has_robot_pose) {
    out << YAML::Key << "robot_pose_rms_m" << YAML::Value << b.robot_pose_rms_m << YAML::Key << "robot_pose_rms_rad"
        << YAML::Value << b.robot_pose_rms_rad;
    out << YAML::Key << "robot_pose_sd" << YAML::Value << YAML::Flow << YAML::BeginSeq << b.robot_pose_sd_m
        << b.robot_pose_sd_rad << YAML::EndSeq;
    if (b.has_robot_pose_sd_measured)
      out << YAML::Key << "robot_pose_sd_measured" << YAML::Value << YAML::Flow << YAML::BeginSeq
          << b.robot_pose_sd_measured_m << b.robot_pose_sd_measured_rad << YAML::EndSeq;
  }
  if (b.has_joint_corrections) {
    out << YAML::Key << "joint_correction_rms_rad" << YAML::Value << b.joint_correction_rms_rad;
    out << YAML::Key << "joint_sd" << YAML::Value << YAML::Flow << b.joint_sd;
    if (!b.joint_sd_measured.empty())
      out << YAML::Key << "joint_sd_measured" << YAML::Value << YAML::Flow << b.joint_sd_measured;
  }
  if (!b.robot_error.empty())
    out << YAML::Key << "robot_error" << YAML::Value << b.robot_error;
  if (b.has_repose)
    out << YAML::Key << "reposed_rms_px" << YAML::Value << b.reposed_rms_px << YAML::Key << "repose_f" << YAML::Value
        << b.repose_f << YAML::Key << "repose_f_limit" << YAML::Value << b.repose_f_limit;
  if (b.sd_scaled_by_sigma0)
    out << YAML::Key << "sd_scaled_by_sigma0" << YAML::Value << true;
  out << YAML::EndMap;
}

void emitWorkspace(YAML::Emitter &out, const char *key, const RF::Workspace &w, const char *comment)
{
  const auto pair = [&out](const char *k, double t, double r) {
    out << YAML::Key << k << YAML::Value << YAML::Flow << YAML::BeginSeq << t << r << YAML::EndSeq;
  };
  out << YAML::Key << key << YAML::Comment(comment) << YAML::Value << YAML::Flow << YAML::BeginMap;
  pair("calibrated", w.calibrated_t, w.calibrated_r);
  pair("bound_90", w.bound_t, w.bound_r);
  pair("nominal", w.nominal_t, w.nominal_r);
  pair("chance_worse", w.worse_t, w.worse_r);
  if (w.scale_left_out)
    out << YAML::Key << "scale_left_out" << YAML::Value << true;
  if (!w.joints_within.empty()) {
    out << YAML::Key << "joints_within" << YAML::Value << YAML::Flow << YAML::BeginMap;
    for (const auto &j : w.joints_within)
      pair(j.first.c_str(), j.second.first, j.second.second);
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
}

void emitEstimated(YAML::Emitter &out, const RF::Contents &c)
{
  if (c.noise) {
    out << YAML::Key << "noise" << YAML::Comment("px: image noise sd used, and measured by the residuals (robust)")
        << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "pixel_sd" << YAML::Value << c.noise->image_noise_px
        << YAML::Key << "measured" << YAML::Value << c.noise->image_noise_measured_px << YAML::EndMap;
    out << YAML::Key << "fit"
        << YAML::Comment("px: reprojection RMS on the calibration views, nominal and calibrated model") << YAML::Value
        << YAML::Flow << YAML::BeginMap << YAML::Key << "nominal" << YAML::Value << c.noise->fit_nominal << YAML::Key
        << "calibrated" << YAML::Value << c.noise->fit_calibrated << YAML::EndMap;
  }
  if (c.workspace)
    emitWorkspace(out, "workspace", *c.workspace,
                  "m, rad: predicted RMS error of the camera's motions over the joint limits, calibrated (and its "
                  "90 % bound) against the nominal model's (from its misfit on these views)");
  if (c.workspace_full_range)
    emitWorkspace(out, "workspace_full_range", *c.workspace_full_range,
                  "the same with the joints of workspace.joints_within anywhere in their limits");
  out << YAML::Key << "estimated" << YAML::Comment("per parameter: value and sd (m or rad)") << YAML::Value
      << YAML::BeginMap;
  for (const RF::Estimate &e : c.estimated)
    out << YAML::Key << e.name << YAML::Value << YAML::Flow << YAML::BeginSeq << e.value << e.sd << YAML::EndSeq;
  out << YAML::EndMap;
  out << YAML::Key << "not_estimated" << YAML::Value << YAML::BeginMap;
  for (const auto &u : c.not_estimated)
    out << YAML::Key << u.first << YAML::Value << YAML::DoubleQuoted << u.second;
  out << YAML::EndMap;
  if (c.estimated_set) {
    const RF::EstimatedSet &s = *c.estimated_set;
    out << YAML::Key << "estimated_set"
        << YAML::Comment("candidates in a fixed preference order, kept when the data determine them "
                         "(doc/concepts.md, \"The estimated set\")")
        << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "rule" << YAML::Value << YAML::DoubleQuoted << s.rule;
    out << YAML::Key << "count" << YAML::Value << s.count;
    out << YAML::Key << "order" << YAML::Value << YAML::Flow << YAML::BeginSeq;
    for (const std::string &n : s.order)
      out << n;
    out << YAML::EndSeq;
    out << YAML::Key << "new_direction" << YAML::Comment("of each estimated parameter, in the order") << YAML::Value
        << YAML::Flow << YAML::BeginMap;
    for (const auto &d : s.new_direction) {
      std::ostringstream v;
      v << std::setprecision(3) << d.second;
      out << YAML::Key << d.first << YAML::Value << v.str();
    }
    out << YAML::EndMap;
    if (!s.fixed_by_user.empty()) {
      out << YAML::Key << "fixed_by_user" << YAML::Value << YAML::Flow << YAML::BeginSeq;
      for (const std::string &n : s.fixed_by_user)
        out << n;
      out << YAML::EndSeq;
    }
    if (!s.left_by_data.empty()) {
      out << YAML::Key << "left_by_data" << YAML::Comment("kept at nominal: the data do not determine them") << YAML::Value
          << YAML::BeginMap;
      for (const auto &l : s.left_by_data)
        out << YAML::Key << l.name << YAML::Value << YAML::BeginMap << YAML::Key << "reason" << YAML::Value
            << YAML::DoubleQuoted << l.reason << YAML::Key << "needs" << YAML::Value << YAML::DoubleQuoted << l.needs
            << YAML::EndMap;
      out << YAML::EndMap;
    }
    if (s.kinematic_prior > 0)
      out << YAML::Key << "kinematic_prior"
          << YAML::Comment("K: each correction's prior sd is its tolerance / K (the sd include the prior)")
          << YAML::Value << s.kinematic_prior;
    if (!s.held_by_prior.empty()) {
      out << YAML::Key << "held_by_prior"
          << YAML::Comment("estimated, but the data alone do not determine them: the prior holds them near nominal")
          << YAML::Value << YAML::BeginMap;
      for (const auto &l : s.held_by_prior)
        out << YAML::Key << l.name << YAML::Value << YAML::BeginMap << YAML::Key << "reason" << YAML::Value
            << YAML::DoubleQuoted << l.reason << YAML::Key << "needs" << YAML::Value << YAML::DoubleQuoted << l.needs
            << YAML::EndMap;
      out << YAML::EndMap;
    }
    out << YAML::EndMap;
  }
  if (c.verification) {
    const RF::Verification &v = *c.verification;
    out << YAML::Key << "verification" << YAML::Comment("the paper's 3-D yardstick error on the held-out views (m)")
        << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "yardstick_error_nominal" << YAML::Value << v.yardstick_error_nominal;
    out << YAML::Key << "yardstick_error_calibrated" << YAML::Value << v.yardstick_error_calibrated;
    out << YAML::Key << "reprojection_rms_nominal" << YAML::Comment("px, points triangulated from these views")
        << YAML::Value << v.reprojection_rms_nominal;
    out << YAML::Key << "reprojection_rms_calibrated" << YAML::Value << v.reprojection_rms_calibrated;
    out << YAML::EndMap;
  }
}

void emitSpread(YAML::Emitter &out, const char *key, const RF::Spread &s)
{
  out << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "mean" << YAML::Value << s.mean
      << YAML::Key << "sd" << YAML::Value << s.sd << YAML::Key << "min" << YAML::Value << s.min << YAML::Key << "max"
      << YAML::Value << s.max << YAML::EndMap;
}

void emitCrossValidation(YAML::Emitter &out, const RF::CrossValidation &cv)
{
  out << YAML::Key << "cross_validation"
      << YAML::Comment("held-out views' reprojection error (px), scene from the training views; view i in fold i mod k")
      << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "folds" << YAML::Value << cv.folds << YAML::Key << "views" << YAML::Value << cv.views
      << YAML::Key << "measured" << YAML::Value << cv.measured << YAML::Key << "failed" << YAML::Value << cv.failed;
  out << YAML::Key << "rms_px" << YAML::Value << YAML::BeginMap;
  emitSpread(out, "calibrated", cv.rms_calibrated);
  emitSpread(out, "nominal", cv.rms_nominal);
  out << YAML::EndMap << YAML::Key << "median_px" << YAML::Value << YAML::BeginMap;
  emitSpread(out, "calibrated", cv.median_calibrated);
  emitSpread(out, "nominal", cv.median_nominal);
  out << YAML::EndMap << YAML::Key << "per_fold" << YAML::Value << YAML::BeginSeq;
  for (const RF::Fold &f : cv.per_fold) {
    out << YAML::Flow << YAML::BeginMap << YAML::Key << "held_out" << YAML::Value << YAML::Flow << f.held_out
        << YAML::Key << "status" << YAML::Value << f.status;
    if (f.calibrated)
      out << YAML::Key << "fx" << YAML::Value << f.fx << YAML::Key << "rms_calibrated" << YAML::Value
          << f.rms_calibrated << YAML::Key << "median_calibrated" << YAML::Value << f.median_calibrated;
    else
      out << YAML::Key << "message" << YAML::Value << YAML::DoubleQuoted << f.message;
    out << YAML::Key << "rms_nominal" << YAML::Value << f.rms_nominal << YAML::Key << "median_nominal" << YAML::Value
        << f.median_nominal << YAML::Key << "observations" << YAML::Value << f.observations;
    if (f.verified)
      out << YAML::Key << "yardstick_error_calibrated" << YAML::Value << f.yardstick_error_calibrated << YAML::Key
          << "yardstick_error_nominal" << YAML::Value << f.yardstick_error_nominal;
    out << YAML::EndMap;
  }
  out << YAML::EndSeq << YAML::EndMap;
}

void emitHeldOut(YAML::Emitter &out, const RF::HeldOutDataset &h)
{
  out << YAML::Key << "heldout_dataset"
      << YAML::Comment("the calibrated model on a second dataset: its views' reprojection error (px), scene "
                       "from these views; yardstick 3-D error (m)")
      << YAML::Value << YAML::BeginMap << YAML::Key << "file" << YAML::Value << h.file << YAML::Key << "views"
      << YAML::Value << h.views << YAML::Key << "rms_px" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
      << "calibrated" << YAML::Value << h.rms_calibrated << YAML::Key << "nominal" << YAML::Value << h.rms_nominal
      << YAML::EndMap << YAML::Key << "median_px" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
      << "calibrated" << YAML::Value << h.median_calibrated << YAML::Key << "nominal" << YAML::Value
      << h.median_nominal << YAML::EndMap << YAML::Key << "observations" << YAML::Value << h.observations;
  if (h.has_yardstick)
    out << YAML::Key << "yardstick_error_nominal" << YAML::Value << h.yardstick_error_nominal << YAML::Key
        << "yardstick_error_calibrated" << YAML::Value << h.yardstick_error_calibrated;
  out << YAML::EndMap;
}

// ---------------------------------------------------------------------------------------------
// Reader

//! Typed access to the nodes of one results.yaml; every error names the file and the key.
class In
{
public:
  explicit In(const std::string &source) : m_source(source) {}
  [[noreturn]] void fail(const std::string &key, const std::string &what) const
  {
    throw vpSelfCalibException(vpSelfCalibException::parseError,
                               "results file " + m_source + ": key '" + key + "': " + what);
  }
  YAML::Node need(const YAML::Node &n, const std::string &key) const
  {
    if (!n.IsMap() || !n[key])
      fail(key, "missing");
    return n[key];
  }
  template <typename T> T get(const YAML::Node &n, const std::string &key) const
  {
    try {
      return need(n, key).as<T>();
    } catch (const YAML::Exception &e) {
      fail(key, std::string("wrong type: ") + e.what());
    }
  }
  template <typename T> std::vector<T> list(const YAML::Node &n, const std::string &key) const
  {
    try {
      return need(n, key).as<std::vector<T>>();
    } catch (const YAML::Exception &e) {
      fail(key, std::string("expected a list: ") + e.what());
    }
  }
  //! name: [value, sd] entries of a map, in the file's order.
  std::vector<RF::Estimate> estimates(const YAML::Node &n, const std::string &key) const
  {
    std::vector<RF::Estimate> out;
    for (const auto &kv : need(n, key)) {
      const std::string name = kv.first.as<std::string>();
      const std::vector<double> v = list<double>(need(n, key), name);
      if (v.size() != 2)
        fail(key + "." + name, "expected [value, sd]");
      out.push_back({name, v[0], v[1]});
    }
    return out;
  }

private:
  std::string m_source;
};

RF::Spread spreadFrom(const In &in, const YAML::Node &n, const std::string &key)
{
  const YAML::Node s = in.need(n, key);
  return {in.get<double>(s, "mean"), in.get<double>(s, "sd"), in.get<double>(s, "min"), in.get<double>(s, "max")};
}

void readHead(const In &in, const YAML::Node &root, RF::Contents &c)
{
  c.dataset = in.get<std::string>(root, "dataset");
  c.method = in.get<std::string>(root, "method");
  c.status = in.get<std::string>(root, "status");
  c.message = in.get<std::string>(root, "message");
  for (const YAML::Node &f : in.need(root, "findings"))
    c.findings.push_back(
        {in.get<std::string>(f, "code"), in.get<std::string>(f, "severity"), in.get<std::string>(f, "message")});
  const YAML::Node cam = in.need(root, "camera");
  c.camera.px = in.get<double>(cam, "px");
  c.camera.py = in.get<double>(cam, "py");
  c.camera.u0 = in.get<double>(cam, "u0");
  c.camera.v0 = in.get<double>(cam, "v0");
  c.camera.px_sd = in.get<double>(cam, "px_sd");
  if (cam["distortion"])
    c.camera.distortion = in.list<double>(cam, "distortion");
  if (root["intrinsics_estimated"])
    c.intrinsics_estimated = in.estimates(root, "intrinsics_estimated");
  for (const char *key : {"eMc", "bMc", "eMo"})
    if (root[key]) {
      const YAML::Node e = root[key];
      const RF::HandEye h{in.list<double>(e, "pose"), in.list<double>(e, "sd")};
      (std::string(key) == "eMc" ? c.eMc : std::string(key) == "bMc" ? c.bMc : c.eMo) = h;
    }
}

RF::BundleAdjustment readBundle(const In &in, const YAML::Node &n)
{
  RF::BundleAdjustment b;
  b.observations = in.get<unsigned int>(n, "observations");
  b.dropped = in.get<unsigned int>(n, "dropped");
  b.rms_px = in.get<double>(n, "rms_px");
  b.sigma0 = in.get<double>(n, "sigma0");
  b.scale_from = in.get<std::string>(n, "scale_from");
  if (n["scale_sd"])
    b.scale_sd = in.get<double>(n, "scale_sd");
  b.has_robot_pose = static_cast<bool>(n["robot_pose_rms_m"]);
  if (b.has_robot_pose) {
    b.robot_pose_rms_m = in.get<double>(n, "robot_pose_rms_m");
    b.robot_pose_rms_rad = in.get<double>(n, "robot_pose_rms_rad");
    const std::vector<double> sd = in.list<double>(n, "robot_pose_sd");
    if (sd.size() != 2)
      in.fail("robot_pose_sd", "expected [T, R]");
    b.robot_pose_sd_m = sd[0];
    b.robot_pose_sd_rad = sd[1];
    b.has_robot_pose_sd_measured = static_cast<bool>(n["robot_pose_sd_measured"]);
    if (b.has_robot_pose_sd_measured) {
      const std::vector<double> m = in.list<double>(n, "robot_pose_sd_measured");
      if (m.size() != 2)
        in.fail("robot_pose_sd_measured", "expected [T, R]");
      b.robot_pose_sd_measured_m = m[0];
      b.robot_pose_sd_measured_rad = m[1];
    }
  }
  b.has_joint_corrections = static_cast<bool>(n["joint_correction_rms_rad"]);
  if (b.has_joint_corrections) {
    b.joint_correction_rms_rad = in.get<double>(n, "joint_correction_rms_rad");
    b.joint_sd = in.list<double>(n, "joint_sd");
    if (n["joint_sd_measured"])
      b.joint_sd_measured = in.list<double>(n, "joint_sd_measured");
  }
  if (n["robot_error"]) {
    b.robot_error = in.get<std::string>(n, "robot_error");
    if (b.robot_error != "measured" && b.robot_error != "stated")
      in.fail("robot_error", "expected measured or stated");
  }
  b.has_repose = static_cast<bool>(n["reposed_rms_px"]);
  if (b.has_repose) {
    b.reposed_rms_px = in.get<double>(n, "reposed_rms_px");
    b.repose_f = in.get<double>(n, "repose_f");
    b.repose_f_limit = in.get<double>(n, "repose_f_limit");
  }
  b.sd_scaled_by_sigma0 = n["sd_scaled_by_sigma0"] && in.get<bool>(n, "sd_scaled_by_sigma0");
  return b;
}

RF::Workspace readWorkspace(const In &in, const YAML::Node &w, const std::string &key)
{
  const auto pair = [&in](const YAML::Node &n, const std::string &k, const std::string &path, double &t, double &r) {
    const std::vector<double> v = in.list<double>(n, k);
    if (v.size() != 2)
      in.fail(path + "." + k, "expected two values");
    t = v[0];
    r = v[1];
  };
  RF::Workspace ws;
  pair(w, "calibrated", key, ws.calibrated_t, ws.calibrated_r);
  pair(w, "bound_90", key, ws.bound_t, ws.bound_r);
  pair(w, "nominal", key, ws.nominal_t, ws.nominal_r);
  pair(w, "chance_worse", key, ws.worse_t, ws.worse_r);
  ws.scale_left_out = w["scale_left_out"] && in.get<bool>(w, "scale_left_out");
  if (w["joints_within"])
    for (const auto &kv : w["joints_within"]) {
      std::pair<double, double> range;
      pair(w["joints_within"], kv.first.as<std::string>(), key + ".joints_within", range.first, range.second);
      ws.joints_within.emplace_back(kv.first.as<std::string>(), range);
    }
  return ws;
}

void readEstimated(const In &in, const YAML::Node &root, RF::Contents &c)
{
  if (root["noise"]) {
    RF::NoiseAndFit nf;
    nf.image_noise_px = in.get<double>(root["noise"], "pixel_sd");
    nf.image_noise_measured_px = in.get<double>(root["noise"], "measured");
    const YAML::Node fit = in.need(root, "fit");
    nf.fit_nominal = in.get<double>(fit, "nominal");
    nf.fit_calibrated = in.get<double>(fit, "calibrated");
    c.noise = nf;
  }
  if (root["workspace"])
    c.workspace = readWorkspace(in, root["workspace"], "workspace");
  if (root["workspace_full_range"])
    c.workspace_full_range = readWorkspace(in, root["workspace_full_range"], "workspace_full_range");
  c.estimated = in.estimates(root, "estimated");
  for (const auto &kv : in.need(root, "not_estimated"))
    c.not_estimated.emplace_back(kv.first.as<std::string>(), kv.second.as<std::string>());
  if (root["estimated_set"]) {
    const YAML::Node s = root["estimated_set"];
    RF::EstimatedSet e;
    e.rule = in.get<std::string>(s, "rule");
    e.count = in.get<unsigned int>(s, "count");
    e.order = in.list<std::string>(s, "order");
    for (const auto &kv : in.need(s, "new_direction"))
      e.new_direction.emplace_back(kv.first.as<std::string>(), in.get<double>(s["new_direction"], kv.first.Scalar()));
    if (s["fixed_by_user"])
      e.fixed_by_user = in.list<std::string>(s, "fixed_by_user");
    if (s["left_by_data"])
      for (const auto &kv : s["left_by_data"])
        e.left_by_data.push_back({kv.first.as<std::string>(), in.get<std::string>(kv.second, "reason"),
                                  in.get<std::string>(kv.second, "needs")});
    if (s["kinematic_prior"])
      e.kinematic_prior = in.get<double>(s, "kinematic_prior");
    if (s["held_by_prior"])
      for (const auto &kv : s["held_by_prior"])
        e.held_by_prior.push_back({kv.first.as<std::string>(), in.get<std::string>(kv.second, "reason"),
                                   in.get<std::string>(kv.second, "needs")});
    c.estimated_set = e;
  }
  if (root["verification"]) {
    const YAML::Node v = root["verification"];
    c.verification = RF::Verification{
        in.get<double>(v, "yardstick_error_nominal"), in.get<double>(v, "yardstick_error_calibrated"),
        in.get<double>(v, "reprojection_rms_nominal"), in.get<double>(v, "reprojection_rms_calibrated")};
  }
}

RF::Fold readFold(const In &in, const YAML::Node &n)
{
  RF::Fold f;
  f.held_out = in.list<unsigned int>(n, "held_out");
  f.status = in.get<std::string>(n, "status");
  f.calibrated = static_cast<bool>(n["fx"]);
  if (f.calibrated) {
    f.fx = in.get<double>(n, "fx");
    f.rms_calibrated = in.get<double>(n, "rms_calibrated");
    f.median_calibrated = in.get<double>(n, "median_calibrated");
  } else {
    f.message = in.get<std::string>(n, "message");
  }
  f.rms_nominal = in.get<double>(n, "rms_nominal");
  f.median_nominal = in.get<double>(n, "median_nominal");
  f.observations = in.get<unsigned int>(n, "observations");
  f.verified = static_cast<bool>(n["yardstick_error_calibrated"]);
  if (f.verified) {
    f.yardstick_error_calibrated = in.get<double>(n, "yardstick_error_calibrated");
    f.yardstick_error_nominal = in.get<double>(n, "yardstick_error_nominal");
  }
  return f;
}

void readProtocol(const In &in, const YAML::Node &root, RF::Contents &c)
{
  const YAML::Node p = in.need(root, "protocol");
  c.calibration_views = in.get<unsigned int>(p, "calibration_views");
  c.held_out_views = in.get<unsigned int>(p, "held_out_views");
  c.folds = in.get<unsigned int>(p, "folds");
  if (root["cross_validation"]) {
    const YAML::Node n = root["cross_validation"];
    RF::CrossValidation cv;
    cv.folds = in.get<unsigned int>(n, "folds");
    cv.views = in.get<unsigned int>(n, "views");
    cv.measured = in.get<unsigned int>(n, "measured");
    cv.failed = in.get<unsigned int>(n, "failed");
    cv.rms_calibrated = spreadFrom(in, in.need(n, "rms_px"), "calibrated");
    cv.rms_nominal = spreadFrom(in, in.need(n, "rms_px"), "nominal");
    cv.median_calibrated = spreadFrom(in, in.need(n, "median_px"), "calibrated");
    cv.median_nominal = spreadFrom(in, in.need(n, "median_px"), "nominal");
    for (const YAML::Node &f : in.need(n, "per_fold"))
      cv.per_fold.push_back(readFold(in, f));
    c.cross_validation = cv;
  }
  if (root["heldout_dataset"]) {
    const YAML::Node n = root["heldout_dataset"];
    RF::HeldOutDataset h;
    h.file = in.get<std::string>(n, "file");
    h.views = in.get<unsigned int>(n, "views");
    h.rms_calibrated = in.get<double>(in.need(n, "rms_px"), "calibrated");
    h.rms_nominal = in.get<double>(in.need(n, "rms_px"), "nominal");
    h.median_calibrated = in.get<double>(in.need(n, "median_px"), "calibrated");
    h.median_nominal = in.get<double>(in.need(n, "median_px"), "nominal");
    h.observations = in.get<unsigned int>(n, "observations");
    h.has_yardstick = static_cast<bool>(n["yardstick_error_nominal"]);
    if (h.has_yardstick) {
      h.yardstick_error_nominal = in.get<double>(n, "yardstick_error_nominal");
      h.yardstick_error_calibrated = in.get<double>(n, "yardstick_error_calibrated");
    }
    c.heldout_dataset = h;
  }
}
} // namespace

vpSelfCalibResultsFile::Contents vpSelfCalibResultsFile::fromRun(const vpRobotSelfCalibration::Result &r,
                                                                 const vpKinematicChain &nominal,
                                                                 const std::string &dataset,
                                                                 const vpSelfCalibProtocol::Result &protocol)
{
  Contents c;
  c.dataset = dataset;
  c.method = vpRobotSelfCalibration::methodName(r.method);
  c.status = vpRobotSelfCalibration::statusName(r.status);
  c.message = r.message;
  for (const auto &f : r.findings)
    c.findings.push_back({f.code, vpSelfCalibDataCheck::severityName(f.severity), f.message});
  c.camera = cameraOf(r);
  if (r.bundle.intrinsic_names.size() == r.bundle.intrinsics_sd.size() && !r.bundle.intrinsic_names.empty() &&
      r.bundle.has_covariance)
    for (unsigned int i = 0; i < r.bundle.intrinsics.size(); ++i)
      c.intrinsics_estimated.push_back({r.bundle.intrinsic_names[i], r.bundle.intrinsics[i], r.bundle.intrinsics_sd[i]});
  const auto block = [](const vpPoseVector &pose, const vpColVector &sd) {
    HandEye e;
    for (unsigned int k = 0; k < 6; ++k) {
      e.pose.push_back(pose[k]);
      e.sd.push_back(sd.size() == 6 ? sd[k] : 0.0);
    }
    return e;
  };
  if (r.has_eMc)
    c.eMc = block(r.eMc, r.eMc_sd);
  if (r.has_bMc)
    c.bMc = block(r.bMc, r.bMc_sd);
  if (r.has_eMo)
    c.eMo = block(r.eMo, r.eMo_sd);
  if (r.method == vpRobotSelfCalibration::BUNDLE_ADJUSTMENT || r.method == vpRobotSelfCalibration::HAND_EYE)
    c.bundle_adjustment = bundleOf(r);
  if (r.method != vpRobotSelfCalibration::PAPER)
    c.noise = NoiseAndFit{r.noise.pixel_sd, r.measured.pixel_sd, r.fit_nominal_rms, r.fit_calibrated_rms};
  const auto workspace = [](const vpRobotSelfCalibration::WorkspaceError &w) {
    Workspace ws{w.calibrated_t, w.calibrated_r, w.bound_t, w.bound_r, w.nominal_t, w.nominal_r, w.worse_t, w.worse_r,
                 w.scale_left_out, {}};
    for (const auto &j : w.joints_within)
      ws.joints_within.emplace_back(j.joint, std::make_pair(j.lo, j.hi));
    return ws;
  };
  if (r.workspace.computed)
    c.workspace = workspace(r.workspace);
  if (r.workspace_full_range.computed)
    c.workspace_full_range = workspace(r.workspace_full_range);
  const std::vector<std::string> names = nominal.getParameterNames();
  for (unsigned int k : r.identifiability.identified)
    c.estimated.push_back(
        {names[k], r.calibrated.getParameters()[k], k < r.parameter_sd.size() ? r.parameter_sd[k] : 0.0});
  for (const auto &u : r.identifiability.unidentifiable)
    c.not_estimated.emplace_back(u.name, u.reason);
  if (!r.identifiability.order.empty())
    c.estimated_set = estimatedSetOf(r.identifiability, names, r.bundle.kinematic_prior);
  if (r.verified)
    c.verification = Verification{r.before.yardstick_error, r.after.yardstick_error, r.before.reprojection_rms,
                                  r.after.reprojection_rms};
  protocolOf(protocol, c);
  return c;
}

std::string vpSelfCalibResultsFile::toYaml(const Contents &c)
{
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap;
  emitHead(out, c);
  if (c.bundle_adjustment)
    emitBundle(out, *c.bundle_adjustment);
  emitEstimated(out, c);
  out << YAML::Key << "protocol" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "calibration_views"
      << YAML::Value << c.calibration_views << YAML::Key << "held_out_views" << YAML::Value << c.held_out_views
      << YAML::Key << "folds" << YAML::Value << c.folds << YAML::EndMap;
  if (c.cross_validation)
    emitCrossValidation(out, *c.cross_validation);
  if (c.heldout_dataset)
    emitHeldOut(out, *c.heldout_dataset);
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

void vpSelfCalibResultsFile::write(const std::string &filename, const Contents &contents)
{
  vpSelfCalibFileWriter::write(filename, toYaml(contents), "results");
}

vpSelfCalibResultsFile::Contents vpSelfCalibResultsFile::fromYaml(const std::string &text, const std::string &source)
{
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception &e) {
    throw vpSelfCalibException(vpSelfCalibException::parseError,
                               "results file " + source + ": not YAML: " + std::string(e.what()));
  }
  const In in(source);
  if (!root.IsMap())
    in.fail("schema_version", "missing: not a results file");
  Contents c;
  c.schema_version = in.get<int>(root, "schema_version");
  if (c.schema_version != kSchemaVersion)
    in.fail("schema_version", std::to_string(c.schema_version) + " is not the version this reader knows (" +
                                  std::to_string(kSchemaVersion) + ")");
  readHead(in, root, c);
  if (root["bundle_adjustment"])
    c.bundle_adjustment = readBundle(in, root["bundle_adjustment"]);
  readEstimated(in, root, c);
  readProtocol(in, root, c);
  return c;
}

vpSelfCalibResultsFile::Contents vpSelfCalibResultsFile::read(const std::string &filename)
{
  return fromYaml(vpSelfCalib::readTextFileBounded(filename, "results file", size_t(256) << 20), filename);
}
