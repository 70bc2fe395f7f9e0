/*
 * ViSP SelfCalib: camera XML through ViSP's vpXmlParserCamera, without its console output.
 */
#include "vpSelfCalibCameraXml.h"

#include <fstream>
#include <iostream>
#include <mutex>
#include <sstream>

#include <visp3/core/vpXmlParserCamera.h>

namespace vpSelfCalib
{
namespace
{
//! std::cout writes nothing while this lives (its buffer is restored, and its state cleared, after).
class SilentCout
{
public:
  SilentCout() : m_saved(std::cout.rdbuf(nullptr)) {}
  ~SilentCout() { std::cout.rdbuf(m_saved); }
  SilentCout(const SilentCout &) = delete;
  SilentCout &operator=(const SilentCout &) = delete;

private:
  std::streambuf *m_saved;
};

std::mutex g_parse_mutex;
} // namespace

bool readCameraXml(const std::string &file, const std::string &name,
                   vpCameraParameters::vpCameraParametersProjType model, CameraXml &out)
{
  std::lock_guard<std::mutex> lock(g_parse_mutex);
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
  std::ifstream in(file, std::ios::binary);
  if (!in)
    return {};
  std::ostringstream os;
  os << in.rdbuf();
  std::string text = os.str();
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
