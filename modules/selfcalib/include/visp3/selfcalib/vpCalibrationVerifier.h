/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpCalibrationVerifier.h
  \brief The paper's verification (Section 4.1, step 5) and held-out pose errors.
*/
#ifndef VP_CALIBRATION_VERIFIER_H
#define VP_CALIBRATION_VERIFIER_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <map>
#include <string>
#include <vector>

#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpColVector.h>
#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>

/*!
  \class vpCalibrationVerifier
  \ingroup group_selfcalib_validation
  \brief The paper's verification (Section 4.1, step 5) and held-out pose errors.

  - 3-D error: every scene point seen in at least two verification views is triangulated in the
    reference frame f with the calibrated model (fMc(q) of each view) and camera, its distortion
    included (the module's one camera model): linear least-squares intersection of the rays, then
    reprojection error minimized with Ceres; a point that lands behind one of its cameras is left
    out, and so are wrong matches among three views or more (triangulate()). The
    paper's 3-D calibration error is | |X_a - X_b| - L | for the yardstick ends; with the true
    points known (simulation) the error of every point-pair distance is given as well.
  - Held-out pose errors: the model's relative pose c_0 M c_i between the first verification view
    and each other one, against the true one, in position (m) and rotation (rad).
*/
class VISP_SELFCALIB_EXPORT vpCalibrationVerifier
{
public:
  //! The result of vpCalibrationVerifier: what it computed, and what the caller needs to judge it.
  struct Result {
    std::map<int, vpColVector> points;  //!< triangulated points (f frame, 3-vectors), by id
    bool has_yardstick = false;
    double yardstick_length = 0;        //!< triangulated (m)
    double yardstick_error = 0;         //!< |length - L| (m), the paper's 3-D error
    /*!
      How well the model explains the views themselves: the RMS (px, per coordinate) of the
      reprojection of every triangulated point into the views that see it, over num_observations
      observations. The triangulation absorbs 3 of each point's 2 x (views) coordinates, so with a
      perfect model and pixel noise sd s the expected value is s sqrt(1 - 3 / (2 views)) (s / 2 with
      2 views); a wrong model raises it. No true pose is needed: it is the figure real data give.
    */
    double reprojection_rms = 0;
    unsigned int num_observations = 0;
    double reprojection_dof = 0; //!< 2 num_observations - 3 (points triangulated)
    unsigned int num_rejected = 0; //!< observations left out as wrong matches (see triangulate())
    // Against true points (when given): all point-pair distances.
    unsigned int num_pairs = 0;
    double distance_error_mean = 0, distance_error_rms = 0, distance_error_max = 0; //!< m
    // Against true camera poses (when given): c_0 M c_i of the views after the first.
    std::vector<double> position_errors, rotation_errors; //!< m, rad
    double position_error_mean = 0, rotation_error_mean = 0;
  };

  //! The model's camera pose of a view: fMc(q), or fMe eMc for a view with a controller pose only.
  static vpHomogeneousMatrix cameraPose(const vpKinematicChain &model, const vpSelfCalibDataset::View &view);

  /*!
    Triangulation of every id seen in two or more of the views (at least 2 views), with the model's
    fMc(q) of each view, or fMe eMc for a view that has a controller pose fMe and no joints, and the
    camera with its distortion (ViSP's k_ud when cam has it). Points whose rays do not meet in front
    of every camera are left out. Robust to wrong matches: of a point seen in three views or more, an
    observation whose error exceeds 5 times the robust sd of all observations' errors is left out
    and the point triangulated again without it. Throws vpSelfCalibException when a view has neither joints nor fMe.
  */
  static std::map<int, vpColVector> triangulate(const vpKinematicChain &model, const vpCameraParameters &cam,
                                                const std::vector<vpSelfCalibDataset::View> &views);

  /*!
    Verification on the given views. true_points (id -> f coordinates) and true_fMc (one per view)
    may be empty (real data): the corresponding figures are then left at 0.
  */
  static Result verify(const vpKinematicChain &model, const vpCameraParameters &cam,
                       const std::vector<vpSelfCalibDataset::View> &views,
                       const vpSelfCalibDataset::Yardstick &yardstick,
                       const std::map<int, vpColVector> &true_points = std::map<int, vpColVector>(),
                       const std::vector<vpHomogeneousMatrix> &true_fMc = std::vector<vpHomogeneousMatrix>());
};

#endif
