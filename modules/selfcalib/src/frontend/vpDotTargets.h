/*
 * ViSP SelfCalib: the front end's dot targets (private, not installed): dot grids (vpDotGrid) and
 * the yardstick's two dots, found in the images beside the natural features. The calibration
 * boards are vpBoardDetector's.
 */
#ifndef VP_DOT_TARGETS_H
#define VP_DOT_TARGETS_H

#include <visp3/selfcalib/vpFeatureFrontEnd.h>

#include <vector>

#include <opencv2/core.hpp>

namespace vpSelfCalib::frontend
{
//! A dark round blob measured by vpDot2.
struct Dot {
  cv::Point2f centre;
  float radius; //!< sqrt(area / pi)
  float major;  //!< semi-major axis of the ellipse of the same moments: the dot's size without foreshortening
};

/*!
  Step 4 of vpFeatureFrontEnd::process(), one image (I, and img its OpenCV copy): every dot of a
  recognised grid of opt.dot_grids gets the grid's id for its place (into observations,
  grid_seen[g][k] set); returns the dots left over, candidates for the yardstick. The grids' dots
  differ in size: a grid is a run of the dots sorted by size, as long as the grid, with a jump in
  size at both ends; the runs with the largest jumps are tried first.
*/
std::vector<Dot> findGrids(const vpImage<unsigned char> &I, const cv::Mat &img, const vpFeatureFrontEnd::Options &opt,
                           std::vector<vpSelfCalibDataset::Observation> &observations,
                           std::vector<std::vector<bool>> &grid_seen, size_t k);

/*!
  Step 5: the yardstick, two loose dots in an image (`loose`, one list per image), the smaller is
  end a; ids after the tracks' (res.num_tracks, + 1) when seen in two images or more, into
  res.observations and res.yardstick_*.
*/
void findYardstick(const std::vector<std::vector<Dot>> &loose, vpFeatureFrontEnd::Result &res);
} // namespace vpSelfCalib::frontend

#endif
