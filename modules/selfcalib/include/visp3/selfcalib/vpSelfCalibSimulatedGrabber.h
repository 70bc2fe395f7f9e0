/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpSelfCalibSimulatedGrabber.h
  \brief A vpFrameGrabber that renders what the camera of a simulated robot sees (vpSelfCalibRenderer
  at the joints the robot reports): the image source of a simulated acquisition.
*/
#ifndef VP_SELFCALIB_SIMULATED_GRABBER_H
#define VP_SELFCALIB_SIMULATED_GRABBER_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <visp3/core/vpColVector.h>
#include <visp3/core/vpFrameGrabber.h>
#include <visp3/robot/vpRobot.h>
#include <visp3/selfcalib/vpSelfCalibRenderer.h>

/*!
  \class vpSelfCalibSimulatedGrabber
  \ingroup group_selfcalib_acquisition
  \brief A vpFrameGrabber that renders what the camera of a simulated robot sees: acquire() reads
  the robot's joints (vpRobot::ARTICULAR_FRAME) and renders the scene through the simulator's true
  robot at those joints (vpSelfCalibRenderer). On a real set-up, a camera's grabber (vp1394TwoGrabber,
  vpV4l2Grabber, vpRealSense2...) takes its place.

  The image noise of a pose is drawn from a stream chosen by the joint values (viewIndex()), so
  the same pose gives the same image whenever and in whatever order it is grabbed (a resumed
  acquisition writes the images an uninterrupted one would).
*/
class VISP_SELFCALIB_EXPORT vpSelfCalibSimulatedGrabber : public vpFrameGrabber
{
public:
  //! The robot and the renderer must outlive the grabber.
  vpSelfCalibSimulatedGrabber(vpRobot &robot, const vpSelfCalibRenderer &renderer);

  void open(vpImage<unsigned char> &I) override;
  void open(vpImage<vpRGBa> &I) override;
  void acquire(vpImage<unsigned char> &I) override;
  void acquire(vpImage<vpRGBa> &I) override;
  void close() override {}

  //! The noise stream of the image at joints q: a hash of their bits.
  static unsigned int viewIndex(const vpColVector &q);

private:
  vpRobot &m_robot;
  const vpSelfCalibRenderer &m_renderer;
};

#endif
