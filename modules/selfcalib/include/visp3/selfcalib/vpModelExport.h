/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpModelExport.h
  \brief A calibrated model in the forms a controller loads (the robot-model YAML itself is
  vpKinematicChain::saveYaml()):.
*/
#ifndef VP_MODEL_EXPORT_H
#define VP_MODEL_EXPORT_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <cstdint>
#include <string>

#include <visp3/selfcalib/vpKinematicChain.h>

/*!
  \class vpModelExport
  \ingroup group_selfcalib_io
  \brief A calibrated model in the forms a controller loads (the robot-model YAML itself is
  vpKinematicChain::saveYaml()):

  - fitDH(): a corrected DH or modified-DH table (rows, base fMb, hand-eye eMc; the flange nMe kept),
    without corrections, whose fMc(q) equals the model's. The calibrated model is a product of
    6-D corrections; a DH table has 4 parameters per joint, so it is fitted (Ceres, numeric
    derivatives) on sampled joint vectors, from the model's rows (converted when the conventions
    differ). Representable when the largest pose difference over the samples is below the
    tolerances. Consecutive nominally parallel axes (PUMA 560, Viper850 joints 2 and 3) are the known
    weak case: a small tilt between them is representable only with a common normal far away (for
    a 0.1° tilt, d of about 150 m on both rows, cancelling); the fit then says it is exact but
    ill-conditioned (well_conditioned = false) and that the YAML model or the URDF should be used.
  - toURDF(): the model as URDF joint origins (xyz, rpy), exact for any corrections: base_link (the
    frame f), one revolute joint per axis (origin = vpKinematicChain::getPlacements(), axis z,
    limits), a fixed flange joint and a fixed camera joint (camera_optical_frame, ViSP's camera
    frame: z forward, x right, y down).
*/
class VISP_SELFCALIB_EXPORT vpModelExport
{
public:
  struct DHOptions {
    unsigned int samples = 100;        //!< joint vectors drawn uniformly within the limits
    uint64_t seed = 1;
    double tolerance_position = 1e-9;  //!< m
    double tolerance_rotation = 1e-9;  //!< rad
    unsigned int max_iterations = 200;
    void check() const;
  };
  struct DHFit {
    bool representable = false;
    std::string message;
    vpKinematicChain table;            //!< DH or MDH rows, fMb, nMe, eMc; no corrections
    double max_position_error = 0;     //!< m, over the samples
    double max_rotation_error = 0;     //!< rad
    bool well_conditioned = true;      //!< false: a row's a or d exceeds 10 times the model's largest
  };
  static DHFit fitDH(const vpKinematicChain &model, vpKinematicChain::Convention convention,
                     const DHOptions &options);
  static DHFit fitDH(const vpKinematicChain &model, vpKinematicChain::Convention convention);

  //! URDF text (17 significant digits); robot_name empty: the model's name.
  static std::string toURDF(const vpKinematicChain &model, const std::string &robot_name = "");
  //! Written atomically (temporary file, then rename).
  static void saveURDF(const vpKinematicChain &model, const std::string &filename);
};

#endif
