/*
 * ViSP SelfCalib: private description of coded-marker targets (not installed), shared by the board
 * detector (frontend), which finds them, and the renderer (simulation) and the tests, which draw
 * them: OpenCV's aruco dictionaries by name, and the printed side of a ChArUco board or of an
 * AprilTag as a function of the position on it, from OpenCV's own layout (CharucoBoard) and bits
 * (drawMarker), so that what is drawn is what the detector's layout says.
 */
#ifndef VP_SELFCALIB_MARKERS_H
#define VP_SELFCALIB_MARKERS_H

#include <functional>
#include <string>
#include <vector>

#include <opencv2/aruco/charuco.hpp>

#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpImage.h>
#include <visp3/robot/vpImageSimulator.h>

namespace vpSelfCalib
{
//! OpenCV's predefined dictionary of a name (DICT_6X6_250, DICT_APRILTAG_36h11...); -1 when OpenCV
//! has none of that name.
int arucoDictionary(const std::string &name);
//! The AprilTag families OpenCV has, as "36h11" (its dictionary: arucoDictionary("DICT_APRILTAG_" +
//! family)); "tag36h11" is read as "36h11". Empty when there is none.
std::string aprilTagFamily(const std::string &name);
//! The names arucoDictionary() knows ("DICT_4X4_50, ..."), and the AprilTag families ("36h11, ...").
std::string arucoDictionaryNames();
std::string aprilTagFamilyNames();
//! How many markers dictionary `dictionary` holds.
int arucoDictionarySize(int dictionary);

//! The printed side of a ChArUco board, grey 0 (black) or 1 (white) at (x, y) m in its frame
//! (OpenCV's: origin at the top-left outer corner, x right, y down); white beyond the board.
class vpCharucoPrint
{
public:
  vpCharucoPrint(int cols, int rows, double square, double marker, int dictionary);
  double at(double x, double y) const;
  const cv::Ptr<cv::aruco::CharucoBoard> &board() const { return m_board; }

private:
  cv::Ptr<cv::aruco::CharucoBoard> m_board;
  double m_square;
  std::vector<cv::Mat> m_bits; //!< per marker, (n + 2) x (n + 2) cells, 0 or 255
};

//! The printed side of an AprilTag of side `size` (the black border's outer edge), 0 or 1 at (x, y)
//! m in its frame (origin at its centre, x right, y down); white beyond it.
class vpTagPrint
{
public:
  vpTagPrint(int dictionary, int id, double size);
  double at(double x, double y) const;

private:
  double m_size;
  cv::Mat m_bits;
};
/*!
  A texture of the printed side `at` (grey 0 to 1 at (x, y) m) over [x0, x1] x [y0, y1]: texel (i, j)
  centred at (x0 + j texel, y0 + i texel), the mean of 4 x 4 samples over its area, grey 30 (black) to
  220 (white): vpImageSimulator puts texel centres from corner to corner of its quad, so the quad's
  corners are (x0, y0) and (x0 + (W - 1) texel, y0 + (H - 1) texel).
*/
vpImage<unsigned char> markerTexture(const std::function<double(double, double)> &at, double x0, double y0, double x1,
                                     double y1, double texel);

/*!
  One textured quad (initialised, its camera pose set) drawn alone on a mid-grey (128) image of
  height x width, each pixel the mean of 4 x 4 samples over its area: a camera 4 times finer whose
  sample (4 u + a, 4 v + b) is at (u + (a - 1.5) / 4, v + (b - 1.5) / 4). The edges of the texture
  are then where the geometry says to a few hundredths of a pixel.
*/
vpImage<unsigned char> renderQuad(vpImageSimulator &quad, const vpCameraParameters &cam, unsigned int height,
                                  unsigned int width);
/*!
  As renderQuad(), several quads painted in the order given (the farthest first: each covers what
  is behind it), each only over its own area.
*/
vpImage<unsigned char> renderQuads(std::vector<vpImageSimulator> &quads, const vpCameraParameters &cam,
                                   unsigned int height, unsigned int width);
} // namespace vpSelfCalib

#endif
