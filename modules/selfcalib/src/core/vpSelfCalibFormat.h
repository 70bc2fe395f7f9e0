/*
 * ViSP SelfCalib: how the library writes a number into a message (findings, errors).
 */
#ifndef VP_SELFCALIB_FORMAT_H
#define VP_SELFCALIB_FORMAT_H

#include <ios>
#include <sstream>
#include <string>

namespace vpSelfCalib
{
//! v in fixed-point notation with `digits` digits after the point ("12.35" for 12.3456, 2).
inline std::string fixed(double v, int digits)
{
  std::ostringstream os;
  os.setf(std::ios::fixed);
  os.precision(digits);
  os << v;
  return os.str();
}
} // namespace vpSelfCalib

#endif
