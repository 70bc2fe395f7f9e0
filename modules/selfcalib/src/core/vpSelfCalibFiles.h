/*
 * ViSP SelfCalib: private atomic file writes (not installed). Every file the module and its tools
 * write goes through here: the content goes to a temporary file beside the target, created
 * exclusively under a fresh name (never one that exists, never through a symbolic link), flushed
 * to disk and then renamed into place, so a failed write never leaves half a file, nor the
 * temporary file. Every system call is checked and a failure names the file and the system's
 * reason (errno text: "No space left on device"...).
 *
 * OutputDirectory writes a set of files (calibrate's results) as one: the files go to a private
 * temporary directory beside the target directory, which then takes the target's place in one
 * rename (an exchange when the target exists), under a lock on the target.
 */
#ifndef VP_SELFCALIB_FILES_H
#define VP_SELFCALIB_FILES_H

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace vpSelfCalib
{
//! The errno text of `err` ("No space left on device"), thread-safe.
std::string errnoText(int err);

/*!
  What `path` is when it is a device node, a FIFO or a socket, or a symbolic link to one ("a
  character device", "a block device", "a FIFO", "a socket"); empty otherwise (absent, a regular
  file, a directory).
*/
std::string specialFileKind(const std::string &path);

/*!
  Throws (ioError) naming `what` and the kind when `filename` is a device node, a FIFO or a socket
  (specialFileKind): outputs go only where a regular file or a directory may be, with --force or
  not. Every writer below calls it before it writes anything (its lock file included).
*/
void refuseSpecialOutput(const std::string &filename, const std::string &what);

/*!
  The content of the text file `filename`, at most `max_bytes` of it, counted while reading: a
  device or a pipe that never ends is refused with the limit's message once the limit is passed, a
  regular file larger than the limit before reading, and a NUL byte (never in a text file: /dev/zero,
  /dev/urandom, a binary file) as soon as it is read, with its line. Throws vpSelfCalibException
  (ioError, or parseError for a NUL byte) naming `what` and the file: cannot open (errno text), a
  directory, a read error, beyond the limit, out of memory. The module's users read through
  vpSelfCalibTextFile::read().
*/
std::string readTextFileBounded(const std::string &filename, const std::string &what, size_t max_bytes);

//! Pixels of an image decoded at most (width x height), as the dataset reader allows.
constexpr double kMaxDecodedPixels = 2.5e8;

//! An image's size as its header gives it (known: PNG, JPEG, PGM/PPM headers were read).
struct ImageHeader
{
  bool known = false;
  unsigned long long width = 0, height = 0;
};

/*!
  Checks an image file before it is decoded: a regular file (not a directory, a device, a FIFO, a
  socket, a symbolic link loop or nothing), of at most 256 MiB, whose header (PNG IHDR, JPEG SOFn,
  PGM/PPM) gives at most `max_pixels` pixels. Throws vpSelfCalibException (ioError) with
  `context` (e.g. "view 3: cannot read image 'a.png'"), ": " and the reason. Returns the header's
  size (unknown for other formats, which the decoder then checks).
*/
ImageHeader checkImageFile(const std::string &file, const std::string &context, double max_pixels = kMaxDecodedPixels);

/*!
  Creates an empty file beside `file` under a fresh name, `.NAME.tmp-XXXXXXXX` with the extension
  of `file` kept (writers such as image encoders choose the format by it), exclusively (O_EXCL,
  O_NOFOLLOW): a planted file or symbolic link is never written through. Throws (ioError) naming
  `what` and the errno text when that fails.
*/
std::filesystem::path createTemporaryFileFor(const std::filesystem::path &file, const std::string &what);

/*!
  Writes `content` to `filename` atomically. Throws vpSelfCalibException (ioError) naming `what`
  (the kind of file: "robot model", "URDF"...), the file and the errno text when the temporary file
  cannot be created, written, flushed or renamed into place. The write holds the target's lock
  (`.NAME.lock` beside it, flock, waited for; writers of one file take turns) and first removes
  what killed writers of that target left (files named like its temporaries,
  `.STEM.tmp-XXXXXXXX.EXT`): with the lock held no live writer owns one, calibrate's rule for its
  output directory. writeFileAtomicallyWith does the same.
*/
void writeFileAtomically(const std::string &filename, const std::string &content, const std::string &what);

/*!
  As above for a writer that creates the file itself from a path (vpXmlParserCamera::save, say):
  `fill` writes the temporary file (an empty file created for it) and returns false when it fails;
  an exception it throws goes through after the temporary file is removed. The file is then flushed
  to disk (a delayed write error is reported) and renamed into place.
*/
void writeFileAtomicallyWith(const std::string &filename, const std::function<bool(const std::string &)> &fill,
                             const std::string &what);

/*!
  A directory of results written as a set. The constructor takes a lock on `target` (the file
  `.NAME.lock` beside it, flock: released by the system when the process dies, kill -9 included),
  removes what runs that were killed left (`.NAME.tmp-*` directories beside it) and creates a
  private temporary directory beside `target` (same file system, mode 0700). Files are written
  there (staging()); commit() puts the set in place at once: a rename when `target` does not
  exist or is empty, else an atomic exchange (renameat2 RENAME_EXCHANGE) followed by the removal of
  the earlier set. A reader, or a kill at any point, sees the earlier set or the new one, never a
  mix. Not committed, the destructor removes the temporary directory. Errors throw
  vpSelfCalibException (ioError) with the errno text; another process holding the lock is an
  error saying so (nothing waits).
*/
class OutputDirectory
{
public:
  explicit OutputDirectory(const std::string &target);
  ~OutputDirectory();
  OutputDirectory(const OutputDirectory &) = delete;
  OutputDirectory &operator=(const OutputDirectory &) = delete;

  const std::string &target() const { return m_target; }
  //! The private temporary directory the files are written to.
  const std::string &staging() const { return m_staging; }
  //! The entries of the existing target directory (names), empty when it does not exist.
  std::vector<std::string> existingEntries() const;
  //! Puts the staged set in place of the target (see the class).
  void commit();

private:
  std::string m_target, m_staging, m_lock_file;
  int m_lock_fd = -1;
  bool m_committed = false;
};
} // namespace vpSelfCalib

#endif
