/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpFundamentalMatrix.h
  \brief Fundamental matrix between two images of pixel correspondences (paper eq.
*/
#ifndef VP_FUNDAMENTAL_MATRIX_H
#define VP_FUNDAMENTAL_MATRIX_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <cstdint>
#include <string>
#include <vector>

#include <visp3/core/vpImagePoint.h>
#include <visp3/core/vpMatrix.h>

/*!
  \class vpFundamentalMatrix
  \ingroup group_selfcalib_twoview
  \brief Fundamental matrix between two images of pixel correspondences (paper eq. 3: m2^T F m1 = 0,
  m1 in image 1, m2 in image 2, homogeneous pixels).

  - eightPoint(): Hartley's normalized 8-point algorithm (centroid at the origin, mean distance
    sqrt(2)), null vector by SVD (Eigen; ViSP's svd is wrong for the wide 8 x 9 system), rank 2
    enforced by zeroing the smallest singular value. The minimal solver and the estimator on all
    points are the same function.
  - sampsonDistance(): first-order geometric error in pixels.
  - estimate(): the 8-point inside RANSAC (seeded sampler, adaptive iteration count), then a
    re-estimate on all inliers; or, with Options::method USAC_MSAC, OpenCV's USAC.
  - eightPointOpenCV(): OpenCV's least-squares 8-point on all the given correspondences.

  The image front end (vpFeatureFrontEnd) verifies its matches with USAC_MSAC and fits its
  epipolar checks with eightPointOpenCV(): its tracks were tuned on OpenCV's estimators, which differ
  from this class's own in their sampler, score and normalisation (see Method).
*/
class VISP_SELFCALIB_EXPORT vpFundamentalMatrix
{
public:
  /*!
    How estimate() searches. The two give different matrices and inlier sets on the same data: USAC
    scores a model by the truncated sum of its errors (MSAC) rather than its inlier count, refines
    the best models inside the loop (local optimisation), draws its samples from OpenCV's own
    generator, and has its own error measure and degeneracy tests.
  */
  enum Method {
    RANSAC_8POINT, //!< this class's RANSAC around eightPoint(), Sampson distance, re-estimate on all inliers
    /*!
      OpenCV's USAC (findFundamentalMat with cv::UsacParams: MSAC score, inner local optimisation,
      sequential), threshold inlier_threshold in OpenCV's own error, random generator state the low
      31 bits of seed; the points go to OpenCV as floats (USAC computes in float anyway). F as OpenCV
      gives it (scaled to F(2,2) = 1), inliers its mask; Result::iterations is 0 (OpenCV does not
      say). Fewer than 8 correspondences (distinct or not) is TOO_FEW_POINTS, no matrix DEGENERATE.
    */
    USAC_MSAC
  };

  //! Settings of vpFundamentalMatrix (the defaults are the member initialisers).
  struct Options {
    Method method = RANSAC_8POINT;
    double inlier_threshold = 1.0;  //!< px, Sampson distance
    double confidence = 0.999;      //!< probability of drawing one outlier-free sample
    unsigned int max_iterations = 5000;
    uint64_t seed = 1;              //!< of the sampler: same seed, same result; another seed, other samples
    void check() const; //!< throws vpSelfCalibException on nonsense
  };

  enum Status { OK, TOO_FEW_POINTS, DEGENERATE };

  //! The result of vpFundamentalMatrix: what it computed, and what the caller needs to judge it.
  struct Result {
    Status status = DEGENERATE;
    std::string message;
    vpMatrix F;                 //!< 3 x 3, Frobenius norm 1, rank 2
    std::vector<bool> inliers;  //!< one per correspondence
    unsigned int num_inliers = 0;
    unsigned int iterations = 0;
    double rms_sampson = 0;     //!< px, over the inliers
  };

  /*!
    Normalized 8-point on the given correspondences (8 or more). Returns false when the system is
    degenerate (fewer than 8 distinct points, all points coincident, rank deficiency).
  */
  static bool eightPoint(const std::vector<vpImagePoint> &p1, const std::vector<vpImagePoint> &p2, vpMatrix &F);
  /*!
    OpenCV's 8-point (findFundamentalMat, FM_8POINT) on all the given correspondences (8 or more;
    the points go to OpenCV as floats, as OpenCV reads them): its own Hartley normalisation, the
    null vector of the normal equations, rank 2 by SVD, F scaled to F(2,2) = 1. Not the same
    digits as eightPoint() (which takes the null vector of the system itself by SVD and scales F to
    norm 1). False when OpenCV gives no 3 x 3 matrix.
  */
  static bool eightPointOpenCV(const std::vector<vpImagePoint> &p1, const std::vector<vpImagePoint> &p2, vpMatrix &F);
  static double sampsonDistance(const vpMatrix &F, const vpImagePoint &p1, const vpImagePoint &p2);
  /*!
    RANSAC estimate. Throws vpSelfCalibException when the two lists differ in size or hold a
    non-finite coordinate; fewer than 8 distinct correspondences is Status TOO_FEW_POINTS.
  */
  static Result estimate(const std::vector<vpImagePoint> &p1, const std::vector<vpImagePoint> &p2,
                         const Options &options);
  //! Number of correspondences that are pairwise distinct (in both images).
  static unsigned int countDistinct(const std::vector<vpImagePoint> &p1, const std::vector<vpImagePoint> &p2);
  //! Throws vpSelfCalibException on size mismatch or non-finite coordinates.
  static void checkCorrespondences(const std::vector<vpImagePoint> &p1, const std::vector<vpImagePoint> &p2,
                                   const char *where);
};

#endif
