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
  CLI::App *c = app.add_subcommand("plan", "planned calibration poses of the reference scenario, or the poses to add to a dataset");
  c->footer("Writes calibration poses planned on the reference scenario's nominal model, then random held-out\n"
            "poses, one joint vector per line.\n"
            "With --from DATASET: calibrates the dataset (method bundle) and proposes the next poses that\n"
            "determine the parameters its views alone do not determine (held by the kinematic prior, or left\n"
            "at nominal: results.yaml's estimated_set.held_by_prior, left_by_data), each with what it adds;\n"
            "written to --out FILE (else stdout) in the same joints format, for simulate --joints or acquire\n"
            "--plan. Exit codes: 0 poses written, or nothing to add (said so);\n"
            "1 bad input (a dataset without joint readings, a camera in the world); 2 bad usage; 3 the\n"
            "calibration failed, or no candidate pose keeps the scene in view.");
  c->add_option("OUT.txt", a.out, "the file to write (not with --from: use --out)")
      ->type_name("FILE")
      ->each([&a](const std::string &) { a.out_given = true; });
  addRobotOption(*c, a.robot);
  c->add_option("--seed", a.so.seed, "scenario seed (default 1); with --from, of the candidate poses")
      ->type_name("N")
      ->check(selfcalibCli::wholeNumber());
  c->add_option("--poses", a.poses,
                "calibration poses, 6 to 1000 (default 15); with --from: the poses to add, at most 100\n"
                "(default: as many as determine the parameters left, up to 6)")
      ->type_name("N")
      ->check(selfcalibCli::wholeNumber(1, 1000));
  c->add_option("--held-out", a.held_out, "held-out poses after them, at most 10000 (default 10)")
      ->type_name("N")
      ->check(selfcalibCli::wholeNumber(0, 10000));
  c->add_option("--method", a.method,
                "observability (default): O1-optimal choice from a pool; paper: the paper's\n"
                "optimal trajectory (eqs. 22-39)")
      ->type_name("M")
      ->check(CLI::IsMember({"observability", "paper"}));
  c->add_option("--from", a.from, "the dataset whose views are taken: propose the poses to add")->type_name("DATASET");
  c->add_option("--out", a.out_file, "with --from: the joints file to write (default: stdout)")->type_name("FILE");
  c->add_option("--tolerance", a.tolerance,
                "with --from: the nominal model's tolerance, as calibrate's (T,R[,TE,RE], m and rad)")
      ->type_name("T,R[,TE,RE]")
      ->delimiter(',')
      ->check(selfcalibCli::number(0, true, 10));
  c->add_flag("--force", a.force, "replace an existing output file");
}

int plan(const PlanArgs &a)
{
  if (!a.from.empty())
    return planFrom(a);
  if (!a.out_given)
    throw CLI::ValidationError("OUT.txt", "give the file to write (or --from DATASET to plan the poses to add to a dataset)");
  if (!a.out_file.empty() || !a.tolerance.empty())
    throw CLI::ValidationError(!a.out_file.empty() ? "--out" : "--tolerance",
                               "is for --from DATASET; the reference scenario's plan goes to OUT.txt");
  if (a.poses != 0 && a.poses < 6)
    throw CLI::ValidationError("--poses", "the reference scenario's plan needs 6 calibration poses or more, got " +
                                              std::to_string(a.poses));
  const std::string &out = a.out, &robot = a.robot, &method = a.method;
  const vpSelfCalibSimulator::Options &so = a.so;
  const unsigned int poses = a.poses == 0 ? 15 : a.poses, held_out = a.held_out;
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
