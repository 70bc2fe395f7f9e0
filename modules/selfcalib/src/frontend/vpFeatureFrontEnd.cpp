/*
 * ViSP SelfCalib: correspondences across views from images (OpenCV features), yardstick dots.
 */
#include <visp3/selfcalib/vpFeatureFrontEnd.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
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
  float radius;
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
    if (fill < 0.65 || fill > 0.9)
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
      d.initTracking(I, vpImagePoint(cy, cx));
      const vpImagePoint g = d.getCog();
      dots.push_back({cv::Point2f(static_cast<float>(g.get_u()), static_cast<float>(g.get_v())),
                      static_cast<float>(std::sqrt(d.getArea() / M_PI))});
    } catch (const vpException &) {
      // vpDot2 could not follow this blob: not a dot.
    }
  }
  return dots;
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
}

vpFeatureFrontEnd::Result vpFeatureFrontEnd::process(const std::vector<vpImage<unsigned char>> &images,
                                                     const Options &opt)
{
  opt.check();
  const auto t0 = std::chrono::steady_clock::now();
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
  Result res;
  cv::Ptr<cv::Feature2D> det;
  if (opt.detector == SIFT)
    det = cv::SIFT::create(static_cast<int>(opt.max_features));
  else
    det = cv::ORB::create(static_cast<int>(opt.max_features));
  std::vector<std::vector<cv::KeyPoint>> kp(m);
  std::vector<cv::Mat> desc(m), mats(m);
  std::vector<size_t> offset(m + 1, 0);
  for (size_t k = 0; k < m; ++k) {
    mats[k] = toMat(images[k]);
    // Detection runs in parallel inside OpenCV and returns the keypoints in an order that depends
    // on the thread count: sorted here (position, then scale), so that tracks, ids and every sum
    // downstream are the same whatever the threads.
    det->detect(mats[k], kp[k]);
    std::sort(kp[k].begin(), kp[k].end(), [](const cv::KeyPoint &a, const cv::KeyPoint &b) {
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
    det->compute(mats[k], kp[k], desc[k]);
    res.features.push_back(static_cast<unsigned int>(kp[k].size()));
    offset[k + 1] = offset[k] + kp[k].size();
  }
  cv::BFMatcher matcher(opt.detector == SIFT ? cv::NORM_L2 : cv::NORM_HAMMING);
  UnionFind uf(offset[m]);
  res.matches.assign(m, std::vector<unsigned int>(m, 0));
  for (size_t i = 0; i < m; ++i)
    for (size_t j = i + 1; j < m; ++j) {
      if (desc[i].empty() || desc[j].empty() || kp[i].size() < 8 || kp[j].size() < 8)
        continue;
      std::vector<std::vector<cv::DMatch>> ij, ji;
      matcher.knnMatch(desc[i], desc[j], ij, 2);
      if (opt.mutual)
        matcher.knnMatch(desc[j], desc[i], ji, 2);
      std::vector<cv::Point2f> a, b;
      std::vector<std::pair<int, int>> pairs;
      for (const auto &mm : ij) {
        if (mm.size() < 2 || mm[0].distance > opt.ratio * mm[1].distance)
          continue;
        if (opt.mutual && (ji[mm[0].trainIdx].empty() || ji[mm[0].trainIdx][0].trainIdx != mm[0].queryIdx))
          continue;
        pairs.push_back({mm[0].queryIdx, mm[0].trainIdx});
        a.push_back(kp[i][mm[0].queryIdx].pt);
        b.push_back(kp[j][mm[0].trainIdx].pt);
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
          uf.join(offset[i] + pairs[k].first, offset[j] + pairs[k].second);
    }

  // Tracks: components with two or more images and at most one feature per image.
  std::map<size_t, std::vector<std::pair<size_t, size_t>>> comp; // root -> (image, keypoint)
  for (size_t k = 0; k < m; ++k)
    for (size_t f = 0; f < kp[k].size(); ++f)
      comp[uf.find(offset[k] + f)].push_back({k, f});
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
      o.ip = vpImagePoint(kp[e.first][e.second].pt.y, kp[e.first][e.second].pt.x);
      res.observations[e.first].push_back(o);
    }
  }

  // The yardstick: two dots, the smaller is end a.
  res.yardstick_seen.assign(m, false);
  if (opt.yardstick) {
    unsigned int seen = 0;
    std::vector<std::pair<Dot, Dot>> ends(m);
    for (size_t k = 0; k < m; ++k) {
      std::vector<Dot> dots = findDots(images[k], mats[k], opt);
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
    if (seen >= 2) {
      res.yardstick_a = static_cast<int>(res.num_tracks);
      res.yardstick_b = static_cast<int>(res.num_tracks + 1);
      for (size_t k = 0; k < m; ++k)
        if (res.yardstick_seen[k]) {
          res.observations[k].push_back({res.yardstick_a, vpImagePoint(ends[k].first.centre.y, ends[k].first.centre.x)});
          res.observations[k].push_back(
              {res.yardstick_b, vpImagePoint(ends[k].second.centre.y, ends[k].second.centre.x)});
        }
    }
  }
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

vpFeatureFrontEnd::Result vpFeatureFrontEnd::fillDataset(vpSelfCalibDataset &ds, const Options &opt)
{
  std::vector<vpImage<unsigned char>> images(ds.views.size());
  for (size_t k = 0; k < ds.views.size(); ++k) {
    const std::string &file = ds.views[k].image;
    if (file.empty())
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpFeatureFrontEnd: view " + std::to_string(k) + " has no image");
    try {
      vpImageIo::read(images[k], file);
    } catch (const vpException &e) {
      throw vpSelfCalibException(vpSelfCalibException::ioError, "vpFeatureFrontEnd: view " + std::to_string(k) +
                                                                    ": cannot read image '" + file +
                                                                    "': " + e.getStringMessage());
    }
    if (images[k].getWidth() != ds.width || images[k].getHeight() != ds.height)
      throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                                 "vpFeatureFrontEnd: view " + std::to_string(k) + ": image '" + file + "' is " +
                                     std::to_string(images[k].getWidth()) + " x " +
                                     std::to_string(images[k].getHeight()) + ", the camera says " +
                                     std::to_string(ds.width) + " x " + std::to_string(ds.height));
  }
  const Result r = process(images, opt);
  for (size_t k = 0; k < ds.views.size(); ++k)
    ds.views[k].points = r.observations[k];
  ds.yardstick.id_a = r.yardstick_a;
  ds.yardstick.id_b = r.yardstick_b;
  return r;
}
