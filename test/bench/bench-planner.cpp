/*
 * bench-planner: the paper's optimal measurement trajectory (Section 3.3) against the initial one.
 *
 *   bench-planner [--seeds N] [--noise 0,0.2,0.5] [--robots puma560,viper850] [--focal shared]
 *                 [--algorithm lbfgs] [--ratio-cost consecutive|spread] [--lambda 1e-7]
 *                 [--start random|smooth] [--csv FILE] [--trajectory-csv FILE] [-h]
 *
 * For every robot and seed the reference scenario is drawn with 25 random feasible configurations
 * (the "initial" trajectory of bench-paper; --start smooth: vpMeasurementPlanner::smoothTrajectory,
 * a closed loop in joint space around the home configuration, amplitudes up to 0.6 rad);
 * vpMeasurementPlanner::planTrajectory plans 25 configurations from it on the nominal model (the
 * "optimal" trajectory). Then, for every noise
 * level, on both trajectories:
 *   - Table 2: errors of the 24 scaled pose measurements (position mm, orientation 1e-4 rad, f_x px);
 *   - the eq. 21 ratio error |(|t_i|/|t_1|) / (|t̄_i|/|t̄_1|) - 1| (true vs nominal; noise-free);
 *   - held-out relative pose errors of the model calibrated on the first 15 configurations of the
 *     trajectory, verified on the last 10 random ones (the same for both);
 * and the planner's wall time, cost terms, cond(J). --trajectory-csv writes the data of the
 * paper's Figures 3-5: camera positions (in f) and |t_i| of both trajectories.
 */
#include <cstdlib>
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
const unsigned int kPoses = 25, kCalibration = 15;

struct Row {
  bench::Stats pos, rot, f, ratio, held_pos, held_rot;
  unsigned int failed = 0;
};
} // namespace

int main(int argc, char **argv)
{
  try {
    unsigned int seeds = 10;
    std::vector<double> noises = {0, 0.2, 0.5};
    std::vector<std::string> robots = {"puma560", "viper850"};
    std::string focal = "shared", csv_path, traj_path, start = "random";
    vpMeasurementPlanner::TrajectoryOptions po;
    std::string algorithm = "lbfgs", ratio_cost = "consecutive";
    CLI::App app("bench-planner: the paper's optimal measurement trajectory (Section 3.3) against the initial one.",
                 "bench-planner");
    selfcalibCli::addSeeds(app, seeds);
    selfcalibCli::addNoiseLevels(app, noises, "pixel noise levels (default 0,0.2,0.5)");
    selfcalibCli::addRobots(app, robots, vpKinematicChain::presetNames());
    app.add_option("--focal", focal, "shared (default), known or per-pair")
        ->type_name("MODE")
        ->check(CLI::IsMember(
            bench::focalModeNames({vpRobotSelfCalibration::FOCAL_SHARED, vpRobotSelfCalibration::FOCAL_KNOWN,
                                   vpRobotSelfCalibration::FOCAL_PER_PAIR})));
    app.add_option("--algorithm", algorithm, "lbfgs (default), mma, slsqp, bobyqa")
        ->type_name("NAME")
        ->check(CLI::IsMember({"lbfgs", "mma", "slsqp", "bobyqa"}));
    app.add_option("--ratio-cost", ratio_cost, "consecutive (default; the intent of eq. 39) or spread")
        ->type_name("NAME")
        ->check(CLI::IsMember({"consecutive", "spread"}));
    app.add_option("--lambda", po.lambda, "weight of cond(J), at least 0 (default 1e-7, the paper's)")
        ->type_name("L")
        ->check(selfcalibCli::number(0));
    app.add_option("--start", start, "initial trajectory: random (default, bench-paper's) or smooth (a loop)")
        ->type_name("S")
        ->check(CLI::IsMember({"random", "smooth"}));
    app.add_option("--csv", csv_path, "one row per robot, seed, noise, trajectory and pose measurement")
        ->type_name("FILE");
    app.add_option("--trajectory-csv", traj_path, "camera positions and |t_i| of both trajectories (Figures 3-5)")
        ->type_name("FILE");
    const int parsed = selfcalibCli::parse(app, argc, argv);
    if (parsed >= 0)
      return parsed;
    po.algorithm = vpMeasurementPlanner::algorithmFromName(algorithm);
    po.ratio_cost =
        ratio_cost == "spread" ? vpMeasurementPlanner::RATIO_SPREAD : vpMeasurementPlanner::RATIO_CONSECUTIVE;
    const vpRobotSelfCalibration::FocalMode mode = vpRobotSelfCalibration::focalModeFromName(focal);
    po.check();

    bench::Csv csv(csv_path, "robot,seed,noise_px,trajectory,pair,position_error_m,orientation_error_rad");
    bench::Csv traj(traj_path, "robot,seed,trajectory,pose,x,y,z,norm_t");
    std::cout << "bench-planner: initial (" << (start == "smooth" ? "smooth loop" : "random feasible")
              << ") vs optimal (planned, " << kPoses << " poses) trajectories, "
              << seeds << " seeds, focal " << focal << ", lambda " << po.lambda << "\n";

    const char *names[2] = {"initial", "optimal"};
    // rows[robot][noise][trajectory]
    std::vector<std::vector<std::vector<Row>>> rows(
        robots.size(), std::vector<std::vector<Row>>(noises.size(), std::vector<Row>(2)));
    std::vector<bench::Stats> plan_time(robots.size()), cond_before(robots.size()), cond_after(robots.size()),
        ratio_before(robots.size()), ratio_after(robots.size());
    std::vector<unsigned int> plan_failed(robots.size(), 0);

    for (size_t ri = 0; ri < robots.size(); ++ri)
      for (unsigned int seed = 1; seed <= seeds; ++seed) {
        std::cerr << robots[ri] << ", seed " << seed << "/" << seeds << ": planning    \r" << std::flush;
        vpSelfCalibSimulator::Options so;
        so.seed = seed;
        const vpSelfCalibSimulator sim0(vpKinematicChain::preset(robots[ri]), so);
        const std::vector<vpColVector> random = sim0.generateConfigurations(kPoses);
        const vpMeasurementPlanner planner(sim0.getNominalChain(), sim0.getPlannerScene());
        std::vector<vpColVector> initial = random;
        if (start == "smooth") {
          const vpColVector home = vpSelfCalibSimulator::homeConfiguration(sim0.getNominalChain());
          initial = planner.smoothTrajectory(home, vpColVector(home.size(), 0.6), kPoses,
                                             po.planning_margin < 0 ? -1.0 : sim0.getPlannerScene().margin + po.planning_margin);
          if (initial.empty()) {
            std::cerr << "\n" << robots[ri] << " seed " << seed << ": no smooth start fits\n";
            ++plan_failed[ri];
            continue;
          }
        }
        vpMeasurementPlanner::TrajectoryOptions o = po;
        o.seed = seed;
        const vpMeasurementPlanner::Result plan = planner.planTrajectory(initial, o);
        plan_time[ri].add(plan.seconds);
        if (plan.status != vpMeasurementPlanner::OK) {
          ++plan_failed[ri];
          std::cerr << "\n" << robots[ri] << " seed " << seed << ": planner: " << plan.message << "\n";
        }
        cond_before[ri].add(plan.before.condition);
        cond_after[ri].add(plan.after.condition);
        ratio_before[ri].add(plan.before.ratio);
        ratio_after[ri].add(plan.after.ratio);
        const std::vector<vpColVector> *trajectories[2] = {&initial, &plan.configurations};
        const std::vector<vpColVector> verification(random.end() - (kPoses - kCalibration), random.end());
        if (traj.enabled())
          for (int t = 0; t < 2; ++t) {
            const std::vector<vpColVector> &q = *trajectories[t];
            const vpHomogeneousMatrix T0 = sim0.getTrueChain().get_fMc(q[0]);
            for (size_t k = 0; k < q.size(); ++k) {
              const vpHomogeneousMatrix T = sim0.getTrueChain().get_fMc(q[k]);
              traj.row() << robots[ri] << "," << seed << "," << names[t] << "," << k << "," << T[0][3] << ","
                         << T[1][3] << "," << T[2][3] << ","
                         << (T.inverse() * T0).getTranslationVector().frobeniusNorm() << "\n";
            }
          }
        for (size_t ni = 0; ni < noises.size(); ++ni) {
          std::cerr << robots[ri] << ", seed " << seed << "/" << seeds << ", noise " << noises[ni] << "    \r"
                    << std::flush;
          vpSelfCalibSimulator::Options sn = so;
          sn.pixel_noise_sd = noises[ni];
          const vpSelfCalibSimulator sim(vpKinematicChain::preset(robots[ri]), sn);
          for (int t = 0; t < 2; ++t) {
            Row &row = rows[ri][ni][t];
            const std::vector<vpColVector> &q = *trajectories[t];
            const bench::PoseMeasurementErrors e = bench::poseMeasurementErrors(sim, q, mode);
            if (e.status != vpRobotSelfCalibration::OK)
              ++row.failed;
            for (size_t k = 0; k < e.position.size(); ++k) {
              row.pos.add(e.position[k]);
              row.rot.add(e.orientation[k]);
              if (csv.enabled())
                csv.row() << robots[ri] << "," << seed << "," << noises[ni] << "," << names[t] << "," << k + 2 << ","
                          << e.position[k] << "," << e.orientation[k] << "\n";
            }
            for (double r : e.scale_ratio)
              row.ratio.add(r);
            for (double f : e.fx)
              row.f.add(f);
            const std::vector<vpColVector> cal(q.begin(), q.begin() + kCalibration);
            const bench::CalibrationErrors ce = bench::calibrationErrors(sim, cal, verification, mode);
            for (size_t k = 0; k < ce.after.position_errors.size(); ++k) {
              row.held_pos.add(ce.after.position_errors[k]);
              row.held_rot.add(ce.after.rotation_errors[k]);
            }
          }
        }
      }
    std::cerr << std::string(60, ' ') << "\r";

    std::cout << "\nTable 2 (24 pose measurements of 25 poses; mean / SD over pairs and seeds) and held-out poses "
                 "(model from the first 15, 10 random verification poses)\n"
              << "| robot | noise | trajectory | position (mm) | orientation (1e-4 rad) | f_x (px) | eq. 21 ratio error (%) "
                 "| held-out position (mm) | held-out rotation (mrad) | runs not ok (doubtful or failed) |\n"
              << "|---|---|---|---|---|---|---|---|---|---|\n"
              << "| paper (PUMA 560) | I | initial | 3.0427 / 1.1051 | 1.4918 / 2.5354 | 0.2249 / 0.2374 | – | – | – | – |\n"
              << "| paper (PUMA 560) | I | optimal | 0.2809 / 0.2452 | 1.0701 / 1.4532 | 0.1539 / 0.2128 | – | – | – | – |\n"
              << "| paper (PUMA 560) | II | initial | 6.9837 / 2.6475 | 4.0876 / 7.1762 | 0.6181 / 0.7324 | – | – | – | – |\n"
              << "| paper (PUMA 560) | II | optimal | 0.3035 / 0.2826 | 2.4016 / 3.2432 | 0.3458 / 0.4791 | – | – | – | – |\n";
    for (size_t ri = 0; ri < robots.size(); ++ri)
      for (size_t ni = 0; ni < noises.size(); ++ni)
        for (int t = 0; t < 2; ++t) {
          const Row &r = rows[ri][ni][t];
          std::ostringstream noise;
          noise << noises[ni] << " px";
          std::cout << "| " << robots[ri] << " | " << noise.str() << " | " << names[t] << " | " << bench::meanSd(r.pos, 1e3, 3)
                    << " | " << bench::meanSd(r.rot, 1e4, 2) << " | "
                    << (mode == vpRobotSelfCalibration::FOCAL_KNOWN ? std::string("(known)") : bench::meanSd(r.f, 1, 2))
                    << " | " << bench::meanSd(r.ratio, 1e2, 3) << " | " << bench::meanSd(r.held_pos, 1e3, 2) << " | "
                    << bench::meanSd(r.held_rot, 1e3, 3) << " | " << r.failed << "/" << seeds << " |\n";
        }
    std::cout << "\nPlanner (25 poses, " << (po.multistart + 1) << " starts, one core), mean / SD over seeds\n"
              << "| robot | wall time (s) | ratio term before | ratio term after | cond(J) before | cond(J) after | "
                 "failed |\n|---|---|---|---|---|---|---|\n";
    for (size_t ri = 0; ri < robots.size(); ++ri)
      std::cout << "| " << robots[ri] << " | " << bench::meanSd(plan_time[ri], 1, 2) << " | " << bench::meanSd(ratio_before[ri], 1, 1)
                << " | " << bench::meanSd(ratio_after[ri], 1, 2) << " | " << bench::meanSd(cond_before[ri], 1, 1) << " | "
                << bench::meanSd(cond_after[ri], 1, 1) << " | " << plan_failed[ri] << "/" << seeds << " |\n";

    std::cout << "targets:";
    for (size_t ri = 0; ri < robots.size(); ++ri)
      for (size_t ni = 0; ni < noises.size(); ++ni)
        if (std::fabs(noises[ni] - 0.2) < 1e-12) {
          const double gain = rows[ri][ni][0].pos.mean() / rows[ri][ni][1].pos.mean();
          std::cout << " " << robots[ri] << " position error initial/optimal at noise I = " << std::setprecision(3)
                    << gain << " (>= 5: " << (gain >= 5 ? "met" : "NOT met") << ");";
        }
    double worst = 0;
    for (const auto &s : plan_time)
      for (double v : s.v)
        worst = std::max(worst, v);
    std::cout << " planning 25 poses < 10 s: " << (worst < 10 ? "met" : "NOT met") << " (max " << std::setprecision(3)
              << worst << " s)\n";
    return EXIT_SUCCESS;
  } catch (const vpException &e) {
    std::cerr << "bench-planner: " << e.getMessage() << "\n";
    return EXIT_FAILURE;
  } catch (const std::exception &e) {
    std::cerr << "bench-planner: " << e.what() << "\n";
    return EXIT_FAILURE;
  }
}
