/*
 * bench-paper: the paper's simulation study (Section 4.2) with its method (vpRobotSelfCalibration)
 * on the reference scenario (README, "Reference scenario"), random ("initial") trajectories.
 *
 *   bench-paper [--seeds N] [--noise 0,0.2,0.5] [--robots puma560,viper850] [--focal shared,known]
 *               [--csv FILE] [-h]
 *
 * For every robot, noise level, focal mode and seed, 25 configurations are drawn, then
 *   - Table 2: the 24 scaled pose measurements c_iMc_1 of the pairs (1, i) (refined factor method,
 *     eq. 21 ratios, yardstick scale) against the truth: position (mm), orientation (1e-4 rad),
 *     |f_x - f| (px), and the error of the eq. 21 ratio |(|t_i|/|t_1|) / ratio_i - 1| (true vs
 *     nominal), which is what the planned trajectory of the paper reduces;
 *   - Figure 6: the model calibrated on the first n poses (n = 6..15), verified on the last 10:
 *     the paper's 3-D error (yardstick length, triangulated with the calibrated model and camera),
 *     RMS error of all point-pair distances, and the held-out relative pose errors c_0Mc_i;
 *   - the wall time of the whole pipeline (15 calibration poses).
 */
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <visp3/selfcalib/vpSelfCalibException.h>

#include "benchCommon.h"
#include "benchPaper.h"
#include "selfcalibCli.h"

namespace
{
const unsigned int kPoses = 25, kVerification = 10, kMinCalibration = 6;



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
  bench::Stats pos, rot, f, ratio, seconds;
  unsigned int failed = 0;
};

struct Figure6Cell {
  bench::Stats yardstick, distance, held_pos, held_rot;
  unsigned int failed = 0;
};
} // namespace

int main(int argc, char **argv)
{
  try {
    unsigned int seeds = 10;
    std::vector<double> noises = {0, 0.2, 0.5};
    std::vector<std::string> robots = {"puma560", "viper850"}, focals = {"shared", "known"};
    std::string csv_path;
    CLI::App app("bench-paper: the paper's simulation study (Section 4.2) with its method on the reference scenario,\n"
                 "random (\"initial\") trajectories: Table 2, Figure 6 and the wall time.",
                 "bench-paper");
    selfcalibCli::addSeeds(app, seeds);
    selfcalibCli::addNoiseLevels(app, noises, "pixel noise levels (default 0,0.2,0.5: noise-free, the paper's I and II)");
    selfcalibCli::addRobots(app, robots, vpKinematicChain::presetNames());
    app.add_option("--focal", focals,
                   "focal modes: shared (self-calibrated, default), known, per-pair (the\n"
                   "paper; degenerate on this scenario) (default shared,known)")
        ->type_name("A,B")
        ->delimiter(',')
        ->check(CLI::IsMember(
            bench::focalModeNames({vpRobotSelfCalibration::FOCAL_SHARED, vpRobotSelfCalibration::FOCAL_KNOWN,
                                   vpRobotSelfCalibration::FOCAL_PER_PAIR})));
    app.add_option("--csv", csv_path, "one row per robot, noise, focal mode, seed and experiment")->type_name("FILE");
    const int parsed = selfcalibCli::parse(app, argc, argv);
    if (parsed >= 0)
      return parsed;
    std::vector<vpRobotSelfCalibration::FocalMode> modes;
    for (const std::string &f : focals)
      modes.push_back(vpRobotSelfCalibration::focalModeFromName(f));

    bench::Csv csv(csv_path, "robot,noise_px,focal,seed,experiment,n_calibration,index,position_m,orientation_rad,"
                             "f_error_px,ratio_error,yardstick_error_m,distance_rms_m,seconds");
    std::cout << "bench-paper: the paper's method on random (\"initial\") trajectories of " << kPoses << " poses, "
              << seeds << " seeds, 80 points + yardstick, f = 1500 px\n";

    // [robot][noise][focal]
    std::vector<std::vector<std::vector<Cell>>> table(
        robots.size(), std::vector<std::vector<Cell>>(noises.size(), std::vector<Cell>(modes.size())));
    std::vector<std::vector<std::vector<std::vector<Figure6Cell>>>> fig6(
        robots.size(), std::vector<std::vector<std::vector<Figure6Cell>>>(
                           noises.size(), std::vector<std::vector<Figure6Cell>>(
                                              modes.size(), std::vector<Figure6Cell>(kPoses - kVerification + 1))));
    std::vector<std::vector<Figure6Cell>> nominal(robots.size(), std::vector<Figure6Cell>(noises.size()));

    for (size_t ri = 0; ri < robots.size(); ++ri)
      for (size_t ni = 0; ni < noises.size(); ++ni)
        for (unsigned int seed = 1; seed <= seeds; ++seed) {
          std::cerr << robots[ri] << ", noise " << noises[ni] << " px, seed " << seed << "/" << seeds << "    \r"
                    << std::flush;
          vpSelfCalibSimulator::Options so;
          so.seed = seed;
          so.pixel_noise_sd = noises[ni];
          const vpSelfCalibSimulator sim(vpKinematicChain::preset(robots[ri]), so);
          const std::vector<vpColVector> q = sim.generateConfigurations(kPoses);
          const std::vector<vpColVector> verification(q.end() - kVerification, q.end());
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
          for (size_t fi = 0; fi < modes.size(); ++fi) {
            const std::string prefix = robots[ri] + "," + std::to_string(noises[ni]) + "," + focals[fi] + "," +
                                       std::to_string(seed) + ",";
            // Table 2 on the 24 pairs.
            const bench::PoseMeasurementErrors e = bench::poseMeasurementErrors(sim, q, modes[fi]);
            Cell &c = table[ri][ni][fi];
            if (e.status != vpRobotSelfCalibration::OK)
              ++c.failed;
            for (size_t k = 0; k < e.position.size(); ++k) {
              c.pos.add(e.position[k]);
              c.rot.add(e.orientation[k]);
              if (csv.enabled())
                csv.row() << prefix << "table2," << kPoses << "," << k << "," << e.position[k] << ","
                          << e.orientation[k] << ",,,,,\n";
            }
            for (double r : e.scale_ratio)
              c.ratio.add(r);
            for (double f : e.fx)
              c.f.add(f);
            // Figure 6: n calibration poses, the last 10 verify.
            for (unsigned int n = kMinCalibration; n <= kPoses - kVerification; ++n) {
              const std::vector<vpColVector> cal(q.begin(), q.begin() + n);
              const bench::CalibrationErrors ce = bench::calibrationErrors(sim, cal, verification, modes[fi]);
              Figure6Cell &g = fig6[ri][ni][fi][n];
              if (n == kPoses - kVerification)
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
                csv.row() << prefix << "figure6," << n << ",,,," << ",," << ce.after.yardstick_error << ","
                          << ce.after.distance_error_rms << "," << ce.seconds << "\n";
            }
          }
        }
    std::cerr << std::string(60, ' ') << "\r";

    // Table 2.
    std::cout << "\nTable 2: errors of the 24 pose measurements c_iMc_1 (mean / SD over pairs and seeds; f_x: over "
                 "seeds, or pairs with per-pair f)\n"
              << "| robot | noise | focal | position (mm) | orientation (1e-4 rad) | f_x (px) | eq. 21 ratio error (%) "
                 "| failed runs |\n"
              << "|---|---|---|---|---|---|---|---|\n"
              << "| paper (PUMA 560) | I | per pair | 3.0427 / 1.1051 | 1.4918 / 2.5354 | 0.2249 / 0.2374 | – | – |\n"
              << "| paper (PUMA 560) | II | per pair | 6.9837 / 2.6475 | 4.0876 / 7.1762 | 0.6181 / 0.7324 | – | – |\n";
    for (size_t ri = 0; ri < robots.size(); ++ri)
      for (size_t ni = 0; ni < noises.size(); ++ni)
        for (size_t fi = 0; fi < modes.size(); ++fi) {
          const Cell &c = table[ri][ni][fi];
          std::cout << "| " << robots[ri] << " | " << noiseName(noises[ni]) << " | " << focals[fi] << " | "
                    << bench::meanSd(c.pos, 1e3, 3) << " | " << bench::meanSd(c.rot, 1e4, 2) << " | "
                    << (modes[fi] == vpRobotSelfCalibration::FOCAL_KNOWN ? std::string("(known)") : bench::meanSd(c.f, 1, 2))
                    << " | " << bench::meanSd(c.ratio, 1e2, 3) << " | " << c.failed << "/" << seeds << " |\n";
        }

    // Figure 6.
    std::cout << "\nFigure 6: model calibrated on the first n poses, verified on the last " << kVerification
              << " (mean / SD over seeds; held-out poses: over poses and seeds)\n"
              << "| robot | noise | focal | n | yardstick 3-D error (mm) | point-pair distance RMS (mm) | held-out "
                 "position (mm) | held-out rotation (mrad) | failed runs |\n"
              << "|---|---|---|---|---|---|---|---|---|\n";
    for (size_t ri = 0; ri < robots.size(); ++ri)
      for (size_t ni = 0; ni < noises.size(); ++ni) {
        const Figure6Cell &b = nominal[ri][ni];
        std::cout << "| " << robots[ri] << " | " << noiseName(noises[ni]) << " | – | nominal | "
                  << bench::meanSd(b.yardstick, 1e3, 3) << " | " << bench::meanSd(b.distance, 1e3, 3) << " | "
                  << bench::meanSd(b.held_pos, 1e3, 2) << " | " << bench::meanSd(b.held_rot, 1e3, 3) << " | – |\n";
        for (size_t fi = 0; fi < modes.size(); ++fi)
          for (unsigned int n = kMinCalibration; n <= kPoses - kVerification; ++n) {
            const Figure6Cell &g = fig6[ri][ni][fi][n];
            std::cout << "| " << robots[ri] << " | " << noiseName(noises[ni]) << " | " << focals[fi] << " | " << n
                      << " | " << bench::meanSd(g.yardstick, 1e3, 3) << " | " << bench::meanSd(g.distance, 1e3, 3) << " | "
                      << bench::meanSd(g.held_pos, 1e3, 2) << " | " << bench::meanSd(g.held_rot, 1e3, 3) << " | " << g.failed
                      << "/" << seeds << " |\n";
          }
      }

    std::cout << "\nPipeline wall time (15 calibration poses, 10 verification poses), mean / SD over seeds (s)\n"
              << "| robot | noise | focal | time (s) |\n|---|---|---|---|\n";
    for (size_t ri = 0; ri < robots.size(); ++ri)
      for (size_t ni = 0; ni < noises.size(); ++ni)
        for (size_t fi = 0; fi < modes.size(); ++fi)
          std::cout << "| " << robots[ri] << " | " << noiseName(noises[ni]) << " | " << focals[fi] << " | "
                    << bench::meanSd(table[ri][ni][fi].seconds, 1, 3) << " |\n";
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
