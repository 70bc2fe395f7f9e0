/*
 * ViSP SelfCalib: private interface of the kinematic bundle adjustment's problem (not installed):
 * the inputs checked (stage 1), the estimated set and the start (stage 2), the Ceres problem of one
 * solve (stage 3), all in vpKinematicBundleAdjustmentProblem.cpp, and the covariance (stage 6,
 * vpKinematicBundleAdjustmentCovariance.cpp). The run (stages 4 and 5) is in
 * vpKinematicBundleAdjustment.cpp.
 */
#ifndef VP_KINEMATIC_BUNDLE_ADJUSTMENT_PROBLEM_H
#define VP_KINEMATIC_BUNDLE_ADJUSTMENT_PROBLEM_H

#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <visp3/selfcalib/vpKinematicBundleAdjustment.h>
#include <visp3/selfcalib/vpKinematicIdentification.h>

#include "../core/vpSelfCalibObservations.h"
#include "vpKinematicBundleAdjustmentCosts.h"

namespace vpKinematicBundle
{
struct Obs {
  unsigned int view;
  int id;
  double u, v;
};

using KBA = vpKinematicBundleAdjustment;

/*!
  Scale direction: the corrections s (and a centre c) with J_t s + c = t_k, J_phi s = 0 for every
  view: to first order they scale every camera position about c and leave orientations unchanged.
*/
Eigen::VectorXd scaleDirection(const KinematicState &st, const std::vector<int> &columns = {});

//! The nominal tolerance of a chain parameter (its index: block and component) on an arm of n_joints joints.
double toleranceOf(unsigned int index, unsigned int n_joints, const KBA::Options &opt);

/*
  The scale held without a yardstick, as the nominal lengths' prior weighs it: with the estimated
  corrections' errors independent of sd tol_i (their tolerance), the least-squares scale of the
  corrections rho against the reference rho_0 along the scale direction s is
  e = s^T T^-1 (rho - rho_0) / (s^T T^-1 s), T = diag(tol_i^2), of variance 1 / (s^T T^-1 s): the
  best-known lengths (the joints') fix it, a guess (eMc's) barely. Returns T^-1 s scaled to
  (T^-1 s)^T s = s^T s (the gauge held: s^T T^-1 (rho - rho_0) = 0) and the variance.
*/
Eigen::VectorXd scaleGauge(const KinematicState &st, const Eigen::VectorXd &s, const KBA::Options &opt, double &variance);
//! The intrinsics block of the camera (and, OpenCV model, the given start coefficients).
void intrinsicsFrom(const vpCameraParameters &cam, const vpKinematicBundleAdjustment::Options &o,
                    double in[kIntrinsics]);
//! The ViSP camera of the block: ViSP's model with k_ud when distortion, else the pinhole (the
//! OpenCV coefficients, which vpCameraParameters cannot hold, are returned apart).
vpCameraParameters cameraFrom(const double in[kIntrinsics], Distortion model, bool distortion);

//! Stage 1, inputs: every view's joints (or, hand-eye-only, its end-effector pose), checked; the
//! number of views that see each point id.
void collectViews(const vpKinematicChain &start, const std::vector<vpSelfCalibDataset::View> &views, const KBA::Options &opt,
                  std::vector<vpColVector> &q, std::vector<Rigid> &fMe, std::map<int, unsigned int> &seen);
//! Stage 1, inputs: the start points of the ids seen in two views or more, checked.
std::map<int, Eigen::Vector3d> startPoints(const std::map<int, vpColVector> &points0,
                                           std::map<int, unsigned int> &seen);
//! Stage 2, the estimated corrections (hand-eye-only: the eMc correction; else the module's one
//! rule, vpKinematicIdentification::analyseConfigurations, at the nominal model).
vpKinematicIdentification::Identifiability estimatedSet(const vpKinematicChain &start,
                                                        const std::vector<vpColVector> &q, const KBA::Options &opt);
//! Stage 2, the intrinsics: their start values (in) and the indices estimated.
std::vector<int> estimatedIntrinsics(const vpCameraParameters &camera, const KBA::Options &opt, double in[kIntrinsics]);

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
  Eigen::VectorXd scale_gauge;  //!< the combination held (scaleGauge())
  double scale_variance = 0;    //!< the relative variance of the scale held (scaleGauge())
  //! The nominal lengths' prior on the scale held counted in the covariance (adjust(), not information()).
  bool scale_prior = false;
  /*!
    The kinematic prior (Settings::kinematic_prior): the sd of each correction's prior residual, about
    rho0 (empty: no prior). It holds the scale too: no scale gauge then.
  */
  std::vector<double> prior_sd;
  bool scale_covariance = false, scale_covariance_chi2 = false;
  /*!
    The robot's error measured in full mode: the image noise's sd the pixels are weighed at, over
    noise.pixel_sd (its variance component, measured with the robot's; 1 until measured).
  */
  double pixel_factor = 1;
  //! The image noise's factor the last covariance measured (pixel_factor for the next solve).
  double pixel_factor_measured = 0;
  //! The weights are the measured variance components: the covariance is not scaled by sigma0 again.
  bool components_measured = false;
  vpSelfCalibNoiseModel noise;    //!< the noise of the adjustment (its pixel part, and the robot's)
  bool has_yardstick = false;
  int P = 0;
  //! Known geometry (Options::known_points): the object's pose (t, theta u) in f, when used.
  std::array<double, 6> object{0, 0, 0, 0, 0, 0};
  bool has_object = false;
  //! The known layout's scale (Settings::measure_layout_scale), a parameter when free_layout_scale.
  std::array<double, 1> layout_scale{1};
  bool free_layout_scale = false;

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

//! Stage 2, known geometry: the object's start pose, the rigid fit of its layout to the start points.
void startObject(const std::map<int, vpColVector> &layout, Adjustment &a);
/*!
  Stage 3, one Ceres problem of the schedule (robust loss of the given scale, 0: plain least
  squares), with its elimination ordering. Null when no observation is kept.
*/
std::unique_ptr<ceres::Problem> buildProblem(Adjustment &a, const vpSelfCalibDataset::Yardstick &yardstick,
                                             const KBA::Options &opt, double loss_scale,
                                             std::shared_ptr<ceres::ParameterBlockOrdering> &order,
                                             KBA::ScaleSource &scale_source, bool gauge = true);
/*!
  Stage 2, the estimated set from the data (vpKinematicBundleAdjustment, "The estimated set from the
  data"): the rule's candidates cut to those the information of this adjustment at the start values
  determines. a is the adjustment of the candidates, filled and prepared; q the views' joints.
*/
vpKinematicIdentification::Identifiability
decideSet(Adjustment &a, const vpKinematicChain &start, const vpKinematicIdentification::Identifiability &candidates,
          const std::vector<vpColVector> &q, const vpSelfCalibDataset::Yardstick &yardstick, const KBA::Options &opt);

/*!
  The predicted sd of the corrections `columns` (columns of the candidates a is built on) estimated
  together, the other candidates held: decideSet's test of one subset (the same information, the
  scale direction held without a yardstick). Infinite when the data do not determine them.
*/
Eigen::VectorXd predictedSd(Adjustment &a, const std::vector<int> &columns, const vpSelfCalibDataset::Yardstick &yardstick,
                            const KBA::Options &opt);

/*!
  The parameter blocks of the corrections' marginal information (decideSet) and covariance (stage
  6), listed once for both: kept, in this order, the corrections rho, the estimated intrinsics, the
  yardstick's two ends (linked by their residual), every view's robot-error correction (the
  controller pose corrections delta, then the joint and model-residual corrections dq), the known
  object's pose; eliminated, every other point in the problem (their 3 x 3 Schur complements).
*/
struct MarginalBlocks {
  std::vector<double *> kept, eliminated;
  int num_ends = 0; //!< the yardstick's ends among kept (0 or 2)
};
MarginalBlocks marginalBlocks(Adjustment &a, ceres::Problem &problem, const vpSelfCalibDataset::Yardstick &yardstick);

/*!
  The information of the corrections (the first a.P rows of marginalBlocks()'s kept blocks) with
  every other block eliminated: the points by marginalInformation, then the intrinsics, the
  yardstick's ends, the robot-error corrections and the object's pose by a Schur complement (a
  pseudo-inverse: a nuisance direction the data leave free carries no information to the
  corrections). Empty when the Jacobian cannot be evaluated. Its inverse is the corrections' block of
  the covariance stage 6 computes at the same state (without the scale gauge).
*/
Eigen::MatrixXd correctionInformation(Adjustment &a, ceres::Problem &problem, const vpSelfCalibDataset::Yardstick &yardstick);

/*!
  Stage 6, the covariance of the corrections and the estimated intrinsics with the points
  marginalized, into res. False when the information is singular (res.undetermined then names the
  parameters of the undetermined directions).
*/
bool fillCovariance(Adjustment &a, ceres::Problem &problem, const vpSelfCalibDataset::Yardstick &yardstick,
                    const std::vector<std::string> &names, KBA::Result &res);
} // namespace vpKinematicBundle

#endif
