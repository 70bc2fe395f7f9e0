/*!
  \example tutorial-selfcalib-viper850.cpp

  Main job of ViSP SelfCalib: builds the reference scenario on ViSP's simulated Viper850, prints
  what self-calibration starts from (the robot, the true seeded errors of the simulated arm, the
  planned poses and what the camera sees at each, how far the nominal model is from the true
  camera poses), acquires rendered images at the poses through the simulated robot and finds the
  correspondences and the yardstick in them (--acquisition dots: the paper's experiment, dot grids
  on a non-planar object; --acquisition points: the simulator's exact correspondences with pixel
  noise instead), self-calibrates on the first 15 poses (default:
  multi-view reconstruction + kinematic bundle adjustment; --method paper: the paper's procedure),
  verifies on the others and writes the report (--report DIR, default selfcalib-report) and, with
  --results FILE, the run's results.yaml (vpSelfCalibResultsFile, the schema visp-selfcalib calibrate writes).

    tutorial-selfcalib-viper850 [--robot viper850|puma560] [--seed N] [--poses N] [--noise PX]
                                [--method bundle|paper] [--focal known|shared|per-pair]
                                [--plan auto|paper|observability|none] [--acquisition images|dots|points]
                                [--report DIR] [--results FILE] [--figure6-step STEP] [-c] [-d] [-h]

  -c and -d are ViSP's tutorial flags (no click, no display); this program never opens a display.
  The command line is CLI11's: --help lists every option; a wrong option or value exits with code 2.
*/
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <iomanip>
#include <optional>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <visp3/core/vpMath.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>
#include <visp3/selfcalib/vpSelfCalibSimulatorViper850.h>
#include <visp3/selfcalib/vpCalibrationVerifier.h>
#include <visp3/selfcalib/vpMeasurementPlanner.h>
#include <visp3/selfcalib/vpFeatureFrontEnd.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibImageCorrespondences.h>
#include <visp3/selfcalib/vpSelfCalibRenderer.h>
#include <visp3/selfcalib/vpSelfCalibReport.h>
#include <visp3/selfcalib/vpSelfCalibResultsFile.h>

#include "selfcalibCli.h"

namespace
{
struct Args {
  std::string robot_name = "viper850";
  vpSelfCalibSimulator::Options opt;
  unsigned int poses = 25;
  std::string focal = "known", plan = "auto", method = "bundle", acquisition = "images", report = "selfcalib-report";
  unsigned int figure6_step = 3;
  std::string results; //!< results.yaml of the run; empty: not written
};

//! The command line; returns -1 to go on, else the exit code (0 after --help, 2 on a usage error).
int parseCommandLine(int argc, char **argv, Args &a)
{
  CLI::App app("Main job of ViSP SelfCalib: the reference scenario on ViSP's simulated Viper850, planned poses,\n"
               "rendered images through the front end, self-calibration on the first 15 poses, verification on\n"
               "the others, report.",
               "tutorial-selfcalib-viper850");
  app.add_option("--robot", a.robot_name, "viper850 (through ViSP's simulator, default) or puma560")
      ->type_name("NAME")
      ->check(CLI::IsMember(vpKinematicChain::presetNames()));
  app.add_option("--seed", a.opt.seed, "seed of the scenario (default 1)")
      ->type_name("N")
      ->check(selfcalibCli::wholeNumber());
  app.add_option("--poses", a.poses,
                 "number of configurations, at least 2 (default 25: 15 calibration + 10\n"
                 "verification)")
      ->type_name("N")
      ->check(selfcalibCli::wholeNumber(2));
  app.add_option("--noise", a.opt.pixel_noise_sd, "image noise sd in pixels (default 0.2, level I)")
      ->type_name("PX")
      ->check(selfcalibCli::number(0));
  app.add_option("--method", a.method,
                 "bundle (default: multi-view reconstruction + kinematic bundle adjustment)\n"
                 "or paper (the paper's two-view measurements, eq. 21 scale, identification)")
      ->type_name("M")
      ->check(CLI::IsMember({vpRobotSelfCalibration::methodName(vpRobotSelfCalibration::BUNDLE_ADJUSTMENT),
                             vpRobotSelfCalibration::methodName(vpRobotSelfCalibration::PAPER)}));
  app.add_option("--focal", a.focal,
                 "known (default), shared (f self-calibrated, one for all views) or\n"
                 "per-pair (the paper: f self-calibrated with each pair; bundle: as shared)")
      ->type_name("MODE")
      ->check(CLI::IsMember({vpRobotSelfCalibration::focalModeName(vpRobotSelfCalibration::FOCAL_KNOWN),
                             vpRobotSelfCalibration::focalModeName(vpRobotSelfCalibration::FOCAL_SHARED),
                             vpRobotSelfCalibration::focalModeName(vpRobotSelfCalibration::FOCAL_PER_PAIR)}));
  app.add_option("--plan", a.plan,
                 "auto (default: observability with bundle, paper with paper), paper (the\n"
                 "paper's optimal trajectory, eqs. 22-39, planned from random feasible poses),\n"
                 "observability (O1-optimal choice from a pool of 60) or none (random poses)")
      ->type_name("MODE")
      ->check(CLI::IsMember({"auto", "paper", "observability", "none"}));
  app.add_option("--acquisition", a.acquisition,
                 "images (default: rendered images, SIFT tracks and the yardstick's dots),\n"
                 "dots (the paper's experiment: rendered dot grids on two planes, matched by\n"
                 "their place in the grid) or points (the simulator's exact correspondences\n"
                 "with --noise pixel noise)")
      ->type_name("M")
      ->check(CLI::IsMember({"images", "dots", "points"}));
  app.add_option("--report", a.report, "where the report goes (default selfcalib-report; 'none': no report)")
      ->type_name("DIR");
  app.add_option("--results", a.results, "also write the run's results.yaml there (the schema of visp-selfcalib calibrate)")
      ->type_name("FILE");
  app.add_option("--figure6-step", a.figure6_step,
                 "the report's Figure 6: every STEP-th number of poses from 15 down to 6 (default 3: 6, 9, 12,\n"
                 "15; 1: every number, 10 calibrations, about 5 s more on 2 cores)")
      ->type_name("STEP")
      ->check(CLI::PositiveNumber);
  app.add_flag("-c", "accepted for ViSP's tutorial convention (no click); nothing is displayed");
  app.add_flag("-d", "accepted for ViSP's tutorial convention (no display); nothing is displayed");
  return selfcalibCli::parse(app, argc, argv);
}
} // namespace

int main(int argc, char **argv)
{
  try {
    Args args;
    const int parsed = parseCommandLine(argc, argv, args);
    if (parsed >= 0)
      return parsed;
    const std::string &robot_name = args.robot_name, &focal = args.focal, &method = args.method,
                      &acquisition = args.acquisition, &report = args.report;
    const vpSelfCalibSimulator::Options &opt = args.opt;
    const unsigned int poses = args.poses;
    std::string plan = args.plan;

    // The robot interface. For the Viper850 it is ViSP's simulator, headless and moved instantly;
    // its nominal model takes the simulator's joint limits and camera mounting.
    std::unique_ptr<vpSelfCalibSimulatorViper850> viper;
    vpKinematicChain nominal;
    if (robot_name == "viper850") {
      viper.reset(new vpSelfCalibSimulatorViper850());
      nominal = viper->getNominalChain();
    } else {
      nominal = vpKinematicChain::preset(robot_name);
    }
    const vpSelfCalibSimulator sim(nominal, opt);
    const vpKinematicChain &truth = sim.getTrueChain();

    std::cout << std::fixed;
    std::cout << "== Robot: " << nominal.getName() << " (" << nominal.getNumJoints() << " revolute joints, "
              << (nominal.getConvention() == vpKinematicChain::DH ? "standard DH" : "modified DH") << ")\n";
    std::cout << "   joint     a [m]     d [m]  alpha [deg]  offset [deg]   limits [deg]\n";
    for (unsigned int i = 0; i < nominal.getNumJoints(); ++i) {
      const vpKinematicChain::Joint &j = nominal.getJoints()[i];
      std::cout << "   " << std::setw(5) << i + 1 << std::setprecision(4) << std::setw(10) << j.a << std::setw(10)
                << j.d << std::setprecision(1) << std::setw(13) << vpMath::deg(j.alpha) << std::setw(14)
                << vpMath::deg(j.theta_offset) << "   [" << vpMath::deg(j.min) << ", " << vpMath::deg(j.max)
                << "]\n";
    }
    const vpSelfCalibDataset::Yardstick ys = sim.getYardstick();
    const vpColVector c = sim.getSceneCentre();
    std::cout << std::setprecision(3);
    std::cout << "== Camera: " << opt.width << "x" << opt.height << ", px = " << opt.px << ", py = " << opt.py
              << ", (u0, v0) = (" << opt.u0 << ", " << opt.v0 << "), noise sd " << opt.pixel_noise_sd << " px\n";
    std::cout << "== Scene: " << opt.num_points << " points in a " << opt.box_x << " x " << opt.box_y << " x "
              << opt.box_z << " m box centred at (" << c[0] << ", " << c[1] << ", " << c[2]
              << ") m; yardstick " << ys.length << " m between ids " << ys.id_a << " and " << ys.id_b << "\n";

    std::cout << "== True robot (seed " << opt.seed << "): 6-D errors [mm, mrad]\n";
    const std::vector<std::string> names = truth.getParameterNames();
    const vpColVector p = truth.getParameters();
    for (unsigned int b = 0; b < names.size() / 6; ++b) {
      const std::string block = names[6 * b].substr(0, names[6 * b].find('.'));
      std::cout << "   " << std::setw(5) << block << "  t = (" << std::setprecision(3);
      for (unsigned int k = 0; k < 3; ++k)
        std::cout << std::setw(7) << 1e3 * p[6 * b + k] << (k < 2 ? ", " : ")");
      std::cout << "  r = (";
      for (unsigned int k = 3; k < 6; ++k)
        std::cout << std::setw(7) << 1e3 * p[6 * b + k] << (k < 5 ? ", " : ")\n");
    }

    const auto t0 = std::chrono::steady_clock::now();
    // The observability choice takes 60 more random configurations as its pool.
    if (plan == "auto")
      plan = method == "bundle" ? "observability" : "paper";
    const unsigned int extra = plan == "observability" ? 60 : 0;
    std::vector<vpColVector> q = sim.generateConfigurations(poses + extra);
    const std::vector<vpColVector> pool_extra(q.begin() + poses, q.end());
    q.resize(poses);
    const double t_gen = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::cout << "== Poses: " << q.size() + extra << " random feasible configurations generated in " << std::setprecision(2)
              << t_gen << " s\n";

    // Step 1 of the paper: plan the calibration poses on the nominal model and the rough scene; the
    // verification poses stay random.
    const unsigned int n_cal = std::min<unsigned int>(15, poses);
    if (plan != "none" && n_cal >= 6) {
      const vpMeasurementPlanner planner(nominal, sim.getPlannerScene());
      const std::vector<vpColVector> initial(q.begin(), q.begin() + n_cal);
      vpMeasurementPlanner::Result pr;
      if (plan == "paper") {
        vpMeasurementPlanner::TrajectoryOptions to;
        to.seed = opt.seed;
        pr = planner.planTrajectory(initial, to, [](const std::string &stage, unsigned int done, unsigned int total) {
          std::cerr << "   ... " << stage << " " << done + 1 << "/" << total << "\n";
        });
      } else {
        std::vector<vpColVector> pool = initial;
        pool.insert(pool.end(), pool_extra.begin(), pool_extra.end());
        pr = planner.selectObservable(pool, n_cal);
      }
      std::cout << "== Planning (" << plan << ") of the " << n_cal << " calibration poses: "
                << vpMeasurementPlanner::statusName(pr.status) << " in " << std::setprecision(2) << pr.seconds << " s\n"
                << "   ratio term (eq. 31) " << std::setprecision(3) << pr.before.ratio << " -> " << pr.after.ratio
                << ", cond(J) " << pr.before.condition << " -> " << pr.after.condition << ", O1 "
                << pr.observability_before.O1 << " -> " << pr.observability_after.O1 << "\n";
      if (pr.status == vpMeasurementPlanner::OK)
        std::copy(pr.configurations.begin(), pr.configurations.end(), q.begin());
      else
        std::cout << "   " << pr.message << "; the random poses are kept\n";
    }
    vpSelfCalibDataset ds = viper ? sim.acquire(*viper, q) : sim.makeDataset(q);
    if (viper) {
      std::cout << "   acquired through vpSimulatorViper850 (vpRobot interface)\n";
      viper.reset(); // released once the poses are acquired: ViSP's simulator thread polls the clock while it lives
    }

    std::cout << "   pose  points seen   nominal model error: absolute       relative to pose 1\n"
              << "                              position [mm] angle [mrad]  position [mm] angle [mrad]\n";
    const vpHomogeneousMatrix T0 = truth.get_fMc(ds.views[0].q), N0 = nominal.get_fMc(ds.views[0].q);
    double worst_rel = 0;
    size_t min_seen = ds.views[0].points.size();
    for (size_t k = 0; k < ds.views.size(); ++k) {
      const vpHomogeneousMatrix T = truth.get_fMc(ds.views[k].q), N = nominal.get_fMc(ds.views[k].q);
      const vpHomogeneousMatrix dA = T.inverse() * N;
      const vpHomogeneousMatrix dR = (T0.inverse() * T).inverse() * (N0.inverse() * N);
      const double rel_mm = 1e3 * dR.getTranslationVector().frobeniusNorm();
      worst_rel = std::max(worst_rel, rel_mm);
      min_seen = std::min(min_seen, ds.views[k].points.size());
      std::cout << "   " << std::setw(4) << k + 1 << std::setw(9) << ds.views[k].points.size() << "/"
                << sim.getScenePoints().size() << std::setprecision(3) << std::setw(18)
                << 1e3 * dA.getTranslationVector().frobeniusNorm() << std::setw(13)
                << 1e3 * dA.getThetaUVector().getTheta() << std::setw(15) << rel_mm << std::setw(13)
                << 1e3 * dR.getThetaUVector().getTheta() << "\n";
    }
    std::cout << "== Summary: every pose sees " << min_seen << " of " << sim.getScenePoints().size()
              << " scene points; the nominal model is off by up to " << std::setprecision(2) << worst_rel
              << " mm in relative camera position.\n";

    // Rendered acquisition: the images the camera takes at the acquired joints, through the true
    // robot; the image front end finds the correspondences and the yardstick's dots in them.
    // The front end fills the observations and the yardstick's ends, the views where it found nothing
    // are left out, the method is set: as visp-selfcalib calibrate does with a dataset's images.
    vpSelfCalibDataset data = ds;
    vpSelfCalibImageCorrespondences::Options co;
    co.method = vpRobotSelfCalibration::methodFromName(method);
    co.prior = nominal; // the front end's prior: the nominal kinematics with eMc and f measured from the images
    vpSelfCalibImageCorrespondences::Result cr;
    if (acquisition != "points") {
      vpSelfCalibRenderer::Options ro;
      ro.seed = opt.seed;
      ro.scene = acquisition == "dots" ? vpSelfCalibRenderer::DOTS : vpSelfCalibRenderer::TEXTURED;
      const vpSelfCalibRenderer renderer(sim, ro);
      std::vector<vpColVector> qs;
      for (const vpSelfCalibDataset::View &v : ds.views)
        qs.push_back(v.q);
      const std::vector<vpImage<unsigned char>> images = renderer.render(qs); // on every core
      std::cerr << "   ... image front end on " << images.size() << " images\n";
      if (acquisition == "dots") { // the paper's experiment: dot grids only
        co.front_end.features = false;
        co.front_end.dot_grids = renderer.getDotGrids();
      }
      cr = vpSelfCalibImageCorrespondences::fromImages(data, images, co);
      const vpFeatureFrontEnd::Result &fe = cr.front_end;
      data.yardstick.length = renderer.getYardstickLength();
      if (acquisition == "dots")
        std::cout << "== Acquisition: " << images.size() << " rendered images (dot grids on two planes, blur, noise); "
                  << "front end (vpDot2 dots, OpenCV circle-grid order): " << cr.grids_found << " of "
                  << fe.grid_seen.size() * images.size() << " grids found, yardstick dots in " << cr.yardstick_images
                  << " images, " << std::setprecision(1) << fe.seconds << " s\n";
      else
        std::cout << "== Acquisition: " << images.size() << " rendered images (textured planes, blur, noise); "
                  << "front end (SIFT, " << (fe.guided ? "kinematics-guided" : "unguided")
                  << " matching, tracks): " << fe.num_tracks
                  << " tracks, yardstick dots in " << cr.yardstick_images << " images, " << std::setprecision(1)
                  << fe.seconds << " s\n";
      for (const std::string &w : cr.warnings) // e.g. the kinematic prior rejected by the images
        std::cout << "   warning: " << w << "\n";
      // A view where the front end found nothing (the grids and the yardstick missed) was left out.
      for (auto d = cr.dropped.rbegin(); d != cr.dropped.rend(); ++d) {
        std::cout << "   pose " << d->index + 1 << ": nothing found in its image, left out\n";
        ds.views.erase(ds.views.begin() + static_cast<long>(d->index));
      }
    } else {
      cr = vpSelfCalibImageCorrespondences::fromDatasetImages(data, co); // the simulator's points: no front end
      std::cout << "== Acquisition: the simulator's exact correspondences with " << opt.pixel_noise_sd << " px noise\n";
    }

    // Self-calibration on the first 15 views; the rest verify.
    data.focal_known = focal != "shared" && focal != "per-pair";
    if (!data.focal_known) // start from a rough guess, as a user with a lens data sheet would
      data.cam.initPersProjWithoutDistortion(0.93 * opt.px, 0.93 * opt.py, opt.u0, opt.v0);
    vpRobotSelfCalibration::Options po;
    po.method = cr.method;
    po.noise.pixel_sd = std::max(0.05, opt.pixel_noise_sd);
    po.num_calibration_poses = std::min<unsigned int>(15, poses);
    po.focal_mode = vpRobotSelfCalibration::focalModeFromName(focal);
    if (po.method == vpRobotSelfCalibration::PAPER)
      std::cout << "== Self-calibration, the paper's procedure (Section 4.1): pairs (1, i) of the first "
                << po.num_calibration_poses << " poses, focal length " << focal << "\n";
    else
      std::cout << "== Self-calibration, multi-view reconstruction + kinematic bundle adjustment, first "
                << po.num_calibration_poses << " poses, focal length " << (data.focal_known ? "known" : "self-calibrated")
                << "\n";
    // With a report, Figure 6 (the calibration again on the first 6, 9, ... poses: --figure6-step) runs
    // first, its calibrations in parallel on every core: its last point is this run, taken from it.
    std::optional<vpSelfCalibPoseStudy::Result> study;
    if (report != "none") {
      std::cerr << "   ... calibrations on the first 6 to " << po.num_calibration_poses << " poses, every " << args.figure6_step
                << " (Figure 6)\n";
      vpSelfCalibPoseStudy::Options so;
      so.step = args.figure6_step;
      study = vpSelfCalibPoseStudy::run(nominal, data, po, so);
    }
    const vpRobotSelfCalibration::Result r =
        study && study->full ? *study->full
                             : vpRobotSelfCalibration::run(nominal, data, po,
                                                           [](const std::string &stage, unsigned int, unsigned int) {
                                                             std::cerr << "   ... " << stage << "\n";
                                                           });
    if (!args.results.empty()) {
      // The split the run made: the first num_calibration_poses views calibrate, the others verify.
      vpSelfCalibProtocol::Result split;
      split.plan.calibration = po.num_calibration_poses;
      split.plan.held_out = static_cast<unsigned int>(data.views.size()) - po.num_calibration_poses;
      vpSelfCalibResultsFile::write(args.results, vpSelfCalibResultsFile::fromRun(r, nominal, "simulated", split));
      std::cout << "   wrote " << args.results << "\n";
    }
    unsigned int ok_pairs = 0;
    for (const auto &pr : r.pairs)
      ok_pairs += pr.status == vpTwoViewEstimator::OK;
    std::cout << "   status: " << vpRobotSelfCalibration::statusName(r.status) << " (" << r.message << ")\n"
              << "   two-view poses: " << ok_pairs << " of " << r.pairs.size() << " pairs" << std::setprecision(5)
              << "; f_x = " << r.fx << " px (sd " << std::setprecision(2) << r.fx_sd << ", true " << opt.px << ")\n";
    if (r.scale.status == vpPoseScale::OK)
      std::cout << "   yardstick scale |k_1| = " << std::setprecision(5) << r.scale.scale << " m (sd " << r.scale.sd
                << ") from " << r.scale.lengths.size() << " pairs\n";
    if (r.method == vpRobotSelfCalibration::BUNDLE_ADJUSTMENT && r.bundle.num_observations > 0)
      std::cout << "   bundle adjustment: " << r.bundle.num_observations << " observations ("
                << r.bundle.num_outliers << " dropped), reprojection RMS " << std::setprecision(3) << r.bundle.rms
                << " px, sigma0 " << std::setprecision(2) << r.bundle.sigma0 << ", scale from "
                << vpKinematicBundleAdjustment::scaleSourceName(r.bundle.scale_source) << "\n";
    for (const auto &f : r.findings)
      std::cout << "   " << (f.severity == vpSelfCalibDataCheck::DOUBT ? "doubt" : "data check") << ": " << f.message
                << "\n";
    // A doubtful model is shown all the same: the verification says how far off it is.
    if (r.status != vpRobotSelfCalibration::OK && r.status != vpRobotSelfCalibration::DOUBTFUL)
      return EXIT_FAILURE;
    std::cout << "   estimated " << r.identifiability.identified.size() << " of " << truth.getNumParameters()
              << " parameters" << std::setprecision(2);
    if (r.method == vpRobotSelfCalibration::PAPER)
      std::cout << "; cond(J) = " << std::setprecision(1) << r.identification.observability.condition_number
                << ", sigma0 = " << std::setprecision(2) << r.identification.sigma0;
    std::cout << "\n   parameter   estimate +- sd [mm or mrad]   true [mm or mrad]\n";
    for (unsigned int k : r.identifiability.identified)
      std::cout << "   " << std::setw(8) << names[k] << std::setprecision(3) << std::setw(11)
                << 1e3 * r.calibrated.getParameters()[k] << " +- " << std::setw(8) << 1e3 * r.parameter_sd[k]
                << std::setw(14) << 1e3 * p[k] << "\n";
    std::cout << "   not estimated (kept at nominal):\n";
    for (const auto &u : r.identifiability.unidentifiable)
      std::cout << "   " << std::setw(8) << u.name << ": " << u.reason << "\n";
    for (const auto &c : r.identification.correlations)
      if (r.method == vpRobotSelfCalibration::PAPER)
        std::cout << "   correlation " << c.a << " / " << c.b << ": " << std::setprecision(3) << c.value << "\n";
    std::cout << "   stage times [s]:";
    for (const auto &st : r.stage_seconds)
      std::cout << " " << st.first << " " << std::setprecision(2) << st.second << ";";
    std::cout << "\n";

    // Verification on the held-out views against the simulated truth.
    if (data.views.size() > po.num_calibration_poses + 1) {
      const std::vector<vpSelfCalibDataset::View> ver(ds.views.begin() + po.num_calibration_poses, ds.views.end());
      const std::vector<vpSelfCalibDataset::View> ver_data(data.views.begin() + po.num_calibration_poses,
                                                           data.views.end());
      // True scene points are known for the simulator's points, not for the tracks of the images.
      const std::map<int, vpColVector> true_points =
          acquisition == "points" ? sim.getScenePointsById() : std::map<int, vpColVector>();
      const std::vector<vpHomogeneousMatrix> true_fMc = sim.getTrueCameraPoses(ver);
      const vpCalibrationVerifier::Result before =
          vpCalibrationVerifier::verify(nominal, ds.cam, ver_data, data.yardstick, true_points, true_fMc);
      const vpCalibrationVerifier::Result after =
          vpCalibrationVerifier::verify(r.calibrated, r.camera, ver_data, data.yardstick, true_points, true_fMc);
      std::cout << "== Verification on " << ver.size() << " held-out poses     nominal   calibrated\n" << std::setprecision(3)
                << "   yardstick 3-D error [mm]        " << std::setw(10) << 1e3 * before.yardstick_error << std::setw(12)
                << 1e3 * after.yardstick_error << "\n";
      if (acquisition == "points")
        std::cout << "   point-pair distance error, mean [mm] " << std::setw(5) << 1e3 * before.distance_error_mean
                  << std::setw(12) << 1e3 * after.distance_error_mean << "\n";
      std::cout
                << "   relative pose error, mean [mm]  " << std::setw(10) << 1e3 * before.position_error_mean
                << std::setw(12) << 1e3 * after.position_error_mean << "\n"
                << "   relative pose error, mean [mrad]" << std::setw(10) << 1e3 * before.rotation_error_mean
                << std::setw(12) << 1e3 * after.rotation_error_mean << "\n";
    }
    std::cout << "== Pipeline time " << std::setprecision(2) << r.seconds << " s\n";
    if (report != "none") {
      vpSelfCalibReport::Record run(nominal, data, po, r);
      run.front_end = cr.front_end_ran ? &cr.front_end : nullptr;
      run.errors_vs_poses = &*study;
      const vpSelfCalibReport::Result rep = vpSelfCalibReport::write(report, run, vpSelfCalibReport::Options());
      std::cout << "== Report: " << report << "/report.md (" << rep.message << ")\n";
    }
    return EXIT_SUCCESS;
  } catch (const vpException &e) {
    std::cerr << "error: " << e.getStringMessage() << std::endl;
    return EXIT_FAILURE;
  }
}
