/*
 * Planar scenes through the whole pipeline (hand-eye method): one plane seen at several tilts
 * determines eMc and f (as in Zhang's calibration), with a real lens (OpenCV's distortion) known or
 * estimated; the errors stay within the Cramér-Rao bound of the same data over several seeds.
 */
#include <gtest/gtest.h>

#include <cmath>

#include <visp3/selfcalib/vpKinematicBundleAdjustment.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "../testCommon.h"
#include "core/vpSelfCalibCamera.h"
#include "core/vpSelfCalibMath.h"
#include "core/vpSelfCalibRandom.h"

using namespace selfcalib_test;
using namespace vpSelfCalib;

namespace
{
const double kLens[9] = {800, 1.0, 330, 236, -0.21, 0.09, 0.0012, -0.0015, 0};

struct PlaneData {
  vpSelfCalibDataset ds;
  std::map<int, vpColVector> X; //!< the plane's points (f)
};

/*
  A 11 x 11 grid (6 cm pitch) on the plane z = 1 m of f, seen by the true camera from 12 tilted
  poses; hand-eye data (controller poses exact), pixels through the lens with `sd` px of noise. The
  yardstick is the grid's first row ends (0.6 m).
*/
PlaneData tiltedPlane(const vpSelfCalibSimulator &sim, const CameraModel &lens, double sd, uint64_t seed)
{
  PlaneData p;
  for (int i = 0; i < 11; ++i)
    for (int j = 0; j < 11; ++j)
      p.X[11 * i + j] = vpColVector({-0.3 + 0.06 * i, -0.3 + 0.06 * j, 1.0});
  Random rng(seed, 3);
  const vpHomogeneousMatrix cMe = sim.getTrueChain().get_eMc_corrected().inverse();
  p.ds.width = 640;
  p.ds.height = 480;
  p.ds.cam.initPersProjWithoutDistortion(lens.px(), lens.py(), lens.u0(), lens.v0());
  p.ds.robot = "viper850";
  for (int k = 0; k < 12; ++k) {
    const vpHomogeneousMatrix fMc(0.04 * (k % 3 - 1), 0.04 * ((k / 3) % 3 - 1), 0.08 * (k % 2), 0.3 * ((k % 3) - 1),
                                  0.3 * ((k / 3) % 3 - 1) + 0.1 * (k % 2), 0.45 * k);
    vpSelfCalibDataset::View v;
    v.has_fMe = true;
    v.fMe = fMc * cMe;
    const Rigid cMf = rigidFromVisp(fMc).inverse();
    for (const auto &e : p.X) {
      const Eigen::Vector2d uv = lens.project(cMf * vec3(e.second));
      const double u = uv(0) + rng.normal(sd), w = uv(1) + rng.normal(sd);
      if (u > 0 && u < 640 && w > 0 && w < 480)
        v.points.push_back({e.first, vpImagePoint(w, u)});
    }
    p.ds.views.push_back(v);
  }
  p.ds.yardstick.length = 0.6;
  p.ds.yardstick.id_a = 0;
  p.ds.yardstick.id_b = 10;
  return p;
}

vpRobotSelfCalibration::Options handEye(bool focal_known)
{
  vpRobotSelfCalibration::Options o;
  o.method = vpRobotSelfCalibration::HAND_EYE;
  o.num_calibration_poses = 12;
  o.focal_mode = focal_known ? vpRobotSelfCalibration::FOCAL_KNOWN : vpRobotSelfCalibration::FOCAL_SHARED;
  return o;
}

//! The eMc correction of the estimate minus the truth's, and its reported sd.
void eMcError(const vpSelfCalibSimulator &sim, const vpRobotSelfCalibration::Result &r, double e[6], double sd[6])
{
  const unsigned int first = r.calibrated.getNumParameters() - vpKinematicChain::kBlockSize;
  for (unsigned int i = 0; i < 6; ++i) {
    e[i] = r.calibrated.getParameters()[first + i] - sim.getTrueChain().getParameters()[first + i];
    sd[i] = r.parameter_sd[first + i];
  }
}
} // namespace

/*
  f self-calibrated from a tilted plane, OpenCV lens known (the dataset's coefficients, pixels as
  measured): over 6 seeds at 0.2 px, f and the 6 eMc components within 3.5 of the Cramér-Rao sd
  (information() at the truth), and the normalized error (RMS of error / CRB sd) below 1.5.
  Noise-free: exact.
*/
TEST(PlanarScene, HandEyeFocalSelfCalibratedWithAKnownLensWithinItsBound)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 91, 0.0);
  const CameraModel lens(Distortion::OPENCV, kLens);
  const std::vector<double> k(kLens + 4, kLens + 9);
  {
    PlaneData p = tiltedPlane(sim, lens, 0.0, 90);
    p.ds.opencv_distortion = k;
    p.ds.focal_known = false;
    vpRobotSelfCalibration::Options o = handEye(false);
    o.bundle.tight = true;
    const auto r = vpRobotSelfCalibration::run(sim.getNominalChain(), p.ds, o);
    ASSERT_EQ(r.status, vpRobotSelfCalibration::OK) << r.message;
    EXPECT_NEAR(r.camera.get_px(), kLens[0], 1e-6);
    double e[6], sd[6];
    eMcError(sim, r, e, sd);
    for (int i = 0; i < 6; ++i)
      EXPECT_NEAR(e[i], 0, 1e-8) << i;
  }
  // The bound: information() at the truth, on the undistorted noise-free pixels (the lens known).
  PlaneData clean = tiltedPlane(sim, lens.withoutDistortion(), 0.0, 90);
  vpKinematicBundleAdjustment::Options bo;
  bo.hand_eye_only = true;
  bo.intrinsics = vpKinematicBundleAdjustment::FX;
  const auto crb = vpKinematicBundleAdjustment::information(sim.getTrueChain(), clean.ds.cam, clean.ds.views,
                                                            clean.ds.yardstick, clean.X, bo);
  ASSERT_TRUE(crb.has_covariance) << crb.message;
  const unsigned int first = sim.getTrueChain().getNumParameters() - vpKinematicChain::kBlockSize;
  double nsq = 0;
  int n = 0;
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    PlaneData p = tiltedPlane(sim, lens, 0.2, seed);
    p.ds.opencv_distortion = k;
    p.ds.focal_known = false;
    // A first guess twice the truth (as the image width is for a wide lens): the start comes from
    // where the predicted rays meet, not from the guess.
    p.ds.cam.initPersProjWithoutDistortion(2 * kLens[0], 2 * kLens[0], kLens[2], kLens[3]);
    const auto r = vpRobotSelfCalibration::run(sim.getNominalChain(), p.ds, handEye(false));
    ASSERT_EQ(r.status, vpRobotSelfCalibration::OK) << seed << ": " << r.message;
    const double ef = (r.camera.get_px() - kLens[0]) / crb.fx_sd;
    EXPECT_LT(std::abs(ef), 3.5) << seed;
    nsq += ef * ef;
    ++n;
    double e[6], sd[6];
    eMcError(sim, r, e, sd);
    for (unsigned int i = 0; i < 6; ++i) {
      const double z = e[i] / crb.sd[first + i];
      EXPECT_LT(std::abs(z), 3.5) << seed << " eMc component " << i;
      nsq += z * z;
      ++n;
    }
  }
  EXPECT_LT(std::sqrt(nsq / n), 1.5);
}

/*
  Nominal intrinsics (f 6 % off, principal point 12 px off, no distortion): f, the principal point
  and OpenCV's k1, k2, p1, p2 estimated with eMc from the tilted plane. Noise-free: exact. At 0.2 px
  over 4 seeds: each within 3.5 of its reported sd, and the reported sd of the principal point and of
  k1 are given (written as intrinsics with their sd).
*/
TEST(PlanarScene, HandEyeNominalIntrinsicsLensAndPrincipalPointEstimated)
{
  const vpSelfCalibSimulator sim = makeSim("viper850", 92, 0.0);
  const CameraModel lens(Distortion::OPENCV, kLens);
  vpRobotSelfCalibration::Options o = handEye(false);
  o.bundle.intrinsics = vpKinematicBundleAdjustment::FX | vpKinematicBundleAdjustment::PRINCIPAL_POINT |
                       vpKinematicBundleAdjustment::DISTORTION;
  o.bundle.distortion_model = vpKinematicBundleAdjustment::DISTORTION_OPENCV;
  for (uint64_t seed = 0; seed <= 4; ++seed) {
    PlaneData p = tiltedPlane(sim, lens, seed == 0 ? 0.0 : 0.2, seed + 20);
    p.ds.focal_known = false;
    p.ds.cam.initPersProjWithoutDistortion(0.94 * kLens[0], 0.94 * kLens[0], 320, 248);
    vpRobotSelfCalibration::Options oo = o;
    oo.bundle.tight = seed == 0;
    const auto r = vpRobotSelfCalibration::run(sim.getNominalChain(), p.ds, oo);
    ASSERT_EQ(r.status, vpRobotSelfCalibration::OK) << seed << ": " << r.message;
    const auto &b = r.bundle;
    ASSERT_EQ(b.intrinsic_names, (std::vector<std::string>{"fx", "u0", "v0", "k1", "k2", "p1", "p2"}));
    const double truth[7] = {kLens[0], kLens[2], kLens[3], kLens[4], kLens[5], kLens[6], kLens[7]};
    for (unsigned int i = 0; i < 7; ++i) {
      if (seed == 0)
        EXPECT_NEAR(b.intrinsics[i], truth[i], 1e-6 * std::max(1.0, std::abs(truth[i]))) << b.intrinsic_names[i];
      else
        EXPECT_LT(std::abs(b.intrinsics[i] - truth[i]), 3.5 * b.intrinsics_sd[i]) << seed << " " << b.intrinsic_names[i];
    }
    ASSERT_EQ(b.opencv_distortion.size(), 5u);
  }
}
