/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpRefinedFactorMethod.h
  \brief The paper's refined nonlinear factor method (eqs.
*/
#ifndef VP_REFINED_FACTOR_METHOD_H
#define VP_REFINED_FACTOR_METHOD_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <string>
#include <vector>

#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/core/vpImagePoint.h>

/*!
  \class vpRefinedFactorMethod
  \ingroup group_selfcalib_twoview
  \brief The paper's refined nonlinear factor method (eqs. 12-13): the symmetric epipolar distance

      sum_i d(m2_i, Q m1_i)^2 + d(m1_i, Q^T m2_i)^2,   Q = A^-T [t]x R A^-1,

  minimized over f_x, R and t (|t| = 1) with Ceres: automatic derivatives, R on the quaternion
  manifold, t on the unit sphere, Levenberg-Marquardt, started from the factor method. Each point
  contributes the residual (m2^T Q m1) sqrt(1 / (l2_1^2 + l2_2^2) + 1 / (l1_1^2 + l1_2^2)) with
  l2 = Q m1, l1 = Q^T m2, whose square is the pair of squared point-to-epipolar-line distances.

  Focal modes: PER_PAIR (the paper: f_x estimated with each pair), KNOWN (f_x fixed), SHARED (one f_x
  for many pairs of the same camera, estimated jointly with every pair's R, t; this keeps focal
  self-calibration working when each pair alone is degenerate). mu and the principal point are
  known, as in the paper (eq. 8).

  Deviation from the paper: the paper's A (eq. 8) has no principal point (image coordinates centred
  beforehand); here A = [[f_x, 0, u0], [0, mu f_x, v0], [0, 0, 1]] takes pixels directly.
*/
class VISP_SELFCALIB_EXPORT vpRefinedFactorMethod
{
public:
  enum FocalMode { PER_PAIR, KNOWN, SHARED };

  //! Settings of vpRefinedFactorMethod (the defaults are the member initialisers).
  struct Options {
    FocalMode focal_mode = PER_PAIR;
    double u0 = 0, v0 = 0, mu = 1;
    double huber = 0;                 //!< px; > 0 applies a Huber loss to the epipolar distances
    unsigned int max_iterations = 500;
    bool tight = true;                //!< tolerances 1e-15 (exact recovery); false: Ceres' defaults
    void check() const;
  };

  //! One image pair: inlier correspondences and an initial c2Mc1 (|t| = 1).
  struct Pair {
    std::vector<vpImagePoint> p1, p2;
    vpHomogeneousMatrix c2Mc1;
  };

  //! The result of vpRefinedFactorMethod: what it computed, and what the caller needs to judge it.
  struct Result {
    bool converged = false;
    std::string message;
    std::vector<vpHomogeneousMatrix> c2Mc1; //!< refined, one per pair, |t| = 1
    double fx = 0, fx_sd = 0;                //!< fx_sd from the covariance (0 when fx is known)
    std::vector<double> rms;                 //!< per pair, RMS symmetric epipolar distance (px)
    unsigned int iterations = 0;
  };

  /*!
    Refines the pairs. PER_PAIR and KNOWN need exactly one pair; SHARED takes any number.
    fx is the known value (KNOWN) or the initial value.
  */
  static Result refine(const std::vector<Pair> &pairs, double fx, const Options &options);

  //! Symmetric epipolar distance (px) of one correspondence: sqrt(d(m2, Q m1)^2 + d(m1, Q^T m2)^2).
  static double symmetricEpipolarDistance(const vpHomogeneousMatrix &c2Mc1, double fx, double u0, double v0,
                                          double mu, const vpImagePoint &p1, const vpImagePoint &p2);
  //! RMS of symmetricEpipolarDistance() over the correspondences (0 when there are none).
  static double rmsSymmetricEpipolarDistance(const vpHomogeneousMatrix &c2Mc1, double fx, double u0, double v0,
                                             double mu, const std::vector<vpImagePoint> &p1,
                                             const std::vector<vpImagePoint> &p2);
};

#endif
