/*
 * bench-twoview: the two-view pose measurement (paper Section 3.1) on the reference scenario.
 *
 *   bench-twoview [--seeds N] [--noise 0.2,0.5] [--robot viper850|puma560] [--poses 25]
 *                 [--fx-guess PX] [--csv FILE] [-h]
 *
 * For every noise level and seed, the reference scenario (README, "Reference scenario") is drawn,
 * and the pairs (first pose, pose i), i = 2..poses, are estimated by
 *   (a) the refined factor method with f self-calibrated per pair (the paper),
 *   (b) the refined factor method with one f shared by all pairs (estimated jointly),
 *   (c) the refined factor method with f known,
 *   (d) OpenCV findEssentialMat (five-point, RANSAC, 1 px, 0.999) + recoverPose with f known,
 * on identical correspondences. Errors against the true relative pose c_iMc_1 of the simulated arm:
 * rotation angle, translation-direction angle, |f - f_true|. Pose errors of (a) are over the pairs
 * that returned OK (the others are counted as failures); f errors of (b) are one per seed.
 *
 * It also prints the Cramer-Rao bounds computed by bundle-adjustment information at the truth
 * (reprojection error, pixel noise sd, all points free, gauge fixed without touching f):
 *   - rotation of each pair with f known (two views): what (c) and (d) can reach;
 *   - f from all views jointly: what any estimator on these images can reach, shared f included.
 */
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <opencv2/calib3d.hpp>

#include <visp3/core/vpThetaUVector.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>
#include <visp3/selfcalib/vpTwoViewEstimator.h>

#include "benchCommon.h"
#include "selfcalibCli.h"

namespace
{
using Clock = std::chrono::steady_clock;

double ms(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double, std::milli>(b - a).count(); }

double rotationError(const vpHomogeneousMatrix &a, const vpHomogeneousMatrix &b)
{
  const vpThetaUVector tu(a.getRotationMatrix().t() * b.getRotationMatrix());
  return std::sqrt(tu.sumSquare());
}

double directionError(const vpHomogeneousMatrix &a, const vpHomogeneousMatrix &b)
{
  vpColVector ta = a.getTranslationVector(), tb = b.getTranslationVector();
  ta.normalize();
  tb.normalize();
  return std::atan2(vpColVector::crossProd(ta, tb).frobeniusNorm(), vpColVector::dotProd(ta, tb));
}

// Reprojection residual of bundle adjustment: camera (angle-axis, translation) maps reference
// coordinates to camera coordinates; pixel = f (x/z, y/z) + (u0, v0), mu = 1.
struct Reprojection {
  double u, v, u0, v0;
  template <typename T> bool operator()(const T *f, const T *cam, const T *X, T *r) const
  {
    T p[3];
    ceres::AngleAxisRotatePoint(cam, X, p);
    p[0] += cam[3];
    p[1] += cam[4];
    p[2] += cam[5];
    r[0] = f[0] * p[0] / p[2] + T(u0) - T(u);
    r[1] = f[0] * p[1] / p[2] + T(v0) - T(v);
    return true;
  }
};

struct Bound {
  double f_sd = NAN;               //!< px
  std::vector<double> rotation_sd; //!< rad, sqrt(trace) of the rotation covariance, per pair
};

/*
  Cramer-Rao bounds from the bundle-adjustment Fisher information at the truth: the first camera
  is the reference (constant), the scale gauge is one translation coordinate of another camera
  (fixing a scene point instead would leak information on f). Noise-free projections, so the
  Jacobian is evaluated at the true values; covariance = sigma^2 (J^T J)^-1.
*/
Bound cramerRao(const vpSelfCalibSimulator &sim, const std::vector<vpColVector> &q, double sigma)
{
  const vpCameraParameters cam = sim.getCamera();
  const vpHomogeneousMatrix fMc0 = sim.getTrueChain().get_fMc(q[0]);
  std::vector<std::array<double, 6>> cams(q.size());
  for (size_t k = 0; k < q.size(); ++k) {
    const vpHomogeneousMatrix ckMc0 = sim.getTrueChain().get_fMc(q[k]).inverse() * fMc0;
    const vpThetaUVector tu(ckMc0.getRotationMatrix());
    cams[k] = {tu[0], tu[1], tu[2], ckMc0[0][3], ckMc0[1][3], ckMc0[2][3]};
  }
  std::vector<std::array<double, 3>> X;
  for (const vpColVector &Pf : sim.getScenePoints()) {
    vpColVector P = fMc0.inverse() * vpColVector({Pf[0], Pf[1], Pf[2], 1.0});
    X.push_back({P[0], P[1], P[2]});
  }
  auto solve = [&](const std::vector<size_t> &views, bool f_free, Bound &out) {
    std::vector<std::array<double, 6>> c = cams;
    std::vector<std::array<double, 3>> x = X;
    double f = cam.get_px();
    ceres::Problem::Options po;
    po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(po);
    for (size_t k : views) {
      for (size_t i = 0; i < x.size(); ++i) {
        double p[3];
        ceres::AngleAxisRotatePoint(c[k].data(), x[i].data(), p);
        const double u = f * (p[0] + c[k][3]) / (p[2] + c[k][5]) + cam.get_u0();
        const double v = f * (p[1] + c[k][4]) / (p[2] + c[k][5]) + cam.get_v0();
        problem.AddResidualBlock(new ceres::AutoDiffCostFunction<Reprojection, 2, 1, 6, 3>(
                                     new Reprojection{u, v, cam.get_u0(), cam.get_v0()}),
                                 nullptr, &f, c[k].data(), x[i].data());
      }
    }
    problem.SetParameterBlockConstant(c[views[0]].data());
    const size_t g = views[1];
    int axis = 3;
    for (int j = 4; j < 6; ++j)
      if (std::fabs(c[g][j]) > std::fabs(c[g][axis]))
        axis = j;
    ceres::SubsetManifold gauge(6, {axis});
    problem.SetManifold(c[g].data(), &gauge);
    if (!f_free)
      problem.SetParameterBlockConstant(&f);
    ceres::Covariance::Options co;
    co.algorithm_type = ceres::DENSE_SVD;
    co.null_space_rank = 0;
    co.min_reciprocal_condition_number = 1e-300;
    ceres::Covariance cov(co);
    std::vector<std::pair<const double *, const double *>> blocks;
    if (f_free)
      blocks.push_back({&f, &f});
    else
      blocks.push_back({c[g].data(), c[g].data()});
    if (!cov.Compute(blocks, &problem))
      return;
    if (f_free) {
      double cf = 0;
      cov.GetCovarianceBlock(&f, &f, &cf);
      out.f_sd = sigma * std::sqrt(cf);
    } else {
      double C[36];
      cov.GetCovarianceBlock(c[g].data(), c[g].data(), C);
      out.rotation_sd.push_back(sigma * std::sqrt(C[0] + C[7] + C[14]));
    }
  };
  Bound b;
  std::vector<size_t> all(q.size());
  for (size_t k = 0; k < q.size(); ++k)
    all[k] = k;
  solve(all, true, b);
  for (size_t k = 1; k < q.size(); ++k)
    solve({0, k}, false, b);
  return b;
}

struct MethodStats {
  bench::Stats rot, dir, f, time;
  unsigned int failures = 0, pairs = 0;
  double rot_ss = 0; // sum of squared rotation errors, for the RMS against the bound
};

} // namespace

int main(int argc, char **argv)
{
  try {
    unsigned int seeds = 10, poses = 25;
    std::vector<double> noises = {0.2, 0.5};
    std::string robot = "viper850", csv_path;
    double fx_guess = 1400;
    CLI::App app("bench-twoview: the two-view pose measurement (paper Section 3.1) on the reference scenario.",
                 "bench-twoview");
    selfcalibCli::addSeeds(app, seeds);
    selfcalibCli::addNoiseLevels(app, noises, "pixel noise levels (default 0.2,0.5)");
    app.add_option("--robot", robot, "viper850 (default) or puma560")
        ->type_name("NAME")
        ->check(CLI::IsMember(vpKinematicChain::presetNames()));
    app.add_option("--poses", poses, "poses of the scenario, at least 3 (default 25: pairs (1, i), i = 2..N)")
        ->type_name("N")
        ->check(selfcalibCli::wholeNumber(3));
    app.add_option("--fx-guess", fx_guess,
                   "initial focal length for (a) and (b) when the closed form fails (default 1400)")
        ->type_name("PX")
        ->check(selfcalibCli::number(0, true));
    app.add_option("--csv", csv_path, "one row per noise, seed, method and pair")->type_name("FILE");
    const int parsed = selfcalibCli::parse(app, argc, argv);
    if (parsed >= 0)
      return parsed;
    bench::Csv csv(csv_path, "noise_px,seed,method,pair,status,rotation_error_rad,direction_error_rad,f_error_px,time_ms");
    const char *names[4] = {"(a) refined, f per pair", "(b) refined, f shared", "(c) refined, f known",
                            "(d) OpenCV 5-point, f known"};
    const char *tags[4] = {"a", "b", "c", "d"};
    std::cout << "bench-twoview: robot " << robot << ", " << seeds << " seeds, pairs (1, i) of " << poses
              << " poses, 80 points + yardstick, f = 1500 px\n";

    for (double noise : noises) {
      MethodStats m[4];
      bench::Stats bound_f, bound_rot_rms;
      for (unsigned int seed = 1; seed <= seeds; ++seed) {
        std::cerr << "noise " << noise << " px, seed " << seed << "/" << seeds << "\r" << std::flush;
        vpSelfCalibSimulator::Options so;
        so.seed = seed;
        so.pixel_noise_sd = noise;
        const vpSelfCalibSimulator sim(vpKinematicChain::preset(robot), so);
        const std::vector<vpColVector> q = sim.generateConfigurations(poses);
        const vpSelfCalibDataset ds = sim.makeDataset(q);
        const vpCameraParameters cam = sim.getCamera();
        const double f_true = cam.get_px();
        // Correspondences of view 0 with view k, by scene id.
        std::vector<std::vector<vpImagePoint>> p1, p2;
        std::vector<vpHomogeneousMatrix> truth;
        for (size_t k = 1; k < ds.views.size(); ++k) {
          std::map<int, vpImagePoint> second;
          for (const auto &o : ds.views[k].points)
            second[o.id] = o.ip;
          p1.emplace_back();
          p2.emplace_back();
          for (const auto &o : ds.views[0].points) {
            auto it = second.find(o.id);
            if (it != second.end()) {
              p1.back().push_back(o.ip);
              p2.back().push_back(it->second);
            }
          }
          truth.push_back(sim.getTrueChain().get_fMc(q[k]).inverse() * sim.getTrueChain().get_fMc(q[0]));
        }
        vpTwoViewEstimator::Options to;
        to.fx = fx_guess;
        to.u0 = cam.get_u0();
        to.v0 = cam.get_v0();
        auto record = [&](int method, size_t k, const vpHomogeneousMatrix *M, const std::string &status,
                          double f_err, double t) {
          MethodStats &s = m[method];
          ++s.pairs;
          double re = NAN, de = NAN;
          if (M) {
            re = rotationError(*M, truth[k]);
            de = directionError(*M, truth[k]);
            s.rot.add(re);
            s.dir.add(de);
            s.rot_ss += re * re;
          } else
            ++s.failures;
          if (std::isfinite(f_err))
            s.f.add(std::fabs(f_err));
          s.time.add(t);
          if (csv.enabled())
            csv.row() << noise << "," << seed << "," << tags[method] << "," << k + 2 << "," << status << ","
                      << re << "," << de << "," << f_err << "," << t << "\n";
        };
        // (a) and (c): one pair at a time.
        for (int method : {0, 2}) {
          vpTwoViewEstimator::Options o = to;
          o.focal_mode = method == 0 ? vpRefinedFactorMethod::PER_PAIR : vpRefinedFactorMethod::KNOWN;
          if (method == 2)
            o.fx = f_true;
          for (size_t k = 0; k < p1.size(); ++k) {
            const Clock::time_point t0 = Clock::now();
            const vpTwoViewEstimator::Result r = vpTwoViewEstimator::estimate(p1[k], p2[k], o);
            const double t = ms(t0, Clock::now());
            const bool ok = r.status == vpTwoViewEstimator::OK;
            record(method, k, ok ? &r.c2Mc1 : nullptr, vpTwoViewEstimator::statusName(r.status),
                   method == 0 && ok ? r.fx - f_true : NAN, t);
          }
        }
        // (b): all pairs at once; the time is shared equally.
        {
          const Clock::time_point t0 = Clock::now();
          const vpTwoViewEstimator::SharedResult r = vpTwoViewEstimator::estimateShared(p1, p2, to);
          const double t = ms(t0, Clock::now()) / p1.size();
          for (size_t k = 0; k < p1.size(); ++k) {
            const bool ok = r.converged && r.pairs[k].status == vpTwoViewEstimator::OK;
            record(1, k, ok ? &r.pairs[k].c2Mc1 : nullptr, vpTwoViewEstimator::statusName(r.pairs[k].status),
                   k == 0 && r.converged ? r.fx - f_true : NAN, t);
          }
          if (!r.converged)
            std::cerr << "\nseed " << seed << ": shared focal did not converge: " << r.message << "\n";
        }
        // (d): OpenCV with the true intrinsics.
        const cv::Mat K = (cv::Mat_<double>(3, 3) << f_true, 0, cam.get_u0(), 0, cam.get_py(), cam.get_v0(), 0, 0, 1);
        for (size_t k = 0; k < p1.size(); ++k) {
          std::vector<cv::Point2d> a, b;
          for (size_t i = 0; i < p1[k].size(); ++i) {
            a.emplace_back(p1[k][i].get_u(), p1[k][i].get_v());
            b.emplace_back(p2[k][i].get_u(), p2[k][i].get_v());
          }
          const Clock::time_point t0 = Clock::now();
          cv::Mat mask, R, t;
          const cv::Mat E = cv::findEssentialMat(a, b, K, cv::RANSAC, 0.999, 1.0, mask);
          const bool ok = E.rows >= 3 && cv::recoverPose(E(cv::Rect(0, 0, 3, 3)), a, b, K, R, t, mask) > 0;
          const double dt = ms(t0, Clock::now());
          vpHomogeneousMatrix M;
          if (ok)
            for (int i = 0; i < 3; ++i) {
              for (int j = 0; j < 3; ++j)
                M[i][j] = R.at<double>(i, j);
              M[i][3] = t.at<double>(i);
            }
          record(3, k, ok ? &M : nullptr, ok ? "ok" : "failed", NAN, dt);
        }
        // Cramer-Rao bounds on the same scenario.
        const Bound b = cramerRao(sim, q, noise);
        bound_f.add(b.f_sd);
        double ss = 0;
        for (double s : b.rotation_sd)
          ss += s * s;
        bound_rot_rms.add(std::sqrt(ss / b.rotation_sd.size()));
      }
      std::cerr << std::string(40, ' ') << "\r";
      std::cout << "\nnoise " << noise << " px (mean / SD over pairs and seeds; f of (b): one value per seed)\n";
      std::cout << "| method | pairs ok | rotation (mrad) | translation dir. (mrad) | abs. f error (px) | time / pair (ms) |\n"
                << "|---|---|---|---|---|---|\n";
      std::cout << std::fixed;
      for (int i = 0; i < 4; ++i) {
        const MethodStats &s = m[i];
        std::cout << "| " << names[i] << " | " << s.pairs - s.failures << "/" << s.pairs << " | " << std::setprecision(2)
                  << 1e3 * s.rot.mean() << " / " << 1e3 * s.rot.sd() << " | " << 1e3 * s.dir.mean() << " / "
                  << 1e3 * s.dir.sd() << " | ";
        if (s.f.count())
          std::cout << s.f.mean() << " / " << s.f.sd();
        else
          std::cout << "(known)";
        std::cout << " | " << s.time.mean() << " |\n";
      }
      std::cout << "Cramer-Rao bounds: RMS rotation error of a pair with f known " << std::setprecision(2)
                << 1e3 * bound_rot_rms.mean() << " mrad (RMS measured: (c) "
                << 1e3 * std::sqrt(m[2].rot_ss / std::max<size_t>(1, m[2].rot.count())) << ", (d) "
                << 1e3 * std::sqrt(m[3].rot_ss / std::max<size_t>(1, m[3].rot.count()))
                << "); sd of f from all " << poses << " views jointly " << bound_f.mean() << " px (mean over seeds)\n";
      // The targets, checked on these figures.
      const bool c_le_d = m[2].rot.mean() <= m[3].rot.mean() && m[2].rot.sd() <= m[3].rot.sd() &&
                          m[2].dir.mean() <= m[3].dir.mean() && m[2].dir.sd() <= m[3].dir.sd();
      std::cout << "targets: (c) <= (d) on every figure: " << (c_le_d ? "met" : "NOT met")
                << "; time < 5 ms per pair for (a)-(c): "
                << (std::max({m[0].time.mean(), m[1].time.mean(), m[2].time.mean()}) < 5 ? "met" : "NOT met");
      if (std::fabs(noise - 0.2) < 1e-12)
        std::cout << "; (b) mean f error < 1 px: " << (m[1].f.mean() < 1 ? "met" : "NOT met");
      std::cout << "\n" << std::defaultfloat;
    }
    return EXIT_SUCCESS;
  } catch (const vpException &e) {
    std::cerr << "bench-twoview: " << e.getMessage() << "\n";
    return EXIT_FAILURE;
  } catch (const std::exception &e) {
    std::cerr << "bench-twoview: " << e.what() << "\n";
    return EXIT_FAILURE;
  }
}
