/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 */
#ifndef VP_SELFCALIB_DATASET_H
#define VP_SELFCALIB_DATASET_H

#include <string>
#include <vector>

#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpColVector.h>
#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/core/vpImagePoint.h>

/*!
  \class vpSelfCalibDataset
  \brief What a self-calibration run consumes: the camera, the robot model name, one view per
  measurement configuration (joint readings and/or controller pose fMe, image points with ids) and
  the yardstick.

  Image points are pixel coordinates (vpImagePoint: i = v = row, j = u = column). The same id in
  two views is the same scene point.
*/
struct vpSelfCalibDataset {
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
    std::vector<Observation> points;
  };

  //! Two marked scene points at a known distance.
  struct Yardstick {
    double length = 0;  //!< m
    int id_a = -1, id_b = -1;
    bool isSet() const { return length > 0 && id_a >= 0 && id_b >= 0 && id_a != id_b; }
  };

  vpCameraParameters cam;      //!< intrinsics; px, py are a first guess when !focal_known
  unsigned int width = 0, height = 0;
  bool focal_known = true;     //!< false: the focal length is to be self-calibrated
  std::string robot;           //!< preset name or robot-model file
  std::vector<View> views;
  Yardstick yardstick;
};

#endif
