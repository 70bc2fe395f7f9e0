/*
 * ViSP SelfCalib: correspondences across views from images (OpenCV features), yardstick dots.
 */
#include <visp3/selfcalib/vpFeatureFrontEnd.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include "../core/vpSelfCalibParallel.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <numeric>
#include <atomic>
#include <exception>
#include <functional>
#include <iterator>
#include <sstream>
#include <thread>

#include <Eigen/Dense>
#include <opencv2/core/hal/hal.hpp>

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
  if (!(contrast_threshold > 0) || neighbours < 1 || !(guided_ratio > 0 && guided_ratio <= 1) ||
      !(track_tolerance > 0) || !(min_overlap >= 0 && min_overlap <= 1) ||
      !(min_prior_agreement >= 0 && min_prior_agreement <= 1))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpFeatureFrontEnd: contrast_threshold > 0, neighbours >= 1, guided_ratio in (0, 1], "
                               "track_tolerance > 0, min_overlap and "
                               "min_prior_agreement in [0, 1] are needed");
  if (!prior.empty() && (!(prior.cam.get_px() > 0) || !(prior.cam.get_py() > 0) || !(prior.rotation_sd >= 0) ||
                         !(prior.translation_sd >= 0) || !(prior.depth >= 0) || !std::isfinite(prior.depth)))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpFeatureFrontEnd: the prior needs px, py > 0 and non-negative sd and depth");
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

using vpSelfCalib::parallelFor;

unsigned int threadCount(const FrontEnd::Options &o)
{
  return o.threads ? o.threads : static_cast<unsigned int>(std::max(1, cv::getNumThreads()));
}

// The keypoints and descriptors of every image; the keypoints of image k are numbered from offset[k]
// in the union-find of the tracks.
struct Features {
  std::vector<std::vector<cv::KeyPoint>> kp;
  std::vector<cv::Mat> desc;
  std::vector<size_t> offset;
  //! Per image, per feature: the squared descriptor distance to the nearest other feature of the
  //! same image (its distinctiveness; filled when a prior guides the matching).
  std::vector<std::vector<float>> self_nn;
};

/*
  Per descriptor (row), the squared distance to the nearest other row of the same matrix. Hamming
  (ORB): OpenCV's brute-force matcher. L2 (SIFT, float rows): |a|^2 + |b|^2 - 2 a.b with the dot
  products as an Eigen matrix product, a block of rows at a time (memory n x 256 floats), each pair
  once. OpenCV's SIFT descriptors are whole numbers up to 255 (128 of them), so every sum stays below
  2^24 and the squared distance is exact (the matcher's knnMatch gave its square root, squared back
  here before: the same tracks on bench-frontend's images); 2.7x less CPU than that knnMatch on its
  25 rendered images (0.65 against 1.75 s on one core; it was 40 % of the detection's time).
*/
std::vector<float> nearestOtherSquared(const cv::Mat &desc, bool l2)
{
  const int n = desc.rows;
  std::vector<float> out(static_cast<size_t>(n), std::numeric_limits<float>::infinity());
  if (!l2 || desc.type() != CV_32F || !desc.isContinuous()) {
    cv::BFMatcher matcher(l2 ? cv::NORM_L2 : cv::NORM_HAMMING);
    std::vector<std::vector<cv::DMatch>> nn;
    matcher.knnMatch(desc, desc, nn, 2);
    for (const auto &mm : nn)
      for (const cv::DMatch &d : mm)
        if (d.trainIdx != d.queryIdx)
          out[static_cast<size_t>(d.queryIdx)] = std::min(out[static_cast<size_t>(d.queryIdx)], d.distance * d.distance);
    return out;
  }
  using RowMajor = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const Eigen::Map<const RowMajor> A(desc.ptr<float>(), n, desc.cols);
  const Eigen::VectorXf norm2 = A.rowwise().squaredNorm();
  // The distances are symmetric: block q0 meets only the rows from q0 on, and each distance
  // updates both of its rows.
  constexpr int kBlock = 256;
  Eigen::MatrixXf G; // (n - q0) x block, column c: the dot products of row q0 + c with rows q0...
  for (int q0 = 0; q0 < n; q0 += kBlock) {
    const int b = std::min(kBlock, n - q0);
    G.noalias() = A.bottomRows(n - q0) * A.middleRows(q0, b).transpose();
    for (int c = 0; c < b; ++c) {
      const int q = q0 + c;
      float best = std::numeric_limits<float>::infinity();
      for (int r = 0; r < n - q0; ++r) {
        const int j = q0 + r;
        if (j == q)
          continue;
        const float d = norm2(j) + norm2(q) - 2.0f * G(r, c);
        best = std::min(best, d);
        float &oj = out[static_cast<size_t>(j)];
        oj = std::min(oj, d);
      }
      float &oq = out[static_cast<size_t>(q)];
      oq = std::min(oq, best);
    }
  }
  for (float &o : out)
    o = std::max(0.0f, o);
  return out;
}

// Step 1: detection (none when opt.features is off), one image per thread; res.features gets the
// count per image.
Features detectFeatures(const std::vector<cv::Mat> &mats, const std::vector<cv::Mat> &masks,
                        const FrontEnd::Options &opt, FrontEnd::Result &res)
{
  const size_t m = mats.size();
  Features f;
  f.kp.resize(m);
  f.desc.resize(m);
  f.self_nn.resize(m);
  f.offset.assign(m + 1, 0);
  if (opt.features)
    parallelFor(m, threadCount(opt), [&](size_t k) {
      cv::Ptr<cv::Feature2D> det;
      if (opt.detector == FrontEnd::SIFT)
        det = cv::SIFT::create(static_cast<int>(opt.max_features), 3, opt.contrast_threshold);
      else
        det = cv::ORB::create(static_cast<int>(opt.max_features));
      const cv::Mat mask = masks.empty() ? cv::Mat() : masks[masks.size() == 1 ? 0 : k];
      // One pass (the scale space is built once for the keypoints and their descriptors). Detection
      // runs in parallel inside OpenCV and returns the keypoints in an order that depends on the
      // thread count: sorted here (position, then scale), descriptors with them, so that tracks, ids
      // and every sum downstream are the same whatever the threads.
      std::vector<cv::KeyPoint> kp;
      cv::Mat desc;
      det->detectAndCompute(mats[k], mask, kp, desc);
      std::vector<size_t> order(kp.size());
      std::iota(order.begin(), order.end(), size_t(0));
      std::sort(order.begin(), order.end(), [&kp](size_t ia, size_t ib) {
        const cv::KeyPoint &a = kp[ia], &b = kp[ib];
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
      f.kp[k].reserve(kp.size());
      f.desc[k].create(static_cast<int>(kp.size()), desc.cols, desc.type());
      for (size_t r = 0; r < order.size(); ++r) {
        f.kp[k].push_back(kp[order[r]]);
        desc.row(static_cast<int>(order[r])).copyTo(f.desc[k].row(static_cast<int>(r)));
      }
      // Distinctiveness, for the guided search's ratio test (see searchGuided).
      if (((opt.guided && !opt.prior.empty()) || opt.complete_tracks) && f.kp[k].size() >= 2)
        f.self_nn[k] = nearestOtherSquared(f.desc[k], opt.detector == FrontEnd::SIFT);
    });
  for (size_t k = 0; k < m; ++k) {
    res.features.push_back(static_cast<unsigned int>(f.kp[k].size()));
    f.offset[k + 1] = f.offset[k] + f.kp[k].size();
  }
  return f;
}

using Match = std::pair<int, int>; // (feature in image i, feature in image j)

// A pair's own RANSAC seed, from the options' seed and the pair (splitmix64).
int pairSeed(uint64_t seed, size_t i, size_t j)
{
  uint64_t z = seed + 0x9e3779b97f4a7c15ULL * (1 + i * 1000003ULL + j);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return static_cast<int>((z ^ (z >> 31)) & 0x7fffffff);
}

// Geometric verification: OpenCV's USAC fundamental matrix (MSAC score, inner local optimisation,
// seeded): the inliers of `cand`, or nothing when fewer than min_matches.
std::vector<Match> verify(const std::vector<Match> &cand, const std::vector<cv::KeyPoint> &ki,
                          const std::vector<cv::KeyPoint> &kj, const FrontEnd::Options &opt, int seed)
{
  if (cand.size() < std::max(opt.min_matches, 8u))
    return {};
  std::vector<cv::Point2f> a, b;
  for (const Match &c : cand) {
    a.push_back(ki[c.first].pt);
    b.push_back(kj[c.second].pt);
  }
  cv::UsacParams p;
  p.threshold = opt.ransac_threshold;
  p.confidence = 0.999;
  p.maxIterations = 10000;
  p.randomGeneratorState = seed;
  p.isParallel = false;
  std::vector<unsigned char> inl;
  cv::Mat F;
  try {
    F = cv::findFundamentalMat(a, b, inl, p);
  } catch (const cv::Exception &) {
    return {}; // degenerate configuration: no model
  }
  if (F.empty() || inl.size() != cand.size())
    return {};
  std::vector<Match> out;
  for (size_t k = 0; k < cand.size(); ++k)
    if (inl[k])
      out.push_back(cand[k]);
  if (out.size() < opt.min_matches)
    return {};
  return out;
}

// Unguided candidates of a pair: two nearest neighbours, ratio test, mutual best match.
std::vector<Match> matchUnguided(const Features &f, size_t i, size_t j, const FrontEnd::Options &opt)
{
  if (f.desc[i].empty() || f.desc[j].empty() || f.kp[i].size() < 8 || f.kp[j].size() < 8)
    return {};
  cv::BFMatcher matcher(opt.detector == FrontEnd::SIFT ? cv::NORM_L2 : cv::NORM_HAMMING);
  std::vector<std::vector<cv::DMatch>> ij, ji;
  matcher.knnMatch(f.desc[i], f.desc[j], ij, 2);
  if (opt.mutual)
    matcher.knnMatch(f.desc[j], f.desc[i], ji, 2);
  std::vector<Match> pairs;
  for (const auto &mm : ij) {
    if (mm.size() < 2 || mm[0].distance > opt.ratio * mm[1].distance)
      continue;
    if (opt.mutual && (ji[mm[0].trainIdx].empty() || ji[mm[0].trainIdx][0].trainIdx != mm[0].queryIdx))
      continue;
    pairs.push_back({mm[0].queryIdx, mm[0].trainIdx});
  }
  return pairs;
}

// The prior's geometry: per view x_c = R x_f + t, and the intrinsics.
struct PriorGeometry {
  Eigen::Matrix3d K, Kinv;
  double f = 1;
  std::vector<Eigen::Matrix3d> R;
  std::vector<Eigen::Vector3d> t, centre, axis; // centre and optical axis in f
  double width = 0, height = 0;

  PriorGeometry(const FrontEnd::Prior &p, unsigned int w, unsigned int h) : width(w), height(h)
  {
    K << p.cam.get_px(), 0, p.cam.get_u0(), 0, p.cam.get_py(), p.cam.get_v0(), 0, 0, 1;
    Kinv = K.inverse();
    f = std::max(p.cam.get_px(), p.cam.get_py());
    for (const vpHomogeneousMatrix &fMc : p.fMc) {
      const vpHomogeneousMatrix cMf = fMc.inverse();
      Eigen::Matrix3d r;
      Eigen::Vector3d tt, c, a;
      for (unsigned int y = 0; y < 3; ++y) {
        for (unsigned int x = 0; x < 3; ++x)
          r(y, x) = cMf[y][x];
        tt(y) = cMf[y][3];
        c(y) = fMc[y][3];
        a(y) = fMc[y][2];
      }
      R.push_back(r);
      t.push_back(tt);
      centre.push_back(c);
      axis.push_back(a);
    }
  }
  // Relative pose x_j = Rji x_i + tji.
  void relative(size_t i, size_t j, Eigen::Matrix3d &Rji, Eigen::Vector3d &tji) const
  {
    Rji = R[j] * R[i].transpose();
    tji = t[j] - Rji * t[i];
  }
  // Fundamental matrix of the prediction: x_j^T F x_i = 0 (pixels).
  Eigen::Matrix3d fundamental(size_t i, size_t j) const
  {
    Eigen::Matrix3d Rji, tx;
    Eigen::Vector3d tji;
    relative(i, j, Rji, tji);
    tx << 0, -tji(2), tji(1), tji(2), 0, -tji(0), -tji(1), tji(0), 0;
    return Kinv.transpose() * tx * Rji * Kinv;
  }
  // Fraction of a grid of image i's pixels, at depth z, that camera j sees.
  double overlapOneWay(size_t i, size_t j, double z) const
  {
    Eigen::Matrix3d Rji;
    Eigen::Vector3d tji;
    relative(i, j, Rji, tji);
    int in = 0, n = 0;
    for (int gy = 0; gy < 6; ++gy)
      for (int gx = 0; gx < 8; ++gx, ++n) {
        const Eigen::Vector3d r = Kinv * Eigen::Vector3d((gx + 0.5) * width / 8, (gy + 0.5) * height / 6, 1);
        const Eigen::Vector3d X = Rji * (z * r) + tji;
        if (X(2) <= 0)
          continue;
        const Eigen::Vector3d x = K * (X / X(2));
        in += x(0) >= 0 && x(0) < width && x(1) >= 0 && x(1) < height;
      }
    return static_cast<double>(in) / n;
  }
  double overlap(size_t i, size_t j, double z) const { return std::min(overlapOneWay(i, j, z), overlapOneWay(j, i, z)); }
  // The scene's depth: where the optical axes meet in the least-squares sense, the median distance
  // along the axes; 0 when they do not meet (parallel axes) or the point is behind the cameras.
  double axesDepth() const
  {
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    for (size_t k = 0; k < axis.size(); ++k) {
      const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - axis[k] * axis[k].transpose();
      A += P;
      b += P * centre[k];
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(A / static_cast<double>(axis.size()));
    if (es.eigenvalues()(0) < 1e-3) // the axes span less than about 2 degrees
      return 0;
    const Eigen::Vector3d X = A.ldlt().solve(b);
    std::vector<double> d;
    for (size_t k = 0; k < axis.size(); ++k)
      d.push_back(axis[k].dot(X - centre[k]));
    std::nth_element(d.begin(), d.begin() + static_cast<long>(d.size() / 2), d.end());
    return d[d.size() / 2] > 0 ? d[d.size() / 2] : 0;
  }
  // Depth in camera i of the point matched at pixels a (image i) and b (image j), through the
  // predicted relative pose (midpoint of the two rays); NaN when the rays are (nearly) parallel.
  double triangulateDepth(size_t i, size_t j, const cv::Point2f &a, const cv::Point2f &b) const
  {
    Eigen::Matrix3d Rji;
    Eigen::Vector3d tji;
    relative(i, j, Rji, tji);
    const Eigen::Vector3d ri = Kinv * Eigen::Vector3d(a.x, a.y, 1), dj = Rji.transpose() * (Kinv * Eigen::Vector3d(b.x, b.y, 1));
    const Eigen::Vector3d cj = -Rji.transpose() * tji;
    // s ri - u dj = cj, least squares in (s, u).
    Eigen::Matrix<double, 3, 2> M;
    M.col(0) = ri;
    M.col(1) = -dj;
    const Eigen::Matrix2d N = M.transpose() * M;
    if (std::fabs(N.determinant()) < 1e-12 * N.trace() * N.trace())
      return std::numeric_limits<double>::quiet_NaN();
    const Eigen::Vector2d su = N.ldlt().solve(M.transpose() * cj);
    return su(0) * ri(2);
  }
};

// Distance of pixel x from the line l (a x + b y + c = 0).
double lineDistance(const Eigen::Vector3d &l, double x, double y)
{
  return std::fabs(l(0) * x + l(1) * y + l(2)) / std::max(1e-12, std::hypot(l(0), l(1)));
}

// Symmetric epipolar distance of pixels a (image i) and b (image j) under F (x_j^T F x_i = 0): the
// larger of b's distance from a's line and a's from b's.
double epipolarDistance(const Eigen::Matrix3d &F, const cv::Point2f &a, const cv::Point2f &b)
{
  const Eigen::Vector3d xa(a.x, a.y, 1), xb(b.x, b.y, 1);
  return std::max(lineDistance(F * xa, xb(0), xb(1)), lineDistance(F.transpose() * xb, xa(0), xa(1)));
}

// Squared descriptor distance of feature a of image i and feature b of image j: L2 for SIFT's float
// descriptors, Hamming (squared, to compare as L2's) for ORB's binary ones.
float descriptorDistance2(const Features &f, size_t i, int a, size_t j, int b)
{
  const int len = f.desc[i].cols;
  if (f.desc[i].type() == CV_32F)
    return cv::hal::normL2Sqr_(f.desc[i].ptr<float>(a), f.desc[j].ptr<float>(b), len);
  const float d = static_cast<float>(cv::hal::normHamming(f.desc[i].ptr<uchar>(a), f.desc[j].ptr<uchar>(b), len));
  return d * d;
}

// Guided candidates of pair (i, j) among the features `from` of image i: a feature is compared with
// the features of image j within `band` px of the segment its epipolar line spans over the depths
// [zmin, zmax] (predicted relative pose) and, when F is given (an estimate of this pair's
// fundamental matrix), within `narrow` px of its epipolar line under F; ratio test and mutual best
// match among those candidates.
std::vector<Match> searchGuided(const Features &f, const PriorGeometry &g, size_t i, size_t j, double band,
                                double zmin, double zmax, const std::vector<int> &from, const Eigen::Matrix3d *F,
                                double narrow, const FrontEnd::Options &opt)
{
  Eigen::Matrix3d Rji;
  Eigen::Vector3d tji;
  g.relative(i, j, Rji, tji);
  // Image j's features in cells of `cell` px.
  const double cell = 32, half_diag = cell * 0.7072;
  const int cols = static_cast<int>(std::ceil(g.width / cell)), rows = static_cast<int>(std::ceil(g.height / cell));
  std::vector<std::vector<int>> grid(static_cast<size_t>(cols * rows));
  for (size_t b = 0; b < f.kp[j].size(); ++b) {
    const int cx = std::min(cols - 1, std::max(0, static_cast<int>(f.kp[j][b].pt.x / cell)));
    const int cy = std::min(rows - 1, std::max(0, static_cast<int>(f.kp[j][b].pt.y / cell)));
    grid[static_cast<size_t>(cy * cols + cx)].push_back(static_cast<int>(b));
  }
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<int> best_a(f.kp[j].size(), -1);
  std::vector<float> best_a_d(f.kp[j].size(), inf);
  std::vector<int> best_b(f.kp[i].size(), -1);
  std::vector<float> d1(f.kp[i].size(), inf), d2(f.kp[i].size(), inf);
  const double eps = 1e-3 * zmin;
  for (int a : from) {
    const Eigen::Vector3d xa(f.kp[i][a].pt.x, f.kp[i][a].pt.y, 1);
    const Eigen::Vector3d d = Rji * (g.Kinv * xa);
    // Depths z in [z0, z1] with the point in front of camera j: z d_z + t_z > eps.
    double z0 = zmin, z1 = zmax;
    if (d(2) > 0)
      z0 = std::max(z0, (eps - tji(2)) / d(2));
    else if (d(2) < 0)
      z1 = std::min(z1, (eps - tji(2)) / d(2));
    else if (tji(2) <= eps)
      continue;
    if (!(z1 > z0))
      continue;
    const Eigen::Vector3d X0 = g.K * (z0 * d + tji), X1 = g.K * (z1 * d + tji);
    const Eigen::Vector2d p0(X0(0) / X0(2), X0(1) / X0(2)), p1(X1(0) / X1(2), X1(1) / X1(2));
    const Eigen::Vector2d seg = p1 - p0;
    const double seg2 = seg.squaredNorm();
    auto segmentDistance2 = [&](const Eigen::Vector2d &x) {
      const double s = seg2 > 0 ? std::max(0.0, std::min(1.0, (x - p0).dot(seg) / seg2)) : 0.0;
      return (x - p0 - s * seg).squaredNorm();
    };
    Eigen::Vector3d l = Eigen::Vector3d::Zero();
    if (F) {
      l = *F * xa;
      l /= std::max(1e-12, std::hypot(l(0), l(1)));
    }
    const double ux0 = std::max(0.0, std::min(p0(0), p1(0)) - band), ux1 = std::min(g.width - 1, std::max(p0(0), p1(0)) + band);
    const double uy0 = std::max(0.0, std::min(p0(1), p1(1)) - band), uy1 = std::min(g.height - 1, std::max(p0(1), p1(1)) + band);
    if (ux0 > ux1 || uy0 > uy1)
      continue;
    const int cx0 = static_cast<int>(ux0 / cell), cx1 = std::min(cols - 1, static_cast<int>(ux1 / cell));
    const int cy0 = static_cast<int>(uy0 / cell), cy1 = std::min(rows - 1, static_cast<int>(uy1 / cell));
    for (int cy = cy0; cy <= cy1; ++cy)
      for (int cx = cx0; cx <= cx1; ++cx) {
        const std::vector<int> &members = grid[static_cast<size_t>(cy * cols + cx)];
        if (members.empty())
          continue;
        const Eigen::Vector2d centre((cx + 0.5) * cell, (cy + 0.5) * cell);
        if (segmentDistance2(centre) > (band + half_diag) * (band + half_diag))
          continue;
        if (F && std::fabs(l.dot(Eigen::Vector3d(centre(0), centre(1), 1))) > narrow + half_diag)
          continue;
        for (int b : members) {
          const Eigen::Vector2d x(f.kp[j][b].pt.x, f.kp[j][b].pt.y);
          if (F && std::fabs(l.dot(Eigen::Vector3d(x(0), x(1), 1))) > narrow)
            continue;
          if (segmentDistance2(x) > band * band)
            continue;
          const float dd = descriptorDistance2(f, i, a, j, b);
          if (dd < d1[a]) {
            d2[a] = d1[a];
            d1[a] = dd;
            best_b[a] = b;
          } else if (dd < d2[a])
            d2[a] = dd;
          if (dd < best_a_d[b] || (dd == best_a_d[b] && a < best_a[b])) {
            best_a_d[b] = dd;
            best_a[b] = a;
          }
        }
      }
  }
  const float r2 = static_cast<float>(opt.guided_ratio * opt.guided_ratio),
              r2s = static_cast<float>(opt.ratio * opt.ratio);
  std::vector<Match> out;
  for (int a : from) {
    const int b = best_b[a];
    if (b < 0 || !(d1[a] <= r2 * d2[a]))
      continue;
    // The candidates near the epipolar line are few, so their second nearest is a weak reference:
    // the match must also beat, by the ratio, the distance from either feature to its nearest
    // twin in its own image (a repeated texture would offer that twin in the other image too).
    if (!f.self_nn[i].empty() && !(d1[a] <= r2s * f.self_nn[i][static_cast<size_t>(a)]))
      continue;
    if (!f.self_nn[j].empty() && !(d1[a] <= r2s * f.self_nn[j][static_cast<size_t>(b)]))
      continue;
    if (opt.mutual && best_a[b] != a)
      continue;
    out.push_back({a, b});
  }
  return out;
}

// The guided matches of pair (i, j), verified. Two stages: the `kStrongest` strongest features of
// image i (SIFT's response) are searched in the prior's band; their verified matches estimate the
// pair's fundamental matrix F; then every feature is searched in the band AND within
// 2 ransac_threshold + 1 px of its epipolar line under F (far fewer candidates, the same
// guarantee). When the first stage finds too few, every feature is searched in the band.
std::vector<Match> matchGuided(const Features &f, const PriorGeometry &g, size_t i, size_t j, double band,
                               double zmin, double zmax, const FrontEnd::Options &opt, int seed)
{
  if (f.desc[i].empty() || f.desc[j].empty() || f.kp[i].size() < 8 || f.kp[j].size() < 8)
    return {};
  const size_t kStrongest = 200;
  std::vector<int> all(f.kp[i].size());
  std::iota(all.begin(), all.end(), 0);
  if (all.size() > 2 * kStrongest) {
    std::vector<int> strong = all;
    std::stable_sort(strong.begin(), strong.end(),
                     [&](int a, int b) { return f.kp[i][a].response > f.kp[i][b].response; });
    strong.resize(kStrongest);
    std::sort(strong.begin(), strong.end());
    const std::vector<Match> first =
        verify(searchGuided(f, g, i, j, band, zmin, zmax, strong, nullptr, 0, opt), f.kp[i], f.kp[j], opt, seed);
    if (first.size() >= std::max(opt.min_matches, 15u)) {
      std::vector<cv::Point2f> a, b;
      for (const Match &m : first) {
        a.push_back(f.kp[i][m.first].pt);
        b.push_back(f.kp[j][m.second].pt);
      }
      const cv::Mat Fcv = cv::findFundamentalMat(a, b, cv::FM_8POINT);
      if (Fcv.rows == 3 && Fcv.cols == 3) {
        Eigen::Matrix3d F;
        for (int y = 0; y < 3; ++y)
          for (int x = 0; x < 3; ++x)
            F(y, x) = Fcv.at<double>(y, x);
        return verify(searchGuided(f, g, i, j, band, zmin, zmax, all, &F, 2 * opt.ransac_threshold + 1, opt),
                      f.kp[i], f.kp[j], opt, seed);
      }
    }
  }
  return verify(searchGuided(f, g, i, j, band, zmin, zmax, all, nullptr, 0, opt), f.kp[i], f.kp[j], opt, seed);
}

// Pair selection (see the class): each image's `neighbours` most overlapping images with overlap
// >= min_overlap, then the edges of a maximum spanning forest of the overlaps that join what is
// still apart. Sorted by (i, j).
std::vector<std::pair<size_t, size_t>> selectPairs(const std::vector<std::vector<double>> &O,
                                                   const FrontEnd::Options &opt)
{
  const size_t m = O.size();
  std::set<std::pair<size_t, size_t>> sel;
  for (size_t i = 0; i < m; ++i) {
    std::vector<size_t> others;
    for (size_t j = 0; j < m; ++j)
      if (j != i)
        others.push_back(j);
    std::stable_sort(others.begin(), others.end(), [&](size_t a, size_t b) { return O[i][a] > O[i][b]; });
    for (size_t k = 0; k < others.size() && k < opt.neighbours; ++k)
      if (O[i][others[k]] >= opt.min_overlap)
        sel.insert({std::min(i, others[k]), std::max(i, others[k])});
  }
  UnionFind uf(m);
  for (const auto &p : sel)
    uf.join(p.first, p.second);
  std::vector<std::pair<size_t, size_t>> all;
  for (size_t i = 0; i < m; ++i)
    for (size_t j = i + 1; j < m; ++j)
      all.push_back({i, j});
  std::stable_sort(all.begin(), all.end(), [&](const std::pair<size_t, size_t> &a, const std::pair<size_t, size_t> &b) {
    return O[a.first][a.second] > O[b.first][b.second];
  });
  for (const auto &p : all)
    if (uf.find(p.first) != uf.find(p.second)) {
      uf.join(p.first, p.second);
      sel.insert(p);
    }
  return std::vector<std::pair<size_t, size_t>>(sel.begin(), sel.end());
}

//! The least-squares (8-point) fundamental matrix of matched points, as an Eigen matrix; false when OpenCV gives none.
bool eightPointF(const std::vector<cv::Point2f> &a, const std::vector<cv::Point2f> &b, Eigen::Matrix3d &F)
{
  const cv::Mat Fcv = cv::findFundamentalMat(a, b, cv::FM_8POINT);
  if (Fcv.rows != 3 || Fcv.cols != 3)
    return false;
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x)
      F(y, x) = Fcv.at<double>(y, x);
  return true;
}

/*
  Step 3b, track completion: a track misses the views where its feature was detected but not
  matched (the pair was not selected, or the ratio test lost it). For each track and each image k it
  misses, the epipolar lines in k of the track's features whose images have a fundamental matrix with
  k (the matched pairs' and the shared tracks', estimated from the images) meet where the scene point
  must be; two lines or more, at least 14 degrees apart, are needed. A feature of image k within
  `tolerance` px of every line (and within 8 px of where they meet) joins the track when its
  descriptor is nearer the track's than any other feature's within 8 px by Lowe's ratio
  (guided_ratio), beats by `ratio` its own nearest twin in image k (a repeated texture would offer
  the twin too), and passes the track check's symmetric epipolar test with every feature of it. A
  feature already in another track brings that track along when the two have no image in common and
  every pair of their features with a fundamental matrix agrees within `tolerance` px. The tracks are
  visited in a fixed order, one after the other: the result does not depend on the threads.
*/
void completeTracks(const Features &f, const std::map<std::pair<size_t, size_t>, Eigen::Matrix3d> &F,
                    double tolerance, double ratio, double guided_ratio,
                    std::vector<std::vector<std::pair<size_t, size_t>>> &tracks, FrontEnd::Result &res)
{
  const size_t m = f.kp.size();
  if (m < 3 || tracks.empty())
    return;
  // Dense lookup: Fm[a][k] maps a pixel of image a to its epipolar line in image k (null: unknown).
  std::vector<std::vector<Eigen::Matrix3d>> Fm(m, std::vector<Eigen::Matrix3d>(m));
  std::vector<std::vector<char>> has(m, std::vector<char>(m, 0));
  for (const auto &e : F) {
    const size_t i = e.first.first, j = e.first.second; // x_j^T F x_i = 0
    Fm[i][j] = e.second;
    Fm[j][i] = e.second.transpose();
    has[i][j] = has[j][i] = 1;
  }
  // Each image's features in cells of 16 px, and the track each feature belongs to (-1: none).
  const double cell = 16;
  std::vector<int> cols(m), rows(m);
  std::vector<std::vector<std::vector<int>>> grid(m);
  for (size_t k = 0; k < m; ++k) {
    float w = 1, h = 1;
    for (const cv::KeyPoint &p : f.kp[k]) {
      w = std::max(w, p.pt.x + 1);
      h = std::max(h, p.pt.y + 1);
    }
    cols[k] = static_cast<int>(std::ceil(w / cell));
    rows[k] = static_cast<int>(std::ceil(h / cell));
    grid[k].resize(static_cast<size_t>(cols[k] * rows[k]));
    for (size_t b = 0; b < f.kp[k].size(); ++b)
      grid[k][static_cast<size_t>(static_cast<int>(f.kp[k][b].pt.y / cell) * cols[k] +
                                  static_cast<int>(f.kp[k][b].pt.x / cell))]
          .push_back(static_cast<int>(b));
  }
  std::vector<long> owner(f.offset[m], -1);
  for (size_t t = 0; t < tracks.size(); ++t)
    for (const auto &e : tracks[t])
      owner[f.offset[e.first] + e.second] = static_cast<long>(t);
  auto agree = [&](const std::pair<size_t, size_t> &x, const std::pair<size_t, size_t> &y) {
    return !has[x.first][y.first] ||
           epipolarDistance(Fm[x.first][y.first], f.kp[x.first][x.second].pt, f.kp[y.first][y.second].pt) <= tolerance;
  };
  // Two lines 14 degrees apart or more: for two unit normals the smallest eigenvalue of their mean
  // n n^T is (1 - cos angle) / 2. Within 1 px of both lines the point is then known to about 8 px.
  const double min_spread = 0.5 * (1 - std::cos(14 * M_PI / 180)), reach = 8;
  const float r2 = static_cast<float>(guided_ratio * guided_ratio), r2s = static_cast<float>(ratio * ratio);
  std::vector<Eigen::Vector3d> lines;
  std::vector<char> in(m);
  for (size_t t = 0; t < tracks.size(); ++t) {
    for (bool grew = true; grew && tracks[t].size() >= 2;) {
      grew = false;
      std::fill(in.begin(), in.end(), 0);
      for (const auto &e : tracks[t])
        in[e.first] = 1;
      for (size_t k = 0; k < m; ++k) {
        if (in[k])
          continue;
        lines.clear();
        for (const auto &e : tracks[t])
          if (has[e.first][k]) {
            const cv::Point2f &p = f.kp[e.first][e.second].pt;
            Eigen::Vector3d l = Fm[e.first][k] * Eigen::Vector3d(p.x, p.y, 1);
            const double n = l.head<2>().norm();
            if (n > 0)
              lines.push_back(l / n);
          }
        if (lines.size() < 2)
          continue;
        Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
        Eigen::Vector2d b = Eigen::Vector2d::Zero();
        for (const Eigen::Vector3d &l : lines) {
          A += l.head<2>() * l.head<2>().transpose();
          b -= l(2) * l.head<2>();
        }
        // The lines' spread: the smallest eigenvalue of sum n n^T / count ((1 - cos angle) / 2 for two).
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(A / static_cast<double>(lines.size()));
        if (!(es.eigenvalues()(0) >= min_spread))
          continue;
        const Eigen::Vector2d p = A.ldlt().solve(b);
        if (!p.allFinite() || p(0) < -reach || p(1) < -reach || p(0) > cols[k] * cell + reach ||
            p(1) > rows[k] * cell + reach)
          continue;
        const int c0 = static_cast<int>(std::floor((p(0) - reach) / cell)), c1 = static_cast<int>(std::floor((p(0) + reach) / cell));
        const int r0 = static_cast<int>(std::floor((p(1) - reach) / cell)), r1 = static_cast<int>(std::floor((p(1) + reach) / cell));
        if (c1 < 0 || r1 < 0 || c0 >= cols[k] || r0 >= rows[k])
          continue;
        // The best candidate (near every line), and the two nearest descriptors among all features
        // within reach of p, near the lines or not: Lowe's test compares the best with the nearest
        // other feature of the neighbourhood (the lines alone leave one candidate most of the time).
        float d1 = std::numeric_limits<float>::infinity(), a1 = d1, a2 = d1;
        int best = -1, nearest = -1;
        for (int cy = std::max(0, r0); cy <= std::min(rows[k] - 1, r1); ++cy)
          for (int cx = std::max(0, c0); cx <= std::min(cols[k] - 1, c1); ++cx)
            for (int c : grid[k][static_cast<size_t>(cy * cols[k] + cx)]) {
              const cv::Point2f &x = f.kp[k][static_cast<size_t>(c)].pt;
              if ((Eigen::Vector2d(x.x, x.y) - p).squaredNorm() > reach * reach)
                continue;
              float d = std::numeric_limits<float>::infinity();
              for (const auto &e : tracks[t])
                d = std::min(d, descriptorDistance2(f, e.first, static_cast<int>(e.second), k, c));
              if (d < a1 || (d == a1 && c < nearest)) {
                a2 = a1;
                a1 = d;
                nearest = c;
              } else if (d < a2)
                a2 = d;
              bool near = true;
              for (const Eigen::Vector3d &l : lines)
                near = near && std::fabs(l.dot(Eigen::Vector3d(x.x, x.y, 1))) <= tolerance;
              if (near && (d < d1 || (d == d1 && c < best))) {
                d1 = d;
                best = c;
              }
            }
        const float d2 = best == nearest ? a2 : a1;
        // Strict: a tie (d1 = d2, or d1 equal to the twin's, repeated texture) is not a match.
        if (best < 0 || !(d1 < r2 * d2))
          continue;
        const size_t bk = static_cast<size_t>(best);
        if (!f.self_nn[k].empty() && !(d1 < r2s * f.self_nn[k][bk]))
          continue;
        const long other = owner[f.offset[k] + bk];
        if (other == static_cast<long>(t))
          continue;
        if (other < 0) {
          // The lines only place the search; the feature must pass the track check's own symmetric
          // test with every feature of the track (the distance in both images of each pair).
          bool consistent = true;
          for (const auto &e : tracks[t])
            consistent = consistent && agree(e, {k, bk});
          if (!consistent)
            continue;
          tracks[t].push_back({k, bk});
          owner[f.offset[k] + bk] = static_cast<long>(t);
          in[k] = 1;
          ++res.track_observations_added;
          grew = true;
          continue;
        }
        // Another track: brought along when disjoint and consistent.
        std::vector<std::pair<size_t, size_t>> &u = tracks[static_cast<size_t>(other)];
        bool ok = true;
        for (const auto &y : u)
          ok = ok && !in[y.first];
        for (size_t a = 0; ok && a < tracks[t].size(); ++a)
          for (size_t c = 0; ok && c < u.size(); ++c)
            ok = agree(tracks[t][a], u[c]);
        if (!ok)
          continue;
        for (const auto &y : u) {
          owner[f.offset[y.first] + y.second] = static_cast<long>(t);
          in[y.first] = 1;
          tracks[t].push_back(y);
        }
        ++res.tracks_merged;
        u.clear();
        grew = true;
      }
    }
    std::sort(tracks[t].begin(), tracks[t].end());
  }
}

// Step 3: tracks. The verified matches join their features' tracks pair by pair in the given
// order, unless the two tracks already hold features of a same image; then the tracks of two or
// more images are numbered 0, 1, ... into res.observations.
void buildTracks(const Features &f, const std::vector<std::pair<size_t, size_t>> &pairs,
                 const std::vector<std::vector<Match>> &verified, double tolerance, uint64_t seed, bool complete,
                 double ratio, double guided_ratio, unsigned int threads, FrontEnd::Result &res)
{
  const size_t m = f.kp.size();
  UnionFind uf(f.offset[m]);
  std::vector<std::vector<uint32_t>> images(f.offset[m]); // per root: the images of its track, sorted
  for (size_t k = 0; k < m; ++k)
    for (size_t i = f.offset[k]; i < f.offset[k + 1]; ++i)
      images[i].push_back(static_cast<uint32_t>(k));
  std::vector<uint32_t> merged;
  for (size_t p = 0; p < pairs.size(); ++p)
    for (const Match &mt : verified[p]) {
      const size_t ra = uf.find(f.offset[pairs[p].first] + static_cast<size_t>(mt.first));
      const size_t rb = uf.find(f.offset[pairs[p].second] + static_cast<size_t>(mt.second));
      if (ra == rb)
        continue;
      merged.clear();
      std::set_union(images[ra].begin(), images[ra].end(), images[rb].begin(), images[rb].end(),
                     std::back_inserter(merged));
      if (merged.size() != images[ra].size() + images[rb].size())
        continue; // the tracks share an image: inconsistent
      uf.parent[ra] = rb;
      images[rb].swap(merged);
      std::vector<uint32_t>().swap(images[ra]);
    }
  std::map<size_t, std::vector<std::pair<size_t, size_t>>> comp; // root -> (image, keypoint)
  for (size_t k = 0; k < m; ++k)
    for (size_t i = 0; i < f.kp[k].size(); ++i)
      comp[uf.find(f.offset[k] + i)].push_back({k, i});
  // Each matched pair's fundamental matrix, least squares on its verified matches (x_j^T F x_i = 0).
  std::map<std::pair<size_t, size_t>, Eigen::Matrix3d> F;
  for (size_t p = 0; p < pairs.size(); ++p) {
    if (verified[p].size() < 8)
      continue;
    std::vector<cv::Point2f> a, b;
    for (const Match &mt : verified[p]) {
      a.push_back(f.kp[pairs[p].first][mt.first].pt);
      b.push_back(f.kp[pairs[p].second][mt.second].pt);
    }
    Eigen::Matrix3d E;
    if (eightPointF(a, b, E))
      F[pairs[p]] = E;
  }
  // The pairs of images that were not matched but share tracks: their F from the shared tracks'
  // features (USAC, then least squares on the inliers), so that the check below sees them too.
  {
    std::map<std::pair<size_t, size_t>, std::pair<std::vector<cv::Point2f>, std::vector<cv::Point2f>>> shared;
    for (const auto &c : comp) {
      if (c.second.size() < 3)
        continue;
      for (size_t x = 0; x < c.second.size(); ++x)
        for (size_t y = x + 1; y < c.second.size(); ++y) {
          const std::pair<size_t, size_t> key(c.second[x].first, c.second[y].first);
          if (F.count(key))
            continue;
          auto &sp = shared[key];
          sp.first.push_back(f.kp[key.first][c.second[x].second].pt);
          sp.second.push_back(f.kp[key.second][c.second[y].second].pt);
        }
    }
    // One pair per item (each with its own seed), in parallel; kept in the map's order.
    std::vector<const decltype(shared)::value_type *> list;
    for (const auto &sp : shared)
      if (sp.second.first.size() >= 30)
        list.push_back(&sp);
    std::vector<Eigen::Matrix3d> Fs(list.size());
    std::vector<char> found(list.size(), 0);
    parallelFor(list.size(), threads, [&](size_t q) {
      const auto &sp = *list[q];
      cv::UsacParams up;
      up.threshold = tolerance;
      up.confidence = 0.999;
      up.maxIterations = 10000;
      up.randomGeneratorState = pairSeed(seed, sp.first.first, sp.first.second);
      up.isParallel = false;
      std::vector<unsigned char> inl;
      cv::Mat Fr;
      try {
        Fr = cv::findFundamentalMat(sp.second.first, sp.second.second, inl, up);
      } catch (const cv::Exception &) {
        return;
      }
      if (Fr.empty() || inl.size() != sp.second.first.size())
        return;
      std::vector<cv::Point2f> a, b;
      for (size_t k = 0; k < inl.size(); ++k)
        if (inl[k]) {
          a.push_back(sp.second.first[k]);
          b.push_back(sp.second.second[k]);
        }
      if (a.size() >= 20)
        found[q] = eightPointF(a, b, Fs[q]) ? 1 : 0;
    });
    for (size_t q = 0; q < list.size(); ++q)
      if (found[q])
        F[list[q]->first] = Fs[q];
  }
  // Consistency of a track of three or more views: every two of its features whose images were
  // matched must satisfy that pair's epipolar constraint (a feature that slid along the epipolar
  // line of one pair misses the lines of the others); the feature with the most violations goes,
  // until none is left. The violations are measured once per track; a drop only lowers the counts
  // of the features it violated with. The tracks are independent: in parallel, kept in order.
  std::vector<std::vector<const Eigen::Matrix3d *>> Fp(m, std::vector<const Eigen::Matrix3d *>(m, nullptr));
  for (const auto &e : F)
    Fp[e.first.first][e.first.second] = &e.second;
  std::vector<std::vector<std::pair<size_t, size_t>> *> multi;
  for (auto &c : comp)
    if (c.second.size() >= 3)
      multi.push_back(&c.second);
  std::vector<unsigned int> dropped(multi.size(), 0);
  parallelFor(multi.size(), threads, [&](size_t q) {
    std::vector<std::pair<size_t, size_t>> &obs = *multi[q];
    const size_t n = obs.size();
    std::vector<char> violates(n * n, 0);
    std::vector<unsigned int> bad(n, 0);
    for (size_t x = 0; x < n; ++x)
      for (size_t y = x + 1; y < n; ++y) {
        const Eigen::Matrix3d *Fxy = Fp[obs[x].first][obs[y].first];
        if (Fxy && epipolarDistance(*Fxy, f.kp[obs[x].first][obs[x].second].pt, f.kp[obs[y].first][obs[y].second].pt) >
                       tolerance) {
          violates[x * n + y] = violates[y * n + x] = 1;
          ++bad[x];
          ++bad[y];
        }
      }
    std::vector<size_t> alive(n);
    std::iota(alive.begin(), alive.end(), size_t(0));
    while (alive.size() >= 3) {
      // The first of the remaining features (in their order) with the most violations.
      size_t at = 0;
      for (size_t r = 1; r < alive.size(); ++r)
        if (bad[alive[r]] > bad[alive[at]])
          at = r;
      const size_t drop = alive[at];
      if (bad[drop] == 0)
        break;
      alive.erase(alive.begin() + static_cast<long>(at));
      for (size_t r : alive)
        bad[r] -= violates[drop * n + r];
      ++dropped[q];
    }
    std::vector<std::pair<size_t, size_t>> kept;
    for (size_t r : alive)
      kept.push_back(obs[r]);
    obs.swap(kept);
  });
  for (unsigned int d : dropped)
    res.track_observations_dropped += d;
  std::vector<std::vector<std::pair<size_t, size_t>>> tracks;
  for (auto &c : comp)
    if (c.second.size() >= 2)
      tracks.push_back(std::move(c.second));
  if (complete)
    completeTracks(f, F, tolerance, ratio, guided_ratio, tracks, res);
  res.observations.assign(m, {});
  for (const auto &t : tracks) {
    if (t.size() < 2)
      continue;
    const int id = static_cast<int>(res.num_tracks++);
    if (res.track_lengths.size() <= t.size())
      res.track_lengths.resize(t.size() + 1, 0);
    ++res.track_lengths[t.size()];
    for (const auto &e : t) {
      vpSelfCalibDataset::Observation o;
      o.id = id;
      o.ip = vpImagePoint(f.kp[e.first][e.second].pt.y, f.kp[e.first][e.second].pt.x);
      res.observations[e.first].push_back(o);
    }
  }
}

// Step 2: the pairs to match and their verified matches (see the class), into res's statistics.
void matchImages(const Features &f, const FrontEnd::Options &opt, unsigned int width, unsigned int height,
                 std::vector<std::pair<size_t, size_t>> &pairs, std::vector<std::vector<Match>> &verified,
                 FrontEnd::Result &res)
{
  const size_t m = f.kp.size();
  const unsigned int threads = threadCount(opt);
  auto run = [&](const std::vector<std::pair<size_t, size_t>> &list,
                 const std::function<std::vector<Match>(size_t, size_t)> &candidates) {
    std::vector<std::vector<Match>> out(list.size());
    parallelFor(list.size(), threads, [&](size_t p) {
      const size_t i = list[p].first, j = list[p].second;
      out[p] = verify(candidates(i, j), f.kp[i], f.kp[j], opt, pairSeed(opt.seed, i, j));
    });
    return out;
  };
  auto unguided = [&](size_t i, size_t j) { return matchUnguided(f, i, j, opt); };
  pairs.clear();
  bool done = false;
  if (opt.guided && !opt.prior.empty()) {
    const PriorGeometry g(opt.prior, width, height);
    double depth = opt.prior.depth > 0 ? opt.prior.depth : g.axesDepth();
    if (!(depth > 0)) {
      depth = 1.0;
      res.warnings.push_back("the prior's optical axes do not meet: the scene's depth is taken as 1 m until the "
                             "probe pairs measure it (set the prior's depth)");
    }
    std::vector<std::vector<double>> O(m, std::vector<double>(m, 0));
    for (size_t i = 0; i < m; ++i)
      for (size_t j = i + 1; j < m; ++j)
        O[i][j] = O[j][i] = g.overlap(i, j, depth);
    const std::vector<std::pair<size_t, size_t>> selected = selectPairs(O, opt);
    // Probes, matched without the prior: the selected pairs that overlap (min_overlap) with the
    // largest predicted relative rotation, where an error of the prior's rotations (e.g. of eMc,
    // which conjugates every relative pose) shows most.
    std::vector<std::pair<size_t, size_t>> probes;
    for (const auto &p : selected)
      if (O[p.first][p.second] >= opt.min_overlap)
        probes.push_back(p);
    if (probes.empty())
      probes = selected;
    auto angle = [&](const std::pair<size_t, size_t> &p) {
      Eigen::Matrix3d Rji;
      Eigen::Vector3d tji;
      g.relative(p.first, p.second, Rji, tji);
      return std::acos(std::max(-1.0, std::min(1.0, 0.5 * (Rji.trace() - 1))));
    };
    std::stable_sort(probes.begin(), probes.end(), [&](const std::pair<size_t, size_t> &a, const std::pair<size_t, size_t> &b) {
      return angle(a) > angle(b);
    });
    probes.resize(std::min<size_t>(probes.size(), opt.probes));
    const std::vector<std::vector<Match>> probe_matches = run(probes, unguided);
    // Agreement of the prior with the probes' verified matches, and the depths they triangulate to.
    const double band0 = opt.ransac_threshold;
    unsigned int inside = 0, total = 0, probe_total = 0;
    std::vector<double> depths;
    std::vector<double> bands(probes.size());
    auto bandOf = [&](double z) {
      const double fr = g.f * opt.prior.rotation_sd, ft = g.f * opt.prior.translation_sd / z;
      return 3 * std::sqrt(fr * fr + ft * ft) + band0;
    };
    for (size_t p = 0; p < probes.size(); ++p) {
      const size_t i = probes[p].first, j = probes[p].second;
      const Eigen::Matrix3d F = g.fundamental(i, j);
      const double band = bandOf(depth);
      probe_total += static_cast<unsigned int>(probe_matches[p].size());
      for (const Match &mt : probe_matches[p]) {
        const cv::Point2f &a = f.kp[i][mt.first].pt, &b = f.kp[j][mt.second].pt;
        const double da = lineDistance(F * Eigen::Vector3d(a.x, a.y, 1), b.x, b.y);
        const double db = lineDistance(F.transpose() * Eigen::Vector3d(b.x, b.y, 1), a.x, a.y);
        ++total;
        if (std::max(da, db) < band) {
          ++inside;
          const double z = g.triangulateDepth(i, j, a, b);
          if (std::isfinite(z) && z > 0)
            depths.push_back(z);
        }
      }
    }
    double zmin = depth / 3, zmax = depth * 3;
    if (depths.size() >= 10) {
      std::sort(depths.begin(), depths.end());
      zmin = depths[depths.size() / 20] / 1.3;
      zmax = depths[depths.size() - 1 - depths.size() / 20] * 1.3;
      depth = depths[depths.size() / 2];
    }
    bool accept = true;
    if (total >= opt.min_matches) {
      res.prior_agreement = static_cast<double>(inside) / total;
      if (res.prior_agreement < opt.min_prior_agreement) {
        accept = false;
        std::ostringstream w;
        w << "the kinematic prior disagrees with the images: " << inside << " of " << total
          << " verified matches of the probe pairs lie within the predicted epipolar band (minimum "
          << opt.min_prior_agreement << "); the prior is not used and every pair is matched without it "
          << "(check the robot model, the hand-eye guess eMc and the intrinsics)";
        res.warnings.push_back(w.str());
      }
    } else
      res.warnings.push_back("the probe pairs found too few verified matches (" + std::to_string(total) +
                             ") to check the kinematic prior: it is used unchecked");
    if (accept) {
      std::vector<std::vector<Match>> guided(selected.size());
      parallelFor(selected.size(), threads, [&](size_t p) {
        const size_t i = selected[p].first, j = selected[p].second;
        guided[p] = matchGuided(f, g, i, j, bandOf(depth), zmin, zmax, opt, pairSeed(opt.seed, i, j));
      });
      // The guided search must find at least half of what the unguided one found on the probes.
      unsigned int guided_probe = 0;
      for (size_t p = 0; p < selected.size(); ++p)
        if (std::find(probes.begin(), probes.end(), selected[p]) != probes.end())
          guided_probe += static_cast<unsigned int>(guided[p].size());
      if (total >= opt.min_matches && 2 * guided_probe < probe_total) {
        std::ostringstream w;
        w << "the kinematic prior disagrees with the images: the guided search found " << guided_probe
          << " verified matches on the probe pairs where the unguided search found " << probe_total
          << "; the prior is not used and every pair is matched without it (check the robot model, the "
          << "hand-eye guess eMc and the intrinsics)";
        res.warnings.push_back(w.str());
      } else {
        pairs = selected;
        verified = std::move(guided);
        res.guided = true;
        res.depth_min = zmin;
        res.depth_max = zmax;
        done = true;
      }
    }
    res.fallback = !done;
  }
  if (!done) {
    for (size_t i = 0; i < m; ++i)
      for (size_t j = i + 1; j < m; ++j)
        pairs.push_back({i, j});
    verified = run(pairs, unguided);
  }
  res.pairs_matched = static_cast<unsigned int>(pairs.size());
  res.matches.assign(m, std::vector<unsigned int>(m, 0));
  for (size_t p = 0; p < pairs.size(); ++p)
    res.matches[pairs[p].first][pairs[p].second] = static_cast<unsigned int>(verified[p].size());
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
  std::vector<cv::Mat> masks;
  if (!opt.masks.empty() && opt.masks.size() != 1 && opt.masks.size() != m)
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               "vpFeatureFrontEnd: " + std::to_string(opt.masks.size()) + " masks for " +
                                   std::to_string(m) + " images (give none, one, or one per image)");
  for (size_t k = 0; k < opt.masks.size(); ++k) {
    if (opt.masks[k].getWidth() != images[0].getWidth() || opt.masks[k].getHeight() != images[0].getHeight())
      throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                                 "vpFeatureFrontEnd: mask " + std::to_string(k) + " is " +
                                     std::to_string(opt.masks[k].getWidth()) + " x " +
                                     std::to_string(opt.masks[k].getHeight()) + ", the images " +
                                     std::to_string(images[0].getWidth()) + " x " +
                                     std::to_string(images[0].getHeight()));
    masks.push_back(toMat(opt.masks[k]));
  }
  if (!opt.prior.empty() && opt.prior.fMc.size() != m)
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               "vpFeatureFrontEnd: the prior has " + std::to_string(opt.prior.fMc.size()) +
                                   " camera poses for " + std::to_string(m) + " images");
  Result res;
  const Features features = detectFeatures(mats, masks, opt, res);
  const auto t1 = std::chrono::steady_clock::now();
  res.seconds_detection = std::chrono::duration<double>(t1 - t0).count();
  std::vector<std::pair<size_t, size_t>> pairs;
  std::vector<std::vector<Match>> verified;
  if (opt.features)
    matchImages(features, opt, images[0].getWidth(), images[0].getHeight(), pairs, verified, res);
  else
    res.matches.assign(m, std::vector<unsigned int>(m, 0));
  res.seconds_matching = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  buildTracks(features, pairs, verified, opt.track_tolerance, opt.seed, opt.complete_tracks, opt.ratio,
              opt.guided_ratio, threadCount(opt), res);

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
