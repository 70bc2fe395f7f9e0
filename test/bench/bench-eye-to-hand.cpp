/*
 * bench-eye-to-hand: the eye-to-hand set-up (a camera fixed in the world, a board on the tool) with
 * the hand-eye method and the full kinematics (bundle) method, against the truth of
 * vpSelfCalibSimulator::simulateEyeToHand.
 *
 *   bench-eye-to-hand [--seeds N] [--draws K] [--noise 0.2,0.5] [--pose-sd T,R] [--joint-sd R]
 *                     [--robots ur5,panda] [--methods hand-eye,bundle] [--robot-error none,with] [--views M]
 *                     [--first-seed S] [--csv FILE]
 *
 * The arms (a 6-axis ur5 and a 7-axis panda by default) carry a board of 8 x 6 corners 3 cm apart
 * (a ChArUco board's corners as points data) seen by a fixed 1280 x 720 camera (f 1000 px) about
 * 0.7 m away; M views (25) drawn about a home configuration. Per method, arm, pixel noise and robot
 * error (without; with: the controller poses' T m / R rad for hand-eye, 2 mm / 2 mrad by default,
 * the joint readings' R rad for bundle, 2 mrad by default, stated as the dataset states it; without,
 * the data stated exact, trust_robot, so that the run models what the bound models):
 *   - accuracy against the Cramér-Rao bound: over N seeds (geometries), the RMS error of bMc and eMo
 *     (translation in m, rotation in rad, over the three axes) over the RMS of the bound, the
 *     covariance of the same problem at the truth (vpKinematicBundleAdjustment::information, the
 *     robot error's prior included) (target <= 1.2). Hand-eye: the truth is bMc and eMo. Bundle:
 *     the base and joint 1's placement act as a change of bMc, the last joint's offset and slide as
 *     one of eMo, so the truth is the same model's noise-free estimate on the same geometry and
 *     estimated set (what the true robot is in the estimated parameters), and the bound is taken
 *     there; and each run's error e against the bound C at its geometry, e' C^-1 e / 6, over the seeds
 *     and over the draws below (1 at the bound), which says whether a ratio above 1.2 is the
 *     estimator (NEES above 1 on the same geometry) or the spread of an RMS over few seeds;
 *   - honesty of the reported covariance: on the first seed's geometry, K noise draws (pixels and
 *     robot error); the mean normalised estimation error squared NEES / 6 of bMc (the chain's eMc
 *     correction block and its covariance) and of eMo (the board pose and its covariance)
 *     (target 0.7-1.4).
 */
#include <algorithm>
#include <chrono>
#include <map>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include <visp3/core/vpException.h>
#include <visp3/selfcalib/vpKinematicBundleAdjustment.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "benchCommon.h"
#include "selfcalibCli.h"

namespace
{
using RSC = vpRobotSelfCalibration;
using KBA = vpKinematicBundleAdjustment;

//! The (t, theta u) of a transform, as a 6-vector (the coordinates of the chain's corrections and of the object pose).
Eigen::Matrix<double, 6, 1> coordinates(const vpHomogeneousMatrix &M)
{
  const vpPoseVector p(M);
  Eigen::Matrix<double, 6, 1> v;
  for (unsigned int i = 0; i < 6; ++i)
    v(i) = p[i];
  return v;
}

//! The rows and columns of `names` in a covariance (6 x 6; empty when one is missing).
Eigen::MatrixXd block(const vpMatrix &C, const std::vector<std::string> &all, const std::vector<std::string> &names)
{
  std::vector<int> row;
  for (const std::string &n : names)
    for (size_t r = 0; r < all.size(); ++r)
      if (all[r] == n)
        row.push_back(static_cast<int>(r));
  if (row.size() != names.size())
    return Eigen::MatrixXd();
  Eigen::MatrixXd B(row.size(), row.size());
  for (size_t i = 0; i < row.size(); ++i)
    for (size_t j = 0; j < row.size(); ++j)
      B(i, j) = C[static_cast<unsigned int>(row[i])][static_cast<unsigned int>(row[j])];
  return B;
}

const std::vector<std::string> kEMc = {"eMc.tx", "eMc.ty", "eMc.tz", "eMc.rx", "eMc.ry", "eMc.rz"};

struct Setup {
  std::string method, robot;
  double noise = 0.2;
  bool robot_error = false;
  unsigned int views = 25;
  std::vector<double> pose_sd;
  double joint_sd = 0;
};

bool isBundle(const Setup &s) { return s.method == "bundle"; }

vpColVector homeOf(const std::string &robot)
{
  if (robot == "ur5")
    return vpColVector({0, -1.0, 1.2, -0.2, 1.2, 0}); // elbow bent, wrist away from its singularity
  return vpColVector();                               // vpSelfCalibSimulator::homeConfiguration()
}

//! The set-up of a seed (geometry) and a noise seed (0: the seed's own draw); clean: no noise at all.
vpSelfCalibDataset simulate(const Setup &s, unsigned int seed, unsigned int noise_seed, bool clean,
                            vpSelfCalibSimulator::EyeToHandTruth &truth)
{
  vpSelfCalibSimulator::EyeToHandOptions so = vpSelfCalibSimulator::eyeToHandHd();
  so.seed = seed;
  so.noise_seed = noise_seed;
  so.robot = s.robot;
  so.home = homeOf(s.robot);
  so.num_views = s.views;
  so.board_cols = 8;
  so.board_rows = 6;
  so.board_spacing = 0.03;
  so.distance_min = 0.6;
  so.distance_max = 0.8;
  so.joint_spread = 0.3;
  so.pixel_noise_sd = clean ? 0 : s.noise;
  if (s.robot_error && !clean && !isBundle(s)) {
    so.pose_sd_translation = s.pose_sd[0];
    so.pose_sd_rotation = s.pose_sd[1];
  }
  if (s.robot_error && !clean && isBundle(s))
    so.joint_sd = s.joint_sd;
  vpSelfCalibDataset ds = vpSelfCalibSimulator::simulateEyeToHand(so, truth);
  if (isBundle(s)) // the full kinematics method reads the joints; the controller poses are not its data
    for (auto &v : ds.views)
      v.has_fMe = false;
  if (s.robot_error && clean && isBundle(s))
    ds.joint_sd = {s.joint_sd}; // the reference run states the same error (same estimated set)
  return ds;
}

RSC::Options options(const Setup &s, const std::map<int, vpColVector> &layout)
{
  RSC::Options o;
  o.method = isBundle(s) ? RSC::BUNDLE_ADJUSTMENT : RSC::HAND_EYE;
  o.num_calibration_poses = s.views; // every view calibrates (the bound is of the same views)
  o.bundle.known_points = layout;
  o.noise.pixel_sd = s.noise;
  // The robot's error stated here, whatever the methods' defaults (which may model or measure it):
  // without, the data exact (the default would model and measure an error that is not there); with,
  // the level the data were drawn with, stated and not measured, the covariance widened by sigma0
  // as for a level the dataset states. The run models what the bound models.
  o.trust_robot = !s.robot_error;
  o.noise.measure_pose_sd = o.noise.measure_joint_sd = o.noise.measure_model_sd = false;
  if (s.robot_error) {
    const vpSelfCalibNoiseModel::Origin stated = vpSelfCalibNoiseModel::STATED;
    o.noise = isBundle(s) ? o.noise.withJointError({s.joint_sd}, stated)
                          : o.noise.withPoseError(s.pose_sd[0], s.pose_sd[1], stated);
    o.bundle.scale_covariance = true;
  }
  return o;
}

bool usable(const RSC::Result &r)
{
  return (r.status == RSC::OK || r.status == RSC::DOUBTFUL) && r.has_eMo && r.bundle.has_covariance;
}

//! The object's covariance of a bundle adjustment result (6 x 6).
Eigen::MatrixXd objectCovariance(const KBA::Result &b)
{
  Eigen::MatrixXd C(6, 6);
  for (unsigned int i = 0; i < 6; ++i)
    for (unsigned int j = 0; j < 6; ++j)
      C(i, j) = b.object_covariance[i][j];
  return C;
}

//! The points of the layout placed in e through eMo.
std::map<int, vpColVector> pointsInE(const std::map<int, vpColVector> &layout, const vpHomogeneousMatrix &eMo)
{
  std::map<int, vpColVector> points;
  for (const auto &p : layout) {
    const vpColVector Y = eMo * vpColVector({p.second[0], p.second[1], p.second[2], 1.0});
    points[p.first] = vpColVector({Y[0], Y[1], Y[2]});
  }
  return points;
}

//! Hand-eye: the Cramér-Rao bound of the problem at the truth (the bMc correction block, eMo).
bool handEyeBound(const Setup &s, const vpSelfCalibDataset &ds, const vpSelfCalibSimulator::EyeToHandTruth &truth,
                  Eigen::MatrixXd &C_bMc, Eigen::MatrixXd &C_eMo)
{
  vpKinematicChain chain = vpKinematicChain::preset(s.robot);
  chain.set_eMc(vpPoseVector(truth.bMc));
  vpSelfCalibDataset inverted = ds;
  for (auto &v : inverted.views)
    v.fMe = v.fMe.inverse();
  KBA::Options ko;
  ko.hand_eye_only = true;
  ko.controller_poses_inverted = true;
  ko.known_points = truth.layout;
  ko.intrinsics = 0;
  vpSelfCalibNoiseModel noise;
  noise.pixel_sd = s.noise;
  noise = noise.withPoseError(ds.pose_sd_translation, ds.pose_sd_rotation, vpSelfCalibNoiseModel::STATED);
  const KBA::Result info = KBA::information(chain, ds.cam, inverted.views, vpSelfCalibDataset::Yardstick(),
                                            pointsInE(truth.layout, truth.eMo), ko, noise);
  if (!info.has_covariance || !info.has_object)
    return false;
  C_bMc = block(info.covariance, info.covariance_names, kEMc);
  C_eMo = objectCovariance(info);
  return C_bMc.size() == 36;
}

//! A bundle reference and its bound, kept per seed and estimated set (the draws share seed 1's).
struct Reference {
  RSC::Result ref;
  Eigen::MatrixXd C_bMc, C_eMo;
  bool ok = false;
};
using ReferenceCache = std::map<std::string, Reference>;

/*
  Bundle: the reference (the same model's noise-free estimate on the same geometry, estimated set
  and stated noise: the truth in the estimated parameters) and the Cramér-Rao bound there (the true
  joints, the stated pixel and joint noise).
*/
bool bundleReference(const Setup &s, unsigned int seed, const RSC::Result &r, RSC::Result &ref, Eigen::MatrixXd &C_bMc,
                     Eigen::MatrixXd &C_eMo)
{
  vpSelfCalibSimulator::EyeToHandTruth truth;
  const vpSelfCalibDataset clean = simulate(s, seed, 0, true, truth);
  RSC::Options o = options(s, truth.layout);
  o.bundle.estimated_set = r.identifiability;
  o.bundle.tight = true;
  ref = RSC::run(vpKinematicChain::preset(s.robot), clean, o);
  if (!usable(ref))
    return false;
  KBA::Options ko;
  ko.eye_to_hand = true;
  ko.known_points = truth.layout;
  ko.intrinsics = 0;
  ko.estimated_set = r.identifiability;
  vpSelfCalibNoiseModel noise;
  noise.pixel_sd = s.noise;
  if (s.robot_error)
    noise.joint_sd = {s.joint_sd};
  const KBA::Result info = KBA::information(ref.calibrated, ref.camera, clean.views, vpSelfCalibDataset::Yardstick(),
                                            ref.bundle.points, ko, noise);
  if (!info.has_covariance || !info.has_object)
    return false;
  C_bMc = block(info.covariance, info.covariance_names, kEMc);
  C_eMo = objectCovariance(info);
  return C_bMc.size() == 36;
}

//! The run's errors: bMc in its chain's correction coordinates (about the reference), eMo in the object pose's.
void errors(const RSC::Result &r, const vpHomogeneousMatrix &bMc, const vpHomogeneousMatrix &eMo,
            Eigen::Matrix<double, 6, 1> &e_bMc, Eigen::Matrix<double, 6, 1> &e_eMo)
{
  const vpHomogeneousMatrix start(r.calibrated.get_eMc_pose());
  const vpHomogeneousMatrix est = r.calibrated.get_eMc_corrected();
  e_bMc = coordinates(start.inverse() * est) - coordinates(start.inverse() * bMc);
  e_eMo = coordinates(vpHomogeneousMatrix(r.eMo)) - coordinates(eMo);
}

double nees(const Eigen::Matrix<double, 6, 1> &e, const Eigen::MatrixXd &C)
{
  return e.dot(C.ldlt().solve(e)) / 6.0;
}

//! One run and its errors against the truth (hand-eye) or the reference (bundle), with the bound; false: failed.
bool measure(const Setup &s, unsigned int seed, unsigned int draw, Eigen::Matrix<double, 6, 1> &eb,
             Eigen::Matrix<double, 6, 1> &eo, Eigen::MatrixXd &Cb, Eigen::MatrixXd &Co, RSC::Result &r,
             ReferenceCache &cache)
{
  vpSelfCalibSimulator::EyeToHandTruth truth;
  const vpSelfCalibDataset ds = simulate(s, seed, draw, false, truth);
  r = RSC::run(vpKinematicChain::preset(s.robot), ds, options(s, truth.layout));
  if (!usable(r))
    return false;
  if (!isBundle(s)) {
    if (!handEyeBound(s, ds, truth, Cb, Co))
      throw std::runtime_error("no bound for seed " + std::to_string(seed));
    errors(r, truth.bMc, truth.eMo, eb, eo);
    return true;
  }
  std::string key = std::to_string(seed);
  for (unsigned int i : r.identifiability.identified)
    key += "," + std::to_string(i);
  auto it = cache.find(key);
  if (it == cache.end()) {
    Reference e;
    e.ok = bundleReference(s, seed, r, e.ref, e.C_bMc, e.C_eMo);
    it = cache.emplace(key, e).first;
  }
  if (!it->second.ok)
    return false;
  Cb = it->second.C_bMc;
  Co = it->second.C_eMo;
  errors(r, it->second.ref.calibrated.get_eMc_corrected(), vpHomogeneousMatrix(it->second.ref.eMo), eb, eo);
  return true;
}

struct RowResult {
  double e2[4] = {0, 0, 0, 0}, b2[4] = {0, 0, 0, 0};
  unsigned int runs = 0, failed = 0;
  bench::Stats nb, no;   //!< NEES / 6 of the run's own covariance over the draws
  bench::Stats cb, co;   //!< NEES / 6 against the Cramér-Rao bound over the seeds
  bench::Stats db, dob;  //!< NEES / 6 against the Cramér-Rao bound over the draws (seed 1's geometry)
  double worst() const
  {
    double w = 0;
    for (int i = 0; i < 4; ++i)
      w = std::max(w, std::sqrt(e2[i] / b2[i]));
    return w;
  }
  bool met() const
  {
    return failed == 0 && worst() <= 1.2 && nb.mean() >= 0.7 && nb.mean() <= 1.4 && no.mean() >= 0.7 && no.mean() <= 1.4;
  }
};

RowResult row(const Setup &s, unsigned int first, unsigned int seeds, unsigned int draws, bench::Csv &csv)
{
  RowResult out;
  ReferenceCache cache;
  const std::string key = s.method + "," + s.robot + "," + std::to_string(s.noise) + "," + (s.robot_error ? "1" : "0");
  for (unsigned int seed = first; seed < first + seeds; ++seed) {
    Eigen::Matrix<double, 6, 1> eb, eo;
    Eigen::MatrixXd Cb, Co;
    RSC::Result r;
    ++out.runs;
    if (!measure(s, seed, 0, eb, eo, Cb, Co, r, cache)) {
      ++out.failed;
      csv.row() << key << ",seed," << seed << ",0," << RSC::statusName(r.status) << ",,,,,,,,\n";
      continue;
    }
    const double parts[4] = {eb.head<3>().squaredNorm(), eb.tail<3>().squaredNorm(), eo.head<3>().squaredNorm(),
                             eo.tail<3>().squaredNorm()};
    const double bounds[4] = {Cb.topLeftCorner<3, 3>().trace(), Cb.bottomRightCorner<3, 3>().trace(),
                              Co.topLeftCorner<3, 3>().trace(), Co.bottomRightCorner<3, 3>().trace()};
    for (int i = 0; i < 4; ++i) {
      out.e2[i] += parts[i];
      out.b2[i] += bounds[i];
    }
    out.cb.add(nees(eb, Cb));
    out.co.add(nees(eo, Co));
    csv.row() << key << ",seed," << seed << ",0," << RSC::statusName(r.status) << "," << std::sqrt(parts[0]) << ","
              << std::sqrt(parts[1]) << "," << std::sqrt(parts[2]) << "," << std::sqrt(parts[3]) << ","
              << std::sqrt(bounds[0]) << "," << std::sqrt(bounds[1]) << "," << out.cb.v.back() << "," << out.co.v.back()
              << "\n";
  }
  // NEES over draws on the first seed's geometry, with the run's own covariance.
  for (unsigned int d = 1; d <= draws; ++d) {
    Eigen::Matrix<double, 6, 1> eb, eo;
    Eigen::MatrixXd Cb, Co;
    RSC::Result r;
    if (!measure(s, first, d, eb, eo, Cb, Co, r, cache))
      continue;
    const Eigen::MatrixXd Rb = block(r.bundle.covariance, r.bundle.covariance_names, kEMc);
    if (Rb.size() != 36)
      continue;
    out.nb.add(nees(eb, Rb));
    out.no.add(nees(eo, objectCovariance(r.bundle)));
    out.db.add(nees(eb, Cb));
    out.dob.add(nees(eo, Co));
    csv.row() << key << ",draw," << first << "," << d << "," << RSC::statusName(r.status) << ",,,,,,," << out.nb.v.back() << ","
              << out.no.v.back() << "\n";
  }
  return out;
}

//! sqrt(chi2_k(0.975) / k): the ratio an RMS over k squared N(0, 1) exceeds with probability 2.5 % (Wilson-Hilferty).
double chi2Ratio975(unsigned int k)
{
  const double a = 2.0 / (9.0 * k), q = 1.0 - a + 1.959964 * std::sqrt(a);
  return std::sqrt(q * q * q);
}

std::string pair(const RowResult &r, int i)
{
  std::ostringstream os;
  const unsigned int ok = std::max(1u, r.runs - r.failed);
  os << std::fixed << std::setprecision(3) << 1e3 * std::sqrt(r.e2[i] / ok) << " / " << 1e3 * std::sqrt(r.b2[i] / ok);
  return os.str();
}
} // namespace

int main(int argc, char **argv)
{
  try {
    unsigned int seeds = 10, draws = 30, views = 25, first_seed = 1;
    std::vector<double> noises = {0.2, 0.5}, pose_sd = {0.002, 0.002};
    double joint_sd = 0.002;
    std::vector<std::string> robots = {"ur5", "panda"}, methods = {"hand-eye", "bundle"}, errors = {"none", "with"};
    std::string csv_path;
    CLI::App app("bench-eye-to-hand: a camera fixed in the world, a board on the tool of a 6- and a 7-axis arm, the\n"
                 "hand-eye and full kinematics methods against the Cramér-Rao bound and their own covariance.",
                 "bench-eye-to-hand");
    selfcalibCli::addSeeds(app, seeds);
    app.add_option("--draws", draws, "noise draws on the first seed's geometry for the NEES (default 30)")
        ->type_name("K")
        ->check(selfcalibCli::wholeNumber());
    selfcalibCli::addNoiseLevels(app, noises, "pixel noise levels, above 0 (default 0.2,0.5)", true);
    app.add_option("--pose-sd", pose_sd, "hand-eye rows with robot error: the controller poses' error T,R (m, rad; "
                                         "default 0.002,0.002)")
        ->type_name("T,R")
        ->delimiter(',')
        ->expected(2);
    app.add_option("--joint-sd", joint_sd, "bundle rows with robot error: the joint readings' error (rad; default 0.002)")
        ->type_name("R")
        ->check(CLI::Range(1e-6, 0.1));
    app.add_option("--robots", robots, "arms (presets; default ur5,panda)")->type_name("R,...")->delimiter(',');
    app.add_option("--methods", methods, "hand-eye and/or bundle (default both)")
        ->type_name("M,...")
        ->delimiter(',')
        ->check(CLI::IsMember({"hand-eye", "bundle"}));
    app.add_option("--robot-error", errors, "rows without and/or with robot error (default none,with)")
        ->type_name("none|with,...")
        ->delimiter(',')
        ->check(CLI::IsMember({"none", "with"}));
    app.add_option("--first-seed", first_seed, "the first seed (geometry; default 1): more seeds of a row in another run")
        ->type_name("S")
        ->check(CLI::Range(1u, 1000000u));
    app.add_option("--views", views, "views per data set (default 25)")->type_name("M")->check(CLI::Range(6, 200));
    app.add_option("--csv", csv_path, "one row per set-up and seed or draw")->type_name("FILE");
    const int parsed = selfcalibCli::parse(app, argc, argv);
    if (parsed >= 0)
      return parsed;
    bench::Csv csv(csv_path, "method,robot,noise_px,robot_error,kind,seed,draw,status,bMc_t_err_m,bMc_r_err_rad,"
                             "eMo_t_err_m,eMo_r_err_rad,bound_bMc_t_m,bound_bMc_r_rad,nees_bMc,nees_eMo");
    // nees_*: a seed's error against the Cramér-Rao bound (kind seed), a draw's against the run's covariance (kind draw)
    std::cout << "bench-eye-to-hand: " << seeds << " seeds, " << draws << " draws; " << views
              << " views of a board of 8 x 6 corners (3 cm) on the tool, a fixed 1280 x 720 camera (f 1000 px) about "
                 "0.7 m away; robot error: controller poses "
              << 1e3 * pose_sd[0] << " mm / " << 1e3 * pose_sd[1] << " mrad (hand-eye), joint readings " << 1e3 * joint_sd
              << " mrad (bundle)\n\n"
              << "| method | arm | noise (px) | robot error | runs | failed | bMc t RMS / bound (mm) | bMc r RMS / bound "
                 "(mrad) | eMo t RMS / bound (mm) | eMo r RMS / bound (mrad) | worst ratio | error / bound NEES/6 bMc, eMo: "
                 "seeds; draws | "
                 "NEES/6 bMc | NEES/6 eMo | targets |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    const auto t_start = std::chrono::steady_clock::now();
    bool all_met = true;
    for (const std::string &method : methods)
      for (const std::string &robot : robots)
        for (double noise : noises)
          for (bool error : {false, true}) {
            if (std::find(errors.begin(), errors.end(), error ? "with" : "none") == errors.end())
              continue;
            Setup s{method, robot, noise, error, views, pose_sd, joint_sd};
            const RowResult r = row(s, first_seed, seeds, draws, csv);
            all_met = all_met && r.met();
            std::cout << std::fixed << std::setprecision(1) << "| " << method << " | " << robot << " | " << noise << " | "
                      << (error ? (method == "bundle" ? "joints" : "poses") : "none") << " | " << r.runs << " | "
                      << r.failed << " | " << pair(r, 0) << " | " << pair(r, 1) << " | " << pair(r, 2) << " | "
                      << pair(r, 3) << " | " << std::setprecision(2) << r.worst() << " | " << r.cb.mean() << ", "
                      << r.co.mean() << "; " << r.db.mean() << ", " << r.dob.mean() << " | " << r.nb.mean() << " ("
                      << r.nb.count() << ") | " << r.no.mean() << " | " << (r.met() ? "met" : "NOT met") << " |\n"
                      << std::flush;
          }
    std::cout << "\nerror / bound NEES/6: a run's error e against the bound C at its geometry, e' C^-1 e / 6, the mean "
                 "over the seeds and over the draws on the first seed's geometry (at the bound: 1, sd "
              << std::setprecision(2) << std::sqrt(2.0 / (6.0 * seeds)) << " over " << seeds << " seeds, "
              << std::sqrt(2.0 / (6.0 * std::max(1u, draws))) << " over " << draws
              << " draws); an RMS / bound ratio of one block over " << seeds << " seeds of an estimator at its bound "
              << "exceeds " << chi2Ratio975(3 * seeds) << " in 2.5 % of the rows (3 axes of equal variance; fewer "
              << "effective axes, more)\n";
    std::cout << "\ntargets: RMS / Cramer-Rao bound <= 1.2 for bMc and eMo (t and r), NEES/6 in 0.7-1.4, no failure: "
              << (all_met ? "met" : "NOT met") << "\ndone in " << std::setprecision(0)
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count() << " s\n";
    return all_met ? EXIT_SUCCESS : 3;
  } catch (const vpException &e) {
    std::cerr << "bench-eye-to-hand: " << e.getStringMessage() << "\n";
  } catch (const std::exception &e) {
    std::cerr << "bench-eye-to-hand: " << e.what() << "\n";
  }
  return EXIT_FAILURE;
}
