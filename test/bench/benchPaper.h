/*
 * The paper's simulation study (Section 4.2) on one scenario draw, shared by bench-paper and
 * bench-planner: Table 2 (errors of the scaled pose measurements) and Figure 6 (3-D errors after
 * calibration against the number of calibration poses).
 */
#ifndef VP_SELFCALIB_BENCH_PAPER_H
#define VP_SELFCALIB_BENCH_PAPER_H

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <visp3/core/vpThetaUVector.h>
#include <visp3/selfcalib/vpCalibrationVerifier.h>
#include <visp3/selfcalib/vpPoseScale.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

namespace bench
{
//! The names of focal modes (vpRobotSelfCalibration::focalModeName), for a command line's choices.
inline std::vector<std::string> focalModeNames(std::initializer_list<vpRobotSelfCalibration::FocalMode> modes)
{
  std::vector<std::string> names;
  for (vpRobotSelfCalibration::FocalMode m : modes)
    names.push_back(vpRobotSelfCalibration::focalModeName(m));
  return names;
}

//! The dataset the pipeline gets: a self-calibrated f starts from a 7% low guess (a lens data sheet).
inline vpSelfCalibDataset pipelineDataset(const vpSelfCalibSimulator &sim, const std::vector<vpColVector> &q,
                                          vpRobotSelfCalibration::FocalMode mode)
{
  vpSelfCalibDataset ds = sim.makeDataset(q);
  ds.focal_known = mode == vpRobotSelfCalibration::FOCAL_KNOWN;
  if (!ds.focal_known) {
    const vpCameraParameters c = sim.getCamera();
    ds.cam.initPersProjWithoutDistortion(0.93 * c.get_px(), 0.93 * c.get_py(), c.get_u0(), c.get_v0());
  }
  return ds;
}

//! Table 2 of the paper: errors of the scaled pose measurements c_iMc_1 of the pairs (1, i).
struct PoseMeasurementErrors {
  vpRobotSelfCalibration::Status status = vpRobotSelfCalibration::TWO_VIEW_FAILED;
  std::vector<double> position;    //!< m, one per pair with a measurement
  std::vector<double> orientation; //!< rad
  std::vector<double> scale_ratio; //!< |(|t_i|/|t_1|) / (|t̄_i|/|t̄_1|) - 1| of eq. 21 (true vs nominal)
  std::vector<double> fx;          //!< |f - f_true| px: one per pair (per-pair mode) or one per run
  // The position error of pair i split into its parts (m): |T_i| times the angle of the translation
  // direction; |T_i| times the error of the norm the same pipeline gives on noise-free images of the
  // same poses, ratio_i k_1^0 (the eq. 21 model bias, the yardstick scale included: the nominal
  // |t_1| error common to every ratio cancels in ratio_i k_1); |T_i| times the relative error of the
  // yardstick scale against that noise-free scale, k_1 / k_1^0 - 1 (the image noise's part, f
  // included); and the Cramér-Rao bound of the direction part (f known).
  std::vector<double> direction_part, ratio_part, scale_part, crb_direction;
  double scale_error = NAN;        //!< k_1 / k_1^0 - 1 (signed; 0 without noise)
  double scale_sd = NAN;           //!< the reported relative sd of k_1
  unsigned int pairs = 0;
  double seconds = 0;
};

/*!
  The pose measurements of the pipeline on all the configurations (pairs (1, i), i = 2..m) against
  the true c_iMc_1 of the simulated arm.
*/
inline PoseMeasurementErrors poseMeasurementErrors(const vpSelfCalibSimulator &sim, const std::vector<vpColVector> &q,
                                                   vpRobotSelfCalibration::FocalMode mode)
{
  vpRobotSelfCalibration::Options po;
  po.method = vpRobotSelfCalibration::PAPER;
  po.num_calibration_poses = static_cast<unsigned int>(q.size());
  po.focal_mode = mode;
  const vpRobotSelfCalibration::Result r = vpRobotSelfCalibration::run(sim.getNominalChain(), pipelineDataset(sim, q, mode), po);
  PoseMeasurementErrors e;
  e.status = r.status;
  e.pairs = static_cast<unsigned int>(r.pairs.size());
  e.seconds = r.seconds;
  const vpKinematicChain &truth = sim.getTrueChain();
  const double f_true = sim.getCamera().get_px();
  const vpHomogeneousMatrix T1 = truth.get_fMc(q[0]);
  const double t1_true = (truth.get_fMc(q[1]).inverse() * T1).getTranslationVector().frobeniusNorm();
  for (size_t i = 1; i < q.size(); ++i) {
    const double ti = (truth.get_fMc(q[i]).inverse() * T1).getTranslationVector().frobeniusNorm();
    if (i - 1 < r.ratios.size())
      e.scale_ratio.push_back(std::fabs((ti / t1_true) / r.ratios[i - 1] - 1));
  }
  const double noise = sim.getOptions().pixel_noise_sd;
  // The same pipeline on noise-free images of the same poses (same robot, scene and camera).
  double k0 = r.scale.scale;
  if (noise > 0) {
    vpSelfCalibSimulator::Options o0 = sim.getOptions();
    o0.pixel_noise_sd = 0;
    const vpSelfCalibSimulator sim0(sim.getNominalChain(), o0);
    const vpRobotSelfCalibration::Result r0 =
        vpRobotSelfCalibration::run(sim0.getNominalChain(), pipelineDataset(sim0, q, mode), po);
    k0 = r0.scale.status == vpPoseScale::OK ? r0.scale.scale : NAN;
  }
  if (r.scale.status == vpPoseScale::OK && r.scale.scale > 0 && k0 > 0) {
    e.scale_error = r.scale.scale / k0 - 1;
    e.scale_sd = r.scale.sd / r.scale.scale;
  }
  const vpCameraParameters cam = sim.getCamera();
  for (const vpKinematicIdentification::Measurement &m : r.measurements) {
    const vpHomogeneousMatrix T = truth.get_fMc(m.q).inverse() * truth.get_fMc(m.q_ref);
    e.position.push_back((m.M.getTranslationVector() - T.getTranslationVector()).frobeniusNorm());
    const vpThetaUVector tu((m.M.getRotationMatrix().t() * T.getRotationMatrix()));
    e.orientation.push_back(std::sqrt(tu.sumSquare()));
    // The split: which pair is it?
    size_t i = 1;
    while (i < q.size() && !(q[i] == m.q))
      ++i;
    if (i >= q.size() || i - 1 >= r.ratios.size())
      continue;
    const vpTranslationVector tm = m.M.getTranslationVector(), tt = T.getTranslationVector();
    const double nT = tt.frobeniusNorm();
    const double c = std::max(-1.0, std::min(1.0, vpColVector::dotProd(vpColVector(tm), vpColVector(tt)) /
                                                       (tm.frobeniusNorm() * nT)));
    e.direction_part.push_back(nT * std::acos(c));
    e.ratio_part.push_back(nT * std::fabs(r.ratios[i - 1] * k0 / nT - 1));
    e.scale_part.push_back(nT * std::fabs(e.scale_error));
    // Cramér-Rao bound of the direction (f known) at the truth, noise-free correspondences.
    if (noise > 0) {
      const auto o0 = sim.observe(q[0], 0, 0), oi = sim.observe(q[i], static_cast<unsigned int>(i), 0);
      std::map<int, vpImagePoint> second;
      for (const auto &o : oi)
        second[o.id] = o.ip;
      std::vector<vpImagePoint> p1, p2;
      for (const auto &o : o0)
        if (second.count(o.id)) {
          p1.push_back(o.ip);
          p2.push_back(second[o.id]);
        }
      vpHomogeneousMatrix Tu = T;
      for (unsigned int k = 0; k < 3; ++k)
        Tu[k][3] /= nT;
      const vpMatrix C = vpPoseScale::twoViewCovariance(Tu, p1, p2, cam.get_px(), cam.get_u0(), cam.get_v0(),
                                                        cam.get_py() / cam.get_px(), noise);
      if (C.getRows() == 5)
        e.crb_direction.push_back(nT * std::sqrt(C[3][3] + C[4][4]));
    }
  }
  if (mode == vpRobotSelfCalibration::FOCAL_PER_PAIR) {
    for (const auto &p : r.pairs)
      if (p.status == vpTwoViewEstimator::OK)
        e.fx.push_back(std::fabs(p.fx - f_true));
  } else if (mode == vpRobotSelfCalibration::FOCAL_SHARED && r.fx > 0)
    e.fx.push_back(std::fabs(r.fx - f_true));
  return e;
}

//! Figure 6 and the held-out pose errors: calibration on n poses, verification on fixed poses.
struct CalibrationErrors {
  vpRobotSelfCalibration::Status status = vpRobotSelfCalibration::TWO_VIEW_FAILED;
  vpCalibrationVerifier::Result after; //!< with truth: yardstick, point-pair distances, held-out poses
  double seconds = 0;
};

//! The verification figures of a model on the views (the nominal model: "before calibration").
inline vpCalibrationVerifier::Result verifyAgainstTruth(const vpSelfCalibSimulator &sim, const vpKinematicChain &model,
                                                        const vpCameraParameters &cam,
                                                        const std::vector<vpSelfCalibDataset::View> &views)
{
  return vpCalibrationVerifier::verify(model, cam, views, sim.getYardstick(), sim.getScenePointsById(),
                                       sim.getTrueCameraPoses(views));
}

/*!
  The pipeline calibrated on calibration configurations, verified on the verification ones (the
  camera used is the pipeline's, with its self-calibrated f).
*/
inline CalibrationErrors calibrationErrors(const vpSelfCalibSimulator &sim, const std::vector<vpColVector> &calibration,
                                           const std::vector<vpColVector> &verification,
                                           vpRobotSelfCalibration::FocalMode mode,
                                           vpRobotSelfCalibration::Method method = vpRobotSelfCalibration::PAPER)
{
  std::vector<vpColVector> q = calibration;
  q.insert(q.end(), verification.begin(), verification.end());
  const vpSelfCalibDataset ds = pipelineDataset(sim, q, mode);
  vpRobotSelfCalibration::Options po;
  po.method = method;
  po.num_calibration_poses = static_cast<unsigned int>(calibration.size());
  po.focal_mode = mode;
  const vpRobotSelfCalibration::Result r = vpRobotSelfCalibration::run(sim.getNominalChain(), ds, po);
  CalibrationErrors e;
  e.status = r.status;
  e.seconds = r.seconds;
  if (r.status == vpRobotSelfCalibration::OK) {
    const std::vector<vpSelfCalibDataset::View> ver(ds.views.begin() + calibration.size(), ds.views.end());
    e.after = verifyAgainstTruth(sim, r.calibrated, r.camera, ver);
  }
  return e;
}
} // namespace bench

#endif
