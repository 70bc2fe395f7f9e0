/*
 * ViSP SelfCalib: vpSelfCalibTextFile, the module's bounded text file reader for its users.
 */
#include <visp3/selfcalib/vpSelfCalibTextFile.h>

#include "../core/vpSelfCalibFiles.h" // readTextFileBounded

std::string vpSelfCalibTextFile::read(const std::string &filename, const std::string &what, std::size_t max_bytes)
{
  return vpSelfCalib::readTextFileBounded(filename, what, max_bytes);
}
