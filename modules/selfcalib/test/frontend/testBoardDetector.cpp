/*
 * Tests of vpBoardDetector: boards rendered here (a texture drawn from the board's layout, projected
 * by vpImageSimulator at known poses, then blurred and noised as the scenario's renderer does), the
 * board description parser, and the real data sets beside the project (skipped when absent).
 */
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <string>

#include <opencv2/calib3d.hpp>

#include <visp3/core/vpPoseVector.h>
#include <visp3/core/vpXmlParserCamera.h>
#include <visp3/io/vpImageIo.h>
#include <visp3/selfcalib/vpBoardDetector.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibRenderer.h>

#include "boardSpecTest.h"
#include "boardTestImages.h"

namespace fs = std::filesystem;

namespace
{
// Largest distance (px) between the detected points and the projections of their layout points;
// every id of the board must be there, once, in order. -1 when not.
double largestError(const vpBoardDetector &det, const vpBoardDetector::Result &r, const vpHomogeneousMatrix &cMo)
{
  const std::map<int, vpColVector> layout = det.getLayout();
  if (!r.found || r.corners.size() != layout.size())
    return -1;
  double worst = 0;
  auto it = layout.begin();
  for (const vpSelfCalibDataset::Observation &o : r.corners) {
    if (o.id != (it++)->first)
      return -1;
    const vpImagePoint truth = boardtest::project(cMo, layout.at(o.id));
    worst = std::max(worst, vpImagePoint::distance(truth, o.ip));
  }
  return worst;
}

// The board at five poses, about half a metre away, tilted, turned in its plane by 0, 90, 180,
// 270 and 35 degrees: found every time, every point with its id and within 0.1 px of its true
// projection.
void expectSubPixelAtPoses(const vpBoardDetector::Options &o, const std::string &what)
{
  const vpBoardDetector det(o);
  const double rolls[] = {0, 90, 180, 270, 35}, tilts[][2] = {{15, -10}, {-20, 12}, {10, 20}, {-12, -18}, {25, 0}};
  double worst = 0;
  for (int k = 0; k < 5; ++k) {
    const vpHomogeneousMatrix cMo = boardtest::pose(det, rolls[k], tilts[k][0], tilts[k][1], 0.5);
    const vpImage<unsigned char> I = boardtest::render(o, cMo, static_cast<uint64_t>(k));
    const vpBoardDetector::Result r = det.detect(I);
    ASSERT_TRUE(r.found) << what << ", roll " << rolls[k] << ": " << r.message;
    const double e = largestError(det, r, cMo);
    ASSERT_GE(e, 0) << what << ", roll " << rolls[k] << ": ids wrong or missing";
    EXPECT_LT(e, 0.1) << what << ", roll " << rolls[k];
    worst = std::max(worst, e);
  }
  std::cout << "[ board    ] " << what << ": largest error " << worst << " px over 5 poses\n";
}
} // namespace

TEST(BoardDetector, ChessboardCornersSubPixelAndStableIds)
{
  expectSubPixelAtPoses(vpBoardDetector::parse("chessboard:6x9:0.02"), "chessboard 6 x 9");
  expectSubPixelAtPoses(vpBoardDetector::parse("chessboard:9x6:0.02"), "chessboard 9 x 6");
}

TEST(BoardDetector, ModifiedCircleGridSubPixelAndStableIds)
{
  expectSubPixelAtPoses(vpBoardDetector::parse("modified-circles:10x10:0.02"), "modified circle grid 10 x 10");
  expectSubPixelAtPoses(vpBoardDetector::parse("modified-circles:5x7:0.025"), "modified circle grid 5 x 7");
}

TEST(BoardDetector, AsymmetricCircleGridSubPixelAndStableIds)
{
  expectSubPixelAtPoses(vpBoardDetector::parse("acircles:11x4:0.02"), "asymmetric circle grid 11 x 4");
}

// A symmetric circle grid looks the same turned by 180 degrees: refused unless 'upright', and then
// labelled from the image: turned by 20 degrees the ids are the layout's, turned by 200 degrees
// they belong to the points opposite (the documented limit of the rule).
TEST(BoardDetector, UprightRuleForSymmetricGrids)
{
  EXPECT_THROW(vpBoardDetector::parse("circles:4x5:0.02"), vpSelfCalibException);
  const vpBoardDetector::Options o = vpBoardDetector::parse("circles:4x5:0.03:upright");
  const vpBoardDetector det(o);
  const std::map<int, vpColVector> layout = det.getLayout();
  for (double roll : {20.0, 200.0}) {
    const vpHomogeneousMatrix cMo = boardtest::pose(det, roll, 10, -15, 0.5);
    const vpBoardDetector::Result r = det.detect(boardtest::render(o, cMo, 7));
    ASSERT_TRUE(r.found) << r.message;
    ASSERT_EQ(r.corners.size(), 20u);
    for (const vpSelfCalibDataset::Observation &ob : r.corners) {
      const int k = ob.id - o.id_offset, opposite = 19 - k; // (r, c) -> (3 - r, 4 - c)
      const int physical = roll < 90 ? k : opposite;
      EXPECT_LT(vpImagePoint::distance(ob.ip, boardtest::project(cMo, layout.at(o.id_offset + physical))), 0.1);
    }
  }
}

TEST(BoardDetector, NotFoundWithReason)
{
  const vpBoardDetector::Options chess = vpBoardDetector::parse("chessboard:6x9:0.02");
  const vpBoardDetector det(chess);
  // A blank, noisy image.
  vpImage<unsigned char> blank(boardtest::kHeight, boardtest::kWidth, 128);
  vpSelfCalibRenderer::blurAndNoise(blank, 0.7, 2.0, 3, 0);
  vpBoardDetector::Result r = det.detect(blank);
  EXPECT_FALSE(r.found);
  EXPECT_TRUE(r.corners.empty());
  EXPECT_EQ(r.message, "no 6 x 9 chessboard (inner corners) found");
  // The board half out of the image.
  vpHomogeneousMatrix cMo = boardtest::pose(det, 0, 0, 0, 0.5);
  cMo[0][3] += 0.15;
  r = det.detect(boardtest::render(chess, cMo, 1));
  EXPECT_FALSE(r.found);
  EXPECT_FALSE(r.message.empty());
  // A circle grid where a chessboard is looked for, and the other way round.
  const vpBoardDetector::Options grid = vpBoardDetector::parse("modified-circles:10x10:0.02");
  const vpBoardDetector grid_det(grid);
  EXPECT_FALSE(det.detect(boardtest::render(grid, boardtest::pose(grid_det, 0, 10, 10, 0.5), 2)).found);
  r = grid_det.detect(boardtest::render(chess, boardtest::pose(det, 0, 10, 10, 0.5), 2));
  EXPECT_FALSE(r.found);
  EXPECT_EQ(r.message.rfind("no 10 x 10 modified circle grid found (", 0), 0u) << r.message;
  // A symmetric grid (no larger dot) looked for as a modified one: found, but no origin.
  const vpBoardDetector::Options plain = vpBoardDetector::parse("circles:10x10:0.02:upright");
  r = grid_det.detect(boardtest::render(plain, boardtest::pose(grid_det, 0, 10, 10, 0.5), 2));
  EXPECT_FALSE(r.found);
  EXPECT_NE(r.message.find("clearly larger"), std::string::npos) << r.message;
  // A modified 5 x 7 grid looked for as 7 x 5: its larger dot is at the wrong corner.
  const vpBoardDetector::Options five = vpBoardDetector::parse("modified-circles:5x7:0.025");
  vpBoardDetector::Options seven = five;
  std::swap(seven.rows, seven.cols);
  r = vpBoardDetector(seven).detect(boardtest::render(five, boardtest::pose(vpBoardDetector(five), 0, 10, 10, 0.5), 4));
  EXPECT_FALSE(r.found);
  EXPECT_NE(r.message.find("swap rows and columns"), std::string::npos) << r.message;
  EXPECT_THROW(det.detect(vpImage<unsigned char>()), vpSelfCalibException);
}

TEST(BoardDetector, AmbiguousBoardsRefused)
{
  auto options = [](vpBoardDetector::Type t, unsigned int rows, unsigned int cols) {
    vpBoardDetector::Options o;
    o.type = t;
    o.rows = rows;
    o.cols = cols;
    return o;
  };
  for (const vpBoardDetector::Options &o :
       {options(vpBoardDetector::CHESSBOARD, 7, 7), options(vpBoardDetector::CHESSBOARD, 5, 7),
        options(vpBoardDetector::CHESSBOARD, 8, 6), options(vpBoardDetector::CIRCLES, 4, 11),
        options(vpBoardDetector::ASYMMETRIC_CIRCLES, 4, 11)}) {
    EXPECT_TRUE(o.isAmbiguous()) << vpBoardDetector::toString(o);
    EXPECT_THROW(o.check(), vpSelfCalibException) << vpBoardDetector::toString(o);
    vpBoardDetector::Options u = o;
    u.assume_upright = true;
    EXPECT_NO_THROW(u.check()) << vpBoardDetector::toString(u);
  }
  for (const vpBoardDetector::Options &o :
       {options(vpBoardDetector::CHESSBOARD, 6, 9), options(vpBoardDetector::CHESSBOARD, 2, 3),
        options(vpBoardDetector::ASYMMETRIC_CIRCLES, 11, 4), options(vpBoardDetector::MODIFIED_CIRCLES, 10, 10)}) {
    EXPECT_FALSE(o.isAmbiguous()) << vpBoardDetector::toString(o);
    EXPECT_NO_THROW(o.check()) << vpBoardDetector::toString(o);
  }
  try {
    options(vpBoardDetector::ASYMMETRIC_CIRCLES, 4, 11).check();
  } catch (const vpSelfCalibException &e) {
    EXPECT_NE(e.getStringMessage().find("looks the same after a turn"), std::string::npos) << e.getStringMessage();
    EXPECT_NE(e.getStringMessage().find("acircles:11x4"), std::string::npos) << e.getStringMessage();
  }
  vpBoardDetector::Options bad = options(vpBoardDetector::CHESSBOARD, 6, 9);
  bad.id_offset = -1;
  EXPECT_THROW(vpBoardDetector{bad}, vpSelfCalibException);
  bad.id_offset = 2147483600;
  EXPECT_THROW(bad.check(), vpSelfCalibException);
  bad = options(vpBoardDetector::CIRCLES, 2, 9);
  bad.assume_upright = true;
  EXPECT_THROW(bad.check(), vpSelfCalibException);
  bad = options(vpBoardDetector::CHESSBOARD, 6, 9);
  bad.spacing = std::nan("");
  EXPECT_THROW(bad.check(), vpSelfCalibException);
}

TEST(BoardDetector, ParseDescriptions)
{
  vpBoardDetector::Options o = vpBoardDetector::parse("chessboard:9x6:0.0236");
  EXPECT_EQ(o.type, vpBoardDetector::CHESSBOARD);
  EXPECT_EQ(o.rows, 9u);
  EXPECT_EQ(o.cols, 6u);
  EXPECT_EQ(o.spacing, 0.0236);
  EXPECT_EQ(o.id_offset, vpBoardDetector::kDefaultIdOffset);
  EXPECT_FALSE(o.assume_upright);
  o = vpBoardDetector::parse("modified-circles:10x10:0.0254");
  EXPECT_EQ(o.type, vpBoardDetector::MODIFIED_CIRCLES);
  EXPECT_EQ(o.spacing, 0.0254);
  o = vpBoardDetector::parse("acircles:11x4:2e-2");
  EXPECT_EQ(o.type, vpBoardDetector::ASYMMETRIC_CIRCLES);
  EXPECT_EQ(o.rows, 11u);
  EXPECT_EQ(o.cols, 4u);
  EXPECT_EQ(o.spacing, 0.02);
  o = vpBoardDetector::parse("circles:4x11:0.02:upright");
  EXPECT_EQ(o.type, vpBoardDetector::CIRCLES);
  EXPECT_TRUE(o.assume_upright);
  for (const char *spec : {"chessboard:9x6:0.0236", "circles:4x11:0.02:upright", "acircles:11x4:0.015",
                           "modified-circles:10x10:0.0254"}) {
    const vpBoardDetector::Options p = vpBoardDetector::parse(spec);
    EXPECT_EQ(vpBoardDetector::toString(p), spec);
  }

  expectParseError("", "expected TYPE:ROWSxCOLS:SPACING[:upright]");
  expectParseError("chessboard", "expected TYPE:ROWSxCOLS:SPACING[:upright]");
  expectParseError("chessboard:9x6", "expected TYPE:ROWSxCOLS:SPACING[:upright]");
  expectParseError("chessboard:9x6:0.02:upright:x", "expected TYPE:ROWSxCOLS:SPACING[:upright]");
  expectParseError("chess:9x6:0.02", "board type 'chess': use chessboard, circles, acircles, modified-circles, "
                                     "charuco, apriltag or apriltag-bundle");
  expectParseError("Chessboard:9x6:0.02", "board type 'Chessboard'");
  expectParseError("chessboard:9*6:0.02", "expected ROWSxCOLS as two whole numbers (e.g. 9x6), got '9*6'");
  expectParseError("chessboard:x6:0.02", "got 'x6'");
  expectParseError("chessboard:9x:0.02", "got '9x'");
  expectParseError("chessboard:-9x6:0.02", "got '-9x6'");
  expectParseError("chessboard:9x6x2:0.02", "got '9x6x2'");
  expectParseError("chessboard: 9x6:0.02", "got ' 9x6'");
  expectParseError("chessboard:99999999x6:0.02", "got '99999999x6'");
  expectParseError("chessboard:9x6:", "expected the spacing in m as a positive number (e.g. 0.0236), got ''");
  expectParseError("chessboard:9x6:-0.02", "got '-0.02'");
  expectParseError("chessboard:9x6:0", "got '0'");
  expectParseError("chessboard:9x6:abc", "got 'abc'");
  expectParseError("chessboard:9x6:0.02m", "got '0.02m'");
  expectParseError("chessboard:9x6:nan", "got 'nan'");
  expectParseError("chessboard:9x6:inf", "got 'inf'");
  expectParseError("chessboard:9x6:1e999", "got '1e999'");
  expectParseError("chessboard:9x6:0.02:up", "unknown option 'up' (the only one is 'upright')");
  expectParseError("chessboard:1x6:0.02", "board 'chessboard:1x6:0.02': vpBoardDetector: a 1 x 6 chessboard");
  expectParseError("modified-circles:2x10:0.02", "too small");
  expectParseError("circles:4x11:0.02", "looks the same after a turn in its plane");
  expectParseError("chessboard:7x7:0.02", "e.g. 9 x 6");
}

TEST(BoardDetector, LayoutAndYardstick)
{
  vpBoardDetector::Options o = vpBoardDetector::parse("chessboard:6x9:0.03");
  o.id_offset = 100;
  const vpBoardDetector chess(o);
  const std::map<int, vpColVector> layout = chess.getLayout();
  ASSERT_EQ(layout.size(), 54u);
  EXPECT_EQ(layout.begin()->first, 100);
  EXPECT_EQ(layout.rbegin()->first, 153);
  const vpColVector &p = layout.at(100 + 1 * 9 + 2); // row 1, column 2
  EXPECT_NEAR(p[0], 0.06, 1e-15);
  EXPECT_NEAR(p[1], 0.03, 1e-15);
  EXPECT_EQ(p[2], 0);
  vpSelfCalibDataset::Yardstick y = chess.getYardstick();
  EXPECT_EQ(y.id_a, 100);
  EXPECT_EQ(y.id_b, 108);
  EXPECT_NEAR(y.length, 0.24, 1e-15);
  EXPECT_TRUE(y.isSet());

  const vpBoardDetector acircles(vpBoardDetector::parse("acircles:11x4:0.02"));
  const std::map<int, vpColVector> a = acircles.getLayout();
  const int first = vpBoardDetector::kDefaultIdOffset;
  EXPECT_NEAR(a.at(first + 4 + 1)[0], 0.06, 1e-15); // row 1 (shifted), column 1: x = (2 + 1) * 0.02
  EXPECT_NEAR(a.at(first + 4 + 1)[1], 0.02, 1e-15);
  y = acircles.getYardstick();
  EXPECT_EQ(y.id_b, first + 3);
  EXPECT_NEAR(y.length, 0.12, 1e-15); // three in-row steps of 2 spacings
}

// ---------------------------------------------------------------------------------------------
// The real data sets beside the project (DESIGN.md: ../shared/data), when they are there.

namespace
{
std::string sharedData(const std::string &set)
{
  return (fs::path(SELFCALIB_SHARED_DATA) / set).string();
}
} // namespace

// ViSP's Franka eye-in-hand set: the 9 x 6 chessboard in all 8 images, and the ids name the same
// physical corners in every view: the board's origin and axes in the robot's base frame (the
// flange pose, ViSP's published eMc, the board's pose from its corners) agree with view 1's within
// 3 cm and 5 degrees (measured: 9 mm and 1.1 degrees, the flange poses' own error); a board labelled
// after a half turn would move its origin by 0.22 m and turn it by 180 degrees.
TEST(BoardDetector, RealFrankaChessboard)
{
  const std::string dir = sharedData("visp-franka-eye-in-hand");
  if (!fs::is_directory(dir))
    GTEST_SKIP() << "no real data: " << dir << " is absent (DESIGN.md, ../shared/data)";
  vpCameraParameters cam;
  vpXmlParserCamera xml;
  ASSERT_EQ(xml.parse(cam, dir + "/franka_camera.xml", "Camera", vpCameraParameters::perspectiveProjWithDistortion),
            vpXmlParserCamera::SEQUENCE_OK);
  const vpHomogeneousMatrix eMc(0.0577, -0.0339, -0.0423, 0.002, 0.0095, 1.5817);
  const vpBoardDetector det(vpBoardDetector::parse("chessboard:9x6:0.0236"));
  const std::map<int, vpColVector> layout = det.getLayout();
  std::vector<vpHomogeneousMatrix> fMo;
  for (int n = 1; n <= 8; ++n) {
    vpImage<unsigned char> I;
    vpImageIo::read(I, dir + "/franka_image-" + std::to_string(n) + ".png");
    const vpBoardDetector::Result r = det.detect(I);
    ASSERT_TRUE(r.found) << "image " << n << ": " << r.message;
    ASSERT_EQ(r.corners.size(), 54u);
    std::vector<cv::Point3d> object;
    std::vector<cv::Point2d> image;
    for (const vpSelfCalibDataset::Observation &o : r.corners) {
      const vpColVector &X = layout.at(o.id);
      object.emplace_back(X[0], X[1], X[2]);
      image.emplace_back(o.ip.get_u(), o.ip.get_v());
    }
    const cv::Matx33d K(cam.get_px(), 0, cam.get_u0(), 0, cam.get_py(), cam.get_v0(), 0, 0, 1);
    cv::Vec3d rvec, tvec;
    ASSERT_TRUE(cv::solvePnP(object, image, K, cv::noArray(), rvec, tvec));
    vpPoseVector fPe;
    ASSERT_TRUE(vpPoseVector::loadYAML(dir + "/franka_pose_rPe_" + std::to_string(n) + ".yaml", fPe));
    fMo.push_back(vpHomogeneousMatrix(fPe) * eMc * vpHomogeneousMatrix(tvec[0], tvec[1], tvec[2], rvec[0], rvec[1], rvec[2]));
  }
  double position = 0, angle = 0;
  for (size_t k = 1; k < fMo.size(); ++k) {
    const vpHomogeneousMatrix d = fMo[0].inverse() * fMo[k];
    position = std::max(position, d.getTranslationVector().frobeniusNorm());
    angle = std::max(angle, vpThetaUVector(d.getRotationMatrix()).getTheta());
  }
  std::cout << "[ board    ] Franka: chessboard found in 8 of 8 images; board pose in the base frame within "
            << 1e3 * position << " mm and " << angle * 180 / M_PI << " deg of view 1's\n";
  EXPECT_LT(position, 0.03);
  EXPECT_LT(angle, 5 * M_PI / 180);
}

// industrial_calibration's 10 x 10 set: the modified circle grid in all 15 images, its origin (id
// 0) on the larger dot: of the grid's four corner dots, the origin's covers more than 1.8 times the
// dark pixels of any other (measured: 2.3 to 6 times) (dark: below the midpoint between the grey at the dot's centre and at
// the centre of its grid cell; counted within 0.6 of the local step).
TEST(BoardDetector, RealIndustrialModifiedCircleGrid)
{
  const std::string dir = sharedData("industrial-calibration-10x10");
  if (!fs::is_directory(dir))
    GTEST_SKIP() << "no real data: " << dir << " is absent (DESIGN.md, ../shared/data)";
  const vpBoardDetector det(vpBoardDetector::parse("modified-circles:10x10:0.0254"));
  unsigned int found = 0;
  for (int n = 0; n < 15; ++n) {
    vpImage<unsigned char> I;
    vpImageIo::read(I, dir + "/images/" + std::to_string(n) + ".png");
    const vpBoardDetector::Result r = det.detect(I);
    EXPECT_TRUE(r.found) << "image " << n << ": " << r.message;
    if (!r.found)
      continue;
    ++found;
    ASSERT_EQ(r.corners.size(), 100u);
    unsigned int dark[4];
    for (int k = 0; k < 4; ++k) {
      const int row = k & 1 ? 9 : 0, col = k & 2 ? 9 : 0, inward = (k & 1 ? -10 : 10) + (k & 2 ? -1 : 1);
      const vpImagePoint &p = r.corners[static_cast<size_t>(row * 10 + col)].ip;
      const vpImagePoint &q = r.corners[static_cast<size_t>(row * 10 + col + inward)].ip;
      const vpImagePoint cell((p.get_i() + q.get_i()) / 2, (p.get_j() + q.get_j()) / 2);
      const double threshold = 0.5 * (I(static_cast<unsigned int>(std::lround(p.get_i())), static_cast<unsigned int>(std::lround(p.get_j()))) +
                                      I(static_cast<unsigned int>(std::lround(cell.get_i())), static_cast<unsigned int>(std::lround(cell.get_j()))));
      dark[k] = boardtest::darkPixelsAround(I, p, 0.6 * vpImagePoint::distance(p, q) / std::sqrt(2.0), threshold);
    }
    EXPECT_GT(dark[0], 1.8 * std::max({dark[1], dark[2], dark[3]}))
        << "image " << n << ": id 0 is not on the larger dot: dark pixels at the corners " << dark[0] << ", "
        << dark[1] << ", " << dark[2] << ", " << dark[3];
  }
  std::cout << "[ board    ] industrial_calibration: modified circle grid found in " << found << " of 15 images\n";
}
