/*
 * visp-selfcalib: command-line tool of ViSP SelfCalib.
 *
 *   visp-selfcalib info    MODEL                 robot model summary and error-model parameters
 *   visp-selfcalib predict MODEL [JOINTS_FILE]   fMc for each joint vector (one per line, rad;
 *                                                from the file or standard input), printed as
 *                                                one pose vector per line: tx ty tz tux tuy tuz
 * MODEL is a preset name (puma560, viper850) or a robot-model YAML file.
 * Exit codes: 0 success, 1 bad input (message on stderr), 2 bad usage.
 */
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>

#include <visp3/core/vpPoseVector.h>
#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

namespace
{
int usage(std::ostream &os, int code)
{
  os << "Usage:\n"
     << "  visp-selfcalib info    MODEL\n"
     << "  visp-selfcalib predict MODEL [JOINTS_FILE]\n"
     << "MODEL: a preset (puma560, viper850) or a robot-model YAML file.\n"
     << "predict reads one joint vector per line (rad, separated by spaces or commas; '#' starts a comment)\n"
     << "from JOINTS_FILE or standard input and prints fMc as 'tx ty tz tux tuy tuz' (m, rad) per line.\n";
  return code;
}

int info(const vpKinematicChain &c)
{
  std::cout << "name: " << c.getName() << "\nconvention: " << (c.getConvention() == vpKinematicChain::DH ? "dh" : "mdh")
            << "\njoints: " << c.getNumJoints() << "\nerror-model parameters: " << c.getNumParameters() << "\n";
  const std::vector<std::string> names = c.getParameterNames();
  for (unsigned int i = 0; i < names.size(); ++i)
    if (c.getParameters()[i] != 0)
      std::cout << "  " << names[i] << " = " << std::setprecision(17) << c.getParameters()[i] << "\n";
  return 0;
}

int predict(const vpKinematicChain &c, std::istream &in, const std::string &source)
{
  std::string line;
  unsigned int lineno = 0;
  std::cout << std::setprecision(17);
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
        if (used != tok.size())
          throw std::invalid_argument(tok);
      } catch (const std::exception &) {
        std::cerr << source << ":" << lineno << ": '" << tok << "' is not a number\n";
        return 1;
      }
    }
    if (v.empty())
      continue;
    if (v.size() != c.getNumJoints()) {
      std::cerr << source << ":" << lineno << ": expected " << c.getNumJoints() << " joint values, got " << v.size()
                << "\n";
      return 1;
    }
    const vpColVector q(v);
    if (!c.isInJointLimits(q))
      std::cerr << source << ":" << lineno << ": warning: joints outside the model's limits\n";
    const vpPoseVector p(c.get_fMc(q));
    for (unsigned int k = 0; k < 6; ++k)
      std::cout << p[k] << (k < 5 ? " " : "\n");
  }
  return 0;
}
} // namespace

int main(int argc, char **argv)
{
  if (argc < 2)
    return usage(std::cerr, 2);
  const std::string cmd = argv[1];
  if (cmd == "-h" || cmd == "--help" || cmd == "help")
    return usage(std::cout, 0);
  if ((cmd != "info" && cmd != "predict") || argc < 3 || (cmd == "info" && argc != 3) || argc > 4 ||
      std::string(argv[2]) == "--help")
    return usage(std::cerr, 2);
  try {
    const vpKinematicChain chain = vpKinematicChain::fromPresetOrFile(argv[2]);
    if (cmd == "info")
      return info(chain);
    if (argc == 4) {
      std::ifstream in(argv[3]);
      if (!in) {
        std::cerr << "error: cannot open joints file '" << argv[3] << "'\n";
        return 1;
      }
      return predict(chain, in, argv[3]);
    }
    return predict(chain, std::cin, "<stdin>");
  } catch (const vpException &e) {
    std::cerr << "error: " << e.getStringMessage() << "\n";
    return 1;
  }
}
