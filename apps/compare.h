/*
 * visp-selfcalib compare: the pieces its files share (compareCommand.cpp: the command line, the
 * truth file read and the eye-in-hand comparison; compareEyeToHand.cpp: the camera fixed in the world).
 */
#ifndef VISP_SELFCALIB_COMPARE_H
#define VISP_SELFCALIB_COMPARE_H

#include <map>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpColVector.h>
#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/selfcalib/vpKinematicChain.h>

#include "commands.h"

/*!
  compare against the truth of simulate --camera-mount world (its keys bMc and eMo, pose vectors):
  the result's bMc and eMo errors (distance, angle, the largest component error in the result's
  sd) and, with joint readings (the truth's true_model), the error of the camera's view of the
  target cMo(q) over --pairs random configurations. Returns the exit code.
*/
int compareEyeToHand(const CompareArgs &a, const YAML::Node &truth);

/*!
  The truth's bMc and eMo in a calibrated model's own frames (compareEyeToHandFrames.cpp): the full
  kinematics method holds the base's and joint 1's placement at nominal, and bMc takes what the true
  robot has there (a change of the base moves the arm as a change of bMc does), eMo the last joint's
  offset and slide, which no view of a camera fixed in the world tells apart. The same method with
  the result's estimated parameters, on the truth's noise-free views of the target at the dataset's
  joint readings, gives them. False when it cannot (no dataset, or that run does not fit exactly).
*/
bool truthInModelFrames(const vpKinematicChain &truth, const vpKinematicChain &nominal, const vpHomogeneousMatrix &bMc,
                        const vpHomogeneousMatrix &eMo, const std::map<int, vpColVector> &layout,
                        const vpCameraParameters &cam, const std::string &dataset,
                        const std::vector<std::string> &estimated, vpHomogeneousMatrix &bMc_model,
                        vpHomogeneousMatrix &eMo_model);

#endif
