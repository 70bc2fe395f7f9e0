/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpBoardDetector.h
  \brief Calibration boards as an optional front end: a chessboard, a circle grid, a ChArUco board or
  AprilTags found in an image, each of its points identified by its place on the board, so that the
  same physical point has the same id in every image whatever the board's rotation in the image.
*/
#ifndef VP_BOARD_DETECTOR_H
#define VP_BOARD_DETECTOR_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <map>
#include <string>
#include <vector>

#include <visp3/core/vpColVector.h>
#include <visp3/core/vpImage.h>
#include <visp3/core/vpPoseVector.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>

/*!
  \class vpBoardDetector
  \ingroup group_selfcalib_frontend
  \brief Calibration boards as an optional front end: a chessboard, a circle grid, a ChArUco board or
  AprilTags found in an image, each of its points identified by its place on the board, so that the
  same physical point has the same id in every image whatever the board's rotation in the image.

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

  <b>Marker boards</b> (OpenCV's aruco module: every point is identified by the coded markers
  around it, so a board half out of view or half hidden still gives identified points):
  - CHARUCO: a chessboard of `cols` x `rows` squares (OpenCV's squaresX x squaresY) of side
    `spacing` with a marker of side `marker_size` of the OpenCV dictionary `dictionary` in each
    white square (cv::aruco::CharucoBoard, OpenCV 4.6's layout: the top-left square is black). Its
    points are the (cols - 1) x (rows - 1) inner corners found by interpolateCornersCharuco (each
    from its two neighbouring markers, refined by cornerSubPix), a corner whose markers were not
    seen is simply missing.
    Board frame: the board as CharucoBoard::draw prints it, origin at its top-left outer corner, x
    along its top edge (left to right), y down its left edge, z into the board. Inner corner (r, c)
    (r = 0 .. rows - 2, c = 0 .. cols - 2) is at ((c + 1), (r + 1), 0) * spacing and has the id
    id_offset + r * (cols - 1) + c (id_offset + OpenCV's ChArUco corner id). The markers fix the
    origin: no turn of the board looks the same, so no upright rule is needed.
  - APRILTAG: AprilTags of family `dictionary` (36h11, 36h10, 25h9, 16h5: OpenCV's
    DICT_APRILTAG_* dictionaries, the tags of the AprilTag library), each of side `marker_size`
    (the outer edge of its black border), either any tag of the family (tag_ids empty), the tags
    of tag_ids, or a bundle: tags of known size and placement in one frame (`bundle`). A tag's
    points are its four outer corners, found by detectMarkers, then refined by a line fit to the
    grey-level edges of each side (sub-pixel) and intersected. Corner k of tag t has the id
    id_offset + 4 t + k; k = 0, 1, 2, 3 are the top-left, top-right, bottom-right and bottom-left
    corners of the tag as printed (OpenCV's order: clockwise seen from the printed side).
    Tag frame: origin at the tag's centre, x to the right, y down, z into the tag (as above):
    corner k at (-s/2, -s/2), (s/2, -s/2), (s/2, s/2), (-s/2, s/2) for a side s. A bundle's tags
    are placed in the bundle's frame by their pose (bMt, ViSP order tx ty tz tux tuy tuz); the
    layout is that of the bundle; tags not in a bundle share no frame (getLayout() refuses
    several of them).

  Library code: nothing is printed; a board not found is a Result with found false and the reason.
*/
class VISP_SELFCALIB_EXPORT vpBoardDetector
{
public:
  enum Type {
    CHESSBOARD,         //!< inner corners of a chessboard
    CIRCLES,            //!< symmetric circle grid
    ASYMMETRIC_CIRCLES, //!< OpenCV's asymmetric circle grid
    MODIFIED_CIRCLES,   //!< symmetric grid with a larger dot at the origin (industrial_calibration)
    CHARUCO,            //!< ChArUco board: inner chessboard corners identified by ArUco markers
    APRILTAG            //!< AprilTags: each tag's four corners (single tags or a bundle)
  };
  //! "chessboard", "circles", "acircles", "modified-circles", "charuco", "apriltag".
  static const char *typeName(Type type);
  //! The inverse of typeName(); throws vpSelfCalibException for another name.
  static Type typeFromName(const std::string &name);

  //! Ids of the board's points start here by default: above the dot grids' ids (1000000 + 1000 g)
  //! and the natural features' tracks (0, 1, ...).
  static constexpr int kDefaultIdOffset = 2000000;

  struct Options {
    Type type = CHESSBOARD;
    unsigned int rows = 6, cols = 9; //!< inner corners (CHESSBOARD) or dots
    double spacing = 0.025;          //!< m: square side, or distance between neighbouring dots (see the class)
    int id_offset = kDefaultIdOffset; //!< id of the point of row 0, column 0
    //! Accept a board whose layout repeats under a turn, labelled by the image's up direction (see
    //! the class: stable only while the board stays within 90 degrees of upright).
    bool assume_upright = false;
    //! CHARUCO: the markers' side (m), below spacing. APRILTAG: the tags' side (m) (outer edge of
    //! the black border) of the tags not in a bundle.
    double marker_size = 0;
    //! CHARUCO: OpenCV's dictionary name (e.g. DICT_6X6_250). APRILTAG: the family (36h11, 36h10,
    //! 25h9, 16h5; "tag36h11" is read as 36h11).
    std::string dictionary;
    //! APRILTAG: the tags looked for (empty: every tag of the family); filled from `bundle` by parse().
    std::vector<int> tag_ids;
    //! APRILTAG: one tag of a bundle: its id, side (m) and pose in the bundle's frame (bMt).
    struct BundleTag {
      int id = 0;
      double size = 0;
      vpPoseVector bMt;
    };
    //! APRILTAG: a bundle (tags of known placement in one frame); empty: single tags.
    std::vector<BundleTag> bundle;
    //! APRILTAG: the bundle's file when it was read from one (toString() names it).
    std::string bundle_file;
    //! Throws vpSelfCalibException: fewer than 2 rows or columns (3 dots for the grids, 3 squares
    //! for a ChArUco board), a spacing that is not a positive finite number, a negative id offset or
    //! ids beyond INT_MAX, a board whose orientation cannot be told from the image without
    //! assume_upright; for CHARUCO a marker not smaller than the squares, a dictionary OpenCV does
    //! not have or with too few markers for the board; for APRILTAG a family OpenCV does not have,
    //! a tag id not in it, a side that is not positive, a tag twice in a bundle.
    void check() const;
    //! True when the layout repeats under a turn in its plane (see the class).
    bool isAmbiguous() const;
    //! How many ids the board's points may take from id_offset on (rows x cols for the grids,
    //! (rows - 1) x (cols - 1) for CHARUCO, 4 x the family's size for APRILTAG).
    int numIds() const;
  };

  /*!
    Parses a board description:
    - TYPE:ROWSxCOLS:SPACING[:upright], e.g. `chessboard:9x6:0.0236`, `circles:4x11:0.02`,
      `acircles:11x4:0.02`, `modified-circles:10x10:0.0254`: ROWS x COLS inner corners
      (chessboard) or dots (grids), SPACING in m. The optional `upright` sets
      Options::assume_upright.
    - `charuco:COLSxROWS:SQUARE:MARKER:DICT`, e.g. `charuco:5x7:0.034:0.028:DICT_6X6_250`: COLS x
      ROWS squares (as OpenCV counts them), the sides of the squares and of the markers in m,
      OpenCV's dictionary.
    - `apriltag:FAMILY:SIZE[:ID,ID...]`, e.g. `apriltag:36h11:0.048:10`: tags of the family, SIZE
      m each, only those ids when given.
    - `apriltag-bundle:FILE.yaml`: a bundle, its family and tags in a YAML file:
      \code{.yaml}
      family: 36h11
      tags:                        # id, side (m), pose of the tag in the bundle's frame (bMt)
        - {id: 0, size: 0.04, pose: [0, 0, 0, 0, 0, 0]}
        - {id: 1, size: 0.04, pose: [0.05, 0, 0, 0, 0, 0]}
      \endcode
    The id offset is the default. Throws vpSelfCalibException (parseError) naming the part that is
    wrong (ioError for a bundle file that cannot be read), or as Options::check() does.
  */
  static Options parse(const std::string &spec);
  //! The description parse() reads back.
  static std::string toString(const Options &options);

  //! What detect() found in one image.
  struct Result {
    //! The grids: all rows x cols points found and their orientation settled. CHARUCO: 4 or more
    //! inner corners identified. APRILTAG: one or more of the tags looked for.
    bool found = false;
    std::string message; //!< why the board was not found (empty when found)
    //! The board's points, by increasing id (see the class), in pixels.
    std::vector<vpSelfCalibDataset::Observation> corners;
  };

  //! Throws as Options::check() does.
  explicit vpBoardDetector(const Options &options);

  //! Finds the board in a grey image. Throws vpSelfCalibException for an empty image only.
  Result detect(const vpImage<unsigned char> &I) const;

  const Options &getOptions() const { return m_options; }
  /*!
    The board's layout in its frame: id -> (x, y, z) in m (see the class; z = 0 but in a bundle
    of tags not in one plane). APRILTAG: one tag or a bundle; throws vpSelfCalibException for
    several single tags (their placement is not known) or any tag of the family.
  */
  std::map<int, vpColVector> getLayout() const;
  /*!
    The board as a yardstick: the two ends of its first row (ids id_offset and id_offset + cols - 1),
    their distance apart ((cols - 1) spacing; twice that for ASYMMETRIC_CIRCLES). CHARUCO: the ends
    of the first row of inner corners ((cols - 2) spacing). APRILTAG: the top edge of the first tag
    (of tag_ids or the bundle; tag 0 of the family when any tag is looked for): corners 0 and 1.
  */
  vpSelfCalibDataset::Yardstick getYardstick() const;

private:
  Options m_options;
};

#endif
