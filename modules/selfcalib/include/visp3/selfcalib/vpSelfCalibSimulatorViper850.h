/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpSelfCalibSimulatorViper850.h
  \brief ViSP's simulated Viper850, headless and moved instantly: the robot interface acquisition code
  talks to (through vpRobot) in the simulated scenario.
*/
#ifndef VP_SELFCALIB_SIMULATOR_VIPER850_H
#define VP_SELFCALIB_SIMULATOR_VIPER850_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <visp3/robot/vpSimulatorViper850.h>
#include <visp3/selfcalib/vpKinematicChain.h>

/*!
  \class vpSelfCalibSimulatorViper850
  \ingroup group_selfcalib_simulation
  \brief ViSP's simulated Viper850, headless and moved instantly: the robot interface acquisition
  code talks to (through vpRobot) in the simulated scenario.

  vpSimulatorViper850::setPosition() busy-waits on the simulator's thread (10 ms to 80 s a move).
  Here an ARTICULAR_FRAME setPosition() sets the joints at once and exactly. The simulator's thread
  is put in constant-sampling mode, in which it only integrates after a setVelocity() call, so it
  never races with these moves. Velocity control is not used by the self-calibration.

  vpSimulatorViper850's constructor prints its default camera on std::cout; this class's
  constructor discards that text (std::cout writes nowhere while the base class is constructed, so
  another thread's output to std::cout in that moment is lost too).

  ViSP 3.5 limits: construct at most one instance at a time (two alive at once crash at exit).
*/
class VISP_SELFCALIB_EXPORT vpSelfCalibSimulatorViper850 : public vpSimulatorViper850
{
public:
  vpSelfCalibSimulatorViper850();

  /*!
    The nominal model of this robot: the viper850 preset with the simulator's narrower joint limits
    and its camera mounting (45 um from vpViper850's default tool in ViSP 3.5).
  */
  vpKinematicChain getNominalChain() const;

  using vpSimulatorViper850::setPosition;
  //! Instant move; only ARTICULAR_FRAME. Throws vpSelfCalibException outside the joint limits.
  void setPosition(const vpRobot::vpControlFrameType frame, const vpColVector &q) override;
};

#endif
