/*
 * Rendered calibration boards for the tests of the board front end (not installed): the board's
 * printed side drawn from its layout into a texture, projected by vpImageSimulator through a known
 * camera and pose, then blurred and noised as vpSelfCalibRenderer does.
 */
#ifndef VP_SELFCALIB_BOARD_TEST_IMAGES_H
#define VP_SELFCALIB_BOARD_TEST_IMAGES_H

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <list>

#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/core/vpImage.h>
#include <visp3/core/vpMeterPixelConversion.h>
#include <visp3/robot/vpImageSimulator.h>
#include <visp3/selfcalib/vpBoardDetector.h>
#include <visp3/selfcalib/vpSelfCalibRenderer.h>

#include "core/vpSelfCalibMarkers.h"

namespace boardtest
{
constexpr unsigned int kWidth = 640, kHeight = 480;
const vpCameraParameters kCamera(800, 800, 320, 240);

//! The pixel of a point given in the board frame, the board at cMo.
inline vpImagePoint project(const vpHomogeneousMatrix &cMo, const vpColVector &X)
{
  const vpColVector c = cMo * vpColVector({X[0], X[1], X[2], 1.0});
  vpImagePoint ip;
  vpMeterPixelConversion::convertPoint(kCamera, c[0] / c[2], c[1] / c[2], ip);
  return ip;
}

//! The board's centre `distance` m in front of the camera, turned by `roll` degrees about its
//! normal, then tilted by tilt_x and tilt_y degrees about the camera's x and y axes.
inline vpHomogeneousMatrix pose(const vpBoardDetector &det, double roll, double tilt_x, double tilt_y,
                                double distance)
{
  vpColVector centre(3, 0.0);
  const std::map<int, vpColVector> layout = det.getLayout();
  for (const auto &p : layout)
    centre += p.second / static_cast<double>(layout.size());
  const double rad = M_PI / 180;
  return vpHomogeneousMatrix(0, 0, distance, 0, 0, 0) * vpHomogeneousMatrix(0, 0, 0, tilt_x * rad, 0, 0) *
         vpHomogeneousMatrix(0, 0, 0, 0, tilt_y * rad, 0) * vpHomogeneousMatrix(0, 0, 0, 0, 0, roll * rad) *
         vpHomogeneousMatrix(-centre[0], -centre[1], 0, 0, 0, 0);
}

//! Grey level of the board's printed side at (x, y), in units of the spacing: a chessboard's
//! squares from -1 to cols (rows), the one at the origin's outer corner black, in a white margin
//! of one square; dots of 0.25 spacing in radius (0.3 for the asymmetric grid; the origin's 0.45
//! on a modified grid).
inline double printed(const vpBoardDetector::Options &o, double x, double y)
{
  const double white = 220, black = 30;
  if (o.type == vpBoardDetector::CHESSBOARD) {
    if (x < -1 || y < -1 || x >= o.cols || y >= o.rows)
      return white;
    return (static_cast<long>(std::floor(x)) + static_cast<long>(std::floor(y)) + 2) % 2 == 0 ? black : white;
  }
  const bool asymmetric = o.type == vpBoardDetector::ASYMMETRIC_CIRCLES;
  const long row = std::lround(y);
  for (long r = row - 1; r <= row + 1; ++r) {
    if (r < 0 || r >= static_cast<long>(o.rows))
      continue;
    const double shift = asymmetric ? static_cast<double>(r % 2) : 0, step = asymmetric ? 2 : 1;
    const long c = std::lround((x - shift) / step);
    if (c < 0 || c >= static_cast<long>(o.cols))
      continue;
    const double radius = o.type == vpBoardDetector::MODIFIED_CIRCLES && r == 0 && c == 0 ? 0.45
                          : asymmetric                                                  ? 0.3
                                                                                        : 0.25;
    if (std::hypot(x - (shift + step * c), y - r) <= radius)
      return black;
  }
  return white;
}

/*!
  The board at cMo through kCamera on a mid-grey background: a texture of 48 texels per spacing,
  each the mean of 4 x 4 samples of printed(), whose texel centres vpImageSimulator places from
  corner to corner of its quad (texel j at x_min + j / 48); bilinear interpolation; then blur and
  noise (stream `stream` of seed 1), by default vpSelfCalibRenderer's: 0.7 px and 2 grey levels.
*/
inline vpImage<unsigned char> render(const vpBoardDetector::Options &o, const vpHomogeneousMatrix &cMo,
                                     uint64_t stream, double blur_sd = 0.7, double noise_sd = 2.0)
{
  const bool chess = o.type == vpBoardDetector::CHESSBOARD;
  const double x_last = o.type == vpBoardDetector::ASYMMETRIC_CIRCLES ? 2.0 * o.cols - 1 : o.cols - 1.0;
  const double x0 = chess ? -2 : -1, y0 = x0, x1 = x_last + (chess ? 2 : 1), y1 = o.rows - 1.0 + (chess ? 2 : 1);
  const int per_unit = 48;
  // printed() is 30 or 220: the texture's grey is 30 + 190 times the white fraction.
  const vpImage<unsigned char> texture = vpSelfCalib::markerTexture(
      [&o](double x, double y) { return (printed(o, x, y) - 30) / 190; }, x0, y0, x1, y1, 1.0 / per_unit);
  const unsigned int W = texture.getWidth(), H = texture.getHeight();
  const double s = o.spacing, xe = x0 + (W - 1.0) / per_unit, ye = y0 + (H - 1.0) / per_unit;
  vpColVector X[4] = {vpColVector({x0 * s, y0 * s, 0}), vpColVector({xe * s, y0 * s, 0}),
                      vpColVector({xe * s, ye * s, 0}), vpColVector({x0 * s, ye * s, 0})};
  vpImageSimulator sim;
  sim.setInterpolationType(vpImageSimulator::BILINEAR_INTERPOLATION);
  sim.init(texture, X);
  sim.setCameraPosition(cMo);
  // Each pixel integrates its area (4 x 4 samples, vpSelfCalib::renderQuad).
  vpImage<unsigned char> I = vpSelfCalib::renderQuad(sim, kCamera, kHeight, kWidth);
  vpSelfCalibRenderer::blurAndNoise(I, blur_sd, noise_sd, 1, stream);
  return I;
}

//! Pixels within `radius` of p darker than `threshold`.
inline unsigned int darkPixelsAround(const vpImage<unsigned char> &I, const vpImagePoint &p, double radius,
                                     double threshold)
{
  unsigned int n = 0;
  const int r = static_cast<int>(std::ceil(radius));
  const int u0 = static_cast<int>(std::lround(p.get_u())), v0 = static_cast<int>(std::lround(p.get_v()));
  for (int v = std::max(0, v0 - r); v <= v0 + r && v < static_cast<int>(I.getHeight()); ++v)
    for (int u = std::max(0, u0 - r); u <= u0 + r && u < static_cast<int>(I.getWidth()); ++u)
      n += std::hypot(u - p.get_u(), v - p.get_v()) <= radius && I[v][u] < threshold;
  return n;
}
} // namespace boardtest

#endif
