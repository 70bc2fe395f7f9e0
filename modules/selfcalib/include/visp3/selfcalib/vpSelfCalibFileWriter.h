/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpSelfCalibFileWriter.h
  \brief Atomic writes of output files, as the module writes its own (models, datasets, URDF, reports):
  the content goes to a temporary file beside the target ("<file>.tmp"), which is then renamed
  into place, so a failed write never leaves half a file, nor the temporary file.
*/
#ifndef VP_SELFCALIB_FILE_WRITER_H
#define VP_SELFCALIB_FILE_WRITER_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <functional>
#include <string>

/*!
  \class vpSelfCalibFileWriter
  \ingroup group_selfcalib_io
  \brief Atomic writes of output files, as the module writes its own (models, datasets, URDF,
  reports): the content goes to a temporary file beside the target ("<file>.tmp"), which is then
  renamed into place, so a failed write never leaves half a file, nor the temporary file.

  Errors throw vpSelfCalibException (ioError) naming the kind of file (`what`) and the file.
*/
class VISP_SELFCALIB_EXPORT vpSelfCalibFileWriter
{
public:
  //! Writes `content` to `filename`.
  static void write(const std::string &filename, const std::string &content, const std::string &what = "file");

  /*!
    For a writer that creates the file itself from a path (vpXmlParserCamera::save, say): `fill`
    gets the temporary file's path (any stale file there is removed first), writes it and returns
    false when that fails.
  */
  static void writeWith(const std::string &filename, const std::function<bool(const std::string &)> &fill,
                        const std::string &what = "file");
};

#endif
