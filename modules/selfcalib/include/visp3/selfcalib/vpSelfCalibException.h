/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpSelfCalibException.h
  \brief Error raised by ViSP SelfCalib for caller mistakes: bad arguments, malformed or inconsistent
  files, calls in the wrong order.
*/
#ifndef VP_SELFCALIB_EXCEPTION_H
#define VP_SELFCALIB_EXCEPTION_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <string>

#include <visp3/core/vpException.h>

/*!
  \class vpSelfCalibException
  \ingroup group_selfcalib_core
  \brief Error raised by ViSP SelfCalib for caller mistakes: bad arguments, malformed or
  inconsistent files, calls in the wrong order.

  Numerical failures (degenerate motion, rank loss, no convergence) are never thrown: they are
  reported as a status in the Result struct of the estimator concerned.
*/
class VISP_SELFCALIB_EXPORT vpSelfCalibException : public vpException
{
public:
  enum errorCodeEnum {
    badValue = 100,   //!< an argument or a value in a file is out of its domain (NaN, min > max...)
    dimensionError,   //!< sizes do not agree (joint vector length, parameter vector length...)
    parseError,       //!< a file is malformed: missing key, wrong type, unknown name
    ioError,          //!< a file cannot be read or written
    notInitialized    //!< an object is used before it was set up
  };

  vpSelfCalibException(int code, const std::string &msg) : vpException(code, msg) {}
};

#endif
