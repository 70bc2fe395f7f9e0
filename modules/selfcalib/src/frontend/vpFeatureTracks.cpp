/*
 * ViSP SelfCalib: the front end's tracks: the verified matches joined across views, the epipolar
 * check of every track, and the completion of the tracks in the views that missed them.
 */
#include "vpFeatureTracks.h"

#include "../core/vpSelfCalibParallel.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <map>

#include <Eigen/Dense>

namespace vpSelfCalib::frontend
{
namespace
{
using Track = std::vector<std::pair<size_t, size_t>>;                         // (image, keypoint)
using FundamentalMap = std::map<std::pair<size_t, size_t>, Eigen::Matrix3d>; // (i, j): x_j^T F x_i = 0
using Components = std::map<size_t, Track>;                                  // union-find root -> its features

// The verified matches join their features' tracks pair by pair in the given order, unless the two
// tracks already hold features of a same image: every feature's track (one per union-find root,
// single features included).
Components joinMatches(const Features &f, const std::vector<std::pair<size_t, size_t>> &pairs,
                       const std::vector<std::vector<Match>> &verified)
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
  Components comp; // root -> (image, keypoint)
  for (size_t k = 0; k < m; ++k)
    for (size_t i = 0; i < f.kp[k].size(); ++i)
      comp[uf.find(f.offset[k] + i)].push_back({k, i});
  return comp;
}

// Each matched pair's fundamental matrix, least squares on its verified matches (x_j^T F x_i = 0).
FundamentalMap pairFundamentals(const Features &f, const std::vector<std::pair<size_t, size_t>> &pairs,
                                const std::vector<std::vector<Match>> &verified)
{
  FundamentalMap F;
  for (size_t p = 0; p < pairs.size(); ++p) {
    if (verified[p].size() < 8)
      continue;
    std::vector<cv::Point2f> a, b;
    for (const Match &mt : verified[p]) {
      a.push_back(f.kp[pairs[p].first][mt.first].pt);
      b.push_back(f.kp[pairs[p].second][mt.second].pt);
    }
    Eigen::Matrix3d E;
    if (leastSquaresFundamental(a, b, E))
      F[pairs[p]] = E;
  }
  return F;
}

// The pairs of images that were not matched but share tracks (30 features or more): their F from
// the shared tracks' features (USAC at `tolerance` px, then least squares on 20 inliers or more),
// so that the track check sees them too. One pair per item (each with its own seed), in parallel;
// kept in the map's order.
void addSharedFundamentals(const Features &f, const Components &comp, double tolerance, uint64_t seed,
                           unsigned int threads, FundamentalMap &F)
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
  std::vector<const decltype(shared)::value_type *> list;
  for (const auto &sp : shared)
    if (sp.second.first.size() >= 30)
      list.push_back(&sp);
  std::vector<Eigen::Matrix3d> Fs(list.size());
  std::vector<char> found(list.size(), 0);
  parallelFor(list.size(), threads, [&](size_t q) {
    const auto &sp = *list[q];
    std::vector<bool> inl;
    if (!fundamentalInliers(sp.second.first, sp.second.second, tolerance,
                            pairSeed(seed, sp.first.first, sp.first.second), inl))
      return;
    std::vector<cv::Point2f> a, b;
    for (size_t k = 0; k < inl.size(); ++k)
      if (inl[k]) {
        a.push_back(sp.second.first[k]);
        b.push_back(sp.second.second[k]);
      }
    if (a.size() >= 20)
      found[q] = leastSquaresFundamental(a, b, Fs[q]) ? 1 : 0;
  });
  for (size_t q = 0; q < list.size(); ++q)
    if (found[q])
      F[list[q]->first] = Fs[q];
}

// Consistency of a track of three or more views: every two of its features whose images have a
// fundamental matrix must satisfy that pair's epipolar constraint (a feature that slid along the
// epipolar line of one pair misses the lines of the others); the feature with the most violations
// goes, until none is left. The violations are measured once per track; a drop only lowers the
// counts of the features it violated with. The tracks are independent: in parallel, kept in order.
// Returns the number of features dropped.
unsigned int dropInconsistent(const Features &f, const FundamentalMap &F, Components &comp, double tolerance,
                              unsigned int threads)
{
  const size_t m = f.kp.size();
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
  unsigned int total = 0;
  for (unsigned int d : dropped)
    total += d;
  return total;
}

// The tracks of two or more images numbered 0, 1, ... into res.observations, with the histogram
// of their lengths.
void numberTracks(const Features &f, const std::vector<Track> &tracks, FrontEnd::Result &res)
{
  const size_t m = f.kp.size();
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

// What the track completion looks up: the epipolar map of every two images, each image's features
// in cells of 16 px, and the track each feature belongs to.
struct Completion {
  const Features &f;
  size_t m;
  double tolerance;
  float r2, r2s;              // squared guided_ratio and ratio
  const double cell = 16;     // px
  const double reach = 8;     // px around the lines' meeting point
  const double min_spread;    // of the lines' normals (see meetingPoint)
  //! Fm[a][k] maps a pixel of image a to its epipolar line in image k (where has[a][k]).
  std::vector<std::vector<Eigen::Matrix3d>> Fm;
  std::vector<std::vector<char>> has;
  std::vector<int> cols, rows;
  std::vector<std::vector<std::vector<int>>> grid;
  std::vector<long> owner; //!< per feature (union-find numbering): its track, -1 none

  Completion(const Features &features, const FundamentalMap &F, const std::vector<Track> &tracks, double tol,
             double ratio, double guided_ratio)
    : f(features), m(features.kp.size()), tolerance(tol), r2(static_cast<float>(guided_ratio * guided_ratio)),
      r2s(static_cast<float>(ratio * ratio)), min_spread(0.5 * (1 - std::cos(14 * M_PI / 180))),
      Fm(m, std::vector<Eigen::Matrix3d>(m)), has(m, std::vector<char>(m, 0)), cols(m), rows(m), grid(m),
      owner(features.offset[m], -1)
  {
    for (const auto &e : F) {
      const size_t i = e.first.first, j = e.first.second; // x_j^T F x_i = 0
      Fm[i][j] = e.second;
      Fm[j][i] = e.second.transpose();
      has[i][j] = has[j][i] = 1;
    }
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
    for (size_t t = 0; t < tracks.size(); ++t)
      for (const auto &e : tracks[t])
        owner[f.offset[e.first] + e.second] = static_cast<long>(t);
  }

  //! The track check's symmetric epipolar test of two features (image, keypoint).
  bool agree(const std::pair<size_t, size_t> &x, const std::pair<size_t, size_t> &y) const
  {
    return !has[x.first][y.first] ||
           epipolarDistance(Fm[x.first][y.first], f.kp[x.first][x.second].pt, f.kp[y.first][y.second].pt) <= tolerance;
  }

  /*!
    Where track t's point must be in image k: the least-squares meeting point p of the epipolar
    lines (unit normals, into `lines`) of its features whose images have a fundamental matrix with
    k. False when there are fewer than two lines, they are less than 14 degrees apart (for two unit
    normals the smallest eigenvalue of their mean n n^T is (1 - cos angle) / 2; within 1 px of both
    lines the point is then known to about 8 px), or p is off the image by more than `reach`.
  */
  bool meetingPoint(const Track &t, size_t k, std::vector<Eigen::Vector3d> &lines, Eigen::Vector2d &p) const
  {
    lines.clear();
    for (const auto &e : t)
      if (has[e.first][k]) {
        const cv::Point2f &x = f.kp[e.first][e.second].pt;
        Eigen::Vector3d l = Fm[e.first][k] * Eigen::Vector3d(x.x, x.y, 1);
        const double n = l.head<2>().norm();
        if (n > 0)
          lines.push_back(l / n);
      }
    if (lines.size() < 2)
      return false;
    Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
    Eigen::Vector2d b = Eigen::Vector2d::Zero();
    for (const Eigen::Vector3d &l : lines) {
      A += l.head<2>() * l.head<2>().transpose();
      b -= l(2) * l.head<2>();
    }
    // The lines' spread: the smallest eigenvalue of sum n n^T / count ((1 - cos angle) / 2 for two).
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(A / static_cast<double>(lines.size()));
    if (!(es.eigenvalues()(0) >= min_spread))
      return false;
    p = A.ldlt().solve(b);
    return p.allFinite() && !(p(0) < -reach || p(1) < -reach || p(0) > cols[k] * cell + reach ||
                              p(1) > rows[k] * cell + reach);
  }

  /*!
    The feature of image k that joins track t, near its meeting point p and within `tolerance` px
    of every line: the best candidate (near every line), compared by Lowe's test (guided_ratio) with
    the nearest other feature within reach of p, near the lines or not (the lines alone leave one
    candidate most of the time), and beating its own nearest twin in image k by `ratio`; -1 when
    none passes.
  */
  int candidate(const Track &t, size_t k, const std::vector<Eigen::Vector3d> &lines, const Eigen::Vector2d &p) const
  {
    const int c0 = static_cast<int>(std::floor((p(0) - reach) / cell)), c1 = static_cast<int>(std::floor((p(0) + reach) / cell));
    const int r0 = static_cast<int>(std::floor((p(1) - reach) / cell)), r1 = static_cast<int>(std::floor((p(1) + reach) / cell));
    if (c1 < 0 || r1 < 0 || c0 >= cols[k] || r0 >= rows[k])
      return -1;
    float d1 = std::numeric_limits<float>::infinity(), a1 = d1, a2 = d1;
    int best = -1, nearest = -1;
    for (int cy = std::max(0, r0); cy <= std::min(rows[k] - 1, r1); ++cy)
      for (int cx = std::max(0, c0); cx <= std::min(cols[k] - 1, c1); ++cx)
        for (int c : grid[k][static_cast<size_t>(cy * cols[k] + cx)]) {
          const cv::Point2f &x = f.kp[k][static_cast<size_t>(c)].pt;
          if ((Eigen::Vector2d(x.x, x.y) - p).squaredNorm() > reach * reach)
            continue;
          float d = std::numeric_limits<float>::infinity();
          for (const auto &e : t)
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
      return -1;
    if (!f.self_nn[k].empty() && !(d1 < r2s * f.self_nn[k][static_cast<size_t>(best)]))
      return -1;
    return best;
  }

  /*!
    Feature (k, bk), in no track, joins track t when it passes the track check's own symmetric
    test with every feature of the track (the lines only place the search).
  */
  bool join(std::vector<Track> &tracks, size_t t, size_t k, size_t bk, std::vector<char> &in, FrontEnd::Result &res)
  {
    bool consistent = true;
    for (const auto &e : tracks[t])
      consistent = consistent && agree(e, {k, bk});
    if (!consistent)
      return false;
    tracks[t].push_back({k, bk});
    owner[f.offset[k] + bk] = static_cast<long>(t);
    in[k] = 1;
    ++res.track_observations_added;
    return true;
  }

  //! Track `other` is brought along into track t when the two have no image in common and agree.
  bool merge(std::vector<Track> &tracks, size_t t, size_t other, std::vector<char> &in, FrontEnd::Result &res)
  {
    Track &u = tracks[other];
    bool ok = true;
    for (const auto &y : u)
      ok = ok && !in[y.first];
    for (size_t a = 0; ok && a < tracks[t].size(); ++a)
      for (size_t c = 0; ok && c < u.size(); ++c)
        ok = agree(tracks[t][a], u[c]);
    if (!ok)
      return false;
    for (const auto &y : u) {
      owner[f.offset[y.first] + y.second] = static_cast<long>(t);
      in[y.first] = 1;
      tracks[t].push_back(y);
    }
    ++res.tracks_merged;
    u.clear();
    return true;
  }
};

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
void completeTracks(const Features &f, const FundamentalMap &F, double tolerance, double ratio, double guided_ratio,
                    std::vector<Track> &tracks, FrontEnd::Result &res)
{
  const size_t m = f.kp.size();
  if (m < 3 || tracks.empty())
    return;
  Completion c(f, F, tracks, tolerance, ratio, guided_ratio);
  std::vector<Eigen::Vector3d> lines;
  std::vector<char> in(m);
  Eigen::Vector2d p;
  for (size_t t = 0; t < tracks.size(); ++t) {
    for (bool grew = true; grew && tracks[t].size() >= 2;) {
      grew = false;
      std::fill(in.begin(), in.end(), 0);
      for (const auto &e : tracks[t])
        in[e.first] = 1;
      for (size_t k = 0; k < m; ++k) {
        if (in[k] || !c.meetingPoint(tracks[t], k, lines, p))
          continue;
        const int best = c.candidate(tracks[t], k, lines, p);
        if (best < 0)
          continue;
        const size_t bk = static_cast<size_t>(best);
        const long other = c.owner[f.offset[k] + bk];
        if (other == static_cast<long>(t))
          continue;
        if (other < 0)
          grew = c.join(tracks, t, k, bk, in, res) || grew;
        else
          grew = c.merge(tracks, t, static_cast<size_t>(other), in, res) || grew;
      }
    }
    std::sort(tracks[t].begin(), tracks[t].end());
  }
}
} // namespace

void buildTracks(const Features &f, const std::vector<std::pair<size_t, size_t>> &pairs,
                 const std::vector<std::vector<Match>> &verified, const TrackOptions &opt, FrontEnd::Result &res)
{
  Components comp = joinMatches(f, pairs, verified);
  FundamentalMap F = pairFundamentals(f, pairs, verified);
  addSharedFundamentals(f, comp, opt.tolerance, opt.seed, opt.threads, F);
  res.track_observations_dropped += dropInconsistent(f, F, comp, opt.tolerance, opt.threads);
  std::vector<Track> tracks;
  for (auto &c : comp)
    if (c.second.size() >= 2)
      tracks.push_back(std::move(c.second));
  if (opt.complete)
    completeTracks(f, F, opt.tolerance, opt.ratio, opt.guided_ratio, tracks, res);
  numberTracks(f, tracks, res);
}
} // namespace vpSelfCalib::frontend
