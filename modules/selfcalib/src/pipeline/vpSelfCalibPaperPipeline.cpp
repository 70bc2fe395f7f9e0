/*
 * ViSP SelfCalib: the paper's self-calibration procedure (Section 4.1, steps 2-4; step 5, the
 * verification, is shared by every method).
 */
#include "vpSelfCalibPipelines.h"

#include <algorithm>
#include <map>
#include <sstream>

#include "../core/vpSelfCalibMath.h"

using namespace vpSelfCalib;

namespace vpSelfCalibPipeline
{
namespace
{
// Correspondences of two views by scene id.
void correspondences(const View &a, const View &b, std::vector<vpImagePoint> &pa, std::vector<vpImagePoint> &pb)
{
  std::map<int, vpImagePoint> second;
  for (const auto &o : b.points)
    second[o.id] = o.ip;
  pa.clear();
  pb.clear();
  for (const auto &o : a.points) {
    auto it = second.find(o.id);
    if (it != second.end()) {
      pa.push_back(o.ip);
      pb.push_back(it->second);
    }
  }
}

bool findPoint(const View &v, int id, vpImagePoint &ip)
{
  for (const auto &o : v.points)
    if (o.id == id) {
      ip = o.ip;
      return true;
    }
  return false;
}

/*
  The focal length's sd from the reconstruction holds at the pixel sd it weighed the observations
  with. Like the identification's sds (from the pose measurements' residuals), it follows the
  residuals when sigma0 is outside its 99.9 % chi-square interval: the factor to apply (1 when the
  pixel sd agrees), with a finding naming both values unless the pixel sd was measured (`measured`)
  and the measurement agrees with it. Without it the paper's f sd was a
  multiple of the given sd (bench-trust --methods paper: f sd over its spread 0.40 / 1.19 / 2.96
  at 0.4x / 1x / 2.5x the true sd).
*/
double imageSigma0Scale(const vpMultiViewReconstruction::Result &mv, double pixel_sd, bool measured, Result &res)
{
  if (!(mv.sigma0 > 0) || (mv.sigma0 >= mv.sigma0_low && mv.sigma0 <= mv.sigma0_high))
    return 1.0;
  // Measured and used: a small disagreement is the robust measurement's own spread, not the user's
  // statement (as the bundle adjustment's noise-mismatch).
  if (measured && !measuredNoiseDiffers(pixel_sd, mv.measured.pixel_sd))
    return mv.sigma0;
  std::ostringstream os;
  os.precision(3);
  os << "the image residuals of the focal length's reconstruction (RMS " << mv.rms
     << " px) contradict the pixel sd (" << pixel_sd << " px): sigma0 " << mv.sigma0
     << " is outside its 99.9 % interval [" << mv.sigma0_low << ", " << mv.sigma0_high
     << "]; the focal length's sd is scaled by sigma0 (the image noise measured: " << mv.measured.pixel_sd
     << " px)";
  vpSelfCalibDataCheck::Finding f;
  f.code = "noise-mismatch";
  f.message = os.str();
  res.findings.push_back(f);
  return mv.sigma0;
}

/*
  Step 2: pose measurements c_iMc_1 (unit translation) on the pairs (1, i), i = 2..N, by the refined
  nonlinear factor method, the focal length shared by all pairs, per pair (the median kept) or known.
  Shared, with Options::paper_focal_all_views (beyond the paper): the focal length from every
  calibration view jointly (the multi-view reconstruction's bundle adjustment, started from the
  pairs' shared one), then the pairs measured again with it known; the pairs' own shared estimate
  is kept when the reconstruction fails (res.multiview says why).
  False (TWO_VIEW_FAILED) when the shared focal length does not converge.
*/
bool measurePoses(const Context &c, Result &res)
{
  const unsigned int N = c.num_calibration;
  vpTwoViewEstimator::Options to = c.twoview;
  std::vector<std::vector<vpImagePoint>> p1(N - 1), p2(N - 1);
  for (unsigned int i = 1; i < N; ++i)
    correspondences(c.calibration[0], c.calibration[i], p1[i - 1], p2[i - 1]);
  if (c.mode == vpRobotSelfCalibration::FOCAL_SHARED) {
    c.report("pose measurements (shared focal length)", 0, N - 1);
    const vpTwoViewEstimator::SharedResult sr = vpTwoViewEstimator::estimateShared(p1, p2, to);
    res.pairs = sr.pairs;
    if (!sr.converged) {
      res.status = vpRobotSelfCalibration::TWO_VIEW_FAILED;
      res.message = "shared focal length: " + sr.message;
      return false;
    }
    res.fx = sr.fx;
    res.fx_sd = sr.fx_sd;
    if (c.options.paper_focal_all_views) {
      // Two-view geometry fixes f weakly and every pair has its own points, so the pairs' shared f
      // is about 0.1 % off at 0.2 px on the paper scene and the yardstick scale inherits 2-2.5 times
      // that; points shared by all views fix f 3-6 times better (bench-paper).
      c.report("focal length from every view", 0, 1);
      vpMultiViewReconstruction::Options mo = c.multiview;
      mo.twoview.fx = sr.fx;
      res.multiview = vpMultiViewReconstruction::reconstruct(c.calibration, c.dataset.yardstick, mo, c.noise);
      // The image noise measured (the noise model's measure_pixel_sd): when the residuals
      // give another level, the reconstruction again at it (a pixel sd too small rejects good
      // observations as outliers, one too large lets wrong matches in).
      const auto attempt = [&](const vpSelfCalibNoiseModel &noise, bool) {
        c.report("focal length from every view, at the measured image noise", 0, 1);
        vpMultiViewReconstruction::Result again =
            vpMultiViewReconstruction::reconstruct(c.calibration, c.dataset.yardstick, mo, noise);
        if (again.status != vpMultiViewReconstruction::OK)
          return NoiseAttempt{false, vpMultiViewReconstruction::statusName(again.status), again.measured};
        res.multiview = std::move(again);
        return NoiseAttempt{true, std::string(), res.multiview.measured};
      };
      const bool ok = res.multiview.status == vpMultiViewReconstruction::OK;
      res.noise = measureNoise(c.noise, res.multiview.measured, ok, ok, false, attempt, res.findings);
      const bool measured = c.noise.measure_pixel_sd;
      const vpMultiViewReconstruction::Result &mv = res.multiview;
      if (mv.status == vpMultiViewReconstruction::OK && mv.fx > 0 && std::isfinite(mv.fx) && std::isfinite(mv.fx_sd)) {
        res.fx = mv.fx;
        res.fx_sd = mv.fx_sd * imageSigma0Scale(mv, res.noise.pixel_sd, measured, res);
        vpTwoViewEstimator::Options known = to;
        known.focal_mode = vpRefinedFactorMethod::KNOWN;
        known.fx = mv.fx;
        res.pairs.clear();
        for (unsigned int i = 1; i < N; ++i) {
          c.report("pose measurements", i - 1, N - 1);
          res.pairs.push_back(vpTwoViewEstimator::estimate(p1[i - 1], p2[i - 1], known));
        }
      }
    }
  } else {
    std::vector<double> focals;
    for (unsigned int i = 1; i < N; ++i) {
      c.report("pose measurements", i - 1, N - 1);
      res.pairs.push_back(vpTwoViewEstimator::estimate(p1[i - 1], p2[i - 1], to));
      if (res.pairs.back().status == vpTwoViewEstimator::OK)
        focals.push_back(res.pairs.back().fx);
    }
    if (c.mode == vpRobotSelfCalibration::FOCAL_KNOWN)
      res.fx = c.dataset.cam.get_px();
    else if (!focals.empty()) {
      std::nth_element(focals.begin(), focals.begin() + focals.size() / 2, focals.end());
      res.fx = focals[focals.size() / 2];
    }
  }
  if (res.fx > 0)
    res.camera.initPersProjWithoutDistortion(res.fx, res.fx * to.mu, to.u0, to.v0);
  return true;
}

/*
  Steps 3 and 4: the eq. 21 ratios from the nominal model, the global scale from the yardstick seen
  in the pairs with a pose, then the scaled pose measurements (|T_i| = ratio_i |k_1|). False
  (SCALE_FAILED, TWO_VIEW_FAILED) when the scale cannot be fixed or no pair gave a pose.
*/
bool scalePoses(const Context &c, Result &res)
{
  const unsigned int N = c.num_calibration;
  const std::vector<View> &cal = c.calibration;
  const vpSelfCalibDataset::Yardstick &ys = c.dataset.yardstick;
  std::vector<vpColVector> qcal;
  for (unsigned int i = 0; i < N; ++i)
    qcal.push_back(cal[i].q);
  res.ratios = vpPoseScale::nominalRatios(c.nominal, qcal);
  // Expected accuracy of each view of the yardstick (weights): the error of the pair's own nominal
  // norm under the nominal model's default tolerance (the |t_1| error common to every ratio cancels
  // in ratio_i k_1, see vpPoseScale::nominalNormSd), and the pair's two-view covariance.
  const std::vector<double> ratio_sd =
      vpPoseScale::nominalNormSd(c.nominal, qcal, vpPoseScale::ModelTolerance());

  std::vector<vpPoseScale::YardstickView> yv;
  vpImagePoint a1, b1;
  const bool in_first = findPoint(cal[0], ys.id_a, a1) && findPoint(cal[0], ys.id_b, b1);
  for (unsigned int i = 1; i < N && in_first; ++i) {
    const vpTwoViewEstimator::Result &r = res.pairs[i - 1];
    vpPoseScale::YardstickView v;
    if (r.status != vpTwoViewEstimator::OK || !findPoint(cal[i], ys.id_a, v.a2) || !findPoint(cal[i], ys.id_b, v.b2))
      continue;
    v.c2Mc1 = r.c2Mc1;
    v.ratio = res.ratios[i - 1];
    v.ratio_sd = ratio_sd[i - 1];
    v.a1 = a1;
    v.b1 = b1;
    std::vector<vpImagePoint> pa, pb;
    correspondences(cal[0], cal[i], pa, pb);
    for (size_t k = 0; k < pa.size(); ++k)
      if (r.inliers.size() != pa.size() || r.inliers[k]) {
        v.p1.push_back(pa[k]);
        v.p2.push_back(pb[k]);
      }
    yv.push_back(v);
  }
  if (res.fx > 0) {
    vpPoseScale::YardstickOptions yo;
    // The image noise of the focal length's reconstruction (measured when measure_pixel_sd asks it).
    const vpSelfCalibNoiseModel &noise = res.noise.pixel_sd > 0 ? res.noise : c.noise;
    if (c.mode == vpRobotSelfCalibration::FOCAL_SHARED && std::isfinite(res.fx_sd))
      yo.fx_sd = res.fx_sd;
    res.scale = vpPoseScale::yardstick(yv, ys.length, res.fx, c.twoview.u0, c.twoview.v0, c.twoview.mu, yo, noise);
  }
  if (res.scale.status != vpPoseScale::OK) {
    res.status = vpRobotSelfCalibration::SCALE_FAILED;
    res.message = yv.empty() ? "the yardstick is not seen in both images of any pair with a pose measurement "
                               "(it must be seen in the first view and at least one other)"
                             : "yardstick: " + res.scale.message;
    return false;
  }

  for (unsigned int i = 1; i < N; ++i) {
    const vpTwoViewEstimator::Result &r = res.pairs[i - 1];
    if (r.status != vpTwoViewEstimator::OK)
      continue;
    Rigid M = rigidFromVisp(r.c2Mc1);
    const double norm = res.ratios[i - 1] * res.scale.scale;
    M.t = M.t.normalized() * norm;
    res.measurements.push_back(poseMeasurement(cal[i].q, cal[0].q, toVisp(M), norm, c.options));
  }
  if (res.measurements.empty()) {
    res.status = vpRobotSelfCalibration::TWO_VIEW_FAILED;
    res.message = "no pair gave a pose measurement";
    return false;
  }
  return true;
}
} // namespace

void runPaper(const Context &c, Result &res)
{
  auto ts = std::chrono::steady_clock::now();
  if (!measurePoses(c, res))
    return;
  res.stage_seconds.push_back({"two-view poses", seconds(ts)});
  ts = std::chrono::steady_clock::now();

  if (!scalePoses(c, res))
    return;
  res.stage_seconds.push_back({"scale", seconds(ts)});
  ts = std::chrono::steady_clock::now();

  // Identification from the nominal model (the paper's step 3, on metric measurements: see the class).
  c.report("identification", 0, 1);
  // The estimated set from every calibration configuration at the nominal model (one rule for every
  // method): a pair lost to noise cannot change it; if the remaining pairs do not determine it, the
  // identification says so (RANK_DEFICIENT).
  res.identification =
      vpKinematicIdentification::identify(c.nominal, res.measurements, c.options.identification, estimatedSet(c));
  res.calibrated = res.identification.chain;
  res.stage_seconds.push_back({"identification", seconds(ts)});
  if (res.identification.status != vpKinematicIdentification::OK) {
    res.status = vpRobotSelfCalibration::IDENTIFICATION_FAILED;
    res.message = res.identification.message;
    return;
  }
  res.identifiability = res.identification.identifiability;
  res.parameter_sd = res.identification.sd;
  vpMatrix covariance = res.identification.covariance;
  // The stated pose errors (pose_sd_*) against the residuals: the sds follow the residuals when
  // sigma0 is outside its 99.9 % chi-square interval, either way.
  const double dof = 6.0 * static_cast<double>(res.measurements.size()) -
                     static_cast<double>(res.identifiability.identified.size());
  double low = 0, high = 0;
  const double s0 = res.identification.sigma0;
  if (dof > 0) {
    vpSelfCalib::sigma0Interval(dof, low, high);
    if (s0 < low || s0 > high) {
      covariance = covariance * (s0 * s0);
      res.identification.covariance = covariance; // what the result's sds say, everywhere
      res.parameter_sd = res.parameter_sd * s0;
      std::ostringstream os;
      os.precision(3);
      os << "the pose measurements' residuals contradict their stated errors (twoview_rotation_sd, twoview_direction_sd): "
         << "sigma0 " << s0 << " is outside its 99.9 % interval [" << low << ", " << high
         << "]; the standard deviations are scaled by sigma0";
      vpSelfCalibDataCheck::Finding f;
      f.code = "noise-mismatch";
      f.message = os.str();
      res.findings.push_back(f);
    }
  }
  {
    // The calibrated eMc with its sd, as the other methods give it.
    const std::vector<std::string> all = res.calibrated.getParameterNames();
    std::vector<std::string> rows;
    for (unsigned int k : res.identification.identifiability.identified)
      rows.push_back(all[k]);
    handEyeWithSd(res, covariance, rows);
  }
  res.status = vpRobotSelfCalibration::OK;
  std::ostringstream os;
  os << "ok: " << res.measurements.size() << " pose measurements, " << res.identification.identifiability.identified.size()
     << " parameters identified";
  res.message = os.str();
}
} // namespace vpSelfCalibPipeline
