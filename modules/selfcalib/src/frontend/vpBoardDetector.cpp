/*
 * ViSP SelfCalib: calibration boards (chessboard, circle grids) found in an image, their points
 * identified by their place on the board. See the header for the conventions.
 */
#include <visp3/selfcalib/vpBoardDetector.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "vpMarkerBoards.h"

namespace
{
// The points of a grid, row by row: p[r * cols + c].
struct Grid {
  unsigned int rows = 0, cols = 0;
  std::vector<cv::Point2d> p;
  std::vector<double> area; //!< dots' areas (px^2), circle grids only
  const cv::Point2d &at(unsigned int r, unsigned int c) const { return p[r * cols + c]; }
};

// The same points labelled after a symmetry of the index grid: bit 0 reverses the rows, bit 1 the
// columns, bit 2 transposes (square grids only).
Grid relabel(const Grid &g, int t)
{
  Grid out;
  out.rows = t & 4 ? g.cols : g.rows;
  out.cols = t & 4 ? g.rows : g.cols;
  for (unsigned int r = 0; r < out.rows; ++r)
    for (unsigned int c = 0; c < out.cols; ++c) {
      unsigned int sr = t & 4 ? c : r, sc = t & 4 ? r : c;
      if (t & 1)
        sr = g.rows - 1 - sr;
      if (t & 2)
        sc = g.cols - 1 - sc;
      out.p.push_back(g.at(sr, sc));
      if (!g.area.empty())
        out.area.push_back(g.area[sr * g.cols + sc]);
    }
  return out;
}

// Board coordinates of point (r, c) in units of the spacing.
cv::Point2d boardPoint(vpBoardDetector::Type type, unsigned int r, unsigned int c)
{
  if (type == vpBoardDetector::ASYMMETRIC_CIRCLES)
    return cv::Point2d(2.0 * c + r % 2, r);
  return cv::Point2d(c, r);
}

// The homography from the board's layout (units of the spacing; `layout` receives it, point by
// point) to the grid's image points, least squares over all of them; false when OpenCV finds none.
bool fitBoardHomography(const Grid &g, vpBoardDetector::Type type, std::vector<cv::Point2d> &layout, cv::Matx33d &H)
{
  layout.clear();
  for (unsigned int r = 0; r < g.rows; ++r)
    for (unsigned int c = 0; c < g.cols; ++c)
      layout.push_back(boardPoint(type, r, c));
  const cv::Mat Hm = cv::findHomography(layout, g.p, 0);
  if (Hm.empty())
    return false;
  H = cv::Matx33d(Hm);
  return true;
}

// Smallest image distance between neighbours in a row or a column (the grid's pitch in pixels).
double smallestStep(const Grid &g)
{
  double d = HUGE_VAL;
  for (unsigned int r = 0; r < g.rows; ++r)
    for (unsigned int c = 0; c < g.cols; ++c) {
      if (c + 1 < g.cols)
        d = std::min(d, cv::norm(g.at(r, c + 1) - g.at(r, c)));
      if (r + 1 < g.rows)
        d = std::min(d, cv::norm(g.at(r + 1, c) - g.at(r, c)));
    }
  return d;
}

// The labellings of the found points that a camera can see: the board's layout maps onto them by a
// homography (within a quarter of the grid's pitch: lens distortion stays well below it, a wrong
// labelling of an asymmetric grid is off by a whole step), and they turn clockwise in the image
// from the first row to the first column (the board seen from its printed side).
std::vector<Grid> visibleLabellings(const Grid &found, vpBoardDetector::Type type)
{
  std::vector<Grid> out;
  const double tolerance = 0.25 * smallestStep(found);
  for (int t = 0; t < (found.rows == found.cols ? 8 : 4); ++t) {
    Grid g = relabel(found, t);
    const cv::Point2d x = g.at(0, g.cols - 1) - g.at(0, 0), y = g.at(g.rows - 1, 0) - g.at(0, 0);
    if (x.x * y.y - x.y * y.x <= 0)
      continue;
    std::vector<cv::Point2d> layout, mapped;
    cv::Matx33d H;
    if (!fitBoardHomography(g, type, layout, H))
      continue;
    cv::perspectiveTransform(layout, mapped, H);
    double error = 0;
    for (size_t k = 0; k < mapped.size(); ++k)
      error = std::max(error, cv::norm(mapped[k] - g.p[k]));
    if (error < tolerance)
      out.push_back(std::move(g));
  }
  return out;
}

// Mean grey level of the 3 x 3 pixels around p (those inside the image).
double greyAround(const cv::Mat &img, const cv::Point2d &p)
{
  const int u = static_cast<int>(std::lround(p.x)), v = static_cast<int>(std::lround(p.y));
  double sum = 0;
  int n = 0;
  for (int dv = -1; dv <= 1; ++dv)
    for (int du = -1; du <= 1; ++du)
      if (u + du >= 0 && v + dv >= 0 && u + du < img.cols && v + dv < img.rows) {
        sum += img.at<unsigned char>(v + dv, u + du);
        ++n;
      }
  return n ? sum / n : 0;
}

// Chessboard: how much darker the inner squares of the origin's colour (those whose centre
// (c + 0.5, r + 0.5) has r + c even, like the outer square at (-0.5, -0.5)) are than the others.
double originSquareDarkness(const cv::Mat &img, const Grid &g)
{
  double sum[2] = {0, 0};
  int n[2] = {0, 0};
  for (unsigned int r = 0; r + 1 < g.rows; ++r)
    for (unsigned int c = 0; c + 1 < g.cols; ++c) {
      const cv::Point2d centre = 0.25 * (g.at(r, c) + g.at(r, c + 1) + g.at(r + 1, c) + g.at(r + 1, c + 1));
      sum[(r + c) % 2] += greyAround(img, centre);
      ++n[(r + c) % 2];
    }
  return n[0] && n[1] ? sum[1] / n[1] - sum[0] / n[0] : 0;
}

// Modified circle grid: the size (square root of the area) of the dot at corner (r, c) relative to
// its two neighbours'.
double cornerDotRatio(const Grid &g, unsigned int r, unsigned int c)
{
  const unsigned int rn = r == 0 ? 1 : r - 1, cn = c == 0 ? 1 : c - 1;
  return 2 * std::sqrt(g.area[r * g.cols + c]) / (std::sqrt(g.area[rn * g.cols + c]) + std::sqrt(g.area[r * g.cols + cn]));
}

// The dot's centre refined to the grey-level centroid of the dot: weights (background - grey),
// clipped to [0, background - darkest], over a disc of radius `window` that holds no other dot; the
// background is the median grey of the disc's outer ring. Three passes, the disc re-centred on the
// last estimate; the centre is kept when the window is too small to hold the dot and a ring. area:
// the dot's area (px^2), the weights' sum over the depth (blur moves the grey, not its sum); left
// as it is when the centre is kept.
cv::Point2d refineDotCentre(const cv::Mat &img, cv::Point2d centre, double radius, double window, double &area)
{
  if (window < radius + 1.5)
    return centre;
  for (int pass = 0; pass < 3; ++pass) {
    const int u0 = static_cast<int>(std::floor(centre.x - window)), u1 = static_cast<int>(std::ceil(centre.x + window));
    const int v0 = static_cast<int>(std::floor(centre.y - window)), v1 = static_cast<int>(std::ceil(centre.y + window));
    if (u0 < 0 || v0 < 0 || u1 >= img.cols || v1 >= img.rows)
      return centre;
    std::vector<unsigned char> ring;
    unsigned char darkest = 255;
    for (int v = v0; v <= v1; ++v)
      for (int u = u0; u <= u1; ++u) {
        const double d = std::hypot(u - centre.x, v - centre.y);
        const unsigned char g = img.at<unsigned char>(v, u);
        if (d <= window) {
          darkest = std::min(darkest, g);
          if (d > radius + 1)
            ring.push_back(g);
        }
      }
    if (ring.size() < 8)
      return centre;
    std::nth_element(ring.begin(), ring.begin() + static_cast<long>(ring.size() / 2), ring.end());
    const double background = ring[ring.size() / 2], depth = background - darkest;
    if (depth <= 0)
      return centre;
    double sw = 0, su = 0, sv = 0;
    for (int v = v0; v <= v1; ++v)
      for (int u = u0; u <= u1; ++u)
        if (std::hypot(u - centre.x, v - centre.y) <= window) {
          const double w = std::min(depth, std::max(0.0, background - img.at<unsigned char>(v, u)));
          sw += w;
          su += w * u;
          sv += w * v;
        }
    if (sw <= 0)
      return centre;
    centre = cv::Point2d(su / sw, sv / sw);
    area = sw / depth;
  }
  return centre;
}

// The dots of a found circle grid: their sizes first from the blob detector (the keypoint nearest
// to each centre), then every centre and area refined on a window that stays clear of its
// neighbouring dots.
void measureDots(const cv::Mat &img, const std::vector<cv::KeyPoint> &keypoints, Grid &g)
{
  std::vector<double> size(g.p.size(), 0); // diameters
  for (size_t k = 0; k < g.p.size(); ++k) {
    double best = HUGE_VAL;
    for (const cv::KeyPoint &kp : keypoints) {
      const double d = cv::norm(cv::Point2d(kp.pt) - g.p[k]);
      if (d < best) {
        best = d;
        size[k] = kp.size;
      }
    }
  }
  g.area.assign(g.p.size(), 0);
  std::vector<cv::Point2d> refined(g.p.size());
  for (unsigned int r = 0; r < g.rows; ++r)
    for (unsigned int c = 0; c < g.cols; ++c) {
      const size_t k = r * g.cols + c;
      double window = size[k];
      g.area[k] = M_PI * 0.25 * size[k] * size[k];
      for (int dr = -1; dr <= 1; ++dr)
        for (int dc = -1; dc <= 1; ++dc) {
          const int nr = static_cast<int>(r) + dr, nc = static_cast<int>(c) + dc;
          if ((dr || dc) && nr >= 0 && nc >= 0 && nr < static_cast<int>(g.rows) && nc < static_cast<int>(g.cols)) {
            const size_t n = static_cast<size_t>(nr) * g.cols + static_cast<size_t>(nc);
            window = std::min(window, cv::norm(g.p[n] - g.p[k]) - 0.5 * size[n] - 2);
          }
        }
      refined[k] = refineDotCentre(img, g.p[k], 0.5 * size[k], window, g.area[k]);
    }
  g.p = refined;
}

/*
  The perspective image of a disc is an ellipse whose centre (what the centroid measures) is not
  the image of the disc's centre: off by about f R^2 / Z^2 times the tilt's sine (0.03 px for a 5 mm
  dot half a metre away, tilted 25 degrees; 0.15 px for the 11 mm origin dot of a modified grid).
  Corrected here from the board's homography H (board units -> px, fitted to the measured centres):
  each disc's radius R follows from its measured area and H's local area scale, the ellipse is the
  image conic H^-T C H^-1 of the circle C, and its centre's offset from H(centre) is removed. One
  pass: the offsets are small next to the errors they would make in H.
*/
void correctEccentricity(Grid &g, vpBoardDetector::Type type)
{
  std::vector<cv::Point2d> layout;
  cv::Matx33d H;
  if (!fitBoardHomography(g, type, layout, H))
    return;
  const cv::Matx33d Hinv = H.inv();
  for (size_t k = 0; k < layout.size(); ++k) {
    const double x = layout[k].x, y = layout[k].y;
    const cv::Vec3d m = H * cv::Vec3d(x, y, 1);
    // Jacobian of (u, v) = (m0, m1) / m2 at (x, y): its determinant is the area scale.
    const double j00 = (H(0, 0) * m[2] - m[0] * H(2, 0)) / (m[2] * m[2]), j01 = (H(0, 1) * m[2] - m[0] * H(2, 1)) / (m[2] * m[2]);
    const double j10 = (H(1, 0) * m[2] - m[1] * H(2, 0)) / (m[2] * m[2]), j11 = (H(1, 1) * m[2] - m[1] * H(2, 1)) / (m[2] * m[2]);
    const double scale = std::fabs(j00 * j11 - j01 * j10);
    if (!(scale > 0) || !(g.area[k] > 0))
      continue;
    const double R2 = g.area[k] / (M_PI * scale);
    const cv::Matx33d C(1, 0, -x, 0, 1, -y, -x, -y, x * x + y * y - R2);
    const cv::Matx33d E = Hinv.t() * C * Hinv;
    const double det = E(0, 0) * E(1, 1) - E(0, 1) * E(0, 1);
    if (!(std::fabs(det) > 0))
      continue;
    const cv::Point2d centre((E(0, 1) * E(1, 2) - E(1, 1) * E(0, 2)) / det, (E(0, 1) * E(0, 2) - E(0, 0) * E(1, 2)) / det);
    g.p[k] -= centre - cv::Point2d(m[0] / m[2], m[1] / m[2]);
  }
}

cv::Ptr<cv::SimpleBlobDetector> dotDetector(const cv::Mat &img)
{
  cv::SimpleBlobDetector::Params p;
  p.filterByColor = true;
  p.blobColor = 0; // dark dots
  p.minThreshold = 30;
  p.maxThreshold = 230;
  p.thresholdStep = 10;
  p.minRepeatability = 2;
  p.minDistBetweenBlobs = 2;
  p.filterByArea = true;
  p.minArea = 8;
  p.maxArea = static_cast<float>(img.total()) / 20;
  p.filterByCircularity = true;
  p.minCircularity = 0.6f; // a disc seen 60 degrees off its axis
  p.filterByInertia = true;
  p.minInertiaRatio = 0.05f;
  p.filterByConvexity = true;
  p.minConvexity = 0.85f;
  return cv::SimpleBlobDetector::create(p);
}

std::string boardName(const vpBoardDetector::Options &o)
{
  std::ostringstream s;
  s << o.rows << " x " << o.cols << " ";
  switch (o.type) {
  case vpBoardDetector::CHESSBOARD:
    s << "chessboard (inner corners)";
    break;
  case vpBoardDetector::CIRCLES:
    s << "circle grid";
    break;
  case vpBoardDetector::ASYMMETRIC_CIRCLES:
    s << "asymmetric circle grid";
    break;
  case vpBoardDetector::MODIFIED_CIRCLES:
    s << "modified circle grid";
    break;
  default:
    return vpBoardDetector::toString(o);
  }
  return s.str();
}

// The chessboard's corners in OpenCV's order (rows of cols corners), refined by cornerSubPix.
bool findChessboard(const cv::Mat &img, const vpBoardDetector::Options &o, Grid &g)
{
  const cv::Size size(static_cast<int>(o.cols), static_cast<int>(o.rows));
  std::vector<cv::Point2f> corners;
  // The sector-based detector first: tens of milliseconds, found or not; the classic one (seconds
  // on an image without the board but for its fast check) when it fails.
  if (!cv::findChessboardCornersSB(img, size, corners, cv::CALIB_CB_NORMALIZE_IMAGE) &&
      !cv::findChessboardCorners(img, size, corners,
                                 cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE | cv::CALIB_CB_FAST_CHECK))
    return false;
  if (corners.size() != o.rows * o.cols)
    return false;
  g.rows = o.rows;
  g.cols = o.cols;
  g.p.assign(corners.begin(), corners.end());
  // The search window must hold this corner's four squares and no other corner.
  const int half = std::max(2, std::min(20, static_cast<int>(0.4 * smallestStep(g))));
  cv::cornerSubPix(img, corners, cv::Size(half, half), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-4));
  g.p.assign(corners.begin(), corners.end());
  return true;
}

// A circle grid's dots in OpenCV's order; a symmetric grid is also looked for as cols x rows (then
// transposed back to rows of cols dots).
bool findCircleGrid(const cv::Mat &img, const vpBoardDetector::Options &o, Grid &g, size_t &blobs)
{
  const cv::Ptr<cv::SimpleBlobDetector> detector = dotDetector(img);
  std::vector<cv::KeyPoint> keypoints;
  detector->detect(img, keypoints);
  blobs = keypoints.size();
  const bool asymmetric = o.type == vpBoardDetector::ASYMMETRIC_CIRCLES;
  const int flags = asymmetric ? cv::CALIB_CB_ASYMMETRIC_GRID : cv::CALIB_CB_SYMMETRIC_GRID;
  for (int transposed = 0; transposed < (asymmetric || o.rows == o.cols ? 1 : 2); ++transposed) {
    const unsigned int rows = transposed ? o.cols : o.rows, cols = transposed ? o.rows : o.cols;
    const cv::Size size(static_cast<int>(cols), static_cast<int>(rows));
    std::vector<cv::Point2f> centres;
    if (!(cv::findCirclesGrid(img, size, centres, flags, detector) ||
          cv::findCirclesGrid(img, size, centres, flags | cv::CALIB_CB_CLUSTERING, detector)) ||
        centres.size() != o.rows * o.cols)
      continue;
    Grid found;
    found.rows = rows;
    found.cols = cols;
    found.p.assign(centres.begin(), centres.end());
    measureDots(img, keypoints, found);
    g = transposed ? relabel(found, 4) : found;
    return true;
  }
  return false;
}

bool wholeNumber(const std::string &s, unsigned int &value)
{
  if (s.empty() || s.size() > 6 || s.find_first_not_of("0123456789") != std::string::npos)
    return false;
  value = static_cast<unsigned int>(std::stoul(s));
  return true;
}
} // namespace

const char *vpBoardDetector::typeName(Type type)
{
  switch (type) {
  case CIRCLES:
    return "circles";
  case ASYMMETRIC_CIRCLES:
    return "acircles";
  case MODIFIED_CIRCLES:
    return "modified-circles";
  case CHARUCO:
    return "charuco";
  case APRILTAG:
    return "apriltag";
  case CHESSBOARD:
    break;
  }
  return "chessboard";
}

vpBoardDetector::Type vpBoardDetector::typeFromName(const std::string &name)
{
  for (Type t : {CHESSBOARD, CIRCLES, ASYMMETRIC_CIRCLES, MODIFIED_CIRCLES, CHARUCO, APRILTAG})
    if (name == typeName(t))
      return t;
  throw vpSelfCalibException(vpSelfCalibException::parseError,
                             "board type '" + name +
                                 "': use chessboard, circles, acircles, modified-circles, charuco, apriltag or "
                                 "apriltag-bundle");
}

bool vpBoardDetector::Options::isAmbiguous() const
{
  switch (type) {
  case CHESSBOARD: // a turn keeps the squares' colours when rows + cols is even
    return rows == cols || (rows + cols) % 2 == 0;
  case CIRCLES:
    return true;
  case ASYMMETRIC_CIRCLES: // the outline is symmetric under a half turn with an even number of rows
    return rows % 2 == 0;
  case MODIFIED_CIRCLES:
  case CHARUCO: // the markers tell every turn apart
  case APRILTAG:
    break;
  }
  return false;
}

int vpBoardDetector::Options::numIds() const
{
  if (type == CHARUCO || type == APRILTAG)
    return vpMarkerBoards::numIds(*this);
  return static_cast<int>(rows * cols);
}

void vpBoardDetector::Options::check() const
{
  if (type == CHARUCO || type == APRILTAG) {
    vpMarkerBoards::check(*this);
    return;
  }
  const unsigned int min_size = type == CHESSBOARD ? 2 : 3;
  if (rows < min_size || cols < min_size)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpBoardDetector: a " + boardName(*this) + " is too small: " +
                                   std::to_string(min_size) + " or more rows and columns are needed");
  if (!(spacing > 0) || !std::isfinite(spacing))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpBoardDetector: the spacing must be a positive number of m, got " +
                                   std::to_string(spacing));
  if (spacing > 10.0) // a printed board's pitch is centimetres; metres by the thousand are a pitch in mm
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpBoardDetector: a spacing of " + std::to_string(spacing) +
                                   " m is beyond the 10 m read: give it in m (e.g. 0.0236 for 23.6 mm)");
  if (id_offset < 0 || static_cast<long long>(id_offset) + numIds() > INT_MAX)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpBoardDetector: the id offset must be >= 0 and leave room for the board's " +
                                   std::to_string(rows * cols) + " ids below " + std::to_string(INT_MAX));
  if (isAmbiguous() && !assume_upright) {
    std::string hint;
    switch (type) {
    case CHESSBOARD:
      hint = "a chessboard with an even x odd count of inner corners (e.g. 9 x 6)";
      break;
    case ASYMMETRIC_CIRCLES:
      hint = "an asymmetric grid with an odd number of rows (OpenCV's pattern: acircles:11x4)";
      break;
    default:
      hint = "a modified circle grid (one larger dot at the origin)";
      break;
    }
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpBoardDetector: a " + boardName(*this) +
                                   " looks the same after a turn in its plane: which point is which cannot be told "
                                   "from the image, so its ids would not be the same in every view. Use " +
                                   hint + ", or accept the upright rule (assume_upright; ':upright' in a board "
                                          "description): ids then stay the same only while the board stays within 90 "
                                          "degrees of upright in the images");
  }
}

vpBoardDetector::Options vpBoardDetector::parse(const std::string &spec)
{
  const std::string where = "board '" + spec + "': ";
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(spec);
  while (std::getline(in, part, ':'))
    parts.push_back(part);
  if (!spec.empty() && spec.back() == ':')
    parts.push_back("");
  if (!parts.empty() && (parts[0] == "charuco" || parts[0] == "apriltag" || parts[0] == "apriltag-bundle")) {
    const Options o = vpMarkerBoards::parse(parts, where);
    try {
      o.check();
    } catch (const vpSelfCalibException &e) {
      throw vpSelfCalibException(vpSelfCalibException::badValue, where + e.getStringMessage());
    }
    return o;
  }
  if (parts.size() < 3 || parts.size() > 4)
    throw vpSelfCalibException(vpSelfCalibException::parseError,
                               where + "expected TYPE:ROWSxCOLS:SPACING[:upright], e.g. chessboard:9x6:0.0236 (or "
                                       "charuco:COLSxROWS:SQUARE:MARKER:DICT, apriltag:FAMILY:SIZE[:ID,...], "
                                       "apriltag-bundle:FILE.yaml)");
  Options o;
  try {
    o.type = typeFromName(parts[0]);
  } catch (const vpSelfCalibException &e) {
    throw vpSelfCalibException(vpSelfCalibException::parseError, where + e.getStringMessage());
  }
  const size_t x = parts[1].find('x');
  if (x == std::string::npos || !wholeNumber(parts[1].substr(0, x), o.rows) ||
      !wholeNumber(parts[1].substr(x + 1), o.cols))
    throw vpSelfCalibException(vpSelfCalibException::parseError,
                               where + "expected ROWSxCOLS as two whole numbers (e.g. 9x6), got '" + parts[1] + "'");
  const std::string &s = parts[2];
  char *end = nullptr;
  o.spacing = s.empty() || s.find_first_not_of("0123456789.eE+-") != std::string::npos
                  ? 0
                  : std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size() || !(o.spacing > 0) || !std::isfinite(o.spacing))
    throw vpSelfCalibException(vpSelfCalibException::parseError,
                               where + "expected the spacing in m as a positive number (e.g. 0.0236), got '" + s +
                                   "'");
  if (parts.size() == 4) {
    if (parts[3] != "upright")
      throw vpSelfCalibException(vpSelfCalibException::parseError,
                                 where + "unknown option '" + parts[3] + "' (the only one is 'upright')");
    o.assume_upright = true;
  }
  try {
    o.check();
  } catch (const vpSelfCalibException &e) {
    throw vpSelfCalibException(vpSelfCalibException::badValue, where + e.getStringMessage());
  }
  return o;
}

std::string vpBoardDetector::toString(const Options &o)
{
  if (o.type == CHARUCO || o.type == APRILTAG)
    return vpMarkerBoards::toString(o);
  // The shortest spacing that reads back as the same double.
  std::string spacing;
  for (int digits = 6; digits <= 17; ++digits) {
    std::ostringstream s;
    s.precision(digits);
    s << o.spacing;
    spacing = s.str();
    if (std::strtod(spacing.c_str(), nullptr) == o.spacing)
      break;
  }
  return std::string(typeName(o.type)) + ":" + std::to_string(o.rows) + "x" + std::to_string(o.cols) + ":" + spacing +
         (o.assume_upright ? ":upright" : "");
}

vpBoardDetector::vpBoardDetector(const Options &options) : m_options(options) { options.check(); }

vpBoardDetector::Result vpBoardDetector::detect(const vpImage<unsigned char> &I) const
{
  if (I.getSize() == 0)
    throw vpSelfCalibException(vpSelfCalibException::dimensionError, "vpBoardDetector: empty image");
  const Options &o = m_options;
  // OpenCV reads the ViSP bitmap in place (row-major 8-bit grey, the same layout).
  const cv::Mat img(static_cast<int>(I.getHeight()), static_cast<int>(I.getWidth()), CV_8UC1,
                    const_cast<unsigned char *>(I.bitmap));
  if (o.type == CHARUCO || o.type == APRILTAG)
    return vpMarkerBoards::detect(img, o);
  Result res;
  Grid found;
  if (o.type == CHESSBOARD) {
    if (!findChessboard(img, o, found)) {
      res.message = "no " + boardName(o) + " found";
      return res;
    }
  } else {
    size_t blobs = 0;
    if (!findCircleGrid(img, o, found, blobs)) {
      res.message = "no " + boardName(o) + " found (" + std::to_string(blobs) + " dots detected)";
      return res;
    }
  }

  std::vector<Grid> candidates = visibleLabellings(found, o.type);
  if (candidates.empty()) {
    res.message = "the points found do not fit a " + boardName(o) + " seen from its printed side";
    return res;
  }
  if (o.type == CHESSBOARD) {
    // The origin's outer corner square is black: its colour class is the darker one (by a clear
    // margin: 20 grey levels). On a board that a turn maps onto itself (assume_upright) the colours
    // may not tell the labellings apart: they only narrow them down when they can.
    std::vector<Grid> kept;
    for (Grid &g : candidates)
      if (originSquareDarkness(img, g) > 20)
        kept.push_back(g);
    if (kept.empty() && !o.isAmbiguous()) {
      res.message = "the chessboard's black and white squares cannot be told apart";
      return res;
    }
    if (!kept.empty())
      candidates.swap(kept);
  } else if (o.type == MODIFIED_CIRCLES) {
    // The larger dot: the corner dot largest relative to its neighbours, by a clear margin (1.25
    // over its neighbours and over the next corner).
    double ratio[4];
    for (int k = 0; k < 4; ++k)
      ratio[k] = cornerDotRatio(found, k & 1 ? found.rows - 1 : 0, k & 2 ? found.cols - 1 : 0);
    const int best = static_cast<int>(std::max_element(ratio, ratio + 4) - ratio);
    double second = 0;
    for (int k = 0; k < 4; ++k)
      if (k != best)
        second = std::max(second, ratio[k]);
    if (ratio[best] < 1.25 || ratio[best] < 1.25 * second) {
      res.message = "no dot at a corner of the grid is clearly larger than the others (the origin)";
      return res;
    }
    const cv::Point2d origin = found.at(best & 1 ? found.rows - 1 : 0, best & 2 ? found.cols - 1 : 0);
    std::vector<Grid> kept;
    for (Grid &g : candidates)
      if (g.at(0, 0) == origin)
        kept.push_back(std::move(g));
    if (kept.empty()) {
      res.message = "the larger dot is at a corner where the grid has " + std::to_string(o.cols) + " rows of " +
                    std::to_string(o.rows) + " dots: swap rows and columns";
      return res;
    }
    candidates.swap(kept);
  }
  if (candidates.size() > 1) {
    // Only boards that check() let through with assume_upright: the first row closest to +u.
    std::stable_sort(candidates.begin(), candidates.end(), [](const Grid &a, const Grid &b) {
      const cv::Point2d da = a.at(0, a.cols - 1) - a.at(0, 0), db = b.at(0, b.cols - 1) - b.at(0, 0);
      return da.x / cv::norm(da) > db.x / cv::norm(db);
    });
  }
  Grid &g = candidates.front();
  if (o.type != CHESSBOARD)
    correctEccentricity(g, o.type);
  for (unsigned int k = 0; k < g.p.size(); ++k) {
    vpSelfCalibDataset::Observation ob;
    ob.id = o.id_offset + static_cast<int>(k);
    ob.ip = vpImagePoint(g.p[k].y, g.p[k].x);
    res.corners.push_back(ob);
  }
  res.found = true;
  return res;
}

std::map<int, vpColVector> vpBoardDetector::getLayout() const
{
  if (m_options.type == CHARUCO || m_options.type == APRILTAG)
    return vpMarkerBoards::layout(m_options);
  std::map<int, vpColVector> layout;
  for (unsigned int r = 0; r < m_options.rows; ++r)
    for (unsigned int c = 0; c < m_options.cols; ++c) {
      const cv::Point2d b = boardPoint(m_options.type, r, c) * m_options.spacing;
      vpColVector X(3, 0.0);
      X[0] = b.x;
      X[1] = b.y;
      layout[m_options.id_offset + static_cast<int>(r * m_options.cols + c)] = X;
    }
  return layout;
}

vpSelfCalibDataset::Yardstick vpBoardDetector::getYardstick() const
{
  if (m_options.type == CHARUCO || m_options.type == APRILTAG)
    return vpMarkerBoards::yardstick(m_options);
  vpSelfCalibDataset::Yardstick y;
  y.id_a = m_options.id_offset;
  y.id_b = m_options.id_offset + static_cast<int>(m_options.cols) - 1;
  y.length = cv::norm(boardPoint(m_options.type, 0, m_options.cols - 1)) * m_options.spacing;
  return y;
}
