/*
 * Tests of the planning layer: the paper's trajectory cost (eqs. 31, 39 intent) and its gradient,
 * the planned trajectory, observability selection, impossible requests.
 */
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <visp3/selfcalib/vpMeasurementPlanner.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "../testCommon.h"

using namespace selfcalib_test;

namespace
{
double tNorm(const vpKinematicChain &c, const vpColVector &qi, const vpColVector &q0)
{
  return (c.get_fMc(qi).inverse() * c.get_fMc(q0)).getTranslationVector().frobeniusNorm();
}

// Mean |(|t_i|/|t_1|) / (|t̄_i|/|t̄_1|) - 1| over the pairs: the error of the eq. 21 ratios.
double meanRatioError(const vpSelfCalibSimulator &sim, const std::vector<vpColVector> &q)
{
  const vpKinematicChain &T = sim.getTrueChain(), &N = sim.getNominalChain();
  double s = 0;
  for (size_t i = 2; i < q.size(); ++i)
    s += std::fabs((tNorm(T, q[i], q[0]) / tNorm(T, q[1], q[0])) / (tNorm(N, q[i], q[0]) / tNorm(N, q[1], q[0])) - 1);
  return s / (q.size() - 2);
}
} // namespace

// The planner's cost is what it says: the ratio term from g_i (consecutive or spread), and g_i is
// the first-order sensitivity of log |t_i| to the parameters (eq. 31).
TEST(Planner, RatioSensitivityIsTheDerivativeOfLogNorm)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 3);
  const std::vector<vpColVector> q = sim.generateConfigurations(6);
  const vpMeasurementPlanner planner(sim.getNominalChain(), sim.getPlannerScene());
  const std::vector<unsigned int> &ids = planner.identifiableParameters();
  ASSERT_EQ(ids.size(), 24u);
  const std::vector<vpColVector> g = planner.ratioSensitivities(q);
  ASSERT_EQ(g.size(), 5u);
  const vpKinematicChain nominal = sim.getNominalChain();
  for (size_t k = 0; k < ids.size(); k += 3) {
    const double h = 1e-6;
    vpKinematicChain p = nominal, m = nominal;
    vpColVector pp = p.getParameters(), pm = m.getParameters();
    pp[ids[k]] += h;
    pm[ids[k]] -= h;
    p.setParameters(pp);
    m.setParameters(pm);
    for (size_t i = 1; i < q.size(); ++i) {
      const double fd = (std::log(tNorm(p, q[i], q[0])) - std::log(tNorm(m, q[i], q[0]))) / (2 * h);
      EXPECT_NEAR(g[i - 1][static_cast<unsigned int>(k)], fd, 1e-6 * std::max(1.0, std::fabs(fd)))
          << "pair " << i << " parameter " << ids[k];
    }
  }
  // The ratio terms from these g_i.
  vpMeasurementPlanner::TrajectoryOptions o;
  o.ratio_cost = vpMeasurementPlanner::RATIO_CONSECUTIVE;
  double consecutive = 0, spread = 0;
  vpColVector mean(g[0].size(), 0.0);
  for (size_t i = 1; i < g.size(); ++i)
    consecutive += (g[i] - g[i - 1]).sumSquare();
  for (const vpColVector &gi : g)
    mean += gi / static_cast<double>(g.size());
  for (const vpColVector &gi : g)
    spread += (gi - mean).sumSquare();
  EXPECT_NEAR(planner.cost(q, o).ratio, consecutive, 1e-9 * consecutive);
  o.ratio_cost = vpMeasurementPlanner::RATIO_SPREAD;
  EXPECT_NEAR(planner.cost(q, o).ratio, spread, 1e-9 * spread);
}

// The gradient against central differences of the whole cost, with every term active: cond(J)
// with a large lambda, visibility hinges (large planning margin) and two configurations too close.
TEST(Planner, GradientMatchesFiniteDifferences)
{
  for (const std::string robot : {"viper850", "puma560"}) {
    const vpSelfCalibSimulator sim = makeSim(robot, 5);
    std::vector<vpColVector> q = sim.generateConfigurations(7);
    q[3] = q[2];
    q[3][5] += 0.01;
    const vpMeasurementPlanner planner(sim.getNominalChain(), sim.getPlannerScene());
    vpMeasurementPlanner::TrajectoryOptions o;
    o.lambda = 1e-2;
    o.planning_margin = 150;
    const vpMeasurementPlanner::CostTerms terms = planner.cost(q, o);
    ASSERT_GT(terms.visibility, 0);
    ASSERT_GT(terms.distinct, 0);
    ASSERT_GT(o.lambda * terms.condition, 1e-3 * terms.ratio);
    for (auto rc : {vpMeasurementPlanner::RATIO_CONSECUTIVE, vpMeasurementPlanner::RATIO_SPREAD}) {
      o.ratio_cost = rc;
      vpColVector grad;
      const double c = planner.costAndGradient(q, o, grad);
      EXPECT_NEAR(c, planner.cost(q, o).total, 1e-12 * c);
      ASSERT_EQ(grad.size(), 6 * q.size());
      const double gmax = grad.getMaxValue() > -grad.getMinValue() ? grad.getMaxValue() : -grad.getMinValue();
      for (size_t k = 0; k < q.size(); ++k)
        for (unsigned int j = 0; j < 6; ++j) {
          const double h = 1e-6;
          std::vector<vpColVector> qp = q, qm = q;
          qp[k][j] += h;
          qm[k][j] -= h;
          const double fd = (planner.cost(qp, o).total - planner.cost(qm, o).total) / (2 * h);
          EXPECT_NEAR(grad[static_cast<unsigned int>(6 * k + j)], fd, 1e-5 * gmax)
              << robot << " configuration " << k << " joint " << j;
        }
    }
  }
}

// Over several seeds: the plan is feasible (every point seen from the nominal camera with the
// margin, joint limits, distinct configurations), cheaper than the start, and it reduces the
// true error of the eq. 21 ratios (the paper's effect).
TEST(Planner, PlannedTrajectoryIsFeasibleCheaperAndFixesTheRatios)
{
  double before = 0, after = 0;
  for (uint64_t seed : {1, 2, 3}) {
    const vpSelfCalibSimulator sim = makeSim("viper850", seed);
    const std::vector<vpColVector> initial = sim.generateConfigurations(12);
    const vpMeasurementPlanner planner(sim.getNominalChain(), sim.getPlannerScene());
    vpMeasurementPlanner::TrajectoryOptions o;
    o.multistart = 0;
    o.max_evaluations = 600;
    const vpMeasurementPlanner::Result r = planner.planTrajectory(initial, o);
    ASSERT_EQ(r.status, vpMeasurementPlanner::OK) << r.message;
    ASSERT_EQ(r.configurations.size(), initial.size());
    for (size_t k = 0; k < r.configurations.size(); ++k) {
      EXPECT_TRUE(planner.isVisible(r.configurations[k], sim.getPlannerScene().margin)) << "seed " << seed << " pose " << k;
      EXPECT_TRUE(sim.getNominalChain().isInJointLimits(r.configurations[k], 1e-9));
      for (size_t l = k + 1; l < r.configurations.size(); ++l)
        EXPECT_GE((r.configurations[k] - r.configurations[l]).frobeniusNorm(), o.min_joint_distance - 1e-6);
    }
    EXPECT_LT(r.after.total, 0.5 * r.before.total);
    EXPECT_LT(r.after.ratio, 0.5 * r.before.ratio);
    EXPECT_TRUE(std::isfinite(r.after.condition));
    EXPECT_GT(r.observability_after.O1, 0);
    EXPECT_GT(r.seconds, 0);
    before += meanRatioError(sim, initial);
    after += meanRatioError(sim, r.configurations);
  }
  EXPECT_LT(after, 0.5 * before);
}

// The smooth start: a closed loop in joint space, every configuration visible with the planning
// margin and within the limits, consecutive configurations close; planning from it lowers the cost.
TEST(Planner, SmoothInitialTrajectoryIsFeasibleAndPlanningImprovesIt)
{
  for (const std::string robot : {"viper850", "puma560"}) {
    const vpSelfCalibSimulator sim = makeSim(robot, 4);
    const vpMeasurementPlanner planner(sim.getNominalChain(), sim.getPlannerScene());
    const vpColVector home = vpSelfCalibSimulator::homeConfiguration(sim.getNominalChain());
    vpColVector amplitude(home.size(), 0.6);
    const double margin = sim.getPlannerScene().margin + 40;
    const std::vector<vpColVector> q = planner.smoothTrajectory(home, amplitude, 12, margin);
    ASSERT_EQ(q.size(), 12u) << robot;
    double step = 0, spread = 0;
    for (size_t k = 0; k < q.size(); ++k) {
      EXPECT_TRUE(planner.isVisible(q[k], margin));
      EXPECT_TRUE(sim.getNominalChain().isInJointLimits(q[k], 0));
      step = std::max(step, (q[(k + 1) % q.size()] - q[k]).frobeniusNorm());
      spread = std::max(spread, (q[k] - q[0]).frobeniusNorm());
    }
    EXPECT_GT(spread, 0.05) << robot << ": the loop has a size";
    EXPECT_LT(step, 0.7 * spread) << robot << ": consecutive configurations are neighbours";
    vpMeasurementPlanner::TrajectoryOptions o;
    o.max_evaluations = 600;
    const vpMeasurementPlanner::Result r = planner.planTrajectory(q, o);
    EXPECT_EQ(r.status, vpMeasurementPlanner::OK) << robot << ": " << r.message;
    EXPECT_LT(r.after.total, 0.1 * r.before.total) << robot;
  }
  // Nothing fits: a scene behind the camera.
  const vpSelfCalibSimulator sim = makeSim("viper850", 4);
  vpMeasurementPlanner::Scene scene = sim.getPlannerScene();
  for (auto &P : scene.points)
    P = -1.0 * P;
  const vpMeasurementPlanner behind(sim.getNominalChain(), scene);
  const vpColVector home = vpSelfCalibSimulator::homeConfiguration(sim.getNominalChain());
  EXPECT_TRUE(behind.smoothTrajectory(home, vpColVector(home.size(), 0.3), 12, 10).empty());
  EXPECT_THROW(behind.smoothTrajectory(home, vpColVector(3, 0.3), 12, 10), vpSelfCalibException);
}

// The paper scene (partial views, f 300 px): the smooth loop works with the default margin (derived
// from the model's tolerance); a plan reported OK is visible through every sampled model and through
// the true robot; a centre that cannot see the scene says why.
TEST(Planner, PaperSceneSmoothStartAndPlanAreRobustToTheModelError)
{
  for (const std::string robot : {"viper850", "puma560"}) {
    vpSelfCalibSimulator::Options so = vpSelfCalibSimulator::sceneOptions("paper");
    so.seed = 3;
    const vpSelfCalibSimulator sim(vpKinematicChain::preset(robot), so);
    const vpMeasurementPlanner planner(sim.getNominalChain(), sim.getPlannerScene());
    const vpColVector home = vpSelfCalibSimulator::homeConfiguration(sim.getNominalChain());
    std::string why;
    const std::vector<vpColVector> q = planner.smoothTrajectory(home, vpColVector(home.size(), 0.6), 12, -1, &why);
    ASSERT_EQ(q.size(), 12u) << robot << ": " << why;
    vpMeasurementPlanner::TrajectoryOptions o;
    o.multistart = 0;
    o.max_evaluations = 400;
    const double margin = planner.robustMargin(q, o);
    EXPECT_GT(margin, 0) << robot;
    EXPECT_LT(margin, 100) << robot;
    const vpMeasurementPlanner::Result r = planner.planTrajectory(q, o);
    EXPECT_EQ(r.planning_margin, margin);
    if (r.status == vpMeasurementPlanner::OK) {
      EXPECT_EQ(planner.robustFailures(r.configurations, o), 0u);
      for (size_t k = 0; k < r.configurations.size(); ++k)
        EXPECT_TRUE(sim.isVisible(r.configurations[k])) << robot << " pose " << k << ": the true robot must see it";
      EXPECT_TRUE(std::isfinite(r.observability_after.condition_number));
    } else
      EXPECT_EQ(r.status, vpMeasurementPlanner::INFEASIBLE) << r.message;
  }
  // A margin larger than the image: the loop cannot start, and the reason names the centre.
  const vpSelfCalibSimulator sim(vpKinematicChain::preset("viper850"), vpSelfCalibSimulator::sceneOptions("paper"));
  const vpMeasurementPlanner planner(sim.getNominalChain(), sim.getPlannerScene());
  const vpColVector home = vpSelfCalibSimulator::homeConfiguration(sim.getNominalChain());
  std::string why;
  EXPECT_TRUE(planner.smoothTrajectory(home, vpColVector(home.size(), 0.6), 12, 300, &why).empty());
  EXPECT_NE(why.find("centre configuration"), std::string::npos) << why;
  // Sampled models that are the nominal one (zero tolerance) never fail where the nominal view is valid.
  vpMeasurementPlanner::TrajectoryOptions zero;
  zero.tolerance_translation = zero.tolerance_rotation = zero.tolerance_hand_eye_translation =
      zero.tolerance_hand_eye_rotation = 0;
  EXPECT_EQ(planner.robustMargin({home}, zero), 0);
  EXPECT_EQ(planner.robustFailures({home}, zero), 0u);
  vpMeasurementPlanner::TrajectoryOptions bad;
  bad.robust_factor = 0.5;
  EXPECT_THROW(planner.robustMargin({home}, bad), vpSelfCalibException);
}

// The error the eq. 21 ratios leave in the scaled poses, against the true robot: with e_i = log
// (|t̄_i| / |t_i|) (nominal over true), one common scale absorbs the mean, and pose i keeps
// |t_i| |e_i - mean(e)| (m). Mean over the pairs.
namespace
{
double scaledNormError(const vpSelfCalibSimulator &sim, const std::vector<vpColVector> &q)
{
  const vpKinematicChain &T = sim.getTrueChain(), &N = sim.getNominalChain();
  std::vector<double> e, t;
  double mean = 0;
  for (size_t i = 1; i < q.size(); ++i) {
    t.push_back(tNorm(T, q[i], q[0]));
    e.push_back(std::log(tNorm(N, q[i], q[0]) / t.back()));
    mean += e.back() / static_cast<double>(q.size() - 1);
  }
  double s = 0;
  for (size_t i = 0; i < e.size(); ++i)
    s += t[i] * std::fabs(e[i] - mean);
  return s / static_cast<double>(e.size());
}
} // namespace

// The paper scene from the smooth loop (bench-paper's set-up, 25 poses, the spread ratio cost):
// the plan is OK on both robots (configurations pulled together stay min_joint_distance apart) and
// the model error the scaled poses keep drops at least 5x (the target, on the truth). With
// the default consecutive cost the plan is OK too and the error drops (on these two seeds the
// Viper850 4x, the PUMA 560 more): the gain it gives up is the price of its robustness to noise.
// The spread cost plans from its one start (no multistart: each start runs to the 2000-evaluation
// budget, and the extra starts change little: the error drops 8.7x on the Viper850 and 17x on the
// PUMA 560 from one start, 10.5x and 17x from three); the consecutive cost keeps its three starts
// (from one the Viper850's drop is 3.3x, too close to its bound).
TEST(Planner, PaperScenePlanFromTheSmoothLoopFixesTheScaledPoses)
{
  for (const auto cost : {vpMeasurementPlanner::RATIO_SPREAD, vpMeasurementPlanner::RATIO_CONSECUTIVE})
  for (const std::string robot : {"viper850", "puma560"}) {
    double before = 0, after = 0;
    for (uint64_t seed : {1, 2}) {
      vpSelfCalibSimulator::Options so = vpSelfCalibSimulator::sceneOptions("paper");
      so.seed = seed;
      const vpSelfCalibSimulator sim(vpKinematicChain::preset(robot), so);
      const vpMeasurementPlanner planner(sim.getNominalChain(), sim.getPlannerScene());
      const vpColVector home = vpSelfCalibSimulator::homeConfiguration(sim.getNominalChain());
      const std::vector<vpColVector> q = planner.smoothTrajectory(home, vpColVector(home.size(), 0.6), 25);
      ASSERT_EQ(q.size(), 25u) << robot;
      vpMeasurementPlanner::TrajectoryOptions o;
      o.seed = seed;
      o.ratio_cost = cost;
      if (cost == vpMeasurementPlanner::RATIO_SPREAD)
        o.multistart = 0;
      const vpMeasurementPlanner::Result r = planner.planTrajectory(q, o);
      ASSERT_EQ(r.status, vpMeasurementPlanner::OK) << robot << " seed " << seed << ": " << r.message;
      for (size_t k = 0; k < r.configurations.size(); ++k)
        for (size_t l = k + 1; l < r.configurations.size(); ++l)
          EXPECT_GE((r.configurations[k] - r.configurations[l]).frobeniusNorm(), o.min_joint_distance);
      before += scaledNormError(sim, q);
      after += scaledNormError(sim, r.configurations);
    }
    EXPECT_GT(before, (cost == vpMeasurementPlanner::RATIO_SPREAD ? 5 : 3) * after)
        << robot << (cost == vpMeasurementPlanner::RATIO_SPREAD ? " spread" : " consecutive") << ": " << before / 2
        << " -> " << after / 2 << " m";
  }
}

TEST(Planner, ImpossibleRequestsGiveAStatus)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 4);
  const std::vector<vpColVector> q = sim.generateConfigurations(8);
  const vpMeasurementPlanner planner(sim.getNominalChain(), sim.getPlannerScene());
  // 4 configurations: 18 equations for 24 parameters.
  const std::vector<vpColVector> few(q.begin(), q.begin() + 4);
  EXPECT_EQ(planner.planTrajectory(few).status, vpMeasurementPlanner::TOO_FEW_CONFIGURATIONS);
  EXPECT_EQ(planner.selectObservable(q, 4).status, vpMeasurementPlanner::TOO_FEW_CONFIGURATIONS);
  // Two scene points 5 m on either side of the object: no camera pose sees them both.
  vpMeasurementPlanner::Scene wide = sim.getPlannerScene();
  const vpColVector c = wide.points[0];
  wide.points.push_back(vpColVector({c[0] + 5, c[1], c[2]}));
  wide.points.push_back(vpColVector({c[0] - 5, c[1], c[2]}));
  const vpMeasurementPlanner lost(sim.getNominalChain(), wide);
  vpMeasurementPlanner::TrajectoryOptions o;
  o.multistart = 0;
  o.max_evaluations = 100;
  const vpMeasurementPlanner::Result r = lost.planTrajectory(q, o);
  EXPECT_EQ(r.status, vpMeasurementPlanner::INFEASIBLE);
  EXPECT_NE(r.message.find("out of reach"), std::string::npos) << r.message;
  EXPECT_EQ(r.configurations.size(), q.size());
}

TEST(Planner, BadInputThrows)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 4);
  const std::vector<vpColVector> q = sim.generateConfigurations(8);
  const vpMeasurementPlanner planner(sim.getNominalChain(), sim.getPlannerScene());
  std::vector<vpColVector> wrong = q;
  wrong[2].resize(5);
  EXPECT_THROW(planner.planTrajectory(wrong), vpSelfCalibException);
  std::vector<vpColVector> outside = q;
  outside[1][0] = sim.getNominalChain().getJointMax()[0] + 0.1;
  EXPECT_THROW(planner.planTrajectory(outside), vpSelfCalibException);
  vpMeasurementPlanner::TrajectoryOptions o;
  o.lambda = -1;
  EXPECT_THROW(planner.cost(q, o), vpSelfCalibException);
  EXPECT_THROW(planner.selectObservable(q, 9), vpSelfCalibException);
  EXPECT_THROW(vpMeasurementPlanner::algorithmFromName("newton"), vpSelfCalibException);
  EXPECT_THROW(vpMeasurementPlanner::indexFromName("O7"), vpSelfCalibException);
  vpMeasurementPlanner::Scene empty = sim.getPlannerScene();
  empty.points.clear();
  EXPECT_THROW(vpMeasurementPlanner(sim.getNominalChain(), empty), vpSelfCalibException);
  vpMeasurementPlanner::Scene nocam = sim.getPlannerScene();
  nocam.width = 0;
  EXPECT_THROW(vpMeasurementPlanner(sim.getNominalChain(), nocam), vpSelfCalibException);
}

// The selection's cost terms (before and after) use the caller's row weights: cond(J) is that of J
// weighted by the caller's direction_sd and rotation_sd (the observability indices' condition
// number, computed independently), which differs from the default weights' when their ratio does.
TEST(Planner, SelectionScoresWithTheCallersStandardDeviations)
{
  const vpSelfCalibSimulator sim = makeSim("puma560", 6);
  const std::vector<vpColVector> pool = sim.generateConfigurations(30);
  const vpMeasurementPlanner planner(sim.getNominalChain(), sim.getPlannerScene());
  const std::vector<vpColVector> first(pool.begin(), pool.begin() + 10);
  vpMeasurementPlanner::SelectionOptions o;
  o.direction_sd = 5e-3;
  o.rotation_sd = 5e-2; // default 5e-3
  const vpMeasurementPlanner::Result r = planner.selectObservable(pool, 10, o);
  ASSERT_EQ(r.status, vpMeasurementPlanner::OK) << r.message;
  const double before = planner.observability(first, o.direction_sd, o.rotation_sd).condition_number;
  const double after = planner.observability(r.configurations, o.direction_sd, o.rotation_sd).condition_number;
  EXPECT_NEAR(r.before.condition, before, 1e-6 * before);
  EXPECT_NEAR(r.after.condition, after, 1e-6 * after);
  const double with_defaults = planner.observability(first, 5e-3, 5e-3).condition_number;
  EXPECT_GT(std::fabs(r.before.condition - with_defaults), 0.01 * with_defaults)
      << "the caller's rotation_sd does not change cond(J)";
}

// Selection from a pool keeps the reference, takes distinct configurations and beats taking the
// first m of the pool on the chosen index, for O1 and O3.
TEST(Planner, ObservabilitySelectionBeatsTheFirstOnes)
{
  const vpSelfCalibSimulator sim = makeSim("puma560", 6);
  const std::vector<vpColVector> pool = sim.generateConfigurations(40);
  const vpMeasurementPlanner planner(sim.getNominalChain(), sim.getPlannerScene());
  for (const std::string index : {"O1", "O3"}) {
    vpMeasurementPlanner::SelectionOptions o;
    o.index = vpMeasurementPlanner::indexFromName(index);
    const vpMeasurementPlanner::Result r = planner.selectObservable(pool, 10, o);
    ASSERT_EQ(r.status, vpMeasurementPlanner::OK) << r.message;
    ASSERT_EQ(r.configurations.size(), 10u);
    EXPECT_EQ((r.configurations[0] - pool[0]).frobeniusNorm(), 0.0);
    for (size_t k = 0; k < r.configurations.size(); ++k)
      for (size_t l = k + 1; l < r.configurations.size(); ++l)
        EXPECT_GT((r.configurations[k] - r.configurations[l]).frobeniusNorm(), 0.0);
    const vpObservabilityIndices direct = planner.observability(r.configurations);
    EXPECT_NEAR(direct.O1, r.observability_after.O1, 1e-9 * direct.O1);
    if (index == "O1")
      EXPECT_GT(r.observability_after.O1, 1.2 * r.observability_before.O1);
    else
      EXPECT_GT(r.observability_after.O3, 1.2 * r.observability_before.O3);
  }
}
