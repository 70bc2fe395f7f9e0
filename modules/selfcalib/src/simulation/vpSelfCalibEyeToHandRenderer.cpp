/*
 * ViSP SelfCalib: rendered images of an eye-to-hand set-up (vpImageSimulator). See the header.
 */
#include <visp3/selfcalib/vpSelfCalibEyeToHandRenderer.h>

#include <algorithm>
#include <string>

#include <visp3/core/vpThetaUVector.h>
#include <visp3/io/vpImageIo.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include "../core/vpSelfCalibMarkers.h"
#include "../core/vpSelfCalibMath.h"
#include "vpSelfCalibBoardPrint.h"

using namespace vpSelfCalib;

namespace
{
vpColVector point(double x, double y, double z) { return vpColVector({x, y, z}); }

vpImage<unsigned char> readTexture(const std::string &file)
{
  vpImage<unsigned char> I;
  try {
    vpImageIo::read(I, file);
  } catch (const vpException &e) {
    throw vpSelfCalibException(vpSelfCalibException::ioError,
                               "vpSelfCalibEyeToHandRenderer: cannot read the texture '" + file +
                                   "' (Debian package visp-images-data): " + e.getStringMessage());
  }
  return I;
}
} // namespace

vpSelfCalibEyeToHandRenderer::vpSelfCalibEyeToHandRenderer(const vpSelfCalibRenderer::Options &options,
                                                           const vpCameraParameters &cam, unsigned int width,
                                                           unsigned int height, const vpHomogeneousMatrix &bMc,
                                                           const vpHomogeneousMatrix &eMo)
  : m_opt(options), m_cam(cam), m_width(width), m_height(height), m_cMb(bMc.inverse()), m_eMo(eMo)
{
  if (options.scene != vpSelfCalibRenderer::CHARUCO && options.scene != vpSelfCalibRenderer::APRILTAGS)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpSelfCalibEyeToHandRenderer: the tool carries a board: scene CHARUCO or APRILTAGS");
  if (width == 0 || height == 0)
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpSelfCalibEyeToHandRenderer: the image is empty");
  options.check();
  const BoardPrint print = boardPrint(options);
  m_print.texture = print.texture;
  m_print.corners[0] = point(print.x0, print.y0, 0);
  m_print.corners[1] = point(print.x1, print.y0, 0);
  m_print.corners[2] = point(print.x1, print.y1, 0);
  m_print.corners[3] = point(print.x0, print.y1, 0);
  const std::string dir = options.texture_dir.empty() ? "/usr/share/visp-images-data/ViSP-images" : options.texture_dir;
  // The plate on the flange (e's z = 0), then the link's four sides reaching back along -z.
  Part plate;
  plate.texture = readTexture(dir + "/Klimt/Klimt.pgm");
  const double w = 0.12, h = 0.09, s = 0.045, depth = 0.22;
  plate.corners[0] = point(-w, -h, 0);
  plate.corners[1] = point(w, -h, 0);
  plate.corners[2] = point(w, h, 0);
  plate.corners[3] = point(-w, h, 0);
  m_parts.push_back(plate);
  const vpImage<unsigned char> link = readTexture(dir + "/Solvay/Solvay_conference_1927_Version2_640x440.png");
  const double side[4][2] = {{-s, -s}, {s, -s}, {s, s}, {-s, s}};
  for (int k = 0; k < 4; ++k) {
    const double *a = side[k], *b = side[(k + 1) % 4];
    Part p;
    p.texture = link;
    p.corners[0] = point(a[0], a[1], 0);
    p.corners[1] = point(b[0], b[1], 0);
    p.corners[2] = point(b[0], b[1], -depth);
    p.corners[3] = point(a[0], a[1], -depth);
    m_parts.push_back(p);
  }
}

vpImage<unsigned char> vpSelfCalibEyeToHandRenderer::render(const vpHomogeneousMatrix &bMe,
                                                           unsigned int view_index) const
{
  const vpHomogeneousMatrix cMe = m_cMb * bMe;
  // The tool's parts farthest first (their centres' depth), each painting over what is behind it;
  // the board, in front of the flange, last.
  std::vector<std::pair<double, const Part *>> order;
  for (const Part &p : m_parts) {
    const vpColVector centre = 0.25 * (p.corners[0] + p.corners[1] + p.corners[2] + p.corners[3]);
    order.emplace_back((cMe * vpHomogeneousMatrix(centre[0], centre[1], centre[2], 0, 0, 0))[2][3], &p);
  }
  std::stable_sort(order.begin(), order.end(), [](const auto &a, const auto &b) { return a.first > b.first; });
  std::vector<vpImageSimulator> quads;
  for (const auto &o : order)
    quads.push_back(quadSimulator(o.second->texture, o.second->corners, cMe));
  quads.push_back(quadSimulator(m_print.texture, m_print.corners, cMe * m_eMo));
  vpImage<unsigned char> I = renderQuads(quads, m_cam, m_height, m_width);
  vpSelfCalibRenderer::blurAndNoise(I, m_opt.blur_sd, m_opt.noise_sd, m_opt.seed, 1000 + view_index);
  return I;
}

vpHomogeneousMatrix vpSelfCalibEyeToHandRenderer::boardOnTool(const vpSelfCalibRenderer::Options &options,
                                                              double offset, double tux, double tuy, double tuz)
{
  const BoardPrint print = boardPrint(options);
  // e -> the print's centre (offset along z, turned half a turn about x: z against e's z, y down
  // as printed against e's y), the turn about the centre, then the centre -> o.
  const vpHomogeneousMatrix eMcentre(0, 0, offset, M_PI, 0, 0);
  const vpHomogeneousMatrix turn(vpTranslationVector(0, 0, 0), vpThetaUVector(tux, tuy, tuz));
  const vpHomogeneousMatrix centreMo(-print.cx, -print.cy, 0, 0, 0, 0);
  return eMcentre * turn * centreMo;
}

std::map<int, vpColVector> vpSelfCalibEyeToHandRenderer::getOutline(const vpSelfCalibRenderer::Options &options)
{
  const BoardPrint print = boardPrint(options);
  return {{0, point(print.x0, print.y0, 0)},
          {1, point(print.x1, print.y0, 0)},
          {2, point(print.x1, print.y1, 0)},
          {3, point(print.x0, print.y1, 0)}};
}

vpSelfCalibSimulator::EyeToHandOptions vpSelfCalibEyeToHandRenderer::simulation(const vpSelfCalibRenderer::Options &options)
{
  vpSelfCalibSimulator::EyeToHandOptions eo = vpSelfCalibSimulator::eyeToHandHd();
  eo.lateral = 0.06;
  eo.layout = getOutline(options);
  eo.eMo = vpPoseVector(boardOnTool(options, 0.05, 0.1, -0.15, 0.3));
  return eo;
}
