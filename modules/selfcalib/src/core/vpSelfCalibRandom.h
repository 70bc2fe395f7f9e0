/*
 * ViSP SelfCalib: private seeded random numbers (not installed).
 *
 * std::uniform_real_distribution and std::normal_distribution are implementation-defined, so the
 * same seed could give other data with another standard library. These draws are defined here,
 * from std::mt19937_64 (whose output the standard fixes), so data are the same bit for bit
 * wherever the module is built.
 */
#ifndef VP_SELFCALIB_RANDOM_H
#define VP_SELFCALIB_RANDOM_H

#include <cmath>
#include <cstdint>
#include <random>

namespace vpSelfCalib
{
class Random
{
public:
  //! A stream for (seed, stream): independent streams for independent uses of one seed.
  explicit Random(uint64_t seed, uint64_t stream = 0) : m_rng(mix(seed ^ mix(stream + 0x9E3779B97F4A7C15ULL))) {}

  //! Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(m_rng() >> 11) * (1.0 / 9007199254740992.0); }
  double uniform(double a, double b) { return a + (b - a) * uniform(); }
  //! Standard normal (Marsaglia's polar method).
  double normal()
  {
    if (m_has_spare) {
      m_has_spare = false;
      return m_spare;
    }
    double u, v, s;
    do {
      u = 2.0 * uniform() - 1.0;
      v = 2.0 * uniform() - 1.0;
      s = u * u + v * v;
    } while (s >= 1.0 || s == 0.0);
    const double f = std::sqrt(-2.0 * std::log(s) / s);
    m_spare = v * f;
    m_has_spare = true;
    return u * f;
  }
  double normal(double sd) { return sd * normal(); }
  uint64_t next() { return m_rng(); }

private:
  static uint64_t mix(uint64_t z)
  {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }
  std::mt19937_64 m_rng;
  bool m_has_spare = false;
  double m_spare = 0;
};

/*!
  OpenCV USAC's random generator state (cv::UsacParams::randomGeneratorState, a non-negative int)
  for (seed, stream): every RANSAC of the module draws from its caller's seed through this, one
  stream per independent use (a pair, a view).
*/
inline int usacSeed(uint64_t seed, uint64_t stream = 0)
{
  return static_cast<int>(Random(seed, stream).next() >> 33); // 31 bits
}
} // namespace vpSelfCalib

#endif
