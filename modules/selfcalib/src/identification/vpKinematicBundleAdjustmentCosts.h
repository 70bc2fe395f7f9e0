/*
 * ViSP SelfCalib: private interface of the kinematic bundle adjustment (not installed): the views'
 * pose models, the projection and the Ceres cost functions (vpKinematicBundleAdjustmentCosts.cpp).
 * The problem building is in vpKinematicBundleAdjustmentProblem.h, the covariance in
 * vpKinematicBundleAdjustmentCovariance.cpp and the run in vpKinematicBundleAdjustment.cpp.
 */
#ifndef VP_KINEMATIC_BUNDLE_ADJUSTMENT_COSTS_H
#define VP_KINEMATIC_BUNDLE_ADJUSTMENT_COSTS_H

#include <array>
#include <vector>

#include <Eigen/Core>
#include <ceres/ceres.h>
#include <ceres/normal_prior.h>
#include <ceres/rotation.h>

#include <visp3/selfcalib/vpKinematicBundleAdjustment.h>

#include "../core/vpSelfCalibCamera.h"
#include "../core/vpSelfCalibMath.h"

namespace vpKinematicBundle
{
using namespace vpSelfCalib;

// The intrinsics block: p_x, mu, u0, v0 and up to five distortion coefficients (ViSP's k_ud uses the
// first; OpenCV's k1, k2, p1, p2, k3 all five); the unused ones are held constant.
constexpr int kIntrinsics = kMaxIntrinsics;
//! The lens model of an adjustment's options.
Distortion lensModel(const vpKinematicBundleAdjustment::Options &o);
//! The name of intrinsic i of the block in the lens model (ViSP: "kud" for the first coefficient).
const char *intrinsicName(Distortion model, int i);

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

//! Full kinematic mode: the view at joints q; with_jacobian: also A, C for the corrections id.
void computeView(const vpKinematicChain &chain, const std::vector<unsigned int> &id, const vpColVector &q,
                 bool with_jacobian, ViewState &v);
//! Full kinematic mode, eye-to-hand (Options::eye_to_hand): the camera pose fMe(q)^-1 bMc in e, bMc
//! the chain's corrected hand-eye slot; with_jacobian: also A, C for the corrections id.
void computeEyeToHandView(const vpKinematicChain &chain, const std::vector<unsigned int> &id, const vpColVector &q,
                          bool with_jacobian, ViewState &v);
//! Full kinematic mode with robot error: the view at q with its own correction c (joints, then the
//! camera pose when camera_delta); eye_to_hand: the view of computeEyeToHandView().
void computeNoisyView(const vpKinematicChain &chain, const std::vector<unsigned int> &id, const vpColVector &q,
                      const double *c, int n_joint, bool camera_delta, bool with_jacobian, ViewState &v,
                      bool eye_to_hand = false);
//! Hand-eye-only mode: the view of the trusted end-effector pose fMe; id: the estimated eMc components.
void computeHandEyeView(const vpKinematicChain &chain, const std::vector<unsigned int> &id, const Rigid &fMe,
                        bool with_jacobian, ViewState &v);
//! Hand-eye-only mode with robot pose error: the view of fMe with its pose correction delta.
void computePoseNoiseView(const vpKinematicChain &chain, const std::vector<unsigned int> &id, const Rigid &fMe,
                          const double *delta, bool with_jacobian, ViewState &v);
//! The same, eye-to-hand (Options::controller_poses_inverted): the view of E(delta)^-1 fMe.
void computeInvertedPoseNoiseView(const vpKinematicChain &chain, const std::vector<unsigned int> &id,
                                  const Rigid &fMe, const double *delta, bool with_jacobian, ViewState &v);
/*!
  Projection of X (f) through a view and the core camera model: (u, v), and on request its
  derivatives (row-major) with respect to the corrections (2 x P), the intrinsics block
  (2 x kIntrinsics), X (2 x 3) and the view's own correction. False behind the camera.
*/
bool project(Distortion model, const ViewState &v, const double *in, const double *Xp, double uv[2], double *Jrho,
             double *Jin, double *JX, int P, double *Jdelta = nullptr);

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
        computeNoisyView(chain, id, q[k], dq[k].data(), n_joint, camera_delta, with_jacobians, views[k], eye_to_hand);
      else if (fMe.empty() && eye_to_hand)
        computeEyeToHandView(chain, id, q[k], with_jacobians, views[k]);
      else if (fMe.empty())
        computeView(chain, id, q[k], with_jacobians, views[k]);
      else if (delta.empty())
        computeHandEyeView(chain, id, fMe[k], with_jacobians, views[k]);
      else if (inverted)
        computeInvertedPoseNoiseView(chain, id, fMe[k], delta[k].data(), with_jacobians, views[k]);
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
  bool inverted = false;     //!< the fMe are inverted controller poses (Options::controller_poses_inverted)
  bool eye_to_hand = false;  //!< full mode, the camera in the world (Options::eye_to_hand)
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

/*!
  The prior of a view's joint corrections (joint-reading noise): r_i = dq_i / sd_i, Ceres' NormalPrior
  with A = diag(1 / sd), b = 0.
*/
inline ceres::CostFunction *jointPriorCost(const std::vector<double> &sd)
{
  const Eigen::Index n = static_cast<Eigen::Index>(sd.size());
  ceres::Matrix A = ceres::Matrix::Zero(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    A(i, i) = 1 / sd[static_cast<size_t>(i)];
  return new ceres::NormalPrior(A, ceres::Vector::Zero(n));
}

/*!
  The kinematic prior (Settings::kinematic_prior): r_i = (rho_i - rho_ref,i) / sd_i on the corrections
  rho (one block), sd_i = tolerance_i / k: Ceres' NormalPrior with A = diag(1 / sd), b = rho_ref. Not the
  paper's: a MAP estimate, so that the corrections the data barely determine stay near the nominal
  model instead of being left out of the estimate.
*/
inline ceres::CostFunction *kinematicPriorCost(const std::vector<double> &ref, const std::vector<double> &sd)
{
  const Eigen::Index n = static_cast<Eigen::Index>(sd.size());
  ceres::Matrix A = ceres::Matrix::Zero(n, n);
  ceres::Vector b(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    A(i, i) = 1 / sd[static_cast<size_t>(i)];
    b(i) = ref[static_cast<size_t>(i)];
  }
  return new ceres::NormalPrior(A, b);
}

//! (X - (R s L + t)) / sd: a known point with the layout's scale s free (blocks fMo, s, X).
struct ScaledKnownPointCost {
  ScaledKnownPointCost(const vpColVector &L, double sd) : L_{L[0], L[1], L[2]}, w(1 / sd) {}
  template <typename T> bool operator()(const T *o, const T *s, const T *X, T *r) const
  {
    const T L[3] = {s[0] * T(L_[0]), s[0] * T(L_[1]), s[0] * T(L_[2])};
    T p[3];
    ceres::AngleAxisRotatePoint(o + 3, L, p);
    for (int i = 0; i < 3; ++i)
      r[i] = (X[i] - (p[i] + o[i])) * T(w);
    return true;
  }
  double L_[3], w;
};

//! (X - (R(o_r) L + o_t)) / sd: a point of known geometry L (object frame) and the object's pose o.
struct KnownPointCost {
  KnownPointCost(const vpColVector &L, double sd) : scaled(L, sd) {}
  template <typename T> bool operator()(const T *o, const T *X, T *r) const
  {
    const T one[1] = {T(1)};
    return scaled(o, one, X, r);
  }
  ScaledKnownPointCost scaled;
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

//! (|X_a - X_b| - s L) / sd: the yardstick's declared length L times a free scale s (its measure).
struct ScaledYardstickCost {
  ScaledYardstickCost(double length, double sd) : L(length), w(1 / sd) {}
  template <typename T> bool operator()(const T *a, const T *b, const T *s, T *r) const
  {
    const T dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    r[0] = (ceres::sqrt(dx * dx + dy * dy + dz * dz) - s[0] * T(L)) * T(w);
    return true;
  }
  double L, w;
};

//! s^T (rho - rho0) / |s|^2 / 1e-8: the relative scale of the model held at rho0's (s: the gauge, scaleGauge()).
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

} // namespace vpKinematicBundle

#endif
