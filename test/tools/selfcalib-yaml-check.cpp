/*!
  \file selfcalib-yaml-check.cpp
  \brief Checks keys of a YAML file (results.yaml, a dataset, an exported model) for the integration
  tests, so that they assert on the parsed file rather than on numbers printed on stdout.

  Usage: selfcalib-yaml-check FILE CHECK [CHECK ...], each CHECK one of
    PATH exists          the key is there
    PATH missing         the key is not there
    PATH eq VALUE        the scalar equals VALUE (as numbers when both are numbers, else as text)
    PATH range LO HI     the scalar is a finite number from LO to HI (both included)
    PATH size N          the sequence or map has N entries
  PATH is a dotted key path (`cross_validation.rms_px.calibrated.mean`); a number indexes a sequence
  (`eMc.pose.0`); a map key that holds dots (`j1.tx`) is found as well. FILE `-` reads stdin.
  Every check is made; each failure is one line on stdout naming the file, the key, the value and
  what was expected. Exit 0 and "yaml-check ok: FILE (N checks)" when all pass, 1 when one fails,
  2 on a usage error or a file that cannot be read.
*/
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace
{
//! The dot-separated components of a key path.
std::vector<std::string> splitPath(const std::string &path)
{
  std::vector<std::string> parts;
  std::string part;
  std::istringstream is(path);
  while (std::getline(is, part, '.'))
    parts.push_back(part);
  return parts;
}

//! A number from the whole of text, or false.
bool toNumber(const std::string &text, double &value)
{
  if (text.empty())
    return false;
  const char *begin = text.c_str();
  char *end = nullptr;
  value = std::strtod(begin, &end);
  return end == begin + text.size();
}

//! The node at parts[i..] below node (an undefined node when absent). A map key may itself hold
//! dots: the longest run of components that names a key is taken first.
YAML::Node find(const YAML::Node &node, const std::vector<std::string> &parts, size_t i)
{
  if (i == parts.size())
    return node;
  if (node.IsSequence()) {
    double index;
    if (!toNumber(parts[i], index) || index < 0 || index >= node.size() || index != std::floor(index))
      return YAML::Node(YAML::NodeType::Undefined);
    return find(node[static_cast<size_t>(index)], parts, i + 1);
  }
  if (!node.IsMap())
    return YAML::Node(YAML::NodeType::Undefined);
  for (size_t j = parts.size(); j > i; --j) {
    std::string key = parts[i];
    for (size_t k = i + 1; k < j; ++k)
      key += "." + parts[k];
    const YAML::Node child = node[key];
    if (child.IsDefined()) {
      const YAML::Node found = find(child, parts, j);
      if (found.IsDefined())
        return found;
    }
  }
  return YAML::Node(YAML::NodeType::Undefined);
}

//! A node as one line of text, for the messages.
std::string show(const YAML::Node &node)
{
  if (!node.IsDefined())
    return "(absent)";
  if (node.IsMap())
    return "a map of " + std::to_string(node.size()) + " entries";
  if (node.IsSequence())
    return "a sequence of " + std::to_string(node.size()) + " entries";
  YAML::Emitter out;
  out << YAML::Flow << node;
  return out.c_str();
}

int usage(const std::string &why)
{
  std::cerr << "selfcalib-yaml-check: " << why << "\n"
            << "usage: selfcalib-yaml-check FILE PATH exists|missing|eq VALUE|range LO HI|size N ...\n";
  return 2;
}
} // namespace

int main(int argc, char **argv)
{
  if (argc < 4)
    return usage("give a file and at least one check");
  const std::string file = argv[1];
  YAML::Node root;
  try {
    if (file == "-")
      root = YAML::Load(std::cin);
    else
      root = YAML::LoadFile(file);
  }
  catch (const YAML::Exception &e) {
    std::cerr << "selfcalib-yaml-check: " << file << ": " << e.what() << "\n";
    return 2;
  }

  int failed = 0, checks = 0;
  for (int a = 2; a < argc;) {
    const std::string path = argv[a];
    if (a + 1 >= argc)
      return usage("'" + path + "': no operation");
    const std::string op = argv[a + 1];
    const int args = op == "eq" || op == "size" ? 1 : op == "range" ? 2 : op == "exists" || op == "missing" ? 0 : -1;
    if (args < 0)
      return usage("'" + op + "': unknown operation");
    if (a + 2 + args > argc)
      return usage("'" + path + " " + op + "': expects " + std::to_string(args) + " value(s)");
    const YAML::Node node = find(root, splitPath(path), 0);
    std::string expected;
    bool ok = false;
    if (op == "exists") {
      ok = node.IsDefined();
      expected = "present";
    }
    else if (op == "missing") {
      ok = !node.IsDefined();
      expected = "absent";
    }
    else if (op == "size") {
      double n;
      if (!toNumber(argv[a + 2], n))
        return usage("size: '" + std::string(argv[a + 2]) + "' is not a number");
      ok = node.IsDefined() && (node.IsSequence() || node.IsMap()) && node.size() == n;
      expected = std::string(argv[a + 2]) + " entries" + (node.IsDefined() ? " (it has " + std::to_string(node.size()) + ")" : "");
    }
    else {
      const bool scalar = node.IsDefined() && node.IsScalar();
      double value = 0, lo = 0, hi = 0;
      const bool number = scalar && toNumber(node.Scalar(), value);
      if (op == "eq") {
        double want;
        ok = scalar && (number && toNumber(argv[a + 2], want) ? value == want : node.Scalar() == argv[a + 2]);
        expected = std::string("equal to ") + argv[a + 2];
      }
      else {
        if (!toNumber(argv[a + 2], lo) || !toNumber(argv[a + 3], hi))
          return usage("range: '" + std::string(argv[a + 2]) + " " + argv[a + 3] + "' are not two numbers");
        ok = number && std::isfinite(value) && value >= lo && value <= hi;
        expected = std::string("a number from ") + argv[a + 2] + " to " + argv[a + 3];
      }
    }
    ++checks;
    if (!ok) {
      ++failed;
      std::cout << "yaml-check FAILED: " << file << ": " << path << " = " << show(node) << ", expected " << expected
                << "\n";
    }
    a += 2 + args;
  }
  if (failed) {
    std::cout << "yaml-check: " << file << ": " << failed << " of " << checks << " checks failed\n";
    return 1;
  }
  std::cout << "yaml-check ok: " << file << " (" << checks << " checks)\n";
  return 0;
}
