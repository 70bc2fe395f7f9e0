/*
 * Tests of the importers (vpSelfCalibImporter): every pose format, ViSP hand-eye folders and
 * industrial_calibration's cal_data.yaml written by the tests in temporary folders, the round trip
 * through the dataset file, and every bad input.
 */
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include <visp3/core/vpImage.h>
#include <visp3/core/vpQuaternionVector.h>
#include <visp3/io/vpImageIo.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibImporter.h>

namespace fs = std::filesystem;

namespace
{
//! A fresh temporary folder, removed with the object.
class TempDir
{
public:
  TempDir()
  {
    char dir[] = "/tmp/selfcalib-import-XXXXXX";
    if (mkdtemp(dir) == nullptr)
      throw std::runtime_error("mkdtemp failed");
    m_path = dir;
  }
  ~TempDir()
  {
    std::error_code ec;
    fs::remove_all(m_path, ec);
  }
  TempDir(const TempDir &) = delete;
  TempDir &operator=(const TempDir &) = delete;
  const fs::path &path() const { return m_path; }
  std::string operator/(const std::string &name) const { return (m_path / name).string(); }

private:
  fs::path m_path;
};

void write(const std::string &file, const std::string &text)
{
  fs::create_directories(fs::path(file).parent_path());
  std::ofstream(file, std::ios::binary) << text;
}

void writeImage(const std::string &file, unsigned int width = 64, unsigned int height = 48)
{
  fs::create_directories(fs::path(file).parent_path());
  vpImageIo::write(vpImage<unsigned char>(height, width, 128), file);
}

void writeCameraXml(const std::string &file, const std::string &cameras)
{
  write(file, "<?xml version=\"1.0\"?>\n<root>\n  <!-- <camera><name>Commented</name></camera> -->\n" + cameras +
                  "</root>\n");
}

std::string cameraElement(const std::string &name, double px,
                          const std::string &model = "perspectiveProjWithoutDistortion", const std::string &k = "")
{
  std::ostringstream os;
  os << "  <camera>\n    <name>" << name << "</name>\n    <image_width>64</image_width>\n"
     << "    <image_height>48</image_height>\n    <model>\n      <type>" << model << "</type>\n"
     << "      <px>" << px << "</px>\n      <py>" << px + 1 << "</py>\n      <u0>31.5</u0>\n      <v0>23.5</v0>\n"
     << k << "    </model>\n  </camera>\n";
  return os.str();
}

//! Poses of the tests: rotations of all sizes (up to near pi), translations of a few decimetres.
vpHomogeneousMatrix truePose(int k)
{
  return vpHomogeneousMatrix(0.1 * k, -0.2 + 0.05 * k, 0.5, 0.3 * k, -0.2, 0.4 + 0.35 * k);
}

std::string text17(const std::vector<double> &v, const char *sep = ", ")
{
  std::ostringstream os;
  os << std::setprecision(17);
  for (size_t i = 0; i < v.size(); ++i)
    os << (i ? sep : "") << v[i];
  return os.str();
}

std::vector<double> poseVector(const vpHomogeneousMatrix &M)
{
  const vpPoseVector p(M);
  return {p[0], p[1], p[2], p[3], p[4], p[5]};
}

std::vector<double> quaternion(const vpHomogeneousMatrix &M, double scale = 1)
{
  const vpQuaternionVector q(M.getRotationMatrix());
  return {M[0][3], M[1][3], M[2][3], scale * q.x(), scale * q.y(), scale * q.z(), scale * q.w()};
}

std::string matrixRows(const vpHomogeneousMatrix &M)
{
  std::string s;
  for (unsigned int i = 0; i < 4; ++i)
    s += std::string(i ? ", " : "") + "[" + text17({M[i][0], M[i][1], M[i][2], M[i][3]}) + "]";
  return s;
}

// Pose files in every format the importer reads, for pose k.
std::string visPoseYaml(const vpHomogeneousMatrix &M)
{
  std::string s = "rows: 6\ncols: 1\ndata:\n";
  for (double x : poseVector(M))
    s += "  - [" + text17({x}) + "]\n";
  return s;
}
std::string quaternionKeys(const vpHomogeneousMatrix &M, double scale = 1)
{
  const std::vector<double> q = quaternion(M, scale);
  const char *keys[] = {"x", "y", "z", "qx", "qy", "qz", "qw"};
  std::string s;
  for (int i = 0; i < 7; ++i)
    s += std::string(keys[i]) + ": " + text17({q[static_cast<size_t>(i)]}) + "\n";
  return s;
}

void expectNear(const vpHomogeneousMatrix &a, const vpHomogeneousMatrix &b, double tol, const std::string &what)
{
  for (unsigned int i = 0; i < 4; ++i)
    for (unsigned int j = 0; j < 4; ++j)
      EXPECT_NEAR(a[i][j], b[i][j], tol) << what << " (" << i << ", " << j << ")";
}

//! The message of the vpSelfCalibException `f` throws, or "" when it throws none.
template <typename F> std::string errorOf(F &&f)
{
  try {
    f();
  } catch (const vpSelfCalibException &e) {
    return e.getStringMessage();
  }
  return "";
}

std::string poseError(const std::string &yaml)
{
  return errorOf([&] { vpSelfCalibImporter::poseFromYamlString(yaml, "'bad.yaml'"); });
}

//! A ViSP hand-eye folder: poses fPe 1, 2, 10 (in three formats), images, a camera XML, a board.
void writeVispFolder(const TempDir &d, const std::string &prefix = "test")
{
  write(d / (prefix + "_pose_fPe_1.yaml"), visPoseYaml(truePose(1)));
  write(d / (prefix + "_pose_fPe_2.yaml"), "[" + text17(poseVector(truePose(2))) + "]\n");
  write(d / (prefix + "_pose_fPe_10.yaml"), "rows: 4\ncols: 4\ndata: [" + matrixRows(truePose(10)) + "]\n");
  for (int k : {1, 2, 10})
    writeImage(d / (prefix + "_image-" + std::to_string(k) + ".png"));
  writeCameraXml(d / (prefix + "_camera.xml"), cameraElement("Camera", 80));
  write(d / "chessboard-data.txt", "Chessboard\n9 x 6\nsquare size: 0.0236 m\n");
}

//! A cal_data.yaml with poses 0..3 (quaternion keys), images, nominal intrinsics and an eMc guess.
void writeCalData(const TempDir &d, const std::string &extra = "")
{
  std::string data = "data:\n";
  for (int k = 0; k < 4; ++k) {
    write(d / ("poses/" + std::to_string(k) + ".yaml"), quaternionKeys(truePose(k + 1)));
    writeImage(d / ("images/" + std::to_string(k) + ".png"));
    data += "  - pose: poses/" + std::to_string(k) + ".yaml\n    image: images/" + std::to_string(k) + ".png\n";
  }
  write(d / "cal_data.yaml", data +
                                 "target_finder:\n  type: ModifiedCircleGridTargetFinder\n  rows: 10\n  cols: 10\n"
                                 "  spacing: 0.0254\n  circle_detector_params: {minThreshold: 20}\n"
                                 "intrinsics:\n  fx: 70.0\n  fy: 70.0\n  cx: 32.0\n  cy: 24.0\n"
                                 "camera_mount_to_camera_guess: {x: 0.01, y: 0.0, z: 0.05, qx: 0.0, qy: 0.0, "
                                 "qz: -0.707107, qw: 0.707107}\nstatic_camera: false\nhomography_threshold: 1.0\n" +
                                 extra);
}

void expectCounts(const vpSelfCalibImporter::Report &r, unsigned int poses, unsigned int images, unsigned int views)
{
  EXPECT_EQ(r.num_pose_files, poses);
  EXPECT_EQ(r.num_images, images);
  EXPECT_EQ(r.num_views, views);
}

bool mentions(const vpSelfCalibImporter::Report &r, const std::string &what, const std::string &reason)
{
  for (const auto &u : r.unused)
    if (u.what.find(what) != std::string::npos && u.reason.find(reason) != std::string::npos)
      return true;
  return false;
}
} // namespace

TEST(Importer, EveryPoseFormat)
{
  const vpHomogeneousMatrix M = truePose(3);
  const std::string pv = text17(poseVector(M)), q = text17(quaternion(M));
  const std::vector<std::pair<std::string, std::string>> files = {
      {"ViSP pose vector YAML", visPoseYaml(M)},
      {"pose vector, 1 x 6", "rows: 1\ncols: 6\ndata: [[" + pv + "]]\n"},
      {"pose vector, flat data", "rows: 6\ncols: 1\ndata: [" + pv + "]\n"},
      {"list of 6", "[" + pv + "]\n"},
      {"column of 6 (text)", text17(poseVector(M), "\n") + "\n"},
      {"quaternion keys", quaternionKeys(M)},
      {"quaternion keys, not normalised", quaternionKeys(M, 3.5)},
      {"list of 7", "[" + q + "]\n"},
      {"line of 7 (text)", text17(quaternion(M), " ") + "\n"},
      {"4 x 4 rows", "[" + matrixRows(M) + "]\n"},
      {"rows: 4 cols: 4", "rows: 4\ncols: 4\ndata: [" + matrixRows(M) + "]\n"},
  };
  for (const auto &f : files)
    expectNear(vpSelfCalibImporter::poseFromYamlString(f.second), M, 1e-12, f.first);

  // A matrix orthonormal within 1e-6 is accepted and made exactly orthonormal.
  vpHomogeneousMatrix N = M;
  N[0][0] += 4e-7;
  const vpHomogeneousMatrix R = vpSelfCalibImporter::poseFromYamlString("[" + matrixRows(N) + "]");
  expectNear(R, M, 1e-6, "nearly orthonormal");
  const vpRotationMatrix Rr = R.getRotationMatrix();
  const vpMatrix I = Rr.t() * static_cast<vpMatrix>(Rr);
  for (unsigned int i = 0; i < 3; ++i)
    for (unsigned int j = 0; j < 3; ++j)
      EXPECT_NEAR(I[i][j], i == j ? 1.0 : 0.0, 1e-14);

  // From a file, the same.
  TempDir d;
  write(d / "p.yaml", quaternionKeys(M));
  expectNear(vpSelfCalibImporter::readPose(d / "p.yaml"), M, 1e-12, "file");
}

TEST(Importer, BadPoseFilesAreErrorsNamingTheFile)
{
  const vpHomogeneousMatrix M = truePose(2);
  vpHomogeneousMatrix scaled = M, reflected = M, last = M;
  for (unsigned int i = 0; i < 3; ++i) {
    scaled[i][0] *= 1.01;
    reflected[i][2] = -reflected[i][2];
  }
  last[3][2] = 0.5;
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"[" + matrixRows(scaled) + "]", "not orthonormal"},
      {"[" + matrixRows(reflected) + "]", "determinant"},
      {"[" + matrixRows(last) + "]", "last row"},
      {"rows: 4\ncols: 4\ndata: [" + matrixRows(scaled) + "]", "not a rigid transform"},
      {"{x: 0, y: 0, z: 0, qx: 0, qy: 0, qz: 0, qw: 0}", "quaternion (qx qy qz qw) is zero"},
      {"[1, 2, 3, 0, 0, 0, 0]", "is zero"},
      {"{x: 0, y: 0, z: .nan, qx: 0, qy: 0, qz: 0, qw: 1}", "expected a finite number"},
      {"[0.1, 0.2, .inf, 0, 0, 0]", "expected a finite number"},
      {"0.1 0.2 nan 0 0 0", "is not a finite number"},
      {"{x: 0, y: 0, z: 0, qx: 0, qy: 0, qz: 0}", "'qw': missing"},
      {"{x: 0, y: 0, z: 0, qx: 0, qy: 0, qz: 0, qw: 1, w: 1}", "unknown key"},
      {"[1, 2, 3, 4, 5]", "5 numbers"},
      {"[0, 0, 0, 7, 0, 0]", "at most 2 pi"},
      {"rows: 3\ncols: 3\ndata: [1, 0, 0, 0, 1, 0, 0, 0, 1]", "3 x 3 array"},
      {"rows: 6\ncols: 1\ndata: [[1], [2]]", "expected 6 rows of 1"},
      {"rows: 6\ncols: 1", "key 'data': expected a list, got nothing"},
      {"[[1, 0, 0, 0], [0, 1, 0], [0, 0, 1, 0], [0, 0, 0, 1]]", "matrix row of 4"},
      {"", "expected a pose"},
      {"[1, 2", "YAML syntax error"},
  };
  for (const auto &c : cases) {
    const std::string e = poseError(c.first);
    EXPECT_NE(e.find("pose file 'bad.yaml'"), std::string::npos) << c.first << " -> " << e;
    EXPECT_NE(e.find(c.second), std::string::npos) << c.first << " -> " << e;
  }
  EXPECT_NE(errorOf([] { vpSelfCalibImporter::readPose("/nonexistent/p.yaml"); }).find("'/nonexistent/p.yaml'"),
            std::string::npos);
}

TEST(Importer, VispFolder)
{
  TempDir d;
  writeVispFolder(d);
  write(d / "test_pose_cPo_1.yaml", "[0, 0, 0.5, 0, 0, 0]\n");
  write(d / "notes.txt", "acquired on Monday\n");
  const vpSelfCalibImporter::Result res = vpSelfCalibImporter::import(d.path().string());
  const vpSelfCalibImporter::Report &r = res.report;
  EXPECT_EQ(r.layout, vpSelfCalibImporter::VISP_HAND_EYE);
  expectCounts(r, 3, 3, 3);
  // Numerical order: 1, 2, 10 (not 1, 10, 2).
  const vpSelfCalibDataset &ds = res.dataset;
  ASSERT_EQ(ds.views.size(), 3u);
  const int order[] = {1, 2, 10};
  for (size_t k = 0; k < 3; ++k) {
    EXPECT_TRUE(ds.views[k].has_fMe);
    EXPECT_EQ(ds.views[k].q.size(), 0u);
    EXPECT_TRUE(ds.views[k].points.empty());
    expectNear(ds.views[k].fMe, truePose(order[k]), 1e-12, "view " + std::to_string(k));
    EXPECT_EQ(ds.views[k].image, d / ("test_image-" + std::to_string(order[k]) + ".png"));
  }
  EXPECT_NE(r.pose_format.find("fPe"), std::string::npos) << r.pose_format;
  // The camera XML: px, py, u0, v0 and the size, known.
  EXPECT_TRUE(ds.focal_known);
  EXPECT_EQ(ds.cam.get_px(), 80);
  EXPECT_EQ(ds.cam.get_py(), 81);
  EXPECT_EQ(ds.cam.get_u0(), 31.5);
  EXPECT_EQ(ds.cam.get_v0(), 23.5);
  EXPECT_EQ(ds.width, 64u);
  EXPECT_EQ(ds.height, 48u);
  EXPECT_NE(r.camera.find("test_camera.xml, camera 'Camera'"), std::string::npos) << r.camera;
  EXPECT_NE(r.board.find("chessboard, 9 x 6 inner corners, squares 0.0236 m"), std::string::npos) << r.board;
  EXPECT_EQ(r.board_option, "chessboard:9x6:0.0236"); // calibrate's --board for it
  // Not a franka folder, no --robot: the generic hand-eye model, to be written beside the dataset.
  EXPECT_TRUE(res.has_robot_model);
  EXPECT_EQ(res.robot_model.getName(), "hand-eye");
  EXPECT_TRUE(ds.robot.empty());
  EXPECT_NE(r.robot.find("generic hand-eye model"), std::string::npos) << r.robot;
  EXPECT_TRUE(mentions(r, "test_pose_cPo_1.yaml", "board pose"));
  EXPECT_TRUE(mentions(r, "notes.txt", "not part of"));
  // Every file read is an input.
  for (const std::string f : {"test_pose_fPe_10.yaml", "test_image-2.png", "test_camera.xml", "chessboard-data.txt"})
    EXPECT_NE(std::find(res.inputs.begin(), res.inputs.end(), d / f), res.inputs.end()) << f;
}

TEST(Importer, VispFolderRobotAndIntrinsicsOptions)
{
  TempDir d;
  writeVispFolder(d, "franka");
  vpSelfCalibImporter::Result res = vpSelfCalibImporter::import(d.path().string());
  EXPECT_FALSE(res.has_robot_model);
  EXPECT_EQ(res.dataset.robot, "panda");
  EXPECT_NE(res.report.robot.find("default for ViSP franka_ folders"), std::string::npos) << res.report.robot;

  vpSelfCalibImporter::Options o;
  o.robot = "ur5";
  o.intrinsics = vpSelfCalibImporter::INTRINSICS_GUESS;
  res = vpSelfCalibImporter::import(d.path().string(), o);
  EXPECT_EQ(res.dataset.robot, "ur5");
  EXPECT_FALSE(res.dataset.focal_known);
  EXPECT_EQ(res.dataset.cam.get_px(), 80); // the start of f
  EXPECT_EQ(res.dataset.cam.get_py(), 80);
  EXPECT_TRUE(mentions(res.report, "py 81", "one focal length"));

  // A robot-model file is used as it is; an unknown name is an error naming the file.
  write(d / "robot.yaml", "preset: panda\neMc: [0, 0, 0.1, 0, 0, 0]\n");
  o.robot = d / "robot.yaml";
  res = vpSelfCalibImporter::import(d.path().string(), o);
  EXPECT_FALSE(res.has_robot_model);
  EXPECT_EQ(res.dataset.robot, d / "robot.yaml");
  o.robot = d / "no-such-robot.yaml";
  EXPECT_NE(errorOf([&] { vpSelfCalibImporter::import(d.path().string(), o); }).find("no-such-robot.yaml"),
            std::string::npos);
}

// Import, save, load: the same poses within 1e-12, the images and the robot model found again.
TEST(Importer, RoundTripThroughTheDatasetFile)
{
  TempDir d;
  writeVispFolder(d);
  const vpSelfCalibImporter::Result res = vpSelfCalibImporter::import(d.path().string());
  const std::string out = d / "out/dataset.yaml";
  fs::create_directories(d / "out");
  res.save(out);
  EXPECT_EQ(vpSelfCalibImporter::robotModelFileFor(out), d / "out/dataset-robot.yaml");
  const vpSelfCalibDataset ds = vpSelfCalibDataset::loadYaml(out);
  ASSERT_EQ(ds.views.size(), res.dataset.views.size());
  // The controller poses' error the importer states, kept through the file and said in the report.
  EXPECT_EQ(ds.pose_sd_translation, vpSelfCalibImporter::kDefaultPoseSdTranslation);
  EXPECT_EQ(ds.pose_sd_rotation, vpSelfCalibImporter::kDefaultPoseSdRotation);
  EXPECT_NE(res.report.robot_error.find("2 mm / 2 mrad"), std::string::npos) << res.report.robot_error;
  for (size_t k = 0; k < ds.views.size(); ++k) {
    EXPECT_TRUE(ds.views[k].has_fMe);
    expectNear(ds.views[k].fMe, res.dataset.views[k].fMe, 1e-12, "view " + std::to_string(k));
    EXPECT_EQ(fs::canonical(ds.views[k].image), fs::canonical(res.dataset.views[k].image));
    EXPECT_TRUE(ds.views[k].points.empty());
  }
  EXPECT_EQ(ds.cam.get_px(), 80);
  EXPECT_TRUE(ds.focal_known);
  EXPECT_EQ(ds.width, 64u);
  // The robot model beside the dataset, written relative to it, loadable.
  EXPECT_EQ(ds.robot, d / "out/dataset-robot.yaml");
  std::ifstream in(out);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("robot: dataset-robot.yaml"), std::string::npos) << text;
  EXPECT_EQ(vpKinematicChain::loadYaml(ds.robot).getName(), "hand-eye");

  // Saved in the data folder itself: image paths relative to it.
  res.save(d / "ds.yaml");
  std::ifstream in2(d / "ds.yaml");
  const std::string text2((std::istreambuf_iterator<char>(in2)), std::istreambuf_iterator<char>());
  EXPECT_NE(text2.find("image: test_image-10.png"), std::string::npos) << text2;
}

TEST(Importer, CalData)
{
  TempDir d;
  writeCalData(d);
  for (const std::string path : {d.path().string(), d / "cal_data.yaml"}) {
    const vpSelfCalibImporter::Result res = vpSelfCalibImporter::import(path);
    const vpSelfCalibImporter::Report &r = res.report;
    EXPECT_EQ(r.layout, vpSelfCalibImporter::INDUSTRIAL_CALIBRATION);
    expectCounts(r, 4, 4, 4);
    ASSERT_EQ(res.dataset.views.size(), 4u);
    for (size_t k = 0; k < 4; ++k)
      expectNear(res.dataset.views[k].fMe, truePose(static_cast<int>(k) + 1), 1e-12, "view " + std::to_string(k));
    EXPECT_NE(r.pose_format.find("quaternion"), std::string::npos);
    // Nominal intrinsics: a guess by default; the size from the images.
    EXPECT_FALSE(res.dataset.focal_known);
    EXPECT_EQ(res.dataset.cam.get_px(), 70);
    EXPECT_EQ(res.dataset.cam.get_u0(), 32);
    EXPECT_EQ(res.dataset.cam.get_v0(), 24);
    EXPECT_EQ(res.dataset.width, 64u);
    EXPECT_EQ(res.dataset.height, 48u);
    EXPECT_NE(r.board.find("ModifiedCircleGridTargetFinder, 10 x 10, spacing 0.0254 m"), std::string::npos) << r.board;
    // The eMc guess goes into the generic model.
    ASSERT_TRUE(res.has_robot_model);
    expectNear(res.robot_model.get_eMc(),
               vpSelfCalibImporter::poseFromYamlString("{x: 0.01, y: 0.0, z: 0.05, qx: 0.0, qy: 0.0, qz: -0.707107, "
                                                       "qw: 0.707107}"),
               1e-12, "eMc guess");
    EXPECT_TRUE(mentions(r, "homography_threshold", "not needed"));
  }
  vpSelfCalibImporter::Options o;
  o.intrinsics = vpSelfCalibImporter::INTRINSICS_KNOWN;
  o.robot = "ur5";
  const vpSelfCalibImporter::Result res = vpSelfCalibImporter::import(d.path().string(), o);
  EXPECT_TRUE(res.dataset.focal_known);
  ASSERT_TRUE(res.has_robot_model); // ur5 with the data's eMc guess
  EXPECT_EQ(res.robot_model.getName(), "ur5");
  EXPECT_NEAR(res.robot_model.get_eMc_pose()[2], 0.05, 1e-12);
}

// What happens when poses and images do not pair up: each one alone is left out and said; the
// others are imported. With no pair left, an error.
TEST(Importer, PoseImageMismatch)
{
  TempDir d;
  writeVispFolder(d);
  write(d / "test_pose_fPe_3.yaml", "[0, 0, 0.5, 0, 0, 0]\n");
  writeImage(d / "test_image-4.png");
  writeImage(d / "test_image-5.png", 32, 24); // another size than the camera's
  write(d / "test_pose_fPe_5.yaml", "[0, 0, 0.5, 0, 0, 0]\n");
  write(d / "test_image-6.png", "not an image");
  write(d / "test_pose_fPe_6.yaml", "[0, 0, 0.5, 0, 0, 0]\n");
  const vpSelfCalibImporter::Result res = vpSelfCalibImporter::import(d.path().string());
  expectCounts(res.report, 6, 6, 3);
  EXPECT_TRUE(mentions(res.report, "test_pose_fPe_3.yaml", "no image test_image-3"));
  EXPECT_TRUE(mentions(res.report, "test_image-4.png", "no pose file test_pose_fPe_4.yaml"));
  EXPECT_TRUE(mentions(res.report, "test_image-5.png", "32 x 24, the camera's size is 64 x 48"));
  EXPECT_TRUE(mentions(res.report, "test_image-6.png", "cannot read the image"));

  // cal_data.yaml: a listed file that is missing leaves its entry out.
  TempDir c;
  writeCalData(c);
  fs::remove(c / "images/2.png");
  fs::remove(c / "poses/3.yaml");
  const vpSelfCalibImporter::Result cr = vpSelfCalibImporter::import(c.path().string());
  expectCounts(cr.report, 3, 3, 2);
  EXPECT_TRUE(mentions(cr.report, "data[2]", "no image images/2.png"));
  EXPECT_TRUE(mentions(cr.report, "data[3]", "no pose file poses/3.yaml"));

  // Poses without any image: nothing to import.
  TempDir e;
  write(e / "x_pose_rPe_1.yaml", "[0, 0, 0.5, 0, 0, 0]\n");
  write(e / "x_pose_rPe_2.yaml", "[0, 0, 0.6, 0, 0, 0]\n");
  writeCameraXml(e / "camera.xml", cameraElement("Camera", 80));
  const std::string err = errorOf([&] { vpSelfCalibImporter::import(e.path().string()); });
  EXPECT_NE(err.find("no pose with its image"), std::string::npos) << err;
  EXPECT_NE(err.find("x_pose_rPe_2.yaml: no image"), std::string::npos) << err;
}

TEST(Importer, BadInput)
{
  // A missing path, a folder without pose files.
  EXPECT_NE(errorOf([] { vpSelfCalibImporter::import("/nonexistent/folder"); }).find("'/nonexistent/folder': no such"),
            std::string::npos);
  TempDir empty;
  writeImage(empty / "test_image-1.png");
  EXPECT_NE(errorOf([&] { vpSelfCalibImporter::import(empty.path().string()); }).find("no pose files"),
            std::string::npos);

  // A pose file that is not a rigid transform, in a folder: the error names it.
  {
    TempDir d;
    writeVispFolder(d);
    vpHomogeneousMatrix M = truePose(2);
    M[0][0] *= 2;
    write(d / "test_pose_fPe_2.yaml", "[" + matrixRows(M) + "]\n");
    const std::string e = errorOf([&] { vpSelfCalibImporter::import(d.path().string()); });
    EXPECT_NE(e.find("test_pose_fPe_2.yaml"), std::string::npos) << e;
    EXPECT_NE(e.find("not a rigid transform"), std::string::npos) << e;
  }
  // A zero quaternion in a cal_data.yaml's pose file.
  {
    TempDir d;
    writeCalData(d);
    write(d / "poses/1.yaml", "{x: 0.1, y: 0.2, z: 0.3, qx: 0, qy: 0, qz: 0, qw: 0}\n");
    const std::string e = errorOf([&] { vpSelfCalibImporter::import(d.path().string()); });
    EXPECT_NE(e.find("poses/1.yaml"), std::string::npos) << e;
    EXPECT_NE(e.find("quaternion (qx qy qz qw) is zero"), std::string::npos) << e;
  }
  // Camera XML: none, several, a name to choose.
  {
    TempDir d;
    writeVispFolder(d);
    fs::remove(d / "test_camera.xml");
    EXPECT_NE(errorOf([&] { vpSelfCalibImporter::import(d.path().string()); }).find("no camera XML"),
              std::string::npos);
    writeCameraXml(d / "a.xml", cameraElement("Camera", 80));
    writeCameraXml(d / "b.xml", cameraElement("Camera", 80));
    EXPECT_NE(errorOf([&] { vpSelfCalibImporter::import(d.path().string()); }).find("several XML files (a.xml, b.xml)"),
              std::string::npos);
    fs::remove(d / "b.xml");
    writeCameraXml(d / "a.xml", cameraElement("Left", 70) + cameraElement("Right", 90));
    EXPECT_NE(errorOf([&] { vpSelfCalibImporter::import(d.path().string()); }).find("'Left', 'Right'"),
              std::string::npos);
    writeCameraXml(d / "a.xml", cameraElement("Left", 70) + cameraElement("Camera", 90));
    EXPECT_EQ(vpSelfCalibImporter::import(d.path().string()).dataset.cam.get_px(), 90);
    // The only camera, whatever its name; its distortion, which the dataset cannot carry, is said.
    writeCameraXml(d / "a.xml", cameraElement("Flea2", 75, "perspectiveProjWithDistortion",
                                              "      <kud>-0.1</kud>\n      <kdu>0.1</kdu>\n"));
    const vpSelfCalibImporter::Result res = vpSelfCalibImporter::import(d.path().string());
    EXPECT_EQ(res.dataset.cam.get_px(), 75);
    EXPECT_TRUE(mentions(res.report, "distortion (kud -0.1, kdu 0.1)", "pinhole"));
  }
  // Two pose series in one folder.
  {
    TempDir d;
    writeVispFolder(d);
    write(d / "other_pose_rPe_1.yaml", "[0, 0, 0.5, 0, 0, 0]\n");
    EXPECT_NE(errorOf([&] { vpSelfCalibImporter::import(d.path().string()); }).find("several pose series"),
              std::string::npos);
  }
  // cal_data.yaml: a static camera, no intrinsics, not a cal_data file.
  {
    TempDir d;
    writeCalData(d);
    write(d / "static.yaml", "data: [{pose: poses/0.yaml, image: images/0.png}]\nstatic_camera: true\n"
                             "intrinsics: {fx: 70, fy: 70, cx: 32, cy: 24}\n");
    EXPECT_NE(errorOf([&] { vpSelfCalibImporter::import(d / "static.yaml"); }).find("wrist camera"), std::string::npos);
    write(d / "nointr.yaml", "data: [{pose: poses/0.yaml, image: images/0.png}]\n");
    const std::string e = errorOf([&] { vpSelfCalibImporter::import(d / "nointr.yaml"); });
    EXPECT_NE(e.find("key 'intrinsics'"), std::string::npos) << e;
    EXPECT_NE(errorOf([&] { vpSelfCalibImporter::import(d / "poses/0.yaml"); }).find("expected a map with data"),
              std::string::npos);
  }
}

// ViSP's eye-to-hand folder: apriltag-data.txt makes the dataset camera_mount world and gives the
// --board to use; a description that is not understood is listed as unused, the mount still world.
TEST(Importer, VispEyeToHandFolder)
{
  TempDir d;
  writeVispFolder(d);
  std::filesystem::remove(d / "chessboard-data.txt"); // ViSP's eye-to-hand folder has the tag's only
  write(d / "apriltag-data.txt", "36h11 Ariltag\nsize: 0.048 m\n");
  const vpSelfCalibImporter::Result res = vpSelfCalibImporter::import(d.path().string());
  EXPECT_EQ(res.dataset.camera_mount, vpSelfCalibDataset::CAMERA_IN_WORLD);
  EXPECT_EQ(res.report.board_option, "apriltag:36h11:0.048");
  EXPECT_NE(res.report.board.find("AprilTag 36h11, 0.048 m"), std::string::npos) << res.report.board;
  EXPECT_NE(res.dataset.toYamlString().find("camera_mount: world"), std::string::npos);
  TempDir e;
  writeVispFolder(e);
  write(e / "apriltag-data.txt", "a tag\n");
  const vpSelfCalibImporter::Result bad = vpSelfCalibImporter::import(e.path().string());
  EXPECT_EQ(bad.dataset.camera_mount, vpSelfCalibDataset::CAMERA_IN_WORLD);
  // No tag option from a description not understood (the folder's chessboard-data.txt gives its own).
  EXPECT_EQ(bad.report.board_option.rfind("apriltag:", 0), std::string::npos) << bad.report.board_option;
  bool listed = false;
  for (const auto &u : bad.report.unused)
    listed = listed || u.what == "apriltag-data.txt";
  EXPECT_TRUE(listed);
}
