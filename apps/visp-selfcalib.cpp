/*
 * visp-selfcalib: command-line tool of ViSP SelfCalib.
 *
 *   visp-selfcalib info      MODEL                 robot model summary and error-model parameters
 *   visp-selfcalib predict   MODEL [JOINTS_FILE]   fMc for each joint vector (one per line, rad;
 *                                                  from the file or standard input), printed as
 *                                                  one pose vector per line: tx ty tz tux tuy tuz
 *   visp-selfcalib plan      OUT.txt [options]     planned calibration poses of the reference scenario
 *   visp-selfcalib simulate  OUT.yaml [options]    a dataset of the reference scenario (observations)
 *   visp-selfcalib calibrate DATASET --out DIR [options]
 *                                                  calibrated model, camera and results in DIR
 *   visp-selfcalib verify    MODEL DATASET         the paper's 3-D yardstick error of a model
 *   visp-selfcalib export    MODEL (--urdf OUT | --dh OUT | --mdh OUT)
 *                                                  URDF joint origins, or a corrected (modified) DH table
 * MODEL is a preset name (puma560, viper850) or a robot-model YAML file.
 * Exit codes: 0 success, 1 bad input (message on stderr), 2 bad usage, 3 the calibration failed
 * (its status and message on stderr). Outputs are written atomically and never over an input.
 */
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <thread>

#include <cstdlib>
#include <opencv2/core.hpp>
#include <limits.h>
#include <sys/stat.h>
#include <vector>

#include <visp3/core/vpPoseVector.h>
#include <visp3/core/vpXmlParserCamera.h>
#include <visp3/selfcalib/vpCalibrationVerifier.h>
#include <visp3/io/vpImageIo.h>
#include <visp3/selfcalib/vpFeatureFrontEnd.h>
#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpMeasurementPlanner.h>
#include <visp3/selfcalib/vpSelfCalibRenderer.h>
#include <visp3/selfcalib/vpSelfCalibReport.h>
#include <visp3/selfcalib/vpModelExport.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

namespace
{
struct Command {
  const char *name;
  const char *synopsis; //!< after "visp-selfcalib NAME "
  const char *help;     //!< what it does, its options
};

const Command kCommands[] = {
    {"info", "MODEL", "Prints the robot model: convention, joints, number of error-model parameters, the corrections\n"
                      "that are not zero.\n"},
    {"predict", "MODEL [JOINTS_FILE]",
     "Reads one joint vector per line (rad, separated by spaces or commas; '#' starts a comment) from\n"
     "JOINTS_FILE or standard input and prints the camera pose fMc as 'tx ty tz tux tuy tuz' (m, rad) per line.\n"},
    {"plan", "OUT.txt [--robot NAME] [--seed N] [--poses N] [--held-out N] [--method observability|paper] [--force]",
     "Writes calibration poses planned on the reference scenario's nominal model, then random held-out\n"
     "poses, one joint vector per line.\n"
     "  --robot NAME      viper850 (default) or puma560\n"
     "  --seed N          scenario seed (default 1)\n"
     "  --poses N         calibration poses (default 15)\n"
     "  --held-out N      held-out poses after them (default 10)\n"
     "  --method M        observability (default): O1-optimal choice from a pool; paper: the paper's\n"
     "                    optimal trajectory (eqs. 22-39)\n"
     "  --force           replace an existing OUT.txt\n"},
    {"simulate",
     "OUT.yaml [--robot NAME] [--seed N] [--poses N | --joints FILE] [--noise PX] [--focal known|shared]\n"
     "                           [--controller-poses] [--images [--target textured|dots]] [--force]",
     "Writes a dataset of the reference scenario (simulated robot with seeded errors, scene, yardstick).\n"
     "  --poses N         random feasible poses (default 25); --joints FILE: the poses of a plan\n"
     "  --noise PX        image noise sd (default 0.2)\n"
     "  --focal M         known (default: px, py in the file) or shared (f to be self-calibrated)\n"
     "  --controller-poses  the true end-effector poses fMe instead of joints (hand-eye datasets)\n"
     "  --images          render the images (OUT's directory/images/) and write no points: calibrate\n"
     "                    then runs the image front end\n"
     "  --target T        textured (default: photographs on two planes, natural features) or dots (the\n"
     "                    paper's experiment: dot grids 4x5 and 4x9 on the two planes; calibrate with\n"
     "                    --dot-grids 4x5,4x9 --no-features)\n"
     "  --force           replace an existing OUT.yaml\n"},
    {"calibrate",
     "DATASET --out DIR [--method bundle|paper|hand-eye] [--calibration N] [--focal auto|known|shared|per-pair]\n"
     "                           [--pixel-sd PX] [--threads N] [--dot-grids CxR[,CxR...]] [--no-features]",
     "Self-calibrates on the first N views and verifies on the others. Writes DIR/model.yaml,\n"
     "DIR/model.urdf, DIR/camera.xml, DIR/results.yaml and DIR/report/ (report.md, gnuplot figures),\n"
     "each atomically, never over an input. The data check's findings are printed as warnings.\n"
     "  --method M        bundle (default; hand-eye when the poses have fMe and no joints): multi-view\n"
     "                    reconstruction + kinematic bundle adjustment; paper: the paper's procedure;\n"
     "                    hand-eye: kinematics trusted, eMc, f and points estimated\n"
     "  --calibration N   calibration views (default 15, or all but 2 when fewer)\n"
     "  --focal M         auto (default: known when the dataset gives px, py), known, shared, per-pair\n"
     "  --pixel-sd PX     image noise sd used as weight (default 0.2)\n"
     "  --threads N       threads of the image front end (default: all cores); the results do not depend on it\n"
     "  --dot-grids LIST  dot targets for the front end: asymmetric circle grids, C columns x R rows (R odd),\n"
     "                    grid g numbered from 1000000 + 1000 g; their dots must differ in size\n"
     "  --no-features     no natural features (dot targets only)\n"
     "Exit codes: 0 calibrated, 1 bad input, 2 bad usage, 3 failed or degenerate data (message on stderr).\n"},
    {"verify", "MODEL DATASET", "Prints the paper's 3-D yardstick error of MODEL on the dataset's views.\n"},
    {"export", "MODEL (--urdf OUT.urdf | --dh OUT.yaml | --mdh OUT.yaml)",
     "Writes the model as URDF joint origins (exact), or as a DH / modified-DH robot-model file without\n"
     "corrections when one reproduces it (exit 3 when none does; a warning when it is ill-conditioned).\n"},
};

int usage(std::ostream &os, int code)
{
  os << "Usage:\n";
  for (const Command &c : kCommands)
    os << "  visp-selfcalib " << c.name << std::string(10 - std::string(c.name).size(), ' ') << c.synopsis << "\n";
  os << "MODEL: a preset (puma560, viper850) or a robot-model YAML file. DATASET: a dataset YAML file (README).\n"
     << "'visp-selfcalib COMMAND --help' describes a command and its options.\n";
  return code;
}

//! The help of one command; the global usage for an unknown one.
int commandHelp(const std::string &name)
{
  for (const Command &c : kCommands)
    if (name == c.name) {
      std::cout << "Usage: visp-selfcalib " << c.name << " " << c.synopsis << "\n\n" << c.help;
      return 0;
    }
  return usage(std::cout, 0);
}

int info(const vpKinematicChain &c)
{
  std::cout << "name: " << c.getName() << "\nconvention: " << (c.getConvention() == vpKinematicChain::DH ? "dh" : "mdh")
            << "\njoints: " << c.getNumJoints() << "\nerror-model parameters: " << c.getNumParameters() << "\n";
  const std::vector<std::string> names = c.getParameterNames();
  for (unsigned int i = 0; i < names.size(); ++i)
    if (c.getParameters()[i] != 0)
      std::cout << "  " << names[i] << " = " << std::setprecision(17) << c.getParameters()[i] << "\n";
  return 0;
}

//! Joint vectors, one per line (rad, spaces or commas, '#' comments); false with a message on error.
bool readJoints(std::istream &in, const std::string &source, unsigned int n, std::vector<vpColVector> &out)
{
  std::string line;
  unsigned int lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    const size_t hash = line.find('#');
    if (hash != std::string::npos)
      line.resize(hash);
    for (char &ch : line)
      if (ch == ',')
        ch = ' ';
    std::istringstream ls(line);
    std::vector<double> v;
    std::string tok;
    while (ls >> tok) {
      try {
        size_t used = 0;
        v.push_back(std::stod(tok, &used));
        if (used != tok.size() || !std::isfinite(v.back()))
          throw std::invalid_argument(tok);
      } catch (const std::exception &) {
        std::cerr << source << ":" << lineno << ": '" << tok << "' is not a number\n";
        return false;
      }
    }
    if (v.empty())
      continue;
    if (v.size() != n) {
      std::cerr << source << ":" << lineno << ": expected " << n << " joint values, got " << v.size() << "\n";
      return false;
    }
    out.push_back(vpColVector(v));
  }
  return true;
}

int predict(const vpKinematicChain &c, std::istream &in, const std::string &source)
{
  std::vector<vpColVector> qs;
  if (!readJoints(in, source, c.getNumJoints(), qs))
    return 1;
  std::cout << std::setprecision(17);
  for (const vpColVector &q : qs) {
    if (!c.isInJointLimits(q))
      std::cerr << source << ": warning: joints outside the model's limits\n";
    const vpPoseVector p(c.get_fMc(q));
    for (unsigned int k = 0; k < 6; ++k)
      std::cout << p[k] << (k < 5 ? " " : "\n");
  }
  return 0;
}

//! Canonical path of an existing file or directory, or "" when it does not exist.
std::string canonical(const std::string &p)
{
  char buf[PATH_MAX];
  return realpath(p.c_str(), buf) ? std::string(buf) : std::string();
}

//! Text to a temporary file, then renamed into place; false (with a message) when that fails.
bool writeAtomically(const std::string &file, const std::string &text)
{
  const std::string tmp = file + ".tmp";
  std::ofstream os(tmp);
  os << text;
  os.close();
  if (!os || std::rename(tmp.c_str(), file.c_str()) != 0) {
    std::remove(tmp.c_str());
    std::cerr << "error: cannot write '" << file << "'\n";
    return false;
  }
  return true;
}

struct BadUsage : std::runtime_error {
  using std::runtime_error::runtime_error;
};

double numberArg(const std::vector<std::string> &a, size_t &i)
{
  if (i + 1 >= a.size())
    throw BadUsage(a[i] + " needs a value");
  const std::string &v = a[++i];
  size_t used = 0;
  double x = 0;
  try {
    x = std::stod(v, &used);
  } catch (const std::exception &) {
    used = 0;
  }
  if (used == 0 || used != v.size() || !std::isfinite(x))
    throw BadUsage(a[i - 1] + ": '" + v + "' is not a number");
  return x;
}

std::string textArg(const std::vector<std::string> &a, size_t &i)
{
  if (i + 1 >= a.size())
    throw BadUsage(a[i] + " needs a value");
  return a[++i];
}

int simulate(const std::vector<std::string> &a)
{
  std::string out, robot = "viper850", focal = "known";
  vpSelfCalibSimulator::Options so;
  unsigned int poses = 25;
  bool force = false, controller = false, images = false;
  std::string target = "textured";
  std::string joints_file;
  for (size_t i = 0; i < a.size(); ++i) {
    if (a[i] == "--joints")
      joints_file = textArg(a, i);
    else if (a[i] == "--controller-poses")
      controller = true;
    else if (a[i] == "--images")
      images = true;
    else if (a[i] == "--target")
      target = textArg(a, i);
    else if (a[i] == "--robot")
      robot = textArg(a, i);
    else if (a[i] == "--seed")
      so.seed = static_cast<uint64_t>(numberArg(a, i));
    else if (a[i] == "--poses")
      poses = static_cast<unsigned int>(numberArg(a, i));
    else if (a[i] == "--noise")
      so.pixel_noise_sd = numberArg(a, i);
    else if (a[i] == "--focal")
      focal = textArg(a, i);
    else if (a[i] == "--force")
      force = true;
    else if (!a[i].empty() && a[i][0] == '-')
      throw BadUsage("simulate: unknown option '" + a[i] + "'");
    else if (out.empty())
      out = a[i];
    else
      throw BadUsage("simulate: one output file");
  }
  if (out.empty())
    throw BadUsage("simulate: the output file is missing");
  if (target != "textured" && target != "dots")
    throw BadUsage("simulate: --target is textured or dots");
  if (target == "dots" && !images)
    throw BadUsage("simulate: --target dots renders images: add --images");
  if (focal != "known" && focal != "shared")
    throw BadUsage("simulate: --focal is known or shared");
  if (poses < 3)
    throw BadUsage("simulate: --poses must be at least 3");
  if (!force && !canonical(out).empty()) {
    std::cerr << "error: '" << out << "' exists; use --force to replace it\n";
    return 1;
  }
  const vpSelfCalibSimulator sim(vpKinematicChain::preset(robot), so);
  std::vector<vpColVector> configurations;
  if (!joints_file.empty()) {
    // The given configurations (a plan), each checked for joint limits and visibility.
    std::ifstream in(joints_file);
    if (!in) {
      std::cerr << "error: cannot open joints file '" << joints_file << "'\n";
      return 1;
    }
    if (!readJoints(in, joints_file, sim.getNominalChain().getNumJoints(), configurations))
      return 1;
    for (size_t k = 0; k < configurations.size(); ++k)
      if (!sim.getNominalChain().isInJointLimits(configurations[k]) || !sim.isVisible(configurations[k])) {
        std::cerr << "error: " << joints_file << ": configuration " << k + 1
                  << " is outside the joint limits or does not see the whole scene\n";
        return 1;
      }
    if (configurations.size() < 3) {
      std::cerr << "error: " << joints_file << ": at least 3 configurations are needed\n";
      return 1;
    }
    poses = static_cast<unsigned int>(configurations.size());
  } else {
    configurations = sim.generateConfigurations(poses, [](unsigned int d, unsigned int n) {
      std::cerr << "configurations " << d << "/" << n << "\r" << std::flush;
    });
    std::cerr << "\n";
  }
  vpSelfCalibDataset ds = sim.makeDataset(configurations);
  ds.robot = robot;
  std::vector<vpColVector> qs;
  for (const auto &v : ds.views)
    qs.push_back(v.q);
  if (controller)
    // What a controller reports: the (true) end-effector pose, no joints.
    for (auto &v : ds.views) {
      v.has_fMe = true;
      v.fMe = sim.getTrueChain().get_fMe(v.q);
      v.q = vpColVector();
    }
  if (focal == "shared") {
    ds.focal_known = false;
    ds.cam.initPersProjWithoutDistortion(0.93 * so.px, 0.93 * so.py, so.u0, so.v0);
  }
  if (images) {
    // Rendered acquisition: images beside the dataset, no points (the front end finds them), the
    // yardstick's length only (its dots are found in the images).
    const size_t slash = out.find_last_of('/');
    const std::string dir = slash == std::string::npos ? "." : out.substr(0, slash);
    const std::string img_dir = dir + "/images";
    if (canonical(img_dir).empty() && mkdir(img_dir.c_str(), 0777) != 0) {
      std::cerr << "error: cannot create '" << img_dir << "'\n";
      return 1;
    }
    vpSelfCalibRenderer::Options ro;
    ro.seed = so.seed;
    ro.scene = target == "dots" ? vpSelfCalibRenderer::DOTS : vpSelfCalibRenderer::TEXTURED;
    const vpSelfCalibRenderer renderer(sim, ro);
    for (size_t k = 0; k < ds.views.size(); ++k) {
      std::ostringstream name;
      name << img_dir << "/" << std::setw(4) << std::setfill('0') << k + 1 << ".png";
      vpImageIo::write(renderer.render(qs[k], static_cast<unsigned int>(k)), name.str());
      ds.views[k].image = name.str();
      ds.views[k].points.clear();
      std::cerr << "rendered " << k + 1 << "/" << ds.views.size() << "\r" << std::flush;
    }
    std::cerr << "\n";
    ds.yardstick.length = renderer.getYardstickLength();
    ds.yardstick.id_a = ds.yardstick.id_b = -1;
  }
  ds.saveYaml(out);
  if (images)
    std::cout << "wrote " << out << ": " << poses << " poses of " << robot << ", rendered images in the images/ "
              << "directory beside it\n";
  else
    std::cout << "wrote " << out << ": " << poses << " poses of " << robot << ", " << sim.getScenePoints().size()
              << " scene points, noise " << so.pixel_noise_sd << " px\n";
  return 0;
}

//! A YAML double-quoted scalar.
std::string quoted(const std::string &text)
{
  std::string q = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\')
      q += '\\';
    q += c;
  }
  return q + "\"";
}

std::string resultsYaml(const vpRobotSelfCalibration::Result &r, const vpKinematicChain &nominal,
                        const std::string &dataset)
{
  std::ostringstream os;
  os << std::setprecision(17);
  os << "dataset: " << dataset << "\nmethod: " << vpRobotSelfCalibration::methodName(r.method) << "\nstatus: "
     << vpRobotSelfCalibration::statusName(r.status) << "\nmessage: " << quoted(r.message) << "\n";
  os << "findings:" << (r.findings.empty() ? " []" : "") << "  # what the data check found, and what to do\n";
  for (const auto &f : r.findings)
    os << "  - {code: " << f.code << ", severity: " << (f.severity == vpSelfCalibDataCheck::DEGENERATE ? "degenerate" : "warning")
       << ", message: " << quoted(f.message) << "}\n";
  os << "camera: {px: " << r.camera.get_px() << ", py: " << r.camera.get_py() << ", u0: " << r.camera.get_u0()
     << ", v0: " << r.camera.get_v0() << ", px_sd: " << r.fx_sd << "}\n";
  if (r.method == vpRobotSelfCalibration::BUNDLE_ADJUSTMENT)
    os << "bundle_adjustment: {observations: " << r.bundle.num_observations << ", dropped: " << r.bundle.num_outliers
       << ", rms_px: " << r.bundle.rms << ", sigma0: " << r.bundle.sigma0 << ", scale_from: \""
       << vpKinematicBundleAdjustment::scaleSourceName(r.bundle.scale_source) << "\"}\n";
  const std::vector<std::string> names = nominal.getParameterNames();
  os << "estimated:  # per parameter: value and sd (m or rad)\n";
  for (unsigned int k : r.identifiability.identified)
    os << "  " << names[k] << ": [" << r.calibrated.getParameters()[k] << ", "
       << (k < r.parameter_sd.size() ? r.parameter_sd[k] : 0.0) << "]\n";
  os << "not_estimated:\n";
  for (const auto &u : r.identifiability.unidentifiable)
    os << "  " << u.name << ": " << quoted(u.reason) << "\n";
  if (r.verified)
    os << "verification:  # the paper's 3-D yardstick error on the held-out views (m)\n"
       << "  yardstick_error_nominal: " << r.before.yardstick_error << "\n  yardstick_error_calibrated: "
       << r.after.yardstick_error << "\n";
  // No wall times here: the same dataset gives the same file, bit for bit (they are in the report).
  return os.str();
}

int calibrate(const std::vector<std::string> &a)
{
  std::string dataset, out, method, focal = "auto";
  unsigned int calibration = 0;
  double pixel_sd = 0.2;
  int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  vpFeatureFrontEnd::Options fo;
  for (size_t i = 0; i < a.size(); ++i) {
    if (a[i] == "--threads")
      threads = static_cast<int>(numberArg(a, i));
    else if (a[i] == "--no-features")
      fo.features = false;
    else if (a[i] == "--dot-grids") {
      // C x R, comma-separated; grid g numbered from 1000000 + 1000 g (as simulate --target dots).
      std::istringstream list(textArg(a, i));
      std::string item;
      while (std::getline(list, item, ',')) {
        vpFeatureFrontEnd::DotGrid g;
        char x = 0;
        std::istringstream is(item);
        if (!(is >> g.cols >> x >> g.rows) || x != 'x' || !is.eof())
          throw BadUsage("calibrate: --dot-grids takes COLSxROWS[,COLSxROWS...], got '" + item + "'");
        g.first_id = vpSelfCalibRenderer::kFirstDotId + 1000 * static_cast<int>(fo.dot_grids.size());
        fo.dot_grids.push_back(g);
      }
    } else if (a[i] == "--out")
      out = textArg(a, i);
    else if (a[i] == "--method")
      method = textArg(a, i);
    else if (a[i] == "--focal")
      focal = textArg(a, i);
    else if (a[i] == "--calibration")
      calibration = static_cast<unsigned int>(numberArg(a, i));
    else if (a[i] == "--pixel-sd")
      pixel_sd = numberArg(a, i);
    else if (!a[i].empty() && a[i][0] == '-')
      throw BadUsage("calibrate: unknown option '" + a[i] + "'");
    else if (dataset.empty())
      dataset = a[i];
    else
      throw BadUsage("calibrate: one dataset file");
  }
  if (dataset.empty() || out.empty())
    throw BadUsage("calibrate: a dataset and --out DIR are needed");
  vpRobotSelfCalibration::Options po;
  if (!method.empty())
    po.method = vpRobotSelfCalibration::methodFromName(method);
  if (focal == "auto")
    po.focal_mode = vpRobotSelfCalibration::FOCAL_AUTO;
  else if (focal == "known")
    po.focal_mode = vpRobotSelfCalibration::FOCAL_KNOWN;
  else if (focal == "shared")
    po.focal_mode = vpRobotSelfCalibration::FOCAL_SHARED;
  else if (focal == "per-pair")
    po.focal_mode = vpRobotSelfCalibration::FOCAL_PER_PAIR;
  else
    throw BadUsage("calibrate: --focal is auto, known, shared or per-pair");
  po.pixel_sd = pixel_sd;

  if (threads < 1)
    throw BadUsage("calibrate: --threads must be at least 1");
  // The image front end runs on `threads` OpenCV threads: its results do not depend on them (test
  // app-deterministic). Everything after it runs on one thread, OpenMP included (OpenCV's
  // setNumThreads sets OpenMP's count, which CHOLMOD/SPQR in the covariance use, and their sums
  // change with it); Ceres's multi-threaded Schur elimination also sums in a scheduling-dependent
  // order. The result files must be bit-reproducible.
  cv::setNumThreads(threads);
  vpSelfCalibDataset ds = vpSelfCalibDataset::loadYaml(dataset);
  const vpKinematicChain nominal = vpKinematicChain::fromPresetOrFile(ds.robot);
  bool need_front_end = false;
  for (const auto &v : ds.views)
    need_front_end = need_front_end || (v.points.empty() && !v.image.empty());
  vpFeatureFrontEnd::Result fe;
  if (need_front_end) {
    std::cerr << "... image front end (" << ds.views.size() << " images)\n";
    fe = vpFeatureFrontEnd::fillDataset(ds, fo);
    unsigned int seen = 0;
    for (bool b : fe.yardstick_seen)
      seen += b;
    unsigned int grids = 0;
    for (const auto &g : fe.grid_seen)
      for (bool b : g)
        grids += b;
    if (!fo.dot_grids.empty())
      std::cerr << "... dot grids found " << grids << " times in " << ds.views.size() << " images\n";
    std::cerr << "... " << fe.num_tracks << " tracks, yardstick in " << seen << " images, " << std::setprecision(2)
              << fe.seconds << " s\n";
    // A view where the front end found nothing cannot be used: left out, said.
    for (size_t k = ds.views.size(); k-- > 0;)
      if (ds.views[k].points.empty()) {
        std::cerr << "warning: view " << k << " (" << ds.views[k].image << "): no correspondence found; left out\n";
        ds.views.erase(ds.views.begin() + static_cast<long>(k));
      }
  }
  cv::setNumThreads(1);
  if (method.empty())
    for (const auto &v : ds.views)
      if (v.q.size() == 0 && v.has_fMe)
        po.method = vpRobotSelfCalibration::HAND_EYE;
  const unsigned int m = static_cast<unsigned int>(ds.views.size());
  po.num_calibration_poses = calibration ? calibration : (m >= 17 ? 15 : std::max(3u, m > 2 ? m - 2 : m));

  // Outputs: never over an input (the dataset or the robot model file).
  if (canonical(out).empty() && mkdir(out.c_str(), 0777) != 0) {
    std::cerr << "error: cannot create the output directory '" << out << "'\n";
    return 1;
  }
  const std::string files[4] = {out + "/model.yaml", out + "/camera.xml", out + "/results.yaml", out + "/model.urdf"};
  for (const std::string &f : files) {
    const std::string c = canonical(f);
    if (!c.empty() && (c == canonical(dataset) || c == canonical(ds.robot))) {
      std::cerr << "error: '" << f << "' is an input of this run; choose another --out\n";
      return 1;
    }
  }
  const vpRobotSelfCalibration::Result r =
      vpRobotSelfCalibration::run(nominal, ds, po, [](const std::string &stage, unsigned int, unsigned int) {
        std::cerr << "... " << stage << "\n";
      });
  if (r.status != vpRobotSelfCalibration::OK) {
    std::cerr << "calibration failed: " << vpRobotSelfCalibration::statusName(r.status) << ": " << r.message << "\n";
    return 3;
  }
  for (const auto &f : r.findings)
    std::cerr << "warning: " << f.message << "\n";
  vpKinematicChain model = r.calibrated;
  model.setName(nominal.getName() + "-calibrated");
  model.saveYaml(files[0]);
  vpModelExport::saveURDF(model, files[3]);
  {
    // vpXmlParserCamera has no atomic write: it writes a temporary file that is renamed here.
    const std::string tmp = files[1] + ".tmp";
    std::remove(tmp.c_str());
    vpXmlParserCamera xml;
    if (xml.save(r.camera, tmp, "Camera", ds.width, ds.height, "self-calibrated by visp-selfcalib") !=
            vpXmlParserCamera::SEQUENCE_OK ||
        std::rename(tmp.c_str(), files[1].c_str()) != 0) {
      std::cerr << "error: cannot write '" << files[1] << "'\n";
      return 1;
    }
  }
  if (!writeAtomically(files[2], resultsYaml(r, nominal, dataset)))
    return 1;
  std::cout << "calibrated " << r.identifiability.identified.size() << " parameters on " << po.num_calibration_poses
            << " views (" << vpRobotSelfCalibration::methodName(r.method) << "), f_x " << std::setprecision(6)
            << r.camera.get_px() << " px";
  if (r.verified)
    std::cout << "; yardstick 3-D error on the held-out views " << std::setprecision(3)
              << 1e3 * r.before.yardstick_error << " mm (nominal) -> " << 1e3 * r.after.yardstick_error << " mm";
  std::cout << "\nwrote " << files[0] << ", " << files[1] << ", " << files[2] << ", " << files[3] << "\n";
  std::cerr << "... report\n";
  const vpSelfCalibPoseStudy::Result study = vpSelfCalibPoseStudy::run(nominal, ds, po); // Figure 6
  const vpSelfCalibReport::Result rep = vpSelfCalibReport::write(out + "/report", nominal, ds, po, r,
                                                                 need_front_end ? &fe : nullptr, &study,
                                                                 vpSelfCalibReport::Options());
  std::cout << "report: " << out << "/report/report.md (" << rep.message << ")\n";
  return 0;
}

int verify(const std::string &model_name, const std::string &dataset)
{
  const vpKinematicChain model = vpKinematicChain::fromPresetOrFile(model_name);
  const vpSelfCalibDataset ds = vpSelfCalibDataset::loadYaml(dataset);
  if (!ds.yardstick.isSet()) {
    std::cerr << "error: dataset '" << dataset << "' has no yardstick to verify against\n";
    return 1;
  }
  const vpCalibrationVerifier::Result v = vpCalibrationVerifier::verify(model, ds.cam, ds.views, ds.yardstick);
  if (!v.has_yardstick) {
    std::cerr << "error: the yardstick's ends are not seen in two views of '" << dataset << "'\n";
    return 1;
  }
  std::cout << std::setprecision(6) << "yardstick length " << v.yardstick_length << " m (true " << ds.yardstick.length
            << "), 3-D error " << 1e3 * v.yardstick_error << " mm, " << v.points.size() << " points triangulated\n";
  return 0;
}
int plan(const std::vector<std::string> &a)
{
  std::string out, robot = "viper850", method = "observability";
  vpSelfCalibSimulator::Options so;
  unsigned int poses = 15, held_out = 10;
  bool force = false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (a[i] == "--robot")
      robot = textArg(a, i);
    else if (a[i] == "--seed")
      so.seed = static_cast<uint64_t>(numberArg(a, i));
    else if (a[i] == "--poses")
      poses = static_cast<unsigned int>(numberArg(a, i));
    else if (a[i] == "--held-out")
      held_out = static_cast<unsigned int>(numberArg(a, i));
    else if (a[i] == "--method")
      method = textArg(a, i);
    else if (a[i] == "--force")
      force = true;
    else if (!a[i].empty() && a[i][0] == '-')
      throw BadUsage("plan: unknown option '" + a[i] + "'");
    else if (out.empty())
      out = a[i];
    else
      throw BadUsage("plan: one output file");
  }
  if (out.empty())
    throw BadUsage("plan: the output file is missing");
  if (method != "paper" && method != "observability")
    throw BadUsage("plan: --method is paper or observability");
  if (poses < 6)
    throw BadUsage("plan: --poses must be at least 6");
  if (!force && !canonical(out).empty()) {
    std::cerr << "error: '" << out << "' exists; use --force to replace it\n";
    return 1;
  }
  const vpSelfCalibSimulator sim(vpKinematicChain::preset(robot), so);
  const unsigned int pool = method == "observability" ? 60 : 0;
  std::cerr << "... random feasible configurations\n";
  const std::vector<vpColVector> q = sim.generateConfigurations(poses + held_out + pool);
  const std::vector<vpColVector> initial(q.begin(), q.begin() + poses);
  const vpMeasurementPlanner planner(sim.getNominalChain(), sim.getPlannerScene());
  vpMeasurementPlanner::Result pr;
  if (method == "paper") {
    vpMeasurementPlanner::TrajectoryOptions to;
    to.seed = so.seed;
    pr = planner.planTrajectory(initial, to, [](const std::string &stage, unsigned int d, unsigned int n) {
      std::cerr << "... " << stage << " " << d + 1 << "/" << n << "\n";
    });
  } else {
    std::vector<vpColVector> candidates = initial;
    candidates.insert(candidates.end(), q.begin() + poses + held_out, q.end());
    pr = planner.selectObservable(candidates, poses);
  }
  if (pr.status != vpMeasurementPlanner::OK) {
    std::cerr << "planning failed: " << vpMeasurementPlanner::statusName(pr.status) << ": " << pr.message << "\n";
    return 3;
  }
  std::ostringstream os;
  os << std::setprecision(17) << "# " << robot << ", seed " << so.seed << ": " << poses << " planned (" << method
     << ") calibration poses, then " << held_out << " random held-out poses; rad\n";
  std::vector<vpColVector> all = pr.configurations;
  all.insert(all.end(), q.begin() + poses, q.begin() + poses + held_out);
  for (const vpColVector &c : all) {
    for (unsigned int i = 0; i < c.size(); ++i)
      os << c[i] << (i + 1 < c.size() ? " " : "\n");
  }
  if (!writeAtomically(out, os.str()))
    return 1;
  std::cout << "wrote " << out << ": " << poses << " planned + " << held_out << " held-out configurations; "
            << std::setprecision(3) << "cond(J) " << pr.before.condition << " -> " << pr.after.condition << ", O1 "
            << pr.observability_before.O1 << " -> " << pr.observability_after.O1 << ", " << std::setprecision(2)
            << pr.seconds << " s\n";
  return 0;
}

int exportModel(const std::vector<std::string> &a)
{
  std::string model_name, kind, out;
  for (size_t i = 0; i < a.size(); ++i) {
    if (a[i] == "--urdf" || a[i] == "--dh" || a[i] == "--mdh") {
      if (!kind.empty())
        throw BadUsage("export: one of --urdf, --dh, --mdh");
      kind = a[i];
      out = textArg(a, i);
    } else if (!a[i].empty() && a[i][0] == '-')
      throw BadUsage("export: unknown option '" + a[i] + "'");
    else if (model_name.empty())
      model_name = a[i];
    else
      throw BadUsage("export: one model");
  }
  if (model_name.empty() || kind.empty())
    throw BadUsage("export: MODEL and one of --urdf, --dh, --mdh");
  const vpKinematicChain model = vpKinematicChain::fromPresetOrFile(model_name);
  if (!canonical(out).empty() && canonical(out) == canonical(model_name)) {
    std::cerr << "error: '" << out << "' is the input model\n";
    return 1;
  }
  if (kind == "--urdf") {
    vpModelExport::saveURDF(model, out);
    std::cout << "wrote " << out << "\n";
    return 0;
  }
  const vpModelExport::DHFit fit =
      vpModelExport::fitDH(model, kind == "--dh" ? vpKinematicChain::DH : vpKinematicChain::MDH);
  std::cerr << fit.message << "\n";
  if (!fit.representable)
    return 3;
  fit.table.saveYaml(out);
  std::cout << "wrote " << out << (fit.well_conditioned ? "" : " (ill-conditioned, see above)") << "\n";
  return 0;
}
} // namespace

int main(int argc, char **argv)
{
  if (argc < 2)
    return usage(std::cerr, 2);
  const std::string cmd = argv[1];
  if (cmd == "-h" || cmd == "--help" || cmd == "help")
    return usage(std::cout, 0);
  const std::vector<std::string> rest(argv + 2, argv + argc);
  for (const std::string &a : rest)
    if (a == "--help" || a == "-h")
      return commandHelp(cmd);
  try {
    if (cmd == "simulate")
      return simulate(rest);
    if (cmd == "calibrate")
      return calibrate(rest);
    if (cmd == "export")
      return exportModel(rest);
    if (cmd == "plan")
      return plan(rest);
    if (cmd == "verify") {
      if (rest.size() != 2)
        throw BadUsage("verify: MODEL DATASET");
      return verify(rest[0], rest[1]);
    }
    if ((cmd != "info" && cmd != "predict") || rest.empty() || (cmd == "info" && rest.size() != 1) || rest.size() > 2)
      return usage(std::cerr, 2);
    const vpKinematicChain chain = vpKinematicChain::fromPresetOrFile(rest[0]);
    if (cmd == "info")
      return info(chain);
    if (rest.size() == 2) {
      std::ifstream in(rest[1]);
      if (!in) {
        std::cerr << "error: cannot open joints file '" << rest[1] << "'\n";
        return 1;
      }
      return predict(chain, in, rest[1]);
    }
    return predict(chain, std::cin, "<stdin>");
  } catch (const BadUsage &e) {
    std::cerr << "error: " << e.what() << "\n";
    return usage(std::cerr, 2);
  } catch (const vpException &e) {
    std::cerr << "error: " << e.getStringMessage() << "\n";
    return 1;
  } catch (const std::exception &e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
}
