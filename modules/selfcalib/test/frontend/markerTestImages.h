/*
 * Rendered ChArUco boards and AprilTags for the tests of the board front end (not installed): the
 * printed side drawn from OpenCV's own layout and bits (src/core/vpSelfCalibMarkers.h) into a
 * texture, projected by vpImageSimulator through boardtest::kCamera at a known pose, an optional
 * occluder painted over it, then blurred and noised as vpSelfCalibRenderer does.
 */
#ifndef VP_SELFCALIB_MARKER_TEST_IMAGES_H
#define VP_SELFCALIB_MARKER_TEST_IMAGES_H

#include <functional>
#include <memory>

#include <visp3/core/vpRect.h>

#include "boardTestImages.h"
#include "core/vpSelfCalibMarkers.h"

namespace markertest
{
//! The printed side of a CHARUCO or APRILTAG board (single tags: the first of tag_ids, or the
//! bundle's tags, laid out by their poses' x, y and turn about z: bundles in one plane): grey 0 or 1 at (x, y) m in the
//! board's frame, and the region it covers with a white margin.
struct Print {
  std::function<double(double, double)> at;
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

inline Print print(const vpBoardDetector::Options &o)
{
  Print p;
  if (o.type == vpBoardDetector::CHARUCO) {
    auto board = std::make_shared<vpSelfCalib::vpCharucoPrint>(static_cast<int>(o.cols), static_cast<int>(o.rows),
                                                               o.spacing, o.marker_size,
                                                               vpSelfCalib::arucoDictionary(o.dictionary));
    p.at = [board](double x, double y) { return board->at(x, y); };
    p.x0 = p.y0 = -0.5 * o.spacing;
    p.x1 = (o.cols + 0.5) * o.spacing;
    p.y1 = (o.rows + 0.5) * o.spacing;
    return p;
  }
  const int dict = vpSelfCalib::arucoDictionary("DICT_APRILTAG_" + o.dictionary);
  std::vector<vpBoardDetector::Options::BundleTag> tags = o.bundle;
  if (tags.empty()) {
    vpBoardDetector::Options::BundleTag t;
    t.id = o.tag_ids.at(0);
    t.size = o.marker_size;
    tags.push_back(t);
  }
  // Each tag's in-plane placement: (x, y) in the board -> (c (x - tx) + s (y - ty), -s (x - tx) + c (y - ty)).
  struct Placed {
    double tx, ty, c, s, reach;
    std::shared_ptr<vpSelfCalib::vpTagPrint> print;
  };
  std::vector<Placed> placed;
  p.x0 = p.y0 = HUGE_VAL;
  p.x1 = p.y1 = -HUGE_VAL;
  for (const auto &t : tags) {
    const double angle = t.bMt[5];
    placed.push_back({t.bMt[0], t.bMt[1], std::cos(angle), std::sin(angle), t.size,
                      std::make_shared<vpSelfCalib::vpTagPrint>(dict, t.id, t.size)});
    p.x0 = std::min(p.x0, t.bMt[0] - t.size);
    p.y0 = std::min(p.y0, t.bMt[1] - t.size);
    p.x1 = std::max(p.x1, t.bMt[0] + t.size);
    p.y1 = std::max(p.y1, t.bMt[1] + t.size);
  }
  p.at = [placed](double x, double y) {
    for (const Placed &t : placed) {
      const double dx = x - t.tx, dy = y - t.ty;
      if (std::fabs(dx) > t.reach || std::fabs(dy) > t.reach)
        continue;
      const double g = t.print->at(t.c * dx + t.s * dy, -t.s * dx + t.c * dy);
      if (g < 1)
        return g;
    }
    return 1.0;
  };
  return p;
}

/*!
  The board at cMo through boardtest::kCamera on a mid-grey background, as boardtest::render()
  draws the grids (texels of `texel` m, 4 x 4 samples each; 4 x 4 samples per pixel; bilinear),
  grey 30 (black) to 220 (white); `occluder` (pixels) painted mid-grey before the blur and noise.
*/
inline vpImage<unsigned char> render(const vpBoardDetector::Options &o, const vpHomogeneousMatrix &cMo, uint64_t stream,
                                     double texel, const vpRect &occluder = vpRect())
{
  const Print p = print(o);
  const int sub = 4;
  const unsigned int W = static_cast<unsigned int>((p.x1 - p.x0) / texel) + 1;
  const unsigned int H = static_cast<unsigned int>((p.y1 - p.y0) / texel) + 1;
  vpImage<unsigned char> texture(H, W);
  for (unsigned int i = 0; i < H; ++i)
    for (unsigned int j = 0; j < W; ++j) {
      double sum = 0;
      for (int a = 0; a < sub; ++a)
        for (int b = 0; b < sub; ++b)
          sum += p.at(p.x0 + (j + (b + 0.5) / sub - 0.5) * texel, p.y0 + (i + (a + 0.5) / sub - 0.5) * texel);
      texture[i][j] = static_cast<unsigned char>(std::lround(30 + 190 * sum / (sub * sub)));
    }
  const double xe = p.x0 + (W - 1.0) * texel, ye = p.y0 + (H - 1.0) * texel;
  vpColVector X[4] = {vpColVector({p.x0, p.y0, 0}), vpColVector({xe, p.y0, 0}), vpColVector({xe, ye, 0}),
                      vpColVector({p.x0, ye, 0})};
  vpImageSimulator sim;
  sim.setInterpolationType(vpImageSimulator::BILINEAR_INTERPOLATION);
  sim.init(texture, X);
  sim.setCameraPosition(cMo);
  const unsigned int n = 4;
  const vpCameraParameters &cam = boardtest::kCamera;
  const vpCameraParameters fine(n * cam.get_px(), n * cam.get_py(), n * cam.get_u0() + 0.5 * (n - 1),
                                n * cam.get_v0() + 0.5 * (n - 1));
  vpImage<unsigned char> F(n * boardtest::kHeight, n * boardtest::kWidth, 128);
  sim.getImage(F, fine);
  vpImage<unsigned char> I(boardtest::kHeight, boardtest::kWidth);
  for (unsigned int i = 0; i < boardtest::kHeight; ++i)
    for (unsigned int j = 0; j < boardtest::kWidth; ++j) {
      unsigned int sum = 0;
      for (unsigned int a = 0; a < n; ++a)
        for (unsigned int b = 0; b < n; ++b)
          sum += F[n * i + a][n * j + b];
      I[i][j] = static_cast<unsigned char>((sum + n * n / 2) / (n * n));
      if (occluder.isInside(vpImagePoint(i, j)))
        I[i][j] = 128;
    }
  vpSelfCalibRenderer::blurAndNoise(I, 0.7, 2.0, 1, stream);
  return I;
}
} // namespace markertest

#endif
