/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpModelExport.h
  \brief A calibrated model as URDF joint origins, for a controller or a robot description.
*/
#ifndef VP_MODEL_EXPORT_H
#define VP_MODEL_EXPORT_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <string>

#include <visp3/selfcalib/vpKinematicChain.h>

/*!
  \class vpModelExport
  \ingroup group_selfcalib_io
  \brief A calibrated model in the forms a controller loads (the robot-model YAML itself is
  vpKinematicChain::saveYaml(); a corrected DH or modified-DH table is vpDHTableFit::fit()):

  - toURDF(): the model as URDF joint origins (xyz, rpy), exact for any corrections: base_link (the
    frame f), one revolute joint per axis (origin = vpKinematicChain::getPlacements(), axis z,
    limits), a fixed flange joint and a fixed camera joint (camera_optical_frame, ViSP's camera
    frame: z forward, x right, y down).
  - eye-to-hand (a camera fixed in the world): the camera joint's parent is base_link with the
    origin bMc, and the target carried by the tool, when known, a fixed joint from the flange
    (link `target`, origin eMo).
*/
class VISP_SELFCALIB_EXPORT vpModelExport
{
public:
  //! URDF text (17 significant digits); robot_name empty: the model's name.
  static std::string toURDF(const vpKinematicChain &model, const std::string &robot_name = "");
  //! Eye-to-hand: the camera a link of the world (bMc from base_link), the target eMo on the flange
  //! (either null: as toURDF() above for the camera, no target link).
  static std::string toURDF(const vpKinematicChain &model, const std::string &robot_name, const vpHomogeneousMatrix *bMc,
                            const vpHomogeneousMatrix *eMo);
  //! Written atomically (temporary file, then rename).
  static void saveURDF(const vpKinematicChain &model, const std::string &filename);
  //! The eye-to-hand form, written atomically.
  static void saveURDF(const vpKinematicChain &model, const std::string &filename, const vpHomogeneousMatrix *bMc,
                       const vpHomogeneousMatrix *eMo);
};

#endif
