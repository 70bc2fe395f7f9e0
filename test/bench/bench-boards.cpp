/*
 * bench-boards: eye-in-hand self-calibration on a ChArUco board, simulated end to end (images
 * rendered, corners detected, the bundle adjustment on them), against the Cramér-Rao bound, with the
 * board's layout unknown (its corners are scene points) and known (calibrate --board-geometry).
 *
 *   bench-boards [--seeds N] [--draws K] [--poses P] [--held-out H] [--noise PX] [--focal known|shared]
 *                [--csv FILE]
 *
 * Per seed: the reference scenario's Viper850 (seeded robot errors), P random poses that see the
 * scene, the first P - H calibrating, the last H held out; the scene is simulate --target charuco's
 * board (7 x 5 squares of 2 cm, DICT_6X6_250) rendered by vpSelfCalibRenderer (blur 0.7 px, noise 2
 * grey levels), K noise draws of the same geometry (renderer seeds). The corners are vpBoardDetector's
 * (ChArUco); their error against the renderer's truth is measured per draw. Gaussian noise of --noise
 * px (seeded) is added to them, a camera noisier than the renderer's 0.01 px: the pixel sd of the
 * run and of its bound is sqrt(measured^2 + noise^2). Figures: held-out relative pose errors c_0 M c_i (first held-out
 * view to the others), RMS over all runs, against the RMS of the Cramér-Rao bound of the same data
 * (vpKinematicBundleAdjustment::information at the truth, the layout prior included when known,
 * propagated to the same pairs). Then the workspace check against the truth: each run's error on the
 * camera's motions over the joint limits (bench::workspaceError), position and rotation, against the
 * nominal model's, beside the check's verdict and predictions (Result::workspace).
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
#include <visp3/core/vpMeterPixelConversion.h>
#include <visp3/selfcalib/vpBoardDetector.h>
#include <visp3/selfcalib/vpKinematicBundleAdjustment.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibRenderer.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "benchCommon.h"
#include "selfcalibCli.h"

namespace
{
const char *kBoard = "charuco:7x5:0.02:0.015:DICT_6X6_250"; // simulate --target charuco's board

struct Row {
  double sum_e2 = 0, sum_pred = 0; // held-out position errors and bound variances, m^2
  unsigned int pairs = 0, runs = 0, failed = 0, doubtful = 0;
  // The workspace check (workspace-worse-than-nominal) against the truth: the camera's motions over the
  // joint limits, position and rotation (a run is truly worse when either error exceeds the nominal
  // model's); sums of squares of the true and predicted errors.
  unsigned int ws_doubt = 0, ws_doubt_worse = 0, ws_pass = 0, ws_pass_worse = 0;
  double ws_true_t2 = 0, ws_pred_t2 = 0, ws_nom_t2 = 0, ws_est_t2 = 0;
  double ws_true_r2 = 0, ws_pred_r2 = 0, ws_nom_r2 = 0, ws_est_r2 = 0;
  double rms() const { return pairs ? std::sqrt(sum_e2 / pairs) : NAN; }
  double bound() const { return pairs ? std::sqrt(sum_pred / pairs) : NAN; }
};

// The detected corners of the calibration views, and their RMS error against the truth (px).
std::vector<vpSelfCalibDataset::View> detectViews(const vpSelfCalibSimulator &sim, const vpSelfCalibRenderer &renderer,
                                                  const vpBoardDetector &det, const std::vector<vpColVector> &q,
                                                  const std::map<int, vpColVector> &truth, double &rms)
{
  const std::vector<vpImage<unsigned char>> images = renderer.render(q, 2);
  std::vector<vpSelfCalibDataset::View> views;
  double sum = 0;
  size_t n = 0;
  for (size_t k = 0; k < q.size(); ++k) {
    const vpBoardDetector::Result r = det.detect(images[k]);
    if (!r.found)
      continue;
    vpSelfCalibDataset::View v;
    v.q = q[k];
    v.points = r.corners;
    const vpHomogeneousMatrix cMf = sim.getTrueChain().get_fMc(q[k]).inverse();
    for (const vpSelfCalibDataset::Observation &o : r.corners) {
      const vpColVector X = cMf * vpColVector({truth.at(o.id)[0], truth.at(o.id)[1], truth.at(o.id)[2], 1.0});
      vpImagePoint t;
      vpMeterPixelConversion::convertPoint(sim.getCamera(), X[0] / X[2], X[1] / X[2], t);
      sum += vpImagePoint::sqrDistance(t, o.ip);
      ++n;
    }
    views.push_back(v);
  }
  rms = n ? std::sqrt(sum / (2.0 * n)) : NAN; // per coordinate
  return views;
}

// Held-out relative pose position errors of `model` (m), pairs (0, i).
std::vector<double> heldOutErrors(const vpKinematicChain &model, const vpKinematicChain &truth,
                                  const std::vector<vpColVector> &held)
{
  std::vector<double> e;
  for (size_t k = 1; k < held.size(); ++k) {
    const vpHomogeneousMatrix m = model.get_fMc(held[0]).inverse() * model.get_fMc(held[k]);
    const vpHomogeneousMatrix t = truth.get_fMc(held[0]).inverse() * truth.get_fMc(held[k]);
    e.push_back((m.getTranslationVector() - t.getTranslationVector()).frobeniusNorm());
  }
  return e;
}
} // namespace

int main(int argc, char **argv)
{
  try {
    unsigned int seeds = 5, draws = 2, poses = 20, held_out = 6, first_seed = 1;
    std::string focal = "known", csv_path;
    double noise = 0.2;
    CLI::App app("bench-boards: eye-in-hand self-calibration on a rendered ChArUco board against the Cramer-Rao\n"
                 "bound, its layout unknown and known (--board-geometry).",
                 "bench-boards");
    selfcalibCli::addSeeds(app, seeds);
    app.add_option("--first-seed", first_seed, "the first seed (geometry; default 1): more seeds in another run")
        ->type_name("S")
        ->check(selfcalibCli::wholeNumber(1, 100000));
    app.add_option("--draws", draws, "noise draws of each seed's geometry (default 2)")
        ->type_name("K")
        ->check(selfcalibCli::wholeNumber(1, 100));
    app.add_option("--poses", poses, "poses per seed, 8 to 100 (default 20)")
        ->type_name("P")
        ->check(selfcalibCli::wholeNumber(8, 100));
    app.add_option("--held-out", held_out, "of them held out, 3 to P - 5 (default 6)")
        ->type_name("H")
        ->check(selfcalibCli::wholeNumber(3, 95));
    app.add_option("--noise", noise, "Gaussian noise added to the detected corners, px (default 0.2; 0: the rendered\n"
                                     "images' own error only)")
        ->type_name("PX")
        ->check(selfcalibCli::number(0, false, 10));
    app.add_option("--focal", focal, "known (default) or shared")
        ->type_name("MODE")
        ->check(CLI::IsMember({"known", "shared"}));
    app.add_option("--csv", csv_path, "one row per seed, draw and layout")->type_name("FILE");
    app.final_callback([&] {
      if (held_out + 5 > poses)
        throw CLI::ValidationError("--held-out", "leave 5 or more poses to calibrate");
    });
    const int parsed = selfcalibCli::parse(app, argc, argv);
    if (parsed >= 0)
      return parsed;
    const vpRobotSelfCalibration::FocalMode mode = vpRobotSelfCalibration::focalModeFromName(focal);
    const vpBoardDetector det(vpBoardDetector::parse(kBoard));
    const std::map<int, vpColVector> layout = det.getLayout();
    bench::Csv csv(csv_path, "seed,draw,layout,status,detector_rms_px,pixel_sd_px,heldout_rms_m,bound_rms_m,"
                             "workspace_doubt,workspace_true_m,workspace_true_rad,workspace_nominal_m,workspace_nominal_rad,"
                             "workspace_predicted_m,workspace_predicted_rad,workspace_nominal_estimated_m,"
                             "workspace_nominal_estimated_rad,workspace_chance_worse_t,workspace_chance_worse_r");
    std::cout << "bench-boards: " << kBoard << " rendered, viper850, " << seeds << " seeds x " << draws
              << " noise draws, " << poses - held_out << " calibration + " << held_out << " held-out poses, focal "
              << focal << ", " << noise << " px added to the corners\n";
    const auto t_start = std::chrono::steady_clock::now();
    Row rows[2]; // layout unknown, known
    bench::Stats detector;
    for (unsigned int seed = first_seed; seed < first_seed + seeds; ++seed) {
      vpSelfCalibSimulator::Options so;
      so.seed = seed;
      const vpSelfCalibSimulator sim(vpKinematicChain::preset("viper850"), so);
      const std::vector<vpColVector> q = sim.generateConfigurations(poses);
      const std::vector<vpColVector> cal(q.begin(), q.end() - held_out), held(q.end() - held_out, q.end());
      for (unsigned int d = 0; d < draws; ++d) {
        std::cerr << "seed " << seed << "/" << first_seed + seeds - 1 << ", draw " << d + 1 << "/" << draws << "      \r" << std::flush;
        vpSelfCalibRenderer::Options ro;
        ro.scene = vpSelfCalibRenderer::CHARUCO;
        ro.seed = 1000 * seed + d;
        const vpSelfCalibRenderer renderer(sim, ro);
        std::map<int, vpColVector> truth;
        for (const auto &p : layout) {
          const vpColVector X = renderer.getBoardPose() * vpColVector({p.second[0], p.second[1], p.second[2], 1.0});
          truth[p.first] = vpColVector({X[0], X[1], X[2]});
        }
        vpSelfCalibDataset ds;
        ds.cam = sim.getCamera();
        ds.focal_known = mode == vpRobotSelfCalibration::FOCAL_KNOWN;
        if (!ds.focal_known)
          ds.cam.initPersProjWithoutDistortion(0.93 * ds.cam.get_px(), 0.93 * ds.cam.get_py(), ds.cam.get_u0(),
                                               ds.cam.get_v0());
        double measured = NAN;
        ds.views = detectViews(sim, renderer, det, cal, truth, measured);
        ds.yardstick = det.getYardstick();
        detector.add(measured);
        std::mt19937_64 rng(7919ULL * seed + d);
        std::normal_distribution<double> gauss(0, noise > 0 ? noise : 1);
        if (noise > 0)
          for (vpSelfCalibDataset::View &v : ds.views)
            for (vpSelfCalibDataset::Observation &o : v.points)
              o.ip = vpImagePoint(o.ip.get_i() + gauss(rng), o.ip.get_j() + gauss(rng));
        const double sd = std::sqrt(measured * measured + noise * noise);
        for (int known = 0; known < 2; ++known) {
          vpRobotSelfCalibration::Options po;
          po.focal_mode = mode;
          po.num_calibration_poses = static_cast<unsigned int>(ds.views.size());
          po.noise.pixel_sd = sd; // the detector's measured error, stated
          if (known)
            po.bundle.known_points = layout;
          const vpRobotSelfCalibration::Result r = vpRobotSelfCalibration::run(sim.getNominalChain(), ds, po);
          Row &row = rows[known];
          ++row.runs;
          if (r.status != vpRobotSelfCalibration::OK)
            std::cerr << "\nseed " << seed << ", draw " << d + 1 << ", layout " << (known ? "known" : "unknown") << ": "
                      << vpRobotSelfCalibration::statusName(r.status) << ": " << r.message << "\n";
          if (r.status != vpRobotSelfCalibration::OK && r.status != vpRobotSelfCalibration::DOUBTFUL) {
            ++row.failed;
            continue;
          }
          row.doubtful += r.status == vpRobotSelfCalibration::DOUBTFUL;
          bench::MotionRms cal{NAN, NAN}, nom{NAN, NAN};
          bool doubt = false;
          if (r.workspace.computed) {
            doubt = bench::hasFinding(r, "workspace-worse-than-nominal");
            cal = bench::workspaceError(r.calibrated, sim.getTrueChain());
            nom = bench::workspaceError(sim.getNominalChain(), sim.getTrueChain());
            const bool worse = cal.t > nom.t || cal.r > nom.r;
            (doubt ? row.ws_doubt : row.ws_pass) += 1;
            (doubt ? row.ws_doubt_worse : row.ws_pass_worse) += worse;
            row.ws_true_t2 += cal.t * cal.t;
            row.ws_true_r2 += cal.r * cal.r;
            row.ws_nom_t2 += nom.t * nom.t;
            row.ws_nom_r2 += nom.r * nom.r;
            row.ws_pred_t2 += r.workspace.calibrated_t * r.workspace.calibrated_t;
            row.ws_pred_r2 += r.workspace.calibrated_r * r.workspace.calibrated_r;
            row.ws_est_t2 += r.workspace.nominal_t * r.workspace.nominal_t;
            row.ws_est_r2 += r.workspace.nominal_r * r.workspace.nominal_r;
          }
          vpKinematicBundleAdjustment::Options bo;
          bo.intrinsics = mode == vpRobotSelfCalibration::FOCAL_KNOWN ? 0u : vpKinematicBundleAdjustment::FX;
          if (known)
            bo.known_points = layout;
          vpSelfCalibNoiseModel bn;
          bn.pixel_sd = sd;
          const auto crb = vpKinematicBundleAdjustment::information(sim.getTrueChain(), sim.getCamera(), ds.views,
                                                                    ds.yardstick, truth, bo, bn);
          if (!crb.has_covariance) {
            ++row.failed;
            continue;
          }
          const std::vector<double> e = heldOutErrors(r.calibrated, sim.getTrueChain(), held);
          double run_e2 = 0, run_pred = 0;
          for (size_t k = 1; k < held.size(); ++k) {
            const vpMatrix C = vpKinematicBundleAdjustment::relativePoseCovariance(
                sim.getTrueChain(), crb.identifiability.identified, crb.covariance, held[0], held[k]);
            run_pred += C[0][0] + C[1][1] + C[2][2];
            run_e2 += e[k - 1] * e[k - 1];
          }
          row.sum_e2 += run_e2;
          row.sum_pred += run_pred;
          row.pairs += static_cast<unsigned int>(e.size());
          if (csv.enabled())
            csv.row() << seed << "," << d << "," << (known ? "known" : "unknown") << ","
                      << vpRobotSelfCalibration::statusName(r.status) << "," << measured << "," << sd << ","
                      << std::sqrt(run_e2 / e.size()) << "," << std::sqrt(run_pred / e.size()) << "," << doubt << ","
                      << cal.t << "," << cal.r << "," << nom.t << "," << nom.r << "," << r.workspace.calibrated_t << ","
                      << r.workspace.calibrated_r << "," << r.workspace.nominal_t << "," << r.workspace.nominal_r << ","
                      << r.workspace.worse_t << "," << r.workspace.worse_r << "\n";
        }
      }
    }
    std::cerr << "\n";
    std::cout << "\nHeld-out relative pose position error (RMS over every pair of every run, um) against the "
                 "Cramer-Rao bound (RMS), corners from the rendered images (detector error "
              << bench::meanSd(detector, 1, 4) << " px per coordinate, mean / sd over the draws; " << noise
              << " px added)\n\n"
              << "| board | layout | focal | runs | failed | doubtful | held-out RMS (um) | Cramer-Rao RMS (um) | "
                 "ratio |\n|---|---|---|---|---|---|---|---|---|\n";
    const char *names[2] = {"unknown", "known (--board-geometry)"};
    for (int known = 0; known < 2; ++known) {
      const Row &r = rows[known];
      std::cout << std::fixed << std::setprecision(2) << "| charuco 7x5 | " << names[known] << " | " << focal << " | "
                << r.runs << " | " << r.failed << " | " << r.doubtful << " | " << 1e6 * r.rms() << " | "
                << 1e6 * r.bound() << " | " << r.rms() / r.bound() << " |\n";
    }
    std::cout << "\nThe same runs, the workspace check (workspace-worse-than-nominal) against the truth: the camera's "
                 "motions between configurations drawn within the joint limits; a run is truly worse when its RMS "
                 "error there, in position or in rotation, exceeds the nominal model's:\n\n"
              << "| board | layout | focal | runs judged | doubtful by it | of those, truly worse | passed | of those, "
                 "truly worse | calibrated RMS: true / predicted (mm, mrad) | nominal RMS: true / estimated (mm, mrad) "
                 "|\n|---|---|---|---|---|---|---|---|---|---|\n";
    for (int known = 0; known < 2; ++known) {
      const Row &r = rows[known];
      const double n = std::max(1u, r.ws_doubt + r.ws_pass);
      const auto mm = [n](double s2) { return 1e3 * std::sqrt(s2 / n); };
      std::cout << std::fixed << std::setprecision(2) << "| charuco 7x5 | " << names[known] << " | " << focal << " | "
                << r.ws_doubt + r.ws_pass << " | " << r.ws_doubt << " | " << r.ws_doubt_worse << " | " << r.ws_pass
                << " | " << r.ws_pass_worse << " | " << mm(r.ws_true_t2) << " / " << mm(r.ws_pred_t2) << ", "
                << mm(r.ws_true_r2) << " / " << mm(r.ws_pred_r2) << " | " << mm(r.ws_nom_t2) << " / "
                << mm(r.ws_est_t2) << ", " << mm(r.ws_nom_r2) << " / " << mm(r.ws_est_r2) << " |\n";
    }
    std::cout << std::setprecision(2) << "\ntargets: board mode RMS / Cramer-Rao bound, layout unknown "
              << rows[0].rms() / rows[0].bound() << " (target <= 1.2: "
              << (rows[0].rms() / rows[0].bound() <= 1.2 ? "met" : "NOT met") << "), layout known "
              << rows[1].rms() / rows[1].bound() << " (target <= 1.2: "
              << (rows[1].rms() / rows[1].bound() <= 1.2 ? "met" : "NOT met") << "); layout known no worse than unknown: "
              << 1e6 * rows[1].rms() << " vs " << 1e6 * rows[0].rms() << " um ("
              << (rows[1].rms() <= rows[0].rms() ? "met" : "NOT met") << "); every run a model: "
              << (rows[0].failed + rows[1].failed == 0 ? "met" : "NOT met") << "\n";
    std::cout << "\ndone in " << std::setprecision(0)
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count() << " s\n";
    return EXIT_SUCCESS;
  } catch (const vpException &e) {
    std::cerr << "bench-boards: " << e.getStringMessage() << "\n";
  } catch (const std::exception &e) {
    std::cerr << "bench-boards: " << e.what() << "\n";
  }
  return EXIT_FAILURE;
}
