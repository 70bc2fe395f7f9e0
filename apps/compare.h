/*
 * visp-selfcalib compare: the pieces its files share (compareCommand.cpp: the command line, the
 * truth file read and the eye-in-hand comparison; compareEyeToHand.cpp: the camera fixed in the world).
 */
#ifndef VISP_SELFCALIB_COMPARE_H
#define VISP_SELFCALIB_COMPARE_H

#include <yaml-cpp/yaml.h>

#include "commands.h"

/*!
  compare against the truth of simulate --camera-mount world (its keys bMc and eMo, pose vectors):
  the result's bMc and eMo errors (distance, angle, the largest component error in the result's
  sd) and, with joint readings (the truth's true_model), the error of the camera's view of the
  target cMo(q) over --pairs random configurations. Returns the exit code.
*/
int compareEyeToHand(const CompareArgs &a, const YAML::Node &truth);

#endif
