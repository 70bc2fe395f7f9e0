/*
 * ViSP SelfCalib: correspondences across views from images (OpenCV features), yardstick dots.
 */
#include <visp3/selfcalib/vpFeatureFrontEnd.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <numeric>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <visp3/blob/vpDot2.h>
#include <visp3/io/vpImageIo.h>
#include <opencv2/features2d.hpp>

namespace
{
cv::Mat toMat(const vpImage<unsigned char> &I)
{
  return cv::Mat(static_cast<int>(I.getHeight()), static_cast<int>(I.getWidth()), CV_8UC1,
                 const_cast<unsigned char *>(I.bitmap))
      .clone();
}

struct UnionFind {
  std::vector<size_t> parent;
  explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  size_t find(size_t x)
  {
    while (parent[x] != x)
      x = parent[x] = parent[parent[x]];
    return x;
  }
  void join(size_t a, size_t b) { parent[find(a)] = find(b); }
};

struct Dot {
  cv::Point2f centre;
  float radius; //!< sqrt(area / pi)
  float major;  //!< semi-major axis of the ellipse of the same moments: the dot's size without foreshortening
};

// Dark round blobs with a white surround: the yardstick's dots. Candidates are the connected
// components of the dark pixels that are round (fill of their box near pi / 4, box nearly square)
// and surrounded by white; each is then measured with ViSP's vpDot2 (centre of gravity, area).
std::vector<Dot> findDots(const vpImage<unsigned char> &I, const cv::Mat &img, const vpFeatureFrontEnd::Options &o)
{
  cv::Mat dark = img < 100, labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(dark, labels, stats, centroids, 8);
  std::vector<Dot> dots;
  const double amin = M_PI * o.dot_min_radius * o.dot_min_radius, amax = M_PI * o.dot_max_radius * o.dot_max_radius;
  for (int c = 1; c < n; ++c) {
    const double area = stats.at<int>(c, cv::CC_STAT_AREA);
    const double w = stats.at<int>(c, cv::CC_STAT_WIDTH), h = stats.at<int>(c, cv::CC_STAT_HEIGHT);
    if (area < amin || area > amax || w > 2 * h || h > 2 * w)
      continue;
    const double fill = area / (w * h);
    if (fill < 0.5 || fill > 0.9) // an ellipse at 45 degrees fills 0.6 of its box, pixelated less
      continue;
    const double cx = centroids.at<double>(c, 0), cy = centroids.at<double>(c, 1), r = std::sqrt(area / M_PI);
    double sum = 0;
    int m = 0;
    for (int a = 0; a < 32; ++a)
      for (double f : {1.4, 1.6, 1.8}) {
        const int x = static_cast<int>(std::lround(cx + f * r * std::cos(a * M_PI / 16)));
        const int y = static_cast<int>(std::lround(cy + f * r * std::sin(a * M_PI / 16)));
        if (x >= 0 && y >= 0 && x < img.cols && y < img.rows) {
          sum += img.at<unsigned char>(y, x);
          ++m;
        }
      }
    if (m < 64 || sum / m < 190)
      continue;
    try {
      vpDot2 d;
      d.setGraphics(false);
      d.setComputeMoments(true);
      d.initTracking(I, vpImagePoint(cy, cx));
      const vpImagePoint g = d.getCog();
      const vpColVector n = d.get_nij(); // n20, n11, n02: covariance of the blob
      const double lmax = 0.5 * (n[0] + n[2]) + std::sqrt(0.25 * (n[0] - n[2]) * (n[0] - n[2]) + n[1] * n[1]);
      dots.push_back({cv::Point2f(static_cast<float>(g.get_u()), static_cast<float>(g.get_v())),
                      static_cast<float>(std::sqrt(d.getArea() / M_PI)),
                      static_cast<float>(std::max(2 * std::sqrt(std::max(0.0, lmax)), std::sqrt(d.getArea() / M_PI)))});
    } catch (const vpException &) {
      // vpDot2 could not follow this blob: not a dot.
    }
  }
  return dots;
}
// A Feature2D that "detects" given keypoints: hands our vpDot2 centres to findCirclesGrid.
class GivenKeypoints : public cv::Feature2D
{
public:
  explicit GivenKeypoints(const std::vector<cv::KeyPoint> &kp) : m_kp(kp) {}
  void detect(cv::InputArray, std::vector<cv::KeyPoint> &kp, cv::InputArray = cv::noArray()) override { kp = m_kp; }

private:
  std::vector<cv::KeyPoint> m_kp;
};

// The dots of `group` in grid g's order (OpenCV's asymmetric-grid order): empty when the group is
// not that grid.
std::vector<Dot> orderGrid(const cv::Mat &img, const std::vector<Dot> &dots, const std::vector<size_t> &group,
                           const vpDotGrid &g, std::vector<size_t> &members)
{
  members.clear();
  std::vector<cv::KeyPoint> kp;
  for (size_t i : group)
    kp.emplace_back(dots[i].centre, 2 * dots[i].radius);
  std::vector<cv::Point2f> centres;
  const cv::Ptr<cv::FeatureDetector> given = cv::makePtr<GivenKeypoints>(kp);
  const cv::Size size(static_cast<int>(g.cols), static_cast<int>(g.rows));
  if (!(cv::findCirclesGrid(img, size, centres, cv::CALIB_CB_ASYMMETRIC_GRID, given) ||
        cv::findCirclesGrid(img, size, centres, cv::CALIB_CB_ASYMMETRIC_GRID | cv::CALIB_CB_CLUSTERING, given)) ||
      centres.size() != g.size())
    return {};
  std::vector<Dot> ordered;
  for (const cv::Point2f &c : centres) {
    size_t best = group[0];
    for (size_t i : group)
      if (cv::norm(dots[i].centre - c) < cv::norm(dots[best].centre - c))
        best = i;
    if (std::find(members.begin(), members.end(), best) != members.end())
      return {}; // two grid places on one dot
    members.push_back(best);
    ordered.push_back(dots[best]);
  }
  // OpenCV's labelling can be any symmetry of the lattice it sees (the order reversed, the rows
  // reversed), and the ids must mean the same dot in every view. Of the four relabellings, keep
  // those that fit the grid's layout (dot k at ((2 j + i % 2), i), a homography within 1 px), then
  // the one a camera sees from the front: first row and first column counterclockwise (y down).
  const unsigned int n = g.size();
  std::vector<cv::Point2f> layout;
  for (unsigned int k = 0; k < n; ++k)
    layout.emplace_back(static_cast<float>(g.x(k)), static_cast<float>(g.y(k)));
  std::vector<Dot> best;
  double best_error = 1.0;
  for (int variant = 0; variant < 4; ++variant) {
    std::vector<Dot> cand(n);
    std::vector<cv::Point2f> image(n);
    for (unsigned int k = 0; k < n; ++k) {
      unsigned int src = variant & 1 ? n - 1 - k : k;
      if (variant & 2)
        src = (g.rows - 1 - src / g.cols) * g.cols + src % g.cols;
      cand[k] = ordered[src];
      image[k] = cand[k].centre;
    }
    const cv::Point2f a = cand[g.cols - 1].centre - cand[0].centre, b = cand[(g.rows - 1) * g.cols].centre - cand[0].centre;
    if (a.x * b.y - a.y * b.x <= 0)
      continue;
    const cv::Mat H = cv::findHomography(layout, image, 0);
    if (H.empty())
      continue;
    std::vector<cv::Point2f> mapped;
    cv::perspectiveTransform(layout, mapped, H);
    double error = 0;
    for (unsigned int k = 0; k < n; ++k)
      error = std::max(error, static_cast<double>(cv::norm(mapped[k] - image[k])));
    if (error < best_error) {
      best_error = error;
      best = cand;
    }
  }
  return best;
}
} // namespace

const char *vpFeatureFrontEnd::detectorName(Detector d) { return d == ORB ? "orb" : "sift"; }

vpFeatureFrontEnd::Detector vpFeatureFrontEnd::detectorFromName(const std::string &name)
{
  if (name == "sift")
    return SIFT;
  if (name == "orb")
    return ORB;
  throw vpSelfCalibException(vpSelfCalibException::badValue, "feature detector '" + name + "': use sift or orb");
}

void vpFeatureFrontEnd::Options::check() const
{
  if (max_features < 8 || !(ratio > 0 && ratio <= 1) || !(ransac_threshold > 0) || min_matches < 8 ||
      !(dot_min_radius > 0 && dot_max_radius > dot_min_radius))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpFeatureFrontEnd: max_features >= 8, ratio in (0, 1], ransac_threshold > 0, "
                               "min_matches >= 8 and 0 < dot_min_radius < dot_max_radius are needed");
  if (!features && dot_grids.empty())
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpFeatureFrontEnd: neither natural features nor dot grids to find");
  std::set<unsigned int> sizes;
  for (const DotGrid &g : dot_grids) {
    if (g.cols < 2 || g.rows < 3 || g.first_id < 0)
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpFeatureFrontEnd: a dot grid needs 2 or more columns, 3 or more rows and a "
                                 "non-negative first id");
    for (const DotGrid &h : dot_grids)
      if (&h != &g && g.first_id <= h.first_id && h.first_id < g.first_id + static_cast<int>(g.size()))
        throw vpSelfCalibException(vpSelfCalibException::badValue,
                                   "vpFeatureFrontEnd: the dot grids' id ranges overlap");
    if (!sizes.insert(g.size()).second)
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpFeatureFrontEnd: the dot grids must have different numbers of dots (a group of "
                                 "dots is recognised by its size)");
  }
}

namespace
{
// The steps of vpFeatureFrontEnd::process(), in order.
using FrontEnd = vpFeatureFrontEnd;

void checkImages(const std::vector<vpImage<unsigned char>> &images)
{
  const size_t m = images.size();
  if (m < 2)
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpFeatureFrontEnd: at least 2 images are needed");
  for (size_t k = 0; k < m; ++k)
    if (images[k].getWidth() != images[0].getWidth() || images[k].getHeight() != images[0].getHeight() ||
        images[k].getSize() == 0)
      throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                                 "vpFeatureFrontEnd: image " + std::to_string(k) + " is " +
                                     std::to_string(images[k].getWidth()) + " x " +
                                     std::to_string(images[k].getHeight()) + ", image 0 is " +
                                     std::to_string(images[0].getWidth()) + " x " +
                                     std::to_string(images[0].getHeight()));
}

// The keypoints and descriptors of every image; the keypoints of image k are numbered from offset[k]
// in the union-find of the tracks.
struct Features {
  std::vector<std::vector<cv::KeyPoint>> kp;
  std::vector<cv::Mat> desc;
  std::vector<size_t> offset;
};

// Step 1: detection (none when opt.features is off); res.features gets the count per image.
Features detectFeatures(const std::vector<cv::Mat> &mats, const FrontEnd::Options &opt, FrontEnd::Result &res)
{
  const size_t m = mats.size();
  cv::Ptr<cv::Feature2D> det;
  if (opt.detector == FrontEnd::SIFT)
    det = cv::SIFT::create(static_cast<int>(opt.max_features));
  else
    det = cv::ORB::create(static_cast<int>(opt.max_features));
  Features f;
  f.kp.resize(m);
  f.desc.resize(m);
  f.offset.assign(m + 1, 0);
  for (size_t k = 0; k < m; ++k) {
    if (!opt.features) {
      res.features.push_back(0);
      f.offset[k + 1] = f.offset[k];
      continue;
    }
    // Detection runs in parallel inside OpenCV and returns the keypoints in an order that depends
    // on the thread count: sorted here (position, then scale), so that tracks, ids and every sum
    // downstream are the same whatever the threads.
    det->detect(mats[k], f.kp[k]);
    std::sort(f.kp[k].begin(), f.kp[k].end(), [](const cv::KeyPoint &a, const cv::KeyPoint &b) {
      if (a.pt.y != b.pt.y)
        return a.pt.y < b.pt.y;
      if (a.pt.x != b.pt.x)
        return a.pt.x < b.pt.x;
      if (a.size != b.size)
        return a.size < b.size;
      if (a.angle != b.angle)
        return a.angle < b.angle;
      return a.octave < b.octave;
    });
    det->compute(mats[k], f.kp[k], f.desc[k]);
    res.features.push_back(static_cast<unsigned int>(f.kp[k].size()));
    f.offset[k + 1] = f.offset[k] + f.kp[k].size();
  }
  return f;
}

// Step 2: matching of every pair, ratio test, mutual best match, RANSAC fundamental matrix; the
// verified matches join their keypoints in uf and are counted in res.matches.
void matchPairs(const Features &f, const FrontEnd::Options &opt, UnionFind &uf, FrontEnd::Result &res)
{
  const size_t m = f.kp.size();
  cv::BFMatcher matcher(opt.detector == FrontEnd::SIFT ? cv::NORM_L2 : cv::NORM_HAMMING);
  res.matches.assign(m, std::vector<unsigned int>(m, 0));
  for (size_t i = 0; i < m; ++i)
    for (size_t j = i + 1; j < m; ++j) {
      if (f.desc[i].empty() || f.desc[j].empty() || f.kp[i].size() < 8 || f.kp[j].size() < 8)
        continue;
      std::vector<std::vector<cv::DMatch>> ij, ji;
      matcher.knnMatch(f.desc[i], f.desc[j], ij, 2);
      if (opt.mutual)
        matcher.knnMatch(f.desc[j], f.desc[i], ji, 2);
      std::vector<cv::Point2f> a, b;
      std::vector<std::pair<int, int>> pairs;
      for (const auto &mm : ij) {
        if (mm.size() < 2 || mm[0].distance > opt.ratio * mm[1].distance)
          continue;
        if (opt.mutual && (ji[mm[0].trainIdx].empty() || ji[mm[0].trainIdx][0].trainIdx != mm[0].queryIdx))
          continue;
        pairs.push_back({mm[0].queryIdx, mm[0].trainIdx});
        a.push_back(f.kp[i][mm[0].queryIdx].pt);
        b.push_back(f.kp[j][mm[0].trainIdx].pt);
      }
      if (pairs.size() < opt.min_matches)
        continue;
      std::vector<unsigned char> inl;
      const cv::Mat F = cv::findFundamentalMat(a, b, cv::FM_RANSAC, opt.ransac_threshold, 0.999, inl);
      if (F.empty())
        continue;
      unsigned int n = 0;
      for (size_t k = 0; k < pairs.size(); ++k)
        n += inl[k] != 0;
      if (n < opt.min_matches)
        continue;
      res.matches[i][j] = n;
      for (size_t k = 0; k < pairs.size(); ++k)
        if (inl[k])
          uf.join(f.offset[i] + pairs[k].first, f.offset[j] + pairs[k].second);
    }
}

// Step 3: tracks, the components of uf with two or more images and at most one feature per image,
// numbered 0, 1, ... into res.observations.
void buildTracks(const Features &f, UnionFind &uf, FrontEnd::Result &res)
{
  const size_t m = f.kp.size();
  std::map<size_t, std::vector<std::pair<size_t, size_t>>> comp; // root -> (image, keypoint)
  for (size_t k = 0; k < m; ++k)
    for (size_t i = 0; i < f.kp[k].size(); ++i)
      comp[uf.find(f.offset[k] + i)].push_back({k, i});
  res.observations.assign(m, {});
  for (const auto &c : comp) {
    if (c.second.size() < 2)
      continue;
    std::vector<bool> in(m, false);
    bool ok = true;
    for (const auto &e : c.second) {
      ok = ok && !in[e.first];
      in[e.first] = true;
    }
    if (!ok)
      continue;
    const int id = static_cast<int>(res.num_tracks++);
    if (res.track_lengths.size() <= c.second.size())
      res.track_lengths.resize(c.second.size() + 1, 0);
    ++res.track_lengths[c.second.size()];
    for (const auto &e : c.second) {
      vpSelfCalibDataset::Observation o;
      o.id = id;
      o.ip = vpImagePoint(f.kp[e.first][e.second].pt.y, f.kp[e.first][e.second].pt.x);
      res.observations[e.first].push_back(o);
    }
  }
}

// Step 4, one image: every dot of a recognised grid gets the grid's id for its place (into
// observations, grid_seen[g] set); returns the dots left over, candidates for the yardstick.
// The grids' dots differ in size: a grid is a run of the dots sorted by size, as long as the grid,
// with a jump in size at both ends; the runs with the largest jumps are tried first.
std::vector<Dot> findGrids(const vpImage<unsigned char> &I, const cv::Mat &img, const FrontEnd::Options &opt,
                           std::vector<vpSelfCalibDataset::Observation> &observations,
                           std::vector<std::vector<bool>> &grid_seen, size_t k)
{
  const std::vector<Dot> dots = findDots(I, img, opt);
  std::vector<bool> used(dots.size(), false);
  std::vector<size_t> by_size(dots.size());
  std::iota(by_size.begin(), by_size.end(), 0);
  std::stable_sort(by_size.begin(), by_size.end(), [&](size_t x, size_t y) { return dots[x].major < dots[y].major; });
  auto jump = [&](size_t n) { // size ratio between sorted dots n - 1 and n (large at the ends)
    return n == 0 || n >= by_size.size() ? 1e9 : dots[by_size[n]].major / std::max(1e-3f, dots[by_size[n - 1]].major);
  };
  for (size_t g = 0; g < opt.dot_grids.size(); ++g) {
    const vpDotGrid &grid = opt.dot_grids[g];
    const size_t count = grid.size();
    std::vector<std::pair<double, size_t>> runs; // (smaller end jump, first index)
    for (size_t first = 0; first + count <= by_size.size(); ++first)
      runs.push_back({std::min(jump(first), jump(first + count)), first});
    std::stable_sort(runs.begin(), runs.end(), [](const std::pair<double, size_t> &x, const std::pair<double, size_t> &y) {
      return x.first > y.first;
    });
    for (size_t r = 0; r < runs.size() && r < 3 && runs[r].first > 1.1; ++r) {
      std::vector<size_t> group(by_size.begin() + runs[r].second, by_size.begin() + runs[r].second + count);
      if (std::any_of(group.begin(), group.end(), [&](size_t i) { return used[i]; }))
        continue;
      std::vector<size_t> members;
      const std::vector<Dot> ordered = orderGrid(img, dots, group, grid, members);
      if (ordered.empty())
        continue;
      for (size_t i = 0; i < ordered.size(); ++i)
        observations.push_back(
            {grid.first_id + static_cast<int>(i), vpImagePoint(ordered[i].centre.y, ordered[i].centre.x)});
      for (size_t i : members)
        used[i] = true;
      grid_seen[g][k] = true;
      break;
    }
  }
  std::vector<Dot> loose;
  for (size_t i = 0; i < dots.size(); ++i)
    if (!used[i])
      loose.push_back(dots[i]);
  return loose;
}

// Step 5: the yardstick, two loose dots in an image, the smaller is end a; ids after the tracks'
// when seen in two images or more.
void findYardstick(const std::vector<std::vector<Dot>> &loose, FrontEnd::Result &res)
{
  const size_t m = loose.size();
  unsigned int seen = 0;
  std::vector<std::pair<Dot, Dot>> ends(m);
  for (size_t k = 0; k < m; ++k) {
    std::vector<Dot> dots = loose[k];
    if (dots.size() != 2)
      continue;
    if (dots[0].radius > dots[1].radius)
      std::swap(dots[0], dots[1]);
    if (dots[1].radius < 1.2f * dots[0].radius)
      continue;
    ends[k] = {dots[0], dots[1]};
    res.yardstick_seen[k] = true;
    ++seen;
  }
  if (seen < 2)
    return;
  res.yardstick_a = static_cast<int>(res.num_tracks);
  res.yardstick_b = static_cast<int>(res.num_tracks + 1);
  for (size_t k = 0; k < m; ++k)
    if (res.yardstick_seen[k]) {
      res.observations[k].push_back({res.yardstick_a, vpImagePoint(ends[k].first.centre.y, ends[k].first.centre.x)});
      res.observations[k].push_back({res.yardstick_b, vpImagePoint(ends[k].second.centre.y, ends[k].second.centre.x)});
    }
}
} // namespace

vpFeatureFrontEnd::Result vpFeatureFrontEnd::process(const std::vector<vpImage<unsigned char>> &images,
                                                     const Options &opt)
{
  opt.check();
  const auto t0 = std::chrono::steady_clock::now();
  checkImages(images);
  const size_t m = images.size();
  std::vector<cv::Mat> mats(m);
  for (size_t k = 0; k < m; ++k)
    mats[k] = toMat(images[k]);
  Result res;
  const Features features = detectFeatures(mats, opt, res);
  UnionFind uf(features.offset[m]);
  matchPairs(features, opt, uf, res);
  buildTracks(features, uf, res);

  for (const DotGrid &g : opt.dot_grids)
    if (g.first_id < static_cast<int>(res.num_tracks) + 2)
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpFeatureFrontEnd: dot grid ids from " + std::to_string(g.first_id) +
                                     " collide with the " + std::to_string(res.num_tracks) +
                                     " feature tracks' ids: use a larger first_id");
  res.grid_seen.assign(opt.dot_grids.size(), std::vector<bool>(m, false));
  std::vector<std::vector<Dot>> loose(m);
  if (opt.yardstick || !opt.dot_grids.empty())
    for (size_t k = 0; k < m; ++k)
      loose[k] = findGrids(images[k], mats[k], opt, res.observations[k], res.grid_seen, k);

  res.yardstick_seen.assign(m, false);
  if (opt.yardstick)
    findYardstick(loose, res);
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

std::vector<vpImage<unsigned char>> vpFeatureFrontEnd::readImages(const vpSelfCalibDataset &ds, const std::string &who)
{
  std::vector<vpImage<unsigned char>> images(ds.views.size());
  for (size_t k = 0; k < ds.views.size(); ++k) {
    const std::string &file = ds.views[k].image, view = who + ": view " + std::to_string(k);
    if (file.empty())
      throw vpSelfCalibException(vpSelfCalibException::badValue, view + " has no image");
    try {
      vpImageIo::read(images[k], file);
    } catch (const vpException &e) {
      throw vpSelfCalibException(vpSelfCalibException::ioError,
                                 view + ": cannot read image '" + file + "': " + e.getStringMessage());
    }
    if (images[k].getWidth() != ds.width || images[k].getHeight() != ds.height)
      throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                                 view + ": image '" + file + "' is " + std::to_string(images[k].getWidth()) + " x " +
                                     std::to_string(images[k].getHeight()) + ", the camera says " +
                                     std::to_string(ds.width) + " x " + std::to_string(ds.height));
  }
  return images;
}

vpFeatureFrontEnd::Result vpFeatureFrontEnd::fillDataset(vpSelfCalibDataset &ds, const Options &opt)
{
  const std::vector<vpImage<unsigned char>> images = readImages(ds);
  const Result r = process(images, opt);
  for (size_t k = 0; k < ds.views.size(); ++k)
    ds.views[k].points = r.observations[k];
  ds.yardstick.id_a = r.yardstick_a;
  ds.yardstick.id_b = r.yardstick_b;
  return r;
}
