/*
 * ViSP SelfCalib: coded-marker targets (OpenCV aruco): dictionaries by name, printed sides.
 */
#include "vpSelfCalibMarkers.h"

#include <cmath>
#include <utility>

namespace vpSelfCalib
{
namespace
{
const std::pair<const char *, int> kDictionaries[] = {
    {"DICT_4X4_50", cv::aruco::DICT_4X4_50},
    {"DICT_4X4_100", cv::aruco::DICT_4X4_100},
    {"DICT_4X4_250", cv::aruco::DICT_4X4_250},
    {"DICT_4X4_1000", cv::aruco::DICT_4X4_1000},
    {"DICT_5X5_50", cv::aruco::DICT_5X5_50},
    {"DICT_5X5_100", cv::aruco::DICT_5X5_100},
    {"DICT_5X5_250", cv::aruco::DICT_5X5_250},
    {"DICT_5X5_1000", cv::aruco::DICT_5X5_1000},
    {"DICT_6X6_50", cv::aruco::DICT_6X6_50},
    {"DICT_6X6_100", cv::aruco::DICT_6X6_100},
    {"DICT_6X6_250", cv::aruco::DICT_6X6_250},
    {"DICT_6X6_1000", cv::aruco::DICT_6X6_1000},
    {"DICT_7X7_50", cv::aruco::DICT_7X7_50},
    {"DICT_7X7_100", cv::aruco::DICT_7X7_100},
    {"DICT_7X7_250", cv::aruco::DICT_7X7_250},
    {"DICT_7X7_1000", cv::aruco::DICT_7X7_1000},
    {"DICT_ARUCO_ORIGINAL", cv::aruco::DICT_ARUCO_ORIGINAL},
    {"DICT_APRILTAG_16h5", cv::aruco::DICT_APRILTAG_16h5},
    {"DICT_APRILTAG_25h9", cv::aruco::DICT_APRILTAG_25h9},
    {"DICT_APRILTAG_36h10", cv::aruco::DICT_APRILTAG_36h10},
    {"DICT_APRILTAG_36h11", cv::aruco::DICT_APRILTAG_36h11},
};
const char *kFamilies[] = {"36h11", "36h10", "25h9", "16h5"};

// The marker's cells, one pixel each, its black border included: (n + 2) x (n + 2), 0 or 255.
cv::Mat markerCells(const cv::Ptr<cv::aruco::Dictionary> &d, int id)
{
  cv::Mat bits;
  cv::aruco::drawMarker(d, id, d->markerSize + 2, bits, 1);
  return bits;
}

// Grey 0 or 1 of the cells `bits` spread over the square [x0, x0 + side) x [y0, y0 + side).
double cellAt(const cv::Mat &bits, double x0, double y0, double side, double x, double y)
{
  const int n = bits.rows;
  const int c = static_cast<int>(std::floor((x - x0) / side * n)), r = static_cast<int>(std::floor((y - y0) / side * n));
  if (r < 0 || c < 0 || r >= n || c >= n)
    return 1;
  return bits.at<unsigned char>(r, c) ? 1 : 0;
}
} // namespace

int arucoDictionary(const std::string &name)
{
  for (const auto &d : kDictionaries)
    if (name == d.first)
      return d.second;
  return -1;
}

std::string aprilTagFamily(const std::string &name)
{
  const std::string family = name.rfind("tag", 0) == 0 ? name.substr(3) : name;
  for (const char *f : kFamilies)
    if (family == f)
      return family;
  return std::string();
}

std::string arucoDictionaryNames()
{
  std::string s;
  for (const auto &d : kDictionaries)
    s += (s.empty() ? "" : ", ") + std::string(d.first);
  return s;
}

std::string aprilTagFamilyNames()
{
  std::string s;
  for (const char *f : kFamilies)
    s += (s.empty() ? "" : ", ") + std::string(f);
  return s;
}

int arucoDictionarySize(int dictionary) { return cv::aruco::getPredefinedDictionary(dictionary)->bytesList.rows; }

vpCharucoPrint::vpCharucoPrint(int cols, int rows, double square, double marker, int dictionary)
    : m_board(cv::aruco::CharucoBoard::create(cols, rows, static_cast<float>(square), static_cast<float>(marker),
                                              cv::aruco::getPredefinedDictionary(dictionary))),
      m_square(square)
{
  for (int id : m_board->ids)
    m_bits.push_back(markerCells(m_board->dictionary, id));
}

double vpCharucoPrint::at(double x, double y) const
{
  const int cx = static_cast<int>(std::floor(x / m_square)), cy = static_cast<int>(std::floor(y / m_square));
  if (x < 0 || y < 0 || cx >= m_board->getChessboardSize().width || cy >= m_board->getChessboardSize().height)
    return 1;
  if ((cx + cy) % 2 == 0) // the top-left square is black
    return 0;
  // A white square: its marker, if the point is on it (objPoints[k][0] is the marker's top-left
  // corner, [2] its bottom-right).
  for (size_t k = 0; k < m_board->objPoints.size(); ++k) {
    const cv::Point3f &a = m_board->objPoints[k][0], &b = m_board->objPoints[k][2];
    if (x >= a.x && x < b.x && y >= a.y && y < b.y)
      return cellAt(m_bits[k], a.x, a.y, b.x - a.x, x, y);
  }
  return 1;
}

vpTagPrint::vpTagPrint(int dictionary, int id, double size)
    : m_size(size), m_bits(markerCells(cv::aruco::getPredefinedDictionary(dictionary), id))
{
}

double vpTagPrint::at(double x, double y) const { return cellAt(m_bits, -0.5 * m_size, -0.5 * m_size, m_size, x, y); }

vpImage<unsigned char> markerTexture(const std::function<double(double, double)> &at, double x0, double y0, double x1,
                                     double y1, double texel)
{
  const int sub = 4;
  // (1e-9: a whole number of texels stays whole through the division)
  const unsigned int W = static_cast<unsigned int>((x1 - x0) / texel + 1e-9) + 1;
  const unsigned int H = static_cast<unsigned int>((y1 - y0) / texel + 1e-9) + 1;
  vpImage<unsigned char> texture(H, W);
  for (unsigned int i = 0; i < H; ++i)
    for (unsigned int j = 0; j < W; ++j) {
      double sum = 0;
      for (int a = 0; a < sub; ++a)
        for (int b = 0; b < sub; ++b)
          sum += at(x0 + (j + (b + 0.5) / sub - 0.5) * texel, y0 + (i + (a + 0.5) / sub - 0.5) * texel);
      texture[i][j] = static_cast<unsigned char>(std::lround(30 + 190 * sum / (sub * sub)));
    }
  return texture;
}

vpImage<unsigned char> renderQuad(vpImageSimulator &quad, const vpCameraParameters &cam, unsigned int height,
                                  unsigned int width)
{
  std::vector<vpImageSimulator> quads(1, quad);
  return renderQuads(quads, cam, height, width);
}

vpImage<unsigned char> renderQuads(std::vector<vpImageSimulator> &quads, const vpCameraParameters &cam,
                                   unsigned int height, unsigned int width)
{
  const unsigned int n = 4;
  const vpCameraParameters fine(n * cam.get_px(), n * cam.get_py(), n * cam.get_u0() + 0.5 * (n - 1),
                                n * cam.get_v0() + 0.5 * (n - 1));
  vpImage<unsigned char> F(n * height, n * width, 128);
  for (vpImageSimulator &quad : quads)
    quad.getImage(F, fine);
  vpImage<unsigned char> I(height, width);
  for (unsigned int i = 0; i < height; ++i)
    for (unsigned int j = 0; j < width; ++j) {
      unsigned int sum = 0;
      for (unsigned int a = 0; a < n; ++a)
        for (unsigned int b = 0; b < n; ++b)
          sum += F[n * i + a][n * j + b];
      I[i][j] = static_cast<unsigned char>((sum + n * n / 2) / (n * n));
    }
  return I;
}
} // namespace vpSelfCalib
