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

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <Eigen/Geometry>

#include <visp3/core/vpThetaUVector.h>
#include <visp3/selfcalib/vpCalibrationVerifier.h>
#include <visp3/selfcalib/vpPoseScale.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include "selfcalibCli.h"

namespace bench
{
//! The names of focal modes (vpRobotSelfCalibration::focalModeName), for a command line's choices.
//! PAPER with FOCAL_SHARED: the focal length from every view jointly (true, the library's default)
//! or the pairs' own shared estimate (bench-paper --shared-focal pairs).
inline bool &paperFocalAllViews()
{
  static bool all_views = vpRobotSelfCalibration::Options().paper_focal_all_views;
  return all_views;
}

//! The option --shared-focal all-views|pairs; apply with paperFocalAllViews() = value == "all-views".
inline void addSharedFocal(CLI::App &app, std::string &value)
{
  app.add_option("--shared-focal", value,
                 "the paper's method, focal shared: all-views (default: from every view jointly,\n"
                 "then known to the pairs) or pairs (the pairs' own joint estimate)")
      ->type_name("HOW")
      ->check(CLI::IsMember({"all-views", "pairs"}));
}

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
  std::string message; //!< the run's status message (why it is not ok)
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
  po.paper_focal_all_views = paperFocalAllViews();
  const vpRobotSelfCalibration::Result r = vpRobotSelfCalibration::run(sim.getNominalChain(), pipelineDataset(sim, q, mode), po);
  PoseMeasurementErrors e;
  e.status = r.status;
  e.message = r.message;
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

/*!
  Cramér-Rao bounds of the relative yardstick scale k_1 (the metric |T_1|) at the truth, with the
  eq. 21 ratios taken as exact (the bench measures the scale's noise part against the noise-free
  pipeline's scale, which has the same ratios), pixel noise sigma on u and v of every observation.
  Pose j = c_jMc_0 is (R_j, k_1 r_j d_j), d_j a unit direction, perturbed as in
  vpPoseScale::twoViewCovariance (R <- exp([w]x) R, d <- normalize(d + a e1 + b e2)); the yardstick
  is its midpoint and direction (length known, so it fixes k_1).
  - pairs: the yardstick ends seen in all the views jointly, with the 24 two-view poses as
    independent measurements of (R_j, d_j) with their first-order covariance
    (vpPoseScale::twoViewCovariance of the pair (0, j), f known): the bound of any estimator that
    triangulates the yardstick from the two-view poses (the pipeline's, which uses the ends of view 0
    with each view j in turn, is one of them);
  - joint: every observation of every view (scene points and yardstick ends), poses, scene points and
    k_1 (and f when not known) estimated together: the bound of any unbiased estimator on these
    images, a bundle adjustment's.
*/
struct ScaleBounds {
  double pairs = NAN;       //!< relative sd, two-view poses + yardstick in every view (f known)
  double joint = NAN;       //!< relative sd, every observation (f known)
  double joint_shared = NAN; //!< relative sd, every observation, f estimated with the rest
};

inline ScaleBounds yardstickScaleBounds(const vpSelfCalibSimulator &sim, const std::vector<vpColVector> &q,
                                        double sigma)
{
  ScaleBounds out;
  const size_t m = q.size();
  if (m < 2 || !(sigma > 0))
    return out;
  const vpCameraParameters cam = sim.getCamera();
  const double f0 = cam.get_px(), mu = cam.get_py() / cam.get_px(), u0 = cam.get_u0(), v0 = cam.get_v0();
  const vpKinematicChain &truth = sim.getTrueChain();
  const vpHomogeneousMatrix T0 = truth.get_fMc(q[0]);
  std::vector<Eigen::Matrix3d> R(m, Eigen::Matrix3d::Identity());
  std::vector<Eigen::Vector3d> d(m, Eigen::Vector3d::Zero());
  std::vector<double> rn(m, 0.0);
  double k = 0;
  for (size_t j = 1; j < m; ++j) {
    const vpHomogeneousMatrix M = truth.get_fMc(q[j]).inverse() * T0;
    for (unsigned int r = 0; r < 3; ++r) {
      for (unsigned int c = 0; c < 3; ++c)
        R[j](r, c) = M[r][c];
      d[j](r) = M[r][3];
    }
    rn[j] = d[j].norm();
    d[j].normalize();
    if (j == 1)
      k = rn[1];
  }
  for (size_t j = 1; j < m; ++j)
    rn[j] /= k;
  // Scene points in c0, the yardstick's ends among them.
  const vpHomogeneousMatrix T0inv = T0.inverse();
  std::map<int, Eigen::Vector3d> X;
  for (const auto &p : sim.getScenePointsById()) {
    const vpColVector &P = p.second;
    vpColVector h(4, 1.0);
    for (unsigned int r = 0; r < 3; ++r)
      h[r] = P[r];
    const vpColVector c = T0inv * h;
    X[p.first] = Eigen::Vector3d(c[0], c[1], c[2]);
  }
  const vpSelfCalibDataset::Yardstick ys = sim.getYardstick();
  if (!X.count(ys.id_a) || !X.count(ys.id_b))
    return out;
  const double L = ys.length;
  const Eigen::Vector3d Ym = 0.5 * (X[ys.id_a] + X[ys.id_b]), Yu = (X[ys.id_a] - X[ys.id_b]).normalized();
  // Visible ids per view (noise-free observations of the simulator's rule).
  std::vector<std::map<int, vpImagePoint>> seen(m);
  for (size_t j = 0; j < m; ++j)
    for (const auto &o : sim.observe(q[j], static_cast<unsigned int>(j), 0))
      seen[j][o.id] = o.ip;
  auto unitPerturb = [](const Eigen::Vector3d &v, double a, double b) {
    const Eigen::Vector3d e1 = v.unitOrthogonal(), e2 = v.cross(e1);
    return Eigen::Vector3d((v + a * e1 + b * e2).normalized());
  };
  // Pixel of the point x (c0) in view j with the local perturbations p = (w 3, a, b, dk, df).
  auto pixel = [&](size_t j, const double *p, const Eigen::Vector3d &x) {
    Eigen::Vector3d xc = x;
    if (j > 0) {
      const Eigen::Vector3d w(p[0], p[1], p[2]);
      const Eigen::Matrix3d Rj =
          (w.norm() > 0 ? Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix() : Eigen::Matrix3d::Identity()) *
          R[j];
      xc = Rj * x + (k + p[5]) * rn[j] * unitPerturb(d[j], p[3], p[4]);
    }
    const double f = f0 + p[6];
    return Eigen::Vector2d(f * xc.x() / xc.z() + u0, f * mu * xc.y() / xc.z() + v0);
  };
  // Parameter layout: [pose j: 5 x (m-1)][k][f][yardstick 5][points 3 each].
  const Eigen::Index iK = static_cast<Eigen::Index>(5 * (m - 1)), iF = iK + 1, iY = iF + 1, iP = iY + 5;
  std::map<int, Eigen::Index> point_index;
  Eigen::Index n_par = iP;
  for (const auto &x : X)
    if (x.first != ys.id_a && x.first != ys.id_b)
      point_index[x.first] = n_par, n_par += 3;
  // Accumulates the information of one observation: (u, v) of id in view j; joint: scene points too.
  auto add = [&](Eigen::MatrixXd &info, size_t j, int id) {
    const bool end = id == ys.id_a || id == ys.id_b;
    const double sgn = id == ys.id_a ? 0.5 : -0.5;
    // Local parameters: pose 5, k, f, then 5 (yardstick) or 3 (point).
    const int nl = 7 + (end ? 5 : 3);
    std::vector<Eigen::Index> glob;
    for (int c = 0; c < 5; ++c)
      glob.push_back(j > 0 ? static_cast<Eigen::Index>(5 * (j - 1) + c) : -1);
    glob.push_back(j > 0 ? iK : -1);
    glob.push_back(iF);
    for (int c = 0; c < nl - 7; ++c)
      glob.push_back(end ? iY + c : point_index.at(id) + c);
    auto eval = [&](const std::vector<double> &l) {
      Eigen::Vector3d x;
      if (end)
        x = Ym + Eigen::Vector3d(l[7], l[8], l[9]) + sgn * L * unitPerturb(Yu, l[10], l[11]);
      else
        x = X.at(id) + Eigen::Vector3d(l[7], l[8], l[9]);
      return pixel(j, l.data(), x);
    };
    Eigen::MatrixXd Jl(2, nl);
    for (int c = 0; c < nl; ++c) {
      const double h = c == 6 ? 1e-3 : 1e-7;
      std::vector<double> lp(static_cast<size_t>(nl), 0.0), lm(static_cast<size_t>(nl), 0.0);
      lp[static_cast<size_t>(c)] = h;
      lm[static_cast<size_t>(c)] = -h;
      Jl.col(c) = (eval(lp) - eval(lm)) / (2 * h);
    }
    const Eigen::MatrixXd A = Jl.transpose() * Jl / (sigma * sigma);
    for (int a = 0; a < nl; ++a)
      for (int b = 0; b < nl; ++b)
        if (glob[static_cast<size_t>(a)] >= 0 && glob[static_cast<size_t>(b)] >= 0)
          info(glob[static_cast<size_t>(a)], glob[static_cast<size_t>(b)]) += A(a, b);
  };
  // The relative sd of k from an information matrix, f fixed (its row and column dropped) or not.
  auto kSd = [&](Eigen::MatrixXd info, bool f_known) {
    if (f_known) {
      info.row(iF).setZero();
      info.col(iF).setZero();
      info(iF, iF) = 1;
    }
    // Unobserved parameters (a point seen in no view) are fixed.
    for (Eigen::Index r = 0; r < info.rows(); ++r)
      if (info(r, r) == 0)
        info(r, r) = 1;
    Eigen::LDLT<Eigen::MatrixXd> ldlt(info);
    Eigen::VectorXd e = Eigen::VectorXd::Zero(info.rows());
    e(iK) = 1;
    const double v = ldlt.solve(e)(iK);
    return v > 0 && std::isfinite(v) ? std::sqrt(v) / k : NAN;
  };
  // Joint: every observation.
  {
    Eigen::MatrixXd info = Eigen::MatrixXd::Zero(n_par, n_par);
    for (size_t j = 0; j < m; ++j)
      for (const auto &o : seen[j])
        if (X.count(o.first))
          add(info, j, o.first);
    out.joint = kSd(info, true);
    out.joint_shared = kSd(info, false);
  }
  // Pairs: the ends in every view, the two-view poses as measurements.
  {
    Eigen::MatrixXd info = Eigen::MatrixXd::Zero(iP, iP);
    bool ok = true;
    for (size_t j = 0; j < m && ok; ++j) {
      for (int id : {ys.id_a, ys.id_b})
        if (seen[j].count(id))
          add(info, j, id);
      if (j == 0)
        continue;
      std::vector<vpImagePoint> p1, p2;
      for (const auto &o : seen[0])
        if (seen[j].count(o.first)) {
          p1.push_back(o.second);
          p2.push_back(seen[j].at(o.first));
        }
      vpHomogeneousMatrix Mu;
      for (unsigned int r = 0; r < 3; ++r) {
        for (unsigned int c = 0; c < 3; ++c)
          Mu[r][c] = R[j](r, c);
        Mu[r][3] = d[j](r);
      }
      const vpMatrix C = vpPoseScale::twoViewCovariance(Mu, p1, p2, f0, u0, v0, mu, sigma);
      if (C.getRows() != 5) {
        ok = false;
        break;
      }
      Eigen::Matrix<double, 5, 5> Ce;
      for (unsigned int r = 0; r < 5; ++r)
        for (unsigned int c = 0; c < 5; ++c)
          Ce(r, c) = C[r][c];
      info.block(static_cast<Eigen::Index>(5 * (j - 1)), static_cast<Eigen::Index>(5 * (j - 1)), 5, 5) += Ce.inverse();
    }
    if (ok)
      out.pairs = kSd(info, true);
  }
  return out;
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
  po.paper_focal_all_views = paperFocalAllViews();
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
