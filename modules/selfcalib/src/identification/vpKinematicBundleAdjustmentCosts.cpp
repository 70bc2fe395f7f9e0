/*
 * ViSP SelfCalib: kinematic bundle adjustment, the views' pose models and the projection with their
 * Jacobians (the cost functions of vpKinematicBundleAdjustmentCosts.h evaluate them).
 */
#include "vpKinematicBundleAdjustmentCosts.h"

#include <Eigen/Geometry>

namespace vpKinematicBundle
{
namespace
{
const char *const kVispNames[kIntrinsics] = {"fx", "mu", "u0", "v0", "kud", "", "", "", ""};
const char *const kOpenCvNames[kIntrinsics] = {"fx", "mu", "u0", "v0", "k1", "k2", "p1", "p2", "k3"};
} // namespace

//! The lens model of an adjustment's options.
Distortion lensModel(const vpKinematicBundleAdjustment::Options &o)
{
  return o.distortion_model == vpKinematicBundleAdjustment::DISTORTION_OPENCV ? Distortion::OPENCV : Distortion::VISP;
}
const char *intrinsicName(Distortion model, int i)
{
  return model == Distortion::OPENCV ? kOpenCvNames[i] : kVispNames[i];
}

namespace
{
//! The chain's identification Jacobian columns of the corrections id at q: camera origin (Jt) and rotation (Jr) in f.
void chainColumns(const vpKinematicChain &chain, const std::vector<unsigned int> &id, const vpColVector &q,
                  Eigen::Matrix<double, 3, Eigen::Dynamic> &Jt, Eigen::Matrix<double, 3, Eigen::Dynamic> &Jr)
{
  const vpMatrix J = chain.getJacobian(q);
  const int P = static_cast<int>(id.size());
  Jt.resize(3, P);
  Jr.resize(3, P);
  for (int c = 0; c < P; ++c)
    for (int a = 0; a < 3; ++a) {
      Jt(a, c) = J[a][id[c]];
      Jr(a, c) = J[a + 3][id[c]];
    }
}
} // namespace

void computeView(const vpKinematicChain &chain, const std::vector<unsigned int> &id, const vpColVector &q,
                 bool with_jacobian, ViewState &v)
{
  const Rigid M = rigidFromVisp(chain.get_fMc(q));
  v.RT = M.R.transpose();
  v.tf = M.t;
  if (!with_jacobian)
    return;
  Eigen::Matrix<double, 3, Eigen::Dynamic> Jt, Jr;
  chainColumns(chain, id, q, Jt, Jr);
  v.A = v.RT * Jt;
  v.C = v.RT * Jr;
}

namespace
{
/*
  Eye-to-hand: the e-frame columns of the camera pose G = T^-1 X (T = fMe(q), X = bMc the chain's
  corrected hand-eye slot) from the chain's f-frame columns (jt, jr) of fMc = T X, p_c its origin,
  x = X's origin. A correction of X (on_X): dt_X = R_T^T jt, dphi_X = R_T^T jr, so
  dg = R_T^T dt_X, dphi_G = R_T^T dphi_X. Any other (T's, a joint): T' = exp(xi) T with
  dphi = jr and dp_T = jt + [p_c - p_T]x jr, so dg = -R_T^T (jt + [p_c - x]x jr), dphi_G = -R_T^T jr.
*/
void eyeToHandColumns(const Eigen::Matrix3d &RTT, const Eigen::Vector3d &pc_minus_x, bool on_X,
                      Eigen::Ref<Eigen::Matrix<double, 3, Eigen::Dynamic>> jt,
                      Eigen::Ref<Eigen::Matrix<double, 3, Eigen::Dynamic>> jr, int c)
{
  if (on_X) {
    jt.col(c) = RTT * (RTT * jt.col(c)).eval();
    jr.col(c) = RTT * (RTT * jr.col(c)).eval();
    return;
  }
  jt.col(c) = -RTT * (jt.col(c) + skew(pc_minus_x) * jr.col(c));
  jr.col(c) = -RTT * jr.col(c);
}

/*
  Eye-to-hand: the columns (f-frame columns of the chain's fMc, in place) turned into those of the
  camera pose in e; eMc_block: the chain index of the hand-eye slot's first component, ids the
  column's chain indices (empty: joints, never on X).
*/
void toEyeToHand(const vpKinematicChain &chain, const vpColVector &q, const std::vector<unsigned int> &ids,
                 Eigen::Matrix<double, 3, Eigen::Dynamic> &jt, Eigen::Matrix<double, 3, Eigen::Dynamic> &jr)
{
  const Rigid T = rigidFromVisp(chain.get_fMe(q));
  const Rigid X = rigidFromVisp(chain.get_eMc_corrected());
  const Eigen::Vector3d pc = T.R * X.t + T.t;
  const unsigned int first = chain.getNumParameters() - vpKinematicChain::kBlockSize;
  const Eigen::Matrix3d RTT = T.R.transpose();
  for (int c = 0; c < static_cast<int>(jt.cols()); ++c)
    eyeToHandColumns(RTT, pc - X.t, !ids.empty() && ids[static_cast<size_t>(c)] >= first, jt, jr, c);
}
} // namespace

/*
  Eye-to-hand (Options::eye_to_hand): the camera fixed in f at X = bMc (the chain's corrected
  hand-eye slot), the points in e: the view's pose G = fMe(q)^-1 X, origin g = R_T^T (x - p_T),
  orientation R_T^T R_X; its columns from the chain's (eyeToHandColumns).
*/
void computeEyeToHandView(const vpKinematicChain &chain, const std::vector<unsigned int> &id, const vpColVector &q,
                          bool with_jacobian, ViewState &v)
{
  const Rigid T = rigidFromVisp(chain.get_fMe(q));
  const Rigid X = rigidFromVisp(chain.get_eMc_corrected());
  const Rigid G = T.inverse() * X;
  v.RT = G.R.transpose();
  v.tf = G.t;
  if (!with_jacobian)
    return;
  Eigen::Matrix<double, 3, Eigen::Dynamic> Jt, Jr;
  chainColumns(chain, id, q, Jt, Jr);
  toEyeToHand(chain, q, id, Jt, Jr);
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
                      const double *c, int n_joint, bool camera_delta, bool with_jacobian, ViewState &v,
                      bool eye_to_hand)
{
  vpColVector qe = q;
  for (int i = 0; i < n_joint; ++i)
    qe[static_cast<unsigned int>(i)] += c[i];
  if (eye_to_hand)
    computeEyeToHandView(chain, id, qe, with_jacobian, v);
  else
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
      if (eye_to_hand) { // in e for now
        Eigen::Matrix<double, 3, Eigen::Dynamic> jt = v.Ad.leftCols(n_joint), jr = v.Cd.leftCols(n_joint);
        toEyeToHand(chain, qe, {}, jt, jr);
        v.Ad.leftCols(n_joint) = jt;
        v.Cd.leftCols(n_joint) = jr;
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
  Eye-to-hand (the views' fMe = G are inverted controller poses bMe^-1, whose error is E(delta) on
  bMe's right): the view's pose is E^-1 G eMc, E = [R_E | t]. With q = G t_c (the camera origin
  before E^-1) the camera origin is p = R_E^T (q - t) and its orientation R_E^T R_G R_c:
  dp/dt = -R_E^T, dp/dr = R_E^T [q - t]x J_l(r), dphi/dr = -R_E^T J_l(r), dphi/dt = 0 (left
  perturbations in f).
*/
void computeInvertedPoseNoiseView(const vpKinematicChain &chain, const std::vector<unsigned int> &id,
                                  const Rigid &fMe, const double *delta, bool with_jacobian, ViewState &v)
{
  const Rigid E = rigidFromVector(delta);
  computeHandEyeView(chain, id, E.inverse() * fMe, with_jacobian, v);
  if (!with_jacobian)
    return;
  const Rigid C = rigidFromVisp(chain.get_eMc_corrected());
  const Eigen::Vector3d q = fMe.R * C.t + fMe.t;
  const Eigen::Matrix3d Jl = leftJacobianSO3(Eigen::Vector3d(delta[3], delta[4], delta[5]));
  Eigen::Matrix<double, 3, 6> dp, dphi;
  dp.leftCols<3>() = -E.R.transpose();
  dp.rightCols<3>() = E.R.transpose() * skew(q - E.t) * Jl;
  dphi.leftCols<3>().setZero();
  dphi.rightCols<3>() = -E.R.transpose() * Jl;
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
             double *Jin, double *JX, int P, double *Jdelta)
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
} // namespace vpKinematicBundle
