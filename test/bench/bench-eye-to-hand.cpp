/*
 * bench-eye-to-hand: the eye-to-hand set-up (a camera fixed in the world, a board on the tool) with
 * the hand-eye method, against the truth of vpSelfCalibSimulator::simulateEyeToHand.
 *
 *   bench-eye-to-hand [--seeds N] [--draws K] [--noise 0.2,0.5] [--pose-sd T,R] [--csv FILE]
 *
 * Per noise level (pixel sd; the controller poses' error T m / R rad, 2 mm / 2 mrad by default):
 *   - accuracy against the Cramér-Rao bound: over N seeds (geometries), the RMS error of bMc and eMo
 *     (translation in m, rotation in rad, over the three axes) over the RMS of the bound, the
 *     covariance of the same problem at the truth (vpKinematicBundleAdjustment::information, the
 *     pose errors' prior included) (target <= 1.2);
 *   - honesty of the reported covariance: on the first seed's geometry, K noise draws (pixels and
 *     pose errors); the mean normalised estimation error squared NEES / 6 of bMc (the chain's eMc
 *     correction block and its covariance) and of eMo (the board pose and its covariance)
 *     (target 0.7-1.4), and the measured pose sd against the true one.
 */
#include <chrono>
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

RSC::Options options(const std::map<int, vpColVector> &layout, double pixel_sd)
{
  RSC::Options o;
  o.method = RSC::HAND_EYE;
  o.bundle.known_points = layout;
  o.noise.pixel_sd = pixel_sd;
  return o;
}

//! The Cramér-Rao bound of the problem at the truth: the bMc correction block and eMo's covariance.
bool bound(const vpSelfCalibDataset &ds, const vpSelfCalibSimulator::EyeToHandTruth &truth, double pixel_sd,
           Eigen::MatrixXd &C_bMc, Eigen::MatrixXd &C_eMo)
{
  vpKinematicChain chain = vpKinematicChain::preset("viper850");
  chain.set_eMc(vpPoseVector(truth.bMc));
  vpSelfCalibDataset inverted = ds;
  for (auto &v : inverted.views)
    v.fMe = v.fMe.inverse();
  std::map<int, vpColVector> points;
  for (const auto &p : truth.layout) {
    vpColVector X(4, 1.0);
    for (unsigned int i = 0; i < 3; ++i)
      X[i] = p.second[i];
    const vpColVector Y = truth.eMo * X;
    points[p.first] = vpColVector({Y[0], Y[1], Y[2]});
  }
  KBA::Options ko;
  ko.hand_eye_only = true;
  ko.controller_poses_inverted = true;
  ko.known_points = truth.layout;
  ko.intrinsics = 0;
  vpSelfCalibNoiseModel noise;
  noise.pixel_sd = pixel_sd;
  noise = noise.withPoseError(ds.pose_sd_translation, ds.pose_sd_rotation, vpSelfCalibNoiseModel::STATED);
  const KBA::Result info = KBA::information(chain, ds.cam, inverted.views, vpSelfCalibDataset::Yardstick(), points, ko, noise);
  if (!info.has_covariance || !info.has_object)
    return false;
  C_bMc = block(info.covariance, info.covariance_names, kEMc);
  C_eMo = Eigen::MatrixXd(6, 6);
  for (unsigned int i = 0; i < 6; ++i)
    for (unsigned int j = 0; j < 6; ++j)
      C_eMo(i, j) = info.object_covariance[i][j];
  return C_bMc.size() == 36;
}

//! The run's errors: bMc in its chain's correction coordinates, eMo in the object pose's.
void errors(const RSC::Result &r, const vpSelfCalibSimulator::EyeToHandTruth &truth, Eigen::Matrix<double, 6, 1> &e_bMc,
            Eigen::Matrix<double, 6, 1> &e_eMo)
{
  const vpHomogeneousMatrix start(r.calibrated.get_eMc_pose());
  const vpHomogeneousMatrix est = r.calibrated.get_eMc_corrected();
  e_bMc = coordinates(start.inverse() * est) - coordinates(start.inverse() * truth.bMc);
  e_eMo = coordinates(vpHomogeneousMatrix(r.eMo)) - coordinates(truth.eMo);
}

//! The set-up of a seed (geometry) and a noise seed (0: the seed's own draw).
vpSelfCalibDataset simulate(unsigned int seed, unsigned int noise_seed, double pixel_sd, const std::vector<double> &pose_sd,
                            vpSelfCalibSimulator::EyeToHandTruth &truth)
{
  vpSelfCalibSimulator::EyeToHandOptions so;
  so.seed = seed;
  so.noise_seed = noise_seed;
  so.pixel_noise_sd = pixel_sd;
  so.pose_sd_translation = pose_sd[0];
  so.pose_sd_rotation = pose_sd[1];
  return vpSelfCalibSimulator::simulateEyeToHand(so, truth);
}

double nees(const Eigen::Matrix<double, 6, 1> &e, const Eigen::MatrixXd &C)
{
  return e.dot(C.ldlt().solve(e)) / 6.0;
}
} // namespace

int main(int argc, char **argv)
{
  try {
    unsigned int seeds = 10, draws = 30;
    std::vector<double> noises = {0.2, 0.5}, pose_sd = {0.002, 0.002};
    std::string csv_path;
    CLI::App app("bench-eye-to-hand: a camera fixed in the world, a board on the tool, the hand-eye method\n"
                 "against the Cramér-Rao bound and its own covariance.",
                 "bench-eye-to-hand");
    selfcalibCli::addSeeds(app, seeds);
    app.add_option("--draws", draws, "noise draws on the first seed's geometry for the NEES (default 30)")
        ->type_name("K")
        ->check(selfcalibCli::wholeNumber());
    selfcalibCli::addNoiseLevels(app, noises, "pixel noise levels, above 0 (default 0.2,0.5)", true);
    app.add_option("--pose-sd", pose_sd, "the controller poses' error T,R (m, rad; default 0.002,0.002)")
        ->type_name("T,R")
        ->delimiter(',')
        ->expected(2);
    app.add_option("--csv", csv_path, "one row per noise, seed or draw")->type_name("FILE");
    const int parsed = selfcalibCli::parse(app, argc, argv);
    if (parsed >= 0)
      return parsed;
    bench::Csv csv(csv_path, "noise_px,kind,seed,draw,status,bMc_t_err_m,bMc_r_err_rad,eMo_t_err_m,eMo_r_err_rad,"
                             "bound_bMc_t_m,bound_bMc_r_rad,nees_bMc,nees_eMo,measured_pose_sd_m,measured_pose_sd_rad");
    std::cout << "bench-eye-to-hand: " << seeds << " seeds, " << draws << " draws; 12 views of a 6 x 5 board (2 cm) "
              << "0.35-0.6 m from a 600 px camera; controller pose error " << 1e3 * pose_sd[0] << " mm / "
              << 1e3 * pose_sd[1] << " mrad\n\n"
              << "| noise (px) | runs | failed | bMc t RMS / bound (mm) | bMc r RMS / bound (mrad) | eMo t RMS / bound (mm) "
                 "| eMo r RMS / bound (mrad) | worst ratio | NEES/6 bMc | NEES/6 eMo | measured pose sd (mm / mrad) | "
                 "targets |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    const auto t_start = std::chrono::steady_clock::now();
    bool all_met = true;
    for (double noise : noises) {
      double e2[4] = {0, 0, 0, 0}, b2[4] = {0, 0, 0, 0};
      unsigned int runs = 0, failed = 0;
      for (unsigned int seed = 1; seed <= seeds; ++seed) {
        vpSelfCalibSimulator::EyeToHandTruth truth;
        const vpSelfCalibDataset ds = simulate(seed, 0, noise, pose_sd, truth);
        Eigen::MatrixXd Cb, Co;
        if (!bound(ds, truth, noise, Cb, Co))
          throw std::runtime_error("no bound for seed " + std::to_string(seed));
        const RSC::Result r = RSC::run(vpKinematicChain::preset("viper850"), ds, options(truth.layout, noise));
        ++runs;
        if (!(r.status == RSC::OK || r.status == RSC::DOUBTFUL) || !r.has_eMo) {
          ++failed;
          continue;
        }
        Eigen::Matrix<double, 6, 1> eb, eo;
        errors(r, truth, eb, eo);
        const double parts[4] = {eb.head<3>().squaredNorm(), eb.tail<3>().squaredNorm(), eo.head<3>().squaredNorm(),
                                 eo.tail<3>().squaredNorm()};
        const double bounds[4] = {Cb.topLeftCorner<3, 3>().trace(), Cb.bottomRightCorner<3, 3>().trace(),
                                  Co.topLeftCorner<3, 3>().trace(), Co.bottomRightCorner<3, 3>().trace()};
        for (int i = 0; i < 4; ++i) {
          e2[i] += parts[i];
          b2[i] += bounds[i];
        }
        csv.row() << noise << ",seed," << seed << ",0," << RSC::statusName(r.status) << "," << std::sqrt(parts[0]) << ","
                  << std::sqrt(parts[1]) << "," << std::sqrt(parts[2]) << "," << std::sqrt(parts[3]) << ","
                  << std::sqrt(bounds[0]) << "," << std::sqrt(bounds[1]) << ",,,,\n";
      }
      // NEES over draws on seed 1's geometry.
      bench::Stats nb, no, mt, mr;
      for (unsigned int d = 1; d <= draws; ++d) {
        vpSelfCalibSimulator::EyeToHandTruth truth;
        const vpSelfCalibDataset ds = simulate(1, d, noise, pose_sd, truth);
        const RSC::Result r = RSC::run(vpKinematicChain::preset("viper850"), ds, options(truth.layout, noise));
        if (!(r.status == RSC::OK || r.status == RSC::DOUBTFUL) || !r.has_eMo || !r.bundle.has_covariance)
          continue;
        Eigen::Matrix<double, 6, 1> eb, eo;
        errors(r, truth, eb, eo);
        const Eigen::MatrixXd Cb = block(r.bundle.covariance, r.bundle.covariance_names, kEMc);
        Eigen::MatrixXd Co(6, 6);
        for (unsigned int i = 0; i < 6; ++i)
          for (unsigned int j = 0; j < 6; ++j)
            Co(i, j) = r.bundle.object_covariance[i][j];
        if (Cb.size() != 36)
          continue;
        nb.add(nees(eb, Cb));
        no.add(nees(eo, Co));
        mt.add(r.measured.pose_sd_translation);
        mr.add(r.measured.pose_sd_rotation);
        csv.row() << noise << ",draw,1," << d << "," << RSC::statusName(r.status) << ",,,,,,," << nb.v.back() << ","
                  << no.v.back() << "," << r.measured.pose_sd_translation << "," << r.measured.pose_sd_rotation << "\n";
      }
      double worst = 0;
      for (int i = 0; i < 4; ++i)
        worst = std::max(worst, std::sqrt(e2[i] / b2[i]));
      const bool met = failed == 0 && worst <= 1.2 && nb.mean() >= 0.7 && nb.mean() <= 1.4 && no.mean() >= 0.7 &&
                       no.mean() <= 1.4;
      all_met = all_met && met;
      const unsigned int ok = runs - failed;
      const auto pair = [&](int i, double unit) {
        std::ostringstream os;
        os << std::fixed << std::setprecision(3) << unit * std::sqrt(e2[i] / std::max(1u, ok)) << " / "
           << unit * std::sqrt(b2[i] / std::max(1u, ok));
        return os.str();
      };
      std::cout << std::fixed << std::setprecision(1) << "| " << noise << " | " << runs << " | " << failed << " | "
                << pair(0, 1e3) << " | " << pair(1, 1e3) << " | " << pair(2, 1e3) << " | " << pair(3, 1e3) << " | "
                << std::setprecision(2) << worst << " | " << nb.mean() << " (" << nb.count() << ") | " << no.mean()
                << " | " << 1e3 * mt.mean() << " / " << 1e3 * mr.mean() << " | " << (met ? "met" : "NOT met")
                << " |\n"
                << std::flush;
    }
    std::cout << "\ntargets: RMS / Cramer-Rao bound <= 1.2 for bMc and eMo (t and r), NEES/6 in 0.7-1.4, no failure: "
              << (all_met ? "met" : "NOT met") << "\ndone in " << std::setprecision(0)
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count() << " s\n";
    return EXIT_SUCCESS;
  } catch (const vpException &e) {
    std::cerr << "bench-eye-to-hand: " << e.getStringMessage() << "\n";
  } catch (const std::exception &e) {
    std::cerr << "bench-eye-to-hand: " << e.what() << "\n";
  }
  return EXIT_FAILURE;
}
