/*
 * bench-pipelines: the default pipeline (multi-view reconstruction + kinematic bundle adjustment)
 * against the paper's pipeline, the nominal model and the Cramér-Rao bound, on the same data.
 *
 *   bench-pipelines [--seeds N] [--draws K] [--robots puma560,viper850] [--noise 0.2,0.5]
 *                   [--focal shared|known] [--no-planned] [--scale yes|no] [--large POSES,POINTS] [--csv FILE]
 *
 * Reference scenario, per robot, noise level and seed: 25 random feasible poses, the first 15 for
 * calibration, the last 10 held out. Methods:
 *   nominal         the nominal model, no calibration;
 *   paper, random   the paper's procedure on the 15 random poses;
 *   paper, planned  the same on the paper's optimal trajectory planned from them (vpMeasurementPlanner);
 *   default         vpRobotSelfCalibration's default on the 15 random poses;
 *   Cramér-Rao      the bound of the bundle adjustment at the truth (vpKinematicBundleAdjustment::information),
 *                   propagated to the held-out relative poses (RMS, not mean).
 * A run counts when it gives a model: ok or DOUBTFUL (the checked-answer verdict, in its own column;
 * the estimator's accuracy against the bound does not depend on it). "failed": no model.
 * Efficiency: the default's held-out errors are dominated by one scalar per run (the scale, through
 * f), so N seeds give about N samples; the default also runs on K extra noise draws of each seed's
 * geometry (images without noise plus seeded Gaussian noise), and its RMS error over all runs is
 * compared with the bound's RMS.
 * Figures: held-out relative pose errors c_0 M c_i (first held-out view to the others), the paper's
 * 3-D yardstick error and the RMS error of all point-pair distances (points triangulated on the
 * held-out views with the calibrated model), |f - f_true|.
 * Scale: the default pipeline on 25 poses x 80 points and on POSES x POINTS (default 100 x 1000),
 * all poses calibrating, solvers on 2 threads, each stage's wall time.
 */
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <visp3/core/vpException.h>
#include <visp3/selfcalib/vpKinematicBundleAdjustment.h>
#include <visp3/selfcalib/vpMeasurementPlanner.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "benchCommon.h"
#include "benchPaper.h"
#include "selfcalibCli.h"

namespace
{
constexpr unsigned int kPoses = 25, kCalibration = 15;
enum Method { NOMINAL, PAPER_RANDOM, PAPER_PLANNED, DEFAULT, NUM_METHODS };
const char *kNames[NUM_METHODS] = {"nominal", "paper, random", "paper, planned", "default"};

struct Row {
  bench::Stats position, orientation, yardstick, distance, f; // m, rad, m, m, px
  double sum_position2 = 0, sum_orientation2 = 0;             // for RMS
  unsigned int num_pairs = 0, failed = 0, doubtful = 0; // failed: no model; doubtful: a model marked so
  void add(const vpCalibrationVerifier::Result &v)
  {
    for (size_t k = 0; k < v.position_errors.size(); ++k) {
      position.add(v.position_errors[k]);
      orientation.add(v.rotation_errors[k]);
      sum_position2 += v.position_errors[k] * v.position_errors[k];
      sum_orientation2 += v.rotation_errors[k] * v.rotation_errors[k];
      ++num_pairs;
    }
    yardstick.add(v.yardstick_error);
    distance.add(v.distance_error_rms);
  }
  double rmsPosition() const { return num_pairs ? std::sqrt(sum_position2 / num_pairs) : NAN; }
  double rmsOrientation() const { return num_pairs ? std::sqrt(sum_orientation2 / num_pairs) : NAN; }
};

struct Bound {
  double sum_position2 = 0, sum_orientation2 = 0, sum_f2 = 0;
  unsigned int num_pairs = 0, num_runs = 0, failed = 0;
};

// A run that gave a model: ok, or doubtful (every field filled, the model marked).
bool hasModel(const vpRobotSelfCalibration::Result &r)
{
  return r.status == vpRobotSelfCalibration::OK || r.status == vpRobotSelfCalibration::DOUBTFUL;
}

vpSelfCalibSimulator makeSim(const std::string &robot, unsigned int seed, double noise, unsigned int points = 80)
{
  vpSelfCalibSimulator::Options so;
  so.seed = seed;
  so.pixel_noise_sd = noise;
  so.num_points = points;
  return vpSelfCalibSimulator(vpKinematicChain::preset(robot), so);
}

vpRobotSelfCalibration::Result runPipeline(const vpSelfCalibSimulator &sim, const vpSelfCalibDataset &ds,
                                           vpRobotSelfCalibration::Method method, vpRobotSelfCalibration::FocalMode mode,
                                           unsigned int num_calibration, double noise, unsigned int threads = 1)
{
  vpRobotSelfCalibration::Options po;
  po.method = method;
  po.focal_mode = mode;
  po.num_calibration_poses = num_calibration;
  po.noise.pixel_sd = std::max(0.05, noise);
  po.paper_focal_all_views = bench::paperFocalAllViews();
  po.multiview.num_threads = threads;
  po.bundle.num_threads = threads;
  return vpRobotSelfCalibration::run(sim.getNominalChain(), ds, po);
}
} // namespace

int main(int argc, char **argv)
{
  try {
    unsigned int seeds = 10, draws = 5;
    std::vector<std::string> robots = {"puma560", "viper850"};
    std::vector<double> noises = {0.2, 0.5};
    std::string focal = "shared", csv_path, scale = "yes";
    bool no_planned = false;
    std::vector<unsigned int> large = {100, 1000};
    CLI::App app("bench-pipelines: the default pipeline against the paper's pipeline, the nominal model and the\n"
                 "Cramer-Rao bound, on the same data; then the default pipeline's wall time at scale.",
                 "bench-pipelines");
    selfcalibCli::addSeeds(app, seeds);
    app.add_option("--draws", draws, "extra noise draws of each seed's geometry for the default (default 5)")
        ->type_name("K")
        ->check(selfcalibCli::wholeNumber());
    selfcalibCli::addRobots(app, robots, vpKinematicChain::presetNames());
    selfcalibCli::addNoiseLevels(app, noises, "pixel noise levels, above 0: the bound needs noise (default 0.2,0.5)",
                                 true);
    app.add_option("--focal", focal, "shared (default) or known")
        ->type_name("MODE")
        ->check(CLI::IsMember(
            bench::focalModeNames({vpRobotSelfCalibration::FOCAL_SHARED, vpRobotSelfCalibration::FOCAL_KNOWN})));
    std::string shared_focal = "all-views";
    bench::addSharedFocal(app, shared_focal);
    app.add_flag("--no-planned", no_planned, "leave out the paper's pipeline on planned trajectories");
    app.add_option("--scale", scale, "yes (default) or no: the wall-time runs at scale")
        ->type_name("S")
        ->check(CLI::IsMember({"yes", "no"}));
    app.add_option("--large", large, "the larger scale run, POSES >= 3 and POINTS >= 8 (default 100,1000)")
        ->type_name("POSES,POINTS")
        ->delimiter(',')
        ->expected(2)
        ->check(selfcalibCli::wholeNumber());
    app.final_callback([&large] {
      if (large.size() != 2 || large[0] < 3 || large[1] < 8)
        throw CLI::ValidationError("--large", "needs POSES >= 3 and POINTS >= 8");
    });
    app.add_option("--csv", csv_path, "one row per robot, seed, noise and method")->type_name("FILE");
    const int parsed = selfcalibCli::parse(app, argc, argv);
    if (parsed >= 0)
      return parsed;
    bench::paperFocalAllViews() = shared_focal == "all-views";
    const vpRobotSelfCalibration::FocalMode mode = vpRobotSelfCalibration::focalModeFromName(focal);
    const bool planned = !no_planned;

    bench::Csv csv(csv_path, "robot,seed,noise_px,method,status,position_mean_m,orientation_mean_rad,yardstick_m,"
                             "distance_rms_m,f_error_px");
    std::cout << "bench-pipelines: " << seeds << " seeds, focal " << focal << ", " << kCalibration
              << " calibration + " << (kPoses - kCalibration) << " held-out poses, 80 points + yardstick\n";
    const auto t_start = std::chrono::steady_clock::now();
    for (const std::string &robot : robots) {
      // Plans depend on the geometry only, not on the noise: one per seed.
      std::vector<std::vector<vpColVector>> plans(seeds + 1);
      for (const double noise : noises) {
        std::vector<Row> rows(NUM_METHODS);
        Bound bound;
        struct {
          double sum_e2 = 0, sum_pred = 0;
          unsigned int runs = 0, failed = 0, doubtful = 0;
        } eff;
        for (unsigned int seed = 1; seed <= seeds; ++seed) {
          std::cerr << robot << ", " << noise << " px, seed " << seed << "/" << seeds << "      \r" << std::flush;
          const vpSelfCalibSimulator sim = makeSim(robot, seed, noise);
          const std::vector<vpColVector> q = sim.generateConfigurations(kPoses);
          const std::vector<vpColVector> cal(q.begin(), q.begin() + kCalibration), ver(q.begin() + kCalibration, q.end());
          const vpSelfCalibDataset ds = bench::pipelineDataset(sim, q, mode);
          const std::vector<vpSelfCalibDataset::View> held(ds.views.begin() + kCalibration, ds.views.end());
          const double f_true = sim.getCamera().get_px();
          auto record = [&](Method m, const vpRobotSelfCalibration::Result *r, const vpCalibrationVerifier::Result &v) {
            rows[m].add(v);
            const bool f_estimated = r && mode != vpRobotSelfCalibration::FOCAL_KNOWN;
            if (f_estimated)
              rows[m].f.add(std::fabs(r->fx - f_true));
            if (csv.enabled())
              csv.row() << robot << "," << seed << "," << noise << "," << kNames[m] << ","
                        << (r ? vpRobotSelfCalibration::statusName(r->status) : "ok") << "," << v.position_error_mean
                        << "," << v.rotation_error_mean << "," << v.yardstick_error << "," << v.distance_error_rms << ","
                        << (f_estimated ? std::fabs(r->fx - f_true) : 0.0) << "\n";
          };
          record(NOMINAL, nullptr, bench::verifyAgainstTruth(sim, sim.getNominalChain(), sim.getCamera(), held));
          bool default_ok = false, default_doubtful = false;
          vpCalibrationVerifier::Result last_default;
          for (Method m : {PAPER_RANDOM, DEFAULT}) {
            const auto r = runPipeline(sim, ds, m == DEFAULT ? vpRobotSelfCalibration::BUNDLE_ADJUSTMENT
                                                             : vpRobotSelfCalibration::PAPER,
                                       mode, kCalibration, noise);
            // A doubtful model is the estimator's answer with a warning on it: its errors count here (the
            // estimator against the bound), the verdict in its own column.
            if (hasModel(r)) {
              const vpCalibrationVerifier::Result v = bench::verifyAgainstTruth(sim, r.calibrated, r.camera, held);
              record(m, &r, v);
              rows[m].doubtful += r.status == vpRobotSelfCalibration::DOUBTFUL;
              if (m == DEFAULT) {
                default_ok = true;
                default_doubtful = r.status == vpRobotSelfCalibration::DOUBTFUL;
                last_default = v;
              }
            } else
              ++rows[m].failed;
          }
          if (planned) {
            if (plans[seed].empty()) {
              vpMeasurementPlanner::TrajectoryOptions to;
              to.seed = seed;
              const auto plan =
                  vpMeasurementPlanner(sim.getNominalChain(), sim.getPlannerScene()).planTrajectory(cal, to);
              plans[seed] = plan.status == vpMeasurementPlanner::OK ? plan.configurations : cal;
              if (plan.status != vpMeasurementPlanner::OK)
                std::cerr << "\n" << robot << " seed " << seed << ": planner: " << plan.message << " (random poses kept)\n";
            }
            std::vector<vpColVector> qp = plans[seed];
            qp.insert(qp.end(), ver.begin(), ver.end());
            const vpSelfCalibDataset dp = bench::pipelineDataset(sim, qp, mode);
            const auto r = runPipeline(sim, dp, vpRobotSelfCalibration::PAPER, mode, kCalibration, noise);
            if (hasModel(r)) {
              record(PAPER_PLANNED, &r, bench::verifyAgainstTruth(sim, r.calibrated, r.camera, held));
              rows[PAPER_PLANNED].doubtful += r.status == vpRobotSelfCalibration::DOUBTFUL;
            } else
              ++rows[PAPER_PLANNED].failed;
          }
          // Cramér-Rao bound of the bundle adjustment at the truth, propagated to the held-out poses.
          vpKinematicBundleAdjustment::Options bo;
          vpSelfCalibNoiseModel bn;
          bn.pixel_sd = noise;
          bo.intrinsics = mode == vpRobotSelfCalibration::FOCAL_KNOWN ? 0u : vpKinematicBundleAdjustment::FX;
          const std::vector<vpSelfCalibDataset::View> calv(ds.views.begin(), ds.views.begin() + kCalibration);
          const auto crb = vpKinematicBundleAdjustment::information(sim.getTrueChain(), sim.getCamera(), calv,
                                                                    sim.getYardstick(), sim.getScenePointsById(), bo, bn);
          if (!crb.has_covariance) {
            ++bound.failed;
            continue;
          }
          for (size_t k = 1; k < ver.size(); ++k) {
            const vpMatrix C = vpKinematicBundleAdjustment::relativePoseCovariance(
                sim.getTrueChain(), crb.identifiability.identified, crb.covariance, ver[0], ver[k]);
            bound.sum_position2 += C[0][0] + C[1][1] + C[2][2];
            bound.sum_orientation2 += C[3][3] + C[4][4] + C[5][5];
            ++bound.num_pairs;
          }
          bound.sum_f2 += crb.fx_sd * crb.fx_sd;
          ++bound.num_runs;
          // The default on more noise draws of the same geometry, against the same bound.
          std::vector<double> pred(ver.size() - 1);
          for (size_t k = 1; k < ver.size(); ++k) {
            const vpMatrix C = vpKinematicBundleAdjustment::relativePoseCovariance(
                sim.getTrueChain(), crb.identifiability.identified, crb.covariance, ver[0], ver[k]);
            pred[k - 1] = C[0][0] + C[1][1] + C[2][2];
          }
          auto addEfficiency = [&](const vpCalibrationVerifier::Result &v) {
            for (size_t k = 0; k < v.position_errors.size(); ++k) {
              eff.sum_e2 += v.position_errors[k] * v.position_errors[k];
              eff.sum_pred += pred[k];
            }
            ++eff.runs;
          };
          if (default_ok) {
            addEfficiency(last_default);
            eff.doubtful += default_doubtful;
          }
          const vpSelfCalibSimulator clean = makeSim(robot, seed, 0.0);
          const vpSelfCalibDataset ds0 = bench::pipelineDataset(clean, q, mode);
          for (unsigned int d = 0; d < draws; ++d) {
            vpSelfCalibDataset dd = ds0;
            std::mt19937_64 rng(1000003ULL * seed + d);
            std::normal_distribution<double> n(0, noise);
            for (auto &v : dd.views)
              for (auto &o : v.points)
                o.ip = vpImagePoint(o.ip.get_i() + n(rng), o.ip.get_j() + n(rng));
            const auto r = runPipeline(sim, dd, vpRobotSelfCalibration::BUNDLE_ADJUSTMENT, mode, kCalibration, noise);
            if (hasModel(r)) {
              addEfficiency(bench::verifyAgainstTruth(sim, r.calibrated, r.camera, held));
              eff.doubtful += r.status == vpRobotSelfCalibration::DOUBTFUL;
            } else
              ++eff.failed;
          }
        }
        std::cerr << std::string(60, ' ') << "\r";
        std::cout << "\n" << robot << ", noise " << noise << " px (mean / SD over 9 held-out pairs x " << seeds
                  << " seeds; 3-D errors and f: over seeds)\n"
                  << "| method | failed | doubtful | position (mm) | orientation (mrad) | RMS position (mm) | yardstick 3-D (mm) | "
                     "point-pair distances, RMS (mm) | abs. f error (px) |\n"
                  << "|---|---|---|---|---|---|---|---|---|\n";
        for (int m = 0; m < NUM_METHODS; ++m) {
          if (m == PAPER_PLANNED && !planned)
            continue;
          const Row &r = rows[m];
          std::ostringstream rms;
          rms << std::fixed << std::setprecision(3) << 1e3 * r.rmsPosition();
          std::cout << "| " << kNames[m] << " | " << r.failed << " | " << (m == NOMINAL ? std::string("–") : std::to_string(r.doubtful))
                    << " | " << bench::meanSd(r.position, 1e3, 3) << " | "
                    << bench::meanSd(r.orientation, 1e3, 3) << " | " << rms.str() << " | "
                    << bench::meanSd(r.yardstick, 1e3, 3) << " | " << bench::meanSd(r.distance, 1e3, 3) << " | "
                    << (m == NOMINAL ? std::string("–") : bench::meanSd(r.f, 1, 2)) << " |\n";
        }
        const double crb_pos = bound.num_pairs ? std::sqrt(bound.sum_position2 / bound.num_pairs) : NAN;
        const double crb_rot = bound.num_pairs ? std::sqrt(bound.sum_orientation2 / bound.num_pairs) : NAN;
        const double crb_f = bound.num_runs ? std::sqrt(bound.sum_f2 / bound.num_runs) : NAN;
        std::cout << std::fixed << std::setprecision(3) << "| Cramér-Rao bound (RMS) | " << bound.failed << " | – | – | "
                  << "RMS " << 1e3 * crb_rot << " | " << 1e3 * crb_pos << " | – | – | "
                  << (mode == vpRobotSelfCalibration::FOCAL_KNOWN ? std::string("(known)")
                                                                   : "sd " + std::to_string(crb_f).substr(0, 5))
                  << " |\n";
        const Row &d = rows[DEFAULT], &p = rows[PAPER_RANDOM];
        const double gain = p.position.mean() / d.position.mean();
        const double efficiency = std::sqrt(eff.sum_e2 / eff.sum_pred);
        std::cout << std::setprecision(3) << "default over " << eff.runs << " runs (" << seeds << " seeds x "
                  << (draws + 1) << " noise draws, " << eff.failed << " failed, " << eff.doubtful << " of the others doubtful): RMS held-out position "
                  << 1e3 * std::sqrt(eff.sum_e2 / (9.0 * eff.runs)) << " mm, Cramer-Rao RMS "
                  << 1e3 * std::sqrt(eff.sum_pred / (9.0 * eff.runs)) << " mm\n";
        std::cout << std::setprecision(2) << "targets: default vs paper (random) held-out position: ";
        if (std::isfinite(gain))
          std::cout << gain << "x lower (target 8x: " << (gain >= 8 ? "met" : "NOT met") << ")";
        else
          std::cout << "no model from the paper's method (every run failed)";
        std::cout << "; default RMS / Cramer-Rao bound "
                  << efficiency << " (target <= 1.2: " << (efficiency <= 1.2 ? "met" : "NOT met") << ")";
        if (mode != vpRobotSelfCalibration::FOCAL_KNOWN && noise == 0.2)
          std::cout << "; f error " << d.f.mean() << " px (target < 0.1 px: " << (d.f.mean() < 0.1 ? "met" : "NOT met")
                    << "; bound sd " << crb_f << " px)";
        std::cout << "\n";
      }
    }

    if (scale == "yes") {
      std::cout << "\nScale: the default pipeline, all poses calibrating, focal " << focal
                << ", noise 0.2 px, 2 solver threads, wall time (s)\n";
      const unsigned int sizes[2][2] = {{25, 80}, {large[0], large[1]}};
      for (const auto &sz : sizes) {
        const vpSelfCalibSimulator sim = makeSim(robots[0], 1, 0.2, sz[1]);
        const auto tg = std::chrono::steady_clock::now();
        const vpSelfCalibDataset ds = bench::pipelineDataset(sim, sim.generateConfigurations(sz[0]), mode);
        const double gen = std::chrono::duration<double>(std::chrono::steady_clock::now() - tg).count();
        const auto r = runPipeline(sim, ds, vpRobotSelfCalibration::BUNDLE_ADJUSTMENT, mode, sz[0], 0.2, 2);
        std::cout << robots[0] << " " << sz[0] << " poses x " << sz[1] << " points (" << r.bundle.num_observations
                  << " observations): " << vpRobotSelfCalibration::statusName(r.status) << ", total " << std::setprecision(2)
                  << r.seconds << " s (target " << (sz[0] <= 25 ? "2" : "60") << " s: "
                  << (r.seconds < (sz[0] <= 25 ? 2.0 : 60.0) ? "met" : "NOT met") << ");";
        for (const auto &st : r.stage_seconds)
          std::cout << " " << st.first << " " << std::setprecision(3) << st.second << ";";
        std::cout << " (simulation, not counted: " << std::setprecision(2) << gen << ")\n";
      }
    }
    std::cout << "\ndone in " << std::setprecision(0)
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count() << " s\n";
    return EXIT_SUCCESS;
  } catch (const vpException &e) {
    std::cerr << "bench-pipelines: " << e.getStringMessage() << "\n";
  } catch (const std::exception &e) {
    std::cerr << "bench-pipelines: " << e.what() << "\n";
  }
  return EXIT_FAILURE;
}
