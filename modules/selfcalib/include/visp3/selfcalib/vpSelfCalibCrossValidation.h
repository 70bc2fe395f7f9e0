/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpSelfCalibCrossValidation.h
  \brief k-fold cross-validation of a self-calibration on real data: the held-out views'
  reprojection error through the calibrated model against the nominal model's, with its spread.
*/
#ifndef VP_SELFCALIB_CROSS_VALIDATION_H
#define VP_SELFCALIB_CROSS_VALIDATION_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <functional>
#include <string>
#include <vector>

#include <visp3/core/vpCameraParameters.h>
#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>

/*!
  \class vpSelfCalibCrossValidation
  \ingroup group_selfcalib_protocol
  \brief k-fold cross-validation of vpRobotSelfCalibration::run() on a dataset: the figure a user
  without a laser tracker (no true pose) can trust.

  <b>Folds.</b> View i (dataset order, from 0) is held out in fold i mod k: the folds are
  interleaved, not contiguous blocks, because datasets are recorded along a trajectory: a block of
  consecutive views covers one region of the workspace, and holding it out would measure
  extrapolation to a region the training views never saw (and could leave a training set that no
  longer moves every joint), while interleaved folds each span the whole trajectory. The assignment
  depends only on the number of views and k: the same dataset gives the same folds.

  <b>Per fold.</b> The calibration runs with the caller's Options on a dataset made of the training
  views first, then the held-out views, with num_calibration_poses the number of training views
  (vpRobotSelfCalibration::run() calibrates on the first num_calibration_poses views and verifies
  the yardstick on the others, so a held-out yardstick gives the fold's 3-D error too). Then the
  held-out views' reprojection error (reprojection()), the same rule for both models:
  - the scene: every point seen in two or more training views, triangulated from the cameras the
    model predicts for the training views (multi-ray midpoint, refined on its reprojection error),
  - projected into each held-out view's predicted camera, compared with the observed pixels.
  The calibrated model: the fold's calibrated chain (joints through the kinematics; for HAND_EYE a
  view's controller pose fMe with the calibrated eMc) and camera (the calibrated intrinsics and
  lens). The nominal model: the nominal chain (fMe with its eMc for HAND_EYE) and the dataset's
  camera. A camera fixed in the world (dataset camera_mount world): the scene is the target, fixed
  in its own frame o, and each view's camera there is oMc = (bMe eMo)^-1 bMc, bMe the view's
  controller pose (HAND_EYE) or the kinematics at its joints; the calibrated model: the fold's bMc,
  eMo, kinematics and camera; the nominal: the fold's bMc and eMo with the nominal kinematics and
  the dataset's camera (HAND_EYE calibrates no kinematics: the two differ by the camera only). A
  fold whose calibration fails keeps its status and message and is left out of the summary
  (counted in num_failed), never hidden.

  <b>What it measures.</b> A held-out pixel is predicted from other views only through the
  model: the error is the image noise (its RMS is sqrt(2) sigma for an isotropic sd sigma per
  coordinate) plus what the model gets wrong on views it was not calibrated on, plus the
  triangulated point's error. The nominal model's figure on the same views is the reference.
*/
class VISP_SELFCALIB_EXPORT vpSelfCalibCrossValidation
{
public:
  //! Settings of vpSelfCalibCrossValidation (the defaults are the member initialisers).
  struct Options {
    unsigned int folds = 5; //!< k: at least 2, at most the number of views
    //! Throws vpSelfCalibException when folds < 2.
    void check() const;
  };

  //! The reprojection error of test views on a scene triangulated from scene views.
  struct Reprojection {
    unsigned int points = 0;       //!< scene points triangulated (seen in 2 or more scene views)
    unsigned int observations = 0; //!< test-view observations compared (their point triangulated and in front)
    unsigned int behind = 0;       //!< test-view observations whose point the predicted camera sees behind it (left out)
    //! Test-view observations whose point the predicted camera has outside its lens model's valid
    //! region: beyond where the distortion polynomial stays monotonic in radius or, with a lens
    //! distortion and the image's size given, undistorted more than a margin (a quarter of the
    //! image's larger side) outside the image the polynomial was fitted on: not seen, left out.
    unsigned int outside = 0;
    double rms = 0;                //!< px, sqrt of the mean squared 2-D error (0 when no observation)
    double median = 0;             //!< px, median 2-D error
  };

  //! One fold.
  struct Fold {
    std::vector<unsigned int> held_out; //!< dataset indices of the held-out views
    vpRobotSelfCalibration::Status status = vpRobotSelfCalibration::TWO_VIEW_FAILED;
    std::string message;                //!< the calibration's message
    double fx = 0;                      //!< px, the fold's focal length (OK and DOUBTFUL folds)
    Reprojection calibrated, nominal;   //!< the held-out views' reprojection error
    //! The yardstick 3-D error (m) on the held-out views, when two of them see its ends.
    bool verified = false;
    double yardstick_error_nominal = 0, yardstick_error_calibrated = 0;
    double seconds = 0;
  };

  //! Mean, sample standard deviation and range of a figure over the folds that measured it.
  struct Spread {
    unsigned int count = 0;
    double mean = 0, sd = 0, min = 0, max = 0;
  };

  //! The result of vpSelfCalibCrossValidation: what it computed, and what the caller needs to judge it.
  struct Result {
    unsigned int views = 0, folds = 0;
    std::vector<Fold> fold;
    unsigned int num_ok = 0;     //!< folds calibrated (status OK or DOUBTFUL) with held-out observations compared
    unsigned int num_failed = 0; //!< folds whose calibration failed (their status in fold)
    //! Over the num_ok folds: the held-out reprojection RMS and median (px), calibrated and nominal.
    Spread calibrated_rms, nominal_rms, calibrated_median, nominal_median;
    std::string message; //!< one line: the figure, or why there is none
    double seconds = 0;
  };

  //! Progress: stage (the fold, then the calibration's stage), done, total.
  using Progress = std::function<void(const std::string &, unsigned int, unsigned int)>;

  /*!
    The held-out views of each of the k folds: view i in fold i mod k. Throws vpSelfCalibException
    when k < 2, k > num_views, or a training set would keep fewer than 3 views
    (num_views - ceil(num_views / k) < 3).
  */
  static std::vector<std::vector<unsigned int>> folds(unsigned int num_views, unsigned int k);

  /*!
    k-fold cross-validation of vpRobotSelfCalibration::run(nominal, dataset, options) (see the class
    description); options.num_calibration_poses is not read (each fold calibrates on its training
    views). Throws vpSelfCalibException on bad cv_options, on a dataset too small for k folds (see
    folds()) and, through vpRobotSelfCalibration::run(), on the caller mistakes it finds (before
    the first fold's work). A fold's numerical failure is its status.
  */
  static Result run(const vpKinematicChain &nominal, const vpSelfCalibDataset &dataset,
                    const vpRobotSelfCalibration::Options &options, const Options &cv_options,
                    const Progress &progress = Progress());

  /*!
    The same cross-validation, each fold started from `full`, the run of the same options on every
    view of `dataset` (what vpSelfCalibProtocol calibrates first). HAND_EYE with the camera on the
    effector and `full` ok or doubtful: a fold is one hand-eye bundle adjustment on its training
    views' observations (the held-out views' left out) from full's eMc, scene points and focal
    length (vpRobotSelfCalibration::Options::start), at the noise full used (its measured levels,
    held); only when the fold's residuals contradict those levels (its sigma0 above its 99.9 %
    interval, or its robot corrections beyond their chi-square bound, where full's were not) does
    the fold measure the noise again as full did. BUNDLE_ADJUSTMENT whose robot error full
    measured and dropped (exact readings; not trusted by the options): run() above with the robot
    trusted (Options::trust_robot), the folds not measuring it again from the prior. Otherwise, and
    for other methods or a camera in the world, run() above. Throws as run().
  */
  static Result run(const vpKinematicChain &nominal, const vpSelfCalibDataset &dataset,
                    const vpRobotSelfCalibration::Options &options, const Options &cv_options,
                    const vpRobotSelfCalibration::Result &full, const Progress &progress = Progress());

  /*!
    The reprojection error of test_views on the scene triangulated from scene_views (the two may be
    the same views), both through `model` and the camera `cam` with OpenCV's lens coefficients
    `opencv_distortion` (empty: cam's own model). A view's camera pose: with controller_poses and a
    controller pose fMe, fMe eMc (the model's eMc); else fMc(q) through the model; else (no joints)
    fMe eMc. `width` x `height`: the image the lens was fitted on (0: not given; see
    Reprojection::outside). Throws vpSelfCalibException when a view has neither joints of the
    model's size nor fMe.
  */
  static Reprojection reprojection(const vpKinematicChain &model, const vpCameraParameters &cam,
                                   const std::vector<double> &opencv_distortion, bool controller_poses,
                                   const std::vector<vpSelfCalibDataset::View> &scene_views,
                                   const std::vector<vpSelfCalibDataset::View> &test_views,
                                   unsigned int width = 0, unsigned int height = 0);

  /*!
    The camera of a calibration result for reprojection(): result.camera with the estimated OpenCV
    coefficients (result.bundle.opencv_distortion), or the dataset's known ones when the run held
    them (applied to the pixels, not estimated).
  */
  static std::vector<double> calibratedDistortion(const vpRobotSelfCalibration::Result &result,
                                                  const vpSelfCalibDataset &dataset);

  //! A calibrated model checked on a second dataset of the same robot and camera.
  struct HeldOut {
    unsigned int views = 0;
    //! The yardstick 3-D error (m), when the dataset declares a yardstick seen in two of its views.
    bool has_yardstick = false;
    double yardstick_error_nominal = 0, yardstick_error_calibrated = 0;
    //! Its views' reprojection error, the scene triangulated from these views themselves.
    Reprojection calibrated, nominal;
  };

  /*!
    The calibration `result` (run on `dataset` with `options`) verified on `held_out`, a dataset of
    the same robot and camera: the paper's 3-D yardstick error (vpCalibrationVerifier) and the
    views' reprojection error through the calibrated model and camera against the nominal model
    with held_out's camera. Throws vpSelfCalibException when held_out has fewer than 2 views, or
    views without joints of the model's size or fMe.
  */
  static HeldOut verifyHeldOut(const vpKinematicChain &nominal, const vpSelfCalibDataset &dataset,
                               const vpRobotSelfCalibration::Options &options,
                               const vpRobotSelfCalibration::Result &result, const vpSelfCalibDataset &held_out);
};

#endif
