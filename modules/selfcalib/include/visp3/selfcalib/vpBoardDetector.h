/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpBoardDetector.h
  \brief Calibration boards as an optional front end: a chessboard or a circle grid found in an image,
  each of its points identified by its place on the board, so that the same physical point has the
  same id in every image whatever the board's rotation in the image.
*/
#ifndef VP_BOARD_DETECTOR_H
#define VP_BOARD_DETECTOR_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <map>
#include <string>
#include <vector>

#include <visp3/core/vpColVector.h>
#include <visp3/core/vpImage.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>

/*!
  \class vpBoardDetector
  \ingroup group_selfcalib_frontend
  \brief Calibration boards as an optional front end: a chessboard or a circle grid found in an
  image, each of its points identified by its place on the board, so that the same physical point
  has the same id in every image whatever the board's rotation in the image.

  <b>Boards</b> (rows x cols points, `spacing` m apart):
  - CHESSBOARD: rows x cols inner corners (OpenCV findChessboardCornersSB, findChessboardCorners
    with its fast check when it fails, then cornerSubPix with a window of 0.4 times the smallest
    corner distance).
  - CIRCLES: a symmetric grid of rows x cols dark dots (OpenCV findCirclesGrid).
  - ASYMMETRIC_CIRCLES: OpenCV's asymmetric grid: `rows` rows of `cols` dots, row r shifted by half
    a step when r is odd; dots of a row are 2 spacing apart, rows spacing apart (OpenCV's sample
    and its pattern generator; OpenCV's printed acircles pattern, its patternSize 4 x 11, is
    `rows` 11, `cols` 4 here).
  - MODIFIED_CIRCLES: industrial_calibration's modified circle grid: a symmetric grid with one
    larger dot at a corner, the origin.

  Dots are found by OpenCV's SimpleBlobDetector (dark, round, convex); each centre is then refined
  to the grey-level centroid of its dot (background-subtracted, iterated on a window that holds no
  other dot) and corrected for perspective: the centre of a disc's image is not the image of its
  centre (about f R^2 / Z^2 times the tilt's sine: 0.03 px for a 5 mm dot at 0.5 m, 0.15 px for a
  larger origin dot); the offset is computed from the board's homography and each dot's measured
  size, and removed. On rendered boards (blur 0.7 px, noise 2 grey levels) the points are within
  0.07 px (chessboard corners) and 0.03 px (dots) of their true projections (testBoardDetector).

  <b>Board frame and ids</b>: the point of row r and column c is at (x, y, 0) = (c, r, 0) * spacing
  ((2 c + r % 2, r, 0) * spacing for ASYMMETRIC_CIRCLES) and has the id id_offset + r * cols + c.
  z points into the board, away from a camera that sees its printed side (OpenCV's chessboard
  convention): in the image, turning from the first row's direction (x) to the first column's (y)
  is clockwise (u right, v down). Which corner is the origin:
  - CHESSBOARD with rows + cols odd (e.g. 9 x 6): the inner corner whose outer corner square
    (the square beyond it, diagonally, at (-0.5, -0.5) spacing) is black. The square's colour flips
    under a 180-degree turn of such a board, so the origin is the same physical corner in every view.
  - ASYMMETRIC_CIRCLES with an odd number of rows: the grid's outline is not symmetric: its rows
    are told apart by which of them is shifted.
  - MODIFIED_CIRCLES: the larger dot (its size relative to its two neighbours, as
    industrial_calibration measures it). With respect to industrial_calibration's target frame
    (origin at the large dot, x along its rows, y towards its first row, z out of the board), x
    and y are swapped: point (r, c) here is its point at (r, c) * spacing.

  The other boards look the same after a turn in their plane (CIRCLES always; a CHESSBOARD with
  rows + cols even or rows = cols; ASYMMETRIC_CIRCLES with an even number of rows): the image alone
  cannot tell which physical point is which. They are refused (Options::check() throws) unless
  Options::assume_upright: then, of the labellings the board allows, the one whose first row runs
  closest to the image's u direction (left to right) is taken. That rule keeps the ids only while
  the board's image turns by less than 90 degrees (45 for a square board) away from upright: a
  wrist camera that turns further gives another labelling, i.e. wrong correspondences.

  Library code: nothing is printed; a board not found is a Result with found false and the reason.
*/
class VISP_SELFCALIB_EXPORT vpBoardDetector
{
public:
  enum Type {
    CHESSBOARD,         //!< inner corners of a chessboard
    CIRCLES,            //!< symmetric circle grid
    ASYMMETRIC_CIRCLES, //!< OpenCV's asymmetric circle grid
    MODIFIED_CIRCLES    //!< symmetric grid with a larger dot at the origin (industrial_calibration)
  };
  //! "chessboard", "circles", "acircles", "modified-circles".
  static const char *typeName(Type type);
  //! The inverse of typeName(); throws vpSelfCalibException for another name.
  static Type typeFromName(const std::string &name);

  //! Ids of the board's points start here by default: above the dot grids' ids (1000000 + 1000 g)
  //! and the natural features' tracks (0, 1, ...).
  static constexpr int kDefaultIdOffset = 2000000;

  //! Settings of vpBoardDetector (the defaults are the member initialisers).
  struct Options {
    Type type = CHESSBOARD;
    unsigned int rows = 6, cols = 9; //!< inner corners (CHESSBOARD) or dots
    double spacing = 0.025;          //!< m: square side, or distance between neighbouring dots (see the class)
    int id_offset = kDefaultIdOffset; //!< id of the point of row 0, column 0
    //! Accept a board whose layout repeats under a turn, labelled by the image's up direction (see
    //! the class: stable only while the board stays within 90 degrees of upright).
    bool assume_upright = false;
    //! Throws vpSelfCalibException: fewer than 2 rows or columns (3 dots for the grids), a spacing
    //! that is not a positive finite number, a negative id offset or ids beyond INT_MAX, or a board
    //! whose orientation cannot be told from the image without assume_upright.
    void check() const;
    //! True when the layout repeats under a turn in its plane (see the class).
    bool isAmbiguous() const;
  };

  /*!
    Parses a board description TYPE:ROWSxCOLS:SPACING[:upright], e.g. `chessboard:9x6:0.0236`,
    `circles:4x11:0.02`, `acircles:11x4:0.02`, `modified-circles:10x10:0.0254`: ROWS x COLS inner
    corners (chessboard) or dots (grids), SPACING in m. The optional `upright` sets
    Options::assume_upright. The id offset is the default. Throws vpSelfCalibException (parseError)
    naming the part that is wrong, or as Options::check() does.
  */
  static Options parse(const std::string &spec);
  //! The description parse() reads back.
  static std::string toString(const Options &options);

  //! What detect() found in one image.
  struct Result {
    bool found = false;  //!< all rows x cols points found and their orientation settled
    std::string message; //!< why the board was not found (empty when found)
    //! The board's points, by increasing id (id_offset + r * cols + c), in pixels.
    std::vector<vpSelfCalibDataset::Observation> corners;
  };

  //! Throws as Options::check() does.
  explicit vpBoardDetector(const Options &options);

  //! Finds the board in a grey image. Throws vpSelfCalibException for an empty image only.
  Result detect(const vpImage<unsigned char> &I) const;

  const Options &getOptions() const { return m_options; }
  //! The board's layout in its frame: id -> (x, y, 0) in m (see the class).
  std::map<int, vpColVector> getLayout() const;
  /*!
    The board as a yardstick: the two ends of its first row (ids id_offset and id_offset + cols - 1),
    their distance apart ((cols - 1) spacing; twice that for ASYMMETRIC_CIRCLES).
  */
  vpSelfCalibDataset::Yardstick getYardstick() const;

private:
  Options m_options;
};

#endif
