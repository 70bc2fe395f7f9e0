/*
 * Tests of the robot-model YAML: round trip, presets, and every malformed input named clearly.
 */
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <random>

#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

namespace
{
const char *kPumaYaml = R"(name: puma
convention: dh
joints:
  - {a: 0.0, d: 0.0, alpha: 1.5707963267948966, theta_offset: 0.0, min: -2.7925, max: 2.7925}
  - {a: 0.4318, d: 0.0, alpha: 0.0, min: -0.785, max: 3.927}
  - {a: 0.0203, d: 0.15005, alpha: -1.5707963267948966, min: -3.927, max: 0.785}
  - {a: 0.0, d: 0.4318, alpha: 1.5707963267948966, min: -1.92, max: 2.967}
  - {a: 0.0, d: 0.0, alpha: -1.5707963267948966, min: -1.745, max: 1.745}
  - {a: 0.0, d: 0.0, alpha: 0.0, min: -4.64, max: 4.64}
base: [0, 0, 0.672, 0, 0, 0.1]
flange: [0, 0, 0.05, 0, 0, 0]
eMc: [0, 0.06, 0.08, 0, 0, 0]
corrections: {j2.tx: 0.001, eMc.ry: -0.002}
)";

std::string tempPath(const std::string &name)
{
  return (testing::TempDir() + "/selfcalib_" + name);
}

void writeFile(const std::string &path, const std::string &text)
{
  std::ofstream(path) << text;
}

// Expects a vpSelfCalibException whose message contains every fragment.
void expectError(const std::string &yaml, const std::vector<std::string> &fragments)
{
  const std::string path = tempPath("bad.yaml");
  writeFile(path, yaml);
  try {
    vpKinematicChain::loadYaml(path);
    ADD_FAILURE() << "no exception for:\n" << yaml;
  } catch (const vpSelfCalibException &e) {
    const std::string msg = e.getStringMessage();
    EXPECT_NE(msg.find(path), std::string::npos) << "message does not name the file: " << msg;
    for (const std::string &f : fragments)
      EXPECT_NE(msg.find(f), std::string::npos) << "message '" << msg << "' lacks '" << f << "'";
  }
}

std::string replace(std::string s, const std::string &from, const std::string &to)
{
  const size_t p = s.find(from);
  EXPECT_NE(p, std::string::npos) << from;
  return p == std::string::npos ? s : s.replace(p, from.size(), to);
}
} // namespace

TEST(KinematicChainYaml, ReadsEveryField)
{
  const vpKinematicChain c = vpKinematicChain::fromYamlString(kPumaYaml);
  EXPECT_EQ(c.getName(), "puma");
  EXPECT_EQ(c.getConvention(), vpKinematicChain::DH);
  ASSERT_EQ(c.getNumJoints(), 6u);
  EXPECT_DOUBLE_EQ(c.getJoints()[2].d, 0.15005);
  EXPECT_DOUBLE_EQ(c.getJoints()[5].max, 4.64);
  EXPECT_DOUBLE_EQ(c.get_fMb_pose()[2], 0.672);
  EXPECT_DOUBLE_EQ(c.get_nMe_pose()[2], 0.05);
  EXPECT_DOUBLE_EQ(c.getParameter("j2.tx"), 0.001);
  EXPECT_DOUBLE_EQ(c.getParameter("eMc.ry"), -0.002);
  EXPECT_EQ(c.getParameter("j3.tx"), 0.0);
}

TEST(KinematicChainYaml, SaveLoadReproducesFMcExactly)
{
  std::mt19937 rng(1);
  std::normal_distribution<double> n(0, 1);
  for (const char *name : {"puma560", "viper850"}) {
    vpKinematicChain c = vpKinematicChain::preset(name);
    vpColVector p(c.getNumParameters());
    for (unsigned int i = 0; i < p.size(); ++i)
      p[i] = n(rng) * 1e-3;
    c.setParameters(p);
    const std::string path = tempPath(std::string(name) + ".yaml");
    c.saveYaml(path);
    const vpKinematicChain d = vpKinematicChain::loadYaml(path);
    EXPECT_EQ(d.getName(), c.getName());
    for (unsigned int i = 0; i < p.size(); ++i)
      EXPECT_EQ(d.getParameters()[i], p[i]);
    for (int k = 0; k < 100; ++k) {
      vpColVector q(6);
      for (unsigned int i = 0; i < 6; ++i)
        q[i] = std::uniform_real_distribution<double>(c.getJointMin()[i], c.getJointMax()[i])(rng);
      const vpHomogeneousMatrix A = c.get_fMc(q), B = d.get_fMc(q);
      for (unsigned int r = 0; r < 3; ++r)
        for (unsigned int s = 0; s < 4; ++s)
          ASSERT_EQ(A[r][s], B[r][s]) << name;
    }
    // A second round trip writes the same text.
    EXPECT_EQ(d.toYamlString(), c.toYamlString());
  }
}

TEST(KinematicChainYaml, PresetWithCorrections)
{
  const vpKinematicChain c =
      vpKinematicChain::fromYamlString("preset: viper850\ncorrections: {j4.rx: 0.001}\n");
  EXPECT_EQ(c.getName(), "viper850");
  EXPECT_DOUBLE_EQ(c.getParameter("j4.rx"), 0.001);
  EXPECT_EQ(vpKinematicChain::fromPresetOrFile("puma560").getName(), "puma560");
}

TEST(KinematicChainYaml, MalformedFilesNameFileKeyAndExpectation)
{
  expectError(replace(kPumaYaml, "convention: dh", "convention: xyz"), {"convention", "'dh' or 'mdh'", "xyz"});
  expectError(replace(kPumaYaml, "convention: dh\n", ""), {"convention", "missing"});
  expectError(replace(kPumaYaml, "{a: 0.4318, d: 0.0,", "{d: 0.0,"), {"joints[1].a", "missing"});
  expectError(replace(kPumaYaml, "alpha: 0.0, min: -0.785", "alpha: abc, min: -0.785"),
              {"joints[1].alpha", "expected a number", "abc"});
  expectError(replace(kPumaYaml, "alpha: 0.0, min: -0.785", "alpha: .nan, min: -0.785"),
              {"joints[1].alpha", "finite"});
  expectError(replace(kPumaYaml, "min: -1.745, max: 1.745", "min: 1.745, max: -1.745"),
              {"joints[4].min", "greater than max"});
  expectError(replace(kPumaYaml, "eMc: [0, 0.06, 0.08, 0, 0, 0]", "eMc: [0, 0.06, 0.08]"),
              {"eMc", "6 numbers", "list of 3"});
  expectError(replace(kPumaYaml, "base: [0, 0, 0.672, 0, 0, 0.1]", "base: [0, 0, x, 0, 0, 0.1]"),
              {"base[2]", "expected a number"});
  expectError(replace(kPumaYaml, "{j2.tx: 0.001", "{j9.tx: 0.001"), {"corrections.j9.tx", "unknown parameter"});
  expectError(replace(kPumaYaml, "flange:", "flang:"), {"flang", "unknown key"});
  expectError(replace(kPumaYaml, "alpha: 0.0, min: -0.785", "alpha: 0.0, mn: -0.785"),
              {"joints[1].mn", "unknown key"});
  expectError("joints: [\n", {"YAML syntax error", "line"});
  expectError("- 1\n- 2\n", {"map at the top level"});
  expectError("preset: kuka\n", {"preset", "unknown robot preset 'kuka'"});
  expectError("convention: dh\njoints: []\n", {"joints", "non-empty list"});
  expectError("convention: dh\njoints: [5]\n", {"joints[0]", "expected a map"});
  // Found by fuzzing (cmake/fuzz.sh): YAML allows a map or a list as a key; it escaped as a
  // yaml-cpp exception instead of an error naming the file.
  expectError("preset: viper850\ncorrections: {j2.tx: 0.001}\n? eMc: [0, 0, 0.1, 0, 0, 0]\n", {"keys are plain names"});
  expectError("preset: viper850\ncorrections: {[j2.tx]: 0.001}\n", {"corrections.(key)", "keys are plain names"});
}

// The camera fixed in the world: the file says camera_mount: world and holds the slot under bMc
// (no eMc key); read back, the model is marked so and gives the same bMc bit for bit, and the
// text is the same on a second round trip. An eye-in-hand model writes neither key.
TEST(KinematicChainYaml, CameraInTheWorldIsWrittenAsBMcAndReadBack)
{
  vpKinematicChain c = vpKinematicChain::preset("puma560");
  c.set_eMc(vpPoseVector(1.2, 0.1, 0.6, -1.4, -1.6, 1.1));
  c.setParameter("eMc.tx", 0.002);
  c.setParameter("j2.ry", -0.001);
  c.setCameraInWorld(true);
  const std::string text = c.toYamlString();
  EXPECT_NE(text.find("camera_mount: world\nbMc: [1.2"), std::string::npos) << text;
  EXPECT_EQ(text.find("eMc:"), std::string::npos) << text;
  const vpKinematicChain d = vpKinematicChain::fromYamlString(text);
  EXPECT_TRUE(d.isCameraInWorld());
  const vpHomogeneousMatrix A = c.get_eMc_corrected(), B = d.get_eMc_corrected();
  for (unsigned int r = 0; r < 3; ++r)
    for (unsigned int s = 0; s < 4; ++s)
      EXPECT_EQ(A[r][s], B[r][s]);
  EXPECT_EQ(d.getParameter("j2.ry"), -0.001);
  EXPECT_EQ(d.toYamlString(), text);
  const vpKinematicChain e = vpKinematicChain::fromYamlString(kPumaYaml);
  EXPECT_FALSE(e.isCameraInWorld());
  EXPECT_EQ(e.toYamlString().find("camera_mount"), std::string::npos);
  EXPECT_EQ(e.toYamlString().find("bMc"), std::string::npos);
  EXPECT_FALSE(vpKinematicChain::fromYamlString(replace(kPumaYaml, "eMc:", "camera_mount: effector\neMc:")).isCameraInWorld());
  // A preset with the camera in the world.
  const vpKinematicChain p =
      vpKinematicChain::fromYamlString("preset: viper850\ncamera_mount: world\nbMc: [1, 0, 0.5, 0, 0, 0]\n");
  EXPECT_TRUE(p.isCameraInWorld());
  EXPECT_DOUBLE_EQ(p.get_eMc_pose()[2], 0.5);
}

// The two slots are never mixed up: world with an eMc key, bMc without world, an unknown mount.
TEST(KinematicChainYaml, CameraMountAndSlotMustAgree)
{
  expectError(replace(kPumaYaml, "eMc:", "camera_mount: world\neMc:"),
              {"eMc", "camera_mount: world holds the camera in the base frame under the key bMc"});
  expectError(replace(kPumaYaml, "eMc:", "bMc:"), {"bMc", "needs camera_mount: world"});
  expectError(replace(kPumaYaml, "eMc:", "camera_mount: ceiling\neMc:"),
              {"camera_mount", "expected effector", "or world", "'ceiling'"});
}

TEST(KinematicChainYaml, UnreadableFileIsNamed)
{
  const std::string path = tempPath("does-not-exist.yaml");
  try {
    vpKinematicChain::loadYaml(path);
    FAIL();
  } catch (const vpSelfCalibException &e) {
    EXPECT_NE(e.getStringMessage().find(path), std::string::npos);
    EXPECT_NE(e.getStringMessage().find("cannot read: No such file or directory"), std::string::npos)
        << e.getStringMessage();
  }
  EXPECT_THROW(vpKinematicChain::fromPresetOrFile("kuka"), vpSelfCalibException);
}

TEST(KinematicChainYaml, SaveDoesNotLeaveTemporaryFiles)
{
  const std::string path = tempPath("saved.yaml");
  vpKinematicChain::preset("puma560").saveYaml(path);
  std::ifstream tmp(path + ".tmp");
  EXPECT_FALSE(tmp.good());
  EXPECT_THROW(vpKinematicChain::preset("puma560").saveYaml("/nonexistent-dir/x.yaml"), vpSelfCalibException);
}
