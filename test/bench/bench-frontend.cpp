/*
 * bench-frontend: the image front end (vpFeatureFrontEnd) on rendered images of the reference
 * scenario (simulated Viper850, textured ridge, blur and noise): time, share of the track
 * observations within 1 px of their true projection, median track length; kinematics-guided
 * matching (the nominal model as the only prior: the images come from the true robot) against
 * unguided matching of every pair, and a wrong prior (the nominal eMc rotated by 10 degrees: the
 * front end must detect it and fall back).
 *
 *   bench-frontend [--images 25,100] [--seed N] [--threads N] [--unguided-max N]
 *   bench-frontend --real DATASET.yaml [--mask-board SPEC] [--prior-sd T,R]   (real images: what the
 *     natural-feature path finds, guided by the dataset's robot model and unguided; no truth)
 */
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <sys/resource.h>

#include <visp3/core/vpMath.h>
#include <opencv2/imgproc.hpp>
#include <visp3/selfcalib/vpBoardDetector.h>
#include <visp3/selfcalib/vpFeatureFrontEnd.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibImageCorrespondences.h>
#include <visp3/selfcalib/vpSelfCalibRenderer.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "../../modules/selfcalib/test/frontend/frontEndTruth.h"
#include "selfcalibCli.h"

namespace
{
double cpuSeconds()
{
  rusage u;
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}
double since(std::chrono::steady_clock::time_point t0)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
// Real images: the front end guided by the dataset's robot model (and its eMc guess) and unguided,
// with the board masked out when asked (its points' convex hull, dilated by 15 px).
int realData(const std::string &file, const std::string &mask_board, const std::vector<double> &prior_sd,
             unsigned int threads)
{
  vpSelfCalibDataset ds = vpSelfCalibDataset::loadYaml(file);
  const vpKinematicChain model = vpKinematicChain::fromPresetOrFile(ds.robot);
  const std::vector<vpImage<unsigned char>> images = vpFeatureFrontEnd::readImages(ds, "bench-frontend");
  vpFeatureFrontEnd::Options base;
  base.threads = threads;
  unsigned int masked = 0;
  if (!mask_board.empty()) {
    const vpBoardDetector detector(vpBoardDetector::parse(mask_board));
    for (const vpImage<unsigned char> &I : images) {
      const vpBoardDetector::Result b = detector.detect(I);
      const vpImage<unsigned char> mask = vpSelfCalibImageCorrespondences::boardMask(b, I.getHeight(), I.getWidth(), 15);
      masked += b.found;
      base.masks.push_back(mask);
    }
  }
  std::cout << "bench-frontend --real " << file << ": " << images.size() << " images " << images[0].getWidth() << " x "
            << images[0].getHeight() << ", robot " << ds.robot << "; board masked in " << masked << " images\n\n"
            << "| matching | pairs matched | pairs >= 20 matches | verified matches | tracks | median track length | "
               "track lengths (2, 3, 4, 5+) | front end (s) | note |\n|---|---|---|---|---|---|---|---|---|\n";
  for (bool guided : {true, false}) {
    vpFeatureFrontEnd::Options fo = base;
    if (guided) {
      fo.prior = vpSelfCalibImageCorrespondences::makePrior(model, ds);
      if (prior_sd.size() == 2) {
        fo.prior.translation_sd = prior_sd[0];
        fo.prior.rotation_sd = prior_sd[1];
      }
    }
    const vpFeatureFrontEnd::Result fe = vpFeatureFrontEnd::process(images, fo);
    unsigned int good = 0, total = 0;
    for (const auto &row : fe.matches)
      for (unsigned int c : row) {
        good += c >= 20;
        total += c;
      }
    std::vector<unsigned int> lengths;
    unsigned int h[4] = {0, 0, 0, 0};
    for (size_t n = 2; n < fe.track_lengths.size(); ++n) {
      h[std::min<size_t>(n, 5) - 2] += fe.track_lengths[n];
      lengths.insert(lengths.end(), fe.track_lengths[n], static_cast<unsigned int>(n));
    }
    std::ostringstream note;
    note << (fe.guided ? "guided" : (fe.fallback ? "fell back" : "no prior"));
    if (fe.prior_agreement >= 0)
      note << std::fixed << std::setprecision(2) << "; agreement " << fe.prior_agreement;
    for (const std::string &w : fe.warnings)
      note << "; " << w;
    std::cout << "| " << (guided ? "guided (robot model + eMc guess)" : "unguided (every pair)") << " | "
              << fe.pairs_matched << " | " << good << " | " << total << " | " << fe.num_tracks << " | "
              << (lengths.empty() ? 0u : lengths[lengths.size() / 2]) << " | " << h[0] << ", " << h[1] << ", " << h[2]
              << ", " << h[3] << " | " << std::fixed << std::setprecision(2) << fe.seconds << " | " << note.str()
              << " |\n";
  }
  return EXIT_SUCCESS;
}
} // namespace

int main(int argc, char **argv)
{
  std::vector<unsigned int> counts = {25, 100};
  unsigned int seed = 1, threads = 2, unguided_max = 25;
  double tolerance = 1.0;
  vpFeatureFrontEnd::Options base;
  CLI::App app("bench-frontend: the image front end on rendered images, guided by the nominal kinematics or not:\n"
               "time, track observations within 1 px of the truth, median track length.",
               "bench-frontend");
  app.add_option("--images", counts, "numbers of rendered images (default 25,100)")
      ->type_name("N,...")
      ->delimiter(',')
      ->check(selfcalibCli::wholeNumber(2));
  app.add_option("--seed", seed, "scenario seed (default 1)")->type_name("N")->check(selfcalibCli::wholeNumber());
  app.add_option("--threads", threads, "front-end threads (default 2)")->type_name("N")->check(selfcalibCli::wholeNumber(1));
  app.add_option("--unguided-max", unguided_max,
                 "unguided matching (every pair) only up to this many images (default 25)")
      ->type_name("N")
      ->check(selfcalibCli::wholeNumber());
  app.add_option("--tolerance", tolerance, "px: an observation within it of its true projection is correct (default 1)")
      ->type_name("PX")
      ->check(selfcalibCli::number(0, true));
  app.add_option("--guided-ratio", base.guided_ratio, "the front end's guided_ratio (default 0.7)")
      ->type_name("R")
      ->check(selfcalibCli::number(0, true));
  app.add_option("--track-tolerance", base.track_tolerance, "the front end's track_tolerance (px, default 1)")
      ->type_name("PX")
      ->check(selfcalibCli::number(0, true));
  app.add_option("--neighbours", base.neighbours, "the front end's neighbours (default 8)")
      ->type_name("N")
      ->check(selfcalibCli::wholeNumber(1));
  std::string real, mask_board;
  std::vector<double> prior_sd;
  app.add_option("--real", real, "a dataset (visp-selfcalib import): its images through the front end, no truth")
      ->type_name("DATASET");
  app.add_option("--mask-board", mask_board, "with --real: mask the board out (vpBoardDetector spec)")->type_name("SPEC");
  app.add_option("--prior-sd", prior_sd, "with --real: the prior's relative-pose sd (m, rad; default 0.005,0.005)")
      ->type_name("T,R")
      ->delimiter(',')
      ->expected(2);
  const int parsed = selfcalibCli::parse(app, argc, argv);
  if (parsed >= 0)
    return parsed;
  try {
    if (!real.empty())
      return realData(real, mask_board, prior_sd, threads);
    const vpKinematicChain nominal = vpKinematicChain::preset("viper850");
    vpSelfCalibSimulator::Options so;
    so.seed = seed;
    const vpSelfCalibSimulator sim(nominal, so);
    vpSelfCalibRenderer::Options ro;
    ro.seed = seed;
    const vpSelfCalibRenderer renderer(sim, ro);
    std::cout << "bench-frontend: viper850, seed " << seed << ", " << threads
              << " threads; prior = nominal model (images from the true robot)\n\n";
    std::cout << "| images | matching | pairs matched | render (s) | front end (s) (detection + matching) | front end CPU (s) | tracks | observations within 1 px (%) "
                 "| tracks all within 1 px (%) (of 3+ views) | median track length | note |\n"
              << "|---|---|---|---|---|---|---|---|---|---|---|\n";
    bool met_speed = true, met_robust = true, met_fallback = true;
    for (unsigned int n : counts) {
      const std::vector<vpColVector> q = sim.generateConfigurations(n);
      auto t0 = std::chrono::steady_clock::now();
      std::vector<vpImage<unsigned char>> images;
      for (unsigned int k = 0; k < n; ++k)
        images.push_back(renderer.render(q[k], k));
      const double t_render = since(t0);
      const vpSelfCalibDataset ds = sim.makeDataset(q);
      const vpFeatureFrontEnd::Prior prior = vpSelfCalibImageCorrespondences::makePrior(nominal, ds);
      vpFeatureFrontEnd::Prior wrong = prior;
      const vpHomogeneousMatrix R10(0, 0, 0, vpMath::rad(10) / std::sqrt(2.0), vpMath::rad(10) / std::sqrt(2.0), 0);
      for (vpHomogeneousMatrix &M : wrong.fMc)
        M = M * R10; // eMc rotated by 10 degrees
      struct Row {
        std::string name;
        const vpFeatureFrontEnd::Prior *prior;
      };
      std::vector<Row> rows = {{"guided (nominal model)", &prior}};
      if (n <= unguided_max) {
        rows.push_back({"unguided (every pair)", nullptr});
        rows.push_back({"prior with eMc 10 deg off", &wrong});
      }
      for (const Row &row : rows) {
        vpFeatureFrontEnd::Options fo = base;
        fo.threads = threads;
        if (row.prior)
          fo.prior = *row.prior;
        t0 = std::chrono::steady_clock::now();
        const double c0 = cpuSeconds();
        const vpFeatureFrontEnd::Result fe = vpFeatureFrontEnd::process(images, fo);
        const double t_fe = since(t0), c_fe = cpuSeconds() - c0;
        const FrontEndTruth t = checkTracks(sim, renderer, q, fe, tolerance);
        std::string note = fe.guided ? "guided" : (fe.fallback ? "fell back: prior rejected" : "no prior");
        if (fe.prior_agreement >= 0) {
          std::ostringstream os;
          os << std::fixed << std::setprecision(2) << "; agreement " << fe.prior_agreement;
          note += os.str();
        }
        std::cout << "| " << n << " | " << row.name << " | " << fe.pairs_matched << " | " << std::fixed
                  << std::setprecision(1) << t_render << " | " << std::setprecision(2) << t_fe << " (" << fe.seconds_detection
                  << " + " << fe.seconds_matching << ") | " << c_fe << " | " << fe.num_tracks
                  << " | " << std::setprecision(1) << 100 * t.observationFraction() << " | "
                  << 100 * t.trackFraction() << " (" << 100 * t.longTrackFraction() << ") | " << std::setprecision(0) << t.median_length << " | " << note
                  << " |\n";
        if (row.prior == &prior) {
          met_speed = met_speed && (n > 25 || t_fe < 3) && (n > 100 || t_fe < 20);
          met_robust = met_robust && fe.guided && t.observationFraction() >= 0.9 && t.median_length >= 5;
        }
        if (row.prior == &wrong)
          met_fallback = met_fallback && fe.fallback && !fe.warnings.empty();
      }
    }
    std::cout << "\ntargets (issue 19): guided front end under 3 s for 25 images and 20 s for 100: "
              << (met_speed ? "met" : "NOT met") << "; >= 90 % of observations within 1 px and median track length >= 5: "
              << (met_robust ? "met" : "NOT met") << "; wrong prior detected and fallen back: "
              << (met_fallback ? "met" : "NOT met") << "\n";
    return EXIT_SUCCESS;
  } catch (const vpException &e) {
    std::cerr << "error: " << e.getStringMessage() << std::endl;
    return EXIT_FAILURE;
  }
}
