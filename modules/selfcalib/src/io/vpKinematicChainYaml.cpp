/*
 * ViSP SelfCalib: robot-model YAML (read and write) for vpKinematicChain, with yaml-cpp.
 *
 *   name: puma560
 *   convention: dh            # or mdh
 *   joints:
 *     - {a: 0.0, d: 0.0, alpha: 1.5707963267948966, theta_offset: 0.0, min: -2.79, max: 2.79}
 *   base: [0, 0, 0, 0, 0, 0]  # fMb pose vector (tx ty tz tux tuy tuz), optional
 *   flange: [0, 0, 0, 0, 0, 0] # nMe, optional
 *   eMc: [0, 0.06, 0.08, 0, 0, 0] # optional
 *   corrections: {j2.tx: 1.0e-3} # optional
 * or
 *   preset: viper850
 *   eMc: [...]                 # optional override of the preset's camera
 *   corrections: {...}         # optional
 */
#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpKinematicChainUrdf.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "vpSelfCalibYaml.h"

using namespace vpSelfCalib;

namespace
{
/*
  The model's camera_mount: effector (the default: eMc) or world (bMc); a file that names the
  other slot's key is refused, so that a bMc is never read as an eMc or the reverse.
*/
bool cameraInWorld(Reader &r, const YAML::Node &root)
{
  bool world = false;
  if (root["camera_mount"]) {
    const std::string mount = r.text(root["camera_mount"], "camera_mount");
    if (mount != "effector" && mount != "world")
      r.fail("camera_mount", "expected effector (the camera on the end-effector: key eMc) or world (the camera "
                             "fixed in the world: key bMc), got '" + mount + "'");
    world = mount == "world";
  }
  if (world && root["eMc"])
    r.fail("eMc", "camera_mount: world holds the camera in the base frame under the key bMc, not eMc");
  if (!world && root["bMc"])
    r.fail("bMc", "the camera in the base frame (bMc) needs camera_mount: world (without it the camera is on the "
                  "end-effector: key eMc)");
  return world;
}

vpKinematicChain parse(const YAML::Node &root, const std::string &source)
{
  Reader r("robot model", source);
  if (!root.IsMap())
    throw vpSelfCalibException(vpSelfCalibException::parseError,
                               "robot model " + source + ": expected a YAML map at the top level");
  vpKinematicChain chain;
  // camera_mount: world: the hand-eye slot holds bMc, under that key (the camera in the base frame).
  const bool world = cameraInWorld(r, root);
  const char *slot = world ? "bMc" : "eMc";
  if (root["preset"]) {
    r.onlyKeys(root, {"name", "preset", "camera_mount", slot, "corrections"}, "");
    const std::string name = r.text(root["preset"], "preset");
    try {
      chain = vpKinematicChain::preset(name);
    } catch (const vpSelfCalibException &e) {
      r.fail("preset", e.getStringMessage());
    }
    if (root[slot])
      chain.set_eMc(r.pose(root[slot], slot));
  } else {
    r.onlyKeys(root, {"name", "convention", "joints", "base", "flange", "camera_mount", slot, "corrections"}, "");
    const std::string conv = r.text(root["convention"], "convention");
    vpKinematicChain::Convention c;
    if (conv == "dh")
      c = vpKinematicChain::DH;
    else if (conv == "mdh")
      c = vpKinematicChain::MDH;
    else
      r.fail("convention", "expected 'dh' or 'mdh', got '" + conv + "'");
    const YAML::Node jn = root["joints"];
    if (!jn.IsDefined() || jn.IsNull())
      r.fail("joints", "missing; expected a list of joints {a, d, alpha, theta_offset, min, max}");
    if (!jn.IsSequence() || jn.size() == 0)
      r.fail("joints", "expected a non-empty list of joints, got " + Reader::show(jn));
    r.atMost(jn, kMaxJoints, "joints", "joints");
    std::vector<vpKinematicChain::Joint> joints;
    for (size_t i = 0; i < jn.size(); ++i) {
      const std::string k = "joints[" + std::to_string(i) + "]";
      if (!jn[i].IsMap())
        r.fail(k, "expected a map {a, d, alpha, theta_offset, min, max}, got " + Reader::show(jn[i]));
      r.onlyKeys(jn[i], {"a", "d", "alpha", "theta_offset", "min", "max"}, k);
      vpKinematicChain::Joint j;
      j.a = r.bounded(jn[i]["a"], k + ".a", -kMaxLength, kMaxLength, "m");
      j.d = r.bounded(jn[i]["d"], k + ".d", -kMaxLength, kMaxLength, "m");
      j.alpha = r.bounded(jn[i]["alpha"], k + ".alpha", -kMaxAngle, kMaxAngle, "rad");
      j.theta_offset =
          jn[i]["theta_offset"] ? r.bounded(jn[i]["theta_offset"], k + ".theta_offset", -kMaxAngle, kMaxAngle, "rad")
                                : 0.0;
      j.min = r.bounded(jn[i]["min"], k + ".min", -kMaxAngle, kMaxAngle, "rad");
      j.max = r.bounded(jn[i]["max"], k + ".max", -kMaxAngle, kMaxAngle, "rad");
      if (j.min > j.max)
        r.fail(k + ".min", "joint limit min (" + std::to_string(j.min) + ") is greater than max (" +
                               std::to_string(j.max) + ")");
      joints.push_back(j);
    }
    const vpPoseVector base = root["base"] ? r.pose(root["base"], "base") : vpPoseVector();
    const vpPoseVector flange = root["flange"] ? r.pose(root["flange"], "flange") : vpPoseVector();
    const vpPoseVector eMc = root[slot] ? r.pose(root[slot], slot) : vpPoseVector();
    chain = vpKinematicChain("robot", c, joints, base, flange, eMc);
  }
  chain.setCameraInWorld(world);
  if (root["name"])
    chain.setName(r.text(root["name"], "name"));
  const YAML::Node corr = root["corrections"];
  if (corr && !corr.IsNull()) {
    if (!corr.IsMap())
      r.fail("corrections", "expected a map 'parameter name: value', got " + Reader::show(corr));
    const std::vector<std::string> names = chain.getParameterNames();
    std::set<std::string> seen;
    for (const auto &kv : corr) {
      const std::string name = r.keyName(kv.first, "corrections");
      const std::string key = "corrections." + name;
      if (!seen.insert(name).second)
        r.fail(key, "given twice (which one is meant?)");
      if (std::find(names.begin(), names.end(), name) == names.end())
        r.fail(key, "unknown parameter (expected base.*, j1.* .. j" + std::to_string(chain.getNumJoints()) +
                        ".* or eMc.*, with * one of tx ty tz rx ry rz)");
      // Translations in m, rotations in rad (the name's last letter: tx.. or rx..).
      const bool rotation = name.size() >= 2 && name[name.size() - 2] == 'r';
      chain.setParameter(name, rotation ? r.bounded(kv.second, key, -2 * M_PI, 2 * M_PI, "rad")
                                        : r.bounded(kv.second, key, -kMaxLength, kMaxLength, "m"));
    }
  }
  return chain;
}

void emitPose(YAML::Emitter &out, const vpPoseVector &p)
{
  out << YAML::Flow << YAML::BeginSeq;
  for (unsigned int i = 0; i < 6; ++i)
    out << p[i];
  out << YAML::EndSeq;
}
} // namespace

vpKinematicChain vpKinematicChain::fromYamlString(const std::string &yaml, const std::string &source)
{
  return parseYaml("robot model", source, [&] { return parse(loadYamlRoot(yaml, "robot model", source), source); });
}

vpKinematicChain vpKinematicChain::loadYaml(const std::string &filename)
{
  // The system's reason when it cannot be read (no such file, permission denied...), a size limit.
  return fromYamlString(readTextFile(filename, "robot model"), "'" + filename + "'");
}

vpKinematicChain vpKinematicChain::fromPresetOrFile(const std::string &name_or_file)
{
  std::string presets;
  for (const std::string &p : presetNames()) {
    if (p == name_or_file)
      return preset(p);
    presets += (presets.empty() ? "" : ", ") + p;
  }
  std::error_code ec;
  if (!std::filesystem::exists(name_or_file, ec) && name_or_file.find_first_of("/.") == std::string::npos)
    throw vpSelfCalibException(vpSelfCalibException::ioError, "robot model '" + name_or_file +
                                                                  "': neither a preset (" + presets +
                                                                  ") nor a file (no such file)");
  if (vpKinematicChainUrdf::isUrdfFile(name_or_file))
    return vpKinematicChainUrdf::load(name_or_file);
  return loadYaml(name_or_file);
}

std::string vpKinematicChain::toYamlString() const
{
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap;
  out << YAML::Key << "name" << YAML::Value << m_name;
  out << YAML::Key << "convention" << YAML::Value << (m_convention == DH ? "dh" : "mdh");
  out << YAML::Key << "joints" << YAML::Value << YAML::BeginSeq;
  for (const Joint &j : m_joints) {
    out << YAML::Flow << YAML::BeginMap;
    out << YAML::Key << "a" << YAML::Value << j.a << YAML::Key << "d" << YAML::Value << j.d;
    out << YAML::Key << "alpha" << YAML::Value << j.alpha;
    out << YAML::Key << "theta_offset" << YAML::Value << j.theta_offset;
    out << YAML::Key << "min" << YAML::Value << j.min << YAML::Key << "max" << YAML::Value << j.max;
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
  out << YAML::Key << "base" << YAML::Value;
  emitPose(out, m_fMb);
  out << YAML::Key << "flange" << YAML::Value;
  emitPose(out, m_nMe);
  if (m_camera_in_world) // the hand-eye slot holds bMc: the file says so
    out << YAML::Key << "camera_mount" << YAML::Value << "world" << YAML::Key << "bMc" << YAML::Value;
  else
    out << YAML::Key << "eMc" << YAML::Value;
  emitPose(out, m_eMc);
  out << YAML::Key << "corrections" << YAML::Value << YAML::BeginMap;
  const std::vector<std::string> names = getParameterNames();
  for (unsigned int i = 0; i < names.size(); ++i)
    if (m_params[i] != 0.0)
      out << YAML::Key << names[i] << YAML::Value << m_params[i];
  out << YAML::EndMap;
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

void vpKinematicChain::saveYaml(const std::string &filename) const
{
  writeFileAtomically(filename, toYamlString(), "robot model");
}
