/*
 * ViSP SelfCalib: private generic RANSAC (not installed).
 *
 * Samples are drawn without replacement from a seeded stream; the number of iterations adapts to
 * the best inlier ratio found: N = log(1 - confidence) / log(1 - w^s) (Fischler & Bolles; Hartley &
 * Zisserman, alg. 4.5).
 */
#ifndef VP_SELFCALIB_RANSAC_H
#define VP_SELFCALIB_RANSAC_H

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "vpSelfCalibRandom.h"

namespace vpSelfCalib
{
template <typename Model> struct RansacResult {
  bool found = false;
  Model model;
  std::vector<bool> inliers;
  unsigned int num_inliers = 0;
  unsigned int iterations = 0;
};

/*!
  \param fit : model(s) from a minimal sample (false when the sample is degenerate).
  \param is_inlier : whether datum i agrees with the model.
*/
template <typename Model>
RansacResult<Model> ransac(unsigned int num_data, unsigned int sample_size,
                           const std::function<bool(const std::vector<unsigned int> &, Model &)> &fit,
                           const std::function<bool(const Model &, unsigned int)> &is_inlier, double confidence,
                           unsigned int max_iterations, Random &rng)
{
  RansacResult<Model> best;
  if (num_data < sample_size)
    return best;
  double needed = max_iterations;
  std::vector<unsigned int> sample(sample_size);
  std::vector<bool> mask(num_data);
  for (unsigned int it = 0; it < max_iterations && it < needed; ++it) {
    best.iterations = it + 1;
    // Sample without replacement (Floyd's algorithm keeps it O(sample_size)).
    std::vector<unsigned int> chosen;
    for (unsigned int j = num_data - sample_size; j < num_data; ++j) {
      const unsigned int t = static_cast<unsigned int>(rng.next() % (j + 1));
      if (std::find(chosen.begin(), chosen.end(), t) == chosen.end())
        chosen.push_back(t);
      else
        chosen.push_back(j);
    }
    std::copy(chosen.begin(), chosen.end(), sample.begin());
    Model m;
    if (!fit(sample, m))
      continue;
    unsigned int count = 0;
    for (unsigned int i = 0; i < num_data; ++i) {
      mask[i] = is_inlier(m, i);
      count += mask[i];
    }
    if (count > best.num_inliers) {
      best.found = true;
      best.model = m;
      best.inliers = mask;
      best.num_inliers = count;
      const double w = static_cast<double>(count) / num_data;
      const double pw = std::pow(w, static_cast<double>(sample_size));
      if (pw >= 1.0 - 1e-12)
        needed = 0;
      else if (pw > 0)
        needed = std::ceil(std::log(1.0 - confidence) / std::log(1.0 - pw));
    }
  }
  return best;
}
} // namespace vpSelfCalib

#endif
