/*
 * ViSP SelfCalib: importers of the eye-in-hand layouts users have (ViSP's hand-eye folders,
 * industrial_calibration's cal_data.yaml) into the dataset format, and the pose-file readers
 * (pose vector, position + quaternion, 4 x 4 matrix). The layouts are in the header.
 */
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibImporter.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <map>
#include <regex>
#include <sstream>

#include <Eigen/Dense>
#include <visp3/core/vpImage.h>
#include <visp3/core/vpQuaternionVector.h>
#include <visp3/core/vpRotationMatrix.h>
#include <visp3/core/vpTranslationVector.h>
#include <visp3/io/vpImageIo.h>
#include <yaml-cpp/yaml.h>

#include "../core/vpSelfCalibFiles.h"
#include "vpSelfCalibCameraXml.h"
#include "vpSelfCalibYaml.h"

namespace fs = std::filesystem;
using namespace vpSelfCalib;

namespace
{
const char *const kPoseFile = "pose file";
const char *const kCalData = "industrial_calibration data";
const double kRigidTolerance = 1e-6;

std::string inQuotes(const std::string &s) { return "'" + s + "'"; }

std::string absolutePath(const fs::path &p) { return fs::absolute(p).lexically_normal().string(); }

//! "a, b, c"
std::string joined(const std::vector<std::string> &items)
{
  std::string s;
  for (const std::string &i : items)
    s += (s.empty() ? "" : ", ") + i;
  return s;
}

std::string fmt(double v)
{
  std::ostringstream os;
  os << std::setprecision(6) << v;
  return os.str();
}

// ---------------------------------------------------------------------------------------------
// Pose files

struct Pose {
  vpHomogeneousMatrix M;
  std::string format;
};

[[noreturn]] void failPose(const std::string &source, const std::string &what)
{
  throw vpSelfCalibException(vpSelfCalibException::parseError, std::string(kPoseFile) + " " + source + ": " + what);
}

Pose fromPoseVector(const Reader &r, const std::vector<double> &v, const std::string &key)
{
  vpPoseVector p;
  for (unsigned int i = 0; i < 6; ++i)
    p[i] = v[i];
  r.checkRotation(p, key);
  return {vpHomogeneousMatrix(p), "ViSP pose vector (tx ty tz tux tuy tuz)"};
}

Pose fromQuaternion(const std::string &source, const std::vector<double> &v)
{
  const double n = std::sqrt(v[3] * v[3] + v[4] * v[4] + v[5] * v[5] + v[6] * v[6]);
  if (!(n >= 1e-6)) {
    std::ostringstream os;
    os << "the quaternion (qx qy qz qw) is zero (norm " << n << "): not a rotation";
    failPose(source, os.str());
  }
  const vpQuaternionVector q(v[3] / n, v[4] / n, v[5] / n, v[6] / n);
  return {vpHomogeneousMatrix(vpTranslationVector(v[0], v[1], v[2]), vpRotationMatrix(q)),
          "position and quaternion (x y z qx qy qz qw)"};
}

/*
  A 4 x 4 matrix, row by row: a rigid transform within kRigidTolerance (R^T R = I, det R = +1, last
  row 0 0 0 1), then its rotation replaced by the nearest rotation (SVD: U V^T), so that the
  dataset holds an exact one.
*/
Pose fromMatrix(const std::string &source, const std::vector<double> &v)
{
  Eigen::Matrix3d R;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      R(i, j) = v[static_cast<size_t>(4 * i + j)];
  std::ostringstream os;
  const double last = std::max({std::abs(v[12]), std::abs(v[13]), std::abs(v[14]), std::abs(v[15] - 1)});
  if (!(last <= kRigidTolerance)) {
    os << "not a rigid transform: the last row is (" << v[12] << " " << v[13] << " " << v[14] << " " << v[15]
       << "), expected 0 0 0 1";
    failPose(source, os.str());
  }
  const double ortho = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (!(ortho <= kRigidTolerance)) {
    os << "not a rigid transform: the rotation part is not orthonormal (largest element of R^T R - I: " << ortho
       << ", tolerance " << kRigidTolerance << ")";
    failPose(source, os.str());
  }
  if (!(R.determinant() > 0)) {
    os << "not a rigid transform: the rotation part has determinant " << R.determinant() << " (a reflection)";
    failPose(source, os.str());
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Matrix3d Rn = svd.matrixU() * svd.matrixV().transpose();
  vpHomogeneousMatrix M;
  for (unsigned int i = 0; i < 3; ++i) {
    for (unsigned int j = 0; j < 3; ++j)
      M[i][j] = Rn(static_cast<int>(i), static_cast<int>(j));
    M[i][3] = v[4 * i + 3];
  }
  return {M, "4 x 4 homogeneous matrix"};
}

//! 6 numbers: a pose vector; 7: a position and a quaternion; 16: a matrix row by row.
Pose fromNumbers(const Reader &r, const std::string &source, const std::vector<double> &v, const std::string &key)
{
  if (v.size() == 6)
    return fromPoseVector(r, v, key);
  if (v.size() == 7)
    return fromQuaternion(source, v);
  if (v.size() == 16)
    return fromMatrix(source, v);
  failPose(source, std::to_string(v.size()) +
                       " numbers: expected 6 (pose vector tx ty tz tux tuy tuz), 7 (x y z qx qy qz qw) or 16 (a 4 x "
                       "4 matrix row by row)");
}

//! Whitespace-separated numbers of a plain scalar (a line or a column of numbers in a file).
std::vector<double> numbersOfText(const std::string &source, const std::string &text)
{
  std::istringstream in(text);
  std::vector<double> v;
  std::string tok;
  while (in >> tok) {
    char *end = nullptr;
    errno = 0;
    const double x = std::strtod(tok.c_str(), &end);
    if (end != tok.c_str() + tok.size() || errno == ERANGE || !std::isfinite(x))
      failPose(source, "'" + tok + "' is not a finite number");
    v.push_back(x);
  }
  return v;
}

//! `rows: R, cols: C, data: ...` (ViSP's vpArray2D YAML): data as R lists of C numbers, or R * C numbers.
Pose fromArray(const Reader &r, const std::string &source, const YAML::Node &root)
{
  r.onlyKeys(root, {"rows", "cols", "data"}, "");
  const double rows = r.number(root["rows"], "rows"), cols = r.number(root["cols"], "cols");
  const YAML::Node data = root["data"];
  if (!data.IsDefined() || !data.IsSequence())
    r.fail("data", "expected a list, got " + Reader::show(data));
  const bool vector = (rows == 6 && cols == 1) || (rows == 1 && cols == 6), matrix = rows == 4 && cols == 4;
  if (!vector && !matrix)
    failPose(source, "a " + fmt(rows) + " x " + fmt(cols) +
                         " array: expected 6 x 1 (a pose vector) or 4 x 4 (a homogeneous matrix)");
  const size_t R = static_cast<size_t>(rows), C = static_cast<size_t>(cols);
  std::vector<double> v;
  if (data.size() == R * C && (R * C == 1 || !data[0].IsSequence())) {
    for (size_t i = 0; i < data.size(); ++i)
      v.push_back(r.number(data[i], "data[" + std::to_string(i) + "]"));
  } else if (data.size() == R) {
    for (size_t i = 0; i < R; ++i) {
      const std::string key = "data[" + std::to_string(i) + "]";
      if (!data[i].IsSequence() || data[i].size() != C)
        r.fail(key, "expected a row of " + std::to_string(C) + " numbers, got " + Reader::show(data[i]));
      for (size_t j = 0; j < C; ++j)
        v.push_back(r.number(data[i][j], key + "[" + std::to_string(j) + "]"));
    }
  } else
    r.fail("data", "expected " + std::to_string(R) + " rows of " + std::to_string(C) + " numbers");
  return vector ? fromPoseVector(r, v, "data") : fromMatrix(source, v);
}

Pose poseFromNode(const YAML::Node &root, const std::string &source)
{
  const Reader r(kPoseFile, source);
  const char *expected = "expected a pose: a pose vector (rows: 6, cols: 1, data: ... or [tx, ty, tz, tux, tuy, "
                         "tuz]), a position and quaternion ({x, y, z, qx, qy, qz, qw} or a list of 7) or a 4 x 4 "
                         "matrix (a list of 4 rows, or rows: 4, cols: 4, data: ...)";
  if (root.IsMap()) {
    if (root["data"] || root["rows"] || root["cols"])
      return fromArray(r, source, root);
    r.onlyKeys(root, {"x", "y", "z", "qx", "qy", "qz", "qw"}, "");
    std::vector<double> v;
    for (const char *k : {"x", "y", "z", "qx", "qy", "qz", "qw"})
      v.push_back(r.number(root[k], k));
    return fromQuaternion(source, v);
  }
  if (root.IsSequence()) {
    std::vector<double> v;
    const bool rows = root.size() == 4 && root[0].IsSequence();
    for (size_t i = 0; i < root.size(); ++i) {
      const std::string key = "[" + std::to_string(i) + "]";
      if (!rows) {
        v.push_back(r.number(root[i], key));
        continue;
      }
      if (!root[i].IsSequence() || root[i].size() != 4)
        r.fail(key, "expected a matrix row of 4 numbers, got " + Reader::show(root[i]));
      for (size_t j = 0; j < 4; ++j)
        v.push_back(r.number(root[i][j], key + "[" + std::to_string(j) + "]"));
    }
    if (rows)
      return fromMatrix(source, v);
    return fromNumbers(r, source, v, "theta-u");
  }
  if (root.IsScalar())
    return fromNumbers(r, source, numbersOfText(source, root.Scalar()), "theta-u");
  failPose(source, expected);
}

Pose readPoseFile(const std::string &file)
{
  const std::string source = inQuotes(file);
  return parseYaml(kPoseFile, source, [&] {
    return poseFromNode(loadYamlRoot(readTextFile(file, kPoseFile), kPoseFile, source), source);
  });
}

// ---------------------------------------------------------------------------------------------
// What the layouts share

bool isPreset(const std::string &name)
{
  const std::vector<std::string> presets = vpKinematicChain::presetNames();
  return std::find(presets.begin(), presets.end(), name) != presets.end();
}

//! The import under way: the result, the camera size, the eMc guess and the pose formats seen.
struct Import {
  vpSelfCalibImporter::Result res;
  bool has_eMc_guess = false;
  vpPoseVector eMc_guess;
  std::string eMc_guess_source;
  std::vector<std::string> formats;

  void unused(const std::string &what, const std::string &reason) { res.report.unused.push_back({what, reason}); }
  void input(const fs::path &file) { res.inputs.push_back(absolutePath(file)); }

  /*
    An image of a view: readable, and of the camera's size (the first readable image gives the size
    when the camera does not). False with the reason otherwise.
  */
  bool imageUsable(const fs::path &file, std::string &reason)
  {
    vpImage<unsigned char> I;
    try {
      vpSelfCalib::checkImageFile(file.string(), "cannot read the image");
    } catch (const vpSelfCalibException &e) {
      reason = e.getStringMessage();
      return false;
    }
    try {
      vpImageIo::read(I, file.string());
    } catch (const vpException &e) {
      reason = "cannot read the image: " + e.getStringMessage();
      return false;
    }
    vpSelfCalibDataset &ds = res.dataset;
    if (ds.width == 0 || ds.height == 0) {
      ds.width = I.getWidth();
      ds.height = I.getHeight();
    } else if (I.getWidth() != ds.width || I.getHeight() != ds.height) {
      reason = "the image is " + std::to_string(I.getWidth()) + " x " + std::to_string(I.getHeight()) +
               ", the camera's size is " + std::to_string(ds.width) + " x " + std::to_string(ds.height);
      return false;
    }
    return true;
  }

  //! A view from a pose file and its image; the image is checked, the pose file must be good.
  void addView(const fs::path &pose_file, const fs::path &image, const std::string &what)
  {
    input(pose_file);
    const Pose p = readPoseFile(pose_file.string());
    if (std::find(formats.begin(), formats.end(), p.format) == formats.end())
      formats.push_back(p.format);
    input(image);
    std::string reason;
    if (!imageUsable(image, reason)) {
      unused(what, reason);
      return;
    }
    vpSelfCalibDataset::View v;
    v.has_fMe = true;
    v.fMe = p.M;
    v.image = absolutePath(image);
    res.dataset.views.push_back(v);
  }

  //! The end: at least one view, the counts, the robot.
  void finish(const vpSelfCalibImporter::Options &opt, const std::string &default_robot, const std::string &where)
  {
    vpSelfCalibImporter::Report &rep = res.report;
    rep.num_views = static_cast<unsigned int>(res.dataset.views.size());
    rep.pose_format = joined(formats);
    if (res.dataset.views.empty()) {
      std::string why;
      for (const auto &u : rep.unused)
        why += "; " + u.what + ": " + u.reason;
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "importer " + inQuotes(rep.source) + ": no pose with its image" + where + why);
    }
    chooseRobot(opt, default_robot);
  }

  /*
    The robot (Options::robot). The hand-eye calibration of controller poses uses only the model's
    eMc guess, so a data set of an unknown robot gets a generic model: one placeholder joint, the
    eMc guess.
  */
  void chooseRobot(const vpSelfCalibImporter::Options &opt, const std::string &default_robot)
  {
    vpSelfCalibImporter::Report &rep = res.report;
    const std::string name = opt.robot.empty() ? default_robot : opt.robot;
    const std::string guess = has_eMc_guess ? "eMc guess from " + eMc_guess_source : "";
    if (!name.empty() && !isPreset(name)) {
      vpKinematicChain::loadYaml(name); // a robot-model file: it must load
      input(name);
      res.dataset.robot = absolutePath(name);
      rep.robot = "robot-model file " + inQuotes(name);
      if (has_eMc_guess)
        unused(eMc_guess_source, "the robot-model file's eMc is the guess");
      return;
    }
    if (!name.empty()) {
      rep.robot = name + " (preset" + (opt.robot.empty() ? ", the default for ViSP franka_ folders" : "") + ")";
      if (!has_eMc_guess) {
        res.dataset.robot = name;
        return;
      }
      res.robot_model = vpKinematicChain::preset(name);
      res.robot_model.set_eMc(eMc_guess);
      rep.robot += ", " + guess;
    } else {
      std::vector<vpKinematicChain::Joint> placeholder(1);
      res.robot_model = vpKinematicChain("hand-eye", vpKinematicChain::DH, placeholder, vpPoseVector(), vpPoseVector(),
                                         has_eMc_guess ? eMc_guess : vpPoseVector());
      rep.robot = "generic hand-eye model (one placeholder joint: the poses are controller poses fMe; --robot "
                  "gives a preset or a model file), " +
                  (has_eMc_guess ? guess : "eMc guess identity (none in the data)");
    }
    res.has_robot_model = true;
    rep.robot += "; written beside the dataset";
  }

  //! How the intrinsics are taken: known, or f self-calibrated from px (one focal length, py = px).
  void takeIntrinsics(bool known, const std::string &what)
  {
    vpSelfCalibDataset &ds = res.dataset;
    const double px = ds.cam.get_px(), py = ds.cam.get_py();
    ds.focal_known = known;
    if (known) {
      res.report.camera += "; taken as known (--intrinsics guess: f self-calibrated from px)";
      return;
    }
    ds.cam.initPersProjWithoutDistortion(px, px, ds.cam.get_u0(), ds.cam.get_v0());
    res.report.camera += "; a guess: f self-calibrated from " + fmt(px) +
                         ", principal point kept (--intrinsics known: take them as calibrated)";
    if (std::abs(py - px) > 1e-3 * px)
      unused(what + " py " + fmt(py), "f is self-calibrated as one focal length (py = px)");
  }
};

//! Digits without leading zeros, ordered as numbers (shorter first, then by digits).
std::string canonicalNumber(const std::string &digits)
{
  const size_t k = digits.find_first_not_of('0');
  return k == std::string::npos ? "0" : digits.substr(k);
}
struct NumberLess {
  bool operator()(const std::string &a, const std::string &b) const
  {
    return a.size() != b.size() ? a.size() < b.size() : a < b;
  }
};

// ---------------------------------------------------------------------------------------------
// ViSP's hand-eye folder

//! "9 x 6" and "square size: 0.0236 m" of chessboard-data.txt, as text; "" when not understood.
std::string chessboardText(const std::string &text, std::string &board_option)
{
  std::smatch size, square;
  if (!std::regex_search(text, size, std::regex("([0-9]+)\\s*x\\s*([0-9]+)")) ||
      !std::regex_search(text, square, std::regex("square size\\s*:\\s*([0-9.eE+-]+)")))
    return "";
  board_option = "chessboard:" + size[1].str() + "x" + size[2].str() + ":" + square[1].str();
  return "chessboard, " + size[1].str() + " x " + size[2].str() + " inner corners, squares " + square[1].str() +
         " m (chessboard-data.txt)";
}

void readVispCamera(Import &im, const fs::path &xml, vpSelfCalibImporter::Intrinsics intrinsics)
{
  const std::string file = xml.string();
  im.input(xml);
  const std::vector<std::string> names = cameraXmlNames(file);
  std::string name;
  if (names.size() == 1)
    name = names[0];
  else if (std::find(names.begin(), names.end(), "Camera") != names.end())
    name = "Camera";
  else {
    std::vector<std::string> list;
    for (const std::string &n : names)
      list.push_back(inQuotes(n));
    throw vpSelfCalibException(
        vpSelfCalibException::parseError,
        "camera XML " + inQuotes(file) +
            (names.empty() ? ": no camera in it" : ": cameras " + joined(list) + ", none named 'Camera': which one?"));
  }
  // A pinhole dataset: the model without distortion when the file has one.
  CameraXml cam;
  const bool pinhole = readCameraXml(file, name, vpCameraParameters::perspectiveProjWithoutDistortion, cam);
  if (!pinhole && !readCameraXml(file, name, vpCameraParameters::perspectiveProjWithDistortion, cam))
    throw vpSelfCalibException(vpSelfCalibException::parseError, "camera XML " + inQuotes(file) + ": camera " +
                                                                     inQuotes(name) +
                                                                     " cannot be read by vpXmlParserCamera");
  vpSelfCalibDataset &ds = im.res.dataset;
  ds.cam.initPersProjWithoutDistortion(cam.cam.get_px(), cam.cam.get_py(), cam.cam.get_u0(), cam.cam.get_v0());
  ds.width = cam.width;
  ds.height = cam.height;
  if (!pinhole && (cam.cam.get_kud() != 0 || cam.cam.get_kdu() != 0))
    im.unused(xml.filename().string() + " distortion (kud " + fmt(cam.cam.get_kud()) + ", kdu " +
                  fmt(cam.cam.get_kdu()) + ")",
              "the dataset's camera is a pinhole: the images are used as they are");
  std::ostringstream os;
  os << std::setprecision(6) << xml.filename().string() << ", camera " << inQuotes(name) << ": px " << cam.cam.get_px()
     << ", py " << cam.cam.get_py() << ", u0 " << cam.cam.get_u0() << ", v0 " << cam.cam.get_v0();
  if (cam.width && cam.height)
    os << ", " << cam.width << " x " << cam.height;
  im.res.report.camera = os.str();
  im.takeIntrinsics(intrinsics != vpSelfCalibImporter::INTRINSICS_GUESS, xml.filename().string());
}

/*
  ViSP's eye-to-hand folder: apriltag-data.txt ("36h11", "size: 0.048 m") describes a tag on the
  tool, the camera fixed in the world (the dataset's camera_mount: world), and the --board for it.
*/
void readTagDescription(Import &im, const fs::path &f)
{
  im.input(f);
  const std::string text = readTextFile(f.string(), "tag description");
  std::smatch family, size;
  im.res.dataset.camera_mount = vpSelfCalibDataset::CAMERA_IN_WORLD;
  vpSelfCalibImporter::Report &rep = im.res.report;
  if (std::regex_search(text, family, std::regex("([0-9]+h[0-9]+)")) &&
      std::regex_search(text, size, std::regex("size:[ \t]*([0-9.eE+-]+)[ \t]*m"))) {
    rep.board = "AprilTag " + family[1].str() + ", " + size[1].str() + " m side, on the end-effector (apriltag-data.txt)";
    rep.board_option = "apriltag:" + family[1].str() + ":" + size[1].str();
  } else
    im.unused(f.filename().string(), "not understood (expected a family such as '36h11' and 'size: S m')");
}

vpSelfCalibImporter::Result importVisp(const fs::path &dir, const vpSelfCalibImporter::Options &opt)
{
  Import im;
  vpSelfCalibImporter::Report &rep = im.res.report;
  rep.layout = vpSelfCalibImporter::VISP_HAND_EYE;
  rep.source = absolutePath(dir);
  std::vector<fs::path> files;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_regular_file(ec))
      files.push_back(it->path());
  if (ec)
    throw vpSelfCalibException(vpSelfCalibException::ioError,
                               "importer " + inQuotes(rep.source) + ": cannot list the folder: " + ec.message());
  std::sort(files.begin(), files.end());

  const std::regex pose_re("(.+)_pose_(rPe|fPe)_([0-9]+)\\.yaml");
  const std::regex image_re("(.+)_image-([0-9]+)\\.(png|jpe?g|pgm|ppm|bmp|tiff?)", std::regex::icase);
  const std::regex board_pose_re("(.+)_pose_cPo_([0-9]+)\\.yaml");
  std::vector<std::pair<std::string, std::string>> series; // prefix, frame
  for (const fs::path &f : files) {
    std::smatch m;
    const std::string name = f.filename().string();
    if (std::regex_match(name, m, pose_re) &&
        std::find(series.begin(), series.end(), std::make_pair(m[1].str(), m[2].str())) == series.end())
      series.emplace_back(m[1].str(), m[2].str());
  }
  if (series.empty())
    throw vpSelfCalibException(vpSelfCalibException::ioError,
                               "importer " + inQuotes(rep.source) +
                                   ": no pose files (ViSP: <prefix>_pose_rPe_N.yaml or <prefix>_pose_fPe_N.yaml; "
                                   "industrial_calibration: cal_data.yaml)");
  if (series.size() > 1) {
    std::vector<std::string> list;
    for (const auto &s : series)
      list.push_back(s.first + "_pose_" + s.second + "_N.yaml");
    throw vpSelfCalibException(vpSelfCalibException::badValue, "importer " + inQuotes(rep.source) +
                                                                   ": several pose series (" + joined(list) +
                                                                   "): one folder per data set");
  }
  const std::string prefix = series[0].first, frame = series[0].second, pose_name = prefix + "_pose_" + frame;

  std::map<std::string, fs::path, NumberLess> poses, images;
  fs::path xml;
  std::vector<fs::path> xmls;
  for (const fs::path &f : files) {
    std::smatch m;
    const std::string name = f.filename().string();
    std::map<std::string, fs::path, NumberLess> *numbered = nullptr;
    std::string digits;
    if (std::regex_match(name, m, pose_re)) {
      numbered = &poses;
      digits = m[3].str();
    } else if (std::regex_match(name, m, image_re) && m[1].str() == prefix) {
      numbered = &images;
      digits = m[2].str();
    } else if (f.extension() == ".xml")
      xmls.push_back(f);
    else if (name == "chessboard-data.txt") {
      im.input(f);
      rep.board = chessboardText(readTextFile(f.string(), "board description"), rep.board_option);
      if (rep.board.empty())
        im.unused(name, "not understood (expected 'C x R' and 'square size: S m')");
    } else if (name == "apriltag-data.txt")
      readTagDescription(im, f);
    else if (std::regex_match(name, m, board_pose_re))
      im.unused(name, "a board pose (ViSP's chessboard pose step): the front end finds its own correspondences");
    else
      im.unused(name, std::regex_match(name, m, image_re) ? "an image of another prefix than " + prefix
                                                          : "not part of ViSP's hand-eye layout");
    if (numbered && !numbered->emplace(canonicalNumber(digits), f).second)
      im.unused(name, "the same number as " + numbered->at(canonicalNumber(digits)).filename().string());
  }
  rep.num_pose_files = static_cast<unsigned int>(poses.size());
  rep.num_images = static_cast<unsigned int>(images.size());

  for (const fs::path &x : xmls)
    if (x.filename() == prefix + "_camera.xml")
      xml = x;
  if (xml.empty() && xmls.size() == 1)
    xml = xmls[0];
  if (xml.empty()) {
    std::vector<std::string> list;
    for (const fs::path &x : xmls)
      list.push_back(x.filename().string());
    throw vpSelfCalibException(vpSelfCalibException::ioError,
                               "importer " + inQuotes(rep.source) +
                                   (xmls.empty() ? ": no camera XML (vpXmlParserCamera)"
                                                 : ": several XML files (" + joined(list) + "), none named " + prefix +
                                                       "_camera.xml: which is the camera?"));
  }
  for (const fs::path &x : xmls)
    if (x != xml)
      im.unused(x.filename().string(), "another XML file than the camera's " + xml.filename().string());
  readVispCamera(im, xml, opt.intrinsics);

  // Paired by N, in numerical order; a pose or an image alone is left out.
  std::map<std::string, bool, NumberLess> numbers;
  for (const auto &p : poses)
    numbers[p.first] = true;
  for (const auto &i : images)
    numbers[i.first] = true;
  for (const auto &n : numbers) {
    const auto p = poses.find(n.first), i = images.find(n.first);
    if (p == poses.end())
      im.unused(i->second.filename().string(), "no pose file " + pose_name + "_" + n.first + ".yaml");
    else if (i == images.end())
      im.unused(p->second.filename().string(), "no image " + prefix + "_image-" + n.first + ".*");
    else
      im.addView(p->second, i->second, i->second.filename().string());
  }
  im.finish(opt, prefix.compare(0, 6, "franka") == 0 ? "panda" : "",
            " (pairs " + pose_name + "_N.yaml, " + prefix + "_image-N.*)");
  rep.pose_format =
      frame + " (" + (frame == "rPe" ? "robot base" : "reference frame") + " to flange): " + rep.pose_format;
  return im.res;
}

// ---------------------------------------------------------------------------------------------
// industrial_calibration's cal_data.yaml

std::string targetFinderText(const Reader &r, const YAML::Node &t, std::string &board_option)
{
  if (!t.IsMap())
    r.fail("target_finder", "expected a map {type, rows, cols, spacing}, got " + Reader::show(t));
  const std::string type = r.text(t["type"], "target_finder.type");
  const double rows = r.number(t["rows"], "target_finder.rows"), cols = r.number(t["cols"], "target_finder.cols");
  const double spacing = r.number(t["spacing"], "target_finder.spacing");
  std::ostringstream os;
  os << type << ", " << rows << " x " << cols << ", spacing " << spacing << " m (cal_data.yaml target_finder)";
  // The circle grids calibrate --board reads (industrial_calibration's names for them).
  const std::string board = type == "ModifiedCircleGridTargetFinder" ? "modified-circles"
                            : type == "CircleGridTargetFinder"       ? "circles"
                                                                     : "";
  if (!board.empty() && rows >= 1 && cols >= 1 && rows == std::floor(rows) && cols == std::floor(cols) && spacing > 0) {
    std::ostringstream opt;
    opt << board << ":" << rows << "x" << cols << ":" << spacing;
    board_option = opt.str();
  }
  return os.str();
}

vpSelfCalibImporter::Result importCalData(const fs::path &file, const vpSelfCalibImporter::Options &opt)
{
  Import im;
  vpSelfCalibImporter::Report &rep = im.res.report;
  rep.layout = vpSelfCalibImporter::INDUSTRIAL_CALIBRATION;
  rep.source = absolutePath(file);
  const std::string source = inQuotes(file.string());
  const fs::path dir = file.parent_path();
  im.input(file);
  const Reader r(kCalData, source);
  parseYaml(kCalData, source, [&] {
    const YAML::Node root = loadYamlRoot(readTextFile(file.string(), kCalData), kCalData, source);
    if (!root.IsMap() || !root["data"])
      throw vpSelfCalibException(vpSelfCalibException::parseError,
                                 std::string(kCalData) + " " + source +
                                     ": expected a map with data: [{pose, image}, ...] (industrial_calibration)");
    if (root["static_camera"]) {
      bool static_camera = false;
      if (!YAML::convert<bool>::decode(root["static_camera"], static_camera))
        r.fail("static_camera", "expected true or false, got " + Reader::show(root["static_camera"]));
      if (static_camera)
        r.fail("static_camera", "true: the camera is not on the robot; the self-calibration needs a wrist camera");
    }

    const YAML::Node in = root["intrinsics"];
    if (!in.IsDefined() || !in.IsMap())
      r.fail("intrinsics", "expected a map {fx, fy, cx, cy}, got " + Reader::show(in));
    r.onlyKeys(in, {"fx", "fy", "cx", "cy"}, "intrinsics");
    const double fx = r.number(in["fx"], "intrinsics.fx"), fy = r.number(in["fy"], "intrinsics.fy");
    if (!(fx > 0 && fy > 0))
      r.fail("intrinsics", "fx and fy must be positive");
    im.res.dataset.cam.initPersProjWithoutDistortion(fx, fy, r.number(in["cx"], "intrinsics.cx"),
                                                     r.number(in["cy"], "intrinsics.cy"));

    if (root["camera_mount_to_camera_guess"]) {
      im.eMc_guess = vpPoseVector(
          poseFromNode(root["camera_mount_to_camera_guess"], source + " key 'camera_mount_to_camera_guess'").M);
      im.has_eMc_guess = true;
      im.eMc_guess_source = "camera_mount_to_camera_guess";
    }
    if (root["target_finder"]) {
      try {
        rep.board = targetFinderText(r, root["target_finder"], rep.board_option);
      } catch (const vpSelfCalibException &e) {
        im.unused("target_finder", "not understood: " + e.getStringMessage());
      }
    }
    std::vector<std::string> others;
    for (const auto &kv : root) {
      const std::string k = r.keyName(kv.first, "");
      if (k != "data" && k != "intrinsics" && k != "camera_mount_to_camera_guess" && k != "target_finder" &&
          k != "static_camera")
        others.push_back(k);
    }
    if (!others.empty())
      im.unused("keys " + joined(others), "industrial_calibration's solver settings and target guess: not needed here");

    const YAML::Node data = root["data"];
    if (!data.IsSequence() || data.size() == 0)
      r.fail("data", "expected a non-empty list of {pose, image}, got " + Reader::show(data));
    for (size_t k = 0; k < data.size(); ++k) {
      const std::string key = "data[" + std::to_string(k) + "]";
      if (!data[k].IsMap())
        r.fail(key, "expected a map {pose, image}, got " + Reader::show(data[k]));
      r.onlyKeys(data[k], {"pose", "image"}, key);
      const std::string pose = r.text(data[k]["pose"], key + ".pose"), image = r.text(data[k]["image"], key + ".image");
      const fs::path pose_file = dir / pose, image_file = dir / image;
      const bool has_pose = fs::is_regular_file(pose_file), has_image = fs::is_regular_file(image_file);
      rep.num_pose_files += has_pose;
      rep.num_images += has_image;
      const std::string what = key + " (" + pose + ", " + image + ")";
      if (!has_pose)
        im.unused(what, "no pose file " + pose);
      else if (!has_image)
        im.unused(what, "no image " + image);
      else
        im.addView(pose_file, image_file, what);
    }
  });
  std::ostringstream os;
  os << std::setprecision(6) << "cal_data.yaml intrinsics: fx " << im.res.dataset.cam.get_px() << ", fy "
     << im.res.dataset.cam.get_py() << ", cx " << im.res.dataset.cam.get_u0() << ", cy " << im.res.dataset.cam.get_v0()
     << ", " << im.res.dataset.width << " x " << im.res.dataset.height << " (the images)";
  rep.camera = os.str();
  im.takeIntrinsics(opt.intrinsics == vpSelfCalibImporter::INTRINSICS_KNOWN, "intrinsics");
  im.finish(opt, "", " in the data list");
  return im.res;
}
} // namespace

const char *vpSelfCalibImporter::layoutName(Layout layout)
{
  return layout == VISP_HAND_EYE ? "ViSP hand-eye folder" : "industrial_calibration cal_data.yaml";
}

vpSelfCalibImporter::Result vpSelfCalibImporter::import(const std::string &path, const Options &options)
{
  if (options.intrinsics != INTRINSICS_DEFAULT && options.intrinsics != INTRINSICS_KNOWN &&
      options.intrinsics != INTRINSICS_GUESS)
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpSelfCalibImporter: unknown Options::intrinsics");
  std::error_code ec;
  if (path.empty() || !fs::exists(path, ec))
    throw vpSelfCalibException(vpSelfCalibException::ioError,
                               "importer " + inQuotes(path) + ": no such file or folder");
  // A FIFO (or a device, a socket) is no data folder and no cal_data.yaml: opening a FIFO that no
  // program writes to would wait for ever.
  if (!fs::is_directory(path, ec) && !fs::is_regular_file(path, ec))
    throw vpSelfCalibException(vpSelfCalibException::ioError,
                               "importer " + inQuotes(path) + ": neither a folder nor a regular file (a FIFO, a "
                               "device or a socket): give a ViSP hand-eye folder or industrial_calibration's "
                               "cal_data.yaml");
  Result res;
  if (fs::is_directory(path, ec) && !fs::is_regular_file(fs::path(path) / "cal_data.yaml", ec))
    res = importVisp(path, options);
  else
    res = importCalData(fs::is_directory(path, ec) ? (fs::path(path) / "cal_data.yaml").string() : path, options);
  // Controller poses are not exact: a serial arm's absolute pose accuracy is of the order of
  // millimetres (the Franka set's poses fit one eMc to about 3 mm / 3 mrad, industrial_calibration's
  // to 8 mm / 20 mrad). The calibration weighs this prior with the pixels and widens its sd by
  // sigma0 when the residuals say the error is larger.
  res.dataset.pose_sd_translation = kDefaultPoseSdTranslation;
  res.dataset.pose_sd_rotation = kDefaultPoseSdRotation;
  res.report.robot_error = "controller poses' error taken as " + fmt(1e3 * kDefaultPoseSdTranslation) + " mm / " +
                           fmt(1e3 * kDefaultPoseSdRotation) +
                           " mrad sd (robot_error in the dataset: edit it, or calibrate --pose-sd; the sd are "
                           "widened by sigma0 when the residuals say more)";
  return res;
}

vpSelfCalibImporter::Result vpSelfCalibImporter::import(const std::string &path) { return import(path, Options()); }

std::string vpSelfCalibImporter::robotModelFileFor(const std::string &dataset_file)
{
  const fs::path p(dataset_file);
  return (p.parent_path() / (p.stem().string() + "-robot.yaml")).string();
}

void vpSelfCalibImporter::Result::save(const std::string &dataset_file) const
{
  // Absolute, so that the writer finds the paths under the dataset's directory and writes them relative.
  const std::string out = absolutePath(dataset_file);
  vpSelfCalibDataset ds = dataset;
  if (!has_robot_model) {
    ds.saveYaml(out);
    return;
  }
  // The pair: the robot model first, then the dataset that names it, so that a dataset is never
  // there without its model. A dataset that cannot be written takes the new model back (the
  // earlier one, or none), so that a failed import leaves the files as they were.
  // A model that changes (a --force import of other data): the earlier dataset is taken away first,
  // so that a kill between the two writes leaves the new model alone (import again), never the
  // earlier dataset paired with the new model.
  ds.robot = robotModelFileFor(out);
  std::error_code ec;
  const bool had_model = fs::is_regular_file(ds.robot, ec);
  const std::string earlier_model =
      had_model ? vpSelfCalib::readTextFileBounded(ds.robot, "robot model", size_t(1) << 24) : std::string();
  const bool had_dataset = had_model && earlier_model != robot_model.toYamlString() && fs::is_regular_file(out, ec);
  const std::string earlier_dataset =
      had_dataset ? vpSelfCalib::readTextFileBounded(out, "dataset", size_t(1) << 28) : std::string();
  if (had_dataset && !fs::remove(out, ec))
    throw vpSelfCalibException(vpSelfCalibException::ioError,
                               "dataset '" + out + "': cannot replace it: " + ec.message());
  try {
    robot_model.saveYaml(ds.robot);
    ds.saveYaml(out);
  } catch (...) {
    try {
      if (had_model)
        vpSelfCalib::writeFileAtomically(ds.robot, earlier_model, "robot model");
      else
        fs::remove(ds.robot, ec);
      if (had_dataset)
        vpSelfCalib::writeFileAtomically(out, earlier_dataset, "dataset");
    } catch (const vpException &) {
      // the dataset's error is the one to report
    }
    throw;
  }
}

vpHomogeneousMatrix vpSelfCalibImporter::readPose(const std::string &filename) { return readPoseFile(filename).M; }

vpHomogeneousMatrix vpSelfCalibImporter::poseFromYamlString(const std::string &yaml, const std::string &source)
{
  return parseYaml(kPoseFile, source, [&] { return poseFromNode(loadYamlRoot(yaml, kPoseFile, source), source).M; });
}
