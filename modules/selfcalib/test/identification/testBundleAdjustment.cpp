/*
 * Tests of vpKinematicBundleAdjustment and of the default pipeline built on it: Jacobians against
 * finite differences, exact recovery on noise-free data, covariance against the spread over noise
 * draws, wrong matches, missing yardstick, degenerate and bad input.
 */
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <visp3/selfcalib/vpKinematicBundleAdjustment.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "../testCommon.h"
#include "core/vpSelfCalibCamera.h"
#include "core/vpSelfCalibMath.h"
#include "core/vpSelfCalibRandom.h"

using namespace selfcalib_test;

using namespace vpSelfCalib;

namespace
{
void addNoise(vpSelfCalibDataset &ds, double sd, Random &rng)
{
  for (auto &v : ds.views)
    for (auto &o : v.points)
      o.ip = vpImagePoint(o.ip.get_i() + rng.normal(sd), o.ip.get_j() + rng.normal(sd));
}

std::vector<vpSelfCalibDataset::View> slice(const vpSelfCalibDataset &ds, size_t a, size_t b)
{
  return std::vector<vpSelfCalibDataset::View>(ds.views.begin() + a, ds.views.begin() + b);
}

// RMS held-out position error (m) of a model on the views [15, end) against the truth.
double heldOutRms(const vpSelfCalibSimulator &sim, const vpKinematicChain &model, const vpSelfCalibDataset &ds)
{
  const auto ver = slice(ds, 15, ds.views.size());
  const auto v = vpCalibrationVerifier::verify(model, sim.getCamera(), ver, ds.yardstick, {}, sim.getTrueCameraPoses(ver));
  double s = 0;
  for (double e : v.position_errors)
    s += e * e;
  return std::sqrt(s / v.position_errors.size());
}
} // namespace

// The analytic observation Jacobian against central differences, at a non-zero parameter vector,
// with every intrinsic active (distortion included), for both robots.
TEST(KinematicBundleAdjustment, ObservationJacobianMatchesFiniteDifferences)
{
  for (const std::string robot : {"puma560", "viper850"}) {
    const vpSelfCalibSimulator sim = makeSim(robot, 41, 0.0);
    vpKinematicChain chain = sim.getTrueChain();
    const vpColVector q = sim.generateConfigurations(1)[0];
    const vpColVector X = sim.getScenePoints()[5];
    std::vector<unsigned int> params;
    for (unsigned int i = 0; i < chain.getNumParameters(); ++i)
      params.push_back(i);
    const double in0[5] = {1480, 1.01, 318, 245, -0.07};
    auto camera = [](const double *in) {
      vpCameraParameters c;
      c.initPersProjWithDistortion(in[0], in[0] * in[1], in[2], in[3], in[4], -in[4]);
      return c;
    };
    vpColVector uv;
    const vpMatrix J = vpKinematicBundleAdjustment::observationJacobian(chain, params, camera(in0), q, X, uv);
    const unsigned int P = static_cast<unsigned int>(params.size());
    ASSERT_EQ(J.getCols(), P + 8);
    auto proj = [&](const vpKinematicChain &c, const double *in, const vpColVector &x) {
      vpColVector p;
      vpKinematicBundleAdjustment::observationJacobian(c, {}, camera(in), q, x, p);
      return p;
    };
    const vpColVector p0 = proj(chain, in0, X);
    EXPECT_LT((p0 - uv).frobeniusNorm(), 1e-12);
    double worst = 0;
    for (unsigned int c = 0; c < P + 8; ++c) {
      vpColVector d(2);
      if (c < P) {
        const double h = 1e-7;
        vpKinematicChain a = chain, b = chain;
        vpColVector pa = chain.getParameters(), pb = pa;
        pa[c] += h;
        pb[c] -= h;
        a.setParameters(pa);
        b.setParameters(pb);
        d = (proj(a, in0, X) - proj(b, in0, X)) / (2 * h);
      } else if (c < P + 5) {
        const double h = c == P + 4 ? 1e-7 : 1e-5;
        double ia[5], ib[5];
        std::copy(in0, in0 + 5, ia);
        std::copy(in0, in0 + 5, ib);
        ia[c - P] += h;
        ib[c - P] -= h;
        d = (proj(chain, ia, X) - proj(chain, ib, X)) / (2 * h);
      } else {
        const double h = 1e-7;
        vpColVector xa = X, xb = X;
        xa[c - P - 5] += h;
        xb[c - P - 5] -= h;
        d = (proj(chain, in0, xa) - proj(chain, in0, xb)) / (2 * h);
      }
      for (unsigned int r = 0; r < 2; ++r)
        worst = std::max(worst, std::fabs(d[r] - J[r][c]) / (1 + std::fabs(J[r][c])));
    }
    EXPECT_LT(worst, 1e-5) << robot;
  }
}

// relativePoseCovariance() is G C G^T with G the derivative of c_ref M c: checked with C = I
// against G from central differences of the chain.
TEST(KinematicBundleAdjustment, RelativePoseCovarianceMatchesFiniteDifferences)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 42, 0.0);
  const vpKinematicChain chain = sim.getTrueChain();
  const std::vector<vpColVector> q = sim.generateConfigurations(2);
  const std::vector<unsigned int> params = {8, 13, 20, 27, 33, 40, 45};
  vpMatrix I(7, 7);
  I.eye();
  const vpMatrix C = vpKinematicBundleAdjustment::relativePoseCovariance(chain, params, I, q[0], q[1]);
  const Rigid M0 = rigidFromVisp(chain.get_fMc(q[0]).inverse() * chain.get_fMc(q[1]));
  Eigen::MatrixXd G(6, 7);
  for (int c = 0; c < 7; ++c) {
    const double h = 1e-7;
    vpKinematicChain a = chain;
    vpColVector p = chain.getParameters();
    p[params[c]] += h;
    a.setParameters(p);
    const Rigid M = rigidFromVisp(a.get_fMc(q[0]).inverse() * a.get_fMc(q[1]));
    G.block<3, 1>(0, c) = (M.t - M0.t) / h;
    G.block<3, 1>(3, c) = logSO3(M.R * M0.R.transpose()) / h;
  }
  const Eigen::MatrixXd Cfd = G * G.transpose();
  for (unsigned int a = 0; a < 6; ++a)
    for (unsigned int b = 0; b < 6; ++b)
      EXPECT_NEAR(C[a][b], Cfd(a, b), 1e-5 * (1 + std::fabs(Cfd(a, b)))) << a << "," << b;
}

// Noise-free images through the default pipeline without the kinematic prior (which pulls every
// correction toward nominal by its weight), f known and f self-calibrated: the estimated
// corrections are those that reproduce the true relative poses (1e-8), held-out poses are exact
// (1e-9 m = 1e-6 mm, 1e-9 rad), f is the true one.
TEST(KinematicBundleAdjustment, NoiseFreeExactRecoveryThroughTheDefaultPipeline)
{
  for (bool focal_known : {true, false}) {
    const vpSelfCalibSimulator sim = makeSim("viper850", 43, 0.0);
    const std::vector<vpColVector> q = sim.generateConfigurations(25);
    vpSelfCalibDataset ds = sim.makeDataset(q);
    ds.focal_known = focal_known;
    if (!focal_known)
      ds.cam.initPersProjWithoutDistortion(1400, 1400, ds.cam.get_u0(), ds.cam.get_v0());
    vpRobotSelfCalibration::Options o;
    o.multiview.tight = true;
    o.bundle.tight = true;
    o.bundle.kinematic_prior = vpKinematicBundleAdjustment::KINEMATIC_PRIOR_OFF;
    const vpRobotSelfCalibration::Result r = vpRobotSelfCalibration::run(sim.getNominalChain(), ds, o);
    ASSERT_EQ(r.status, vpRobotSelfCalibration::OK) << r.message;
    EXPECT_EQ(r.method, vpRobotSelfCalibration::BUNDLE_ADJUSTMENT);
    EXPECT_EQ(r.bundle.scale_source, vpKinematicBundleAdjustment::SCALE_YARDSTICK);
    EXPECT_EQ(r.identifiability.identified.size(), 24u);
    if (!focal_known) {
      EXPECT_NEAR(r.fx, sim.getCamera().get_px(), 1e-6);
      EXPECT_GT(r.fx_sd, 0);
    }
    // Reference corrections: identification from the exact relative poses of the calibration views.
    std::vector<vpKinematicIdentification::Measurement> ms;
    for (size_t k = 1; k < 15; ++k) {
      vpKinematicIdentification::Measurement m;
      m.q = q[k];
      m.q_ref = q[0];
      m.M = sim.getTrueChain().get_fMc(q[k]).inverse() * sim.getTrueChain().get_fMc(q[0]);
      ms.push_back(m);
    }
    // Same estimated set, the others at their nominal (zero) value in both.
    vpKinematicIdentification::Options io;
    const std::vector<std::string> names = sim.getNominalChain().getParameterNames();
    for (unsigned int i = 0; i < names.size(); ++i)
      if (std::find(r.identifiability.identified.begin(), r.identifiability.identified.end(), i) ==
          r.identifiability.identified.end())
        io.fixed.push_back(names[i]);
    const auto ref = vpKinematicIdentification::identify(sim.getNominalChain(), ms, io);
    ASSERT_EQ(ref.status, vpKinematicIdentification::OK) << ref.message;
    ASSERT_EQ(ref.identifiability.identified, r.identifiability.identified);
    for (unsigned int i : r.identifiability.identified)
      EXPECT_NEAR(r.calibrated.getParameters()[i], ref.chain.getParameters()[i], 1e-8)
          << r.calibrated.getParameterNames()[i];
    const auto ver = slice(ds, 15, 25);
    const auto v = vpCalibrationVerifier::verify(r.calibrated, r.camera, ver, ds.yardstick, sim.getScenePointsById(),
                                                 sim.getTrueCameraPoses(ver));
    for (size_t k = 0; k < v.position_errors.size(); ++k) {
      EXPECT_LT(v.position_errors[k], 1e-9);
      EXPECT_LT(v.rotation_errors[k], 1e-9);
    }
    EXPECT_LT(v.yardstick_error, 1e-9);
  }
}

// Distortion folded into the estimate: images through ViSP's k_ud model, the bundle adjustment
// from the nominal model, a wrong camera (f -2%, principal point off by 6 px, k_ud = 0) and points
// off by a millimetre recovers every intrinsic and the held-out poses exactly.
TEST(KinematicBundleAdjustment, NoiseFreeRecoveryOfAllIntrinsicsWithDistortion)
{
  const vpSelfCalibSimulator sim = makeSim("puma560", 44, 0.0);
  const std::vector<vpColVector> q = sim.generateConfigurations(25);
  vpSelfCalibDataset ds = sim.makeDataset(q);
  const double kud = -0.12, mu = 1.004;
  const vpCameraParameters c0 = sim.getCamera();
  const std::vector<vpHomogeneousMatrix> T = sim.getTrueCameraPoses(ds.views);
  for (size_t k = 0; k < ds.views.size(); ++k)
    for (auto &o : ds.views[k].points) {
      const Eigen::Vector3d Xc = rigidFromVisp(T[k]).inverse() * vec3(sim.getScenePoints()[o.id]);
      const double x = Xc(0) / Xc(2), y = Xc(1) / Xc(2), g = 1 + kud * (x * x + y * y);
      o.ip = vpImagePoint(c0.get_v0() + mu * c0.get_px() * y * g, c0.get_u0() + c0.get_px() * x * g);
    }
  Random rng(44, 1);
  std::map<int, vpColVector> start_points = sim.getScenePointsById();
  for (auto &e : start_points)
    for (unsigned int a = 0; a < 3; ++a)
      e.second[a] += rng.normal(1e-3);
  vpCameraParameters cam;
  cam.initPersProjWithoutDistortion(0.98 * c0.get_px(), 0.98 * c0.get_px(), c0.get_u0() + 6, c0.get_v0() - 4);
  vpKinematicBundleAdjustment::Options o;
  o.intrinsics = vpKinematicBundleAdjustment::FX | vpKinematicBundleAdjustment::ASPECT |
                 vpKinematicBundleAdjustment::PRINCIPAL_POINT | vpKinematicBundleAdjustment::DISTORTION;
  o.tight = true;
  o.kinematic_prior = vpKinematicBundleAdjustment::KINEMATIC_PRIOR_OFF; // exact: no pull toward nominal
  const auto cal = slice(ds, 0, 15);
  const auto r = vpKinematicBundleAdjustment::adjust(sim.getNominalChain(), cam, cal, ds.yardstick, start_points, o, vpSelfCalibNoiseModel());
  ASSERT_EQ(r.status, vpKinematicBundleAdjustment::OK) << r.message;
  ASSERT_EQ(r.intrinsic_names.size(), 5u);
  EXPECT_NEAR(r.camera.get_px(), c0.get_px(), 1e-6);
  EXPECT_NEAR(r.camera.get_py() / r.camera.get_px(), mu, 1e-10);
  EXPECT_NEAR(r.camera.get_u0(), c0.get_u0(), 1e-6);
  EXPECT_NEAR(r.camera.get_v0(), c0.get_v0(), 1e-6);
  EXPECT_NEAR(r.camera.get_kud(), kud, 1e-9);
  EXPECT_EQ(r.num_outliers, 0u);
  // Points: in f up to the base gauge (the base correction is not estimated), so their distances.
  ASSERT_EQ(r.points.size(), sim.getScenePoints().size());
  for (const auto &a : r.points)
    for (const auto &b : r.points)
      EXPECT_NEAR((vec3(a.second) - vec3(b.second)).norm(),
                  (vec3(sim.getScenePoints()[a.first]) - vec3(sim.getScenePoints()[b.first])).norm(), 1e-9);
  const auto ver = slice(ds, 15, 25);
  const std::vector<vpHomogeneousMatrix> Tv = sim.getTrueCameraPoses(ver);
  const Rigid m0 = rigidFromVisp(r.chain.get_fMc(ver[0].q)), t0 = rigidFromVisp(Tv[0]);
  for (size_t k = 1; k < ver.size(); ++k) {
    const Rigid a = m0.inverse() * rigidFromVisp(r.chain.get_fMc(ver[k].q)), b = t0.inverse() * rigidFromVisp(Tv[k]);
    EXPECT_LT((a.t - b.t).norm(), 1e-9);
    EXPECT_LT(logSO3(a.R * b.R.transpose()).norm(), 1e-9);
  }
}

// The covariance is honest: over 60 noise draws on one geometry, the spread of f, of the held-out
// relative positions and of the corrections (normalized estimation error squared) agree with the
// predicted covariance within 20%. Without the kinematic prior: with it the covariance is the
// posterior one, which also holds the prior's uncertainty of the robot, not only the noise's spread.
TEST(KinematicBundleAdjustment, PredictedStandardDeviationsMatchTheSpreadOverNoiseDraws)
{
  const double sd = 0.5;
  const vpSelfCalibSimulator sim = makeSim("viper850", 45, 0.0);
  const vpSelfCalibDataset clean = sim.makeDataset(sim.generateConfigurations(25));
  const auto cal = slice(clean, 0, 15), ver = slice(clean, 15, 25);
  vpKinematicBundleAdjustment::Options o;
  o.kinematic_prior = vpKinematicBundleAdjustment::KINEMATIC_PRIOR_OFF;
  vpSelfCalibNoiseModel noise;
  noise.pixel_sd = sd;
  vpCameraParameters cam0 = sim.getCamera();
  // The noise-free solution: the truth in the estimated coordinates.
  const auto exact = vpKinematicBundleAdjustment::adjust(sim.getNominalChain(), cam0, cal, clean.yardstick,
                                                         sim.getScenePointsById(), o, noise);
  ASSERT_EQ(exact.status, vpKinematicBundleAdjustment::OK) << exact.message;
  const std::vector<unsigned int> &id = exact.identifiability.identified;
  const unsigned int P = static_cast<unsigned int>(id.size());
  // Information matrix (the covariance spans m, rad and px: a full inverse, not a truncated one).
  Eigen::MatrixXd C(P + 1, P + 1);
  for (unsigned int a = 0; a <= P; ++a)
    for (unsigned int b = 0; b <= P; ++b)
      C(a, b) = exact.covariance[a][b];
  const Eigen::MatrixXd Cinv = C.ldlt().solve(Eigen::MatrixXd::Identity(P + 1, P + 1));
  std::vector<double> pred_pos(ver.size() - 1);
  for (size_t k = 1; k < ver.size(); ++k) {
    const vpMatrix C = vpKinematicBundleAdjustment::relativePoseCovariance(exact.chain, id, exact.covariance, ver[0].q,
                                                                           ver[k].q);
    pred_pos[k - 1] = C[0][0] + C[1][1] + C[2][2];
  }
  const std::vector<vpHomogeneousMatrix> T = sim.getTrueCameraPoses(ver);
  const unsigned int trials = 60;
  Random rng(45, 9);
  double f2 = 0, nees = 0, pos_emp = 0, pos_pred = 0;
  for (unsigned int t = 0; t < trials; ++t) {
    vpSelfCalibDataset ds = clean;
    addNoise(ds, sd, rng);
    const auto r = vpKinematicBundleAdjustment::adjust(sim.getNominalChain(), cam0, slice(ds, 0, 15), ds.yardstick,
                                                       sim.getScenePointsById(), o, noise);
    ASSERT_EQ(r.status, vpKinematicBundleAdjustment::OK) << r.message;
    ASSERT_EQ(r.identifiability.identified, id);
    f2 += std::pow(r.camera.get_px() - exact.camera.get_px(), 2);
    Eigen::VectorXd e(P + 1);
    for (unsigned int i = 0; i < P; ++i)
      e(i) = r.chain.getParameters()[id[i]] - exact.chain.getParameters()[id[i]];
    e(P) = r.camera.get_px() - exact.camera.get_px();
    nees += e.dot(Cinv * e) / (P + 1.0);
    const auto v = vpCalibrationVerifier::verify(r.chain, r.camera, ver, ds.yardstick, {}, T);
    for (size_t k = 0; k < v.position_errors.size(); ++k) {
      pos_emp += v.position_errors[k] * v.position_errors[k];
      pos_pred += pred_pos[k];
    }
  }
  EXPECT_NEAR(std::sqrt(f2 / trials) / exact.fx_sd, 1.0, 0.2);
  EXPECT_NEAR(std::sqrt(pos_emp / pos_pred), 1.0, 0.2);
  EXPECT_NEAR(std::sqrt(nees / trials), 1.0, 0.2);
}

// The estimate is the optimum: the default options give what the whole schedule run to tolerances
// of 1e-15 gives, to 1 % of each sd. The last solve stopped at Ceres' default relative cost change
// (1e-6) used to leave f up to 0.3 sd from it, the covariance taken there.
TEST(KinematicBundleAdjustment, TheEstimateIsTheConvergedOptimum)
{
  const double sd = 0.5;
  const vpSelfCalibSimulator sim = makeSim("viper850", 45, 0.0);
  const vpSelfCalibDataset clean = sim.makeDataset(sim.generateConfigurations(15));
  vpKinematicBundleAdjustment::Options o, tight;
  vpSelfCalibNoiseModel noise;
  noise.pixel_sd = sd;
  tight.tight = true;
  vpCameraParameters cam0 = sim.getCamera(); // f from a 7 % low guess, as a lens data sheet gives
  cam0.initPersProjWithoutDistortion(0.93 * cam0.get_px(), 0.93 * cam0.get_py(), cam0.get_u0(), cam0.get_v0());
  Random rng(45, 11);
  for (unsigned int t = 0; t < 4; ++t) {
    vpSelfCalibDataset ds = clean;
    addNoise(ds, sd, rng);
    const auto r = vpKinematicBundleAdjustment::adjust(sim.getNominalChain(), cam0, ds.views, ds.yardstick,
                                                       sim.getScenePointsById(), o, noise);
    const auto c = vpKinematicBundleAdjustment::adjust(sim.getNominalChain(), cam0, ds.views, ds.yardstick,
                                                       sim.getScenePointsById(), tight, noise);
    ASSERT_EQ(r.status, vpKinematicBundleAdjustment::OK) << r.message;
    ASSERT_EQ(c.status, vpKinematicBundleAdjustment::OK) << c.message;
    ASSERT_EQ(r.identifiability.identified, c.identifiability.identified);
    ASSERT_GT(c.fx_sd, 0);
    EXPECT_LT(std::fabs(r.camera.get_px() - c.camera.get_px()), 0.01 * c.fx_sd) << "draw " << t;
    for (unsigned int k : c.identifiability.identified)
      EXPECT_LT(std::fabs(r.chain.getParameters()[k] - c.chain.getParameters()[k]), 0.01 * c.sd[k])
          << "draw " << t << ", parameter " << k;
  }
}

// 20% wrong correspondences: the robust default stays within 2x of its error without them (mean
// over two scenario draws, one of them the hardest of 51-53: measured 0.76 mm against 0.67 mm
// without them); with plain least squares in every step (the noise model's loss none, no outlier
// test) the same data is far worse, or the run fails with a status (counted 1 m; both draws fail).
TEST(KinematicBundleAdjustment, DefaultPipelineIsRobustToWrongMatches)
{
  double clean = 0, robust = 0, plain = 0;
  for (uint64_t seed : {52, 53}) {
    const vpSelfCalibSimulator sim = makeSim("viper850", seed, 0.2);
    vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(25));
    ds.focal_known = false;
    vpSelfCalibDataset bad = ds;
    corrupt(bad, 0.2, seed, 78);
    vpRobotSelfCalibration::Options o;
    const auto rc = vpRobotSelfCalibration::run(sim.getNominalChain(), ds, o);
    const auto rb = vpRobotSelfCalibration::run(sim.getNominalChain(), bad, o);
    // f self-calibrated: better than the nominal model over the joint limits (5.7 and 3.5 mm against
    // 9.3 on seed 52 against the truth) with a predicted error that can leave a 12 % chance of the
    // contrary: doubtful by the workspace check alone, which is not the subject here.
    const auto workspace_doubt_only = [](const vpRobotSelfCalibration::Result &x) {
        return x.status == vpRobotSelfCalibration::DOUBTFUL &&
               std::all_of(x.findings.begin(), x.findings.end(), [](const auto &f) {
                 return f.severity != vpSelfCalibDataCheck::DOUBT || f.code == "workspace-worse-than-nominal";
               });
      };
    ASSERT_TRUE(rc.status == vpRobotSelfCalibration::OK || workspace_doubt_only(rc)) << rc.message;
    ASSERT_TRUE(rb.status == vpRobotSelfCalibration::OK || workspace_doubt_only(rb)) << rb.message;
    EXPECT_GT(rb.bundle.num_outliers, 0.12 * (rb.bundle.num_outliers + rb.bundle.num_observations));
    o.noise.loss = vpSelfCalibNoiseModel::LOSS_NONE;
    o.noise.outlier_threshold = 0;
    const auto rp = vpRobotSelfCalibration::run(sim.getNominalChain(), bad, o);
    clean += heldOutRms(sim, rc.calibrated, ds);
    robust += heldOutRms(sim, rb.calibrated, bad);
    plain += rp.status == vpRobotSelfCalibration::OK ? heldOutRms(sim, rp.calibrated, bad) : 1.0;
  }
  EXPECT_LT(robust, 2 * clean);
  EXPECT_GT(plain, 3 * clean);
}

// Without a yardstick the pipeline still calibrates, keeps the nominal scale (the set rule's gauge: no
// kinematic prior, which would hold the scale itself and pull the noise-free fit toward nominal) and
// says so.
TEST(KinematicBundleAdjustment, WithoutYardstickTheNominalScaleIsKeptAndReported)
{
  const vpSelfCalibSimulator sim = makeSim("puma560", 46, 0.0);
  vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(18));
  ds.yardstick = vpSelfCalibDataset::Yardstick();
  vpRobotSelfCalibration::Options po;
  po.bundle.kinematic_prior = vpKinematicBundleAdjustment::KINEMATIC_PRIOR_OFF;
  const auto r = vpRobotSelfCalibration::run(sim.getNominalChain(), ds, po);
  ASSERT_EQ(r.status, vpRobotSelfCalibration::OK) << r.message;
  EXPECT_FALSE(r.multiview.metric);
  EXPECT_EQ(r.bundle.scale_source, vpKinematicBundleAdjustment::SCALE_NOMINAL);
  EXPECT_NE(r.message.find("nominal scale"), std::string::npos) << r.message;
  EXPECT_TRUE(std::any_of(r.findings.begin(), r.findings.end(),
                          [](const vpSelfCalibDataCheck::Finding &f) { return f.code == "scale-nominal"; }));
  // With the yardstick the scale is measured and nothing is said of it.
  const auto y = vpRobotSelfCalibration::run(sim.getNominalChain(), sim.makeDataset(sim.generateConfigurations(18)), po);
  ASSERT_EQ(y.status, vpRobotSelfCalibration::OK) << y.message;
  EXPECT_FALSE(std::any_of(y.findings.begin(), y.findings.end(),
                           [](const vpSelfCalibDataCheck::Finding &f) { return f.code == "scale-nominal"; }));
  // Orientations do not depend on the scale: the held-out rotations are exact.
  const auto ver = slice(ds, 15, 18);
  const auto v = vpCalibrationVerifier::verify(r.calibrated, r.camera, ver, ds.yardstick, {}, sim.getTrueCameraPoses(ver));
  for (double e : v.rotation_errors)
    EXPECT_LT(e, 1e-7);
}

TEST(KinematicBundleAdjustment, DegenerateAndBadInput)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 47, 0.2);
  const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(6));
  const std::map<int, vpColVector> X = sim.getScenePointsById();
  const vpKinematicBundleAdjustment::Options o;
  // The same configuration three times: nothing to estimate.
  std::vector<vpSelfCalibDataset::View> same(3, ds.views[0]);
  auto r = vpKinematicBundleAdjustment::adjust(sim.getNominalChain(), ds.cam, same, ds.yardstick, X, o, vpSelfCalibNoiseModel());
  EXPECT_EQ(r.status, vpKinematicBundleAdjustment::TOO_FEW_OBSERVATIONS);
  // Caller mistakes.
  EXPECT_THROW(vpKinematicBundleAdjustment::adjust(sim.getNominalChain(), ds.cam, {ds.views[0]}, ds.yardstick, X, o, vpSelfCalibNoiseModel()),
               vpSelfCalibException);
  std::vector<vpSelfCalibDataset::View> bad = ds.views;
  bad[2].q.resize(5);
  EXPECT_THROW(vpKinematicBundleAdjustment::adjust(sim.getNominalChain(), ds.cam, bad, ds.yardstick, X, o, vpSelfCalibNoiseModel()),
               vpSelfCalibException);
  bad = ds.views;
  bad[1].points[0].ip.set_v(std::numeric_limits<double>::infinity());
  EXPECT_THROW(vpKinematicBundleAdjustment::adjust(sim.getNominalChain(), ds.cam, bad, ds.yardstick, X, o, vpSelfCalibNoiseModel()),
               vpSelfCalibException);
  bad = ds.views;
  bad[1].points.push_back(bad[1].points[2]);
  EXPECT_THROW(vpKinematicBundleAdjustment::adjust(sim.getNominalChain(), ds.cam, bad, ds.yardstick, X, o, vpSelfCalibNoiseModel()),
               vpSelfCalibException);
  std::map<int, vpColVector> badX = X;
  badX[3] = vpColVector(2);
  EXPECT_THROW(vpKinematicBundleAdjustment::adjust(sim.getNominalChain(), ds.cam, ds.views, ds.yardstick, badX, o, vpSelfCalibNoiseModel()),
               vpSelfCalibException);
  vpKinematicBundleAdjustment::Options bo;
  bo.fixed = {"j9.tx"};
  EXPECT_THROW(vpKinematicBundleAdjustment::adjust(sim.getNominalChain(), ds.cam, ds.views, ds.yardstick, X, bo, vpSelfCalibNoiseModel()),
               vpSelfCalibException);
  bo = o;
  bo.intrinsics = 64;
  EXPECT_THROW(bo.check(), vpSelfCalibException);
  bo = o;
  bo.yardstick_sd = -1;
  EXPECT_THROW(bo.check(), vpSelfCalibException);
  vpRobotSelfCalibration::Options po;
  EXPECT_THROW(vpRobotSelfCalibration::methodFromName("magic"), vpSelfCalibException);
  po.noise.pixel_sd = 0;
  EXPECT_THROW(po.check(), vpSelfCalibException);
}

// Hand-eye-only mode through the pipeline: views with controller poses fMe only (the true robot's,
// trusted), f self-calibrated, with and without the yardstick: eMc and f exact on noise-free images.
TEST(HandEye, NoiseFreeExactRecoveryFromControllerPoses)
{
  for (bool yardstick : {true, false}) {
    vpSelfCalibSimulator sim = makeSim("viper850", 71, 0.0);
    vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(12));
    for (auto &v : ds.views) {
      v.has_fMe = true;
      v.fMe = sim.getTrueChain().get_fMe(v.q);
      v.q = vpColVector();
    }
    ds.focal_known = false;
    ds.cam.initPersProjWithoutDistortion(1400, 1400, 320, 240);
    if (!yardstick)
      ds.yardstick = vpSelfCalibDataset::Yardstick();
    vpRobotSelfCalibration::Options o;
    o.method = vpRobotSelfCalibration::HAND_EYE;
    o.multiview.tight = true;
    o.bundle.tight = true;
    o.trust_robot = true; // the controller poses are the true ones, and stated so
    const auto r = vpRobotSelfCalibration::run(sim.getNominalChain(), ds, o);
    ASSERT_EQ(r.status, vpRobotSelfCalibration::OK) << r.message;
    EXPECT_EQ(r.bundle.scale_source, vpKinematicBundleAdjustment::SCALE_ROBOT_MOTION);
    EXPECT_EQ(r.identifiability.identified.size(), 6u);
    EXPECT_NEAR(r.fx, 1500, 1e-6);
    EXPECT_GT(r.fx_sd, 0);
    const vpHomogeneousMatrix e = sim.getTrueChain().get_eMc_corrected(), g = r.calibrated.get_eMc_corrected();
    EXPECT_LT(translationDistance(e, g), 1e-9) << yardstick;
    EXPECT_LT(rotationDistance(e, g), 1e-9) << yardstick;
    // Only the eMc block moved.
    for (unsigned int i = 0; i + 6 < r.calibrated.getNumParameters(); ++i)
      EXPECT_EQ(r.calibrated.getParameters()[i], 0.0);
  }
}

// End-effector rotations all about one axis (the base's z): the hand-eye translation along it is not
// observable; the bundle adjustment says so instead of returning a number.
TEST(HandEye, RotationsAboutOneAxisAreRankDeficient)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 72, 0.0);
  const vpColVector q0 = sim.generateConfigurations(1)[0];
  const vpHomogeneousMatrix fMe0 = sim.getTrueChain().get_fMe(q0), eMc = sim.getTrueChain().get_eMc_corrected();
  const vpCameraParameters cam = sim.getCamera();
  std::vector<vpSelfCalibDataset::View> views;
  for (int k = -3; k <= 3; ++k) {
    vpSelfCalibDataset::View v;
    v.has_fMe = true;
    v.fMe = vpHomogeneousMatrix(0, 0, 0, 0, 0, k * 0.03) * fMe0;
    const Rigid cMf = rigidFromVisp(v.fMe * eMc).inverse();
    for (size_t j = 0; j < sim.getScenePoints().size(); ++j) {
      const Eigen::Vector3d x = cMf * vec3(sim.getScenePoints()[j]);
      const double u = cam.get_u0() + cam.get_px() * x(0) / x(2), w = cam.get_v0() + cam.get_py() * x(1) / x(2);
      if (x(2) > 0 && u > 0 && u < 640 && w > 0 && w < 480)
        v.points.push_back({static_cast<int>(j), vpImagePoint(w, u)});
    }
    views.push_back(v);
  }
  vpKinematicBundleAdjustment::Options o;
  o.hand_eye_only = true;
  o.intrinsics = 0;
  const auto r = vpKinematicBundleAdjustment::adjust(sim.getNominalChain(), cam, views, vpSelfCalibDataset::Yardstick(),
                                                     sim.getScenePointsById(), o, vpSelfCalibNoiseModel());
  EXPECT_EQ(r.status, vpKinematicBundleAdjustment::RANK_DEFICIENT) << r.message;
  EXPECT_NE(r.message.find("another axis"), std::string::npos) << r.message;
}

namespace
{
/*
  Hand-eye data whose controller poses carry robot pose error: the true fMe of each view moved by
  exp of a random (t, theta u) with sd (sd_t, sd_r) in its end-effector frame; images of the true
  camera with 0.2 px noise, f known. Returns the eMc error (true -> estimate: t, theta u) and the
  reported sd of eMc.t*, eMc.r*.
*/
struct HandEyeRun {
  bool ok = false;
  vpRobotSelfCalibration::Status status = vpRobotSelfCalibration::OK;
  Eigen::Matrix<double, 6, 1> error, sd;
  double sigma0 = 0, pose_rms_t = 0;
  double pose_sd_t = 0, pose_sd_r = 0; //!< the pose error the final run used
  std::string message;
  std::vector<std::string> findings; //!< codes
  bool has(const std::string &code) const { return std::find(findings.begin(), findings.end(), code) != findings.end(); }
};
HandEyeRun handEyeWithPoseError(uint64_t seed, double sd_t, double sd_r, double model_t, double model_r,
                                bool measure_pose_sd = false)
{
  vpSelfCalibSimulator sim = makeSim("viper850", seed, 0.2);
  vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(12));
  toControllerPoses(sim, ds, sd_t, sd_r, seed, 99);
  vpRobotSelfCalibration::Options o;
  o.method = vpRobotSelfCalibration::HAND_EYE;
  o.num_calibration_poses = 12;
  o.noise.pose_sd_translation = model_t;
  o.noise.pose_sd_rotation = model_r;
  o.trust_robot = !(model_t > 0); // 0: the poses trusted (not the default's measured error)
  if (measure_pose_sd)
    o.noise.measure_pose_sd = true;
  const auto r = vpRobotSelfCalibration::run(sim.getNominalChain(), ds, o);
  HandEyeRun out;
  out.ok = r.status == vpRobotSelfCalibration::OK;
  out.status = r.status;
  out.message = r.message;
  for (const auto &f : r.findings)
    out.findings.push_back(f.code);
  if (!out.ok)
    return out;
  // The estimated eMc correction against the one that gives the true eMc.
  const vpKinematicChain &truth = sim.getTrueChain();
  const unsigned int first = truth.getNumParameters() - vpKinematicChain::kBlockSize;
  for (unsigned int i = 0; i < 6; ++i) {
    out.error(i) = r.calibrated.getParameters()[first + i] - truth.getParameters()[first + i];
    out.sd(i) = r.parameter_sd[first + i];
  }
  out.sigma0 = r.bundle.sigma0;
  out.pose_rms_t = r.bundle.pose_rms_translation;
  out.pose_sd_t = r.noise.pose_sd_translation;
  out.pose_sd_r = r.noise.pose_sd_rotation;
  return out;
}
} // namespace

/*
  Robot pose error (2 mm, 2 mrad per controller pose, the order of a real arm's): modelled, the
  reported sd of eMc covers the error (mean normalized squared error over 6 axes x 8 seeds near 1, and
  sigma0 near 1); not modelled (poses trusted), the pose error looks like wrong matches: runs fail
  on rejected observations, or report sd several times too small.
*/
TEST(HandEye, RobotPoseErrorIsModelledAndTheSdAreHonest)
{
  double nees_model = 0, nees_trust = 0, sigma0 = 0;
  int n = 0, trusted_ok = 0;
  for (uint64_t seed = 80; seed < 88; ++seed) {
    const HandEyeRun m = handEyeWithPoseError(seed, 2e-3, 2e-3, 2e-3, 2e-3);
    ASSERT_TRUE(m.ok) << seed << ": " << m.message;
    for (int i = 0; i < 6; ++i)
      nees_model += std::pow(m.error(i) / m.sd(i), 2);
    sigma0 += m.sigma0;
    EXPECT_GT(m.pose_rms_t, 0.5e-3) << seed;
    ++n;
    const HandEyeRun t = handEyeWithPoseError(seed, 2e-3, 2e-3, 0, 0);
    if (t.ok) {
      ++trusted_ok;
      for (int i = 0; i < 6; ++i)
        nees_trust += std::pow(t.error(i) / t.sd(i), 2);
    }
  }
  nees_model /= 6 * n;
  sigma0 /= n;
  EXPECT_GT(nees_model, 0.4);
  EXPECT_LT(nees_model, 2.0);
  EXPECT_NEAR(sigma0, 1.0, 0.2);
  // Poses trusted: the pose error is taken for wrong matches (most runs fail on rejected
  // observations), and the runs that pass report sd at least 3x too small.
  if (trusted_ok > 0)
    EXPECT_GT(nees_trust / (6 * trusted_ok), 9.0);
  // Nonsense settings are refused.
  vpSelfCalibNoiseModel bn;
  bn.pose_sd_translation = 1e-3;
  EXPECT_THROW(bn.check(), vpSelfCalibException);
  bn.pose_sd_rotation = 1e-3;
  EXPECT_NO_THROW(bn.check());
}

/*
  The robot pose error measured (the noise model's pose_sd of origin MEASURED): 2 mm / 2 mrad of true error, stated
  4x too small and 4x too large, 8 seeds (12 poses each). Each run's measured error within
  1.2-3 mm and mrad (36 values per part: about 12 % sd each), their mean within 15 % of the truth
  (measured: 2.04 mm / 1.87 mrad from below, 2.12 / 2.03 from above), both starts giving each seed
  the same value within 15 % (the rounds stop at 10 %), and the eMc sd honest (mean normalized
  square 0.5-1.6; measured 1.01 and 0.89).
*/
TEST(HandEye, RobotPoseErrorIsMeasured)
{
  std::vector<double> first_t, first_r;
  for (double start : {0.5e-3, 8e-3}) {
    double t = 0, r = 0, nees = 0;
    int n = 0;
    for (uint64_t seed = 80; seed < 88; ++seed) {
      const HandEyeRun m = handEyeWithPoseError(seed, 2e-3, 2e-3, start, start, true);
      ASSERT_TRUE(m.ok) << seed << ": " << m.message;
      EXPECT_GT(m.pose_sd_t, 1.2e-3) << seed;
      EXPECT_LT(m.pose_sd_t, 3e-3) << seed;
      EXPECT_GT(m.pose_sd_r, 1.2e-3) << seed;
      EXPECT_LT(m.pose_sd_r, 3e-3) << seed;
      if (start < 1e-3) {
        first_t.push_back(m.pose_sd_t);
        first_r.push_back(m.pose_sd_r);
      } else {
        EXPECT_NEAR(m.pose_sd_t / first_t[static_cast<size_t>(n)], 1, 0.15) << seed;
        EXPECT_NEAR(m.pose_sd_r / first_r[static_cast<size_t>(n)], 1, 0.15) << seed;
      }
      t += m.pose_sd_t;
      r += m.pose_sd_r;
      for (int i = 0; i < 6; ++i)
        nees += std::pow(m.error(i) / m.sd(i), 2);
      ++n;
    }
    EXPECT_NEAR(t / n, 2e-3, 0.3e-3) << "start " << start;
    EXPECT_NEAR(r / n, 2e-3, 0.3e-3) << "start " << start;
    EXPECT_GT(nees / (6 * n), 0.5) << "start " << start;
    EXPECT_LT(nees / (6 * n), 1.6) << "start " << start;
  }
}

/*
  Robot pose error left out of the model (poses trusted): 2 mm / 2 mrad per controller pose against
  0.2 px of image noise. Re-posing each camera alone takes most of the residuals away, so no run is
  ok: doubtful with the finding that names it and the --pose-sd to state, or refused. Exact poses
  give no such finding, and with the pose error modelled it is not tested (4 seeds each).
*/
TEST(HandEye, UnmodelledRobotPoseErrorIsNotOk)
{
  for (uint64_t seed = 80; seed < 84; ++seed) {
    const HandEyeRun trusted = handEyeWithPoseError(seed, 2e-3, 2e-3, 0, 0);
    EXPECT_NE(trusted.status, vpRobotSelfCalibration::OK) << seed << ": " << trusted.message;
    if (trusted.status == vpRobotSelfCalibration::DOUBTFUL) {
      EXPECT_TRUE(trusted.has("robot-error-unmodelled")) << seed << ": " << trusted.message;
      EXPECT_NE(trusted.message.find("--pose-sd"), std::string::npos) << trusted.message;
    }
    const HandEyeRun exact = handEyeWithPoseError(seed, 0, 0, 0, 0);
    EXPECT_EQ(exact.status, vpRobotSelfCalibration::OK) << seed << ": " << exact.message;
    EXPECT_FALSE(exact.has("robot-error-unmodelled")) << seed;
    const HandEyeRun modelled = handEyeWithPoseError(seed, 2e-3, 2e-3, 2e-3, 2e-3);
    EXPECT_FALSE(modelled.has("robot-error-unmodelled")) << seed;
  }
}

/*
  The robot part of the residuals is checked against the stated robot error: the pose corrections'
  chi-square within its 99.9 % bound when the stated error is the true one (no finding, 4 seeds);
  a true error twice the stated one is a warning and the run stays ok, its sd scaled by sigma0;
  corrections that must be 10 times their stated sd (as when they take the error of an eMc the
  adjustment left at its guess: the industrial set target-free, README I4) are never ok: doubtful
  with the finding that says so, or refused.
*/
TEST(HandEye, PoseCorrectionsAreCheckedAgainstTheStatedRobotError)
{
  for (uint64_t seed = 80; seed < 84; ++seed) {
    const HandEyeRun right = handEyeWithPoseError(seed, 2e-3, 2e-3, 2e-3, 2e-3);
    ASSERT_TRUE(right.ok) << seed << ": " << right.message;
    EXPECT_FALSE(right.has("robot-error-above-stated")) << seed;
    EXPECT_FALSE(right.has("robot-corrections-stand-in")) << seed;
  }
  int warned = 0;
  for (uint64_t seed = 80; seed < 84; ++seed) {
    const HandEyeRun larger = handEyeWithPoseError(seed, 4e-3, 4e-3, 2e-3, 2e-3);
    ASSERT_TRUE(larger.ok) << seed << ": " << larger.message;
    EXPECT_FALSE(larger.has("robot-corrections-stand-in")) << seed;
    warned += larger.has("robot-error-above-stated");
  }
  EXPECT_GE(warned, 3);
  for (uint64_t seed = 80; seed < 82; ++seed) {
    const HandEyeRun off = handEyeWithPoseError(seed, 20e-3, 20e-3, 2e-3, 2e-3);
    EXPECT_FALSE(off.ok) << seed << ": " << off.message;
    if (off.status == vpRobotSelfCalibration::DOUBTFUL)
      EXPECT_TRUE(off.has("robot-corrections-stand-in")) << seed << ": " << off.message;
  }
}

namespace
{
//! Views of a plane z = 1 (f frame) by a camera at fMc_k, hand-eye data (fMe = fMc eMc^-1, exact).
std::vector<vpSelfCalibDataset::View> planeViews(const vpKinematicChain &chain, const vpCameraParameters &cam,
                                                 const std::vector<vpHomogeneousMatrix> &fMc,
                                                 std::map<int, vpColVector> &X)
{
  X.clear();
  for (int i = 0; i < 7; ++i)
    for (int j = 0; j < 7; ++j)
      X[7 * i + j] = vpColVector({-0.15 + 0.05 * i, -0.15 + 0.05 * j, 1.0});
  const vpHomogeneousMatrix cMe = chain.get_eMc_corrected().inverse();
  std::vector<vpSelfCalibDataset::View> views;
  for (const vpHomogeneousMatrix &M : fMc) {
    vpSelfCalibDataset::View v;
    v.has_fMe = true;
    v.fMe = M * cMe;
    const Rigid cMf = rigidFromVisp(M).inverse();
    for (const auto &e : X) {
      const Eigen::Vector3d x = cMf * vec3(e.second);
      v.points.push_back({e.first, vpImagePoint(cam.get_v0() + cam.get_py() * x(1) / x(2),
                                                cam.get_u0() + cam.get_px() * x(0) / x(2))});
    }
    views.push_back(v);
  }
  return views;
}
} // namespace

/*
  One plane, f self-calibrated (hand-eye): views at one tilt (the camera translating parallel to the
  plane and turning about its optical axis) leave f undetermined (it trades with the plane's depth
  and the hand-eye translation along the axis): RANK_DEFICIENT, with fx named. The same plane seen
  at several tilts determines f (Zhang's calibration): exact on noise-free data.
*/
TEST(HandEye, OnePlaneAtOneTiltLeavesFUndeterminedAndNamesIt)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 73, 0.0);
  const vpKinematicChain chain = sim.getNominalChain();
  const vpCameraParameters cam = sim.getCamera();
  vpKinematicBundleAdjustment::Options o;
  o.hand_eye_only = true;
  o.intrinsics = vpKinematicBundleAdjustment::FX;
  o.tight = true;
  std::map<int, vpColVector> X;
  std::vector<vpHomogeneousMatrix> flat, tilted;
  for (int k = 0; k < 8; ++k) {
    flat.push_back(vpHomogeneousMatrix(0.03 * (k % 3 - 1), 0.03 * (k / 3 - 1), 0, 0, 0, 0.3 * k));
    tilted.push_back(vpHomogeneousMatrix(0.03 * (k % 3 - 1), 0.03 * (k / 3 - 1), 0.02 * (k % 2), 0.25 * ((k % 3) - 1),
                                         0.25 * ((k / 3) % 3 - 1), 0.3 * k));
  }
  vpCameraParameters start;
  start.initPersProjWithoutDistortion(1400, 1400, cam.get_u0(), cam.get_v0());
  const auto r = vpKinematicBundleAdjustment::adjust(chain, start, planeViews(chain, cam, flat, X),
                                                     vpSelfCalibDataset::Yardstick(), X, o, vpSelfCalibNoiseModel());
  EXPECT_EQ(r.status, vpKinematicBundleAdjustment::RANK_DEFICIENT) << r.message;
  ASSERT_FALSE(r.undetermined.empty()) << r.message;
  EXPECT_NE(std::find(r.undetermined.begin(), r.undetermined.end(), "fx"), r.undetermined.end()) << r.message;
  EXPECT_NE(r.message.find("not determined: "), std::string::npos) << r.message;
  EXPECT_NE(r.message.find(" observations kept of "), std::string::npos) << r.message; // the causes, counts first
  const auto t = vpKinematicBundleAdjustment::adjust(chain, start, planeViews(chain, cam, tilted, X),
                                                     vpSelfCalibDataset::Yardstick(), X, o, vpSelfCalibNoiseModel());
  ASSERT_EQ(t.status, vpKinematicBundleAdjustment::OK) << t.message;
  EXPECT_NEAR(t.camera.get_px(), cam.get_px(), 1e-6);
}

// A board of known layout (known_points, in its own frame: here the plane's points moved by an
// arbitrary rigid transform): the adjustment estimates the board's pose with the rest and recovers
// eMc exactly on noise-free data; a layout with fewer than 3 observed points is refused.
TEST(HandEye, KnownBoardLayoutIsAPriorOnItsPoints)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 74, 0.0);
  const vpKinematicChain truth = sim.getTrueChain();
  const vpCameraParameters cam = sim.getCamera();
  std::map<int, vpColVector> X;
  std::vector<vpHomogeneousMatrix> poses;
  for (int k = 0; k < 8; ++k)
    poses.push_back(vpHomogeneousMatrix(0.03 * (k % 3 - 1), 0.03 * (k / 3 - 1), 0.02 * (k % 2), 0.25 * ((k % 3) - 1),
                                        0.25 * ((k / 3) % 3 - 1), 0.3 * k));
  const auto views = planeViews(truth, cam, poses, X);
  const vpHomogeneousMatrix oMf(0.1, -0.2, 0.3, 0.2, -0.1, 0.4); // the board frame, anywhere
  std::map<int, vpColVector> layout;
  for (const auto &e : X) {
    const vpColVector p = oMf * vpColVector({e.second[0], e.second[1], e.second[2], 1.0});
    layout[e.first] = vpColVector({p[0], p[1], p[2]});
  }
  vpKinematicBundleAdjustment::Options o;
  o.hand_eye_only = true;
  o.intrinsics = 0;
  o.tight = true;
  o.known_points = layout;
  // Start from the nominal model and points 1 cm off.
  std::map<int, vpColVector> X0 = X;
  for (auto &e : X0)
    e.second[2] += 0.01;
  const auto r = vpKinematicBundleAdjustment::adjust(sim.getNominalChain(), cam, views,
                                                     vpSelfCalibDataset::Yardstick(), X0, o, vpSelfCalibNoiseModel());
  ASSERT_EQ(r.status, vpKinematicBundleAdjustment::OK) << r.message;
  EXPECT_LT(translationDistance(r.chain.get_eMc_corrected(), truth.get_eMc_corrected()), 1e-7);
  EXPECT_LT(rotationDistance(r.chain.get_eMc_corrected(), truth.get_eMc_corrected()), 1e-7);
  for (double sd : {0.0, -1e-5, std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN()}) {
    vpKinematicBundleAdjustment::Options bad = o;
    bad.known_points_sd = sd;
    EXPECT_THROW(bad.check(), vpSelfCalibException) << sd;
  }
  o.known_points = {{0, layout[0]}, {1, layout[1]}, {900, layout[2]}};
  EXPECT_THROW(vpKinematicBundleAdjustment::adjust(sim.getNominalChain(), cam, views, vpSelfCalibDataset::Yardstick(),
                                                   X0, o, vpSelfCalibNoiseModel()),
               vpSelfCalibException);
}

/*
  A board of known layout is held as known: with the default known_points_sd (10 um) the adjusted
  grid keeps the layout's spacing (RMS difference below 10 um; with the 0.1 mm of earlier versions
  it is 54-57 um on these exact boards, checked above 30 um for seed 1: the 0.2 px of noise moves
  the points, the data locating each to about 0.2 px x 0.5 m / 540 px / sqrt(12) = 53 um), and the
  intrinsics come from the board as in Zhang's calibration though the robot reports its tilts 5 %
  large (up to 20 mrad, as the industrial_calibration set's poses): f (from 4 % low) and the
  principal point (from 8 px off in each axis) self-calibrated, the points started 1 cm off, pose
  sd stated 5 mm / 10 mrad, 0.2 px, 4 seeds: each within 3 reported sd of the truth, f within 0.5 %.
*/
TEST(HandEye, KnownLayoutIsHeldAndGivesTheIntrinsics)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 76, 0.0);
  const vpKinematicChain truth = sim.getTrueChain();
  const vpCameraParameters cam(540, 540, 322, 226);
  std::map<int, vpColVector> layout;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      layout[10 * i + j] = vpColVector({0.025 * i, 0.025 * j, 0.0});
  const vpHomogeneousMatrix fMo(-0.11, -0.11, 0.5, 0, 0, 0); // the board, 0.5 m in front of f's origin
  const vpHomogeneousMatrix cMe = truth.get_eMc_corrected().inverse();
  vpKinematicBundleAdjustment::Options o;
  o.hand_eye_only = true;
  o.intrinsics = vpKinematicBundleAdjustment::FX | vpKinematicBundleAdjustment::PRINCIPAL_POINT;
  o.tight = true;
  o.known_points = layout;
  vpSelfCalibNoiseModel noise;
  noise.pose_sd_translation = 0.005;
  noise.pose_sd_rotation = 0.01;
  o.scale_covariance = true;
  noise.pixel_sd = 0.2;
  EXPECT_DOUBLE_EQ(o.known_points_sd, 1e-5);
  std::map<int, vpColVector> X, X0; // the board's points in f; the start, 1 cm off
  for (const auto &e : layout) {
    const vpColVector p = fMo * vpColVector({e.second[0], e.second[1], e.second[2], 1.0});
    X[e.first] = vpColVector({p[0], p[1], p[2]});
    X0[e.first] = vpColVector({p[0], p[1], p[2] + 0.01});
  }
  // RMS difference between the adjusted grid's neighbour distances and the layout's.
  const auto spacingRms = [&layout](const std::map<int, vpColVector> &points) {
    double ss = 0;
    int n = 0;
    for (const auto &e : layout) {
      const int id = e.first, right = id + 1, below = id + 10;
      for (int nb : {right, below}) {
        if ((nb == right && id % 10 == 9) || !layout.count(nb) || !points.count(id) || !points.count(nb))
          continue;
        const double d = (vec3(points.at(id)) - vec3(points.at(nb))).norm() -
                         (vec3(layout.at(id)) - vec3(layout.at(nb))).norm();
        ss += d * d;
        ++n;
      }
    }
    return n > 100 ? std::sqrt(ss / n) : std::numeric_limits<double>::infinity();
  };
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    Random rng(seed, 76);
    std::vector<vpSelfCalibDataset::View> views;
    for (int k = 0; k < 12; ++k) {
      const double tx = 0.04 * (k % 3 - 1) + rng.normal(0.01), ty = 0.04 * (k / 3 % 3 - 1) + rng.normal(0.01);
      const double ax = 0.3 * ((k % 3) - 1) + rng.normal(0.05), ay = 0.3 * ((k / 3) % 3 - 1) + rng.normal(0.05);
      const vpHomogeneousMatrix fMc(tx, ty, 0.05 * (k % 2), ax, ay, 0.5 * k);
      vpSelfCalibDataset::View v;
      v.has_fMe = true;
      // The robot reports its tilts 5 % large (up to 20 mrad off, as the industrial set's poses).
      v.fMe = vpHomogeneousMatrix(tx, ty, 0.05 * (k % 2), 1.05 * ax, 1.05 * ay, 0.5 * k) * cMe;
      const Rigid cMf = rigidFromVisp(fMc).inverse();
      for (const auto &e : X) {
        const Eigen::Vector3d x = cMf * vec3(e.second);
        const double u = cam.get_u0() + cam.get_px() * x(0) / x(2) + rng.normal(0.2);
        const double w = cam.get_v0() + cam.get_py() * x(1) / x(2) + rng.normal(0.2);
        if (x(2) > 0 && u > 0 && u < 640 && w > 0 && w < 480)
          v.points.push_back({e.first, vpImagePoint(w, u)});
      }
      views.push_back(v);
    }
    vpCameraParameters start;
    start.initPersProjWithoutDistortion(518, 518, 330, 218);
    const auto r = vpKinematicBundleAdjustment::adjust(sim.getNominalChain(), start, views,
                                                       vpSelfCalibDataset::Yardstick(), X0, o, noise);
    ASSERT_EQ(r.status, vpKinematicBundleAdjustment::OK) << r.message;
    ASSERT_EQ(r.intrinsics_sd.size(), 3u);
    EXPECT_LT(spacingRms(r.points), 1e-5) << "seed " << seed;
    EXPECT_LT(std::fabs(r.camera.get_px() - cam.get_px()), 3 * r.intrinsics_sd[0])
        << "seed " << seed << ": f " << r.camera.get_px() << " +- " << r.intrinsics_sd[0];
    EXPECT_LT(std::fabs(r.camera.get_u0() - cam.get_u0()), 3 * r.intrinsics_sd[1]) << "seed " << seed;
    EXPECT_LT(std::fabs(r.camera.get_v0() - cam.get_v0()), 3 * r.intrinsics_sd[2]) << "seed " << seed;
    EXPECT_NEAR(r.camera.get_px(), cam.get_px(), 0.005 * cam.get_px()) << "seed " << seed;
    if (seed == 1) { // the prior of earlier versions: the points drift with the noise
      vpKinematicBundleAdjustment::Options loose = o;
      loose.known_points_sd = 1e-4;
      const auto l = vpKinematicBundleAdjustment::adjust(sim.getNominalChain(), start, views,
                                                         vpSelfCalibDataset::Yardstick(), X0, loose, noise);
      ASSERT_EQ(l.status, vpKinematicBundleAdjustment::OK) << l.message;
      EXPECT_GT(spacingRms(l.points), 3e-5);
    }
  }
}

/*
  OpenCV's lens model (k1, k2, p1, p2) estimated with f, the aspect ratio and the principal point
  from views of one plane at several tilts (hand-eye, poses exact), as Zhang's calibration does:
  exact recovery on noise-free data from a start with no distortion, f 5 % and the principal point
  10 px off; k3 held at its start value; the names say which coefficients were estimated. Bad
  settings (coefficients with the ViSP model, a camera with k_ud under the OpenCV model, K3 alone)
  are refused.
*/
TEST(HandEye, OpenCvDistortionAndPrincipalPointFromATiltedPlane)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 75, 0.0);
  const vpKinematicChain truth = sim.getTrueChain();
  const double in[9] = {800, 1.002, 330, 236, -0.21, 0.09, 0.0012, -0.0015, 0};
  const CameraModel lens(Distortion::OPENCV, in);
  std::map<int, vpColVector> X;
  for (int i = 0; i < 11; ++i)
    for (int j = 0; j < 11; ++j)
      X[11 * i + j] = vpColVector({-0.3 + 0.06 * i, -0.3 + 0.06 * j, 1.0});
  const vpHomogeneousMatrix cMe = truth.get_eMc_corrected().inverse();
  std::vector<vpSelfCalibDataset::View> views;
  for (int k = 0; k < 9; ++k) {
    const vpHomogeneousMatrix fMc(0.03 * (k % 3 - 1), 0.03 * (k / 3 - 1), 0.05 * (k % 2), 0.3 * ((k % 3) - 1),
                                  0.3 * ((k / 3) % 3 - 1), 0.4 * k);
    vpSelfCalibDataset::View v;
    v.has_fMe = true;
    v.fMe = fMc * cMe;
    const Rigid cMf = rigidFromVisp(fMc).inverse();
    for (const auto &e : X) {
      const Eigen::Vector2d uv = lens.project(cMf * vec3(e.second));
      if (uv(0) > 0 && uv(0) < 640 && uv(1) > 0 && uv(1) < 480)
        v.points.push_back({e.first, vpImagePoint(uv(1), uv(0))});
    }
    views.push_back(v);
  }
  vpCameraParameters start;
  start.initPersProjWithoutDistortion(760, 760, 320, 246);
  vpKinematicBundleAdjustment::Options o;
  o.hand_eye_only = true;
  o.intrinsics = vpKinematicBundleAdjustment::FX | vpKinematicBundleAdjustment::ASPECT |
                 vpKinematicBundleAdjustment::PRINCIPAL_POINT | vpKinematicBundleAdjustment::DISTORTION;
  o.distortion_model = vpKinematicBundleAdjustment::DISTORTION_OPENCV;
  o.tight = true;
  const auto r = vpKinematicBundleAdjustment::adjust(truth, start, views, vpSelfCalibDataset::Yardstick(), X, o, vpSelfCalibNoiseModel());
  ASSERT_EQ(r.status, vpKinematicBundleAdjustment::OK) << r.message;
  const std::vector<std::string> names = {"fx", "mu", "u0", "v0", "k1", "k2", "p1", "p2"};
  EXPECT_EQ(r.intrinsic_names, names);
  ASSERT_EQ(r.opencv_distortion.size(), 5u);
  EXPECT_NEAR(r.camera.get_px(), in[0], 1e-6);
  EXPECT_NEAR(r.camera.get_py() / r.camera.get_px(), in[1], 1e-10);
  EXPECT_NEAR(r.camera.get_u0(), in[2], 1e-6);
  EXPECT_NEAR(r.camera.get_v0(), in[3], 1e-6);
  for (int i = 0; i < 5; ++i)
    EXPECT_NEAR(r.opencv_distortion[i], in[4 + i], 1e-8) << i;
  EXPECT_EQ(r.camera.get_kud(), 0.0);
  for (unsigned int i = 0; i < r.intrinsics_sd.size(); ++i)
    EXPECT_GT(r.intrinsics_sd[i], 0.0) << r.intrinsic_names[i];
  EXPECT_LT(translationDistance(r.chain.get_eMc_corrected(), truth.get_eMc_corrected()), 1e-8);

  vpKinematicBundleAdjustment::Options bad = o;
  bad.distortion_model = vpKinematicBundleAdjustment::DISTORTION_VISP;
  bad.opencv_distortion = {0, 0, 0, 0, 0};
  EXPECT_THROW(bad.check(), vpSelfCalibException);
  bad = o;
  bad.opencv_distortion = {0.1, 0.2};
  EXPECT_THROW(bad.check(), vpSelfCalibException);
  bad = o;
  bad.intrinsics = vpKinematicBundleAdjustment::FX | vpKinematicBundleAdjustment::DISTORTION_K3;
  EXPECT_THROW(bad.check(), vpSelfCalibException);
  vpCameraParameters kud;
  kud.initPersProjWithDistortion(760, 760, 320, 246, -0.1, 0.1);
  EXPECT_THROW(vpKinematicBundleAdjustment::adjust(truth, kud, views, vpSelfCalibDataset::Yardstick(), X, o, vpSelfCalibNoiseModel()),
               vpSelfCalibException);
}

namespace
{
/*
  The noise-free full-mode adjustment of 15 simulated views (the truth in the estimated
  coordinates) and the NEES of another estimate against it: corrections and f, with the estimate's
  own covariance. fixed: the parameters outside the noise-free estimated set (a guard only: the
  estimated set depends on the nominal model and the joints, so noisy runs estimate the same set).
*/
struct NoiseFreeReference {
  vpSelfCalibSimulator sim;
  vpSelfCalibDataset clean;
  vpKinematicBundleAdjustment::Result exact;
  std::vector<std::string> fixed;
  NoiseFreeReference(uint64_t seed, const vpKinematicBundleAdjustment::Options &o, const vpSelfCalibNoiseModel &noise)
    : sim(makeSim("viper850", seed, 0.0)), clean(sim.makeDataset(sim.generateConfigurations(15)))
  {
    exact = vpKinematicBundleAdjustment::adjust(sim.getNominalChain(), sim.getCamera(), clean.views, clean.yardstick,
                                                sim.getScenePointsById(), o, noise);
    const std::vector<unsigned int> &id = exact.identifiability.identified;
    const std::vector<std::string> names = sim.getNominalChain().getParameterNames();
    for (unsigned int i = 0; i < names.size(); ++i)
      if (std::find(id.begin(), id.end(), i) == id.end())
        fixed.push_back(names[i]);
  }
  double nees(const vpKinematicBundleAdjustment::Result &r) const
  {
    const std::vector<unsigned int> &id = exact.identifiability.identified;
    const unsigned int P = static_cast<unsigned int>(id.size());
    Eigen::MatrixXd C(P + 1, P + 1);
    for (unsigned int a = 0; a <= P; ++a)
      for (unsigned int b = 0; b <= P; ++b)
        C(a, b) = r.covariance[a][b];
    Eigen::VectorXd e(P + 1);
    for (unsigned int i = 0; i < P; ++i)
      e(i) = r.chain.getParameters()[id[i]] - exact.chain.getParameters()[id[i]];
    e(P) = r.camera.get_px() - exact.camera.get_px();
    return e.dot(C.ldlt().solve(e)) / (P + 1.0);
  }
};
} // namespace

/*
  Joint-reading noise (0.3 mrad per joint: backlash and compliance of a real arm) in the full
  kinematic mode, with 0.2 px pixel noise: modelled (joint_sd), the normalized estimation error of
  the corrections and f (against the noise-free solution) and sigma0 are near 1 over 12 draws; not
  modelled (readings trusted), the reported covariance is too small (NEES at least 2x larger). The
  joint corrections are reported. Bad settings are refused.
*/
TEST(KinematicBundleAdjustment, JointReadingNoiseIsModelledAndTheSdAreHonest)
{
  const double pixel_sd = 0.2, joint_sd = 3e-4;
  vpKinematicBundleAdjustment::Options o;
  vpSelfCalibNoiseModel noise;
  noise.pixel_sd = pixel_sd;
  const NoiseFreeReference ref(46, o, noise);
  ASSERT_EQ(ref.exact.status, vpKinematicBundleAdjustment::OK) << ref.exact.message;
  const vpSelfCalibSimulator &sim = ref.sim;
  const vpSelfCalibDataset &clean = ref.clean;
  const vpCameraParameters cam0 = sim.getCamera();
  const std::vector<unsigned int> &id = ref.exact.identifiability.identified;
  o.fixed = ref.fixed;
  auto nees = [&](const vpKinematicBundleAdjustment::Result &r) { return ref.nees(r); };
  Random rng(46, 7);
  double n_model = 0, n_trust = 0, sigma0 = 0, joint_rms = 0, measured = 0;
  const unsigned int trials = 16;
  unsigned int used = 0, skipped = 0;
  vpSelfCalibNoiseModel nm = noise;
  nm.joint_sd = {joint_sd};
  for (unsigned int t = 0; t < trials; ++t) {
    vpSelfCalibDataset ds = clean;
    addNoise(ds, pixel_sd, rng);
    for (auto &v : ds.views)
      for (unsigned int i = 0; i < v.q.size(); ++i)
        v.q[i] += rng.normal(joint_sd);
    const auto m = vpKinematicBundleAdjustment::adjust(sim.getNominalChain(), cam0, ds.views, ds.yardstick,
                                                       sim.getScenePointsById(), o, nm);
    ASSERT_EQ(m.status, vpKinematicBundleAdjustment::OK) << m.message;
    ASSERT_EQ(m.joint_corrections.size(), ds.views.size());
    const auto r = vpKinematicBundleAdjustment::adjust(sim.getNominalChain(), cam0, ds.views, ds.yardstick,
                                                       sim.getScenePointsById(), o, noise);
    ASSERT_EQ(r.status, vpKinematicBundleAdjustment::OK) << r.message;
    if (m.identifiability.identified != id || r.identifiability.identified != id) {
      ++skipped;
      continue;
    }
    ++used;
    n_model += nees(m);
    sigma0 += m.sigma0;
    joint_rms += m.joint_rms;
    // Variance components at the true sd give it back, one factor on every joint.
    ASSERT_EQ(m.measured.joint_sd.size(), ds.views[0].q.size());
    EXPECT_EQ(m.measured.joint_sd[0], m.measured.joint_sd.back());
    EXPECT_GT(m.measured.joint_sd[0], 0.6 * joint_sd);
    EXPECT_LT(m.measured.joint_sd[0], 1.6 * joint_sd);
    measured += m.measured.joint_sd[0];
    EXPECT_FALSE(m.measured.hasModelError()); // not modelled, not measured
    n_trust += nees(r);
  }
  ASSERT_GE(used, trials / 2) << skipped << " draws with another estimated set";
  n_model /= used;
  n_trust /= used;
  EXPECT_GT(n_model, 0.4);
  EXPECT_LT(n_model, 2.0);
  EXPECT_NEAR(sigma0 / used, 1.0, 0.25);
  EXPECT_GT(joint_rms / used, 0.3 * joint_sd);
  EXPECT_LT(joint_rms / used, joint_sd);
  EXPECT_NEAR(measured / used / joint_sd, 1.0, 0.2);
  EXPECT_GT(n_trust, 2 * n_model);

  vpSelfCalibNoiseModel bad = noise;
  bad.joint_sd = {-1e-3};
  EXPECT_THROW(bad.check(), vpSelfCalibException);
  bad.joint_sd = {1e-3, 1e-3};
  EXPECT_THROW(vpKinematicBundleAdjustment::adjust(sim.getNominalChain(), cam0, clean.views, clean.yardstick,
                                                   sim.getScenePointsById(), o, bad),
               vpSelfCalibException);
  bad.joint_sd = {1e-3};
  vpKinematicBundleAdjustment::Options hand_eye = o;
  hand_eye.hand_eye_only = true;
  EXPECT_THROW(vpKinematicBundleAdjustment::adjust(sim.getNominalChain(), cam0, clean.views, clean.yardstick,
                                                   sim.getScenePointsById(), hand_eye, bad),
               vpSelfCalibException);
}

/*
  The kinematic model's own residual in the full mode (model_sd_*: a camera pose correction per view
  in the camera frame): images taken from camera poses off the model by 1 mm / 1 mrad per view (what
  no kinematic parameter explains), 0.2 px noise. Modelled, the normalized estimation error of the
  corrections and f and sigma0 are near 1 over 12 draws, and the robot part of the residuals is
  reported; not modelled, runs fail or their covariance is too small (NEES at least 2x larger).
*/
TEST(KinematicBundleAdjustment, ModelResidualIsModelledInTheFullMode)
{
  const double pixel_sd = 0.2, sd_t = 1e-3, sd_r = 1e-3;
  vpKinematicBundleAdjustment::Options o;
  vpSelfCalibNoiseModel noise;
  noise.pixel_sd = pixel_sd;
  const NoiseFreeReference ref(47, o, noise);
  ASSERT_EQ(ref.exact.status, vpKinematicBundleAdjustment::OK) << ref.exact.message;
  const vpSelfCalibSimulator &sim = ref.sim;
  const vpSelfCalibDataset &clean = ref.clean;
  const vpCameraParameters cam0 = sim.getCamera();
  const std::vector<unsigned int> &id = ref.exact.identifiability.identified;
  o.fixed = ref.fixed;
  auto nees = [&](const vpKinematicBundleAdjustment::Result &r) { return ref.nees(r); };
  vpSelfCalibNoiseModel nm = noise;
  nm.model_sd_translation = sd_t;
  nm.model_sd_rotation = sd_r;
  Random rng(47, 7);
  const unsigned int trials = 12;
  double n_model = 0, n_trust = 0, sigma0 = 0, pose_rms = 0, measured_t = 0, measured_r = 0;
  unsigned int trusted_ok = 0;
  for (unsigned int t = 0; t < trials; ++t) {
    vpSelfCalibDataset ds = clean;
    for (auto &v : ds.views) {
      const double d[6] = {rng.normal(sd_t), rng.normal(sd_t), rng.normal(sd_t),
                           rng.normal(sd_r), rng.normal(sd_r), rng.normal(sd_r)};
      const Rigid cMf = (rigidFromVisp(sim.getTrueChain().get_fMc(v.q)) * rigidFromVector(d)).inverse();
      for (auto &ob : v.points) {
        const Eigen::Vector3d x = cMf * vec3(sim.getScenePoints()[ob.id]);
        ob.ip = vpImagePoint(cam0.get_v0() + cam0.get_py() * x(1) / x(2) + rng.normal(pixel_sd),
                             cam0.get_u0() + cam0.get_px() * x(0) / x(2) + rng.normal(pixel_sd));
      }
    }
    const auto m = vpKinematicBundleAdjustment::adjust(sim.getNominalChain(), cam0, ds.views, ds.yardstick,
                                                       sim.getScenePointsById(), o, nm);
    ASSERT_EQ(m.status, vpKinematicBundleAdjustment::OK) << m.message;
    ASSERT_EQ(m.identifiability.identified, id);
    ASSERT_EQ(m.pose_corrections.size(), ds.views.size());
    const auto r = vpKinematicBundleAdjustment::adjust(sim.getNominalChain(), cam0, ds.views, ds.yardstick,
                                                       sim.getScenePointsById(), o, noise);
    n_model += nees(m);
    if (r.status == vpKinematicBundleAdjustment::OK) {
      n_trust += nees(r);
      ++trusted_ok;
    }
    sigma0 += m.sigma0;
    pose_rms += m.pose_rms_translation;
    // Variance components at the true sd give it back.
    measured_t += m.measured.model_sd_translation;
    measured_r += m.measured.model_sd_rotation;
    EXPECT_TRUE(m.measured.joint_sd.empty());
  }
  EXPECT_NEAR(measured_t / trials / sd_t, 1.0, 0.2);
  EXPECT_NEAR(measured_r / trials / sd_r, 1.0, 0.2);
  n_model /= trials;
  EXPECT_GT(n_model, 0.4);
  EXPECT_LT(n_model, 2.0);
  EXPECT_NEAR(sigma0 / trials, 1.0, 0.25);
  EXPECT_GT(pose_rms / trials, 0.2 * sd_t);
  // Not modelled: runs that fail (the pose error breaks the estimate's conditioning) or report sd
  // too small.
  if (trusted_ok > 0)
    EXPECT_GT(n_trust / trusted_ok, 2 * n_model);
}
