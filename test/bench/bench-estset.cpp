/*
 * bench-estset: the estimated set from what the data determine, on arms one of whose joints barely
 * moves (the real Franka set's joint 3 moves 0.51 deg while the others move 51-122 deg).
 *
 *   bench-estset [--seeds N] [--draws K] [--stable D] [--stable-geometries G] [--robots panda,puma560]
 *                [--views 12,25] [--noise 0.2,0.5] [--focal known,shared] [--kinematic-prior K|off]
 *                [--alternatives BOOL] [--tables main,add] [--csv FILE]
 *
 * Per robot (its stuck joint: the Panda's j3, a 6-axis arm's wrist j5), number of calibration views,
 * focal mode, noise level and seed: a true robot with seeded errors (vpSelfCalibSimulator, 80 points
 * and a yardstick), V calibration and 10 held-out configurations drawn around the home with the stuck
 * joint within +-0.5 deg of it and every scene point in view (each draw aimed at the scene by a few
 * Gauss-Newton steps on the other joints), the default pipeline (method bundle, the pixel sd stated,
 * calibrate's kinematic prior unless --kinematic-prior says otherwise) on K + 1 noise draws, the joint
 * readings trusted (calibrate --joint-sd 0: the simulated robot has no reading error). Per row:
 *   ok / doubtful / failed  the run's status (the pipeline's checks; failed: no model);
 *   not determined          the parameters the data do not determine (cause DATA): left at nominal by
 *                           the set rule (--kinematic-prior off), held by the prior with it; the most
 *                           frequent list;
 *   sets over the seeds     the number of different lists over the runs of the row (seeds are different
 *                           geometries; the same-set check below is the one of a geometry);
 *   nominal / calibrated    the held-out relative position error (c_0 M c_k, first held-out view to the
 *                           others) of the nominal and the calibrated model, RMS over the runs, and the
 *                           worst run's ratio calibrated / nominal (below 1: better in every run);
 *   gain                    the mean over the runs of nominal / calibrated;
 *   CRB RMS                 the RMS error the Cramer-Rao bound of the set estimated predicts;
 *   set's bias RMS          the held-out error of the noise-free fit with the run's set (the
 *                           parameters left at nominal held there, the others fitted to the true
 *                           images; with the prior, its pull toward nominal): what leaving them (or
 *                           the prior's pull) costs, which the bound does not hold;
 *   gain the bound allows   nominal RMS / CRB RMS: what an efficient estimator of that set gains;
 *   CRB ratio               RMS error / the RMS the Cramer-Rao bound of the set estimated predicts
 *                           (vpKinematicBundleAdjustment::information at the truth with that set,
 *                           propagated by relativePoseCovariance): 1 is efficient; the parameters
 *                           left at nominal keep their true error, a bias the bound does not hold;
 *   ratio to CRB + bias     RMS error / sqrt(CRB^2 + bias^2): 1 when the bound and the set's bias
 *                           together account for the error.
 * A doubtful run prints its doubts and, against the truth, its estimated parameter farthest from the
 * noise-free fit of its set (in its sd: the estimator's own error) and from the true robot.
 * Then, on the same runs, what other estimators of the same data would give (Alternatives below: the
 * expected held-out error to first order at the truth, the set's own reproducing its CRB + bias): the
 * oracle set (the parameters to leave at nominal chosen knowing the truth: the floor of any set rule,
 * which no rule reaches without the truth), the full set (everything the data separate at all: no
 * bias, more variance; also run), the expected-risk set (a rule from what a user has: each parameter
 * left when the bias its tolerance implies costs the calibration views less than its variance), every
 * parameter estimated with the prior (p - nominal) / tolerance and / (tolerance / 3), and the Bayes
 * estimator (the prior the simulated errors' own sd: no estimator, whatever it is told, has a lower
 * expected error over robots drawn so). The targets column says "beyond the bound" where the Bayes
 * estimator's gain is short of the target, "beyond the tolerances' bound" where it is not but every
 * estimator from what a user states (data, nominal model, tolerances) is.
 * With the kinematic prior (calibrate's default, or --kinematic-prior K: every candidate estimated,
 * each correction's prior sd its tolerance / K), the same runs calibrated again with the set rule
 * (calibrate --kinematic-prior off) and a table of the prior beside it: held-out error, worst ratio,
 * gain, and ratio to the bound (the prior's: the posterior covariance at the truth, the prior's
 * information included); the alternatives compare the set rule's set. --kinematic-prior off: the
 * main table is the set rule's, no prior table. --alternatives false leaves out the first-order
 * table (and its full-set runs).
 * Then the same-set check: per robot and noise level, D draws of each of G geometries (12 views, f
 * known): the geometries whose D draws all leave the same list at nominal.
 * Then (--tables add) the poses to add: per robot and seed (12 views, 0.2 px, f known), calibrate, the
 * poses vpMeasurementPlanner::planAdditions proposes (as plan --from: as many as determine what was
 * left), the true robot's views at them with the same noise, calibrate again: what is left before and
 * after, the poses added, the held-out error before and after on held-out views of two kinds: A with the
 * stuck joint within +-0.5 deg (as the calibration views: the parameters left have almost no effect
 * there), B with it moving +-0.5 rad as the others (what a model of the whole workspace is for). The
 * views kept keep their noise (a user adds the poses to the data taken: a paired comparison); the
 * expected error on B before and after (each set's CRB plus its bias, at the truth).
 * Target: nothing left after and a lower held-out error on B in every run ("met in expectation": lower
 * expected error in every run, a realized one not lower in some: the draw, not the estimator).
 * Targets (f known): ok in every run, the calibrated error below the nominal one in every run, gain
 * >= 3 with 12 views and >= 5 with 25, CRB ratio <= 1.3, one set per geometry. The f self-calibrated
 * rows are measured, not claimed (with 12 views f itself limits the gain).
 */
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <iomanip>
#include <iostream>
#include <map>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include <visp3/core/vpException.h>
#include <visp3/selfcalib/vpKinematicBundleAdjustment.h>
#include <visp3/selfcalib/vpMeasurementPlanner.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibDataCheck.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "benchCommon.h"
#include "benchPaper.h"
#include "selfcalibCli.h"
#include "testStuckJoint.h"

namespace
{
constexpr unsigned int kHeldOut = 10;
constexpr int kLinearDraws = 200; //!< noise draws of the first-order model per run (the alternatives' mean gain)
using selfcalib_test::configurations;
using selfcalib_test::home;
using selfcalib_test::kStuck;
using selfcalib_test::makeStuckSim;
using selfcalib_test::stuckJoint;

vpSelfCalibDataset noisy(const vpSelfCalibDataset &ds0, double noise, uint64_t seed)
{
  vpSelfCalibDataset dd = ds0;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0, noise);
  for (auto &v : dd.views)
    for (auto &o : v.points)
      o.ip = vpImagePoint(o.ip.get_i() + n(rng), o.ip.get_j() + n(rng));
  return dd;
}

double g_tolerance_t = 3e-3, g_tolerance_r = 5e-3; // --tolerance
// --kinematic-prior: the main runs' kinematic prior (0: off, the set rule); empty: calibrate's default
// (vpKinematicBundleAdjustment::DEFAULT_KINEMATIC_PRIOR).
std::optional<double> g_prior;
bool g_alternatives = true;   // --alternatives: the other estimators' table (first order)

vpRobotSelfCalibration::Options optionsOf(vpRobotSelfCalibration::FocalMode mode, double noise, unsigned int views,
                                          const std::optional<double> &prior)
{
  vpRobotSelfCalibration::Options po;
  po.bundle.kinematic_prior = prior;
  po.tolerance_translation = g_tolerance_t;
  po.tolerance_rotation = g_tolerance_r;
  po.focal_mode = mode;
  po.num_calibration_poses = views;
  po.noise.pixel_sd = noise;
  // The robot's error: none simulated, the joint readings trusted (stated, not the CLI's default).
  po.noise.joint_sd.clear();
  po.noise.measure_joint_sd = po.noise.measure_model_sd = false;
  po.noise.model_sd_translation = po.noise.model_sd_rotation = 0;
  return po;
}

//! A run of the pipeline; prior: its kinematic prior (0: off, the set rule), by default the main runs' (g_prior).
vpRobotSelfCalibration::Result calibrate(const vpSelfCalibSimulator &sim, const vpSelfCalibDataset &ds,
                                         vpRobotSelfCalibration::FocalMode mode, double noise, unsigned int views,
                                         const std::optional<double> &prior = g_prior)
{
  return vpRobotSelfCalibration::run(sim.getNominalChain(), ds, optionsOf(mode, noise, views, prior));
}

//! The parameters the kinematic prior held (the data alone leave them at nominal), or "none".
std::string heldByPrior(const vpRobotSelfCalibration::Result &r)
{
  std::string s;
  for (const auto &u : r.identifiability.held_by_prior)
    s += (s.empty() ? "" : " ") + u.name;
  return s.empty() ? "none" : s;
}

/*
  The parameters the data do not determine, or "none": left at nominal (the set rule) or held by the
  kinematic prior (estimated, held near nominal), the same decision.
*/
std::string notDetermined(const vpRobotSelfCalibration::Result &r)
{
  std::string s;
  for (const auto &u : r.identifiability.unidentifiable)
    if (u.cause == vpKinematicIdentification::CAUSE_DATA)
      s += (s.empty() ? "" : " ") + u.name;
  for (const auto &u : r.identifiability.held_by_prior)
    s += (s.empty() ? "" : " ") + u.name;
  return s.empty() ? "none" : s;
}

double rms(const std::vector<double> &e)
{
  double s = 0;
  for (double x : e)
    s += x * x;
  return e.empty() ? NAN : std::sqrt(s / e.size());
}

struct Row {
  unsigned int ok = 0, doubtful = 0, failed = 0, runs = 0;
  std::map<std::string, unsigned int> sets;
  double sum_nominal2 = 0, sum_calibrated2 = 0, sum_bound2 = 0, worst = 0;
  unsigned int pairs = 0, bound_pairs = 0;
  bench::Stats gain;
  double sum_e2_bounded = 0, sum_bias2 = 0;
  // The other estimators (Alternatives): expected sums of squares, their pairs; the full set's run.
  double alt_today = 0, alt_oracle = 0, alt_full = 0, alt_map1 = 0, alt_map3 = 0, alt_bayes = 0, alt_risk = 0, alt_nominal2 = 0;
  double alt_prior_nominal = 0, alt_prior_bayes = 0, alt_prior_map3 = 0;
  unsigned int alt_pairs = 0;
  bench::Stats oracle_left, full_size, full_gain, risk_left;
  // Per run, the mean gain over the first-order model's noise draws: set, oracle set, full set, expected-risk
  // set, prior tolerance, /3, Bayes.
  bench::Stats alt_gain[7];
  double full_measured2 = 0, full_nominal2 = 0, full_worst = 0;
  unsigned int full_pairs = 0, full_failed = 0;
  // --kinematic-prior: the same runs with the prior (its posterior covariance the bound).
  unsigned int prior_ok = 0, prior_doubtful = 0, prior_failed = 0, prior_pairs = 0;
  std::map<std::string, unsigned int> prior_held;
  double prior_calibrated2 = 0, prior_nominal2 = 0, prior_bound2 = 0, prior_e2_bounded = 0, prior_worst = 0;
  bench::Stats prior_gain;
  // The set rule's run (--kinematic-prior off) on the runs the prior's row counts (both ok or doubtful):
  // its errors, worst ratio, gain and the Cramer-Rao bound of its set.
  double set_e2 = 0, set_worst = 0, set_e2_bounded = 0, set_bound2 = 0;
  bench::Stats set_gain;
  // Whether the reported sd cover the error: the held-out errors' sum of squares over the variances the
  // run's own covariance predicts (coverage()); the worst run's ratio; the ok runs whose ratio exceeds 2.
  double set_cov_e2 = 0, set_cov_var = 0, set_cov_worst = 0, prior_cov_e2 = 0, prior_cov_var = 0, prior_cov_worst = 0;
  unsigned int prior_ok_understated = 0, prior_contradicted = 0;
  // The largest factor a tolerance group's prior sd are off by (Result::prior_groups: sqrt(chi2 / redundancy)).
  bench::Stats prior_factor;
  // The workspace check against the truth (the camera's motions over the joint limits, the stuck joint within the
  // views' range): runs judged, doubtful by it, and of each kind those whose model is truly worse than nominal there;
  // sums of squares of the true and predicted errors, calibrated and nominal.
  unsigned int ws_runs = 0, ws_doubt = 0, ws_doubt_worse = 0, ws_pass = 0, ws_pass_worse = 0;
  double ws_true2 = 0, ws_pred2 = 0, ws_nom2 = 0, ws_nom_est2 = 0;
};

/*
  Whether a run's reported uncertainty covers its error: the variance of each held-out relative position
  (c_0 M c_k) its own covariance predicts (relativePoseCovariance, the estimated corrections), added to
  var; the squared errors e to e2. Returns the run's ratio sqrt(e2 / var) (1: the sd are right; above:
  they understate the error), NAN without a covariance.
*/
double coverage(const vpRobotSelfCalibration::Result &r, const std::vector<vpColVector> &held,
                const std::vector<double> &e, double &e2, double &var)
{
  if (!r.bundle.has_covariance)
    return NAN;
  double se = 0, sv = 0;
  for (size_t k = 1; k < held.size() && k - 1 < e.size(); ++k) {
    const vpMatrix C = vpKinematicBundleAdjustment::relativePoseCovariance(
        r.calibrated, r.bundle.identifiability.identified, r.bundle.covariance, held[0], held[k]);
    sv += C[0][0] + C[1][1] + C[2][2];
    se += e[k - 1] * e[k - 1];
  }
  e2 += se;
  var += sv;
  return sv > 0 ? std::sqrt(se / sv) : NAN;
}

//! The Cramer-Rao bound of the set r estimated, at the truth, propagated to the held-out pairs (sum of variances);
//! with r's kinematic prior, the posterior covariance.
bool boundOf(const vpSelfCalibSimulator &sim, const vpSelfCalibDataset &ds0, unsigned int views,
             const std::vector<vpColVector> &held, const vpRobotSelfCalibration::Result &r,
             vpRobotSelfCalibration::FocalMode mode, double noise, std::vector<double> &pred)
{
  const double prior = r.bundle.kinematic_prior; // the run's (0: none)
  vpKinematicBundleAdjustment::Options bo;
  bo.intrinsics = mode == vpRobotSelfCalibration::FOCAL_KNOWN ? 0u : vpKinematicBundleAdjustment::FX;
  bo.estimated_set = r.identifiability;
  // With the prior, the bound is the posterior covariance at the run's tolerances (the prior's sd).
  const vpRobotSelfCalibration::Options po = optionsOf(mode, noise, views, prior);
  bo.kinematic_prior = prior;
  bo.tolerance_translation = po.tolerance_translation;
  bo.tolerance_rotation = po.tolerance_rotation;
  bo.tolerance_hand_eye_translation = po.tolerance_hand_eye_translation;
  bo.tolerance_hand_eye_rotation = po.tolerance_hand_eye_rotation;
  vpSelfCalibNoiseModel bn;
  bn.pixel_sd = noise;
  const std::vector<vpSelfCalibDataset::View> cal(ds0.views.begin(), ds0.views.begin() + views);
  const auto crb = vpKinematicBundleAdjustment::information(sim.getTrueChain(), sim.getCamera(), cal, sim.getYardstick(),
                                                            sim.getScenePointsById(), bo, bn);
  if (!crb.has_covariance)
    return false;
  pred.clear();
  for (size_t k = 1; k < held.size(); ++k) {
    const vpMatrix C = vpKinematicBundleAdjustment::relativePoseCovariance(
        sim.getTrueChain(), crb.identifiability.identified, crb.covariance, held[0], held[k]);
    pred.push_back(C[0][0] + C[1][1] + C[2][2]);
  }
  return true;
}

/*
  The error the set itself costs: the bundle adjustment on the noise-free calibration views with the
  run's set (the parameters it left at nominal held there, the others fitted to the true images; the
  true points as start) and the run's kinematic prior (its pull toward nominal), the held-out
  position errors of that fit. The bound holds the noise part of
  a run's error; this is the rest (0 when nothing is left at nominal).
*/
std::vector<double> biasOf(const vpSelfCalibSimulator &sim, const vpSelfCalibDataset &ds0, unsigned int views,
                           const vpRobotSelfCalibration::Result &r, vpRobotSelfCalibration::FocalMode mode, double noise,
                           vpKinematicChain &limit)
{
  vpKinematicBundleAdjustment::Options bo;
  bo.intrinsics = mode == vpRobotSelfCalibration::FOCAL_KNOWN ? 0u : vpKinematicBundleAdjustment::FX;
  bo.estimated_set = r.identifiability;
  bo.covariance = false;
  // The run's prior (0: none) at the run's tolerances (the prior's sd).
  const vpRobotSelfCalibration::Options po = optionsOf(mode, noise, views, r.bundle.kinematic_prior);
  bo.kinematic_prior = r.bundle.kinematic_prior;
  bo.tolerance_translation = po.tolerance_translation;
  bo.tolerance_rotation = po.tolerance_rotation;
  bo.tolerance_hand_eye_translation = po.tolerance_hand_eye_translation;
  bo.tolerance_hand_eye_rotation = po.tolerance_hand_eye_rotation;
  vpSelfCalibNoiseModel bn;
  bn.pixel_sd = noise;
  const std::vector<vpSelfCalibDataset::View> cal(ds0.views.begin(), ds0.views.begin() + views);
  const auto fit = vpKinematicBundleAdjustment::adjust(sim.getNominalChain(), sim.getCamera(), cal, sim.getYardstick(),
                                                       sim.getScenePointsById(), bo, bn);
  if (fit.status != vpKinematicBundleAdjustment::OK)
    return {};
  limit = fit.chain;
  const std::vector<vpSelfCalibDataset::View> hv(ds0.views.begin() + views, ds0.views.end());
  return bench::verifyAgainstTruth(sim, fit.chain, fit.camera, hv).position_errors;
}

/*
  What other estimators of the same data give, to first order (the bound of each): F, the corrections
  the data determine at all (estimatedSet with the tolerances lifted: the separation test alone), at
  the nominal model; M, their information at the truth (the points and intrinsics eliminated:
  vpKinematicBundleAdjustment::information, inverted); x_F, the noise-free fit of F (the truth as F
  expresses it; its own held-out error r_k is what no estimator of F removes) and d = x_F - nominal;
  J_k, the Jacobian of the k-th held-out relative position at x_F (central differences). An estimator
  whose error x - x_F has mean b and covariance C has the expected squared held-out error
  sum_k |r_k + J_k b|^2 + tr(J_k C J_k^T):
   - a set E estimated, the rest L of F at nominal: b_E = M_EE^-1 M_EL d_L, b_L = -d_L, C = M_EE^-1;
   - the oracle set: the E of least expected error given the truth (greedy: from F dropping one at a
     time, and from the run's set adding or dropping one at a time, while it lowers; the best of the
     two): the floor of any rule that leaves parameters at nominal;
   - F itself: b = 0, C = M^-1 (the full set's bound: no bias, more variance);
   - every parameter of F estimated with the prior residual (p - nominal) / s: P = diag(1 / s^2),
     b = -(M + P)^-1 P d, C = (M + P)^-1 M (M + P)^-1 (the MAP estimate); s the tolerance given to
     calibrate (what a user states), and s the sd the simulated errors are drawn with (the Bayes
     estimator of this simulation: on average over robots drawn so, no estimator of these data has a
     smaller expected error; the bound of any estimator, whatever it is told).
  The full set is also run (the bundle adjustment with F, from the nominal model, on the run's noisy
  views): its measured error.
*/
struct Alternatives {
  bool ok = false;
  double today = 0, oracle = 0, full = 0, map1 = 0, map3 = 0, bayes = 0, risk_set = 0; // expected sums of squares
  // Expected over robots drawn with the simulated sd (the prior's own distribution): the nominal model, the
  // Bayes estimator (posterior covariance), the tolerance/3 prior (sums of squares over the pairs).
  double prior_nominal = 0, prior_bayes = 0, prior_map3 = 0;
  unsigned int pairs = 0, oracle_left = 0, full_size = 0, risk_left = 0;
  //! Mean gain over the noise's draws: set, oracle set, full set, expected-risk set, prior tolerance, /3, Bayes.
  double gain[7] = {NAN, NAN, NAN, NAN, NAN, NAN, NAN};
  std::vector<double> full_measured; // held-out position errors of the full set's run
};

using Mat = Eigen::MatrixXd;
using Vec = Eigen::VectorXd;

//! The held-out relative positions (c_0 M c_k).t of the chain, stacked.
Vec relativePositions(const vpKinematicChain &chain, const std::vector<vpColVector> &held)
{
  Vec t(3 * static_cast<Eigen::Index>(held.size() - 1));
  const vpHomogeneousMatrix c0Mf = chain.get_fMc(held[0]).inverse();
  for (size_t k = 1; k < held.size(); ++k) {
    const vpHomogeneousMatrix M = c0Mf * chain.get_fMc(held[k]);
    for (unsigned int a = 0; a < 3; ++a)
      t(3 * static_cast<Eigen::Index>(k - 1) + a) = M[a][3];
  }
  return t;
}

//! The Jacobian of relativePositions over the parameters F (central differences).
Mat positionJacobian(const vpKinematicChain &chain, const std::vector<unsigned int> &F, const std::vector<vpColVector> &q)
{
  const double h = 1e-6;
  const vpColVector x = chain.getParameters();
  Mat J(3 * static_cast<Eigen::Index>(q.size() - 1), static_cast<Eigen::Index>(F.size()));
  for (size_t i = 0; i < F.size(); ++i) {
    vpKinematicChain a = chain, b = chain;
    vpColVector pa = x, pb = x;
    pa[F[i]] += h;
    pb[F[i]] -= h;
    a.setParameters(pa);
    b.setParameters(pb);
    J.col(static_cast<Eigen::Index>(i)) = (relativePositions(a, q) - relativePositions(b, q)) / (2 * h);
  }
  return J;
}

struct Linear {
  Mat M, J;  // information over F, Jacobian of the stacked held-out positions over F
  Vec d, r;  // x_F - nominal over F; the noise-free fit's held-out position error
  //! Expected sum of squared held-out errors of an estimator with error mean b and covariance C.
  double mse(const Vec &b, const Mat &C) const
  {
    return (r + J * b).squaredNorm() + (J * C * J.transpose()).trace();
  }
  /*!
    The estimator of the set `est` (true: estimated), the rest L of F at nominal: its error's
    covariance C and its mean's response A to the errors d_L of the parameters left (b = A d_L).
  */
  void ofSet(const std::vector<bool> &est, std::vector<int> &l, Mat &A, Mat &C) const
  {
    std::vector<int> e;
    l.clear();
    for (int i = 0; i < static_cast<int>(est.size()); ++i)
      (est[i] ? e : l).push_back(i);
    A = Mat::Zero(d.size(), l.size());
    C = Mat::Zero(d.size(), d.size());
    for (size_t j = 0; j < l.size(); ++j)
      A(l[j], j) = -1;
    if (e.empty())
      return;
    Mat Mee(e.size(), e.size()), Mel(e.size(), l.size());
    for (size_t i = 0; i < e.size(); ++i) {
      for (size_t j = 0; j < e.size(); ++j)
        Mee(i, j) = M(e[i], e[j]);
      for (size_t j = 0; j < l.size(); ++j)
        Mel(i, j) = M(e[i], l[j]);
    }
    const Eigen::LDLT<Mat> ldlt(Mee);
    const Mat Cee = ldlt.solve(Mat::Identity(e.size(), e.size()));
    const Mat Ae = l.empty() ? Mat(e.size(), 0) : Mat(ldlt.solve(Mel));
    for (size_t i = 0; i < e.size(); ++i) {
      for (size_t j = 0; j < l.size(); ++j)
        A(e[i], j) = Ae(i, j);
      for (size_t j = 0; j < e.size(); ++j)
        C(e[i], e[j]) = Cee(i, j);
    }
  }
  //! The expected error of the set `est` given the truth (d); its error's mean b and covariance C.
  double ofSet(const std::vector<bool> &est, Vec &b, Mat &C) const
  {
    std::vector<int> l;
    Mat A;
    ofSet(est, l, A, C);
    Vec dl(l.size());
    for (size_t j = 0; j < l.size(); ++j)
      dl(j) = d(l[j]);
    b = A * dl;
    return mse(b, C);
  }
  double ofSet(const std::vector<bool> &est) const
  {
    Vec b;
    Mat C;
    return ofSet(est, b, C);
  }
  /*!
    The gain a run of an estimator of error b + K g (g ~ N(0, M): the noise's gradient) has, mean over
    the draws G (columns: g's draws): nominal / the RMS of the held-out errors r + J (b + K g), as the
    table's measured gain is (the mean of a ratio is above the ratio of the RMS).
  */
  double meanGain(const Vec &b, const Mat &K, const Mat &G, double nominal) const
  {
    const Mat E = (J * (K * G)).colwise() + (r + J * b);
    const double pairs = static_cast<double>(E.rows() / 3);
    double sum = 0;
    for (Eigen::Index c = 0; c < E.cols(); ++c)
      sum += nominal / std::sqrt(E.col(c).squaredNorm() / pairs);
    return sum / static_cast<double>(E.cols());
  }
  /*!
    The expected error of the set `est` over robots whose errors (over F) have the variances `var`,
    on the relative positions whose Jacobian is Jc (the calibration views': what a user has): the
    set rule that weighs each parameter's variance against the bias its tolerance implies.
  */
  double risk(const std::vector<bool> &est, const Mat &Jc, const Vec &var) const
  {
    std::vector<int> l;
    Mat A, C;
    ofSet(est, l, A, C);
    Vec vl(l.size());
    for (size_t j = 0; j < l.size(); ++j)
      vl(j) = var(l[j]);
    const Mat JA = Jc * A;
    return (Jc * C * Jc.transpose()).trace() + (JA * vl.asDiagonal() * JA.transpose()).trace();
  }
  //! Greedy descent over the sets from `est`: the single add or drop that lowers `cost` most, while one does.
  std::vector<bool> descend(std::vector<bool> est, const std::function<double(const std::vector<bool> &)> &cost) const
  {
    double best = cost(est);
    for (;;) {
      int flip = -1;
      double next = best;
      for (size_t i = 0; i < est.size(); ++i) {
        est[i] = !est[i];
        const double v = cost(est);
        est[i] = !est[i];
        if (v < next) {
          next = v;
          flip = static_cast<int>(i);
        }
      }
      if (flip < 0)
        break;
      est[flip] = !est[flip];
      best = next;
    }
    return est;
  }
  //! The MAP estimate with the prior precision P (diagonal); its error's mean b and response K to the noise.
  double map(const Vec &p, Vec &b, Mat &K) const
  {
    const Mat A = M + Mat(p.asDiagonal());
    K = A.ldlt().solve(Mat::Identity(A.rows(), A.cols()));
    b = -K * p.asDiagonal() * d;
    return mse(b, K * M * K);
  }
};

double toleranceOfParameter(unsigned int index, unsigned int joints, const vpKinematicBundleAdjustment::Options &o)
{
  const bool eMc = index / vpKinematicChain::kBlockSize == joints + 1, t = index % vpKinematicChain::kBlockSize < 3;
  return eMc ? (t ? o.tolerance_hand_eye_translation : o.tolerance_hand_eye_rotation)
             : (t ? o.tolerance_translation : o.tolerance_rotation);
}

//! The sd of the simulated robot's error of a parameter (vpSelfCalibSimulator's defaults, which makeStuckSim keeps).
double simulatedSd(unsigned int index, unsigned int joints)
{
  const vpSelfCalibSimulator::Options so;
  const unsigned int block = index / vpKinematicChain::kBlockSize;
  const bool t = index % vpKinematicChain::kBlockSize < 3;
  if (block == 0)
    return t ? so.base_translation_sd : so.base_rotation_sd;
  if (block == joints + 1)
    return t ? so.hand_eye_translation_sd : so.hand_eye_rotation_sd;
  return t ? so.joint_translation_sd : so.joint_rotation_sd;
}

Alternatives alternativesOf(const vpSelfCalibSimulator &sim, const vpSelfCalibDataset &ds0, const vpSelfCalibDataset &noisy_ds,
                            unsigned int views, const std::vector<vpColVector> &held,
                            const vpRobotSelfCalibration::Result &r, vpRobotSelfCalibration::FocalMode mode, double noise,
                            double nominal_rms, uint64_t seed)
{
  Alternatives out;
  vpKinematicBundleAdjustment::Options bo =
      vpRobotSelfCalibration::bundleOptions(optionsOf(mode, noise, views, vpKinematicBundleAdjustment::KINEMATIC_PRIOR_OFF), ds0);
  const vpKinematicBundleAdjustment::Options tol = bo;
  bo.estimated_set = vpKinematicIdentification::Identifiability();
  bo.tolerance_translation = bo.tolerance_rotation = bo.tolerance_hand_eye_translation = bo.tolerance_hand_eye_rotation = 1e9;
  bo.fixed.clear();
  bo.free.clear();
  vpSelfCalibNoiseModel bn;
  bn.pixel_sd = noise;
  const vpKinematicChain &nominal = sim.getNominalChain();
  const std::vector<vpSelfCalibDataset::View> cal(ds0.views.begin(), ds0.views.begin() + views);
  const auto points = sim.getScenePointsById();
  bo.estimated_set =
      vpKinematicBundleAdjustment::estimatedSet(nominal, sim.getCamera(), cal, sim.getYardstick(), points, bo, bn);
  const std::vector<unsigned int> F = bo.estimated_set.identified;
  const int n = static_cast<int>(F.size());
  out.full_size = F.size();
  // The full set run on the noisy views.
  bo.covariance = false;
  const std::vector<vpSelfCalibDataset::View> noisy_cal(noisy_ds.views.begin(), noisy_ds.views.begin() + views);
  const auto run = vpKinematicBundleAdjustment::adjust(nominal, sim.getCamera(), noisy_cal, sim.getYardstick(), points, bo, bn);
  if (run.status == vpKinematicBundleAdjustment::OK) {
    const std::vector<vpSelfCalibDataset::View> hv(ds0.views.begin() + views, ds0.views.end());
    out.full_measured = bench::verifyAgainstTruth(sim, run.chain, run.camera, hv).position_errors;
  }
  // x_F and its own held-out error.
  const auto fit = vpKinematicBundleAdjustment::adjust(nominal, sim.getCamera(), cal, sim.getYardstick(), points, bo, bn);
  bo.covariance = true;
  bo.scale_covariance = bo.scale_covariance_chi2 = false; // the bound: the stated noise, not the noise-free residuals
  const auto crb = vpKinematicBundleAdjustment::information(sim.getTrueChain(), sim.getCamera(), cal, sim.getYardstick(),
                                                            points, bo, bn);
  if (fit.status != vpKinematicBundleAdjustment::OK || !crb.has_covariance || n == 0)
    return out;
  Linear lin;
  Mat C(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      C(i, j) = crb.covariance[i][j];
  lin.M = C.ldlt().solve(Mat::Identity(n, n));
  lin.M = 0.5 * (lin.M + lin.M.transpose());
  const vpColVector xF = fit.chain.getParameters(), x0 = nominal.getParameters();
  lin.d.resize(n);
  for (int i = 0; i < n; ++i)
    lin.d(i) = xF[F[i]] - x0[F[i]];
  lin.r = relativePositions(fit.chain, held) - relativePositions(sim.getTrueChain(), held);
  lin.J = positionJacobian(fit.chain, F, held);
  // The noise's draws, common to the estimators: g = L z, L L^T = M.
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> z01(0, 1);
  Mat Z(n, kLinearDraws);
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < Z.cols(); ++c)
      Z(i, c) = z01(rng);
  const Mat G = Mat(lin.M.llt().matrixL()) * Z;
  Vec b;
  Mat K;
  std::vector<bool> today(n), all(n, true);
  for (int i = 0; i < n; ++i)
    today[i] = std::binary_search(r.identifiability.identified.begin(), r.identifiability.identified.end(), F[i]);
  out.today = lin.ofSet(today, b, K);
  out.gain[0] = lin.meanGain(b, K, G, nominal_rms);
  out.full = lin.ofSet(all, b, K);
  out.gain[2] = lin.meanGain(b, K, G, nominal_rms);
  auto given = [&](const std::vector<bool> &e) { return lin.ofSet(e); };
  const std::vector<bool> oa = lin.descend(all, given), ob = lin.descend(today, given);
  const std::vector<bool> &oracle = lin.ofSet(oa) <= lin.ofSet(ob) ? oa : ob;
  out.oracle = lin.ofSet(oracle, b, K);
  out.gain[1] = lin.meanGain(b, K, G, nominal_rms);
  out.oracle_left = static_cast<unsigned int>(std::count(oracle.begin(), oracle.end(), false));
  Vec p1(n), p3(n), pb(n);
  for (int i = 0; i < n; ++i) {
    const double t = toleranceOfParameter(F[i], nominal.getNumJoints(), tol);
    p1(i) = 1 / (t * t);
    p3(i) = 9 / (t * t);
    const double sd = simulatedSd(F[i], nominal.getNumJoints());
    pb(i) = 1 / (sd * sd);
  }
  out.map1 = lin.map(p1, b, K);
  out.gain[4] = lin.meanGain(b, K, G, nominal_rms);
  out.map3 = lin.map(p3, b, K);
  out.gain[5] = lin.meanGain(b, K, G, nominal_rms);
  out.bayes = lin.map(pb, b, K);
  out.gain[6] = lin.meanGain(b, K, G, nominal_rms);
  // Over robots drawn with the simulated sd (d ~ N(0, Pb^-1)), not at this run's truth: the nominal model's
  // expected error, the Bayes estimator's (its posterior covariance) and the tolerance/3 prior's.
  const Mat Pb_inv = Mat(pb.cwiseInverse().asDiagonal());
  out.prior_nominal = (lin.J * Pb_inv * lin.J.transpose()).trace();
  out.prior_bayes = (lin.J * K * lin.J.transpose()).trace();
  {
    Vec b3;
    Mat K3;
    lin.map(p3, b3, K3);
    const Mat B = K3 * Mat(p3.asDiagonal());
    out.prior_map3 = (lin.J * (B * Pb_inv * B.transpose() + K3 * lin.M * K3) * lin.J.transpose()).trace();
  }
  // The expected-risk set rule: the calibration views' relative positions, the tolerance as 3 sd.
  const std::vector<vpColVector> qc = [&] {
    std::vector<vpColVector> v;
    for (const auto &view : cal)
      v.push_back(view.q);
    return v;
  }();
  const Mat Jc = positionJacobian(fit.chain, F, qc);
  const Vec var = p3.cwiseInverse();
  const std::vector<bool> rs = lin.descend(today, [&](const std::vector<bool> &e) { return lin.risk(e, Jc, var); });
  out.risk_set = lin.ofSet(rs, b, K);
  out.gain[3] = lin.meanGain(b, K, G, nominal_rms);
  out.risk_left = static_cast<unsigned int>(std::count(rs.begin(), rs.end(), false));
  out.pairs = static_cast<unsigned int>(held.size() - 1);
  out.ok = true;
  return out;
}

/*
  A doubtful run against the truth: the estimated parameter farthest from the noise-free fit of the
  same set (the estimator's own error, in its sd: a doubt about the estimate is right when it is
  large) and the one farthest from the true robot (which the set's bias adds to).
*/
std::string againstTruth(const vpSelfCalibSimulator &sim, const vpKinematicChain &limit,
                         const vpRobotSelfCalibration::Result &r)
{
  const vpColVector &est = r.calibrated.getParameters(), &lim = limit.getParameters(),
                    &tru = sim.getTrueChain().getParameters();
  const std::vector<std::string> names = r.calibrated.getParameterNames();
  double z_lim = 0, z_true = 0;
  std::string n_lim, n_true;
  for (unsigned int i : r.identifiability.identified) {
    const double sd = i < r.parameter_sd.size() ? r.parameter_sd[i] : 0;
    if (!(sd > 0))
      continue;
    const double a = std::fabs(est[i] - lim[i]) / sd, b = std::fabs(est[i] - tru[i]) / sd;
    if (a > z_lim) {
      z_lim = a;
      n_lim = names[i];
    }
    if (b > z_true) {
      z_true = b;
      n_true = names[i];
    }
  }
  std::ostringstream os;
  os << std::setprecision(2) << "worst |estimate - noise-free fit| / sd " << z_lim << " (" << n_lim
     << "), worst |estimate - truth| / sd " << z_true << " (" << n_true << ")";
  return os.str();
}

/*
  A main run r with the kinematic prior (held-out errors e) beside the set rule (calibrate
  --kinematic-prior off) on the same noisy views: the prior's held-out error, gain, ratio to its bound
  (the posterior covariance at the truth, the prior's information included), whether its sd cover the
  error and whether the data agree with the prior; the set rule's error, worst ratio, gain, ratio to
  the bound of its set and coverage. Returns the set rule's run (its set is the alternatives' "set").
*/
vpRobotSelfCalibration::Result compareWithSetRule(const vpSelfCalibSimulator &clean, const vpSelfCalibDataset &ds0,
                                                  const vpSelfCalibDataset &ds, const std::vector<vpColVector> &held,
                                                  unsigned int views, vpRobotSelfCalibration::FocalMode mode, double noise,
                                                  const std::vector<double> &nominal_errors,
                                                  const vpRobotSelfCalibration::Result &r, const std::vector<double> &e,
                                                  Row &row, const std::string &tag)
{
  (r.status == vpRobotSelfCalibration::OK ? row.prior_ok : row.prior_doubtful)++;
  ++row.prior_held[heldByPrior(r)];
  const double e_nom = rms(nominal_errors);
  row.prior_worst = std::max(row.prior_worst, rms(e) / e_nom);
  row.prior_gain.add(e_nom / rms(e));
  const double cover = coverage(r, held, e, row.prior_cov_e2, row.prior_cov_var);
  if (std::isfinite(cover)) {
    row.prior_cov_worst = std::max(row.prior_cov_worst, cover);
    row.prior_ok_understated += r.status == vpRobotSelfCalibration::OK && cover > 2;
  }
  // The prior against the data: the largest factor a group's sd are off by, the runs where one exceeds its quantile.
  double factor = 0;
  bool contradicted = false;
  for (const auto &g : r.bundle.prior_groups)
    if (g.redundancy >= 1)
      factor = std::max(factor, std::sqrt(g.chi2 / g.redundancy));
  for (const auto &f : r.findings)
    contradicted = contradicted || f.code == "kinematic-prior-contradicted";
  if (factor > 0)
    row.prior_factor.add(factor);
  row.prior_contradicted += contradicted;
  // The set rule on the same views.
  const auto s = calibrate(clean, ds, mode, noise, views, vpKinematicBundleAdjustment::KINEMATIC_PRIOR_OFF);
  if (s.status != vpRobotSelfCalibration::OK && s.status != vpRobotSelfCalibration::DOUBTFUL) {
    std::cerr << "\n" << tag << ": the set rule: " << vpRobotSelfCalibration::statusName(s.status) << ": " << s.message
              << "\n";
    return s;
  }
  const std::vector<vpSelfCalibDataset::View> hv(ds0.views.begin() + views, ds0.views.end());
  const std::vector<double> se = bench::verifyAgainstTruth(clean, s.calibrated, s.camera, hv).position_errors;
  row.set_worst = std::max(row.set_worst, rms(se) / e_nom);
  row.set_gain.add(e_nom / rms(se));
  const double set_cover = coverage(s, held, se, row.set_cov_e2, row.set_cov_var);
  if (std::isfinite(set_cover))
    row.set_cov_worst = std::max(row.set_cov_worst, set_cover);
  std::vector<double> pred, set_pred;
  const bool bound = boundOf(clean, ds0, views, held, r, mode, noise, pred);
  const bool set_bound = boundOf(clean, ds0, views, held, s, mode, noise, set_pred);
  for (size_t k = 0; k < e.size() && k < nominal_errors.size() && k < se.size(); ++k) {
    row.prior_calibrated2 += e[k] * e[k];
    row.prior_nominal2 += nominal_errors[k] * nominal_errors[k];
    row.set_e2 += se[k] * se[k];
    ++row.prior_pairs;
    if (bound && k < pred.size()) {
      row.prior_bound2 += pred[k];
      row.prior_e2_bounded += e[k] * e[k];
    }
    if (set_bound && k < set_pred.size()) {
      row.set_bound2 += set_pred[k];
      row.set_e2_bounded += se[k] * se[k];
    }
  }
  return s;
}

//! --kinematic-prior's value: off or 0: 0 (the set rule); tolerance 1; tolerance/K or K (above 0); empty when not one.
std::optional<double> priorOf(const std::string &v)
{
  if (v == "off" || v == "0")
    return vpKinematicBundleAdjustment::KINEMATIC_PRIOR_OFF;
  const std::string k = v == "tolerance" ? "1" : v.rfind("tolerance/", 0) == 0 ? v.substr(10) : v;
  char *end = nullptr;
  const double d = std::strtod(k.c_str(), &end);
  if (k.empty() || end != k.c_str() + k.size() || !std::isfinite(d) || !(d > 0))
    return std::nullopt;
  return d;
}

//! The main runs' kinematic prior (0: none): --kinematic-prior, else calibrate's default.
double mainPrior() { return g_prior ? *g_prior : vpKinematicBundleAdjustment::DEFAULT_KINEMATIC_PRIOR; }

void runOnce(const vpSelfCalibSimulator &clean, const vpSelfCalibDataset &ds0, const std::vector<vpColVector> &held,
             unsigned int views, vpRobotSelfCalibration::FocalMode mode, double noise, uint64_t draw_seed,
             const std::vector<double> &nominal_errors, Row &row, bench::Csv &csv, const std::string &tag)
{
  const vpSelfCalibDataset ds = noisy(ds0, noise, draw_seed);
  const auto r = calibrate(clean, ds, mode, noise, views);
  ++row.runs;
  if (r.status != vpRobotSelfCalibration::OK && r.status != vpRobotSelfCalibration::DOUBTFUL) {
    ++row.failed;
    row.prior_failed += mainPrior() > 0;
    std::cerr << "\n" << tag << ": " << vpRobotSelfCalibration::statusName(r.status) << ": " << r.message << "\n";
    return;
  }
  (r.status == vpRobotSelfCalibration::OK ? row.ok : row.doubtful)++;
  if (r.status == vpRobotSelfCalibration::DOUBTFUL)
    for (const auto &f : r.findings)
      if (f.severity == vpSelfCalibDataCheck::DOUBT)
        std::cerr << "\n" << tag << ": doubtful: " << f.code << ": " << f.message << "\n";
  ++row.sets[notDetermined(r)];
  const std::vector<vpSelfCalibDataset::View> hv(ds0.views.begin() + views, ds0.views.end());
  const vpCalibrationVerifier::Result v = bench::verifyAgainstTruth(clean, r.calibrated, r.camera, hv);
  const double e_cal = rms(v.position_errors), e_nom = rms(nominal_errors);
  row.worst = std::max(row.worst, e_cal / e_nom);
  row.gain.add(e_nom / e_cal);
  for (size_t k = 0; k < v.position_errors.size(); ++k) {
    row.sum_calibrated2 += v.position_errors[k] * v.position_errors[k];
    row.sum_nominal2 += nominal_errors[k] * nominal_errors[k];
    ++row.pairs;
  }
  std::vector<double> pred;
  double run_bound2 = 0, run_bias2 = 0;
  unsigned int run_pairs = 0;
  if (boundOf(clean, ds0, views, held, r, mode, noise, pred)) {
    vpKinematicChain limit = clean.getNominalChain();
    const std::vector<double> bias = biasOf(clean, ds0, views, r, mode, noise, limit);
    if (r.status == vpRobotSelfCalibration::DOUBTFUL)
      std::cerr << "\n" << tag << ": doubtful: " << againstTruth(clean, limit, r) << "\n";
    for (size_t k = 0; k < pred.size() && k < v.position_errors.size() && k < bias.size(); ++k) {
      run_bound2 += pred[k];
      run_bias2 += bias[k] * bias[k];
      row.sum_e2_bounded += v.position_errors[k] * v.position_errors[k];
      ++run_pairs;
    }
  }
  // With the prior, the set rule beside it; the alternatives compare the set rule's set (its run's when it has one).
  const bool with_prior = r.bundle.kinematic_prior > 0;
  const vpRobotSelfCalibration::Result set_rule =
      with_prior ? compareWithSetRule(clean, ds0, ds, held, views, mode, noise, nominal_errors, r, v.position_errors, row, tag)
                 : r;
  const bool set_ok = set_rule.status == vpRobotSelfCalibration::OK || set_rule.status == vpRobotSelfCalibration::DOUBTFUL;
  const Alternatives alt = g_alternatives && set_ok
                               ? alternativesOf(clean, ds0, ds, views, held, set_rule, mode, noise, e_nom, draw_seed)
                               : Alternatives();
  if (alt.ok) {
    row.alt_today += alt.today;
    row.alt_oracle += alt.oracle;
    row.alt_full += alt.full;
    row.alt_map1 += alt.map1;
    row.alt_bayes += alt.bayes;
    row.alt_map3 += alt.map3;
    row.alt_risk += alt.risk_set;
    row.alt_prior_nominal += alt.prior_nominal;
    row.alt_prior_bayes += alt.prior_bayes;
    row.alt_prior_map3 += alt.prior_map3;
    row.risk_left.add(alt.risk_left);
    for (int a = 0; a < 7; ++a)
      row.alt_gain[a].add(alt.gain[a]);
    row.alt_pairs += alt.pairs;
    for (size_t k = 0; k < alt.pairs && k < nominal_errors.size(); ++k)
      row.alt_nominal2 += nominal_errors[k] * nominal_errors[k];
    row.oracle_left.add(alt.oracle_left);
    row.full_size.add(alt.full_size);
  }
  if (alt.full_measured.size() == nominal_errors.size()) {
    for (size_t k = 0; k < nominal_errors.size(); ++k) {
      row.full_measured2 += alt.full_measured[k] * alt.full_measured[k];
      row.full_nominal2 += nominal_errors[k] * nominal_errors[k];
      ++row.full_pairs;
    }
    row.full_gain.add(e_nom / rms(alt.full_measured));
    row.full_worst = std::max(row.full_worst, rms(alt.full_measured) / e_nom);
  } else
    ++row.full_failed;
  row.sum_bound2 += run_bound2;
  row.sum_bias2 += run_bias2;
  row.bound_pairs += run_pairs;
  const std::string doubts = bench::doubtCodes(r);
  const double ws_cal = bench::workspaceError(r.calibrated, clean.getTrueChain(), r.workspace.joints_within).t,
               ws_nom = bench::workspaceError(clean.getNominalChain(), clean.getTrueChain(), r.workspace.joints_within).t;
  if (r.workspace.computed) {
    const bool doubt = bench::hasFinding(r, "workspace-worse-than-nominal");
    ++row.ws_runs;
    (doubt ? row.ws_doubt : row.ws_pass)++;
    (doubt ? row.ws_doubt_worse : row.ws_pass_worse) += ws_cal > ws_nom;
    row.ws_true2 += ws_cal * ws_cal;
    row.ws_pred2 += r.workspace.calibrated_t * r.workspace.calibrated_t;
    row.ws_nom2 += ws_nom * ws_nom;
    row.ws_nom_est2 += r.workspace.nominal_t * r.workspace.nominal_t;
  }
  if (csv.enabled())
    csv.row() << tag << "," << vpRobotSelfCalibration::statusName(r.status) << "," << e_nom << "," << e_cal << ","
              << std::sqrt(run_bound2 / std::max(1u, run_pairs)) << "," << std::sqrt(run_bias2 / std::max(1u, run_pairs))
              << ",\"" << notDetermined(r) << "\",\"" << doubts << "\"," << r.predicted_rms << "," << r.fit_nominal_rms;
  if (csv.enabled()) {
    const double np = std::max(1u, alt.pairs);
    csv.row() << "," << alt.full_size << "," << std::sqrt(alt.today / np) << "," << std::sqrt(alt.oracle / np) << ","
              << alt.oracle_left << "," << std::sqrt(alt.full / np) << "," << rms(alt.full_measured) << ","
              << std::sqrt(alt.map1 / np) << "," << std::sqrt(alt.map3 / np) << "," << std::sqrt(alt.bayes / np) << ","
              << std::sqrt(alt.risk_set / np) << "," << alt.risk_left << ","
              << bench::workspaceError(r.calibrated, clean.getTrueChain()).t << ","
              << bench::workspaceError(clean.getNominalChain(), clean.getTrueChain()).t << "," << r.workspace.calibrated_t << ","
              << r.workspace.bound_t << "," << r.workspace.nominal_t << "," << r.workspace.worse_t << ","
              << ws_cal << "," << ws_nom << "\n";
  }
}

//! The poses to add table: one run per seed, before and after the poses plan --from proposes.
struct AddRow {
  unsigned int runs = 0, failed = 0, left_before = 0, left_after = 0, better = 0;
  std::map<std::string, unsigned int> before;
  bench::Stats added, gain_before, gain_after;
  double sum_nominal2 = 0, sum_before2 = 0, sum_after2 = 0;
  unsigned int pairs = 0;
  // The held-out views where the stuck joint moves too (+-0.5 rad, as the others).
  bench::Stats wide_gain_before, wide_gain_after;
  double wide_nominal2 = 0, wide_before2 = 0, wide_after2 = 0;
  unsigned int wide_pairs = 0;
  // Expected on B (the bound of each set plus its bias, at the truth): sums of squares; the runs whose
  // expected error after the poses is below the one before (where "better in every run" is possible).
  double expected_before2 = 0, expected_after2 = 0;
  unsigned int expected_pairs = 0, expected_better = 0;
};

/*
  The held-out error on the views qb a calibration of the set of r on the views q (f known) is
  expected to have at the truth: the set's Cramer-Rao bound plus its bias (boundOf, biasOf), the sum
  of squares over the pairs (NAN when the bound is not finite).
*/
double expectedOn(const vpSelfCalibSimulator &sim, const std::vector<vpColVector> &q, const std::vector<vpColVector> &qb,
                  const vpRobotSelfCalibration::Result &r, double noise, unsigned int &pairs)
{
  std::vector<vpColVector> all = q;
  all.insert(all.end(), qb.begin(), qb.end());
  const vpRobotSelfCalibration::FocalMode mode = vpRobotSelfCalibration::FOCAL_KNOWN;
  const vpSelfCalibDataset ds0 = bench::pipelineDataset(sim, all, mode);
  const unsigned int views = static_cast<unsigned int>(q.size());
  std::vector<double> pred;
  if (!boundOf(sim, ds0, views, qb, r, mode, noise, pred))
    return NAN;
  vpKinematicChain limit = sim.getNominalChain();
  const std::vector<double> bias = biasOf(sim, ds0, views, r, mode, noise, limit);
  double sum = 0;
  pairs = 0;
  for (size_t k = 0; k < pred.size() && k < bias.size(); ++k, ++pairs)
    sum += pred[k] + bias[k] * bias[k];
  return pairs ? sum : NAN;
}

//! Sums of squares of the held-out errors of the nominal model and of the two calibrations.
void addErrors(const std::vector<double> &e_nom, const std::vector<double> &e1, const std::vector<double> &e2,
               double &nominal2, double &before2, double &after2, unsigned int &pairs)
{
  for (size_t k = 0; k < e_nom.size() && k < e1.size() && k < e2.size(); ++k) {
    nominal2 += e_nom[k] * e_nom[k];
    before2 += e1[k] * e1[k];
    after2 += e2[k] * e2[k];
    ++pairs;
  }
}

/*
  One geometry (12 views, f known, the stuck joint): calibrate, plan the poses to add
  (vpMeasurementPlanner::planAdditions on the calibration, as plan --from), simulate the true
  robot's observations at them (the same noise), calibrate again on the views and the added poses;
  the held-out error of both against the nominal model's.
*/
void addPosesRun(const std::string &robot, unsigned int seed, double noise, unsigned int views, AddRow &row)
{
  const vpSelfCalibSimulator clean = makeStuckSim(robot, seed);
  const unsigned int stuck = stuckJoint(robot);
  const std::vector<vpColVector> q = configurations(clean, home(robot, clean.getNominalChain()), stuck, views + kHeldOut, seed);
  const vpRobotSelfCalibration::FocalMode mode = vpRobotSelfCalibration::FOCAL_KNOWN;
  const vpSelfCalibDataset ds1 = noisy(bench::pipelineDataset(clean, q, mode), noise, 1000003ULL * seed);
  const auto r1 = calibrate(clean, ds1, mode, noise, views);
  ++row.runs;
  if (r1.status != vpRobotSelfCalibration::OK && r1.status != vpRobotSelfCalibration::DOUBTFUL) {
    ++row.failed;
    return;
  }
  const std::vector<vpSelfCalibDataset::View> cal(ds1.views.begin(), ds1.views.begin() + views);
  vpPlannerScene scene;
  for (const auto &p : r1.bundle.points)
    scene.points.push_back(p.second);
  scene.cam = r1.camera;
  scene.width = ds1.width;
  scene.height = ds1.height;
  vpMeasurementPlanner::AdditionOptions ao;
  ao.seed = seed;
  for (const auto &u : r1.identifiability.unidentifiable)
    if (u.cause == vpKinematicIdentification::CAUSE_DATA)
      ao.left.push_back(u.name);
  for (const auto &u : r1.identifiability.held_by_prior) // as plan --from: what the prior holds, the data do not determine
    ao.left.push_back(u.name);
  const auto plan = vpMeasurementPlanner(clean.getNominalChain(), scene)
                        .planAdditions(cal, r1.camera, r1.bundle.points, ds1.yardstick,
                                       vpRobotSelfCalibration::bundleOptions(optionsOf(mode, noise, views, g_prior), ds1), r1.noise, ao);
  if (plan.status != vpMeasurementPlanner::OK)
    std::cerr << "\n" << robot << ", seed " << seed << ": planAdditions " << vpMeasurementPlanner::statusName(plan.status)
              << ": " << plan.message << "\n";
  std::vector<vpColVector> q2(q.begin(), q.begin() + views);
  for (const auto &a : plan.additions)
    q2.push_back(a.q);
  q2.insert(q2.end(), q.begin() + views, q.end());
  const unsigned int views2 = views + static_cast<unsigned int>(plan.additions.size());
  // The views kept keep their noise (the same stream: the same draws on the same first views): what a
  // user adds the poses to is the data already taken, so the comparison is paired.
  const vpSelfCalibDataset ds2 = noisy(bench::pipelineDataset(clean, q2, mode), noise, 1000003ULL * seed);
  for (unsigned int k = 0; k < views; ++k)
    for (size_t i = 0; i < ds2.views[k].points.size(); ++i)
      if (ds2.views[k].points[i].ip != ds1.views[k].points[i].ip)
        throw vpException(vpException::fatalError, "bench-estset: the views kept lost their noise draws");
  const auto r2 = calibrate(clean, ds2, mode, noise, views2);
  if (r2.status != vpRobotSelfCalibration::OK && r2.status != vpRobotSelfCalibration::DOUBTFUL) {
    ++row.failed;
    return;
  }
  row.added.add(static_cast<double>(plan.additions.size()));
  ++row.before[notDetermined(r1)];
  row.left_before += notDetermined(r1) != "none";
  row.left_after += notDetermined(r2) != "none";
  const std::vector<vpSelfCalibDataset::View> hv(ds1.views.begin() + views, ds1.views.end());
  const std::vector<double> e_nom =
      bench::verifyAgainstTruth(clean, clean.getNominalChain(), clean.getCamera(), hv).position_errors;
  const std::vector<double> e1 = bench::verifyAgainstTruth(clean, r1.calibrated, r1.camera, hv).position_errors;
  const std::vector<double> e2 = bench::verifyAgainstTruth(clean, r2.calibrated, r2.camera, hv).position_errors;
  row.gain_before.add(rms(e_nom) / rms(e1));
  row.gain_after.add(rms(e_nom) / rms(e2));
  addErrors(e_nom, e1, e2, row.sum_nominal2, row.sum_before2, row.sum_after2, row.pairs);
  const std::vector<vpColVector> qw =
      configurations(clean, home(robot, clean.getNominalChain()), stuck, kHeldOut, seed + 5000, 0.5);
  const vpSelfCalibDataset dw = bench::pipelineDataset(clean, qw, mode);
  const std::vector<double> w_nom =
      bench::verifyAgainstTruth(clean, clean.getNominalChain(), clean.getCamera(), dw.views).position_errors;
  const std::vector<double> w1 = bench::verifyAgainstTruth(clean, r1.calibrated, r1.camera, dw.views).position_errors;
  const std::vector<double> w2 = bench::verifyAgainstTruth(clean, r2.calibrated, r2.camera, dw.views).position_errors;
  row.wide_gain_before.add(rms(w_nom) / rms(w1));
  row.wide_gain_after.add(rms(w_nom) / rms(w2));
  row.better += rms(w2) < rms(w1);
  unsigned int pb = 0, pa = 0;
  const double xb = expectedOn(clean, std::vector<vpColVector>(q.begin(), q.begin() + views), qw, r1, noise, pb);
  const double xa = expectedOn(clean, std::vector<vpColVector>(q2.begin(), q2.begin() + views2), qw, r2, noise, pa);
  if (std::isfinite(xb) && std::isfinite(xa) && pa == pb) {
    row.expected_before2 += xb;
    row.expected_after2 += xa;
    row.expected_pairs += pb;
    row.expected_better += xa < xb;
  }
  if (!(rms(w2) < rms(w1)))
    std::cerr << "\n" << robot << ", seed " << seed << ": not better on B after the poses: " << 1e3 * rms(w1) << " -> "
              << 1e3 * rms(w2) << " mm (nominal " << 1e3 * rms(w_nom) << ", expected " << 1e3 * std::sqrt(xb / std::max(1u, pb))
              << " -> " << 1e3 * std::sqrt(xa / std::max(1u, pa)) << "); left before [" << notDetermined(r1) << "], after ["
              << notDetermined(r2) << "], " << plan.additions.size() << " poses added\n";
  addErrors(w_nom, w1, w2, row.wide_nominal2, row.wide_before2, row.wide_after2, row.wide_pairs);
}

std::string mostFrequent(const std::map<std::string, unsigned int> &sets)
{
  std::string common = "-";
  unsigned int most = 0;
  for (const auto &s : sets)
    if (s.second > most) {
      most = s.second;
      common = s.first;
    }
  return common;
}

/*
  A row's targets: met; else, when the gain is short of the target, whether any estimator could reach
  it (the Bayes estimator's mean gain over the runs and the first-order noise draws: "beyond the bound") or any estimator of
  what a user states (the set rules and the tolerance priors: "beyond the tolerances' bound").
*/
//! A row of the workspace check against the truth.
std::string workspaceRow(const std::string &robot, unsigned int stuck, unsigned int views, const std::string &focal,
                         double noise, const Row &row)
{
  const double n = std::max(1u, row.ws_runs);
  std::ostringstream os;
  os << std::fixed << "| " << robot << " | j" << stuck + 1 << " | " << views << " | " << focal << " | "
     << std::setprecision(1) << noise << " | " << row.ws_runs << " | " << row.ws_doubt << " | " << row.ws_doubt_worse
     << " | " << row.ws_pass << " | " << row.ws_pass_worse << " | " << std::setprecision(2)
     << 1e3 * std::sqrt(row.ws_true2 / n) << " / " << 1e3 * std::sqrt(row.ws_pred2 / n) << " | "
     << 1e3 * std::sqrt(row.ws_nom2 / n) << " / " << 1e3 * std::sqrt(row.ws_nom_est2 / n) << " |\n";
  return os.str();
}

//! The prior table's row: the main runs with the kinematic prior beside the set rule on the same runs.
std::string priorRow(const std::string &robot, unsigned int stuck, unsigned int views, const std::string &focal,
                     double noise, const Row &row)
{
  const double set_crb_ratio = row.set_bound2 > 0 ? std::sqrt(row.set_e2_bounded / row.set_bound2) : NAN;
  std::string common;
  unsigned int most = 0;
  for (const auto &s : row.prior_held)
    if (s.second > most) {
      most = s.second;
      common = s.first;
    }
  const double n = std::max(1u, row.prior_pairs);
  const double crb = row.prior_bound2 > 0 ? std::sqrt(row.prior_e2_bounded / row.prior_bound2) : NAN;
  const double target = views >= 25 ? 5.0 : 3.0;
  const bool met = row.prior_failed == 0 && row.prior_doubtful == 0 && row.prior_worst < 1 &&
                   row.prior_gain.mean() >= target && crb <= 1.3;
  std::ostringstream os;
  os << std::fixed << "| " << robot << " | j" << stuck + 1 << " | " << views << " | " << focal << " | "
     << std::setprecision(1) << noise << " | " << row.prior_ok << " | " << row.prior_doubtful << " | " << row.prior_failed
     << " | " << common << " | " << std::setprecision(3) << 1e3 * std::sqrt(row.prior_nominal2 / n) << " | "
     << 1e3 * std::sqrt(row.set_e2 / n) << " | " << std::setprecision(2) << row.set_worst << " | "
     << bench::meanSd(row.set_gain, 1, 1) << " | " << set_crb_ratio << " | " << std::setprecision(3)
     << 1e3 * std::sqrt(row.prior_calibrated2 / n) << " | " << 1e3 * std::sqrt(row.prior_bound2 / n) << " | "
     << std::setprecision(2) << row.prior_worst << " | " << bench::meanSd(row.prior_gain, 1, 1) << " | " << crb << " | "
     << std::sqrt(row.set_cov_e2 / row.set_cov_var) << ", " << row.set_cov_worst << " | "
     << std::sqrt(row.prior_cov_e2 / row.prior_cov_var) << ", " << row.prior_cov_worst << " | "
     << row.prior_ok_understated << " | " << bench::meanSd(row.prior_factor, 1, 2) << " | " << row.prior_contradicted
     << " | " << (focal == "known" ? (met ? "met" : "NOT met") : "(not claimed)") << " |\n";
  return os.str();
}

std::string verdict(bool met, const Row &row, double target_gain)
{
  if (met)
    return "met";
  if (row.alt_gain[6].count() == 0 || row.gain.mean() >= target_gain)
    return "NOT met";
  if (row.alt_gain[6].mean() < target_gain)
    return "beyond the bound";
  double user = 0;
  for (int a : {0, 2, 3, 4, 5})
    user = std::max(user, row.alt_gain[a].mean());
  return user < target_gain ? "beyond the tolerances' bound" : "NOT met";
}

//! The other estimators' row (Alternatives) of a main-table row.
std::string alternativesRow(const std::string &robot, unsigned int stuck, unsigned int views, const std::string &focal,
                            double noise, const Row &row)
{
  const double n = std::max(1u, row.alt_pairs), nominal = std::sqrt(row.alt_nominal2 / n);
  auto mm = [&](double sum2) { return 1e3 * std::sqrt(sum2 / n); };
  auto gain = [&](double sum2) { return nominal / std::sqrt(sum2 / n); };
  std::ostringstream os;
  os << std::fixed << "| " << robot << " | j" << stuck + 1 << " | " << views << " | " << focal << " | "
     << std::setprecision(1) << noise << " | " << std::setprecision(3) << 1e3 * nominal << " | " << mm(row.alt_today)
     << " | " << std::setprecision(0) << row.full_size.mean() << " | " << std::setprecision(3) << mm(row.alt_full)
     << " | " << 1e3 * std::sqrt(row.full_measured2 / std::max(1u, row.full_pairs)) << " | " << std::setprecision(2)
     << bench::meanSd(row.full_gain, 1, 1) << " | " << row.full_worst << " | " << std::setprecision(1)
     << row.oracle_left.mean() << " | " << std::setprecision(3) << mm(row.alt_oracle) << " | " << std::setprecision(1)
     << row.risk_left.mean() << " | " << std::setprecision(3) << mm(row.alt_risk) << " | " << mm(row.alt_map1) << " | "
     << mm(row.alt_map3) << " | " << mm(row.alt_bayes) << " | " << std::setprecision(2) << gain(row.alt_today) << ", "
     << gain(row.alt_oracle) << ", " << gain(row.alt_full) << ", " << gain(row.alt_risk) << ", " << gain(row.alt_map1)
     << ", " << gain(row.alt_map3) << ", " << gain(row.alt_bayes) << " | " << std::setprecision(1);
  for (int a = 0; a < 7; ++a)
    os << (a ? ", " : "") << row.alt_gain[a].mean();
  os << " | " << std::setprecision(3) << mm(row.alt_prior_nominal) << ", " << mm(row.alt_prior_bayes) << ", "
     << mm(row.alt_prior_map3) << " | " << std::setprecision(2) << std::sqrt(row.alt_prior_nominal / row.alt_prior_bayes)
     << ", " << std::sqrt(row.alt_prior_nominal / row.alt_prior_map3) << " |\n";
  return os.str();
}

/*
  The same-set check: per robot, noise level and geometry (seeds 1..G, 12 views, f known), D noise
  draws calibrated; the number of different lists left at nominal over the draws (1: a decision the
  noise does not move). True when every geometry gives one set at every level.
*/
bool sameSetCheck(const std::vector<std::string> &robots, const std::vector<double> &noises, unsigned int draws,
                  unsigned int geometries)
{
  bool same = true;
  std::cout << "\n\nthe same set in " << draws << " noise draws of one geometry (12 views, f known), seeds 1-" << geometries
            << ":\n\n| robot | noise (px) | geometries | with one set | sets (per geometry) | most frequent |\n"
            << "|---|---|---|---|---|---|\n";
  for (const std::string &robot : robots)
    for (const double noise : noises) {
      const unsigned int stuck = stuckJoint(robot), views = 12;
      unsigned int one = 0;
      std::string counts;
      std::map<std::string, unsigned int> all;
      for (unsigned int g = 1; g <= geometries; ++g) {
        const vpSelfCalibSimulator clean = makeStuckSim(robot, g);
        const std::vector<vpColVector> q =
            configurations(clean, home(robot, clean.getNominalChain()), stuck, views + kHeldOut, g);
        const vpSelfCalibDataset ds0 = bench::pipelineDataset(clean, q, vpRobotSelfCalibration::FOCAL_KNOWN);
        std::map<std::string, unsigned int> sets;
        for (unsigned int d = 0; d < draws; ++d) {
          std::cerr << robot << " " << noise << " px, geometry " << g << ", same-set draw " << d + 1 << "/" << draws
                    << "      \r" << std::flush;
          const auto r = calibrate(clean, noisy(ds0, noise, 5000011ULL + 7919ULL * g + d),
                                   vpRobotSelfCalibration::FOCAL_KNOWN, noise, views);
          const bool have = r.status == vpRobotSelfCalibration::OK || r.status == vpRobotSelfCalibration::DOUBTFUL;
          ++sets[have ? notDetermined(r) : "(failed)"];
        }
        one += sets.size() == 1;
        counts += (counts.empty() ? "" : " ") + std::to_string(sets.size());
        if (sets.size() > 1)
          for (const auto &s : sets)
            std::cerr << "\n" << robot << " " << noise << " px, geometry " << g << ": [" << s.first << "] x" << s.second;
        for (const auto &s : sets)
          all[s.first] += s.second;
      }
      same = same && one == geometries;
      std::cout << std::fixed << std::setprecision(1) << "| " << robot << " | " << noise << " | " << geometries << " | "
                << one << " | " << counts << " | " << mostFrequent(all) << " |\n"
                << std::flush;
    }
  return same;
}

//! The second table; true when every run estimates every parameter after the poses and its held-out error drops.
bool addPosesTable(const std::vector<std::string> &robots, unsigned int seeds)
{
  const unsigned int views = 12;
  const double noise = 0.2;
  std::cout << "\n\nposes to add (plan --from): " << views << " views, f known, " << noise
            << " px; the poses proposed simulated (true robot, same noise) and calibrated again, " << seeds
            << " seeds\n\n"
            << "held-out A: 10 views with the stuck joint within +-0.5 deg (as the calibration views); held-out B: 10 "
               "views with the stuck joint moving +-0.5 rad as the others. RMS of the relative position error (mm), "
               "nominal / calibrated before / after the poses; gain: nominal / calibrated, mean +- sd over the runs\n\n"
            << "| robot | stuck | runs | failed | left at nominal before (most frequent) | poses added (mean) | "
               "runs with parameters left after | A: nominal | A: before | A: after | B: nominal | B: before | B: after | "
               "B: gain before | B: gain after | runs better on B | B expected: before | B expected: after | "
               "runs expected better on B | targets |\n"
            << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  bool all = true;
  for (const std::string &robot : robots) {
    AddRow row;
    for (unsigned int seed = 1; seed <= seeds; ++seed) {
      std::cerr << robot << " poses to add, seed " << seed << "/" << seeds << "      \r" << std::flush;
      addPosesRun(robot, seed, noise, views, row);
    }
    const bool met = row.failed == 0 && row.left_after == 0 && row.better == row.runs;
    all = all && met;
    const double n = std::max(1u, row.pairs), nw = std::max(1u, row.wide_pairs);
    std::cout << std::fixed << "| " << robot << " | j" << stuckJoint(robot) + 1 << " | " << row.runs << " | " << row.failed
              << " | " << mostFrequent(row.before) << " | " << std::setprecision(1) << row.added.mean() << " | "
              << row.left_after << " | " << std::setprecision(3) << 1e3 * std::sqrt(row.sum_nominal2 / n) << " | "
              << 1e3 * std::sqrt(row.sum_before2 / n) << " | " << 1e3 * std::sqrt(row.sum_after2 / n) << " | "
              << 1e3 * std::sqrt(row.wide_nominal2 / nw) << " | " << 1e3 * std::sqrt(row.wide_before2 / nw) << " | "
              << 1e3 * std::sqrt(row.wide_after2 / nw) << " | " << std::setprecision(2)
              << bench::meanSd(row.wide_gain_before, 1, 1) << " | " << bench::meanSd(row.wide_gain_after, 1, 1) << " | "
              << row.better << " | " << std::setprecision(3)
              << 1e3 * std::sqrt(row.expected_before2 / std::max(1u, row.expected_pairs)) << " | "
              << 1e3 * std::sqrt(row.expected_after2 / std::max(1u, row.expected_pairs)) << " | " << row.expected_better
              << " | " << (met ? "met" : row.expected_better == row.runs ? "met in expectation" : "NOT met") << " |\n"
              << std::flush;
  }
  return all;
}
} // namespace

int main(int argc, char **argv)
{
  try {
    unsigned int seeds = 10, draws = 0, stable = 30, stable_geometries = 1;
    std::vector<std::string> robots = {"panda", "puma560"};
    std::vector<unsigned int> view_counts = {12, 25};
    std::vector<double> noises = {0.2, 0.5};
    std::vector<std::string> focals = {"known", "shared"};
    std::string csv_path;
    CLI::App app("bench-estset: the estimated set from what the data determine, an arm with one joint stuck within "
                 "+-0.5 deg.",
                 "bench-estset");
    selfcalibCli::addSeeds(app, seeds);
    app.add_option("--draws", draws, "extra noise draws of each seed's geometry (default 0)")
        ->type_name("K")
        ->check(selfcalibCli::wholeNumber());
    app.add_option("--stable", stable, "noise draws of one geometry for the same-set check (default 30; 0: none)")
        ->type_name("D")
        ->check(selfcalibCli::wholeNumber());
    app.add_option("--stable-geometries", stable_geometries,
                   "geometries (seeds 1..G) of the same-set check, each at every --noise level (default 1)")
        ->type_name("G")
        ->check(CLI::PositiveNumber);
    selfcalibCli::addRobots(app, robots, vpKinematicChain::presetNames());
    app.add_option("--views", view_counts, "calibration views (default 12,25)")->type_name("V")->delimiter(',');
    selfcalibCli::addNoiseLevels(app, noises, "pixel noise levels, above 0 (default 0.2,0.5)", true);
    app.add_option("--focal", focals, "focal modes (default known,shared)")
        ->type_name("MODES")
        ->delimiter(',')
        ->check(CLI::IsMember(
            bench::focalModeNames({vpRobotSelfCalibration::FOCAL_KNOWN, vpRobotSelfCalibration::FOCAL_SHARED})));
    std::vector<double> tolerance = {g_tolerance_t, g_tolerance_r};
    app.add_option("--tolerance", tolerance,
                   "the nominal model's tolerance given to calibrate, joint placements (m, rad); default 0.003,0.005: "
                   "3 sd of the simulated robot's errors (1 mm, 0.1 deg)")
        ->type_name("T,R")
        ->delimiter(',')
        ->expected(2);
    std::string prior_text;
    app.add_option("--kinematic-prior", prior_text,
                   "the main runs' kinematic prior (calibrate --kinematic-prior: each correction's prior sd its "
                   "tolerance / K): K above 0 (or tolerance/K), off or 0: the set rule (default: calibrate's, K = " +
                       [] {
                         std::ostringstream os;
                         os << vpKinematicBundleAdjustment::DEFAULT_KINEMATIC_PRIOR;
                         return os.str();
                       }() +
                       "). With a prior, the set rule also runs on the same views and the prior's table puts the two "
                       "side by side")
        ->type_name("K|off")
        ->check(CLI::Validator(
            [](std::string &v) {
              return priorOf(v) ? std::string() : "expected off, 0, tolerance, tolerance/K or K (K above 0), got '" + v + "'";
            },
            "K|off", "prior"));
    app.add_option("--alternatives", g_alternatives,
                   "the other estimators' table (first order; the full set also run) (default true)")
        ->type_name("BOOL");
    app.add_option("--csv", csv_path, "one row per run")->type_name("FILE");
    std::vector<std::string> tables = {"main", "add"};
    app.add_option("--tables", tables,
                   "main: the set from the data and the same-set check; add: the poses plan --from proposes, "
                   "added and calibrated again (12 views, 0.2 px, f known; its own seeds) (default main,add)")
        ->type_name("T")
        ->delimiter(',')
        ->check(CLI::IsMember({"main", "add"}));
    const int parsed = selfcalibCli::parse(app, argc, argv);
    if (parsed >= 0)
      return parsed;

    if (!prior_text.empty())
      g_prior = priorOf(prior_text);
    g_tolerance_t = tolerance.at(0);
    g_tolerance_r = tolerance.at(1);
    bench::Csv csv(csv_path, "robot,views,focal,noise,seed,draw,status,nominal_rms_m,calibrated_rms_m,crb_rms_m,bias_rms_m,left_at_nominal,doubts,"
                   "predicted_px,nominal_fit_px,full_set_size,today_expected_rms_m,oracle_expected_rms_m,oracle_left,"
                   "full_expected_rms_m,full_measured_rms_m,map_tol_expected_rms_m,map_tol3_expected_rms_m,bayes_expected_rms_m,risk_set_expected_rms_m,risk_set_left,"
                   "workspace_calibrated_m,workspace_nominal_m,workspace_predicted_m,workspace_bound_m,"
                   "workspace_nominal_estimated_m,workspace_chance_worse,held_workspace_calibrated_m,held_workspace_nominal_m");
    std::cout << "bench-estset: " << seeds << " seeds x " << (draws + 1) << " noise draws, the stuck joint within +-0.5 deg, "
              << kHeldOut << " held-out views, the joint readings trusted (--joint-sd 0)\n";
    if (std::find(tables.begin(), tables.end(), "main") != tables.end())
      std::cout << "\n| robot | stuck | views | focal | noise (px) | ok | doubtful | failed | not determined by the data: left at nominal or held by the prior (most frequent) | sets over the seeds | "
                 "nominal RMS (mm) | calibrated RMS (mm) | CRB RMS (mm) | set's bias RMS (mm) | worst cal/nom | gain (mean) | gain the bound allows | CRB ratio | "
                 "ratio to CRB + bias | targets |\n"
              << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    const auto t_start = std::chrono::steady_clock::now();
    bool all_met = true;
    std::ostringstream alternatives, prior_rows, workspace_rows;
    const bool main_table = std::find(tables.begin(), tables.end(), "main") != tables.end();
    const bool add_table = std::find(tables.begin(), tables.end(), "add") != tables.end();
    for (const std::string &robot : robots) {
      if (!main_table)
        break;
      const unsigned int stuck = stuckJoint(robot);
      for (unsigned int views : view_counts)
        for (const std::string &focal : focals) {
          const vpRobotSelfCalibration::FocalMode mode = vpRobotSelfCalibration::focalModeFromName(focal);
          for (const double noise : noises) {
            Row row;
            for (unsigned int seed = 1; seed <= seeds; ++seed) {
              const vpSelfCalibSimulator clean = makeStuckSim(robot, seed);
              const std::vector<vpColVector> q =
                  configurations(clean, home(robot, clean.getNominalChain()), stuck, views + kHeldOut, seed);
              const std::vector<vpColVector> held(q.begin() + views, q.end());
              const vpSelfCalibDataset ds0 = bench::pipelineDataset(clean, q, mode);
              const std::vector<vpSelfCalibDataset::View> hv(ds0.views.begin() + views, ds0.views.end());
              const std::vector<double> nominal_errors =
                  bench::verifyAgainstTruth(clean, clean.getNominalChain(), clean.getCamera(), hv).position_errors;
              for (unsigned int d = 0; d <= draws; ++d) {
                std::ostringstream tag;
                tag << robot << "," << views << "," << focal << "," << noise << "," << seed << "," << d;
                std::cerr << tag.str() << "        \r" << std::flush;
                runOnce(clean, ds0, held, views, mode, noise, 1000003ULL * seed + d, nominal_errors, row, csv, tag.str());
              }
            }
            std::string common;
            unsigned int most = 0;
            for (const auto &s : row.sets)
              if (s.second > most) {
                most = s.second;
                common = s.first;
              }
            const double crb = row.sum_bound2 > 0 ? std::sqrt(row.sum_e2_bounded / row.sum_bound2) : NAN;
            const double with_bias =
                row.sum_bound2 > 0 ? std::sqrt(row.sum_e2_bounded / (row.sum_bound2 + row.sum_bias2)) : NAN;
            const double target_gain = views >= 25 ? 5.0 : 3.0;
            const bool met = row.failed == 0 && row.doubtful == 0 && row.worst < 1 && row.gain.mean() >= target_gain &&
                             crb <= 1.3;
            if (mode == vpRobotSelfCalibration::FOCAL_KNOWN)
              all_met = all_met && met;
            alternatives << alternativesRow(robot, stuck, views, focal, noise, row);
            if (mainPrior() > 0)
              prior_rows << priorRow(robot, stuck, views, focal, noise, row);
            workspace_rows << workspaceRow(robot, stuck, views, focal, noise, row);
            std::cout << std::fixed << "| " << robot << " | j" << stuck + 1 << " | " << views << " | " << focal << " | "
                      << std::setprecision(1) << noise << " | " << row.ok << " | " << row.doubtful << " | " << row.failed
                      << " | " << common << " | " << row.sets.size() << " | " << std::setprecision(3)
                      << 1e3 * std::sqrt(row.sum_nominal2 / std::max(1u, row.pairs)) << " | "
                      << 1e3 * std::sqrt(row.sum_calibrated2 / std::max(1u, row.pairs)) << " | "
                      << 1e3 * std::sqrt(row.sum_bound2 / std::max(1u, row.bound_pairs)) << " | "
                      << 1e3 * std::sqrt(row.sum_bias2 / std::max(1u, row.bound_pairs)) << " | " << std::setprecision(2)
                      << row.worst << " | " << bench::meanSd(row.gain, 1, 1) << " | "
                      << std::sqrt(row.sum_nominal2 / std::max(1u, row.pairs)) /
                             std::sqrt(row.sum_bound2 / std::max(1u, row.bound_pairs))
                      << " | " << crb << " | " << with_bias << " | "
                      << (mode == vpRobotSelfCalibration::FOCAL_KNOWN ? verdict(met, row, target_gain) : "(not claimed)")
                      << " |\n"
                      << std::flush;
          }
        }
    }
    if (main_table && mainPrior() > 0)
      std::cout << "\n\nthe same runs (calibrate's kinematic prior, --kinematic-prior " << std::defaultfloat
                << mainPrior() << ": each correction's prior sd its tolerance / " << mainPrior()
                << ") beside the set rule (calibrate --kinematic-prior off) on the same views (RMS over the runs both "
                   "calibrated; the worst ratio, the gain and the CRB ratio as in the first table):\n\n"
                << "| robot | stuck | views | focal | noise (px) | ok | doubtful | failed | held by the prior (most "
                   "frequent) | nominal RMS (mm) | set rule: RMS (mm) | set rule: worst cal/nom | set rule: gain (mean) | "
                   "set rule: CRB ratio | prior: RMS (mm) | prior: posterior CRB RMS (mm) | prior: worst cal/nom | "
                   "prior: gain (mean) | prior: CRB ratio | set rule: error / reported sd (RMS, worst run) | "
                   "prior: error / reported sd (RMS, worst run) | prior: ok runs with error > 2 reported sd | "
                   "prior: sd factor measured, largest group (mean / sd) | "
                   "prior: runs doubtful by kinematic-prior-contradicted | "
                   "targets (prior) |\n"
                << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n"
                << prior_rows.str();
    if (main_table)
      std::cout << "\n\nthe same runs, the workspace check (workspace-worse-than-nominal) against the truth: the "
                   "relative camera position over configurations drawn within the joint limits, the stuck joint within "
                   "its range in the calibration views as the check judges it (results.yaml's workspace); a run is truly "
                   "worse when its RMS error there exceeds the nominal model's:\n\n"
                << "| robot | stuck | views | focal | noise (px) | runs judged | doubtful by it | of those, truly worse | "
                   "passed | of those, truly worse | calibrated RMS: true / predicted (mm) | nominal RMS: true / "
                   "estimated (mm) |\n"
                << "|---|---|---|---|---|---|---|---|---|---|---|---|\n"
                << workspace_rows.str();
    if (main_table && g_alternatives)
      std::cout << "\n\nthe same runs, other estimators (their expected held-out error to first order at the truth, "
                   "over the same runs; the full set also run):\n\n"
                << "| robot | stuck | views | focal | noise (px) | nominal RMS (mm) | set's RMS, expected (mm) | "
                   "full set: parameters | full set: CRB RMS (mm) | full set: measured RMS (mm) | full set: gain (mean) | "
                   "full set: worst cal/nom | oracle set: left at nominal (mean) | oracle set: RMS (mm) | "
                   "expected-risk set: left at nominal (mean) | expected-risk set: RMS (mm) | "
                   "prior tolerance: RMS (mm) | prior tolerance/3: RMS (mm) | Bayes (prior the simulated sd): RMS (mm) | "
                   "gain allowed (nominal RMS / expected RMS): set, oracle set, full set, expected-risk set, prior tolerance, "
                   "prior tolerance/3, Bayes | gain (mean over the runs and 200 draws of the noise each, to first order) | "
                   "over robots drawn with the simulated sd, RMS (mm): nominal, Bayes (posterior), prior tolerance/3 | "
                   "gain so (ratio of RMS): Bayes, prior tolerance/3 |\n"
                << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n"
                << alternatives.str();
    // The same set in repeated draws of one geometry, at each noise level.
    const bool same = stable == 0 || !main_table || sameSetCheck(robots, noises, stable, stable_geometries);
    const bool added = !add_table || addPosesTable(robots, seeds);
    std::cerr << std::string(70, ' ') << "\r";
    if (main_table)
      std::cout << "\n\ntargets (f known): ok in every run, calibrated below nominal in every run, gain >= 3 (12 views) "
                   "/ 5 (25 views), CRB ratio <= 1.3: "
                << (all_met ? "met" : "NOT met") << "; the same set in every draw: " << (same ? "met" : "NOT met");
    if (add_table)
      std::cout << "\n\nposes to add: every parameter estimated after adding the poses and the held-out error (B) lower "
                   "in every run: "
                << (added ? "met" : "NOT met");
    std::cout << "\ndone in " << std::setprecision(0)
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count() << " s\n";
    return EXIT_SUCCESS;
  } catch (const vpException &e) {
    std::cerr << "bench-estset: " << e.getStringMessage() << "\n";
  } catch (const std::exception &e) {
    std::cerr << "bench-estset: " << e.what() << "\n";
  }
  return EXIT_FAILURE;
}
