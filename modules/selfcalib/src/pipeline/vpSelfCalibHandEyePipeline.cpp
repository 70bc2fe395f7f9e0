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
  The nominal model with its eMc correction set so that its eMc is `eMc` (eMc_nominal D = eMc, the
  correction's translation and rotation vector). plausible: the correction is finite and under 1 m.
*/
vpKinematicChain withEMc(const vpKinematicChain &nominal, const Rigid &eMc, bool &plausible)
{
  const Rigid D = rigidFromPose(nominal.get_eMc_pose()).inverse() * eMc;
  const Eigen::Vector3d r = logSO3(D.R);
  const unsigned int first = nominal.getNumParameters() - vpKinematicChain::kBlockSize;
  vpColVector p = nominal.getParameters();
  for (unsigned int i = 0; i < 3; ++i) {
    p[first + i] = D.t(i);
    p[first + 3 + i] = r(i);
  }
  vpKinematicChain chain = nominal;
  chain.setParameters(p);
  plausible = D.t.allFinite() && r.allFinite() && D.t.norm() < 1.0;
  return chain;
}

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
  bool plausible = false;
  const vpKinematicChain tsai = withEMc(nominal, eMc, plausible);
  return plausible ? tsai : start;
}
} // namespace

namespace
{
/*
  The better of two finished runs: the one whose robot pose corrections do not stand in for eMc
  (robotCorrectionsStandIn: the other's eMc did not converge, its pose corrections took its error),
  then more observations kept (beyond 2 %), then the lower sigma0.
*/
bool better(const Result &a, const Result &b)
{
  if (a.status != vpRobotSelfCalibration::OK)
    return false;
  if (b.status != vpRobotSelfCalibration::OK)
    return true;
  const bool a_stands_in = robotCorrectionsStandIn(a.bundle), b_stands_in = robotCorrectionsStandIn(b.bundle);
  if (a_stands_in != b_stands_in)
    return b_stands_in;
  const double na = a.bundle.num_observations, nb = b.bundle.num_observations;
  if (std::abs(na - nb) > 0.02 * std::max(na, nb))
    return na > nb;
  return a.bundle.sigma0 < b.bundle.sigma0;
}
} // namespace

/*
  Two starts, both adjusted, the better kept (better()): (1) the points triangulated from the camera
  poses the controller poses and the model's eMc predict, at the dataset's focal length (run()
  measured it where these rays meet best when f is self-calibrated; no two-view geometry: works on
  planes); (2) the multi-view
  reconstruction and Tsai's closed form (works when the model's eMc is far off).
*/
void runHandEye(const Context &c, Result &res)
{
  const unsigned int N = c.num_calibration;
  const std::vector<View> &cal = c.calibration;
  std::vector<Rigid> fMe;
  for (const auto &v : cal)
    fMe.push_back(rigidFromVisp(v.has_fMe ? v.fMe : c.nominal.get_fMe(v.q)));
  std::vector<View> views = cal;
  for (unsigned int k = 0; k < N; ++k)
    if (!views[k].has_fMe) {
      views[k].has_fMe = true;
      views[k].fMe = toVisp(fMe[k]);
    }
  // From an earlier run (Options::start): one adjustment from its eMc, points and focal length.
  if (c.options.start.set) {
    const vpRobotSelfCalibration::Options::Start &s = c.options.start;
    if (bundleFrom(c, s.model, s.points, s.fx, views, c.bundle, "hand-eye bundle adjustment", res))
      res.message = "start from an earlier run; " + res.message;
    return;
  }
  const Result before = res;

  // (1) From the robot's predicted poses.
  Result predicted = before;
  {
    auto ts = std::chrono::steady_clock::now();
    const Rigid eMc0 = rigidFromVisp(c.nominal.get_eMc_corrected());
    std::vector<Rigid> fMc;
    for (const Rigid &M : fMe)
      fMc.push_back(M * eMc0);
    const PredictedStart p =
        predictedStart(cal, fMc, lensOf(c.dataset), true); // the dataset's f: measured by run() when self-calibrated
    predicted.stage_seconds.push_back({"start from the robot's poses", seconds(ts)});
    if (p.ok && bundleFrom(c, c.nominal, p.points, p.fx, views, c.bundle, "hand-eye bundle adjustment", predicted))
      predicted.message = "start from the controller poses; " + predicted.message;
    else if (!p.ok) {
      predicted.status = vpRobotSelfCalibration::TWO_VIEW_FAILED;
      predicted.message = "fewer than 10 observations triangulate from the controller poses";
    }
  }

  // (1b) When the pose corrections stand in for eMc (robotCorrectionsStandIn: eMc stayed near its
  // guess, every controller pose corrected by much the same amount), their mean moved into eMc,
  // fMe E(d) eMc = fMe E(d - m) (E(m) eMc) to first order, and adjusted again from there.
  if (predicted.status == vpRobotSelfCalibration::OK && robotCorrectionsStandIn(predicted.bundle) &&
      !predicted.bundle.pose_corrections.empty()) {
    double m[6] = {0, 0, 0, 0, 0, 0};
    for (const vpColVector &d : predicted.bundle.pose_corrections)
      for (unsigned int i = 0; i < 6; ++i)
        m[i] += d[i] / static_cast<double>(predicted.bundle.pose_corrections.size());
    bool plausible = false;
    const vpKinematicChain start =
        withEMc(c.nominal, rigidFromVector(m) * rigidFromVisp(predicted.calibrated.get_eMc_corrected()), plausible);
    Result again = before;
    if (bundleFrom(c, start, predicted.bundle.points, predicted.fx, views, c.bundle, "hand-eye bundle adjustment",
                   again)) {
      again.message = "start from the controller poses, eMc moved by their mean correction; " + again.message;
      if (better(again, predicted))
        predicted = again;
    }
  }

  // (2) From the multi-view reconstruction.
  Result multi = before;
  if (multiView(c, multi)) {
    auto ts = std::chrono::steady_clock::now();
    // Metric unit: the yardstick, else the end-effector baseline of the reference pair with the model's eMc.
    const Rigid eMc0 = rigidFromVisp(c.nominal.get_eMc_corrected());
    double s = 1;
    if (!multi.multiview.metric) {
      const unsigned int r = multi.multiview.reference_view;
      const double baseline = ((fMe[r] * eMc0).inverse() * (fMe[0] * eMc0)).t.norm();
      s = baseline / multi.multiview.cMc0[r].getTranslationVector().frobeniusNorm();
    }
    const vpKinematicChain start = handEyeStart(c.nominal, fMe, multi.multiview, s);
    multi.stage_seconds.push_back({"hand-eye closed form", seconds(ts)});
    // Kinematic bundle adjustment in hand-eye-only mode (bundleOptions), points moved to f through
    // the first eMc; every view with its end-effector pose.
    bundle(c, start, toVisp(fMe[0]) * start.get_eMc_corrected(), s, views, c.bundle, "hand-eye bundle adjustment",
           multi);
  }
  if (better(predicted, multi)) {
    const vpMultiViewReconstruction::Result mv = multi.multiview;
    res = predicted;
    res.multiview = mv; // what the reconstruction found, for the report
    res.pairs = multi.pairs;
  } else if (multi.status == vpRobotSelfCalibration::OK || predicted.status != vpRobotSelfCalibration::OK) {
    res = multi;
    if (predicted.status != vpRobotSelfCalibration::OK && multi.status != vpRobotSelfCalibration::OK)
      res.message += "; from the controller poses: " + predicted.message;
  } else
    res = predicted;
}
} // namespace vpSelfCalibPipeline
