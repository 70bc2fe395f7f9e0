/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 */
#ifndef VP_ROBOT_SELF_CALIBRATION_H
#define VP_ROBOT_SELF_CALIBRATION_H

#include <functional>
#include <string>
#include <vector>

#include <visp3/core/vpCameraParameters.h>
#include <visp3/selfcalib/vpCalibrationVerifier.h>
#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpKinematicIdentification.h>
#include <visp3/selfcalib/vpPoseScale.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>
#include <visp3/selfcalib/vpTwoViewEstimator.h>

/*!
  \class vpRobotSelfCalibration
  \brief The paper's procedure (Section 4.1, steps 2 to 5) on a dataset:

  2. pose measurements: the refined nonlinear factor method on the image pairs (pose 1, pose i) of
     the calibration views, i = 2..N (vpTwoViewEstimator), with the focal length per pair (the
     paper), shared by all pairs, or known;
  3. scale: eq. 21 ratios from the nominal model times one global scale (vpPoseScale);
  4. the global scale from the yardstick seen in the pairs (least squares). The paper identifies with
     scale 1 and fixes the scale afterwards; the two orders give the same model because the scale
     multiplies every measured translation, so here the scale is applied first and identification
     runs once on metric measurements;
  3'. identification of the kinematic parameters from the nominal model (vpKinematicIdentification);
  5. verification on the remaining views: the paper's 3-D error of the yardstick before (nominal)
     and after calibration (vpCalibrationVerifier).

  Views are used in dataset order: the first num_calibration_poses for calibration, the rest for
  verification.
*/
class vpRobotSelfCalibration
{
public:
  enum FocalMode {
    FOCAL_AUTO,     //!< KNOWN when the dataset says the focal length is known, else SHARED
    FOCAL_PER_PAIR, //!< the paper: f self-calibrated with each pair, the median of the pairs kept
    FOCAL_SHARED,   //!< one f estimated jointly over all pairs
    FOCAL_KNOWN     //!< the dataset's px
  };

  struct Options {
    unsigned int num_calibration_poses = 15; //!< the paper's 15 of 25
    FocalMode focal_mode = FOCAL_AUTO;
    vpTwoViewEstimator::Options twoview;      //!< fx, u0, v0, mu and focal_mode are set from the dataset
    double pose_sd_rotation = 5e-3;           //!< rad, expected two-view rotation error (weights)
    double pose_sd_direction = 5e-3;          //!< rad, expected translation-direction error (weights)
    vpKinematicIdentification::Options identification;
    void check() const;
  };

  enum Status { OK, TWO_VIEW_FAILED, SCALE_FAILED, IDENTIFICATION_FAILED };
  static const char *statusName(Status s);

  struct Result {
    Status status = TWO_VIEW_FAILED;
    std::string message;
    vpKinematicChain calibrated;           //!< the nominal model with the identified corrections
    vpCameraParameters camera;             //!< with the focal length used
    double fx = 0, fx_sd = 0;
    std::vector<vpTwoViewEstimator::Result> pairs;      //!< pair (1, i + 2) at index i
    std::vector<double> ratios;                         //!< eq. 21 ratios, one per pair
    vpPoseScale::Result scale;
    std::vector<vpKinematicIdentification::Measurement> measurements; //!< the scaled pose measurements
    vpKinematicIdentification::Result identification;
    bool verified = false;                 //!< true when there were 2 or more verification views
    vpCalibrationVerifier::Result before, after; //!< yardstick 3-D error with the nominal and calibrated models
    double seconds = 0;
  };

  //! Progress of a run: stage name, done, total.
  using Progress = std::function<void(const std::string &, unsigned int, unsigned int)>;

  /*!
    Throws vpSelfCalibException on caller mistakes: fewer than 3 calibration views, a view without
    joints of the model's size or without any image point, no yardstick in the dataset, an unknown
    focal length with FOCAL_KNOWN. Numerical failures are statuses.
  */
  static Result run(const vpKinematicChain &nominal, const vpSelfCalibDataset &dataset, const Options &options,
                    const Progress &progress = Progress());
};

#endif
