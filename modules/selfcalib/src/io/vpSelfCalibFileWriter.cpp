/*
 * ViSP SelfCalib: the public entry point of the module's atomic file writes.
 */
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibFileWriter.h>

#include <cmath>
#include <filesystem>
#include <mutex>

#include <opencv2/imgcodecs.hpp>
#include <visp3/core/vpImageConvert.h>
#include <visp3/core/vpXmlParserCamera.h>

#include "../core/vpSelfCalibFiles.h"
#include "vpSelfCalibCameraXml.h"

void vpSelfCalibFileWriter::write(const std::string &filename, const std::string &content, const std::string &what)
{
  vpSelfCalib::writeFileAtomically(filename, content, what);
}

void vpSelfCalibFileWriter::writeWith(const std::string &filename, const std::function<bool(const std::string &)> &fill,
                                      const std::string &what)
{
  vpSelfCalib::writeFileAtomicallyWith(filename, fill, what);
}

void vpSelfCalibFileWriter::writeCameraXml(const std::string &filename, const vpCameraParameters &cam,
                                           const std::string &name, unsigned int width, unsigned int height,
                                           const std::string &comment)
{
  const std::string what = "camera XML";
  vpSelfCalib::writeFileAtomicallyWith(
      filename,
      [&](const std::string &tmp) {
        // The temporary file is new and empty: vpXmlParserCamera::save writes a new document.
        std::filesystem::remove(tmp);
        vpXmlParserCamera xml;
        if (xml.save(cam, tmp, name, width, height, comment) != vpXmlParserCamera::SEQUENCE_OK)
          return false;
        // vpXmlParserCamera does not report a failed write: read the file back.
        vpSelfCalib::CameraXml back;
        if (!vpSelfCalib::readCameraXml(tmp, name, cam.get_projModel(), back) || back.width != width ||
            back.height != height || std::abs(back.cam.get_px() - cam.get_px()) > 1e-6 * std::abs(cam.get_px()))
          throw vpSelfCalibException(vpSelfCalibException::ioError,
                                     what + " '" + filename + "': the file written does not read back (disk full?)");
        return true;
      },
      what);
}

void vpSelfCalibFileWriter::writeImage(const std::string &filename, const vpImage<unsigned char> &image)
{
  const std::string ext = std::filesystem::path(filename).extension().string();
  cv::Mat m;
  vpImageConvert::convert(image, m);
  std::vector<unsigned char> bytes;
  bool ok = false;
  try {
    ok = !ext.empty() && cv::imencode(ext, m, bytes);
  } catch (const cv::Exception &) {
    ok = false;
  }
  if (!ok)
    throw vpSelfCalibException(vpSelfCalibException::ioError,
                               "image '" + filename + "': cannot encode an image as '" + ext + "'");
  vpSelfCalib::writeFileAtomically(filename, std::string(bytes.begin(), bytes.end()), "image");
}

vpSelfCalibOutputDirectory::vpSelfCalibOutputDirectory(const std::string &directory)
  : m_impl(new vpSelfCalib::OutputDirectory(directory))
{
}

vpSelfCalibOutputDirectory::~vpSelfCalibOutputDirectory() = default;

const std::string &vpSelfCalibOutputDirectory::target() const { return m_impl->target(); }

const std::string &vpSelfCalibOutputDirectory::staging() const { return m_impl->staging(); }

std::vector<std::string> vpSelfCalibOutputDirectory::existingEntries() const { return m_impl->existingEntries(); }

void vpSelfCalibOutputDirectory::commit() { m_impl->commit(); }
