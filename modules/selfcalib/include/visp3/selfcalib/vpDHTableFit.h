/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpDHTableFit.h
  \brief A corrected DH or modified-DH table fitted to a calibrated model, for controllers that
  load a table.
*/
#ifndef VP_DH_TABLE_FIT_H
#define VP_DH_TABLE_FIT_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <cstdint>
#include <string>

#include <visp3/selfcalib/vpKinematicChain.h>

/*!
  \class vpDHTableFit
  \ingroup group_selfcalib_kinematics
  \brief A corrected DH or modified-DH table (rows, base fMb, hand-eye eMc; the flange nMe kept),
  without corrections, whose fMc(q) equals a calibrated model's.

  The calibrated model is a product of 6-D corrections; a DH table has 4 parameters per joint, so it
  is fitted (Ceres, numeric derivatives) on sampled joint vectors, from the model's rows (converted
  when the conventions differ). Representable when the largest pose difference over the samples is
  below the tolerances. Consecutive nominally parallel axes (PUMA 560, Viper850 joints 2 and 3) are
  the known weak case: a small tilt between them is representable only with a common normal far
  away (for a 0.1 degree tilt, d of about 150 m on both rows, cancelling); the fit then says it is
  exact but ill-conditioned (well_conditioned = false) and that the YAML model or the URDF
  (vpModelExport) should be used.
*/
class VISP_SELFCALIB_EXPORT vpDHTableFit
{
public:
  //! Settings of vpDHTableFit (the defaults are the member initialisers).
  struct Options {
    unsigned int samples = 100;        //!< joint vectors drawn uniformly within the limits
    uint64_t seed = 1;
    double tolerance_position = 1e-9;  //!< m
    double tolerance_rotation = 1e-9;  //!< rad
    unsigned int max_iterations = 200;
    //! Throws vpSelfCalibException unless samples >= 3, max_iterations >= 1 and the tolerances are positive.
    void check() const;
  };
  //! The result of vpDHTableFit: what it computed, and what the caller needs to judge it.
  struct Result {
    bool representable = false;
    std::string message;
    vpKinematicChain table;            //!< DH or MDH rows, fMb, nMe, eMc; no corrections
    double max_position_error = 0;     //!< m, over the samples
    double max_rotation_error = 0;     //!< rad
    bool well_conditioned = true;      //!< false: a row's a or d exceeds 10 times the model's largest
  };
  static Result fit(const vpKinematicChain &model, vpKinematicChain::Convention convention, const Options &options);
  //! fit() with the default options.
  static Result fit(const vpKinematicChain &model, vpKinematicChain::Convention convention);
};

#endif
