/*!
  \file selfcalib-yaml-check.cpp
  \brief Checks keys of a YAML file (results.yaml, a dataset, an exported model) for the integration
  tests, so that they assert on the parsed file rather than on numbers printed on stdout.

  Usage: selfcalib-yaml-check [--line REGEX] FILE CHECK [CHECK ...], each CHECK one of
    PATH exists          the key is there
    PATH missing         the key is not there
    PATH eq VALUE        the scalar equals VALUE (as numbers when both are numbers, else as text)
    PATH range LO HI     the scalar is a finite number from LO to HI (both included)
    PATH size N          the sequence or map has N entries
  PATH is a dotted key path (`cross_validation.rms_px.calibrated.mean`); a number indexes a sequence
  (`eMc.pose.0`); a map key that holds dots (`j1.tx`) is found as well. FILE `-` reads stdin.
  With --line, FILE is text (a command's output) and is not parsed: the first line REGEX (ECMAScript,
  searched in the line) matches is read, and its capture groups are the entries 0, 1, ... of the
  sequence the checks see. For the few figures a command prints and writes to no YAML file; no
  matching line is a failed check.
  Every check is made; each failure is one line on stdout naming the file, the key, the value and
  what was expected. Exit 0 and "yaml-check ok: FILE (N checks)" when all pass, 1 when one fails,
  2 on a usage error or a file that cannot be read.
*/
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <regex>
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
            << "usage: selfcalib-yaml-check [--line REGEX] FILE PATH exists|missing|eq VALUE|range LO HI|size N ...\n";
  return 2;
}

/*!
  The capture groups of the first line of `in` that `pattern` matches, as a YAML sequence of
  scalars; an undefined node when no line matches.
*/
YAML::Node lineCaptures(std::istream &in, const std::regex &pattern)
{
  std::string line;
  std::smatch m;
  while (std::getline(in, line))
    if (std::regex_search(line, m, pattern)) {
      YAML::Node captures(YAML::NodeType::Sequence);
      for (size_t g = 1; g < m.size(); ++g)
        captures.push_back(m[g].str());
      return captures;
    }
  return YAML::Node(YAML::NodeType::Undefined);
}

/*!
  The checked node of `file`: the parsed YAML, or with --line (`line` true) the captures of the
  first line `regex` matches. Returns 0, or the exit status: 1 when no line matches, 2 when the
  file cannot be read or parsed or the expression is not one.
*/
int load(const std::string &file, bool line, const std::string &regex, YAML::Node &root)
{
  if (!line) {
    try {
      root = file == "-" ? YAML::Load(std::cin) : YAML::LoadFile(file);
    }
    catch (const YAML::Exception &e) {
      std::cerr << "selfcalib-yaml-check: " << file << ": " << e.what() << "\n";
      return 2;
    }
    return 0;
  }
  std::regex pattern;
  try {
    pattern = std::regex(regex, std::regex::ECMAScript);
  }
  catch (const std::regex_error &e) {
    return usage("--line: '" + regex + "' is not a regular expression (" + e.what() + ")");
  }
  std::ifstream text;
  if (file != "-") {
    text.open(file);
    if (!text) {
      std::cerr << "selfcalib-yaml-check: " << file << ": cannot read\n";
      return 2;
    }
  }
  root = lineCaptures(file == "-" ? std::cin : text, pattern);
  if (!root.IsDefined()) {
    std::cout << "yaml-check FAILED: " << file << ": no line matches '" << regex << "'\n";
    return 1;
  }
  return 0;
}
} // namespace

int main(int argc, char **argv)
{
  const bool line = argc > 1 && std::string(argv[1]) == "--line";
  if (line && argc < 3)
    return usage("--line: give a regular expression");
  const int first = line ? 3 : 1; // the argument FILE is
  if (argc < first + 3)
    return usage("give a file and at least one check");
  const std::string file = argv[first];
  YAML::Node root;
  if (const int status = load(file, line, line ? argv[2] : "", root))
    return status;

  int failed = 0, checks = 0;
  for (int a = first + 1; a < argc;) {
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
