/*
 * Tests of the joint corrections' structure (pipeline/vpSelfCalibRobotErrorStructure.h): reading
 * noise against a constant offset and a per-view displacement of the camera, on corrections drawn
 * with a known structure (no adjustment: the statistic itself, on its ground truth).
 */
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

#include <Eigen/Dense>

#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "core/vpSelfCalibRandom.h"
#include "core/vpSelfCalibRobotErrorLevels.h"
#include "pipeline/vpSelfCalibRobotErrorStructure.h"

namespace
{
using Draw = std::function<vpColVector(vpSelfCalib::Random &, const vpKinematicChain &, const vpColVector &)>;

//! 15 views of the Viper850's simulated reference poses, their joint corrections drawn by `draw`.
struct Corrections {
  vpKinematicBundleAdjustment::Result b;
  std::vector<vpSelfCalibDataset::View> views;
};

Corrections corrections(uint64_t seed, const Draw &draw)
{
  vpSelfCalibSimulator::Options so;
  so.seed = seed;
  const vpSelfCalibSimulator sim(vpKinematicChain::preset("viper850"), so);
  Corrections c;
  c.b.chain = sim.getNominalChain();
  vpSelfCalib::Random rng(seed, 29);
  for (const vpColVector &q : sim.generateConfigurations(15)) {
    vpSelfCalibDataset::View v;
    v.q = q;
    c.views.push_back(v);
    c.b.joint_corrections.push_back(draw(rng, c.b.chain, q));
  }
  return c;
}

//! The joint corrections that move the camera by a 6-D displacement d (base frame, t then theta u): J^-1 d.
vpColVector jointsFor(const vpKinematicChain &chain, const vpColVector &q, const Eigen::Matrix<double, 6, 1> &d)
{
  const vpMatrix Jv = chain.getJointJacobian(q);
  Eigen::Matrix<double, 6, 6> J;
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c)
      J(r, c) = Jv[static_cast<unsigned int>(r)][static_cast<unsigned int>(c)];
  const Eigen::Matrix<double, 6, 1> dq = J.fullPivLu().solve(d);
  vpColVector out(6);
  for (unsigned int i = 0; i < 6; ++i)
    out[i] = dq[i];
  return out;
}

const double kLowCost = 0.15 * M_PI / 180.0; // a low-cost arm's backlash, beyond kJointErrorPlausible

vpSelfCalibNoiseModel measuredJoints(double sd)
{
  return vpSelfCalibNoiseModel().withJointError({sd}, vpSelfCalibNoiseModel::MEASURED);
}
} // namespace

/*
  Independent reading noise (0.15 deg on every joint of every view) is judged reading noise in every
  one of 20 draws (no offset: Student's t of the means within the 0.1 % Bonferroni bound; the
  per-view pose model is not preferred), and a measured level of that size stands
  (robotErrorImplausible() false); the same level beyond any arm's (1.5 deg) does not.
*/
TEST(RobotErrorStructure, ReadingNoiseIsReadingNoise)
{
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    const Corrections c = corrections(seed, [](vpSelfCalib::Random &rng, const vpKinematicChain &, const vpColVector &) {
      vpColVector dq(6);
      for (unsigned int i = 0; i < 6; ++i)
        dq[i] = rng.normal(kLowCost);
      return dq;
    });
    const vpSelfCalibNoiseModel n = measuredJoints(kLowCost);
    const vpSelfCalibPipeline::JointErrorStructure s = vpSelfCalibPipeline::jointErrorStructure(c.b, n, c.views);
    ASSERT_TRUE(s.judged) << seed;
    EXPECT_TRUE(s.pose_compared) << seed;
    EXPECT_TRUE(s.readingNoise()) << seed << ": " << s.describe() << " (t " << s.offset_t << ", BIC gain "
                                  << s.pose_bic_gain << ")";
    EXPECT_LT(s.pose_bic_gain, 0) << seed; // the joint model explains joint noise better
    EXPECT_FALSE(vpSelfCalibPipeline::robotErrorImplausible(n, c.b, c.views)) << seed;
    EXPECT_TRUE(vpSelfCalibPipeline::robotErrorImplausible(measuredJoints(10 * kLowCost), c.b, c.views)) << seed;
  }
}

/*
  The same noise with a constant offset of 2 sd on joint 3 (a parameter held at a wrong value): an
  offset on joint 3 in each of 10 draws, and the level is implausible.
*/
TEST(RobotErrorStructure, ConstantOffsetIsNoReadingNoise)
{
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    const Corrections c = corrections(seed, [](vpSelfCalib::Random &rng, const vpKinematicChain &, const vpColVector &) {
      vpColVector dq(6);
      for (unsigned int i = 0; i < 6; ++i)
        dq[i] = rng.normal(kLowCost) + (i == 2 ? 2 * kLowCost : 0);
      return dq;
    });
    const vpSelfCalibNoiseModel n = measuredJoints(kLowCost);
    const vpSelfCalibPipeline::JointErrorStructure s = vpSelfCalibPipeline::jointErrorStructure(c.b, n, c.views);
    EXPECT_TRUE(s.offset) << seed << ": t " << s.offset_t << " bound " << s.offset_bound;
    EXPECT_EQ(s.offset_joint, "joint 3") << seed;
    EXPECT_TRUE(vpSelfCalibPipeline::robotErrorImplausible(n, c.b, c.views)) << seed;
  }
}

/*
  Each view's camera displaced by 0.5 mm / 0.6 mrad on every axis (a rendering's displacement, a loose
  camera), the joints taking it (J^-1 d): a per-view pose error, not reading noise, in each of 10 draws,
  and a joint level beyond a well-built arm's measured from it is implausible; the same corrections
  at a level below kJointErrorPlausible are not questioned.
*/
TEST(RobotErrorStructure, PerViewDisplacementIsNoReadingNoise)
{
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    const Corrections c = corrections(seed, [](vpSelfCalib::Random &rng, const vpKinematicChain &chain, const vpColVector &q) {
      Eigen::Matrix<double, 6, 1> d;
      for (int i = 0; i < 6; ++i)
        d[i] = rng.normal(i < 3 ? 0.5e-3 : 0.6e-3);
      return jointsFor(chain, q, d);
    });
    const vpSelfCalibNoiseModel n = measuredJoints(1.35e-3);
    const vpSelfCalibPipeline::JointErrorStructure s = vpSelfCalibPipeline::jointErrorStructure(c.b, n, c.views);
    EXPECT_TRUE(s.pose_like) << seed << ": BIC gain " << s.pose_bic_gain;
    EXPECT_TRUE(vpSelfCalibPipeline::robotErrorImplausible(n, c.b, c.views)) << seed;
    EXPECT_FALSE(vpSelfCalibPipeline::robotErrorImplausible(measuredJoints(0.9e-3), c.b, c.views)) << seed;
  }
}
