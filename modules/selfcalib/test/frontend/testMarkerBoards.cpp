/*
 * Tests of vpBoardDetector's marker boards: ChArUco boards and AprilTags (single and bundle)
 * rendered at known poses (whole, 40 % out of view, partly hidden; blur and noise as the grids'
 * tests), their descriptions and bad descriptions, and the real eye-to-hand set's AprilTag
 * (skipped when ../shared/data is absent).
 */
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

#include <opencv2/calib3d.hpp>

#include <visp3/core/vpXmlParserCamera.h>
#include <visp3/io/vpImageIo.h>
#include <visp3/selfcalib/vpBoardDetector.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include "markerTestImages.h"

namespace fs = std::filesystem;

namespace
{
// A view of the test series: the board turned in its plane, tilted, at a distance, shifted across
// the image by `shift` of its width (0.4: 40 % of it out of view), with an occluder.
struct View {
  double roll, tilt_x, tilt_y, distance, shift;
  vpRect occluder;
};

// Ten views: six whole, two with 40 % of the board out of the image (left, right), two with a
// quarter of the image hidden by an occluder.
std::vector<View> tenViews(double distance)
{
  return {{0, 15, -10, distance, 0, vpRect()},
          {90, -20, 12, distance, 0, vpRect()},
          {180, 10, 20, distance * 1.2, 0, vpRect()},
          {270, -12, -18, distance, 0, vpRect()},
          {35, 25, 0, distance, 0, vpRect()},
          {-60, 0, 30, distance * 0.9, 0, vpRect()},
          {10, 10, 10, distance, 0.4, vpRect()},
          {200, -10, 15, distance, -0.4, vpRect()},
          {20, 15, 5, distance, 0, vpRect(0, 0, 320, 240)},
          {120, -15, -10, distance, 0, vpRect(300, 200, 340, 280)}};
}

struct Measure {
  double worst = 0;
  size_t points = 0, expected = 0;
};

// Detects the board in each view; every point found must be a point of the layout, in view and not
// hidden, within `tolerance` px of its true projection (a wrong id is a square or a corner away).
void measure(const vpBoardDetector::Options &o, double texel, double distance, double tolerance, const std::string &what,
             Measure &m)
{
  const vpBoardDetector det(o);
  const std::map<int, vpColVector> layout = det.getLayout();
  int k = 0;
  for (const View &v : tenViews(distance)) {
    vpHomogeneousMatrix cMo = boardtest::pose(det, v.roll, v.tilt_x, v.tilt_y, v.distance);
    if (v.shift != 0) {
      // The printed board's edge `shift` of its width beyond the image's side (the board upright).
      const markertest::Print p = markertest::print(o);
      const double width = p.x1 - p.x0, edge = 0.5 * boardtest::kWidth / boardtest::kCamera.get_px() * v.distance;
      cMo[0][3] += (v.shift > 0 ? 1 : -1) * (edge - (0.5 - std::fabs(v.shift)) * width);
    }
    const vpImage<unsigned char> I = markertest::render(o, cMo, static_cast<uint64_t>(k), texel, v.occluder);
    const vpBoardDetector::Result r = det.detect(I);
    size_t visible = 0;
    for (const auto &p : layout) {
      const vpImagePoint t = boardtest::project(cMo, p.second);
      visible += t.get_u() > 5 && t.get_v() > 5 && t.get_u() < boardtest::kWidth - 5 &&
                 t.get_v() < boardtest::kHeight - 5 && !v.occluder.isInside(t);
    }
    // A single tag partly out of view or hidden cannot be decoded: not found, and said why.
    if (!r.found && o.type == vpBoardDetector::APRILTAG && o.bundle.empty() && visible < layout.size()) {
      EXPECT_FALSE(r.message.empty());
      std::cout << "[ markers  ] " << what << ", view " << k << ": " << visible
                << " of 4 corners visible, not found: " << r.message << "\n";
      ++k;
      continue;
    }
    ASSERT_TRUE(r.found) << what << ", view " << k << ": " << r.message;
    for (size_t i = 0; i < r.corners.size(); ++i) {
      const vpSelfCalibDataset::Observation &ob = r.corners[i];
      ASSERT_TRUE(layout.count(ob.id)) << what << ", view " << k << ": id " << ob.id << " is not the board's";
      if (i > 0)
        ASSERT_LT(r.corners[i - 1].id, ob.id) << what << ", view " << k << ": ids not increasing";
      const vpImagePoint t = boardtest::project(cMo, layout.at(ob.id));
      EXPECT_FALSE(v.occluder.isInside(t)) << what << ", view " << k << ": id " << ob.id << " found where it is hidden";
      const double e = vpImagePoint::distance(t, ob.ip);
      EXPECT_LT(e, tolerance) << what << ", view " << k << ", id " << ob.id;
      m.worst = std::max(m.worst, e);
    }
    std::cout << "[ markers  ] " << what << ", view " << k << ": " << r.corners.size() << " of " << visible
              << " visible points found\n";
    m.points += r.corners.size();
    m.expected += visible;
    ++k;
  }
  std::cout << "[ markers  ] " << what << ": " << m.points << " of " << m.expected
            << " visible points found over 10 views, largest error " << m.worst << " px\n";
}

void expectParseError(const std::string &spec, const std::string &message)
{
  try {
    vpBoardDetector::parse(spec);
    ADD_FAILURE() << "'" << spec << "' was accepted";
  } catch (const vpSelfCalibException &e) {
    EXPECT_NE(e.getStringMessage().find(message), std::string::npos)
        << "'" << spec << "': " << e.getStringMessage() << " (expected '" << message << "')";
  }
}

std::string writeBundle(const std::string &name, const std::string &content)
{
  const fs::path file = fs::temp_directory_path() / ("selfcalib-" + std::to_string(::getpid()) + "-" + name);
  std::ofstream(file) << content;
  return file.string();
}

const char *kBundle = "family: 36h11\n"
                      "tags:\n"
                      "  - {id: 3, size: 0.04, pose: [0, 0, 0, 0, 0, 0]}\n"
                      "  - {id: 7, size: 0.04, pose: [0.06, 0, 0, 0, 0, 0]}\n"
                      "  - {id: 12, size: 0.03, pose: [0, 0.06, 0, 0, 0, 1.5707963267948966]}\n"
                      "  - {id: 20, size: 0.04, pose: [0.06, 0.06, 0, 0, 0, 0]}\n";
} // namespace

TEST(MarkerBoards, CharucoCornersAtTenPosesPartlyOutOfViewAndHidden)
{
  const vpBoardDetector::Options o = vpBoardDetector::parse("charuco:5x7:0.034:0.028:DICT_6X6_250");
  Measure m;
  measure(o, o.spacing / 48, 0.6, 0.1, "charuco 5x7", m);
  EXPECT_GT(m.points, 0.9 * m.expected);
}

TEST(MarkerBoards, SingleAprilTagCornersAtTenPoses)
{
  const vpBoardDetector::Options o = vpBoardDetector::parse("apriltag:36h11:0.048:10");
  Measure m;
  measure(o, o.marker_size / 96, 0.35, 0.1, "apriltag 36h11 id 10", m);
  EXPECT_GE(m.points, 4u * 6); // the six views where it is whole
}

TEST(MarkerBoards, AprilTagBundleCornersAtTenPoses)
{
  const std::string file = writeBundle("bundle.yaml", kBundle);
  const vpBoardDetector::Options o = vpBoardDetector::parse("apriltag-bundle:" + file);
  fs::remove(file);
  ASSERT_EQ(o.bundle.size(), 4u);
  Measure m;
  measure(o, 0.04 / 96, 0.45, 0.1, "apriltag bundle of 4", m);
  EXPECT_GT(m.points, 0.8 * m.expected);
}

// The real eye-to-hand set: AprilTag 36h11 id 10 of 0.048 m in all 8 views, its four corners in
// OpenCV's order: a square of that side seen through the set's intrinsics (IPPE planar PnP)
// reprojects onto them within 1 px RMS in every view, 0.13 to 0.26 m away. (Measured: 0.02 to 0.6
// px; OpenCV's own corner refinements give 0.1 to 0.67 px on the same views: what is left is the
// intrinsics' and the print's error, not the corners'. A corner out of order is tens of px off.)
TEST(MarkerBoards, RealFrankaAprilTag)
{
  const std::string dir = std::string(SELFCALIB_SHARED_DATA) + "/visp-franka-eye-to-hand";
  if (!fs::is_directory(dir))
    GTEST_SKIP() << "no real data: " << dir << " is absent (DESIGN.md, ../shared/data)";
  vpCameraParameters cam;
  vpXmlParserCamera xml;
  ASSERT_EQ(xml.parse(cam, dir + "/franka_camera.xml", "Camera", vpCameraParameters::perspectiveProjWithDistortion),
            vpXmlParserCamera::SEQUENCE_OK);
  const vpBoardDetector det(vpBoardDetector::parse("apriltag:36h11:0.048:10"));
  const std::map<int, vpColVector> layout = det.getLayout();
  const cv::Matx33d K(cam.get_px(), 0, cam.get_u0(), 0, cam.get_py(), cam.get_v0(), 0, 0, 1);
  double worst = 0;
  for (int n = 1; n <= 8; ++n) {
    vpImage<unsigned char> I;
    vpImageIo::read(I, dir + "/franka_image-" + std::to_string(n) + ".png");
    const vpBoardDetector::Result r = det.detect(I);
    ASSERT_TRUE(r.found) << "image " << n << ": " << r.message;
    ASSERT_EQ(r.corners.size(), 4u) << "image " << n;
    std::vector<cv::Point3d> object;
    std::vector<cv::Point2d> image, projected;
    for (int k = 0; k < 4; ++k) {
      ASSERT_EQ(r.corners[static_cast<size_t>(k)].id, vpBoardDetector::kDefaultIdOffset + 40 + k);
      const vpColVector &X = layout.at(r.corners[static_cast<size_t>(k)].id);
      object.emplace_back(X[0], X[1], X[2]);
      image.emplace_back(r.corners[static_cast<size_t>(k)].ip.get_u(), r.corners[static_cast<size_t>(k)].ip.get_v());
    }
    cv::Vec3d rvec, tvec;
    ASSERT_TRUE(cv::solvePnP(object, image, K, cv::noArray(), rvec, tvec, false, cv::SOLVEPNP_IPPE));
    cv::projectPoints(object, rvec, tvec, K, cv::noArray(), projected);
    double sum = 0;
    for (int k = 0; k < 4; ++k)
      sum += std::pow(cv::norm(projected[static_cast<size_t>(k)] - image[static_cast<size_t>(k)]), 2);
    const double rms = std::sqrt(sum / 4);
    EXPECT_LT(rms, 1.0) << "image " << n;
    std::cout << "[ markers  ] Franka eye-to-hand image " << n << ": square-fit RMS " << rms << " px, "
              << tvec[2] << " m away\n";
    EXPECT_GT(tvec[2], 0.1) << "image " << n; // in front of the camera, 0.13 to 0.26 m away
    EXPECT_LT(tvec[2], 0.3) << "image " << n;
    worst = std::max(worst, rms);
  }
  std::cout << "[ markers  ] Franka eye-to-hand: AprilTag 36h11 id 10 in 8 of 8 images, square-fit RMS at most "
            << worst << " px\n";
}
