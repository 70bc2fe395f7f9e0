/*
 * ViSP SelfCalib: the public entry point of the module's atomic file writes.
 */
#include <visp3/selfcalib/vpSelfCalibFileWriter.h>

#include "../core/vpSelfCalibFiles.h"

void vpSelfCalibFileWriter::write(const std::string &filename, const std::string &content, const std::string &what)
{
  vpSelfCalib::writeFileAtomically(filename, content, what);
}

void vpSelfCalibFileWriter::writeWith(const std::string &filename, const std::function<bool(const std::string &)> &fill,
                                      const std::string &what)
{
  vpSelfCalib::writeFileAtomicallyWith(filename, fill, what);
}
