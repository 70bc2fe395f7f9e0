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

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/core/vpImage.h>
#include <visp3/selfcalib/vpDotGrid.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>

/*!
  \class vpFeatureFrontEnd
  \ingroup group_selfcalib_frontend
  \brief Correspondences across views from images of a natural scene, and the yardstick's dots.

  1. Features: OpenCV SIFT (default) or ORB, at most max_features per image, outside the masked
     regions (Options::masks), one image per thread.
  2. Matching, one pair per thread. Without a prior (Options::prior empty or Options::guided off):
     every pair of images, two nearest neighbours (L2 for SIFT, Hamming for ORB), Lowe's ratio test,
     mutual best match. With a prior (each image's predicted camera pose, e.g. nominal forward
     kinematics and the nominal eMc, and the intrinsics), kinematics-guided:
     - the scene's rough depth: where the predicted optical axes meet (least squares), unless
       Prior::depth gives it;
     - pair selection: each pair's predicted overlap (a grid of image i's pixels at that depth,
       seen from camera j, both ways, the smaller fraction); each image is matched with its
       `neighbours` most overlapping images (overlap >= min_overlap), plus the pairs of a maximum
       spanning tree of the overlaps, so that every image is connected;
     - probes: the `probes` selected pairs (overlap >= min_overlap) with the largest predicted
       relative rotation (where an error of eMc shows most) are first matched without the prior;
       their verified matches measure how far the prior's epipolar geometry is from the images
       (Result::prior_agreement, the fraction of them inside the predicted band) and give the
       scene's depth range (triangulated through the predicted poses);
     - guided search: a feature of image i is compared only with the features of image j within
       `band` px of the segment of its epipolar line that the depth range spans (predicted F,
       the band inflated by the prior's uncertainty: 3 sqrt((f sd_R)^2 + (f sd_t / depth)^2) for the
       relative pose, plus ransac_threshold), ratio test (guided_ratio) and mutual best match among
       those; the match must also beat, by `ratio`, each feature's nearest twin in its own image
       (distinctiveness: the second nearest of a few candidates is a weak reference, and a
       repeated texture would offer the twin in the other image too). In two stages: the 400 strongest features of image i first, whose verified matches
       estimate the pair's F; then every feature, within the band and within
       2 ransac_threshold + 1 px of its epipolar line under that F;
     - a prior measured from the images (Options::measure_prior, when Options::prior is empty): a
       pilot first, matched without any prior: the reference view, the one whose 300 strongest
       features find the most candidate matches (ratio test, mutual) among the other images'
       strongest (image content alone), matched with every other image; its verified matches
       become tracks (not completed), which measure_prior turns into a prior (e.g. the camera's
       motions against the robot's: vpSelfCalibImageCorrespondences). That prior then guides the
       matching as a given one does (probes and checks included); the pilot's verified matches are
       reused wherever the same pair is matched without a prior (probes, fallback). An empty
       measured prior: every pair unguided;
     - fallback: when the prior disagrees with the images (prior_agreement < min_prior_agreement,
       or the guided search finds fewer than half the probes' unguided matches on the probe pairs),
       every pair is matched without the prior and Result::warnings says why.
     Then geometric verification: the fundamental matrix by vpFundamentalMatrix with OpenCV's USAC
     (vpFundamentalMatrix::USAC_MSAC, ransac_threshold px, seeded from Options::seed and the
     pair); a pair with fewer than min_matches verified matches is left out.
  3. Tracks: the verified matches, pair by pair in a fixed order, join their features' tracks
     unless the two tracks already hold features of a same image (a track holds at most one
     feature per image). Then each track of three views or more is checked: two of its features
     whose images were matched, or share 30 tracks or more, must lie within track_tolerance px of
     each other's epipolar lines (the pair's F, least squares on its verified matches or on the
     USAC inliers of the shared tracks' features); the feature with the most violations
     leaves the track until none is left (a feature that slid along one pair's epipolar line
     misses the others'). Then, unless Options::complete_tracks is off, each track is completed: in
     every image it misses, the epipolar lines of its features (two or more, 14 degrees apart or
     more, from the pairs' fundamental matrices) meet where its point must be; the feature there
     (within track_tolerance px of every line, 8 px of their meeting point) whose descriptor is
     nearer the track's than any other feature's within 8 px by guided_ratio, beats its own nearest
     twin by `ratio` and passes the track check with every feature of the track joins it, or brings
     its own track along when the two share no image and agree with every pair's epipolar
     geometry. SIFT re-detects a point in several views that the pairwise matching missed
     (not selected pairs, ratio tests lost), and a point split in two tracks is joined. Every track
     seen in two or more images becomes a scene point id (0, 1, ...).
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
  order OpenCV's parallel detection returns them in; every pair's RANSAC has its own seed and the
  pairs' matches are merged in a fixed order: the same images and options give the same tracks
  whatever Options::threads (tested with 1 and 2).

  Statistics for the report (Result): features per image, the verified matches of every pair
  (Result::matches, an m x m matrix, upper triangle: a matrix image of it shows which views are
  connected), the track-length histogram (Result::track_lengths), where the yardstick was found,
  whether the prior guided the matching and the warnings.
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

  /*!
    What the robot predicts about the views (step 2): each image's camera pose in a common frame
    (fMc, e.g. nominal forward kinematics times the nominal eMc, or the controller's flange pose
    times eMc; vpSelfCalibImageCorrespondences::makePrior builds it from a dataset and a model) and
    the intrinsics. The sd are those of a predicted RELATIVE pose between two views (the nominal
    model's error, not the noise of one pose). Empty fMc: no prior.
  */
  struct Prior {
    std::vector<vpHomogeneousMatrix> fMc; //!< per image, or empty
    vpCameraParameters cam;               //!< px, py, u0, v0 (distortion ignored)
    double rotation_sd = 0.005;           //!< rad, sd of a predicted relative rotation
    double translation_sd = 0.005;        //!< m, sd of a predicted relative translation
    double depth = 0;                     //!< m, rough scene depth; 0: where the optical axes meet
    bool empty() const { return fMc.empty(); }
  };

  //! Settings of vpFeatureFrontEnd (the defaults are the member initialisers).
  struct Options {
    bool features = true;            //!< natural features (steps 1-3)
    std::vector<DotGrid> dot_grids;  //!< dot targets to find (step 4)
    Detector detector = SIFT;
    unsigned int max_features = 2000;
    double ratio = 0.8;              //!< Lowe's ratio test
    //! Lowe's ratio in the guided search, against the second nearest candidate near the epipolar
    //! line; the match must also beat, by `ratio`, each feature's nearest twin in its own image
    //! (the few candidates near the line are a weak reference alone).
    double guided_ratio = 0.8;
    //! px: two features of a track whose images were matched must lie within it of each other's
    //! epipolar lines (the pair's F); otherwise the feature with the most violations leaves the track.
    double track_tolerance = 1.0;
    //! Track completion (step 3b): each track is looked for in the images it misses, where the
    //! epipolar lines of its features meet (the pairs' fundamental matrices estimated from the
    //! images), by descriptor; off: the tracks are the verified matches' only.
    bool complete_tracks = true;
    bool mutual = true;              //!< keep mutual best matches only
    double ransac_threshold = 1.0;   //!< px, fundamental-matrix RANSAC
    unsigned int min_matches = 20;   //!< verified matches a pair needs
    double contrast_threshold = 0.04; //!< SIFT's contrast threshold (OpenCV's default)
    //! Where features may be detected (non-zero pixels, OpenCV's convention): none (everywhere),
    //! one mask for every image, or one per image, each of the images' size. Dots are looked for
    //! everywhere.
    std::vector<vpImage<unsigned char>> masks;
    Prior prior;                      //!< kinematic prior (step 2); empty: every pair, unguided
    /*!
      A prior measured from the images (step 2), used when `prior` is empty and `guided` is on: it is
      given the pilot's observations (per image, tracks of the reference view with every other, ids
      0, 1, ...) and returns the prior that guides the matching (empty: every pair unguided).
      Unset: no pilot.
    */
    std::function<Prior(const std::vector<std::vector<vpSelfCalibDataset::Observation>> &pilot)> measure_prior;
    bool guided = true;               //!< use the prior when there is one
    unsigned int neighbours = 8;      //!< guided: images each image is matched with, most overlapping first
    double min_overlap = 0.25;        //!< guided: predicted overlap a neighbour needs (0-1)
    unsigned int probes = 3;          //!< guided: pairs matched without the prior to check it
    double min_prior_agreement = 0.8; //!< guided: below, the prior is rejected (fallback; 0.63 for eMc 10 deg off, 1.0 for the nominal model on rendered images)
    unsigned int threads = 0;         //!< worker threads; 0: cv::getNumThreads(). Results do not depend on it
    uint64_t seed = 1;                //!< RANSAC's seed (combined with each pair's indices)
    bool yardstick = true;           //!< detect the yardstick's dots
    double dot_min_radius = 2.5;     //!< px
    double dot_max_radius = 40;      //!< px
    void check() const;
  };

  //! The result of vpFeatureFrontEnd: what it computed, and what the caller needs to judge it.
  struct Result {
    //! Per image, the observations with their scene point ids (tracks, then the yardstick's ends).
    std::vector<std::vector<vpSelfCalibDataset::Observation>> observations;
    unsigned int num_tracks = 0;
    int yardstick_a = -1, yardstick_b = -1; //!< ids of the ends, -1 when not found in two images
    std::vector<unsigned int> features;     //!< per image
    //! Match-count matrix: matches[i][j], i < j, the verified matches of pair (i, j) (0 if left out
    //! or not matched); m x m, the lower triangle and the diagonal are 0.
    std::vector<std::vector<unsigned int>> matches;
    //! Track-length histogram: track_lengths[n] tracks seen in n images (n >= 2).
    std::vector<unsigned int> track_lengths;
    unsigned int pairs_matched = 0;  //!< pairs whose matching was attempted
    unsigned int track_observations_dropped = 0; //!< features taken out of tracks by the consistency check
    unsigned int track_observations_added = 0;   //!< features of no track added to one by the completion (step 3b)
    unsigned int tracks_merged = 0;              //!< tracks joined to another (whole) by the completion
    bool guided = false;             //!< the prior guided the matching (false: none, or fallback)
    bool fallback = false;           //!< a prior was given and rejected (see warnings)
    //! Options::measure_prior ran: the pilot's reference view (-1: no pilot) and its verified matches.
    int pilot_reference = -1;
    unsigned int pilot_matches = 0;
    double prior_agreement = -1;     //!< fraction of the probes' unguided matches inside the predicted band (-1: not measured)
    double depth_min = 0, depth_max = 0; //!< guided: scene depth range used (m)
    //! What the caller should tell the user (the prior rejected and why, masks ignored...).
    std::vector<std::string> warnings;
    std::vector<bool> yardstick_seen;        //!< per image
    std::vector<std::vector<bool>> grid_seen; //!< per dot grid, per image
    double seconds = 0;
    double seconds_detection = 0, seconds_matching = 0; //!< of which: step 1, step 2
  };

  //! Throws vpSelfCalibException with fewer than 2 images, images of different sizes, masks or a
  //! prior of the wrong size, or bad options.
  static Result process(const std::vector<vpImage<unsigned char>> &images, const Options &options);

  /*!
    A dataset whose views have images but no points: reads every view's image (vpImageIo), checks
    its size against the dataset's camera, adds the views' own masks (viewMasks()), runs process()
    and fills the observations; the
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

  /*!
    The masks the front end runs with on a dataset's views: `masks` (none, one for every view, or
    one per view: Options::masks) and each view's own mask file (vpSelfCalibDataset::View::mask)
    combined: a pixel is searched where both allow it (non-zero in both). Without any view mask,
    `masks` unchanged; else one mask per view (all 255 for a view with neither). Each mask file is
    checked as the images are (the file, its header, its size against the camera's): a missing,
    unreadable or wrongly sized one throws vpSelfCalibException starting with `who`, naming the
    view and the file.
  */
  static std::vector<vpImage<unsigned char>> viewMasks(const vpSelfCalibDataset &dataset,
                                                       const std::vector<vpImage<unsigned char>> &masks,
                                                       const std::string &who = "vpFeatureFrontEnd");

  /*!
    One image file read as grey (a mask, a texture), checked as the dataset's images are before it
    is decoded: a regular file of at most 256 MiB whose header gives a size that is decoded (not a
    directory, a device, a FIFO or a decompression bomb). Throws vpSelfCalibException (ioError)
    whose message is `context`, ": " and the reason.
  */
  static vpImage<unsigned char> readImage(const std::string &file, const std::string &context);
};

#endif
