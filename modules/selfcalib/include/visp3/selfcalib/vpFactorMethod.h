/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpFactorMethod.h
  \brief The factor method (paper Theorem 1, Hartley 1992): relative pose of two views from the
  fundamental matrix and the intrinsics.
*/
#ifndef VP_FACTOR_METHOD_H
#define VP_FACTOR_METHOD_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <vector>

#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/core/vpImagePoint.h>
#include <visp3/core/vpMatrix.h>

/*!
  \class vpFactorMethod
  \ingroup group_selfcalib_twoview
  \brief The factor method (paper Theorem 1, Hartley 1992): relative pose of two views from the
  fundamental matrix and the intrinsics.

  With A = [[f_x, 0, u0], [0, mu f_x, v0], [0, 0, 1]], the essential matrix is E = A^T F A (eq. 4:
  F = A^-T [t]x R A^-1). With E = U D V^T (det U, det V > 0), Theorem 1 gives [t]x ~ U Z U^T and
  R = U E' V^T or U E'^T V^T, where E' = [[0, 1, 0], [-1, 0, 0], [0, 0, 1]]; t = +-u3. Of the four
  candidates, the one that puts the most correspondences in front of both cameras is kept
  (cheirality, over all given points).

  Pose convention of the paper (eq. 9): P1 = A [I 0], P2 = A [R t], so (R, t) is c2Mc1: X2 = R X1 + t.
  t has unit norm (the scale is not observable from two images).
*/
class VISP_SELFCALIB_EXPORT vpFactorMethod
{
public:
  //! The result of vpFactorMethod: what it computed, and what the caller needs to judge it.
  struct Result {
    vpHomogeneousMatrix c2Mc1;   //!< R, t with |t| = 1
    unsigned int num_in_front = 0; //!< correspondences in front of both cameras for the chosen candidate
  };
  static vpMatrix intrinsicMatrix(double fx, double u0, double v0, double mu);
  static Result estimate(const vpMatrix &F, double fx, double u0, double v0, double mu,
                         const std::vector<vpImagePoint> &p1, const std::vector<vpImagePoint> &p2);
  //! Depths (z in camera 1, z in camera 2) of the midpoint triangulation of one normalized correspondence.
  static void triangulateDepths(const vpHomogeneousMatrix &c2Mc1, const double x1[2], const double x2[2], double &z1,
                                double &z2);
};

#endif
