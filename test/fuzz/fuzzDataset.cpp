/*
 * libFuzzer target: the dataset YAML parser (vpSelfCalibDataset::fromYamlString).
 * Any input must either parse or throw vpSelfCalibException; a parsed dataset must write and read
 * back to the same text (the writer keeps 17 significant digits). Relative paths are kept as they
 * are (no base directory), so no image is read. Build and run with cmake/fuzz.sh.
 */
#include <cstdint>
#include <cstdlib>
#include <string>

#include <visp3/selfcalib/vpSelfCalibDataset.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  const std::string text(reinterpret_cast<const char *>(data), size);
  vpSelfCalibDataset ds;
  try {
    ds = vpSelfCalibDataset::fromYamlString(text, "<fuzz>");
  } catch (const vpSelfCalibException &) {
    return 0; // a clear error is the expected answer to bad input
  }
  const std::string written = ds.toYamlString();
  const vpSelfCalibDataset again = vpSelfCalibDataset::fromYamlString(written, "<round trip>");
  if (again.toYamlString() != written)
    std::abort();
  return 0;
}
