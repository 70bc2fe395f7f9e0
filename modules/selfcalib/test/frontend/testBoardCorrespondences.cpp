/*
 * Tests of a calibration board as the front end of vpSelfCalibImageCorrespondences: its points as
 * the observations, alone or with natural features, the yardstick rule, views without the board,
 * id collisions, and a dataset's image files.
 */
#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include <unistd.h>

#include <visp3/io/vpImageIo.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibImageCorrespondences.h>

#include "boardTestImages.h"

namespace fs = std::filesystem;

namespace
{
const char *const kBoard = "chessboard:6x9:0.02";

// Four views of the board (turned by 0, 90, 200 and 300 degrees, tilted) and a fifth without it;
// controller poses, no joints.
struct Scene {
  vpSelfCalibDataset dataset;
  std::vector<vpImage<unsigned char>> images;
};

Scene makeScene()
{
  Scene s;
  s.dataset.width = boardtest::kWidth;
  s.dataset.height = boardtest::kHeight;
  s.dataset.cam = boardtest::kCamera;
  s.dataset.robot = "panda";
  const vpBoardDetector::Options o = vpBoardDetector::parse(kBoard);
  const vpBoardDetector det(o);
  const double rolls[] = {0, 90, 200, 300};
  for (int k = 0; k < 5; ++k) {
    vpSelfCalibDataset::View v;
    v.has_fMe = true;
    v.fMe = vpHomogeneousMatrix(0.4, 0.1 * k, 0.5, 0, 0, 0.1 * k);
    s.dataset.views.push_back(v);
    if (k < 4)
      s.images.push_back(boardtest::render(o, boardtest::pose(det, rolls[k], 12, -8, 0.5), static_cast<uint64_t>(k)));
  }
  vpImage<unsigned char> blank(boardtest::kHeight, boardtest::kWidth, 128);
  vpSelfCalibRenderer::blurAndNoise(blank, 0.7, 2.0, 1, 9);
  s.images.push_back(blank);
  return s;
}

vpSelfCalibImageCorrespondences::Options boardOnly()
{
  vpSelfCalibImageCorrespondences::Options o;
  o.front_end.features = false;
  o.board = vpBoardDetector::parse(kBoard);
  return o;
}
} // namespace

// The board alone: its 54 corners are every kept view's observations, with the board's ids; the view
// without it is left out with a warning that says why; the board is the yardstick (its first row,
// 8 squares); controller poses choose the hand-eye method.
TEST(BoardCorrespondences, BoardAloneIsTheObservations)
{
  Scene s = makeScene();
  const vpSelfCalibImageCorrespondences::Result r =
      vpSelfCalibImageCorrespondences::fromImages(s.dataset, s.images, boardOnly());
  EXPECT_FALSE(r.front_end_ran);
  EXPECT_TRUE(r.board_ran);
  ASSERT_EQ(r.board.size(), 5u);
  EXPECT_EQ(r.board_images, 4u);
  ASSERT_EQ(r.dropped.size(), 1u);
  EXPECT_EQ(r.dropped[0].index, 4u);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_EQ(r.warnings[0], "view 4: board not found: no 6 x 9 chessboard (inner corners) found");
  ASSERT_EQ(s.dataset.views.size(), 4u);
  for (size_t k = 0; k < 4; ++k) {
    ASSERT_EQ(s.dataset.views[k].points.size(), 54u);
    for (size_t i = 0; i < 54; ++i) {
      EXPECT_EQ(s.dataset.views[k].points[i].id, vpBoardDetector::kDefaultIdOffset + static_cast<int>(i));
      EXPECT_EQ(s.dataset.views[k].points[i].ip, r.board[k].corners[i].ip);
    }
  }
  EXPECT_TRUE(r.board_yardstick);
  EXPECT_EQ(s.dataset.yardstick.id_a, vpBoardDetector::kDefaultIdOffset);
  EXPECT_EQ(s.dataset.yardstick.id_b, vpBoardDetector::kDefaultIdOffset + 8);
  EXPECT_NEAR(s.dataset.yardstick.length, 0.16, 1e-15);
  EXPECT_EQ(r.method, vpRobotSelfCalibration::HAND_EYE);
}

// A yardstick the dataset declares is kept when it is set; a declared length whose ends the front
// end did not find is replaced by the board's, with a warning; a board seen once is no yardstick.
TEST(BoardCorrespondences, YardstickRule)
{
  Scene s = makeScene();
  vpSelfCalibDataset declared = s.dataset;
  declared.yardstick.length = 0.5;
  vpSelfCalibImageCorrespondences::Result r =
      vpSelfCalibImageCorrespondences::fromImages(declared, s.images, boardOnly());
  EXPECT_TRUE(r.board_yardstick);
  EXPECT_NEAR(declared.yardstick.length, 0.16, 1e-15);
  ASSERT_EQ(r.warnings.size(), 2u);
  EXPECT_EQ(r.warnings[1],
            "the dataset's yardstick (0.5 m) was not found in the images: the board's first row is the yardstick instead");

  vpSelfCalibDataset once = s.dataset;
  std::vector<vpImage<unsigned char>> images(s.images.size(), s.images.back());
  images[0] = s.images[0];
  r = vpSelfCalibImageCorrespondences::fromImages(once, images, boardOnly());
  EXPECT_EQ(r.board_images, 1u);
  EXPECT_FALSE(r.board_yardstick);
  EXPECT_FALSE(once.yardstick.isSet());
  EXPECT_EQ(once.views.size(), 1u);
}

// With natural features too: the tracks keep their ids (below the board's), the board's corners are
// added to them, no id twice in a view; a view without the board keeps its features. Ids that would
// collide are refused before anything is found.
TEST(BoardCorrespondences, BoardWithFeatures)
{
  Scene s = makeScene();
  vpSelfCalibImageCorrespondences::Options o = boardOnly();
  o.front_end.features = true;
  o.front_end.yardstick = false;
  vpSelfCalibDataset data = s.dataset;
  const vpSelfCalibImageCorrespondences::Result r = vpSelfCalibImageCorrespondences::fromImages(data, s.images, o);
  EXPECT_TRUE(r.front_end_ran);
  EXPECT_TRUE(r.board_ran);
  EXPECT_EQ(r.board_images, 4u);
  EXPECT_GT(r.front_end.num_tracks, 0u);
  for (size_t k = 0; k < data.views.size(); ++k) {
    std::set<int> ids;
    unsigned int board_points = 0;
    for (const vpSelfCalibDataset::Observation &ob : data.views[k].points) {
      EXPECT_TRUE(ids.insert(ob.id).second) << "id " << ob.id << " twice in view " << k;
      EXPECT_TRUE(ob.id < static_cast<int>(r.front_end.num_tracks) || ob.id >= vpBoardDetector::kDefaultIdOffset);
      board_points += ob.id >= vpBoardDetector::kDefaultIdOffset;
    }
    EXPECT_EQ(board_points, k < 4 ? 54u : 0u);
    EXPECT_EQ(data.views[k].points.size(), r.front_end.observations[k].size() + board_points);
  }
  EXPECT_TRUE(r.board_yardstick);

  o.board->id_offset = 0; // the tracks' ids
  data = s.dataset;
  EXPECT_THROW(vpSelfCalibImageCorrespondences::fromImages(data, s.images, o), vpSelfCalibException);
  o = boardOnly();
  vpFeatureFrontEnd::DotGrid grid;
  grid.first_id = vpBoardDetector::kDefaultIdOffset + 10;
  o.front_end.dot_grids.push_back(grid);
  data = s.dataset;
  try {
    vpSelfCalibImageCorrespondences::fromImages(data, s.images, o);
    ADD_FAILURE() << "colliding ids accepted";
  } catch (const vpSelfCalibException &e) {
    EXPECT_NE(e.getStringMessage().find("collide with a dot grid's"), std::string::npos) << e.getStringMessage();
  }
}

// The board only masked out (a target-free run in a scene with a board): no observation on the
// board's region in the views where it was found, none with the board's ids, the board is not the
// yardstick; without the mask the same features do land on the board (so the mask is what keeps
// them off). Options that cannot work are refused.
TEST(BoardCorrespondences, BoardMaskedOutLeavesOnlyNaturalFeatures)
{
  Scene s = makeScene();
  vpSelfCalibImageCorrespondences::Options o = boardOnly();
  o.front_end.features = true;
  o.front_end.yardstick = false;
  o.front_end.min_matches = 8;
  vpSelfCalibDataset plain = s.dataset;
  const auto unmasked = vpSelfCalibImageCorrespondences::fromImages(plain, s.images, o);
  o.mask_board = true;
  vpSelfCalibDataset data = s.dataset;
  const vpSelfCalibImageCorrespondences::Result r = vpSelfCalibImageCorrespondences::fromImages(data, s.images, o);
  EXPECT_TRUE(r.board_ran);
  EXPECT_EQ(r.board_images, 4u);
  EXPECT_FALSE(r.board_yardstick);
  EXPECT_FALSE(data.yardstick.isSet());
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_EQ(r.warnings[0], "view 4: board not found, so not masked: no 6 x 9 chessboard (inner corners) found");
  unsigned int on_board_unmasked = 0;
  for (size_t k = 0; k < 4; ++k) {
    const vpImage<unsigned char> mask =
        vpSelfCalibImageCorrespondences::boardMask(r.board[k], boardtest::kHeight, boardtest::kWidth, o.mask_margin);
    // The pixel a feature at (u, v) is in, as OpenCV's mask filter rounds it.
    auto at = [&mask](const vpImagePoint &ip) {
      return mask[static_cast<unsigned int>(ip.get_v() + 0.5)][static_cast<unsigned int>(ip.get_u() + 0.5)];
    };
    for (const auto &ob : unmasked.front_end.observations[k])
      on_board_unmasked += at(ob.ip) == 0;
    for (const auto &ob : r.front_end.observations[k]) {
      EXPECT_NE(at(ob.ip), 0)
          << "view " << k << ": a feature on the masked board at " << ob.ip;
      EXPECT_LT(ob.id, vpBoardDetector::kDefaultIdOffset);
    }
  }
  EXPECT_GT(on_board_unmasked, 20u);

  // The mask: the hull of the board's points and a margin around it, all 255 without a board.
  const vpImage<unsigned char> mask = vpSelfCalibImageCorrespondences::boardMask(r.board[0], 480, 640, 15);
  const vpImagePoint c = r.board[0].corners.front().ip;
  EXPECT_EQ(mask[static_cast<unsigned int>(c.get_v())][static_cast<unsigned int>(c.get_u())], 0);
  EXPECT_EQ(mask[0][0], 255);
  const vpImage<unsigned char> none = vpSelfCalibImageCorrespondences::boardMask(r.board[4], 480, 640, 15);
  for (unsigned int i = 0; i < none.getSize(); ++i)
    ASSERT_EQ(none.bitmap[i], 255);

  vpSelfCalibImageCorrespondences::Options bad = o;
  bad.board.reset();
  data = s.dataset;
  EXPECT_THROW(vpSelfCalibImageCorrespondences::fromImages(data, s.images, bad), vpSelfCalibException);
  bad = o;
  bad.front_end.features = false;
  EXPECT_THROW(vpSelfCalibImageCorrespondences::fromImages(data, s.images, bad), vpSelfCalibException);
  bad = o;
  bad.mask_margin = -1;
  EXPECT_THROW(vpSelfCalibImageCorrespondences::fromImages(data, s.images, bad), vpSelfCalibException);
}

// A dataset's image files with a board: read, searched, the view without the board left out; a
// missing file or one of another size is an error that names the view and the file.
TEST(BoardCorrespondences, DatasetImageFiles)
{
  Scene s = makeScene();
  const fs::path dir = fs::temp_directory_path() / ("selfcalib-board-test-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  for (size_t k = 0; k < s.images.size(); ++k) {
    s.dataset.views[k].image = (dir / ("view" + std::to_string(k) + ".png")).string();
    vpImageIo::write(s.images[k], s.dataset.views[k].image);
  }
  ASSERT_TRUE(vpSelfCalibImageCorrespondences::needsFrontEnd(s.dataset));
  vpSelfCalibDataset data = s.dataset;
  const vpSelfCalibImageCorrespondences::Result r = vpSelfCalibImageCorrespondences::fromDatasetImages(data, boardOnly());
  EXPECT_EQ(r.board_images, 4u);
  EXPECT_EQ(data.views.size(), 4u);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_EQ(r.warnings[0], "view 4 (" + s.dataset.views[4].image +
                               "): board not found: no 6 x 9 chessboard (inner corners) found");
  ASSERT_EQ(r.dropped.size(), 1u);
  EXPECT_EQ(r.dropped[0].image, s.dataset.views[4].image);

  data = s.dataset;
  data.views[2].image = (dir / "none.png").string();
  try {
    vpSelfCalibImageCorrespondences::fromDatasetImages(data, boardOnly());
    ADD_FAILURE() << "a missing image was accepted";
  } catch (const vpSelfCalibException &e) {
    EXPECT_NE(e.getStringMessage().find("view 2: cannot read image '" + data.views[2].image + "'"), std::string::npos)
        << e.getStringMessage();
  }
  data = s.dataset;
  data.width = 320;
  try {
    vpSelfCalibImageCorrespondences::fromDatasetImages(data, boardOnly());
    ADD_FAILURE() << "an image of another size was accepted";
  } catch (const vpSelfCalibException &e) {
    EXPECT_NE(e.getStringMessage().find("view 0: image '" + data.views[0].image + "' is 640 x 480, the camera says 320 x 480"),
              std::string::npos)
        << e.getStringMessage();
  }
  data = s.dataset;
  data.views[1].image.clear();
  EXPECT_THROW(vpSelfCalibImageCorrespondences::fromDatasetImages(data, boardOnly()), vpSelfCalibException);
  fs::remove_all(dir);
}
