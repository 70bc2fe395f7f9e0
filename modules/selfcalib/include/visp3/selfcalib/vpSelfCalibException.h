/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 */
#ifndef VP_SELFCALIB_EXCEPTION_H
#define VP_SELFCALIB_EXCEPTION_H

#include <string>

#include <visp3/core/vpException.h>

/*!
  \class vpSelfCalibException
  \brief Error raised by ViSP SelfCalib for caller mistakes: bad arguments, malformed or
  inconsistent files, calls in the wrong order.

  Numerical failures (degenerate motion, rank loss, no convergence) are never thrown: they are
  reported as a status in the Result struct of the estimator concerned.
*/
class vpSelfCalibException : public vpException
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
