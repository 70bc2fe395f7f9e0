/*
 * Kinematics-guided matching (vpFeatureFrontEnd with a prior) on rendered images: the nominal model
 * as the only prior of images taken by the true robot, a wrong prior, thread counts.
 */
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include <visp3/core/vpMath.h>
#include <visp3/selfcalib/vpFeatureFrontEnd.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibImageCorrespondences.h>
#include <visp3/selfcalib/vpSelfCalibRenderer.h>

#include "frontEndTruth.h"

namespace
{
// A rendered sequence of the reference scenario, its true robot's images, the nominal model's prior.
struct Sequence {
  vpSelfCalibSimulator sim;
  vpSelfCalibRenderer renderer;
  std::vector<vpColVector> q;
  std::vector<vpImage<unsigned char>> images;
  vpFeatureFrontEnd::Prior prior;
  Sequence(uint64_t seed, unsigned int n)
    : sim(vpKinematicChain::preset("viper850"), [&] {
        vpSelfCalibSimulator::Options o;
        o.seed = seed;
        return o;
      }()),
      renderer(sim, vpSelfCalibRenderer::Options()), q(sim.generateConfigurations(n))
  {
    for (unsigned int k = 0; k < n; ++k)
      images.push_back(renderer.render(q[k], k));
    prior = vpSelfCalibImageCorrespondences::makePrior(sim.getNominalChain(), sim.makeDataset(q));
  }
};
} // namespace

// The nominal model predicts the true robot's views: the matching is guided (the prior agrees with
// the images), >= 90 % of the track observations lie within 1 px of their true projection (the
// renderer's ray cast, see frontEndTruth.h), >= 90 % of the tracks have every observation within
// 1 px, the tracks span several views, and pairs were selected (fewer than all); two seeds.
TEST(GuidedMatching, NominalPriorGivesCorrectLongTracks)
{
  for (uint64_t seed : {3u, 7u}) {
    const Sequence s(seed, 10);
    vpFeatureFrontEnd::Options o;
    o.prior = s.prior;
    o.neighbours = 5;
    o.threads = 2;
    const vpFeatureFrontEnd::Result fe = vpFeatureFrontEnd::process(s.images, o);
    EXPECT_TRUE(fe.guided) << (fe.warnings.empty() ? "" : fe.warnings[0]);
    EXPECT_FALSE(fe.fallback);
    EXPECT_GT(fe.prior_agreement, 0.9);
    EXPECT_LT(fe.pairs_matched, 10u * 9u / 2u);
    ASSERT_GT(fe.num_tracks, 300u);
    const FrontEndTruth t = checkTracks(s.sim, s.renderer, s.q, fe);
    EXPECT_GE(t.observationFraction(), 0.9) << "seed " << seed;
    EXPECT_GE(t.trackFraction(), 0.9) << "seed " << seed;
    EXPECT_GE(t.median_length, 3) << "seed " << seed;
    // The match-count matrix: upper triangle, one entry per matched pair.
    unsigned int nonzero = 0;
    for (size_t i = 0; i < fe.matches.size(); ++i)
      for (size_t j = 0; j <= i; ++j)
        EXPECT_EQ(fe.matches[i][j], 0u);
    for (const auto &row : fe.matches)
      for (unsigned int c : row)
        nonzero += c > 0;
    EXPECT_LE(nonzero, fe.pairs_matched);
    // A track holds at most one feature per image.
    for (const auto &obs : fe.observations) {
      std::set<int> ids;
      for (const auto &o2 : obs)
        EXPECT_TRUE(ids.insert(o2.id).second);
    }
  }
}

// Track completion (step 3b) on 16 views with 4 neighbours each: the tracks grow (median length up
// by 1 or more, fewer two-view tracks), features are added and split tracks joined, and the added
// observations are as right as the matched ones (>= 90 % within 1 px of the truth, within 2 points
// of the fraction without completion); every track keeps one feature per image. Two seeds.
TEST(GuidedMatching, CompletionLengthensTracksWithoutWrongObservations)
{
  for (uint64_t seed : {3u, 9u}) {
    const Sequence s(seed, 16);
    vpFeatureFrontEnd::Options o;
    o.prior = s.prior;
    o.neighbours = 4;
    o.threads = 2;
    o.complete_tracks = false;
    const vpFeatureFrontEnd::Result off = vpFeatureFrontEnd::process(s.images, o);
    o.complete_tracks = true;
    const vpFeatureFrontEnd::Result on = vpFeatureFrontEnd::process(s.images, o);
    ASSERT_TRUE(on.guided);
    EXPECT_EQ(off.track_observations_added, 0u);
    EXPECT_EQ(off.tracks_merged, 0u);
    EXPECT_GT(on.track_observations_added, 500u) << "seed " << seed;
    EXPECT_GT(on.tracks_merged, 0u) << "seed " << seed;
    EXPECT_EQ(on.matches, off.matches); // the matching itself is the same
    const FrontEndTruth a = checkTracks(s.sim, s.renderer, s.q, off), b = checkTracks(s.sim, s.renderer, s.q, on);
    EXPECT_GE(b.median_length, a.median_length + 1) << "seed " << seed;
    ASSERT_GE(off.track_lengths.size(), 3u);
    ASSERT_GE(on.track_lengths.size(), 3u);
    EXPECT_LT(on.track_lengths[2], off.track_lengths[2]) << "seed " << seed;
    EXPECT_GE(b.observationFraction(), 0.9) << "seed " << seed;
    EXPECT_GE(b.observationFraction(), a.observationFraction() - 0.02) << "seed " << seed;
    // Observations: those of the tracks without completion plus the ones added.
    size_t n_off = 0, n_on = 0;
    for (size_t k = 0; k < on.observations.size(); ++k) {
      std::set<int> ids;
      for (const auto &x : on.observations[k])
        if (x.id < static_cast<int>(on.num_tracks)) {
          EXPECT_TRUE(ids.insert(x.id).second);
          ++n_on;
        }
      for (const auto &x : off.observations[k])
        n_off += x.id < static_cast<int>(off.num_tracks);
    }
    EXPECT_EQ(n_on, n_off + on.track_observations_added);
  }
}

// The same completion with ORB's binary descriptors (Hamming distances, integer ties) and without a
// prior (every pair matched unguided): it adds features, and the added observations are as right
// as the matched ones (within 2 points of the fraction within 1 px without completion).
TEST(GuidedMatching, CompletionWithOrbAndNoPriorAddsNoWrongObservations)
{
  const Sequence s(4, 10);
  vpFeatureFrontEnd::Options o;
  o.detector = vpFeatureFrontEnd::ORB;
  o.threads = 2;
  o.complete_tracks = false;
  const vpFeatureFrontEnd::Result off = vpFeatureFrontEnd::process(s.images, o);
  o.complete_tracks = true;
  const vpFeatureFrontEnd::Result on = vpFeatureFrontEnd::process(s.images, o);
  EXPECT_FALSE(on.guided);
  EXPECT_EQ(on.matches, off.matches);
  EXPECT_GT(on.track_observations_added, 0u);
  const FrontEndTruth a = checkTracks(s.sim, s.renderer, s.q, off), b = checkTracks(s.sim, s.renderer, s.q, on);
  EXPECT_GE(b.observationFraction(), a.observationFraction() - 0.02);
  for (const auto &obs : on.observations) {
    std::set<int> ids;
    for (const auto &x : obs)
      EXPECT_TRUE(ids.insert(x.id).second);
  }
}

// A wrong prior (the hand-eye guess rotated by 10 degrees) is detected: the front end falls back to
// unguided matching of every pair, says so in a warning, and still finds correct tracks.
TEST(GuidedMatching, WrongPriorFallsBackWithWarning)
{
  const Sequence s(5, 6);
  vpFeatureFrontEnd::Options o;
  o.prior = s.prior;
  o.threads = 2;
  const vpHomogeneousMatrix R10(0, 0, 0, vpMath::rad(10) / std::sqrt(2.0), vpMath::rad(10) / std::sqrt(2.0), 0);
  for (vpHomogeneousMatrix &M : o.prior.fMc)
    M = M * R10;
  const vpFeatureFrontEnd::Result fe = vpFeatureFrontEnd::process(s.images, o);
  EXPECT_FALSE(fe.guided);
  EXPECT_TRUE(fe.fallback);
  ASSERT_FALSE(fe.warnings.empty());
  EXPECT_NE(fe.warnings[0].find("prior disagrees with the images"), std::string::npos) << fe.warnings[0];
  EXPECT_LT(fe.prior_agreement, o.min_prior_agreement);
  EXPECT_EQ(fe.pairs_matched, 6u * 5u / 2u);
  const FrontEndTruth t = checkTracks(s.sim, s.renderer, s.q, fe);
  EXPECT_GE(t.observationFraction(), 0.9);
}

// One and two threads give the same tracks, guided and not (same ids, same pixels, same order).
TEST(GuidedMatching, ThreadCountDoesNotChangeTracks)
{
  Sequence s(11, 6);
  for (bool guided : {true, false}) {
    if (!guided) { // every pair: fewer images keep the test short
      s.images.resize(4);
      s.prior.fMc.resize(4);
    }
    vpFeatureFrontEnd::Options o;
    o.prior = s.prior;
    o.guided = guided;
    o.threads = 1;
    const vpFeatureFrontEnd::Result a = vpFeatureFrontEnd::process(s.images, o);
    o.threads = 2;
    const vpFeatureFrontEnd::Result b = vpFeatureFrontEnd::process(s.images, o);
    EXPECT_EQ(a.guided, guided);
    ASSERT_EQ(a.num_tracks, b.num_tracks);
    ASSERT_GT(a.num_tracks, 50u);
    EXPECT_EQ(a.matches, b.matches);
    for (size_t k = 0; k < a.observations.size(); ++k) {
      ASSERT_EQ(a.observations[k].size(), b.observations[k].size());
      for (size_t i = 0; i < a.observations[k].size(); ++i) {
        EXPECT_EQ(a.observations[k][i].id, b.observations[k][i].id);
        EXPECT_EQ(a.observations[k][i].ip.get_u(), b.observations[k][i].ip.get_u());
        EXPECT_EQ(a.observations[k][i].ip.get_v(), b.observations[k][i].ip.get_v());
      }
    }
  }
}

// Masks: no feature in the masked-out half; masks and priors of the wrong size are refused.
TEST(GuidedMatching, MasksAndBadInputs)
{
  const Sequence s(13, 3);
  vpFeatureFrontEnd::Options o;
  vpImage<unsigned char> mask(s.images[0].getHeight(), s.images[0].getWidth(), 255);
  for (unsigned int i = 0; i < mask.getHeight(); ++i)
    for (unsigned int j = 0; j < mask.getWidth() / 2; ++j)
      mask[i][j] = 0;
  o.masks = {mask};
  o.yardstick = false;
  const vpFeatureFrontEnd::Result fe = vpFeatureFrontEnd::process(s.images, o);
  ASSERT_GT(fe.num_tracks, 10u);
  for (const auto &obs : fe.observations)
    for (const auto &p : obs)
      EXPECT_GE(p.ip.get_u(), mask.getWidth() / 2 - 1.0);
  o.masks = {mask, mask};
  EXPECT_THROW(vpFeatureFrontEnd::process(s.images, o), vpSelfCalibException);
  o.masks = {vpImage<unsigned char>(10, 10, 255)};
  EXPECT_THROW(vpFeatureFrontEnd::process(s.images, o), vpSelfCalibException);
  o.masks.clear();
  o.prior = s.prior;
  o.prior.fMc.pop_back();
  EXPECT_THROW(vpFeatureFrontEnd::process(s.images, o), vpSelfCalibException);
  o.prior = s.prior;
  o.prior.rotation_sd = -1;
  EXPECT_THROW(vpFeatureFrontEnd::process(s.images, o), vpSelfCalibException);
}
