/*
 * Arms with one joint that barely moves, shared by the estimated-set tests and bench-estset (public
 * API only): the Panda with joint 3 and the PUMA 560 with joint 5 within +-0.5 deg of a home, the
 * other joints drawn around it and aimed at the scene.
 */
#ifndef VP_SELFCALIB_TEST_STUCK_JOINT_H
#define VP_SELFCALIB_TEST_STUCK_JOINT_H

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <visp3/core/vpColVector.h>
#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/core/vpMatrix.h>
#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

namespace selfcalib_test
{
constexpr double kStuck = 0.5 * M_PI / 180.0; // rad, half the stuck joint's range

//! The joint that barely moves (0-based): the Panda's j3, a 6-axis arm's wrist j5.
inline unsigned int stuckJoint(const std::string &robot) { return robot == "panda" ? 2 : 4; }

//! The home configuration the views are drawn around.
inline vpColVector home(const std::string &robot, const vpKinematicChain &chain)
{
  if (robot == "panda")
    return vpColVector({0, -0.5, 0, -2.2, 0, 1.9, 0.785});
  return vpSelfCalibSimulator::homeConfiguration(chain);
}

//! The reference scene (f known, every point in view, no pixel noise) for the robot at its home.
inline vpSelfCalibSimulator makeStuckSim(const std::string &robot, unsigned int seed)
{
  const vpKinematicChain chain = vpKinematicChain::preset(robot);
  vpSelfCalibSimulator::Options so;
  so.seed = seed;
  so.pixel_noise_sd = 0;
  so.home = home(robot, chain);
  return vpSelfCalibSimulator(chain, so);
}

/*
  One configuration: the joints drawn around the home (the stuck one within +-kStuck of its home
  value, the others within +-0.5 rad), then the others moved by damped Gauss-Newton steps so that the
  optical axis passes through the scene centre at a drawn distance; kept when within the limits and
  every scene point is in view.
*/
inline bool drawConfiguration(const vpSelfCalibSimulator &sim, const vpColVector &q0, unsigned int stuck,
                              std::mt19937_64 &rng, vpColVector &q, double stuck_range = kStuck)
{
  const vpKinematicChain &chain = sim.getNominalChain();
  const unsigned int n = chain.getNumJoints();
  std::uniform_real_distribution<double> u(-1, 1);
  q = q0;
  for (unsigned int j = 0; j < n; ++j)
    q[j] += j == stuck ? stuck_range * u(rng) : 0.5 * u(rng);
  const vpColVector c = sim.getSceneCentre();
  const double dist = 0.6 + 0.2 * 0.5 * (u(rng) + 1);
  auto residual = [&](const vpColVector &x) {
    const vpHomogeneousMatrix cMf = chain.get_fMc(x).inverse();
    vpColVector X(4);
    for (unsigned int a = 0; a < 3; ++a)
      X[a] = c[a];
    X[3] = 1;
    const vpColVector Xc = cMf * X;
    return vpColVector({Xc[0] / Xc[2], Xc[1] / Xc[2], (Xc[2] - dist) / dist});
  };
  for (int it = 0; it < 30; ++it) {
    const vpColVector r = residual(q);
    if (r.frobeniusNorm() < 1e-9)
      break;
    vpMatrix J(3, n - 1);
    unsigned int col = 0;
    for (unsigned int j = 0; j < n; ++j) {
      if (j == stuck)
        continue;
      vpColVector qe = q;
      qe[j] += 1e-6;
      const vpColVector d = (residual(qe) - r) / 1e-6;
      for (unsigned int a = 0; a < 3; ++a)
        J[a][col] = d[a];
      ++col;
    }
    const vpColVector step = J.pseudoInverse() * r;
    col = 0;
    for (unsigned int j = 0; j < n; ++j)
      if (j != stuck)
        q[j] -= std::max(-0.3, std::min(0.3, step[col++]));
  }
  return residual(q).frobeniusNorm() < 1e-6 && chain.isInJointLimits(q) && sim.isVisible(q);
}

//! count configurations of drawConfiguration() around q0, seeded by seed; throws std::runtime_error
//! when 200 draws per configuration do not find them.
inline std::vector<vpColVector> configurations(const vpSelfCalibSimulator &sim, const vpColVector &q0, unsigned int stuck,
                                               unsigned int count, unsigned int seed, double stuck_range = kStuck)
{
  std::mt19937_64 rng(7919ULL * seed + 17);
  std::vector<vpColVector> out;
  for (unsigned int attempt = 0; out.size() < count && attempt < 200 * count; ++attempt) {
    vpColVector q;
    if (drawConfiguration(sim, q0, stuck, rng, q, stuck_range))
      out.push_back(q);
  }
  if (out.size() < count)
    throw std::runtime_error("no feasible configurations around the home");
  return out;
}
} // namespace selfcalib_test

#endif
