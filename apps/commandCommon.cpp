/*
 * visp-selfcalib: what the commands share (see commands.h).
 */
#include "commands.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>

#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibResultsFile.h>
#include <visp3/selfcalib/vpSelfCalibTextFile.h>

namespace fs = std::filesystem;

const char *const kProgram = "visp-selfcalib";
std::string presetList()
{
  std::string list;
  for (const std::string &p : vpKinematicChain::presetNames())
    list += (list.empty() ? "" : ", ") + p;
  return list;
}

std::string modelHelp() { return "a preset (" + presetList() + "), a robot-model YAML or a URDF file"; }

vpKinematicChain readModelArgument(const std::string &model)
{
  vpKinematicChain chain = vpKinematicChain::fromPresetOrFile(model);
  std::error_code ec;
  const fs::path file(model);
  if (chain.isCameraInWorld() || !fs::is_regular_file(file, ec) || file.extension() == ".urdf")
    return chain;
  const fs::path results = file.parent_path() / "results.yaml";
  if (!fs::is_regular_file(results, ec))
    return chain;
  bool eye_to_hand = false;
  try {
    eye_to_hand = vpSelfCalibResultsFile::read(results.string()).bMc.has_value();
  } catch (const vpSelfCalibException &) {
    return chain; // a results.yaml that does not read says nothing about this model
  }
  if (eye_to_hand)
    throw vpSelfCalibException(
        vpSelfCalibException::badValue,
        model + ": an eye-to-hand model file of the older form: its eMc holds the camera in the world (" +
            results.string() + " beside it has bMc), and the file does not say camera_mount: world. Rename its key "
            "'eMc:' to 'bMc:' and add the line 'camera_mount: world' (sed -i 's/^eMc:/camera_mount: world\\nbMc:/' " +
            model + "), or run calibrate again");
  return chain;
}

namespace
{
constexpr size_t kMaxJointsLineBytes = size_t(1) << 16; //!< a line of joint values (64 joints take 2 kB)
constexpr size_t kMaxJointVectors = 100000;            //!< joint vectors in a file, as poses in a dataset
constexpr double kMaxJointValue = 1000;                //!< rad, as in a dataset

//! One line of `in`, at most kMaxJointsLineBytes counted while reading (an input without end, such
//! as /dev/zero, is refused at once); false at the end of the input.
bool boundedLine(std::istream &in, const std::string &source, unsigned int lineno, std::string &line)
{
  line.clear();
  std::streambuf *buf = in.rdbuf();
  for (;;) {
    const int c = buf->sbumpc();
    if (c == std::char_traits<char>::eof())
      return !line.empty();
    if (c == '\n')
      return true;
    if (c == '\0') // <stdin> (a file is read by vpSelfCalibTextFile, which says the same)
      throw vpSelfCalibException(vpSelfCalibException::parseError,
                                 source + ": a NUL byte on line " + std::to_string(lineno) +
                                     ": not a text file of joint vectors (one per line, rad)");
    if (line.size() == kMaxJointsLineBytes)
      throw vpSelfCalibException(vpSelfCalibException::ioError,
                                 source + ":" + std::to_string(lineno) + ": a line longer than " +
                                     std::to_string(kMaxJointsLineBytes) +
                                     " bytes: not a file of joint vectors (one per line, rad)");
    line.push_back(static_cast<char>(c));
  }
}

std::vector<vpColVector> readJointLines(std::istream &in, const std::string &source, unsigned int n)
{
  std::vector<vpColVector> out;
  std::string line;
  for (unsigned int lineno = 1; boundedLine(in, source, lineno, line); ++lineno) {
    const std::string where = source + ":" + std::to_string(lineno) + ": ";
    const size_t hash = line.find('#');
    if (hash != std::string::npos)
      line.resize(hash);
    for (char &ch : line)
      if (ch == ',')
        ch = ' ';
    std::istringstream ls(line);
    std::vector<double> v;
    std::string tok;
    while (ls >> tok) {
      size_t used = 0;
      double x = 0;
      try {
        x = std::stod(tok, &used);
      } catch (const std::exception &) {
        used = 0;
      }
      if (used != tok.size() || !std::isfinite(x))
        throw vpSelfCalibException(vpSelfCalibException::badValue, where + "'" + tok + "' is not a number");
      if (std::abs(x) > kMaxJointValue)
        throw vpSelfCalibException(vpSelfCalibException::badValue,
                                   where + "expected a joint value from -1000 to 1000 rad, got '" + tok + "'");
      v.push_back(x);
    }
    if (v.empty())
      continue;
    if (v.size() != n)
      throw vpSelfCalibException(vpSelfCalibException::dimensionError, where + "expected " + std::to_string(n) +
                                                                           " joint values, got " +
                                                                           std::to_string(v.size()));
    if (out.size() == kMaxJointVectors)
      throw vpSelfCalibException(vpSelfCalibException::badValue, where + "more than " +
                                                                     std::to_string(kMaxJointVectors) +
                                                                     " joint vectors: at most that many are read");
    out.push_back(vpColVector(v));
  }
  return out;
}
} // namespace

std::vector<vpColVector> readJoints(const std::string &file, const std::string &what, unsigned int n)
{
  if (file.empty() || file == "-")
    return readJointLines(std::cin, "<stdin>", n);
  // Read whole and bounded first, as the module reads its files (vpSelfCalibTextFile): a FIFO no
  // program writes to is refused instead of blocking the open for ever, a device without end stops
  // at the bound, a NUL byte is named with its line.
  std::istringstream in(vpSelfCalibTextFile::read(file, what, size_t(64) << 20));
  return readJointLines(in, file, n);
}

std::string canonical(const std::string &p)
{
  std::error_code ec;
  const fs::path c = fs::canonical(p, ec);
  return ec ? std::string() : c.string();
}

namespace
{
std::string specialKind(fs::file_type t)
{
  switch (t) {
  case fs::file_type::character:
    return "a character device";
  case fs::file_type::block:
    return "a block device";
  case fs::file_type::fifo:
    return "a FIFO";
  case fs::file_type::socket:
    return "a socket";
  default:
    return "";
  }
}
} // namespace

bool controllerPosesOnly(const vpSelfCalibDataset &ds)
{
  return std::all_of(ds.views.begin(), ds.views.end(),
                     [](const vpSelfCalibDataset::View &v) { return v.has_fMe && v.q.size() == 0; });
}

bool sameView(const vpSelfCalibDataset::View &a, const vpSelfCalibDataset::View &b)
{
  if (!a.image.empty() && !b.image.empty() && !canonical(a.image).empty() && canonical(a.image) == canonical(b.image))
    return true;
  if (a.q.size() != 0 && a.q.size() == b.q.size()) {
    for (unsigned int j = 0; j < a.q.size(); ++j)
      if (std::abs(a.q[j] - b.q[j]) > 1e-12)
        return false;
    return true;
  }
  if (a.has_fMe && b.has_fMe) {
    for (unsigned int r = 0; r < 3; ++r)
      for (unsigned int c = 0; c < 4; ++c)
        if (std::abs(a.fMe[r][c] - b.fMe[r][c]) > 1e-12)
          return false;
    return true;
  }
  return false;
}

bool outputRefused(const std::string &out, bool force)
{
  if (out.empty()) {
    std::cerr << "error: the output path is empty: give a file name\n";
    return true;
  }
  std::error_code ec;
  std::string kind = specialKind(fs::symlink_status(out, ec).type());
  if (kind.empty())
    kind = specialKind(fs::status(out, ec).type());
  if (!kind.empty()) {
    std::cerr << "error: '" << out << "' is " << kind
              << ", not a regular file: outputs are written only as regular files (and directories); choose "
                 "another path\n";
    return true;
  }
  // These outputs are single files: a directory at the path is no earlier output, --force or not.
  if (fs::is_directory(out, ec)) {
    std::cerr << "error: '" << out << "' is a directory: the output is a file; give a file's path (e.g. '"
              << (fs::path(out) / fs::path(out).filename()).string() << "')\n";
    return true;
  }
  if (!force && !canonical(out).empty()) {
    std::cerr << "error: '" << out << "' exists; use --force to replace it\n";
    return true;
  }
  // A symbolic link whose target does not exist is not written through: the file replaces the link.
  if (!force && fs::is_symlink(fs::symlink_status(out, ec))) {
    std::cerr << "error: '" << out << "' is a symbolic link to '" << fs::read_symlink(out, ec).string()
              << "', which does not exist: the file written replaces the link, not its target; use --force to "
                 "replace the link, or give the target's path\n";
    return true;
  }
  return false;
}

bool makeDirectory(const fs::path &dir)
{
  std::error_code ec;
  return fs::is_directory(dir, ec) || fs::create_directory(dir, ec);
}

std::vector<std::string> focalNames(std::initializer_list<vpRobotSelfCalibration::FocalMode> modes)
{
  std::vector<std::string> names;
  for (vpRobotSelfCalibration::FocalMode m : modes)
    names.push_back(vpRobotSelfCalibration::focalModeName(m));
  return names;
}

CLI::Option *addRobotOption(CLI::App &app, std::string &robot)
{
  return app.add_option("--robot", robot, "the robot: viper850 (default), another preset, or a robot-model YAML or URDF file")
      ->type_name("NAME")
      ->check(CLI::IsMember(vpKinematicChain::presetNames()) | CLI::ExistingFile);
}
