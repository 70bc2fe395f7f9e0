/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpTwoViewEstimator.h
  \brief The paper's pose measurement (Section 3.1) on pixel correspondences between two images of one
  camera: fundamental matrix (normalized 8-point in RANSAC), focal length from F, factor method,
  refined nonlinear factor method.
*/
#ifndef VP_TWO_VIEW_ESTIMATOR_H
#define VP_TWO_VIEW_ESTIMATOR_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <string>
#include <vector>

#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/core/vpImagePoint.h>
#include <visp3/core/vpMatrix.h>
#include <visp3/selfcalib/vpFundamentalMatrix.h>
#include <visp3/selfcalib/vpRefinedFactorMethod.h>

/*!
  \class vpTwoViewEstimator
  \ingroup group_selfcalib_twoview
  \brief The paper's pose measurement (Section 3.1) on pixel correspondences between two images of
  one camera: fundamental matrix (normalized 8-point in RANSAC), focal length from F, factor method,
  refined nonlinear factor method.

  Pose convention of the paper: c2Mc1 = [R t], X2 = R X1 + t, |t| = 1.

  Before the fundamental matrix is trusted, a homography (OpenCV findHomography, classic RANSAC:
  deterministic with OpenCV's fixed internal seed, not ransac.seed; USAC called most of the main
  job's pairs planar) is fitted to
  the same points. When it keeps at least planar_ratio times as many inliers as the fundamental
  matrix (or F does not exist: a plane makes the 8-point system rank-deficient), the pair is
  - PURE_ROTATION if A^-1 H A is a rotation (no translation: the pose is R only, t = 0), or
  - PLANAR otherwise. With a known focal length the pose is still returned, from OpenCV's five-point
    solver (findEssentialMat + recoverPose, valid for planes) refined with the known f (that RANSAC is
    OpenCV's classic one, deterministic with its fixed internal seed, not ransac.seed: OpenCV 4.6's
    USAC essential matrix fails on planes); with the focal
    length unknown no pose is returned (f is not observable from two views of a plane).
*/
class VISP_SELFCALIB_EXPORT vpTwoViewEstimator
{
public:
  enum Status { OK, TOO_FEW_POINTS, PURE_ROTATION, PLANAR, FOCAL_UNOBSERVABLE, NO_CONVERGENCE };
  static const char *statusName(Status s);

  /*!
    The caller's settings of vpTwoViewEstimator (the defaults are the member initialisers): how the
    pair is estimated, whatever the camera. vpRobotSelfCalibration::Options holds these; the camera
    and the focal mode, the run's inputs, are added by vpRobotSelfCalibration::twoViewOptions().
  */
  struct Settings {
    //! The fundamental matrix's RANSAC; its seed also seeds, in vpMultiViewReconstruction, the
    //! PnP resection's USAC.
    vpFundamentalMatrix::Options ransac;
    bool refine = true;            //!< run the refined nonlinear factor method
    double huber = 0;              //!< px, robust loss of the refinement (0: plain least squares)
    double planar_ratio = 0.95;    //!< share of F inliers a homography must explain to call the pair planar
    double min_coplanarity = 1e-3; //!< see vpFocalFromFundamental
    double rotation_tolerance = 1e-3; //!< max |singular value - 1| of A^-1 H A for a pure rotation
    //! PER_PAIR: a refined f_x whose standard deviation exceeds this fraction of f_x makes the pair
    //! FOCAL_UNOBSERVABLE (pose and f_x are kept for information). Near-meeting optical axes give
    //! sd of hundreds of pixels while the closed form still returns a number.
    double max_fx_relative_sd = 0.05;
    void check() const; //!< throws vpSelfCalibException on a setting out of range
  };

  //! What vpTwoViewEstimator runs with: the settings and the camera (the defaults are the member initialisers).
  struct Options : Settings {
    vpRefinedFactorMethod::FocalMode focal_mode = vpRefinedFactorMethod::PER_PAIR; //!< PER_PAIR or KNOWN here
    double fx = 1000;   //!< known value (KNOWN) or initial guess (px)
    double u0 = 320, v0 = 240, mu = 1;
    void check() const; //!< Settings::check() and the camera's
  };

  //! The result of vpTwoViewEstimator: what it computed, and what the caller needs to judge it.
  struct Result {
    Status status = TOO_FEW_POINTS;
    std::string message;
    vpHomogeneousMatrix c2Mc1; //!< R, t (|t| = 1; t = 0 for a pure rotation)
    double fx = 0;             //!< focal used for the pose (0 if the closed form could not estimate it)
    double fx_sd = 0;          //!< sd of fx (px) from the refinement's covariance; infinite if singular
    vpMatrix F;                //!< fundamental matrix (pixels), when estimated
    std::vector<bool> inliers;
    unsigned int num_inliers = 0;
    double rms = 0;            //!< RMS symmetric epipolar distance over the inliers (px)
    bool hasPose() const { return status == OK || status == PURE_ROTATION || (status == PLANAR && fx > 0); }
  };

  /*!
    One pair. Throws vpSelfCalibException on caller mistakes (lists of different sizes, non-finite
    pixels, nonsense options); everything else is a status.
  */
  static Result estimate(const std::vector<vpImagePoint> &p1, const std::vector<vpImagePoint> &p2,
                         const Options &options);

  //! What estimateShared() returns: the shared focal length and each pair's pose.
  struct SharedResult {
    bool converged = false;
    std::string message;
    double fx = 0, fx_sd = 0;
    std::vector<Result> pairs; //!< per pair; pairs that could not be initialized keep their status
  };
  /*!
    Many pairs of the same camera, one focal length estimated over all of them jointly
    (vpRefinedFactorMethod SHARED). The initial f is the median of the per-pair closed-form
    estimates that succeeded, else options.fx.
  */
  static SharedResult estimateShared(const std::vector<std::vector<vpImagePoint>> &p1,
                                     const std::vector<std::vector<vpImagePoint>> &p2, const Options &options);
};

#endif
