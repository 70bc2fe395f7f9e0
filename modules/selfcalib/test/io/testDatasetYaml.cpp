/*
 * Tests of the dataset file: round trip, relative paths, camera XML with distortion, bad input.
 */
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>

#include <visp3/core/vpMeterPixelConversion.h>
#include <visp3/core/vpXmlParserCamera.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

namespace
{
vpSelfCalibDataset simulated(bool focal_known)
{
  vpSelfCalibSimulator::Options o;
  o.seed = 61;
  const vpSelfCalibSimulator sim(vpKinematicChain::preset("viper850"), o);
  vpSelfCalibDataset ds = sim.makeDataset(sim.generateConfigurations(4));
  ds.focal_known = focal_known;
  if (!focal_known)
    ds.cam.initPersProjWithoutDistortion(1400, 1400, ds.cam.get_u0(), ds.cam.get_v0());
  // A controller pose instead of joints (a pose with both is refused as ambiguous).
  ds.views[1].has_fMe = true;
  ds.views[1].fMe = sim.getNominalChain().get_fMe(ds.views[1].q);
  ds.views[1].q = vpColVector();
  return ds;
}

void expectSame(const vpSelfCalibDataset &a, const vpSelfCalibDataset &b)
{
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  EXPECT_EQ(a.focal_known, b.focal_known);
  EXPECT_EQ(a.cam.get_px(), b.cam.get_px());
  EXPECT_EQ(a.cam.get_py(), b.cam.get_py());
  EXPECT_EQ(a.cam.get_u0(), b.cam.get_u0());
  EXPECT_EQ(a.cam.get_v0(), b.cam.get_v0());
  EXPECT_EQ(a.robot, b.robot);
  EXPECT_EQ(a.camera_mount, b.camera_mount);
  ASSERT_EQ(a.views.size(), b.views.size());
  for (size_t k = 0; k < a.views.size(); ++k) {
    ASSERT_EQ(a.views[k].q.size(), b.views[k].q.size());
    for (unsigned int i = 0; i < a.views[k].q.size(); ++i)
      EXPECT_EQ(a.views[k].q[i], b.views[k].q[i]);
    EXPECT_EQ(a.views[k].has_fMe, b.views[k].has_fMe);
    if (a.views[k].has_fMe)
      for (unsigned int i = 0; i < 3; ++i)
        for (unsigned int j = 0; j < 4; ++j)
          EXPECT_NEAR(a.views[k].fMe[i][j], b.views[k].fMe[i][j], 1e-15);
    EXPECT_EQ(a.views[k].image, b.views[k].image);
    ASSERT_EQ(a.views[k].points.size(), b.views[k].points.size());
    for (size_t j = 0; j < a.views[k].points.size(); ++j) {
      EXPECT_EQ(a.views[k].points[j].id, b.views[k].points[j].id);
      EXPECT_EQ(a.views[k].points[j].ip.get_u(), b.views[k].points[j].ip.get_u());
      EXPECT_EQ(a.views[k].points[j].ip.get_v(), b.views[k].points[j].ip.get_v());
    }
  }
  EXPECT_EQ(a.yardstick.length, b.yardstick.length);
  EXPECT_EQ(a.yardstick.id_a, b.yardstick.id_a);
  EXPECT_EQ(a.yardstick.id_b, b.yardstick.id_b);
}

// The message of the exception thrown by parsing text, or "" when none.
std::string parseError(const std::string &yaml)
{
  try {
    vpSelfCalibDataset::fromYamlString(yaml, "<test>");
  } catch (const vpSelfCalibException &e) {
    return e.getStringMessage();
  }
  return "";
}

const std::string kHead = "camera: {width: 640, height: 480, u0: 320, v0: 240, px: 1500, py: 1500}\nrobot: viper850\n";
} // namespace

TEST(DatasetYaml, RoundTripIsExact)
{
  for (bool known : {true, false}) {
    const vpSelfCalibDataset ds = simulated(known);
    expectSame(ds, vpSelfCalibDataset::fromYamlString(ds.toYamlString()));
  }
}

// Found by fuzzing (cmake/fuzz.sh): a controller pose written as theta-u from its matrix came back
// one ulp off (0.12 -> 0.12000000000000001 -> 0.12000000000000002...), drifting at every write and
// read. The text read, written and read again is now a fixed point, and the value read is kept.
TEST(DatasetYaml, ControllerPoseRoundTripDoesNotDrift)
{
  const std::string text = "camera: {width: 640, height: 480, u0: 320, v0: 240, px: 1500, py: 1500}\n"
                           "robot: viper850\nposes:\n  - fMe: [0.1, 0.2, 0.3, 0, 0.12, 0]\n"
                           "    points: [[0, 300.5, 241.25], [1, 400.0, 190.7]]\n";
  const vpSelfCalibDataset a = vpSelfCalibDataset::fromYamlString(text);
  const std::string written = a.toYamlString();
  EXPECT_NE(written.find("0.12, 0]"), std::string::npos) << written;
  const vpSelfCalibDataset b = vpSelfCalibDataset::fromYamlString(written);
  EXPECT_EQ(b.toYamlString(), written);
  for (unsigned int r = 0; r < 3; ++r)
    for (unsigned int c = 0; c < 4; ++c)
      EXPECT_EQ(a.views[0].fMe[r][c], b.views[0].fMe[r][c]);
}

TEST(DatasetYaml, FileRoundTripWithRelativePaths)
{
  char dir[] = "/tmp/selfcalib-dataset-XXXXXX";
  ASSERT_NE(mkdtemp(dir), nullptr);
  vpSelfCalibDataset ds = simulated(true);
  ds.views[0].image = std::string(dir) + "/images/0001.png";
  ds.views[2].image = "/elsewhere/0003.png";
  const std::string file = std::string(dir) + "/dataset.yaml";
  ds.saveYaml(file);
  std::ifstream in(file);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("image: images/0001.png"), std::string::npos);
  EXPECT_NE(text.find("image: /elsewhere/0003.png"), std::string::npos);
  expectSame(ds, vpSelfCalibDataset::loadYaml(file));
  std::remove(file.c_str());
  rmdir(dir);
}

// A camera XML with ViSP's distortion model: observations are undistorted on reading.
TEST(DatasetYaml, CameraXmlDistortionIsAppliedToObservations)
{
  char dir[] = "/tmp/selfcalib-xml-XXXXXX";
  ASSERT_NE(mkdtemp(dir), nullptr);
  vpCameraParameters cam;
  const double kud = -0.05, kdu = 0.05;
  cam.initPersProjWithDistortion(1500, 1502, 321, 239, kud, kdu);
  const std::string xml = std::string(dir) + "/camera.xml";
  vpXmlParserCamera parser;
  ASSERT_EQ(parser.save(cam, xml, "Flea2", 640, 480), vpXmlParserCamera::SEQUENCE_OK);
  // Ideal (undistorted) normalized points, their distorted pixels.
  std::string yaml = "camera_xml: {file: camera.xml, name: Flea2}\nrobot: viper850\nposes:\n  - joints: [0, 0, 0, 0, 0, 0]\n    points: [";
  const double xs[3][2] = {{0.0, 0.0}, {0.15, -0.1}, {-0.2, 0.14}};
  for (int i = 0; i < 3; ++i) {
    double u = 0, v = 0;
    vpMeterPixelConversion::convertPoint(cam, xs[i][0], xs[i][1], u, v);
    yaml += (i ? ", [" : "[") + std::to_string(i) + ", " + std::to_string(u) + ", " + std::to_string(v) + "]";
  }
  yaml += "]\n";
  const vpSelfCalibDataset ds = vpSelfCalibDataset::fromYamlString(yaml, "<xml test>", dir);
  EXPECT_EQ(ds.width, 640u);
  EXPECT_EQ(ds.height, 480u);
  EXPECT_TRUE(ds.focal_known);
  EXPECT_EQ(ds.cam.get_projModel(), vpCameraParameters::perspectiveProjWithoutDistortion);
  for (int i = 0; i < 3; ++i) {
    const vpImagePoint &ip = ds.views[0].points[i].ip;
    // The distortion (k_ud, the model ViSP projects with) is inverted exactly; the pixels in the
    // file are written with 6 decimals.
    EXPECT_NEAR(ip.get_u(), 321 + 1500 * xs[i][0], 1e-5) << i;
    EXPECT_NEAR(ip.get_v(), 239 + 1502 * xs[i][1], 1e-5) << i;
  }
  EXPECT_NE(parseError("camera_xml: {file: /nonexistent.xml, name: Flea2}\nrobot: viper850\nposes: []\n")
                .find("camera_xml.file"),
            std::string::npos);
  EXPECT_THROW(vpSelfCalibDataset::fromYamlString("camera_xml: {file: camera.xml, name: Other}\nrobot: viper850\nposes: []\n",
                                                  "<t>", dir),
               vpSelfCalibException);
  std::remove(xml.c_str());
  rmdir(dir);
}

// OpenCV's lens model in the camera map: read (4 coefficients: k3 = 0), pixels kept as measured,
// written back exactly; malformed coefficient lists are refused naming the key.
TEST(DatasetYaml, OpenCvDistortionInTheCameraMap)
{
  const std::string pose = "poses:\n  - joints: [0, 0, 0, 0, 0, 0]\n    points: [[1, 10.5, 20.25]]\n";
  const std::string cam = "camera: {width: 640, height: 480, u0: 320, v0: 240, px: 600, py: 600, distortion: ";
  const vpSelfCalibDataset ds =
      vpSelfCalibDataset::fromYamlString(cam + "[-0.2, 0.05, 0.001, -0.002]}\nrobot: viper850\n" + pose);
  ASSERT_EQ(ds.opencv_distortion.size(), 5u);
  EXPECT_EQ(ds.opencv_distortion[0], -0.2);
  EXPECT_EQ(ds.opencv_distortion[3], -0.002);
  EXPECT_EQ(ds.opencv_distortion[4], 0.0);
  EXPECT_EQ(ds.views[0].points[0].ip.get_u(), 10.5);
  EXPECT_EQ(ds.views[0].points[0].ip.get_v(), 20.25);
  const vpSelfCalibDataset back = vpSelfCalibDataset::fromYamlString(ds.toYamlString());
  EXPECT_EQ(back.opencv_distortion, ds.opencv_distortion);
  EXPECT_TRUE(vpSelfCalibDataset::fromYamlString(kHead + pose).opencv_distortion.empty());
  for (const std::string bad : {"[0.1, 0.2]", "[1, 2, 3, 4, 5, 6, 7, 8]", "{k1: 0.1}", "[0.1, .nan, 0, 0]",
                                "[1e9, 0, 0, 0]"})
    EXPECT_NE(parseError(cam + bad + "}\nrobot: viper850\n" + pose).find("camera.distortion"), std::string::npos)
        << bad;
}

// Every kind of malformed input gets an error naming the key and what was expected.
TEST(DatasetYaml, BadInputNamesTheKey)
{
  const std::string pose = "poses:\n  - joints: [0, 0, 0, 0, 0, 0]\n    points: [[1, 10, 20]]\n";
  EXPECT_EQ(parseError(kHead + pose), "");
  const std::pair<std::string, std::string> cases[] = {
      {"robot: viper850\n" + pose, "camera"},
      {"camera: {width: 640, height: 480, u0: 320, v0: 240, px: 1500}\nrobot: viper850\n" + pose, "camera.py"},
      {"camera: {width: -4, height: 480, u0: 320, v0: 240}\nrobot: viper850\n" + pose, "camera"},
      {kHead, "poses"},
      {kHead + "poses:\n  - joints: [0, .nan, 0, 0, 0, 0]\n", "poses[0].joints[1]"},
      {kHead + "poses:\n  - joints: [0, 0, 0, 0, 0, 0]\n  - joints: [0, 0, 0]\n", "poses[1].joints"},
      {kHead + "poses:\n  - image: a.png\n", "poses[0]"},
      {kHead + "poses:\n  - joints: [0, 0, 0, 0, 0, 0]\n    points: [[1, 10, 20], [1, 11, 21]]\n", "poses[0].points[1]"},
      {kHead + "poses:\n  - joints: [0, 0, 0, 0, 0, 0]\n    points: [[-1, 10, 20]]\n", "poses[0].points[0][0]"},
      {kHead + "poses:\n  - joints: [0, 0, 0, 0, 0, 0]\n    points: [[1, 10]]\n", "poses[0].points[0]"},
      {kHead + "poses:\n  - joints: [0, 0, 0, 0, 0, 0]\n    pixels: []\n", "poses[0].pixels"},
      {kHead + pose + "yardstick: {length: 0.1, ends: [3, 3]}\n", "yardstick.ends"},
      {kHead + pose + "yardstick: {length: -0.1, ends: [3, 4]}\n", "yardstick.length"},
      {kHead + "poses: [\n", "syntax error"},
      {"- 1\n- 2\n", "top level"},
      // Found by fuzzing (cmake/fuzz.sh): a list as a map key escaped as a yaml-cpp exception.
      {"? [camera]: 1\n" + kHead, "keys are plain names"},
      {"camera: {width: 640, height: 480, u0: 320, v0: 240, px: 1500, py: 1500, {a: 1}: 2}\nrobot: viper850\n" + pose,
       "camera.(key)"},
      {"camera: {width: 1e300, height: 480, u0: 320, v0: 240}\nrobot: viper850\n" + pose, "camera"},
      {kHead + pose + "yardstick: {length: 0.1, ends: [3, 1e12]}\n", "yardstick.ends"},
      // Found by fuzzing: a huge theta-u (its matrix turned into a NaN pose on writing).
      {kHead + "poses:\n  - fMe: [0.1, 0, 0.4, 0, 0.41e308, 5.0]\n    points: [[1, 10, 20]]\n", "poses[0].fMe"},
      // Found by fuzzing: invalid UTF-8 in a name or path (yaml-cpp writes it back as U+FFFD).
      {"camera: {width: 640, height: 480, u0: 320, v0: 240}\nrobot: model.ya\xEA\x06v2ml\n" + pose, "robot"},
      {kHead + "poses:\n  - joints: [0, 0, 0, 0, 0, 0]\n    image: a\xC0\xAF.png\n", "poses[0].image"},
      // Found by fuzzing: a control character (a carriage return ending a path; yaml-cpp writes it
      // back unquoted and reads the line break) in a name or path.
      {kHead + "poses:\n  - joints: [0, 0, 0, 0, 0, 0]\n    image: images/a.png\r", "poses[0].image': expected text without control"},
      {kHead + "poses:\n  - joints: [0, 0, 0, 0, 0, 0]\n    image: \"images/a\\tb.png\"\n", "control character"},
      {"camera: {width: 640, height: 480, u0: 320, v0: 240}\nrobot: \"viper\\n850\"\n" + pose, "robot"},
  };
  for (const auto &c : cases) {
    const std::string msg = parseError(c.first);
    EXPECT_NE(msg.find(c.second), std::string::npos) << "input:\n" << c.first << "\nmessage: " << msg;
  }
  EXPECT_THROW(vpSelfCalibDataset::loadYaml("/nonexistent/dataset.yaml"), vpSelfCalibException);
}

// The camera's mount: effector by default, world read and written back, anything else refused naming
// the key and the accepted values.
TEST(DatasetYaml, CameraMount)
{
  const std::string pose = "poses:\n  - fMe: [0.3, 0, 0.4, 0, 0, 0]\n    points: [[1, 10, 20]]\n";
  EXPECT_EQ(vpSelfCalibDataset::fromYamlString(kHead + pose).camera_mount, vpSelfCalibDataset::CAMERA_ON_EFFECTOR);
  EXPECT_EQ(vpSelfCalibDataset::fromYamlString(kHead + "camera_mount: effector\n" + pose).camera_mount,
            vpSelfCalibDataset::CAMERA_ON_EFFECTOR);
  const vpSelfCalibDataset world = vpSelfCalibDataset::fromYamlString(kHead + "camera_mount: world\n" + pose);
  EXPECT_EQ(world.camera_mount, vpSelfCalibDataset::CAMERA_IN_WORLD);
  const std::string text = world.toYamlString();
  EXPECT_NE(text.find("camera_mount: world"), std::string::npos);
  expectSame(world, vpSelfCalibDataset::fromYamlString(text));
  // The default is not written (files of eye-in-hand set-ups stay as they were).
  EXPECT_EQ(vpSelfCalibDataset::fromYamlString(kHead + pose).toYamlString().find("camera_mount"), std::string::npos);
  const std::string msg = parseError(kHead + "camera_mount: ceiling\n" + pose);
  EXPECT_NE(msg.find("camera_mount"), std::string::npos) << msg;
  EXPECT_NE(msg.find("effector"), std::string::npos) << msg;
  EXPECT_NE(msg.find("world"), std::string::npos) << msg;
  EXPECT_NE(msg.find("ceiling"), std::string::npos) << msg;
  EXPECT_NE(parseError(kHead + "camera_mount: [world]\n" + pose).find("camera_mount"), std::string::npos);
}

// The user's fix: and free: lists (names or glob patterns) are read, written back and checked.
TEST(DatasetYaml, FixAndFreeListsRoundTrip)
{
  vpSelfCalibDataset ds = simulated(true);
  ds.fix = {"j3.*", "base.tx"};
  ds.free = {"j2.tz"};
  const vpSelfCalibDataset back = vpSelfCalibDataset::fromYamlString(ds.toYamlString());
  EXPECT_EQ(back.fix, ds.fix);
  EXPECT_EQ(back.free, ds.free);
  EXPECT_TRUE(simulated(true).toYamlString().find("fix:") == std::string::npos);
  const std::string poses = "poses:\n  - {joints: [0, 0, 0, 0, 0, 0]}\n";
  EXPECT_NE(parseError(kHead + "fix: j3.tx\n" + poses).find("key 'fix': expected a list of parameter names"), std::string::npos)
      << parseError(kHead + "fix: j3.tx\n" + poses);
  EXPECT_NE(parseError(kHead + "free: ['']\n" + poses).find("free[0]"), std::string::npos);
}

// The kinematic prior: not said (empty, not written, read back empty) distinct from off (0, written
// "off", read back 0), written and read back, its forms (off, tolerance, tolerance/K, K), bad values refused.
TEST(DatasetYaml, KinematicPriorRoundTripsAndRefusesBadValues)
{
  vpSelfCalibDataset ds = simulated(true);
  EXPECT_FALSE(ds.kinematic_prior.has_value());
  EXPECT_TRUE(ds.toYamlString().find("kinematic_prior") == std::string::npos);
  EXPECT_FALSE(vpSelfCalibDataset::fromYamlString(ds.toYamlString()).kinematic_prior.has_value());
  ds.kinematic_prior = 0;
  EXPECT_NE(ds.toYamlString().find("kinematic_prior: off"), std::string::npos) << ds.toYamlString();
  ASSERT_TRUE(vpSelfCalibDataset::fromYamlString(ds.toYamlString()).kinematic_prior.has_value());
  EXPECT_EQ(*vpSelfCalibDataset::fromYamlString(ds.toYamlString()).kinematic_prior, 0);
  ds.kinematic_prior = 3;
  EXPECT_EQ(vpSelfCalibDataset::fromYamlString(ds.toYamlString()).kinematic_prior, 3);
  const std::string poses = "poses:\n  - {joints: [0, 0, 0, 0, 0, 0]}\n";
  const std::map<std::string, double> good = {{"off", 0}, {"tolerance", 1}, {"tolerance/3", 3}, {"2.5", 2.5}};
  for (const auto &g : good)
    EXPECT_EQ(vpSelfCalibDataset::fromYamlString(kHead + "kinematic_prior: " + g.first + "\n" + poses).kinematic_prior,
              std::optional<double>(g.second))
        << g.first;
  for (const std::string bad : {"0", "-1", "tolerance/0", "tolerance/-3", "nan", "inf", "tolerance/", "loose"})
    EXPECT_NE(parseError(kHead + "kinematic_prior: " + bad + "\n" + poses).find("kinematic_prior"), std::string::npos)
        << bad;
}
