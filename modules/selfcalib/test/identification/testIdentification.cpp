/*
 * Tests of the identification layer (kinematic identification, identifiability, covariance,
 * observability indices) and of the scale layer, against ground truth.
 */
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <visp3/selfcalib/vpKinematicIdentification.h>
#include <visp3/selfcalib/vpObservabilityIndices.h>
#include <visp3/selfcalib/vpPoseScale.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "../testCommon.h"
#include "core/vpSelfCalibMath.h"
#include "core/vpSelfCalibRandom.h"

using namespace selfcalib_test;

using namespace vpSelfCalib;

namespace
{
using Measurements = std::vector<vpKinematicIdentification::Measurement>;

// Exact measurements from the true chain: relative (c_i M c_0, i >= 1) or absolute (fMc).
Measurements exactMeasurements(const vpKinematicChain &truth, const std::vector<vpColVector> &q, bool relative,
                               double sd = 1e-4)
{
  Measurements ms;
  for (size_t i = relative ? 1 : 0; i < q.size(); ++i) {
    vpKinematicIdentification::Measurement m;
    m.q = q[i];
    if (relative) {
      m.q_ref = q[0];
      m.M = truth.get_fMc(q[i]).inverse() * truth.get_fMc(q[0]);
    } else
      m.M = truth.get_fMc(q[i]);
    m.sd_position = sd;
    m.sd_rotation = sd;
    ms.push_back(m);
  }
  return ms;
}

} // namespace

// Theory (README, "Identifiability"): 4 n + 6 = 30 independent parameters for a 6R arm with
// absolute poses; relative poses lose the 6 of a rigid motion of the whole arm: 24.
TEST(Identification, IdentifiabilityCountsMatchTheory)
{
  for (const std::string robot : {"puma560", "viper850"}) {
    const vpSelfCalibSimulator sim = makeSim(robot, 1);
    const std::vector<vpColVector> q = sim.generateConfigurations(15);
    vpKinematicIdentification::Options o;
    const auto abs = vpKinematicIdentification::analyse(sim.getNominalChain(), exactMeasurements(sim.getTrueChain(), q, false), o);
    const auto rel = vpKinematicIdentification::analyse(sim.getNominalChain(), exactMeasurements(sim.getTrueChain(), q, true), o);
    EXPECT_EQ(abs.rank, 30u) << robot;
    EXPECT_EQ(abs.identified.size(), 30u) << robot;
    EXPECT_EQ(rel.rank, 24u) << robot;
    EXPECT_EQ(rel.identified.size() + rel.unidentifiable.size(), 48u);
    // The gap between the estimated parameters' new directions and the dependent ones' is wide.
    double min_kept = 1, max_dependent = 0;
    for (unsigned int i = 0; i < rel.new_direction.size(); ++i)
      if (std::binary_search(rel.identified.begin(), rel.identified.end(), i))
        min_kept = std::min(min_kept, rel.new_direction[i]);
      else
        max_dependent = std::max(max_dependent, rel.new_direction[i]);
    EXPECT_GT(min_kept, 1e-4) << robot;
    EXPECT_LT(max_dependent, 1e-12) << robot;
    // Reasons: the base cancels in relative poses; the slide along the last axis is a hand-eye translation.
    for (const auto &u : rel.unidentifiable) {
      if (u.name.rfind("base.", 0) == 0 || u.name.rfind("j1.", 0) == 0)
        EXPECT_NE(u.reason.find("no effect on relative poses"), std::string::npos) << u.name;
      if (u.name == "j6.tz")
        EXPECT_NE(u.reason.find("eMc.tz"), std::string::npos) << u.reason;
    }
  }
}

TEST(Identification, FixedParametersAreReportedAsSuch)
{
  const vpSelfCalibSimulator sim = makeSim("puma560", 2);
  const std::vector<vpColVector> q = sim.generateConfigurations(12);
  vpKinematicIdentification::Options o;
  o.fixed = {"eMc.tx"};
  const auto a = vpKinematicIdentification::analyse(sim.getNominalChain(), exactMeasurements(sim.getTrueChain(), q, true), o);
  // eMc.tx has dependent twins (a shift of the last axis), one of which takes its place.
  EXPECT_EQ(a.rank, 24u);
  EXPECT_EQ(std::count(a.identified.begin(), a.identified.end(), sim.getNominalChain().getParameterIndex("eMc.tx")), 0);
  bool found = false;
  for (const auto &u : a.unidentifiable)
    found = found || (u.name == "eMc.tx" && u.reason == "fixed by the caller");
  EXPECT_TRUE(found);
  o.fixed = {"eMc.qq"};
  EXPECT_THROW(vpKinematicIdentification::analyse(sim.getNominalChain(), exactMeasurements(sim.getTrueChain(), q, true), o),
               vpSelfCalibException);
}

// The analytic Jacobian of the weighted residual against central differences, relative and
// absolute, at a non-zero parameter value (the true chain) where the residual is not zero.
TEST(Identification, JacobianMatchesFiniteDifferences)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 3);
  const std::vector<vpColVector> q = sim.generateConfigurations(4);
  for (bool relative : {true, false}) {
    const Measurements ms = exactMeasurements(sim.getNominalChain(), q, relative, 1e-3);
    const vpKinematicChain &at = sim.getTrueChain();
    const vpMatrix J = vpKinematicIdentification::jacobian(at, ms);
    const double h = 1e-6;
    for (size_t i = 0; i < ms.size(); ++i)
      for (unsigned int c = 0; c < at.getNumParameters(); ++c) {
        vpKinematicChain plus = at, minus = at;
        vpColVector p = at.getParameters();
        p[c] += h;
        plus.setParameters(p);
        p[c] -= 2 * h;
        minus.setParameters(p);
        const vpColVector fd = (vpKinematicIdentification::residual(plus, ms[i]) -
                                vpKinematicIdentification::residual(minus, ms[i])) / (2 * h);
        for (unsigned int r = 0; r < 6; ++r)
          EXPECT_NEAR(J[static_cast<unsigned int>(6 * i + r)][c], fd[r], 1e-5 * std::max(1.0, std::fabs(fd[r])))
              << (relative ? "relative " : "absolute ") << i << " row " << r << " col " << c;
      }
  }
}

// Noise-free relative poses with the true scale (oracle): the identified model predicts every
// relative pose of the true arm, at configurations it never saw, to 1e-8.
TEST(Identification, NoiseFreeOracleScaleRecoversIdentifiableCombinations)
{
  for (const std::string robot : {"puma560", "viper850"}) {
    const vpSelfCalibSimulator sim = makeSim(robot, 4);
    const std::vector<vpColVector> q = sim.generateConfigurations(15);
    const auto r = vpKinematicIdentification::identify(sim.getNominalChain(), exactMeasurements(sim.getTrueChain(), q, true),
                                                       vpKinematicIdentification::Options());
    ASSERT_EQ(r.status, vpKinematicIdentification::OK) << r.message;
    EXPECT_LT(r.rms_position, 1e-10);
    EXPECT_LT(r.rms_rotation, 1e-10);
    const std::vector<vpColVector> qv = sim.generateConfigurations(25);
    for (size_t i = 1; i < qv.size(); ++i) {
      const vpHomogeneousMatrix pred = r.chain.get_fMc(qv[i]).inverse() * r.chain.get_fMc(qv[0]);
      const vpHomogeneousMatrix truth = sim.getTrueChain().get_fMc(qv[i]).inverse() * sim.getTrueChain().get_fMc(qv[0]);
      EXPECT_LT(translationDistance(pred, truth), 1e-8) << robot << " " << i;
      EXPECT_LT(rotationDistance(pred, truth), 1e-8) << robot << " " << i;
    }
  }
}

// Measurements with Gaussian noise of the stated sd: over 50 seeds the spread of every identified
// parameter agrees with its predicted sd (average ratio within 20%, each within the sampling range).
TEST(Identification, PredictedStandardDeviationsMatchTheSpreadOver50Seeds)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 5);
  const std::vector<vpColVector> q = sim.generateConfigurations(15);
  const double sd = 2e-4;
  const Measurements exact = exactMeasurements(sim.getTrueChain(), q, true, sd);
  std::vector<unsigned int> ids;
  vpColVector predicted, sum, sum2;
  const int runs = 50;
  for (int s = 0; s < runs; ++s) {
    Random rng(100 + s);
    Measurements ms = exact;
    for (auto &m : ms) {
      Rigid M = rigidFromVisp(m.M);
      const Eigen::Vector3d dr(rng.normal(sd), rng.normal(sd), rng.normal(sd));
      M.R = expSO3(dr) * M.R;
      M.t += Eigen::Vector3d(rng.normal(sd), rng.normal(sd), rng.normal(sd));
      m.M = toVisp(M);
    }
    const auto r = vpKinematicIdentification::identify(sim.getNominalChain(), ms, vpKinematicIdentification::Options());
    ASSERT_EQ(r.status, vpKinematicIdentification::OK) << r.message;
    if (s == 0) {
      ids = r.identifiability.identified;
      predicted = r.sd;
      sum.resize(r.sd.size());
      sum2.resize(r.sd.size());
    }
    ASSERT_EQ(r.identifiability.identified, ids);
    for (unsigned int k : ids) {
      sum[k] += r.chain.getParameters()[k];
      sum2[k] += r.chain.getParameters()[k] * r.chain.getParameters()[k];
    }
    EXPECT_GT(r.sigma0, 0.6);
    EXPECT_LT(r.sigma0, 1.4);
  }
  double ratio_sum = 0;
  for (unsigned int k : ids) {
    const double mean = sum[k] / runs;
    const double emp = std::sqrt((sum2[k] - runs * mean * mean) / (runs - 1));
    const double ratio = emp / predicted[k];
    ratio_sum += ratio;
    // One sample SD of 50 draws: relative standard error 10%; 0.6-1.4 is 4 of them.
    EXPECT_GT(ratio, 0.6) << k;
    EXPECT_LT(ratio, 1.4) << k;
  }
  const double mean_ratio = ratio_sum / ids.size();
  EXPECT_GT(mean_ratio, 0.8);
  EXPECT_LT(mean_ratio, 1.2);
}

TEST(Identification, BadInputsGiveAStatusOrAnError)
{
  const vpSelfCalibSimulator sim = makeSim("puma560", 6);
  const std::vector<vpColVector> q = sim.generateConfigurations(15);
  const vpKinematicIdentification::Options o;
  // 6 m <= n: 4 relative measurements (24 equations) for 24 identifiable parameters.
  const std::vector<vpColVector> q5(q.begin(), q.begin() + 5);
  auto r = vpKinematicIdentification::identify(sim.getNominalChain(), exactMeasurements(sim.getTrueChain(), q5, true), o);
  EXPECT_EQ(r.status, vpKinematicIdentification::TOO_FEW_MEASUREMENTS) << r.message;
  EXPECT_NE(r.message.find("6 m > n"), std::string::npos);
  // All configurations equal.
  const std::vector<vpColVector> same(10, q[0]);
  r = vpKinematicIdentification::identify(sim.getNominalChain(), exactMeasurements(sim.getTrueChain(), same, true), o);
  EXPECT_EQ(r.status, vpKinematicIdentification::RANK_DEFICIENT);
  // Caller mistakes.
  Measurements ms = exactMeasurements(sim.getTrueChain(), q, true);
  Measurements bad = ms;
  bad[2].q.resize(5);
  EXPECT_THROW(vpKinematicIdentification::identify(sim.getNominalChain(), bad, o), vpSelfCalibException);
  bad = ms;
  bad[1].sd_position = 0;
  EXPECT_THROW(vpKinematicIdentification::identify(sim.getNominalChain(), bad, o), vpSelfCalibException);
  bad = ms;
  bad[0].M[0][3] = NAN;
  EXPECT_THROW(vpKinematicIdentification::identify(sim.getNominalChain(), bad, o), vpSelfCalibException);
  EXPECT_THROW(vpKinematicIdentification::identify(sim.getNominalChain(), Measurements(), o), vpSelfCalibException);
}

// Hand-computed: singular values 4, 2, 1 over m = 2 configurations.
TEST(Observability, IndicesOnAHandComputedCase)
{
  const vpObservabilityIndices o = vpObservabilityIndices::fromSingularValues({1, 4, 2}, 2);
  EXPECT_NEAR(o.O1, 2.0 / std::sqrt(2.0), 1e-15); // (4*2*1)^(1/3) / sqrt(2)
  EXPECT_NEAR(o.O2, 0.25, 1e-15);
  EXPECT_NEAR(o.O3, 1.0, 1e-15);
  EXPECT_NEAR(o.O4, 0.25, 1e-15);                   // 1^2 / 4
  EXPECT_NEAR(o.O5, 1.0 / 1.75, 1e-15);             // 1 / (1/4 + 1/2 + 1)
  EXPECT_NEAR(o.condition_number, 4.0, 1e-15);
  // The same from a Jacobian with those singular values (rotated rows).
  vpMatrix J(4, 3);
  J[0][0] = 4;
  J[1][1] = 2;
  J[2][2] = 1;
  const double c = std::cos(0.3), s = std::sin(0.3);
  vpMatrix G(4, 4);
  G.eye();
  G[0][0] = c;
  G[0][3] = -s;
  G[3][0] = s;
  G[3][3] = c;
  const vpObservabilityIndices oj = vpObservabilityIndices::fromJacobian(G * J, 2);
  EXPECT_NEAR(oj.O5, o.O5, 1e-12);
  EXPECT_NEAR(oj.condition_number, 4.0, 1e-12);
  // A zero singular value: unobservable.
  const vpObservabilityIndices z = vpObservabilityIndices::fromSingularValues({3, 0}, 1);
  EXPECT_TRUE(std::isinf(z.condition_number));
  EXPECT_EQ(z.O1, 0.0);
  EXPECT_EQ(z.O3, 0.0);
  EXPECT_EQ(z.O5, 0.0);
  EXPECT_THROW(vpObservabilityIndices::fromSingularValues({}, 1), vpSelfCalibException);
  EXPECT_THROW(vpObservabilityIndices::fromSingularValues({1, -1}, 1), vpSelfCalibException);
}

// Eq. 21 ratios of the true chain are the true ratios; the yardstick from exact two-view poses
// (unit t) gives the true |T_1| exactly, from one view or from many.
TEST(Scale, NominalRatiosAndYardstickAreExactOnExactData)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 7);
  const std::vector<vpColVector> q = sim.generateConfigurations(8);
  const vpKinematicChain &truth = sim.getTrueChain();
  const std::vector<double> r = vpPoseScale::nominalRatios(truth, q);
  ASSERT_EQ(r.size(), 7u);
  const double T1 = translationDistance(truth.get_fMc(q[1]).inverse() * truth.get_fMc(q[0]), vpHomogeneousMatrix());
  const vpCameraParameters cam = sim.getCamera();
  const vpSelfCalibDataset::Yardstick ys = sim.getYardstick();
  std::vector<vpPoseScale::YardstickView> views;
  for (size_t i = 1; i < q.size(); ++i) {
    const vpHomogeneousMatrix M = truth.get_fMc(q[i]).inverse() * truth.get_fMc(q[0]);
    EXPECT_NEAR(r[i - 1], translationDistance(M, vpHomogeneousMatrix()) / T1, 1e-12);
    vpPoseScale::YardstickView v;
    v.c2Mc1 = M;
    vpColVector t = M.getTranslationVector();
    for (unsigned int k = 0; k < 3; ++k)
      v.c2Mc1[k][3] = t[k] / t.frobeniusNorm();
    v.ratio = r[i - 1];
    const auto o0 = sim.observe(q[0], 0, 0.0), oi = sim.observe(q[i], static_cast<unsigned int>(i), 0.0);
    for (const auto &o : o0) {
      if (o.id == ys.id_a) v.a1 = o.ip;
      if (o.id == ys.id_b) v.b1 = o.ip;
    }
    for (const auto &o : oi) {
      if (o.id == ys.id_a) v.a2 = o.ip;
      if (o.id == ys.id_b) v.b2 = o.ip;
    }
    views.push_back(v);
  }
  const auto one = vpPoseScale::yardstick({views[0]}, ys.length, cam.get_px(), cam.get_u0(), cam.get_v0(), 1.0, vpPoseScale::YardstickOptions(), vpSelfCalibNoiseModel());
  ASSERT_EQ(one.status, vpPoseScale::OK) << one.message;
  EXPECT_NEAR(one.scale, T1, 1e-9);
  const auto all = vpPoseScale::yardstick(views, ys.length, cam.get_px(), cam.get_u0(), cam.get_v0(), 1.0, vpPoseScale::YardstickOptions(), vpSelfCalibNoiseModel());
  ASSERT_EQ(all.status, vpPoseScale::OK) << all.message;
  EXPECT_NEAR(all.scale, T1, 1e-9);
  // Weighted (default): the sd is predicted from the stated pixel noise, not from the (zero) residuals.
  EXPECT_GT(all.predicted_sd, 0);
  EXPECT_NEAR(all.sd, all.predicted_sd, 1e-12);
  // The paper's plain least squares: sd from the residuals, zero here.
  vpPoseScale::YardstickOptions plain;
  plain.weighted = false;
  const auto unweighted = vpPoseScale::yardstick(views, ys.length, cam.get_px(), cam.get_u0(), cam.get_v0(), 1.0, plain, vpSelfCalibNoiseModel());
  EXPECT_NEAR(unweighted.scale, T1, 1e-9);
  EXPECT_LT(unweighted.sd, 1e-9);
  // No view: a status; nonsense: an exception.
  EXPECT_EQ(vpPoseScale::yardstick({}, 0.1, 1500, 320, 240, 1, vpPoseScale::YardstickOptions(), vpSelfCalibNoiseModel()).status, vpPoseScale::TOO_FEW_VIEWS);
  EXPECT_THROW(vpPoseScale::yardstick(views, -1, 1500, 320, 240, 1, vpPoseScale::YardstickOptions(), vpSelfCalibNoiseModel()), vpSelfCalibException);
  EXPECT_THROW(vpPoseScale::nominalRatios(truth, {q[0]}), vpSelfCalibException);
}
