/*
 * bench-hd: how long `visp-selfcalib calibrate` takes on HD images, where the time goes, and what it
 * gives. A hand-eye data set of the reference scenario (simulated Viper850, controller poses, textured
 * scene) rendered at W x H (the focal length scaled with the height: the same vertical field of view
 * as the 640 x 480 reference camera), then calibrated as a user would:
 *
 *   visp-selfcalib calibrate DS.yaml --out DIR --method hand-eye --folds K --threads T
 *
 * Its progress lines (stderr) are stamped as they come: the image front end, the calibration on every
 * view and the K folds of the cross-validation each get their wall time. results.yaml then gives the
 * calibrated eMc (against the simulation's truth), f and the RMS figures. The same on a dataset
 * file of images (--dataset, e.g. an imported real set), its reference eMc given by --reference.
 *
 *   bench-hd [--size 1280x720] [--views 12] [--seeds 1] [--folds 5] [--threads 2] [--work DIR]
 *   bench-hd --dataset DS.yaml [--reference tx,ty,tz,tux,tuy,tuz] [--with 'CALIBRATE-OPTIONS']
 *
 * Target: 12 views of 1280 x 720, hand-eye with 5-fold cross-validation, under 30 s on 2 cores.
 */
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <yaml-cpp/yaml.h>

#include <visp3/core/vpPoseVector.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibFileWriter.h>
#include <visp3/selfcalib/vpSelfCalibRenderer.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "benchCommon.h"
#include "selfcalibCli.h"

namespace fs = std::filesystem;

namespace
{
using Clock = std::chrono::steady_clock;

//! The wall time of each stage of one calibrate run, and its exit code.
struct Timing {
  double front_end = 0, calibration = 0, cross_validation = 0, rest = 0, total = 0;
  double cpu = 0; //!< user + system seconds of the run (its threads summed): the machine's load aside
  std::vector<double> folds;
  int exit_code = -1;
  std::string last_line;
};

//! What results.yaml says.
struct Figures {
  std::string status;
  vpHomogeneousMatrix eMc;
  double px = NAN, rms = NAN, cv_rms = NAN;
  bool ok = false;
};

std::string quote(const std::string &s) { return "'" + s + "'"; }

/*
  Runs the command, its stderr and stdout merged and read line by line: the stage a progress line
  ("... STAGE") opens lasts until the next stage of another kind starts.
*/
double childrenCpu()
{
  rusage u;
  getrusage(RUSAGE_CHILDREN, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

Timing runTimed(const std::string &command, const std::string &log_file)
{
  const double cpu0 = childrenCpu();
  Timing t;
  std::ofstream log(log_file);
  const auto t0 = Clock::now();
  FILE *p = popen((command + " 2>&1").c_str(), "r");
  if (!p)
    throw std::runtime_error("cannot run " + command);
  enum Stage { NONE, FRONT_END, CALIBRATION, FOLD, REST } stage = NONE;
  auto last = t0;
  auto close = [&](Stage next) {
    const auto now = Clock::now();
    const double s = std::chrono::duration<double>(now - last).count();
    if (stage == FRONT_END)
      t.front_end += s;
    else if (stage == CALIBRATION || stage == NONE)
      t.calibration += s;
    else if (stage == FOLD)
      t.folds.back() += s;
    else
      t.rest += s;
    last = now;
    stage = next;
  };
  char buf[4096];
  while (fgets(buf, sizeof buf, p)) {
    std::string line(buf);
    log << line << std::flush;
    if (!line.empty() && line.back() == '\n')
      line.pop_back();
    if (line.rfind("... ", 0) != 0) {
      if (!line.empty())
        t.last_line = line;
      continue;
    }
    const std::string what = line.substr(4);
    if (what.rfind("image front end", 0) == 0 || what.rfind("board", 0) == 0)
      close(FRONT_END);
    else if (what.rfind("cross-validation fold ", 0) == 0 && what.find(':') == std::string::npos) {
      close(FOLD);
      t.folds.push_back(0);
    } else if (what.rfind("cross-validation fold ", 0) == 0)
      continue;
    else if (what == "cross-validation" || what.rfind("report", 0) == 0)
      close(REST);
    else if (stage == FRONT_END || stage == NONE)
      close(CALIBRATION);
  }
  close(REST);
  const int status = pclose(p);
  t.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  t.total = std::chrono::duration<double>(Clock::now() - t0).count();
  t.cpu = childrenCpu() - cpu0;
  for (double f : t.folds)
    t.cross_validation += f;
  return t;
}

Figures readResults(const std::string &file)
{
  Figures f;
  if (!fs::exists(file))
    return f;
  const YAML::Node r = YAML::LoadFile(file);
  f.status = r["status"].as<std::string>();
  if (r["eMc"] && r["eMc"]["pose"]) {
    vpPoseVector p;
    for (unsigned int i = 0; i < 6; ++i)
      p[i] = r["eMc"]["pose"][i].as<double>();
    f.eMc.buildFrom(p);
    f.ok = true;
  }
  if (r["camera"])
    f.px = r["camera"]["px"].as<double>();
  if (r["bundle_adjustment"])
    f.rms = r["bundle_adjustment"]["rms_px"].as<double>();
  if (r["cross_validation"] && r["cross_validation"]["rms_px"])
    f.cv_rms = r["cross_validation"]["rms_px"]["calibrated"]["mean"].as<double>();
  return f;
}

//! Translation (m) and rotation (rad) between two poses.
std::pair<double, double> poseError(const vpHomogeneousMatrix &a, const vpHomogeneousMatrix &b)
{
  const vpHomogeneousMatrix d = a.inverse() * b;
  return {d.getTranslationVector().frobeniusNorm(), vpThetaUVector(d.getRotationMatrix()).getTheta()};
}

//! The simulated hand-eye set at width x height, its images in dir; returns the dataset file.
std::string makeDataset(const std::string &dir, unsigned int width, unsigned int height, unsigned int views,
                        uint64_t seed, vpHomogeneousMatrix &true_eMc, double &true_px)
{
  vpSelfCalibSimulator::Options so;
  so.seed = seed;
  so.width = width;
  so.height = height;
  so.px = so.py = 1500.0 * height / 480.0;
  so.u0 = 0.5 * width;
  so.v0 = 0.5 * height;
  const vpSelfCalibSimulator sim(vpKinematicChain::fromPresetOrFile("viper850"), so);
  const std::vector<vpColVector> qs = sim.generateConfigurations(views);
  vpSelfCalibDataset ds = sim.makeDataset(qs);
  ds.robot = "viper850";
  vpSelfCalibRenderer::Options ro;
  ro.seed = seed;
  const vpSelfCalibRenderer renderer(sim, ro);
  fs::create_directories(dir);
  for (size_t k = 0; k < ds.views.size(); ++k) {
    vpSelfCalibDataset::View &v = ds.views[k];
    const std::string image = dir + "/" + std::to_string(k + 1) + ".png";
    vpSelfCalibFileWriter::writeImage(image, renderer.render(qs[k], static_cast<unsigned int>(k)));
    v.image = image;
    v.points.clear();
    v.has_fMe = true;
    v.fMe = sim.getTrueChain().get_fMe(v.q);
    v.q = vpColVector();
  }
  ds.yardstick.length = renderer.getYardstickLength();
  ds.yardstick.id_a = ds.yardstick.id_b = -1;
  const std::string file = dir + "/ds.yaml";
  ds.saveYaml(file);
  true_eMc = sim.getTrueChain().get_eMc();
  true_px = so.px;
  return file;
}

std::string fixed(double x, int precision)
{
  if (!std::isfinite(x))
    return "–";
  std::ostringstream os;
  os << std::fixed << std::setprecision(precision) << x;
  return os.str();
}

void printRow(const std::string &label, const Timing &t, const Figures &f, const vpHomogeneousMatrix *truth,
              double true_px)
{
  std::string err_t = "–", err_r = "–";
  if (truth && f.ok) {
    const auto e = poseError(*truth, f.eMc);
    err_t = fixed(1e3 * e.first, 2);
    err_r = fixed(1e3 * e.second, 2);
  }
  std::ostringstream folds;
  for (size_t i = 0; i < t.folds.size(); ++i)
    folds << (i ? " " : "") << fixed(t.folds[i], 1);
  std::cout << "| " << label << " | " << (f.status.empty() ? "exit " + std::to_string(t.exit_code) : f.status)
            << " | " << fixed(t.total, 1) << " | " << fixed(t.cpu, 1) << " | " << fixed(t.front_end, 1) << " | " << fixed(t.calibration, 1) << " | "
            << fixed(t.cross_validation, 1) << " (" << folds.str() << ") | " << fixed(t.rest, 1) << " | " << err_t
            << " | " << err_r << " | " << fixed(f.px, 1)
            << (std::isfinite(true_px) ? " (" + fixed(true_px, 0) + ")" : std::string()) << " | " << fixed(f.rms, 3)
            << " | " << fixed(f.cv_rms, 3) << " |\n";
  if (f.status.empty())
    std::cout << "  (no results.yaml; last line: " << t.last_line << ")\n";
}

std::string appPath(const char *argv0)
{
  const fs::path self = fs::absolute(argv0).parent_path();
  for (const fs::path &p : {self / "visp-selfcalib", self.parent_path() / "bin" / "visp-selfcalib"})
    if (fs::exists(p))
      return p.string();
  return "visp-selfcalib";
}
} // namespace

int main(int argc, char **argv)
{
  try {
    std::string size = "1280x720", work, dataset, app = appPath(argv[0]), csv_path;
    unsigned int views = 12, seeds = 1, folds = 5, threads = 2;
    std::vector<double> reference;
    std::string with;
    CLI::App cli("bench-hd: the wall time of `visp-selfcalib calibrate --method hand-eye --folds K` on HD images,\n"
                 "stage by stage, and its accuracy (rendered hand-eye set, or a dataset of images).",
                 "bench-hd");
    cli.add_option("--size", size, "rendered image size WxH (default 1280x720)")->type_name("WxH");
    cli.add_option("--views", views, "rendered views (default 12)")->check(selfcalibCli::wholeNumber(3, 200));
    cli.add_option("--seeds", seeds, "rendered sets, seeds 1..N (default 1)")->check(selfcalibCli::wholeNumber(1, 100));
    cli.add_option("--folds", folds, "cross-validation folds (default 5)")->check(selfcalibCli::wholeNumber(2, 100));
    cli.add_option("--threads", threads, "calibrate --threads (default 2)")->check(selfcalibCli::wholeNumber(1, 1024));
    cli.add_option("--work", work, "where the sets and runs go (default: a fresh directory under /tmp, removed)")
        ->type_name("DIR");
    cli.add_option("--dataset", dataset, "a dataset of images instead of rendered sets")->type_name("FILE");
    cli.add_option("--reference", reference, "with --dataset: the reference eMc (tx,ty,tz,tux,tuy,tuz; m, rad)")
        ->delimiter(',')
        ->expected(6)
        ->type_name("POSE");
    cli.add_option("--app", app, "the visp-selfcalib program (default: beside this one)")->type_name("FILE");
    cli.add_option("--with", with, "more calibrate options, as one argument (e.g. '--board chessboard:9x6:0.0236')")
        ->type_name("OPTIONS");
    cli.add_option("--csv", csv_path, "one row per run")->type_name("FILE");
    const int parsed = selfcalibCli::parse(cli, argc, argv);
    if (parsed >= 0)
      return parsed;
    unsigned int width = 0, height = 0;
    if (std::sscanf(size.c_str(), "%ux%u", &width, &height) != 2 || width < 64 || height < 64 || width > 8192 ||
        height > 8192) {
      std::cerr << "error: --size: expected WxH, 64 to 8192 each, got '" + size + "'\n";
      return 2;
    }
    const bool temporary = work.empty();
    if (temporary)
      work = (fs::temp_directory_path() / ("bench-hd-" + std::to_string(getpid()))).string();
    fs::create_directories(work);
    const std::string more = with.empty() ? std::string() : " " + with; // split by the shell

    std::cout << "| set | status | total s | cpu s | front end s | calibration s | cross-validation s (folds) | report s "
                 "| eMc error mm | eMc error mrad | f px (true) | rms px | held-out rms px |\n"
                 "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
    bench::Stats totals;
    auto calibrate = [&](const std::string &ds, const std::string &out) {
      const std::string cmd = quote(app) + " calibrate " + quote(ds) + " --out " + quote(out) +
                              " --method hand-eye --force --folds " + std::to_string(folds) + " --threads " +
                              std::to_string(threads) + more;
      const Timing t = runTimed(cmd, out + ".log");
      totals.add(t.total);
      return std::make_pair(t, readResults(out + "/results.yaml"));
    };
    if (!dataset.empty()) {
      vpHomogeneousMatrix ref;
      if (reference.size() == 6)
        ref.buildFrom(vpPoseVector(reference[0], reference[1], reference[2], reference[3], reference[4], reference[5]));
      const auto r = calibrate(dataset, work + "/run");
      printRow(fs::path(dataset).filename().string(), r.first, r.second, reference.size() == 6 ? &ref : nullptr, NAN);
    } else
      for (unsigned int s = 1; s <= seeds; ++s) {
        vpHomogeneousMatrix truth;
        double true_px = 0;
        const std::string dir = work + "/set-" + std::to_string(s);
        const std::string ds = makeDataset(dir, width, height, views, s, truth, true_px);
        const auto r = calibrate(ds, dir + "/run");
        printRow(std::to_string(views) + " x " + size + ", seed " + std::to_string(s), r.first, r.second, &truth,
                 true_px);
      }
    if (temporary)
      fs::remove_all(work);
    std::cout << "\ntargets:\n- " << (dataset.empty() ? std::to_string(views) + " views of " + size : dataset)
              << ", hand-eye with " << folds << "-fold cross-validation under 30 s on " << threads
              << " threads: worst " << fixed(*std::max_element(totals.v.begin(), totals.v.end()), 1) << " s, "
              << (*std::max_element(totals.v.begin(), totals.v.end()) < 30 ? "met" : "NOT met") << "\ndone\n";
    return 0;
  } catch (const std::exception &e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
}
