/*
 * visp-selfcalib compare, a camera fixed in the world with joint readings: the truth of bMc and eMo
 * in the calibrated model's own frames (see compare.h).
 */
#include "compare.h"

#include <algorithm>
#include <filesystem>

#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>

namespace fs = std::filesystem;

namespace
{
//! The truth's noise-free view of the target's layout at joints q (pinhole, points in front only).
vpSelfCalibDataset::View trueView(const vpKinematicChain &truth, const vpHomogeneousMatrix &bMc,
                                  const vpHomogeneousMatrix &eMo, const std::map<int, vpColVector> &layout,
                                  const vpCameraParameters &cam, const vpColVector &q)
{
  vpSelfCalibDataset::View v;
  v.q = q;
  const vpHomogeneousMatrix cMo = bMc.inverse() * truth.get_fMe(q) * eMo;
  for (const auto &l : layout) {
    const vpColVector X = cMo * vpColVector({l.second[0], l.second[1], l.second[2], 1.0});
    if (X[2] > 0)
      v.points.push_back({l.first, vpImagePoint(cam.get_v0() + cam.get_py() * X[1] / X[2],
                                                cam.get_u0() + cam.get_px() * X[0] / X[2])});
  }
  return v;
}
} // namespace

bool truthInModelFrames(const vpKinematicChain &truth, const vpKinematicChain &nominal, const vpHomogeneousMatrix &bMc,
                        const vpHomogeneousMatrix &eMo, const std::map<int, vpColVector> &layout,
                        const vpCameraParameters &cam, const std::string &dataset,
                        const std::vector<std::string> &estimated, vpHomogeneousMatrix &bMc_model,
                        vpHomogeneousMatrix &eMo_model)
{
  if (dataset.empty() || !fs::is_regular_file(dataset) || layout.size() < 4)
    return false;
  vpSelfCalibDataset ds;
  try {
    ds = vpSelfCalibDataset::loadYaml(dataset);
  } catch (const vpException &) {
    return false;
  }
  vpSelfCalibDataset clean;
  clean.cam = cam;
  clean.focal_known = true;
  clean.camera_mount = vpSelfCalibDataset::CAMERA_IN_WORLD;
  for (const auto &v : ds.views)
    if (v.q.size() == nominal.getNumJoints() && nominal.isInJointLimits(v.q))
      clean.views.push_back(trueView(truth, bMc, eMo, layout, cam, v.q));
  const std::vector<std::string> names = nominal.getParameterNames();
  vpRobotSelfCalibration::Options o;
  for (unsigned int i = 0; i < names.size(); ++i)
    if (std::find(estimated.begin(), estimated.end(), names[i]) != estimated.end())
      o.bundle.estimated_set.identified.push_back(i);
  if (clean.views.size() < 3 || o.bundle.estimated_set.identified.empty())
    return false;
  o.bundle.estimated_set.rank = static_cast<unsigned int>(o.bundle.estimated_set.identified.size());
  o.method = vpRobotSelfCalibration::BUNDLE_ADJUSTMENT;
  o.num_calibration_poses = static_cast<unsigned int>(clean.views.size());
  o.bundle.known_points = layout;
  o.bundle.tight = true;
  o.bundle.kinematic_prior = vpKinematicBundleAdjustment::KINEMATIC_PRIOR_OFF; // an exact fit: no pull toward nominal
  o.trust_robot = true;
  o.noise.measure_joint_sd = o.noise.measure_model_sd = o.noise.measure_pose_sd = false;
  try {
    const vpRobotSelfCalibration::Result r = vpRobotSelfCalibration::run(nominal, clean, o);
    if ((r.status != vpRobotSelfCalibration::OK && r.status != vpRobotSelfCalibration::DOUBTFUL) || !r.has_bMc ||
        !r.has_eMo || !(r.bundle.rms < 1e-3))
      return false;
    bMc_model = vpHomogeneousMatrix(r.bMc);
    eMo_model = vpHomogeneousMatrix(r.eMo);
  } catch (const vpException &) {
    return false;
  }
  return true;
}
