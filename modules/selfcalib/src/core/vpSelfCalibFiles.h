/*
 * ViSP SelfCalib: private atomic file writes (not installed). Every file the module and its tools
 * write goes through here: the content goes to a temporary file beside the target, which is then
 * renamed into place, so a failed write never leaves half a file, nor the temporary file.
 */
#ifndef VP_SELFCALIB_FILES_H
#define VP_SELFCALIB_FILES_H

#include <filesystem>
#include <functional>
#include <string>

namespace vpSelfCalib
{
//! The temporary file an atomic write of `file` goes through: `file` with ".tmp" appended.
std::filesystem::path temporaryFileFor(const std::filesystem::path &file);

/*!
  Writes `content` to `filename` atomically. Throws vpSelfCalibException (ioError) naming `what`
  (the kind of file: "robot model", "URDF"...) and the file when the temporary file cannot be
  opened or written, or cannot be renamed into place.
*/
void writeFileAtomically(const std::string &filename, const std::string &content, const std::string &what);

/*!
  As above for a writer that creates the file itself from a path (vpXmlParserCamera::save, say):
  `fill` writes the temporary file (any stale one is removed first) and returns false when it
  fails; an exception it throws goes through after the temporary file is removed.
*/
void writeFileAtomicallyWith(const std::string &filename, const std::function<bool(const std::string &)> &fill,
                             const std::string &what);
} // namespace vpSelfCalib

#endif
