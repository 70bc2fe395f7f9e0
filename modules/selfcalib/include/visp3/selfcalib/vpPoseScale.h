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

#include <cmath>
#include <string>
#include <vector>

#include <visp3/core/vpColVector.h>
#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/core/vpImagePoint.h>
#include <visp3/core/vpMatrix.h>
#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpSelfCalibNoiseModel.h>

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

  //! The stated tolerance of a nominal model: sd of the 6-D error of every joint placement and of
  //! the base (m, rad) and of eMc (the reference scenario's values).
  struct ModelTolerance {
    double translation = 1e-3;
    double rotation = 0.1 * M_PI / 180.0;
    double hand_eye_translation = 1e-3;
    double hand_eye_rotation = 0.2 * M_PI / 180.0;
  };
  /*!
    Expected relative error (sd) of each eq. 21 ratio of nominalRatios() when the true robot differs
    from the model by the tolerance: first order, sd_i^2 = sum_k sigma_k^2 (d log r_i / d rho_k)^2
    over the model's error parameters (central differences). Ratio 1 (= 1 exactly) has sd 0.
  */
  static std::vector<double> nominalRatioSd(const vpKinematicChain &model, const std::vector<vpColVector> &q,
                                            const ModelTolerance &tolerance);
  /*!
    Expected relative error (sd) of the nominal norms |t_i| themselves (i = 1..m-1, pair 1 included),
    first order as nominalRatioSd(). These are the yardstick's weights: every ratio shares the error
    of |t_1|, which cancels in the scaled norms ratio_i k_1 (k_1 absorbs it), so only each pair's own
    norm error spreads the per-view scales.
  */
  static std::vector<double> nominalNormSd(const vpKinematicChain &model, const std::vector<vpColVector> &q,
                                           const ModelTolerance &tolerance);
  //! nominalRatioSd() with the default tolerance.
  static std::vector<double> nominalRatioSd(const vpKinematicChain &model, const std::vector<vpColVector> &q);

  /*!
    First-order covariance (5 x 5) of a two-view pose c2Mc1 = [R t] (|t| = 1) estimated from the
    correspondences p1, p2 (pixels, noise sd pixel_sd on u and v): sigma^2 (J^T J)^-1 with J the
    Jacobian of the Sampson (first-order geometric) epipolar distances with respect to the rotation
    (3, R <- exp([w]x) R) and the translation direction (2, t <- normalize(t + a e1 + b e2), e1, e2 a
    basis orthogonal to t, e1 = t.unitOrthogonal()). With the true pose it is the Cramér-Rao bound of
    the pose with the focal length known. Empty matrix with fewer than 5 correspondences or a
    singular J.
  */
  static vpMatrix twoViewCovariance(const vpHomogeneousMatrix &c2Mc1, const std::vector<vpImagePoint> &p1,
                                    const std::vector<vpImagePoint> &p2, double fx, double u0, double v0, double mu,
                                    double pixel_sd);

  //! One yardstick measurement: a pair with unit-translation pose and both ends seen in both images.
  struct YardstickView {
    vpHomogeneousMatrix c2Mc1;    //!< two-view pose, |t| = 1 (the paper's convention)
    double ratio = 1;             //!< |T| of this pair in units of the global scale (eq. 21 ratio)
    vpImagePoint a1, b1, a2, b2;  //!< ends a and b in image 1 and image 2 (pixels)
    double ratio_sd = 0;          //!< relative sd of ratio (nominalRatioSd()); 0: exact
    //! The pair's correspondences (pixels), for its two-view covariance (twoViewCovariance()); empty:
    //! the pose counts as exact and only the ends' pixel noise weighs.
    std::vector<vpImagePoint> p1, p2;
  };

  //! Settings of yardstick(): weighting and the joint fit of the yardstick ends.
  struct YardstickOptions {
    //! true: each view weighted by its expected accuracy (below); false: the paper's plain least
    //! squares on L = scale ratio_j l_j (short-baseline pairs then dominate).
    bool weighted = true;
    /*!
      Weighted and every view's first image the same (the pairs (0, j)): true (default) fits the
      ends in every image jointly (below); false: one triangulation per pair, combined by their
      expected accuracies (the reference image's end noise is then counted once per pair as if
      independent: the pairs' errors are correlated, the more the closer their geometry).
    */
    bool joint = true;
    //! px, sd of a self-calibrated focal length (0: known). Its error is common to every view: it
    //! adds (scale g fx_sd)^2 to the variance, g the weighted mean of d log l_j / d fx.
    double fx_sd = 0;
    void check() const;
  };

  enum Status { OK, TOO_FEW_VIEWS, DEGENERATE };

  //! The result of vpPoseScale: what it computed, and what the caller needs to judge it.
  struct Result {
    Status status = TOO_FEW_VIEWS;
    std::string message;
    double scale = 0;            //!< |k_1| (m): the metric length of the unit translation of ratio 1
    double sd = 0;               //!< standard deviation of scale (see yardstick())
    double predicted_sd = 0;     //!< weighted: sd predicted from the expected accuracies alone
    std::vector<double> lengths; //!< per view, the yardstick length triangulated with unit scale
    std::vector<double> relative_sd; //!< weighted: per view, expected relative sd of its scale
  };

  /*!
    Global scale from yardstick views by least squares (Ceres): each view j gives the yardstick's
    length l_j triangulated (OpenCV, normalized coordinates) with the unit translation, so that
    L = scale * ratio_j * l_j, i.e. view j alone says scale_j = L / (ratio_j l_j).

    Weighted (default; beyond the paper, which weighs every view alike): view j's expected relative
    error v_j = (sd(l_j) / l_j)^2 + ratio_sd_j^2, where sd(l_j) propagates to first order the pixel
    noise of the four ends and the pair's two-view covariance (twoViewCovariance(), from p1, p2) through
    the triangulation: a short baseline gives a large v_j. scale minimizes
    sum_j (scale ratio_j l_j / L - 1)^2 / v_j; predicted_sd = scale / sqrt(sum_j 1 / v_j) and
    sd = predicted_sd max(1, sqrt(chi2 / (n - 1))) (a scatter larger than predicted widens it), and
    options.fx_sd adds the focal length's common error to both.
    Joint (options.joint, weighted, every view sharing the first image): the ends A = M + (L/2) u and
    B = M - (L/2) u (c_1 frame, metres) reprojected in the first image and in every view j, whose pose
    is (exp([w_j]x) R_j, scale ratio_j exp(rho_j) normalize(t_j + a_j e1 + b_j e2)): the 5 pose
    corrections held by the pair's two-view covariance, rho_j by ratio_sd_j, the reprojections by
    the noise model's pixel_sd; scale, M, u and the corrections by least squares (Ceres); predicted_sd from its
    covariance, sd = predicted_sd max(1, sqrt(chi2 / dof)), and the focal length's part
    (d scale / d fx by a second solve) added to both. Falls back to the per-pair combination when
    the joint fit fails. lengths and relative_sd stay per pair.
    Unweighted: the paper's sum_j (scale ratio_j l_j - L)^2, sd from the residuals (0 with one view).

    One view (two images) is enough (the paper's minimum). A view whose ends do not triangulate
    in front of both cameras is DEGENERATE. Throws vpSelfCalibException on a non-positive length or
    focal length, a non-finite pixel, p1, p2 of different sizes, or a nonsense noise model (its
    pixel_sd is the image noise of the expected accuracies; the rest of it is not used).
  */
  static Result yardstick(const std::vector<YardstickView> &views, double length, double fx, double u0, double v0,
                          double mu, const YardstickOptions &options,
                          const vpSelfCalibNoiseModel &noise);
};

#endif
