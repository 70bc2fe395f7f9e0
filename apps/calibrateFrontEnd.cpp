/*
 * visp-selfcalib calibrate: the front end's part of its command line (dot grids, natural features,
 * a board, a mask) and the front end's options it gives (see calibrate.h).
 */
#include "calibrate.h"

#include <visp3/selfcalib/vpBoardDetector.h>
#include <visp3/selfcalib/vpDotGrid.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include "selfcalibCli.h"

namespace
{
//! "CxR": C columns, R rows of an asymmetric circle grid; false when it is not that.
bool parseDotGrid(const std::string &item, vpFeatureFrontEnd::DotGrid &g)
{
  const size_t x = item.find('x');
  const std::string digits = "0123456789";
  if (x == std::string::npos || x == 0 || x + 1 == item.size() ||
      item.substr(0, x).find_first_not_of(digits) != std::string::npos ||
      item.substr(x + 1).find_first_not_of(digits) != std::string::npos || item.size() > 12)
    return false;
  const unsigned long cols = std::stoul(item.substr(0, x)), rows = std::stoul(item.substr(x + 1));
  if (cols == 0 || rows == 0 || cols > 1000 || rows > 1000)
    return false;
  g.cols = static_cast<unsigned int>(cols);
  g.rows = static_cast<unsigned int>(rows);
  return true;
}
} // namespace

//! The front end: dot grids, natural features, a board, a mask.
void addFrontEndOptions(CLI::App *c, CalibrateArgs &a)
{
  c->add_option("--dot-grids", a.dot_grids,
                "dot targets for the front end: asymmetric circle grids, C columns x R rows (R odd),\n"
                "grid g numbered from 1000000 + 1000 g; their dots must differ in size")
      ->type_name("CxR[,CxR...]")
      ->delimiter(',')
      ->check(CLI::Validator(
          [](std::string &item) -> std::string {
            vpFeatureFrontEnd::DotGrid g;
            return parseDotGrid(item, g) ? std::string() : "expected COLSxROWS[,COLSxROWS...], got '" + item + "'";
          },
          std::string()));
  CLI::Option *no_features = c->add_flag("--no-features", a.no_features, "no natural features (dot targets only)");
  CLI::Option *board =
      c->add_option("--board", a.board,
                    "a calibration board whose points are the observations (their ids from\n"
                    "2000000 + row * cols + col): chessboard:ROWSxCOLS:SPACING (inner corners),\n"
                    "circles:, acircles: or modified-circles:ROWSxCOLS:SPACING (dots), spacing in m,\n"
                    "e.g. chessboard:9x6:0.0236, modified-circles:10x10:0.0254; ':upright' accepts a\n"
                    "board that looks the same turned.\n"
                    "charuco:COLSxROWS:SQUARE:MARKER:DICT: a ChArUco board of COLS x ROWS squares\n"
                    "(OpenCV's count), SQUARE and MARKER sides in m, an OpenCV dictionary, e.g.\n"
                    "charuco:5x7:0.034:0.028:DICT_6X6_250; inner corner (r, c) has the id\n"
                    "2000000 + r * (COLS - 1) + c (OpenCV's ChArUco corner id) and lies at\n"
                    "((c + 1), (r + 1)) * SQUARE from the board's top-left outer corner (x right,\n"
                    "y down, z into the board); a board partly out of view or hidden still gives\n"
                    "the corners it shows.\n"
                    "apriltag:FAMILY:SIZE[:ID,...]: AprilTags (36h11, 36h10, 25h9, 16h5) of side\n"
                    "SIZE m, only those ids when given, e.g. apriltag:36h11:0.048:10; corner k\n"
                    "(0..3: top-left, top-right, bottom-right, bottom-left as printed) of tag t has\n"
                    "the id 2000000 + 4 * t + k; tag frame: centre, x right, y down.\n"
                    "apriltag-bundle:FILE.yaml: tags of known placement as one board (family: 36h11,\n"
                    "tags: [{id: 0, size: 0.04, pose: [tx, ty, tz, tux, tuy, tuz]}, ...], the pose\n"
                    "of each tag in the bundle's frame).\n"
                    "Without a yardstick in the dataset, the ends of the board's first row (a\n"
                    "ChArUco board's first row of corners, the first tag's top edge) are the yardstick")
          ->type_name("SPEC")
          ->check(CLI::Validator(
              [](std::string &spec) -> std::string {
                try {
                  vpBoardDetector::parse(spec);
                  return std::string();
                } catch (const vpSelfCalibException &e) {
                  return e.getStringMessage();
                }
              },
              std::string()));
  c->add_flag("--with-features", a.with_features, "with --board: natural features too")->needs(board)->excludes(no_features);
  CLI::Option *mask_board = c->add_flag("--mask-board", a.mask_board,
              "with --board: the board is found only to be masked out (its region, 15 px beyond its\n"
              "outer points); the calibration uses the natural features around it, target-free")
      ->needs(board)
      ->excludes(no_features);
  c->add_option("--mask", a.mask,
                "an image of the camera's size: where it is black (0) no natural feature is looked\n"
                "for in any view (the robot's own parts, a drawn overlay, a moving background)")
      ->type_name("PNG")
      ->check(CLI::ExistingFile);
  CLI::Option *board_geometry =
      c->add_flag("--board-geometry", a.board_geometry,
                  "with --board: its layout is known (a prior of --board-sd on each point, the\n"
                  "board's pose estimated); without it the board's points are unknown scene points.\n"
                  "AprilTags: one tag (apriltag:FAMILY:SIZE:ID) or a bundle")
          ->needs(board)
          ->excludes(mask_board);
  c->add_option("--board-sd", a.board_sd,
                "with --board-geometry: sd (m) of each point's placement on the board (default 1e-5,\n"
                "10 um: a printed or machined board's accuracy; the layout then holds the points)")
      ->type_name("SD")
      ->check(selfcalibCli::number(0, true, 0.01))
      ->needs(board_geometry);
}

vpSelfCalibImageCorrespondences::Options frontEndOptions(const CalibrateArgs &a)
{
  vpSelfCalibImageCorrespondences::Options co;
  // A board alone unless natural features are asked for too.
  co.front_end.features = a.board.empty() ? !a.no_features : (a.with_features || a.mask_board);
  if (!a.board.empty())
    co.board = vpBoardDetector::parse(a.board);
  co.mask_board = a.mask_board;
  if (!a.mask.empty()) {
    co.front_end.masks.push_back(vpFeatureFrontEnd::readImage(a.mask, "--mask: cannot read the image '" + a.mask + "'"));
  }
  // C x R; grid g numbered from 1000000 + 1000 g (as simulate --target dots).
  for (const std::string &item : a.dot_grids) {
    vpFeatureFrontEnd::DotGrid g;
    parseDotGrid(item, g);
    g.first_id = vpDotGrid::kDefaultFirstId + 1000 * static_cast<int>(co.front_end.dot_grids.size());
    co.front_end.dot_grids.push_back(g);
  }
  if (!a.method.empty())
    co.method = vpRobotSelfCalibration::methodFromName(a.method);
  return co;
}
