/*
 * The truth behind the front end's tracks on rendered images (tests and bench-frontend): each
 * observation's scene point is where its pixel's ray meets the rendered scene through the true
 * camera (vpSelfCalibRenderer::surfacePoint); the candidate that most of the track's observations
 * agree with (within 2 px) picks them, and the track's point is triangulated from those through
 * the true cameras (rays' least-squares point: the features' own localisation noise is not
 * counted against the track). An observation is correct when it lies within `tolerance` px of that
 * point's projection through the true camera.
 */
#ifndef SELFCALIB_FRONT_END_TRUTH_H
#define SELFCALIB_FRONT_END_TRUTH_H

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include <visp3/core/vpMatrix.h>
#include <visp3/selfcalib/vpFeatureFrontEnd.h>
#include <visp3/selfcalib/vpSelfCalibRenderer.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

struct FrontEndTruth {
  unsigned int tracks = 0, correct_tracks = 0; //!< correct track: every observation correct
  unsigned int long_tracks = 0, correct_long_tracks = 0; //!< the same for the tracks of 3 views or more
  unsigned int observations = 0, correct = 0;  //!< track observations (yardstick excluded)
  double median_length = 0;                    //!< views per track
  double observationFraction() const { return observations ? static_cast<double>(correct) / observations : 0; }
  double trackFraction() const { return tracks ? static_cast<double>(correct_tracks) / tracks : 0; }
  double longTrackFraction() const { return long_tracks ? static_cast<double>(correct_long_tracks) / long_tracks : 0; }
};

inline FrontEndTruth checkTracks(const vpSelfCalibSimulator &sim, const vpSelfCalibRenderer &renderer,
                                 const std::vector<vpColVector> &q, const vpFeatureFrontEnd::Result &fe,
                                 double tolerance = 1.0)
{
  const vpCameraParameters cam = sim.getCamera();
  std::vector<vpHomogeneousMatrix> cMf;
  for (const vpColVector &qk : q)
    cMf.push_back(sim.getTrueChain().get_fMc(qk).inverse());
  std::map<int, std::vector<std::pair<size_t, vpImagePoint>>> tracks;
  for (size_t k = 0; k < fe.observations.size(); ++k)
    for (const vpSelfCalibDataset::Observation &o : fe.observations[k])
      if (o.id >= 0 && o.id < static_cast<int>(fe.num_tracks))
        tracks[o.id].push_back({k, o.ip});
  auto error = [&](const vpColVector &X, size_t k, const vpImagePoint &ip) {
    vpColVector Xh(4, 1);
    for (unsigned int a = 0; a < 3; ++a)
      Xh[a] = X[a];
    const vpColVector c = cMf[k] * Xh;
    if (c[2] <= 0)
      return 1e9;
    return std::hypot(cam.get_u0() + cam.get_px() * c[0] / c[2] - ip.get_u(),
                      cam.get_v0() + cam.get_py() * c[1] / c[2] - ip.get_v());
  };
  // The point closest to the rays of the observations in `use` (true cameras).
  auto triangulate = [&](const std::vector<std::pair<size_t, vpImagePoint>> &obs, const std::vector<bool> &use) {
    vpMatrix A(3, 3, 0.0);
    vpColVector b(3, 0.0);
    for (size_t i = 0; i < obs.size(); ++i) {
      if (!use[i])
        continue;
      const vpHomogeneousMatrix fMc = cMf[obs[i].first].inverse();
      vpColVector d(3), c(3);
      const double x = (obs[i].second.get_u() - cam.get_u0()) / cam.get_px(),
                   y = (obs[i].second.get_v() - cam.get_v0()) / cam.get_py();
      for (unsigned int r = 0; r < 3; ++r) {
        d[r] = fMc[r][0] * x + fMc[r][1] * y + fMc[r][2];
        c[r] = fMc[r][3];
      }
      d.normalize();
      vpMatrix P(3, 3);
      P.eye();
      P -= d * d.t();
      A += P;
      b += P * c;
    }
    return vpColVector(A.pseudoInverse() * b);
  };
  FrontEndTruth t;
  std::vector<double> lengths;
  for (const auto &tr : tracks) {
    unsigned int best = 0;
    std::vector<bool> agree(tr.second.size(), false);
    for (const auto &cand : tr.second) {
      vpColVector X;
      if (!renderer.surfacePoint(q[cand.first], cand.second, X))
        continue;
      std::vector<bool> in(tr.second.size());
      unsigned int n = 0;
      for (size_t i = 0; i < tr.second.size(); ++i)
        n += (in[i] = error(X, tr.second[i].first, tr.second[i].second) < 2 * tolerance);
      if (n > best) {
        best = n;
        agree = in;
      }
    }
    if (best >= 2) {
      const vpColVector X = triangulate(tr.second, agree);
      best = 0;
      for (const auto &o : tr.second)
        best += error(X, o.first, o.second) < tolerance;
    } else
      best = std::min<unsigned int>(best, 1); // one observation agrees with itself
    ++t.tracks;
    t.observations += static_cast<unsigned int>(tr.second.size());
    t.correct += best;
    t.correct_tracks += best == tr.second.size();
    if (tr.second.size() >= 3) {
      ++t.long_tracks;
      t.correct_long_tracks += best == tr.second.size();
    }
    lengths.push_back(static_cast<double>(tr.second.size()));
  }
  if (!lengths.empty()) {
    std::sort(lengths.begin(), lengths.end());
    t.median_length = lengths[lengths.size() / 2];
  }
  return t;
}

#endif
