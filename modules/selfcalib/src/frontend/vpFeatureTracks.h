/*
 * ViSP SelfCalib: the front end's tracks (private, not installed): the verified matches joined into
 * tracks across views, checked against every pair's epipolar geometry, and completed in the views
 * where their feature was detected but not matched.
 */
#ifndef VP_FEATURE_TRACKS_H
#define VP_FEATURE_TRACKS_H

#include "vpFeatureMatching.h"

#include <cstdint>
#include <utility>
#include <vector>

namespace vpSelfCalib::frontend
{
//! Parameters of buildTracks(), from vpFeatureFrontEnd::Options.
struct TrackOptions {
  double tolerance = 2;       //!< px, the symmetric epipolar distance a track's features must keep (track_tolerance)
  uint64_t seed = 1;          //!< of the fundamental matrices of the pairs that were not matched
  bool complete = true;       //!< complete the tracks (complete_tracks)
  double ratio = 0.8;         //!< Lowe's ratio against a feature's twin in its own image
  double guided_ratio = 0.8;  //!< Lowe's ratio of the completion's candidates
  unsigned int threads = 1;   //!< worker threads; the result does not depend on them
};

/*!
  Step 3 of vpFeatureFrontEnd::process(): tracks. The verified matches join their features' tracks
  pair by pair in the given order, unless the two tracks already hold features of a same image; a
  track of three or more views loses the features that break its pairs' epipolar constraints; the
  tracks are completed (TrackOptions::complete); then the tracks of two or more images are numbered
  0, 1, ... into res.observations (and res's track statistics).
*/
void buildTracks(const Features &f, const std::vector<std::pair<size_t, size_t>> &pairs,
                 const std::vector<std::vector<Match>> &verified, const TrackOptions &opt, FrontEnd::Result &res);
} // namespace vpSelfCalib::frontend

#endif
