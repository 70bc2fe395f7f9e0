/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpMultiViewReconstruction.h
  \brief Scale-consistent camera poses of all views and the scene points, with one focal length (beyond
  the paper: the paper scales each two-view pose separately with the nominal model, eq.
*/
#ifndef VP_MULTI_VIEW_RECONSTRUCTION_H
#define VP_MULTI_VIEW_RECONSTRUCTION_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <map>
#include <string>
#include <vector>

#include <visp3/core/vpColVector.h>
#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>
#include <visp3/selfcalib/vpSelfCalibNoiseModel.h>
#include <visp3/selfcalib/vpTwoViewEstimator.h>

/*!
  \class vpMultiViewReconstruction
  \ingroup group_selfcalib_reconstruction
  \brief Scale-consistent camera poses of all views and the scene points, with one focal length
  (beyond the paper: the paper scales each two-view pose separately with the nominal model, eq. 21).

  1. Two-view poses c_kMc_0 of the pairs (view 0, view k) (vpTwoViewEstimator: RANSAC, the refined
     factor method; f known, or one f shared by all pairs), each with |t_k| = 1, on at most
     max_pair_points correspondences of the pair, evenly spread (the others are tested against
     the pair's fundamental matrix and used from step 2 on).
  2. Scale chaining: the inliers of each pair are triangulated in the frame of view 0 with the unit
     baseline. The reference pair is the one with the widest baseline relative to the scene (the
     smallest median depth); every other pair k gets the scale s_k = median_j |X_j^ref| / |X_j^k| over
     the points both triangulated (a depth seen from camera 0 grows linearly with the baseline).
     Initial points: coordinate-wise median of the scaled triangulations (robust to a wrong match
     in one pair). A point without a usable observation in view 0 (not seen there, or a wrong
     match there) is triangulated from the pair of posed views that most other views agree with
     (reprojection within init_tolerance px), when at least three agree.
  3. Bundle adjustment (Ceres, Schur complement) over the poses of views 1..m-1 (rotations on the
     quaternion manifold), the points in the frame of view 0 and the shared focal length, on the
     reprojection error of every observation, divided by the pixel noise sd. Gauge: view 0 is the
     identity and the reference pair's translation stays on the unit sphere. Robust loss (Cauchy by
     default, scale in noise sd), then the observations whose error exceeds outlier_threshold sd
     are dropped (with the points left with fewer than two observations) and the problem is solved
     again with plain least squares. On large problems the adjustment uses at most
     max_bundle_points points (evenly spread, the yardstick's ends always in): the result starts
     the kinematic bundle adjustment, which uses them all; the others are triangulated from the
     adjusted poses (midpoint of the rays, views beyond the outlier threshold left out; a point
     whose rays meet behind a camera is dropped).
  4. Scale: when both yardstick ends are reconstructed, everything is scaled so that their distance
     is the yardstick's length (metric = true); otherwise the unit of length stays the reference
     baseline.

  Image points are pixels (vpImagePoint: i = v, j = u), the camera model is the pinhole of
  vpTwoViewEstimator (u = u0 + fx x, v = v0 + mu fx y).
*/
class VISP_SELFCALIB_EXPORT vpMultiViewReconstruction
{
public:
  /*!
    The caller's settings of vpMultiViewReconstruction (the defaults are the member initialisers).
    vpRobotSelfCalibration::Options holds these; the two-view options (with the camera) and the
    focal mode, the run's inputs, are added by vpRobotSelfCalibration::multiViewOptions().
  */
  struct Settings {
    unsigned int min_points = 8;    //!< triangulated points a pair needs to be chained
    unsigned int max_pair_points = 300; //!< correspondences per pair for the two-view step (0: all)
    unsigned int max_bundle_points = 400; //!< points in the bundle adjustment (0: all; see step 3)
    double init_tolerance = 10;     //!< px, agreement of views on a point initialized without view 0
    unsigned int max_iterations = 100;
    bool tight = false;             //!< tolerances 1e-15 (exact recovery on noise-free data)
    unsigned int num_threads = 1;       //!< more is faster on large problems, but not bit-reproducible
    void check() const; //!< throws vpSelfCalibException on a setting out of range
  };

  //! What vpMultiViewReconstruction runs with: the settings, the camera and the focal mode.
  struct Options : Settings {
    bool focal_known = true;        //!< false: one f for all views, self-calibrated
    vpTwoViewEstimator::Options twoview; //!< fx (known value or first guess), u0, v0, mu: the camera
    void check() const; //!< Settings::check() and the two-view options'
  };

  enum Status { OK, TOO_FEW_VIEWS, TWO_VIEW_FAILED, NO_CONVERGENCE };
  static const char *statusName(Status s);

  //! The result of vpMultiViewReconstruction: what it computed, and what the caller needs to judge it.
  struct Result {
    Status status = TOO_FEW_VIEWS;
    std::string message;
    std::vector<vpHomogeneousMatrix> cMc0;  //!< per view, c_k M c_0 (view 0: identity)
    std::vector<bool> posed;                //!< views that got a pose (the others are left out)
    std::map<int, vpColVector> points;      //!< id -> 3-vector in the frame of view 0
    unsigned int reference_view = 0;        //!< the view whose pair with view 0 sets the unit before scaling
    bool metric = false;                    //!< scaled by the yardstick: lengths in m
    double yardstick_unit_length = 0;       //!< the yardstick's length in the reference unit (before scaling)
    //! px; fx_sd from the covariance of the final solve, the points marginalized (0 when f is known,
    //! infinite when the information is singular).
    double fx = 0, fx_sd = 0;
    //! Per view, per input point (same order as View::points): used in the final solve. False for
    //! wrong matches, for points that could not be initialized or kept two observations.
    std::vector<std::vector<bool>> inliers;
    unsigned int num_observations = 0, num_outliers = 0;
    double rms = 0;                         //!< px, reprojection RMS over the inliers
    //! rms over the noise model's pixel_sd for the degrees of freedom, and its 99.9 % chi-square interval (0
    //! when there are no degrees of freedom).
    double sigma0 = 0, sigma0_low = 0, sigma0_high = 0;
    //! The image noise measured (measured.pixel_sd, px) from the residuals of every observation, the
    //! rejected ones too (1.4826 x their median absolute value, for the degrees of freedom): right
    //! even when a stated pixel_sd too small rejected good observations (0 without degrees of freedom).
    vpSelfCalibNoiseModel measured = vpSelfCalibNoiseModel::unmeasured();
    std::vector<vpTwoViewEstimator::Result> pairs; //!< pair (0, k) at index k - 1
    double seconds_twoview = 0, seconds_bundle = 0;
  };

  /*!
    Reconstruction of the views (their image points; joints are not used). Throws
    vpSelfCalibException on caller mistakes: fewer than 2 views, a non-finite pixel, an id seen twice
    in one view, nonsense options or noise model. A failure of the data (no pair gives a pose, the
    solver does not converge) is a status. The noise model's image part weighs the residuals (pixel_sd),
    sets the robust loss and the outlier test; its robot part is not used.
  */
  static Result reconstruct(const std::vector<vpSelfCalibDataset::View> &views,
                            const vpSelfCalibDataset::Yardstick &yardstick, const Options &options,
                            const vpSelfCalibNoiseModel &noise);
};

#endif
