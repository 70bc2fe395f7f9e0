/*
 * bench-plane-scan: a flat scene of unknown layout (a board's corners taken as scene points) given as
 * projected points, no images: how often the multi-view reconstruction is wrong and how often a
 * wrong calibration ends "ok".
 *
 *   bench-plane-scan [--seeds N] [--first-seed S] [--draws K] [--noise PX] [--stated PX] [--csv FILE]
 *
 * Per seed (geometry): the reference scenario's Viper850 (seeded robot errors), 20 random poses, the
 * first 14 calibrating, the last 6 held out; the scene is the corners of simulate --target charuco's
 * board (7 x 5 squares of 2 cm: 24 corners) at the renderer's board pose, projected by the true camera
 * with Gaussian noise of --noise px (K draws per geometry), f known, the layout not given. Per draw:
 * - the multi-view step alone (the options the bundle pipeline builds): a view is wrong when its
 *   c_kMc_0 is more than 2 deg off the truth; its sigma0 against its 99 % interval, its outliers;
 * - the whole calibration (bundle method): wrong when eMc is beyond 3 sd of the truth in a
 *   component (translation or theta-u) or the held-out relative positions beyond 3 predicted sd (RMS
 *   of error / sd over the pairs (0, i) of the held-out views, the covariance of the run).
 * --stated states another pixel sd than the data's (a wrong statement: the verdicts it gives).
 * The table counts the draws by verdict (ok, doubtful, failed) and right or wrong; a wrong "ok" is a
 * silent wrong answer.
 */
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <visp3/core/vpException.h>
#include <visp3/selfcalib/vpBoardDetector.h>
#include <visp3/selfcalib/vpKinematicBundleAdjustment.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibRenderer.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "../../modules/selfcalib/test/testPlaneDraws.h"
#include "benchCommon.h"
#include "selfcalibCli.h"

namespace
{
//! The workspace check against the truth, for the CSV: the calibrated and the nominal model's error over the joint
//! limits (bench::workspaceError, m and rad) and the check's chances.
std::string workspaceColumns(const vpRobotSelfCalibration::Result &r, const vpSelfCalibSimulator &sim)
{
  std::ostringstream os;
  const bench::MotionRms cal = r.workspace.computed ? bench::workspaceError(r.calibrated, sim.getTrueChain())
                                                    : bench::MotionRms{NAN, NAN};
  const bench::MotionRms nom = bench::workspaceError(sim.getNominalChain(), sim.getTrueChain());
  os << cal.t << "," << cal.r << "," << nom.t << "," << nom.r << "," << r.workspace.worse_t << "," << r.workspace.worse_r;
  return os.str();
}

const char *kBoard = "charuco:7x5:0.02:0.015:DICT_6X6_250"; // simulate --target charuco's board (PlaneDraw's)
const unsigned int kPoses = 20, kHeldOut = 6;                 // PlaneDraw's

//! The views of the reconstruction more than 2 deg off the truth (c_kMc_0), and the largest error (deg).
unsigned int wrongViews(const vpMultiViewReconstruction::Result &r, const vpSelfCalibSimulator &sim,
                        const std::vector<vpColVector> &q, double &worst_deg)
{
  unsigned int wrong = 0;
  worst_deg = 0;
  const vpHomogeneousMatrix fMc0 = sim.getTrueChain().get_fMc(q[0]);
  for (size_t k = 1; k < q.size() && k < r.posed.size(); ++k) {
    if (!r.posed[k])
      continue;
    const vpHomogeneousMatrix E = (sim.getTrueChain().get_fMc(q[k]).inverse() * fMc0).inverse() * r.cMc0[k];
    const double deg = std::sqrt(vpThetaUVector(E.getRotationMatrix()).sumSquare()) * 180 / M_PI;
    worst_deg = std::max(worst_deg, deg);
    wrong += deg > 2;
  }
  return wrong;
}

/*
  The largest |error| / sd of eMc's components (translation, theta-u) against the truth, and the RMS
  of the held-out relative position errors over their predicted sd.
*/
void finalErrors(const vpRobotSelfCalibration::Result &r, const vpSelfCalibSimulator &sim,
                 const std::vector<vpColVector> &held, double &emc_ratio, double &held_ratio)
{
  emc_ratio = held_ratio = NAN;
  if (r.has_eMc) {
    const vpPoseVector t(sim.getTrueChain().get_eMc_corrected());
    emc_ratio = 0;
    for (unsigned int i = 0; i < 6; ++i)
      emc_ratio = std::max(emc_ratio, std::fabs(r.eMc[i] - t[i]) / std::max(r.eMc_sd[i], 1e-12));
  }
  if (r.bundle.covariance.getRows() == 0)
    return;
  double e2 = 0, p2 = 0;
  for (size_t k = 1; k < held.size(); ++k) {
    const vpHomogeneousMatrix m = r.calibrated.get_fMc(held[0]).inverse() * r.calibrated.get_fMc(held[k]);
    const vpHomogeneousMatrix t = sim.getTrueChain().get_fMc(held[0]).inverse() * sim.getTrueChain().get_fMc(held[k]);
    e2 += (m.getTranslationVector() - t.getTranslationVector()).sumSquare();
    const vpMatrix C = vpKinematicBundleAdjustment::relativePoseCovariance(r.calibrated, r.identifiability.identified,
                                                                           r.bundle.covariance, held[0], held[k]);
    p2 += C[0][0] + C[1][1] + C[2][2];
  }
  held_ratio = std::sqrt(e2 / p2);
}

struct Counts {
  unsigned int draws = 0, mv_wrong = 0, mv_sigma0_out = 0;
  unsigned int ok_right = 0, ok_wrong = 0, doubtful_right = 0, doubtful_wrong = 0, failed = 0;
  double worst_ok = 0; //!< the largest error (eMc or held-out, in sd) of an ok draw
};
} // namespace

int main(int argc, char **argv)
{
  try {
    unsigned int seeds = 12, draws = 6, first_seed = 1;
    double noise = 0.2, stated = 0;
    std::string csv_path;
    CLI::App app("bench-plane-scan: a flat scene of unknown layout as projected points: wrong multi-view\n"
                 "reconstructions and wrong calibrations against their verdict.",
                 "bench-plane-scan");
    selfcalibCli::addSeeds(app, seeds);
    app.add_option("--first-seed", first_seed, "the first seed (geometry; default 1)")
        ->type_name("S")
        ->check(selfcalibCli::wholeNumber(1, 100000));
    app.add_option("--draws", draws, "noise draws of each seed's geometry (default 6)")
        ->type_name("K")
        ->check(selfcalibCli::wholeNumber(1, 100));
    app.add_option("--noise", noise, "Gaussian noise of the corners, px (default 0.2)")
        ->type_name("PX")
        ->check(selfcalibCli::number(0, true, 10));
    app.add_option("--stated", stated, "the pixel sd stated to the calibration, px (default: --noise)")
        ->type_name("PX")
        ->check(selfcalibCli::number(0, true, 10));
    app.add_option("--csv", csv_path, "one row per seed and draw")->type_name("FILE");
    const int parsed = selfcalibCli::parse(app, argc, argv);
    if (parsed >= 0)
      return parsed;
    bench::Csv csv(csv_path, "seed,draw,mv_wrong_views,mv_worst_deg,mv_sigma0,mv_sigma0_high,mv_outliers,mv_measured_px,status,"
                             "outliers,bundle_sigma0,bundle_sigma0_high,eMc_ratio,heldout_ratio,wrong,doubts,workspace_true_m,"
                             "workspace_true_rad,workspace_nominal_m,workspace_nominal_rad,workspace_chance_worse_t,"
                             "workspace_chance_worse_r");
    std::cout << "bench-plane-scan: " << kBoard << " corners as points (layout unknown), viper850, " << seeds
              << " seeds x " << draws << " draws, " << kPoses - kHeldOut << " calibration + " << kHeldOut
              << " held-out poses, focal known, " << noise << " px (stated " << (stated > 0 ? stated : noise) << " px)\n";
    const auto t_start = std::chrono::steady_clock::now();
    Counts c;
    for (unsigned int seed = first_seed; seed < first_seed + seeds; ++seed) {
      for (unsigned int d = 0; d < draws; ++d) {
        std::cerr << "seed " << seed << "/" << first_seed + seeds - 1 << ", draw " << d + 1 << "/" << draws
                  << "      \r" << std::flush;
        const selfcalib_test::PlaneDraw p(seed, d, noise);
        const vpSelfCalibSimulator &sim = p.sim;
        const vpSelfCalibDataset &ds = p.ds;
        const std::vector<vpColVector> &cal = p.cal, &held = p.held;
        vpRobotSelfCalibration::Options po;
        po.num_calibration_poses = static_cast<unsigned int>(ds.views.size());
        po.noise.pixel_sd = stated > 0 ? stated : noise;
        const vpRobotSelfCalibration::Result r = vpRobotSelfCalibration::run(sim.getNominalChain(), ds, po);
        ++c.draws;
        double worst = 0;
        const unsigned int wrong_views = wrongViews(r.multiview, sim, cal, worst);
        c.mv_wrong += wrong_views > 0;
        const vpMultiViewReconstruction::Result &mv = r.multiview;
        c.mv_sigma0_out += mv.sigma0 > mv.sigma0_high;
        double emc = NAN, ho = NAN;
        finalErrors(r, sim, held, emc, ho);
        const bool wrong = !(emc <= 3) || !(ho <= 3);
        if (r.status == vpRobotSelfCalibration::OK) {
          ++(wrong ? c.ok_wrong : c.ok_right);
          c.worst_ok = std::max(c.worst_ok, std::max(std::isfinite(emc) ? emc : 0.0, std::isfinite(ho) ? ho : 0.0));
        }
        else if (r.status == vpRobotSelfCalibration::DOUBTFUL)
          ++(wrong ? c.doubtful_wrong : c.doubtful_right);
        else
          ++c.failed;
        if (csv.enabled())
          csv.row() << seed << "," << d << "," << wrong_views << "," << worst << "," << mv.sigma0 << ","
                    << mv.sigma0_high << "," << mv.num_outliers << "," << mv.measured.pixel_sd << ","
                    << vpRobotSelfCalibration::statusName(r.status)
                    << "," << r.bundle.num_outliers << "," << r.bundle.sigma0 << "," << r.bundle.sigma0_high << "," << emc << "," << ho << "," << wrong << ","
                    << bench::doubtCodes(r) << "," << workspaceColumns(r, sim) << "\n";
        if (std::getenv("BP_DEBUG"))
          for (size_t k = 0; k < mv.pairs.size(); ++k)
            std::cerr << "pair " << k + 1 << " " << vpTwoViewEstimator::statusName(mv.pairs[k].status) << " inl "
                      << mv.pairs[k].num_inliers << " ref " << mv.reference_view << "\n";
        if (wrong_views > 0 || wrong)
          std::cerr << "\nseed " << seed << ", draw " << d << ": " << wrong_views << " views > 2 deg (worst " << worst
                    << "), sigma0 " << mv.sigma0 << " [" << mv.sigma0_low << ", " << mv.sigma0_high << "], "
                    << mv.num_outliers << " outliers; " << vpRobotSelfCalibration::statusName(r.status)
                    << ", eMc " << emc << " sd, held-out " << ho << " sd\n";
      }
    }
    std::cerr << "\n";
    std::cout << "\n| draws | multi-view wrong (a view > 2 deg) | multi-view sigma0 above its interval | ok, right | "
                 "ok, wrong | doubtful, right | doubtful, wrong | failed |\n|---|---|---|---|---|---|---|---|\n"
              << "| " << c.draws << " | " << c.mv_wrong << " | " << c.mv_sigma0_out << " | " << c.ok_right << " | "
              << c.ok_wrong << " | " << c.doubtful_right << " | " << c.doubtful_wrong << " | " << c.failed << " |\n";
    // Six eMc components per draw at 3 sd: about 0.27 % each beyond it by chance.
    std::cout << std::setprecision(1) << std::fixed << "\nthe largest error of an ok draw: " << c.worst_ok
              << " sd (eMc components beyond 3 sd by chance: about " << c.draws * 6 * 0.0027 << " in " << c.draws
              << " draws)\ntargets: no wrong calibration ends ok: " << (c.ok_wrong == 0 ? "met" : "NOT met")
              << "; no ok draw beyond 10 sd: " << (c.worst_ok <= 10 ? "met" : "NOT met") << "\n";
    std::cout << "\ndone in " << std::setprecision(0)
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count() << " s\n";
    return EXIT_SUCCESS;
  } catch (const vpException &e) {
    std::cerr << "bench-plane-scan: " << e.getStringMessage() << "\n";
  } catch (const std::exception &e) {
    std::cerr << "bench-plane-scan: " << e.what() << "\n";
  }
  return EXIT_FAILURE;
}
