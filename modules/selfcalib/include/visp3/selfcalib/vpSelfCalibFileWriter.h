/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpSelfCalibFileWriter.h
  \brief Atomic writes of output files, as the module writes its own (models, datasets, URDF, reports):
  the content goes to a temporary file beside the target, which is then renamed into place, so a
  failed write never leaves half a file, nor the temporary file; and directories of results
  written as one set (vpSelfCalibOutputDirectory).
*/
#ifndef VP_SELFCALIB_FILE_WRITER_H
#define VP_SELFCALIB_FILE_WRITER_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpImage.h>

namespace vpSelfCalib
{
class OutputDirectory;
}

/*!
  \class vpSelfCalibFileWriter
  \ingroup group_selfcalib_io
  \brief Atomic writes of output files, as the module writes its own (models, datasets, URDF,
  reports): the content goes to a temporary file beside the target, created exclusively under a
  fresh name (`.NAME.tmp-XXXXXXXX.EXT`: never a file that exists, never through a symbolic link),
  flushed to disk, then renamed into place, so a failed write never leaves half a file, nor the
  temporary file. A write holds the target's lock (`.NAME.lock` beside it, released by the system
  when the process ends, killed or not; writers of one file take turns) and removes the temporary
  files killed writers of that target left: no live writer owns one while the lock is held.

  Errors throw vpSelfCalibException (ioError) naming the kind of file (`what`), the file and the
  system's reason (errno text, e.g. "No space left on device"). Thread-safe.
*/
class VISP_SELFCALIB_EXPORT vpSelfCalibFileWriter
{
public:
  //! Writes `content` to `filename`.
  static void write(const std::string &filename, const std::string &content, const std::string &what = "file");

  /*!
    For a writer that creates the file itself from a path: `fill` gets the temporary file's path
    (a new empty file), writes it and returns false when that fails.
  */
  static void writeWith(const std::string &filename, const std::function<bool(const std::string &)> &fill,
                        const std::string &what = "file");

  /*!
    A camera in ViSP's XML (vpXmlParserCamera, camera `name`, image size), read back before it is
    renamed into place: a writer that hides its write errors (a full disk) cannot leave a
    truncated file.
  */
  static void writeCameraXml(const std::string &filename, const vpCameraParameters &cam, const std::string &name,
                             unsigned int width, unsigned int height, const std::string &comment);

  //! An image encoded by OpenCV in memory (format from the extension: .png, .jpg...), then written as above.
  static void writeImage(const std::string &filename, const vpImage<unsigned char> &image);
};

/*!
  \class vpSelfCalibOutputDirectory
  \ingroup group_selfcalib_io
  \brief A directory of results written as one set (visp-selfcalib calibrate's --out).

  The constructor locks the directory (a file `.NAME.lock` beside it, released by the system when
  the process ends, killed or not): a second writer is refused with an error saying so. It removes
  what killed runs left (`.NAME.tmp-*` beside it) and creates a private temporary directory beside
  the target, where the files are written (staging()). commit() puts the whole set in place at
  once (a rename, or an atomic exchange with the earlier set, which is then removed): a reader or
  a kill sees the earlier set or the new one, never a mix. Without commit() the destructor removes
  the temporary directory and leaves the target as it was.
*/
class VISP_SELFCALIB_EXPORT vpSelfCalibOutputDirectory
{
public:
  explicit vpSelfCalibOutputDirectory(const std::string &directory);
  ~vpSelfCalibOutputDirectory();
  vpSelfCalibOutputDirectory(const vpSelfCalibOutputDirectory &) = delete;
  vpSelfCalibOutputDirectory &operator=(const vpSelfCalibOutputDirectory &) = delete;

  //! The target directory, as an absolute path.
  const std::string &target() const;
  //! Where the set is written before commit().
  const std::string &staging() const;
  //! Names of the entries of the target directory as it is now (empty when it does not exist).
  std::vector<std::string> existingEntries() const;
  void commit();

private:
  std::unique_ptr<vpSelfCalib::OutputDirectory> m_impl;
};

#endif
