/*
 * ViSP SelfCalib: atomic file writes through a temporary file beside the target, and result
 * directories written as a set (POSIX and Linux system calls, every one checked).
 */
#include "vpSelfCalibFiles.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <cstdint>
#include <fstream>
#include <iomanip>
#include <new>
#include <random>
#include <sstream>
#include <system_error>
#include <thread>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <visp3/selfcalib/vpSelfCalibException.h>

namespace fs = std::filesystem;

namespace vpSelfCalib
{
namespace
{
void removeQuietly(const fs::path &p)
{
  std::error_code ec;
  fs::remove(p, ec);
}

[[noreturn]] void fail(const std::string &what, const std::string &file, const std::string &action, int err)
{
  throw vpSelfCalibException(vpSelfCalibException::ioError,
                             what + " '" + file + "': " + action + ": " + errnoText(err));
}

//! 8 hex digits, different in every call of every thread and process (file names only).
std::string uniqueSuffix()
{
  static std::atomic<uint64_t> counter{0};
  thread_local std::mt19937_64 rng(std::random_device{}() ^ (static_cast<uint64_t>(::getpid()) << 32) ^
                                   std::hash<std::thread::id>{}(std::this_thread::get_id()));
  const uint64_t v = rng() ^ (counter++ * 0x9E3779B97F4A7C15ULL);
  char buf[17];
  std::snprintf(buf, sizeof buf, "%08x", static_cast<unsigned int>(v ^ (v >> 32)));
  return buf;
}

//! The directory of `p` ("." for a bare name).
fs::path directoryOf(const fs::path &p) { return p.has_parent_path() ? p.parent_path() : fs::path("."); }

/*
  The lock of one file's writes: flock on `.NAME.lock` beside it, waited for (writers of one file
  take turns; a run killed while it holds the lock releases it: the system closes its descriptor),
  the lock file removed while still held (see OutputDirectory's constructor for the inode check).
  It lets a writer tell the temporary files of killed runs from those of live ones: while a writer
  holds the lock no other live writer of that file has a temporary file, so any there is a leftover.
*/
class FileLock
{
public:
  FileLock(const fs::path &file, const std::string &what)
  {
    m_path = (directoryOf(file) / ("." + file.filename().string() + ".lock")).string();
    for (int attempt = 0;; ++attempt) {
      const int fd = ::open(m_path.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0666);
      if (fd < 0) {
        const int err = errno;
        struct stat dir;
        if (err == ENOENT && ::stat(directoryOf(file).c_str(), &dir) != 0)
          fail(what, file.string(), "its directory '" + directoryOf(file).string() + "' is not there", errno);
        fail(what, file.string(), "cannot create the lock file '" + m_path + "'", err);
      }
      while (::flock(fd, LOCK_EX) != 0)
        if (errno != EINTR) {
          const int err = errno;
          ::close(fd);
          fail(what, file.string(), "cannot lock '" + m_path + "'", err);
        }
      struct stat a, b;
      if (::fstat(fd, &a) == 0 && ::stat(m_path.c_str(), &b) == 0 && a.st_ino == b.st_ino && a.st_dev == b.st_dev) {
        m_fd = fd;
        return;
      }
      ::close(fd);
      if (attempt > 100)
        fail(what, file.string(), "cannot lock '" + m_path + "'", EAGAIN);
    }
  }
  ~FileLock()
  {
    ::unlink(m_path.c_str()); // while still locked
    ::close(m_fd);
  }
  FileLock(const FileLock &) = delete;
  FileLock &operator=(const FileLock &) = delete;

private:
  std::string m_path;
  int m_fd = -1;
};

/*
  Removes the temporary files killed writers of `file` left: the names createTemporaryFileFor gives
  (`.STEM.tmp-`, 8 lower-case hex digits, the extension), files or symbolic links (a link is
  removed, not followed), never a directory (OutputDirectory's leftovers are directories, removed by
  its own constructor). Called with the file's lock held, which is calibrate's rule for its
  directories: no live writer of the file owns one. Errors are ignored (the write that follows
  reports a directory it cannot use).
*/
void removeStaleTemporaries(const fs::path &file)
{
  const std::string stem = file.filename().stem().string(), ext = file.filename().extension().string();
  const std::string prefix = "." + stem + ".tmp-";
  std::error_code ec;
  for (const fs::directory_entry &e : fs::directory_iterator(directoryOf(file), ec)) {
    const std::string n = e.path().filename().string();
    if (n.size() != prefix.size() + 8 + ext.size() || n.compare(0, prefix.size(), prefix) != 0 ||
        n.compare(prefix.size() + 8, std::string::npos, ext) != 0)
      continue;
    bool hex = true;
    for (size_t i = prefix.size(); i < prefix.size() + 8; ++i)
      hex = hex && (std::isdigit(static_cast<unsigned char>(n[i])) || (n[i] >= 'a' && n[i] <= 'f'));
    std::error_code ec2;
    if (hex && (e.is_symlink(ec2) || !e.is_directory(ec2)))
      ::unlink(e.path().c_str());
  }
}

//! fsync of a directory, so that a rename in it survives a crash; errors ignored (some file systems refuse).
void syncDirectory(const fs::path &dir)
{
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}

//! Flushes a file to disk; a delayed write error (a full disk on some file systems) shows here.
void syncFile(const fs::path &file, const std::string &what, const std::string &target)
{
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
  if (fd < 0)
    fail(what, target, "cannot reopen '" + file.string() + "'", errno);
  if (::fsync(fd) != 0 && errno != EINVAL) {
    const int err = errno;
    ::close(fd);
    fail(what, target, "cannot flush '" + file.string() + "' to disk", err);
  }
  if (::close(fd) != 0)
    fail(what, target, "cannot close '" + file.string() + "'", errno);
}

void renameIntoPlace(const fs::path &tmp, const std::string &filename, const std::string &what)
{
  if (::rename(tmp.c_str(), filename.c_str()) != 0) {
    const int err = errno;
    removeQuietly(tmp);
    fail(what, filename, "cannot rename the temporary file into place", err);
  }
  syncDirectory(directoryOf(filename));
}

//! The kind of a special file ("a character device"...), empty for a regular file, a directory or a symbolic link.
std::string specialKind(mode_t m)
{
  if (S_ISCHR(m))
    return "a character device";
  if (S_ISBLK(m))
    return "a block device";
  if (S_ISFIFO(m))
    return "a FIFO";
  if (S_ISSOCK(m))
    return "a socket";
  return "";
}

//! Big-endian 16 and 32 bits.
unsigned long long be(const unsigned char *p, int n)
{
  unsigned long long v = 0;
  for (int i = 0; i < n; ++i)
    v = (v << 8) | p[i];
  return v;
}

//! The size in a JPEG's first SOFn segment (the segments before it skipped by their lengths).
ImageHeader jpegHeader(FILE *f)
{
  ImageHeader h;
  unsigned char b[8];
  for (int segments = 0; segments < 10000; ++segments) {
    int c = std::fgetc(f);
    if (c != 0xFF)
      return h;
    while (c == 0xFF)
      c = std::fgetc(f);
    if (c == EOF || c == 0xD9 || c == 0xDA)
      return h;
    if ((c >= 0xD0 && c <= 0xD7) || c == 0x01)
      continue;
    if (std::fread(b, 1, 2, f) != 2)
      return h;
    const long len = static_cast<long>(be(b, 2));
    if (c >= 0xC0 && c <= 0xCF && c != 0xC4 && c != 0xC8 && c != 0xCC) {
      if (len < 7 || std::fread(b, 1, 5, f) != 5)
        return h;
      h.known = true;
      h.height = be(b + 1, 2);
      h.width = be(b + 3, 2);
      return h;
    }
    if (len < 2 || std::fseek(f, len - 2, SEEK_CUR) != 0)
      return h;
  }
  return h;
}

//! The size in a PGM/PPM header (P1 to P6: magic, width, height, '#' comments).
ImageHeader pnmHeader(FILE *f)
{
  ImageHeader h;
  unsigned long long v[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    int c = std::fgetc(f);
    while (c == '#' || std::isspace(c)) {
      if (c == '#')
        while (c != '\n' && c != EOF)
          c = std::fgetc(f);
      c = std::fgetc(f);
    }
    if (!std::isdigit(c))
      return h;
    for (int digits = 0; std::isdigit(c) && digits < 19; ++digits, c = std::fgetc(f))
      v[k] = v[k] * 10 + static_cast<unsigned long long>(c - '0');
  }
  h.known = true;
  h.width = v[0];
  h.height = v[1];
  return h;
}

//! The process's umask, read without changing it (umask(2) would, for every thread).
mode_t currentUmask()
{
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("Umask:", 0) == 0)
      return static_cast<mode_t>(std::stoul(line.substr(6), nullptr, 8));
  return 022;
}
//! "dataset" -> "dataset file"; "joints file" stays (what to give, in a message).
std::string fileKind(const std::string &what)
{
  const std::string file = "file";
  const bool ends = what.size() >= file.size() && what.compare(what.size() - file.size(), file.size(), file) == 0;
  return ends ? what : what + " file";
}
} // namespace

std::string errnoText(int err)
{
  std::error_code ec(err, std::generic_category());
  return ec.message();
}

std::string specialFileKind(const std::string &path)
{
  struct stat st;
  std::string kind;
  if (::lstat(path.c_str(), &st) == 0)
    kind = specialKind(st.st_mode);
  if (kind.empty() && ::stat(path.c_str(), &st) == 0) // a symbolic link to one
    kind = specialKind(st.st_mode);
  return kind;
}

void refuseSpecialOutput(const std::string &filename, const std::string &what)
{
  const std::string kind = specialFileKind(filename);
  if (!kind.empty())
    throw vpSelfCalibException(vpSelfCalibException::ioError,
                               what + " '" + filename + "': is " + kind +
                                   ", not a regular file: outputs are written only as regular files (and "
                                   "directories); choose another path");
}

std::string readTextFileBounded(const std::string &filename, const std::string &what, size_t max_bytes)
{
  // Opened without blocking: a FIFO no program writes to would block the open for ever; then read
  // blocking again (a pipe with a writer, e.g. a shell's <(...), is read to its end), where such a FIFO
  // reads as empty.
  const int fd = ::open(filename.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0)
    fail(what, filename, "cannot read", errno);
  const int flags = ::fcntl(fd, F_GETFL);
  if (flags >= 0)
    ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
  struct stat st;
  if (::fstat(fd, &st) == 0 && S_ISDIR(st.st_mode)) {
    ::close(fd);
    fail(what, filename, "cannot read", EISDIR);
  }
  const std::string limit = std::to_string(max_bytes >> 20) + " MiB";
  if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && static_cast<uint64_t>(st.st_size) > max_bytes) {
    ::close(fd);
    throw vpSelfCalibException(vpSelfCalibException::ioError, what + " '" + filename + "': " +
                                                                  std::to_string(st.st_size) + " bytes, more than the " +
                                                                  limit + " read");
  }
  // Counted while reading: a device or a pipe has no size to check first (/dev/zero never ends).
  std::string text;
  try {
    if (S_ISREG(st.st_mode))
      text.reserve(static_cast<size_t>(st.st_size) + 1);
    char buf[1 << 16];
    for (;;) {
      const ssize_t n = ::read(fd, buf, sizeof buf);
      if (n < 0 && errno == EINTR)
        continue;
      if (n < 0) {
        const int err = errno;
        ::close(fd);
        fail(what, filename, "read error", err);
      }
      if (n == 0)
        break;
      if (const void *nul = std::memchr(buf, '\0', static_cast<size_t>(n))) {
        ::close(fd);
        // Its line (1-based): the newlines read before it, in the text and in this buffer.
        const char *at = static_cast<const char *>(nul);
        const size_t line = 1 + static_cast<size_t>(std::count(text.begin(), text.end(), '\n')) +
                            static_cast<size_t>(std::count(static_cast<const char *>(buf), at, '\n'));
        throw vpSelfCalibException(vpSelfCalibException::parseError,
                                   what + " '" + filename + "': a NUL byte on line " + std::to_string(line) +
                                       ": not a text file; give a " + fileKind(what));
      }
      if (text.size() + static_cast<size_t>(n) > max_bytes) {
        ::close(fd);
        throw vpSelfCalibException(vpSelfCalibException::ioError,
                                   what + " '" + filename + "': more than the " + limit +
                                       " read (a device or a stream without end?); give a " + fileKind(what));
      }
      text.append(buf, static_cast<size_t>(n));
    }
  } catch (const std::bad_alloc &) {
    ::close(fd);
    throw vpSelfCalibException(vpSelfCalibException::ioError, what + " '" + filename + "': out of memory after " +
                                                                  std::to_string(text.size() >> 20) + " MiB read");
  }
  ::close(fd);
  if (text.empty() && S_ISFIFO(st.st_mode))
    throw vpSelfCalibException(vpSelfCalibException::ioError,
                               what + " '" + filename + "': a FIFO that no program writes to (read as empty); give a " +
                                   fileKind(what) + ", or write to the FIFO first");
  return text;
}

ImageHeader checkImageFile(const std::string &file, const std::string &context, double max_pixels)
{
  const auto refuse = [&](const std::string &why) {
    throw vpSelfCalibException(vpSelfCalibException::ioError, context + ": " + why);
  };
  struct stat st;
  if (::stat(file.c_str(), &st) != 0)
    refuse(errnoText(errno));
  if (S_ISDIR(st.st_mode))
    refuse("is a directory, not an image file");
  if (!S_ISREG(st.st_mode))
    refuse("is " + specialFileKind(file) + ", not an image file");
  constexpr uint64_t kMaxImageBytes = uint64_t(256) << 20;
  if (static_cast<uint64_t>(st.st_size) > kMaxImageBytes)
    refuse(std::to_string(st.st_size) + " bytes, more than the 256 MiB read");
  FILE *f = std::fopen(file.c_str(), "rb");
  if (!f)
    refuse(errnoText(errno));
  unsigned char b[24] = {0};
  const size_t n = std::fread(b, 1, sizeof b, f);
  ImageHeader h;
  static const unsigned char png[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  if (n >= 24 && std::memcmp(b, png, 8) == 0 && std::memcmp(b + 12, "IHDR", 4) == 0) {
    h.known = true;
    h.width = be(b + 16, 4);
    h.height = be(b + 20, 4);
  } else if (n >= 2 && b[0] == 0xFF && b[1] == 0xD8) {
    std::fseek(f, 2, SEEK_SET);
    h = jpegHeader(f);
  } else if (n >= 2 && b[0] == 'P' && b[1] >= '1' && b[1] <= '6') {
    std::fseek(f, 2, SEEK_SET);
    h = pnmHeader(f);
  }
  std::fclose(f);
  if (h.known && static_cast<double>(h.width) * static_cast<double>(h.height) > max_pixels) {
    std::ostringstream os;
    os << "its header says " << h.width << " x " << h.height << " px, more than the " << std::fixed
       << std::setprecision(0) << max_pixels
       << " pixels decoded: refused before decoding";
    refuse(os.str());
  }
  return h;
}

fs::path createTemporaryFileFor(const fs::path &file, const std::string &what)
{
  const fs::path dir = directoryOf(file);
  const std::string stem = file.filename().stem().string(), ext = file.filename().extension().string();
  for (int attempt = 0; attempt < 100; ++attempt) {
    const fs::path tmp = dir / ("." + stem + ".tmp-" + uniqueSuffix() + ext);
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd >= 0) {
      ::close(fd);
      return tmp;
    }
    if (errno != EEXIST)
      fail(what, file.string(), "cannot create a temporary file in '" + dir.string() + "'", errno);
  }
  fail(what, file.string(), "cannot create a temporary file in '" + dir.string() + "'", EEXIST);
}

void writeFileAtomicallyWith(const std::string &filename, const std::function<bool(const std::string &)> &fill,
                             const std::string &what)
{
  refuseSpecialOutput(filename, what);
  const FileLock lock(filename, what);
  removeStaleTemporaries(filename);
  const fs::path tmp = createTemporaryFileFor(filename, what);
  bool written = false;
  try {
    written = fill(tmp.string());
    if (written)
      syncFile(tmp, what, filename);
  } catch (...) {
    removeQuietly(tmp);
    throw;
  }
  if (!written) {
    removeQuietly(tmp);
    throw vpSelfCalibException(vpSelfCalibException::ioError,
                               what + " '" + filename + "': cannot write '" + tmp.string() + "'");
  }
  renameIntoPlace(tmp, filename, what);
}

void writeFileAtomically(const std::string &filename, const std::string &content, const std::string &what)
{
  refuseSpecialOutput(filename, what);
  const FileLock lock(filename, what);
  removeStaleTemporaries(filename);
  const fs::path tmp = createTemporaryFileFor(filename, what);
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_TRUNC | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) {
    const int err = errno;
    removeQuietly(tmp);
    fail(what, filename, "cannot open '" + tmp.string() + "' for writing", err);
  }
  int err = 0;
  for (size_t done = 0; done < content.size() && !err;) {
    const ssize_t n = ::write(fd, content.data() + done, content.size() - done);
    if (n < 0 && errno != EINTR)
      err = errno;
    else if (n > 0)
      done += static_cast<size_t>(n);
  }
  if (!err && ::fsync(fd) != 0 && errno != EINVAL)
    err = errno;
  if (::close(fd) != 0 && !err)
    err = errno;
  if (err) {
    removeQuietly(tmp);
    fail(what, filename, "cannot write '" + tmp.string() + "'", err);
  }
  renameIntoPlace(tmp, filename, what);
}

// ---------------------------------------------------------------------------------------------
// OutputDirectory

OutputDirectory::OutputDirectory(const std::string &target)
{
  if (target.empty())
    throw vpSelfCalibException(vpSelfCalibException::ioError, "output directory '': an empty path: give a directory");
  fs::path t = fs::absolute(target).lexically_normal();
  if (!t.has_filename())
    t = t.parent_path(); // "out/" or "."
  m_target = t.string();
  const std::string what = "output directory";
  if (t == t.root_path())
    throw vpSelfCalibException(vpSelfCalibException::ioError, what + " '" + target + "': the root cannot be replaced");
  const fs::path parent = t.parent_path(), name = t.filename();
  struct stat st;
  if (::stat(parent.c_str(), &st) != 0)
    fail(what, target, "its parent '" + parent.string() + "' is not there", errno);
  if (!specialFileKind(t.string()).empty())
    throw vpSelfCalibException(vpSelfCalibException::ioError,
                               what + " '" + target + "': is " + specialFileKind(t.string()) +
                                   ", not a directory: outputs are written only as regular files and directories; "
                                   "choose another path");
  if (::lstat(t.c_str(), &st) == 0 && S_ISLNK(st.st_mode)) {
    std::error_code ec;
    const fs::path to = fs::read_symlink(t, ec);
    throw vpSelfCalibException(vpSelfCalibException::ioError,
                               what + " '" + target + "': is a symbolic link" +
                                   (ec ? std::string() : " to '" + to.string() + "'") +
                                   ": the set replaces what is at the path, so give the directory itself");
  }
  if (::lstat(t.c_str(), &st) == 0 && !S_ISDIR(st.st_mode))
    throw vpSelfCalibException(vpSelfCalibException::ioError,
                               what + " '" + target + "': exists and is not a directory");

  // The lock: a file beside the target (the target itself is replaced by the commit).
  m_lock_file = (parent / ("." + name.string() + ".lock")).string();
  for (int attempt = 0;; ++attempt) {
    const int fd = ::open(m_lock_file.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd < 0)
      fail(what, target, "cannot create the lock file '" + m_lock_file + "'", errno);
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int err = errno;
      ::close(fd);
      if (err == EWOULDBLOCK)
        throw vpSelfCalibException(vpSelfCalibException::ioError,
                                   what + " '" + target + "' is being written by another run (it holds the lock '" +
                                       m_lock_file + "'): wait for it to end, or choose another directory");
      fail(what, target, "cannot lock '" + m_lock_file + "'", err);
    }
    // The lock file may have been removed by the run that held it: lock the file that is there.
    struct stat a, b;
    if (::fstat(fd, &a) == 0 && ::stat(m_lock_file.c_str(), &b) == 0 && a.st_ino == b.st_ino && a.st_dev == b.st_dev) {
      m_lock_fd = fd;
      break;
    }
    ::close(fd);
    if (attempt > 100)
      fail(what, target, "cannot lock '" + m_lock_file + "'", EAGAIN);
  }

  // Leftovers of killed runs: no live run owns them, since this one holds the lock.
  const std::string prefix = "." + name.string() + ".tmp-";
  std::error_code ec;
  for (const fs::directory_entry &e : fs::directory_iterator(parent, ec)) {
    const std::string n = e.path().filename().string();
    if (n.rfind(prefix, 0) == 0 && e.is_directory(ec) && !e.is_symlink(ec))
      fs::remove_all(e.path(), ec);
  }

  char tmpl[4096];
  const std::string pattern = (parent / (prefix + "XXXXXX")).string();
  if (pattern.size() >= sizeof tmpl)
    throw vpSelfCalibException(vpSelfCalibException::ioError, what + " '" + target + "': path too long");
  std::memcpy(tmpl, pattern.c_str(), pattern.size() + 1);
  if (!::mkdtemp(tmpl)) {
    const int err = errno;
    ::unlink(m_lock_file.c_str());
    ::close(m_lock_fd);
    fail(what, target, "cannot create a temporary directory in '" + parent.string() + "'", err);
  }
  m_staging = tmpl;
}

OutputDirectory::~OutputDirectory()
{
  if (!m_committed && !m_staging.empty()) {
    std::error_code ec;
    fs::remove_all(m_staging, ec);
  }
  if (m_lock_fd >= 0) {
    ::unlink(m_lock_file.c_str()); // while still locked: see the constructor's inode check
    ::close(m_lock_fd);
  }
}

std::vector<std::string> OutputDirectory::existingEntries() const
{
  std::vector<std::string> names;
  std::error_code ec;
  for (const fs::directory_entry &e : fs::directory_iterator(m_target, ec))
    names.push_back(e.path().filename().string());
  return names;
}

void OutputDirectory::commit()
{
  const std::string what = "output directory";
  // The temporary directory was private (0700); the results get the usual permissions.
  if (::chmod(m_staging.c_str(), 0777 & ~currentUmask()) != 0)
    fail(what, m_target, "cannot set the permissions of '" + m_staging + "'", errno);
  syncDirectory(m_staging);
  const fs::path parent = fs::path(m_target).parent_path();
  if (::rename(m_staging.c_str(), m_target.c_str()) == 0) { // no target, or an empty one
    m_committed = true;
    syncDirectory(parent);
    return;
  }
  if (errno != ENOTEMPTY && errno != EEXIST)
    fail(what, m_target, "cannot move the results into place", errno);
  // An earlier set: exchanged with the new one in one step, then removed.
  if (::syscall(SYS_renameat2, AT_FDCWD, m_staging.c_str(), AT_FDCWD, m_target.c_str(), 2 /* RENAME_EXCHANGE */) ==
      0) {
    m_committed = true;
    syncDirectory(parent);
    std::error_code ec;
    fs::remove_all(m_staging, ec); // now the earlier set; a leftover is removed by the next run
    return;
  }
  if (errno != EINVAL && errno != ENOSYS)
    fail(what, m_target, "cannot move the results into place", errno);
  // A file system without exchange: the earlier set moves aside first (never a mix, but for a
  // moment no set at all).
  const std::string aside = m_staging + "-old";
  if (::rename(m_target.c_str(), aside.c_str()) != 0)
    fail(what, m_target, "cannot move the earlier results aside", errno);
  if (::rename(m_staging.c_str(), m_target.c_str()) != 0) {
    const int err = errno;
    ::rename(aside.c_str(), m_target.c_str());
    fail(what, m_target, "cannot move the results into place", err);
  }
  m_committed = true;
  syncDirectory(parent);
  std::error_code ec;
  fs::remove_all(aside, ec);
}
} // namespace vpSelfCalib
