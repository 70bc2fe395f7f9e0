/*
 * ViSP SelfCalib: private camera XML helpers (not installed), shared by the dataset reader and the
 * importers. The parsing itself is ViSP's vpXmlParserCamera.
 */
#ifndef VP_SELFCALIB_CAMERA_XML_H
#define VP_SELFCALIB_CAMERA_XML_H

#include <string>
#include <vector>

#include <visp3/core/vpCameraParameters.h>

namespace vpSelfCalib
{
//! One camera of a vpXmlParserCamera file in one projection model.
struct CameraXml {
  vpCameraParameters cam;
  unsigned int width = 0, height = 0; //!< image size the file gives (0 when it gives none)
};

/*!
  Reads the camera `name` in projection `model` from a vpXmlParserCamera file; false when the file
  cannot be parsed or has no such camera in that model. ViSP 3.5's parser writes "Found camera
  with name ..." on std::cout for every camera it reads; library code never prints, so std::cout
  is silenced during the parse (parses are serialised for that).
*/
bool readCameraXml(const std::string &file, const std::string &name,
                   vpCameraParameters::vpCameraParametersProjType model, CameraXml &out);

/*!
  The names of the cameras of a vpXmlParserCamera file, in file order ("" for a camera without a
  name): a scan of its <camera> elements for their <name>, comments skipped, to choose which
  camera to read. Empty when the file cannot be read.
*/
std::vector<std::string> cameraXmlNames(const std::string &file);
} // namespace vpSelfCalib

#endif
