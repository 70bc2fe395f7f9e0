/*
 * ViSP SelfCalib: kinematic bundle adjustment, the problem: the inputs checked, the estimated set,
 * the start (gauge, known geometry) and the Ceres problem of one solve.
 */
#include "vpKinematicBundleAdjustmentProblem.h"

#include <visp3/selfcalib/vpSelfCalibException.h>

#include <algorithm>
#include <set>

#include <Eigen/Geometry>

#include "../core/vpSelfCalibGeometry.h"

namespace vpKinematicBundle
{
/*
  Scale direction: the corrections s (and a centre c) with J_t s + c = t_k, J_phi s = 0 for every
  view: to first order they scale every camera position about c and leave orientations unchanged.
*/
Eigen::VectorXd scaleDirection(const KinematicState &st, const std::vector<int> &columns)
{
  std::vector<int> cols = columns;
  if (cols.empty())
    for (int i = 0; i < static_cast<int>(st.id.size()); ++i)
      cols.push_back(i);
  const int P = static_cast<int>(cols.size());
  const int m = static_cast<int>(st.q.size());
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(6 * m, P + 3);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(6 * m);
  for (int k = 0; k < m; ++k) {
    const Eigen::Matrix3d R = st.views[k].RT.transpose();
    for (int c = 0; c < P; ++c) {
      A.block(6 * k, c, 3, 1) = R * st.views[k].A.col(cols[c]);
      A.block(6 * k + 3, c, 3, 1) = R * st.views[k].C.col(cols[c]);
    }
    A.block(6 * k, P, 3, 3).setIdentity();
    b.segment<3>(6 * k) = st.views[k].tf;
  }
  return A.colPivHouseholderQr().solve(b).head(P);
}

double toleranceOf(unsigned int index, unsigned int n_joints, const KBA::Options &opt)
{
  const bool eMc = index / vpKinematicChain::kBlockSize == n_joints + 1;
  const bool t = index % vpKinematicChain::kBlockSize < 3;
  return eMc ? (t ? opt.tolerance_hand_eye_translation : opt.tolerance_hand_eye_rotation)
             : (t ? opt.tolerance_translation : opt.tolerance_rotation);
}

Eigen::VectorXd scaleGauge(const KinematicState &st, const Eigen::VectorXd &s, const KBA::Options &opt, double &variance)
{
  Eigen::VectorXd w(s.size());
  double information = 0;
  for (int r = 0; r < s.size(); ++r) {
    const double tol = toleranceOf(static_cast<unsigned int>(st.id[r]), st.chain.getNumJoints(), opt);
    w(r) = tol > 0 ? s(r) / (tol * tol) : 0.0;
    information += w(r) * s(r);
  }
  variance = information > 0 ? 1.0 / information : 0.0;
  // Scaled so that w^T s = s^T s: the held coordinate moves as the plain one along s.
  return information > 0 ? (w * (s.squaredNorm() / information)).eval() : s;
}

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

namespace
{
/*
  Eye-to-hand (Options::eye_to_hand), the module's rule mirrored. The target's motion relative to its
  first view, o_0Mo_k = eMo^-1 fMe(q_0)^-1 fMe(q_k) eMo, does not involve the camera: it has the
  form of the eye-in-hand relative poses with the target's pose eMo in the hand-eye slot, so the
  rule on the views' joints gives the joint placements it determines (the base and joint 1's
  placement cancel in it; the last joint's offset and slide act as a change of eMo). The absolute
  views cMo_k = bMc^-1 fMe(q_k) eMo then add bMc's six, which the base and joint 1's placement
  would only duplicate. Same set, the reasons said for this set-up.
*/
vpKinematicIdentification::Identifiability eyeToHandSet(const vpKinematicChain &start, const std::vector<vpColVector> &q,
                                                        const vpKinematicIdentification::Options &io)
{
  vpKinematicIdentification::Identifiability set = vpKinematicIdentification::analyseConfigurations(start, q, io);
  const unsigned int B = vpKinematicChain::kBlockSize;
  for (auto &u : set.unidentifiable) {
    if (u.cause != vpKinematicIdentification::CAUSE_MODEL)
      continue;
    if (u.index < 2 * B) {
      u.reason = "eye-to-hand: a change of the base or of joint 1's placement moves the whole arm rigidly "
                 "before its first rotation, which a change of bMc (the camera in the base frame, estimated) "
                 "makes in its place";
      continue;
    }
    std::string r = u.reason;
    for (size_t at = r.find("eMc."); at != std::string::npos; at = r.find("eMc.", at + 4))
      r.replace(at, 4, "eMo.");
    u.reason = "eye-to-hand, in the target's motion relative to its first view (the target's pose eMo, "
               "estimated, in the hand-eye slot's place): " + r;
  }
  return set;
}
} // namespace

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
  const std::vector<std::string> fixed_names =
      vpKinematicIdentification::matchParameters(start, opt.fixed, "vpKinematicBundleAdjustment: the fixed parameters");
  if (!opt.hand_eye_only) {
    vpKinematicIdentification::Options io;
    io.rank_tolerance = opt.rank_tolerance;
    io.fixed = fixed_names;
    return opt.eye_to_hand ? eyeToHandSet(start, q, io) : vpKinematicIdentification::analyseConfigurations(start, q, io);
  }
  vpKinematicIdentification::Identifiability ident;
  const unsigned int first = start.getNumParameters() - vpKinematicChain::kBlockSize;
  for (unsigned int i = 0; i < start.getNumParameters(); ++i) {
    const bool fixed = std::find(fixed_names.begin(), fixed_names.end(), names[i]) != fixed_names.end();
    if (i >= first && !fixed)
      ident.identified.push_back(i);
    else
      ident.unidentifiable.push_back({i, names[i],
                                      fixed ? "fixed by the caller" : "hand-eye-only mode: the robot's kinematics are trusted",
                                      fixed ? vpKinematicIdentification::CAUSE_FIXED
                                            : vpKinematicIdentification::CAUSE_MODEL,
                                      ""});
  }
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
                                             KBA::ScaleSource &scale_source, bool gauge)
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
    problem->AddResidualBlock(new ObservationCost(&a.state, a.obs[n].view, a.obs[n].u, a.obs[n].v,
                                                 a.noise.pixel_sd * a.pixel_factor),
                              loss_scale > 0 ? makeLoss(static_cast<RobustLoss>(a.noise.loss), loss_scale) : nullptr,
                              blocks);
    // The yardstick residual links its two ends: they stay in the reduced system.
    const bool end = a.has_yardstick && (a.obs[n].id == yardstick.id_a || a.obs[n].id == yardstick.id_b);
    order->AddElementToGroup(Xp, end ? 1 : 0);
  }
  if (!problem->HasParameterBlock(a.in))
    return nullptr;
  // With the layout's scale free (measureLayoutScale) a yardstick between two of its points is part
  // of the layout (a board's row at its declared size): left out, or it would hold the scale.
  const bool layout_yardstick = a.free_layout_scale && opt.known_points.count(yardstick.id_a) &&
                                opt.known_points.count(yardstick.id_b);
  const bool use_yardstick = a.has_yardstick && !layout_yardstick && problem->HasParameterBlock(a.X[yardstick.id_a].data()) &&
                             problem->HasParameterBlock(a.X[yardstick.id_b].data());
  // Eye-to-hand with a target of known points: its layout fixes the scale.
  bool known = false;
  for (const auto &e : opt.known_points)
    known = known || (a.has_object && a.X.count(e.first) && problem->HasParameterBlock(a.X[e.first].data()));
  scale_source = opt.hand_eye_only ? KBA::SCALE_ROBOT_MOTION
                 : use_yardstick  ? KBA::SCALE_YARDSTICK
                 : (opt.eye_to_hand && known) ? KBA::SCALE_KNOWN_POINTS
                                              : KBA::SCALE_NOMINAL;
  // With the scale free and no known layout, the yardstick is what is measured: its declared length
  // times the free scale (measureLayoutScale), the robot's metric motion the only reference.
  const bool scaled_yardstick = use_yardstick && a.free_layout_scale && !known;
  if (scaled_yardstick)
    problem->AddResidualBlock(new ceres::AutoDiffCostFunction<ScaledYardstickCost, 1, 3, 3, 1>(
                                  new ScaledYardstickCost(yardstick.length, opt.yardstick_sd)),
                              nullptr, a.X[yardstick.id_a].data(), a.X[yardstick.id_b].data(), a.layout_scale.data());
  else if (use_yardstick)
    problem->AddResidualBlock(new ceres::AutoDiffCostFunction<YardstickCost, 1, 3, 3>(
                                  new YardstickCost(yardstick.length, opt.yardstick_sd)),
                              nullptr, a.X[yardstick.id_a].data(), a.X[yardstick.id_b].data());
  else if (scale_source == KBA::SCALE_NOMINAL && gauge && a.prior_sd.empty())
    problem->AddResidualBlock(new ScaleCost(a.scale_gauge, a.rho0), nullptr, a.state.rho.data());
  // The kinematic prior on every correction (it holds the scale without a yardstick).
  if (!a.prior_sd.empty() && a.prior_sd.size() == a.state.rho.size())
    problem->AddResidualBlock(kinematicPriorCost(a.rho0, a.prior_sd), nullptr, a.state.rho.data());
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
    problem->AddResidualBlock(jointPriorCost(a.joint_sd), nullptr, a.state.dq[k].data());
    order->AddElementToGroup(a.state.dq[k].data(), 4 + static_cast<int>(k));
  }
  if (a.has_object) {
    for (const auto &e : opt.known_points)
      if (a.X.count(e.first) && problem->HasParameterBlock(a.X[e.first].data())) {
        if (a.free_layout_scale)
          problem->AddResidualBlock(new ceres::AutoDiffCostFunction<ScaledKnownPointCost, 3, 6, 1, 3>(
                                        new ScaledKnownPointCost(e.second, opt.known_points_sd)),
                                    nullptr, a.object.data(), a.layout_scale.data(), a.X[e.first].data());
        else
          problem->AddResidualBlock(new ceres::AutoDiffCostFunction<KnownPointCost, 3, 6, 3>(
                                        new KnownPointCost(e.second, opt.known_points_sd)),
                                    nullptr, a.object.data(), a.X[e.first].data());
      }
    const int group = 4 + static_cast<int>(std::max(a.state.delta.size(), a.state.dq.size()));
    if (problem->HasParameterBlock(a.object.data()))
      order->AddElementToGroup(a.object.data(), group);
    if (problem->HasParameterBlock(a.layout_scale.data()))
      order->AddElementToGroup(a.layout_scale.data(), group + 1);
  } else if (scaled_yardstick) {
    const int group = 5 + static_cast<int>(std::max(a.state.delta.size(), a.state.dq.size()));
    order->AddElementToGroup(a.layout_scale.data(), group);
  }
  if (a.free_in.empty())
    problem->SetParameterBlockConstant(a.in);
  else if (a.subset)
    problem->SetManifold(a.in, a.subset.get());
  return problem;
}

MarginalBlocks marginalBlocks(Adjustment &a, ceres::Problem &problem, const vpSelfCalibDataset::Yardstick &yardstick)
{
  MarginalBlocks b;
  b.kept.push_back(a.state.rho.data());
  if (!a.free_in.empty())
    b.kept.push_back(a.in);
  std::set<const double *> ends;
  if (a.has_yardstick && problem.HasParameterBlock(a.X[yardstick.id_a].data()) &&
      problem.HasParameterBlock(a.X[yardstick.id_b].data()))
    for (int e : {yardstick.id_a, yardstick.id_b}) {
      b.kept.push_back(a.X[e].data());
      ends.insert(a.X[e].data());
    }
  b.num_ends = static_cast<int>(ends.size());
  for (auto &d : a.state.delta)
    b.kept.push_back(d.data());
  for (auto &d : a.state.dq)
    b.kept.push_back(d.data());
  if (a.has_object && problem.HasParameterBlock(a.object.data()))
    b.kept.push_back(a.object.data());
  if (a.free_layout_scale && problem.HasParameterBlock(a.layout_scale.data()))
    b.kept.push_back(a.layout_scale.data()); // after the object's block: the last one kept
  for (const auto &e : a.X.index())
    if (!ends.count(a.X[e.first].data()) && problem.HasParameterBlock(a.X[e.first].data()))
      b.eliminated.push_back(a.X[e.first].data());
  return b;
}

} // namespace vpKinematicBundle
