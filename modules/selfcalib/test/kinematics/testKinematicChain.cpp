/*
 * Tests of vpKinematicChain: presets against ViSP, error model, analytic Jacobians against
 * central finite differences.
 */
#include <gtest/gtest.h>

#include <random>

#include <visp3/robot/vpViper850.h>
#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include "core/vpSelfCalibMath.h"

namespace
{
vpColVector randomJoints(const vpKinematicChain &c, std::mt19937 &rng)
{
  vpColVector q(c.getNumJoints());
  for (unsigned int i = 0; i < q.size(); ++i)
    q[i] = std::uniform_real_distribution<double>(c.getJointMin()[i], c.getJointMax()[i])(rng);
  return q;
}

vpColVector randomParameters(const vpKinematicChain &c, std::mt19937 &rng, double t_sd, double r_sd)
{
  vpColVector p(c.getNumParameters());
  std::normal_distribution<double> n(0, 1);
  for (unsigned int i = 0; i < p.size(); ++i)
    p[i] = n(rng) * ((i % 6) < 3 ? t_sd : r_sd);
  return p;
}

double maxAbsDiff(const vpHomogeneousMatrix &A, const vpHomogeneousMatrix &B)
{
  double m = 0;
  for (unsigned int i = 0; i < 3; ++i)
    for (unsigned int j = 0; j < 4; ++j)
      m = std::max(m, std::fabs(A[i][j] - B[i][j]));
  return m;
}

// 6-vector difference of camera poses in the Jacobian's convention (position in f, rotation in f).
vpColVector poseDelta(const vpHomogeneousMatrix &Mp, const vpHomogeneousMatrix &Mm)
{
  const vpSelfCalib::Rigid A = vpSelfCalib::rigidFromVisp(Mp), B = vpSelfCalib::rigidFromVisp(Mm);
  const Eigen::Vector3d dt = A.t - B.t;
  const Eigen::Vector3d dphi = vpSelfCalib::logSO3(A.R * B.R.transpose());
  vpColVector d(6);
  for (int k = 0; k < 3; ++k) {
    d[k] = dt(k);
    d[3 + k] = dphi(k);
  }
  return d;
}

// Relative agreement max|J - Jfd| / max(1, max|J|).
double relativeError(const vpMatrix &J, const vpMatrix &Jfd)
{
  double num = 0, den = 1;
  for (unsigned int i = 0; i < J.getRows(); ++i)
    for (unsigned int j = 0; j < J.getCols(); ++j) {
      num = std::max(num, std::fabs(J[i][j] - Jfd[i][j]));
      den = std::max(den, std::fabs(J[i][j]));
    }
  return num / den;
}
} // namespace

TEST(KinematicChain, Viper850PresetMatchesViSPAt1000RandomJointVectors)
{
  const vpKinematicChain chain = vpKinematicChain::preset("viper850");
  vpViper850 viper;
  ASSERT_EQ(chain.getNumJoints(), 6u);
  for (unsigned int i = 0; i < 6; ++i) {
    EXPECT_EQ(chain.getJointMin()[i], viper.getJointMin()[i]);
    EXPECT_EQ(chain.getJointMax()[i], viper.getJointMax()[i]);
  }
  std::mt19937 rng(42);
  double worst_c = 0, worst_e = 0;
  for (int k = 0; k < 1000; ++k) {
    const vpColVector q = randomJoints(chain, rng);
    vpHomogeneousMatrix fMc, fMe;
    viper.get_fMc(q, fMc);
    viper.get_fMe(q, fMe);
    worst_c = std::max(worst_c, maxAbsDiff(chain.get_fMc(q), fMc));
    worst_e = std::max(worst_e, maxAbsDiff(chain.get_fMe(q), fMe));
  }
  EXPECT_LT(worst_c, 1e-12);
  EXPECT_LT(worst_e, 1e-12);
}

TEST(KinematicChain, Puma560ReferencePoses)
{
  const vpKinematicChain chain = vpKinematicChain::preset("puma560");
  EXPECT_EQ(chain.getNumParameters(), 48u);
  // Corke's Robotics Toolbox: fkine(qz) has translation (a2 + a3, -d3, d4), fkine(qr) (a3, -d3, a2 + d4)
  // with the tool z axis pointing up.
  vpColVector q(6, 0.0);
  vpHomogeneousMatrix fMe = chain.get_fMe(q);
  EXPECT_NEAR(fMe[0][3], 0.4318 + 0.0203, 1e-12);
  EXPECT_NEAR(fMe[1][3], -0.15005, 1e-12);
  EXPECT_NEAR(fMe[2][3], 0.4318, 1e-12);
  q[1] = M_PI / 2;
  q[2] = -M_PI / 2;
  fMe = chain.get_fMe(q);
  EXPECT_NEAR(fMe[0][3], 0.0203, 1e-12);
  EXPECT_NEAR(fMe[1][3], -0.15005, 1e-12);
  EXPECT_NEAR(fMe[2][3], 0.8636, 1e-12);
  EXPECT_NEAR(fMe[2][2], 1.0, 1e-12);
}

TEST(KinematicChain, ParameterNamesAndAccess)
{
  vpKinematicChain chain = vpKinematicChain::preset("puma560");
  const std::vector<std::string> names = chain.getParameterNames();
  ASSERT_EQ(names.size(), 48u);
  EXPECT_EQ(names[0], "base.tx");
  EXPECT_EQ(names[6 + 5], "j1.rz");
  EXPECT_EQ(names[6 * 2 + 0], "j2.tx");
  EXPECT_EQ(names[47], "eMc.rz");
  chain.setParameter("j3.ry", 0.25);
  EXPECT_EQ(chain.getParameters()[chain.getParameterIndex("j3.ry")], 0.25);
  EXPECT_EQ(chain.getParameter("j3.ry"), 0.25);
  EXPECT_THROW(chain.getParameterIndex("j7.tx"), vpSelfCalibException);
  EXPECT_THROW(chain.setParameter("j1.rx", std::nan("")), vpSelfCalibException);
  EXPECT_THROW(chain.setParameters(vpColVector(3)), vpSelfCalibException);
  EXPECT_THROW(chain.get_fMc(vpColVector(5)), vpSelfCalibException);
  vpColVector q(6, 0.0);
  q[2] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(chain.get_fMc(q), vpSelfCalibException);
}

// The rz component of a joint correction is that joint's offset error; the eMc block moves the
// camera in its own frame; the base block moves everything in the base frame.
TEST(KinematicChain, CorrectionsHaveTheirDocumentedMeaning)
{
  const vpKinematicChain nominal = vpKinematicChain::preset("viper850");
  std::mt19937 rng(3);
  const vpColVector q = randomJoints(nominal, rng);
  for (unsigned int j = 1; j <= 6; ++j) {
    vpKinematicChain c = nominal;
    c.setParameter("j" + std::to_string(j) + ".rz", 0.01);
    vpColVector q2 = q;
    q2[j - 1] += 0.01;
    EXPECT_LT(maxAbsDiff(c.get_fMc(q), nominal.get_fMc(q2)), 1e-14) << "joint " << j;
  }
  vpKinematicChain c = nominal;
  const double v[6] = {0.01, -0.02, 0.03, 0.01, 0.02, -0.03};
  const char *comp[6] = {"tx", "ty", "tz", "rx", "ry", "rz"};
  for (int k = 0; k < 6; ++k)
    c.setParameter(std::string("eMc.") + comp[k], v[k]);
  EXPECT_LT(maxAbsDiff(c.get_fMc(q), nominal.get_fMc(q) * vpKinematicChain::correction(v)), 1e-14);
  vpKinematicChain b = nominal;
  for (int k = 0; k < 6; ++k)
    b.setParameter(std::string("base.") + comp[k], v[k]);
  EXPECT_LT(maxAbsDiff(b.get_fMc(q), vpKinematicChain::correction(v) * nominal.get_fMc(q)), 1e-14);
}

TEST(KinematicChain, ModifiedDHEqualsStandardDHOfTheSameArm)
{
  // A standard-DH arm rewritten in Craig's modified convention gives the same fMe up to the
  // convention's frame placement: the MDH row i carries alpha_{i-1}, a_{i-1}; the last DH link
  // becomes the flange.
  const vpKinematicChain dh = vpKinematicChain::preset("puma560");
  std::vector<vpKinematicChain::Joint> rows(6);
  const auto &j = dh.getJoints();
  for (unsigned int i = 0; i < 6; ++i) {
    rows[i] = j[i];
    rows[i].a = i == 0 ? 0.0 : j[i - 1].a;
    rows[i].alpha = i == 0 ? 0.0 : j[i - 1].alpha;
  }
  // flange = Tx(a6) Rx(alpha6) of the last DH row (both zero for the PUMA).
  const vpKinematicChain mdh("puma560-mdh", vpKinematicChain::MDH, rows);
  std::mt19937 rng(5);
  for (int k = 0; k < 100; ++k) {
    const vpColVector q = randomJoints(dh, rng);
    EXPECT_LT(maxAbsDiff(dh.get_fMe(q), mdh.get_fMe(q)), 1e-12);
  }
}

TEST(KinematicChain, IdentificationJacobianMatchesCentralDifferences)
{
  std::mt19937 rng(7);
  for (const char *name : {"puma560", "viper850"}) {
    for (int trial = 0; trial < 20; ++trial) {
      vpKinematicChain chain = vpKinematicChain::preset(name);
      // Small corrections as in calibration, and large ones (0.5 rad) to exercise the left Jacobian.
      const double rsd = trial % 2 ? 0.5 : 2e-3;
      chain.setParameters(randomParameters(chain, rng, 0.01, rsd));
      const vpColVector q = randomJoints(chain, rng);
      const vpMatrix J = chain.getJacobian(q);
      ASSERT_EQ(J.getRows(), 6u);
      ASSERT_EQ(J.getCols(), chain.getNumParameters());
      vpMatrix Jfd(6, chain.getNumParameters());
      const double h = 1e-6;
      for (unsigned int k = 0; k < chain.getNumParameters(); ++k) {
        vpKinematicChain cp = chain, cm = chain;
        vpColVector p = chain.getParameters();
        p[k] += h;
        cp.setParameters(p);
        p[k] -= 2 * h;
        cm.setParameters(p);
        const vpColVector d = poseDelta(cp.get_fMc(q), cm.get_fMc(q)) / (2 * h);
        for (unsigned int r = 0; r < 6; ++r)
          Jfd[r][k] = d[r];
      }
      EXPECT_LT(relativeError(J, Jfd), 1e-6) << name << " trial " << trial;
    }
  }
}

TEST(KinematicChain, JointJacobianMatchesCentralDifferences)
{
  std::mt19937 rng(11);
  for (const char *name : {"puma560", "viper850"}) {
    vpKinematicChain chain = vpKinematicChain::preset(name);
    chain.setParameters(randomParameters(chain, rng, 0.01, 0.05));
    for (int trial = 0; trial < 20; ++trial) {
      const vpColVector q = randomJoints(chain, rng);
      const vpMatrix J = chain.getJointJacobian(q);
      vpMatrix Jfd(6, chain.getNumJoints());
      const double h = 1e-6;
      for (unsigned int k = 0; k < chain.getNumJoints(); ++k) {
        vpColVector qp = q, qm = q;
        qp[k] += h;
        qm[k] -= h;
        const vpColVector d = poseDelta(chain.get_fMc(qp), chain.get_fMc(qm)) / (2 * h);
        for (unsigned int r = 0; r < 6; ++r)
          Jfd[r][k] = d[r];
      }
      EXPECT_LT(relativeError(J, Jfd), 1e-6) << name;
    }
  }
}

TEST(KinematicChain, BadConstructionThrows)
{
  std::vector<vpKinematicChain::Joint> rows(2);
  EXPECT_THROW(vpKinematicChain("x", vpKinematicChain::DH, {}), vpSelfCalibException);
  rows[1].min = 1;
  rows[1].max = 0;
  EXPECT_THROW(vpKinematicChain("x", vpKinematicChain::DH, rows), vpSelfCalibException);
  rows[1].max = 2;
  rows[0].a = std::nan("");
  EXPECT_THROW(vpKinematicChain("x", vpKinematicChain::DH, rows), vpSelfCalibException);
  EXPECT_THROW(vpKinematicChain::preset("kuka"), vpSelfCalibException);
  vpKinematicChain c = vpKinematicChain::preset("puma560");
  EXPECT_THROW(c.setJointLimits(vpColVector(6, 1.0), vpColVector(6, 0.0)), vpSelfCalibException);
}

// The Panda (7 axes, modified DH) and UR5 presets at their zero configurations, against the
// manufacturers' published zero poses of the flange: Panda (0.088, 0, 0.926) with the flange
// z axis pointing down; UR5 (a2 + a3, -(d4 + d6), d1 - d5) with the flange z axis along -y.
TEST(KinematicChain, PandaAndUr5PresetsAtZero)
{
  const vpKinematicChain panda = vpKinematicChain::preset("panda");
  ASSERT_EQ(panda.getNumJoints(), 7u);
  EXPECT_EQ(panda.getNumParameters(), 6u * 9u);
  const vpHomogeneousMatrix P = panda.get_fMe(vpColVector(7, 0.0));
  EXPECT_NEAR(P[0][3], 0.088, 1e-12);
  EXPECT_NEAR(P[1][3], 0.0, 1e-12);
  EXPECT_NEAR(P[2][3], 0.333 + 0.316 + 0.384 - 0.107, 1e-12);
  EXPECT_NEAR(P[0][0], 1.0, 1e-12);
  EXPECT_NEAR(P[1][1], -1.0, 1e-12);
  EXPECT_NEAR(P[2][2], -1.0, 1e-12);
  const vpKinematicChain ur5 = vpKinematicChain::preset("ur5");
  ASSERT_EQ(ur5.getNumJoints(), 6u);
  const vpHomogeneousMatrix U = ur5.get_fMe(vpColVector(6, 0.0));
  EXPECT_NEAR(U[0][3], -0.425 - 0.39225, 1e-12);
  EXPECT_NEAR(U[1][3], -(0.10915 + 0.0823), 1e-12);
  EXPECT_NEAR(U[2][3], 0.089159 - 0.09465, 1e-12);
  EXPECT_NEAR(U[1][2], -1.0, 1e-12);
}
