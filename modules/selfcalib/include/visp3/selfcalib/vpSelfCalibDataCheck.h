/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpSelfCalibDataCheck.h
  \brief What is wrong with a calibration dataset before it is calibrated, in words that say what to do
  (layer pipeline; vpRobotSelfCalibration runs it first).
*/
#ifndef VP_SELFCALIB_DATA_CHECK_H
#define VP_SELFCALIB_DATA_CHECK_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <map>
#include <string>
#include <vector>

#include <visp3/core/vpColVector.h>
#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>
#include <visp3/selfcalib/vpSelfCalibNoiseModel.h>

/*!
  \class vpSelfCalibDataCheck
  \ingroup group_selfcalib_validation
  \brief What is wrong with a calibration dataset before it is calibrated, in words that say what
  to do (layer pipeline; vpRobotSelfCalibration runs it first).

  Caller mistakes throw vpSelfCalibException: a non-finite joint, controller pose or pixel, a joint
  outside the model's limits (beyond a tolerance), a view with joints of the wrong size.

  Degenerate data gives findings:
  - DEGENERATE (no calibration is attempted): no two distinct poses; no parallax in any image pair
    (the camera only rotates, or the scene is a plane, or it is far away compared with the baseline):
    a homography explains the matched points of every pair, so depths and the two-view geometry are
    undefined;
  - WARNING (calibration runs, the result says what is weak): views with too few points, repeated
    poses, joints that barely move, a camera that barely rotates, end-effector rotations all about
    parallel axes (hand-eye translation along them unobservable), a yardstick seen in fewer than two
    views, points outside the image.
*/
class VISP_SELFCALIB_EXPORT vpSelfCalibDataCheck
{
public:
  enum Severity {
    WARNING,   //!< calibration runs; part of the result is weak or missing
    DEGENERATE, //!< the data cannot determine the calibration: it is not attempted
    DOUBT       //!< after a run: the answer fails one of its checks (vpRobotSelfCalibration::DOUBTFUL)
  };

  //! "warning", "degenerate" or "doubt".
  static const char *severityName(Severity s);

  //! One finding: its severity, a stable code, and a message that says what is wrong and what to do.
  struct Finding {
    Severity severity = WARNING;
    std::string code;    //!< stable identifier, e.g. "joints-barely-move", "no-parallax"
    std::string message; //!< what is wrong, what it costs, what to do
  };

  //! Settings of vpSelfCalibDataCheck (the defaults are the member initialisers).
  struct Options {
    double joint_limit_tolerance = 1e-3;           //!< rad beyond the model's limits still accepted
    unsigned int min_points = 6;                   //!< fewer points in a view: warning
    double same_pose_tolerance = 1e-4;             //!< rad, every joint: two poses are the same
    double min_joint_range = 2.0 * M_PI / 180.0;   //!< rad: a joint moving less "barely moves"
    double min_rotation = 2.0 * M_PI / 180.0;      //!< rad: largest relative camera rotation below this
    double parallel_axes_tolerance = 2.0 * M_PI / 180.0; //!< rad between rotation axes
    //! Fraction of a pair's points within max(1, 3 pixel_sd) (the noise model's) of a homography: the pair has no
    //! parallax. Measured on the reference scenario at 0.2 px: 0.95-1 for a plane, 0-0.1 for the
    //! 8 cm deep scene, 0.05-0.4 with 1 cm of relief.
    double homography_inliers = 0.9;
    /*!
      Points of a known layout (a board's, the bundle adjustment's known_points; vpRobotSelfCalibration
      fills it from its options when empty): a view that sees only such points is placed by PnP from
      4 coplanar ones (the few-points warning asks it for 4, not min_points), and the layout, not
      the parallax between views, gives their depth (no parallax finding when every calibration
      view sees only such points).
    */
    std::map<int, vpColVector> known_points;
    void check() const;
  };

  /*!
    Checks the calibration views (the first num_calibration of the dataset) and the yardstick.
    hand_eye: views may have a controller pose fMe in place of joints, and the parallel-axes test
    applies. The noise model's pixel_sd sets the homography test's threshold, max(1, 3 pixel_sd).
    Throws vpSelfCalibException on the caller mistakes listed above and on a nonsense noise model.
  */
  static std::vector<Finding> check(const vpKinematicChain &nominal, const vpSelfCalibDataset &dataset,
                                    unsigned int num_calibration, bool hand_eye, const Options &options,
                                    const vpSelfCalibNoiseModel &noise);

  //! True when a finding is DEGENERATE.
  static bool degenerate(const std::vector<Finding> &findings);
};

#endif
