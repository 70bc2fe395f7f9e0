/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpMeasurementPlanner.h
  \brief Choice of the measurement configurations (paper Section 3.3, eqs.
*/
#ifndef VP_MEASUREMENT_PLANNER_H
#define VP_MEASUREMENT_PLANNER_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpColVector.h>
#include <visp3/selfcalib/vpKinematicBundleAdjustment.h>
#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpObservabilityIndices.h>
#include <visp3/selfcalib/vpPlannerScene.h>

/*!
  \class vpMeasurementPlanner
  \ingroup group_selfcalib_planning
  \brief Choice of the measurement configurations (paper Section 3.3, eqs. 22-39), on the nominal
  model and a rough scene (points in the reference frame f, the camera, the image size).

  <b>The paper's trajectory (planTrajectory).</b> With the configurations q_0 .. q_{m-1}, pair i
  (i = 1..m-1) is (q_0, q_i) and t_i the translation of c_iMc_0 on the nominal model. To first
  order the error of the eq. 21 ratio |t_i| / |t_1| caused by parameter errors drho is
  (g_i - g_1) drho with the row vector
      g_i = t_i^T (dt_i / drho) / |t_i|^2      (eq. 31: t̄_i^T R̄_i df/drho / |t̄_i|^2)
  over the independently identifiable parameters (relative measurements; SI units), so the ratios
  are right whatever drho when all g_i are equal (eq. 38). The cost is
      ratio term + lambda cond(J) + visibility penalty + distinctness penalty.
  Deviation from the paper, on purpose: eq. 39 as printed puts the sum of the consecutive
  differences g_i - g_{i-1} inside one norm, which telescopes to |g_{m-1} - g_1| and ignores every
  pose in between. The ratio term here is the spread sum_i |g_i - mean(g)|^2 (SPREAD, default: the
  scaled pose i keeps the error |T_i| (g_i - g_w) drho, g_w the yardstick's weighted mean), or the
  intent of eq. 39, sum_i |g_i - g_{i-1}|^2 (CONSECUTIVE).

  J is the identification Jacobian of the relative pose measurements of the pairs with the
  pipeline's weights (translation rows divided by direction_sd |t_i|, rotation rows by rotation_sd;
  columns the identifiable parameters in SI units, see vpObservabilityIndices).

  Constraints: joint limits are bounds; every scene point inside the image (with margin +
  planning_margin) and in front of the camera (depth >= min_depth), and configurations at least
  min_joint_distance apart, are smooth penalties (squared hinges). With partial views
  (Scene::min_visible > 0) the hinges hold the required points (the yardstick ends) and the scene's
  centroid only; the count of visible points is checked at the end. The final configurations are
  checked with the scene's margin (not the planning margin): a violation is the status INFEASIBLE.

  <b>Robustness to the nominal model's error.</b> The true robot differs from the nominal model by
  its stated tolerance (TrajectoryOptions::tolerance_*: the sd of a 6-D error on every joint
  placement, the base and eMc). robust_samples models are drawn from it (seeded); the planning
  margin is by default derived from them (robustMargin(): robust_factor times the largest pixel
  displacement of the constrained points over the models and the initial configurations), and a plan
  is OK only when every configuration is visible (scene margin) through every sampled model too.

  Gradient: exact chain rule through g_i, the singular values of J (dsigma = u^T dJ v), the
  projections and the joint distances; the only numerical derivative is that of the per-pair block
  (t_i, dt_i/drho, dtheta_i/drho) with respect to the joints, by central differences of the
  kinematic model (the chain offers first derivatives only).

  <b>Observability selection (selectObservable).</b> For the multi-view pipeline: m configurations
  from a pool (the first one is the reference and always kept), maximizing an observability index
  of J (O1, the D-optimal criterion, by default): greedy addition, then exchanges of one selected
  with one unselected configuration while the index improves.

  <b>Poses to add (planAdditions).</b> After a calibration whose data left parameters at nominal
  (vpKinematicBundleAdjustment::estimatedSet: a joint that barely moves, say), the next poses that
  determine them. Candidates are drawn around the views taken: one joint moved by up to
  AdditionOptions::step, the others re-aimed (damped Gauss-Newton) so that the optical axis passes
  through the scene's centroid at the view's distance; a candidate is kept when within the joint
  limits, min_joint_distance from every view, and when at least min_visible scene points are in view
  (scene margin) through the nominal model and through every model sampled from its tolerance. Its
  simulated observations are the scene points it sees, projected through the nominal model. Score of
  a set of added poses: the estimated set's own walk over the parameters left at nominal (in the
  preference order, each tested with those estimated and those already admitted,
  vpKinematicBundleAdjustment::predictedSd), the sum of log(max(sd / tolerance, 0.1)), lower is
  better. Greedy, until every one is within AdditionOptions::target of its tolerance: the best candidate of the pool, refined by NLopt (LN_BOBYQA, joints within
  +-refine_step of it; a configuration that is not valid scores as undetermined), then the next.
  Finally the estimated set of the views with the proposed poses says what is still left.

  Library code: no printing; caller mistakes throw vpSelfCalibException; failures are statuses.
*/
class VISP_SELFCALIB_EXPORT vpMeasurementPlanner
{
public:
  //! What the camera must see (see vpPlannerScene).
  using Scene = vpPlannerScene;

  enum RatioCost {
    RATIO_CONSECUTIVE, //!< sum_i |g_i - g_{i-1}|^2 (the intent of eq. 39 as printed; default)
    RATIO_SPREAD       //!< sum_i |g_i - mean(g)|^2 (the error the scaled poses keep without noise)
  };
  enum Algorithm {
    ALGO_MMA,    //!< NLopt LD_MMA with the gradient
    ALGO_SLSQP,  //!< NLopt LD_SLSQP with the gradient
    ALGO_LBFGS,  //!< NLopt LD_LBFGS with the gradient (default: fastest here)
    ALGO_BOBYQA  //!< NLopt LN_BOBYQA, derivative-free
  };
  static Algorithm algorithmFromName(const std::string &name); //!< "mma", "slsqp", "lbfgs", "bobyqa"

  //! Settings of planTrajectory(): the paper's cost, the nominal model's tolerance, the optimizer.
  struct TrajectoryOptions {
    //! CONSECUTIVE (default) or SPREAD. Without noise, pose i's position error is
    //! |T_i| (g_i - g_w) drho, g_w the yardstick's weighted mean of the g_j, so the spread around the
    //! mean is the error itself, and SPREAD removes more of it than consecutive differences, which
    //! allow a drift along the trajectory. Under image noise SPREAD gathers the configurations so
    //! tightly that the shared focal length suffers, and real data have noise: CONSECUTIVE is the
    //! default. bench-paper --ratio-cost compares them (doc/benchmarks.md).
    RatioCost ratio_cost = RATIO_CONSECUTIVE;
    double lambda = 1e-7;               //!< weight of cond(J) (the paper's best value)
    Algorithm algorithm = ALGO_LBFGS;
    unsigned int multistart = 2;        //!< extra starts from the initial trajectory perturbed by multistart_sd
    double multistart_sd = 0.05;        //!< rad
    uint64_t seed = 1;                  //!< of the multistart perturbations
    //! px added to Scene::margin inside the penalty (model errors); < 0 (default): derived from the
    //! model's tolerance by robustMargin() at the initial configurations.
    double planning_margin = -1;
    //! The nominal model's stated tolerance: sd of the 6-D error of every joint placement and of the
    //! base (m, rad), and of eMc (the reference scenario's values).
    double tolerance_translation = 1e-3;
    double tolerance_rotation = 0.1 * M_PI / 180.0;
    double tolerance_hand_eye_translation = 1e-3;
    double tolerance_hand_eye_rotation = 0.2 * M_PI / 180.0;
    unsigned int robust_samples = 30; //!< perturbed models of the margin and of the final check (0: no check)
    double robust_factor = 1.5;       //!< derived margin = factor x largest displacement over the samples
    double visibility_weight = 1;       //!< per px^2 of violation
    double min_joint_distance = 0.05;   //!< rad, between any two configurations
    //! rad added to min_joint_distance inside the penalty (as planning_margin for the views): a
    //! squared hinge is only zero outside its threshold, and a cost that pulls configurations
    //! together settles slightly inside it, so a hinge at the checked distance itself ends
    //! INFEASIBLE. Default 20 % of the default min_joint_distance.
    double joint_distance_margin = 0.01;
    double distinct_weight = 1e6;       //!< per rad^2 of violation
    double direction_sd = 5e-3;         //!< rad, row weights of J (as the pipeline)
    double rotation_sd = 5e-3;          //!< rad
    unsigned int max_evaluations = 2000; //!< per start
    double relative_tolerance = 1e-6;   //!< on the cost
    void check() const;
  };

  //! The cost terms at a set of configurations.
  struct CostTerms {
    double ratio = 0;      //!< the ratio term (eq. 31 intent)
    double condition = 0;  //!< cond(J) (eq. 7); infinite if J is rank deficient
    double visibility = 0; //!< penalty (0 when every point is inside the planning margin)
    double distinct = 0;   //!< penalty
    double total = 0;      //!< ratio + lambda condition + penalties
  };

  enum Status {
    OK,
    TOO_FEW_CONFIGURATIONS, //!< 6 (m - 1) <= number of identifiable parameters
    INFEASIBLE,             //!< some scene point outside the image / behind the camera, or configurations too close
    FAILED,                 //!< the optimizer failed on every start
    UNDETERMINED            //!< planAdditions: parameters still left at nominal after the poses proposed
  };
  static const char *statusName(Status s);

  //! The result of vpMeasurementPlanner: what it computed, and what the caller needs to judge it.
  struct Result {
    Status status = FAILED;
    std::string message;
    std::vector<vpColVector> configurations; //!< the plan (the initial ones when not OK)
    CostTerms before, after;
    vpObservabilityIndices observability_before, observability_after; //!< conditioning: condition_number
    double planning_margin = 0;      //!< px, the planning margin used (given or derived)
    unsigned int robust_failures = 0; //!< (configuration, sampled model) pairs of the returned plan not visible
    unsigned int evaluations = 0, starts = 0;
    double seconds = 0;
  };

  enum Index { INDEX_O1, INDEX_O2, INDEX_O3, INDEX_O4, INDEX_O5 };
  static Index indexFromName(const std::string &name); //!< "O1" .. "O5"

  //! Settings of selectObservable(): the index maximised and the search.
  struct SelectionOptions {
    Index index = INDEX_O1;
    unsigned int max_exchange_passes = 20;
    double direction_sd = 5e-3, rotation_sd = 5e-3; //!< rad, row weights of J
    double min_joint_distance = 0.05;               //!< rad: closer candidates are not both taken
    void check() const;
  };

  //! Settings of planAdditions(): how many poses, the candidates, the nominal model's tolerance.
  struct AdditionOptions {
    //! Poses to propose; 0 (default): as many as determine every parameter left, up to max_poses.
    unsigned int poses = 0;
    unsigned int max_poses = 6;
    /*!
      The parameters to determine (names, e.g. a calibration's left_by_data); empty (default): those
      vpKinematicBundleAdjustment::estimatedSet() leaves at nominal for these views.
    */
    std::vector<std::string> left;
    /*!
      Poses are added until every parameter to determine has a predicted sd of at most target times
      its tolerance: below 1, a margin over the estimated set's own test (whose prediction moves with
      the start values a calibration decides it at) and an estimate that improves on the nominal value.
    */
    double target = 0.5;
    unsigned int pool = 64;            //!< candidates drawn per pose (feasible ones kept)
    unsigned int max_evaluations = 30; //!< NLopt refinement of each chosen pose (0: none)
    double step = 0.8;                 //!< rad, largest move of the drawn joint from a view's value
    double refine_step = 0.1;          //!< rad, the refinement's box around the chosen candidate
    double min_joint_distance = 0.05;  //!< rad, from every view and every pose proposed
    //! Scene points a proposed view must see; 0 (default): half the median number the views observe (at least 6).
    unsigned int min_visible = 0;
    uint64_t seed = 1;
    /*!
      The nominal model's tolerance (sd of the 6-D error of the joint placements and eMc) and the
      number of models sampled from it that must see the scene too (TrajectoryOptions' fields of the
      same names; only these are read).
    */
    TrajectoryOptions robust;
    void check() const;
  };

  //! One proposed pose and what it adds.
  struct Addition {
    vpColVector q;
    unsigned int visible = 0;            //!< scene points in view through the nominal model
    std::vector<double> ratio;           //!< per parameter left: predicted sd / tolerance with this pose and those before it
    std::vector<std::string> determined; //!< parameters it brings within target times their tolerance
  };

  //! The result of planAdditions().
  struct AdditionResult {
    Status status = FAILED;  //!< OK: every parameter left is determined with the poses proposed
    std::string message;
    std::vector<std::string> left;     //!< parameters the views leave at nominal (none: nothing to add)
    std::vector<unsigned int> left_index;
    std::vector<double> ratio_before;  //!< their predicted sd / tolerance with the views alone (1e6: undetermined)
    std::vector<Addition> additions;
    std::vector<std::string> still_left; //!< left at nominal by the views and the poses proposed (estimatedSet)
    unsigned int candidates = 0;       //!< feasible candidates scored
    double seconds = 0;
  };

  //! Progress of long runs: stage, done, total.
  using Progress = std::function<void(const std::string &, unsigned int, unsigned int)>;

  /*!
    Throws vpSelfCalibException on an empty scene, a point that is not a 3- or 4-vector, a camera
    without focal length or an empty image.
  */
  vpMeasurementPlanner(const vpKinematicChain &nominal, const Scene &scene);

  //! Indices (in the chain's parameter vector) of the parameters identifiable from relative poses.
  const std::vector<unsigned int> &identifiableParameters() const { return m_identified; }

  //! Cost terms at q (all of the chain's joint count, within limits or not).
  CostTerms cost(const std::vector<vpColVector> &q, const TrajectoryOptions &options) const;
  //! Total cost and its gradient (size 6 m, configuration after configuration).
  double costAndGradient(const std::vector<vpColVector> &q, const TrajectoryOptions &options,
                         vpColVector &gradient) const;
  //! The vectors g_i of eq. 31 (one per pair), for inspection.
  std::vector<vpColVector> ratioSensitivities(const std::vector<vpColVector> &q) const;
  //! Observability of the relative pose measurements of the pairs (0, i).
  vpObservabilityIndices observability(const std::vector<vpColVector> &q, double direction_sd = 5e-3,
                                       double rotation_sd = 5e-3) const;

  //! The scene's visibility rule (every point, or with partial views at least min_visible points and
  //! the required ones) with the given margin, from the nominal camera.
  bool isVisible(const vpColVector &q, double margin) const;
  //! The same rule through another model of the robot (e.g. a perturbed one).
  bool isVisible(const vpKinematicChain &chain, const vpColVector &q, double margin) const;

  //! options.robust_samples models drawn from the nominal model's tolerance (seeded by options.seed).
  std::vector<vpKinematicChain> sampleModels(const TrajectoryOptions &options) const;
  /*!
    The planning margin derived from the model's tolerance: robust_factor times the largest pixel
    displacement, between the nominal and the sampled models, of the constrained points (all points,
    or the required ones and the centroid) at the configurations q. 0 with no samples.
  */
  double robustMargin(const std::vector<vpColVector> &q, const TrajectoryOptions &options) const;
  /*!
    Number of (configuration, sampled model) pairs whose view is not valid (scene margin); the first
    one described in why when given.
  */
  unsigned int robustFailures(const std::vector<vpColVector> &q, const TrajectoryOptions &options,
                              std::string *why = nullptr) const;

  /*!
    An initial smooth trajectory for planTrajectory: m configurations on a closed curve in joint
    space, q_k = centre + s a .* sin(2 pi k / m + 2 pi j / n) for joint j (n joints, so the joints
    are out of phase and the curve is a loop, not a line). a_j is amplitude_j halved until moving
    joint j alone by +-a_j keeps the scene in view and the joint within its limits; s is the largest
    of {1, 0.8, 0.8^2, ...} (down to 1e-3) for which every configuration does. Empty when none does,
    and then `why` (when given) says why: the centre outside the limits, the view at the centre not
    valid with this margin (which point, where), or the loop not fitting at any scale. margin < 0:
    the scene margin plus robustMargin() at the centre with default TrajectoryOptions. Throws on
    sizes that do not match the chain or m < 2.
  */
  std::vector<vpColVector> smoothTrajectory(const vpColVector &centre, const vpColVector &amplitude, unsigned int m,
                                            double margin = -1, std::string *why = nullptr) const;

  /*!
    The paper's optimal trajectory from an initial one (its size is m). Throws on a configuration
    of the wrong size or outside the joint limits.
  */
  Result planTrajectory(const std::vector<vpColVector> &initial, const TrajectoryOptions &options,
                        const Progress &progress = Progress()) const;
  Result planTrajectory(const std::vector<vpColVector> &initial) const;

  /*!
    m configurations of the pool (pool[0] kept as the reference) maximizing the chosen index.
    Throws when m > pool size, m < 2 or a configuration has the wrong size.
  */
  Result selectObservable(const std::vector<vpColVector> &pool, unsigned int m, const SelectionOptions &options,
                          const Progress &progress = Progress()) const;
  Result selectObservable(const std::vector<vpColVector> &pool, unsigned int m) const;

  /*!
    The poses to add to `views` (joints; the scene `points` in f, by id, as reconstructed from them;
    the camera, yardstick, bundle options and noise of the calibration) so that the parameters they
    leave at nominal are determined (see "Poses to add" above). Throws vpSelfCalibException on a view
    without joints of the chain's size, on hand-eye-only bundle options, and as
    vpKinematicBundleAdjustment::estimatedSet().
  */
  AdditionResult planAdditions(const std::vector<vpSelfCalibDataset::View> &views, const vpCameraParameters &camera,
                               const std::map<int, vpColVector> &points, const vpSelfCalibDataset::Yardstick &yardstick,
                               const vpKinematicBundleAdjustment::Options &bundle, const vpSelfCalibNoiseModel &noise,
                               const AdditionOptions &options, const Progress &progress = Progress()) const;

private:
  double evaluate(const std::vector<vpColVector> &q, const TrajectoryOptions &o, CostTerms *terms,
                  std::vector<double> *gradient) const;
  // The steps of evaluate(): the pair blocks of q (with their derivatives when grad is set),
  // then each cost term, added to ct and, when gradient is given, to the gradient.
  struct PairBlocks;
  PairBlocks pairBlocks(const std::vector<vpColVector> &q, bool grad) const;
  void ratioTerm(const PairBlocks &blocks, const TrajectoryOptions &o, CostTerms &ct,
                 std::vector<double> *gradient) const;
  void conditionTerm(const PairBlocks &blocks, const TrajectoryOptions &o, CostTerms &ct,
                     std::vector<double> *gradient) const;
  void visibilityTerm(const std::vector<vpColVector> &q, const PairBlocks &blocks, const TrajectoryOptions &o,
                      CostTerms &ct, std::vector<double> *gradient) const;
  void distinctTerm(const std::vector<vpColVector> &q, const TrajectoryOptions &o, CostTerms &ct,
                    std::vector<double> *gradient) const;
  void checkConfigurations(const std::vector<vpColVector> &q, const char *where, bool limits) const;

  bool visibleWith(const vpKinematicChain &chain, const vpColVector &q, double margin, std::string *why) const;

  vpKinematicChain m_chain;
  Scene m_scene;
  std::vector<vpColVector> m_constrained; //!< points held in view by the penalty
  std::vector<unsigned int> m_identified;
};

#endif
