/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpSelfCalibDataset.h
  \brief What a self-calibration run consumes: the camera, the robot model name, one view per measurement
  configuration (joint readings and/or controller pose fMe, image points with ids) and the
  yardstick.
*/
#ifndef VP_SELFCALIB_DATASET_H
#define VP_SELFCALIB_DATASET_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <optional>
#include <string>
#include <vector>

#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpColVector.h>
#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/core/vpImagePoint.h>

/*!
  \class vpSelfCalibDataset
  \ingroup group_selfcalib_core
  \brief What a self-calibration run consumes: the camera, the robot model name, one view per
  measurement configuration (joint readings and/or controller pose fMe, image points with ids) and
  the yardstick.

  Image points are pixel coordinates (vpImagePoint: i = v = row, j = u = column). The same id in
  two views is the same scene point.

  <b>File</b> (YAML; lengths in m, angles in rad; doc/formats.md, "Dataset file"):
  \code
  camera: {width: 640, height: 480, u0: 320, v0: 240, px: 1500, py: 1500}
  # f self-calibrated: omit px, py (optionally f_guess: 1400, default the image width)
  # lens distortion, OpenCV's model: distortion: [k1, k2, p1, p2, k3] in the camera map (pixels are
  #    kept as measured; the pipeline undistorts them, or estimates the coefficients from these)
  # or camera_xml: {file: camera.xml, name: Camera}   (vpXmlParserCamera; a distortion model in it is
  #    applied: every observation is undistorted and the dataset's camera has none)
  robot: viper850                 # preset name or robot-model file (relative to this file)
  camera_mount: effector          # optional: effector (default, eye-in-hand: the camera on the flange,
                                  # the scene fixed in the base frame) or world (eye-to-hand: the camera
                                  # fixed in the robot's world, the target carried by the end-effector;
                                  # the unknowns are then bMc and the target in the effector frame eMo)
  robot_error: {pose_sd: [0.002, 0.002], joint_sd: [1e-4]}   # optional: the expected error of the
                                  # controller poses (m, rad) and of the joint readings (rad; one for
                                  # every joint or one per joint); absent: exact
  poses:
    - joints: [q1, q2, q3, q4, q5, q6]   # or fMe: [tx, ty, tz, tux, tuy, tuz]
      image: images/0001.png           # optional, relative to this file
      mask: masks/0001.png             # optional, relative to this file: where this view's image is
                                       # black (0), no natural feature is looked for (the gripper, an
                                       # overlay, something that moves); combined with a global mask
      points: [[id, u, v], ...]        # optional
  yardstick: {length: 0.1, ends: [80, 81]}   # optional; without ends: dots found in the images
  fix: [j3.*, base.*]             # optional: parameters kept nominal (names or glob patterns)
  free: [j2.tz]                   # optional: parameters estimated whatever their predicted sd
  kinematic_prior: off            # optional: a prior on every kinematic correction, sd tolerance / K
                                  # (tolerance/K or K; default tolerance/3), or off: none
  \endcode
*/
struct VISP_SELFCALIB_EXPORT vpSelfCalibDataset {
  //! One image point of a scene point.
  struct Observation {
    int id = -1;
    vpImagePoint ip;
  };

  //! One measurement configuration.
  struct View {
    vpColVector q;            //!< joint readings (rad); empty when only fMe is known
    bool has_fMe = false;     //!< true when the controller pose fMe is given
    vpHomogeneousMatrix fMe;  //!< controller pose, when has_fMe
    std::string image;        //!< image path, may be empty
    /*!
      Mask of this view's image, may be empty: an image of the camera's size, where it is black (0)
      no natural feature is looked for. A global mask (vpFeatureFrontEnd::Options::masks with one
      image) applies too: a pixel is searched only where both allow it.
    */
    std::string mask;
    std::vector<Observation> points;
  };

  //! Two marked scene points at a known distance.
  struct Yardstick {
    double length = 0;  //!< m
    int id_a = -1, id_b = -1;
    bool isSet() const { return length > 0 && id_a >= 0 && id_b >= 0 && id_a != id_b; }
  };

  //! Where the camera is: on the end-effector (eye-in-hand) or fixed in the robot's world (eye-to-hand).
  enum CameraMount {
    CAMERA_ON_EFFECTOR, //!< eye-in-hand: unknown eMc, the scene fixed in the base frame (default)
    CAMERA_IN_WORLD     //!< eye-to-hand: unknown bMc, the target fixed on the end-effector (unknown eMo)
  };
  //! The file's name of a mount ("effector" or "world").
  static const char *cameraMountName(CameraMount m);

  vpCameraParameters cam;      //!< intrinsics; px, py are a first guess when !focal_known
  CameraMount camera_mount = CAMERA_ON_EFFECTOR; //!< key camera_mount: effector (default) or world
  unsigned int width = 0, height = 0;
  bool focal_known = true;     //!< false: the focal length is to be self-calibrated
  /*!
    OpenCV's lens distortion (k1, k2, p1, p2, k3) of the camera, for the pixels as measured; empty:
    none (or ViSP's k_ud in cam). Known coefficients are applied by the pipeline; with the distortion
    estimated they are the start.
  */
  std::vector<double> opencv_distortion;
  std::string robot;           //!< preset name or robot-model file
  //! Expected error of the controller poses (m, rad; 0: exact) and of the joint readings (rad; one
  //! value for every joint or one per joint; empty: exact). Read by the pipeline's bundle adjustment
  //! when its own options leave them unset.
  double pose_sd_translation = 0, pose_sd_rotation = 0;
  std::vector<double> joint_sd;
  /*!
    Kinematic parameters the user keeps at their nominal value (fix) or has estimated whatever their
    predicted sd (free): names or glob patterns of the model's parameters ("j3.*", "eMc.rz"); the
    pipeline adds them to its bundle adjustment's (vpKinematicBundleAdjustment::Options fixed, free).
  */
  std::vector<std::string> fix, free;
  /*!
    The bundle adjustment's kinematic prior the dataset asks for, K (each correction's prior sd its
    tolerance / K; vpKinematicBundleAdjustment::Settings::kinematic_prior), used when the caller's
    options say nothing; 0 (vpKinematicBundleAdjustment::KINEMATIC_PRIOR_OFF): none; empty: the
    file says nothing (the bundle adjustment's default,
    vpKinematicBundleAdjustment::DEFAULT_KINEMATIC_PRIOR). In the file: off, tolerance (1),
    tolerance/K or K.
  */
  std::optional<double> kinematic_prior;
  std::vector<View> views;
  Yardstick yardstick;

  /*!
    Reads a dataset file. Relative robot-model and image paths are resolved against the file's
    directory. Every malformed or inconsistent input (missing or unknown key, wrong type, NaN or
    inf, joint vectors of different sizes, a view with neither joints nor fMe, a point id twice in
    one view, a negative id, a yardstick with equal ends...) throws vpSelfCalibException naming the
    file, the key and what was expected.
  */
  static vpSelfCalibDataset loadYaml(const std::string &filename);
  //! The same from text; base_dir resolves relative paths (empty: kept as they are).
  static vpSelfCalibDataset fromYamlString(const std::string &yaml, const std::string &source = "<string>",
                                           const std::string &base_dir = "");
  //! Full precision (17 significant digits): a written dataset reads back identical, controller
  //! poses bit for bit when a pose vector rebuilds their matrix exactly (the writer looks for one;
  //! a pose read from a file with a rotation angle of at most pi has one), else within 1e-15. Paths under
  //! base_dir are written relative to it.
  std::string toYamlString(const std::string &base_dir = "") const;
  //! Written atomically (temporary file, then rename); paths relative to the file's directory.
  void saveYaml(const std::string &filename) const;
};

#endif
