/*
 * ViSP SelfCalib: kinematic bundle adjustment (beyond the paper). See the header for the model.
 */
#include <visp3/selfcalib/vpKinematicBundleAdjustment.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <set>
#include <sstream>

#include <ceres/ceres.h>

#include "../core/vpSelfCalibCeres.h"
#include "../core/vpSelfCalibMath.h"
#include "../core/vpSelfCalibGeometry.h"
#include "../core/vpSelfCalibObservations.h"

using namespace vpSelfCalib;

namespace
{
/*!
  Covariance of the `kept` blocks (in order, tangent coordinates) with the 3-D `eliminated` blocks
  marginalized: the inverse of the Schur complement of J^T J, J from Problem::Evaluate on one
  thread. Computed here rather than by ceres::Covariance (SPARSE_QR): SuiteSparseQR runs on TBB's
  threads, and its sums, so the last digits of every standard deviation, changed from run to run
  once another library had started TBB workers. False when the information is singular (relative
  eigenvalue of the diagonally scaled complement below 1e-15) or a point is not determined.
*/
bool marginalCovariance(ceres::Problem &problem, const std::vector<double *> &kept,
                        const std::vector<double *> &eliminated, Eigen::MatrixXd &cov)
{
  ceres::Problem::EvaluateOptions eo;
  eo.parameter_blocks = kept;
  eo.parameter_blocks.insert(eo.parameter_blocks.end(), eliminated.begin(), eliminated.end());
  eo.num_threads = 1;
  ceres::CRSMatrix J;
  if (!problem.Evaluate(eo, nullptr, nullptr, nullptr, &J))
    return false;
  const int nA = J.num_cols - 3 * static_cast<int>(eliminated.size());
  if (nA <= 0)
    return false;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(nA, nA);
  std::vector<Eigen::Matrix<double, Eigen::Dynamic, 3>> B(eliminated.size(), Eigen::Matrix<double, Eigen::Dynamic, 3>::Zero(nA, 3));
  std::vector<Eigen::Matrix3d> C(eliminated.size(), Eigen::Matrix3d::Zero());
  std::vector<std::pair<int, double>> a;
  for (int r = 0; r < J.num_rows; ++r) {
    a.clear();
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    int point = -1;
    for (int k = J.rows[r]; k < J.rows[r + 1]; ++k) {
      const int c = J.cols[k];
      if (c < nA)
        a.push_back({c, J.values[k]});
      else {
        const int i = (c - nA) / 3;
        if (point >= 0 && point != i)
          return false; // a residual on two eliminated points: not this problem's structure
        point = i;
        p((c - nA) % 3) = J.values[k];
      }
    }
    for (const auto &x : a)
      for (const auto &y : a)
        H(x.first, y.first) += x.second * y.second;
    if (point >= 0) {
      for (const auto &x : a)
        B[point].row(x.first) += x.second * p.transpose();
      C[point] += p * p.transpose();
    }
  }
  for (size_t i = 0; i < C.size(); ++i) {
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(C[i]);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 1e-12 * ldlt.vectorD().maxCoeff()))
      return false;
    H.noalias() -= B[i] * ldlt.solve(B[i].transpose());
  }
  const Eigen::VectorXd d = H.diagonal();
  if (!(d.minCoeff() > 0))
    return false;
  const Eigen::VectorXd scale = d.cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd Hs = scale.asDiagonal() * H * scale.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (Hs + Hs.transpose()));
  if (eig.info() != Eigen::Success || !(eig.eigenvalues().minCoeff() > 1e-15 * eig.eigenvalues().maxCoeff()))
    return false;
  cov = scale.asDiagonal() *
        (eig.eigenvectors() * eig.eigenvalues().cwiseInverse().asDiagonal() * eig.eigenvectors().transpose()) *
        scale.asDiagonal();
  return cov.allFinite();
}

constexpr int kIntrinsics = 5; // p_x, mu, u0, v0, k_ud
const char *const kIntrinsicNames[kIntrinsics] = {"fx", "mu", "u0", "v0", "kud"};

//! Pose of one view and its derivatives with respect to the estimated corrections.
struct ViewState {
  Eigen::Matrix3d RT;                          // fRc^T
  Eigen::Vector3d tf;                          // camera origin in f
  Eigen::Matrix<double, 3, Eigen::Dynamic> A;  // fRc^T J_t
  Eigen::Matrix<double, 3, Eigen::Dynamic> C;  // fRc^T J_phi
};

void computeView(const vpKinematicChain &chain, const std::vector<unsigned int> &id, const vpColVector &q,
                 bool with_jacobian, ViewState &v)
{
  const Rigid M = rigidFromVisp(chain.get_fMc(q));
  v.RT = M.R.transpose();
  v.tf = M.t;
  if (!with_jacobian)
    return;
  const vpMatrix J = chain.getJacobian(q);
  const int P = static_cast<int>(id.size());
  Eigen::Matrix<double, 3, Eigen::Dynamic> Jt(3, P), Jr(3, P);
  for (int c = 0; c < P; ++c)
    for (int a = 0; a < 3; ++a) {
      Jt(a, c) = J[a][id[c]];
      Jr(a, c) = J[a + 3][id[c]];
    }
  v.A = v.RT * Jt;
  v.C = v.RT * Jr;
}

/*
  Hand-eye-only mode: fMc = fMe eMc D(t, r) with fMe given (trusted kinematics) and only the eMc
  correction estimated. With A = fMe eMc (nominal): d p / dt = R_A, d phi / dr = R_A J_l(r) (the
  chain's formula for its last block). id holds the chain indices of the estimated eMc components.
*/
void computeHandEyeView(const vpKinematicChain &chain, const std::vector<unsigned int> &id, const Rigid &fMe,
                        bool with_jacobian, ViewState &v)
{
  const unsigned int first = chain.getNumParameters() - vpKinematicChain::kBlockSize;
  const Rigid A = fMe * rigidFromPose(chain.get_eMc_pose());
  const Rigid M = rigidFromVisp(toVisp(fMe) * chain.get_eMc_corrected());
  v.RT = M.R.transpose();
  v.tf = M.t;
  if (!with_jacobian)
    return;
  const Eigen::Vector3d r(chain.getParameters()[first + 3], chain.getParameters()[first + 4],
                          chain.getParameters()[first + 5]);
  const Eigen::Matrix3d Jr = A.R * leftJacobianSO3(r);
  const int P = static_cast<int>(id.size());
  Eigen::Matrix<double, 3, Eigen::Dynamic> Jt = Eigen::Matrix<double, 3, Eigen::Dynamic>::Zero(3, P),
                                          Jp = Eigen::Matrix<double, 3, Eigen::Dynamic>::Zero(3, P);
  for (int c = 0; c < P; ++c) {
    const unsigned int a = id[c] - first;
    if (a < 3)
      Jt.col(c) = A.R.col(a);
    else
      Jp.col(c) = Jr.col(a - 3);
  }
  v.A = v.RT * Jt;
  v.C = v.RT * Jp;
}

/*
  Projection of X (f) through a view: (u, v), and on request its derivatives with respect to the
  corrections (2 x P), the intrinsics (2 x 5) and X (2 x 3). in = (p_x, mu, u0, v0, k_ud).
*/
bool project(const ViewState &v, const double *in, const double *Xp, double uv[2], double *Jrho, double *Jin,
             double *JX, int P)
{
  const Eigen::Vector3d Xc = v.RT * (Eigen::Map<const Eigen::Vector3d>(Xp) - v.tf);
  if (!(Xc(2) > 1e-9))
    return false;
  const double fx = in[0], mu = in[1], k = in[4];
  const double x = Xc(0) / Xc(2), y = Xc(1) / Xc(2), r2 = x * x + y * y, g = 1 + k * r2;
  uv[0] = in[2] + fx * x * g;
  uv[1] = in[3] + mu * fx * y * g;
  if (!Jrho && !Jin && !JX)
    return true;
  Eigen::Matrix2d Dxy;
  Dxy << fx * (g + 2 * k * x * x), fx * 2 * k * x * y, mu * fx * 2 * k * x * y, mu * fx * (g + 2 * k * y * y);
  Eigen::Matrix<double, 2, 3> Dc;
  Dc << 1 / Xc(2), 0, -x / Xc(2), 0, 1 / Xc(2), -y / Xc(2);
  const Eigen::Matrix<double, 2, 3> D = Dxy * Dc;
  if (JX) {
    Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> Jx(JX);
    Jx = D * v.RT;
  }
  if (Jrho) {
    Eigen::Map<Eigen::Matrix<double, 2, Eigen::Dynamic, Eigen::RowMajor>> Jr(Jrho, 2, P);
    Jr = D * (-v.A + skew(Xc) * v.C);
  }
  if (Jin) {
    Eigen::Map<Eigen::Matrix<double, 2, kIntrinsics, Eigen::RowMajor>> Ji(Jin);
    Ji << x * g, 0, 1, 0, fx * x * r2, mu * y * g, fx * y * g, 0, 1, mu * fx * y * r2;
  }
  return true;
}

/*
  The chain at the solver's current corrections, and every view's pose and Jacobian, refreshed once
  per evaluation point before Ceres evaluates the residuals (instead of once per observation).
*/
class KinematicState : public ceres::EvaluationCallback
{
public:
  KinematicState(const vpKinematicChain &start, const std::vector<unsigned int> &id, const std::vector<vpColVector> &q,
                 const std::vector<Rigid> &fMe = std::vector<Rigid>())
    : chain(start), base(start.getParameters()), id(id), q(q), fMe(fMe), rho(id.size()), views(q.size())
  {
    for (size_t i = 0; i < id.size(); ++i)
      rho[i] = base[id[i]];
  }
  void PrepareForEvaluation(bool evaluate_jacobians, bool new_point) override
  {
    if (new_point || (evaluate_jacobians && !has_jacobians_))
      update(evaluate_jacobians);
  }
  void update(bool with_jacobians)
  {
    vpColVector p = base;
    for (size_t i = 0; i < id.size(); ++i)
      p[id[i]] = rho[i];
    chain.setParameters(p);
    for (size_t k = 0; k < q.size(); ++k)
      if (fMe.empty())
        computeView(chain, id, q[k], with_jacobians, views[k]);
      else
        computeHandEyeView(chain, id, fMe[k], with_jacobians, views[k]);
    has_jacobians_ = with_jacobians;
  }

  vpKinematicChain chain;
  vpColVector base;
  std::vector<unsigned int> id;
  std::vector<vpColVector> q;
  std::vector<Rigid> fMe; //!< hand-eye-only mode: the trusted end-effector poses (else empty)
  std::vector<double> rho;
  std::vector<ViewState> views;

private:
  bool has_jacobians_ = false;
};

//! Whitened reprojection error of one observation; blocks: corrections (P), intrinsics (5), point (3).
class ObservationCost : public ceres::CostFunction
{
public:
  ObservationCost(const KinematicState *state, unsigned int view, double u, double v, double sd)
    : state_(state), view_(view), u_(u), v_(v), w_(1 / sd)
  {
    set_num_residuals(2);
    mutable_parameter_block_sizes()->push_back(static_cast<int>(state->id.size()));
    mutable_parameter_block_sizes()->push_back(kIntrinsics);
    mutable_parameter_block_sizes()->push_back(3);
  }
  bool Evaluate(double const *const *p, double *r, double **J) const override
  {
    const int P = static_cast<int>(state_->id.size());
    double uv[2];
    if (!project(state_->views[view_], p[1], p[2], uv, J ? J[0] : nullptr, J ? J[1] : nullptr, J ? J[2] : nullptr, P))
      return false;
    r[0] = (uv[0] - u_) * w_;
    r[1] = (uv[1] - v_) * w_;
    if (J)
      for (int b = 0; b < 3; ++b)
        if (J[b]) {
          const int n = 2 * (b == 0 ? P : (b == 1 ? kIntrinsics : 3));
          for (int i = 0; i < n; ++i)
            J[b][i] *= w_;
        }
    return true;
  }

private:
  const KinematicState *state_;
  unsigned int view_;
  double u_, v_, w_;
};

//! (|X_a - X_b| - L) / sd: the yardstick fixes the scale.
struct YardstickCost {
  YardstickCost(double length, double sd) : L(length), w(1 / sd) {}
  template <typename T> bool operator()(const T *a, const T *b, T *r) const
  {
    const T dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    r[0] = (ceres::sqrt(dx * dx + dy * dy + dz * dz) - T(L)) * T(w);
    return true;
  }
  double L, w;
};

//! s^T (rho - rho0) / |s|^2 / 1e-8: the relative scale of the model held at its start value.
class ScaleCost : public ceres::CostFunction
{
public:
  ScaleCost(const Eigen::VectorXd &s, const std::vector<double> &rho0) : s_(s / s.squaredNorm() / 1e-8), rho0_(rho0)
  {
    set_num_residuals(1);
    mutable_parameter_block_sizes()->push_back(static_cast<int>(s.size()));
  }
  bool Evaluate(double const *const *p, double *r, double **J) const override
  {
    r[0] = 0;
    for (int i = 0; i < s_.size(); ++i)
      r[0] += s_(i) * (p[0][i] - rho0_[i]);
    if (J && J[0])
      for (int i = 0; i < s_.size(); ++i)
        J[0][i] = s_(i);
    return true;
  }

private:
  Eigen::VectorXd s_;
  std::vector<double> rho0_;
};

/*
  Scale direction: the corrections s (and a centre c) with J_t s + c = t_k, J_phi s = 0 for every
  view: to first order they scale every camera position about c and leave orientations unchanged.
*/
Eigen::VectorXd scaleDirection(const KinematicState &st)
{
  const int P = static_cast<int>(st.id.size());
  const int m = static_cast<int>(st.q.size());
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(6 * m, P + 3);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(6 * m);
  for (int k = 0; k < m; ++k) {
    const Eigen::Matrix3d R = st.views[k].RT.transpose();
    A.block(6 * k, 0, 3, P) = R * st.views[k].A;
    A.block(6 * k + 3, 0, 3, P) = R * st.views[k].C;
    A.block(6 * k, P, 3, 3).setIdentity();
    b.segment<3>(6 * k) = st.views[k].tf;
  }
  return A.colPivHouseholderQr().solve(b).head(P);
}

struct Obs {
  unsigned int view;
  int id;
  double u, v;
};

void intrinsicsFrom(const vpCameraParameters &cam, double in[kIntrinsics])
{
  in[0] = cam.get_px();
  in[1] = cam.get_py() / cam.get_px();
  in[2] = cam.get_u0();
  in[3] = cam.get_v0();
  in[4] = cam.get_projModel() == vpCameraParameters::perspectiveProjWithDistortion ? cam.get_kud() : 0.0;
}

vpCameraParameters cameraFrom(const double in[kIntrinsics], bool distortion)
{
  vpCameraParameters c;
  if (distortion)
    // ViSP also stores the inverse model k_du; its first-order value is -k_ud.
    c.initPersProjWithDistortion(in[0], in[1] * in[0], in[2], in[3], in[4], -in[4]);
  else
    c.initPersProjWithoutDistortion(in[0], in[1] * in[0], in[2], in[3]);
  return c;
}

vpKinematicBundleAdjustment::Result run(const vpKinematicChain &start, const vpCameraParameters &camera,
                                        const std::vector<vpSelfCalibDataset::View> &views,
                                        const vpSelfCalibDataset::Yardstick &yardstick,
                                        const std::map<int, vpColVector> &points0,
                                        const vpKinematicBundleAdjustment::Options &opt, bool solve)
{
  using KBA = vpKinematicBundleAdjustment;
  opt.check();
  const QuietCeres quiet;
  const auto t0 = std::chrono::steady_clock::now();
  const unsigned int m = static_cast<unsigned int>(views.size());
  if (m < 2)
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpKinematicBundleAdjustment: at least 2 views are needed");
  if (!(camera.get_px() > 0) || !(camera.get_py() > 0))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment: the camera needs positive px and py");
  std::vector<vpColVector> q(m);
  std::vector<Rigid> fMe;
  std::map<int, unsigned int> seen;
  for (unsigned int k = 0; k < m; ++k) {
    const bool has_q = views[k].q.size() == start.getNumJoints() && allFinite(views[k].q);
    if (opt.hand_eye_only) {
      if (!views[k].has_fMe && !has_q)
        throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                                   "vpKinematicBundleAdjustment: view " + std::to_string(k) +
                                       " needs an end-effector pose fMe or " + std::to_string(start.getNumJoints()) +
                                       " finite joint values");
      fMe.push_back(rigidFromVisp(views[k].has_fMe ? views[k].fMe : start.get_fMe(views[k].q)));
      if (!fMe.back().R.allFinite() || !fMe.back().t.allFinite())
        throw vpSelfCalibException(vpSelfCalibException::badValue,
                                   "vpKinematicBundleAdjustment: view " + std::to_string(k) + " has a non-finite fMe");
    } else if (!has_q)
      throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                                 "vpKinematicBundleAdjustment: view " + std::to_string(k) + " needs " +
                                     std::to_string(start.getNumJoints()) + " finite joint values");
    q[k] = views[k].q;
    std::set<int> ids;
    for (const auto &o : views[k].points) {
      if (!std::isfinite(o.ip.get_u()) || !std::isfinite(o.ip.get_v()))
        throw vpSelfCalibException(vpSelfCalibException::badValue,
                                   "vpKinematicBundleAdjustment: view " + std::to_string(k) + " has a non-finite pixel");
      if (!ids.insert(o.id).second)
        throw vpSelfCalibException(vpSelfCalibException::badValue, "vpKinematicBundleAdjustment: view " +
                                                                       std::to_string(k) + " has point id " +
                                                                       std::to_string(o.id) + " twice");
      ++seen[o.id];
    }
  }
  std::map<int, Eigen::Vector3d> X0;
  for (const auto &e : points0) {
    if (e.second.size() != 3 || !allFinite(e.second))
      throw vpSelfCalibException(vpSelfCalibException::badValue, "vpKinematicBundleAdjustment: point " +
                                                                     std::to_string(e.first) +
                                                                     " is not a finite 3-vector");
    if (seen[e.first] >= 2)
      X0[e.first] = vec3(e.second);
  }
  PointStore X(X0);

  KBA::Result res;
  res.chain = start;
  res.camera = camera;
  res.sd.resize(start.getNumParameters());

  const std::vector<std::string> names = start.getParameterNames();
  if (opt.hand_eye_only) {
    // The eMc correction, but for the components the caller fixes; the kinematics are trusted.
    const unsigned int first = start.getNumParameters() - vpKinematicChain::kBlockSize;
    for (unsigned int i = 0; i < start.getNumParameters(); ++i) {
      const bool fixed = std::find(opt.fixed.begin(), opt.fixed.end(), names[i]) != opt.fixed.end();
      if (i >= first && !fixed)
        res.identifiability.identified.push_back(i);
      else
        res.identifiability.unidentifiable.push_back(
            {i, names[i], fixed ? "fixed by the caller" : "hand-eye-only mode: the robot's kinematics are trusted"});
    }
    for (const std::string &f : opt.fixed)
      if (std::find(names.begin(), names.end(), f) == names.end())
        throw vpSelfCalibException(vpSelfCalibException::badValue,
                                   "vpKinematicBundleAdjustment: unknown fixed parameter '" + f + "'");
    res.identifiability.rank = static_cast<unsigned int>(res.identifiability.identified.size());
  } else {
    // Estimated corrections: independent for the relative poses of the views at the start model.
    std::vector<vpKinematicIdentification::Measurement> rel;
    const vpHomogeneousMatrix fMc0 = start.get_fMc(q[0]);
    for (unsigned int k = 1; k < m; ++k) {
      vpKinematicIdentification::Measurement me;
      me.q = q[k];
      me.q_ref = q[0];
      me.M = start.get_fMc(q[k]).inverse() * fMc0;
      rel.push_back(me);
    }
    vpKinematicIdentification::Options io;
    io.rank_tolerance = opt.rank_tolerance;
    io.fixed = opt.fixed;
    res.identifiability = vpKinematicIdentification::analyse(start, rel, io);
  }
  const std::vector<unsigned int> &id = res.identifiability.identified;
  const int P = static_cast<int>(id.size());

  std::vector<Obs> obs;
  for (unsigned int k = 0; k < m; ++k)
    for (const auto &o : views[k].points)
      if (X.count(o.id))
        obs.push_back({k, o.id, o.ip.get_u(), o.ip.get_v()});
  double in[kIntrinsics];
  intrinsicsFrom(camera, in);
  std::vector<int> free_in;
  if (opt.intrinsics & KBA::FX)
    free_in.push_back(0);
  if (opt.intrinsics & KBA::ASPECT)
    free_in.push_back(1);
  if (opt.intrinsics & KBA::PRINCIPAL_POINT) {
    free_in.push_back(2);
    free_in.push_back(3);
  }
  if (opt.intrinsics & KBA::DISTORTION)
    free_in.push_back(4);
  const bool distortion = (opt.intrinsics & KBA::DISTORTION) || in[4] != 0;
  const size_t unknowns = P + free_in.size() + 3 * X.size();
  if (P == 0 || 2 * obs.size() <= unknowns) {
    res.status = KBA::TOO_FEW_OBSERVATIONS;
    res.message = std::to_string(obs.size()) + " observations of points seen twice for " + std::to_string(unknowns) +
                  " unknowns";
    return res;
  }

  KinematicState state(start, id, q, fMe);
  state.update(true);
  const std::vector<double> rho0 = state.rho;
  const bool has_yardstick = yardstick.isSet() && X.count(yardstick.id_a) && X.count(yardstick.id_b);
  // Hand-eye-only: the metric end-effector motion fixes the scale; no gauge constraint.
  const Eigen::VectorXd scale_dir = opt.hand_eye_only ? Eigen::VectorXd() : scaleDirection(state);

  // Observations of points behind their camera at the start cannot be evaluated: left out.
  std::vector<bool> inlier(obs.size(), true);
  for (size_t n = 0; n < obs.size(); ++n) {
    double uv[2];
    inlier[n] = project(state.views[obs[n].view], in, X[obs[n].id].data(), uv, nullptr, nullptr, nullptr, P);
  }
  dropPoorlyObservedPoints(obs, inlier);
  ceres::Solver::Summary summary;
  ceres::Problem::Options po;
  po.evaluation_callback = &state;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  std::unique_ptr<ceres::Manifold> subset;
  if (!free_in.empty() && free_in.size() < kIntrinsics) {
    std::vector<int> constant;
    for (int i = 0; i < kIntrinsics; ++i)
      if (std::find(free_in.begin(), free_in.end(), i) == free_in.end())
        constant.push_back(i);
    subset.reset(new ceres::SubsetManifold(kIntrinsics, constant));
  }
  std::unique_ptr<ceres::Problem> problem;
  RobustSchedule schedule;
  if (solve) {
    std::vector<double> start_errors;
    for (size_t n = 0; n < obs.size(); ++n) {
      double uv[2];
      if (inlier[n] && project(state.views[obs[n].view], in, X[obs[n].id].data(), uv, nullptr, nullptr, nullptr, P))
        start_errors.push_back(std::hypot(uv[0] - obs[n].u, uv[1] - obs[n].v) / opt.pixel_sd);
    }
    schedule = robustSchedule(opt.loss != vpMultiViewReconstruction::LOSS_NONE, opt.loss_scale, opt.outlier_threshold,
                              start_errors);
  } else
    schedule.scales = {0};
  for (size_t stage = 0; stage < schedule.scales.size(); ++stage) {
    const double loss_scale = schedule.scales[stage];
    const bool robust = loss_scale > 0;
    problem.reset(new ceres::Problem(po));
    auto order = std::make_shared<ceres::ParameterBlockOrdering>();
    for (size_t n = 0; n < obs.size(); ++n) {
      if (!inlier[n])
        continue;
      double *Xp = X[obs[n].id].data();
      problem->AddResidualBlock(new ObservationCost(&state, obs[n].view, obs[n].u, obs[n].v, opt.pixel_sd),
                                robust ? makeLoss(static_cast<RobustLoss>(opt.loss), loss_scale) : nullptr, state.rho.data(), in, Xp);
      // The yardstick residual links its two ends: they stay in the reduced system.
      const bool end = has_yardstick && (obs[n].id == yardstick.id_a || obs[n].id == yardstick.id_b);
      order->AddElementToGroup(Xp, end ? 1 : 0);
    }
    if (!problem->HasParameterBlock(in)) {
      res.status = KBA::TOO_FEW_OBSERVATIONS;
      res.message = "every observation was rejected as an outlier";
      res.chain = state.chain;
      return res;
    }
    const bool use_yardstick = has_yardstick && problem->HasParameterBlock(X[yardstick.id_a].data()) &&
                               problem->HasParameterBlock(X[yardstick.id_b].data());
    res.scale_source =
        opt.hand_eye_only ? KBA::SCALE_ROBOT_MOTION : (use_yardstick ? KBA::SCALE_YARDSTICK : KBA::SCALE_NOMINAL);
    if (use_yardstick)
      problem->AddResidualBlock(new ceres::AutoDiffCostFunction<YardstickCost, 1, 3, 3>(
                                    new YardstickCost(yardstick.length, opt.yardstick_sd)),
                                nullptr, X[yardstick.id_a].data(), X[yardstick.id_b].data());
    else if (!opt.hand_eye_only)
      problem->AddResidualBlock(new ScaleCost(scale_dir, rho0), nullptr, state.rho.data());
    // One group per block: within a group Ceres orders blocks by address, and the address order of
    // separately allocated blocks changes from run to run (and so would the last digits).
    order->AddElementToGroup(state.rho.data(), 2);
    order->AddElementToGroup(in, 3);
    if (free_in.empty())
      problem->SetParameterBlockConstant(in);
    else if (subset)
      problem->SetManifold(in, subset.get());
    if (!solve)
      break;
    ceres::Solver::Options so = solverOptions(opt.max_iterations, opt.tight, ceres::DENSE_SCHUR);
    so.linear_solver_ordering = order;
    so.num_threads = static_cast<int>(opt.num_threads);
    vpSelfCalib::solve(so, problem.get(), &summary);
    res.iterations += static_cast<unsigned int>(summary.iterations.size());
    state.update(true); // the callback last saw the final trial point, not necessarily the solution
    if (!summary.IsSolutionUsable())
      break;
    if (static_cast<int>(stage) == schedule.trim_after) {
      for (size_t n = 0; n < obs.size(); ++n) {
        double uv[2];
        inlier[n] = project(state.views[obs[n].view], in, X[obs[n].id].data(), uv, nullptr, nullptr, nullptr, P) &&
                    std::hypot(uv[0] - obs[n].u, uv[1] - obs[n].v) <= opt.outlier_threshold * opt.pixel_sd;
      }
      dropPoorlyObservedPoints(obs, inlier);
    }
  }
  res.seconds_solve = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  // Results at the final state.
  res.chain = state.chain;
  res.camera = cameraFrom(in, distortion);
  std::set<int> kept;
  double sum = 0;
  for (size_t n = 0; n < obs.size(); ++n) {
    double uv[2];
    if (!inlier[n] ||
        !project(state.views[obs[n].view], in, X[obs[n].id].data(), uv, nullptr, nullptr, nullptr, P)) {
      inlier[n] = false;
      ++res.num_outliers;
      continue;
    }
    sum += std::pow(uv[0] - obs[n].u, 2) + std::pow(uv[1] - obs[n].v, 2);
    ++res.num_observations;
    kept.insert(obs[n].id);
  }
  res.rms = res.num_observations ? std::sqrt(sum / (2.0 * res.num_observations)) : 0;
  const double dof = 2.0 * res.num_observations - static_cast<double>(P + free_in.size() + 3 * kept.size());
  res.sigma0 = dof > 0 ? res.rms / opt.pixel_sd * std::sqrt(2.0 * res.num_observations / dof) : 0;
  for (int idp : kept) {
    vpColVector v(3);
    for (unsigned int a = 0; a < 3; ++a)
      v[a] = X[idp](a);
    res.points[idp] = v;
  }
  for (int i : free_in) {
    res.intrinsic_names.push_back(kIntrinsicNames[i]);
  }
  res.intrinsics.resize(static_cast<unsigned int>(free_in.size()));
  res.intrinsics_sd.resize(static_cast<unsigned int>(free_in.size()));
  for (size_t i = 0; i < free_in.size(); ++i)
    res.intrinsics[static_cast<unsigned int>(i)] = in[free_in[i]];
  if (solve && !summary.IsSolutionUsable()) {
    res.status = KBA::NO_CONVERGENCE;
    res.message = summary.message.empty() ? summary.BriefReport() : summary.message;
    return res;
  }

  // Covariance of the corrections and the estimated intrinsics, points marginalized.
  if (opt.covariance) {
    const auto tc = std::chrono::steady_clock::now();
    std::vector<double *> kept = {state.rho.data()}, eliminated;
    if (!free_in.empty())
      kept.push_back(in);
    // The yardstick's ends are linked by their residual: kept in the complement (as in the solve).
    std::set<const double *> ends;
    if (has_yardstick && problem->HasParameterBlock(X[yardstick.id_a].data()) &&
        problem->HasParameterBlock(X[yardstick.id_b].data()))
      for (int e : {yardstick.id_a, yardstick.id_b}) {
        kept.push_back(X[e].data());
        ends.insert(X[e].data());
      }
    for (const auto &e : X.index())
      if (!ends.count(X[e.first].data()) && problem->HasParameterBlock(X[e.first].data()))
        eliminated.push_back(X[e.first].data());
    const int N = P + static_cast<int>(free_in.size());
    Eigen::MatrixXd full;
    if (marginalCovariance(*problem, kept, eliminated, full)) {
      res.covariance.resize(N, N);
      for (int a = 0; a < N; ++a)
        for (int b = 0; b < N; ++b)
          res.covariance[a][b] = full(a, b);
      for (int a = 0; a < P; ++a)
        res.sd[id[a]] = std::sqrt(std::max(0.0, res.covariance[a][a]));
      for (size_t a = 0; a < free_in.size(); ++a) {
        res.intrinsics_sd[static_cast<unsigned int>(a)] = std::sqrt(std::max(0.0, res.covariance[P + a][P + a]));
        if (free_in[a] == 0)
          res.fx_sd = res.intrinsics_sd[static_cast<unsigned int>(a)];
      }
      for (int a = 0; a < P; ++a)
        res.covariance_names.push_back(names[id[a]]);
      for (int i : free_in)
        res.covariance_names.push_back(kIntrinsicNames[i]);
      res.has_covariance = true;
    }
    res.seconds_covariance = std::chrono::duration<double>(std::chrono::steady_clock::now() - tc).count();
    if (!res.has_covariance) {
      res.status = KBA::RANK_DEFICIENT;
      res.message = opt.hand_eye_only
                        ? "the information matrix of the hand-eye correction and intrinsics is singular: the "
                          "end-effector rotations do not determine eMc (all about parallel axes?); add poses "
                          "rotating about another axis"
                        : "the information matrix of the corrections and intrinsics is singular: the views do not "
                          "determine them (too few or too similar configurations)";
      return res;
    }
  }
  res.status = KBA::OK;
  std::ostringstream os;
  os << "ok: " << P << " corrections, " << free_in.size() << " intrinsics, " << res.points.size() << " points, "
     << res.num_observations << " observations (" << res.num_outliers << " dropped), rms " << res.rms
     << " px, scale from " << KBA::scaleSourceName(res.scale_source);
  res.message = os.str();
  return res;
}
} // namespace

const char *vpKinematicBundleAdjustment::scaleSourceName(ScaleSource s)
{
  switch (s) {
  case SCALE_YARDSTICK:
    return "the yardstick";
  case SCALE_ROBOT_MOTION:
    return "the robot's metric motion (and the yardstick when seen)";
  default:
    return "the start model (nominal scale: no yardstick)";
  }
}

const char *vpKinematicBundleAdjustment::statusName(Status s)
{
  switch (s) {
  case OK:
    return "ok";
  case TOO_FEW_OBSERVATIONS:
    return "too few observations";
  case RANK_DEFICIENT:
    return "rank deficient";
  case NO_CONVERGENCE:
    return "no convergence";
  }
  return "unknown";
}

void vpKinematicBundleAdjustment::Options::check() const
{
  if (intrinsics > (FX | ASPECT | PRINCIPAL_POINT | DISTORTION))
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpKinematicBundleAdjustment: unknown intrinsics flag");
  if (!(pixel_sd > 0) || !(yardstick_sd > 0) || !(loss_scale > 0) || !(outlier_threshold >= 0) ||
      !std::isfinite(outlier_threshold) || !(rank_tolerance > 0 && rank_tolerance < 1))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment: pixel_sd, yardstick_sd and loss_scale must be positive, "
                               "outlier_threshold non-negative, rank_tolerance in (0, 1)");
  if (max_iterations == 0 || num_threads == 0)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment: max_iterations and num_threads must be at least 1");
}

vpKinematicBundleAdjustment::Result vpKinematicBundleAdjustment::adjust(const vpKinematicChain &start,
                                                                       const vpCameraParameters &camera,
                                                                       const std::vector<vpSelfCalibDataset::View> &views,
                                                                       const vpSelfCalibDataset::Yardstick &yardstick,
                                                                       const std::map<int, vpColVector> &points,
                                                                       const Options &options)
{
  return run(start, camera, views, yardstick, points, options, true);
}

vpKinematicBundleAdjustment::Result vpKinematicBundleAdjustment::information(
    const vpKinematicChain &state, const vpCameraParameters &camera, const std::vector<vpSelfCalibDataset::View> &views,
    const vpSelfCalibDataset::Yardstick &yardstick, const std::map<int, vpColVector> &points, const Options &options)
{
  Options o = options;
  o.covariance = true;
  return run(state, camera, views, yardstick, points, o, false);
}

vpMatrix vpKinematicBundleAdjustment::relativePoseCovariance(const vpKinematicChain &chain,
                                                             const std::vector<unsigned int> &parameters,
                                                             const vpMatrix &covariance, const vpColVector &q_ref,
                                                             const vpColVector &q)
{
  const unsigned int P = static_cast<unsigned int>(parameters.size());
  if (covariance.getRows() < P || covariance.getCols() < P)
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               "vpKinematicBundleAdjustment::relativePoseCovariance: the covariance is smaller than "
                               "the parameter list");
  for (unsigned int i : parameters)
    if (i >= chain.getNumParameters())
      throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                                 "vpKinematicBundleAdjustment::relativePoseCovariance: parameter index out of range");
  const Rigid A = rigidFromVisp(chain.get_fMc(q_ref)), B = rigidFromVisp(chain.get_fMc(q));
  const vpMatrix JA = chain.getJacobian(q_ref), JB = chain.getJacobian(q);
  // c_ref M c = A^-1 B: dt = R_A^T (dt_B - dt_A + [t_B - t_A]x dphi_A), dphi = R_A^T (dphi_B - dphi_A).
  const Eigen::Matrix3d RAt = A.R.transpose(), D = skew(B.t - A.t);
  Eigen::MatrixXd G(6, P), S(P, P);
  for (unsigned int c = 0; c < P; ++c) {
    Eigen::Vector3d tA, tB, pA, pB;
    for (unsigned int a = 0; a < 3; ++a) {
      tA(a) = JA[a][parameters[c]];
      tB(a) = JB[a][parameters[c]];
      pA(a) = JA[a + 3][parameters[c]];
      pB(a) = JB[a + 3][parameters[c]];
    }
    G.block<3, 1>(0, c) = RAt * (tB - tA + D * pA);
    G.block<3, 1>(3, c) = RAt * (pB - pA);
    for (unsigned int d = 0; d < P; ++d)
      S(c, d) = covariance[c][d];
  }
  const Eigen::MatrixXd C = G * S * G.transpose();
  vpMatrix out(6, 6);
  for (unsigned int a = 0; a < 6; ++a)
    for (unsigned int b = 0; b < 6; ++b)
      out[a][b] = C(a, b);
  return out;
}

vpMatrix vpKinematicBundleAdjustment::observationJacobian(const vpKinematicChain &chain,
                                                          const std::vector<unsigned int> &parameters,
                                                          const vpCameraParameters &camera, const vpColVector &q,
                                                          const vpColVector &X, vpColVector &uv)
{
  if (X.size() != 3)
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               "vpKinematicBundleAdjustment::observationJacobian: X must be a 3-vector");
  for (unsigned int i : parameters)
    if (i >= chain.getNumParameters())
      throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                                 "vpKinematicBundleAdjustment::observationJacobian: parameter index out of range");
  ViewState v;
  computeView(chain, parameters, q, true, v);
  double in[kIntrinsics];
  intrinsicsFrom(camera, in);
  const int P = static_cast<int>(parameters.size());
  std::vector<double> Jr(2 * P), Ji(2 * kIntrinsics), JX(6);
  double Xp[3] = {X[0], X[1], X[2]}, p[2];
  uv.resize(2);
  vpMatrix J(2, P + kIntrinsics + 3);
  if (!project(v, in, Xp, p, Jr.data(), Ji.data(), JX.data(), P))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment::observationJacobian: the point is behind the camera");
  uv[0] = p[0];
  uv[1] = p[1];
  for (unsigned int r = 0; r < 2; ++r) {
    for (int c = 0; c < P; ++c)
      J[r][c] = Jr[r * P + c];
    for (int c = 0; c < kIntrinsics; ++c)
      J[r][P + c] = Ji[r * kIntrinsics + c];
    for (int c = 0; c < 3; ++c)
      J[r][P + kIntrinsics + c] = JX[r * 3 + c];
  }
  return J;
}
