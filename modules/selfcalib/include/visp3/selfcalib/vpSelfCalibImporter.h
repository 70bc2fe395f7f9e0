/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpSelfCalibImporter.h
  \brief Eye-in-hand data sets in the layouts users already have, as a vpSelfCalibDataset: one view per
  controller pose fMe (base to end-effector) with its image, no image points (the front end finds
  them when calibrating).
*/
#ifndef VP_SELFCALIB_IMPORTER_H
#define VP_SELFCALIB_IMPORTER_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <string>
#include <vector>

#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>

/*!
  \class vpSelfCalibImporter
  \ingroup group_selfcalib_io
  \brief Eye-in-hand data sets in the layouts users already have, as a vpSelfCalibDataset: one view
  per controller pose fMe (base to end-effector) with its image, no image points (the front end
  finds them when calibrating).

  <b>Layouts</b> (import() recognises them from the path):
  - ViSP's hand-eye folders (apps/calibration/hand-eye in ViSP): `<prefix>_pose_rPe_N.yaml` or
    `<prefix>_pose_fPe_N.yaml` (the flange pose, a vpPoseVector YAML), `<prefix>_image-N.png` (or
    .jpg, .pgm, .ppm, .bmp, .tif), and a camera XML (vpXmlParserCamera): `<prefix>_camera.xml`, else
    the only .xml file of the folder; its only camera, or the one named "Camera". Poses and images
    are paired by N, in numerical order. `chessboard-data.txt` ("9 x 6", "square size: 0.0236 m"),
    when present, describes the board. `apriltag-data.txt` ("36h11", "size: 0.048 m") marks ViSP's
    eye-to-hand folder: a tag on the tool, the camera fixed in the world (the dataset's
    camera_mount: world; the pose files are then base -> end-effector).
  - industrial_calibration's `cal_data.yaml` (the file or its folder): `data: [{pose, image}, ...]`
    (paths relative to the file), in the listed order; `intrinsics: {fx, fy, cx, cy}`;
    `target_finder` (type, rows, cols, spacing) describes the board;
    `camera_mount_to_camera_guess` (x y z qx qy qz qw) is the eMc guess. `static_camera: true` (the
    camera is not on the robot) is refused.

  <b>Pose files</b> (readPose(); YAML, m and rad): a ViSP pose vector (`rows: 6, cols: 1, data:
  [[tx], [ty], [tz], [tux], [tuy], [tuz]]`, or a list of 6 numbers); a position and a quaternion
  (`{x, y, z, qx, qy, qz, qw}` or a list of 7 numbers `x y z qx qy qz qw`; normalised, a zero
  quaternion is an error); a 4 x 4 homogeneous matrix (a list of 4 rows of 4, or `rows: 4, cols:
  4, data: ...`), whose rotation must be orthonormal with determinant +1 and last row 0 0 0 1 within
  1e-6 (it is then made exactly orthonormal). The numbers may also be one whitespace-separated
  line or column (6, 7 or 16 numbers, a matrix row by row). Every number must be finite.

  <b>What cannot be used is said, not guessed.</b> A pose without its image, an image without its
  pose, an image that cannot be read or whose size differs from the camera's, a file of the folder
  that is not part of the layout, a setting with no meaning here: each is left out and listed in
  Report::unused with the reason. When no pose with its image is left, import() throws.

  Caller mistakes throw vpSelfCalibException naming the file: a missing path, a folder without pose
  files, a pose file that cannot be read or is not a rigid transform, no camera, an unknown robot.
*/
class VISP_SELFCALIB_EXPORT vpSelfCalibImporter
{
public:
  enum Layout {
    VISP_HAND_EYE,         //!< ViSP's hand-eye folder
    INDUSTRIAL_CALIBRATION //!< industrial_calibration's cal_data.yaml
  };
  //! What the imported intrinsics are taken as.
  enum Intrinsics {
    INTRINSICS_DEFAULT, //!< per layout: a ViSP camera XML known, industrial_calibration's (nominal) a guess
    INTRINSICS_KNOWN,   //!< px, py fixed: the dataset's focal_known
    INTRINSICS_GUESS    //!< f self-calibrated, starting from px (the dataset's f_guess)
  };

  //! Settings of vpSelfCalibImporter (the defaults are the member initialisers).
  struct Options {
    /*!
      The robot: a preset name or a robot-model file. Empty: the panda preset for a ViSP folder
      whose prefix starts with "franka", else a generic hand-eye model (one placeholder joint: the
      poses are controller poses, and the hand-eye calibration uses only the model's eMc guess).
      With an eMc guess in the data (camera_mount_to_camera_guess), a preset or the generic model
      is written beside the dataset with that eMc (Result::robot_model).
    */
    std::string robot;
    Intrinsics intrinsics = INTRINSICS_DEFAULT;
  };

  //! Something found that the dataset does not use, and why.
  struct Unused {
    std::string what; //!< a file name, a key or a value
    std::string reason;
  };

  //! What was found, as the tool prints it.
  //! The controller pose error an imported dataset states (robot_error.pose_sd): m, rad.
  static constexpr double kDefaultPoseSdTranslation = 0.002, kDefaultPoseSdRotation = 0.002;

  //! What an import found and what it could not use, with the reason.
  struct Report {
    Layout layout = VISP_HAND_EYE;
    std::string source;              //!< the folder or the cal_data.yaml file read
    std::string pose_format;         //!< the pose files' format(s), e.g. "ViSP pose vector (rPe)"
    unsigned int num_pose_files = 0; //!< pose files found (ViSP) or listed (cal_data.yaml)
    unsigned int num_images = 0;     //!< images found or listed
    unsigned int num_views = 0;      //!< poses with their image: the dataset's views
    std::string camera;              //!< where the intrinsics come from, their values and how they are taken
    std::string robot;               //!< the robot model used and where its eMc guess comes from
    std::string board;               //!< the calibration board described by the data, "" when none
    std::string board_option;        //!< calibrate's --board for it when the importer knows one (chessboard, circle grid, AprilTag)
    std::string robot_error;         //!< the robot pose error the dataset states, and why
    std::vector<Unused> unused;
  };

  //! The result of vpSelfCalibImporter: what it computed, and what the caller needs to judge it.
  struct Result {
    /*!
      Views with has_fMe and fMe from the pose files, absolute image paths, no points. robot is the
      model name or file, or "" when has_robot_model (save() writes the model and sets it).
    */
    vpSelfCalibDataset dataset;
    bool has_robot_model = false; //!< robot_model is to be written beside the dataset
    vpKinematicChain robot_model;
    Report report;
    std::vector<std::string> inputs; //!< every file read (absolute): outputs must not replace them

    /*!
      Writes the dataset (and robot_model, when has_robot_model, as robotModelFileFor(dataset_file)),
      each atomically, the model first: a dataset is never there without its model, and when the
      dataset cannot be written the model written for it is taken back. Image and robot paths under
      the dataset's directory are written relative to it, the others absolute.
    */
    void save(const std::string &dataset_file) const;
  };

  //! Imports a ViSP hand-eye folder, or a cal_data.yaml (the file or its folder).
  static Result import(const std::string &path, const Options &options);
  static Result import(const std::string &path);

  //! The robot-model file save() writes beside a dataset: "ds.yaml" -> "ds-robot.yaml".
  static std::string robotModelFileFor(const std::string &dataset_file);

  //! A pose file in one of the formats above, as a homogeneous matrix; errors name the file.
  static vpHomogeneousMatrix readPose(const std::string &filename);
  //! The same from text; `source` names it in errors.
  static vpHomogeneousMatrix poseFromYamlString(const std::string &yaml, const std::string &source = "<string>");

  static const char *layoutName(Layout layout);
};

#endif
