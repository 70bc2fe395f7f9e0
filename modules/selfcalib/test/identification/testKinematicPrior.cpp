/*
 * Tests of the kinematic prior of vpKinematicBundleAdjustment (Settings::kinematic_prior): the
 * default (tolerance / 3) and off (the set rule), the residual's Jacobian, exact recovery when the
 * prior's centre is the truth, the pull of a prior centred off the truth bounded by its weight, the
 * posterior covariance against (J^T J + P)^-1, the parameters the data leave to the prior named, the
 * data's agreement with the prior measured, and bad values refused.
 */
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <visp3/selfcalib/vpKinematicBundleAdjustment.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "../testCommon.h"
#include "identification/vpKinematicBundleAdjustmentCosts.h"

using namespace selfcalib_test;

namespace
{
using KBA = vpKinematicBundleAdjustment;

std::vector<double> parametersOf(const vpKinematicChain &c)
{
  const vpColVector p = c.getParameters();
  return std::vector<double>(p.data, p.data + p.size());
}

/*!
  A nominal model the truth differs from only in the parameters the adjustment estimates with the
  prior (the rule's candidates: those the data determine and those they leave): the true robot with
  those reset to the simulator's nominal values. The truth is then a point of the estimate's space
  (the base, joint 1 and the rule's redundant twins, which images cannot see or which fold into
  others, are at their true values in both).
*/
vpKinematicChain nominalOfTheSet(const vpSelfCalibSimulator &sim, const vpKinematicIdentification::Identifiability &set)
{
  vpColVector p = sim.getTrueChain().getParameters();
  const vpColVector nominal = sim.getNominalChain().getParameters();
  for (unsigned int i : set.identified)
    p[i] = nominal[i];
  for (const auto &u : set.unidentifiable)
    if (u.cause == vpKinematicIdentification::CAUSE_DATA)
      p[u.index] = nominal[u.index];
  vpKinematicChain c = sim.getTrueChain();
  c.setParameters(p);
  return c;
}

/*!
  A PUMA 560 whose wrist joint 5 moves 1 deg over 12 noise-free views, 0.3 px stated, f known, and
  the start model nominalOfTheSet() of the rule's set: the set-up of the tests that solve with the
  prior from a start whose only error is in the estimated parameters.
*/
struct StuckWristAtTheSet {
  StuckWrist w{3, 12, 1.0};
  vpSelfCalibNoiseModel noise;
  KBA::Options bo;
  vpKinematicChain start;
  StuckWristAtTheSet()
  {
    noise.pixel_sd = 0.3;
    bo.intrinsics = 0;
    bo.tight = true;
    bo.covariance = false;
    start = nominalOfTheSet(w.sim, KBA::estimatedSet(w.sim.getNominalChain(), w.ds.cam, w.ds.views, w.ds.yardstick,
                                                     w.sim.getScenePointsById(), bo, noise));
  }
};

//! The prior's sd of chain parameter i (KBA::Settings::kinematic_prior's tolerance / k).
double priorSd(unsigned int i, unsigned int joints, const KBA::Options &o)
{
  const bool eMc = i / vpKinematicChain::kBlockSize == joints + 1, t = i % vpKinematicChain::kBlockSize < 3;
  return (eMc ? (t ? o.tolerance_hand_eye_translation : o.tolerance_hand_eye_rotation)
              : (t ? o.tolerance_translation : o.tolerance_rotation)) /
         o.kinematicPrior();
}
} // namespace

// The prior block (Ceres' NormalPrior, built from the tolerances' sd): residual (x - ref) / sd and
// Jacobian diag(1 / sd).
TEST(KinematicBundlePrior, ResidualIsTheCorrectionsOffTheReferenceInSd)
{
  const std::vector<double> ref = {0.01, -0.02, 0.3}, sd = {1e-3, 5e-3, 0.2};
  const std::unique_ptr<ceres::CostFunction> cost(vpKinematicBundle::kinematicPriorCost(ref, sd));
  ASSERT_EQ(cost->num_residuals(), 3);
  ASSERT_EQ(cost->parameter_block_sizes(), std::vector<int32_t>({3}));
  std::vector<double> x = {0.012, -0.05, 0.1};
  double r[3], J[9];
  const double *p[] = {x.data()};
  double *Jp[] = {J};
  ASSERT_TRUE(cost->Evaluate(p, r, Jp));
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(r[i], (x[i] - ref[i]) / sd[i], 1e-12);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(J[i * 3 + c], i == c ? 1 / sd[i] : 0.0, 1e-12);
  }
}

/*
  A PUMA 560 whose wrist joint 5 moves 1 deg over 12 noise-free views: the data leave parameters at
  nominal. With the prior centred on the true robot (the truth is its own nominal model) the estimate
  is the truth exactly, every candidate of the rule estimated and those the data alone do not
  determine named as held by the prior, with their reason and what would determine them.
*/
TEST(KinematicBundlePrior, NoiseFreeRecoveryWhenTheTruthIsTheNominalModel)
{
  const StuckWrist w(3, 12, 1.0);
  vpSelfCalibNoiseModel noise;
  noise.pixel_sd = 0.3;
  KBA::Options bo;
  bo.intrinsics = 0;
  bo.tight = true;
  bo.kinematic_prior = KBA::KINEMATIC_PRIOR_OFF;
  const auto without = KBA::adjust(w.sim.getNominalChain(), w.ds.cam, w.ds.views, w.ds.yardstick,
                                   w.sim.getScenePointsById(), bo, noise);
  ASSERT_EQ(without.status, KBA::OK) << without.message;
  const std::vector<std::string> left = leftByData(without.identifiability);
  ASSERT_FALSE(left.empty());
  bo.kinematic_prior = 3;
  bo.scale_reference = parametersOf(w.sim.getTrueChain());
  const auto r = KBA::adjust(nominalOfTheSet(w.sim, without.identifiability), w.ds.cam, w.ds.views, w.ds.yardstick, w.sim.getScenePointsById(),
                             bo, noise);
  ASSERT_EQ(r.status, KBA::OK) << r.message;
  EXPECT_EQ(r.kinematic_prior, 3);
  EXPECT_TRUE(leftByData(r.identifiability).empty());
  std::vector<std::string> held;
  for (const auto &u : r.identifiability.held_by_prior) {
    held.push_back(u.name);
    EXPECT_FALSE(u.reason.empty());
    EXPECT_NE(u.needs.find("j5 moves"), std::string::npos) << u.name << ": " << u.needs;
    EXPECT_TRUE(std::binary_search(r.identifiability.identified.begin(), r.identifiability.identified.end(), u.index));
  }
  EXPECT_EQ(held, left);
  EXPECT_EQ(r.identifiability.identified.size(), without.identifiability.identified.size() + left.size());
  const vpColVector truth = w.sim.getTrueChain().getParameters();
  for (unsigned int i : r.identifiability.identified)
    EXPECT_NEAR(r.chain.getParameters()[i], truth[i], 1e-8) << r.chain.getParameterNames()[i];
  // The sd of a parameter held by the prior is about the prior's, below it.
  for (const auto &u : r.identifiability.held_by_prior) {
    const double sd = priorSd(u.index, w.sim.getNominalChain().getNumJoints(), bo);
    EXPECT_LE(r.sd[u.index], sd * (1 + 1e-9)) << u.name;
    EXPECT_GT(r.sd[u.index], 0.1 * sd) << u.name;
  }
}

/*
  The default is the prior, tolerance / 3: a PUMA 560 whose wrist joint 5 moves 1 deg over 12 views, no
  option said: every parameter the data leave is held by the prior (none left at nominal), the
  result's k DEFAULT_KINEMATIC_PRIOR. KINEMATIC_PRIOR_OFF is the set rule: the same parameters left
  at nominal, none held. Freeing them: the set rule refuses those the data cannot separate from the
  others (RANK_DEFICIENT, each named with its reason) and estimates the others; the prior refuses
  none, every freed one estimated, the inseparable ones held by the prior.
*/
TEST(KinematicBundlePrior, TheDefaultIsTheToleranceOverThreeAndOffIsTheSetRule)
{
  const StuckWrist w(3, 12, 1.0);
  vpSelfCalibNoiseModel noise;
  noise.pixel_sd = 0.3;
  KBA::Options bo;
  bo.intrinsics = 0;
  EXPECT_FALSE(bo.kinematic_prior.has_value());
  EXPECT_EQ(bo.kinematicPrior(), 3.0);
  const auto def = KBA::adjust(w.sim.getNominalChain(), w.ds.cam, w.ds.views, w.ds.yardstick,
                               w.sim.getScenePointsById(), bo, noise);
  ASSERT_EQ(def.status, KBA::OK) << def.message;
  EXPECT_EQ(def.kinematic_prior, KBA::DEFAULT_KINEMATIC_PRIOR);
  EXPECT_TRUE(leftByData(def.identifiability).empty());
  std::vector<std::string> held;
  for (const auto &u : def.identifiability.held_by_prior)
    held.push_back(u.name);
  EXPECT_FALSE(held.empty());
  bo.kinematic_prior = KBA::KINEMATIC_PRIOR_OFF;
  const auto off = KBA::adjust(w.sim.getNominalChain(), w.ds.cam, w.ds.views, w.ds.yardstick,
                               w.sim.getScenePointsById(), bo, noise);
  ASSERT_EQ(off.status, KBA::OK) << off.message;
  EXPECT_EQ(off.kinematic_prior, 0.0);
  EXPECT_TRUE(off.identifiability.held_by_prior.empty());
  EXPECT_EQ(leftByData(off.identifiability), held);
  // Freed: the set rule refuses those the data cannot separate (here j6.tx and j6.rx: joint 5 barely
  // turns), naming them; the prior estimates every one of them.
  bo.free = held;
  const auto free_off = KBA::adjust(w.sim.getNominalChain(), w.ds.cam, w.ds.views, w.ds.yardstick,
                                    w.sim.getScenePointsById(), bo, noise);
  EXPECT_EQ(free_off.status, KBA::RANK_DEFICIENT) << free_off.message;
  EXPECT_NE(free_off.message.find("freed parameters the data do not determine, refused: j6.tx: the data cannot "
                                  "separate it"),
            std::string::npos)
      << free_off.message;
  bo.kinematic_prior.reset();
  const auto free_prior = KBA::adjust(w.sim.getNominalChain(), w.ds.cam, w.ds.views, w.ds.yardstick,
                                      w.sim.getScenePointsById(), bo, noise);
  ASSERT_EQ(free_prior.status, KBA::OK) << free_prior.message;
  for (const std::string &n : held) {
    const unsigned int k = w.sim.getNominalChain().getParameterIndex(n);
    EXPECT_TRUE(std::binary_search(free_prior.identifiability.identified.begin(),
                                   free_prior.identifiability.identified.end(), k))
        << n;
  }
  EXPECT_TRUE(leftByData(free_prior.identifiability).empty());
}

/*
  The prior centred on the nominal model (nominalOfTheSet()), the truth off it, noise-free views: the estimate minimizes
  pixels' chi-square plus the prior's, which is the prior's chi-square of the truth at the truth. Both
  parts at the estimate are bounded by it: the pull moves the images by no more than the prior's
  weight on the truth's error allows. A weaker prior pulls less: the held-out error of the views'
  relative poses shrinks as K does, and the parameters the data determine approach the truth.
*/
TEST(KinematicBundlePrior, PullOfAPriorOffTheTruthIsBoundedByItsWeight)
{
  StuckWristAtTheSet f;
  const StuckWrist &w = f.w;
  const vpSelfCalibNoiseModel &noise = f.noise;
  KBA::Options &bo = f.bo;
  const vpKinematicChain &start = f.start;
  const vpColVector truth = w.sim.getTrueChain().getParameters(), nominal = start.getParameters();
  double previous = std::numeric_limits<double>::infinity();
  for (double k : {3.0, 0.3, 0.03}) {
    bo.kinematic_prior = k;
    const auto r = KBA::adjust(start, w.ds.cam, w.ds.views, w.ds.yardstick,
                               w.sim.getScenePointsById(), bo, noise);
    ASSERT_EQ(r.status, KBA::OK) << r.message;
    const unsigned int n = w.sim.getNominalChain().getNumJoints();
    double prior_truth = 0, prior_estimate = 0, determined = 0;
    for (unsigned int i : r.identifiability.identified) {
      const double sd = priorSd(i, n, bo);
      prior_truth += std::pow((truth[i] - nominal[i]) / sd, 2);
      prior_estimate += std::pow((r.chain.getParameters()[i] - nominal[i]) / sd, 2);
    }
    const double pixels = 2.0 * r.num_observations * r.rms * r.rms / (noise.pixel_sd * noise.pixel_sd);
    EXPECT_GT(prior_truth, 0);
    EXPECT_LE(pixels + prior_estimate, prior_truth * (1 + 1e-6)) << "K " << k;
    for (unsigned int i : r.identifiability.identified) {
      if (!r.identifiability.heldByPrior(i))
        determined = std::max(determined, std::fabs(r.chain.getParameters()[i] - truth[i]) / priorSd(i, n, bo) * k);
    }
    EXPECT_LT(determined, previous) << "K " << k; // in units of the tolerance
    previous = determined;
  }
  EXPECT_LT(previous, 1e-3); // K 0.03: within a thousandth of the tolerance
}

/*
  The covariance with the prior is the posterior one: on a small problem whose data determine every
  parameter (no yardstick gauge, no parameter left), information() with the prior equals
  (C^-1 + P)^-1, C the covariance without it (the points and nuisance blocks eliminated: the prior
  is on the corrections only, so it adds to their information unchanged), P = diag((K / tol)^2) on
  the corrections and 0 on f.
*/
TEST(KinematicBundlePrior, CovarianceIsTheInverseOfTheInformationPlusThePrior)
{
  const vpSelfCalibSimulator sim = makeSim("puma560", 7, 0.0);
  const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(8));
  vpSelfCalibNoiseModel noise;
  noise.pixel_sd = 0.5;
  KBA::Options bo; // f estimated too
  const auto set = KBA::estimatedSet(sim.getTrueChain(), sim.getCamera(), ds.views, ds.yardstick,
                                     sim.getScenePointsById(), bo, noise);
  ASSERT_TRUE(leftByData(set).empty());
  bo.estimated_set = set;
  bo.kinematic_prior = KBA::KINEMATIC_PRIOR_OFF;
  const auto c0 = KBA::information(sim.getTrueChain(), sim.getCamera(), ds.views, ds.yardstick, sim.getScenePointsById(),
                                   bo, noise);
  ASSERT_TRUE(c0.has_covariance) << c0.message;
  bo.kinematic_prior = 2;
  const auto c1 = KBA::information(sim.getTrueChain(), sim.getCamera(), ds.views, ds.yardstick, sim.getScenePointsById(),
                                   bo, noise);
  ASSERT_TRUE(c1.has_covariance) << c1.message;
  ASSERT_EQ(c0.covariance_names, c1.covariance_names);
  const int N = static_cast<int>(c0.covariance.getRows()), P = static_cast<int>(set.identified.size());
  ASSERT_EQ(N, P + 1);
  Eigen::MatrixXd C0(N, N), C1(N, N);
  for (int r = 0; r < N; ++r)
    for (int c = 0; c < N; ++c) {
      C0(r, c) = c0.covariance[r][c];
      C1(r, c) = c1.covariance[r][c];
    }
  Eigen::MatrixXd H = C0.inverse();
  for (int r = 0; r < P; ++r)
    H(r, r) += 1.0 / std::pow(priorSd(set.identified[r], sim.getTrueChain().getNumJoints(), bo), 2);
  const Eigen::MatrixXd expected = H.inverse();
  for (int r = 0; r < N; ++r)
    for (int c = 0; c < N; ++c)
      EXPECT_NEAR(C1(r, c), expected(r, c), 1e-6 * std::sqrt(expected(r, r) * expected(c, c)))
          << c1.covariance_names[r] << ", " << c1.covariance_names[c];
  // And the prior tightens every sd.
  for (unsigned int i : set.identified)
    EXPECT_LT(c1.sd[i], c0.sd[i]) << sim.getTrueChain().getParameterNames()[i];
}

/*
  The prior against the data (Result::prior_groups): a PUMA 560 whose wrist joint 5 moves 1 deg, the truth off the prior's centre by the simulator's errors (1 mm, 0.1
  deg; eMc 1 mm, 0.2 deg), 25 views with 0.1 px of noise (the data determine the joints' corrections
  well below those sd). Tolerances 3 times those sd and K = 3: the prior is the errors' own
  distribution, and each group's squared prior residuals average their redundancy and stay below
  their 99.9 % quantile (at most one of the seeds over it). Tolerances 3 times smaller (the prior's sd
  a third of the arm's errors): the joint groups measure a factor above 2 and the doubt's rule flags
  all seeds but at most one.
*/
TEST(KinematicBundlePrior, DataContradictAPriorTighterThanTheArmsErrors)
{
  const double deg = M_PI / 180;
  unsigned int matched_over = 0, seeds = 0, tight_runs = 0;
  double chi2 = 0, redundancy = 0, tight_chi2 = 0, tight_redundancy = 0;
  for (uint64_t seed : {3, 4, 5, 6, 7}) {
    StuckWrist w(seed, 25, 1.0);
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> n(0, 0.1);
    for (auto &v : w.ds.views)
      for (auto &o : v.points)
        o.ip = vpImagePoint(o.ip.get_i() + n(rng), o.ip.get_j() + n(rng));
    vpSelfCalibNoiseModel noise;
    noise.pixel_sd = 0.1;
    KBA::Options bo;
    bo.intrinsics = 0;
    bo.covariance = false;
    const auto set = KBA::estimatedSet(w.sim.getNominalChain(), w.ds.cam, w.ds.views, w.ds.yardstick,
                                       w.sim.getScenePointsById(), bo, noise);
    const vpKinematicChain start = nominalOfTheSet(w.sim, set);
    bo.covariance = true;
    bo.kinematic_prior = 3;
    for (double shrink : {1.0, 1.0 / 3}) {
      bo.tolerance_translation = shrink * 3e-3;
      bo.tolerance_rotation = shrink * 0.3 * deg;
      bo.tolerance_hand_eye_translation = shrink * 3e-3;
      bo.tolerance_hand_eye_rotation = shrink * 0.6 * deg;
      const auto r = KBA::adjust(start, w.ds.cam, w.ds.views, w.ds.yardstick, w.sim.getScenePointsById(), bo, noise);
      ASSERT_EQ(r.status, KBA::OK) << r.message;
      ASSERT_TRUE(r.has_covariance);
      ASSERT_EQ(r.prior_groups.size(), 4u); // joint and hand-eye translations and rotations
      bool over = false, tight_flagged = false;
      for (const auto &g : r.prior_groups) {
        EXPECT_GT(g.redundancy, 0) << g.name;
        EXPECT_GT(g.quantile, g.redundancy) << g.name;
        over = over || g.chi2 > g.quantile;
        if (shrink == 1.0) {
          chi2 += g.chi2;
          redundancy += g.redundancy;
        } else if (g.name.rfind("joint", 0) == 0) {
          tight_chi2 += g.chi2;
          tight_redundancy += g.redundancy;
          // The doubt's rule (kinematic-prior-contradicted): over the quantile, the sd off by 2 or more.
          tight_flagged = tight_flagged || (g.chi2 > g.quantile && g.chi2 >= 4 * g.redundancy);
        }
      }
      if (shrink == 1.0)
        matched_over += over;
      else
        tight_runs += tight_flagged;
    }
    ++seeds;
  }
  EXPECT_LE(matched_over, 1u);
  // The prior 3 times too tight: the joints' corrections measure a factor of about 3 (the pooled one above 2), and
  // the doubt's rule flags most seeds (a seed whose true errors happen to lie where the data see little escapes).
  EXPECT_GT(std::sqrt(tight_chi2 / tight_redundancy), 2.0) << tight_chi2 << " / " << tight_redundancy;
  EXPECT_GE(tight_runs, seeds - 1);
  // The matched prior's residuals average their redundancy: a sum of about `redundancy` unit variances.
  EXPECT_NEAR(chi2 / redundancy, 1.0, 3.29 * std::sqrt(2.0 / redundancy) + 0.2) << chi2 << " / " << redundancy;
}

/*
  A measured eMc (Options::eMc_measured: the pipeline's start measured it from the same data) gets
  no prior where the data determine it: the same data from two measured starts 20 mm and 10 mrad
  apart give the same joints' corrections and the same calibrated eMc, and no hand-eye group is
  judged against the prior. With the prior on it (eMc_measured false), the stuck wrist's offsets,
  which the data see only together with eMc, are shared around each start: the results differ.
*/
TEST(KinematicBundlePrior, AMeasuredEMcIsLeftToTheData)
{
  StuckWristAtTheSet f;
  const StuckWrist &w = f.w;
  const vpSelfCalibNoiseModel &noise = f.noise;
  KBA::Options &bo = f.bo;
  const vpKinematicChain &a = f.start;
  vpKinematicChain b = a;
  b.set_eMc(vpPoseVector(vpHomogeneousMatrix(a.get_eMc_pose()) * vpHomogeneousMatrix(0.012, -0.016, 0.0, 0.006, 0.0, -0.008)));
  const unsigned int n = a.getNumJoints(), eMc_first = (n + 1) * vpKinematicChain::kBlockSize;
  bo.kinematic_prior = 3;
  bo.covariance = true;
  double joints_apart[2] = {0, 0}, eMc_apart[2] = {0, 0};
  for (bool measured : {true, false}) {
    bo.eMc_measured = measured;
    const auto ra = KBA::adjust(a, w.ds.cam, w.ds.views, w.ds.yardstick, w.sim.getScenePointsById(), bo, noise);
    const auto rb = KBA::adjust(b, w.ds.cam, w.ds.views, w.ds.yardstick, w.sim.getScenePointsById(), bo, noise);
    ASSERT_EQ(ra.status, KBA::OK) << ra.message;
    ASSERT_EQ(rb.status, KBA::OK) << rb.message;
    ASSERT_FALSE(ra.identifiability.held_by_prior.empty()); // the stuck wrist leaves parameters to the prior
    for (unsigned int i = 0; i < eMc_first; ++i)
      joints_apart[measured] =
          std::max(joints_apart[measured], std::fabs(ra.chain.getParameters()[i] - rb.chain.getParameters()[i]));
    eMc_apart[measured] = (ra.chain.get_eMc_corrected().getTranslationVector() -
                           rb.chain.get_eMc_corrected().getTranslationVector()).frobeniusNorm();
    if (measured)
      for (const auto &g : ra.prior_groups)
        EXPECT_EQ(g.name.rfind("hand-eye", 0), std::string::npos) << g.name;
  }
  EXPECT_LT(joints_apart[1], 1e-7) << "measured eMc: the joints' corrections depend on the start";
  EXPECT_LT(eMc_apart[1], 1e-7) << "measured eMc: the calibrated eMc depends on the start";
  EXPECT_GT(joints_apart[0], 10 * joints_apart[1] + 1e-6) << "the prior on eMc made no difference: the test sees nothing";
}

// Bad values of the prior are refused: negative, not a number, infinite.
TEST(KinematicBundlePrior, BadValuesAreRefused)
{
  const vpSelfCalibSimulator sim = makeSim("puma560", 7, 0.0);
  const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(6));
  for (double k : {-1.0, -1e-9, std::nan(""), std::numeric_limits<double>::infinity()}) {
    KBA::Options bo;
    bo.kinematic_prior = k;
    EXPECT_THROW(bo.check(), vpSelfCalibException) << k;
    EXPECT_THROW(KBA::adjust(sim.getNominalChain(), sim.getCamera(), ds.views, ds.yardstick, sim.getScenePointsById(), bo,
                             vpSelfCalibNoiseModel()),
                 vpSelfCalibException)
        << k;
  }
  KBA::Options off;
  off.kinematic_prior = 0; // no prior: fine
  EXPECT_NO_THROW(off.check());
}
