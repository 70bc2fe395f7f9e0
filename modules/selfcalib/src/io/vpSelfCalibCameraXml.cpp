/*
 * ViSP SelfCalib: camera XML through ViSP's vpXmlParserCamera, without its console output.
 */
#include "vpSelfCalibCameraXml.h"

#include <fstream>
#include <iostream>
#include <sstream>

#include <cerrno>
#include <cstdint>

#include <sys/stat.h>

#include <visp3/core/vpXmlParserCamera.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include "../core/vpSelfCalibFiles.h" // readTextFileBounded, specialFileKind
#include "../core/vpSelfCalibSilentCout.h"

namespace vpSelfCalib
{
namespace
{
//! Bytes of a camera XML file (a few cameras take a few kB).
constexpr size_t kMaxCameraXmlBytes = size_t(16) << 20;

/*
  ViSP's parser reads the file itself, without a bound: only a regular file of at most
  kMaxCameraXmlBytes goes to it (a device or a pipe would be read without end, or wait forever).
*/
void checkCameraXmlFile(const std::string &file)
{
  struct stat st;
  if (::stat(file.c_str(), &st) != 0)
    throw vpSelfCalibException(vpSelfCalibException::ioError,
                               "camera XML '" + file + "': cannot read: " + errnoText(errno));
  if (S_ISDIR(st.st_mode))
    throw vpSelfCalibException(vpSelfCalibException::ioError,
                               "camera XML '" + file + "': cannot read: " + errnoText(EISDIR));
  if (!S_ISREG(st.st_mode))
    throw vpSelfCalibException(vpSelfCalibException::ioError,
                               "camera XML '" + file + "': is " + specialFileKind(file) + ", not a regular file");
  if (static_cast<uint64_t>(st.st_size) > kMaxCameraXmlBytes)
    throw vpSelfCalibException(vpSelfCalibException::ioError, "camera XML '" + file + "': " +
                                                                  std::to_string(st.st_size) + " bytes, more than the " +
                                                                  std::to_string(kMaxCameraXmlBytes >> 20) + " MiB read");
}
} // namespace

bool readCameraXml(const std::string &file, const std::string &name,
                   vpCameraParameters::vpCameraParametersProjType model, CameraXml &out)
{
  checkCameraXmlFile(file);
  const SilentCout silent;
  vpXmlParserCamera parser;
  vpCameraParameters cam;
  if (parser.parse(cam, file, name, model) != vpXmlParserCamera::SEQUENCE_OK)
    return false;
  out.cam = cam;
  out.width = parser.getWidth();
  out.height = parser.getHeight();
  return true;
}

std::vector<std::string> cameraXmlNames(const std::string &file)
{
  checkCameraXmlFile(file);
  std::string text = readTextFileBounded(file, "camera XML", kMaxCameraXmlBytes);
  for (size_t c = text.find("<!--"); c != std::string::npos; c = text.find("<!--", c)) {
    const size_t e = text.find("-->", c);
    text.erase(c, e == std::string::npos ? std::string::npos : e + 3 - c);
  }
  std::vector<std::string> names;
  for (size_t c = text.find("<camera"); c != std::string::npos; c = text.find("<camera", c + 1)) {
    const char after = c + 7 < text.size() ? text[c + 7] : '\0';
    if (after != '>' && after != ' ' && after != '\t' && after != '\r' && after != '\n')
      continue; // another element whose name starts with "camera"
    const size_t end = text.find("</camera>", c);
    const size_t n = text.find("<name>", c);
    std::string name;
    if (n != std::string::npos && n < end) {
      const size_t ne = text.find("</name>", n);
      if (ne != std::string::npos)
        name = text.substr(n + 6, ne - n - 6); // as ViSP compares it: untrimmed
    }
    names.push_back(name);
  }
  return names;
}
} // namespace vpSelfCalib
