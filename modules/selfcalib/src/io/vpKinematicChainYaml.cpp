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
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include <yaml-cpp/yaml.h>

namespace
{
class Reader
{
public:
  explicit Reader(const std::string &source) : m_source(source) {}

  [[noreturn]] void fail(const std::string &key, const std::string &what) const
  {
    throw vpSelfCalibException(vpSelfCalibException::parseError,
                               "robot model " + m_source + ": key '" + key + "': " + what);
  }

  static std::string show(const YAML::Node &n)
  {
    if (!n.IsDefined() || n.IsNull())
      return "nothing";
    if (n.IsScalar())
      return "'" + n.Scalar() + "'";
    return n.IsSequence() ? "a list" : "a map";
  }

  double number(const YAML::Node &n, const std::string &key) const
  {
    if (!n.IsDefined() || n.IsNull())
      fail(key, "missing; expected a number");
    if (!n.IsScalar())
      fail(key, "expected a number, got " + show(n));
    double v = 0;
    try {
      v = n.as<double>();
    } catch (const YAML::Exception &) {
      fail(key, "expected a number, got " + show(n));
    }
    if (!std::isfinite(v))
      fail(key, "expected a finite number, got " + show(n));
    return v;
  }

  std::string text(const YAML::Node &n, const std::string &key) const
  {
    if (!n.IsDefined() || n.IsNull())
      fail(key, "missing; expected a string");
    if (!n.IsScalar())
      fail(key, "expected a string, got " + show(n));
    return n.Scalar();
  }

  vpPoseVector pose(const YAML::Node &n, const std::string &key) const
  {
    if (!n.IsSequence() || n.size() != 6)
      fail(key, "expected a pose vector of 6 numbers [tx, ty, tz, tux, tuy, tuz] (m, rad), got " +
                    (n.IsSequence() ? "a list of " + std::to_string(n.size()) : show(n)));
    vpPoseVector p;
    for (unsigned int i = 0; i < 6; ++i)
      p[i] = number(n[i], key + "[" + std::to_string(i) + "]");
    return p;
  }

  void onlyKeys(const YAML::Node &map, const std::set<std::string> &allowed, const std::string &where) const
  {
    for (const auto &kv : map) {
      const std::string k = kv.first.as<std::string>();
      if (!allowed.count(k)) {
        std::string list;
        for (const std::string &a : allowed)
          list += (list.empty() ? "" : ", ") + a;
        fail(where.empty() ? k : where + "." + k, "unknown key (expected one of: " + list + ")");
      }
    }
  }

private:
  std::string m_source;
};

vpKinematicChain parse(const YAML::Node &root, const std::string &source)
{
  Reader r(source);
  if (!root.IsMap())
    throw vpSelfCalibException(vpSelfCalibException::parseError,
                               "robot model " + source + ": expected a YAML map at the top level");
  vpKinematicChain chain;
  if (root["preset"]) {
    r.onlyKeys(root, {"name", "preset", "eMc", "corrections"}, "");
    const std::string name = r.text(root["preset"], "preset");
    try {
      chain = vpKinematicChain::preset(name);
    } catch (const vpSelfCalibException &e) {
      r.fail("preset", e.getStringMessage());
    }
    if (root["eMc"])
      chain.set_eMc(r.pose(root["eMc"], "eMc"));
  } else {
    r.onlyKeys(root, {"name", "convention", "joints", "base", "flange", "eMc", "corrections"}, "");
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
    std::vector<vpKinematicChain::Joint> joints;
    for (size_t i = 0; i < jn.size(); ++i) {
      const std::string k = "joints[" + std::to_string(i) + "]";
      if (!jn[i].IsMap())
        r.fail(k, "expected a map {a, d, alpha, theta_offset, min, max}, got " + Reader::show(jn[i]));
      r.onlyKeys(jn[i], {"a", "d", "alpha", "theta_offset", "min", "max"}, k);
      vpKinematicChain::Joint j;
      j.a = r.number(jn[i]["a"], k + ".a");
      j.d = r.number(jn[i]["d"], k + ".d");
      j.alpha = r.number(jn[i]["alpha"], k + ".alpha");
      j.theta_offset = jn[i]["theta_offset"] ? r.number(jn[i]["theta_offset"], k + ".theta_offset") : 0.0;
      j.min = r.number(jn[i]["min"], k + ".min");
      j.max = r.number(jn[i]["max"], k + ".max");
      if (j.min > j.max)
        r.fail(k + ".min", "joint limit min (" + std::to_string(j.min) + ") is greater than max (" +
                               std::to_string(j.max) + ")");
      joints.push_back(j);
    }
    const vpPoseVector base = root["base"] ? r.pose(root["base"], "base") : vpPoseVector();
    const vpPoseVector flange = root["flange"] ? r.pose(root["flange"], "flange") : vpPoseVector();
    const vpPoseVector eMc = root["eMc"] ? r.pose(root["eMc"], "eMc") : vpPoseVector();
    chain = vpKinematicChain("robot", c, joints, base, flange, eMc);
  }
  if (root["name"])
    chain.setName(r.text(root["name"], "name"));
  const YAML::Node corr = root["corrections"];
  if (corr && !corr.IsNull()) {
    if (!corr.IsMap())
      r.fail("corrections", "expected a map 'parameter name: value', got " + Reader::show(corr));
    const std::vector<std::string> names = chain.getParameterNames();
    for (const auto &kv : corr) {
      const std::string name = kv.first.as<std::string>();
      const std::string key = "corrections." + name;
      if (std::find(names.begin(), names.end(), name) == names.end())
        r.fail(key, "unknown parameter (expected base.*, j1.* .. j" + std::to_string(chain.getNumJoints()) +
                        ".* or eMc.*, with * one of tx ty tz rx ry rz)");
      chain.setParameter(name, r.number(kv.second, key));
    }
  }
  return chain;
}

YAML::Node loadRoot(const std::string &text, const std::string &source)
{
  try {
    return YAML::Load(text);
  } catch (const YAML::ParserException &e) {
    std::ostringstream os;
    os << "robot model " << source << ": YAML syntax error at line " << e.mark.line + 1 << ", column "
       << e.mark.column + 1 << ": " << e.msg;
    throw vpSelfCalibException(vpSelfCalibException::parseError, os.str());
  }
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
  return parse(loadRoot(yaml, source), source);
}

vpKinematicChain vpKinematicChain::loadYaml(const std::string &filename)
{
  std::ifstream in(filename, std::ios::binary);
  if (!in)
    throw vpSelfCalibException(vpSelfCalibException::ioError,
                               "robot model '" + filename + "': cannot open the file for reading");
  std::stringstream ss;
  ss << in.rdbuf();
  return fromYamlString(ss.str(), "'" + filename + "'");
}

vpKinematicChain vpKinematicChain::fromPresetOrFile(const std::string &name_or_file)
{
  for (const std::string &p : presetNames())
    if (p == name_or_file)
      return preset(p);
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
  // Written to a temporary file and renamed, so that a failed write never leaves half a model.
  const std::string tmp = filename + ".tmp";
  {
    std::ofstream os(tmp, std::ios::binary | std::ios::trunc);
    if (!os)
      throw vpSelfCalibException(vpSelfCalibException::ioError,
                                 "robot model '" + filename + "': cannot open '" + tmp + "' for writing");
    os << toYamlString();
    os.flush();
    if (!os)
      throw vpSelfCalibException(vpSelfCalibException::ioError, "robot model '" + filename + "': write failed");
  }
  if (std::rename(tmp.c_str(), filename.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw vpSelfCalibException(vpSelfCalibException::ioError,
                               "robot model '" + filename + "': cannot rename the temporary file into place");
  }
}
