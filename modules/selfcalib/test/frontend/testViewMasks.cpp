/*
 * Tests of the per-view masks (vpSelfCalibDataset::View::mask, vpFeatureFrontEnd::viewMasks): a
 * textured patch that moves from view to view (an overlay drawn on the images, the gripper) hidden
 * by each view's own mask, the masks combined with a global one, and bad mask files.
 */
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <unistd.h>

#include <visp3/io/vpImageIo.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibImageCorrespondences.h>
#include <visp3/selfcalib/vpSelfCalibRenderer.h>

#include "../testCommon.h"
#include "frontEndTruth.h"

namespace fs = std::filesystem;

namespace
{
//! A patch's place in one view: rows [top, top + size), columns [left, left + size).
struct Patch {
  unsigned int top = 0, left = 0, size = 0;
  bool contains(const vpImagePoint &ip) const
  {
    return ip.get_i() >= top && ip.get_i() < top + size && ip.get_j() >= left && ip.get_j() < left + size;
  }
};

/*
  Six rendered views of the reference scenario (hand-eye: controller poses), each with the same
  textured patch (a mirrored crop of view 0's centre) pasted at a place that moves from view to
  view, written to `dir` with each view's mask (black over its patch, 4 px beyond).
*/
struct MovingPatch {
  vpSelfCalibSimulator sim = selfcalib_test::makeSim("viper850", 5);
  vpSelfCalibRenderer renderer{sim, vpSelfCalibRenderer::Options()};
  std::vector<vpColVector> q;
  std::vector<Patch> patches;
  vpSelfCalibDataset dataset;
  fs::path dir;

  MovingPatch()
  {
    dir = fs::temp_directory_path() / ("selfcalib-view-masks-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    q = sim.generateConfigurations(6);
    dataset = sim.makeDataset(q);
    selfcalib_test::toControllerPoses(sim, dataset, 0, 0, 5, 1);
    std::vector<vpImage<unsigned char>> images;
    for (unsigned int k = 0; k < q.size(); ++k)
      images.push_back(renderer.render(q[k], k));
    const unsigned int size = 150;
    vpImage<unsigned char> patch(size, size);
    for (unsigned int i = 0; i < size; ++i)
      for (unsigned int j = 0; j < size; ++j)
        patch[i][j] = images[0][165 + i][245 + size - 1 - j];
    for (unsigned int k = 0; k < images.size(); ++k) {
      const Patch p{40 + 45 * k, 30 + 85 * k, size};
      patches.push_back(p);
      vpImage<unsigned char> mask(images[k].getHeight(), images[k].getWidth(), 255);
      for (unsigned int i = 0; i < size; ++i)
        for (unsigned int j = 0; j < size; ++j)
          images[k][p.top + i][p.left + j] = patch[i][j];
      for (unsigned int i = p.top - 4; i < p.top + size + 4; ++i)
        for (unsigned int j = p.left - 4; j < p.left + size + 4; ++j)
          mask[i][j] = 0;
      dataset.views[k].image = (dir / ("view" + std::to_string(k) + ".png")).string();
      dataset.views[k].mask = (dir / ("mask" + std::to_string(k) + ".png")).string();
      dataset.views[k].points.clear();
      vpImageIo::write(images[k], dataset.views[k].image);
      vpImageIo::write(mask, dataset.views[k].mask);
    }
  }
  ~MovingPatch()
  {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

//! Observations inside their view's patch.
unsigned int insidePatches(const vpFeatureFrontEnd::Result &fe, const std::vector<Patch> &patches)
{
  unsigned int n = 0;
  for (size_t k = 0; k < fe.observations.size(); ++k)
    for (const auto &o : fe.observations[k])
      n += patches[k].contains(o.ip);
  return n;
}

//! eMc's error against the truth per axis: translation (m) and theta u of truth^-1 estimate (rad).
vpColVector eMcError(const vpSelfCalibSimulator &sim, const vpRobotSelfCalibration::Result &r)
{
  return selfcalib_test::poseError(r.eMc, sim.getTrueChain().get_eMc_corrected());
}

//! Observations of each view whose pixel its own mask (file) hides.
unsigned int insideMasks(const vpFeatureFrontEnd::Result &fe, const vpSelfCalibDataset &ds)
{
  unsigned int n = 0;
  for (size_t k = 0; k < fe.observations.size(); ++k) {
    vpImage<unsigned char> mask;
    vpImageIo::read(mask, ds.views[k].mask);
    for (const auto &o : fe.observations[k])
      n += mask[static_cast<unsigned int>(o.ip.get_i() + 0.5)][static_cast<unsigned int>(o.ip.get_j() + 0.5)] == 0;
  }
  return n;
}
} // namespace

// The patch moves from view to view and drags wrong matches along. Each view's own mask (the
// dataset's mask:, read back from its file) hides it: no feature where a view's mask is black,
// every track as correct as without the masks or more, and the hand-eye calibration within 3 of
// its own sd of the truth on every axis of eMc and no worse than without the masks (beyond its sd).
TEST(ViewMasks, HideAPatchThatMovesFromViewToView)
{
  const MovingPatch s;
  const vpSelfCalibDataset read = vpSelfCalibDataset::fromYamlString(s.dataset.toYamlString());
  for (size_t k = 0; k < read.views.size(); ++k)
    EXPECT_EQ(read.views[k].mask, s.dataset.views[k].mask);
  // Unguided: every pair matched, so the patch's twins in other views are offered to the matching.
  vpSelfCalibImageCorrespondences::Options o;
  o.method = vpRobotSelfCalibration::HAND_EYE;
  vpSelfCalibDataset masked = read, unmasked = read;
  for (auto &v : unmasked.views)
    v.mask.clear();
  const auto with = vpSelfCalibImageCorrespondences::fromDatasetImages(masked, o);
  const auto without = vpSelfCalibImageCorrespondences::fromDatasetImages(unmasked, o);
  ASSERT_EQ(masked.views.size(), 6u);
  ASSERT_EQ(unmasked.views.size(), 6u);
  EXPECT_EQ(insideMasks(with.front_end, read), 0u);
  EXPECT_GT(insideMasks(without.front_end, read), 20u); // the patch is a problem without masks
  EXPECT_GT(insidePatches(without.front_end, s.patches), 20u);
  const FrontEndTruth t_with = checkTracks(s.sim, s.renderer, s.q, with.front_end);
  const FrontEndTruth t_without = checkTracks(s.sim, s.renderer, s.q, without.front_end);
  ASSERT_GT(t_with.tracks, 100u);
  EXPECT_GE(t_with.observationFraction(), t_without.observationFraction());
  EXPECT_GT(t_with.observationFraction(), 0.95);

  vpRobotSelfCalibration::Options co;
  co.method = vpRobotSelfCalibration::HAND_EYE;
  co.trust_robot = true; // exact controller poses: the masks are the subject, not the robot's error
  const vpRobotSelfCalibration::Result r_with = vpRobotSelfCalibration::run(s.sim.getNominalChain(), masked, co);
  const vpRobotSelfCalibration::Result r_without = vpRobotSelfCalibration::run(s.sim.getNominalChain(), unmasked, co);
  ASSERT_EQ(r_with.status, vpRobotSelfCalibration::OK) << r_with.message;
  ASSERT_TRUE(r_with.has_eMc);
  ASSERT_EQ(r_with.eMc_sd.size(), 6u);
  const vpColVector e_with = eMcError(s.sim, r_with);
  for (unsigned int i = 0; i < 6; ++i) {
    EXPECT_GT(r_with.eMc_sd[i], 0) << "axis " << i;
    EXPECT_LE(std::abs(e_with[i]), 3 * r_with.eMc_sd[i]) << "axis " << i << ": error " << e_with[i] << ", sd " << r_with.eMc_sd[i];
  }
  if (r_without.status == vpRobotSelfCalibration::OK || r_without.status == vpRobotSelfCalibration::DOUBTFUL) {
    // No worse: the error's translation and rotation no larger than without the masks, beyond 3 of
    // the masked run's own sd (both runs see the same images but for the patch).
    const vpColVector e_without = eMcError(s.sim, r_without);
    for (unsigned int part = 0; part < 2; ++part) {
      double with2 = 0, without2 = 0, sd2 = 0;
      for (unsigned int i = 3 * part; i < 3 * part + 3; ++i) {
        with2 += e_with[i] * e_with[i];
        without2 += e_without[i] * e_without[i];
        sd2 += r_with.eMc_sd[i] * r_with.eMc_sd[i];
      }
      EXPECT_LE(std::sqrt(with2), std::sqrt(without2) + 3 * std::sqrt(sd2)) << (part ? "rotation" : "translation");
    }
  }
}

// A global mask and the views' own combine: a pixel is searched where both allow it; a view
// without a mask file gets the global mask alone; without any view mask the masks are unchanged.
TEST(ViewMasks, CombinedWithAGlobalMask)
{
  const MovingPatch s;
  vpImage<unsigned char> global(s.dataset.height, s.dataset.width, 255);
  for (unsigned int i = 0; i < global.getHeight(); ++i)
    for (unsigned int j = 0; j < 100; ++j)
      global[i][j] = 0;
  vpSelfCalibDataset ds = s.dataset;
  ds.views[3].mask.clear();
  const std::vector<vpImage<unsigned char>> m = vpFeatureFrontEnd::viewMasks(ds, {global});
  ASSERT_EQ(m.size(), ds.views.size());
  for (size_t k = 0; k < m.size(); ++k) {
    const Patch &p = s.patches[k];
    EXPECT_EQ(m[k][p.top + 10][p.left + 120], k == 3 ? 255 : 0) << "view " << k; // the patch
    EXPECT_EQ(m[k][5][50], 0) << "view " << k;                                     // the global mask
    EXPECT_EQ(m[k][470][630], 255) << "view " << k;                                // neither
  }
  vpSelfCalibDataset plain = s.dataset;
  for (auto &v : plain.views)
    v.mask.clear();
  EXPECT_EQ(vpFeatureFrontEnd::viewMasks(plain, {global}).size(), 1u);
  EXPECT_TRUE(vpFeatureFrontEnd::viewMasks(plain, {}).empty());
}

// Bad mask files: missing, a directory, of another size than the camera's, a global mask of another
// size, or a mask without an image in the file: each refused with the view (or key) and the file named.
TEST(ViewMasks, BadMasksAreRefusedNamingTheViewAndTheFile)
{
  const MovingPatch s;
  auto message = [&](vpSelfCalibDataset ds, const std::vector<vpImage<unsigned char>> &global) {
    try {
      vpFeatureFrontEnd::viewMasks(ds, global, "who");
    } catch (const vpSelfCalibException &e) {
      return e.getStringMessage();
    }
    return std::string("no exception");
  };
  vpSelfCalibDataset ds = s.dataset;
  ds.views[2].mask = (s.dir / "none.png").string();
  EXPECT_EQ(message(ds, {}).rfind("who: view 2: cannot read mask '" + ds.views[2].mask + "': ", 0), 0u)
      << message(ds, {});
  fs::create_directories(s.dir / "adir.png");
  ds.views[2].mask = (s.dir / "adir.png").string();
  EXPECT_NE(message(ds, {}).find("view 2: cannot read mask '" + ds.views[2].mask + "': is a directory"),
            std::string::npos);
  const std::string small = (s.dir / "small.png").string();
  vpImageIo::write(vpImage<unsigned char>(240, 320, 255), small);
  ds.views[2].mask = small;
  EXPECT_EQ(message(ds, {}), "who: view 2: mask '" + small + "' is 320 x 240, the camera says 640 x 480");
  ds = s.dataset;
  EXPECT_EQ(message(ds, {vpImage<unsigned char>(10, 10, 255)}),
            "who: the mask for view 0 is 10 x 10, the camera says 640 x 480");
  EXPECT_EQ(message(ds, {vpImage<unsigned char>(480, 640, 255), vpImage<unsigned char>(480, 640, 255)}),
            "who: 2 masks for 6 views (give none, one, or one per view)");

  // The dataset file: a mask needs an image and an extension.
  const std::string yaml = "camera: {width: 640, height: 480, u0: 320, v0: 240, px: 1500, py: 1500}\n"
                           "robot: viper850\nposes:\n";
  const std::string pose = "  - {joints: [0, 0, 0, 0, 0, 0], ";
  try {
    vpSelfCalibDataset::fromYamlString(yaml + pose + "mask: m.png}\n" + pose + "image: a.png}\n" + pose +
                                       "image: b.png}\n");
    ADD_FAILURE() << "a mask without an image was accepted";
  } catch (const vpSelfCalibException &e) {
    EXPECT_NE(e.getStringMessage().find("poses[0].mask"), std::string::npos) << e.getStringMessage();
    EXPECT_NE(e.getStringMessage().find("a mask without an image"), std::string::npos) << e.getStringMessage();
  }
  try {
    vpSelfCalibDataset::fromYamlString(yaml + pose + "image: a.png, mask: m}\n" + pose + "image: a.png}\n" + pose +
                                       "image: b.png}\n");
    ADD_FAILURE() << "a mask without an extension was accepted";
  } catch (const vpSelfCalibException &e) {
    EXPECT_NE(e.getStringMessage().find("poses[0].mask"), std::string::npos) << e.getStringMessage();
    EXPECT_NE(e.getStringMessage().find("has no extension"), std::string::npos) << e.getStringMessage();
  }
  // Written relative to the dataset's directory, read back resolved.
  ds = s.dataset;
  const std::string text = ds.toYamlString(s.dir.string());
  EXPECT_NE(text.find("mask: mask0.png"), std::string::npos);
  EXPECT_EQ(vpSelfCalibDataset::fromYamlString(text, "<string>", s.dir.string()).views[0].mask, ds.views[0].mask);
}
