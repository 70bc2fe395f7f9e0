/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpFocalFromFundamental.h
  \brief Focal length f_x of one camera from the fundamental matrix of two of its images, with the
  principal point (u0, v0) and the aspect ratio mu = f_y / f_x known (paper Section 3.1, after
  Hartley 1992).
*/
#ifndef VP_FOCAL_FROM_FUNDAMENTAL_H
#define VP_FOCAL_FROM_FUNDAMENTAL_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <string>

#include <visp3/core/vpMatrix.h>

/*!
  \class vpFocalFromFundamental
  \ingroup group_selfcalib_twoview
  \brief Focal length f_x of one camera from the fundamental matrix of two of its images, with the
  principal point (u0, v0) and the aspect ratio mu = f_y / f_x known (paper Section 3.1, after
  Hartley 1992).

  Pixels are first mapped to a square-pixel frame centred on the principal point and scaled by a
  nominal length s: x = (u - u0) / s, y = (v - v0) / (mu s), so that K = diag(g, g, 1) with g = f_x / s.
  With the SVD F' = U diag(a, b, 0) V^T of F in that frame, Kruppa's equations
  (Hartley 1992; closed form of Sturm 2001, equivalent to Bougnoux's formula) give two equations
  linear in w = g^2:
    w [a^2 u13 u23 (1 - v13^2) + a b v13 v23 (1 - u23^2)] = -[a^2 u13 u23 v13^2 + a b v13 v23 u23^2]
    w [a b v13 v23 (1 - u13^2) + b^2 u13 u23 (1 - v23^2)] = -[a b v13 v23 u13^2 + b^2 u13 u23 v23^2]
  (u_i3, v_i3: third components of the i-th columns of U and V), solved in least squares.

  Failures are reported, never returned as a number: w <= 0 (NEGATIVE), and the degenerate geometry in
  which the two optical axes meet (the principal points are corresponding points, m2^T F m1 = 0 at
  the principal points, and both equations vanish: UNOBSERVABLE).
*/
class VISP_SELFCALIB_EXPORT vpFocalFromFundamental
{
public:
  enum Status { OK, NEGATIVE, UNOBSERVABLE };
  //! The result of vpFocalFromFundamental: what it computed, and what the caller needs to judge it.
  struct Result {
    Status status = UNOBSERVABLE;
    std::string message;
    double fx = 0;
    //! |F33| of the normalized F (unit norm), 0 when the optical axes meet.
    double axes_coplanarity = 0;
  };
  /*!
    \param F : fundamental matrix in pixels (m2^T F m1 = 0).
    \param scale : nominal length s (px) for conditioning, for example the image width.
    \param min_coplanarity : below this |F33| (normalized frame, |F| = 1) the focal is unobservable.
  */
  static Result estimate(const vpMatrix &F, double u0, double v0, double mu, double scale,
                         double min_coplanarity = 1e-3);
};

#endif
