/*
 * ViSP SelfCalib: the front end's matching step: pair selection, unguided and kinematics-guided
 * candidate matches, and their geometric verification (vpFundamentalMatrix, OpenCV's USAC).
 */
#include "vpFeatureMatching.h"
#include "vpFeatureTracks.h"

#include <visp3/selfcalib/vpSelfCalibException.h>

#include <visp3/selfcalib/vpFundamentalMatrix.h>

#include "../core/vpSelfCalibMath.h"
#include "../core/vpSelfCalibParallel.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include <Eigen/Dense>

namespace vpSelfCalib::frontend
{
// A pair's own RANSAC seed, from the options' seed and the pair (splitmix64).
int pairSeed(uint64_t seed, size_t i, size_t j)
{
  uint64_t z = seed + 0x9e3779b97f4a7c15ULL * (1 + i * 1000003ULL + j);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return static_cast<int>((z ^ (z >> 31)) & 0x7fffffff);
}

namespace
{
std::vector<vpImagePoint> pixels(const std::vector<cv::Point2f> &p)
{
  std::vector<vpImagePoint> out;
  out.reserve(p.size());
  for (const cv::Point2f &q : p)
    out.emplace_back(q.y, q.x);
  return out;
}
} // namespace

bool fundamentalInliers(const std::vector<cv::Point2f> &a, const std::vector<cv::Point2f> &b, double threshold,
                        int seed, std::vector<bool> &inliers)
{
  vpFundamentalMatrix::Options o;
  o.method = vpFundamentalMatrix::USAC_MSAC;
  o.inlier_threshold = threshold;
  o.confidence = 0.999;
  o.max_iterations = 10000;
  o.seed = static_cast<uint64_t>(seed);
  const vpFundamentalMatrix::Result r = vpFundamentalMatrix::estimate(pixels(a), pixels(b), o);
  if (r.status != vpFundamentalMatrix::OK)
    return false;
  inliers = r.inliers;
  return true;
}

bool leastSquaresFundamental(const std::vector<cv::Point2f> &a, const std::vector<cv::Point2f> &b, Eigen::Matrix3d &F)
{
  vpMatrix M;
  if (!vpFundamentalMatrix::eightPointOpenCV(pixels(a), pixels(b), M))
    return false;
  F = toEigen3(M);
  return true;
}

double lineDistance(const Eigen::Vector3d &l, double x, double y)
{
  return std::fabs(l(0) * x + l(1) * y + l(2)) / std::max(1e-12, std::hypot(l(0), l(1)));
}

double epipolarDistance(const Eigen::Matrix3d &F, const cv::Point2f &a, const cv::Point2f &b)
{
  const Eigen::Vector3d xa(a.x, a.y, 1), xb(b.x, b.y, 1);
  return std::max(lineDistance(F * xa, xb(0), xb(1)), lineDistance(F.transpose() * xb, xa(0), xa(1)));
}

namespace
{
// Geometric verification: the inliers of `cand` under the pair's fundamental matrix
// (fundamentalInliers, ransac_threshold px), or nothing when fewer than min_matches.
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
  std::vector<bool> inl;
  if (!fundamentalInliers(a, b, opt.ransac_threshold, seed, inl))
    return {}; // degenerate configuration: no model
  std::vector<Match> out;
  for (size_t k = 0; k < cand.size(); ++k)
    if (inl[k])
      out.push_back(cand[k]);
  if (out.size() < opt.min_matches)
    return {};
  return out;
}

// The two nearest (distance, index) of a row or a column, the first index of equals first.
struct TwoNearest {
  float d1 = std::numeric_limits<float>::infinity(), d2 = std::numeric_limits<float>::infinity();
  int i1 = -1;
  void add(float d, int i)
  {
    if (d < d1) {
      d2 = d1;
      d1 = d;
      i1 = i;
    } else if (d < d2)
      d2 = d;
  }
};

/*
  Unguided candidates of a pair of SIFT descriptor matrices: the decisions of OpenCV's brute-force
  matcher (two nearest neighbours by L2 both ways, ratio test on the distances, mutual best match)
  from one matrix of distances (cv::batchDistance, the function knnMatch calls, with every pair kept)
  read by rows and by columns, instead of two knnMatch passes that compute each distance twice.
  Scanning in index order with a strict comparison keeps the first index of equal distances, as the
  matcher does.
*/
std::vector<Match> matchUnguidedL2(const cv::Mat &di, const cv::Mat &dj, const FrontEnd::Options &opt)
{
  cv::Mat D; // di.rows x dj.rows
  cv::batchDistance(di, dj, D, CV_32F, cv::noArray(), cv::NORM_L2, 0);
  std::vector<TwoNearest> row(static_cast<size_t>(di.rows)), col(static_cast<size_t>(dj.rows));
  for (int a = 0; a < di.rows; ++a) {
    const float *d = D.ptr<float>(a);
    TwoNearest &ra = row[static_cast<size_t>(a)];
    for (int k = 0; k < dj.rows; ++k) {
      ra.add(d[k], k);
      col[static_cast<size_t>(k)].add(d[k], a);
    }
  }
  std::vector<Match> pairs;
  for (int a = 0; a < di.rows; ++a) {
    const TwoNearest &ra = row[static_cast<size_t>(a)];
    if (ra.i1 < 0 || !std::isfinite(ra.d2) || ra.d1 > opt.ratio * ra.d2)
      continue;
    if (opt.mutual && col[static_cast<size_t>(ra.i1)].i1 != a)
      continue;
    pairs.push_back({a, ra.i1});
  }
  return pairs;
}

// Unguided candidates of a pair: two nearest neighbours, ratio test, mutual best match.
std::vector<Match> matchUnguided(const Features &f, size_t i, size_t j, const FrontEnd::Options &opt)
{
  if (f.desc[i].empty() || f.desc[j].empty() || f.kp[i].size() < 8 || f.kp[j].size() < 8)
    return {};
  if (opt.detector == FrontEnd::SIFT && f.desc[i].type() == CV_32F && f.desc[j].type() == CV_32F)
    return matchUnguidedL2(f.desc[i], f.desc[j], opt);
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
      Eigen::Matrix3d F;
      if (leastSquaresFundamental(a, b, F))
        return verify(searchGuided(f, g, i, j, band, zmin, zmax, all, &F, 2 * opt.ransac_threshold + 1, opt),
                      f.kp[i], f.kp[j], opt, seed);
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

using Pairs = std::vector<std::pair<size_t, size_t>>;

// The verified matches of every pair of `list` (one pair per thread), candidates(i, j) giving each
// pair's candidates.
std::vector<std::vector<Match>> verifyPairs(const Features &f, const FrontEnd::Options &opt, const Pairs &list,
                                            const std::function<std::vector<Match>(size_t, size_t)> &candidates)
{
  std::vector<std::vector<Match>> out(list.size());
  parallelFor(list.size(), threadCount(opt), [&](size_t p) {
    const size_t i = list[p].first, j = list[p].second;
    out[p] = verify(candidates(i, j), f.kp[i], f.kp[j], opt, pairSeed(opt.seed, i, j));
  });
  return out;
}

// Verified matches already found without a prior (the pilot's), by pair.
using Known = std::map<std::pair<size_t, size_t>, std::vector<Match>>;

// The verified matches of every pair of `list` matched without a prior, those of `known` reused (a
// pair's matches do not depend on when it is matched: its RANSAC has its own seed).
std::vector<std::vector<Match>> unguidedPairs(const Features &f, const FrontEnd::Options &opt, const Pairs &list,
                                              const Known &known)
{
  Pairs todo;
  for (const auto &p : list)
    if (!known.count(p))
      todo.push_back(p);
  std::vector<std::vector<Match>> found =
      verifyPairs(f, opt, todo, [&](size_t i, size_t j) { return matchUnguided(f, i, j, opt); });
  std::vector<std::vector<Match>> out;
  size_t t = 0;
  for (const auto &p : list) {
    const auto k = known.find(p);
    out.push_back(k != known.end() ? k->second : std::move(found[t++]));
  }
  return out;
}

//! Features of each image the pilot's reference view is chosen on: the strongest.
const size_t kContentFeatures = 300;

// The pilot's reference view by image content alone (see the class): the kContentFeatures strongest
// features of every image (by detector response) matched without a prior with every other image's
// (ratio test, mutual); the view with the most candidate matches over its pairs, the first of equals.
size_t referenceByContent(const Features &f, const FrontEnd::Options &opt)
{
  const size_t m = f.kp.size();
  Features strong;
  strong.kp.resize(m);
  strong.desc.resize(m);
  for (size_t i = 0; i < m; ++i) {
    std::vector<size_t> order(f.kp[i].size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return f.kp[i][a].response > f.kp[i][b].response; });
    order.resize(std::min(order.size(), kContentFeatures));
    for (size_t k : order) {
      strong.kp[i].push_back(f.kp[i][k]);
      strong.desc[i].push_back(f.desc[i].row(static_cast<int>(k)));
    }
  }
  Pairs all;
  for (size_t i = 0; i < m; ++i)
    for (size_t j = i + 1; j < m; ++j)
      all.push_back({i, j});
  std::vector<size_t> count(all.size(), 0);
  parallelFor(all.size(), threadCount(opt),
              [&](size_t p) { count[p] = matchUnguided(strong, all[p].first, all[p].second, opt).size(); });
  std::vector<size_t> score(m, 0);
  for (size_t p = 0; p < all.size(); ++p) {
    score[all[p].first] += count[p];
    score[all[p].second] += count[p];
  }
  return static_cast<size_t>(std::max_element(score.begin(), score.end()) - score.begin());
}

// The prior measured from a pilot (Options::measure_prior, see the class): the reference view by
// content matched with every other image without a prior, its verified matches (kept in `known`)
// made into tracks (not completed), given to measure_prior. Throws vpSelfCalibException when the
// prior it returns has not one pose per image.
FrontEnd::Prior measurePrior(const Features &f, const FrontEnd::Options &opt, Known &known, FrontEnd::Result &res)
{
  const size_t m = f.kp.size(), r = referenceByContent(f, opt);
  Pairs pairs;
  for (size_t k = 0; k < m; ++k)
    if (k != r)
      pairs.push_back({std::min(r, k), std::max(r, k)});
  const std::vector<std::vector<Match>> verified = unguidedPairs(f, opt, pairs, known);
  res.pilot_reference = static_cast<int>(r);
  for (size_t p = 0; p < pairs.size(); ++p) {
    known[pairs[p]] = verified[p];
    res.pilot_matches += static_cast<unsigned int>(verified[p].size());
  }
  TrackOptions to;
  to.tolerance = opt.track_tolerance;
  to.seed = opt.seed;
  to.complete = false;
  to.ratio = opt.ratio;
  to.guided_ratio = opt.guided_ratio;
  to.threads = threadCount(opt);
  FrontEnd::Result pilot;
  buildTracks(f, pairs, verified, to, pilot);
  FrontEnd::Prior prior = opt.measure_prior(pilot.observations);
  if (!prior.empty() && prior.fMc.size() != m)
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               "vpFeatureFrontEnd: measure_prior returned " + std::to_string(prior.fMc.size()) +
                                   " camera poses for " + std::to_string(m) + " images");
  return prior;
}

// The half-width (px) of the guided search's band at depth z: the prior's uncertainty (3 sd) plus
// ransac_threshold.
double bandOf(const PriorGeometry &g, const FrontEnd::Options &opt, double z)
{
  const double band0 = opt.ransac_threshold;
  const double fr = g.f * opt.prior.rotation_sd, ft = g.f * opt.prior.translation_sd / z;
  return 3 * std::sqrt(fr * fr + ft * ft) + band0;
}

// Probes, matched without the prior: the selected pairs that overlap (min_overlap) with the
// largest predicted relative rotation, where an error of the prior's rotations (e.g. of eMc,
// which conjugates every relative pose) shows most; at most opt.probes of them.
Pairs chooseProbes(const Pairs &selected, const std::vector<std::vector<double>> &O, const PriorGeometry &g,
                   const FrontEnd::Options &opt)
{
  Pairs probes;
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
  return probes;
}

// What the probes' verified matches say of the prior: how many lie inside the predicted band, and
// the depth range they triangulate to.
struct ProbeCheck {
  unsigned int inside = 0, total = 0, probe_total = 0; // in the band, verified matches, and again
  double depth = 0, zmin = 0, zmax = 0;                 // the scene's depth and range
};

ProbeCheck checkProbes(const Features &f, const PriorGeometry &g, const FrontEnd::Options &opt, const Pairs &probes,
                       const std::vector<std::vector<Match>> &probe_matches, double depth)
{
  ProbeCheck c;
  std::vector<double> depths;
  for (size_t p = 0; p < probes.size(); ++p) {
    const size_t i = probes[p].first, j = probes[p].second;
    const Eigen::Matrix3d F = g.fundamental(i, j);
    const double band = bandOf(g, opt, depth);
    c.probe_total += static_cast<unsigned int>(probe_matches[p].size());
    for (const Match &mt : probe_matches[p]) {
      const cv::Point2f &a = f.kp[i][mt.first].pt, &b = f.kp[j][mt.second].pt;
      const double da = lineDistance(F * Eigen::Vector3d(a.x, a.y, 1), b.x, b.y);
      const double db = lineDistance(F.transpose() * Eigen::Vector3d(b.x, b.y, 1), a.x, a.y);
      ++c.total;
      if (std::max(da, db) < band) {
        ++c.inside;
        const double z = g.triangulateDepth(i, j, a, b);
        if (std::isfinite(z) && z > 0)
          depths.push_back(z);
      }
    }
  }
  c.depth = depth;
  c.zmin = depth / 3;
  c.zmax = depth * 3;
  if (depths.size() >= 10) {
    std::sort(depths.begin(), depths.end());
    c.zmin = depths[depths.size() / 20] / 1.3;
    c.zmax = depths[depths.size() - 1 - depths.size() / 20] * 1.3;
    c.depth = depths[depths.size() / 2];
  }
  return c;
}

// Whether the probes agree with the prior (prior_agreement >= min_prior_agreement); res gets the
// agreement and the warnings.
bool priorAgrees(const ProbeCheck &c, const FrontEnd::Options &opt, FrontEnd::Result &res)
{
  if (c.total >= opt.min_matches) {
    res.prior_agreement = static_cast<double>(c.inside) / c.total;
    if (res.prior_agreement < opt.min_prior_agreement) {
      std::ostringstream w;
      w << "the kinematic prior disagrees with the images: " << c.inside << " of " << c.total
        << " verified matches of the probe pairs lie within the predicted epipolar band (minimum "
        << opt.min_prior_agreement << "); the prior is not used and every pair is matched without it "
        << "(check the robot model, the hand-eye guess eMc and the intrinsics)";
      res.warnings.push_back(w.str());
      return false;
    }
  } else
    res.warnings.push_back("the probe pairs found too few verified matches (" + std::to_string(c.total) +
                           ") to check the kinematic prior: it is used unchecked");
  return true;
}

// The kinematics-guided matching (see the class): true with the selected pairs and their verified
// matches, false (res.warnings says why) when the prior disagrees with the images.
bool matchWithPrior(const Features &f, const FrontEnd::Options &opt, unsigned int width, unsigned int height,
                    const Known &known, Pairs &pairs, std::vector<std::vector<Match>> &verified, FrontEnd::Result &res)
{
  const size_t m = f.kp.size();
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
  const Pairs selected = selectPairs(O, opt);
  const Pairs probes = chooseProbes(selected, O, g, opt);
  const std::vector<std::vector<Match>> probe_matches = unguidedPairs(f, opt, probes, known);
  const ProbeCheck c = checkProbes(f, g, opt, probes, probe_matches, depth);
  if (!priorAgrees(c, opt, res))
    return false;
  std::vector<std::vector<Match>> guided(selected.size());
  parallelFor(selected.size(), threadCount(opt), [&](size_t p) {
    const size_t i = selected[p].first, j = selected[p].second;
    guided[p] = matchGuided(f, g, i, j, bandOf(g, opt, c.depth), c.zmin, c.zmax, opt, pairSeed(opt.seed, i, j));
  });
  // The guided search must find at least half of what the unguided one found on the probes.
  unsigned int guided_probe = 0;
  for (size_t p = 0; p < selected.size(); ++p)
    if (std::find(probes.begin(), probes.end(), selected[p]) != probes.end())
      guided_probe += static_cast<unsigned int>(guided[p].size());
  if (c.total >= opt.min_matches && 2 * guided_probe < c.probe_total) {
    std::ostringstream w;
    w << "the kinematic prior disagrees with the images: the guided search found " << guided_probe
      << " verified matches on the probe pairs where the unguided search found " << c.probe_total
      << "; the prior is not used and every pair is matched without it (check the robot model, the "
      << "hand-eye guess eMc and the intrinsics)";
    res.warnings.push_back(w.str());
    return false;
  }
  pairs = selected;
  verified = std::move(guided);
  res.guided = true;
  res.depth_min = c.zmin;
  res.depth_max = c.zmax;
  return true;
}
} // namespace

void matchImages(const Features &f, const FrontEnd::Options &opt, unsigned int width, unsigned int height,
                 Pairs &pairs, std::vector<std::vector<Match>> &verified, FrontEnd::Result &res)
{
  const size_t m = f.kp.size();
  pairs.clear();
  bool done = false;
  Known known;
  FrontEnd::Options measured;
  const FrontEnd::Options *use = &opt;
  if (opt.guided && opt.prior.empty() && opt.measure_prior && m >= 3) {
    measured = opt;
    measured.prior = measurePrior(f, opt, known, res);
    measured.check();
    use = &measured;
  }
  if (use->guided && !use->prior.empty()) {
    done = matchWithPrior(f, *use, width, height, known, pairs, verified, res);
    res.fallback = !done;
  }
  if (!done) {
    for (size_t i = 0; i < m; ++i)
      for (size_t j = i + 1; j < m; ++j)
        pairs.push_back({i, j});
    verified = unguidedPairs(f, opt, pairs, known);
  }
  res.pairs_matched = static_cast<unsigned int>(pairs.size());
  res.matches.assign(m, std::vector<unsigned int>(m, 0));
  for (size_t p = 0; p < pairs.size(); ++p)
    res.matches[pairs[p].first][pairs[p].second] = static_cast<unsigned int>(verified[p].size());
}
} // namespace vpSelfCalib::frontend
