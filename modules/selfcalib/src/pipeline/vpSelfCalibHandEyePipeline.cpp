/*
 * ViSP SelfCalib: target-less hand-eye calibration (the kinematics trusted): multi-view
 * reconstruction, Tsai's closed form, then the kinematic bundle adjustment on eMc, f_x and points.
 */
#include "vpSelfCalibPipelines.h"

#include "../core/vpSelfCalibMath.h"

#include <opencv2/calib3d.hpp>

using namespace vpSelfCalib;

namespace vpSelfCalibPipeline
{
namespace
{
/*
  First eMc: Tsai's closed form (OpenCV) from the end-effector poses fMe and the scene-to-camera
  poses of the multi-view reconstruction (translations times s), as a correction of the model's eMc
  (eMc_nominal D = eMc). The nominal model when fewer than 3 views are posed or the closed form gives
  nonsense (non-finite, or a correction of 1 m or more).
*/
vpKinematicChain handEyeStart(const vpKinematicChain &nominal, const std::vector<Rigid> &fMe,
                              const vpMultiViewReconstruction::Result &mv, double s)
{
  vpKinematicChain start = nominal;
  std::vector<cv::Mat> Rg, tg, Rt, tt;
  for (size_t k = 0; k < fMe.size(); ++k) {
    if (!mv.posed[k])
      continue;
    const Rigid c = rigidFromVisp(mv.cMc0[k]);
    cv::Mat a(3, 3, CV_64F), b(3, 1, CV_64F), c3(3, 3, CV_64F), d(3, 1, CV_64F);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        a.at<double>(i, j) = fMe[k].R(i, j);
        c3.at<double>(i, j) = c.R(i, j);
      }
      b.at<double>(i) = fMe[k].t(i);
      d.at<double>(i) = s * c.t(i);
    }
    Rg.push_back(a);
    tg.push_back(b);
    Rt.push_back(c3);
    tt.push_back(d);
  }
  if (Rg.size() < 3)
    return start;
  cv::Mat R, t;
  cv::calibrateHandEye(Rg, tg, Rt, tt, R, t, cv::CALIB_HAND_EYE_TSAI);
  Rigid eMc;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j)
      eMc.R(i, j) = R.at<double>(i, j);
    eMc.t(i) = t.at<double>(i);
  }
  const Rigid D = rigidFromPose(nominal.get_eMc_pose()).inverse() * eMc;
  const Eigen::Vector3d r = logSO3(D.R);
  const unsigned int first = nominal.getNumParameters() - vpKinematicChain::kBlockSize;
  vpColVector p = nominal.getParameters();
  for (unsigned int i = 0; i < 3; ++i) {
    p[first + i] = D.t(i);
    p[first + 3 + i] = r(i);
  }
  if (D.t.allFinite() && r.allFinite() && D.t.norm() < 1.0)
    start.setParameters(p);
  return start;
}
} // namespace

void runHandEye(const Context &c, Result &res)
{
  const unsigned int N = c.num_calibration;
  const std::vector<View> &cal = c.calibration;
  if (!multiView(c, res))
    return;
  auto ts = std::chrono::steady_clock::now();
  std::vector<Rigid> fMe;
  for (const auto &v : cal)
    fMe.push_back(rigidFromVisp(v.has_fMe ? v.fMe : c.nominal.get_fMe(v.q)));

  // Metric unit: the yardstick, else the end-effector baseline of the reference pair with the model's eMc.
  const Rigid eMc0 = rigidFromVisp(c.nominal.get_eMc_corrected());
  double s = 1;
  if (!res.multiview.metric) {
    const unsigned int r = res.multiview.reference_view;
    const double baseline = ((fMe[r] * eMc0).inverse() * (fMe[0] * eMc0)).t.norm();
    s = baseline / res.multiview.cMc0[r].getTranslationVector().frobeniusNorm();
  }
  const vpKinematicChain start = handEyeStart(c.nominal, fMe, res.multiview, s);
  res.stage_seconds.push_back({"hand-eye closed form", seconds(ts)});

  // Kinematic bundle adjustment in hand-eye-only mode (bundleOptions), points moved to f through the
  // first eMc; every view with its end-effector pose.
  std::vector<View> views = cal;
  for (unsigned int k = 0; k < N; ++k)
    if (!views[k].has_fMe) {
      views[k].has_fMe = true;
      views[k].fMe = toVisp(fMe[k]);
    }
  bundle(c, start, toVisp(fMe[0]) * start.get_eMc_corrected(), s, views, c.bundle, "hand-eye bundle adjustment", res);
}
} // namespace vpSelfCalibPipeline
