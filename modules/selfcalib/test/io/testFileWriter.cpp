/*
 * Tests of the atomic file writes (vpSelfCalibFileWriter, through the core's writer) and of the
 * bounded reads (vpSelfCalibTextFile).
 */
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibFileWriter.h>
#include <visp3/selfcalib/vpSelfCalibTextFile.h>

namespace
{
std::string readAll(const std::filesystem::path &p)
{
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
} // namespace

TEST(FileWriter, WritesAndLeavesNoTemporary)
{
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "selfcalib-file-writer";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string file = (dir / "a.txt").string();
  vpSelfCalibFileWriter::write(file, "first\n");
  vpSelfCalibFileWriter::write(file, "second\n");
  EXPECT_EQ(readAll(file), "second\n");

  // A writer that fills the file itself gets a new empty file.
  vpSelfCalibFileWriter::writeWith(file, [](const std::string &tmp) {
    std::ofstream(tmp, std::ios::app) << "third\n";
    return true;
  });
  EXPECT_EQ(readAll(file), "third\n");

  // Failures: the target is left as it was, and no temporary file stays.
  EXPECT_THROW(vpSelfCalibFileWriter::writeWith(file,
                                                [](const std::string &tmp) {
                                                  std::ofstream(tmp) << "half";
                                                  return false;
                                                }),
               vpSelfCalibException);
  EXPECT_THROW(vpSelfCalibFileWriter::writeWith(file,
                                                [](const std::string &tmp) -> bool {
                                                  std::ofstream(tmp) << "half";
                                                  throw std::runtime_error("disk full");
                                                }),
               std::runtime_error);
  EXPECT_EQ(readAll(file), "third\n");
  for (const auto &e : std::filesystem::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string(), "a.txt") << "left behind: " << e.path();

  // Files planted where the old fixed temporary names were (a.txt.tmp), a symbolic link among
  // them, are neither written through nor removed.
  const std::filesystem::path victim = dir / "victim.txt";
  std::ofstream(victim) << "victim";
  std::filesystem::create_symlink(victim, file + ".tmp");
  vpSelfCalibFileWriter::write(file, "fourth\n");
  EXPECT_EQ(readAll(file), "fourth\n");
  EXPECT_EQ(readAll(victim), "victim");
  EXPECT_TRUE(std::filesystem::is_symlink(file + ".tmp"));
  std::filesystem::remove(file + ".tmp");
  std::filesystem::remove(victim);
  try {
    vpSelfCalibFileWriter::write((dir / "missing" / "b.txt").string(), "x", "results");
    FAIL();
  } catch (const vpSelfCalibException &e) {
    EXPECT_NE(e.getStringMessage().find("results '"), std::string::npos) << e.getStringMessage();
    EXPECT_NE(e.getStringMessage().find("b.txt"), std::string::npos) << e.getStringMessage();
  }
  std::filesystem::remove_all(dir);
}

// A killed writer leaves its temporary file (`.NAME.tmp-XXXXXXXX.EXT`); the next write of the same
// target removes such leftovers (it holds the target's lock, so no live writer owns one), and
// nothing else: not another target's, not a directory, not a name that only looks alike.
TEST(FileWriter, RemovesStaleTemporariesOfItsTarget)
{
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "selfcalib-file-writer-stale";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const auto plant = [&](const std::string &name) {
    std::ofstream(dir / name) << "half a file";
    return dir / name;
  };
  const fs::path stale1 = plant(".model.tmp-0123abcd.yaml"), stale2 = plant(".model.tmp-deadbeef.yaml");
  const fs::path victim = plant("victim.txt");
  fs::create_symlink(victim, dir / ".model.tmp-feedf00d.yaml"); // removed as a link, the victim kept
  const std::vector<fs::path> kept = {plant(".model.tmp-0123abcd.xml"),   // another target (model.xml)
                                      plant(".other.tmp-0123abcd.yaml"),  // another target
                                      plant(".model.tmp-0123abcd.yaml~"), // not a temporary's name
                                      plant(".model.tmp-0123ABCD.yaml"),  // not hex as written
                                      plant(".model.tmp-0123abc.yaml"),   // 7 digits
                                      plant("model.tmp-0123abcd.yaml")};  // no leading dot
  fs::create_directory(dir / ".model.tmp-aaaaaaaa.yaml"); // a directory: OutputDirectory's rule, not this one
  vpSelfCalibFileWriter::write((dir / "model.yaml").string(), "corrections: {}\n", "robot model");
  EXPECT_EQ(readAll(dir / "model.yaml"), "corrections: {}\n");
  EXPECT_FALSE(fs::exists(stale1));
  EXPECT_FALSE(fs::exists(stale2));
  EXPECT_FALSE(fs::is_symlink(dir / ".model.tmp-feedf00d.yaml"));
  EXPECT_EQ(readAll(victim), "half a file");
  for (const fs::path &k : kept)
    EXPECT_TRUE(fs::exists(k)) << k;
  EXPECT_TRUE(fs::is_directory(dir / ".model.tmp-aaaaaaaa.yaml"));
  EXPECT_FALSE(fs::exists(dir / ".model.yaml.lock")); // the lock file goes with the write

  // writeWith (images, camera XML) follows the same rule.
  const fs::path stale3 = plant(".img.tmp-00000001.png");
  vpSelfCalibFileWriter::writeWith((dir / "img.png").string(), [](const std::string &tmp) {
    std::ofstream(tmp) << "png";
    return true;
  });
  EXPECT_FALSE(fs::exists(stale3));
  EXPECT_EQ(readAll(dir / "img.png"), "png");
  fs::remove_all(dir);
}

// A write that fails says why, with the system's text (here a full device: /dev/full's directory
// is not writable, so the failure is the temporary file's creation; the write itself through
// the output directory's set is tested by app-output-set-full-disk).
TEST(FileWriter, ErrorsCarryTheSystemsReason)
{
  try {
    vpSelfCalibFileWriter::write("/nonexistent-dir/x.txt", "x", "results");
    FAIL();
  } catch (const vpSelfCalibException &e) {
    EXPECT_NE(e.getStringMessage().find("No such file or directory"), std::string::npos) << e.getStringMessage();
  }
}

// The output directory: a second holder of the lock is refused, the set appears at commit only,
// an earlier set is exchanged whole, and nothing is left beside the target.
TEST(OutputDirectory, LockStagingAndCommit)
{
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "selfcalib-output-directory";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string target = (dir / "out").string();
  {
    vpSelfCalibOutputDirectory a(target);
    EXPECT_THROW(vpSelfCalibOutputDirectory b(target), vpSelfCalibException);
    vpSelfCalibFileWriter::write(a.staging() + "/r.txt", "one\n");
    EXPECT_FALSE(std::filesystem::exists(target));
    a.commit();
  }
  EXPECT_EQ(readAll(dir / "out" / "r.txt"), "one\n");
  {
    vpSelfCalibOutputDirectory a(target);
    EXPECT_EQ(a.existingEntries(), std::vector<std::string>{"r.txt"});
    vpSelfCalibFileWriter::write(a.staging() + "/s.txt", "two\n");
    a.commit();
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "r.txt")); // the earlier set went as a whole
  EXPECT_EQ(readAll(dir / "out" / "s.txt"), "two\n");
  {
    vpSelfCalibOutputDirectory a(target); // not committed: the target stays as it was
    vpSelfCalibFileWriter::write(a.staging() + "/t.txt", "three\n");
  }
  EXPECT_EQ(readAll(dir / "out" / "s.txt"), "two\n");
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "t.txt"));
  // A leftover of a killed run is removed by the next one.
  std::filesystem::create_directories(dir / ".out.tmp-Killed");
  { vpSelfCalibOutputDirectory a(target); }
  std::vector<std::string> left;
  for (const auto &e : std::filesystem::directory_iterator(dir))
    left.push_back(e.path().filename().string());
  EXPECT_EQ(left, std::vector<std::string>{"out"});
  std::filesystem::remove_all(dir);
}

namespace
{
//! The message vpSelfCalibTextFile::read throws on `file` (empty when it reads).
std::string readError(const std::string &file, const std::string &what, size_t max_bytes)
{
  try {
    vpSelfCalibTextFile::read(file, what, max_bytes);
  } catch (const vpSelfCalibException &e) {
    return e.getStringMessage();
  }
  return std::string();
}
} // namespace

/*
  The bounded reader the tools use: a text file read whole; a NUL byte named with its line (the
  third line here, after a block of 70000 bytes of text: lines counted across read buffers); a file
  beyond the bound, a missing file and a directory refused naming the kind of file once ("joints
  file", not "joints file file"; a "dataset" asks for a dataset file).
*/
TEST(TextFile, ReadsBoundedAndNamesTheLineOfANulByte)
{
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "selfcalib-text-file";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string good = (dir / "j.txt").string(), binary = (dir / "b.txt").string();
  std::ofstream(good) << "0 1 2\n3 4 5\n";
  EXPECT_EQ(vpSelfCalibTextFile::read(good, "joints file", 1 << 10), "0 1 2\n3 4 5\n");
  {
    std::ofstream out(binary, std::ios::binary);
    out << "first\n" << std::string(70000, 'x') << "\nthi";
    out.put('\0');
    out << "rd\n";
  }
  EXPECT_EQ(readError(binary, "joints file", 1 << 20),
            "joints file '" + binary + "': a NUL byte on line 3: not a text file; give a joints file");
  EXPECT_NE(readError(good, "dataset", 4).find("': 12 bytes, more than the 0 MiB read"), std::string::npos);
  EXPECT_EQ(readError((dir / "none.txt").string(), "joints file", 1 << 10),
            "joints file '" + (dir / "none.txt").string() + "': cannot read: No such file or directory");
  EXPECT_EQ(readError(dir.string(), "dataset", 1 << 10), "dataset '" + dir.string() + "': cannot read: Is a directory");
  std::filesystem::remove_all(dir);
}
