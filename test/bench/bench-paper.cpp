/*
 * bench-paper: the paper's simulation study (Section 4.2) with its method (vpRobotSelfCalibration,
 * PAPER) on a named scene: the reference scenario (README, "Reference scenario") or the paper-like
 * scene (vpSelfCalibSimulator::sceneOptions("paper"): f 300 px, a large deep scene, wide views,
 * partial views).
 *
 *   bench-paper [--scene reference|paper] [--seeds N] [--noise 0,0.2,0.5] [--robots puma560,viper850]
 *               [--focal shared,known] [--trajectories random,smooth,optimal] [--start smooth|random]
 *               [--max-evaluations N] [--multistart N] [--figure6-step 3] [--figure6 FILE.png] [--csv FILE] [-h]
 *
 * For every robot and seed: 25 random feasible configurations ("initial (random)", the last 10 of
 * them are the verification poses of every trajectory), a smooth loop around the home configuration
 * (vpMeasurementPlanner::smoothTrajectory with its default margin, "initial (smooth)"), and the
 * paper's optimal trajectory planned from the smooth loop (--start random: from the random poses)
 * with the default options (planning margin from the model's tolerance, checked through sampled
 * models). Every plan reported OK is checked through the true robot (simulator's visibility rule).
 * Then, for every noise level, trajectory and focal mode:
 *   - Table 2: the 24 scaled pose measurements c_iMc_1 of the pairs (1, i) against the truth, with
 *     the position error split into its parts (translation direction, eq. 21 ratio, yardstick scale)
 *     beside the Cramér-Rao bound of the direction part; the yardstick scale's error and sd;
 *   - Figure 6: the model calibrated on the first n poses (n = 6, 9, 12, 15; --figure6-step 1: 6..15), verified on the 10
 *     verification poses (yardstick 3-D error, point-pair distances, held-out poses);
 *     --figure6 draws it (gnuplot, png, headless; the data beside it as FILE.dat);
 * and cond(J) of the first 15 poses of each trajectory. With noise 0 and the smooth and optimal
 * trajectories, a line per robot: noise-free gain (optimal vs smooth initial), ROBOT: N.NNx.
 */
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <visp3/selfcalib/vpMeasurementPlanner.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include "benchCommon.h"
#include "benchPaper.h"
#include "selfcalibCli.h"

namespace
{
const unsigned int kPoses = 25, kVerification = 10, kMinCalibration = 6, kCalibration = kPoses - kVerification;

std::string noiseName(double noise)
{
  if (noise == 0)
    return "noise-free";
  if (std::fabs(noise - 0.2) < 1e-12)
    return "I (0.2 px)";
  if (std::fabs(noise - 0.5) < 1e-12)
    return "II (0.5 px)";
  std::ostringstream os;
  os << noise << " px";
  return os.str();
}

struct Cell {
  bench::Stats pos, rot, f, ratio, seconds, dir, ratio_part, scale_part, crb, scale_err, scale_sd, scale_z;
  bench::Stats crb_pairs, crb_joint; // Cramér-Rao bounds of the relative scale (bench::yardstickScaleBounds)
  unsigned int failed = 0, runs = 0;
};

struct Figure6Cell {
  bench::Stats yardstick, distance, held_pos, held_rot;
  unsigned int failed = 0;
};

enum Trajectory { RANDOM, SMOOTH, OPTIMAL };
const char *trajectoryName(int t)
{
  static const char *names[3] = {"initial (random)", "initial (smooth)", "optimal"};
  return names[t];
}
} // namespace

int main(int argc, char **argv)
{
  try {
    unsigned int seeds = 10;
    std::vector<double> noises = {0, 0.2, 0.5};
    std::vector<std::string> robots = {"puma560", "viper850"}, focals = {"shared", "known"};
    std::vector<std::string> trajectories = {"random", "smooth", "optimal"};
    std::string csv_path, scene = "reference", start = "smooth", figure_path;
    CLI::App app("bench-paper: the paper's simulation study (Section 4.2) with its method: Table 2 (with the position\n"
                 "error split and the Cramér-Rao bound) and Figure 6 on random, smooth and optimal trajectories.",
                 "bench-paper");
    selfcalibCli::addSeeds(app, seeds);
    selfcalibCli::addNoiseLevels(app, noises, "pixel noise levels (default 0,0.2,0.5: noise-free, the paper's I and II)");
    selfcalibCli::addRobots(app, robots, vpKinematicChain::presetNames());
    app.add_option("--scene", scene, "reference (default: README, Reference scenario) or paper (f 300 px, large\n"
                                     "deep scene, wide views, partial views)")
        ->type_name("NAME")
        ->check(CLI::IsMember(vpSelfCalibSimulator::sceneNames()));
    std::string shared_focal = "all-views";
    bench::addSharedFocal(app, shared_focal);
    app.add_option("--focal", focals,
                   "focal modes: shared (self-calibrated, default), known, per-pair (the\n"
                   "paper; degenerate on the reference scenario) (default shared,known)")
        ->type_name("A,B")
        ->delimiter(',')
        ->check(CLI::IsMember(
            bench::focalModeNames({vpRobotSelfCalibration::FOCAL_SHARED, vpRobotSelfCalibration::FOCAL_KNOWN,
                                   vpRobotSelfCalibration::FOCAL_PER_PAIR})));
    app.add_option("--trajectories", trajectories, "random, smooth, optimal (default all three)")
        ->type_name("A,B")
        ->delimiter(',')
        ->check(CLI::IsMember({"random", "smooth", "optimal"}));
    app.add_option("--start", start, "start of the optimal trajectory: smooth (default) or random")
        ->type_name("S")
        ->check(CLI::IsMember({"smooth", "random"}));
    unsigned int max_evaluations = 6000,
                 multistart = vpMeasurementPlanner::TrajectoryOptions().multistart;
    app.add_option("--max-evaluations", max_evaluations, "planner: cost evaluations per start (default 6000; the\nplanner's own default is 2000)")
        ->type_name("N")
        ->check(selfcalibCli::wholeNumber(1));
    std::string ratio_cost = "default";
    app.add_option("--ratio-cost", ratio_cost, "planner: consecutive or spread (default: the planner's)")
        ->type_name("C")
        ->check(CLI::IsMember({"default", "consecutive", "spread"}));
    app.add_option("--multistart", multistart, "planner: extra starts (default 2)")->type_name("N")->check(selfcalibCli::wholeNumber(0));
    unsigned int figure6_step = 3;
    app.add_option("--figure6-step", figure6_step, "Figure 6: every STEP-th n from 15 down to 6 (default 3: 6, 9, 12, 15)")
        ->type_name("STEP")
        ->check(selfcalibCli::wholeNumber(1));
    app.add_option("--figure6", figure_path, "draw Figure 6 (gnuplot, png; data in FILE.dat)")->type_name("FILE");
    app.add_option("--csv", csv_path, "one row per robot, noise, trajectory, focal mode, seed and experiment")
        ->type_name("FILE");
    const int parsed = selfcalibCli::parse(app, argc, argv);
    if (parsed >= 0)
      return parsed;
    bench::paperFocalAllViews() = shared_focal == "all-views";
    std::vector<vpRobotSelfCalibration::FocalMode> modes;
    for (const std::string &f : focals)
      modes.push_back(vpRobotSelfCalibration::focalModeFromName(f));
    bool want[3] = {false, false, false};
    for (const std::string &t : trajectories)
      want[t == "random" ? RANDOM : t == "smooth" ? SMOOTH : OPTIMAL] = true;
    const bool need_smooth = want[SMOOTH] || (want[OPTIMAL] && start == "smooth");

    const vpSelfCalibSimulator::Options base = vpSelfCalibSimulator::sceneOptions(scene);
    bench::Csv csv(csv_path, "robot,noise_px,trajectory,focal,seed,experiment,n_calibration,index,position_m,"
                             "orientation_rad,direction_part_m,ratio_part_m,scale_part_m,crb_direction_m,"
                             "yardstick_error_m,distance_rms_m,seconds");
    std::cout << "bench-paper: scene " << scene << " (f " << base.px << " px, " << base.num_points
              << " points in " << base.box_x << " x " << base.box_y << " x " << base.box_z << " m + yardstick "
              << base.yardstick_length << " m, distance " << base.distance_min << "-" << base.distance_max
              << " m, view cone " << base.view_cone * 180 / M_PI << " deg, "
              << (base.min_visible_points ? "partial views (>= " + std::to_string(base.min_visible_points) +
                                                " points and the yardstick)"
                                          : std::string("every point in every view"))
              << "), " << kPoses << " poses, " << seeds << " seeds, optimal planned from the " << start
              << " start\n";

    const size_t R = robots.size(), N = noises.size(), F = modes.size();
    // [robot][noise][trajectory][focal]
    std::vector<std::vector<std::vector<std::vector<Cell>>>> table(
        R, std::vector<std::vector<std::vector<Cell>>>(N, std::vector<std::vector<Cell>>(3, std::vector<Cell>(F))));
    std::vector<std::vector<std::vector<std::vector<std::vector<Figure6Cell>>>>> fig6(
        R, std::vector<std::vector<std::vector<std::vector<Figure6Cell>>>>(
               N, std::vector<std::vector<std::vector<Figure6Cell>>>(
                      3, std::vector<std::vector<Figure6Cell>>(F, std::vector<Figure6Cell>(kCalibration + 1)))));
    std::vector<std::vector<Figure6Cell>> nominal(R, std::vector<Figure6Cell>(N));
    // Planning: [robot][trajectory]
    std::vector<std::vector<bench::Stats>> cond15(R, std::vector<bench::Stats>(3)), cond_pairs(R, std::vector<bench::Stats>(3));
    std::vector<bench::Stats> plan_time(R), plan_margin(R);
    std::vector<unsigned int> smooth_failed(R, 0), plan_failed(R, 0), plans_ok(R, 0), unseen_views(R, 0);
    std::vector<std::string> why_not(R);

    for (size_t ri = 0; ri < R; ++ri)
      for (unsigned int seed = 1; seed <= seeds; ++seed) {
        std::cerr << robots[ri] << ", seed " << seed << "/" << seeds << ": trajectories      \r" << std::flush;
        vpSelfCalibSimulator::Options so = base;
        so.seed = seed;
        so.pixel_noise_sd = 0;
        const vpSelfCalibSimulator sim0(vpKinematicChain::preset(robots[ri]), so);
        std::vector<std::vector<vpColVector>> traj(3);
        traj[RANDOM] = sim0.generateConfigurations(kPoses);
        const std::vector<vpColVector> verification(traj[RANDOM].end() - kVerification, traj[RANDOM].end());
        const vpMeasurementPlanner planner(sim0.getNominalChain(), sim0.getPlannerScene());
        if (need_smooth) {
          const vpColVector home = vpSelfCalibSimulator::homeConfiguration(sim0.getNominalChain());
          std::string why;
          traj[SMOOTH] = planner.smoothTrajectory(home, vpColVector(home.size(), 0.6), kPoses, -1, &why);
          if (traj[SMOOTH].empty()) {
            ++smooth_failed[ri];
            why_not[ri] = why;
          }
        }
        if (want[OPTIMAL]) {
          const std::vector<vpColVector> &from = start == "smooth" ? traj[SMOOTH] : traj[RANDOM];
          if (!from.empty()) {
            vpMeasurementPlanner::TrajectoryOptions po;
            po.seed = seed;
            po.max_evaluations = max_evaluations;
            po.multistart = multistart;
            if (ratio_cost != "default")
              po.ratio_cost = ratio_cost == "spread" ? vpMeasurementPlanner::RATIO_SPREAD
                                                     : vpMeasurementPlanner::RATIO_CONSECUTIVE;
            const vpMeasurementPlanner::Result plan = planner.planTrajectory(from, po);
            plan_time[ri].add(plan.seconds);
            plan_margin[ri].add(plan.planning_margin);
            if (plan.status == vpMeasurementPlanner::OK) {
              traj[OPTIMAL] = plan.configurations;
              ++plans_ok[ri];
              for (const vpColVector &q : plan.configurations)
                if (!sim0.isVisible(q))
                  ++unseen_views[ri];
            } else {
              ++plan_failed[ri];
              why_not[ri] = plan.message;
            }
          }
        }
        for (int t = 0; t < 3; ++t)
          if (traj[t].size() == kPoses) {
            const std::vector<vpColVector> first(traj[t].begin(), traj[t].begin() + kCalibration);
            cond15[ri][t].add(planner.observability(first).condition_number);
            cond_pairs[ri][t].add(planner.observability(traj[t]).condition_number);
          }

        for (size_t ni = 0; ni < N; ++ni) {
          std::cerr << robots[ri] << ", seed " << seed << "/" << seeds << ", noise " << noises[ni] << "      \r"
                    << std::flush;
          vpSelfCalibSimulator::Options sn = so;
          sn.pixel_noise_sd = noises[ni];
          const vpSelfCalibSimulator sim(vpKinematicChain::preset(robots[ri]), sn);
          {
            const vpSelfCalibDataset ds = sim.makeDataset(verification);
            const vpCalibrationVerifier::Result b =
                bench::verifyAgainstTruth(sim, sim.getNominalChain(), sim.getCamera(), ds.views);
            Figure6Cell &c = nominal[ri][ni];
            c.yardstick.add(b.yardstick_error);
            c.distance.add(b.distance_error_rms);
            for (size_t k = 0; k < b.position_errors.size(); ++k) {
              c.held_pos.add(b.position_errors[k]);
              c.held_rot.add(b.rotation_errors[k]);
            }
          }
          for (int t = 0; t < 3; ++t) {
            if (!want[t])
              continue;
            const std::vector<vpColVector> &q = traj[t];
            for (size_t fi = 0; fi < F; ++fi) {
              Cell &c = table[ri][ni][t][fi];
              ++c.runs;
              if (q.size() != kPoses) {
                ++c.failed;
                continue;
              }
              const bench::PoseMeasurementErrors e = bench::poseMeasurementErrors(sim, q, modes[fi]);
              if (e.status != vpRobotSelfCalibration::OK) {
                ++c.failed;
                std::cerr << "\n" << robots[ri] << ", seed " << seed << ", noise " << noises[ni] << ", trajectory " << t
                          << ", focal " << fi << ": " << vpRobotSelfCalibration::statusName(e.status) << ": " << e.message
                          << "\n";
              }
              for (size_t k = 0; k < e.position.size(); ++k) {
                c.pos.add(e.position[k]);
                c.rot.add(e.orientation[k]);
              }
              for (size_t k = 0; k < e.direction_part.size(); ++k) {
                c.dir.add(e.direction_part[k]);
                c.ratio_part.add(e.ratio_part[k]);
                c.scale_part.add(e.scale_part[k]);
                if (csv.enabled())
                  csv.row() << robots[ri] << "," << noises[ni] << "," << trajectoryName(t) << "," << focals[fi] << ","
                            << seed << ",table2," << kPoses << "," << k << ","
                            << (k < e.position.size() ? e.position[k] : NAN) << ","
                            << (k < e.orientation.size() ? e.orientation[k] : NAN) << "," << e.direction_part[k]
                            << "," << e.ratio_part[k] << "," << e.scale_part[k] << ","
                            << (k < e.crb_direction.size() ? e.crb_direction[k] : NAN) << ",,,\n";
              }
              for (double b : e.crb_direction)
                c.crb.add(b);
              if (noises[ni] > 0) {
                const bench::ScaleBounds sb = bench::yardstickScaleBounds(sim, q, noises[ni]);
                if (std::isfinite(sb.pairs))
                  c.crb_pairs.add(sb.pairs);
                const double joint = modes[fi] == vpRobotSelfCalibration::FOCAL_KNOWN ? sb.joint : sb.joint_shared;
                if (std::isfinite(joint))
                  c.crb_joint.add(joint);
              }
              if (std::isfinite(e.scale_error)) {
                c.scale_err.add(std::fabs(e.scale_error));
                c.scale_sd.add(e.scale_sd);
                if (e.scale_sd > 0)
                  c.scale_z.add(e.scale_error / e.scale_sd);
              }
              for (double r : e.scale_ratio)
                c.ratio.add(r);
              for (double f : e.fx)
                c.f.add(f);
              // Figure 6: the first n poses of the trajectory, the 10 verification poses.
              for (unsigned int n = kMinCalibration; n <= kCalibration; ++n) {
                if ((kCalibration - n) % figure6_step)
                  continue;
                const std::vector<vpColVector> cal(q.begin(), q.begin() + n);
                const bench::CalibrationErrors ce = bench::calibrationErrors(sim, cal, verification, modes[fi]);
                Figure6Cell &g = fig6[ri][ni][t][fi][n];
                if (n == kCalibration)
                  c.seconds.add(ce.seconds);
                if (ce.status != vpRobotSelfCalibration::OK) {
                  ++g.failed;
                  continue;
                }
                g.yardstick.add(ce.after.yardstick_error);
                g.distance.add(ce.after.distance_error_rms);
                for (size_t k = 0; k < ce.after.position_errors.size(); ++k) {
                  g.held_pos.add(ce.after.position_errors[k]);
                  g.held_rot.add(ce.after.rotation_errors[k]);
                }
                if (csv.enabled())
                  csv.row() << robots[ri] << "," << noises[ni] << "," << trajectoryName(t) << "," << focals[fi] << ","
                            << seed << ",figure6," << n << ",,,,,,,," << ce.after.yardstick_error << ","
                            << ce.after.distance_error_rms << "," << ce.seconds << "\n";
              }
            }
          }
        }
      }
    std::cerr << std::string(60, ' ') << "\r";

    // Trajectories.
    std::cout << "\nTrajectories (mean / SD over seeds): cond(J) of the relative-pose identification Jacobian of the "
                 "first 15 poses and of all 25; planner\n"
              << "| robot | trajectory | cond(J) 15 poses | cond(J) 25 poses | failed |\n|---|---|---|---|---|\n";
    for (size_t ri = 0; ri < R; ++ri)
      for (int t = 0; t < 3; ++t)
        if (want[t] || (t == SMOOTH && need_smooth))
          std::cout << "| " << robots[ri] << " | " << trajectoryName(t) << " | " << bench::meanSd(cond15[ri][t], 1, 1)
                    << " | " << bench::meanSd(cond_pairs[ri][t], 1, 1) << " | "
                    << (t == RANDOM ? 0u : t == SMOOTH ? smooth_failed[ri] : plan_failed[ri] + (start == "smooth" ? smooth_failed[ri] : 0))
                    << "/" << seeds << " |\n";
    if (want[OPTIMAL])
      for (size_t ri = 0; ri < R; ++ri) {
        std::cout << robots[ri] << ": planner " << bench::meanSd(plan_time[ri], 1, 2) << " s, planning margin "
                  << bench::meanSd(plan_margin[ri], 1, 1) << " px (from the model's tolerance); plans reported OK: "
                  << plans_ok[ri] << "/" << seeds << ", their views the true robot cannot see: " << unseen_views[ri]
                  << (unseen_views[ri] ? " (CHECK FAILED)" : " (check passed)") << "\n";
      }
    for (size_t ri = 0; ri < R; ++ri)
      if (!why_not[ri].empty())
        std::cout << robots[ri] << ": last trajectory failure: " << why_not[ri] << "\n";

    // Table 2.
    std::cout << "\nTable 2: errors of the 24 pose measurements c_iMc_1 (mean / SD over pairs and seeds; f_x: over "
                 "seeds, or pairs with per-pair f). Position split: |T_i| x direction angle; ratio: |T_i| x the norm "
                 "error of the same pipeline on noise-free images (the eq. 21 model bias); scale: |T_i| x the yardstick "
                 "scale's error against that noise-free scale (the image noise's part, f included); CRB: Cramér-Rao "
                 "bound of the direction part (f known); scale error and reported sd of the yardstick scale (%, over "
                 "seeds); scale CRB: Cramér-Rao bounds of the relative scale (%), from the two-view poses and the "
                 "yardstick in every view (f known) / from every observation jointly (f as the focal mode)\n"
              << "| robot | noise | trajectory | focal | position (mm) | direction (mm) | CRB direction (mm) | ratio (mm) "
                 "| scale (mm) | scale error (%) | scale sd (%) | scale CRB pairs / joint (%) | orientation (1e-4 rad) | "
                 "f_x (px) | eq. 21 ratio error (%) | runs not ok (doubtful or failed) |\n"
              << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n"
              << "| paper (PUMA 560) | I | initial | per pair | 3.0427 / 1.1051 | – | – | – | – | – | – | – | 1.4918 / 2.5354 "
                 "| 0.2249 / 0.2374 | – | – |\n"
              << "| paper (PUMA 560) | I | optimal | per pair | 0.2809 / 0.2452 | – | – | – | – | – | – | – | 1.0701 / 1.4532 "
                 "| 0.1539 / 0.2128 | – | – |\n"
              << "| paper (PUMA 560) | II | initial | per pair | 6.9837 / 2.6475 | – | – | – | – | – | – | – | 4.0876 / "
                 "7.1762 | 0.6181 / 0.7324 | – | – |\n"
              << "| paper (PUMA 560) | II | optimal | per pair | 0.3035 / 0.2826 | – | – | – | – | – | – | – | 2.4016 / "
                 "3.2432 | 0.3458 / 0.4791 | – | – |\n";
    for (size_t ri = 0; ri < R; ++ri)
      for (size_t ni = 0; ni < N; ++ni)
        for (int t = 0; t < 3; ++t) {
          if (!want[t])
            continue;
          for (size_t fi = 0; fi < F; ++fi) {
            const Cell &c = table[ri][ni][t][fi];
            std::cout << "| " << robots[ri] << " | " << noiseName(noises[ni]) << " | " << trajectoryName(t) << " | "
                      << focals[fi] << " | " << bench::meanSd(c.pos, 1e3, 3) << " | " << bench::meanSd(c.dir, 1e3, 3)
                      << " | " << bench::meanSd(c.crb, 1e3, 3) << " | " << bench::meanSd(c.ratio_part, 1e3, 3) << " | "
                      << bench::meanSd(c.scale_part, 1e3, 3) << " | " << bench::meanSd(c.scale_err, 1e2, 3) << " | "
                      << bench::meanSd(c.scale_sd, 1e2, 3) << " | "
                      << (c.crb_pairs.count() ? bench::meanSd(c.crb_pairs, 1e2, 3) : std::string("–")) << " ; "
                      << (c.crb_joint.count() ? bench::meanSd(c.crb_joint, 1e2, 3) : std::string("–")) << " | "
                      << bench::meanSd(c.rot, 1e4, 2) << " | "
                      << (modes[fi] == vpRobotSelfCalibration::FOCAL_KNOWN ? std::string("(known)")
                                                                           : bench::meanSd(c.f, 1, 2))
                      << " | " << bench::meanSd(c.ratio, 1e2, 3) << " | " << c.failed << "/" << c.runs << " |\n";
          }
        }

    // Summary lines.
    std::cout << "\n";
    for (size_t ni = 0; ni < N; ++ni) {
      if (noises[ni] != 0 || !want[SMOOTH] || !want[OPTIMAL])
        continue;
      for (size_t ri = 0; ri < R; ++ri) {
        const Cell &a = table[ri][ni][SMOOTH][0], &b = table[ri][ni][OPTIMAL][0];
        std::cout << "noise-free gain (optimal vs smooth initial), " << robots[ri] << ": " << std::fixed
                  << std::setprecision(2) << a.pos.mean() / b.pos.mean() << "x (" << std::setprecision(4)
                  << 1e3 * a.pos.mean() << " -> " << 1e3 * b.pos.mean() << " mm, focal " << focals[0] << ", "
                  << b.pos.count() / 24 << " runs; target >= 5x: " << (a.pos.mean() / b.pos.mean() >= 5 ? "met" : "NOT met")
                  << ")\n";
        std::cout.unsetf(std::ios::fixed);
      }
    }
    for (size_t ni = 0; ni < N; ++ni) {
      if (noises[ni] == 0)
        continue;
      for (size_t ri = 0; ri < R; ++ri)
        for (int t = 0; t < 3; ++t) {
          if (!want[t])
            continue;
          const Cell &c = table[ri][ni][t][0];
          std::cout << "yardstick scale at noise " << noises[ni] << " px, " << robots[ri] << ", " << trajectoryName(t)
                    << ", focal " << focals[0] << ": |error| " << bench::meanSd(c.scale_err, 1e2, 3)
                    << " %, reported sd " << bench::meanSd(c.scale_sd, 1e2, 3) << " %, error/sd RMS "
                    << (c.scale_z.count() ? std::sqrt(c.scale_z.mean() * c.scale_z.mean() +
                                                      (c.scale_z.count() > 1 ? c.scale_z.sd() * c.scale_z.sd() : 0))
                                          : NAN)
                    << "; Cramér-Rao bound " << bench::meanSd(c.crb_pairs, 1e2, 3)
                    << " % from the two-view poses (yardstick in every view, f known), "
                    << bench::meanSd(c.crb_joint, 1e2, 3) << " % from every observation jointly (f " << focals[0]
                    << ")"
                    << (std::fabs(noises[ni] - 0.2) < 1e-12
                            ? std::string(c.scale_err.mean() <= 1e-3 ? " (target <= 0.1 %: met)" : " (target <= 0.1 %: NOT met)")
                            : std::string())
                    << "\n";
        }
      for (size_t ri = 0; ri < R; ++ri)
        if (want[RANDOM] && want[OPTIMAL]) {
          const Cell &a = table[ri][ni][RANDOM][0], &b = table[ri][ni][OPTIMAL][0], &s = table[ri][ni][SMOOTH][0];
          std::cout << "noise " << noises[ni] << " px, " << robots[ri] << ": position error random / optimal "
                    << a.pos.mean() / b.pos.mean() << "x, smooth / optimal " << s.pos.mean() / b.pos.mean() << "x\n";
        }
    }

    // Figure 6.
    std::cout << "\nFigure 6: model calibrated on the first n poses of the trajectory, verified on the " << kVerification
              << " verification poses (mean / SD over seeds; held-out poses: over poses and seeds)\n"
              << "| robot | noise | trajectory | focal | n | yardstick 3-D error (mm) | point-pair distance RMS (mm) | "
                 "held-out position (mm) | held-out rotation (mrad) | runs not ok (doubtful or failed) |\n"
              << "|---|---|---|---|---|---|---|---|---|---|\n";
    for (size_t ri = 0; ri < R; ++ri)
      for (size_t ni = 0; ni < N; ++ni) {
        const Figure6Cell &b = nominal[ri][ni];
        std::cout << "| " << robots[ri] << " | " << noiseName(noises[ni]) << " | – | – | nominal | "
                  << bench::meanSd(b.yardstick, 1e3, 3) << " | " << bench::meanSd(b.distance, 1e3, 3) << " | "
                  << bench::meanSd(b.held_pos, 1e3, 2) << " | " << bench::meanSd(b.held_rot, 1e3, 3) << " | – |\n";
        for (int t = 0; t < 3; ++t) {
          if (!want[t])
            continue;
          for (size_t fi = 0; fi < F; ++fi)
            for (unsigned int n = kMinCalibration; n <= kCalibration; ++n) {
              if ((kCalibration - n) % figure6_step)
                continue;
              const Figure6Cell &g = fig6[ri][ni][t][fi][n];
              std::cout << "| " << robots[ri] << " | " << noiseName(noises[ni]) << " | " << trajectoryName(t) << " | "
                        << focals[fi] << " | " << n << " | " << bench::meanSd(g.yardstick, 1e3, 3) << " | "
                        << bench::meanSd(g.distance, 1e3, 3) << " | " << bench::meanSd(g.held_pos, 1e3, 2) << " | "
                        << bench::meanSd(g.held_rot, 1e3, 3) << " | " << g.failed << "/" << seeds << " |\n";
            }
        }
      }

    if (!figure_path.empty()) {
      // The paper's Figure 6: 3-D (yardstick) error after calibration against n, one curve per robot,
      // noise and trajectory (first focal mode), drawn headless with gnuplot.
      const std::string dat = figure_path + ".dat";
      std::ofstream out(dat);
      if (!out)
        throw std::runtime_error("cannot write " + dat);
      std::vector<std::string> titles;
      for (size_t ri = 0; ri < R; ++ri)
        for (size_t ni = 0; ni < N; ++ni)
          for (int t = 0; t < 3; ++t) {
            if (!want[t])
              continue;
            titles.push_back(robots[ri] + ", " + noiseName(noises[ni]) + ", " + trajectoryName(t));
            out << "# " << titles.back() << "\n# n yardstick_3d_error_mm sd_mm\n";
            for (unsigned int n = kMinCalibration; n <= kCalibration; ++n) {
              if ((kCalibration - n) % figure6_step)
                continue;
              const Figure6Cell &g = fig6[ri][ni][t][0][n];
              out << n << " " << 1e3 * g.yardstick.mean() << " " << 1e3 * (g.yardstick.count() > 1 ? g.yardstick.sd() : 0)
                  << "\n";
            }
            out << "\n\n";
          }
      out.close();
      const std::string gp = figure_path + ".gp";
      std::ofstream g(gp);
      g << "set terminal png size 1000,700\nset output '" << figure_path << "'\n"
        << "set title 'Figure 6: 3-D errors after calibration (scene " << scene << ", focal " << focals[0] << ")'\n"
        << "set xlabel 'number of calibration poses'\nset ylabel 'yardstick 3-D error (mm)'\nset logscale y\n"
        << "set key outside right\nplot ";
      for (size_t k = 0; k < titles.size(); ++k)
        g << (k ? ", " : "") << "'" << dat << "' index " << k << " using 1:2 with linespoints title '" << titles[k]
          << "'";
      g << "\n";
      g.close();
      const int rc = std::system(("gnuplot '" + gp + "' 2>/dev/null").c_str());
      std::cout << "\nFigure 6: " << (rc == 0 ? "drawn in " + figure_path : "gnuplot failed; data in " + dat)
                << " (data " << dat << ", script " << gp << ")\n";
    }

    std::cout << "\nPipeline wall time (15 calibration poses, 10 verification poses), mean / SD over seeds (s)\n"
              << "| robot | noise | trajectory | focal | time (s) |\n|---|---|---|---|---|\n";
    for (size_t ri = 0; ri < R; ++ri)
      for (size_t ni = 0; ni < N; ++ni)
        for (int t = 0; t < 3; ++t)
          if (want[t])
            for (size_t fi = 0; fi < F; ++fi)
              std::cout << "| " << robots[ri] << " | " << noiseName(noises[ni]) << " | " << trajectoryName(t) << " | "
                        << focals[fi] << " | " << bench::meanSd(table[ri][ni][t][fi].seconds, 1, 3) << " |\n";
    std::cout << "done\n";
    return EXIT_SUCCESS;
  } catch (const vpException &e) {
    std::cerr << "bench-paper: " << e.getMessage() << "\n";
    return EXIT_FAILURE;
  } catch (const std::exception &e) {
    std::cerr << "bench-paper: " << e.what() << "\n";
    return EXIT_FAILURE;
  }
}
