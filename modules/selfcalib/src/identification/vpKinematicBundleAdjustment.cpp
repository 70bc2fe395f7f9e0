/*
 * ViSP SelfCalib: kinematic bundle adjustment (beyond the paper). See the header for the model.
 */
#include <visp3/selfcalib/vpKinematicBundleAdjustment.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <memory>
#include <set>
#include <sstream>

#include <Eigen/Geometry>
#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include "../core/vpSelfCalibCamera.h"
#include "../core/vpSelfCalibCeres.h"
#include "../core/vpSelfCalibMath.h"
#include "../core/vpSelfCalibGeometry.h"
#include "../core/vpSelfCalibObservations.h"
#include "../core/vpSelfCalibRange.h"

using namespace vpSelfCalib;

namespace
{
// The intrinsics block: p_x, mu, u0, v0 and up to five distortion coefficients (ViSP's k_ud uses the
// first; OpenCV's k1, k2, p1, p2, k3 all five); the unused ones are held constant.
constexpr int kIntrinsics = kMaxIntrinsics;
const char *const kVispNames[kIntrinsics] = {"fx", "mu", "u0", "v0", "kud", "", "", "", ""};
const char *const kOpenCvNames[kIntrinsics] = {"fx", "mu", "u0", "v0", "k1", "k2", "p1", "p2", "k3"};
//! The lens model of an adjustment's options.
Distortion lensModel(const vpKinematicBundleAdjustment::Options &o)
{
  return o.distortion_model == vpKinematicBundleAdjustment::DISTORTION_OPENCV ? Distortion::OPENCV : Distortion::VISP;
}
const char *intrinsicName(Distortion model, int i)
{
  return model == Distortion::OPENCV ? kOpenCvNames[i] : kVispNames[i];
}

//! Pose of one view and its derivatives with respect to the estimated corrections.
struct ViewState {
  Eigen::Matrix3d RT;                          // fRc^T
  Eigen::Vector3d tf;                          // camera origin in f
  Eigen::Matrix<double, 3, Eigen::Dynamic> A;  // fRc^T J_t
  Eigen::Matrix<double, 3, Eigen::Dynamic> C;  // fRc^T J_phi
  // The same for the view's own correction: its pose correction delta (6, robot pose error) or its
  // joint corrections (n, joint-reading noise).
  Eigen::Matrix<double, 3, Eigen::Dynamic> Ad, Cd;
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
  Full kinematic mode with robot error: the view's own correction c = (dq, delta), dq the joint
  corrections (n_joint values, joint-reading noise), delta = (t, r) a correction of the camera pose
  in its own frame (6 values when camera_delta: the kinematic model's own residual): the pose is
  fMc(q + dq; rho) E(delta), E = [exp([r]x) | t]. With fMc = [R | p]: p' = p + R t, R' = R exp(r);
  dp'/d(rho, dq) = J_t - [R t]x J_phi, dphi'/d(rho, dq) = J_phi, dp'/dt = R, dphi'/dr = R J_l(r).
*/
void computeNoisyView(const vpKinematicChain &chain, const std::vector<unsigned int> &id, const vpColVector &q,
                      const double *c, int n_joint, bool camera_delta, bool with_jacobian, ViewState &v)
{
  vpColVector qe = q;
  for (int i = 0; i < n_joint; ++i)
    qe[static_cast<unsigned int>(i)] += c[i];
  computeView(chain, id, qe, with_jacobian, v);
  const int S = n_joint + (camera_delta ? 6 : 0);
  const Eigen::Matrix3d R = v.RT.transpose();
  if (with_jacobian) {
    v.Ad = Eigen::Matrix<double, 3, Eigen::Dynamic>::Zero(3, S);
    v.Cd = Eigen::Matrix<double, 3, Eigen::Dynamic>::Zero(3, S);
    if (n_joint > 0) {
      const vpMatrix J = chain.getJointJacobian(qe);
      for (int k = 0; k < n_joint; ++k)
        for (int a = 0; a < 3; ++a) {
          v.Ad(a, k) = J[a][k];     // in f for now
          v.Cd(a, k) = J[a + 3][k];
        }
    }
  }
  if (!camera_delta) {
    if (with_jacobian && n_joint > 0) {
      v.Ad = v.RT * v.Ad;
      v.Cd = v.RT * v.Cd;
    }
    return;
  }
  const Rigid E = rigidFromVector(c + n_joint);
  const Eigen::Vector3d Rt = R * E.t;
  const Eigen::Matrix3d RT2 = (R * E.R).transpose();
  if (with_jacobian) {
    const Eigen::Matrix<double, 3, Eigen::Dynamic> Jt = R * v.A, Jr = R * v.C;
    v.A = RT2 * (Jt - skew(Rt) * Jr);
    v.C = RT2 * Jr;
    if (n_joint > 0) {
      const Eigen::Matrix<double, 3, Eigen::Dynamic> Jtq = v.Ad.leftCols(n_joint), Jrq = v.Cd.leftCols(n_joint);
      v.Ad.leftCols(n_joint) = RT2 * (Jtq - skew(Rt) * Jrq);
      v.Cd.leftCols(n_joint) = RT2 * Jrq;
    }
    v.Ad.block(0, n_joint, 3, 3) = E.R.transpose();
    v.Cd.block(0, n_joint + 3, 3, 3) =
        E.R.transpose() * leftJacobianSO3(Eigen::Vector3d(c[n_joint + 3], c[n_joint + 4], c[n_joint + 5]));
  }
  v.tf = v.tf + Rt;
  v.RT = RT2;
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
  Hand-eye-only mode with robot pose error: the view's pose is fMe E(delta) eMc, E = [exp([r]x) | t]
  for delta = (t, r). With fMe = [R_G | t_G] and eMc = [R_c | t_c] (corrected), the camera origin is
  p = R_G (R_E t_c + t) + t_G and its orientation R_G R_E R_c: dp/dt = R_G,
  dp/dr = -R_G [R_E t_c]x J_l(r), dphi/dr = R_G J_l(r), dphi/dt = 0 (left perturbations in f, as the
  chain's Jacobian).
*/
void computePoseNoiseView(const vpKinematicChain &chain, const std::vector<unsigned int> &id, const Rigid &fMe,
                          const double *delta, bool with_jacobian, ViewState &v)
{
  const Rigid E = rigidFromVector(delta);
  computeHandEyeView(chain, id, fMe * E, with_jacobian, v);
  if (!with_jacobian)
    return;
  const Rigid C = rigidFromVisp(chain.get_eMc_corrected());
  const Eigen::Matrix3d Jl = leftJacobianSO3(Eigen::Vector3d(delta[3], delta[4], delta[5]));
  Eigen::Matrix<double, 3, 6> dp, dphi;
  dp.leftCols<3>() = fMe.R;
  dp.rightCols<3>() = -fMe.R * skew(E.R * C.t) * Jl;
  dphi.leftCols<3>().setZero();
  dphi.rightCols<3>() = fMe.R * Jl;
  v.Ad = v.RT * dp;
  v.Cd = v.RT * dphi;
}

/*
  Projection of X (f) through a view and the core camera model (ViSP's k_ud or OpenCV's distortion;
  zero coefficients are the pinhole): (u, v), and on request its derivatives with respect to the
  corrections (2 x P), the intrinsics block (2 x kIntrinsics) and X (2 x 3), row-major.
  in = (p_x, mu, u0, v0, distortion coefficients). With D = d uv / d X_c:
  d uv / d rho = D (-R^T J_t + [X_c]x R^T J_phi), d uv / d X = D R^T.
*/
bool project(Distortion model, const ViewState &v, const double *in, const double *Xp, double uv[2], double *Jrho,
             double *Jin, double *JX, int P, double *Jdelta = nullptr)
{
  const Eigen::Vector3d Xc = v.RT * (Eigen::Map<const Eigen::Vector3d>(Xp) - v.tf);
  const CameraModel camera(model, in);
  Eigen::Vector2d p;
  Eigen::Matrix<double, 2, 3> D;
  double Jm[2 * kIntrinsics];
  if (!camera.project(Xc, p, (Jrho || JX || Jdelta) ? &D : nullptr, Jin ? Jm : nullptr))
    return false;
  if (Jin) { // the model's 2 x size() Jacobian in the 2 x kIntrinsics block (unused coefficients: 0)
    const int n = camera.size();
    for (int r = 0; r < 2; ++r)
      for (int c = 0; c < kIntrinsics; ++c)
        Jin[r * kIntrinsics + c] = c < n ? Jm[r * n + c] : 0.0;
  }
  uv[0] = p(0);
  uv[1] = p(1);
  if (JX) {
    Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> Jx(JX);
    Jx = D * v.RT;
  }
  if (Jrho) {
    Eigen::Map<Eigen::Matrix<double, 2, Eigen::Dynamic, Eigen::RowMajor>> Jr(Jrho, 2, P);
    Jr = D * (-v.A + skew(Xc) * v.C);
  }
  if (Jdelta) {
    Eigen::Map<Eigen::Matrix<double, 2, Eigen::Dynamic, Eigen::RowMajor>> Jd(Jdelta, 2, v.Ad.cols());
    Jd = D * (-v.Ad + skew(Xc) * v.Cd);
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
                 const std::vector<Rigid> &fMe = std::vector<Rigid>(), bool pose_noise = false, int n_joint_ = 0,
                 bool camera_delta_ = false)
    : chain(start), base(start.getParameters()), id(id), q(q), fMe(fMe), rho(id.size()), views(q.size()),
      delta(pose_noise ? q.size() : 0, std::array<double, 6>{0, 0, 0, 0, 0, 0}),
      dq(n_joint_ > 0 || camera_delta_ ? q.size() : 0, std::vector<double>(n_joint_ + (camera_delta_ ? 6 : 0), 0.0)),
      n_joint(n_joint_), camera_delta(camera_delta_)
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
      if (fMe.empty() && !dq.empty())
        computeNoisyView(chain, id, q[k], dq[k].data(), n_joint, camera_delta, with_jacobians, views[k]);
      else if (fMe.empty())
        computeView(chain, id, q[k], with_jacobians, views[k]);
      else if (delta.empty())
        computeHandEyeView(chain, id, fMe[k], with_jacobians, views[k]);
      else
        computePoseNoiseView(chain, id, fMe[k], delta[k].data(), with_jacobians, views[k]);
    has_jacobians_ = with_jacobians;
  }

  vpKinematicChain chain;
  vpColVector base;
  std::vector<unsigned int> id;
  std::vector<vpColVector> q;
  std::vector<Rigid> fMe; //!< hand-eye-only mode: the trusted end-effector poses (else empty)
  std::vector<double> rho;
  std::vector<ViewState> views;
  //! Hand-eye-only mode with robot pose error: each view's pose correction (a parameter block); else empty.
  std::vector<std::array<double, 6>> delta;
  //! Full mode with robot error: each view's correction (joint corrections, then the camera pose
  //! correction; a parameter block); else empty.
  std::vector<std::vector<double>> dq;
  int n_joint = 0;           //!< joint corrections per view
  bool camera_delta = false; //!< a camera pose correction per view (the model's own residual)
  Distortion model = Distortion::VISP; //!< the lens model of the intrinsics block
  //! The size of a view's own correction block (6, the number of joints, or 0).
  int correctionSize() const { return !delta.empty() ? 6 : (!dq.empty() ? static_cast<int>(dq[0].size()) : 0); }
  double *correction(size_t k) { return !delta.empty() ? delta[k].data() : dq[k].data(); }

private:
  bool has_jacobians_ = false;
};

//! Whitened reprojection error of one observation; blocks: corrections (P), intrinsics (kIntrinsics),
//! point (3), and the view's pose correction (6) when robot pose error is modelled.
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
    if (state->correctionSize() > 0)
      mutable_parameter_block_sizes()->push_back(state->correctionSize());
  }
  bool Evaluate(double const *const *p, double *r, double **J) const override
  {
    const int P = static_cast<int>(state_->id.size());
    const int S = state_->correctionSize();
    const int blocks = S > 0 ? 4 : 3;
    double uv[2];
    if (!project(state_->model, state_->views[view_], p[1], p[2], uv, J ? J[0] : nullptr, J ? J[1] : nullptr, J ? J[2] : nullptr, P,
                 J && blocks == 4 ? J[3] : nullptr))
      return false;
    r[0] = (uv[0] - u_) * w_;
    r[1] = (uv[1] - v_) * w_;
    if (J)
      for (int b = 0; b < blocks; ++b)
        if (J[b]) {
          const int n = 2 * (b == 0 ? P : (b == 1 ? kIntrinsics : (b == 2 ? 3 : S)));
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

//! (t / sd_t, theta u / sd_r): the prior of a view's controller-pose correction (robot pose error).
struct PosePriorCost {
  PosePriorCost(double sd_t, double sd_r) : wt(1 / sd_t), wr(1 / sd_r) {}
  template <typename T> bool operator()(const T *d, T *r) const
  {
    for (int i = 0; i < 3; ++i) {
      r[i] = d[i] * T(wt);
      r[3 + i] = d[3 + i] * T(wr);
    }
    return true;
  }
  double wt, wr;
};

//! dq_i / sd_i: the prior of a view's joint corrections (joint-reading noise).
class JointPriorCost : public ceres::CostFunction
{
public:
  explicit JointPriorCost(const std::vector<double> &sd) : sd_(sd)
  {
    set_num_residuals(static_cast<int>(sd.size()));
    mutable_parameter_block_sizes()->push_back(static_cast<int>(sd.size()));
  }
  bool Evaluate(double const *const *p, double *r, double **J) const override
  {
    const size_t n = sd_.size();
    for (size_t i = 0; i < n; ++i)
      r[i] = p[0][i] / sd_[i];
    if (J && J[0])
      for (size_t i = 0; i < n; ++i)
        for (size_t j = 0; j < n; ++j)
          J[0][i * n + j] = i == j ? 1 / sd_[i] : 0.0;
    return true;
  }

private:
  std::vector<double> sd_;
};

//! (X - (R(o_r) L + o_t)) / sd: a point of known geometry L (object frame) and the object's pose o.
struct KnownPointCost {
  KnownPointCost(const vpColVector &L, double sd) : L_{L[0], L[1], L[2]}, w(1 / sd) {}
  template <typename T> bool operator()(const T *o, const T *X, T *r) const
  {
    const T L[3] = {T(L_[0]), T(L_[1]), T(L_[2])};
    T p[3];
    ceres::AngleAxisRotatePoint(o + 3, L, p);
    for (int i = 0; i < 3; ++i)
      r[i] = (X[i] - (p[i] + o[i])) * T(w);
    return true;
  }
  double L_[3], w;
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

//! The intrinsics block of the camera (and, OpenCV model, the given start coefficients).
void intrinsicsFrom(const vpCameraParameters &cam, const vpKinematicBundleAdjustment::Options &o,
                    double in[kIntrinsics])
{
  const CameraModel c = CameraModel::fromVisp(cam);
  std::fill(in, in + kIntrinsics, 0.0);
  for (int i = 0; i < c.size(); ++i)
    in[i] = c.intrinsics()[i];
  if (lensModel(o) == Distortion::OPENCV)
    for (size_t i = 0; i < o.opencv_distortion.size(); ++i)
      in[4 + i] = o.opencv_distortion[i];
}

//! The ViSP camera of the block: ViSP's model with k_ud when distortion, else the pinhole (the
//! OpenCV coefficients, which vpCameraParameters cannot hold, are returned apart).
vpCameraParameters cameraFrom(const double in[kIntrinsics], Distortion model, bool distortion)
{
  return CameraModel(distortion && model == Distortion::VISP ? Distortion::VISP : Distortion::NONE, in).toVisp();
}

using KBA = vpKinematicBundleAdjustment;

/*
  Stage 1, inputs: every view's joints (or, hand-eye-only, its end-effector pose), checked; the
  number of views that see each point id.
*/
void collectViews(const vpKinematicChain &start, const std::vector<vpSelfCalibDataset::View> &views, const KBA::Options &opt,
                  std::vector<vpColVector> &q, std::vector<Rigid> &fMe, std::map<int, unsigned int> &seen)
{
  const unsigned int m = static_cast<unsigned int>(views.size());
  q.assign(m, vpColVector());
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
}

//! Stage 1, inputs: the start points of the ids seen in two views or more, checked.
std::map<int, Eigen::Vector3d> startPoints(const std::map<int, vpColVector> &points0,
                                           std::map<int, unsigned int> &seen)
{
  std::map<int, Eigen::Vector3d> X0;
  for (const auto &e : points0) {
    if (e.second.size() != 3 || !allFinite(e.second))
      throw vpSelfCalibException(vpSelfCalibException::badValue, "vpKinematicBundleAdjustment: point " +
                                                                     std::to_string(e.first) +
                                                                     " is not a finite 3-vector");
    if (seen[e.first] >= 2)
      X0[e.first] = vec3(e.second);
  }
  return X0;
}

/*
  Stage 2, the estimated corrections: hand-eye-only, the eMc correction but for the components the
  caller fixes (the kinematics are trusted; a degenerate motion is a status, not a smaller set); else
  the module's one rule (vpKinematicIdentification::analyseConfigurations): the preference-order
  selection for the relative poses of the views' joints at the NOMINAL model, whatever the start.
*/
vpKinematicIdentification::Identifiability estimatedSet(const vpKinematicChain &start,
                                                        const std::vector<vpColVector> &q, const KBA::Options &opt)
{
  const std::vector<std::string> names = start.getParameterNames();
  if (!opt.hand_eye_only) {
    vpKinematicIdentification::Options io;
    io.rank_tolerance = opt.rank_tolerance;
    io.fixed = opt.fixed;
    return vpKinematicIdentification::analyseConfigurations(start, q, io);
  }
  vpKinematicIdentification::Identifiability ident;
  const unsigned int first = start.getNumParameters() - vpKinematicChain::kBlockSize;
  for (unsigned int i = 0; i < start.getNumParameters(); ++i) {
    const bool fixed = std::find(opt.fixed.begin(), opt.fixed.end(), names[i]) != opt.fixed.end();
    if (i >= first && !fixed)
      ident.identified.push_back(i);
    else
      ident.unidentifiable.push_back(
          {i, names[i], fixed ? "fixed by the caller" : "hand-eye-only mode: the robot's kinematics are trusted"});
  }
  for (const std::string &f : opt.fixed)
    if (std::find(names.begin(), names.end(), f) == names.end())
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpKinematicBundleAdjustment: unknown fixed parameter '" + f + "'");
  ident.rank = static_cast<unsigned int>(ident.identified.size());
  return ident;
}

//! Stage 2, the intrinsics: their start values (in) and the indices estimated.
std::vector<int> estimatedIntrinsics(const vpCameraParameters &camera, const KBA::Options &opt, double in[kIntrinsics])
{
  const unsigned int flags = opt.intrinsics;
  intrinsicsFrom(camera, opt, in);
  std::vector<int> free_in;
  if (flags & KBA::FX)
    free_in.push_back(0);
  if (flags & KBA::ASPECT)
    free_in.push_back(1);
  if (flags & KBA::PRINCIPAL_POINT) {
    free_in.push_back(2);
    free_in.push_back(3);
  }
  if (flags & KBA::DISTORTION) {
    free_in.push_back(4);
    if (lensModel(opt) == Distortion::OPENCV) // k2, p1, p2; k3 only on request (poorly determined)
      for (int i : {5, 6, 7})
        free_in.push_back(i);
  }
  if ((flags & KBA::DISTORTION_K3) && lensModel(opt) == Distortion::OPENCV)
    free_in.push_back(8);
  return free_in;
}

/*
  The robot's error of the noise model, as the mode takes it: hand-eye-only the controller poses'
  (pose_sd_*), full kinematics the joint readings' (joint_sd: 1 or one per joint) and the model's
  residual (model_sd_*). A part of the other mode is a caller mistake.
*/
void checkRobotError(const vpKinematicChain &start, const KBA::Options &opt, const vpSelfCalibNoiseModel &noise)
{
  if (opt.hand_eye_only && !noise.joint_sd.empty())
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment: joint_sd (joint-reading noise) is for the full kinematic "
                               "mode; in hand-eye-only mode give the controller pose error (pose_sd_*)");
  if (opt.hand_eye_only && noise.hasModelError())
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment: model_sd_* (the kinematic model's residual) is for the "
                               "full kinematic mode; in hand-eye-only mode give the controller pose error (pose_sd_*)");
  if (!opt.hand_eye_only && noise.hasPoseError())
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment: pose_sd_* (the controller poses' error) is for the "
                               "hand-eye-only mode; in the full kinematic mode the camera pose correction is model_sd_*");
  if (!noise.joint_sd.empty() && noise.joint_sd.size() != 1 && noise.joint_sd.size() != start.getNumJoints())
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               "vpKinematicBundleAdjustment: joint_sd needs 1 or " +
                                   std::to_string(start.getNumJoints()) + " values, got " +
                                   std::to_string(noise.joint_sd.size()));
}

//! Everything one adjustment works on, built by the stages and shared by them.
struct Adjustment {
  Adjustment(const std::map<int, Eigen::Vector3d> &X0, const vpKinematicChain &start, const std::vector<unsigned int> &id,
             const std::vector<vpColVector> &q, const std::vector<Rigid> &fMe, bool pose_noise,
             const std::vector<double> &full_sd_, int n_joint, bool camera_delta)
    : X(X0), state(start, id, q, fMe, pose_noise, n_joint, camera_delta), joint_sd(full_sd_)
  {
  }
  PointStore X;
  KinematicState state;
  //! Full mode with robot error: the sd of a view's correction (joints in rad, then t in m and r in rad), else empty.
  std::vector<double> joint_sd;
  std::vector<Obs> obs;
  std::vector<bool> inlier;
  double in[kIntrinsics];
  std::vector<int> free_in;
  std::unique_ptr<ceres::Manifold> subset; //!< the intrinsics held constant (none when all or none are)
  std::vector<double> rho0;
  Eigen::VectorXd scale_dir;
  bool scale_covariance = false, scale_covariance_chi2 = false;
  vpSelfCalibNoiseModel noise;    //!< the noise of the adjustment (its pixel part, and the robot's)
  bool has_yardstick = false;
  int P = 0;
  //! Known geometry (Options::known_points): the object's pose (t, theta u) in f, when used.
  std::array<double, 6> object{0, 0, 0, 0, 0, 0};
  bool has_object = false;

  bool reproject(size_t n, double uv[2])
  {
    return project(state.model, state.views[obs[n].view], in, X[obs[n].id].data(), uv, nullptr, nullptr, nullptr, P);
  }
  //! Observations of points behind their camera cannot be evaluated: left out; then the points
  //! seen fewer than twice.
  void keepVisible()
  {
    inlier.assign(obs.size(), true);
    for (size_t n = 0; n < obs.size(); ++n) {
      double uv[2];
      inlier[n] = reproject(n, uv);
    }
    dropPoorlyObservedPoints(obs, inlier);
  }
  /*!
    Stage 4, after the robust solve: observations beyond threshold noise sds dropped. The noise sd
    is the stated one or, when larger, the one the residuals measure (robustNoiseSd over every
    observation that projects, wrong matches included: the median holds up to half of them). A
    stated sd 2.5x too small would otherwise drop about 13 % of the good observations at 5 stated
    sd, truncate the residuals and make the sds too small whatever sigma0 scaling follows.
  */
  void trim(double threshold, double pixel_sd)
  {
    std::vector<double> abs_residuals;
    for (size_t n = 0; n < obs.size(); ++n) {
      double uv[2];
      if (reproject(n, uv)) {
        abs_residuals.push_back(std::fabs(uv[0] - obs[n].u));
        abs_residuals.push_back(std::fabs(uv[1] - obs[n].v));
      }
    }
    const double threshold_px = threshold * std::max(pixel_sd, robustNoiseSd(abs_residuals, 1.0));
    for (size_t n = 0; n < obs.size(); ++n) {
      double uv[2];
      inlier[n] = reproject(n, uv) && std::hypot(uv[0] - obs[n].u, uv[1] - obs[n].v) <= threshold_px;
    }
    dropPoorlyObservedPoints(obs, inlier);
  }
  //! The whitened start errors of the kept observations (the robust schedule's first scale).
  std::vector<double> startErrors(double pixel_sd)
  {
    std::vector<double> e;
    for (size_t n = 0; n < obs.size(); ++n) {
      double uv[2];
      if (inlier[n] && reproject(n, uv))
        e.push_back(std::hypot(uv[0] - obs[n].u, uv[1] - obs[n].v) / pixel_sd);
    }
    return e;
  }
};

/*
  Stage 2, known geometry: the object's start pose, the rigid fit (Umeyama, no scale) of its layout
  to the start points it has among the reconstructed ones. A caller mistake when fewer than 3 of them
  are there or a layout entry is not a finite 3-vector.
*/
void startObject(const std::map<int, vpColVector> &layout, Adjustment &a)
{
  std::vector<int> ids;
  for (const auto &e : layout) {
    if (e.second.size() != 3 || !allFinite(e.second))
      throw vpSelfCalibException(vpSelfCalibException::badValue, "vpKinematicBundleAdjustment: known point " +
                                                                     std::to_string(e.first) +
                                                                     " is not a finite 3-vector");
    if (a.X.count(e.first))
      ids.push_back(e.first);
  }
  if (ids.size() < 3)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment: only " + std::to_string(ids.size()) +
                                   " of the known points are observed in two views; at least 3 are needed");
  Eigen::Matrix3Xd L(3, ids.size()), X(3, ids.size());
  for (size_t i = 0; i < ids.size(); ++i) {
    L.col(static_cast<Eigen::Index>(i)) = vec3(layout.at(ids[i]));
    X.col(static_cast<Eigen::Index>(i)) = a.X[ids[i]];
  }
  const Eigen::Matrix4d T = Eigen::umeyama(L, X, false);
  const Eigen::Vector3d r = logSO3(T.topLeftCorner<3, 3>());
  for (int i = 0; i < 3; ++i) {
    a.object[i] = T(i, 3);
    a.object[3 + i] = r(i);
  }
  a.has_object = true;
}

/*
  Stage 3, one Ceres problem of the schedule: the kept observations (robust loss of the given scale,
  0: plain least squares), the gauge (yardstick residual, or the scale direction held, or nothing in
  hand-eye-only mode), the ordering and the intrinsics' manifold. Null when no observation is kept.
*/
std::unique_ptr<ceres::Problem> buildProblem(Adjustment &a, const vpSelfCalibDataset::Yardstick &yardstick,
                                             const KBA::Options &opt, double loss_scale,
                                             std::shared_ptr<ceres::ParameterBlockOrdering> &order,
                                             KBA::ScaleSource &scale_source)
{
  ceres::Problem::Options po;
  po.evaluation_callback = &a.state;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  std::unique_ptr<ceres::Problem> problem(new ceres::Problem(po));
  order = std::make_shared<ceres::ParameterBlockOrdering>();
  for (size_t n = 0; n < a.obs.size(); ++n) {
    if (!a.inlier[n])
      continue;
    double *Xp = a.X[a.obs[n].id].data();
    std::vector<double *> blocks = {a.state.rho.data(), a.in, Xp};
    if (a.state.correctionSize() > 0)
      blocks.push_back(a.state.correction(a.obs[n].view));
    problem->AddResidualBlock(new ObservationCost(&a.state, a.obs[n].view, a.obs[n].u, a.obs[n].v, a.noise.pixel_sd),
                              loss_scale > 0 ? makeLoss(static_cast<RobustLoss>(a.noise.loss), loss_scale) : nullptr,
                              blocks);
    // The yardstick residual links its two ends: they stay in the reduced system.
    const bool end = a.has_yardstick && (a.obs[n].id == yardstick.id_a || a.obs[n].id == yardstick.id_b);
    order->AddElementToGroup(Xp, end ? 1 : 0);
  }
  if (!problem->HasParameterBlock(a.in))
    return nullptr;
  const bool use_yardstick = a.has_yardstick && problem->HasParameterBlock(a.X[yardstick.id_a].data()) &&
                             problem->HasParameterBlock(a.X[yardstick.id_b].data());
  scale_source =
      opt.hand_eye_only ? KBA::SCALE_ROBOT_MOTION : (use_yardstick ? KBA::SCALE_YARDSTICK : KBA::SCALE_NOMINAL);
  if (use_yardstick)
    problem->AddResidualBlock(new ceres::AutoDiffCostFunction<YardstickCost, 1, 3, 3>(
                                  new YardstickCost(yardstick.length, opt.yardstick_sd)),
                              nullptr, a.X[yardstick.id_a].data(), a.X[yardstick.id_b].data());
  else if (!opt.hand_eye_only)
    problem->AddResidualBlock(new ScaleCost(a.scale_dir, a.rho0), nullptr, a.state.rho.data());
  // One group per block: within a group Ceres orders blocks by address, and the address order of
  // separately allocated blocks changes from run to run (and so would the last digits).
  order->AddElementToGroup(a.state.rho.data(), 2);
  order->AddElementToGroup(a.in, 3);
  // Robot pose error: each view's correction with its prior (a view whose observations were all
  // rejected keeps only its prior: the correction stays 0).
  for (size_t k = 0; k < a.state.delta.size(); ++k) {
    problem->AddResidualBlock(new ceres::AutoDiffCostFunction<PosePriorCost, 6, 6>(
                                  new PosePriorCost(a.noise.pose_sd_translation, a.noise.pose_sd_rotation)),
                              nullptr, a.state.delta[k].data());
    order->AddElementToGroup(a.state.delta[k].data(), 4 + static_cast<int>(k));
  }
  // Joint-reading noise: each view's joint corrections with their prior.
  for (size_t k = 0; k < a.state.dq.size(); ++k) {
    problem->AddResidualBlock(new JointPriorCost(a.joint_sd), nullptr, a.state.dq[k].data());
    order->AddElementToGroup(a.state.dq[k].data(), 4 + static_cast<int>(k));
  }
  if (a.has_object) {
    for (const auto &e : opt.known_points)
      if (a.X.count(e.first) && problem->HasParameterBlock(a.X[e.first].data()))
        problem->AddResidualBlock(new ceres::AutoDiffCostFunction<KnownPointCost, 3, 6, 3>(
                                      new KnownPointCost(e.second, opt.known_points_sd)),
                                  nullptr, a.object.data(), a.X[e.first].data());
    if (problem->HasParameterBlock(a.object.data()))
      order->AddElementToGroup(a.object.data(),
                               4 + static_cast<int>(std::max(a.state.delta.size(), a.state.dq.size())));
  }
  if (a.free_in.empty())
    problem->SetParameterBlockConstant(a.in);
  else if (a.subset)
    problem->SetManifold(a.in, a.subset.get());
  return problem;
}

/*
  Stage 4, the robust solve schedule (robustSchedule: a wide loss when the start is far off, the
  narrow robust loss, trimming, plain least squares). Returns the last problem (for the covariance),
  or null when every observation was rejected; summary: the last solve's.
*/
std::unique_ptr<ceres::Problem> solveSchedule(Adjustment &a, const vpSelfCalibDataset::Yardstick &yardstick,
                                              const KBA::Options &opt, bool solve, ceres::Solver::Summary &summary,
                                              KBA::Result &res)
{
  RobustSchedule schedule;
  if (solve)
    schedule = robustSchedule(a.noise.loss != vpSelfCalibNoiseModel::LOSS_NONE, a.noise.loss_scale,
                              a.noise.outlier_threshold, a.startErrors(a.noise.pixel_sd));
  else
    schedule.scales = {0};
  std::unique_ptr<ceres::Problem> problem;
  for (size_t stage = 0; stage < schedule.scales.size(); ++stage) {
    std::shared_ptr<ceres::ParameterBlockOrdering> order;
    problem = buildProblem(a, yardstick, opt, schedule.scales[stage], order, res.scale_source);
    if (!problem || !solve)
      return problem;
    // The last solve gives the estimate: converged to the tight tolerances whatever opt.tight (the
    // default ones stopped it at a relative cost change of 1e-6 while f still moved by up to 0.3
    // of its sd, bench-trust's PUMA); the robust stages before it only give it a start and the
    // outliers, and keep the default tolerances.
    const bool last = stage + 1 == schedule.scales.size();
    ceres::Solver::Options so = solverOptions(opt.max_iterations, opt.tight || last, ceres::DENSE_SCHUR);
    so.linear_solver_ordering = order;
    so.num_threads = static_cast<int>(opt.num_threads);
    vpSelfCalib::solve(so, problem.get(), &summary);
    res.iterations += static_cast<unsigned int>(summary.iterations.size());
    a.state.update(true); // the callback last saw the final trial point, not necessarily the solution
    if (!summary.IsSolutionUsable())
      break;
    if (static_cast<int>(stage) == schedule.trim_after)
      a.trim(a.noise.outlier_threshold, a.noise.pixel_sd);
  }
  return problem;
}

/*
  Without robot error modelled: each view's camera re-posed alone on its kept observations
  (reposeCamera), the F statistic of the fit gained against the residuals left (Result::repose_f).
  Its 99.9 % quantile: the chi-square quantile of the numerator's degrees of freedom (Wilson-Hilferty,
  z = 3.09) over them, widened by the denominator's own spread (z sqrt(2 / its dof)).
*/
void reposeViews(Adjustment &a, KBA::Result &res)
{
  const CameraModel camera(a.state.model, a.in);
  std::vector<std::vector<Eigen::Vector3d>> Xc(a.state.views.size());
  std::vector<std::vector<Eigen::Vector2d>> uv(a.state.views.size());
  std::set<int> kept;
  for (size_t n = 0; n < a.obs.size(); ++n) {
    if (!a.inlier[n])
      continue;
    kept.insert(a.obs[n].id);
    const ViewState &v = a.state.views[a.obs[n].view];
    Xc[a.obs[n].view].push_back(v.RT * (a.X[a.obs[n].id] - v.tf));
    uv[a.obs[n].view].emplace_back(a.obs[n].u, a.obs[n].v);
  }
  double before = 0, after = 0, st = 0, sr = 0, used = 0;
  unsigned int views = 0;
  for (size_t k = 0; k < Xc.size(); ++k) {
    Eigen::Matrix<double, 6, 1> c;
    double cost = 0;
    if (!reposeCamera(camera, Xc[k], uv[k], c, cost))
      continue;
    for (size_t i = 0; i < Xc[k].size(); ++i) {
      Eigen::Vector2d p;
      if (camera.project(Xc[k][i], p, nullptr, nullptr))
        before += (p - uv[k][i]).squaredNorm();
    }
    after += cost;
    used += static_cast<double>(Xc[k].size());
    st += c.head<3>().squaredNorm();
    sr += c.tail<3>().squaredNorm();
    ++views;
  }
  // The solution's degrees of freedom over the views used: its share of the whole.
  const double unknowns = static_cast<double>(a.P + a.free_in.size()) + 3.0 * static_cast<double>(kept.size());
  const double dof = 2.0 * used - unknowns * used / std::max(1.0, static_cast<double>(res.num_observations)) - 6.0 * views;
  if (views == 0 || !(dof > 0) || !(after > 0))
    return;
  res.reposed_views = views;
  res.reposed_rms = std::sqrt(after / (2.0 * used));
  res.repose_rms_before = std::sqrt(before / (2.0 * used));
  res.repose_rms_translation = std::sqrt(st / (3.0 * views));
  res.repose_rms_rotation = std::sqrt(sr / (3.0 * views));
  const double nu = 6.0 * views;
  res.repose_f = (std::max(0.0, before - after) / nu) / (after / dof);
  const double z = 3.09, h = 2.0 / (9.0 * nu);
  res.repose_f_limit = std::pow(1.0 - h + z * std::sqrt(h), 3) * (1.0 + z * std::sqrt(2.0 / dof));
}

//! Stage 5, the estimate at the final state: chain, camera, points, rms and sigma0, intrinsics.
void fillEstimate(Adjustment &a, const KBA::Options &opt, bool distortion, KBA::Result &res)
{
  res.chain = a.state.chain;
  res.camera = cameraFrom(a.in, a.state.model, distortion);
  if (a.state.model == Distortion::OPENCV)
    res.opencv_distortion.assign(a.in + 4, a.in + 9);
  std::set<int> kept;
  double sum = 0;
  std::vector<double> abs_residuals; // every observation that projects, for the robust noise level
  for (size_t n = 0; n < a.obs.size(); ++n) {
    double uv[2];
    const bool projects = a.reproject(n, uv);
    if (projects) {
      abs_residuals.push_back(std::fabs(uv[0] - a.obs[n].u));
      abs_residuals.push_back(std::fabs(uv[1] - a.obs[n].v));
    }
    if (!a.inlier[n] || !projects) {
      a.inlier[n] = false;
      ++res.num_outliers;
      continue;
    }
    sum += std::pow(uv[0] - a.obs[n].u, 2) + std::pow(uv[1] - a.obs[n].v, 2);
    ++res.num_observations;
    kept.insert(a.obs[n].id);
  }
  res.rms = res.num_observations ? std::sqrt(sum / (2.0 * res.num_observations)) : 0;
  // The pose priors add as many residuals as unknowns: the degrees of freedom are the pixels'.
  const double dof = 2.0 * res.num_observations - static_cast<double>(a.P + a.free_in.size() + 3 * kept.size());
  res.sigma0 = dof > 0 ? res.rms / a.noise.pixel_sd * std::sqrt(2.0 * res.num_observations / dof) : 0;
  if (dof > 0 && !abs_residuals.empty()) {
    res.measured.pixel_sd = vpSelfCalib::robustNoiseSd(abs_residuals, std::sqrt(2.0 * res.num_observations / dof));
    vpSelfCalib::sigma0Interval(dof, res.sigma0_low, res.sigma0_high);
  }
  if (!a.state.delta.empty()) {
    double chi2 = sum / (a.noise.pixel_sd * a.noise.pixel_sd), st = 0, sr = 0;
    for (const auto &d : a.state.delta) {
      const double t2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2], r2 = d[3] * d[3] + d[4] * d[4] + d[5] * d[5];
      st += t2;
      sr += r2;
      const double robot = t2 / (a.noise.pose_sd_translation * a.noise.pose_sd_translation) +
                           r2 / (a.noise.pose_sd_rotation * a.noise.pose_sd_rotation);
      chi2 += robot;
      res.robot_chi2 += robot;
      res.robot_dof += 6;
      res.pose_corrections.push_back(vpColVector({d[0], d[1], d[2], d[3], d[4], d[5]}));
    }
    const double views = static_cast<double>(a.state.delta.size());
    res.pose_rms_translation = std::sqrt(st / (3 * views));
    res.pose_rms_rotation = std::sqrt(sr / (3 * views));
    res.robot_rms_ratio = std::max(res.pose_rms_translation / a.noise.pose_sd_translation,
                                   res.pose_rms_rotation / a.noise.pose_sd_rotation);
    res.sigma0 = dof > 0 ? std::sqrt(chi2 / dof) : 0;
  }
  if (!a.state.dq.empty()) {
    double chi2 = sum / (a.noise.pixel_sd * a.noise.pixel_sd), sq = 0, st = 0, sr = 0;
    double part[3] = {0, 0, 0}; // whitened squares: joints, camera translation, camera rotation
    const int nj = a.state.n_joint;
    for (const auto &d : a.state.dq) {
      for (size_t i = 0; i < d.size(); ++i) {
        const double robot = d[i] * d[i] / (a.joint_sd[i] * a.joint_sd[i]);
        chi2 += robot;
        res.robot_chi2 += robot;
        ++res.robot_dof;
        part[static_cast<int>(i) < nj ? 0 : (static_cast<int>(i) < nj + 3 ? 1 : 2)] += robot;
      }
      if (nj > 0) {
        vpColVector c(static_cast<unsigned int>(nj));
        for (int i = 0; i < nj; ++i) {
          c[static_cast<unsigned int>(i)] = d[i];
          sq += d[i] * d[i];
        }
        res.joint_corrections.push_back(c);
      }
      if (a.state.camera_delta) {
        res.pose_corrections.push_back(
            vpColVector({d[nj], d[nj + 1], d[nj + 2], d[nj + 3], d[nj + 4], d[nj + 5]}));
        for (int i = 0; i < 3; ++i) {
          st += d[nj + i] * d[nj + i];
          sr += d[nj + 3 + i] * d[nj + 3 + i];
        }
      }
    }
    const double views = static_cast<double>(a.state.dq.size());
    if (nj > 0)
      res.joint_rms = std::sqrt(sq / (views * nj));
    if (a.state.camera_delta) {
      res.pose_rms_translation = std::sqrt(st / (3 * views));
      res.pose_rms_rotation = std::sqrt(sr / (3 * views));
    }
    if (nj > 0)
      res.robot_rms_ratio = std::sqrt(part[0] / (views * nj));
    if (a.state.camera_delta)
      res.robot_rms_ratio =
          std::max(res.robot_rms_ratio, std::sqrt(std::max(part[1], part[2]) / (3 * views)));
    res.sigma0 = dof > 0 ? std::sqrt(chi2 / dof) : 0;
  }
  for (int idp : kept) {
    vpColVector v(3);
    for (unsigned int c = 0; c < 3; ++c)
      v[c] = a.X[idp](c);
    res.points[idp] = v;
  }
  for (int i : a.free_in)
    res.intrinsic_names.push_back(intrinsicName(a.state.model, i));
  res.intrinsics.resize(static_cast<unsigned int>(a.free_in.size()));
  res.intrinsics_sd.resize(static_cast<unsigned int>(a.free_in.size()));
  for (size_t i = 0; i < a.free_in.size(); ++i)
    res.intrinsics[static_cast<unsigned int>(i)] = a.in[a.free_in[i]];
}

/*
  Stage 6, the covariance of the corrections and the estimated intrinsics with the points
  marginalized (core marginalCovariance); the yardstick's ends, linked by their residual, stay in
  the complement as in the solve. False when the information is singular.
*/
bool fillCovariance(Adjustment &a, ceres::Problem &problem, const vpSelfCalibDataset::Yardstick &yardstick,
                    const std::vector<std::string> &names, KBA::Result &res)
{
  const std::vector<unsigned int> &id = res.identifiability.identified;
  std::vector<double *> kept = {a.state.rho.data()}, eliminated;
  if (!a.free_in.empty())
    kept.push_back(a.in);
  std::set<const double *> ends;
  if (a.has_yardstick && problem.HasParameterBlock(a.X[yardstick.id_a].data()) &&
      problem.HasParameterBlock(a.X[yardstick.id_b].data()))
    for (int e : {yardstick.id_a, yardstick.id_b}) {
      kept.push_back(a.X[e].data());
      ends.insert(a.X[e].data());
    }
  for (auto &d : a.state.delta)
    kept.push_back(d.data());
  for (auto &d : a.state.dq)
    kept.push_back(d.data());
  if (a.has_object && problem.HasParameterBlock(a.object.data()))
    kept.push_back(a.object.data());
  for (const auto &e : a.X.index())
    if (!ends.count(a.X[e.first].data()) && problem.HasParameterBlock(a.X[e.first].data()))
      eliminated.push_back(a.X[e.first].data());
  const int P = a.P, N = P + static_cast<int>(a.free_in.size());
  Eigen::MatrixXd full;
  Eigen::MatrixXd undetermined;
  if (!marginalCovariance(problem, kept, eliminated, full, &undetermined)) {
    // Name the estimated parameters in the undetermined directions (a component of 0.3 or more in
    // one of them; the pose corrections and the yardstick's ends, also kept, are not named).
    std::vector<std::pair<double, std::string>> named;
    for (int r = 0; r < std::min<int>(N, static_cast<int>(undetermined.rows())); ++r) {
      const double c = undetermined.row(r).cwiseAbs().maxCoeff();
      if (c >= 0.3)
        named.push_back({-c, r < P ? names[id[r]] : intrinsicName(a.state.model, a.free_in[r - P])});
    }
    std::sort(named.begin(), named.end());
    for (const auto &e : named)
      res.undetermined.push_back(e.second);
    return false;
  }
  // The robot pose error measured (variance component estimation): each correction's redundancy is
  // 1 - its posterior variance over its prior one, at the stated weights (the covariance before any
  // sigma0 scaling); the corrections follow the kept blocks before them.
  const double stated_pose_sd[2] = {a.noise.pose_sd_translation, a.noise.pose_sd_rotation};
  if (!a.state.delta.empty() && stated_pose_sd[0] > 0 && stated_pose_sd[1] > 0) {
    const int first = N + 3 * static_cast<int>(ends.size());
    double sum[2] = {0, 0}, redundancy[2] = {0, 0};
    for (size_t k = 0; k < a.state.delta.size(); ++k)
      for (int i = 0; i < 6; ++i) {
        const int part = i < 3 ? 0 : 1, r = first + 6 * static_cast<int>(k) + i;
        const double prior = stated_pose_sd[part] * stated_pose_sd[part];
        sum[part] += a.state.delta[k][i] * a.state.delta[k][i];
        redundancy[part] += 1.0 - full(r, r) / prior;
      }
    if (redundancy[0] >= 1 && redundancy[1] >= 1) {
      res.measured.pose_sd_translation = std::sqrt(sum[0] / redundancy[0]);
      res.measured.pose_sd_rotation = std::sqrt(sum[1] / redundancy[1]);
    }
  }
  // The a posteriori variance factor: the stated noise is too small for the residuals.
  // With robot pose corrections the pose priors take up what the pixels do not: a sigma0 below 1
  // then says the priors were loose, not that the estimate is better, and is not used to shrink.
  const double s2 = res.sigma0 * res.sigma0;
  const bool pose_priors = !a.state.delta.empty() || !a.state.dq.empty();
  const double factor =
      a.scale_covariance_chi2 && !pose_priors ? (res.sigma0 < res.sigma0_low || res.sigma0 > res.sigma0_high ? s2 : 1.0)
      : (a.scale_covariance || a.scale_covariance_chi2) && res.sigma0 > 1 ? s2
                                                                          : 1.0;
  res.covariance_scaled = factor != 1.0;
  res.covariance.resize(N, N);
  for (int r = 0; r < N; ++r)
    for (int c = 0; c < N; ++c)
      res.covariance[r][c] = factor * full(r, c);
  for (int r = 0; r < P; ++r)
    res.sd[id[r]] = std::sqrt(std::max(0.0, res.covariance[r][r]));
  for (size_t r = 0; r < a.free_in.size(); ++r) {
    res.intrinsics_sd[static_cast<unsigned int>(r)] = std::sqrt(std::max(0.0, res.covariance[P + r][P + r]));
    if (a.free_in[r] == 0)
      res.fx_sd = res.intrinsics_sd[static_cast<unsigned int>(r)];
  }
  for (int r = 0; r < P; ++r)
    res.covariance_names.push_back(names[id[r]]);
  for (int i : a.free_in)
    res.covariance_names.push_back(intrinsicName(a.state.model, i));
  res.has_covariance = true;
  return true;
}

//! The adjustment (solve) or only its information at the start state (!solve); see the header.
vpKinematicBundleAdjustment::Result run(const vpKinematicChain &start, const vpCameraParameters &camera,
                                        const std::vector<vpSelfCalibDataset::View> &views,
                                        const vpSelfCalibDataset::Yardstick &yardstick,
                                        const std::map<int, vpColVector> &points0,
                                        const vpKinematicBundleAdjustment::Options &opt,
                                        const vpSelfCalibNoiseModel &noise, bool solve)
{
  opt.check();
  noise.check("vpKinematicBundleAdjustment");
  vpSelfCalib::checkCamera(camera, "vpKinematicBundleAdjustment: the camera");
  vpSelfCalib::checkChain(start, "vpKinematicBundleAdjustment: the model '" + start.getName() + "'");
  // Checked here rather than in check(): the pipeline sets hand_eye_only from its method.
  const QuietCeres quiet;
  const auto t0 = std::chrono::steady_clock::now();
  const unsigned int m = static_cast<unsigned int>(views.size());
  if (m < 2)
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpKinematicBundleAdjustment: at least 2 views are needed");
  if (!(camera.get_px() > 0) || !(camera.get_py() > 0))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment: the camera needs positive px and py");
  if (opt.distortion_model == KBA::DISTORTION_OPENCV && CameraModel::fromVisp(camera).distortion() != Distortion::NONE)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment: with the OpenCV distortion model the camera must have no "
                               "ViSP distortion (k_ud): give the start coefficients in opencv_distortion");
  std::vector<vpColVector> q;
  std::vector<Rigid> fMe;
  std::map<int, unsigned int> seen;
  collectViews(start, views, opt, q, fMe, seen);
  const std::map<int, Eigen::Vector3d> X0 = startPoints(points0, seen);

  KBA::Result res;
  res.chain = start;
  res.camera = camera;
  res.sd.resize(start.getNumParameters());
  res.identifiability = estimatedSet(start, q, opt);
  checkRobotError(start, opt, noise);
  std::vector<double> joint_sd;
  if (!noise.joint_sd.empty()) {
    joint_sd.assign(start.getNumJoints(), noise.joint_sd[0]);
    if (noise.joint_sd.size() > 1)
      joint_sd = noise.joint_sd;
  }
  // Full mode: the camera pose error the model leaves (model_sd_*), after the joint corrections.
  const bool camera_delta = !opt.hand_eye_only && noise.hasModelError();
  const int n_joint = static_cast<int>(joint_sd.size());
  if (camera_delta)
    for (int i = 0; i < 6; ++i)
      joint_sd.push_back(i < 3 ? noise.model_sd_translation : noise.model_sd_rotation);
  Adjustment a(X0, start, res.identifiability.identified, q, fMe, opt.hand_eye_only && noise.hasPoseError(), joint_sd,
               n_joint, camera_delta);
  a.noise = noise;
  a.P = static_cast<int>(res.identifiability.identified.size());
  for (unsigned int k = 0; k < m; ++k)
    for (const auto &o : views[k].points)
      if (a.X.count(o.id))
        a.obs.push_back({k, o.id, o.ip.get_u(), o.ip.get_v()});
  a.state.model = lensModel(opt);
  a.free_in = estimatedIntrinsics(camera, opt, a.in);
  a.scale_covariance = opt.scale_covariance;
  a.scale_covariance_chi2 = opt.scale_covariance_chi2;
  const bool distortion = (opt.intrinsics & KBA::DISTORTION) || a.in[4] != 0;
  const size_t unknowns = a.P + a.free_in.size() + 3 * a.X.size();
  if (a.P == 0 || 2 * a.obs.size() <= unknowns) {
    res.status = KBA::TOO_FEW_OBSERVATIONS;
    res.message = std::to_string(a.obs.size()) + " observations of points seen twice for " +
                  std::to_string(unknowns) + " unknowns";
    return res;
  }
  a.state.update(true);
  a.rho0 = a.state.rho;
  a.has_yardstick = yardstick.isSet() && a.X.count(yardstick.id_a) && a.X.count(yardstick.id_b);
  // Hand-eye-only: the metric end-effector motion fixes the scale; no gauge constraint.
  if (!opt.hand_eye_only)
    a.scale_dir = scaleDirection(a.state);
  a.keepVisible();
  if (!opt.known_points.empty())
    startObject(opt.known_points, a);
  if (!a.free_in.empty() && a.free_in.size() < kIntrinsics) {
    std::vector<int> constant;
    for (int i = 0; i < kIntrinsics; ++i)
      if (std::find(a.free_in.begin(), a.free_in.end(), i) == a.free_in.end())
        constant.push_back(i);
    a.subset.reset(new ceres::SubsetManifold(kIntrinsics, constant));
  }

  ceres::Solver::Summary summary;
  const std::unique_ptr<ceres::Problem> problem = solveSchedule(a, yardstick, opt, solve, summary, res);
  if (!problem) {
    res.status = KBA::TOO_FEW_OBSERVATIONS;
    res.message = "every observation was rejected as an outlier";
    res.chain = a.state.chain;
    return res;
  }
  res.seconds_solve = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  fillEstimate(a, opt, distortion, res);
  if (solve && a.state.delta.empty() && a.state.dq.empty())
    reposeViews(a, res);
  if (solve && !summary.IsSolutionUsable()) {
    res.status = KBA::NO_CONVERGENCE;
    res.message = summary.message.empty() ? summary.BriefReport() : summary.message;
    return res;
  }
  if (opt.covariance) {
    const auto tc = std::chrono::steady_clock::now();
    fillCovariance(a, *problem, yardstick, start.getParameterNames(), res);
    res.seconds_covariance = std::chrono::duration<double>(std::chrono::steady_clock::now() - tc).count();
    if (!res.has_covariance) {
      res.status = KBA::RANK_DEFICIENT;
      // Every cause that makes it singular named, the observations kept first: after many rejected
      // matches the few left are the likelier cause than the poses' geometry.
      const std::string kept_text = std::to_string(res.num_observations) + " observations kept of " +
                                    std::to_string(res.num_observations + res.num_outliers);
      res.message = opt.hand_eye_only
                        ? "the information matrix of the hand-eye correction and intrinsics is singular (" +
                              kept_text +
                              "): the observations kept do not determine eMc and the intrinsics: too few points "
                              "or views left, end-effector rotations all about parallel axes, or intrinsics a "
                              "planar scene cannot fix; add views, poses rotating about another axis, or fix the "
                              "intrinsics"
                        : "the information matrix of the corrections and intrinsics is singular (" + kept_text +
                              "): the views do not determine them (too few or too similar configurations, or too "
                              "few observations left)";
      if (!res.undetermined.empty()) {
        std::string list;
        for (const std::string &n : res.undetermined)
          list += (list.empty() ? "" : ", ") + n;
        res.message += "; not determined: " + list;
      }
      return res;
    }
  }
  res.status = KBA::OK;
  std::ostringstream os;
  os << "ok: " << a.P << " corrections, " << a.free_in.size() << " intrinsics, " << res.points.size() << " points, "
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
  if (intrinsics > (FX | ASPECT | PRINCIPAL_POINT | DISTORTION | DISTORTION_K3))
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpKinematicBundleAdjustment: unknown intrinsics flag");
  if (distortion_model != DISTORTION_VISP && distortion_model != DISTORTION_OPENCV)
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpKinematicBundleAdjustment: unknown distortion model");
  if (distortion_model == DISTORTION_VISP ? !opencv_distortion.empty()
                                          : !(opencv_distortion.empty() || opencv_distortion.size() == 5))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment: opencv_distortion is (k1, k2, p1, p2, k3), with "
                               "distortion_model DISTORTION_OPENCV only (empty: all 0)");
  for (double k : opencv_distortion)
    if (!std::isfinite(k) || std::abs(k) > 1e3)
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpKinematicBundleAdjustment: opencv_distortion coefficients must be finite, |k| <= 1000");
  if ((intrinsics & DISTORTION_K3) && !(intrinsics & DISTORTION))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment: DISTORTION_K3 goes with DISTORTION");
  if (!(yardstick_sd > 0) || !(rank_tolerance > 0 && rank_tolerance < 1))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment: yardstick_sd must be positive, rank_tolerance in (0, 1)");
  if (!(known_points_sd > 0) || !std::isfinite(known_points_sd))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment: known_points_sd must be positive and finite");
  if (max_iterations == 0 || num_threads == 0)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment: max_iterations and num_threads must be at least 1");
}

vpKinematicBundleAdjustment::Result vpKinematicBundleAdjustment::adjust(const vpKinematicChain &start,
                                                                       const vpCameraParameters &camera,
                                                                       const std::vector<vpSelfCalibDataset::View> &views,
                                                                       const vpSelfCalibDataset::Yardstick &yardstick,
                                                                       const std::map<int, vpColVector> &points,
                                                                       const Options &options,
                                                                       const vpSelfCalibNoiseModel &noise)
{
  return run(start, camera, views, yardstick, points, options, noise, true);
}

vpKinematicBundleAdjustment::Result vpKinematicBundleAdjustment::information(
    const vpKinematicChain &state, const vpCameraParameters &camera, const std::vector<vpSelfCalibDataset::View> &views,
    const vpSelfCalibDataset::Yardstick &yardstick, const std::map<int, vpColVector> &points, const Options &options,
    const vpSelfCalibNoiseModel &noise)
{
  Options o = options;
  o.covariance = true;
  return run(state, camera, views, yardstick, points, o, noise, false);
}

vpMatrix vpKinematicBundleAdjustment::relativePoseCovariance(const vpKinematicChain &chain,
                                                             const std::vector<unsigned int> &parameters,
                                                             const vpMatrix &covariance, const vpColVector &q_ref,
                                                             const vpColVector &q)
{
  vpSelfCalib::checkChain(chain, "vpKinematicBundleAdjustment::relativePoseCovariance: the model");
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
  Eigen::MatrixXd JAs(6, P), JBs(6, P), S(P, P);
  for (unsigned int c = 0; c < P; ++c) {
    for (unsigned int a = 0; a < 6; ++a) {
      JAs(a, c) = JA[a][parameters[c]];
      JBs(a, c) = JB[a][parameters[c]];
    }
    for (unsigned int d = 0; d < P; ++d)
      S(c, d) = covariance[c][d];
  }
  // c_ref M c = A^-1 B (core relativePoseJacobian), then G S G^T.
  Eigen::MatrixXd Jt, Jr, G(6, P);
  relativePoseJacobian(A, JAs, B, JBs, Jt, Jr);
  G.topRows(3) = Jt;
  G.bottomRows(3) = Jr;
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
  vpSelfCalib::checkCamera(camera, "vpKinematicBundleAdjustment::observationJacobian: the camera");
  vpSelfCalib::checkChain(chain, "vpKinematicBundleAdjustment::observationJacobian: the model");
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
  intrinsicsFrom(camera, Options(), in);
  constexpr int kVisp = 5; // p_x, mu, u0, v0, k_ud
  const int P = static_cast<int>(parameters.size());
  std::vector<double> Jr(2 * P), Ji(2 * kIntrinsics), JX(6);
  double Xp[3] = {X[0], X[1], X[2]}, p[2];
  uv.resize(2);
  vpMatrix J(2, P + kVisp + 3);
  if (!project(Distortion::VISP, v, in, Xp, p, Jr.data(), Ji.data(), JX.data(), P))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicBundleAdjustment::observationJacobian: the point is behind the camera");
  uv[0] = p[0];
  uv[1] = p[1];
  for (unsigned int r = 0; r < 2; ++r) {
    for (int c = 0; c < P; ++c)
      J[r][c] = Jr[r * P + c];
    for (int c = 0; c < kVisp; ++c)
      J[r][P + c] = Ji[r * kIntrinsics + c];
    for (int c = 0; c < 3; ++c)
      J[r][P + kVisp + c] = JX[r * 3 + c];
  }
  return J;
}
