/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpKinematicChainUrdf.h
  \brief URDF import: the serial chain from a base link to a tip link of a URDF (urdfdom) as a
  vpKinematicChain (a DH or modified-DH table with its base, flange and hand-eye frames).
*/
#ifndef VP_KINEMATIC_CHAIN_URDF_H
#define VP_KINEMATIC_CHAIN_URDF_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <string>
#include <vector>

#include <visp3/core/vpPoseVector.h>
#include <visp3/selfcalib/vpKinematicChain.h>

/*!
  \class vpKinematicChainUrdf
  \ingroup group_selfcalib_io
  \brief URDF import: the serial chain from a base link to a tip link of a URDF (parsed with
  urdfdom) as a vpKinematicChain, with the same complete error model as any other chain.

  <b>What is read.</b> The joints on the path from the base link (the frame f) to the tip link (the
  flange, frame e): revolute and continuous joints with their origin (xyz, rpy), axis and limits
  (continuous: -pi..pi), fixed joints folded into the placements. The camera frame c is a link
  below the tip reached through fixed joints only (ViSP's camera frame: z forward, x right, y down,
  as a ROS `*_optical_frame`), or a fixed transform eMc given in the options. Joint angle 0 of the
  chain is joint angle 0 of the URDF, positive in the same sense.

  <b>How.</b> At q = 0 every joint axis is a line in f. The lines are turned into a DH (or Craig
  modified-DH) table by the common-normal construction: frame i's z axis on axis i + 1 (DH) or i
  (MDH), x along the common normal of consecutive axes, its sign taken from the URDF's own joint
  frame so that a URDF written from a DH table gives that table back; consecutive parallel axes
  take the common normal through the previous frame's origin (d = 0), coaxial ones the URDF joint
  frame. The base frame fMb is the base link when it is a valid frame 0 of the table, else the
  first joint's frame; what follows the last joint is the flange nMe. The forward kinematics of
  the result equals the URDF's to rounding (the import checks it and throws on a mismatch).
  Options::convention AUTO picks the convention whose frames are closer to the URDF's joint
  frames (a URDF written from a modified-DH table gives MDH back), DH on a tie.

  <b>Errors</b> (vpSelfCalibException, naming the source): a malformed file (urdfdom's message),
  a loop (a link that is the child of two joints, or no root link), a base or tip link that does
  not exist or a tip that is not below the base, a prismatic, planar or floating joint on the
  chain, a zero axis, no revolute joint, a camera link not below the tip or reached through a
  moving joint.
*/
class VISP_SELFCALIB_EXPORT vpKinematicChainUrdf
{
public:
  enum Convention { AUTO, DH, MDH };

  //! Settings of vpKinematicChainUrdf (the defaults are the member initialisers).
  struct Options {
    //! Empty: the URDF's root link.
    std::string base_link;
    /*!
      Empty: the parent link of the camera link's fixed sub-chain when a camera link is found,
      else the end of the chain from the base (the link where it ends or branches).
    */
    std::string tip_link;
    /*!
      Empty: the link named "camera_optical_frame" when there is one below the tip (what
      vpModelExport::toURDF() writes), else no camera link and eMc below is used.
    */
    std::string camera_link;
    //! Hand-eye transform when there is no camera link (tip link to camera, pose vector).
    vpPoseVector eMc;
    Convention convention = AUTO;
    //! Empty: the URDF's robot name.
    std::string name;
  };

  //! Reads a URDF file. Throws vpSelfCalibException (see the class description).
  static vpKinematicChain load(const std::string &filename, const Options &options);
  //! load() with the default options.
  static vpKinematicChain load(const std::string &filename);
  //! The same from URDF text; `source` names it in the messages.
  static vpKinematicChain fromString(const std::string &urdf, const Options &options,
                                     const std::string &source = "<string>");

  /*!
    True when the name ends in .urdf (any case): vpKinematicChain::fromPresetOrFile(), which every
    tool uses to read a robot model, then reads it with load() and the default options.
  */
  static bool isUrdfFile(const std::string &filename);
};

#endif
