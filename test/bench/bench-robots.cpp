/*
 * bench-robots: the default pipeline (multi-view reconstruction + kinematic bundle adjustment) on
 * other arms than the reference Viper850, 7-axis Panda (modified DH) and UR5 (standard DH) by
 * default, with the focal length known and self-calibrated, against the Cramér-Rao bound.
 *
 *   bench-robots [--seeds N] [--draws K] [--robots panda,ur5] [--noise 0.2,0.5] [--focal known,shared] [--csv FILE]
 *
 * Per robot, focal mode, noise level and seed: the reference scenario (vpSelfCalibSimulator: true
 * robot with seeded errors, 80 points and a yardstick, 25 random feasible poses, the first 15
 * calibrating, the last 10 held out), the default pipeline on the seed's noise and on K more noise
 * draws of the same geometry. Efficiency as in bench-pipelines: the RMS of the held-out relative
 * position errors (c_0 M c_i, first held-out view to the others) over all runs, divided by the RMS
 * the Cramér-Rao bound of the bundle adjustment at the truth predicts for the same pairs
 * (vpKinematicBundleAdjustment::information, propagated by relativePoseCovariance). Target <= 1.2.
 * Home configurations (the scene is placed in front of the camera there): the robot's "ready" pose.
 * A seed whose information matrix at the truth is singular has no bound: it is left out and counted.
 * runs: the runs with a model (ok or doubtful); failed: without one; doubtful: the models the
 * checked answers marked DOUBTFUL, kept in the figures.
 */
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include <visp3/core/vpException.h>
#include <visp3/selfcalib/vpKinematicBundleAdjustment.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "benchCommon.h"
#include "benchPaper.h"
#include "selfcalibCli.h"

namespace
{
constexpr unsigned int kPoses = 25, kCalibration = 15;

// A home where the wrist camera looks ahead and down at arm's length, away from singularities.
vpColVector home(const std::string &robot)
{
  if (robot == "panda")
    return vpColVector({0, -0.5, 0, -2.2, 0, 1.9, 0.785});
  if (robot == "ur5")
    return vpColVector({0.3, -1.9, 1.9, -1.3, -1.57, 0.2});
  return vpColVector();
}

vpSelfCalibSimulator makeSim(const std::string &robot, unsigned int seed, double noise)
{
  vpSelfCalibSimulator::Options so;
  so.seed = seed;
  so.pixel_noise_sd = noise;
  so.home = home(robot);
  return vpSelfCalibSimulator(vpKinematicChain::preset(robot), so);
}

vpRobotSelfCalibration::Result runDefault(const vpSelfCalibSimulator &sim, const vpSelfCalibDataset &ds,
                                          vpRobotSelfCalibration::FocalMode mode, double noise)
{
  vpRobotSelfCalibration::Options po;
  po.focal_mode = mode;
  po.num_calibration_poses = kCalibration;
  po.noise.pixel_sd = std::max(0.05, noise);
  return vpRobotSelfCalibration::run(sim.getNominalChain(), ds, po);
}
} // namespace

int main(int argc, char **argv)
{
  try {
    unsigned int seeds = 5, draws = 3;
    std::vector<std::string> robots = {"panda", "ur5"};
    std::vector<double> noises = {0.2, 0.5};
    std::vector<std::string> focals = {"known", "shared"};
    std::string csv_path;
    CLI::App app("bench-robots: the default pipeline on the Panda (7 axes) and the UR5, f known and self-calibrated,\n"
                 "against the Cramer-Rao bound.",
                 "bench-robots");
    selfcalibCli::addSeeds(app, seeds);
    app.add_option("--draws", draws, "extra noise draws of each seed's geometry (default 3)")
        ->type_name("K")
        ->check(selfcalibCli::wholeNumber());
    selfcalibCli::addRobots(app, robots, vpKinematicChain::presetNames());
    selfcalibCli::addNoiseLevels(app, noises, "pixel noise levels, above 0: the bound needs noise (default 0.2,0.5)",
                                 true);
    app.add_option("--focal", focals, "focal modes (default known,shared)")
        ->type_name("MODES")
        ->delimiter(',')
        ->check(CLI::IsMember(
            bench::focalModeNames({vpRobotSelfCalibration::FOCAL_KNOWN, vpRobotSelfCalibration::FOCAL_SHARED})));
    app.add_option("--csv", csv_path, "one row per robot, focal mode, noise, seed and draw")->type_name("FILE");
    const int parsed = selfcalibCli::parse(app, argc, argv);
    if (parsed >= 0)
      return parsed;

    bench::Csv csv(csv_path, "robot,focal,noise_px,seed,draw,status,position_rms_m,bound_rms_m,f_error_px");
    std::cout << "bench-robots: " << seeds << " seeds x " << (draws + 1) << " noise draws, " << kCalibration
              << " calibration + " << (kPoses - kCalibration) << " held-out poses, 80 points + yardstick\n\n"
              << "| robot | joints | focal | noise (px) | seeds without a bound | runs | failed | doubtful | estimated | RMS held-out position (mm) | "
                 "Cramér-Rao RMS (mm) | ratio | RMS orientation (mrad) | abs. f error (px) | target <= 1.2 |\n"
              << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    const auto t_start = std::chrono::steady_clock::now();
    bool all_met = true;
    for (const std::string &robot : robots)
      for (const std::string &focal : focals) {
        const vpRobotSelfCalibration::FocalMode mode = vpRobotSelfCalibration::focalModeFromName(focal);
        for (const double noise : noises) {
          double sum_e2 = 0, sum_pred = 0, sum_r2 = 0;
          bench::Stats f_err;
          unsigned int runs = 0, failed = 0, doubtful = 0, pairs = 0, no_bound = 0;
          size_t estimated = 0;
          for (unsigned int seed = 1; seed <= seeds; ++seed) {
            std::cerr << robot << ", f " << focal << ", " << noise << " px, seed " << seed << "/" << seeds << "      \r"
                      << std::flush;
            const vpSelfCalibSimulator clean = makeSim(robot, seed, 0.0);
            const std::vector<vpColVector> q = clean.generateConfigurations(kPoses);
            const std::vector<vpColVector> ver(q.begin() + kCalibration, q.end());
            const vpSelfCalibDataset ds0 = bench::pipelineDataset(clean, q, mode);
            const std::vector<vpSelfCalibDataset::View> held(ds0.views.begin() + kCalibration, ds0.views.end());
            // The bound at the truth, propagated to the held-out pairs (c_0, c_k).
            vpKinematicBundleAdjustment::Options bo;
            vpSelfCalibNoiseModel bn;
            bn.pixel_sd = noise;
            bo.intrinsics = mode == vpRobotSelfCalibration::FOCAL_KNOWN ? 0u : vpKinematicBundleAdjustment::FX;
            const std::vector<vpSelfCalibDataset::View> calv(ds0.views.begin(), ds0.views.begin() + kCalibration);
            const auto crb = vpKinematicBundleAdjustment::information(clean.getTrueChain(), clean.getCamera(), calv,
                                                                      clean.getYardstick(), clean.getScenePointsById(), bo, bn);
            if (!crb.has_covariance) {
              std::cerr << "\n" << robot << " seed " << seed << ": no Cramer-Rao bound (singular information at the truth); seed left out\n";
              ++no_bound;
              continue;
            }
            std::vector<double> pred(ver.size() - 1);
            double pred_sum = 0;
            for (size_t k = 1; k < ver.size(); ++k) {
              const vpMatrix C = vpKinematicBundleAdjustment::relativePoseCovariance(
                  clean.getTrueChain(), crb.identifiability.identified, crb.covariance, ver[0], ver[k]);
              pred[k - 1] = C[0][0] + C[1][1] + C[2][2];
              pred_sum += pred[k - 1];
            }
            for (unsigned int d = 0; d <= draws; ++d) {
              vpSelfCalibDataset dd = ds0;
              std::mt19937_64 rng(1000003ULL * seed + d);
              std::normal_distribution<double> n(0, noise);
              for (auto &v : dd.views)
                for (auto &o : v.points)
                  o.ip = vpImagePoint(o.ip.get_i() + n(rng), o.ip.get_j() + n(rng));
              const auto r = runDefault(clean, dd, mode, noise);
              double run_e2 = 0;
              // A doubtful model counts (its own column) and stays in the figures: the ratio compares
              // the estimator with the bound, which does not depend on the verdict (leaving it out
              // would keep the lucky draws where the check is strict, at 0.5 px with f self-calibrated).
              if (r.status == vpRobotSelfCalibration::OK || r.status == vpRobotSelfCalibration::DOUBTFUL) {
                doubtful += r.status == vpRobotSelfCalibration::DOUBTFUL;
                const vpCalibrationVerifier::Result v = bench::verifyAgainstTruth(clean, r.calibrated, r.camera, held);
                for (size_t k = 0; k < v.position_errors.size(); ++k) {
                  run_e2 += v.position_errors[k] * v.position_errors[k];
                  sum_e2 += v.position_errors[k] * v.position_errors[k];
                  sum_pred += pred[k];
                  sum_r2 += v.rotation_errors[k] * v.rotation_errors[k];
                  ++pairs;
                }
                if (mode != vpRobotSelfCalibration::FOCAL_KNOWN)
                  f_err.add(std::fabs(r.fx - clean.getCamera().get_px()));
                estimated = r.identifiability.identified.size();
                ++runs;
              } else {
                std::cerr << "\n" << robot << " seed " << seed << " draw " << d << ": "
                          << vpRobotSelfCalibration::statusName(r.status) << ": " << r.message << "\n";
                ++failed;
              }
              if (csv.enabled())
                csv.row() << robot << "," << focal << "," << noise << "," << seed << "," << d << ","
                          << vpRobotSelfCalibration::statusName(r.status) << ","
                          << std::sqrt(run_e2 / (ver.size() - 1)) << "," << std::sqrt(pred_sum / (ver.size() - 1))
                          << "," << (mode != vpRobotSelfCalibration::FOCAL_KNOWN ? std::fabs(r.fx - clean.getCamera().get_px()) : 0.0)
                          << "\n";
            }
          }
          std::cerr << std::string(70, ' ') << "\r";
          const double ratio = sum_pred > 0 ? std::sqrt(sum_e2 / sum_pred) : NAN;
          const bool met = ratio <= 1.2 && failed == 0;
          all_met = all_met && met;
          std::cout << std::fixed << "| " << robot << " | " << vpKinematicChain::preset(robot).getNumJoints() << " | "
                    << focal << " | " << std::setprecision(1) << noise << " | " << no_bound << " | " << runs << " | " << failed << " | " << doubtful << " | "
                    << estimated << " of " << vpKinematicChain::preset(robot).getNumParameters() << " | "
                    << std::setprecision(4) << 1e3 * std::sqrt(sum_e2 / std::max(1u, pairs)) << " | "
                    << 1e3 * std::sqrt(sum_pred / std::max(1u, pairs)) << " | " << std::setprecision(2) << ratio
                    << " | " << std::setprecision(4) << 1e3 * std::sqrt(sum_r2 / std::max(1u, pairs)) << " | "
                    << (mode == vpRobotSelfCalibration::FOCAL_KNOWN ? std::string("(known)") : bench::meanSd(f_err, 1, 3))
                    << " | " << (met ? "met" : "NOT met") << " |\n"
                    << std::flush;
        }
      }
    std::cout << "\ntargets: default RMS / Cramer-Rao bound <= 1.2 on every row, no failure: "
              << (all_met ? "met" : "NOT met") << "\ndone in " << std::setprecision(0)
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count() << " s\n";
    return EXIT_SUCCESS;
  } catch (const vpException &e) {
    std::cerr << "bench-robots: " << e.getStringMessage() << "\n";
  } catch (const std::exception &e) {
    std::cerr << "bench-robots: " << e.what() << "\n";
  }
  return EXIT_FAILURE;
}
