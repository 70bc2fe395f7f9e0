/*
 * Helpers shared by the module's tests (not installed).
 */
#ifndef VP_SELFCALIB_TEST_COMMON_H
#define VP_SELFCALIB_TEST_COMMON_H

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <visp3/core/vpPoseVector.h>
#include <visp3/selfcalib/vpBoardDetector.h>
#include <visp3/selfcalib/vpKinematicIdentification.h>
#include <visp3/selfcalib/vpSelfCalibRenderer.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "core/vpSelfCalibMath.h"
#include "core/vpSelfCalibRandom.h"

namespace selfcalib_test
{
//! The reference scenario for a preset, with the given seed and pixel noise (default: the simulator's).
inline vpSelfCalibSimulator makeSim(const std::string &robot, uint64_t seed, double noise = 0.2)
{
  vpSelfCalibSimulator::Options o;
  o.seed = seed;
  o.pixel_noise_sd = noise;
  return vpSelfCalibSimulator(vpKinematicChain::preset(robot), o);
}

//! Wrong matches: each observation replaced by a uniform pixel with probability `fraction`
//! (random stream `stream` of the seed).
inline void corrupt(vpSelfCalibDataset &ds, double fraction, uint64_t seed, uint64_t stream)
{
  vpSelfCalib::Random rng(seed, stream);
  for (auto &v : ds.views)
    for (auto &o : v.points)
      if (rng.uniform(0, 1) < fraction)
        o.ip = vpImagePoint(rng.uniform(0, ds.height), rng.uniform(0, ds.width));
}

/*!
  Hand-eye data: the views of ds given as controller poses fMe (the true flange pose of sim's robot,
  each off by a pose error of sd (t m, r rad), random stream `stream` of the seed) and no joints.
*/
inline void toControllerPoses(const vpSelfCalibSimulator &sim, vpSelfCalibDataset &ds, double sd_t, double sd_r,
                              uint64_t seed, uint64_t stream)
{
  vpSelfCalib::Random rng(seed, stream);
  for (auto &v : ds.views) {
    const double d[6] = {rng.normal(sd_t), rng.normal(sd_t), rng.normal(sd_t),
                         rng.normal(sd_r), rng.normal(sd_r), rng.normal(sd_r)};
    v.has_fMe = true;
    v.fMe = sim.getTrueChain().get_fMe(v.q) * vpSelfCalib::toVisp(vpSelfCalib::rigidFromVector(d));
    v.q = vpColVector();
  }
}

//! Per-axis errors (estimate - truth): translation (m) and theta u of truth^-1 estimate (rad).
inline vpColVector poseError(const vpPoseVector &estimate, const vpHomogeneousMatrix &truth)
{
  const vpHomogeneousMatrix E(estimate);
  const vpPoseVector d(truth.inverse() * E);
  vpColVector e(6);
  for (unsigned int i = 0; i < 3; ++i) {
    e[i] = E[i][3] - truth[i][3];
    e[3 + i] = d[3 + i];
  }
  return e;
}

//! The detector of the renderer's tag bundle (scene APRILTAGS: vpSelfCalibRenderer::getTagBundle()).
inline vpBoardDetector::Options tagBundleDetector(const vpSelfCalibRenderer::Options &ro)
{
  vpBoardDetector::Options o;
  o.type = vpBoardDetector::APRILTAG;
  o.dictionary = ro.tag_family;
  for (const auto &t : vpSelfCalibRenderer::getTagBundle(ro)) {
    vpBoardDetector::Options::BundleTag b;
    b.id = t.first;
    b.size = ro.tag_size;
    b.bMt = t.second;
    o.bundle.push_back(b);
    o.tag_ids.push_back(t.first);
  }
  return o;
}

/*!
  simulate --target charuco's board (7 x 5 squares of 2 cm, 24 corners), its layout unknown: the
  reference scenario of `sim` (eye-in-hand) with the board where vpSelfCalibRenderer places it, its
  corners projected through the true camera at the configurations q (those in the image), with
  Gaussian noise of sd px (random stream `stream` of `seed`; none at 0); the board's yardstick. The
  corners' true positions in f go to `truth`. No image is rendered: the corners are exact.
*/
inline vpSelfCalibDataset charucoBoardViews(const vpSelfCalibSimulator &sim, const std::vector<vpColVector> &q, double sd,
                                            uint64_t seed, uint64_t stream, std::map<int, vpColVector> &truth)
{
  const vpBoardDetector det(vpBoardDetector::parse("charuco:7x5:0.02:0.015:DICT_6X6_250"));
  vpSelfCalibRenderer::Options ro;
  ro.scene = vpSelfCalibRenderer::CHARUCO;
  const vpHomogeneousMatrix fMb = vpSelfCalibRenderer(sim, ro).getBoardPose();
  truth.clear();
  for (const auto &e : det.getLayout()) {
    const vpColVector X = fMb * vpColVector({e.second[0], e.second[1], e.second[2], 1.0});
    truth[e.first] = vpColVector({X[0], X[1], X[2]});
  }
  vpSelfCalib::Random rng(seed, stream);
  vpSelfCalibDataset ds;
  ds.cam = sim.getCamera();
  ds.width = sim.getOptions().width;
  ds.height = sim.getOptions().height;
  ds.focal_known = true;
  ds.yardstick = det.getYardstick();
  for (const vpColVector &qk : q) {
    vpSelfCalibDataset::View v;
    v.q = qk;
    const vpHomogeneousMatrix cMf = sim.getTrueChain().get_fMc(qk).inverse();
    for (const auto &e : truth) {
      const vpColVector p = cMf * vpColVector({e.second[0], e.second[1], e.second[2], 1.0});
      const double u = ds.cam.get_u0() + ds.cam.get_px() * p[0] / p[2] + (sd > 0 ? rng.normal(sd) : 0.0);
      const double w = ds.cam.get_v0() + ds.cam.get_py() * p[1] / p[2] + (sd > 0 ? rng.normal(sd) : 0.0);
      if (p[2] > 0 && u >= 0 && w >= 0 && u < ds.width && w < ds.height)
        v.points.push_back({e.first, vpImagePoint(w, u)});
    }
    ds.views.push_back(v);
  }
  return ds;
}

//! The parameters an estimated set leaves at nominal because the data do not determine them.
inline std::vector<std::string> leftByData(const vpKinematicIdentification::Identifiability &s)
{
  std::vector<std::string> out;
  for (const auto &u : s.unidentifiable)
    if (u.cause == vpKinematicIdentification::CAUSE_DATA)
      out.push_back(u.name);
  return out;
}

/*!
  A stuck wrist: the PUMA 560 (standard DH) in the simulator (f known, no pixel noise, 20 scene points
  or more in view), `views` configurations drawn with joint 5's deviation from the home scaled down
  so that it spans `range_deg` (within +-range_deg / 2 of the home; 0: the configurations as drawn).
*/
struct StuckWrist {
  vpSelfCalibSimulator sim;
  std::vector<vpColVector> q;
  vpSelfCalibDataset ds;
  StuckWrist(uint64_t seed, unsigned int views, double range_deg) : sim(simOf(seed))
  {
    const vpColVector home = vpSelfCalibSimulator::homeConfiguration(sim.getNominalChain());
    q = sim.generateConfigurations(views);
    double widest = 0;
    for (const vpColVector &c : q)
      widest = std::max(widest, std::fabs(c[4] - home[4]));
    for (vpColVector &c : q)
      if (range_deg > 0)
        c[4] = home[4] + (c[4] - home[4]) * (0.5 * range_deg * M_PI / 180.0) / widest;
    ds = sim.makeDataset(q);
  }
  //! The simulator of the stuck wrist's views, before any joint is squeezed.
  static vpSelfCalibSimulator simOf(uint64_t seed)
  {
    vpSelfCalibSimulator::Options o;
    o.seed = seed;
    o.pixel_noise_sd = 0;
    o.min_visible_points = 20;
    return vpSelfCalibSimulator(vpKinematicChain::preset("puma560"), o);
  }
};

/*
  The RMS error of `model`'s relative camera motions c_iM c_j against `truth`'s (m, rad) over
  `pairs` pairs of configurations drawn uniformly within the joint limits (seeded): what `compare`
  measures against a simulation's truth, the figure the workspace doubt predicts.
*/
struct MotionRms {
  double t = 0, r = 0;
};
//! A joint drawn within [lo, hi] (rad) instead of its limits by workspaceMotionError().
struct HeldJoint {
  unsigned int joint = 0;
  double lo = 0, hi = 0;
};
inline MotionRms workspaceMotionError(const vpKinematicChain &model, const vpKinematicChain &truth,
                                      unsigned int pairs = 1000, const std::vector<HeldJoint> &held = {})
{
  vpSelfCalib::Random rng(1, 7);
  const auto draw = [&]() {
    vpColVector q(truth.getNumJoints());
    for (unsigned int j = 0; j < q.size(); ++j)
      q[j] = rng.uniform(truth.getJoints()[j].min, truth.getJoints()[j].max);
    for (const HeldJoint &h : held)
      q[h.joint] = rng.uniform(h.lo, h.hi);
    return q;
  };
  MotionRms e;
  for (unsigned int k = 0; k < pairs; ++k) {
    const vpColVector qi = draw(), qj = draw();
    const vpHomogeneousMatrix m = model.get_fMc(qi).inverse() * model.get_fMc(qj),
                              t = truth.get_fMc(qi).inverse() * truth.get_fMc(qj);
    e.t += std::pow(vpSelfCalib::translationDistance(m, t), 2) / pairs;
    e.r += std::pow(vpSelfCalib::rotationDistance(m, t), 2) / pairs;
  }
  e.t = std::sqrt(e.t);
  e.r = std::sqrt(e.r);
  return e;
}
} // namespace selfcalib_test

#endif
