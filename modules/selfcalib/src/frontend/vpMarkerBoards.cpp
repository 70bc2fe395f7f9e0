/*
 * ViSP SelfCalib: ChArUco boards and AprilTags for vpBoardDetector (OpenCV aruco). See the header
 * of vpBoardDetector for the frames and ids.
 */
#include "vpMarkerBoards.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>

#include <opencv2/aruco/charuco.hpp>
#include <opencv2/imgproc.hpp>
#include <yaml-cpp/yaml.h>

#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include "../core/vpSelfCalibFiles.h" // readTextFileBounded
#include "../core/vpSelfCalibMarkers.h"

namespace
{
using Options = vpBoardDetector::Options;

vpSelfCalibException badValue(const std::string &what)
{
  return vpSelfCalibException(vpSelfCalibException::badValue, "vpBoardDetector: " + what);
}

bool positiveNumber(const std::string &s, double &value)
{
  char *end = nullptr;
  value = s.empty() || s.find_first_not_of("0123456789.eE+-") != std::string::npos ? 0 : std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && value > 0 && std::isfinite(value);
}

bool wholeNumber(const std::string &s, int &value)
{
  if (s.empty() || s.size() > 6 || s.find_first_not_of("0123456789") != std::string::npos)
    return false;
  value = std::atoi(s.c_str());
  return true;
}

std::string shortest(double v)
{
  std::string out;
  for (int digits = 6; digits <= 17; ++digits) {
    std::ostringstream s;
    s.precision(digits);
    s << v;
    out = s.str();
    if (std::strtod(out.c_str(), nullptr) == v)
      break;
  }
  return out;
}

int tagDictionary(const Options &o) { return vpSelfCalib::arucoDictionary("DICT_APRILTAG_" + o.dictionary); }

std::string idList(const std::vector<int> &ids)
{
  std::string s;
  for (int id : ids)
    s += (s.empty() ? "" : ",") + std::to_string(id);
  return s;
}

/*
  The largest side of a square, a marker or a tag read (m): a printed target on a robot arm's scene is
  a few decimetres; a side in metres by the thousand is a size given in mm (48 for 0.048).
*/
constexpr double kMaxSide = 10.0;

void checkSide(const std::string &what, double side)
{
  if (side > kMaxSide)
    throw badValue(what + " of " + shortest(side) + " m is beyond the " + shortest(kMaxSide) +
                   " m read: give it in m (e.g. 0.048 for 48 mm)");
}

/*
  Two tags of a bundle whose centres are closer than a quarter of their two sides together overlap
  (squares that do not overlap hold disjoint disks of half their side, so in one plane their centres
  are at least half the sum of the sides apart; the faces of a cube are 0.71 side apart): one region
  of the target cannot carry both.
*/
void checkOverlap(const std::vector<Options::BundleTag> &bundle)
{
  for (size_t i = 0; i < bundle.size(); ++i)
    for (size_t j = i + 1; j < bundle.size(); ++j) {
      const vpPoseVector &a = bundle[i].bMt, &b = bundle[j].bMt;
      const double d = std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
      if (d < 0.25 * (bundle[i].size + bundle[j].size))
        throw badValue("tags " + std::to_string(bundle[i].id) + " and " + std::to_string(bundle[j].id) +
                       " of the bundle overlap: their centres are " + shortest(d) + " m apart, less than " +
                       shortest(0.25 * (bundle[i].size + bundle[j].size)) +
                       " m for sides of " + shortest(bundle[i].size) + " and " + shortest(bundle[j].size) +
                       " m; check their poses (m, in the bundle's frame)");
    }
}

void checkCharuco(const Options &o)
{
  if (o.rows < 3 || o.cols < 3)
    throw badValue("a ChArUco board of " + std::to_string(o.cols) + " x " + std::to_string(o.rows) +
                   " squares is too small: 3 or more squares each way are needed");
  if (!(o.spacing > 0) || !std::isfinite(o.spacing) || !(o.marker_size > 0) || !std::isfinite(o.marker_size))
    throw badValue("a ChArUco board's square and marker sides must be positive numbers of m, got " +
                   shortest(o.spacing) + " and " + shortest(o.marker_size));
  checkSide("a ChArUco board's square", o.spacing);
  if (o.marker_size >= o.spacing)
    throw badValue("a ChArUco board's markers (" + shortest(o.marker_size) + " m) must be smaller than its squares (" +
                   shortest(o.spacing) + " m)");
  const int d = vpSelfCalib::arucoDictionary(o.dictionary);
  if (d < 0)
    throw badValue("no OpenCV dictionary is called '" + o.dictionary + "': use one of " +
                   vpSelfCalib::arucoDictionaryNames());
  const unsigned int markers = o.rows * o.cols / 2;
  if (static_cast<int>(markers) > vpSelfCalib::arucoDictionarySize(d))
    throw badValue("a ChArUco board of " + std::to_string(o.cols) + " x " + std::to_string(o.rows) + " squares needs " +
                   std::to_string(markers) + " markers, " + o.dictionary + " has " +
                   std::to_string(vpSelfCalib::arucoDictionarySize(d)));
}

void checkTags(const Options &o)
{
  const int d = tagDictionary(o);
  if (d < 0)
    throw badValue("no AprilTag family '" + o.dictionary + "' (OpenCV's aruco has " +
                   vpSelfCalib::aprilTagFamilyNames() + ")");
  const int size = vpSelfCalib::arucoDictionarySize(d);
  if (o.bundle.empty() && (!(o.marker_size > 0) || !std::isfinite(o.marker_size)))
    throw badValue("the tags' side must be a positive number of m, got " + shortest(o.marker_size));
  if (o.bundle.empty())
    checkSide("a tag side", o.marker_size);
  std::set<int> seen;
  for (const Options::BundleTag &t : o.bundle) {
    if (!(t.size > 0) || !std::isfinite(t.size))
      throw badValue("tag " + std::to_string(t.id) + " of the bundle: its size must be a positive number of m, got " +
                     shortest(t.size));
    for (unsigned int k = 0; k < 6; ++k)
      if (!std::isfinite(t.bMt[k]))
        throw badValue("tag " + std::to_string(t.id) + " of the bundle: its pose is not finite");
    checkSide("tag " + std::to_string(t.id) + " of the bundle: a side", t.size);
    if (!seen.insert(t.id).second)
      throw badValue("tag " + std::to_string(t.id) + " is twice in the bundle");
  }
  checkOverlap(o.bundle);
  for (int id : o.tag_ids)
    if (id < 0 || id >= size)
      throw badValue("tag id " + std::to_string(id) + " is not in family " + o.dictionary + " (ids 0 to " +
                     std::to_string(size - 1) + ")");
  for (const Options::BundleTag &t : o.bundle)
    if (t.id < 0 || t.id >= size)
      throw badValue("tag id " + std::to_string(t.id) + " is not in family " + o.dictionary + " (ids 0 to " +
                     std::to_string(size - 1) + ")");
}

// A tag's side: its size in the bundle, else the tags' side.
double tagSize(const Options &o, int id)
{
  for (const Options::BundleTag &t : o.bundle)
    if (t.id == id)
      return t.size;
  return o.marker_size;
}

/*
  The grey-level crossing of an edge: along the normal n, from `r` px before p to `r` px after it,
  the point where the bilinearly interpolated grey crosses the mean of the two ends' levels (dark to
  bright or bright to dark). False when the two levels are less than 20 grey levels apart (the edge
  hidden or off the image there).
*/
bool edgeCrossing(const cv::Mat &img, const cv::Point2d &p, const cv::Point2d &n, double r, cv::Point2d &edge,
                  double &contrast)
{
  const double step = 0.25;
  const int m = static_cast<int>(std::ceil(2 * r / step));
  std::vector<double> g(static_cast<size_t>(m) + 1);
  for (int i = 0; i <= m; ++i) {
    const cv::Point2d q = p + (-r + i * step) * n;
    if (q.x < 0 || q.y < 0 || q.x > img.cols - 2 || q.y > img.rows - 2)
      return false;
    const int u = static_cast<int>(q.x), v = static_cast<int>(q.y);
    const double a = q.x - u, b = q.y - v;
    g[static_cast<size_t>(i)] =
        (1 - b) * ((1 - a) * img.at<unsigned char>(v, u) + a * img.at<unsigned char>(v, u + 1)) +
        b * ((1 - a) * img.at<unsigned char>(v + 1, u) + a * img.at<unsigned char>(v + 1, u + 1));
  }
  const double first = 0.5 * (g[0] + g[1]), last = 0.5 * (g[g.size() - 1] + g[g.size() - 2]);
  contrast = std::fabs(last - first);
  if (contrast < 20)
    return false;
  const double mid = 0.5 * (first + last), sign = last > first ? 1 : -1;
  for (size_t i = 0; i + 1 < g.size(); ++i)
    if (sign * (g[i] - mid) < 0 && sign * (g[i + 1] - mid) >= 0) {
      const double s = -r + step * (i + (mid - g[i]) / (g[i + 1] - g[i]));
      edge = p + s * n;
      return true;
    }
  return false;
}

/*
  The line a u + b v + c = 0 fitted to an edge's samples (cv::fitLine, Huber), of `tried` profiles.
  The samples whose contrast is below 0.7 of the edge's median are left out (where something lies
  over the edge: an occluder's border is an edge too, of another contrast); false when fewer than
  70 % of the profiles tried, or fewer than 4, are left: the edge is not seen well enough.
*/
bool fitEdgeLine(const std::vector<cv::Point2f> &samples, const std::vector<double> &contrast, size_t tried,
                 cv::Vec3d &line)
{
  if (samples.size() < 4)
    return false;
  std::vector<double> sorted = contrast;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(sorted.size() / 2), sorted.end());
  const double median = sorted[sorted.size() / 2];
  std::vector<cv::Point2f> edge;
  for (size_t k = 0; k < samples.size(); ++k)
    if (contrast[k] >= 0.7 * median)
      edge.push_back(samples[k]);
  if (edge.size() < 4 || edge.size() < 0.7 * tried)
    return false;
  cv::Vec4f l;
  cv::fitLine(edge, l, cv::DIST_HUBER, 0, 0.01, 0.01);
  line = cv::Vec3d(l[1], -l[0], l[0] * l[3] - l[1] * l[2]);
  return true;
}

// The intersection of two lines; false when they are parallel.
bool intersect(const cv::Vec3d &a, const cv::Vec3d &b, cv::Point2f &p)
{
  const cv::Vec3d x = a.cross(b);
  if (std::fabs(x[2]) < 1e-12)
    return false;
  p = cv::Point2f(static_cast<float>(x[0] / x[2]), static_cast<float>(x[1] / x[2]));
  return true;
}

/*
  A tag's four corners refined (two passes): each side's edge sampled at every pixel of its middle
  80 % (edgeCrossing, within 0.45 of a cell of the side: the tag's inner bits stay out of reach),
  a line fitted to the samples (fitEdgeLine), neighbouring sides' lines intersected. False when a
  side is not seen well enough (partly hidden, or off the image): such a tag is left out.
*/
bool refineTag(const cv::Mat &img, int cells, std::vector<cv::Point2f> &corners)
{
  for (int pass = 0; pass < 2; ++pass) {
    cv::Point2d centre(0, 0);
    for (const cv::Point2f &c : corners)
      centre += 0.25 * cv::Point2d(c);
    cv::Vec3d lines[4];
    for (int k = 0; k < 4; ++k) {
      const cv::Point2d a = corners[k], b = corners[(k + 1) % 4];
      const double len = cv::norm(b - a);
      const cv::Point2d dir = (b - a) / len;
      cv::Point2d n(dir.y, -dir.x);
      if (n.dot(0.5 * (a + b) - centre) < 0)
        n = -n;
      const double r = std::max(1.5, std::min(4.0, 0.45 * len / cells));
      std::vector<cv::Point2f> edge;
      std::vector<double> contrast;
      const int samples = std::max(4, static_cast<int>(0.8 * len));
      for (int i = 0; i < samples; ++i) {
        cv::Point2d e;
        double c = 0;
        if (edgeCrossing(img, a + (0.1 + 0.8 * (i + 0.5) / samples) * (b - a), n, r, e, c)) {
          edge.emplace_back(e);
          contrast.push_back(c);
        }
      }
      if (!fitEdgeLine(edge, contrast, static_cast<size_t>(samples), lines[k]))
        return false;
    }
    for (int k = 0; k < 4; ++k)
      if (!intersect(lines[(k + 3) % 4], lines[k], corners[k]))
        return false;
  }
  return true;
}

void addPoint(vpBoardDetector::Result &res, int id, const cv::Point2f &p)
{
  vpSelfCalibDataset::Observation ob;
  ob.id = id;
  ob.ip = vpImagePoint(p.y, p.x);
  res.corners.push_back(ob);
}

/*
  The ChArUco corners refined, each on its own: first by cornerSubPix on a window that holds the
  corner's four squares but none of the markers in its two white squares (0.8 of the gap between
  the markers and the squares' sides, (square - marker) / 2, in pixels; 2 px at least), then by the
  two lines through it: each square side that meets at the corner is sampled across (edgeCrossing,
  within 0.45 of that gap: the markers stay out of reach) from 0.2 to 0.8 of a square on both sides
  of the corner, a line fitted to each of the two sides' samples, the lines intersected. The board's
  homography (fitted to the corners found, RANSAC) places the samples. A corner whose lines cannot
  be fitted (hidden, at the image's border) keeps cornerSubPix's position. On rendered boards (blur
  0.7 px, noise 2 grey levels): OpenCV 4.6's refinement in interpolateCornersCharuco leaves the
  corners half a pixel off along u and v, cornerSubPix on the small window that the markers leave
  is within 0.05 px RMS (0.15 px at most), the lines within 0.02 px RMS (0.06 px at most; what is
  left is mostly the markers' own edges, 1.5 to 2 px beyond the sampled profiles on tilted views).
*/
void refineCharucoCorners(const cv::Mat &img, const Options &o, const std::vector<int> &ids,
                          std::vector<cv::Point2f> &corners)
{
  const int n = static_cast<int>(o.cols) - 1;
  std::vector<cv::Point2f> board;
  for (int id : ids)
    board.emplace_back(static_cast<float>(id % n + 1), static_cast<float>(id / n + 1));
  cv::Matx33d H;
  auto map = [&H](double x, double y) {
    const cv::Vec3d m = H * cv::Vec3d(x, y, 1);
    return cv::Point2d(m[0] / m[2], m[1] / m[2]);
  };
  // The corner's pitch in the image (px per square), from the homography.
  auto pitch = [&map](double x, double y) {
    return 0.5 * (cv::norm(map(x + 0.5, y) - map(x - 0.5, y)) + cv::norm(map(x, y + 0.5) - map(x, y - 0.5)));
  };
  const double gap = (o.spacing - o.marker_size) / (2 * o.spacing);
  for (int pass = 0; pass < 2; ++pass) {
    // The samples must straddle the edges: the homography of the corners as refined so far.
    const cv::Mat Hm = cv::findHomography(board, corners, cv::RANSAC, 2.0);
    if (Hm.empty())
      return;
    H = cv::Matx33d(Hm);
    for (size_t k = 0; k < corners.size(); ++k) {
      const double x = board[k].x, y = board[k].y, px = pitch(x, y);
      if (pass == 0) {
        const int half = std::max(2, static_cast<int>(0.8 * gap * px));
        std::vector<cv::Point2f> one(1, corners[k]);
        cv::cornerSubPix(img, one, cv::Size(half, half), cv::Size(-1, -1),
                         cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-4));
        corners[k] = one[0];
        continue;
      }
      const double r = std::max(1.5, std::min(4.0, 0.45 * gap * px));
      cv::Vec3d lines[2];
      bool fitted = true;
      for (int axis = 0; axis < 2 && fitted; ++axis) {
        std::vector<cv::Point2f> edge;
        std::vector<double> contrast;
        const int samples = std::max(4, static_cast<int>(0.6 * px));
        for (int side = -1; side <= 1; side += 2)
          for (int i = 0; i < samples; ++i) {
            const double t = side * (0.2 + 0.6 * (i + 0.5) / samples);
            const cv::Point2d p = axis == 0 ? map(x + t, y) : map(x, y + t);
            const cv::Point2d d = axis == 0 ? map(x + t + 0.01, y) - p : map(x, y + t + 0.01) - p;
            cv::Point2d e;
            double c = 0;
            if (edgeCrossing(img, p, cv::Point2d(-d.y, d.x) / cv::norm(d), r, e, c)) {
              edge.emplace_back(e);
              contrast.push_back(c);
            }
          }
        fitted = fitEdgeLine(edge, contrast, 2 * static_cast<size_t>(samples), lines[axis]);
      }
      cv::Point2f p;
      if (fitted && intersect(lines[0], lines[1], p) && cv::norm(p - corners[k]) < 1)
        corners[k] = p;
    }
  }
}

vpBoardDetector::Result detectCharuco(const cv::Mat &img, const Options &o)
{
  vpBoardDetector::Result res;
  const vpSelfCalib::vpCharucoPrint print(static_cast<int>(o.cols), static_cast<int>(o.rows), o.spacing, o.marker_size,
                                          vpSelfCalib::arucoDictionary(o.dictionary));
  std::vector<std::vector<cv::Point2f>> markers;
  std::vector<int> ids;
  cv::aruco::detectMarkers(img, print.board()->dictionary, markers, ids);
  std::vector<cv::Point2f> corners;
  std::vector<int> corner_ids;
  if (!ids.empty())
    cv::aruco::interpolateCornersCharuco(markers, ids, img, print.board(), corners, corner_ids);
  if (corners.size() < 4) {
    res.message = "no ChArUco board " + std::to_string(o.cols) + " x " + std::to_string(o.rows) + " of " +
                  o.dictionary + " found: " + std::to_string(ids.size()) + " markers of the dictionary and " +
                  std::to_string(corners.size()) + " of its inner corners seen, 4 or more corners are needed";
    return res;
  }
  refineCharucoCorners(img, o, corner_ids, corners);
  std::vector<size_t> order(corners.size());
  for (size_t k = 0; k < order.size(); ++k)
    order[k] = k;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return corner_ids[a] < corner_ids[b]; });
  for (size_t k : order)
    addPoint(res, o.id_offset + corner_ids[k], corners[k]);
  res.found = true;
  return res;
}

// The AprilTags of the other families OpenCV has, when none of `family` is in the image: "tags of
// family 25h9 (ids 3, 4)", or empty.
std::string otherFamilies(const cv::Mat &img, const std::string &family)
{
  std::string s;
  for (const char *f : {"36h11", "36h10", "25h9", "16h5"}) {
    if (family == f)
      continue;
    std::vector<std::vector<cv::Point2f>> quads;
    std::vector<int> ids;
    cv::aruco::detectMarkers(img, cv::aruco::getPredefinedDictionary(vpSelfCalib::arucoDictionary(
                                      std::string("DICT_APRILTAG_") + f)),
                             quads, ids);
    std::sort(ids.begin(), ids.end());
    if (!ids.empty())
      s += (s.empty() ? "" : "; ") + std::string("tags of family ") + f + " (ids " + idList(ids) + ")";
  }
  return s;
}

vpBoardDetector::Result detectTags(const cv::Mat &img, const Options &o)
{
  vpBoardDetector::Result res;
  const cv::Ptr<cv::aruco::Dictionary> dict = cv::aruco::getPredefinedDictionary(tagDictionary(o));
  std::vector<std::vector<cv::Point2f>> quads;
  std::vector<int> ids;
  cv::aruco::detectMarkers(img, dict, quads, ids);
  std::vector<std::pair<int, std::vector<cv::Point2f>>> kept;
  std::vector<int> others;
  for (size_t k = 0; k < ids.size(); ++k) {
    if (!o.tag_ids.empty() && std::find(o.tag_ids.begin(), o.tag_ids.end(), ids[k]) == o.tag_ids.end()) {
      others.push_back(ids[k]);
      continue;
    }
    if (refineTag(img, dict->markerSize + 2, quads[k]))
      kept.emplace_back(ids[k], quads[k]);
  }
  if (kept.empty()) {
    std::string seen;
    if (!others.empty())
      seen = "tags " + idList(others) + " of that family are in the image";
    else if (ids.empty())
      seen = otherFamilies(img, o.dictionary);
    else
      seen = "the tags found had edges too faint or too close to the image's border to be refined";
    res.message = "no AprilTag " + o.dictionary + (o.tag_ids.empty() ? "" : " with id " + idList(o.tag_ids)) +
                  " found" + (seen.empty() ? std::string() : " (" + seen + ")");
    return res;
  }
  std::sort(kept.begin(), kept.end(),
            [](const std::pair<int, std::vector<cv::Point2f>> &a, const std::pair<int, std::vector<cv::Point2f>> &b) {
              return a.first < b.first;
            });
  for (size_t k = 0; k < kept.size(); ++k) {
    if (k > 0 && kept[k].first == kept[k - 1].first) {
      // The same tag twice: which is which cannot be told; neither is kept.
      res.corners.resize(res.corners.size() - 4);
      continue;
    }
    for (int c = 0; c < 4; ++c)
      addPoint(res, o.id_offset + 4 * kept[k].first + c, kept[k].second[static_cast<size_t>(c)]);
  }
  res.found = !res.corners.empty();
  if (!res.found)
    res.message = "every AprilTag " + o.dictionary + " found is in the image twice";
  return res;
}

/*
  A bundle file's scalar as T, or the error naming the key, the tag and what was expected (yaml-cpp's
  own text is "bad conversion").
*/
template <typename T>
T bundleValue(const YAML::Node &n, const std::string &where, const std::string &key, const std::string &expected)
{
  try {
    return n.as<T>();
  } catch (const YAML::BadConversion &) {
    const std::string got = n.IsScalar() ? "'" + n.Scalar() + "'" : n.IsSequence() ? "a list" : "a map";
    throw vpSelfCalibException(vpSelfCalibException::parseError, where + key + ": expected " + expected + ", got " +
                                                                     got + " (line " + std::to_string(n.Mark().line + 1) +
                                                                     ")");
  }
}

// parse(): the YAML bundle file.
Options readBundle(const std::string &file, const std::string &where)
{
  // Read as every input text is (a directory, a device, a stream without end or a binary file is
  // refused with the reason), then parsed.
  std::string text;
  try {
    text = vpSelfCalib::readTextFileBounded(file, "tag bundle", size_t(1) << 20);
  } catch (const vpSelfCalibException &e) {
    throw vpSelfCalibException(vpSelfCalibException::ioError, where + e.getStringMessage());
  }
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception &e) {
    throw vpSelfCalibException(vpSelfCalibException::parseError, where + file + ": " + e.what());
  }
  Options o;
  o.type = vpBoardDetector::APRILTAG;
  o.bundle_file = file;
  try {
    if (!root["family"] || !root["tags"] || !root["tags"].IsSequence() || root["tags"].size() == 0)
      throw vpSelfCalibException(vpSelfCalibException::parseError,
                                 where + file + ": expected 'family' and a list 'tags' of {id, size, pose}");
    const std::string family = bundleValue<std::string>(root["family"], where + file + ": ", "family",
                                                        "an AprilTag family such as 36h11");
    o.dictionary = vpSelfCalib::aprilTagFamily(family);
    if (o.dictionary.empty())
      o.dictionary = family; // check() names it
    for (size_t k = 0; k < root["tags"].size(); ++k) {
      const YAML::Node t = root["tags"][k];
      if (!t["id"] || !t["size"] || !t["pose"] || !t["pose"].IsSequence() || t["pose"].size() != 6)
        throw vpSelfCalibException(vpSelfCalibException::parseError,
                                   where + file + ": tag " + std::to_string(k + 1) +
                                       ": expected {id: N, size: M, pose: [tx, ty, tz, tux, tuy, tuz]}");
      Options::BundleTag b;
      const std::string tag = where + file + ": tag " + std::to_string(k + 1) + ": ";
      b.id = bundleValue<int>(t["id"], tag, "id", "the tag's id as a whole number");
      b.size = bundleValue<double>(t["size"], tag, "size", "the tag's side in m as a number (e.g. 0.04)");
      for (unsigned int i = 0; i < 6; ++i)
        b.bMt[i] = bundleValue<double>(t["pose"][i], tag, "pose[" + std::to_string(i) + "]",
                                       "a number (tx, ty, tz in m, then theta u in rad)");
      o.bundle.push_back(b);
      o.tag_ids.push_back(b.id);
    }
  } catch (const YAML::Exception &e) {
    throw vpSelfCalibException(vpSelfCalibException::parseError, where + file + ": " + e.what());
  }
  return o;
}

Options parseCharuco(const std::vector<std::string> &parts, const std::string &where)
{
  if (parts.size() != 5)
    throw vpSelfCalibException(vpSelfCalibException::parseError,
                               where + "expected charuco:COLSxROWS:SQUARE:MARKER:DICT, e.g. "
                                       "charuco:5x7:0.034:0.028:DICT_6X6_250");
  Options o;
  o.type = vpBoardDetector::CHARUCO;
  const size_t x = parts[1].find('x');
  int cols = 0, rows = 0;
  if (x == std::string::npos || !wholeNumber(parts[1].substr(0, x), cols) || !wholeNumber(parts[1].substr(x + 1), rows))
    throw vpSelfCalibException(vpSelfCalibException::parseError,
                               where + "expected COLSxROWS squares as two whole numbers (e.g. 5x7), got '" + parts[1] +
                                   "'");
  o.cols = static_cast<unsigned int>(cols);
  o.rows = static_cast<unsigned int>(rows);
  if (!positiveNumber(parts[2], o.spacing))
    throw vpSelfCalibException(vpSelfCalibException::parseError,
                               where + "expected the square's side in m as a positive number (e.g. 0.034), got '" +
                                   parts[2] + "'");
  if (!positiveNumber(parts[3], o.marker_size))
    throw vpSelfCalibException(vpSelfCalibException::parseError,
                               where + "expected the marker's side in m as a positive number (e.g. 0.028), got '" +
                                   parts[3] + "'");
  o.dictionary = parts[4];
  return o;
}

Options parseTags(const std::vector<std::string> &parts, const std::string &where)
{
  if (parts.size() < 3 || parts.size() > 4)
    throw vpSelfCalibException(vpSelfCalibException::parseError,
                               where + "expected apriltag:FAMILY:SIZE[:ID,ID...], e.g. apriltag:36h11:0.048:10");
  Options o;
  o.type = vpBoardDetector::APRILTAG;
  o.dictionary = vpSelfCalib::aprilTagFamily(parts[1]);
  if (o.dictionary.empty())
    o.dictionary = parts[1]; // check() names it
  if (!positiveNumber(parts[2], o.marker_size))
    throw vpSelfCalibException(vpSelfCalibException::parseError,
                               where + "expected the tags' side in m as a positive number (e.g. 0.048), got '" +
                                   parts[2] + "'");
  if (parts.size() == 4) {
    std::istringstream in(parts[3]);
    std::string item;
    while (std::getline(in, item, ',')) {
      int id = 0;
      if (!wholeNumber(item, id))
        throw vpSelfCalibException(vpSelfCalibException::parseError,
                                   where + "expected the tag ids as whole numbers separated by commas (e.g. 0,1,2), got '" +
                                       parts[3] + "'");
      if (std::find(o.tag_ids.begin(), o.tag_ids.end(), id) == o.tag_ids.end())
        o.tag_ids.push_back(id);
    }
    if (o.tag_ids.empty() || parts[3].back() == ',')
      throw vpSelfCalibException(vpSelfCalibException::parseError,
                                 where + "expected the tag ids as whole numbers separated by commas (e.g. 0,1,2), got '" +
                                     parts[3] + "'");
  }
  return o;
}

// The four corners of a tag of side s in its frame (see vpBoardDetector.h).
std::vector<vpColVector> tagCorners(double s)
{
  const double h = 0.5 * s;
  return {vpColVector({-h, -h, 0}), vpColVector({h, -h, 0}), vpColVector({h, h, 0}), vpColVector({-h, h, 0})};
}
} // namespace

namespace vpMarkerBoards
{
void check(const Options &o)
{
  if (o.type == vpBoardDetector::CHARUCO)
    checkCharuco(o);
  else
    checkTags(o);
  if (o.id_offset < 0 || static_cast<long long>(o.id_offset) + numIds(o) > INT_MAX)
    throw badValue("the id offset must be >= 0 and leave room for the board's " + std::to_string(numIds(o)) +
                   " ids below " + std::to_string(INT_MAX));
}

int numIds(const Options &o)
{
  if (o.type == vpBoardDetector::CHARUCO)
    return o.rows > 0 && o.cols > 0 ? static_cast<int>((o.rows - 1) * (o.cols - 1)) : 0;
  const int d = tagDictionary(o);
  return d < 0 ? 0 : 4 * vpSelfCalib::arucoDictionarySize(d);
}

Options parse(const std::vector<std::string> &parts, const std::string &where)
{
  if (parts[0] == "charuco")
    return parseCharuco(parts, where);
  if (parts[0] == "apriltag")
    return parseTags(parts, where);
  if (parts.size() < 2 || parts[1].empty())
    throw vpSelfCalibException(vpSelfCalibException::parseError,
                               where + "expected apriltag-bundle:FILE.yaml (the bundle's family and tags)");
  std::string file = parts[1];
  for (size_t k = 2; k < parts.size(); ++k)
    file += ":" + parts[k];
  return readBundle(file, where);
}

std::string toString(const Options &o)
{
  if (o.type == vpBoardDetector::CHARUCO)
    return "charuco:" + std::to_string(o.cols) + "x" + std::to_string(o.rows) + ":" + shortest(o.spacing) + ":" +
           shortest(o.marker_size) + ":" + o.dictionary;
  if (!o.bundle_file.empty())
    return "apriltag-bundle:" + o.bundle_file;
  if (!o.bundle.empty())
    return "apriltag-bundle of " + std::to_string(o.bundle.size()) + " tags " + o.dictionary;
  return "apriltag:" + o.dictionary + ":" + shortest(o.marker_size) + (o.tag_ids.empty() ? "" : ":" + idList(o.tag_ids));
}

vpBoardDetector::Result detect(const cv::Mat &img, const Options &o)
{
  return o.type == vpBoardDetector::CHARUCO ? detectCharuco(img, o) : detectTags(img, o);
}

std::map<int, vpColVector> layout(const Options &o)
{
  std::map<int, vpColVector> out;
  if (o.type == vpBoardDetector::CHARUCO) {
    for (unsigned int r = 0; r + 1 < o.rows; ++r)
      for (unsigned int c = 0; c + 1 < o.cols; ++c)
        out[o.id_offset + static_cast<int>(r * (o.cols - 1) + c)] = vpColVector({(c + 1) * o.spacing, (r + 1) * o.spacing, 0});
    return out;
  }
  if (o.bundle.empty() && o.tag_ids.size() != 1)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpBoardDetector: the layout of " +
                                   std::string(o.tag_ids.empty() ? "any AprilTag of a family" : "several single AprilTags") +
                                   " is not known (each tag's placement is not): describe the tags as a bundle "
                                   "(apriltag-bundle:FILE.yaml), or use one tag");
  if (o.bundle.empty()) {
    const std::vector<vpColVector> c = tagCorners(o.marker_size);
    for (int k = 0; k < 4; ++k)
      out[o.id_offset + 4 * o.tag_ids[0] + k] = c[static_cast<size_t>(k)];
    return out;
  }
  for (const Options::BundleTag &t : o.bundle) {
    const vpHomogeneousMatrix bMt(t.bMt);
    const std::vector<vpColVector> c = tagCorners(t.size);
    for (int k = 0; k < 4; ++k) {
      const vpColVector X = bMt * vpColVector({c[static_cast<size_t>(k)][0], c[static_cast<size_t>(k)][1], 0, 1});
      out[o.id_offset + 4 * t.id + k] = vpColVector({X[0], X[1], X[2]});
    }
  }
  return out;
}

vpSelfCalibDataset::Yardstick yardstick(const Options &o)
{
  vpSelfCalibDataset::Yardstick y;
  if (o.type == vpBoardDetector::CHARUCO) {
    y.id_a = o.id_offset;
    y.id_b = o.id_offset + static_cast<int>(o.cols) - 2;
    y.length = (o.cols - 2.0) * o.spacing;
    return y;
  }
  const int tag = o.bundle.empty() ? (o.tag_ids.empty() ? 0 : o.tag_ids[0]) : o.bundle[0].id;
  y.id_a = o.id_offset + 4 * tag;
  y.id_b = y.id_a + 1;
  y.length = tagSize(o, tag);
  return y;
}
} // namespace vpMarkerBoards
