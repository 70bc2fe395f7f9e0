/*
 * ViSP SelfCalib: the front end's matching step (private, not installed): the pairs of images to
 * match, their candidate matches (unguided, or guided by a kinematic prior) and their geometric
 * verification by a fundamental matrix.
 */
#ifndef VP_FEATURE_MATCHING_H
#define VP_FEATURE_MATCHING_H

#include "vpFeatureDetection.h"

#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace vpSelfCalib::frontend
{
using Match = std::pair<int, int>; //!< (feature in image i, feature in image j)

//! Disjoint sets with path halving: the pair selection's components and the tracks.
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

//! A pair's own RANSAC seed, from the options' seed and the pair (splitmix64).
int pairSeed(uint64_t seed, size_t i, size_t j);

/*!
  The inliers of the fundamental matrix of matched pixels a (image i) -> b (image j) by
  vpFundamentalMatrix with OpenCV's USAC (USAC_MSAC: confidence 0.999, at most 10000 samples,
  sequential), inlier threshold in px, seeded; false when it finds no matrix.
*/
bool fundamentalInliers(const std::vector<cv::Point2f> &a, const std::vector<cv::Point2f> &b, double threshold,
                        int seed, std::vector<bool> &inliers);

/*!
  The least-squares fundamental matrix of matched pixels a (image i) -> b (image j),
  x_j^T F x_i = 0, by vpFundamentalMatrix::eightPointOpenCV(); false when there is none.
*/
bool leastSquaresFundamental(const std::vector<cv::Point2f> &a, const std::vector<cv::Point2f> &b, Eigen::Matrix3d &F);

//! Distance of pixel (x, y) from the line l (a x + b y + c = 0).
double lineDistance(const Eigen::Vector3d &l, double x, double y);

/*!
  Symmetric epipolar distance of pixels a (image i) and b (image j) under F (x_j^T F x_i = 0): the
  larger of b's distance from a's line and a's from b's.
*/
double epipolarDistance(const Eigen::Matrix3d &F, const cv::Point2f &a, const cv::Point2f &b);

/*!
  Step 2 of vpFeatureFrontEnd::process(): the pairs to match (sorted by (i, j)) and their verified
  matches (see the class), into res's statistics (pairs_matched, matches, and with a prior
  prior_agreement, guided, fallback, the depth range and warnings).
*/
void matchImages(const Features &f, const FrontEnd::Options &opt, unsigned int width, unsigned int height,
                 std::vector<std::pair<size_t, size_t>> &pairs, std::vector<std::vector<Match>> &verified,
                 FrontEnd::Result &res);
} // namespace vpSelfCalib::frontend

#endif
