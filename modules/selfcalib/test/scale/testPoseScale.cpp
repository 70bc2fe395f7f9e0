/*
 * Tests of the yardstick scale weighted by each pair's expected accuracy, of the two-view covariance
 * it uses, and of the expected error of the eq. 21 ratios (vpPoseScale).
 */
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <map>

#include <Eigen/Dense>

#include <visp3/selfcalib/vpPoseScale.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>
#include <visp3/selfcalib/vpTwoViewEstimator.h>

namespace
{
double tNorm(const vpKinematicChain &c, const vpColVector &qi, const vpColVector &q0)
{
  return (c.get_fMc(qi).inverse() * c.get_fMc(q0)).getTranslationVector().frobeniusNorm();
}

vpImagePoint find(const std::vector<vpSelfCalibDataset::Observation> &obs, int id)
{
  for (const auto &o : obs)
    if (o.id == id)
      return o.ip;
  ADD_FAILURE() << "point " << id << " not seen";
  return vpImagePoint();
}

/*
  The yardstick views of pairs (0, i) on the paper scene, noise draw `trial` (views observed with the
  noise streams of index 1000 trial + k), the two-view pose from the images with f known, and the
  TRUE eq. 21 ratios (so that only the image noise is left). truth: |T_1|.
*/
std::vector<vpPoseScale::YardstickView> views(const vpSelfCalibSimulator &sim, const std::vector<vpColVector> &q,
                                              unsigned int trial, double sd, double &truth)
{
  const vpKinematicChain &T = sim.getTrueChain();
  const vpCameraParameters cam = sim.getCamera();
  const vpSelfCalibDataset::Yardstick ys = sim.getYardstick();
  truth = tNorm(T, q[1], q[0]);
  const auto o0 = sim.observe(q[0], 1000 * trial, sd);
  std::vector<vpPoseScale::YardstickView> out;
  for (size_t i = 1; i < q.size(); ++i) {
    const auto oi = sim.observe(q[i], static_cast<unsigned int>(1000 * trial + i), sd);
    std::map<int, vpImagePoint> second;
    for (const auto &o : oi)
      second[o.id] = o.ip;
    vpPoseScale::YardstickView v;
    for (const auto &o : o0)
      if (second.count(o.id)) {
        v.p1.push_back(o.ip);
        v.p2.push_back(second[o.id]);
      }
    vpTwoViewEstimator::Options to;
    to.focal_mode = vpRefinedFactorMethod::KNOWN;
    to.fx = cam.get_px();
    to.u0 = cam.get_u0();
    to.v0 = cam.get_v0();
    const vpTwoViewEstimator::Result r = vpTwoViewEstimator::estimate(v.p1, v.p2, to);
    EXPECT_EQ(r.status, vpTwoViewEstimator::OK) << r.message;
    v.c2Mc1 = r.c2Mc1;
    v.ratio = tNorm(T, q[i], q[0]) / truth;
    v.a1 = find(o0, ys.id_a);
    v.b1 = find(o0, ys.id_b);
    v.a2 = find(oi, ys.id_a);
    v.b2 = find(oi, ys.id_b);
    out.push_back(v);
  }
  return out;
}
} // namespace

// Noise-free: the scale is exact, weighted or not.
TEST(PoseScale, WeightedYardstickIsExactWithoutNoise)
{
  const vpSelfCalibSimulator sim(vpKinematicChain::preset("viper850"), vpSelfCalibSimulator::sceneOptions("paper"));
  const std::vector<vpColVector> q = sim.generateConfigurations(6);
  double truth = 0;
  const auto v = views(sim, q, 0, 0.0, truth);
  const vpCameraParameters cam = sim.getCamera();
  for (bool weighted : {true, false}) {
    vpPoseScale::YardstickOptions o;
    o.weighted = weighted;
    const auto r = vpPoseScale::yardstick(v, sim.getYardstick().length, cam.get_px(), cam.get_u0(), cam.get_v0(), 1, o, vpSelfCalibNoiseModel());
    ASSERT_EQ(r.status, vpPoseScale::OK);
    EXPECT_NEAR(r.scale / truth, 1, 1e-8) << (weighted ? "weighted" : "plain");
  }
}

// Over noise draws at 0.2 px on the paper scene: the weighted scale (joint, the default) is unbiased
// (mean error within 3 standard errors), its reported sd is honest (RMS of error / sd between 0.6
// and 1.6), and it is at least as accurate as the paper's plain least squares and as the per-pair
// combination.
TEST(PoseScale, WeightedYardstickIsUnbiasedWithAnHonestSd)
{
  const vpSelfCalibSimulator sim(vpKinematicChain::preset("viper850"), vpSelfCalibSimulator::sceneOptions("paper"));
  const std::vector<vpColVector> q = sim.generateConfigurations(8);
  const vpCameraParameters cam = sim.getCamera();
  const unsigned int trials = 30;
  double sum_z = 0, sum_z2 = 0, sq_w = 0, sq_p = 0, sq_pairs = 0;
  for (unsigned int t = 1; t <= trials; ++t) {
    double truth = 0;
    const auto v = views(sim, q, t, 0.2, truth);
    vpPoseScale::YardstickOptions o;
    const auto w = vpPoseScale::yardstick(v, sim.getYardstick().length, cam.get_px(), cam.get_u0(), cam.get_v0(), 1, o, vpSelfCalibNoiseModel());
    o.joint = false;
    const auto pw = vpPoseScale::yardstick(v, sim.getYardstick().length, cam.get_px(), cam.get_u0(), cam.get_v0(), 1, o, vpSelfCalibNoiseModel());
    sq_pairs += std::pow(pw.scale / truth - 1, 2);
    o.weighted = false;
    const auto p = vpPoseScale::yardstick(v, sim.getYardstick().length, cam.get_px(), cam.get_u0(), cam.get_v0(), 1, o, vpSelfCalibNoiseModel());
    ASSERT_EQ(w.status, vpPoseScale::OK);
    ASSERT_GT(w.sd, 0);
    ASSERT_EQ(w.relative_sd.size(), v.size());
    const double z = (w.scale - truth) / w.predicted_sd;
    sum_z += z;
    sum_z2 += z * z;
    sq_w += std::pow(w.scale / truth - 1, 2);
    sq_p += std::pow(p.scale / truth - 1, 2);
  }
  const double mean_z = sum_z / trials, rms_z = std::sqrt(sum_z2 / trials);
  EXPECT_LT(std::fabs(mean_z), 3 / std::sqrt(double(trials))) << "bias";
  EXPECT_GT(rms_z, 0.6) << "the predicted sd is too large";
  EXPECT_LT(rms_z, 1.6) << "the predicted sd is too small";
  EXPECT_LE(std::sqrt(sq_w / trials), 1.05 * std::sqrt(sq_p / trials)) << "weighted worse than plain";
  // The joint fit (default) uses the first image's ends once, not once per pair.
  EXPECT_LE(std::sqrt(sq_w / trials), 1.05 * std::sqrt(sq_pairs / trials)) << "joint worse than per pair";
  std::cout << "scale RMS error over " << trials << " draws: joint " << 100 * std::sqrt(sq_w / trials) << " %, per pair "
            << 100 * std::sqrt(sq_pairs / trials) << " %, plain " << 100 * std::sqrt(sq_p / trials)
            << " %; error / predicted sd RMS " << rms_z << "\n";
}

// The two-view covariance is the spread of the estimated pose: over noise draws, the squared
// Mahalanobis distance of the direction error averages about 2 (its 2 degrees of freedom).
TEST(PoseScale, TwoViewCovariancePredictsTheDirectionSpread)
{
  const vpSelfCalibSimulator sim(vpKinematicChain::preset("puma560"), vpSelfCalibSimulator::sceneOptions("paper"));
  const std::vector<vpColVector> q = sim.generateConfigurations(3);
  const vpCameraParameters cam = sim.getCamera();
  const vpHomogeneousMatrix T = sim.getTrueChain().get_fMc(q[2]).inverse() * sim.getTrueChain().get_fMc(q[0]);
  vpColVector t(3);
  for (unsigned int k = 0; k < 3; ++k)
    t[k] = T[k][3];
  t.normalize();
  double d2 = 0;
  const unsigned int trials = 30;
  for (unsigned int trial = 1; trial <= trials; ++trial) {
    double truth = 0;
    const auto v = views(sim, q, trial, 0.2, truth);
    const vpMatrix C = vpPoseScale::twoViewCovariance(v[1].c2Mc1, v[1].p1, v[1].p2, cam.get_px(), cam.get_u0(),
                                                      cam.get_v0(), 1, 0.2);
    ASSERT_EQ(C.getRows(), 5u);
    // Direction error in the basis (e1, e2) the covariance uses.
    vpColVector te(3);
    for (unsigned int k = 0; k < 3; ++k)
      te[k] = v[1].c2Mc1[k][3];
    te.normalize();
    const Eigen::Vector3d tt(t[0], t[1], t[2]), e(te[0], te[1], te[2]);
    const Eigen::Vector3d e1 = e.unitOrthogonal(), e2 = e.cross(e1);
    const Eigen::Vector2d d(e1.dot(tt - e), e2.dot(tt - e));
    Eigen::Matrix2d Cd;
    Cd << C[3][3], C[3][4], C[4][3], C[4][4];
    d2 += d.dot(Cd.inverse() * d);
  }
  EXPECT_GT(d2 / trials, 2 * 0.5);
  EXPECT_LT(d2 / trials, 2 * 1.8);
}

// nominalRatioSd and nominalNormSd predict the spread of the eq. 21 ratio errors and of the nominal
// norms' errors over robots drawn from the tolerance.
TEST(PoseScale, RatioSdPredictsTheModelErrorOfTheRatios)
{
  const vpSelfCalibSimulator sim(vpKinematicChain::preset("viper850"), vpSelfCalibSimulator::Options());
  const std::vector<vpColVector> q = sim.generateConfigurations(8);
  const std::vector<double> nominal = vpPoseScale::nominalRatios(sim.getNominalChain(), q);
  const std::vector<double> sd = vpPoseScale::nominalRatioSd(sim.getNominalChain(), q);
  ASSERT_EQ(sd.size(), nominal.size());
  EXPECT_EQ(sd[0], 0);
  const std::vector<double> nsd = vpPoseScale::nominalNormSd(sim.getNominalChain(), q, vpPoseScale::ModelTolerance());
  ASSERT_EQ(nsd.size(), nominal.size());
  std::vector<double> nominal_norms;
  for (size_t i = 1; i < q.size(); ++i)
    nominal_norms.push_back(tNorm(sim.getNominalChain(), q[i], q[0]));
  std::vector<double> sq(nominal.size(), 0), sqn(nominal.size(), 0);
  const unsigned int robots = 40;
  for (uint64_t seed = 1; seed <= robots; ++seed) {
    vpSelfCalibSimulator::Options o;
    o.seed = seed;
    const vpSelfCalibSimulator other(vpKinematicChain::preset("viper850"), o);
    const std::vector<double> r = vpPoseScale::nominalRatios(other.getTrueChain(), q);
    for (size_t i = 0; i < r.size(); ++i) {
      sq[i] += std::pow(std::log(r[i] / nominal[i]), 2);
      sqn[i] += std::pow(std::log(tNorm(other.getTrueChain(), q[i + 1], q[0]) / nominal_norms[i]), 2);
    }
  }
  double ratio_n = 0;
  for (size_t i = 0; i < sqn.size(); ++i)
    ratio_n += std::sqrt(sqn[i] / robots) / nsd[i];
  ratio_n /= sqn.size();
  EXPECT_GT(ratio_n, 0.7);
  EXPECT_LT(ratio_n, 1.3);
  double ratio = 0;
  for (size_t i = 1; i < sq.size(); ++i)
    ratio += std::sqrt(sq[i] / robots) / sd[i];
  ratio /= sq.size() - 1;
  EXPECT_GT(ratio, 0.7);
  EXPECT_LT(ratio, 1.3);
}

TEST(PoseScale, BadInputsThrowOrGiveAStatus)
{
  vpPoseScale::YardstickView v;
  v.c2Mc1.buildFrom(0.1, 0, 0, 0, 0.1, 0);
  v.a1.set_uv(300, 200);
  v.b1.set_uv(340, 200);
  v.a2.set_uv(290, 200);
  v.b2.set_uv(330, 200);
  v.p1 = {v.a1};
  EXPECT_THROW(vpPoseScale::yardstick({v}, 0.1, 300, 320, 240, 1, vpPoseScale::YardstickOptions(), vpSelfCalibNoiseModel()), vpSelfCalibException); // p1, p2 sizes
  v.p1.clear();
  v.ratio_sd = -1;
  EXPECT_THROW(vpPoseScale::yardstick({v}, 0.1, 300, 320, 240, 1, vpPoseScale::YardstickOptions(), vpSelfCalibNoiseModel()), vpSelfCalibException);
  v.ratio_sd = 0;
  vpPoseScale::YardstickOptions o;
  vpSelfCalibNoiseModel noise;
  noise.pixel_sd = 0;
  EXPECT_THROW(vpPoseScale::yardstick({v}, 0.1, 300, 320, 240, 1, o, noise), vpSelfCalibException);
  o.fx_sd = -1;
  EXPECT_THROW(vpPoseScale::yardstick({v}, 0.1, 300, 320, 240, 1, o, vpSelfCalibNoiseModel()), vpSelfCalibException);
  EXPECT_EQ(vpPoseScale::yardstick({}, 0.1, 300, 320, 240, 1, vpPoseScale::YardstickOptions(), vpSelfCalibNoiseModel()).status, vpPoseScale::TOO_FEW_VIEWS);
  EXPECT_EQ(vpPoseScale::twoViewCovariance(v.c2Mc1, {v.a1}, {v.a2}, 300, 320, 240, 1, 0.2).getRows(), 0u);
  EXPECT_THROW(vpPoseScale::twoViewCovariance(v.c2Mc1, {v.a1}, {}, 300, 320, 240, 1, 0.2), vpSelfCalibException);
}
