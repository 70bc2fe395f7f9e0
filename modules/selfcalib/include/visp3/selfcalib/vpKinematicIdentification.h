/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpKinematicIdentification.h
  \brief Pose-based kinematic identification (paper Section 2.3, eq.
*/
#ifndef VP_KINEMATIC_IDENTIFICATION_H
#define VP_KINEMATIC_IDENTIFICATION_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <cstdint>
#include <string>
#include <vector>

#include <visp3/core/vpColVector.h>
#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/core/vpMatrix.h>
#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpObservabilityIndices.h>

/*!
  \class vpKinematicIdentification
  \ingroup group_selfcalib_identification
  \brief Pose-based kinematic identification (paper Section 2.3, eq. 6): the corrections of a
  vpKinematicChain from measured camera poses, by Levenberg-Marquardt (Ceres), residuals weighted by
  their expected noise, started at the chain given (normally the nominal model).

  Measurements:
  - relative (the paper's): cMc_ref = c_i M c_ref, the pose of the camera at the reference
    configuration q_ref seen from the camera at q (what two images give: c2Mc1 with 1 = reference);
  - absolute: fMc at q (a laser tracker, or a test of the theory).

  Residual of one measurement M_meas against the prediction M (6 rows):
      e_t = t(M) - t(M_meas)                 (m, in the measurement's frame)
      e_r = log(R(M) R(M_meas)^T)            (rad, theta-u, same frame)
  each divided by its standard deviation. The Jacobian is analytic, from
  vpKinematicChain::getJacobian() (with the inverse left Jacobian of SO(3) on e_r).

  Identifiability (the estimated set; one rule for every estimator of the module: this class, the
  kinematic bundle adjustment and the pipelines): a deterministic greedy selection that depends only
  on the robot's NOMINAL model and the joint configurations, never on measured values, noise, weights
  or a start estimate, so the same robot and poses always give the same set, whatever the noise.
  - Design Jacobian: the identification Jacobian of the predictions (relative c_i M c_ref or
    absolute fMc) at the nominal model (all corrections zero) and the measurements' joint vectors,
    rows in SI units unweighted (1 m of position error weighs as 1 rad of rotation error), columns in
    the physical unit of their parameter (1 m or 1 rad). The test below is invariant to the scale of
    each column; the columns are normalised to unit norm for the numerics only.
  - Preference order (preferenceOrder()): eMc first (tx ty tz rx ry rz), then the base (tx ty tz rx
    ry rz), then the joint placements base to tip, each in the order rz tz tx rx ry ty. Why: the
    hand-eye transform is the least known part of the model (a rough guess) and, with a camera on
    the flange, the last joint's offset (j6.rz) and slide (j6.tz) are indistinguishable from it, so
    eMc is kept whole (as the hand-eye-only mode estimates it) and they are folded into it; within a
    joint, the joint offset (rz, DH's theta), the slide along the axis (tz, DH's d), then tx and rx
    (DH's a and alpha when the frames are DH frames), then ry (Hayati's beta for parallel axes) and
    ty last: for standard DH frames the kept set is the DH error parameters of each joint, and for
    nominally parallel consecutive axes Hayati's (theta, a, alpha, beta).
  - Walk: a parameter is estimated when its column adds a new direction to the span of those
    already estimated: ||(I - P) a|| / ||a|| > Options::rank_tolerance (default 1e-6: exact
    dependences sit at 1e-13..1e-16, real identifiability at 1e-3 or more; see doc/concepts.md,
    "The estimated set"). A column below 1e-10 of the largest is "no effect" (relative poses
    cancel everything before the first joint rotation: the base and the placement of joint 1); a
    dependent column is reported with the estimated parameters its column is a combination of
    (for example j6.tz with eMc.tz: a slide along the last axis is a hand-eye translation).
  The previous rule (QR with column pivoting of the noise-weighted Jacobian at the start model) chose
  among nearly tied columns by their noisy norms, so the set changed from run to run; it is gone.

  Uncertainty: covariance (J^T J)^-1 of the identified parameters at the solution (Ceres), so the
  standard deviations are those implied by the given measurement noise; sigma0 = sqrt(2 cost / dof)
  tells whether that noise was right (about 1 when it was).
*/
class VISP_SELFCALIB_EXPORT vpKinematicIdentification
{
public:
  //! One pose measurement: the configuration(s) and the measured camera pose with its expected error.
  struct Measurement {
    vpColVector q;            //!< joints of this pose
    vpColVector q_ref;        //!< joints of the reference pose; empty for an absolute measurement
    vpHomogeneousMatrix M;    //!< c_i M c_ref (relative) or fMc (absolute)
    double sd_position = 1e-3; //!< m, expected noise of each translation component
    double sd_rotation = 1e-3; //!< rad, expected noise of each rotation component
    bool isRelative() const { return q_ref.size() > 0; }
  };

  //! Settings of vpKinematicIdentification (the defaults are the member initialisers).
  struct Options {
    double rank_tolerance = 1e-6;     //!< relative new-direction norm below which a column is dependent (see the class)
    double correlation_threshold = 0.95; //!< |correlation| listed above this
    unsigned int max_iterations = 200;
    bool tight = true;                //!< tolerances 1e-15 (exact recovery on noise-free data)
    std::vector<std::string> fixed;   //!< parameters kept at their start value by the caller (names or glob patterns, matchParameters())
    void check() const;
  };

  /*!
    Why a parameter is not estimated: MODEL, the model's structure for these joint configurations
    (no effect on the measurements, or a combination of parameters estimated before it: a redundancy
    of the complete error model); FIXED, the caller fixed it (Options::fixed, calibrate --fix); DATA,
    the data do not determine it (vpKinematicBundleAdjustment: its predicted sd would exceed the
    nominal model's tolerance, or the data cannot separate it from the parameters estimated before
    it), left at its nominal value.
  */
  enum Cause { CAUSE_MODEL, CAUSE_FIXED, CAUSE_DATA };
  //! A parameter not estimated, with the reason and its cause.
  struct Unidentifiable {
    unsigned int index = 0;
    std::string name;
    std::string reason;
    Cause cause = CAUSE_MODEL;
    //! CAUSE_DATA: what would determine it (which joint must move, and about how far), else empty.
    std::string needs;
  };

  //! Which parameters the configurations identify (the estimated set), and why the others are not.
  struct Identifiability {
    std::vector<unsigned int> identified;        //!< parameter indices, in chain order
    std::vector<Unidentifiable> unidentifiable;  //!< the others, with their reason, in chain order
    unsigned int rank = 0;
    std::vector<unsigned int> order;             //!< the preference order walked (preferenceOrder())
    /*!
      Per parameter (chain order): the relative norm of the new direction its column added when it
      was walked, ||(I - P) a|| / ||a|| (1 for the first; 0 when fixed or without effect). Estimated
      parameters are above the threshold, dependent ones far below.
    */
    std::vector<double> new_direction;
    /*!
      The set's bias (vpKinematicBundleAdjustment's set from the data; empty otherwise): rows the
      identified parameters, columns the unidentifiable entries (both in their lists' order), how far
      an error of 1 in a parameter left at nominal by the data moves each estimated one when the
      estimated ones absorb it, -M_ee^-1 M_el of the corrections' marginal information at the start
      values (the scale direction held as in the solve; 0 in the columns of the other causes).
    */
    vpMatrix bias;
    /*!
      vpKinematicBundleAdjustment with a kinematic prior (Settings::kinematic_prior): the parameters
      the data alone do not determine (those the set from the data would leave at nominal, with that
      reason and what would determine them, cause CAUSE_DATA), estimated nonetheless and held near
      their nominal value by the prior. They are also in `identified`. Empty otherwise.
    */
    std::vector<Unidentifiable> held_by_prior;
    //! Whether chain parameter `index` is in held_by_prior.
    bool heldByPrior(unsigned int index) const
    {
      for (const Unidentifiable &u : held_by_prior)
        if (u.index == index)
          return true;
      return false;
    }
  };

  //! A pair of identified parameters whose correlation exceeds the reporting threshold.
  struct Correlation {
    std::string a, b;
    double value = 0;
  };

  enum Status { OK, TOO_FEW_MEASUREMENTS, RANK_DEFICIENT, NO_CONVERGENCE };
  static const char *statusName(Status s);

  //! The result of vpKinematicIdentification: what it computed, and what the caller needs to judge it.
  struct Result {
    Status status = TOO_FEW_MEASUREMENTS;
    std::string message;
    vpKinematicChain chain;              //!< the start chain with the identified corrections
    Identifiability identifiability;
    vpColVector sd;                      //!< per chain parameter (0 for those not identified)
    vpMatrix covariance;                 //!< identified x identified, in identifiability.identified order
    std::vector<Correlation> correlations; //!< pairs above the threshold
    vpObservabilityIndices observability; //!< of the weighted Jacobian of the identified parameters
    double sigma0 = 0;                   //!< sqrt(2 cost / (rows - identified))
    double rms_position = 0, rms_rotation = 0; //!< unweighted residual RMS (m, rad) at the solution
    unsigned int iterations = 0;
  };

  //! Weighted residual (6) of one measurement at the chain's current parameters (see above).
  static vpColVector residual(const vpKinematicChain &chain, const Measurement &measurement);

  /*!
    Weighted identification Jacobian of all chain parameters for the measurements at the chain's
    current parameters (6 rows per measurement).
  */
  static vpMatrix jacobian(const vpKinematicChain &chain, const std::vector<Measurement> &measurements);

  /*!
    The parameter names of the chain that names or shell-style glob patterns (`*`, `?`, `[...]`:
    "j3.*", "eMc.r?") match, each once, in chain order. A pattern that matches nothing throws
    vpSelfCalibException naming it, `what` (the option or key it came from) and the valid names.
  */
  static std::vector<std::string> matchParameters(const vpKinematicChain &chain, const std::vector<std::string> &patterns,
                                                  const std::string &what);

  /*!
    The fixed preference order of the estimated-set selection (see the class): eMc (tx ty tz rx ry
    rz), base (tx ty tz rx ry rz), then j1 .. jn each as rz tz tx rx ry ty; parameter indices.
  */
  static std::vector<unsigned int> preferenceOrder(const vpKinematicChain &chain);

  /*!
    The estimated set (see the class) for the measurements' joint configurations, at the chain's
    NOMINAL model (its corrections are ignored, as are the measured values and their sd).
  */
  static Identifiability analyse(const vpKinematicChain &chain, const std::vector<Measurement> &measurements,
                                 const Options &options);

  /*!
    The identifiable set of a list of configurations: analyse() on the relative poses
    c_kMc_0 = fMc(q_k)^-1 fMc(q_0) of configurations 1.. against configuration 0, at the chain's
    nominal model. Throws vpSelfCalibException with fewer than 2 configurations.
  */
  static Identifiability analyseConfigurations(const vpKinematicChain &chain, const std::vector<vpColVector> &q,
                                               const Options &options);

  /*!
    count configurations drawn uniformly within the chain's joint limits from rng_seed / rng_stream
    (the module's seeded generator), joint by joint, configuration by configuration.
  */
  static std::vector<vpColVector> randomConfigurations(const vpKinematicChain &chain, unsigned int count,
                                                       uint64_t rng_seed, uint64_t rng_stream);

  /*!
    Identification from the chain's current parameters. Throws vpSelfCalibException on caller
    mistakes (joint vectors of the wrong size, non-finite values, non-positive sd, unknown fixed
    name); too few measurements (6 m <= identifiable parameters), a rank-deficient set and no
    convergence are statuses.
  */
  static Result identify(const vpKinematicChain &start, const std::vector<Measurement> &measurements,
                         const Options &options);

  /*!
    Identification of a set the caller decided (normally analyseConfigurations() on every planned
    configuration, so that a pose measurement lost to noise cannot change the set). When these
    measurements do not determine every parameter of the set, the status is RANK_DEFICIENT and the
    message names those parameters. Throws as identify() and on a set of another chain's size.
  */
  static Result identify(const vpKinematicChain &start, const std::vector<Measurement> &measurements,
                         const Options &options, const Identifiability &estimated);
};

#endif
