/*
 * Tests of vpKinematicChainUrdf: the UR5 and Panda URDFs (test/io/data, written from the public
 * kinematic tables) against the DH / modified-DH presets; round trips through vpModelExport::toURDF;
 * calibrations of the imported and the preset robot; bad URDFs.
 */
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include <visp3/selfcalib/vpKinematicChainUrdf.h>
#include <visp3/selfcalib/vpModelExport.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "core/vpSelfCalibRandom.h"

#ifndef SELFCALIB_TEST_DATA
#error "SELFCALIB_TEST_DATA (modules/selfcalib/test/io/data) must be defined"
#endif

namespace
{
const std::string kData = SELFCALIB_TEST_DATA;

double maxDiff(const vpHomogeneousMatrix &A, const vpHomogeneousMatrix &B)
{
  double e = 0;
  for (unsigned int r = 0; r < 3; ++r)
    for (unsigned int c = 0; c < 4; ++c)
      e = std::max(e, std::fabs(A[r][c] - B[r][c]));
  return e;
}

vpColVector randomJoints(const vpKinematicChain &c, vpSelfCalib::Random &rng)
{
  vpColVector q(c.getNumJoints());
  for (unsigned int i = 0; i < q.size(); ++i)
    q[i] = rng.uniform(c.getJoints()[i].min, c.getJoints()[i].max);
  return q;
}

// Largest fMc difference over n random joint vectors within a's limits.
double fkDifference(const vpKinematicChain &a, const vpKinematicChain &b, uint64_t seed, int n = 200)
{
  vpSelfCalib::Random rng(seed, 1);
  double e = 0;
  for (int k = 0; k < n; ++k) {
    const vpColVector q = randomJoints(a, rng);
    e = std::max(e, maxDiff(a.get_fMc(q), b.get_fMc(q)));
  }
  return e;
}

// Two tables row by row (DH parameters and limits), and their frames.
void expectSameTable(const vpKinematicChain &a, const vpKinematicChain &b, double tol)
{
  ASSERT_EQ(a.getConvention(), b.getConvention());
  ASSERT_EQ(a.getNumJoints(), b.getNumJoints());
  for (unsigned int i = 0; i < a.getNumJoints(); ++i) {
    const auto &x = a.getJoints()[i], &y = b.getJoints()[i];
    EXPECT_NEAR(x.a, y.a, tol) << "row " << i + 1;
    EXPECT_NEAR(x.d, y.d, tol) << "row " << i + 1;
    EXPECT_NEAR(x.alpha, y.alpha, tol) << "row " << i + 1;
    EXPECT_NEAR(x.theta_offset, y.theta_offset, tol) << "row " << i + 1;
  }
  EXPECT_LT(maxDiff(a.get_fMb(), b.get_fMb()), tol);
  EXPECT_LT(maxDiff(a.get_nMe(), b.get_nMe()), tol);
  EXPECT_LT(maxDiff(a.get_eMc(), b.get_eMc()), tol);
}

vpKinematicChainUrdf::Options ur5Options(vpKinematicChainUrdf::Convention c = vpKinematicChainUrdf::DH)
{
  vpKinematicChainUrdf::Options o;
  o.convention = c;
  o.eMc = vpKinematicChain::preset("ur5").get_eMc_pose();
  return o;
}

vpKinematicChainUrdf::Options pandaOptions(vpKinematicChainUrdf::Convention c = vpKinematicChainUrdf::MDH)
{
  vpKinematicChainUrdf::Options o;
  o.convention = c;
  o.tip_link = "panda_link8";
  o.eMc = vpKinematicChain::preset("panda").get_eMc_pose();
  return o;
}

std::string readText(const std::string &path)
{
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The message of the vpSelfCalibException thrown by f (empty when nothing is thrown).
template <class F> std::string errorOf(F f)
{
  try {
    f();
  } catch (const vpSelfCalibException &e) {
    return e.getStringMessage();
  }
  return "";
}
} // namespace

// The URDFs written from the public tables give the presets' tables back (DH for the UR5, Craig's
// modified DH for the Panda) and their forward kinematics to 1e-12 over random joint vectors.
TEST(Urdf, Ur5AndPandaMatchTheirDhPresets)
{
  const vpKinematicChain ur5 = vpKinematicChainUrdf::load(kData + "/ur5.urdf", ur5Options());
  EXPECT_EQ(ur5.getName(), "ur5");
  expectSameTable(ur5, vpKinematicChain::preset("ur5"), 1e-12);
  EXPECT_LT(fkDifference(ur5, vpKinematicChain::preset("ur5"), 1), 1e-12);

  const vpKinematicChain panda = vpKinematicChainUrdf::load(kData + "/panda.urdf", pandaOptions());
  ASSERT_EQ(panda.getNumJoints(), 7u);
  expectSameTable(panda, vpKinematicChain::preset("panda"), 1e-12);
  EXPECT_LT(fkDifference(panda, vpKinematicChain::preset("panda"), 2), 1e-12);
  EXPECT_NEAR(panda.getJoints()[3].max, -0.0698, 1e-15); // limits read
  EXPECT_NEAR(panda.getJoints()[5].min, -0.0175, 1e-15);

  // In the other convention (and with AUTO, which takes the one the joint frames follow: both
  // files place their joints in modified-DH form) the table differs, the robot does not.
  for (auto c : {vpKinematicChainUrdf::MDH, vpKinematicChainUrdf::AUTO}) {
    const vpKinematicChain u = vpKinematicChainUrdf::load(kData + "/ur5.urdf", ur5Options(c));
    EXPECT_EQ(u.getConvention(), vpKinematicChain::MDH);
    EXPECT_LT(fkDifference(u, vpKinematicChain::preset("ur5"), 3), 1e-12);
  }
  const vpKinematicChain p_dh = vpKinematicChainUrdf::load(kData + "/panda.urdf", pandaOptions(vpKinematicChainUrdf::DH));
  EXPECT_EQ(p_dh.getConvention(), vpKinematicChain::DH);
  EXPECT_LT(fkDifference(p_dh, vpKinematicChain::preset("panda"), 4), 1e-12);
  EXPECT_EQ(vpKinematicChainUrdf::load(kData + "/panda.urdf", pandaOptions(vpKinematicChainUrdf::AUTO)).getConvention(),
            vpKinematicChain::MDH);

  // Default tip of the Panda file: where the chain branches (the hand, turned by -45 degrees).
  const vpKinematicChain hand = vpKinematicChainUrdf::load(kData + "/panda.urdf");
  const vpHomogeneousMatrix nMhand(0, 0, 0, 0, 0, -M_PI / 4);
  vpSelfCalib::Random rng(5, 1);
  const vpColVector q = randomJoints(hand, rng);
  EXPECT_LT(maxDiff(hand.get_fMe(q), vpKinematicChain::preset("panda").get_fMe(q) * nMhand), 1e-12);
}

// Axes other than +z, fixed joints between the revolute ones, a base link off the first axis and a
// camera link: the imported chain's forward kinematics is the URDF's (composed here by hand).
TEST(Urdf, GeneralAxesFixedJointsAndCameraLink)
{
  const std::string urdf = R"(<?xml version="1.0"?>
<robot name="odd">
  <link name="world"/><link name="base"/><link name="l1"/><link name="l1b"/><link name="l2"/><link name="l3"/>
  <link name="tool"/><link name="cam_mount"/><link name="cam"/>
  <joint name="w" type="fixed"><parent link="world"/><child link="base"/><origin xyz="0.1 -0.2 0.05" rpy="0 0 0.3"/></joint>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><origin xyz="0.02 0.01 0.3" rpy="0.1 0 0"/>
    <axis xyz="0 0 -1"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="f1" type="fixed"><parent link="l1"/><child link="l1b"/><origin xyz="0 0.05 0.1" rpy="0 0.2 0"/></joint>
  <joint name="j2" type="continuous"><parent link="l1b"/><child link="l2"/><origin xyz="0 0 0.1" rpy="0 0 0"/>
    <axis xyz="0 1 0"/></joint>
  <joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/><origin xyz="0.4 0.03 0" rpy="0 0 0"/>
    <axis xyz="0.6 0 0.8"/><limit lower="-1" upper="1.5" effort="1" velocity="1"/></joint>
  <joint name="t" type="fixed"><parent link="l3"/><child link="tool"/><origin xyz="0.1 0 0.02" rpy="0 1.5707963267948966 0"/></joint>
  <joint name="m" type="fixed"><parent link="tool"/><child link="cam_mount"/><origin xyz="0 0.05 0" rpy="0 0 0"/></joint>
  <joint name="c" type="fixed"><parent link="cam_mount"/><child link="cam"/><origin xyz="0 0 0.03" rpy="0 0 1.5707963267948966"/></joint>
</robot>)";
  vpKinematicChainUrdf::Options o;
  o.base_link = "world";
  o.tip_link = "tool";
  o.camera_link = "cam";
  for (auto conv : {vpKinematicChainUrdf::DH, vpKinematicChainUrdf::MDH}) {
    o.convention = conv;
    const vpKinematicChain chain = vpKinematicChainUrdf::fromString(urdf, o, "odd");
    ASSERT_EQ(chain.getNumJoints(), 3u);
    EXPECT_DOUBLE_EQ(chain.getJoints()[0].min, -2);
    EXPECT_DOUBLE_EQ(chain.getJoints()[1].max, M_PI); // continuous
    // The URDF composed by hand: origin, then the rotation about the axis.
    const auto T = [](double x, double y, double z, double r, double p, double yw) {
      return vpHomogeneousMatrix(vpTranslationVector(x, y, z), vpRotationMatrix(vpRxyzVector(0, 0, 0)) *
                                                                 vpRotationMatrix(vpThetaUVector(0, 0, yw)) *
                                                                 vpRotationMatrix(vpThetaUVector(0, p, 0)) *
                                                                 vpRotationMatrix(vpThetaUVector(r, 0, 0)));
    };
    const auto R = [](double x, double y, double z, double q) {
      const double n = std::sqrt(x * x + y * y + z * z);
      return vpHomogeneousMatrix(0, 0, 0, q * x / n, q * y / n, q * z / n);
    };
    vpSelfCalib::Random rng(6, 1);
    double err = 0;
    for (int k = 0; k < 50; ++k) {
      const vpColVector q = randomJoints(chain, rng);
      const vpHomogeneousMatrix fMtool = T(0.1, -0.2, 0.05, 0, 0, 0.3) * T(0.02, 0.01, 0.3, 0.1, 0, 0) *
                                         R(0, 0, -1, q[0]) * T(0, 0.05, 0.1, 0, 0.2, 0) * T(0, 0, 0.1, 0, 0, 0) *
                                         R(0, 1, 0, q[1]) * T(0.4, 0.03, 0, 0, 0, 0) * R(0.6, 0, 0.8, q[2]) *
                                         T(0.1, 0, 0.02, 0, M_PI / 2, 0);
      const vpHomogeneousMatrix fMcam = fMtool * T(0, 0.05, 0, 0, 0, 0) * T(0, 0, 0.03, 0, 0, M_PI / 2);
      err = std::max({err, maxDiff(chain.get_fMe(q), fMtool), maxDiff(chain.get_fMc(q), fMcam)});
    }
    EXPECT_LT(err, 1e-12);
  }
}

// Import -> export (vpModelExport::toURDF) -> import gives the same table, frames and forward
// kinematics, in both conventions; a calibrated model (corrections on every joint) exported and
// imported keeps its forward kinematics.
TEST(Urdf, RoundTripThroughTheExportIsExact)
{
  const vpKinematicChain ur5 = vpKinematicChainUrdf::load(kData + "/ur5.urdf", ur5Options());
  const vpKinematicChain panda = vpKinematicChainUrdf::load(kData + "/panda.urdf", pandaOptions());
  for (const vpKinematicChain &a : {ur5, panda}) {
    const vpKinematicChain b = vpKinematicChainUrdf::fromString(vpModelExport::toURDF(a), vpKinematicChainUrdf::Options(), "export");
    expectSameTable(a, b, 1e-12);
    EXPECT_LT(fkDifference(a, b, 7), 1e-12);
    const vpKinematicChain c = vpKinematicChainUrdf::fromString(vpModelExport::toURDF(b), vpKinematicChainUrdf::Options(), "export 2");
    expectSameTable(b, c, 1e-12);
  }
  for (const std::string robot : {"ur5", "panda", "viper850", "puma560"}) {
    vpSelfCalibSimulator::Options so;
    so.seed = 8;
    vpKinematicChain calibrated = vpKinematicChain::preset(robot);
    vpSelfCalib::Random rng(8, 3);
    vpColVector p(calibrated.getNumParameters());
    for (unsigned int i = 0; i < p.size(); ++i)
      p[i] = rng.normal(i % 6 < 3 ? 1e-3 : 2e-3);
    calibrated.setParameters(p);
    const vpKinematicChain imported = vpKinematicChainUrdf::fromString(vpModelExport::toURDF(calibrated), vpKinematicChainUrdf::Options(), robot);
    EXPECT_EQ(imported.getConvention(), calibrated.getConvention()) << robot;
    // Nearly parallel axes (UR5 2-3-4, PUMA and Viper 2-3) put the common normals hundreds of
    // metres away: the table is exact but its rounding is amplified (vpModelExport says the same).
    EXPECT_LT(fkDifference(calibrated, imported, 9), 1e-10) << robot;
    const vpKinematicChain again = vpKinematicChainUrdf::fromString(vpModelExport::toURDF(imported), vpKinematicChainUrdf::Options(), robot);
    expectSameTable(imported, again, 1e-12);
    EXPECT_LT(fkDifference(imported, again, 10), 1e-12) << robot;
  }
}

// The tools read a robot model named *.urdf through vpKinematicChain::fromPresetOrFile.
TEST(Urdf, ToolsReadUrdfFilesByTheirExtension)
{
  EXPECT_TRUE(vpKinematicChainUrdf::isUrdfFile("a/b/Robot.URDF"));
  EXPECT_FALSE(vpKinematicChainUrdf::isUrdfFile("robot.urdf.yaml"));
  const vpKinematicChain u = vpKinematicChain::fromPresetOrFile(kData + "/ur5.urdf");
  EXPECT_EQ(u.getNumJoints(), 6u);
  vpSelfCalib::Random rng(11, 1);
  for (int k = 0; k < 20; ++k) {
    const vpColVector q = randomJoints(u, rng);
    EXPECT_LT(maxDiff(u.get_fMe(q), vpKinematicChain::preset("ur5").get_fMe(q)), 1e-12);
  }
}

// A URDF robot and the same robot from its DH table calibrate identically on noise-free simulated
// data: same estimated set, same held-out errors (to 1e-9); the UR5 (DH) and the Panda (7 axes, MDH).
TEST(Urdf, ImportedAndPresetRobotsCalibrateIdentically)
{
  for (const std::string robot : {"ur5", "panda"}) {
    const vpKinematicChain preset = vpKinematicChain::preset(robot);
    const vpKinematicChain urdf = robot == "ur5" ? vpKinematicChainUrdf::load(kData + "/ur5.urdf", ur5Options())
                                                 : vpKinematicChainUrdf::load(kData + "/panda.urdf", pandaOptions());
    vpSelfCalibSimulator::Options so;
    so.seed = 21;
    so.pixel_noise_sd = 0;
    if (robot == "ur5")
      so.home = vpColVector({0.3, -1.9, 1.9, -1.3, -1.57, 0.2});
    const vpSelfCalibSimulator sim(preset, so);
    const vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(20));
    vpRobotSelfCalibration::Options o;
    o.num_calibration_poses = 14;
    o.trust_robot = true; // exact joints: the two models of one robot are the subject
    // Noise-free: without the kinematic prior, whose pull toward nominal leaves residuals the
    // robot-error check takes for each camera's own displacement.
    o.bundle.kinematic_prior = vpKinematicBundleAdjustment::KINEMATIC_PRIOR_OFF;
    const auto a = vpRobotSelfCalibration::run(preset, ds, o);
    const auto b = vpRobotSelfCalibration::run(urdf, ds, o);
    ASSERT_EQ(a.status, vpRobotSelfCalibration::OK) << robot << ": " << a.message;
    ASSERT_EQ(b.status, vpRobotSelfCalibration::OK) << robot << ": " << b.message;
    EXPECT_EQ(a.identifiability.identified, b.identifiability.identified) << robot;
    EXPECT_EQ(a.identifiability.identified.size(), 4u * preset.getNumJoints()) << robot;
    ASSERT_TRUE(a.verified && b.verified);
    ASSERT_EQ(a.after.position_errors.size(), b.after.position_errors.size());
    for (size_t i = 0; i < a.after.position_errors.size(); ++i) {
      EXPECT_NEAR(a.after.position_errors[i], b.after.position_errors[i], 1e-9) << robot;
      EXPECT_NEAR(a.after.rotation_errors[i], b.after.rotation_errors[i], 1e-9) << robot;
    }
    EXPECT_NEAR(a.after.yardstick_error, b.after.yardstick_error, 1e-9) << robot;
    EXPECT_LT(a.after.position_error_mean, 1e-6) << robot; // noise-free: exact recovery
  }
}

// Bad URDFs: a clear message for each.
TEST(Urdf, BadFilesAreRefusedWithAClearMessage)
{
  const std::string head = "<?xml version=\"1.0\"?><robot name=\"r\"><link name=\"a\"/><link name=\"b\"/><link name=\"c\"/>";
  const auto rev = [](const std::string &name, const std::string &p, const std::string &c) {
    return "<joint name=\"" + name + "\" type=\"revolute\"><parent link=\"" + p + "\"/><child link=\"" + c +
           "\"/><axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" effort=\"0\" velocity=\"0\"/></joint>";
  };
  // Loops: a full cycle (no root) and a link with two parents.
  EXPECT_NE(errorOf([&] { vpKinematicChainUrdf::fromString(head + rev("j1", "a", "b") + rev("j2", "b", "c") + rev("j3", "c", "a") + "</robot>", vpKinematicChainUrdf::Options(), "cycle"); })
                .find("URDF cycle: the joints form a loop"),
            std::string::npos);
  const std::string two_parents =
      "<robot name=\"r\"><link name=\"w\"/><link name=\"a\"/><link name=\"b\"/><link name=\"c\"/>"
      "<joint name=\"j0\" type=\"fixed\"><parent link=\"w\"/><child link=\"a\"/></joint>" +
      rev("j1", "a", "b") + rev("j2", "b", "c") + rev("j3", "c", "a") + "</robot>";
  const std::string loop = errorOf([&] { vpKinematicChainUrdf::fromString(two_parents, vpKinematicChainUrdf::Options(), "loop"); });
  EXPECT_NE(loop.find("the joints form a loop: link 'a' is the child of joints"), std::string::npos) << loop;
  // A prismatic joint on the chain.
  vpKinematicChainUrdf::Options o;
  o.tip_link = "panda_leftfinger";
  const std::string pris = errorOf([&] { vpKinematicChainUrdf::load(kData + "/panda.urdf", o); });
  EXPECT_NE(pris.find("joint 'panda_finger_joint1' between 'panda_link0' and 'panda_leftfinger' is prismatic: only "
                      "revolute, continuous and fixed joints are supported"),
            std::string::npos)
      << pris;
  // Missing links, a tip above the base, a camera behind a moving joint.
  o.tip_link = "panda_link9";
  EXPECT_NE(errorOf([&] { vpKinematicChainUrdf::load(kData + "/panda.urdf", o); }).find("no link named 'panda_link9' (the tip link)"),
            std::string::npos);
  o.tip_link = "panda_link2";
  o.base_link = "panda_link4";
  EXPECT_NE(errorOf([&] { vpKinematicChainUrdf::load(kData + "/panda.urdf", o); })
                .find("the tip link 'panda_link2' is not below the base link 'panda_link4'"),
            std::string::npos);
  o = vpKinematicChainUrdf::Options();
  o.tip_link = "panda_link3";
  o.camera_link = "panda_link8";
  EXPECT_NE(errorOf([&] { vpKinematicChainUrdf::load(kData + "/panda.urdf", o); })
                .find("through revolute joint 'panda_joint4': only fixed joints may follow the tip"),
            std::string::npos);
  o.camera_link = "panda_link1";
  EXPECT_NE(errorOf([&] { vpKinematicChainUrdf::load(kData + "/panda.urdf", o); })
                .find("the camera link 'panda_link1' is not below the tip link 'panda_link3'"),
            std::string::npos);
  // Malformed: not XML, a revolute joint without limits, only fixed joints, a missing file.
  EXPECT_NE(errorOf([] { vpKinematicChainUrdf::fromString("<robot name='x'><link name='a'/>", vpKinematicChainUrdf::Options(), "cut"); })
                .find("URDF cut: malformed URDF:"),
            std::string::npos);
  EXPECT_NE(errorOf([] {
              vpKinematicChainUrdf::fromString("<robot name='x'><link name='a'/><link name='b'/><joint name='j' type='revolute'>"
                                               "<parent link='a'/><child link='b'/></joint></robot>",
                                               {}, "nolimits");
            }).find("does not specify limits"),
            std::string::npos);
  EXPECT_NE(errorOf([] {
              vpKinematicChainUrdf::fromString("<robot name='x'><link name='a'/><link name='b'/><joint name='j' type='fixed'>"
                                               "<parent link='a'/><child link='b'/></joint></robot>",
                                               {}, "fixed");
            }).find("no revolute joint between 'a' and 'b'"),
            std::string::npos);
  try {
    vpKinematicChainUrdf::load("/nonexistent/robot.urdf");
    ADD_FAILURE() << "no exception";
  } catch (const vpSelfCalibException &e) {
    EXPECT_EQ(e.getCode(), vpSelfCalibException::ioError);
    EXPECT_NE(e.getStringMessage().find("'/nonexistent/robot.urdf': cannot read: No such file or directory"),
              std::string::npos);
  }
  // A file without end (a device) is refused at once, not read until memory runs out.
  try {
    vpKinematicChainUrdf::load("/dev/zero");
    ADD_FAILURE() << "no exception";
  } catch (const vpSelfCalibException &e) {
    EXPECT_NE(e.getStringMessage().find("'/dev/zero': a NUL byte on line 1: not a text file"), std::string::npos)
        << e.getStringMessage();
  }
}
