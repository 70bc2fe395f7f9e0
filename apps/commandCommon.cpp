/*
 * visp-selfcalib: what the commands share (see commands.h).
 */
#include "commands.h"

#include <cmath>
#include <iostream>
#include <sstream>

#include <visp3/selfcalib/vpKinematicChain.h>

namespace fs = std::filesystem;

const char *const kProgram = "visp-selfcalib";
const char *const kModelHelp = "a preset (puma560, viper850, panda, ur5), a robot-model YAML or a URDF file";

bool readJoints(std::istream &in, const std::string &source, unsigned int n, std::vector<vpColVector> &out)
{
  std::string line;
  unsigned int lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
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
      try {
        size_t used = 0;
        v.push_back(std::stod(tok, &used));
        if (used != tok.size() || !std::isfinite(v.back()))
          throw std::invalid_argument(tok);
      } catch (const std::exception &) {
        std::cerr << source << ":" << lineno << ": '" << tok << "' is not a number\n";
        return false;
      }
    }
    if (v.empty())
      continue;
    if (v.size() != n) {
      std::cerr << source << ":" << lineno << ": expected " << n << " joint values, got " << v.size() << "\n";
      return false;
    }
    out.push_back(vpColVector(v));
  }
  return true;
}

std::string canonical(const std::string &p)
{
  std::error_code ec;
  const fs::path c = fs::canonical(p, ec);
  return ec ? std::string() : c.string();
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
