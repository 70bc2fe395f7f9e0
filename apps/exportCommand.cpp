/*
 * visp-selfcalib export: a model as URDF joint origins, or as a (modified) DH table without corrections.
 */
#include "commands.h"

#include <iostream>

#include <visp3/selfcalib/vpDHTableFit.h>
#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpModelExport.h>

void addExport(CLI::App &app, ExportArgs &a)
{
  CLI::App *c = app.add_subcommand("export", "URDF joint origins, or a corrected (modified) DH table");
  c->footer("Writes the model as URDF joint origins (exact), or as a DH / modified-DH robot-model file without\n"
            "corrections when one reproduces it (exit 3 when none does; a warning when it is ill-conditioned).");
  c->add_option("MODEL", a.model, modelHelp())->type_name("NAME|FILE")->required();
  CLI::Option_group *g = c->add_option_group("output", "the file to write");
  g->add_option("--urdf", a.urdf, "URDF joint origins")->type_name("OUT.urdf");
  g->add_option("--dh", a.dh, "a DH robot-model file")->type_name("OUT.yaml");
  g->add_option("--mdh", a.mdh, "a modified-DH robot-model file")->type_name("OUT.yaml");
  g->require_option(1);
  c->add_flag("--force", a.force, "replace an existing output file");
}

int exportModel(const ExportArgs &a)
{
  const std::string &model_name = a.model;
  const std::string &out = !a.urdf.empty() ? a.urdf : (!a.dh.empty() ? a.dh : a.mdh);
  const vpKinematicChain model = readModelArgument(model_name);
  if (!canonical(out).empty() && canonical(out) == canonical(model_name)) {
    std::cerr << "error: '" << out << "' is the input model\n";
    return 1;
  }
  if (outputRefused(out, a.force))
    return 1;
  if (!a.urdf.empty()) {
    // camera_mount: world: the hand-eye slot is bMc, the camera a link of the world (the target is
    // not in the model file: calibrate's own model.urdf has it, from results.yaml's eMo).
    const vpHomogeneousMatrix bMc = model.get_eMc_corrected();
    vpModelExport::saveURDF(model, out, model.isCameraInWorld() ? &bMc : nullptr, nullptr);
    std::cout << "wrote " << out << "\n";
    return 0;
  }
  const vpDHTableFit::Result fit =
      vpDHTableFit::fit(model, !a.dh.empty() ? vpKinematicChain::DH : vpKinematicChain::MDH);
  std::cerr << fit.message << "\n";
  if (!fit.representable)
    return 3;
  vpKinematicChain table = fit.table;
  table.setCameraInWorld(model.isCameraInWorld()); // a bMc stays a bMc
  table.saveYaml(out);
  std::cout << "wrote " << out << (fit.well_conditioned ? "" : " (ill-conditioned, see above)") << "\n";
  return 0;
}
