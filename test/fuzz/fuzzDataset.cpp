/*
 * libFuzzer target: the dataset YAML parser (vpSelfCalibDataset::fromYamlString).
 * Any input must either parse or throw vpSelfCalibException; a parsed dataset must write and read
 * back to the same dataset: every field bit for bit, except controller poses, which come back
 * within 1e-12 (theta-u from a matrix is not always the vector the matrix was built from; the
 * writer finds one that rebuilds it exactly when it can). Relative paths are kept as they are (no
 * base directory), so no image is read. Build and run with cmake/fuzz.sh.
 */
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include <visp3/selfcalib/vpSelfCalibDataset.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

namespace
{
bool same(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

void check(bool ok)
{
  if (!ok)
    std::abort();
}

void expectSame(const vpSelfCalibDataset &a, const vpSelfCalibDataset &b)
{
  check(a.width == b.width && a.height == b.height && a.focal_known == b.focal_known && a.robot == b.robot);
  check(same(a.cam.get_px(), b.cam.get_px()) && same(a.cam.get_py(), b.cam.get_py()) &&
        same(a.cam.get_u0(), b.cam.get_u0()) && same(a.cam.get_v0(), b.cam.get_v0()));
  check(a.yardstick.id_a == b.yardstick.id_a && a.yardstick.id_b == b.yardstick.id_b &&
        same(a.yardstick.length, b.yardstick.length));
  check(a.views.size() == b.views.size());
  for (size_t k = 0; k < a.views.size(); ++k) {
    const auto &u = a.views[k], &v = b.views[k];
    check(u.q.size() == v.q.size() && u.has_fMe == v.has_fMe && u.image == v.image &&
          u.points.size() == v.points.size());
    for (unsigned int i = 0; i < u.q.size(); ++i)
      check(same(u.q[i], v.q[i]));
    for (size_t i = 0; i < u.points.size(); ++i)
      check(u.points[i].id == v.points[i].id && same(u.points[i].ip.get_u(), v.points[i].ip.get_u()) &&
            same(u.points[i].ip.get_v(), v.points[i].ip.get_v()));
    if (u.has_fMe)
      for (unsigned int r = 0; r < 3; ++r)
        for (unsigned int c = 0; c < 4; ++c)
          check(std::fabs(u.fMe[r][c] - v.fMe[r][c]) <= 1e-12);
  }
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  const std::string text(reinterpret_cast<const char *>(data), size);
  vpSelfCalibDataset ds;
  try {
    ds = vpSelfCalibDataset::fromYamlString(text, "<fuzz>");
  } catch (const vpSelfCalibException &) {
    return 0; // a clear error is the expected answer to bad input
  }
  expectSame(ds, vpSelfCalibDataset::fromYamlString(ds.toYamlString(), "<round trip>"));
  return 0;
}
