/*
 * Tests of the atomic file writes (vpSelfCalibFileWriter, through the core's writer).
 */
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibFileWriter.h>

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
  EXPECT_FALSE(std::filesystem::exists(file + ".tmp"));

  // A writer that fills the file itself; a stale temporary file is not appended to.
  std::ofstream(file + ".tmp") << "stale";
  vpSelfCalibFileWriter::writeWith(file, [](const std::string &tmp) {
    std::ofstream(tmp, std::ios::app) << "third\n";
    return true;
  });
  EXPECT_EQ(readAll(file), "third\n");
  EXPECT_FALSE(std::filesystem::exists(file + ".tmp"));

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
  EXPECT_FALSE(std::filesystem::exists(file + ".tmp"));
  try {
    vpSelfCalibFileWriter::write((dir / "missing" / "b.txt").string(), "x", "results");
    FAIL();
  } catch (const vpSelfCalibException &e) {
    EXPECT_NE(e.getStringMessage().find("results '"), std::string::npos) << e.getStringMessage();
    EXPECT_NE(e.getStringMessage().find("b.txt"), std::string::npos) << e.getStringMessage();
  }
  std::filesystem::remove_all(dir);
}
