/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpSelfCalibSimulator.h
  \brief The reference simulation scenario (doc/formats.md, "Reference scenario"): a "true" robot (nominal plus
  seeded 6-D errors on every joint placement, the base and eMc), a pinhole camera, a cloud of
  scene points in a box in front of the robot, a yardstick (two extra scene points at a known
  distance), pixel noise, and a generator of joint configurations from which every scene point is
  seen (or, with partial views, enough points and the yardstick); named scenes (sceneOptions()).
*/
#ifndef VP_SELFCALIB_SIMULATOR_H
#define VP_SELFCALIB_SIMULATOR_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpColVector.h>
#include <visp3/robot/vpRobot.h>
#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpPlannerScene.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>

/*!
  \class vpSelfCalibSimulator
  \ingroup group_selfcalib_simulation
  \brief The reference simulation scenario (doc/formats.md, "Reference scenario"): a "true" robot (nominal
  plus seeded 6-D errors on every joint placement, the base and eMc), a pinhole camera, a cloud of
  scene points in a box in front of the robot, a yardstick (two extra scene points at a known
  distance), pixel noise, and a generator of joint configurations from which every scene point is
  seen.

  Everything random comes from Options::seed through independent streams (errors, scene,
  configurations, noise of view k), so the same options give the same data bit for bit, whatever
  the order of the calls.

  Scene ids: 0 .. num_points-1 for the box points, num_points and num_points+1 for the yardstick ends.
*/
class VISP_SELFCALIB_EXPORT vpSelfCalibSimulator
{
public:
  //! Settings of vpSelfCalibSimulator (the defaults are the member initialisers).
  struct Options {
    uint64_t seed = 1;
    // True robot: sd of the seeded errors (m, rad). Joint rotations include the joint offsets.
    double joint_translation_sd = 1e-3;
    double joint_rotation_sd = 0.1 * M_PI / 180.0;
    double base_translation_sd = 1e-3;
    double base_rotation_sd = 0.1 * M_PI / 180.0;
    double hand_eye_translation_sd = 1e-3;
    double hand_eye_rotation_sd = 0.2 * M_PI / 180.0;
    // Camera (pinhole, no distortion).
    unsigned int width = 640, height = 480;
    double px = 1500, py = 1500, u0 = 320, v0 = 240;
    // Scene: points uniform in a box (axis-aligned in the base frame) centred on the point seen
    // at distance (distance_min + distance_max) / 2 along the optical axis at the home configuration.
    unsigned int num_points = 80;
    double box_x = 0.18, box_y = 0.14, box_z = 0.08;
    double yardstick_length = 0.1; //!< m; its ends are scene points too, inside the box
    // Viewpoints: camera at distance [distance_min, distance_max] from the box centre, looking at
    // it, from directions within view_cone of the home direction, rolled by at most roll_range.
    double distance_min = 0.6, distance_max = 0.8;
    double view_cone = 25 * M_PI / 180.0;
    double roll_range = 30 * M_PI / 180.0;
    vpColVector home;            //!< home joints; empty: the preset's (see homeConfiguration())
    double image_margin = 10;    //!< px kept free at the image border
    /*!
      Visibility rule of a view (isVisible(), generateConfigurations(), the planner's scene).
      0 (the reference scenario): every scene point in the image (with the margin) and in front.
      N > 0 (partial views): at least N scene points (yardstick ends included) and both yardstick
      ends in the image with the margin and in front; the other points may be outside.
    */
    unsigned int min_visible_points = 0;
    double pixel_noise_sd = 0.2; //!< px, Gaussian, on u and v
    unsigned int max_attempts = 100; //!< viewpoint draws per requested configuration

    //! Throws vpSelfCalibException on nonsense (negative sd, empty image, dmin > dmax...).
    void check() const;
  };

  /*!
    Named scenes: "reference" (the default Options: doc/formats.md, "Reference scenario") and "paper" (a
    paper-like scene: wide lens f = 300 px, 250 points in a large deep box 0.8 x 0.9 x 0.5 m seen
    from 0.6-0.8 m within a 60 degree cone, a 0.4 m yardstick, partial views with at least 40 points
    and both yardstick ends). The seed and the noise keep their defaults. Throws
    vpSelfCalibException on another name.
  */
  static Options sceneOptions(const std::string &name);
  //! "reference", "paper".
  static std::vector<std::string> sceneNames();

  //! Progress of long runs: (done, total).
  using Progress = std::function<void(unsigned int, unsigned int)>;

  vpSelfCalibSimulator(const vpKinematicChain &nominal, const Options &options);

  //! A home configuration for the presets: viper850 (0, -1.2, 2.4, 0, 0.4, 0), puma560
  //! (0, pi/4, -pi, 0, pi/4, 0); other robots: the middle of the joint ranges.
  static vpColVector homeConfiguration(const vpKinematicChain &chain);

  const Options &getOptions() const { return m_opt; }
  const vpKinematicChain &getNominalChain() const { return m_nominal; }
  const vpKinematicChain &getTrueChain() const { return m_true; }
  vpCameraParameters getCamera() const;
  const std::vector<vpColVector> &getScenePoints() const { return m_points; } //!< in f, index = id
  vpColVector getSceneCentre() const { return m_centre; }
  vpSelfCalibDataset::Yardstick getYardstick() const;
  //! The planner's view of the scene: its points, the camera, the image size and margin.
  vpPlannerScene getPlannerScene() const;
  //! The scene points by id (the ground truth vpCalibrationVerifier::verify() takes).
  std::map<int, vpColVector> getScenePointsById() const;
  //! The true camera poses fMc of the views (the ground truth of the held-out pose errors).
  std::vector<vpHomogeneousMatrix> getTrueCameraPoses(const std::vector<vpSelfCalibDataset::View> &views) const;

  /*!
    Draws m joint configurations within the nominal chain's limits: a look-at viewpoint, numerical
    IK on the nominal model (Ceres, joint limits as bounds), kept when the view is valid through the
    true robot (isVisible(): every scene point, or with partial views at least N and the yardstick).
    Throws vpSelfCalibException if a configuration cannot be found in max_attempts draws (the
    scene is out of reach or the options too tight).
  */
  std::vector<vpColVector> generateConfigurations(unsigned int m, const Progress &progress = Progress()) const;

  //! True when the view from the true camera at q is valid under Options::min_visible_points
  //! (every point, or at least N points and both yardstick ends, inside the image with the margin and
  //! in front).
  bool isVisible(const vpColVector &q) const;
  //! The same rule through another model of the robot (a nominal or perturbed chain).
  bool isVisible(const vpKinematicChain &chain, const vpColVector &q) const;
  //! Number of scene points inside the image with the margin and in front, from the true camera at q.
  unsigned int countVisible(const vpColVector &q) const;

  /*!
    Image points of all visible scene points through the true robot at q. view_index selects the
    noise stream, so view k always gets the same noise; noise_sd < 0 uses Options::pixel_noise_sd.
  */
  std::vector<vpSelfCalibDataset::Observation> observe(const vpColVector &q, unsigned int view_index,
                                                       double noise_sd = -1) const;

  //! Dataset for the given configurations, observations straight from the true chain.
  vpSelfCalibDataset makeDataset(const std::vector<vpColVector> &configurations) const;

  /*!
    Acquisition through a robot interface: for each configuration, move the robot
    (ARTICULAR_FRAME), read its joints back, and observe from the true camera at the joints read.
    This is what acquisition code does with a real vpRobot.
  */
  vpSelfCalibDataset acquire(vpRobot &robot, const std::vector<vpColVector> &configurations,
                             const Progress &progress = Progress()) const;

  //! An eye-to-hand set-up: a camera fixed in the robot's world and a target carried by the tool.
  struct EyeToHandOptions {
    unsigned int seed = 1;       //!< the geometry (target, poses) and, unless noise_seed, the noise
    unsigned int noise_seed = 0; //!< the image noise and the pose error (0: from seed): draws on one geometry
    unsigned int num_views = 12;
    //! Camera: bMc looks from `camera_position` (base frame, m) at `look_at`; pinhole intrinsics.
    vpColVector camera_position = vpColVector({1.2, 0.1, 0.6});
    vpColVector look_at = vpColVector({0.5, 0.0, 0.3});
    unsigned int width = 640, height = 480;
    double px = 600, py = 600, u0 = 320, v0 = 240;
    /*!
      The target: board true: a planar grid of board_cols x board_rows points board_spacing apart
      (id board_id_offset + r * board_cols + c at (c, r) board_spacing, z = 0: vpBoardDetector's chessboard layout
      for cols x rows inner corners), in the target frame o; false: num_points
      natural features in a box of box_size (m) about o. eMo: the target in the effector frame.
    */
    bool board = true;
    unsigned int board_cols = 6, board_rows = 5;
    double board_spacing = 0.02;
    int board_id_offset = 2000000; //!< the first board point's id (vpBoardDetector's default)
    unsigned int num_points = 40;
    double box_size = 0.08;
    vpPoseVector eMo = vpPoseVector(0.02, -0.01, 0.06, 0.1, -0.15, 0.3);
    /*!
      Not empty: the target's points in o instead (a printed board's outline, for rendered images):
      every one must be in the image, and o's z points away from the camera (vpBoardDetector's
      frame, z into the board: the printed side faces the camera); empty: the grid or the features
      above, o's z towards the camera.
    */
    std::map<int, vpColVector> layout;
    //! Target poses: distance from the camera (m), lateral range (m), tilt range (rad) about the facing pose.
    double distance_min = 0.35, distance_max = 0.6, lateral = 0.08, tilt = 30 * M_PI / 180.0;
    double pixel_noise_sd = 0.2;                 //!< px, Gaussian, on u and v
    double pose_sd_translation = 0, pose_sd_rotation = 0; //!< the controller poses' error (m, rad)
    /*!
      Joint readings, for the full kinematics method: a robot (a preset name or a model file) whose
      true model (nominal plus seeded 6-D errors of robot_translation_sd / robot_rotation_sd on the
      base and every joint placement) carries the target. The views are configurations drawn about
      `home` (empty: vpSelfCalibSimulator::homeConfiguration()) within +-joint_spread (rad) per joint
      and the joint limits, kept when every target point is in the image and the target faces the
      camera; the camera is placed facing the target's centre at home, (distance_min +
      distance_max) / 2 away (camera_position, look_at, lateral and tilt are then unused). Each view
      has the joint readings q_true - dq (dq ~ N(0, joint_sd) per joint) and the controller pose
      bMe_true E(delta)^-1 (pose_sd_*). Empty (default): controller poses only, no robot model.
    */
    std::string robot;
    vpColVector home;
    double joint_spread = 0.35;
    double robot_translation_sd = 1e-3, robot_rotation_sd = 1e-3;
    double joint_sd = 0; //!< rad, the joint readings' error
  };
  //! What the eye-to-hand simulation draws: the truth the calibration should recover.
  struct EyeToHandTruth {
    vpHomogeneousMatrix bMc, eMo;
    std::vector<vpHomogeneousMatrix> bMe;   //!< the true end-effector poses (the dataset's are measured)
    std::map<int, vpColVector> layout;      //!< the target's points in o, by id
    //! With EyeToHandOptions::robot: the true robot (nominal model plus its errors, bMc in its
    //! hand-eye slot's place not set: the slot keeps the nominal's) and the true joints of the views.
    vpKinematicChain chain;
    std::vector<vpColVector> q;
  };
  /*!
    Points data of an eye-to-hand set-up (dataset camera_mount world, robot `viper850`, every view a
    controller pose fMe = bMe): the target at random poses facing the camera, its points projected
    through the true pose bMe_true, the controller pose written as bMe_true E(delta)^-1 (so that the
    true pose is the measured one times E(delta), delta ~ N(0, pose_sd) per component), image noise
    added. Seeded: the same options give the same data.
  */
  static vpSelfCalibDataset simulateEyeToHand(const EyeToHandOptions &options, EyeToHandTruth &truth);
  /*!
    The eye-to-hand options with the fixed camera of the rendered set-up
    (vpSelfCalibEyeToHandRenderer::simulation()): 1280 x 720 pixels, f 1000 px, the principal point
    at the image's centre; the other options their defaults.
  */
  static EyeToHandOptions eyeToHandHd();

private:
  bool inverseKinematics(const vpHomogeneousMatrix &fMc, const vpColVector &q0, vpColVector &q) const;

  Options m_opt;
  vpKinematicChain m_nominal, m_true;
  vpColVector m_home, m_centre;
  std::vector<vpColVector> m_points;
};

#endif
