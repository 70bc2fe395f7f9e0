/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpFeatureFrontEnd.h
  \brief Correspondences across views from images of a natural scene, and the yardstick's dots.
*/
#ifndef VP_FEATURE_FRONT_END_H
#define VP_FEATURE_FRONT_END_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <string>
#include <vector>

#include <visp3/core/vpImage.h>
#include <visp3/selfcalib/vpDotGrid.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>

/*!
  \class vpFeatureFrontEnd
  \ingroup group_selfcalib_frontend
  \brief Correspondences across views from images of a natural scene, and the yardstick's dots.

  1. Features: OpenCV SIFT (default) or ORB, at most max_features per image.
  2. Matching of every pair of images: two nearest neighbours (L2 for SIFT, Hamming for ORB), Lowe's
     ratio test, mutual best match, then geometric verification: OpenCV's RANSAC fundamental matrix
     (ransac_threshold px); a pair with fewer than min_matches verified matches is left out.
  3. Tracks: union-find over the verified matches; a track that holds two features of one image is
     inconsistent and dropped; every track seen in two or more images becomes a scene point id
     (0, 1, ...).
  4. Dot targets (the paper's experiment), when Options::dot_grids lists them: dark round dots on a
     white surround (below, measured by vpDot2), sorted by size (the semi-major axis of their
     ellipse, which foreshortening leaves alone): a grid is a run of as many dots as it has, with a
     jump in size (over 10%) at both ends, so the grids' dots must differ in size from each other's
     and from the yardstick's; the run is ordered by OpenCV's findCirclesGrid (asymmetric grid). Dot k of grid g gets the id dot_grids[g].first_id + k in
     every image: the dots are matched across views by their place in the grid, which assumes the
     target is seen with the same side up in every view (within about 45 degrees of roll; the
     asymmetric grid has no 180-degree symmetry with an odd number of rows, but OpenCV orders it
     from the image). The grids' numbers of dots must differ.
  5. Yardstick: dark round dots on a white surround (round connected components of the dark pixels
     with a white ring around them, then measured by ViSP's vpDot2: centre of gravity and area), two
     per image; the smaller is end a, the larger end b (radius ratio at least 1.2); their centres
     get the ids num_tracks and num_tracks + 1.

  Reproducibility: keypoints are sorted after detection, so the result does not depend on the
  order OpenCV's parallel detection returns them in; the same images and the same OpenCV thread
  count (cv::setNumThreads) give the same tracks. visp-selfcalib uses one thread by default.

  Statistics for the report: features per image, verified matches per pair, the track-length
  histogram, where the yardstick was found.
*/
class VISP_SELFCALIB_EXPORT vpFeatureFrontEnd
{
public:
  enum Detector { SIFT, ORB };
  static const char *detectorName(Detector d);
  //! "sift" or "orb"; throws vpSelfCalibException otherwise.
  static Detector detectorFromName(const std::string &name);

  //! An asymmetric circle grid to find (OpenCV's layout, see vpDotGrid): the caller describes it,
  //! from the target it printed or, in simulation, from vpSelfCalibRenderer::getDotGrids().
  using DotGrid = vpDotGrid;

  struct Options {
    bool features = true;            //!< natural features (steps 1-3)
    std::vector<DotGrid> dot_grids;  //!< dot targets to find (step 4)
    Detector detector = SIFT;
    unsigned int max_features = 2000;
    double ratio = 0.8;              //!< Lowe's ratio test
    bool mutual = true;              //!< keep mutual best matches only
    double ransac_threshold = 1.0;   //!< px, fundamental-matrix RANSAC
    unsigned int min_matches = 20;   //!< verified matches a pair needs
    bool yardstick = true;           //!< detect the yardstick's dots
    double dot_min_radius = 2.5;     //!< px
    double dot_max_radius = 40;      //!< px
    void check() const;
  };

  struct Result {
    //! Per image, the observations with their scene point ids (tracks, then the yardstick's ends).
    std::vector<std::vector<vpSelfCalibDataset::Observation>> observations;
    unsigned int num_tracks = 0;
    int yardstick_a = -1, yardstick_b = -1; //!< ids of the ends, -1 when not found in two images
    std::vector<unsigned int> features;     //!< per image
    std::vector<std::vector<unsigned int>> matches; //!< verified matches of pair (i, j), i < j (0 if left out)
    std::vector<unsigned int> track_lengths; //!< histogram: track_lengths[n] tracks seen in n images
    std::vector<bool> yardstick_seen;        //!< per image
    std::vector<std::vector<bool>> grid_seen; //!< per dot grid, per image
    double seconds = 0;
  };

  //! Throws vpSelfCalibException with fewer than 2 images, images of different sizes, or bad options.
  static Result process(const std::vector<vpImage<unsigned char>> &images, const Options &options);

  /*!
    A dataset whose views have images but no points: reads every view's image (vpImageIo), checks
    its size against the dataset's camera, runs process() and fills the observations; the
    yardstick's ends get the ids of the dots found (its length stays the dataset's). Throws
    vpSelfCalibException naming the view and the file when an image is missing, unreadable or of
    another size, or when a view has no image.
  */
  static Result fillDataset(vpSelfCalibDataset &dataset, const Options &options);

  /*!
    The images of a dataset's views (grey), checked: a view without an image, an unreadable file or
    an image of another size than the camera's throws vpSelfCalibException, the message starting
    with `who` and the view's index.
  */
  static std::vector<vpImage<unsigned char>> readImages(const vpSelfCalibDataset &dataset,
                                                        const std::string &who = "vpFeatureFrontEnd");
};

#endif
