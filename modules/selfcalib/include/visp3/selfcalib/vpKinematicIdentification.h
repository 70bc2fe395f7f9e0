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

  Identifiability: QR with column pivoting (Eigen ColPivHouseholderQR) of the weighted Jacobian at
  the start, columns scaled to unit norm, rank where |R_kk| < rank_tolerance |R_11|. The pivoted-in
  columns are identified, the others stay at their start value and are reported with the reason:
  "no effect" when their column vanishes (relative poses cancel everything before the first joint
  rotation: the base and the placement of joint 1), otherwise the identified parameters whose columns
  combine into theirs (for example j6.tz with eMc.tz: a slide along the last axis is a hand-eye
  translation).

  Uncertainty: covariance (J^T J)^-1 of the identified parameters at the solution (Ceres), so the
  standard deviations are those implied by the given measurement noise; sigma0 = sqrt(2 cost / dof)
  tells whether that noise was right (about 1 when it was).
*/
class VISP_SELFCALIB_EXPORT vpKinematicIdentification
{
public:
  struct Measurement {
    vpColVector q;            //!< joints of this pose
    vpColVector q_ref;        //!< joints of the reference pose; empty for an absolute measurement
    vpHomogeneousMatrix M;    //!< c_i M c_ref (relative) or fMc (absolute)
    double sd_position = 1e-3; //!< m, expected noise of each translation component
    double sd_rotation = 1e-3; //!< rad, expected noise of each rotation component
    bool isRelative() const { return q_ref.size() > 0; }
  };

  struct Options {
    double rank_tolerance = 1e-6;     //!< relative |R_kk| below which a column is dependent
    double correlation_threshold = 0.95; //!< |correlation| listed above this
    unsigned int max_iterations = 200;
    bool tight = true;                //!< tolerances 1e-15 (exact recovery on noise-free data)
    std::vector<std::string> fixed;   //!< parameters kept at their start value by the caller
    void check() const;
  };

  struct Unidentifiable {
    unsigned int index = 0;
    std::string name;
    std::string reason;
  };

  struct Identifiability {
    std::vector<unsigned int> identified;        //!< parameter indices, in chain order
    std::vector<Unidentifiable> unidentifiable;  //!< the others, with their reason
    unsigned int rank = 0;
    std::vector<double> pivots;                  //!< |R_kk| / |R_11| in pivot order
  };

  struct Correlation {
    std::string a, b;
    double value = 0;
  };

  enum Status { OK, TOO_FEW_MEASUREMENTS, RANK_DEFICIENT, NO_CONVERGENCE };
  static const char *statusName(Status s);

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

  //! Identifiability analysis at the chain's current parameters.
  static Identifiability analyse(const vpKinematicChain &chain, const std::vector<Measurement> &measurements,
                                 const Options &options);

  /*!
    The identifiable set of a list of configurations: analyse() on the relative poses
    c_kMc_0 = fMc(q_k)^-1 fMc(q_0) of configurations 1.. against configuration 0, at the chain's
    current parameters (the measurement values do not matter: the analysis uses the Jacobian of the
    prediction). Throws vpSelfCalibException with fewer than 2 configurations.
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
};

#endif
