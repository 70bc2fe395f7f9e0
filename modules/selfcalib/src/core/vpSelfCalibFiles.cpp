/*
 * ViSP SelfCalib: atomic file writes through a temporary file beside the target.
 */
#include "vpSelfCalibFiles.h"

#include <fstream>
#include <system_error>

#include <visp3/selfcalib/vpSelfCalibException.h>

namespace vpSelfCalib
{
namespace
{
void removeQuietly(const std::filesystem::path &p)
{
  std::error_code ec;
  std::filesystem::remove(p, ec);
}
} // namespace

std::filesystem::path temporaryFileFor(const std::filesystem::path &file)
{
  std::filesystem::path tmp = file;
  tmp += ".tmp";
  return tmp;
}

void writeFileAtomicallyWith(const std::string &filename, const std::function<bool(const std::string &)> &fill,
                             const std::string &what)
{
  const std::filesystem::path tmp = temporaryFileFor(filename);
  removeQuietly(tmp);
  bool written = false;
  try {
    written = fill(tmp.string());
  } catch (...) {
    removeQuietly(tmp);
    throw;
  }
  if (!written) {
    removeQuietly(tmp);
    throw vpSelfCalibException(vpSelfCalibException::ioError,
                               what + " '" + filename + "': cannot write '" + tmp.string() + "'");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, filename, ec);
  if (ec) {
    removeQuietly(tmp);
    throw vpSelfCalibException(vpSelfCalibException::ioError,
                               what + " '" + filename + "': cannot rename the temporary file into place");
  }
}

void writeFileAtomically(const std::string &filename, const std::string &content, const std::string &what)
{
  writeFileAtomicallyWith(
      filename,
      [&](const std::string &tmp) {
        std::ofstream os(tmp, std::ios::binary | std::ios::trunc);
        if (!os)
          throw vpSelfCalibException(vpSelfCalibException::ioError,
                                     what + " '" + filename + "': cannot open '" + tmp + "' for writing");
        os << content;
        os.flush();
        if (!os)
          throw vpSelfCalibException(vpSelfCalibException::ioError, what + " '" + filename + "': write failed");
        return true;
      },
      what);
}
} // namespace vpSelfCalib
