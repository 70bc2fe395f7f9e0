/*
 * ViSP SelfCalib: the report of a calibration run (report.md, data files, gnuplot figures).
 */
#include <visp3/selfcalib/vpSelfCalibReport.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <opencv2/imgcodecs.hpp>

#include "../core/vpSelfCalibCamera.h"
#include "vpSelfCalibYaml.h"

using namespace vpSelfCalib;

namespace
{
/*
  Reprojection residual norms (px) of every observation of the views, points triangulated from them;
  a point the camera does not see through its lens model (CameraModel::withImage() on the
  width x height image) is left out.
*/
std::vector<std::vector<double>> residuals(const vpKinematicChain &model, const vpCameraParameters &cam,
                                           const std::vector<vpSelfCalibDataset::View> &views, unsigned int width,
                                           unsigned int height)
{
  std::vector<std::vector<double>> out(views.size());
  if (views.size() < 2)
    return out;
  const std::map<int, vpColVector> X = vpCalibrationVerifier::triangulate(model, cam, views);
  const vpSelfCalib::CameraModel camera = vpSelfCalib::CameraModel::fromVisp(cam).withImage(width, height);
  for (size_t k = 0; k < views.size(); ++k) {
    const vpHomogeneousMatrix cMf = vpCalibrationVerifier::cameraPose(model, views[k]).inverse();
    for (const auto &o : views[k].points) {
      auto it = X.find(o.id);
      if (it == X.end())
        continue;
      vpColVector P(4, 1.0);
      for (unsigned int a = 0; a < 3; ++a)
        P[a] = it->second[a];
      const vpColVector c = cMf * P;
      const Eigen::Vector3d Xc(c[0], c[1], c[2]);
      if (!camera.sees(Xc))
        continue; // behind the camera, or outside its lens model's valid region
      const Eigen::Vector2d uv = camera.project(Xc);
      out[k].push_back(std::hypot(uv(0) - o.ip.get_u(), uv(1) - o.ip.get_v()));
    }
  }
  return out;
}

void writeText(const std::string &file, const std::string &text, std::vector<std::string> &files)
{
  writeFileAtomically(file, text, "report file");
  files.push_back(file);
}

std::string mm(double m, int precision = 3)
{
  std::ostringstream os;
  os << std::fixed << std::setprecision(precision) << 1e3 * m;
  return os.str();
}

//! One figure of plots.gp: its name (name.png from name.dat) and its gnuplot commands.
struct Figure {
  const char *name;
  const char *commands;
};

const char *kPlotsHeader = "# Figures of the ViSP SelfCalib report: gnuplot plots.gp (in this directory)\n"
                           "set terminal pngcairo size 800,600\n"
                           "set grid\n";

const Figure kFigures[] = {
    {"trajectory", R"(set output 'trajectory.png'
set title 'Camera positions (calibrated model), m'
set xlabel 'x'
set ylabel 'y'
set zlabel 'z'
set format xy '%.2f'
splot 'trajectory.dat' index 0 using 1:2:3 with linespoints title 'calibration views', \
      '' index 1 using 1:2:3 with points pt 7 title 'held-out views'
set format xy '%g'
)"},
    {"position_norms", R"(set output 'position_norms.png'
set title 'Norm of the position vector |t_i| of c_i M c_1 (calibrated model)'
set xlabel 'pose i'
set ylabel '|t_i| (m)'
plot 'position_norms.dat' using 1:2 with linespoints notitle
)"},
    {"residuals", R"(set output 'residuals.png'
set title 'Reprojection residuals on the calibration views'
set xlabel 'residual (px)'
set ylabel 'observations'
binwidth = 0.05
bin(x) = binwidth * floor(x / binwidth) + binwidth / 2
set boxwidth binwidth
set style fill solid 0.5
plot 'residuals.dat' using (bin($1)):(1.0) smooth freq with boxes notitle
)"},
    {"verification", R"(set output 'verification.png'
set title 'Reprojection RMS of each held-out view (points triangulated on the held-out views)'
set xlabel 'held-out view'
set ylabel 'RMS (px)'
set style fill solid 0.5
set boxwidth 0.6
plot 'verification.dat' using 1:2 with boxes notitle
)"},
    {"errors_vs_poses", R"(set output 'errors_vs_poses.png'
set title '3-D yardstick error on the held-out views against the number of calibration poses'
set xlabel 'calibration poses'
set ylabel 'error (mm)'
plot 'errors_vs_poses.dat' using 1:2 with linespoints title 'calibrated', \
     '' using 1:3 with lines dt 2 title 'nominal'
)"},
    {"view_residuals", R"(set output 'view_residuals.png'
set title 'Reprojection RMS of each calibration view (points triangulated on the calibration views)'
set xlabel 'calibration view'
set ylabel 'RMS (px)'
set style data histogram
set style histogram clustered gap 1
set style fill solid 0.5
plot 'view_residuals.dat' using 2:xtic(1) title 'calibrated model', '' using 3 title 'nominal model'
reset
set grid
)"},
    {"matches", R"(set output 'matches.png'
set title 'Verified matches of each image pair (white: not matched)'
set xlabel 'image'
set ylabel 'image'
set size ratio -1
set yrange [*:*] reverse
set autoscale fix
set palette defined (0 'white', 1 '#9ecae1', 2 '#08306b')
set cblabel 'matches'
plot 'matches.dat' matrix using ($1 + 1):($2 + 1):3 with image notitle
reset
set grid
)"},
    {"track_lengths", R"(set output 'track_lengths.png'
set title 'Track lengths: scene points seen in n images'
set xlabel 'images per track'
set ylabel 'tracks'
set style fill solid 0.5
set boxwidth 0.8
set xtics 1
plot 'track_lengths.dat' using 1:2 with boxes notitle
)"},
};
//! The figures drawn only when the image front end ran (the last two of kFigures).
const size_t kFrontEndFigures = 2;

//! True when a data file has a data line (not a comment, not blank).
bool hasData(const std::string &text)
{
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    const size_t c = line.find_first_not_of(" \t");
    if (c != std::string::npos && line[c] != '#')
      return true;
  }
  return false;
}

/*!
  Runs `program script` in `dir` with its output in dir/gnuplot.log: posix_spawnp with an argument
  vector, no shell (a path is never parsed as a command). Returns the exit status, or -1 with
  `spawn_error` set (errno) when the program could not be started (not installed: ENOENT), or -2
  when the log cannot be created.
*/
int runProgram(const std::string &program, const std::string &dir, const std::string &script, int &spawn_error)
{
  spawn_error = 0;
  // The log is opened here, so that a failure of the spawn itself (ENOENT) means the program is missing.
  const std::string log = (std::filesystem::path(dir) / "gnuplot.log").string();
  const int log_fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (log_fd < 0) {
    spawn_error = errno;
    return -2;
  }
  const std::string abs_dir = std::filesystem::absolute(dir).string();
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addchdir_np(&actions, abs_dir.c_str());
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, log_fd, STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, log_fd, STDERR_FILENO);
  std::vector<std::string> args = {program, script};
  std::vector<char *> argv;
  for (std::string &a : args)
    argv.push_back(&a[0]);
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, program.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(log_fd);
  if (rc != 0) {
    spawn_error = rc;
    return -1;
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) {
      spawn_error = errno;
      return -1;
    }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}
std::string px(double v)
{
  std::ostringstream os;
  os << std::fixed << std::setprecision(3) << v;
  return os.str();
}

// The k-fold cross-validation: the figure, then one row per fold (failed folds with their status).
void crossValidationSection(std::ostream &md, const vpSelfCalibCrossValidation::Result &cv)
{
  md << "\n## Cross-validation\n\n"
     << cv.folds << " folds over the " << cv.views << " views (views numbered from 1: view n is held out in fold "
     << "((n - 1) mod " << cv.folds << ") + 1): each fold calibrates on the others and predicts the held-out views' pixels from the scene "
        "the training views triangulate, through the calibrated model and camera, and through the nominal "
        "model with the dataset's camera. No true pose is needed: this is the figure to trust on real data. "
        "Image noise alone gives an RMS of sqrt(2) times the pixel sd.\n\n";
  if (cv.num_ok > 0)
    md << "Held-out reprojection RMS: calibrated **" << px(cv.calibrated_rms.mean) << " px** (sd "
       << px(cv.calibrated_rms.sd) << ", " << px(cv.calibrated_rms.min) << " to " << px(cv.calibrated_rms.max)
       << "), nominal " << px(cv.nominal_rms.mean) << " px (sd " << px(cv.nominal_rms.sd) << ", "
       << px(cv.nominal_rms.min) << " to " << px(cv.nominal_rms.max) << "); median " << px(cv.calibrated_median.mean)
       << " px calibrated, " << px(cv.nominal_median.mean) << " px nominal; over " << cv.num_ok << " of " << cv.folds
       << " folds.\n\n";
  else
    md << "No fold measured: " << cv.message << ".\n\n";
  md << "| fold | held-out views | status | f_x (px) | RMS calibrated (px) | RMS nominal (px) | median calibrated "
        "(px) | median nominal (px) | observations | yardstick error calibrated / nominal (mm) |\n"
        "|---|---|---|---|---|---|---|---|---|---|\n";
  for (size_t f = 0; f < cv.fold.size(); ++f) {
    const vpSelfCalibCrossValidation::Fold &d = cv.fold[f];
    std::string views;
    for (unsigned int i : d.held_out)
      views += (views.empty() ? "" : " ") + std::to_string(i + 1);
    // A doubtful fold's model predicts the held-out views too (its figures are in the means above).
    const bool ok = d.status == vpRobotSelfCalibration::OK;
    const bool measured = ok || d.status == vpRobotSelfCalibration::DOUBTFUL;
    md << "| " << f + 1 << " | " << views << " | " << vpRobotSelfCalibration::statusName(d.status)
       << (ok ? "" : ": " + d.message) << " | " << (measured ? px(d.fx) : "-") << " | "
       << (measured ? px(d.calibrated.rms) : "-") << " | " << px(d.nominal.rms) << " | "
       << (measured ? px(d.calibrated.median) : "-") << " | " << px(d.nominal.median) << " | " << d.nominal.observations
       << " | "
       << (d.verified ? mm(d.yardstick_error_calibrated) + " / " + mm(d.yardstick_error_nominal) : std::string("-"))
       << " |\n";
  }
}

// The calibration verified on a second dataset.
void heldOutSection(std::ostream &md, const vpSelfCalibCrossValidation::HeldOut &h)
{
  md << "\n## Held-out dataset\n\n"
     << "The calibrated model on a second dataset of " << h.views
     << " views (not used to calibrate). Reprojection error of its views, the scene triangulated from "
        "these views themselves: calibrated "
     << px(h.calibrated.rms) << " px RMS (median " << px(h.calibrated.median) << ", " << h.calibrated.observations
     << " observations), nominal " << px(h.nominal.rms) << " px RMS (median " << px(h.nominal.median) << ").\n";
  if (h.has_yardstick)
    md << "\n3-D yardstick error (the paper's): nominal " << mm(h.yardstick_error_nominal) << " mm, calibrated "
       << mm(h.yardstick_error_calibrated) << " mm.\n";
  else
    md << "\nNo yardstick seen in two of its views: no 3-D error.\n";
}
//! The data files of the figures, and the figures' numbers report.md quotes.
struct ReportData {
  std::string files[8]; //!< one per figure of kFigures, in its order
  std::vector<double> ver_rms; //!< reprojection RMS of each held-out view (px)
  std::vector<double> view_rms; //!< reprojection RMS of each calibration view (px), calibrated model
  double sum2 = 0;             //!< sum of the squared residuals on the calibration views (px^2)
  size_t count = 0;            //!< their number
};

//! The views of a report: the first N calibrate, the others are held out.
struct Views {
  unsigned int N = 0;
  std::vector<vpSelfCalibDataset::View> cal, ver;
};

/*
  The calibration views the calibrated model does not explain while it explains the others: a
  reprojection RMS above 3 px and above 5 times the views' median. Such a view's joints most likely
  do not belong to its image (two poses swapped, a reading of another moment): the bundle
  adjustment drops its observations as outliers and goes on, so the report names it. Empty when
  there is none, or when half the views or more are such (then it is the model, not the views).
*/
std::string unexplainedViews(const std::vector<double> &view_rms)
{
  if (view_rms.size() < 3)
    return "";
  std::vector<double> sorted = view_rms;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(sorted.size() / 2), sorted.end());
  const double median = sorted[sorted.size() / 2], limit = std::max(3.0, 5 * median);
  std::vector<size_t> bad;
  for (size_t k = 0; k < view_rms.size(); ++k)
    if (view_rms[k] > limit)
      bad.push_back(k);
  if (bad.empty() || 2 * bad.size() >= view_rms.size())
    return "";
  std::ostringstream os, rms;
  os << std::fixed << std::setprecision(2) << (bad.size() == 1 ? "view " : "views ");
  for (size_t i = 0; i < bad.size(); ++i) {
    const std::string sep = i == 0 ? "" : (i + 1 == bad.size() ? " and " : ", ");
    os << sep << bad[i];
    rms << sep << std::fixed << std::setprecision(2) << view_rms[bad[i]];
  }
  os << (bad.size() == 1 ? " is" : " are") << " not explained by the calibrated model (reprojection RMS "
     << rms.str() << " px; the views' median " << median
     << " px): the joints of " << (bad.size() == 1 ? "this view" : "these views")
     << " most likely do not belong to " << (bad.size() == 1 ? "its image" : "their images")
     << " (poses swapped, or read at another moment), and their observations were dropped as outliers; check "
        "them, or leave them out of the dataset";
  return os.str();
}

//! The front end's data files: the match matrix, symmetric (the front end fills the upper triangle), and track lengths.
void frontEndData(const vpFeatureFrontEnd::Result &fe, std::ostringstream &match_matrix, std::ostringstream &lengths)
{
  // One row per image.
  match_matrix << "# verified matches of image pair (row, column), images numbered from 0\n";
  const size_t m = fe.matches.size();
  if (m >= 2)
    for (size_t i = 0; i < m; ++i) {
      for (size_t j = 0; j < m; ++j) {
        const unsigned int v = i < j ? (j < fe.matches[i].size() ? fe.matches[i][j] : 0)
                                     : (i < fe.matches[j].size() && i != j ? fe.matches[j][i] : 0);
        match_matrix << (j ? " " : "") << v;
      }
      match_matrix << "\n";
    }
  lengths << "# images per track, tracks\n";
  for (size_t n = 2; n < fe.track_lengths.size(); ++n)
    if (fe.track_lengths[n] > 0)
      lengths << n << " " << fe.track_lengths[n] << "\n";
}

//! The data files of the figures, from the model the report shows (calibrated, or nominal when the run failed).
ReportData reportData(const vpSelfCalibReport::Record &run, const Views &views, const vpKinematicChain &model)
{
  const vpSelfCalibDataset &ds = run.dataset;
  const vpRobotSelfCalibration::Result &r = run.result;
  const unsigned int N = views.N;
  const std::vector<vpSelfCalibDataset::View> &cal = views.cal, &ver = views.ver;
  ReportData out;
  std::ostringstream traj, norms, resid, verif, curve;
  traj << std::setprecision(10) << "# x y z (m): calibration views, then (index 1) held-out views\n";
  for (size_t k = 0; k < ds.views.size(); ++k) {
    if (k == N)
      traj << "\n\n";
    const vpTranslationVector t = vpCalibrationVerifier::cameraPose(model, ds.views[k]).getTranslationVector();
    traj << t[0] << " " << t[1] << " " << t[2] << "\n";
  }
  norms << std::setprecision(10) << "# pose |t_i| (m) of c_i M c_1\n";
  const vpHomogeneousMatrix fMc1 = vpCalibrationVerifier::cameraPose(model, cal[0]);
  for (size_t k = 1; k < cal.size(); ++k)
    norms << k + 1 << " "
          << (vpCalibrationVerifier::cameraPose(model, cal[k]).inverse() * fMc1).getTranslationVector().frobeniusNorm()
          << "\n";
  const auto rc = residuals(model, r.camera, cal, ds.width, ds.height);
  resid << std::setprecision(6) << "# reprojection residual (px), calibration views\n";
  for (const auto &v : rc)
    for (double e : v) {
      resid << e << "\n";
      out.sum2 += e * e;
      ++out.count;
    }
  const auto rv = residuals(model, r.camera, ver, ds.width, ds.height);
  verif << std::setprecision(6) << "# held-out view, reprojection RMS (px)\n";
  for (size_t k = 0; k < rv.size(); ++k) {
    double s = 0;
    for (double e : rv[k])
      s += e * e;
    out.ver_rms.push_back(rv[k].empty() ? 0 : std::sqrt(s / rv[k].size()));
    verif << k + 1 << " " << out.ver_rms.back() << "\n";
  }
  curve << std::setprecision(6) << "# calibration poses, yardstick 3-D error (mm): calibrated, nominal\n";
  if (run.errors_vs_poses)
    for (const vpSelfCalibPoseStudy::Point &p : run.errors_vs_poses->points)
      curve << p.poses << " " << 1e3 * p.yardstick_error << " " << 1e3 * run.errors_vs_poses->nominal_error << "\n";
  // Each calibration view's reprojection RMS, calibrated and nominal: where a user looks for a bad view.
  const auto rn = residuals(run.nominal, ds.cam, cal, ds.width, ds.height);
  const auto rms = [](const std::vector<double> &e) {
    double s = 0;
    for (double x : e)
      s += x * x;
    return e.empty() ? 0.0 : std::sqrt(s / e.size());
  };
  std::ostringstream view_resid, match_matrix, lengths;
  view_resid << std::setprecision(6) << "# calibration view, reprojection RMS (px): calibrated model, nominal model\n";
  if (out.count > 0)
    for (size_t k = 0; k < rc.size(); ++k) {
      view_resid << k + 1 << " " << rms(rc[k]) << " " << (k < rn.size() ? rms(rn[k]) : 0.0) << "\n";
      out.view_rms.push_back(rms(rc[k]));
    }
  if (run.front_end)
    frontEndData(*run.front_end, match_matrix, lengths);
  const std::string data[] = {traj.str(),  norms.str(),      resid.str(),        verif.str(),
                              curve.str(), view_resid.str(), match_matrix.str(), lengths.str()};
  constexpr size_t kNumFigures = sizeof(kFigures) / sizeof(kFigures[0]);
  static_assert(sizeof(data) / sizeof(data[0]) == kNumFigures, "one data file per figure");
  static_assert(sizeof(out.files) / sizeof(out.files[0]) == kNumFigures, "one data file per figure");
  for (size_t i = 0; i < kNumFigures; ++i)
    out.files[i] = data[i];
  return out;
}

//! The message of the figures drawn by gnuplot (or why not); the decoded PNG files into res.files.
void drawFigures(const std::string &dir, const std::vector<std::string> &drawable, const std::string &no_data,
                 const vpSelfCalibReport::Options &ro, vpSelfCalibReport::Result &res)
{
  int spawn_error = 0;
  const int rc_plot = runProgram(ro.gnuplot, dir, "plots.gp", spawn_error);
  std::vector<std::string> bad;
  if (rc_plot == 0)
    for (const std::string &n : drawable) {
      // A figure is kept only when it decodes (gnuplot does not always report a failed write).
      const std::string png = dir + "/" + n + ".png";
      if (cv::imread(png, cv::IMREAD_UNCHANGED).empty()) {
        bad.push_back(n);
        std::error_code ec;
        std::filesystem::remove(png, ec);
      } else
        res.files.push_back(png);
    }
  res.figures = rc_plot == 0 && bad.empty();
  if (rc_plot < 0 && spawn_error == ENOENT)
    res.message = "figures not drawn: '" + ro.gnuplot + "' is not installed (Debian package gnuplot-nox)" + no_data;
  else if (rc_plot == -2)
    res.message = "figures not drawn: cannot write gnuplot.log: " + errnoText(spawn_error) + no_data;
  else if (rc_plot < 0)
    res.message = "figures not drawn: cannot run '" + ro.gnuplot + "': " + errnoText(spawn_error) + no_data;
  else if (rc_plot != 0)
    res.message = "figures not drawn: '" + ro.gnuplot + "' failed (exit " + std::to_string(rc_plot) +
                  "); see gnuplot.log" + no_data;
  else if (!bad.empty())
    res.message = "figures drawn with " + ro.gnuplot + " except " + std::to_string(bad.size()) +
                  " that did not write completely (disk full?)" + no_data;
  else
    res.message = "figures drawn with " + ro.gnuplot + no_data;
}

/*!
  Writes the data files and plots.gp, which draws the figures that have data (the front end's
  figures exist only when it ran), then runs gnuplot; the figures without data into `empty`.
*/
void writeFigures(const std::string &dir, const ReportData &data, bool front_end, const vpSelfCalibReport::Options &ro,
                  vpSelfCalibReport::Result &res, std::vector<std::string> &empty)
{
  constexpr size_t kNumFigures = sizeof(kFigures) / sizeof(kFigures[0]);
  std::string plots = kPlotsHeader;
  std::vector<std::string> drawable;
  for (size_t i = 0; i < kNumFigures; ++i) {
    if (!front_end && i + kFrontEndFigures >= kNumFigures)
      continue;
    writeText(dir + "/" + kFigures[i].name + ".dat", data.files[i], res.files);
    if (hasData(data.files[i])) {
      plots += kFigures[i].commands;
      drawable.push_back(kFigures[i].name);
    } else
      empty.push_back(kFigures[i].name);
  }
  writeText(dir + "/plots.gp", plots, res.files);

  // Figures: gnuplot run without a shell; each cause of a missing figure said as it is.
  std::string no_data;
  for (const std::string &n : empty)
    no_data += (no_data.empty() ? "" : ", ") + n;
  if (!no_data.empty())
    no_data = "; not drawn, no data: " + no_data;
  if (ro.gnuplot.empty())
    res.message = "figures not requested";
  else if (drawable.empty())
    res.message = "figures not drawn: no figure has data" + no_data;
  else
    drawFigures(dir, drawable, no_data, ro, res);
}

//! A figure's link when it was drawn; otherwise why it is not there (no data: the reason given).
struct FigureLink {
  const std::string &dir;
  const vpSelfCalibReport::Result &res;
  const std::vector<std::string> &empty;
  std::string operator()(const std::string &name, const std::string &alt, const std::string &no_data_reason) const
  {
    const std::string png = dir + "/" + name + ".png";
    if (std::find(res.files.begin(), res.files.end(), png) != res.files.end())
      return "![" + alt + "](" + name + ".png)";
    if (std::find(empty.begin(), empty.end(), name) != empty.end())
      return "(figure " + name + ".png not drawn, no data: " + no_data_reason + ")";
    return "(figure " + name + ".png not drawn: " + res.message + ")";
  }
};

//! report.md's head: the run's table, the message, the data check and the stage times.
void runSection(std::ostream &md, const vpSelfCalibReport::Record &run, const Views &views)
{
  const vpRobotSelfCalibration::Result &r = run.result;
  md << "# ViSP SelfCalib report\n\n"
     << "| | |\n|---|---|\n"
     << "| robot | " << run.nominal.getName() << " |\n"
     << "| method | " << vpRobotSelfCalibration::methodName(r.method) << " |\n"
     << "| status | " << vpRobotSelfCalibration::statusName(r.status) << " |\n"
     << "| views | " << views.N << " calibrating, " << views.ver.size() << " held out |\n"
     << "| f_x | " << std::setprecision(7) << r.camera.get_px() << " px (sd " << std::setprecision(3) << r.fx_sd
     << "), " << (run.dataset.focal_known ? "known" : "self-calibrated") << " |\n";
  if (r.method != vpRobotSelfCalibration::PAPER && r.bundle.num_observations)
    md << "| scale | from " << vpKinematicBundleAdjustment::scaleSourceName(r.bundle.scale_source) << " |\n"
       << "| bundle adjustment | " << r.bundle.num_observations << " observations (" << r.bundle.num_outliers
       << " dropped as outliers), reprojection RMS " << std::setprecision(3) << r.bundle.rms << " px, sigma0 "
       << r.bundle.sigma0 << " |\n";
  if (r.method != vpRobotSelfCalibration::PAPER && r.fit_calibrated_rms > 0)
    md << "| image noise | " << std::setprecision(3) << r.noise.pixel_sd << " px used, " << r.measured.pixel_sd
       << " px measured by the residuals |\n"
       << "| calibration views explained | reprojection RMS " << r.fit_nominal_rms << " px (nominal model) -> "
       << r.fit_calibrated_rms << " px (calibrated) |\n";
  if (r.verified && r.after.num_observations)
    md << "| held-out views explained | reprojection RMS " << std::setprecision(3) << r.before.reprojection_rms
       << " px (nominal model) -> " << r.after.reprojection_rms << " px (calibrated) |\n";
  if (r.status == vpRobotSelfCalibration::DOUBTFUL)
    md << "\n**DOUBTFUL: the calibrated model was written, but it failed the checks marked `doubt` below; "
          "use it with care.**\n";
  md << "\nMessage: " << r.message << "\n";
  md << "\n## Data check\n\n";
  if (r.findings.empty())
    md << "Nothing to report: the poses move every joint, the camera rotates and translates, the scene has "
          "relief, the yardstick is seen.\n";
  for (const auto &f : r.findings)
    md << "- **" << vpSelfCalibDataCheck::severityName(f.severity) << "** (" << f.code
       << "): " << f.message << "\n";
  md << "\n## Stage times\n\n| stage | s |\n|---|---|\n";
  for (const auto &s : r.stage_seconds)
    md << "| " << s.first << " | " << std::setprecision(3) << s.second << " |\n";
}

//! The image front end: features per image, track lengths, the match matrix.
void frontEndSection(std::ostream &md, const vpFeatureFrontEnd::Result &fe, const FigureLink &figure)
{
  md << "\n## Image front end\n\n" << fe.num_tracks << " tracks (scene points seen in two or more images), "
     << std::setprecision(3) << fe.seconds << " s.\n\n| image | features | yardstick |\n|---|---|---|\n";
  for (size_t k = 0; k < fe.features.size(); ++k)
    md << "| " << k + 1 << " | " << fe.features[k] << " | " << (fe.yardstick_seen[k] ? "yes" : "no") << " |\n";
  md << "\nTrack lengths (images per track):\n\n| length | tracks |\n|---|---|\n";
  for (size_t n = 2; n < fe.track_lengths.size(); ++n)
    md << "| " << n << " | " << fe.track_lengths[n] << " |\n";
  md << "\n" << figure("track_lengths", "track lengths", "no track") << "\n\n"
     << "Which image pairs matched (images numbered from 1; a view that matches few others is weakly tied "
        "to the rest):\n\n"
     << figure("matches", "matches per image pair", "fewer than 2 images") << "\n";
}

//! Eye-to-hand: the camera in the base frame bMc and the target in the effector frame eMo, with their sd.
void eyeToHandSection(std::ostream &md, const vpRobotSelfCalibration::Result &r)
{
  md << "\n## Camera in the world, target on the tool\n\nThe camera is fixed in the robot's world (camera_mount: "
        "world): bMc is the camera in the robot's base frame, eMo the target in the end-effector frame (pose vectors "
        "tx ty tz in mm, theta-u in mrad; sd from the covariance with the controller poses' error modelled).\n\n"
        "| transform | tx | ty | tz | tux | tuy | tuz |\n|---|---|---|---|---|---|---|\n";
  const auto row = [&md](const std::string &name, const vpPoseVector &p, const vpColVector &sd) {
    md << "| " << name << " |";
    for (unsigned int k = 0; k < 6; ++k)
      md << " " << mm(p[k]) << " &plusmn; " << mm(sd.size() == 6 ? sd[k] : 0.0) << " |";
    md << "\n";
  };
  row("bMc", r.bMc, r.bMc_sd);
  if (r.has_eMo)
    row("eMo", r.eMo, r.eMo_sd);
  else
    md << "\neMo: no board, the target's points in the effector frame are the natural features' (no frame of their "
          "own).\n";
}

//! The estimated parameters, those not estimated, and the residuals on the calibration views.
void parametersSection(std::ostream &md, const vpSelfCalibReport::Record &run, const ReportData &data,
                       const FigureLink &figure)
{
  const vpRobotSelfCalibration::Result &r = run.result;
  const std::vector<std::string> names = run.nominal.getParameterNames();
  if (r.has_bMc)
    eyeToHandSection(md, r);
  md << "\n## Estimated parameters\n\n"
     << (r.has_bMc ? "Eye-to-hand: the eMc.* rows are the corrections of bMc from its closed-form start.\n\n" : "")
     << "| parameter | estimate (mm or mrad) | sd (mm or mrad) |\n|---|---|---|\n";
  for (unsigned int k : r.identifiability.identified)
    md << "| " << names[k] << " | " << mm(r.calibrated.getParameters()[k]) << " | "
       << mm(k < r.parameter_sd.size() ? r.parameter_sd[k] : 0.0) << " |\n";
  md << "\n## Not estimated (kept at nominal)\n\nThe estimated set follows a fixed preference order (eMc, base, "
        "then each joint as rz tz tx rx ry ty, base to tip) at the nominal model and the calibration joints only, so "
        "the same robot and poses give the same set whatever the noise (doc/concepts.md, \"The estimated set\"); the bundle "
        "adjustment estimates those its own information at the start values (the stated noise) determines within "
        "the nominal model's tolerance, and, with the kinematic prior (the default), the others too, held near "
        "nominal by the prior.\n\n";
  using Ident = vpKinematicIdentification;
  std::string fixed, by_data;
  for (const auto &u : r.identifiability.unidentifiable)
    if (u.cause == Ident::CAUSE_FIXED)
      fixed += (fixed.empty() ? "" : ", ") + u.name;
    else if (u.cause == Ident::CAUSE_DATA)
      by_data += "| " + u.name + " | " + u.reason + " | " + u.needs + " |\n";
  md << "Fixed by the user (--fix, the dataset's fix:): " << (fixed.empty() ? "none" : fixed) << ".\n\n";
  if (r.bundle.kinematic_prior > 0) {
    md << "Estimated with a prior on every kinematic correction (--kinematic-prior; off: without): its sd the "
          "tolerance / "
       << r.bundle.kinematic_prior << "; the sd above include it.";
    std::string held;
    for (const auto &u : r.identifiability.held_by_prior)
      held += "| " + u.name + " | " + u.reason + " | " + u.needs + " |\n";
    if (held.empty())
      md << "\n\n";
    else
      md << " Held by the prior (estimated, but the data alone do not determine them: they stay near nominal):\n\n"
            "| parameter | why | what would determine it |\n|---|---|---|\n"
         << held << "\n";
  }
  if (!by_data.empty())
    md << "Left at nominal by the data (they do not determine them):\n\n| parameter | why | what would determine it "
          "|\n|---|---|---|\n"
       << by_data << "\n";
  md << "Left out by the model's structure (redundant for these joint configurations):\n\n| parameter | why |\n|---|---|\n";
  for (const auto &u : r.identifiability.unidentifiable)
    if (u.cause == Ident::CAUSE_MODEL)
      md << "| " << u.name << " | " << u.reason << " |\n";
  md << "\n## Residuals\n\nReprojection RMS on the calibration views (points triangulated with the calibrated model): "
     << std::setprecision(3) << (data.count ? std::sqrt(data.sum2 / data.count) : 0.0) << " px over " << data.count
     << " observations.\n\n" << figure("residuals", "residuals", "no residual") << "\n\n"
     << "Each calibration view, calibrated against nominal model (a view far above the others is the first "
        "suspect: a wrong joint reading, a moved scene, a blurred image):\n\n"
     << figure("view_residuals", "residuals per view", "no residual") << "\n";
}

//! The verification on the held-out views (or why there is none).
void verificationSection(std::ostream &md, const vpSelfCalibReport::Record &run, const Views &views,
                         const ReportData &data, const FigureLink &figure)
{
  const vpRobotSelfCalibration::Result &r = run.result;
  md << "\n## Verification on the held-out views\n\n";
  if (views.ver.empty())
    md << "No view was held out: all " << views.N << " views calibrate, so there is no 3-D yardstick error on "
       << "held-out views and neither the per-view figure nor the figure of that error against the number of "
       << "calibration poses is drawn (they would be empty)."
       << (run.cross_validation ? " The cross-validation below measures the model on views it was not calibrated on."
                                : "")
       << "\n";
  else {
    if (r.verified)
      md << "3-D yardstick error (the paper's): nominal " << mm(r.before.yardstick_error) << " mm, calibrated "
         << mm(r.after.yardstick_error) << " mm.\n\n";
    md << "| held-out view | reprojection RMS (px) |\n|---|---|\n";
    for (size_t k = 0; k < data.ver_rms.size(); ++k)
      md << "| " << k + 1 << " | " << std::setprecision(3) << data.ver_rms[k] << " |\n";
    md << "\n" << figure("verification", "verification", "fewer than 2 held-out views") << "\n\n"
       << figure("errors_vs_poses", "errors against poses",
                 run.errors_vs_poses ? run.errors_vs_poses->message
                                     : std::string("no study of the errors against the number of poses was run"))
       << "\n";
  }
}
} // namespace

vpSelfCalibReport::Record::Record(const vpKinematicChain &nominal_model, const vpSelfCalibDataset &run_dataset,
                                  const vpRobotSelfCalibration::Options &run_options,
                                  const vpRobotSelfCalibration::Result &run_result)
  : nominal(nominal_model), dataset(run_dataset), options(run_options), result(run_result)
{
}

vpSelfCalibReport::Record::Record(const vpKinematicChain &nominal_model, const vpSelfCalibDataset &run_dataset,
                                  const vpSelfCalibProtocol::Result &protocol)
  : nominal(nominal_model), dataset(run_dataset), options(protocol.options), result(protocol.calibration),
    cross_validation(protocol.cv ? &*protocol.cv : nullptr), held_out(protocol.verified ? &*protocol.verified : nullptr)
{
}

vpSelfCalibReport::Result vpSelfCalibReport::write(const std::string &dir, const Record &run, const Options &ro)
{
  std::error_code ec;
  std::filesystem::create_directory(dir, ec);
  if (ec || !std::filesystem::is_directory(dir, ec))
    throw vpSelfCalibException(vpSelfCalibException::ioError,
                               "vpSelfCalibReport: cannot create the directory '" + dir + "'");
  Result res;
  const vpSelfCalibDataset &ds = run.dataset;
  const vpRobotSelfCalibration::Result &r = run.result;
  Views views;
  views.N = std::min<unsigned int>(run.options.num_calibration_poses, static_cast<unsigned int>(ds.views.size()));
  views.cal.assign(ds.views.begin(), ds.views.begin() + views.N);
  views.ver.assign(ds.views.begin() + views.N, ds.views.end());
  const bool ok = r.status == vpRobotSelfCalibration::OK || r.status == vpRobotSelfCalibration::DOUBTFUL;
  const vpKinematicChain &model = ok ? r.calibrated : run.nominal;

  const ReportData data = reportData(run, views, model);
  std::vector<std::string> empty;
  writeFigures(dir, data, run.front_end != nullptr, ro, res, empty);
  const FigureLink figure{dir, res, empty};

  const std::string unexplained = unexplainedViews(data.view_rms);
  if (!unexplained.empty())
    res.warnings.push_back(unexplained);

  std::ostringstream md;
  runSection(md, run, views);
  if (!unexplained.empty())
    md << "\n**Warning:** " << unexplained << ".\n";
  if (run.front_end)
    frontEndSection(md, *run.front_end, figure);
  parametersSection(md, run, data, figure);
  verificationSection(md, run, views, data, figure);
  if (run.cross_validation)
    crossValidationSection(md, *run.cross_validation);
  if (run.held_out)
    heldOutSection(md, *run.held_out);
  md << "\n## Trajectory\n\n" << figure("trajectory", "trajectory", "no view") << "\n\n"
     << figure("position_norms", "position norms", "one calibration view") << "\n\n"
     << "Figures: " << res.message << ". Data files beside them; `gnuplot plots.gp` redraws them.\n";
  writeText(dir + "/report.md", md.str(), res.files);
  return res;
}
