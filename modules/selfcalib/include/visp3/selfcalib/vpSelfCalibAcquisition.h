/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpSelfCalibAcquisition.h
  \brief Acquisition of a self-calibration dataset over any vpRobot and any image source: planned
  configurations visited in a short-travel order, joints read back, images, the dataset written as
  it goes and resumed after an interruption; teach mode.
*/
#ifndef VP_SELFCALIB_ACQUISITION_H
#define VP_SELFCALIB_ACQUISITION_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <functional>
#include <string>
#include <vector>

#include <visp3/core/vpColVector.h>
#include <visp3/core/vpFrameGrabber.h>
#include <visp3/core/vpImage.h>
#include <visp3/robot/vpRobot.h>
#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>

/*!
  \class vpSelfCalibAcquisition
  \ingroup group_selfcalib_acquisition
  \brief Drives a robot (any vpRobot: setPosition / getPosition in vpRobot::ARTICULAR_FRAME)
  through planned joint configurations and records, at each, the joints the robot reports (not the
  commanded ones) and an image (a vpFrameGrabber or a callback), into a dataset file.

  - <b>Order.</b> run() visits the configurations in an order that keeps the joint travel short
    (shortTravelOrder(): nearest neighbour from the first configuration, then 2-opt), separately
    for the first Options::calibration_poses and for the rest, so that the dataset's first views
    are still the calibration views and the others the held-out ones. The order depends on the
    plan only, never on where the robot is, so a resumed run visits the same poses in the same order.
  - <b>Safety.</b> Every configuration is checked against the model's joint limits before the
    first move (a configuration outside them is a caller error: vpSelfCalibException, nothing
    moves) and again before each move.
  - <b>Settling.</b> After each move, Options::settle_time seconds pass before the joints are read
    and the image is grabbed.
  - <b>Writing as it goes.</b> After each pose the image (images/NNNN.png beside the dataset file)
    and then the dataset are written atomically (temporary file, then rename): the dataset on disk
    is always complete and readable, and lists only poses whose image is written.
  - <b>Resume.</b> When the dataset file exists, run() reads it, checks that its views are the first
    ones of this plan's order (joints within Options::resume_tolerance of the planned ones; camera
    and robot as in Options::header) and continues from the next pose: an interrupted run (killed,
    robot error) gives, once resumed, the dataset of an uninterrupted run.
  - <b>Errors.</b> A robot that throws, refuses a move or ends farther than
    Options::reach_tolerance from the commanded joints, or a grabber that throws, stops the run
    with status ROBOT_ERROR or IMAGE_ERROR and a message saying which pose and what happened; the
    dataset written so far is kept intact.
  - <b>Teach mode.</b> record() appends the current pose (joints read, image grabbed) on request,
    while a person moves the arm (hand guiding).

  Library code never prints: progress goes through a callback.
*/
class VISP_SELFCALIB_EXPORT vpSelfCalibAcquisition
{
public:
  //! An image source other than a vpFrameGrabber: fills the image, throws on failure.
  using ImageSource = std::function<void(vpImage<unsigned char> &)>;
  //! Progress: poses in the dataset, poses planned, what was done ("pose 3 of 25 recorded"...).
  using Progress = std::function<void(unsigned int, unsigned int, const std::string &)>;

  //! Settings of vpSelfCalibAcquisition (the defaults are the member initialisers).
  struct Options {
    std::string dataset_file;            //!< the dataset YAML written (required)
    std::string image_dir = "images";    //!< relative to the dataset file's directory
    vpSelfCalibDataset header;           //!< camera, robot, yardstick of the dataset (views ignored)
    unsigned int calibration_poses = 0;  //!< the first ones, ordered apart from the rest (0: all together)
    bool reorder = true;                 //!< false: visit in plan order
    double settle_time = 0;              //!< s, waited after each move
    double reach_tolerance = 0.01;       //!< rad: a joint farther than this from its command is an error
    double resume_tolerance = 0.01;      //!< rad: a recorded view matches its planned configuration
    //! Throws vpSelfCalibException on nonsense (no dataset file, negative times or tolerances).
    void check() const;
  };

  enum Status { OK, ROBOT_ERROR, IMAGE_ERROR };
  //! The result of vpSelfCalibAcquisition: what it computed, and what the caller needs to judge it.
  struct Result {
    Status status = OK;
    std::string message;
    unsigned int resumed = 0;   //!< poses found in the dataset file at the start
    unsigned int acquired = 0;  //!< poses recorded by this run
    unsigned int total = 0;     //!< poses in the dataset at the end
    std::vector<unsigned int> order; //!< plan indices in visiting order
    double travel_plan_order = 0, travel = 0; //!< rad, summed joint distances (Euclidean), plan and visiting order
    vpSelfCalibDataset dataset; //!< as written
  };

  //! The robot, the model (joint limits) and the grabber must outlive the acquisition.
  vpSelfCalibAcquisition(vpRobot &robot, const vpKinematicChain &model, vpFrameGrabber &grabber,
                         const Options &options);
  vpSelfCalibAcquisition(vpRobot &robot, const vpKinematicChain &model, const ImageSource &source,
                         const Options &options);

  /*!
    Visits the plan (resuming a dataset file that exists). Throws vpSelfCalibException on caller
    errors: an empty plan, a configuration of the wrong size or outside the model's joint limits,
    an existing dataset that is not the start of this acquisition. Robot and image failures are a
    status (the dataset so far kept).
  */
  Result run(const std::vector<vpColVector> &plan, const Progress &progress = Progress());

  /*!
    Teach mode: reads the current joints, grabs an image and appends them to the dataset (created
    when missing). Refuses (status ROBOT_ERROR) a pose outside the model's joint limits.
  */
  Result record(const Progress &progress = Progress());

  //! Plan indices in a short-travel order: nearest neighbour from index 0, improved by 2-opt.
  static std::vector<unsigned int> shortTravelOrder(const std::vector<vpColVector> &configurations);
  //! Summed Euclidean joint distances along the configurations in the given order.
  static double travel(const std::vector<vpColVector> &configurations, const std::vector<unsigned int> &order);

  //! Status names: "ok", "robot error", "image error".
  static const char *statusName(Status s);

private:
  Result recordPose(vpSelfCalibDataset &ds, const vpColVector *command, unsigned int index, const std::string &what);
  vpSelfCalibDataset loadExisting() const;

  vpRobot &m_robot;
  const vpKinematicChain &m_model;
  ImageSource m_source;
  Options m_opt;
};

#endif
