/*
 * visp-selfcalib plan: calibration poses planned on the reference scenario's nominal model.
 */
#include "commands.h"

#include <unistd.h>

#include <iomanip>
#include <iostream>
#include <sstream>

#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpMeasurementPlanner.h>
#include <visp3/selfcalib/vpSelfCalibFileWriter.h>

#include "selfcalibCli.h"

void addPlan(CLI::App &app, PlanArgs &a)
{
  CLI::App *c = app.add_subcommand("plan", "planned calibration poses of the reference scenario");
  c->footer("Writes calibration poses planned on the reference scenario's nominal model, then random held-out\n"
            "poses, one joint vector per line.");
  c->add_option("OUT.txt", a.out, "the file to write")->type_name("FILE")->required();
  addRobotOption(*c, a.robot);
  c->add_option("--seed", a.so.seed, "scenario seed (default 1)")->type_name("N")->check(selfcalibCli::wholeNumber());
  c->add_option("--poses", a.poses, "calibration poses, 6 to 1000 (default 15)")
      ->type_name("N")
      ->check(selfcalibCli::wholeNumber(6, 1000));
  c->add_option("--held-out", a.held_out, "held-out poses after them, at most 10000 (default 10)")
      ->type_name("N")
      ->check(selfcalibCli::wholeNumber(0, 10000));
  c->add_option("--method", a.method,
                "observability (default): O1-optimal choice from a pool; paper: the paper's\n"
                "optimal trajectory (eqs. 22-39)")
      ->type_name("M")
      ->check(CLI::IsMember({"observability", "paper"}));
  c->add_flag("--force", a.force, "replace an existing OUT.txt");
}

int plan(const PlanArgs &a)
{
  const std::string &out = a.out, &robot = a.robot, &method = a.method;
  const vpSelfCalibSimulator::Options &so = a.so;
  const unsigned int poses = a.poses, held_out = a.held_out;
  if (outputRefused(out, a.force))
    return 1;
  const vpSelfCalibSimulator sim(vpKinematicChain::fromPresetOrFile(robot), so);
  const unsigned int pool = method == "observability" ? 60 : 0;
  // Progress on a terminal only, on one line rewritten in place; nothing in a pipe or a log.
  const bool tty = ::isatty(STDERR_FILENO) != 0;
  const auto progress = [tty](const std::string &stage, unsigned int d, unsigned int n) {
    if (tty)
      std::cerr << "\r\033[K... " << stage << " " << d << "/" << n << std::flush;
  };
  const std::vector<vpColVector> q = sim.generateConfigurations(
      poses + held_out + pool, [&progress](unsigned int d, unsigned int n) { progress("random feasible configurations", d, n); });
  const std::vector<vpColVector> initial(q.begin(), q.begin() + poses);
  const vpMeasurementPlanner planner(sim.getNominalChain(), sim.getPlannerScene());
  vpMeasurementPlanner::Result pr;
  if (method == "paper") {
    vpMeasurementPlanner::TrajectoryOptions to;
    to.seed = so.seed;
    pr = planner.planTrajectory(initial, to, [&progress](const std::string &stage, unsigned int d, unsigned int n) {
      progress(stage, d + 1, n);
    });
  } else {
    std::vector<vpColVector> candidates = initial;
    candidates.insert(candidates.end(), q.begin() + poses + held_out, q.end());
    pr = planner.selectObservable(candidates, poses);
  }
  if (tty)
    std::cerr << "\r\033[K" << std::flush;
  if (pr.status != vpMeasurementPlanner::OK) {
    std::cerr << "planning failed: " << vpMeasurementPlanner::statusName(pr.status) << ": " << pr.message << "\n";
    return 3;
  }
  std::ostringstream os;
  os << std::setprecision(17) << "# " << robot << ", seed " << so.seed << ": " << poses << " planned (" << method
     << ") calibration poses, then " << held_out << " random held-out poses; rad\n";
  std::vector<vpColVector> all = pr.configurations;
  all.insert(all.end(), q.begin() + poses, q.begin() + poses + held_out);
  for (const vpColVector &c : all) {
    for (unsigned int i = 0; i < c.size(); ++i)
      os << c[i] << (i + 1 < c.size() ? " " : "\n");
  }
  vpSelfCalibFileWriter::write(out, os.str(), "plan");
  std::cout << "wrote " << out << ": " << poses << " planned + " << held_out << " held-out configurations; "
            << std::setprecision(3) << "cond(J) " << pr.before.condition << " -> " << pr.after.condition
            << " (lower is better), O1 " << pr.observability_before.O1 << " -> " << pr.observability_after.O1
            << " (higher is better), " << std::setprecision(2)
            << pr.seconds << " s\n";
  return 0;
}
