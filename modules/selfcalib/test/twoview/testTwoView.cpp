/*
 * Tests of the two-view layer against ground truth.
 */
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include <opencv2/calib3d.hpp>

#include <visp3/selfcalib/vpFactorMethod.h>
#include <visp3/selfcalib/vpFocalFromFundamental.h>
#include <visp3/selfcalib/vpFundamentalMatrix.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>
#include <visp3/selfcalib/vpTwoViewEstimator.h>

#include "core/vpSelfCalibMath.h"
#include "core/vpSelfCalibRandom.h"

using namespace vpSelfCalib;

namespace
{
const double kF = 1500, kU0 = 320, kV0 = 240;

struct PairData {
  vpHomogeneousMatrix c2Mc1; // truth, |t| arbitrary
  std::vector<vpImagePoint> p1, p2;
};

vpImagePoint project(const Eigen::Vector3d &X)
{
  vpImagePoint ip;
  ip.set_uv(kU0 + kF * X.x() / X.z(), kV0 + kF * X.y() / X.z());
  return ip;
}

// Camera frame at centre c looking at target (z towards it), x from the y axis rolled by roll.
Rigid lookAt(const Eigen::Vector3d &c, const Eigen::Vector3d &target, double roll)
{
  const Eigen::Vector3d z = (target - c).normalized();
  const Eigen::Vector3d x = Eigen::AngleAxisd(roll, z) * Eigen::Vector3d::UnitY().cross(z).normalized();
  Rigid M;
  M.R.col(0) = x;
  M.R.col(1) = z.cross(x);
  M.R.col(2) = z;
  M.t = c;
  return M;
}

// Random general pair: points in a cloud 2.5-3.5 in front of camera 1; camera 2 displaced by up to
// (1, 0.6, 0.3) and aimed at a random point near the cloud centre (off camera 1's axis, so the axes
// do not meet), with a random roll. Points are kept when inside both images.
// planar: all points on one plane; pure_rotation: camera 2 at camera 1's centre.
PairData makePair(Random &rng, unsigned int n, double noise, bool planar = false, bool pure_rotation = false)
{
  PairData d;
  const Eigen::Vector3d c2 = pure_rotation ? Eigen::Vector3d::Zero()
                                           : Eigen::Vector3d(rng.uniform(-1, 1), rng.uniform(-0.6, 0.6), rng.uniform(-0.3, 0.3));
  const Eigen::Vector3d target(rng.uniform(0.1, 0.3) * (rng.uniform() < 0.5 ? -1 : 1), rng.uniform(-0.3, 0.3), 3);
  const Rigid M = lookAt(c2, target, rng.uniform(-0.5, 0.5)).inverse();
  d.c2Mc1 = toVisp(M);
  const Eigen::Vector3d normal = Eigen::Vector3d(rng.normal(0.2), rng.normal(0.2), 1).normalized();
  for (int attempts = 0; d.p1.size() < n && attempts < 100000; ++attempts) {
    const double x1 = rng.uniform(-0.2, 0.2), y1 = rng.uniform(-0.15, 0.15);
    double depth = rng.uniform(2.5, 3.5);
    if (planar) // plane normal . X = 3
      depth = 3.0 / normal.dot(Eigen::Vector3d(x1, y1, 1));
    const Eigen::Vector3d X1(x1 * depth, y1 * depth, depth);
    const Eigen::Vector3d X2 = M * X1;
    if (X2.z() < 0.5)
      continue;
    vpImagePoint a = project(X1), b = project(X2);
    if (b.get_u() < 0 || b.get_u() > 639 || b.get_v() < 0 || b.get_v() > 479)
      continue;
    a.set_uv(a.get_u() + rng.normal(noise), a.get_v() + rng.normal(noise));
    b.set_uv(b.get_u() + rng.normal(noise), b.get_v() + rng.normal(noise));
    d.p1.push_back(a);
    d.p2.push_back(b);
  }
  EXPECT_EQ(d.p1.size(), n) << "test data generator could not place the points";
  return d;
}

vpTwoViewEstimator::Options options(vpRefinedFactorMethod::FocalMode mode, double f_guess = kF)
{
  vpTwoViewEstimator::Options o;
  o.focal_mode = mode;
  o.fx = f_guess;
  o.u0 = kU0;
  o.v0 = kV0;
  return o;
}

double rotationError(const vpHomogeneousMatrix &A, const vpHomogeneousMatrix &B)
{
  return logSO3(rigidFromVisp(A).R.transpose() * rigidFromVisp(B).R).norm();
}

double directionError(const vpHomogeneousMatrix &A, const vpHomogeneousMatrix &B)
{
  const Eigen::Vector3d a = rigidFromVisp(A).t.normalized(), b = rigidFromVisp(B).t.normalized();
  return std::atan2(a.cross(b).norm(), a.dot(b));
}
} // namespace

TEST(TwoView, EightPointIsExactOnNoiseFreeData)
{
  Random rng(1);
  for (int k = 0; k < 20; ++k) {
    const PairData d = makePair(rng, 8 + k, 0.0);
    vpMatrix F;
    ASSERT_TRUE(vpFundamentalMatrix::eightPoint(d.p1, d.p2, F));
    for (size_t i = 0; i < d.p1.size(); ++i)
      EXPECT_LT(vpFundamentalMatrix::sampsonDistance(F, d.p1[i], d.p2[i]), 1e-8);
  }
}

TEST(TwoView, NoiseFreeExactRecoveryOverManyRandomPoses)
{
  Random rng(2);
  for (int k = 0; k < 30; ++k) {
    const PairData d = makePair(rng, 60, 0.0);
    for (auto mode : {vpRefinedFactorMethod::PER_PAIR, vpRefinedFactorMethod::KNOWN}) {
      const vpTwoViewEstimator::Result r = vpTwoViewEstimator::estimate(d.p1, d.p2, options(mode, 1400));
      ASSERT_EQ(r.status, vpTwoViewEstimator::OK) << r.message;
      if (mode == vpRefinedFactorMethod::KNOWN)
        continue; // f known at a wrong value (1400) is not exact by design; checked below with 1500
      EXPECT_LT(rotationError(r.c2Mc1, d.c2Mc1), 1e-9) << "pose " << k;
      EXPECT_LT(directionError(r.c2Mc1, d.c2Mc1), 1e-9) << "pose " << k;
      EXPECT_NEAR(r.fx, kF, 1e-6) << "pose " << k;
      EXPECT_EQ(r.num_inliers, 60u);
    }
    const vpTwoViewEstimator::Result r = vpTwoViewEstimator::estimate(d.p1, d.p2, options(vpRefinedFactorMethod::KNOWN));
    EXPECT_LT(rotationError(r.c2Mc1, d.c2Mc1), 1e-9);
    EXPECT_LT(directionError(r.c2Mc1, d.c2Mc1), 1e-9);
  }
}

// The epipolar distance is even in t: a refinement that ends at -t must be turned back by
// cheirality. Started at the true rotation with t negated, the result must have the true t.
TEST(TwoView, RefinementKeepsTheCheiralSignOfT)
{
  Random rng(5);
  for (int k = 0; k < 10; ++k) {
    const PairData d = makePair(rng, 60, 0.0);
    vpHomogeneousMatrix start = d.c2Mc1;
    vpColVector t = d.c2Mc1.getTranslationVector();
    t.normalize();
    for (unsigned int i = 0; i < 3; ++i)
      start[i][3] = -t[i];
    vpRefinedFactorMethod::Options ro;
    ro.focal_mode = vpRefinedFactorMethod::KNOWN;
    ro.u0 = kU0;
    ro.v0 = kV0;
    const vpRefinedFactorMethod::Result r = vpRefinedFactorMethod::refine({{d.p1, d.p2, start}}, kF, ro);
    ASSERT_TRUE(r.converged) << r.message;
    EXPECT_LT(directionError(r.c2Mc1[0], d.c2Mc1), 1e-9) << "pose " << k;
    EXPECT_LT(rotationError(r.c2Mc1[0], d.c2Mc1), 1e-9) << "pose " << k;
  }
}

TEST(TwoView, FactorMethodAndFocalAreExactWithoutRefinement)
{
  Random rng(3);
  const PairData d = makePair(rng, 40, 0.0);
  vpMatrix F;
  ASSERT_TRUE(vpFundamentalMatrix::eightPoint(d.p1, d.p2, F));
  const vpFocalFromFundamental::Result f = vpFocalFromFundamental::estimate(F, kU0, kV0, 1.0, 640);
  ASSERT_EQ(f.status, vpFocalFromFundamental::OK) << f.message;
  EXPECT_NEAR(f.fx, kF, 1e-4);
  const vpFactorMethod::Result fm = vpFactorMethod::estimate(F, kF, kU0, kV0, 1.0, d.p1, d.p2);
  EXPECT_EQ(fm.num_in_front, 40u);
  EXPECT_LT(rotationError(fm.c2Mc1, d.c2Mc1), 1e-7);
  EXPECT_LT(directionError(fm.c2Mc1, d.c2Mc1), 1e-7);
}

// Noisy data over several seeds: the error in f is consistent with the predicted standard deviation.
// Of the 40 seeds, the pairs that determine f (28; the others are reported FOCAL_UNOBSERVABLE) each
// fall outside 3 sd with probability p = 0.0027 when the sd is right, so the number outside is
// binomial(n, p): P(2 or more outside) = 1 - (1-p)^n - n p (1-p)^(n-1) = 0.0026 for n = 28, and the
// test allows at most 1 (measured: 0 outside; the largest |error| / sd is 2.64, the mean of
// (error / sd)^2 is 1.6, i.e. the sd is about 25 % optimistic at 0.5 px, well inside the 3-sd bound).
// With this narrow field of view
// (+-12 deg) and f self-calibrated, rotation, translation direction and f are strongly coupled, so
// rotation only gets a gross-error check.
TEST(TwoView, NoisyRecoveryWithinPredictedBounds)
{
  unsigned int within = 0, total = 0;
  for (uint64_t seed = 10; seed < 50; ++seed) {
    Random rng(seed);
    const PairData d = makePair(rng, 100, 0.5);
    const vpTwoViewEstimator::Result r =
        vpTwoViewEstimator::estimate(d.p1, d.p2, options(vpRefinedFactorMethod::PER_PAIR, 1200));
    // A pair whose optical axes nearly meet is reported instead of returning a poor focal length:
    // either the closed form fails (fx = 0) or the refined f has sd above 5% of f.
    if (r.status == vpTwoViewEstimator::FOCAL_UNOBSERVABLE) {
      EXPECT_TRUE(r.fx == 0 || r.fx_sd > 0.05 * r.fx) << r.message;
      continue;
    }
    ASSERT_EQ(r.status, vpTwoViewEstimator::OK) << r.message;
    ++total;
    within += std::fabs(r.fx - kF) < 3 * r.fx_sd;
    EXPECT_GT(r.fx_sd, 0.0);
    EXPECT_LT(rotationError(r.c2Mc1, d.c2Mc1), 0.05);
    // Symmetric distance: two point-line distances, each with the noise of at least one point and at
    // most both: RMS between sigma and 2 sigma (plus sampling spread); the 1 px inlier threshold
    // trims the tails.
    EXPECT_GT(r.rms, 0.5);
    EXPECT_LT(r.rms, 2.2 * 0.5);
  }
  EXPECT_GE(total, 20u);
  EXPECT_LE(total - within, 1u) << within << " of " << total << " pairs within 3 sd";
}

TEST(TwoView, ThirtyPercentOutliers)
{
  // Over 8 seeds: RANSAC rejects the outliers and the mean rotation error stays within 2x of the
  // same pairs without outliers (70 of 100 points remain: about 1.2x expected).
  double err_out = 0, err_clean = 0;
  for (uint64_t seed = 100; seed < 108; ++seed) {
    Random rng(seed);
    PairData d = makePair(rng, 100, 0.2);
    const PairData clean = d;
    std::vector<bool> outlier(d.p1.size(), false);
    for (size_t i = 0; i < d.p1.size(); i += 10)
      for (size_t j = i; j < i + 3; ++j) { // 3 of every 10
        d.p2[j].set_uv(rng.uniform(0, 639), rng.uniform(0, 479));
        outlier[j] = true;
      }
    const vpTwoViewEstimator::Result r = vpTwoViewEstimator::estimate(d.p1, d.p2, options(vpRefinedFactorMethod::KNOWN));
    ASSERT_EQ(r.status, vpTwoViewEstimator::OK) << r.message;
    unsigned int caught = 0;
    for (size_t i = 0; i < outlier.size(); ++i)
      caught += outlier[i] && !r.inliers[i];
    EXPECT_GE(caught, 28u); // a random pixel may land within 1 px of its epipolar line
    const vpTwoViewEstimator::Result rc =
        vpTwoViewEstimator::estimate(clean.p1, clean.p2, options(vpRefinedFactorMethod::KNOWN));
    err_out += rotationError(r.c2Mc1, d.c2Mc1);
    err_clean += rotationError(rc.c2Mc1, d.c2Mc1);
  }
  EXPECT_LT(err_out, 2 * err_clean);
}

TEST(TwoView, PureRotationIsReported)
{
  Random rng(4);
  const PairData d = makePair(rng, 50, 0.1, false, true);
  const vpTwoViewEstimator::Result r = vpTwoViewEstimator::estimate(d.p1, d.p2, options(vpRefinedFactorMethod::KNOWN));
  EXPECT_EQ(r.status, vpTwoViewEstimator::PURE_ROTATION) << r.message;
  EXPECT_LT(rotationError(r.c2Mc1, d.c2Mc1), 1e-3);
}

TEST(TwoView, PlanarSceneIsReportedAndThePoseStillRecoveredWithKnownFocal)
{
  Random rng(5);
  for (int k = 0; k < 5; ++k) {
    const PairData d = makePair(rng, 80, 0.0, true);
    const vpTwoViewEstimator::Result known =
        vpTwoViewEstimator::estimate(d.p1, d.p2, options(vpRefinedFactorMethod::KNOWN));
    EXPECT_EQ(known.status, vpTwoViewEstimator::PLANAR) << known.message;
    EXPECT_TRUE(known.hasPose());
    EXPECT_LT(rotationError(known.c2Mc1, d.c2Mc1), 1e-6);
    EXPECT_LT(directionError(known.c2Mc1, d.c2Mc1), 1e-6);
    const vpTwoViewEstimator::Result self =
        vpTwoViewEstimator::estimate(d.p1, d.p2, options(vpRefinedFactorMethod::PER_PAIR));
    EXPECT_EQ(self.status, vpTwoViewEstimator::PLANAR);
    EXPECT_FALSE(self.hasPose());
  }
}

TEST(TwoView, TooFewCoincidentAndNonFinitePoints)
{
  Random rng(6);
  const PairData d = makePair(rng, 7, 0.0);
  EXPECT_EQ(vpTwoViewEstimator::estimate(d.p1, d.p2, options(vpRefinedFactorMethod::KNOWN)).status,
            vpTwoViewEstimator::TOO_FEW_POINTS);
  std::vector<vpImagePoint> same(20, d.p1[0]), same2(20, d.p2[0]);
  EXPECT_EQ(vpTwoViewEstimator::estimate(same, same2, options(vpRefinedFactorMethod::KNOWN)).status,
            vpTwoViewEstimator::TOO_FEW_POINTS);
  PairData e = makePair(rng, 20, 0.0);
  e.p2[3].set_u(std::nan(""));
  EXPECT_THROW(vpTwoViewEstimator::estimate(e.p1, e.p2, options(vpRefinedFactorMethod::KNOWN)), vpSelfCalibException);
  e.p2.pop_back();
  EXPECT_THROW(vpTwoViewEstimator::estimate(e.p1, e.p2, options(vpRefinedFactorMethod::KNOWN)), vpSelfCalibException);
  vpTwoViewEstimator::Options bad = options(vpRefinedFactorMethod::KNOWN);
  bad.fx = -1;
  EXPECT_THROW(vpTwoViewEstimator::estimate(d.p1, d.p2, bad), vpSelfCalibException);
}

// Camera 2 looks at a point of camera 1's optical axis: the axes meet and f is not observable.
TEST(TwoView, ConvergingOpticalAxesMakeTheFocalUnobservable)
{
  Random rng(7);
  // Camera 2 at (0.8, 0, 0) in camera-1 coordinates, looking at (0, 0, 3) on camera 1's axis.
  const Eigen::Vector3d c2(0.8, 0.1, 0.2), target(0, 0, 3);
  const Rigid M = lookAt(c2, target, 0.0).inverse();
  std::vector<vpImagePoint> p1, p2;
  while (p1.size() < 60) {
    const Eigen::Vector3d X = target + Eigen::Vector3d(rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3));
    p1.push_back(project(X));
    p2.push_back(project(M * X));
  }
  const vpTwoViewEstimator::Result r = vpTwoViewEstimator::estimate(p1, p2, options(vpRefinedFactorMethod::PER_PAIR));
  EXPECT_EQ(r.status, vpTwoViewEstimator::FOCAL_UNOBSERVABLE) << r.message;
  EXPECT_EQ(r.fx, 0.0);
  EXPECT_NE(r.message.find("optical axes"), std::string::npos);
}

// The reference scenario: every view looks at the same object, so each pair (first, i) alone is
// nearly degenerate for f. One focal length shared by the 24 pairs converges and its error is
// consistent with its predicted standard deviation. Measured with seed 3 at 0.2 px: sd about 11 px.
// Even the Cramer-Rao bound of f from all 25 views jointly is about 7 px here (bench-twoview), so
// no estimator reaches 1 px on this scenario; see the README.
TEST(TwoView, SharedFocalOnTheReferenceScenario)
{
  vpSelfCalibSimulator::Options so;
  so.seed = 3;
  so.pixel_noise_sd = 0.2;
  const vpSelfCalibSimulator sim(vpKinematicChain::preset("viper850"), so);
  const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(25));
  std::vector<std::vector<vpImagePoint>> a, b;
  // Correspondences by point id (a view lists the points it sees, in no promised order).
  for (size_t k = 1; k < ds.views.size(); ++k) {
    a.emplace_back();
    b.emplace_back();
    std::map<int, vpImagePoint> in_k;
    for (const auto &o : ds.views[k].points)
      in_k[o.id] = o.ip;
    for (const auto &o : ds.views[0].points) {
      const auto it = in_k.find(o.id);
      if (it != in_k.end()) {
        a.back().push_back(o.ip);
        b.back().push_back(it->second);
      }
    }
    ASSERT_GE(a.back().size(), 8u) << "view " << k;
  }
  const vpTwoViewEstimator::SharedResult r = vpTwoViewEstimator::estimateShared(a, b, options(vpRefinedFactorMethod::PER_PAIR, 1300));
  ASSERT_TRUE(r.converged) << r.message;
  EXPECT_GT(r.fx_sd, 0.0);
  EXPECT_LT(std::fabs(r.fx - kF), 4 * r.fx_sd) << "fx " << r.fx << " sd " << r.fx_sd;
  for (size_t k = 0; k < r.pairs.size(); ++k) {
    EXPECT_EQ(r.pairs[k].status, vpTwoViewEstimator::OK);
    const vpHomogeneousMatrix truth =
        sim.getTrueChain().get_fMc(ds.views[k + 1].q).inverse() * sim.getTrueChain().get_fMc(ds.views[0].q);
    EXPECT_LT(rotationError(r.pairs[k].c2Mc1, truth), 0.05);
  }
  // With f known, on the same pairs, the refined factor method is at least as accurate on average as
  // OpenCV's five-point solver (findEssentialMat + recoverPose). Both are far from the noise-free
  // answer here: a small, distant object makes two-view rotation ill-conditioned (seed 3, 0.2 px:
  // about 10 mrad mean for ours, 38 mrad for OpenCV).
  double ours = 0, opencv = 0;
  const cv::Mat K = (cv::Mat_<double>(3, 3) << kF, 0, kU0, 0, kF, kV0, 0, 0, 1);
  for (size_t k = 0; k < a.size(); ++k) {
    const vpTwoViewEstimator::Result rk = vpTwoViewEstimator::estimate(a[k], b[k], options(vpRefinedFactorMethod::KNOWN));
    ASSERT_EQ(rk.status, vpTwoViewEstimator::OK) << rk.message;
    const vpHomogeneousMatrix truth =
        sim.getTrueChain().get_fMc(ds.views[k + 1].q).inverse() * sim.getTrueChain().get_fMc(ds.views[0].q);
    ours += rotationError(rk.c2Mc1, truth);
    std::vector<cv::Point2d> ca, cb;
    for (size_t i = 0; i < a[k].size(); ++i) {
      ca.emplace_back(a[k][i].get_u(), a[k][i].get_v());
      cb.emplace_back(b[k][i].get_u(), b[k][i].get_v());
    }
    cv::Mat mask, R, t;
    const cv::Mat E = cv::findEssentialMat(ca, cb, K, cv::RANSAC, 0.999, 1.0, mask);
    cv::recoverPose(E(cv::Rect(0, 0, 3, 3)), ca, cb, K, R, t, mask);
    Rigid M;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        M.R(i, j) = R.at<double>(i, j);
    opencv += rotationError(toVisp(M), truth);
  }
  EXPECT_LE(ours, opencv);
  EXPECT_LT(ours / a.size(), 0.03);
}
