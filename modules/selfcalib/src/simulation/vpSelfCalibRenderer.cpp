/*
 * ViSP SelfCalib: rendered images of the reference scenario (vpImageSimulator). See the header.
 */
#include <visp3/selfcalib/vpSelfCalibRenderer.h>

#include "../core/vpSelfCalibParallel.h"
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <list>
#include <memory>

#include <visp3/core/vpImageFilter.h>
#include <visp3/io/vpImageIo.h>
#include <visp3/robot/vpImageSimulator.h>

#include "../core/vpSelfCalibFiles.h" // checkImageFile
#include "../core/vpSelfCalibMarkers.h"
#include "../core/vpSelfCalibMath.h"
#include "../core/vpSelfCalibRandom.h"
#include "vpSelfCalibBoardPrint.h"

using namespace vpSelfCalib;

namespace
{
vpColVector toCol(const Eigen::Vector3d &v)
{
  vpColVector c(3);
  for (unsigned int a = 0; a < 3; ++a)
    c[a] = v(a);
  return c;
}

// A white square patch with a dark disk of the given radius (fraction of the half side).
vpImage<unsigned char> dotTexture(double radius_fraction)
{
  const int n = 64;
  vpImage<unsigned char> I(n, n, 255);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double y = (i + 0.5) / n * 2 - 1, x = (j + 0.5) / n * 2 - 1;
      if (x * x + y * y <= radius_fraction * radius_fraction)
        I[i][j] = 20;
    }
  return I;
}
// Dot k of the grid in the target's plane (m): its place in the asymmetric layout times the step.
Eigen::Vector2d gridDot(const vpDotGrid &g, unsigned int k, double step)
{
  return Eigen::Vector2d(g.x(k) * step, g.y(k) * step);
}

// A face of width x height (m) seen with u along the columns and v along the rows, white, with the
// grid's dots centred at (u0 + x, v0 + y).
vpImage<unsigned char> gridTexture(double width, double height, const vpDotGrid &g, double step, double u0, double v0,
                                   double r, bool mirror_u)
{
  const double px_per_m = 4000;
  const unsigned int W = static_cast<unsigned int>(width * px_per_m), H = static_cast<unsigned int>(height * px_per_m);
  vpImage<unsigned char> I(H, W, 235);
  for (unsigned int k = 0; k < g.size(); ++k) {
    const Eigen::Vector2d c = gridDot(g, k, step) + Eigen::Vector2d(u0, v0);
    for (unsigned int i = 0; i < H; ++i) {
      const double v = (i + 0.5) / px_per_m;
      if (std::fabs(v - c.y()) > r)
        continue;
      for (unsigned int j = 0; j < W; ++j) {
        const double u = mirror_u ? width - (j + 0.5) / px_per_m : (j + 0.5) / px_per_m;
        if ((u - c.x()) * (u - c.x()) + (v - c.y()) * (v - c.y()) <= r * r)
          I[i][j] = 20;
      }
    }
  }
  return I;
}
} // namespace

void vpSelfCalibRenderer::Options::check() const
{
  if (!(blur_sd >= 0) || !(noise_sd >= 0) || !std::isfinite(blur_sd) || !std::isfinite(noise_sd))
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpSelfCalibRenderer: blur_sd and noise_sd must be >= 0");
  if (scene == CHARUCO &&
      (charuco_cols < 2 || charuco_rows < 2 || !(charuco_marker > 0) || !(charuco_marker < charuco_square) ||
       arucoDictionary(charuco_dictionary) < 0 ||
       static_cast<int>(charuco_cols * charuco_rows / 2) > arucoDictionarySize(arucoDictionary(charuco_dictionary))))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpSelfCalibRenderer: the ChArUco board needs 2 or more squares each way, markers "
                               "smaller than the squares and an OpenCV dictionary with enough markers");
  if (scene == APRILTAGS && (aprilTagFamily(tag_family).empty() || !(tag_size > 0) || !(tag_spacing > tag_size)))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpSelfCalibRenderer: the tags need a family OpenCV has (" + aprilTagFamilyNames() +
                                   "), a positive size and a spacing above it");
}

std::map<int, vpPoseVector> vpSelfCalibRenderer::getTagBundle(const Options &o)
{
  std::map<int, vpPoseVector> tags;
  for (int k = 0; k < 4; ++k)
    tags[k] = vpPoseVector((k % 2 - 0.5) * o.tag_spacing, (k / 2 - 0.5) * o.tag_spacing, 0, 0, 0, 0);
  return tags;
}

BoardPrint vpSelfCalib::boardPrint(const vpSelfCalibRenderer::Options &o)
{
  std::function<double(double, double)> at;
  double x0, y0, x1, y1, texel;
  BoardPrint print;
  if (o.scene == vpSelfCalibRenderer::CHARUCO) {
    auto board = std::make_shared<vpCharucoPrint>(static_cast<int>(o.charuco_cols), static_cast<int>(o.charuco_rows),
                                                  o.charuco_square, o.charuco_marker,
                                                  arucoDictionary(o.charuco_dictionary));
    at = [board](double x, double y) { return board->at(x, y); };
    x0 = y0 = -0.5 * o.charuco_square;
    x1 = (o.charuco_cols + 0.5) * o.charuco_square;
    y1 = (o.charuco_rows + 0.5) * o.charuco_square;
    texel = o.charuco_square / 48;
    print.cx = 0.5 * o.charuco_cols * o.charuco_square;
    print.cy = 0.5 * o.charuco_rows * o.charuco_square;
  } else {
    const int dict = arucoDictionary("DICT_APRILTAG_" + aprilTagFamily(o.tag_family));
    std::vector<std::pair<vpPoseVector, std::shared_ptr<vpTagPrint>>> tags;
    for (const auto &t : vpSelfCalibRenderer::getTagBundle(o))
      tags.emplace_back(t.second, std::make_shared<vpTagPrint>(dict, t.first, o.tag_size));
    at = [tags](double x, double y) {
      for (const auto &t : tags) {
        const double g = t.second->at(x - t.first[0], y - t.first[1]);
        if (g < 1)
          return g;
      }
      return 1.0;
    };
    x0 = y0 = -0.5 * o.tag_spacing - o.tag_size;
    x1 = y1 = 0.5 * o.tag_spacing + o.tag_size;
    texel = o.tag_size / 96;
  }
  print.texture = markerTexture(at, x0, y0, x1, y1, texel);
  print.x0 = x0;
  print.y0 = y0;
  print.x1 = x0 + (print.texture.getWidth() - 1.0) * texel;
  print.y1 = y0 + (print.texture.getHeight() - 1.0) * texel;
  return print;
}

vpImageSimulator vpSelfCalib::quadSimulator(const vpImage<unsigned char> &texture, const vpColVector X[4],
                                            const vpHomogeneousMatrix &cMa)
{
  vpImageSimulator s;
  s.setInterpolationType(vpImageSimulator::BILINEAR_INTERPOLATION);
  const Eigen::Vector3d c0 = vec3(X[0]), c1 = vec3(X[1]), c3 = vec3(X[3]);
  const Eigen::Vector3d n = (c1 - c0).cross(c3 - c0), cam = rigidFromVisp(cMa).inverse().t;
  vpColVector Y[4] = {X[0], X[1], X[2], X[3]};
  if (!(n.dot(cam - c0) < 0)) {
    std::swap(Y[0], Y[1]);
    std::swap(Y[2], Y[3]);
  }
  s.init(texture, Y);
  s.setCameraPosition(cMa);
  return s;
}

// The board scenes: one quad, its texture the board's printed side, its frame fMb: centred on the
// scene centre, z (into the board) away from the home camera, x along the home camera's x.
void vpSelfCalibRenderer::addBoard(const vpHomogeneousMatrix &fMc_home, const vpColVector &centre)
{
  const BoardPrint print = boardPrint(m_opt);
  Quad q;
  q.texture = print.texture;
  // The board's frame: its centre (the print's) on the scene centre.
  const Eigen::Vector3d c = vec3(centre), cam = rigidFromVisp(fMc_home).t;
  const Eigen::Vector3d z = (c - cam).normalized();
  Eigen::Vector3d x = rigidFromVisp(fMc_home).R.col(0);
  x = (x - x.dot(z) * z).normalized();
  const Eigen::Vector3d y = z.cross(x);
  const Eigen::Vector3d origin = c - print.cx * x - print.cy * y;
  for (unsigned int i = 0; i < 3; ++i) {
    m_fMb[i][0] = x(i);
    m_fMb[i][1] = y(i);
    m_fMb[i][2] = z(i);
    m_fMb[i][3] = origin(i);
  }
  const double corners[4][2] = {{print.x0, print.y0}, {print.x1, print.y0}, {print.x1, print.y1}, {print.x0, print.y1}};
  for (int k = 0; k < 4; ++k)
    q.corners[k] = toCol(origin + corners[k][0] * x + corners[k][1] * y);
  m_quads.push_back(q);
  m_end_a = m_end_b = vpColVector(3, 0.0);
}

vpSelfCalibRenderer::vpSelfCalibRenderer(const vpSelfCalibSimulator &sim, const Options &opt) : m_sim(sim), m_opt(opt)
{
  opt.check();
  const std::string dir = opt.texture_dir.empty() ? "/usr/share/visp-images-data/ViSP-images" : opt.texture_dir;
  const std::string files[2] = {dir + "/Klimt/Klimt.pgm", dir + "/Solvay/Solvay_conference_1927_Version2_640x440.png"};
  // Frame of the scene: the ridge along e2 through the centre, d towards the home viewpoint.
  const vpColVector home = sim.getOptions().home.size() ? sim.getOptions().home
                                                        : vpSelfCalibSimulator::homeConfiguration(sim.getNominalChain());
  const Rigid H = rigidFromVisp(sim.getNominalChain().get_fMc(home));
  if (opt.scene == CHARUCO || opt.scene == APRILTAGS) {
    addBoard(sim.getNominalChain().get_fMc(home), sim.getSceneCentre());
    return;
  }
  const Eigen::Vector3d c = vec3(sim.getSceneCentre());
  const Eigen::Vector3d d = (H.t - c).normalized();
  Eigen::Vector3d e1 = H.R.col(0) - H.R.col(0).dot(d) * d;
  e1.normalize();
  const Eigen::Vector3d e2 = d.cross(e1); // roughly the image's down direction seen from home
  const double width = 0.11, height = 0.16, tilt = 30 * M_PI / 180;
  // Scene DOTS: grid g on side g, in face coordinates (u from the ridge, v from the top edge).
  const unsigned int grid_rows[2] = {5, 9};
  // Dot radii differ between the grids (and from the yardstick's 4 and 6 mm): the front end tells
  // the grids apart by the dots' size.
  const double step = 0.01, grid_u0 = 0.035, dot_radius[2] = {0.0022, 0.0032};
  for (int side = 0; side < 2; ++side) {
    Quad q;
    // Plane side 0 on the -e1 side of the ridge, side 1 on the +e1 side, both leaning back from the viewer.
    const double s = side == 0 ? -1 : 1;
    const Eigen::Vector3d u = (std::cos(tilt) * e1 * s - std::sin(tilt) * d).normalized(); // away from the ridge
    if (opt.scene == DOTS) {
      // Texture columns run from corner 0 to corner 1: outer to inner on side 0 (u mirrored), unless
      // render() swaps the corners because the cameras see the quad from its back (it mirrors
      // photographs; the dots' places must not move).
      const Eigen::Vector3d top = c - 0.5 * height * e2, c0 = side == 0 ? top + width * u : top,
                            c1 = side == 0 ? top : top + width * u, c3 = c0 + height * e2;
      const bool back = !((c1 - c0).cross(c3 - c0).dot(H.t - c0) < 0);
      vpDotGrid g;
      g.cols = 4;
      g.rows = grid_rows[side];
      g.first_id = kFirstDotId + 1000 * side;
      const double v0 = 0.5 * (height - (g.rows - 1) * step);
      q.texture = gridTexture(width, height, g, step, grid_u0, v0, dot_radius[side], (side == 0) != back);
      // Ids as vpFeatureFrontEnd numbers them: the first row and the first column turn
      // counterclockwise in the image (seen from the home viewpoint), else the rows are numbered
      // from the other end.
      std::vector<Eigen::Vector3d> X;
      for (unsigned int k = 0; k < g.size(); ++k) {
        const Eigen::Vector2d p = gridDot(g, k, step);
        X.push_back(c + (grid_u0 + p.x()) * u + (v0 + p.y() - 0.5 * height) * e2);
      }
      const Rigid cMf = H.inverse();
      auto image = [&](unsigned int k) {
        const Eigen::Vector3d x = cMf * X[k];
        return Eigen::Vector2d(x.x() / x.z(), x.y() / x.z());
      };
      const Eigen::Vector2d a = image(g.cols - 1) - image(0), b = image((g.rows - 1) * g.cols) - image(0);
      const bool reversed = a.x() * b.y() - a.y() * b.x() < 0;
      for (unsigned int k = 0; k < g.size(); ++k) {
        const unsigned int i = k / g.cols, j = k % g.cols, label = (reversed ? g.rows - 1 - i : i) * g.cols + j;
        m_dot_centres[g.first_id + static_cast<int>(label)] = toCol(X[k]);
      }
      m_grids.push_back(g);
    } else
      try {
        // The file and its header checked before decoding, as the dataset's images are.
        vpSelfCalib::checkImageFile(files[side], "vpSelfCalibRenderer: cannot read the texture '" + files[side] + "'");
        vpImageIo::read(q.texture, files[side]);
      } catch (const vpSelfCalibException &) {
        throw;
      } catch (const vpException &e) {
        throw vpSelfCalibException(vpSelfCalibException::ioError,
                                   "vpSelfCalibRenderer: cannot read the texture '" + files[side] +
                                       "' (Debian package visp-images-data): " + e.getStringMessage());
      }
    const Eigen::Vector3d a = c, b = c + width * u;
    const Eigen::Vector3d inner_top = a - 0.5 * height * e2, outer_top = b - 0.5 * height * e2;
    const Eigen::Vector3d inner_bottom = a + 0.5 * height * e2, outer_bottom = b + 0.5 * height * e2;
    if (side == 0) {
      q.corners[0] = toCol(outer_top);
      q.corners[1] = toCol(inner_top);
      q.corners[2] = toCol(inner_bottom);
      q.corners[3] = toCol(outer_bottom);
    } else {
      q.corners[0] = toCol(inner_top);
      q.corners[1] = toCol(outer_top);
      q.corners[2] = toCol(outer_bottom);
      q.corners[3] = toCol(inner_bottom);
    }
    m_quads.push_back(q);
    if (side == 0) {
      // The yardstick: two dot patches on this plane, 1 mm in front of it, along e2.
      const Eigen::Vector3d nrm = u.cross(e2).dot(d) > 0 ? u.cross(e2).normalized() : (-u.cross(e2)).normalized();
      const Eigen::Vector3d mid = c + 0.5 * width * u + 0.001 * nrm;
      const double L = sim.getYardstick().length;
      const Eigen::Vector3d ends[2] = {mid - 0.5 * L * e2, mid + 0.5 * L * e2};
      const double radius[2] = {kDotRadiusA, kDotRadiusB};
      for (int k = 0; k < 2; ++k) {
        const double half = 0.015; // 3 cm white patch
        Quad dot;
        dot.texture = dotTexture(radius[k] / half);
        const Eigen::Vector3d &p = ends[k];
        const Eigen::Vector3d uu = u * half * (side == 0 ? -1 : 1), vv = e2 * half;
        dot.corners[0] = toCol(p - uu - vv);
        dot.corners[1] = toCol(p + uu - vv);
        dot.corners[2] = toCol(p + uu + vv);
        dot.corners[3] = toCol(p - uu + vv);
        m_quads.push_back(dot);
      }
      m_end_a = toCol(ends[0]);
      m_end_b = toCol(ends[1]);
    }
  }
}

double vpSelfCalibRenderer::getYardstickLength() const { return (m_end_a - m_end_b).frobeniusNorm(); }

vpImage<unsigned char> vpSelfCalibRenderer::render(const vpColVector &q, unsigned int view_index) const
{
  const vpHomogeneousMatrix cMf = m_sim.getTrueChain().get_fMc(q).inverse();
  // vpImageSimulator takes the corners in the frame of the quad and its pose; the quad frame here is f.
  std::list<vpImageSimulator> list;
  for (const Quad &quad : m_quads)
    list.push_back(quadSimulator(quad.texture, quad.corners, cMf));
  const vpSelfCalibSimulator::Options &so = m_sim.getOptions();
  vpImage<unsigned char> I(so.height, so.width, 128);
  if (m_opt.scene == CHARUCO || m_opt.scene == APRILTAGS)
    // The board alone (vpImageSimulator's drawing of a list paints the rest of a quad's bounding
    // box white), 4 x 4 samples per pixel: its edges where the truth says.
    I = renderQuad(list.front(), m_sim.getCamera(), so.height, so.width);
  else
    vpImageSimulator::getImage(I, list, m_sim.getCamera());
  blurAndNoise(I, m_opt.blur_sd, m_opt.noise_sd, m_opt.seed, 1000 + view_index);
  return I;
}

std::vector<vpImage<unsigned char>> vpSelfCalibRenderer::render(const std::vector<vpColVector> &qs,
                                                                unsigned int threads) const
{
  std::vector<vpImage<unsigned char>> images(qs.size());
  vpSelfCalib::parallelFor(qs.size(), vpSelfCalib::threadCount(threads),
                           [&](size_t k) { images[k] = render(qs[k], static_cast<unsigned int>(k)); });
  return images;
}

bool vpSelfCalibRenderer::surfacePoint(const vpColVector &q, const vpImagePoint &ip, vpColVector &fX) const
{
  const Rigid fMc = rigidFromVisp(m_sim.getTrueChain().get_fMc(q));
  const vpCameraParameters cam = m_sim.getCamera();
  const Eigen::Vector3d d =
      fMc.R * Eigen::Vector3d((ip.get_u() - cam.get_u0()) / cam.get_px(), (ip.get_v() - cam.get_v0()) / cam.get_py(), 1);
  double best = std::numeric_limits<double>::infinity();
  for (const Quad &quad : m_quads) {
    const Eigen::Vector3d c0 = vec3(quad.corners[0]), e1 = vec3(quad.corners[1]) - c0, e2 = vec3(quad.corners[3]) - c0;
    const Eigen::Vector3d n = e1.cross(e2);
    const double den = n.dot(d);
    if (std::fabs(den) < 1e-12)
      continue;
    const double t = n.dot(c0 - fMc.t) / den;
    if (!(t > 0) || t >= best)
      continue;
    const Eigen::Vector3d P = fMc.t + t * d;
    const double a = (P - c0).dot(e1) / e1.squaredNorm(), b = (P - c0).dot(e2) / e2.squaredNorm();
    if (a < 0 || a > 1 || b < 0 || b > 1)
      continue;
    best = t;
    fX = toCol(P);
  }
  return std::isfinite(best);
}

void vpSelfCalibRenderer::blurAndNoise(vpImage<unsigned char> &I, double blur_sd, double noise_sd, uint64_t seed,
                                       uint64_t stream)
{
  vpImage<double> F;
  if (blur_sd > 0) {
    vpImage<double> G;
    vpImageConvert::convert(I, G);
    vpImageFilter::gaussianBlur(G, F, static_cast<unsigned int>(2 * std::ceil(3 * blur_sd) + 1), blur_sd);
  } else
    vpImageConvert::convert(I, F);
  Random rng(seed, stream);
  for (unsigned int i = 0; i < I.getHeight(); ++i)
    for (unsigned int j = 0; j < I.getWidth(); ++j)
      I[i][j] = static_cast<unsigned char>(std::max(0.0, std::min(255.0, std::round(F[i][j] + rng.normal(noise_sd)))));
}
