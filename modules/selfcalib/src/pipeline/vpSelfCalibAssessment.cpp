/*
 * ViSP SelfCalib: the checks of a run's own word (vpRobotSelfCalibration::DOUBTFUL): a model is
 * called ok only when it is plausible against the nominal model's tolerance, explains its
 * calibration views and the held-out views better than the nominal model, reproduces the
 * yardstick, and its residuals measure a plausible image noise.
 */
#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include <visp3/selfcalib/vpKinematicBundleAdjustment.h>

#include "../core/vpSelfCalibChiSquare.h"
#include "../core/vpSelfCalibFormat.h"
#include "../core/vpSelfCalibGeometry.h"
#include "../core/vpSelfCalibMath.h"
#include "../core/vpSelfCalibRange.h"
#include "../core/vpSelfCalibRobotErrorLevels.h"

#include "vpSelfCalibMultiViewFit.h"
#include "vpSelfCalibPipelines.h"
#include "vpSelfCalibRobotErrorStructure.h"

namespace vpSelfCalibPipeline
{
namespace
{
using Finding = vpSelfCalibDataCheck::Finding;

void add(Result &res, vpSelfCalibDataCheck::Severity severity, const std::string &code, const std::string &message)
{
  Finding f;
  f.severity = severity;
  f.code = code;
  f.message = message;
  res.findings.push_back(f);
}

using vpSelfCalib::fixed;

/*
  The held-out yardstick: a calibrated model measuring it more than 3 % off (and worse than twice the
  nominal model) has a wrong scale or geometry. Good calibrations of the reference scenario measure
  it 0.01-1.3 % off at 0.2-0.5 px (two to ten held-out views; the figure is one distance between two
  triangulated points, noisy), the paper's method on doubtful runs 5-10 %.
*/
constexpr double kYardstickTolerance = 0.03;

bool isTranslation(const std::string &name) { return name.size() > 3 && name[name.size() - 2] == 't'; }

//! The nominal model's tolerance of a parameter (m or rad): a joint placement's or the base's, or eMc's.
double toleranceOf(const vpRobotSelfCalibration::Options &o, const std::string &name)
{
  const bool t = isTranslation(name);
  return name.rfind("eMc.", 0) == 0 ? (t ? o.tolerance_hand_eye_translation : o.tolerance_hand_eye_rotation)
                                    : (t ? o.tolerance_translation : o.tolerance_rotation);
}

//! The relative pose c_a M c_b's Jacobian (6 x |index|: position, then rotation) over the chain parameters `index`.
Eigen::MatrixXd motionJacobian(const vpKinematicChain &chain, const vpColVector &qa, const vpColVector &qb,
                               const std::vector<unsigned int> &index)
{
  const int n = static_cast<int>(index.size());
  const vpSelfCalib::Rigid A = vpSelfCalib::rigidFromVisp(chain.get_fMc(qa));
  const vpSelfCalib::Rigid B = vpSelfCalib::rigidFromVisp(chain.get_fMc(qb));
  const vpMatrix JA = chain.getJacobian(qa), JB = chain.getJacobian(qb);
  Eigen::MatrixXd JAs(6, n), JBs(6, n), Jt, Jr, J(6, n);
  for (int j = 0; j < n; ++j)
    for (unsigned int r = 0; r < 6; ++r) {
      JAs(r, j) = JA[r][index[j]];
      JBs(r, j) = JB[r][index[j]];
    }
  vpSelfCalib::relativePoseJacobian(A, JAs, B, JBs, Jt, Jr);
  J.topRows(3) = Jt;
  J.bottomRows(3) = Jr;
  return J;
}

/*
  How the parameters `estimated` move to absorb a unit error of each of `held` on the views' motions
  (c_0 M c_k, least squares): -J_E^+ J_H (|estimated| x |held|).
*/
Eigen::MatrixXd motionAbsorption(const vpKinematicChain &chain, const std::vector<View> &views,
                                 const std::vector<unsigned int> &estimated, const std::vector<unsigned int> &held)
{
  const int K = static_cast<int>(views.size());
  Eigen::MatrixXd JE(6 * (K - 1), static_cast<Eigen::Index>(estimated.size())),
      JH(6 * (K - 1), static_cast<Eigen::Index>(held.size()));
  for (int k = 1; k < K; ++k) {
    JE.middleRows(6 * (k - 1), 6) = motionJacobian(chain, views[0].q, views[k].q, estimated);
    JH.middleRows(6 * (k - 1), 6) = motionJacobian(chain, views[0].q, views[k].q, held);
  }
  return -JE.colPivHouseholderQr().solve(JH);
}

/*
  How the estimated parameters absorb the others through the relative poses of the calibration
  views (c_0 M c_k, the run's model): per parameter not estimated (columns in unidentifiable's
  order), the least-squares combination of the estimated ones' columns that reproduces its column,
  with the sign of an absorption. Exact for a parameter the model's rule folds into the estimated
  ones (CAUSE_MODEL: its column is in their span, e.g. j6.tz in eMc.tz); the others' absorption is
  the set's bias of the image information (Identifiability::bias).
*/
Eigen::MatrixXd poseAbsorption(const Context &c, const Result &res)
{
  const vpKinematicIdentification::Identifiability &set = res.identifiability;
  const int E = static_cast<int>(set.identified.size()), L = static_cast<int>(set.unidentifiable.size());
  const int K = static_cast<int>(c.calibration.size());
  if (E == 0 || L == 0 || K < 2 || c.calibration.front().q.size() == 0)
    return Eigen::MatrixXd::Zero(E, L);
  std::vector<unsigned int> left(static_cast<size_t>(L));
  for (int j = 0; j < L; ++j)
    left[static_cast<size_t>(j)] = set.unidentifiable[j].index;
  return motionAbsorption(res.calibrated, c.calibration, set.identified, left);
}

/*
  What the parameters not estimated can move the estimated one at row k: each one's error up to its
  tolerance, absorbed by the estimated ones, sum_l (a_kl tol_l)^2 (the tolerances as independent
  bounds of the same confidence), a_kl the set's bias (Identifiability::bias) for those the data
  left at nominal, the pose absorption (poseAbsorption) for those the model's rule folds into the
  estimated ones; a parameter fixed by the user is at the value the user states. The correction of
  an estimated parameter is its own error plus that part.
*/
double setBiasVariance(const vpRobotSelfCalibration::Options &o, const vpKinematicIdentification::Identifiability &set,
                       const Eigen::MatrixXd &absorption, unsigned int k)
{
  double v = 0;
  for (unsigned int l = 0; l < set.unidentifiable.size(); ++l) {
    const bool data = set.unidentifiable[l].cause == vpKinematicIdentification::CAUSE_DATA;
    if (set.unidentifiable[l].cause == vpKinematicIdentification::CAUSE_FIXED)
      continue;
    double a = 0;
    if (data && k < set.bias.getRows() && l < set.bias.getCols())
      a = set.bias[k][l];
    else if (!data && k < absorption.rows() && l < absorption.cols())
      a = absorption(k, l);
    const double b = std::isfinite(a) ? a * toleranceOf(o, set.unidentifiable[l].name) : 0.0;
    v += b * b;
  }
  return v;
}

/*
  poorly-determined: an estimated parameter whose sd after the solve exceeds this many times its
  tolerance. The estimated set keeps a parameter whose predicted sd is within the tolerance (at the
  start values, the stated noise); the sd after the solve moves from that prediction with the
  residuals (sigma0) and the solution, so a doubt at the decision's own threshold would doubt the
  parameters kept just under it (bench-estset, Panda, 12 views, 0.5 px: j2.tz and j4.tz
  kept within 3 mm, 3.2 and 3.1 mm after the solve). Beyond twice the tolerance, estimating it is
  clearly worse than the nominal value (a mean square error four times the tolerance's): the data
  are worse than the decision assumed (the noise-mismatch warning says by how much). Deciding at
  half the tolerance instead leaves more parameters at nominal, and their bias cost more than the
  doubt (bench-estset, Panda, 12 views: the mean gain 7.4 -> 6.6 at 0.2 px, a run worse than
  nominal at 0.5 px).
*/
constexpr double kPoorlyDetermined = 2.0;

// Corrections and sds against the nominal model's stated tolerance.
void checkTolerance(const Context &c, Result &res)
{
  const vpRobotSelfCalibration::Options &o = c.options;
  const std::vector<std::string> names = res.calibrated.getParameterNames();
  const vpColVector &cal = res.calibrated.getParameters(), &nom = c.nominal.getParameters();
  std::string beyond, loose, mount;
  const bool world = c.dataset.camera_mount == vpSelfCalibDataset::CAMERA_IN_WORLD;
  unsigned int num_beyond = 0, num_loose = 0, num_mount = 0;
  const vpKinematicIdentification::Identifiability &set = res.identifiability;
  const Eigen::MatrixXd absorption = poseAbsorption(c, res);
  for (unsigned int k = 0; k < set.identified.size(); ++k) {
    const unsigned int i = set.identified[k];
    const std::string &n = names[i];
    const bool hand_eye = n.rfind("eMc.", 0) == 0;
    // The hand-eye method's eMc (bMc), or one the run started from the data, is the quantity calibrated,
    // from any start (the caller's guess: findGuessFar()): its correction has no tolerance, but an sd
    // beyond the guess's tolerance says the views do not determine it.
    const bool calibrated_hand_eye = hand_eye && o.method == vpRobotSelfCalibration::HAND_EYE;
    const bool started_hand_eye = hand_eye && !calibrated_hand_eye && c.eMc_from_data;
    const bool t = isTranslation(n);
    const double tol = toleranceOf(o, n);
    const double scale = 1e3, corr = cal[i] - nom[i]; // mm or mrad
    const double sd = i < res.parameter_sd.size() ? res.parameter_sd[i] : 0.0;
    const std::string unit = t ? " mm" : " mrad";
    if (calibrated_hand_eye) {
      if (sd > tol && num_mount++ < 4)
        mount += (mount.empty() ? "" : ", ") + (world ? "bMc." + n.substr(4) : n) + " +- " + fixed(scale * sd, 1) + unit + " (tolerance " +
                 fixed(scale * tol, 1) + unit + ")";
      continue;
    }
    if (started_hand_eye) { // the bundle method's eMc: poorly determined, not beyond a tolerance
      if (sd > kPoorlyDetermined * tol && num_loose++ < 4)
        loose += (loose.empty() ? "" : ", ") + n + " +- " + fixed(scale * sd, 1) + unit;
      continue;
    }
    // Beyond the tolerance by more than its own uncertainty (3 sd): a poorly determined correction
    // is the next check's business. The tolerance of the correction: its own and what the
    // parameters not estimated move it (the set's bias), together.
    const double bias2 = setBiasVariance(o, set, absorption, k), widened = std::sqrt(tol * tol + bias2);
    if (std::fabs(corr) - 3.0 * sd > widened && num_beyond++ < 4)
      beyond += (beyond.empty() ? "" : ", ") + n + " " + fixed(scale * corr, 1) + " +- " + fixed(scale * sd, 1) + unit +
                " (tolerance " + fixed(scale * tol, 1) + unit +
                (bias2 > 0 ? ", " + fixed(scale * widened, 1) + unit + " with the parameters not estimated" : "") + ")";
    if (sd > kPoorlyDetermined * tol && num_loose++ < 4)
      loose += (loose.empty() ? "" : ", ") + n + " +- " + fixed(scale * sd, 1) + unit + " (tolerance " +
               fixed(scale * tol, 1) + unit + ")";
  }
  if (num_beyond)
    add(res, vpSelfCalibDataCheck::DOUBT, "correction-beyond-tolerance",
        std::to_string(num_beyond) + " correction(s) exceed the nominal model's tolerance: " + beyond +
            (num_beyond > 4 ? ", ..." : "") +
            ". A correction that large is more likely a wrong input (u and v swapped, joints that do not "
            "belong to their image, a wrong robot model or camera) than the robot's real error; if the nominal "
            "model is really that far off, state a larger tolerance (calibrate --tolerance)");
  if (num_mount) {
    add(res, vpSelfCalibDataCheck::DOUBT, "hand-eye-not-determined",
        "the views do not determine the camera's mount: " + mount +
            (num_mount > 4 ? ", ..." : "") +
            ". They do not fit one rigid camera mount: check the dataset's camera_mount (" +
            (world ? "world: a camera fixed in the world sees a target on the tool; a camera on the flange "
                     "looking at a fixed scene is camera_mount: effector"
                   : "effector: a camera on the flange sees a scene fixed in the world; a camera fixed in the "
                     "world looking at a target on the tool is camera_mount: world") +
            "), the pairing of poses and images, and that the poses vary in rotation about two axes or more");
  }
  if (num_loose)
    add(res, vpSelfCalibDataCheck::DOUBT, "poorly-determined",
        std::to_string(num_loose) + " parameter(s) are determined by these views less well than twice the nominal "
            "model's tolerance: " + loose + (num_loose > 4 ? ", ..." : "") +
            ". Calibrating them may make the model worse: add views (more, and more varied, configurations; "
            "visp-selfcalib plan) or a yardstick");
}

/*
  A model's reprojection RMS on views exceeds a reference model's beyond what the image noise sigma
  explains, and by 5 % or more. Each mean square is (systematic)^2 plus noise; with n coordinates its
  variance is about (4 sigma^2 systematic^2 + 2 sigma^4) / n, so the difference of the two mean
  squares is tested at 3.29 of its sd (99.9 %, one-sided 99.95 %).
*/
bool worse(const vpCalibrationVerifier::Result &model, const vpCalibrationVerifier::Result &reference, double sigma)
{
  if (model.num_observations < 2 || reference.num_observations < 2)
    return false;
  const double n = 2.0 * std::min(model.num_observations, reference.num_observations);
  const double a2 = model.reprojection_rms * model.reprojection_rms;
  const double b2 = reference.reprojection_rms * reference.reprojection_rms;
  const double s2 = sigma * sigma;
  const double sd = std::sqrt((4.0 * s2 * (a2 + b2) + 4.0 * s2 * s2) / n);
  return a2 - b2 > 3.29 * sd && model.reprojection_rms > 1.05 * reference.reprojection_rms;
}

// The image noise the checks assume: the measured one, else the stated one.
double noiseOf(const Context &c, const Result &res)
{
  return res.measured.pixel_sd > 0 ? res.measured.pixel_sd : c.noise.pixel_sd;
}

/*
  The pixel of a point X (f frame) in view k moves by J_k dT_k when the relative pose
  T_k = c_0 M c_k moves by dT_k (position, then the left rotation perturbation, both in c_0's
  frame): X_k = cMf X moves by -R_T^T dt + [X_k]x R_T^T dphi, its pixel by f / Z (dX - x dZ,
  dY - y dZ); and by K_k dX when the point moves (K_k = f / Z P R_cf). Taken whole, with the cross
  terms: the data determine the combination of position and rotation the images see.
*/
struct PixelJacobians {
  Eigen::Matrix<double, 2, 6> pose;
  Eigen::Matrix<double, 2, 3> point;
};

bool pixelJacobians(const vpSelfCalib::Rigid &cMf, const Eigen::Matrix3d &R_T, const Eigen::Vector3d &X, double f,
                    PixelJacobians &J)
{
  const Eigen::Vector3d Xk = cMf * X;
  if (!(Xk.z() > 0))
    return false;
  Eigen::Matrix<double, 2, 3> P;
  P << 1, 0, -Xk.x() / Xk.z(), 0, 1, -Xk.y() / Xk.z();
  Eigen::Matrix<double, 3, 6> G;
  G.leftCols(3) = -R_T.transpose();
  G.rightCols(3) = vpSelfCalib::skew(Xk) * R_T.transpose();
  J.pose = (f / Xk.z()) * P * G;
  J.point = (f / Xk.z()) * P * cMf.R;
  return true;
}

/*
  The calibrated model's error on new views like the calibration ones from its covariance C (the
  estimated parameters d ~ N(0, C)), propagated to the relative camera poses of the calibration
  views (c_0 M c_k, view 0 fixed), to the pixels of the points each view sees, and then with each
  point triangulated again from its views (the part of the pixels' displacement a shift of the
  point explains removed, as the misfit it is compared with triangulates each model's points): the
  mean square per coordinate is d^T Q d, a weighted sum of chi-squares with the eigenvalues of
  L^T Q L (C = L L^T). Returns its mean (the variance) and its 99.9 % quantile. The parameters left
  at nominal by the data do not enter: on views of this geometry their error is what the estimated
  parameters and the scene points absorb (the set's bias), and what is left of it is in the
  calibrated model's own fit, which fit-worse-than-nominal compares with the nominal model's.
*/
void predictedError(const Context &c, const Result &res, const std::map<int, vpColVector> &points, const vpMatrix &C,
                    double &mean_square, double &quantile)
{
  const std::vector<unsigned int> &id = res.identifiability.identified;
  const int P = static_cast<int>(id.size()), K = static_cast<int>(c.calibration.size());
  Eigen::MatrixXd S(P, P), Q = Eigen::MatrixXd::Zero(P, P);
  for (int i = 0; i < P; ++i)
    for (int j = 0; j < P; ++j)
      S(i, j) = C[i][j];
  // Per view: cMf, the relative rotation and the relative pose's Jacobian (6 x P; view 0: 0).
  const vpSelfCalib::Rigid A = vpSelfCalib::rigidFromVisp(res.calibrated.get_fMc(c.calibration[0].q));
  std::vector<vpSelfCalib::Rigid> cMf(K);
  std::vector<Eigen::Matrix3d> R_T(K);
  std::vector<Eigen::MatrixXd> G(K, Eigen::MatrixXd::Zero(6, P));
  for (int k = 0; k < K; ++k) {
    const vpSelfCalib::Rigid B = vpSelfCalib::rigidFromVisp(res.calibrated.get_fMc(c.calibration[k].q));
    cMf[k] = B.inverse();
    R_T[k] = A.R.transpose() * B.R;
    if (k > 0)
      G[k] = motionJacobian(res.calibrated, c.calibration[0].q, c.calibration[k].q, id);
  }
  // Per point: its pixels' displacement over the views that see it, less what the point's own shift explains.
  std::map<int, std::vector<int>> seen;
  for (int k = 0; k < K; ++k)
    for (const auto &o : c.calibration[k].points)
      seen[o.id].push_back(k);
  unsigned int count = 0;
  const double f = res.camera.get_px();
  for (const auto &e : seen) {
    const auto X = points.find(e.first);
    if (X == points.end() || e.second.size() < 2)
      continue;
    const Eigen::Vector3d Xf(X->second[0], X->second[1], X->second[2]);
    const int n = static_cast<int>(e.second.size());
    Eigen::MatrixXd D(2 * n, P), Kp(2 * n, 3);
    int rows = 0;
    for (int k : e.second) {
      PixelJacobians J;
      if (!pixelJacobians(cMf[k], R_T[k], Xf, f, J))
        continue;
      D.middleRows(rows, 2) = J.pose * G[k];
      Kp.middleRows(rows, 2) = J.point;
      rows += 2;
    }
    if (rows < 4)
      continue;
    const Eigen::MatrixXd Dr = D.topRows(rows), Kr = Kp.topRows(rows);
    const Eigen::MatrixXd Res = Dr - Kr * Kr.colPivHouseholderQr().solve(Dr);
    Q += Res.transpose() * Res;
    count += static_cast<unsigned int>(rows / 2);
  }
  mean_square = quantile = 0;
  if (count == 0)
    return;
  Q /= 2.0 * count; // per coordinate
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (S + S.transpose()));
  const Eigen::MatrixXd L = es.eigenvectors() * es.eigenvalues().cwiseMax(0).cwiseSqrt().asDiagonal();
  const Eigen::MatrixXd R = L.transpose() * Q * L;
  const Eigen::VectorXd lambda = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(0.5 * (R + R.transpose())).eigenvalues();
  mean_square = lambda.cwiseMax(0).sum();
  quantile = vpSelfCalib::weightedChi2Quantile999(lambda);
}

/*
  The calibrated model's predicted error on new views against the nominal model's misfit (see
  Result::predicted_rms); points: the scene triangulated through the calibrated model (f frame).
*/
void checkPredicted(const Context &c, Result &res, const std::map<int, vpColVector> &points)
{
  if (c.options.method == vpRobotSelfCalibration::HAND_EYE || res.fit_nominal_rms <= 0 || points.empty())
    return;
  const vpMatrix &C = c.options.method == vpRobotSelfCalibration::PAPER ? res.identification.covariance
                                                                         : res.bundle.covariance;
  const std::vector<unsigned int> &id = res.identifiability.identified;
  if (id.empty() || C.getRows() < id.size() || c.calibration.size() < 2)
    return;
  double mean_square = 0, q999 = 0;
  predictedError(c, res, points, C, mean_square, q999);
  if (!(mean_square > 0))
    return;
  res.predicted_rms = std::sqrt(mean_square);
  // A checked answer must be better than the nominal model with confidence: its own uncertainty
  // must leave at most a 0.1 % chance that its error on new views exceeds twice the nominal misfit:
  // the 99.9 % quantile of that error's mean square (one direction alone, the focal length or the
  // scale, gives 3.29 times the predicted RMS; an error spread over several, less).
  const double bound = std::sqrt(q999), limit = 2.0 * res.fit_nominal_rms;
  if (bound > limit)
    add(res, vpSelfCalibDataCheck::DOUBT, "expected-worse-than-nominal",
        "the calibrated model's own predicted error on new views (" + fixed(res.predicted_rms, 2) +
            " px RMS from its covariance, 99.9 % bound " + fixed(bound, 2) +
            " px) leaves more than a 0.1 % chance that it is worse than twice the "
            "nominal model's misfit on the calibration views (" +
            fixed(res.fit_nominal_rms, 2) + " px; limit " + fixed(limit, 2) +
            " px): these views cannot make the model reliably better than the nominal one; add views (more, and "
            "more varied, configurations), a yardstick, or fix the focal length if it is known");
}

/*
  Where a model is used: the camera's motions c_a M c_b between configurations drawn uniformly within
  the joint limits (kWorkspacePairs pairs of a fixed draw), the figure `compare` measures against a
  simulation's truth. The calibration views determine the model near their own configurations;
  away from them, few views (6 (n - 1) relative-pose equations for some 24 parameters) leave
  combinations of the parameters that their covariance spreads over tens of mm, and at any number
  of views a large image noise, or a self-calibrated focal length (its error moves the translations),
  can leave the model worse than the nominal one there.
*/
constexpr unsigned int kWorkspacePairs = 100;
/*
  The calibrated model must be better than the nominal one there with confidence: at most a 10 %
  chance that its RMS error exceeds the nominal model's, given what the calibration views show of
  both (chanceWorse()); the 90 % bound (kWorkspaceZ, one-sided) of its own error is reported beside
  it. The level was chosen with the two errors judged apart, on simulated Viper850 and PUMA 560
  runs (seeds 1-10, 5 to 12 views, compared with the truth): at 50 % runs of 5 and 6 views worse than
  the nominal model stayed ok; at 95 % a run of 10 views better than the nominal model turned
  doubtful; at 90 % neither.
*/
constexpr double kWorkspaceZ = 1.2816;
constexpr double kWorkspaceLevel = 0.1; //!< its one-sided level: the chance of the calibrated model being the worse

//! Mean squares of a motion error (m^2, rad^2): position and rotation.
struct MotionSquares {
  double t = 0, r = 0;
};

//! The mean square error of the motions over `pairs` when the parameters err by `shape` (a variance per chain parameter).
MotionSquares toleranceSpread(const vpKinematicChain &chain, const std::vector<std::pair<vpColVector, vpColVector>> &pairs,
                              const Eigen::VectorXd &shape)
{
  std::vector<unsigned int> all(static_cast<size_t>(shape.size()));
  for (unsigned int i = 0; i < all.size(); ++i)
    all[i] = i;
  MotionSquares m;
  for (const auto &p : pairs) {
    const Eigen::MatrixXd J = motionJacobian(chain, p.first, p.second, all);
    m.t += (J.topRows(3).array().square().rowwise() * shape.transpose().array()).sum() / pairs.size();
    m.r += (J.bottomRows(3).array().square().rowwise() * shape.transpose().array()).sum() / pairs.size();
  }
  return m;
}

/*
  What the calibrated model's error on the workspace's motions consists of: its estimated parameters'
  error (their covariance) and the error of the parameters it holds at their nominal value, which the
  calibration views let the estimated ones absorb near their configurations only: the parameters
  the data left at nominal (the set rule), and eMc's held near its start by the kinematic prior.
  Each held parameter errs as the nominal model's parameters do (its
  tolerance's square times the variance factor the data measure: nominalOnWorkspace()) and moves
  the estimated ones by its absorption (the set's bias, Identifiability::bias, where the bundle
  adjustment computed it; else the least-squares absorption through the calibration views'
  motions). A parameter the model's rule folds into the estimated ones (CAUSE_MODEL) errs nowhere,
  one the caller fixed is at the value stated. Without a yardstick, the nominal scale's error is
  the nominal model's as much as the calibrated one's, and is left out of the comparison.
*/
struct ErrorModel {
  vpKinematicChain chain;               //!< the model whose motions are judged (eye-to-hand: eMo in the hand-eye slot)
  std::vector<unsigned int> estimated;  //!< chain indices of the estimated parameters judged
  std::vector<unsigned int> held;       //!< chain indices of the parameters held at nominal
  Eigen::MatrixXd absorption;           //!< estimated x held: the estimated ones' move per unit error of a held one
  Eigen::MatrixXd covariance;           //!< of [estimated error, held error]
  Eigen::MatrixXd estimate_covariance;  //!< the estimated parameters' covariance as the adjustment gave it
  Eigen::VectorXd scale_move;           //!< the estimated parameters' move along the scale (with scale_sd > 0)
  double scale_sd = 0;                  //!< the nominal scale's relative sd, shared with the nominal model (removed)
};

//! The error model's motion Jacobian on a pair: [J_E, J_H + J_E absorption] (6 x (E + H)).
Eigen::MatrixXd errorJacobian(const ErrorModel &m, const vpColVector &qa, const vpColVector &qb)
{
  const Eigen::Index E = static_cast<Eigen::Index>(m.estimated.size()), H = static_cast<Eigen::Index>(m.held.size());
  std::vector<unsigned int> all = m.estimated;
  all.insert(all.end(), m.held.begin(), m.held.end());
  const Eigen::MatrixXd J = motionJacobian(m.chain, qa, qb, all);
  Eigen::MatrixXd G(6, E + H);
  G.leftCols(E) = J.leftCols(E);
  if (H > 0)
    G.rightCols(H) = J.rightCols(H) + J.leftCols(E) * m.absorption;
  return G;
}

/*
  The estimated parameters' move along the scale (s: J s = [t; 0] on every calibration view's motion,
  least squares), for removing the nominal scale's error from their covariance: without a yardstick
  the calibrated model keeps the nominal model's scale, and its error (the covariance counts it:
  vpKinematicBundleAdjustment::Result::nominal_scale_sd) is the nominal model's too.
*/
Eigen::VectorXd scaleMove(const ErrorModel &m, const std::vector<View> &views)
{
  const int K = static_cast<int>(views.size()), E = static_cast<int>(m.estimated.size());
  Eigen::MatrixXd A(6 * (K - 1), E);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(6 * (K - 1));
  for (int k = 1; k < K; ++k) {
    A.middleRows(6 * (k - 1), 6) = motionJacobian(m.chain, views[0].q, views[k].q, m.estimated);
    const vpHomogeneousMatrix M = m.chain.get_fMc(views[0].q).inverse() * m.chain.get_fMc(views[k].q);
    for (unsigned int i = 0; i < 3; ++i)
      b(6 * (k - 1) + static_cast<int>(i)) = M[i][3];
  }
  return A.colPivHouseholderQr().solve(b);
}

bool errorModel(const Context &c, const Result &res, const vpMatrix &C, ErrorModel &m)
{
  const vpKinematicIdentification::Identifiability &set = res.identifiability;
  const bool e2h = c.bundle.eye_to_hand;
  const std::vector<std::string> names = res.calibrated.getParameterNames();
  const unsigned int first_eMc = res.calibrated.getNumParameters() - vpKinematicChain::kBlockSize;
  m.chain = res.calibrated;
  if (e2h) { // the target's motions: eMo in the hand-eye slot, whose bMc does not move them
    if (!res.bundle.has_object)
      return false;
    m.chain = withNominalEMc(res.calibrated, res.bundle.object_pose);
  }
  // A joint parameter held by the kinematic prior is one of the estimated ones: the error covariance
  // of the estimate with the prior (errorWithThePrior()) gives it the arm's error level where the data
  // do not see it, and its correlations move the others as the data let them absorb it. eMc's, whose
  // prior is about a guess and not the arm's error, is judged as a parameter left at nominal.
  const auto held_apart = [&](unsigned int i) { return set.heldByPrior(i) && i >= first_eMc; };
  std::vector<unsigned int> rows; // rows of C kept
  for (unsigned int k = 0; k < set.identified.size(); ++k)
    if ((!e2h || set.identified[k] < first_eMc) && !held_apart(set.identified[k])) {
      m.estimated.push_back(set.identified[k]);
      rows.push_back(k);
    }
  std::vector<int> bias_column; // per held parameter: its column of the set's bias, or -1
  for (const auto &u : set.held_by_prior)
    if (!e2h && held_apart(u.index)) {
      m.held.push_back(u.index);
      bias_column.push_back(-1);
    }
  for (unsigned int l = 0; l < set.unidentifiable.size(); ++l)
    if (set.unidentifiable[l].cause == vpKinematicIdentification::CAUSE_DATA &&
        !(e2h && set.unidentifiable[l].index >= first_eMc)) {
      m.held.push_back(set.unidentifiable[l].index);
      const bool biased = l < set.bias.getCols() && set.bias.getRows() == set.identified.size();
      bias_column.push_back(biased ? static_cast<int>(l) : -1);
    }
  const Eigen::Index E = static_cast<Eigen::Index>(m.estimated.size()), H = static_cast<Eigen::Index>(m.held.size());
  const int K = static_cast<int>(c.calibration.size());
  if (E == 0 || K < 2)
    return false;
  // Absorption: the set's bias where there is one, else least squares over the views' motions.
  m.absorption = Eigen::MatrixXd::Zero(E, H);
  if (H > 0) {
    const Eigen::MatrixXd ls = motionAbsorption(m.chain, c.calibration, m.estimated, m.held);
    for (Eigen::Index h = 0; h < H; ++h)
      for (Eigen::Index e = 0; e < E; ++e) {
        const int col = bias_column[static_cast<size_t>(h)];
        const double b = col >= 0 ? set.bias[rows[static_cast<size_t>(e)]][static_cast<unsigned int>(col)] : ls(e, h);
        m.absorption(e, h) = std::isfinite(b) ? b : 0.0;
      }
  }
  m.covariance = Eigen::MatrixXd::Zero(E + H, E + H);
  for (Eigen::Index i = 0; i < E; ++i)
    for (Eigen::Index j = 0; j < E; ++j)
      m.covariance(i, j) = C[rows[static_cast<size_t>(i)]][rows[static_cast<size_t>(j)]];
  m.estimate_covariance = m.covariance.topLeftCorner(E, E);
  // The joint tolerance's square (the nominal model's shape), times its variance factor (nominalOnWorkspace()).
  for (Eigen::Index h = 0; h < H; ++h)
    m.covariance(E + h, E + h) = std::pow(isTranslation(names[m.held[static_cast<size_t>(h)]])
                                              ? c.options.tolerance_translation
                                              : c.options.tolerance_rotation,
                                          2);
  // The nominal scale's error, common to both models, out of the comparison.
  m.scale_sd = e2h ? 0.0 : res.bundle.nominal_scale_sd;
  if (m.scale_sd > 0) {
    m.scale_move = scaleMove(m, c.calibration);
    m.covariance.topLeftCorner(E, E) -= m.scale_sd * m.scale_sd * m.scale_move * m.scale_move.transpose();
  }
  return true;
}

/*
  The nominal model's error on the workspace's motions, from what the data measure: its motions
  between the calibration views against the calibrated model's, which the images pin there (with
  the calibrated model's own covariance on them counted: varianceFactors()), as the error of every parameter of the
  complete model (joint placements and eMc) with a variance in proportion to its tolerance's square,
  one factor for the translations and one for the rotations (variance components: the motions'
  rotation error is the rotations' alone, its position error both's), carried to the workspace's
  pairs. A nominal model whose misfit there is within the calibrated model's own uncertainty is taken
  as exact: the calibration is not shown better than it, not even on its own views (a 5-view
  Viper850 run 188 mm off over the workspace, its own uncertainty on its views' motions above the
  nominal model's misfit). The factors also give the parameters the calibrated model holds at nominal
  their error (errorModel()). Simulated Viper850 and PUMA 560, seeds 1-10, 8 to 15 views, f known
  0.2 px: the estimate within -7 % to +33 % of compare's truth; subtracting the calibrated model's
  expected error instead, a run whose own error was large along the yardstick's scale or the focal
  length took it for the nominal model's (15 views, f self-calibrated: estimates 6.6-11.2 mm over
  noise draws of one geometry, 10.7 and 11.2 where the calibrated model was 12.5 and 11.9 mm off and
  called ok, against a true 6.5; now 7.0-7.6 on every draw).
*/
struct NominalError {
  MotionSquares workspace;             //!< the nominal model's mean squares on the workspace's pairs
  double factor_t = 0, factor_r = 0;   //!< a parameter's error variance over its tolerance's square
  Eigen::Matrix2d factor_covariance = Eigen::Matrix2d::Zero(); //!< the factors' (Fisher information inverted)
  Eigen::MatrixXd misfit_jacobian;     //!< the calibration views' motions (c_0 M c_k) by the estimated parameters
  Eigen::VectorXd misfit;              //!< the calibrated minus the nominal model's motions there
};

/*
  The two variance factors by maximum likelihood (Fisher scoring) on the misfit d of the K - 1 motions
  c_0 M c_k (6 (K - 1) values), d ~ N(0, a_t A_t + a_r A_r + S): A the nominal model's motion Jacobian
  with the tolerances' squares, S the calibrated model's own covariance carried to the same motions.
  S in the misfit's covariance down-weights the directions the calibrated model itself does not pin
  (the focal length's or the yardstick's scale moving the translations): its realized error there is
  not taken for the nominal model's. Worked in the span of A (to first order the misfit lies in it).
  The factors' covariance is the inverse of the Fisher information.
*/
void varianceFactors(const Eigen::MatrixXd &Bt, const Eigen::MatrixXd &Br, const Eigen::MatrixXd &S,
                     const Eigen::VectorXd &d, Eigen::Vector2d &a, Eigen::Matrix2d &cov)
{
  Eigen::MatrixXd B(Bt.rows(), Bt.cols() + Br.cols());
  B << Bt, Br;
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(B, Eigen::ComputeThinU);
  const Eigen::VectorXd &sv = svd.singularValues();
  Eigen::Index r = 0;
  while (r < sv.size() && sv(r) > 1e-6 * sv(0))
    ++r;
  const Eigen::MatrixXd U = svd.matrixU().leftCols(r);
  const Eigen::MatrixXd A[2] = {U.transpose() * Bt * Bt.transpose() * U, U.transpose() * Br * Br.transpose() * U};
  const Eigen::MatrixXd Sr = U.transpose() * S * U;
  const Eigen::VectorXd dr = U.transpose() * d;
  constexpr double floor = 1e-4; // 1 % of the tolerances: a nominal model taken as exact
  a = Eigen::Vector2d(1.0, 1.0);
  Eigen::Matrix2d F = Eigen::Matrix2d::Identity();
  for (int it = 0; it < 50; ++it) {
    const Eigen::MatrixXd Sigma = a(0) * A[0] + a(1) * A[1] + Sr;
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(Sigma);
    const Eigen::MatrixXd SiA[2] = {ldlt.solve(A[0]), ldlt.solve(A[1])};
    const Eigen::MatrixXd SiS = ldlt.solve(Sr);
    const Eigen::VectorXd Sid = ldlt.solve(dr);
    Eigen::Vector2d q;
    for (int i = 0; i < 2; ++i) {
      q(i) = Sid.dot(A[i] * Sid) - (SiA[i] * SiS).trace();
      for (int j = 0; j < 2; ++j)
        F(i, j) = (SiA[i] * SiA[j]).trace();
    }
    const Eigen::Vector2d next = F.ldlt().solve(q).cwiseMax(floor);
    const bool done = ((next - a).array().abs() <= 1e-4 * a.array().abs().max(floor)).all();
    a = next;
    if (done)
      break;
  }
  cov = 2.0 * F.inverse();
}

NominalError nominalOnWorkspace(const Context &c, const ErrorModel &em,
                                const std::vector<std::pair<vpColVector, vpColVector>> &workspace)
{
  const std::vector<std::string> names = c.guess.getParameterNames();
  const Eigen::Index P = static_cast<Eigen::Index>(names.size());
  Eigen::VectorXd shape_t = Eigen::VectorXd::Zero(P), shape_r = shape_t;
  for (size_t i = 0; i < names.size(); ++i)
    (isTranslation(names[i]) ? shape_t : shape_r)[static_cast<Eigen::Index>(i)] =
        std::pow(isTranslation(names[i]) ? c.options.tolerance_translation : c.options.tolerance_rotation, 2);
  // The nominal kinematics with the judged model's hand-eye slot (eye-to-hand: the target's pose).
  const vpKinematicChain nominal = c.bundle.eye_to_hand ? withNominalEMc(c.guess, em.chain.get_eMc_pose()) : c.guess;
  std::vector<unsigned int> all(static_cast<size_t>(P));
  for (unsigned int i = 0; i < all.size(); ++i)
    all[i] = i;
  const std::vector<View> &v = c.calibration;
  const Eigen::Index E = static_cast<Eigen::Index>(em.estimated.size());
  const Eigen::MatrixXd C = em.covariance.topLeftCorner(E, E);
  const Eigen::Index n = 6 * (static_cast<Eigen::Index>(v.size()) - 1);
  Eigen::MatrixXd Bt(n, P), Br(n, P), JE(n, E);
  Eigen::VectorXd d(n);
  for (size_t k = 1; k < v.size(); ++k) {
    const Eigen::Index row = 6 * (static_cast<Eigen::Index>(k) - 1);
    const Eigen::MatrixXd J = motionJacobian(nominal, v[0].q, v[k].q, all);
    Bt.middleRows(row, 6) = J * shape_t.cwiseSqrt().asDiagonal();
    Br.middleRows(row, 6) = J * shape_r.cwiseSqrt().asDiagonal();
    JE.middleRows(row, 6) = motionJacobian(em.chain, v[0].q, v[k].q, em.estimated);
    const vpSelfCalib::Rigid cal = vpSelfCalib::rigidFromVisp(em.chain.get_fMc(v[0].q).inverse() * em.chain.get_fMc(v[k].q));
    const vpSelfCalib::Rigid nom = vpSelfCalib::rigidFromVisp(nominal.get_fMc(v[0].q).inverse() * nominal.get_fMc(v[k].q));
    d.segment<3>(row) = cal.t - nom.t;
    d.segment<3>(row + 3) = vpSelfCalib::logSO3(cal.R * nom.R.transpose());
  }
  Eigen::Vector2d a;
  Eigen::Matrix2d cov;
  varianceFactors(Bt, Br, JE * C * JE.transpose(), d, a, cov);
  const MotionSquares ws_t = toleranceSpread(nominal, workspace, shape_t);
  const MotionSquares ws_r = toleranceSpread(nominal, workspace, shape_r);
  NominalError e;
  e.factor_t = a(0);
  e.factor_r = a(1);
  e.factor_covariance = cov;
  e.misfit_jacobian = JE;
  e.misfit = d;
  e.workspace.t = e.factor_t * ws_t.t + e.factor_r * ws_r.t;
  e.workspace.r = e.factor_r * ws_r.r;
  return e;
}

/*
  The kinematic prior's precision on each estimated parameter, K^2 / tolerance^2 (eMc's corrections
  have none), and the factor f the adjustment's covariance was scaled by after the solve
  (Result::covariance_factor): C = f (H + P)^-1, the solve's weights those of the stated noise.
*/
Eigen::VectorXd priorPrecision(const Context &c, const Result &res, const ErrorModel &em, double &f)
{
  const std::vector<std::string> names = res.calibrated.getParameterNames();
  const double K = res.bundle.kinematic_prior;
  f = res.bundle.covariance_factor > 0 ? res.bundle.covariance_factor : 1.0;
  Eigen::VectorXd p = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(em.estimated.size()));
  for (Eigen::Index e = 0; K > 0 && e < p.size(); ++e) {
    const std::string &name = names[em.estimated[static_cast<size_t>(e)]];
    if (name.rfind("eMc.", 0) != 0)
      p(e) = K * K / std::pow(toleranceOf(c.options, name), 2);
  }
  return p;
}

/*
  With the kinematic prior, the estimated joint parameters' covariance C = (H + P)^-1 is the posterior
  at the prior the tolerances state, P = diag((K / tol)^2): where the data see a parameter weakly its sd
  is the prior's, which says what the tolerances allow, not the arm's error. The estimate's error is
  (H + P)^-1 (noise term - P x), x the arm's true corrections; for the workspace judgement x errs as the
  nominal model's misfit measures (nominalOnWorkspace(): Sigma = a variance factor times the
  tolerance's square, as for the parameters left at nominal), and the error's covariance is the
  sandwich C (H + P Sigma P) C = C - C (P - P Sigma P) C on the estimated block: the image noise's
  part plus the prior's pull on an arm that is not at nominal. Not the posterior at the measured
  level, (H + Sigma^-1)^-1, which is the error of an estimator run with that prior, not of this one: on
  a Viper850 with 8 views it predicted 2.6 mm over the workspace where 30 noise draws of the same
  arm gave 4.1 mm RMS; the sandwich predicts 4.1. eMc's corrections keep theirs (its tolerance is not
  the joints'). A covariance scaled after the solve by a factor f (the residuals measuring another
  noise than the one stated: Result::covariance_factor) is f C0, C0 = (H + P)^-1 at the stated
  noise, the weights the estimate was computed with: its error is then f (C0 - C0 P C0) + C0 P Sigma
  P C0 = C - C (P / f - P Sigma P / f^2) C (the noise stated 10x too high, f = 0.01: the prior pulled
  ten times harder than the covariance says, and the model was 6.9 mm off over the workspace where
  C - C (P - P Sigma P) C predicted 1.8; this predicts 3.3, still about half, and the chance given
  the misfit, chanceWorse(), makes the run doubtful).
*/
void errorWithThePrior(const Context &c, const Result &res, const NominalError &ne, const std::vector<std::string> &names,
                       ErrorModel &em)
{
  const double K = res.bundle.kinematic_prior;
  const Eigen::Index E = static_cast<Eigen::Index>(em.estimated.size());
  if (!(K > 0) || E == 0)
    return;
  double f = 1;
  const Eigen::VectorXd p = priorPrecision(c, res, em, f);
  Eigen::VectorXd d(E); // P / f - P Sigma P / f^2, Sigma = factor tol^2: p Sigma = K^2 factor
  for (Eigen::Index e = 0; e < E; ++e) {
    const double factor = isTranslation(names[em.estimated[static_cast<size_t>(e)]]) ? ne.factor_t : ne.factor_r;
    d(e) = p(e) / f * (1 - K * K * factor / f);
  }
  const Eigen::MatrixXd C = em.covariance.topLeftCorner(E, E);
  const Eigen::MatrixXd N = C - C * d.asDiagonal() * C;
  em.covariance.topLeftCorner(E, E) = 0.5 * (N + N.transpose());
}

/*
  The chance that the calibrated model's mean square error on the motions `pairs` exceeds the nominal
  model's, in position and in rotation, given what the data show of both: the two models' difference
  on the calibration views' motions (NominalError::misfit). To first order, with z = (u_E, u_h, w):
  u the nominal model's error (nominal minus true) on the estimated and the held parameters, ~ N(0,
  Sigma), Sigma the tolerances' squares times the variance factors (nominalOnWorkspace()); w the
  image noise's part of the estimate, ~ N(0, C - C P C), C the adjustment's covariance and P the
  kinematic prior's precision (the nominal scale's error, common to both models, removed). The
  calibrated model errs by e_E = w + C P u_E + A u_h on the estimated parameters (A the absorption of
  the held ones) and by u_h on the held ones, the nominal model by u; the misfit is J_cal (e_E - u_E).
  Both models' mean square errors over the pairs are quadratic forms in z, and the chance is that of
  their difference being positive under z's posterior given the misfit (a fixed sample), averaged
  over the factors' uncertainty (a 3 x 3 Gauss-Hermite rule on their normal).
  Judged apart instead (the calibrated model's error from its covariance against the nominal
  model's estimated mean square, as two independent errors), what both models share counts twice:
  where the data do not see a parameter both carry the same error, which cancels in their
  difference, and where they see it the misfit says which of the two errs. Against the truth over
  the joint limits, judged apart then given the misfit: simulated Viper850 with a flat board of
  unknown layout, 14 views, 0.2 px (bench-plane-scan, 72 draws) 27 doubtful of which 1 truly worse
  and 2 worse runs passed, now 8 doubtful of which 3 worse and none passed; rendered ChArUco
  (bench-boards, 40 runs) 13 doubtful none worse and 2 worse passed, now the 2 worse ones doubtful
  and nothing else; Viper850 and PUMA 560, 8 to 15 views, 0.2 px (80 runs) 1 worse run passed (8
  views), now doubtful and every other ok; at 2 px (80 runs, 39 worse) 79 doubtful, now 66 and 1
  worse passed (6 % worse in position, 35 % better in rotation); stuck-joint PUMA 560 and Panda, 12
  views, 0.5 px (160 draws of 20 geometries) 113 doubtful of which 24 worse and 1 worse passed,
  now 106 of which 25 worse and none passed.
*/
Eigen::Vector2d chanceWorse(const Context &c, const Result &res, const ErrorModel &em, const NominalError &ne,
                            const std::vector<std::pair<vpColVector, vpColVector>> &pairs)
{
  const std::vector<std::string> names = res.calibrated.getParameterNames();
  const Eigen::Index E = static_cast<Eigen::Index>(em.estimated.size()), H = static_cast<Eigen::Index>(em.held.size());
  const Eigen::Index D = 2 * E + H;
  const Eigen::MatrixXd &C = em.estimate_covariance;
  const auto nameOf = [&](Eigen::Index i) -> const std::string & {
    return names[i < E ? em.estimated[static_cast<size_t>(i)] : em.held[static_cast<size_t>(i - E)]];
  };
  // C = f C0 when the covariance was scaled after the solve (errorWithThePrior()): the prior's pull
  // is C0 P, the noise's part f (C0 - C0 P C0).
  double f = 1;
  const Eigen::VectorXd prior = priorPrecision(c, res, em, f);
  const Eigen::MatrixXd CP = C * prior.asDiagonal() / f;
  Eigen::MatrixXd N = C - CP * C;
  if (em.scale_sd > 0 && em.scale_move.size() == E)
    N -= em.scale_sd * em.scale_sd * em.scale_move * em.scale_move.transpose();
  {
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (N + N.transpose()));
    N = es.eigenvectors() * es.eigenvalues().cwiseMax(0).asDiagonal() * es.eigenvectors().transpose();
  }
  Eigen::MatrixXd Qt = Eigen::MatrixXd::Zero(D, D), Qr = Qt;
  for (const auto &p : pairs) {
    const Eigen::MatrixXd G = errorJacobian(em, p.first, p.second);
    const Eigen::MatrixXd GE = G.leftCols(E), GH = G.rightCols(H);
    Eigen::MatrixXd Fc = Eigen::MatrixXd::Zero(6, D), Fn = Fc;
    Fc.leftCols(E) = GE * CP;
    Fc.middleCols(E, H) = GH;
    Fc.rightCols(E) = GE;
    Fn.leftCols(E) = GE;
    if (H > 0)
      Fn.middleCols(E, H) = GH - GE * em.absorption;
    const double n = static_cast<double>(pairs.size());
    Qt += (Fc.topRows(3).transpose() * Fc.topRows(3) - Fn.topRows(3).transpose() * Fn.topRows(3)) / n;
    Qr += (Fc.bottomRows(3).transpose() * Fc.bottomRows(3) - Fn.bottomRows(3).transpose() * Fn.bottomRows(3)) / n;
  }
  // The misfit in the span of J_cal (6 (K - 1) rows, at most E directions): U^T y = S V^T (e_E - u_E).
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(ne.misfit_jacobian, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd &sv = svd.singularValues();
  Eigen::Index M = 0;
  while (M < sv.size() && sv(M) > 1e-9 * sv(0))
    ++M;
  const Eigen::MatrixXd J = sv.head(M).asDiagonal() * svd.matrixV().leftCols(M).transpose(); // M x E
  const Eigen::VectorXd y = svd.matrixU().leftCols(M).transpose() * ne.misfit;
  Eigen::MatrixXd Go = Eigen::MatrixXd::Zero(M, D);
  Go.leftCols(E) = -J * (Eigen::MatrixXd::Identity(E, E) - CP);
  if (H > 0)
    Go.middleCols(E, H) = J * em.absorption;
  Go.rightCols(E) = J;
  Eigen::VectorXd shape_t = Eigen::VectorXd::Zero(E + H), shape_r = shape_t;
  for (Eigen::Index i = 0; i < E + H; ++i)
    (isTranslation(nameOf(i)) ? shape_t : shape_r)(i) =
        std::pow(isTranslation(nameOf(i)) ? c.options.tolerance_translation : c.options.tolerance_rotation, 2);
  Eigen::Matrix2d Lf = Eigen::Matrix2d::Zero();
  const Eigen::LLT<Eigen::Matrix2d> llt(ne.factor_covariance);
  if (ne.factor_covariance.allFinite() && llt.info() == Eigen::Success)
    Lf = llt.matrixL();
  const double node[3] = {-std::sqrt(3.0), 0.0, std::sqrt(3.0)}, weight[3] = {1.0 / 6, 2.0 / 3, 1.0 / 6};
  constexpr int kSamples = 4000;
  std::mt19937_64 rng(0x776f727365ULL);
  std::normal_distribution<double> gauss;
  double worse_t = 0, worse_r = 0, total = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const Eigen::Vector2d a = (Eigen::Vector2d(ne.factor_t, ne.factor_r) + Lf * Eigen::Vector2d(node[i], node[j]))
                                    .cwiseMax(1e-4);
      Eigen::MatrixXd S = Eigen::MatrixXd::Zero(D, D);
      S.topLeftCorner(E + H, E + H).diagonal() = a(0) * shape_t + a(1) * shape_r;
      S.bottomRightCorner(E, E) = N;
      const Eigen::MatrixXd SGt = S * Go.transpose();
      Eigen::MatrixXd So = Go * SGt;
      So.diagonal().array() += 1e-4 * So.trace() / static_cast<double>(std::max<Eigen::Index>(M, 1)); // a floor
      const Eigen::LDLT<Eigen::MatrixXd> ldlt(0.5 * (So + So.transpose()));
      const Eigen::MatrixXd Kt = ldlt.solve(SGt.transpose());
      const Eigen::VectorXd mu = Kt.transpose() * y;
      const Eigen::MatrixXd post = S - Kt.transpose() * Go * S;
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (post + post.transpose()));
      const Eigen::MatrixXd L = es.eigenvectors() * es.eigenvalues().cwiseMax(0).cwiseSqrt().asDiagonal();
      const int n = static_cast<int>(std::lround(weight[i] * weight[j] * kSamples));
      for (int k = 0; k < n; ++k) {
        Eigen::VectorXd x(D);
        for (Eigen::Index l = 0; l < D; ++l)
          x(l) = gauss(rng);
        const Eigen::VectorXd z = mu + L * x;
        worse_t += z.dot(Qt * z) > 0 ? 1.0 : 0.0;
        worse_r += z.dot(Qr * z) > 0 ? 1.0 : 0.0;
        total += 1.0;
      }
    }
  return total > 0 ? Eigen::Vector2d(worse_t / total, worse_r / total) : Eigen::Vector2d(0, 0);
}

/*
  The joints that barely move over the calibration views (the data check's min_joint_range), with
  the range they cover there: the model is calibrated with each of them where its views hold it.
*/
struct StillJoint {
  unsigned int joint = 0;
  double lo = 0, hi = 0;
};

std::vector<StillJoint> stillJoints(const Context &c)
{
  std::vector<StillJoint> still;
  const unsigned int n = c.guess.getNumJoints();
  if (c.calibration.empty() || c.calibration.front().q.size() != n)
    return still;
  for (unsigned int j = 0; j < n; ++j) {
    StillJoint s{j, c.calibration.front().q[j], c.calibration.front().q[j]};
    for (const View &v : c.calibration) {
      s.lo = std::min(s.lo, v.q[j]);
      s.hi = std::max(s.hi, v.q[j]);
    }
    if (s.hi - s.lo < c.data_check.min_joint_range)
      still.push_back(s);
  }
  return still;
}

/*
  The calibrated model's predicted error on the workspace's motions `pairs` from its error model
  (errorModel(): the estimated parameters' covariance and the held ones' tolerances; to first order
  its mean square per pair is d^T W d, a weighted sum of chi-squares with the eigenvalues of L^T W L,
  cov(d) = L L^T) against the nominal model's error there (nominalOnWorkspace()), and the chance that
  the calibrated model is the worse.
*/
vpRobotSelfCalibration::WorkspaceError judgeWorkspace(const Context &c, const Result &res, ErrorModel em,
                                                      const std::vector<std::pair<vpColVector, vpColVector>> &pairs)
{
  const Eigen::Index N = em.covariance.rows();
  Eigen::MatrixXd Wt = Eigen::MatrixXd::Zero(N, N), Wr = Wt;
  for (const auto &p : pairs) {
    const Eigen::MatrixXd J = errorJacobian(em, p.first, p.second);
    Wt += J.topRows(3).transpose() * J.topRows(3) / static_cast<double>(pairs.size());
    Wr += J.bottomRows(3).transpose() * J.bottomRows(3) / static_cast<double>(pairs.size());
  }
  const NominalError ne = nominalOnWorkspace(c, em, pairs);
  const std::vector<std::string> names = res.calibrated.getParameterNames();
  const Eigen::Index E = static_cast<Eigen::Index>(em.estimated.size());
  for (Eigen::Index h = 0; h < static_cast<Eigen::Index>(em.held.size()); ++h) {
    const std::string &name = names[em.held[static_cast<size_t>(h)]];
    em.covariance(E + h, E + h) *= isTranslation(name) ? ne.factor_t : ne.factor_r;
  }
  const Eigen::Vector2d worse = chanceWorse(c, res, em, ne, pairs);
  errorWithThePrior(c, res, ne, names, em);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (em.covariance + em.covariance.transpose()));
  const Eigen::MatrixXd L = es.eigenvectors() * es.eigenvalues().cwiseMax(0).cwiseSqrt().asDiagonal();
  auto weights = [&L](const Eigen::MatrixXd &W) {
    const Eigen::MatrixXd R = L.transpose() * W * L;
    return Eigen::VectorXd(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(0.5 * (R + R.transpose())).eigenvalues());
  };
  const Eigen::VectorXd lt = weights(Wt), lr = weights(Wr);
  vpRobotSelfCalibration::WorkspaceError w;
  w.computed = true;
  w.calibrated_t = std::sqrt(lt.cwiseMax(0).sum());
  w.calibrated_r = std::sqrt(lr.cwiseMax(0).sum());
  w.bound_t = std::sqrt(vpSelfCalib::weightedChi2Quantile(lt, kWorkspaceZ));
  w.bound_r = std::sqrt(vpSelfCalib::weightedChi2Quantile(lr, kWorkspaceZ));
  w.nominal_t = std::sqrt(std::max(0.0, ne.workspace.t));
  w.nominal_r = std::sqrt(std::max(0.0, ne.workspace.r));
  w.worse_t = worse(0);
  w.worse_r = worse(1);
  w.scale_left_out = em.scale_sd > 0;
  return w;
}

bool worseOnWorkspace(const vpRobotSelfCalibration::WorkspaceError &w)
{
  return w.worse_t > kWorkspaceLevel || w.worse_r > kWorkspaceLevel;
}

//! "5.0 mm / 5.37 mrad RMS, 90 % bound 6.6 mm / 7.36 mrad" and the nominal model's, for a message.
std::string workspaceFigures(const vpRobotSelfCalibration::WorkspaceError &w)
{
  return fixed(1e3 * w.calibrated_t, 1) + " mm / " + fixed(1e3 * w.calibrated_r, 2) + " mrad RMS, 90 % bound " +
         fixed(1e3 * w.bound_t, 1) + " mm / " + fixed(1e3 * w.bound_r, 2) + " mrad" +
         (w.scale_left_out ? "; the nominal scale's error, common to both, left out" : "") +
         ") exceeds the nominal model's error there (" + fixed(1e3 * w.nominal_t, 1) + " mm / " +
         fixed(1e3 * w.nominal_r, 2) +
         " mrad, estimated from its misfit on the calibration views' motions extrapolated by the tolerances; "
         "the chance that the calibrated model is the worse, given the two models' difference on those motions: " +
         fixed(100 * w.worse_t, 0) + " % / " + fixed(100 * w.worse_r, 0) + " %, above " +
         fixed(100 * kWorkspaceLevel, 0) + " %)";
}

/*
  The calibrated model against the nominal one where it is used (judgeWorkspace()): when the 90 %
  bound of the calibrated model's RMS error, in position or in rotation, exceeds the nominal model's,
  these views do not make the model better than the nominal one there (a doubt). The predicted
  error on the calibration views' own pixels (checkPredicted) does not see it: those views determine
  the model near their configurations. The camera's motions with the camera on the flange; with the
  camera in the world, the target's motions (what the camera sees of it, less the camera's own pose,
  which no motion of the arm moves).
  A joint that barely moves in the views (stillJoints()) is judged where they hold it: the model is
  calibrated for that joint's position, and no set of views of it at one angle tells how its own
  placement and those beyond it change with the angle; the parameters left at nominal and the
  estimated ones that absorb them near the views err there as much as the nominal model does, or
  more (simulated PUMA 560, joint 5 within +-0.5 deg, 12 views, 0.5 px, calibrate's default
  tolerances: 0.4-0.6 mm on held-out views at that angle, about half the nominal model's, and
  5.6-13 mm over joint 5's whole range, against the nominal model's 6.9-9.6). Over the whole range it is a warning that says so, with
  both figures and the views to add.
*/
void checkWorkspace(const Context &c, Result &res, const vpMatrix &C)
{
  const std::vector<unsigned int> &id = res.identifiability.identified;
  const Eigen::Index P = static_cast<Eigen::Index>(id.size());
  if (P == 0 || C.getRows() < id.size() || c.calibration.size() < 2)
    return;
  ErrorModel em;
  if (!errorModel(c, res, C, em))
    return;
  const std::vector<vpColVector> q =
      vpKinematicIdentification::randomConfigurations(c.guess, 2 * kWorkspacePairs, 0x6d6f7469, 1);
  const std::vector<StillJoint> still = stillJoints(c);
  std::vector<std::pair<vpColVector, vpColVector>> pairs, held_pairs;
  for (unsigned int k = 0; k < kWorkspacePairs; ++k) {
    pairs.emplace_back(q[2 * k], q[2 * k + 1]);
    std::pair<vpColVector, vpColVector> h = pairs.back();
    for (const StillJoint &s : still) { // the same draw, mapped to the range the views cover
      const vpKinematicChain::Joint &joint = c.guess.getJoints()[s.joint];
      const double span = joint.max - joint.min;
      for (vpColVector *v : {&h.first, &h.second})
        (*v)[s.joint] = s.lo + (s.hi - s.lo) * (span > 0 ? ((*v)[s.joint] - joint.min) / span : 0.5);
    }
    held_pairs.push_back(h);
  }
  res.workspace = judgeWorkspace(c, res, em, still.empty() ? pairs : held_pairs);
  std::string within;
  for (const StillJoint &s : still) {
    const std::string name = "j" + std::to_string(s.joint + 1);
    within += (within.empty() ? "" : ", ") + name + " within " + fixed(s.lo * 180.0 / M_PI, 2) + " to " +
              fixed(s.hi * 180.0 / M_PI, 2) + " deg";
    res.workspace.joints_within.push_back({name, s.lo, s.hi, s.joint});
  }
  const std::string motions = c.bundle.eye_to_hand ? "the target's motions in the camera" : "the camera's motions";
  const std::string held =
      em.held.empty() ? std::string()
                      : " and the " + std::to_string(em.held.size()) + " parameters the data do not determine";
  if (worseOnWorkspace(res.workspace))
    add(res, vpSelfCalibDataCheck::DOUBT, "workspace-worse-than-nominal",
        "away from its " + std::to_string(c.calibration.size()) + " calibration views the calibrated model is not " +
            "reliably better than the nominal one: its predicted error on " + motions + " between configurations "
            "spread over the joint limits" + (still.empty() ? "" : " (" + within + ", as in the views)") +
            " (from its covariance" + held + ": " + workspaceFigures(res.workspace) +
            ": these views determine the " + std::to_string(P) + " parameters estimated only near their own "
            "configurations. Add views that move every joint (visp-selfcalib plan --from DATASET proposes them), "
            "or keep the nominal model");
  if (still.empty())
    return;
  res.workspace_full_range = judgeWorkspace(c, res, em, pairs);
  if (worseOnWorkspace(res.workspace_full_range))
    add(res, vpSelfCalibDataCheck::WARNING, "workspace-limited-by-still-joints",
        "the model is calibrated for " + within + " (their range in the calibration views): with " +
            (still.size() == 1 ? "that joint" : "those joints") + " anywhere in " +
            (still.size() == 1 ? "its" : "their") + " limits, its predicted error on " + motions + " (" +
            workspaceFigures(res.workspace_full_range) + ": use it with " +
            (still.size() == 1 ? "that joint" : "those joints") + " where the views held " +
            (still.size() == 1 ? "it" : "them") + ", or add views that move " +
            (still.size() == 1 ? "it" : "them") + " (visp-selfcalib plan --from DATASET proposes them)");
}

/*
  The hand-eye method on joint readings: the end-effector poses are the nominal kinematics' at the
  readings, taken as exact, and eMc is fitted to the views through them: the kinematics' error goes into
  eMc, which reproduces the views near their configurations and carries that error to every other one.
  The model's motions are then no better than the nominal kinematics', and can be worse than the nominal
  model's away from the views (simulated Viper850, 8 views: 24.6 mm on the camera's motions against the
  nominal model's 6.5). The data cannot tell how much (the views do not separate the kinematics' error from
  eMc's): a warning that says so and names the method that calibrates the kinematics.
*/
void checkHandEyeOnJoints(const Context &c, Result &res)
{
  if (c.options.method != vpRobotSelfCalibration::HAND_EYE)
    return;
  const auto joints_only = [](const View &v) { return v.q.size() > 0 && !v.has_fMe; };
  if (std::any_of(c.calibration.begin(), c.calibration.end(), joints_only))
    handEyeOnJoints(c.dataset.camera_mount == vpSelfCalibDataset::CAMERA_IN_WORLD, res);
}

// How well the calibrated and the nominal model explain the calibration views (same rule for both).
void checkFit(const Context &c, Result &res)
{
  if (c.calibration.size() < 2)
    return;
  const bool opencv = !res.bundle.opencv_distortion.empty();
  const bool lens = !c.dataset.opencv_distortion.empty();
  // Eye-to-hand with joints: each model's views as camera poses in the effector frame.
  const bool e2h = c.bundle.eye_to_hand;
  const std::vector<View> &cal = c.calibration;
  const vpCalibrationVerifier::Result nominal = vpCalibrationVerifier::verify(
      c.guess, c.dataset.cam,
      e2h ? eyeToHandViews(c.guess, lens ? undistorted(cal, lensOf(c.dataset)) : cal)
          : (lens ? undistorted(cal, lensOf(c.dataset)) : cal),
      c.dataset.yardstick);
  const std::vector<View> cal_calibrated =
      opencv ? undistorted(cal, lensOf(res.camera, res.bundle.opencv_distortion)) : cal;
  const vpCalibrationVerifier::Result calibrated = vpCalibrationVerifier::verify(
      res.calibrated, res.camera, e2h ? eyeToHandViews(res.calibrated, cal_calibrated) : cal_calibrated,
      c.dataset.yardstick);
  res.fit_nominal_rms = nominal.reprojection_rms;
  res.fit_calibrated_rms = calibrated.reprojection_rms;
  // (eye-to-hand: the predicted error is the eye-in-hand relative poses', not this set-up's)
  if (c.options.method != vpRobotSelfCalibration::HAND_EYE && !e2h && c.calibration.front().q.size() > 0)
    checkPredicted(c, res, calibrated.points);
  // The workspace's motions: the camera's on the flange, the target's with the camera in the world.
  if (c.options.method != vpRobotSelfCalibration::HAND_EYE && c.calibration.front().q.size() > 0)
    checkWorkspace(c, res,
                   c.options.method == vpRobotSelfCalibration::PAPER ? res.identification.covariance
                                                                       : res.bundle.covariance);
  // Eye-to-hand hand-eye with the poses' error modelled: the "nominal" bMc is a start fitted to these
  // views with the poses taken as exact (PnP), and the calibrated one, which corrects the poses, need
  // not fit the raw poses better (simulated 2 mm / 2 mrad: 2-12 % worse, with bMc within 1 sd of the
  // truth); the robot-error and noise checks judge it.
  const bool start_fitted = c.options.method == vpRobotSelfCalibration::HAND_EYE &&
                            c.dataset.camera_mount == vpSelfCalibDataset::CAMERA_IN_WORLD &&
                            !res.bundle.pose_corrections.empty();
  if (!start_fitted && worse(calibrated, nominal, noiseOf(c, res)))
    add(res, vpSelfCalibDataCheck::DOUBT, "fit-worse-than-nominal",
        "the calibrated model explains its own calibration views worse than the nominal model (reprojection " +
            fixed(calibrated.reprojection_rms, 3) + " px against " + fixed(nominal.reprojection_rms, 3) +
            " px, points triangulated through each model): the estimate did not converge to the data; check the "
            "robot model, the camera and the pairing of joints and images");
}

// The held-out views: the calibrated model must explain them and measure the yardstick as the nominal one does, or better.
void checkHeldOut(const Context &c, Result &res)
{
  if (!res.verified)
    return;
  if (worse(res.after, res.before, noiseOf(c, res)))
    add(res, vpSelfCalibDataCheck::DOUBT, "held-out-worse-than-nominal",
        "the calibrated model explains the " + std::to_string(c.verification.size()) +
            " held-out views worse than the nominal model (reprojection " + fixed(res.after.reprojection_rms, 3) +
            " px against " + fixed(res.before.reprojection_rms, 3) +
            " px): it fits the calibration views but does not generalise; add calibration views or estimate fewer "
            "parameters");
  const double L = c.dataset.yardstick.length;
  if (res.after.has_yardstick && res.before.has_yardstick &&
      res.after.yardstick_error > std::max(2.0 * res.before.yardstick_error, kYardstickTolerance * L))
    add(res, vpSelfCalibDataCheck::DOUBT, "yardstick-not-reproduced",
        "the calibrated model measures the yardstick on the held-out views " +
            fixed(1e3 * res.after.yardstick_error, 2) + " mm off (" +
            fixed(100.0 * res.after.yardstick_error / L, 2) + " % of its length; the nominal model: " +
            fixed(1e3 * res.before.yardstick_error, 2) +
            " mm): the scale or the model is wrong; check the yardstick's length and end ids");
}

// The residuals' noise level: stated against measured.
void checkNoise(const Context &c, Result &res)
{
  if (c.options.method == vpRobotSelfCalibration::PAPER)
    return;
  const vpKinematicBundleAdjustment::Result &b = res.bundle;
  const bool measured_pixel = c.noise.measure_pixel_sd;
  if (res.measured.pixel_sd > c.options.max_pixel_noise)
    add(res, vpSelfCalibDataCheck::DOUBT, "residuals-too-large",
        "the residuals measure an image noise of " + fixed(res.measured.pixel_sd, 2) + " px, above " +
            fixed(c.options.max_pixel_noise, 2) +
            " px: the model does not explain the images (a wrong robot model or camera, joints that do not belong "
            "to their images, a moving scene, wrong matches, or a wrong camera_mount: the dataset says " +
            (c.dataset.camera_mount == vpSelfCalibDataset::CAMERA_IN_WORLD
                 ? "world; a camera on the flange is camera_mount: effector"
                 : "effector; a camera fixed in the world, looking at a target on the tool, is camera_mount: world") +
            ")");
  else if (b.covariance_scaled &&
           (!measured_pixel || measuredNoiseDiffers(res.noise.pixel_sd, res.measured.pixel_sd)))
    add(res, vpSelfCalibDataCheck::WARNING, "noise-mismatch",
        "the residuals contradict the stated noise: sigma0 " + fixed(b.sigma0, 2) + " is outside its 99.9 % interval [" +
            fixed(b.sigma0_low, 2) + ", " + fixed(b.sigma0_high, 2) + "]; the image noise is " +
            fixed(res.measured.pixel_sd, 3) + " px where " + fixed(res.noise.pixel_sd, 3) +
            " px was stated: the standard deviations are scaled by sigma0" +
            (measured_pixel ? std::string() : " (calibrate --pixel-sd auto measures the noise)"));
}

/*
  The multi-view step's own fit (multiViewMisfit) when the bundle adjustment that started from it
  does not explain the images either (its sigma0 above its 99.9 % interval): a doubt, with what to
  do. A bundle adjustment at the noise has left the start's misfit behind (the hand-eye method on a
  plane with f self-calibrated: the reconstruction's sigma0 1.6 with 11 of 824 observations
  rejected, the final fit at 0.18 px with none).
*/
void checkMultiViewFit(const Context &c, Result &res)
{
  const vpMultiViewReconstruction::Result &mv = res.multiview;
  const vpKinematicBundleAdjustment::Result &b = res.bundle;
  const unsigned int total = mv.num_observations + mv.num_outliers;
  if (multiViewMisfit(mv) && b.sigma0_high > 0 && b.sigma0 > b.sigma0_high)
    add(res, vpSelfCalibDataCheck::DOUBT, "multiview-misfit",
        "the multi-view reconstruction, the start of the calibration, does not explain the images: sigma0 " +
            fixed(mv.sigma0, 2) + " (99.9 % interval [" + fixed(mv.sigma0_low, 2) + ", " + fixed(mv.sigma0_high, 2) +
            "]) with " + std::to_string(mv.num_outliers) + " of " + std::to_string(total) +
            " observations rejected, and the bundle adjustment that started from it neither (sigma0 " +
            fixed(b.sigma0, 2) + "): a reconstruction in a local minimum (on a flat scene, views on the wrong one "
            "of a plane's two motions), or wrong matches with an image noise of " +
            fixed(mv.measured.pixel_sd, 3) + " px where " + fixed(c.noise.pixel_sd, 3) +
            " px was stated; measure the noise (calibrate --pixel-sd auto), give the board's layout "
            "(--board-geometry) or add views of a scene with depth");
}

/*
  Without robot error modelled: are the residuals image noise, or each view's own camera
  displacement? The bundle adjustment re-posed each camera alone (Result::reposed_rms, repose_f).
  Beyond the F test's 99.9 % quantile the robot's poses (or joints) are off by more than the image
  noise explains; when re-posing also removes half the residuals' variance or more, that error
  dominates them: the estimate absorbs it and its sds, computed as if the residuals were independent
  image noise, are too small whatever sigma0 scaling (a doubt; a warning otherwise). Residuals below
  kResidualFloorPx are below what any image measures (noise-free simulated data, where the kinematic
  prior's pull leaves 1e-6 to 1e-3 px of structured misfit): whatever their structure, nothing to say.
*/
constexpr double kResidualFloorPx = 0.01;

void checkUnmodelledRobotError(const Context &c, Result &res)
{
  if (c.options.method == vpRobotSelfCalibration::PAPER)
    return;
  const vpKinematicBundleAdjustment::Result &b = res.bundle;
  if (b.reposed_views == 0 || !(b.repose_f > b.repose_f_limit) || b.repose_rms_before < kResidualFloorPx)
    return;
  const bool dominant = b.reposed_rms <= b.repose_rms_before / std::sqrt(2.0); // over the same views
  const std::string what = c.options.method == vpRobotSelfCalibration::HAND_EYE ? "controller poses" : "joint readings";
  add(res, dominant ? vpSelfCalibDataCheck::DOUBT : vpSelfCalibDataCheck::WARNING, "robot-error-unmodelled",
      "the residuals are " + std::string(dominant ? "mostly" : "partly") +
          " a displacement of each view's own camera, not image noise: re-posing each camera alone brings the "
          "reprojection RMS from " +
          fixed(b.repose_rms_before, 3) + " to " + fixed(b.reposed_rms, 3) + " px (camera corrections " +
          fixed(1e3 * b.repose_rms_translation, 1) + " mm / " + fixed(1e3 * b.repose_rms_rotation, 1) +
          " mrad rms; F " + fixed(b.repose_f, 1) + " against " + fixed(b.repose_f_limit, 2) + " at 99.9 %). The " +
          what + " are taken as exact and are not: the estimate absorbs their error" +
          (dominant ? " and its standard deviations are too small" : std::string()) +
          (c.options.method == vpRobotSelfCalibration::HAND_EYE
               ? "; state the robot's pose error (calibrate --pose-sd T,R or the dataset's robot_error; a serial "
                 "arm's absolute accuracy is a few mm and mrad; the camera corrections above overstate it where a "
                 "rotation and a translation of the camera look alike)"
               : "; model the joint readings' error and the model's own residual (calibrate's default measures "
                 "them; or state them: --joint-sd, the dataset's robot_error joint_sd, --pose-sd T,R)"));
}

/*
  The robot part of the residuals: the corrections of the controller poses (or joints) against the
  stated robot error. Estimated corrections are shrunk towards 0, so their chi-square stays below its
  number of values when the stated error is right. Above its 99.9 % quantile the robot's error is
  larger than stated (a warning: the sds are scaled by sigma0, which includes it); corrections that
  average kRobotRatioDoubt times their stated sd or more (one part: the translations, the rotations
  or the joints) stand in for what the model does not explain, an eMc or kinematics left off, and the
  estimate rests on them (a doubt).
*/
constexpr double kRobotRatioDoubt = 3.0;

void checkRobotError(const Context &c, Result &res)
{
  const vpKinematicBundleAdjustment::Result &b = res.bundle;
  if (robotCorrectionsWithinStated(b))
    return;
  std::string stated;
  if (!b.pose_corrections.empty())
    stated = "pose corrections rms " + fixed(1e3 * b.pose_rms_translation, 1) + " mm / " +
             fixed(1e3 * b.pose_rms_rotation, 1) + " mrad";
  if (!b.joint_corrections.empty())
    stated += std::string(stated.empty() ? "" : ", ") + "joint corrections rms " + fixed(1e3 * b.joint_rms, 2) +
              " mrad";
  if (c.options.method == vpRobotSelfCalibration::HAND_EYE || !b.pose_corrections.empty()) {
    // The per-view correction's prior: the controller poses' error (hand-eye), else the model's residual.
    const bool hand_eye = c.options.method == vpRobotSelfCalibration::HAND_EYE;
    const double t = hand_eye ? c.noise.pose_sd_translation : c.noise.model_sd_translation;
    const double r = hand_eye ? c.noise.pose_sd_rotation : c.noise.model_sd_rotation;
    stated += " against a stated pose error of " + fixed(1e3 * t, 1) + " mm / " + fixed(1e3 * r, 1) + " mrad";
  }
  const std::string figures = stated + "; chi-square " + fixed(b.robot_chi2, 0) + " for " +
                              std::to_string(b.robot_dof) + " values, 99.9 % bound " + fixed(robotChi2Bound(b), 0);
  if (robotCorrectionsStandIn(b))
    add(res, vpSelfCalibDataCheck::DOUBT, "robot-corrections-stand-in",
        "the robot's poses had to be corrected by " + fixed(b.robot_rms_ratio, 1) +
            " times their stated error on average (" + figures +
            "): the corrections stand in for what the model does not explain, an eMc or kinematics the "
            "adjustment left off; check the hand-eye guess and the robot model, or state the robot's real "
            "pose error (--pose-sd)");
  else
    add(res, vpSelfCalibDataCheck::WARNING, "robot-error-above-stated",
        "the robot's poses are off by more than stated (" + figures + "): " +
            (b.covariance_scaled ? "the standard deviations are scaled by sigma0 (" + fixed(b.sigma0, 2) + ")"
                                 : std::string("the standard deviations may be too small")) +
            "; give the robot's real pose error (--pose-sd)");
}

/*
  The robot's error the bundle method measured (joint readings, the model's residual) against what
  a real arm has (kJointErrorPlausible, kModelErrorPlausible; a joint level beyond its bound with
  corrections that look like reading noise is a low-cost arm's: robotErrorImplausible()): a level
  beyond them is no reading noise but a misfit the model cannot explain (a parameter held at a
  wrong value, a wrong robot model, joints paired with another view's image), which the
  corrections absorb instead of the parameters. The pipeline then takes the readings as exact (the checks of a trusted run judge the
  misfit); a level that still stands beyond them is a doubt. A level stated by the caller is not
  questioned. A level asked to be measured that could not be (the corrections at the prior's level
  leaving the estimate undetermined) makes the result the trusted run's, with its warning; when
  the trusted run failed, this run, its readings taken as exact inside the adjustment, says it.
*/
void checkMeasuredRobotError(const Context &c, Result &res)
{
  using namespace vpSelfCalib;
  if (c.options.method != vpRobotSelfCalibration::BUNDLE_ADJUSTMENT)
    return;
  const vpSelfCalibNoiseModel &n = res.bundle.noise;
  if (!c.options.trust_robot && robotErrorNotMeasured(n))
    // The trusted run failed: this run stands; the level guessed is the options' and the dataset's.
    res.findings.push_back(
        robotErrorNotMeasuredFinding(levelsOf(vpRobotSelfCalibration::noiseModel(c.options, c.dataset), JOINT_ERROR).r));
  // A joint level beyond a well-built arm's is a low-cost arm's reading noise when its corrections
  // look like it (jointErrorStructure()), and a misfit when they do not or when it is beyond any arm's.
  // Judged once for res.bundle's corrections: the run's drop decision may have judged them already.
  const double joint_level = levelsOf(n, JOINT_ERROR).r;
  const bool beyond = n.measure_joint_sd && n.joint_sd_origin == vpSelfCalibNoiseModel::MEASURED &&
                      joint_level > kJointErrorPlausible;
  if (beyond && !res.joint_error_structure.judged)
    res.joint_error_structure = jointErrorStructure(res.bundle, n, c.calibration);
  const JointErrorStructure &structure = res.joint_error_structure;
  const bool joints = beyond && (joint_level > kJointErrorImpossible || !structure.readingNoise());
  const bool model = n.measure_model_sd && n.model_sd_origin == vpSelfCalibNoiseModel::MEASURED &&
                     (n.model_sd_translation > kModelErrorPlausible || n.model_sd_rotation > kModelErrorPlausible);
  if (!joints && !model)
    return;
  std::string what;
  if (joints)
    what = "the joint readings' error " + fixed(1e3 * joint_level, 2) + " mrad (" +
           (joint_level > kJointErrorImpossible
                ? "no arm's readings are off by more than " + fixed(1e3 * kJointErrorImpossible, 0) + " mrad"
                : "beyond a well-built arm's " + fixed(1e3 * kJointErrorPlausible, 1) +
                      " mrad, and the joint corrections show " + structure.describe()) +
           ")";
  if (model)
    what += std::string(joints ? ", " : "") + "the model's residual " + fixed(1e3 * n.model_sd_translation, 2) +
            " mm / " + fixed(1e3 * n.model_sd_rotation, 2) + " mrad (at most about " +
            fixed(1e3 * kModelErrorPlausible, 1) + " mm / " + fixed(1e3 * kModelErrorPlausible, 1) + " mrad)";
  add(res, vpSelfCalibDataCheck::DOUBT, "robot-error-implausible",
      "the robot's error measured from the corrections is beyond what a real arm has: " + what +
          ". The corrections absorb a misfit the model cannot explain: a parameter held at a wrong value "
          "(--fix), a wrong robot model or eMc guess, or joints paired with another view's images. Check "
          "them; if the readings really are that noisy, state their level (calibrate --joint-sd RAD)");
}

/*
  The controller poses' error the hand-eye method measured (calibrate's default, --pose-sd auto)
  against what a serial arm's controller is usually off (a few mm and mrad uncalibrated, ISO 9283
  figures): beyond kPoseErrorPlausible in either part the per-view corrections may absorb a misfit of
  another kind. The likeliest is the camera's mount declared the wrong way (a fixed camera on the
  flange: each view's camera pose then needs a correction the size of the arm's motion; the real
  eye-to-hand set declared effector measures 23 mm / 14 mrad, the eye-in-hand set declared world
  83 mm / 353 mrad), then poses paired with other views' images, wrong matches (the industrial grid
  described 9 x 9: 25 mm / 27 mrad), or poses in another frame. A warning, not a doubt: the level
  alone does not tell them from a real arm that far off (the industrial_calibration set, whose wrist
  poses fit one eMc only to about 8 mm and 20 mrad, measures 22 mm / 27 mrad with its focal length
  self-calibrated and its right mount). Beyond kPoseErrorImpossible (5 cm or 0.1 rad: 6 deg, twice
  the industrial set's translation and four times its rotation) no working controller is that far
  off: a doubt (the eye-in-hand set declared world measures 83 mm / 353 mrad). A level stated by the
  caller is not questioned.
*/
constexpr double kPoseErrorPlausibleT = 0.01, kPoseErrorPlausibleR = 0.01; // m, rad
constexpr double kPoseErrorImpossibleT = 0.05, kPoseErrorImpossibleR = 0.1; // m, rad

void checkMeasuredPoseError(const Context &c, Result &res)
{
  if (c.options.method != vpRobotSelfCalibration::HAND_EYE || res.bundle.pose_corrections.empty())
    return;
  const vpSelfCalibNoiseModel &n = res.noise;
  if (n.pose_sd_origin != vpSelfCalibNoiseModel::MEASURED ||
      !(n.pose_sd_translation > kPoseErrorPlausibleT || n.pose_sd_rotation > kPoseErrorPlausibleR))
    return;
  const bool world = c.dataset.camera_mount == vpSelfCalibDataset::CAMERA_IN_WORLD;
  const bool impossible = n.pose_sd_translation > kPoseErrorImpossibleT || n.pose_sd_rotation > kPoseErrorImpossibleR;
  add(res, impossible ? vpSelfCalibDataCheck::DOUBT : vpSelfCalibDataCheck::WARNING, "pose-error-implausible",
      "the controller poses' error measured from the corrections, " + fixed(1e3 * n.pose_sd_translation, 1) +
          " mm / " + fixed(1e3 * n.pose_sd_rotation, 1) + " mrad, is beyond what an arm's controller is usually off " +
          (impossible ? "(a few mm and mrad), and beyond any working one's (" + fixed(1e3 * kPoseErrorImpossibleT, 0) +
                            " mm or " + fixed(1e3 * kPoseErrorImpossibleR, 0) + " mrad): the corrections absorb a "
                            "misfit of another kind, the likeliest a wrong camera_mount: the dataset says "
                      : "(a few mm and mrad; here over " + fixed(1e3 * kPoseErrorPlausibleT, 0) + " mm or " +
                            fixed(1e3 * kPoseErrorPlausibleR, 0) + " mrad): if this arm's poses really are that far "
                            "off, the result stands (its sd counts them); else the corrections absorb a misfit of "
                            "another kind, the likeliest a wrong camera_mount: the dataset says ") +
          (world ? "world (a camera fixed in the world, looking at a target on the tool) and a camera on the flange "
                   "looking at a fixed scene is camera_mount: effector"
                 : "effector (a camera on the flange, looking at a fixed scene) and a camera fixed in the world "
                   "looking at a target on the tool is camera_mount: world") +
          "; then poses paired with other views' images, points matched wrongly (a board described with other rows "
          "or columns than it has: check --board), or poses that are not the flange in the robot's base frame (fMe: "
          "m and rad)");
}
} // namespace

double robotChi2Bound(const vpKinematicBundleAdjustment::Result &bundle)
{
  double low = 0, high = 0;
  vpSelfCalib::sigma0Interval(bundle.robot_dof, low, high);
  return high * high * bundle.robot_dof;
}

bool robotCorrectionsWithinStated(const vpKinematicBundleAdjustment::Result &bundle)
{
  return bundle.robot_dof == 0 || !(bundle.robot_chi2 > robotChi2Bound(bundle));
}

bool robotCorrectionsStandIn(const vpKinematicBundleAdjustment::Result &bundle)
{
  return !robotCorrectionsWithinStated(bundle) && bundle.robot_rms_ratio >= kRobotRatioDoubt;
}

bool measuredNoiseDiffers(double stated, double measured)
{
  return measured >= vpSelfCalib::kPixelSdFloor && (measured > 1.25 * stated || measured < 0.8 * stated);
}

/*
  The declared size of the target's layout (the board spec's spacing, a tag's side) against what the
  views measure (vpKinematicBundleAdjustment's layout_scale s, its sd from the covariance): a layout
  declared at the wrong size moves every camera position by (s - 1) times its distance from the
  target, which eMc (bMc) and the target's pose absorb but for what the robot's metric motion does
  not allow. The sd counts the robot's random pose error, not its systematic part, which biases s
  too: on the real Franka set (8 views, a few mm of pose error) the printed size measures
  1.12 +- 0.04, and 27 % too large a declared size 0.88 +- 0.03. Hence a doubt beyond 3 sd and
  kLayoutScaleDoubt, above that bias (simulated eye-to-hand sets with a 20-25 % error: 0.79-0.81,
  4-8 sd), a warning beyond 3 sd and kLayoutScaleWarning, and a warning when the sd exceeds
  kLayoutScaleDoubt / 3 (the views could not have told a wrong size of kLayoutScaleDoubt).
*/
constexpr double kLayoutScaleDoubt = 0.15, kLayoutScaleWarning = 0.02;
/*
  Without known points the yardstick's length is measured instead (two scene points, a board's first
  row without --board-geometry): its measure carries the robot's bias and the scene's own
  reconstruction error. On the Franka set the printed 0.0236 m row measures 1.152 +- 0.042, 0.03 m
  0.907 +- 0.027 and 0.02 m 1.359 +- 0.094, a common bias of 1.15; simulated boards 25 % too large
  and 20 % too small measure 0.793 +- 0.053 and 1.240 +- 0.059. Hence a doubt beyond 3 sd and 20 %.
*/
constexpr double kYardstickScaleDoubt = 0.20;

void checkLayoutScale(const Context &c, Result &res)
{
  const vpKinematicBundleAdjustment::Result &b = res.bundle;
  if (!b.has_layout_scale)
    return;
  // Without known points the yardstick was measured (its declared length, often a board's first row).
  const bool layout = !c.options.bundle.known_points.empty();
  const vpSelfCalibDataset::Yardstick &y = c.dataset.yardstick;
  const std::string what = layout ? "the target's layout" : "the yardstick (points " + std::to_string(y.id_a) +
                                                              " and " + std::to_string(y.id_b) + ", " +
                                                              fixed(y.length, 4) + " m)";
  const std::string size = layout ? "declared size" : "declared length";
  const double s = b.layout_scale, off = std::fabs(s - 1), sd = b.layout_scale_sd;
  const std::string measured = "the views measure " + what + " at " + fixed(s, 3) + " +- " + fixed(sd, 3) +
                               " times its " + size + " (" + fixed(100 * off, 1) + " % " +
                               (s > 1 ? "larger" : "smaller") + ", " + fixed(off / sd, 1) + " sd)";
  const std::string check = layout ? "Check the board spec (the spacing or the tag's side as printed, in m: measure it)"
                                   : "Check the yardstick's length (a board's first row without --board-geometry: "
                                     "the spacing of the board spec, as printed, in m: measure it)";
  if (std::isfinite(sd) && off > 3 * sd && off > (layout ? kLayoutScaleDoubt : kYardstickScaleDoubt))
    add(res, vpSelfCalibDataCheck::DOUBT, "board-size-mismatch",
        measured + ": the camera's mount and the target's pose absorb a wrong size. " + check +
            " and calibrate again with the size times " + fixed(s, 3));
  else if (std::isfinite(sd) && off > 3 * sd && off > kLayoutScaleWarning)
    add(res, vpSelfCalibDataCheck::WARNING, "board-size-uncertain",
        measured + ", from the robot's motion, whose systematic pose error biases this measure by several % "
                   "(not counted in its sd): if the board's size was not measured, measure it (a wrong size "
                   "moves the camera's mount by the error times the distance to the target)");
  else if (!(sd <= kLayoutScaleDoubt / 3))
    add(res, vpSelfCalibDataCheck::WARNING, "board-size-not-determined",
        "the views do not measure the size of " + what + " (its scale +- " +
            (std::isfinite(sd) ? fixed(100 * sd, 1) + " %" : std::string("undetermined")) +
            "): a board declared at the wrong size would go unseen, the camera's mount and the target's pose "
            "absorbing it. Measure the printed size, or add views that change the distance to the target and "
            "rotate the flange about points away from it");
}

/*
  The kinematic prior against the data (vpKinematicBundleAdjustment::Result::prior_groups): a group of
  corrections whose squared prior residuals exceed their 99.9 % quantile under the prior (the
  corrections drawn with the prior's sd) says the arm's errors are larger than the tolerances / k
  stated: the prior then pulls the corrections it holds toward nominal more than the arm allows, and
  the sd, which it narrows, understate the error. A doubt when, besides, the prior's sd are off by a
  factor of 2 or more (sqrt(chi2 / redundancy)): below it the sd the prior narrows understate the error
  by less than that. bench-estset, tolerances 3 sd of the simulated errors and K = 3 (the prior the
  errors' own distribution but for the base's errors, which the joints' corrections take up): the
  largest group's factor 1.27-1.41 on average over the rows, one run of 80 over its quantile at 1.8;
  tolerances 3 times tighter: a factor of about 3 and more.
*/
constexpr double kPriorContradicted = 2.0;

void checkKinematicPrior(const Context &c, Result &res)
{
  std::string off;
  for (const auto &g : res.bundle.prior_groups)
    if (g.chi2 > g.quantile && g.redundancy > 0 && g.chi2 >= kPriorContradicted * kPriorContradicted * g.redundancy)
      off += (off.empty() ? "" : ", ") + g.name + " " + fixed(std::sqrt(g.chi2 / g.redundancy), 1) +
             " times the prior's sd (sum of squares " + fixed(g.chi2, 1) + ", expected " + fixed(g.redundancy, 1) +
             ", 99.9 % quantile " + fixed(g.quantile, 1) + ")";
  if (off.empty())
    return;
  add(res, vpSelfCalibDataCheck::DOUBT, "kinematic-prior-contradicted",
      "the data put the kinematic corrections beyond the prior's sd (the tolerance / " +
          fixed(res.bundle.kinematic_prior, 1) + "): " + off +
          ". The arm's errors are larger than its stated tolerances (" + fixed(1e3 * c.options.tolerance_translation, 1) +
          " mm, " + fixed(1e3 * c.options.tolerance_rotation, 1) + " mrad; eMc " +
          fixed(1e3 * c.options.tolerance_hand_eye_translation, 1) + " mm, " +
          fixed(1e3 * c.options.tolerance_hand_eye_rotation, 1) + " mrad): the prior holds the corrections the data barely see too near nominal, and the sd, which it "
          "narrows, understate the error. State the arm's real tolerances (calibrate --tolerance T,R or "
          "T,R,T_eMc,R_eMc) or calibrate without the prior (--kinematic-prior off)");
}

void handEyeOnJoints(bool world, Result &res)
{
  add(res, vpSelfCalibDataCheck::WARNING, "hand-eye-kinematics-nominal",
      std::string("the hand-eye method takes the nominal kinematics at the joint readings as exact: their error "
                  "goes into ") +
          (world ? "bMc and the target's pose" : "eMc") +
          ", which then reproduces these views but carries that error to other configurations (the model can be "
          "worse than the nominal one away from the views), and " + (world ? "their" : "its") +
          " sd do not count it (an error the views share, not a noise of each). The bundle method (--method bundle) calibrates the "
          "kinematics with " + (world ? "bMc" : "eMc") + "; use hand-eye on joint readings only with kinematics known "
          "to be accurate");
}

void assess(const Context &c, Result &res)
{
  if (res.status != vpRobotSelfCalibration::OK)
    return;
  checkTolerance(c, res);
  checkHandEyeOnJoints(c, res);
  checkFit(c, res);
  checkHeldOut(c, res);
  checkNoise(c, res);
  checkMultiViewFit(c, res);
  checkRobotError(c, res);
  checkMeasuredRobotError(c, res);
  checkMeasuredPoseError(c, res);
  checkUnmodelledRobotError(c, res);
  checkLayoutScale(c, res);
  checkKinematicPrior(c, res);
  std::string doubts;
  for (const Finding &f : res.findings)
    if (f.severity == vpSelfCalibDataCheck::DOUBT)
      doubts += (doubts.empty() ? "" : "; ") + f.message;
  if (!doubts.empty()) {
    res.status = vpRobotSelfCalibration::DOUBTFUL;
    res.message += "; doubtful: " + doubts;
    // The warnings often say why (a thin scene, the noise level): said with the doubt, as a failed
    // run's message says them with the failure.
    std::string warnings;
    for (const Finding &f : res.findings)
      if (f.severity == vpSelfCalibDataCheck::WARNING)
        warnings += (warnings.empty() ? "" : "; ") + f.message;
    if (!warnings.empty())
      res.message += "; warnings: " + warnings;
  }
}
} // namespace vpSelfCalibPipeline
