/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpPoseScale.h
  \brief The scale of two-view pose measurements (paper Section 3.2).
*/
#ifndef VP_POSE_SCALE_H
#define VP_POSE_SCALE_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <string>
#include <vector>

#include <visp3/core/vpColVector.h>
#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/core/vpImagePoint.h>
#include <visp3/selfcalib/vpKinematicChain.h>

/*!
  \class vpPoseScale
  \ingroup group_selfcalib_scale
  \brief The scale of two-view pose measurements (paper Section 3.2).

  Two images give c_iMc_1 = [R_i | t_i] with |t_i| = 1: the true translation is k_i t_i with an
  unknown k_i per pose. Theorem 2 / eq. 21: |k_i| = (|T_i| / |T_1|) |k_1|, where T_i is the actual
  position vector of pose i relative to the reference pose (paper Figure 2). The paper approximates
  the ratio |T_i| / |T_1| by the nominal model's (nominalRatios()), which is exact only on a planned
  trajectory (issue "planning"); one global scale |k_1| remains, fixed by a yardstick
  (yardstick()).

  Indexing: configurations q[0] (the reference, the paper's first pose) and q[1..m-1]; ratio i is
  |T_i| / |T_1| with T_i the translation of c_iMc_0, so ratio 1 = 1.
*/
class VISP_SELFCALIB_EXPORT vpPoseScale
{
public:
  /*!
    Eq. 21 ratios from a (nominal) model: r[i-1] = |t(c_iMc_0)| / |t(c_1Mc_0)|, i = 1..m-1.
    Throws vpSelfCalibException with fewer than 2 configurations or when pose 1 equals pose 0.
  */
  static std::vector<double> nominalRatios(const vpKinematicChain &model, const std::vector<vpColVector> &q);

  //! One yardstick measurement: a pair with unit-translation pose and both ends seen in both images.
  struct YardstickView {
    vpHomogeneousMatrix c2Mc1;    //!< two-view pose, |t| = 1 (the paper's convention)
    double ratio = 1;             //!< |T| of this pair in units of the global scale (eq. 21 ratio)
    vpImagePoint a1, b1, a2, b2;  //!< ends a and b in image 1 and image 2 (pixels)
  };

  enum Status { OK, TOO_FEW_VIEWS, DEGENERATE };

  struct Result {
    Status status = TOO_FEW_VIEWS;
    std::string message;
    double scale = 0;            //!< |k_1| (m): the metric length of the unit translation of ratio 1
    double sd = 0;               //!< standard deviation of scale from the spread of the measurements (0 with one)
    std::vector<double> lengths; //!< per view, the yardstick length triangulated with unit scale
  };

  /*!
    Global scale from yardstick views by least squares (Ceres): each view j gives the yardstick's
    length l_j triangulated (OpenCV, normalized coordinates) with the unit translation, so that
    L = scale * ratio_j * l_j; scale minimizes sum_j (scale ratio_j l_j - L)^2. One view (two images)
    is enough (the paper's minimum); its sd is then unknown (0). A view whose ends do not triangulate
    in front of both cameras is DEGENERATE. Throws vpSelfCalibException on a non-positive length or
    focal length, or a non-finite pixel.
  */
  static Result yardstick(const std::vector<YardstickView> &views, double length, double fx, double u0, double v0,
                          double mu);
};

#endif
