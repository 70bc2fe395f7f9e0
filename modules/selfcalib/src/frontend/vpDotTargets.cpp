/*
 * ViSP SelfCalib: the front end's dot targets: dark round dots (vpDot2), dot grids ordered by
 * OpenCV's asymmetric circle grid finder, and the yardstick's two dots.
 */
#include "vpDotTargets.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <visp3/blob/vpDot2.h>

namespace vpSelfCalib::frontend
{
namespace
{
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

std::vector<Dot> findGrids(const vpImage<unsigned char> &I, const cv::Mat &img, const vpFeatureFrontEnd::Options &opt,
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

void findYardstick(const std::vector<std::vector<Dot>> &loose, vpFeatureFrontEnd::Result &res)
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
} // namespace vpSelfCalib::frontend
