/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpSelfCalibTextFile.h
  \brief Bounded reads of input text files, as the module reads its own (datasets, robot models,
  tag bundles, results).
*/
#ifndef VP_SELFCALIB_TEXT_FILE_H
#define VP_SELFCALIB_TEXT_FILE_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <cstddef>
#include <string>

/*!
  \class vpSelfCalibTextFile
  \ingroup group_selfcalib_io
  \brief Reads an input text file whole, bounded, as the module reads its own: what a tool reads
  from a path its user gives (a joints file, a plan) fails with a clear message instead of blocking
  or filling the memory.
*/
class VISP_SELFCALIB_EXPORT vpSelfCalibTextFile
{
public:
  /*!
    The content of the text file `filename`, at most `max_bytes` of it, counted while reading. The
    file is opened without blocking: a FIFO no program writes to reads as empty and is refused
    (instead of blocking the open for ever), a pipe with a writer (a shell's <(...)) is read to its
    end. A regular file larger than the limit is refused before reading, a device or a stream
    without end once the limit is passed, and a NUL byte (never in a text file: /dev/zero, a binary
    file) as soon as it is read, with its line. Throws vpSelfCalibException (ioError, or parseError
    for a NUL byte) whose message starts with `what` (the kind of file: "joints file", "dataset")
    and the file: "joints file 'j.txt': cannot read: No such file or directory", "...: cannot read:
    Is a directory", "...: a NUL byte on line 3: not a text file", "...: more than the 64 MiB read",
    "...: a FIFO that no program writes to (read as empty)", a read error, out of memory.
  */
  static std::string read(const std::string &filename, const std::string &what, std::size_t max_bytes);
};

#endif
