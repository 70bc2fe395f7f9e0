/*
 * libFuzzer target: the robot-model YAML parser (vpKinematicChain::fromYamlString).
 * Any input must either parse or throw vpSelfCalibException; a parsed model must survive a round
 * trip through toYamlString() with the same camera pose. Build and run with cmake/fuzz.sh.
 */
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  const std::string text(reinterpret_cast<const char *>(data), size);
  vpKinematicChain chain;
  try {
    chain = vpKinematicChain::fromYamlString(text, "<fuzz>");
  } catch (const vpSelfCalibException &) {
    return 0; // a clear error is the expected answer to bad input
  }
  // Round trip: what was read is written and read back to the same model.
  const vpKinematicChain again = vpKinematicChain::fromYamlString(chain.toYamlString(), "<round trip>");
  if (again.getNumJoints() != chain.getNumJoints())
    std::abort();
  vpColVector q(chain.getNumJoints());
  for (unsigned int i = 0; i < q.size(); ++i)
    q[i] = 0.1 * (i + 1);
  const vpHomogeneousMatrix a = chain.get_fMc(q), b = again.get_fMc(q);
  for (unsigned int r = 0; r < 3; ++r)
    for (unsigned int c = 0; c < 4; ++c)
      if (!(a[r][c] == b[r][c]) && !(std::isnan(a[r][c]) && std::isnan(b[r][c])))
        std::abort();
  return 0;
}
