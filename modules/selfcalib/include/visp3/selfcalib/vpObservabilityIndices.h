/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpObservabilityIndices.h
  \brief Observability of a set of measurement configurations, from the singular values sigma_1 >= .
*/
#ifndef VP_OBSERVABILITY_INDICES_H
#define VP_OBSERVABILITY_INDICES_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <vector>

#include <visp3/core/vpMatrix.h>

/*!
  \class vpObservabilityIndices
  \ingroup group_selfcalib_identification
  \brief Observability of a set of measurement configurations, from the singular values
  sigma_1 >= ... >= sigma_L > 0 of the identification Jacobian J (L identified parameters, m
  measurement configurations), in the convention of Sun and Hollerbach (ICRA 2008):

  - O1 (Borm and Menq):            (sigma_1 sigma_2 ... sigma_L)^(1/L) / sqrt(m)
  - O2 (Driels and Pathre):        sigma_L / sigma_1 (the inverse of the condition number, eq. 7)
  - O3 (Nahvi, Hollerbach, Hayward): sigma_L
  - O4 (Nahvi and Hollerbach, noise amplification index): sigma_L^2 / sigma_1
  - O5 (Sun and Hollerbach):       1 / (1/sigma_1 + ... + 1/sigma_L)

  Larger is better for all five. The condition number of the paper (eq. 7) is sigma_1 / sigma_L.

  Convention of this module for J: rows are the pose residuals divided by their expected noise
  (dimensionless), columns the identified parameters in SI units (m, rad); so sigma is in 1/m or
  1/rad, and the indices of two plans are comparable only with the same noise model and units.
*/
struct VISP_SELFCALIB_EXPORT vpObservabilityIndices {
  double O1 = 0, O2 = 0, O3 = 0, O4 = 0, O5 = 0;
  double condition_number = 0; //!< sigma_1 / sigma_L (eq. 7); infinite when sigma_L = 0

  //! From singular values in any order; m is the number of measurement configurations.
  //! Throws vpSelfCalibException when the list is empty, a value is negative or m is 0.
  static vpObservabilityIndices fromSingularValues(std::vector<double> sigma, unsigned int m);
  //! From the Jacobian (its singular values by SVD).
  static vpObservabilityIndices fromJacobian(const vpMatrix &J, unsigned int m);
};

#endif
