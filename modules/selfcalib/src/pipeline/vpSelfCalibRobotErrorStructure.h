/*
 * ViSP SelfCalib: whether the joint corrections of a full-kinematics bundle adjustment look like a
 * real arm's reading noise (not installed). Shared by the run, which takes the readings as exact
 * when they do not, and the assessment, which says why.
 */
#ifndef VP_SELFCALIB_ROBOT_ERROR_STRUCTURE_H
#define VP_SELFCALIB_ROBOT_ERROR_STRUCTURE_H

#include <string>
#include <vector>

#include <visp3/selfcalib/vpKinematicBundleAdjustment.h>
#include <visp3/selfcalib/vpSelfCalibDataCheck.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>

namespace vpSelfCalibPipeline
{
/*!
  The structure of the joint corrections dq_k (one per calibration view) against that of reading
  noise, which is independent from view to view and from joint to joint, with mean 0:
  - offset: a joint's corrections have a mean far from 0 against their spread (Student's t over the
    views, two-sided 0.1 % with Bonferroni over the joints): a parameter held at a wrong value, not
    noise (an estimated joint offset takes the mean of the readings' noise, which leaves none);
  - the per-view camera displacements the corrections make, e_k = J_k dq_k (J_k the joint Jacobian
    at the view's readings), under two models: reading noise, e_k ~ N(0, s J_k D J_k^T) (D the
    stated ratios of the joints' sd), and a per-view 6-D pose error of one level in translation and
    one in rotation (a rendering's, a loose camera's, a model residual). Both are compared by their
    restricted likelihood (the contrasts of e that the estimated parameters do not move: the
    corrections are a residual of the adjustment) at their maximum likelihood levels, through the
    Bayesian information criteria. pose_bic_gain > kPoseLikeBic (Kass and Raftery's "very strong"
    evidence, a Bayes factor above 150): pose_like; below -kPoseLikeBic: the joints' noise is
    very strongly the better explanation. Compared on arms of 6 joints or more (fewer do not span a
    6-D displacement: their model residual, a separate variance component, takes it).
  readingNoise(): judged, no offset, and the joint model very strongly preferred: a level beyond a
  well-built arm's stands only on that evidence (on few views, where the images leave much of each
  displacement to the prior, neither model is: the level is not trusted).
  judged: the corrections were there to be judged (a full-kinematics run that modelled the joints).
*/
struct JointErrorStructure {
  bool judged = false;
  double offset_t = 0, offset_bound = 0; //!< the largest |t| of a joint's mean, and the 0.1 % bound
  std::string offset_joint;              //!< the joint of offset_t ("joint 3")
  bool offset = false;
  bool pose_compared = false; //!< the per-view pose model was compared (6 joints or more)
  double pose_bic_gain = 0;   //!< BIC of reading noise minus BIC of a per-view pose error
  bool pose_like = false;
  bool readingNoise() const;
  //! What the corrections look like, for a finding ("a constant offset on joint 3 (t = 9.1)...").
  std::string describe() const;
};

//! Bayesian information criterion gain beyond which the per-view pose model explains the corrections.
constexpr double kPoseLikeBic = 10;

/*!
  The structure of b's joint corrections (b.joint_corrections, one per view of `views`, their
  readings; b.chain the model they were estimated at; noise the joints' sd used, for their ratios).
*/
JointErrorStructure jointErrorStructure(const vpKinematicBundleAdjustment::Result &b, const vpSelfCalibNoiseModel &noise,
                                        const std::vector<vpSelfCalibDataset::View> &views);

/*!
  The robot's error measured (noise) is beyond a real arm's: the model residual beyond
  kModelErrorPlausible, or the joints' level beyond kJointErrorPlausible with corrections that do
  not look like reading noise (jointErrorStructure(): an offset or a per-view pose error; a level
  beyond the bound whose corrections look like reading noise is a low-cost arm's, and stands).
  structure (when not null) receives the joints' structure when it was judged.
*/
bool robotErrorImplausible(const vpSelfCalibNoiseModel &noise, const vpKinematicBundleAdjustment::Result &b,
                           const std::vector<vpSelfCalibDataset::View> &views, JointErrorStructure *structure = nullptr);
/*!
  The warning robot-error-not-measured: the robot's error asked to be measured could not be (the
  corrections at the guessed level leave the estimate undetermined: vpSelfCalib::robotErrorNotMeasured()),
  and the readings and the model are taken as exact. guessed: the joints' level (rad) the
  measurement started from (the prior's, or the dataset's robot_error).
*/
vpSelfCalibDataCheck::Finding robotErrorNotMeasuredFinding(double guessed);
} // namespace vpSelfCalibPipeline

#endif
