/*
 * visp-selfcalib info: a robot model's summary and its error-model parameters that are not zero.
 */
#include "commands.h"

#include <iomanip>
#include <iostream>

#include <visp3/selfcalib/vpKinematicChain.h>

void addInfo(CLI::App &app, ModelArgs &a)
{
  CLI::App *c = app.add_subcommand("info", "robot model summary and error-model parameters");
  c->footer("Prints the robot model: convention, joints, number of error-model parameters, the corrections\n"
            "that are not zero.");
  c->add_option("MODEL", a.model, modelHelp())->type_name("NAME|FILE")->required();
}

int info(const ModelArgs &a)
{
  const vpKinematicChain c = vpKinematicChain::fromPresetOrFile(a.model);
  std::cout << "name: " << c.getName() << "\nconvention: " << (c.getConvention() == vpKinematicChain::DH ? "dh" : "mdh")
            << "\njoints: " << c.getNumJoints() << "\nerror-model parameters: " << c.getNumParameters() << "\n";
  const std::vector<std::string> names = c.getParameterNames();
  for (unsigned int i = 0; i < names.size(); ++i)
    if (c.getParameters()[i] != 0)
      std::cout << "  " << names[i] << " = " << std::setprecision(17) << c.getParameters()[i] << "\n";
  return 0;
}
