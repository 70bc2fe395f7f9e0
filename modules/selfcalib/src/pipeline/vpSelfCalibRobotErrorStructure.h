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
  noise (vpRobotSelfCalibration::JointErrorStructure, carried in the run's result):
  - offset: Student's t of each joint's mean over the views (an estimated joint offset takes the
    mean of the readings' noise, which leaves none);
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
*/
using JointErrorStructure = vpRobotSelfCalibration::JointErrorStructure;

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
  structure (when not null): b's joints' structure, judged once: used as it is when already judged
  (it must then be b's), else it receives the structure when it is judged here.
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
