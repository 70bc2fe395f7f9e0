/*
 * bench-trust: can a run's result be trusted, and compared with another run's? (issue 20)
 *
 *   bench-trust [--seeds N] [--draws K] [--robots ur5,puma-mdh] [--noise 0.2,0.5]
 *               [--methods bundle[,paper]] [--focal known,shared] [--sd-factors 1,2.5,0.4] [--auto] [--csv FILE]
 *               [--blocks B]
 *
 * The hidden-robot style of check: a UR5 (preset, home as in bench-robots) and a modified-DH PUMA 560
 * (the preset refitted as an MDH table, vpDHTableFit::fit), camera 800 x 600, f 1200 px, the
 * reference scene (80 points and a yardstick), 25 random feasible poses per seed (15 calibrating, 10
 * held out). Per seed (one geometry) K noise draws of the pixels (the same draws for every method,
 * focal mode and given sd); each draw is calibrated with --pixel-sd set to the true sd times each
 * factor (1, and 2.5 and 0.4 on purpose: a user who got it wrong). Per row (robot, method, focal
 * mode, noise, given-sd factor), over its seeds:
 *   - runs and their statuses (vpRobotSelfCalibration::statusName, so new statuses show);
 *   - sets: the largest number of distinct estimated sets over one seed's draws (target 1);
 *   - sd ratios: the reported sd (RMS over the draws) over the empirical spread of the estimate over
 *     the draws (sample sd; every run with an estimate, ok or doubtful), for f (self-calibrated rows) and for the hand-eye translation eMc.t
 *     (pooled over tx, ty, tz); the range over the seeds (target 0.7-1.4 for each seed);
 *   - held-out position error: the RMS over the held-out pairs (c_0, c_k) of the error of the
 *     predicted relative position against the simulator's true poses (bench::verifyAgainstTruth);
 *     the mean over the ok runs, the nominal model's (the mean over seeds), and the run's own
 *     predicted error: its covariance propagated to the same pairs
 *     (vpKinematicBundleAdjustment::relativePoseCovariance, the run's estimated set);
 *   - trusted-but-wrong: the ok runs whose held-out error is above 2x the nominal model's or above
 *     5x their own predicted error (target 0).
 * With --blocks B, each seed's sd ratios over all its draws and over each block of B consecutive
 * draws: a ratio over 30 draws is itself uncertain (its sample sd by about 13 %, 1 sd), and the
 * blocks show by how much on the geometry at hand.
 * A last line per robot gives the selection margins of the estimated set (smallest new direction of
 * an estimated parameter, largest of a dependent one; vpKinematicIdentification::analyseConfigurations).
 */
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <visp3/core/vpException.h>
#include <visp3/selfcalib/vpDHTableFit.h>
#include <visp3/selfcalib/vpKinematicBundleAdjustment.h>
#include <visp3/selfcalib/vpKinematicIdentification.h>
#include <visp3/selfcalib/vpModelExport.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "benchCommon.h"
#include "benchPaper.h"
#include "selfcalibCli.h"

namespace
{
constexpr unsigned int kPoses = 25, kCalibration = 15;

vpSelfCalibSimulator makeSim(const std::string &robot, unsigned int seed)
{
  vpSelfCalibSimulator::Options so;
  so.seed = seed;
  so.pixel_noise_sd = 0;
  so.width = 800;
  so.height = 600;
  so.px = so.py = 1200;
  so.u0 = 400;
  so.v0 = 300;
  if (robot == "ur5") {
    so.home = vpColVector({0.3, -1.9, 1.9, -1.3, -1.57, 0.2});
    return vpSelfCalibSimulator(vpKinematicChain::preset("ur5"), so);
  }
  // puma-mdh: the PUMA 560 preset as a modified-DH table (same fMc(q), so the preset's home).
  const vpDHTableFit::Result fit = vpDHTableFit::fit(vpKinematicChain::preset("puma560"), vpKinematicChain::MDH);
  if (!fit.representable)
    throw std::runtime_error("the PUMA 560 is not representable as an MDH table: " + fit.message);
  vpKinematicChain mdh = fit.table;
  mdh.setName("puma560-mdh");
  so.home = vpSelfCalibSimulator::homeConfiguration(vpKinematicChain::preset("puma560"));
  return vpSelfCalibSimulator(mdh, so);
}

//! sqrt(mean of squares) of the reported sd over the sample sd of the values (NaN with < 3 values).
double sdRatio(const std::vector<double> &values, const std::vector<double> &reported)
{
  if (values.size() < 3)
    return NAN;
  bench::Stats s;
  double r2 = 0;
  for (size_t k = 0; k < values.size(); ++k) {
    s.add(values[k]);
    r2 += reported[k] * reported[k];
  }
  return std::sqrt(r2 / reported.size()) / s.sd();
}

//! Everything one row gathers, per seed where the spread is taken.
struct Row {
  std::string robot, method, focal;
  double noise = 0, factor = 1;
  std::map<std::string, unsigned int> statuses;
  unsigned int runs = 0, ok = 0, above_nominal = 0, above_predicted = 0;
  unsigned int max_sets = 0;
  bench::Stats err, nominal, predicted;
  std::vector<double> f_ratio, t_ratio; // one per seed
  // per seed, reset by startSeed()
  std::set<std::vector<unsigned int>> sets;
  std::vector<double> f, f_sd, t[3], t_sd[3];
  void startSeed()
  {
    sets.clear();
    f.clear();
    f_sd.clear();
    for (int a = 0; a < 3; ++a) {
      t[a].clear();
      t_sd[a].clear();
    }
  }
  //! Per seed with --blocks: the ratios over every draw, then over each block of `block` draws.
  struct SeedRatios {
    unsigned int seed = 0;
    double f_all = NAN, t_all = NAN;
    std::vector<double> f_blocks, t_blocks;
  };
  std::vector<SeedRatios> per_seed;
  void endSeed(unsigned int seed, unsigned int block)
  {
    max_sets = std::max(max_sets, static_cast<unsigned int>(sets.size()));
    const double rf = sdRatio(f, f_sd);
    if (std::isfinite(rf))
      f_ratio.push_back(rf);
    const double rt = tRatio(0, t[0].size());
    if (std::isfinite(rt))
      t_ratio.push_back(rt);
    if (block > 0) {
      SeedRatios s;
      s.seed = seed;
      s.f_all = rf;
      s.t_all = rt;
      for (size_t b = 0; b + block <= f.size(); b += block)
        s.f_blocks.push_back(sdRatio(std::vector<double>(f.begin() + b, f.begin() + b + block),
                                     std::vector<double>(f_sd.begin() + b, f_sd.begin() + b + block)));
      for (size_t b = 0; b + block <= t[0].size(); b += block)
        s.t_blocks.push_back(tRatio(b, b + block));
      per_seed.push_back(s);
    }
  }
  //! eMc.t pooled over draws [b, e): sqrt(mean reported variance / mean empirical variance) over the
  //! three components (NaN with fewer than 3 draws).
  double tRatio(size_t b, size_t e) const
  {
    double rep = 0, emp = 0;
    for (int a = 0; a < 3; ++a) {
      if (e > t[a].size() || e < b + 3)
        return NAN;
      bench::Stats s;
      double r2 = 0;
      for (size_t k = b; k < e; ++k) {
        s.add(t[a][k]);
        r2 += t_sd[a][k] * t_sd[a][k];
      }
      rep += r2 / static_cast<double>(e - b);
      emp += s.sd() * s.sd();
    }
    return emp > 0 ? std::sqrt(rep / emp) : NAN;
  }
};

std::string range(const std::vector<double> &v)
{
  if (v.empty())
    return "–";
  std::ostringstream os;
  os << std::fixed << std::setprecision(2) << *std::min_element(v.begin(), v.end());
  if (v.size() > 1)
    os << "-" << *std::max_element(v.begin(), v.end());
  return os.str();
}

bool within(const std::vector<double> &v, double lo, double hi)
{
  return std::all_of(v.begin(), v.end(), [&](double x) { return x >= lo && x <= hi; });
}
} // namespace

int main(int argc, char **argv)
{
  try {
    unsigned int seeds = 3, draws = 30, blocks = 0;
    std::vector<std::string> robots = {"ur5", "puma-mdh"};
    std::vector<double> noises = {0.2, 0.5};
    std::vector<std::string> methods = {"bundle"};
    std::vector<std::string> focals = {"known", "shared"};
    std::vector<double> factors = {1, 2.5, 0.4};
    bool auto_noise = false;
    std::string csv_path;
    CLI::App app("bench-trust: the same set in every noise draw, honest sd and no trusted-but-wrong result, on a\n"
                 "UR5 and a modified-DH PUMA with the pixel sd given right and wrong on purpose (issue 20).",
                 "bench-trust");
    selfcalibCli::addSeeds(app, seeds);
    app.add_option("--draws", draws, "noise draws per seed's geometry (default 30)")
        ->type_name("K")
        ->check(selfcalibCli::wholeNumber(1));
    app.add_option("--blocks", blocks,
                   "also print each seed's sd ratios over all its draws and over each block of B\n"
                   "consecutive draws (e.g. --draws 90 --blocks 30: how much a 30-draw ratio varies)")
        ->type_name("B")
        ->check(selfcalibCli::wholeNumber(3));
    app.add_option("--robots", robots, "robots (default ur5,puma-mdh)")
        ->type_name("LIST")
        ->delimiter(',')
        ->check(CLI::IsMember({"ur5", "puma-mdh"}));
    selfcalibCli::addNoiseLevels(app, noises, "true pixel noise levels, above 0 (default 0.2,0.5)", true);
    app.add_option("--methods", methods, "methods: bundle, paper (default bundle)")
        ->type_name("LIST")
        ->delimiter(',')
        ->check(CLI::IsMember({"bundle", "paper"}));
    app.add_option("--focal", focals, "focal modes (default known,shared)")
        ->type_name("MODES")
        ->delimiter(',')
        ->check(CLI::IsMember(
            bench::focalModeNames({vpRobotSelfCalibration::FOCAL_KNOWN, vpRobotSelfCalibration::FOCAL_SHARED})));
    app.add_option("--sd-factors", factors, "given --pixel-sd over the true one (default 1,2.5,0.4)")
        ->type_name("LIST")
        ->delimiter(',')
        ->check(selfcalibCli::number(0, true));
    app.add_flag("--auto", auto_noise,
                 "measure the pixel noise from the residuals (calibrate's default, --pixel-sd auto),\n"
                 "starting from the given value; without it the given value is used as stated");
    app.add_option("--csv", csv_path, "one row per robot, seed, focal mode, noise, draw, method and sd factor")
        ->type_name("FILE");
    const int parsed = selfcalibCli::parse(app, argc, argv);
    if (parsed >= 0)
      return parsed;

    bench::Csv csv(csv_path, "robot,seed,focal,noise_px,draw,method,sd_factor,status,estimated,fx,fx_sd,"
                             "heldout_rms_m,nominal_rms_m,predicted_rms_m,workspace_true_m,workspace_true_rad,"
                             "workspace_nominal_m,workspace_nominal_rad,workspace_chance_worse_t,workspace_chance_worse_r");
    std::cout << "bench-trust: " << seeds << " seeds x " << draws << " noise draws, camera 800 x 600 f 1200, "
              << kCalibration << " calibration + " << (kPoses - kCalibration)
              << " held-out poses, 80 points + yardstick; the given pixel sd is the true one times the factor"
              << (auto_noise ? " (the start of --pixel-sd auto)" : " (used as stated)") << "\n\n";
    const auto t_start = std::chrono::steady_clock::now();
    std::vector<Row> rows;
    auto rowOf = [&](const std::string &robot, const std::string &method, const std::string &focal, double noise,
                     double factor) -> Row & {
      for (Row &r : rows)
        if (r.robot == robot && r.method == method && r.focal == focal && r.noise == noise && r.factor == factor)
          return r;
      rows.push_back(Row());
      Row &r = rows.back();
      r.robot = robot;
      r.method = method;
      r.focal = focal;
      r.noise = noise;
      r.factor = factor;
      return r;
    };
    // Create the rows in print order.
    for (const auto &robot : robots)
      for (const auto &method : methods)
        for (const auto &focal : focals)
          for (double noise : noises)
            for (double factor : factors)
              rowOf(robot, method, focal, noise, factor);
    std::map<std::string, std::pair<double, double>> margins; // robot -> (smallest kept, largest dependent)
    const unsigned int total = static_cast<unsigned int>(robots.size() * seeds * focals.size() * noises.size() * draws);
    unsigned int done = 0;
    for (const std::string &robot : robots)
      for (unsigned int seed = 1; seed <= seeds; ++seed) {
        const vpSelfCalibSimulator clean = makeSim(robot, seed);
        const std::vector<vpColVector> q = clean.generateConfigurations(kPoses);
        const std::vector<vpColVector> ver(q.begin() + kCalibration, q.end());
        {
          const std::vector<vpColVector> qc(q.begin(), q.begin() + kCalibration);
          const auto a = vpKinematicIdentification::analyseConfigurations(clean.getNominalChain(), qc,
                                                                          vpKinematicIdentification::Options());
          auto &m = margins.emplace(robot, std::make_pair(1.0, 0.0)).first->second;
          for (unsigned int i = 0; i < a.new_direction.size(); ++i)
            if (std::binary_search(a.identified.begin(), a.identified.end(), i))
              m.first = std::min(m.first, a.new_direction[i]);
            else
              m.second = std::max(m.second, a.new_direction[i]);
        }
        for (const std::string &focal : focals) {
          const vpRobotSelfCalibration::FocalMode mode = vpRobotSelfCalibration::focalModeFromName(focal);
          const vpSelfCalibDataset ds0 = bench::pipelineDataset(clean, q, mode);
          const std::vector<vpSelfCalibDataset::View> held(ds0.views.begin() + kCalibration, ds0.views.end());
          bench::Stats nom;
          for (double e : bench::verifyAgainstTruth(clean, clean.getNominalChain(), clean.getCamera(), held).position_errors)
            nom.add(e * e);
          const double nominal_rms = std::sqrt(nom.mean());
          for (const double noise : noises) {
            for (const auto &method : methods)
              for (double factor : factors)
                rowOf(robot, method, focal, noise, factor).startSeed();
            for (unsigned int d = 0; d < draws; ++d, ++done) {
              std::cerr << "bench-trust: " << robot << " seed " << seed << ", f " << focal << ", " << noise
                        << " px, draw " << d + 1 << "/" << draws << " (" << done << "/" << total << ")      \r"
                        << std::flush;
              vpSelfCalibDataset dd = ds0;
              std::mt19937_64 rng(1000003ULL * seed + 7919ULL * d + static_cast<unsigned long long>(1000 * noise));
              std::normal_distribution<double> n(0, noise);
              for (auto &v : dd.views)
                for (auto &o : v.points)
                  o.ip = vpImagePoint(o.ip.get_i() + n(rng), o.ip.get_j() + n(rng));
              for (const auto &method : methods)
                for (double factor : factors) {
                  Row &row = rowOf(robot, method, focal, noise, factor);
                  vpRobotSelfCalibration::Options po;
                  po.method = vpRobotSelfCalibration::methodFromName(method);
                  po.focal_mode = mode;
                  po.num_calibration_poses = kCalibration;
                  po.noise.pixel_sd = factor * noise;
                  if (auto_noise) // calibrate --pixel-sd auto, from the given value
                    po.noise.measure_pixel_sd = true;
                  const auto r = vpRobotSelfCalibration::run(clean.getNominalChain(), dd, po);
                  ++row.runs;
                  ++row.statuses[vpRobotSelfCalibration::statusName(r.status)];
                  if (!r.identifiability.identified.empty())
                    row.sets.insert(r.identifiability.identified);
                  double err = NAN, pred = NAN;
                  if (r.status == vpRobotSelfCalibration::OK) {
                    ++row.ok;
                    const auto v = bench::verifyAgainstTruth(clean, r.calibrated, r.camera, held);
                    double e2 = 0;
                    for (double e : v.position_errors)
                      e2 += e * e;
                    err = std::sqrt(e2 / v.position_errors.size());
                    const bool bundle = po.method != vpRobotSelfCalibration::PAPER;
                    const vpMatrix &C = bundle ? r.bundle.covariance : r.identification.covariance;
                    if (C.getRows() >= r.identifiability.identified.size()) {
                      double p2 = 0;
                      for (size_t k = 1; k < ver.size(); ++k) {
                        const vpMatrix Ck = vpKinematicBundleAdjustment::relativePoseCovariance(
                            r.calibrated, r.identifiability.identified, C, ver[0], ver[k]);
                        p2 += Ck[0][0] + Ck[1][1] + Ck[2][2];
                      }
                      pred = std::sqrt(p2 / (ver.size() - 1));
                    }
                    row.err.add(err);
                    row.nominal.add(nominal_rms);
                    if (std::isfinite(pred))
                      row.predicted.add(pred);
                    if (err > 2 * nominal_rms)
                      ++row.above_nominal;
                    if (!(err <= 5 * pred))
                      ++row.above_predicted;
                  }
                  // The sd ratios over every run with an estimate (a doubtful one included: leaving
                  // it out would bias the spread).
                  if (r.status == vpRobotSelfCalibration::OK || r.status == vpRobotSelfCalibration::DOUBTFUL) {
                    if (mode != vpRobotSelfCalibration::FOCAL_KNOWN) {
                      row.f.push_back(r.fx);
                      row.f_sd.push_back(r.fx_sd);
                    }
                    if (r.has_eMc)
                      for (unsigned int a = 0; a < 3; ++a) {
                        row.t[a].push_back(r.eMc[a]);
                        row.t_sd[a].push_back(r.eMc_sd[a]);
                      }
                  }
                  if (csv.enabled()) { // with the workspace check against the truth (the camera's motions over the joint limits)
                    const bool model = r.status == vpRobotSelfCalibration::OK || r.status == vpRobotSelfCalibration::DOUBTFUL;
                    const bench::MotionRms cal = model ? bench::workspaceError(r.calibrated, clean.getTrueChain())
                                                       : bench::MotionRms{NAN, NAN};
                    const bench::MotionRms nom = bench::workspaceError(clean.getNominalChain(), clean.getTrueChain());
                    csv.row() << robot << "," << seed << "," << focal << "," << noise << "," << d << "," << method
                              << "," << factor << "," << vpRobotSelfCalibration::statusName(r.status) << ","
                              << r.identifiability.identified.size() << "," << r.fx << "," << r.fx_sd << "," << err
                              << "," << nominal_rms << "," << pred << "," << cal.t << "," << cal.r << "," << nom.t << ","
                              << nom.r << "," << r.workspace.worse_t << "," << r.workspace.worse_r << "\n";
                  }
                }
            }
            for (const auto &method : methods)
              for (double factor : factors)
                rowOf(robot, method, focal, noise, factor).endSeed(seed, blocks);
          }
        }
      }
    std::cerr << std::string(90, ' ') << "\r";

    std::cout << "| robot | method | focal | noise (px) | given sd | runs | statuses | sets | sd ratio f | sd ratio eMc.t | "
                 "held-out (mm) | nominal (mm) | predicted (mm) | ok > 2x nominal | ok > 5x predicted |\n"
              << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    bool sets_met = true, bad_met = true, sd_met = true;
    for (const Row &r : rows) {
      std::ostringstream st;
      for (const auto &s : r.statuses)
        st << (st.tellp() > 0 ? ", " : "") << s.first << " " << s.second;
      sets_met = sets_met && r.max_sets <= 1;
      bad_met = bad_met && r.above_nominal == 0 && r.above_predicted == 0;
      sd_met = sd_met && within(r.f_ratio, 0.7, 1.4) && within(r.t_ratio, 0.7, 1.4);
      std::cout << std::fixed << "| " << r.robot << " | " << r.method << " | " << r.focal << " | "
                << std::setprecision(1) << r.noise << " | " << std::setprecision(1) << r.factor << "x | " << r.runs
                << " | " << st.str() << " | " << r.max_sets << " | "
                << (r.focal == "known" ? std::string("(known)") : range(r.f_ratio)) << " | " << range(r.t_ratio)
                << " | " << std::setprecision(3) << 1e3 * r.err.mean() << " | " << 1e3 * r.nominal.mean() << " | "
                << 1e3 * r.predicted.mean() << " | " << r.above_nominal << " | " << r.above_predicted << " |\n"
                << std::flush;
    }
    if (blocks > 0) {
      std::cout << "\nsd ratios per seed (reported sd over the spread): over all " << draws << " draws [over draws 1-"
                << blocks << ", " << blocks + 1 << "-" << 2 * blocks << ", ...]\n";
      auto list = [](const std::vector<double> &v) {
        std::ostringstream os;
        os << std::fixed << std::setprecision(2);
        for (size_t k = 0; k < v.size(); ++k)
          os << (k ? " " : "") << v[k];
        return os.str();
      };
      for (const Row &r : rows)
        for (const Row::SeedRatios &s : r.per_seed)
          std::cout << "  " << r.robot << " " << r.method << " f " << r.focal << " " << std::setprecision(2) << r.noise
                    << " px " << r.factor << "x seed " << s.seed << ":"
                    << (r.focal == "known" ? std::string()
                                           : " f " + list({s.f_all}) + " [" + list(s.f_blocks) + "];")
                    << " eMc.t " << list({s.t_all}) << " [" << list(s.t_blocks) << "]\n";
    }
    std::cout << "\nselection margins (new direction of a column: smallest estimated / largest dependent; threshold "
              << std::scientific << std::setprecision(0) << vpKinematicIdentification::Options().rank_tolerance << "):";
    for (const auto &m : margins)
      std::cout << " " << m.first << " " << std::scientific << std::setprecision(1) << m.second.first << " / "
                << m.second.second << ";";
    std::cout << std::fixed << "\n\ntargets: the same estimated set in every draw of a seed: "
              << (sets_met ? "met" : "NOT met")
              << "; no ok run above 2x the nominal model's held-out error or 5x its own predicted error: "
              << (bad_met ? "met" : "NOT met") << "; reported sd within 0.7-1.4x the spread (f, eMc.t, every seed): "
              << (sd_met ? "met" : "NOT met") << "\ndone in " << std::setprecision(0)
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count() << " s\n";
    return EXIT_SUCCESS;
  } catch (const vpException &e) {
    std::cerr << "bench-trust: " << e.getStringMessage() << "\n";
  } catch (const std::exception &e) {
    std::cerr << "bench-trust: " << e.what() << "\n";
  }
  return EXIT_FAILURE;
}
