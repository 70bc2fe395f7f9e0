/*
 * ViSP SelfCalib: dataset YAML (read and write) for vpSelfCalibDataset, with yaml-cpp; camera XML
 * through ViSP's vpXmlParserCamera. The format is in the header and doc/formats.md.
 */
#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "../core/vpSelfCalibCamera.h"
#include "vpSelfCalibCameraXml.h"
#include "vpSelfCalibYaml.h"

using namespace vpSelfCalib;

namespace
{
const char *const kWhat = "dataset";

bool isAbsolute(const std::string &p) { return std::filesystem::path(p).is_absolute(); }

std::string resolve(const std::string &base_dir, const std::string &p)
{
  if (p.empty() || base_dir.empty() || isAbsolute(p))
    return p;
  return (std::filesystem::path(base_dir) / p).string();
}

//! p relative to base_dir when it lies below it; p itself otherwise.
std::string relativeTo(const std::string &base_dir, const std::string &p)
{
  if (base_dir.empty() || p.empty())
    return p;
  const std::filesystem::path rel = std::filesystem::path(p).lexically_relative(base_dir);
  if (rel.empty() || *rel.begin() == "..")
    return p;
  return rel.string();
}

/*
  An image file's path as the dataset holds it: relative to the dataset's directory, ".." included
  (a dataset imported beside its data reads "../data/image.png", and moves with it); absolute only
  when the two share nothing but the root.
*/
std::string imagePathFor(const std::string &base_dir, const std::string &p)
{
  namespace fs = std::filesystem;
  if (base_dir.empty() || p.empty())
    return p;
  std::error_code ec;
  const fs::path a = fs::absolute(p, ec).lexically_normal(), b = fs::absolute(base_dir, ec).lexically_normal();
  const fs::path rel = a.lexically_relative(b);
  if (ec || rel.empty())
    return p;
  size_t up = 0, depth = 0;
  for (const fs::path &c : rel)
    up += c == "..";
  for (const fs::path &c : b.relative_path())
    depth += !c.empty();
  return up >= depth ? p : rel.string();
}

std::string directoryOf(const std::string &file)
{
  const std::filesystem::path dir = std::filesystem::path(file).parent_path();
  return dir.empty() ? "." : dir.string();
}

void parseCamera(const Reader &r, const YAML::Node &root, const std::string &base_dir, vpSelfCalibDataset &ds,
                 vpCameraParameters &distorted, bool &has_distortion)
{
  has_distortion = false;
  if (root["camera"] && root["camera_xml"])
    r.fail("camera", "give either camera or camera_xml, not both");
  if (root["camera_xml"]) {
    const YAML::Node cx = root["camera_xml"];
    if (!cx.IsMap())
      r.fail("camera_xml", "expected a map {file, name}, got " + Reader::show(cx));
    r.onlyKeys(cx, {"file", "name"}, "camera_xml");
    const std::string file = resolve(base_dir, r.text(cx["file"], "camera_xml.file"));
    const std::string name = r.text(cx["name"], "camera_xml.name");
    if (!std::ifstream(file))
      r.fail("camera_xml.file", "cannot read '" + file + "'");
    CameraXml xml;
    if (readCameraXml(file, name, vpCameraParameters::perspectiveProjWithDistortion, xml)) {
      has_distortion = xml.cam.get_kud() != 0 || xml.cam.get_kdu() != 0;
      distorted = xml.cam;
    } else if (!readCameraXml(file, name, vpCameraParameters::perspectiveProjWithoutDistortion, xml)) {
      // Say which it is: a file that is not a camera XML, a camera that is not there, or one that
      // ViSP cannot read.
      const std::vector<std::string> names = cameraXmlNames(file);
      std::string list;
      for (const std::string &n : names)
        list += (list.empty() ? "'" : ", '") + n + "'";
      if (names.empty())
        r.fail("camera_xml", "'" + file + "' is not a ViSP camera XML file, or is broken (no <camera> element read)");
      if (std::find(names.begin(), names.end(), name) == names.end())
        r.fail("camera_xml", "no camera named '" + name + "' in '" + file + "' (it has " + list + ")");
      r.fail("camera_xml", "'" + file + "': ViSP cannot read camera '" + name +
                               "' (broken XML, or a projection model without the expected parameters)");
    }
    const vpCameraParameters &cam = xml.cam;
    ds.width = xml.width;
    ds.height = xml.height;
    if (ds.width == 0 || ds.height == 0)
      r.fail("camera_xml", "'" + file + "' gives no image_width / image_height for camera '" + name + "'");
    if (ds.width > kMaxPixels || ds.height > kMaxPixels ||
        static_cast<double>(ds.width) * ds.height > kMaxImagePixels)
      r.fail("camera_xml", "'" + file + "': an image of " + std::to_string(ds.width) + " x " +
                               std::to_string(ds.height) + " px is beyond what is read (250 Mpx)");
    if (!(std::isfinite(cam.get_px()) && std::isfinite(cam.get_py()) && cam.get_px() > 0 && cam.get_py() > 0 &&
          cam.get_px() <= kMaxPixels && cam.get_py() <= kMaxPixels && std::abs(cam.get_u0()) <= kMaxPixels &&
          std::abs(cam.get_v0()) <= kMaxPixels))
      r.fail("camera_xml", "'" + file + "': camera '" + name + "' has px, py, u0 or v0 outside (0, 1e6] px");
    ds.cam.initPersProjWithoutDistortion(cam.get_px(), cam.get_py(), cam.get_u0(), cam.get_v0());
    ds.focal_known = true;
    return;
  }
  const YAML::Node c = root["camera"];
  if (!c.IsDefined() || c.IsNull())
    r.fail("camera", "missing; expected {width, height, u0, v0, px, py} or camera_xml");
  if (!c.IsMap())
    r.fail("camera", "expected a map {width, height, u0, v0, px, py}, got " + Reader::show(c));
  r.onlyKeys(c, {"width", "height", "u0", "v0", "px", "py", "f_guess", "distortion"}, "camera");
  if (c["distortion"]) {
    // OpenCV's lens model; the pixels stay as measured (the pipeline applies the model).
    const YAML::Node d = c["distortion"];
    if (!d.IsSequence() || (d.size() != 4 && d.size() != 5))
      r.fail("camera.distortion", "expected OpenCV's [k1, k2, p1, p2] or [k1, k2, p1, p2, k3], got " + Reader::show(d));
    ds.opencv_distortion.assign(5, 0.0);
    for (size_t i = 0; i < d.size(); ++i) {
      const double k = r.number(d[i], "camera.distortion[" + std::to_string(i) + "]");
      if (!(std::abs(k) <= 1e3))
        r.fail("camera.distortion[" + std::to_string(i) + "]", "a distortion coefficient between -1000 and 1000");
      ds.opencv_distortion[i] = k;
    }
  }
  const double w = r.number(c["width"], "camera.width"), h = r.number(c["height"], "camera.height");
  if (!(w >= 1 && h >= 1 && w <= kMaxPixels && h <= kMaxPixels && w == std::floor(w) && h == std::floor(h)))
    r.fail("camera", "width and height must be whole numbers of pixels from 1 to 1000000");
  if (w * h > kMaxImagePixels)
    r.fail("camera", "an image of " + std::to_string(static_cast<long long>(w)) + " x " +
                         std::to_string(static_cast<long long>(h)) + " px is beyond what is read (250 Mpx)");
  ds.width = static_cast<unsigned int>(w);
  ds.height = static_cast<unsigned int>(h);
  // The principal point within the image, give or take an image: beyond, it is a mistake.
  const double u0 = r.bounded(c["u0"], "camera.u0", -w, 2 * w, "px"),
               v0 = r.bounded(c["v0"], "camera.v0", -h, 2 * h, "px");
  const bool has_px = c["px"].IsDefined(), has_py = c["py"].IsDefined();
  if (has_px != has_py)
    r.fail(has_px ? "camera.py" : "camera.px", "give both px and py (f known) or neither (f self-calibrated)");
  if (has_px) {
    if (c["f_guess"])
      r.fail("camera.f_guess", "only with px and py omitted (f self-calibrated)");
    const double px = r.number(c["px"], "camera.px"), py = r.number(c["py"], "camera.py");
    if (!(px > 0 && py > 0))
      r.fail("camera", "px and py must be positive");
    r.bounded(c["px"], "camera.px", 1, kMaxPixels, "px"); // below 1 px: a mistake (and beyond ViSP's range)
    r.bounded(c["py"], "camera.py", 1, kMaxPixels, "px");
    ds.cam.initPersProjWithoutDistortion(px, py, u0, v0);
    ds.focal_known = true;
  } else {
    const double f = c["f_guess"] ? r.number(c["f_guess"], "camera.f_guess") : w;
    if (!(f > 0))
      r.fail("camera.f_guess", "must be positive");
    if (c["f_guess"])
      r.bounded(c["f_guess"], "camera.f_guess", 1, kMaxPixels, "px");
    ds.cam.initPersProjWithoutDistortion(f, f, u0, v0);
    ds.focal_known = false;
  }
}

//! The robot's expected pose error (robot_error: {pose_sd: [m, rad], joint_sd: [rad, ...]}), when given.
void parseRobotError(const Reader &r, const YAML::Node &root, vpSelfCalibDataset &ds)
{
  if (!root["robot_error"])
    return;
  // The expected error of the robot's poses (controller poses, joint readings).
  const YAML::Node e = root["robot_error"];
  if (!e.IsMap())
    r.fail("robot_error", "expected a map {pose_sd: [m, rad], joint_sd: [rad, ...]}, got " + Reader::show(e));
  r.onlyKeys(e, {"pose_sd", "joint_sd"}, "robot_error");
  if (e["pose_sd"]) {
    const YAML::Node p = e["pose_sd"];
    if (!p.IsSequence() || p.size() != 2)
      r.fail("robot_error.pose_sd", "expected [translation m, rotation rad], got " + Reader::show(p));
    ds.pose_sd_translation = r.number(p[0], "robot_error.pose_sd[0]");
    ds.pose_sd_rotation = r.number(p[1], "robot_error.pose_sd[1]");
    if (!(ds.pose_sd_translation > 0 && ds.pose_sd_translation < 1 && ds.pose_sd_rotation > 0 &&
          ds.pose_sd_rotation < 1))
      r.fail("robot_error.pose_sd", "both positive, below 1 m and 1 rad");
  }
  if (e["joint_sd"]) {
    const YAML::Node j = e["joint_sd"];
    if (!j.IsSequence() || j.size() == 0)
      r.fail("robot_error.joint_sd", "expected a list of joint sd (rad): one for every joint, or one per joint, got " +
                                         Reader::show(j));
    for (size_t i = 0; i < j.size(); ++i) {
      const double v = r.number(j[i], "robot_error.joint_sd[" + std::to_string(i) + "]");
      if (!(v > 0 && v < 1))
        r.fail("robot_error.joint_sd[" + std::to_string(i) + "]", "positive, below 1 rad");
      ds.joint_sd.push_back(v);
    }
  }
}

//! The kinematic parameters the user fixes or frees (fix: [names or patterns], free: [...]), when given.
void parseParameterLists(const Reader &r, const YAML::Node &root, vpSelfCalibDataset &ds)
{
  for (const char *key : {"fix", "free"}) {
    if (!root[key])
      continue;
    const YAML::Node l = root[key];
    if (!l.IsSequence())
      r.fail(key, "expected a list of parameter names or glob patterns (e.g. [j3.*, eMc.rz]), got " + Reader::show(l));
    std::vector<std::string> &out = std::string(key) == "fix" ? ds.fix : ds.free;
    for (size_t i = 0; i < l.size(); ++i) {
      const std::string v = r.text(l[i], std::string(key) + "[" + std::to_string(i) + "]");
      if (v.empty())
        r.fail(std::string(key) + "[" + std::to_string(i) + "]", "a parameter name or glob pattern, not empty");
      out.push_back(v);
    }
  }
}

//! The kinematic prior (kinematic_prior: off, tolerance, tolerance/K or K, K above 0 and at most 1000), when given.
void parseKinematicPrior(const Reader &r, const YAML::Node &root, vpSelfCalibDataset &ds)
{
  if (!root["kinematic_prior"])
    return;
  const std::string v = r.text(root["kinematic_prior"], "kinematic_prior");
  if (v == "off") {
    ds.kinematic_prior = 0;
    return;
  }
  const std::string k = v == "tolerance" ? "1" : v.rfind("tolerance/", 0) == 0 ? v.substr(10) : v;
  char *end = nullptr;
  const double d = std::strtod(k.c_str(), &end);
  if (k.empty() || end != k.c_str() + k.size() || !std::isfinite(d) || !(d > 0) || d > 1e3)
    r.fail("kinematic_prior", "expected off, tolerance, tolerance/K or K (K above 0, at most 1000), got '" + v + "'");
  ds.kinematic_prior = d;
}

//! A pose's points [id, u, v] (pixels through the inverse of the lens distortion when it has one).
void parsePoints(const Reader &r, const YAML::Node &pts, const std::string &key, bool has_distortion,
                 const vpSelfCalib::CameraModel &camera, vpSelfCalibDataset::View &v)
{
  if (!pts.IsSequence())
    r.fail(key + ".points", "expected a list of [id, u, v], got " + Reader::show(pts));
  std::set<int> ids;
  for (size_t i = 0; i < pts.size(); ++i) {
    const std::string pk = key + ".points[" + std::to_string(i) + "]";
    if (!pts[i].IsSequence() || pts[i].size() != 3)
      r.fail(pk, "expected [id, u, v], got " + Reader::show(pts[i]));
    const double id = r.number(pts[i][0], pk + "[0]");
    if (!(id >= 0 && id == std::floor(id) && id < 2147483647.0))
      r.fail(pk + "[0]", "a point id is a non-negative whole number");
    vpSelfCalibDataset::Observation o;
    o.id = static_cast<int>(id);
    if (!ids.insert(o.id).second)
      r.fail(pk, "point id " + std::to_string(o.id) + " appears twice in this pose");
    const double u = r.bounded(pts[i][1], pk + "[1]", -kMaxPixels, kMaxPixels, "px"),
                 vv = r.bounded(pts[i][2], pk + "[2]", -kMaxPixels, kMaxPixels, "px");
    if (has_distortion) {
      // Undistorted pixel: the camera model's exact inverse of k_ud (ViSP's separately fitted
      // k_du, a first-order inverse, is not used), then the pinhole.
      const Eigen::Vector2d uv = camera.undistortPixel(Eigen::Vector2d(u, vv));
      o.ip = vpImagePoint(uv(1), uv(0));
    } else
      o.ip = vpImagePoint(vv, u);
    v.points.push_back(o);
  }
}

//! A pose's joints (as many as the earlier poses': num_joints, -1 before the first) or controller pose.
void parseRobotPose(const Reader &r, const YAML::Node &p, const std::string &key, int &num_joints,
                    vpSelfCalibDataset::View &v)
{
  if (!p["joints"] && !p["fMe"])
    r.fail(key, "needs joints (rad) or fMe (a controller pose vector)");
  if (p["joints"] && p["fMe"])
    r.fail(key, "gives both joints and fMe: give one (joints when the robot model is to be calibrated, fMe for "
                "the controller's poses)");
  if (p["joints"]) {
    const YAML::Node j = p["joints"];
    if (j.IsSequence() && j.size() == 0)
      r.fail(key + ".joints", "an empty list: expected the robot's joint values (rad)");
    if (!j.IsSequence())
      r.fail(key + ".joints", "expected a list of joint values (rad), got " + Reader::show(j));
    r.atMost(j, kMaxJoints, key + ".joints", "joint values");
    if (num_joints >= 0 && static_cast<int>(j.size()) != num_joints)
      r.fail(key + ".joints", std::to_string(j.size()) + " values, earlier poses have " + std::to_string(num_joints));
    num_joints = static_cast<int>(j.size());
    v.q.resize(static_cast<unsigned int>(j.size()));
    for (size_t i = 0; i < j.size(); ++i)
      v.q[static_cast<unsigned int>(i)] =
          r.bounded(j[i], key + ".joints[" + std::to_string(i) + "]", -kMaxAngle, kMaxAngle, "rad");
  }
  if (p["fMe"]) {
    v.fMe = vpHomogeneousMatrix(r.pose(p["fMe"], key + ".fMe"));
    v.has_fMe = true;
  }
}

//! The poses' list: checked, its observations counted before any is read (YAML aliases let a small
//! file name millions).
void checkPosesList(const Reader &r, const YAML::Node &poses)
{
  if (!poses.IsDefined() || poses.IsNull())
    r.fail("poses", "missing; expected a list of poses {joints or fMe, image, points}");
  if (!poses.IsSequence())
    r.fail("poses", "expected a list, got " + Reader::show(poses));
  r.atMost(poses, kMaxPoses, "poses", "poses");
  size_t num_observations = 0;
  for (size_t k = 0; k < poses.size(); ++k) {
    const YAML::Node p = poses[k];
    if (p.IsMap()) {
      const YAML::Node pts = p["points"];
      if (pts && pts.IsSequence())
        num_observations += pts.size();
    }
  }
  if (num_observations > kMaxObservations)
    r.fail("poses", std::to_string(num_observations) + " observations (YAML aliases expand to that many?): at most " +
                        std::to_string(kMaxObservations) + " are read");
}

//! The yardstick {length, ends: [id_a, id_b]} (ends optional: the front end finds its dots).
void parseYardstick(const Reader &r, const YAML::Node &y, vpSelfCalibDataset &ds)
{
  if (!y.IsMap())
    r.fail("yardstick", "expected a map {length, ends: [id_a, id_b]}, got " + Reader::show(y));
  r.onlyKeys(y, {"length", "ends"}, "yardstick");
  // Below a micrometre a yardstick is a mistake (and every scale from it underflows).
  ds.yardstick.length = r.bounded(y["length"], "yardstick.length", 1e-6, kMaxLength, "m");
  if (!(ds.yardstick.length > 0))
    r.fail("yardstick.length", "must be positive (m)");
  // Without ends: the front end finds the yardstick's dots in the images.
  if (y["ends"]) {
    const YAML::Node e = y["ends"];
    if (!e.IsSequence() || e.size() != 2)
      r.fail("yardstick.ends", "expected [id_a, id_b], got " + Reader::show(e));
    const double a = r.number(e[0], "yardstick.ends[0]"), b = r.number(e[1], "yardstick.ends[1]");
    if (!(a >= 0 && b >= 0 && a < 2147483647.0 && b < 2147483647.0 && a == std::floor(a) && b == std::floor(b) &&
          a != b))
      r.fail("yardstick.ends", "two different non-negative point ids");
    ds.yardstick.id_a = static_cast<int>(a);
    ds.yardstick.id_b = static_cast<int>(b);
  }
}

vpSelfCalibDataset parse(const YAML::Node &root, const std::string &source, const std::string &base_dir)
{
  const Reader r(kWhat, source);
  if (!root.IsMap())
    throw vpSelfCalibException(vpSelfCalibException::parseError,
                               std::string(kWhat) + " " + source + ": expected a YAML map at the top level");
  r.onlyKeys(root, {"camera", "camera_xml", "robot", "camera_mount", "robot_error", "poses", "yardstick", "fix", "free", "kinematic_prior"}, "");
  vpSelfCalibDataset ds;
  if (root["camera_mount"]) {
    const std::string mount = r.text(root["camera_mount"], "camera_mount");
    if (mount == "world")
      ds.camera_mount = vpSelfCalibDataset::CAMERA_IN_WORLD;
    else if (mount != "effector")
      r.fail("camera_mount", "expected effector (the camera on the end-effector, eye-in-hand) or world (the camera "
                             "fixed in the robot's world, eye-to-hand), got '" + mount + "'");
  }
  vpCameraParameters distorted;
  bool has_distortion = false;
  parseRobotError(r, root, ds);
  parseParameterLists(r, root, ds);
  parseKinematicPrior(r, root, ds);
  parseCamera(r, root, base_dir, ds, distorted, has_distortion);
  const vpSelfCalib::CameraModel camera = vpSelfCalib::CameraModel::fromVisp(distorted);

  const std::string robot = r.text(root["robot"], "robot");
  const std::vector<std::string> presets = vpKinematicChain::presetNames();
  ds.robot = std::find(presets.begin(), presets.end(), robot) != presets.end() ? robot : resolve(base_dir, robot);

  const YAML::Node poses = root["poses"];
  checkPosesList(r, poses);
  int num_joints = -1;
  for (size_t k = 0; k < poses.size(); ++k) {
    const std::string key = "poses[" + std::to_string(k) + "]";
    const YAML::Node p = poses[k];
    if (!p.IsMap())
      r.fail(key, "expected a map {joints or fMe, image, points}, got " + Reader::show(p));
    r.onlyKeys(p, {"joints", "fMe", "image", "mask", "points"}, key);
    vpSelfCalibDataset::View v;
    parseRobotPose(r, p, key, num_joints, v);
    if (p["image"]) {
      v.image = resolve(base_dir, r.text(p["image"], key + ".image"));
      // Image readers choose the format by the extension (ViSP's throws a bare substr error without one).
      if (std::filesystem::path(v.image).extension().string().size() < 2)
        r.fail(key + ".image", "'" + v.image + "' has no extension: expected an image file (.png, .jpg, .pgm...)");
    }
    if (p["mask"]) {
      v.mask = resolve(base_dir, r.text(p["mask"], key + ".mask"));
      if (std::filesystem::path(v.mask).extension().string().size() < 2)
        r.fail(key + ".mask", "'" + v.mask + "' has no extension: expected an image file (.png, .pgm...)");
      if (!p["image"])
        r.fail(key + ".mask", "a mask without an image: the mask says where this view's image has no features");
    }
    if (p["points"])
      parsePoints(r, p["points"], key, has_distortion, camera, v);
    ds.views.push_back(v);
  }
  if (root["yardstick"])
    parseYardstick(r, root["yardstick"], ds);
  return ds;
}

/*!
  The pose vector written for a controller pose: theta-u from the matrix can be one ulp away from
  the vector the matrix was built from, and a dataset would then drift by an ulp at every write and
  read (found by fuzzing). The theta-u components are nudged by up to 2 ulps each until the vector
  rebuilds the matrix bit for bit; when none does, the plain conversion is written.
*/
vpPoseVector exactPose(const vpHomogeneousMatrix &M)
{
  const vpPoseVector p0(M);
  auto rebuilds = [&M](const vpPoseVector &p) {
    const vpHomogeneousMatrix B(p);
    for (unsigned int r = 0; r < 3; ++r)
      for (unsigned int c = 0; c < 4; ++c)
        if (B[r][c] != M[r][c])
          return false;
    return true;
  };
  if (rebuilds(p0))
    return p0;
  auto nudge = [](double x, int ulps) {
    for (; ulps > 0; --ulps)
      x = std::nextafter(x, HUGE_VAL);
    for (; ulps < 0; ++ulps)
      x = std::nextafter(x, -HUGE_VAL);
    return x;
  };
  for (int a = -2; a <= 2; ++a)
    for (int b = -2; b <= 2; ++b)
      for (int c = -2; c <= 2; ++c) {
        vpPoseVector p = p0;
        p[3] = nudge(p0[3], a);
        p[4] = nudge(p0[4], b);
        p[5] = nudge(p0[5], c);
        if (rebuilds(p))
          return p;
      }
  return p0;
}
} // namespace

vpSelfCalibDataset vpSelfCalibDataset::fromYamlString(const std::string &yaml, const std::string &source,
                                                      const std::string &base_dir)
{
  return parseYaml(kWhat, source, [&] { return parse(loadYamlRoot(yaml, kWhat, source), source, base_dir); });
}

vpSelfCalibDataset vpSelfCalibDataset::loadYaml(const std::string &filename)
{
  return fromYamlString(readTextFile(filename, kWhat), "'" + filename + "'", directoryOf(filename));
}

std::string vpSelfCalibDataset::toYamlString(const std::string &base_dir) const
{
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap;
  out << YAML::Key << "camera" << YAML::Value << YAML::Flow << YAML::BeginMap;
  out << YAML::Key << "width" << YAML::Value << width << YAML::Key << "height" << YAML::Value << height;
  out << YAML::Key << "u0" << YAML::Value << cam.get_u0() << YAML::Key << "v0" << YAML::Value << cam.get_v0();
  if (focal_known)
    out << YAML::Key << "px" << YAML::Value << cam.get_px() << YAML::Key << "py" << YAML::Value << cam.get_py();
  else
    out << YAML::Key << "f_guess" << YAML::Value << cam.get_px();
  if (!opencv_distortion.empty()) {
    out << YAML::Key << "distortion" << YAML::Value << YAML::Flow << YAML::BeginSeq;
    for (double k : opencv_distortion)
      out << k;
    out << YAML::EndSeq;
  }
  out << YAML::EndMap;
  out << YAML::Key << "robot" << YAML::Value << relativeTo(base_dir, robot);
  if (camera_mount != CAMERA_ON_EFFECTOR)
    out << YAML::Key << "camera_mount" << YAML::Value << cameraMountName(camera_mount);
  if (pose_sd_translation > 0 || !joint_sd.empty()) {
    out << YAML::Key << "robot_error" << YAML::Value << YAML::Flow << YAML::BeginMap;
    if (pose_sd_translation > 0)
      out << YAML::Key << "pose_sd" << YAML::Value << YAML::Flow << YAML::BeginSeq << pose_sd_translation
          << pose_sd_rotation << YAML::EndSeq;
    if (!joint_sd.empty()) {
      out << YAML::Key << "joint_sd" << YAML::Value << YAML::Flow << YAML::BeginSeq;
      for (double v : joint_sd)
        out << v;
      out << YAML::EndSeq;
    }
    out << YAML::EndMap;
  }
  for (const auto &list : {std::make_pair("fix", &fix), std::make_pair("free", &free)})
    if (!list.second->empty()) {
      out << YAML::Key << list.first << YAML::Value << YAML::Flow << YAML::BeginSeq;
      for (const std::string &n : *list.second)
        out << n;
      out << YAML::EndSeq;
    }
  if (kinematic_prior && *kinematic_prior > 0)
    out << YAML::Key << "kinematic_prior" << YAML::Value << *kinematic_prior;
  else if (kinematic_prior)
    out << YAML::Key << "kinematic_prior" << YAML::Value << "off";
  out << YAML::Key << "poses" << YAML::Value << YAML::BeginSeq;
  for (const View &v : views) {
    out << YAML::BeginMap;
    if (v.q.size()) {
      out << YAML::Key << "joints" << YAML::Value << YAML::Flow << YAML::BeginSeq;
      for (unsigned int i = 0; i < v.q.size(); ++i)
        out << v.q[i];
      out << YAML::EndSeq;
    }
    if (v.has_fMe) {
      const vpPoseVector p = exactPose(v.fMe);
      out << YAML::Key << "fMe" << YAML::Value << YAML::Flow << YAML::BeginSeq;
      for (unsigned int i = 0; i < 6; ++i)
        out << p[i];
      out << YAML::EndSeq;
    }
    if (!v.image.empty())
      out << YAML::Key << "image" << YAML::Value << imagePathFor(base_dir, v.image);
    if (!v.mask.empty())
      out << YAML::Key << "mask" << YAML::Value << imagePathFor(base_dir, v.mask);
    out << YAML::Key << "points" << YAML::Value << YAML::BeginSeq;
    for (const Observation &o : v.points)
      out << YAML::Flow << YAML::BeginSeq << o.id << o.ip.get_u() << o.ip.get_v() << YAML::EndSeq;
    out << YAML::EndSeq << YAML::EndMap;
  }
  out << YAML::EndSeq;
  if (yardstick.length > 0) {
    out << YAML::Key << "yardstick" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "length"
        << YAML::Value << yardstick.length;
    if (yardstick.isSet())
      out << YAML::Key << "ends" << YAML::Value << YAML::Flow << YAML::BeginSeq << yardstick.id_a << yardstick.id_b
          << YAML::EndSeq;
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

const char *vpSelfCalibDataset::cameraMountName(CameraMount m)
{
  return m == CAMERA_IN_WORLD ? "world" : "effector";
}

void vpSelfCalibDataset::saveYaml(const std::string &filename) const
{
  writeFileAtomically(filename, toYamlString(directoryOf(filename)), kWhat);
}
