/*
 * visp-selfcalib predict: the camera pose fMc of a model for each joint vector read.
 */
#include "commands.h"

#include <fstream>
#include <iomanip>
#include <iostream>

#include <visp3/core/vpPoseVector.h>
#include <visp3/selfcalib/vpKinematicChain.h>

namespace
{
int predictFrom(const vpKinematicChain &c, const std::vector<vpColVector> &qs, const std::string &source)
{
  std::cout << std::setprecision(17);
  for (const vpColVector &q : qs) {
    if (!c.isInJointLimits(q))
      std::cerr << source << ": warning: joints outside the model's limits\n";
    const vpPoseVector p(c.get_fMc(q));
    for (unsigned int k = 0; k < 6; ++k)
      std::cout << p[k] << (k < 5 ? " " : "\n");
  }
  return 0;
}
} // namespace

void addPredict(CLI::App &app, ModelArgs &a)
{
  CLI::App *c = app.add_subcommand("predict", "fMc for each joint vector (one per line, rad)");
  c->footer("Reads one joint vector per line (rad, separated by spaces or commas; '#' starts a comment) from\n"
            "JOINTS_FILE or standard input and prints the camera pose fMc as 'tx ty tz tux tuy tuz' (m, rad)\n"
            "per line.");
  c->add_option("MODEL", a.model, modelHelp())->type_name("NAME|FILE")->required();
  c->add_option("JOINTS_FILE", a.second, "joint vectors (default: standard input)")->type_name("FILE");
}

int predict(const ModelArgs &a)
{
  const vpKinematicChain chain = readModelArgument(a.model);
  if (chain.isCameraInWorld()) {
    std::cerr << "error: " << a.model << ": the camera is fixed in the world (camera_mount: world): its pose is the "
              << "model's bMc whatever the joints; predict gives the pose of a camera on the end-effector\n";
    return 1;
  }
  const std::string source = a.second.empty() ? "<stdin>" : a.second;
  const std::vector<vpColVector> qs = readJoints(a.second, "joints file", chain.getNumJoints());
  if (qs.empty()) {
    std::cerr << "error: " << source << ": no joint vector (one per line, " << chain.getNumJoints()
              << " values in rad): nothing to predict\n";
    return 1;
  }
  return predictFrom(chain, qs, source);
}
