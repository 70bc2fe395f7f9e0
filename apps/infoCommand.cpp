/*
 * visp-selfcalib info: a robot model's summary and its error-model parameters that are not zero.
 */
#include "commands.h"

#include <algorithm>
#include <iomanip>
#include <iostream>

#include <visp3/selfcalib/vpKinematicChain.h>

void addInfo(CLI::App &app, ModelArgs &a)
{
  CLI::App *c = app.add_subcommand("info", "robot model summary and error-model parameters");
  c->footer("Prints the robot model: convention, joints, the base and flange frames, the hand-eye eMc (a\n"
            "preset's is a guess: the camera's mounting is not the robot's; calibrate measures it), the number\n"
            "of error-model parameters and the corrections that are not zero. Poses: tx ty tz (m), theta-u (rad).");
  c->add_option("MODEL", a.model, modelHelp())->type_name("NAME|FILE")->required();
}

int info(const ModelArgs &a)
{
  const vpKinematicChain c = vpKinematicChain::fromPresetOrFile(a.model);
  std::cout << "name: " << c.getName() << "\nconvention: " << (c.getConvention() == vpKinematicChain::DH ? "dh" : "mdh")
            << "\njoints: " << c.getNumJoints() << "\n";
  const auto pose = [](const char *name, const vpPoseVector &p, const char *note) {
    std::cout << name << ": [" << std::setprecision(6);
    for (unsigned int i = 0; i < 6; ++i)
      std::cout << (i ? ", " : "") << p[i];
    std::cout << "]" << note << "\n";
  };
  pose("base (fMb)", c.get_fMb_pose(), "");
  pose("flange (nMe)", c.get_nMe_pose(), "");
  const std::vector<std::string> presets = vpKinematicChain::presetNames();
  const bool preset = std::find(presets.begin(), presets.end(), a.model) != presets.end();
  pose("eMc", c.get_eMc_pose(), preset ? "  # a guess of the preset, not this camera's mounting: calibrate measures it" : "");
  std::cout << "error-model parameters: " << c.getNumParameters() << "\n";
  const std::vector<std::string> names = c.getParameterNames();
  for (unsigned int i = 0; i < names.size(); ++i)
    if (c.getParameters()[i] != 0)
      std::cout << "  " << names[i] << " = " << std::setprecision(17) << c.getParameters()[i] << "\n";
  return 0;
}
