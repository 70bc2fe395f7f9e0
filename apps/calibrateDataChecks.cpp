/*
 * visp-selfcalib calibrate: the checks of the dataset against the robot and the method (the
 * controller poses' and the yardstick's units against the arm's reach, what the robot model is
 * used for, the data the method needs), see calibrate.h.
 */
#include "calibrate.h"

#include <algorithm>
#include <iostream>

#include <visp3/selfcalib/vpKinematicChain.h>

double armReach(const vpSelfCalibDataset &ds, const vpKinematicChain &nominal)
{
  double reach = 0;
  for (const vpSelfCalibDataset::View &v : ds.views) {
    if (v.has_fMe)
      reach = std::max(reach, v.fMe.getTranslationVector().frobeniusNorm());
    else if (v.q.size() == nominal.getNumJoints())
      reach = std::max(reach, nominal.get_fMe(v.q).getTranslationVector().frobeniusNorm());
  }
  return reach;
}

int checkYardstick(const std::string &dataset, const vpSelfCalibDataset &ds, const vpKinematicChain &nominal)
{
  // The yardstick is measured in the scene the arm's motion measures (the camera's translations
  // between views, at most twice the reach): one ten times the flange's farthest position from the
  // base is a length in other units (mm typed as m), and the scale it sets contradicts the robot's
  // motion so far that the adjustment fails without naming it.
  // Under a thousandth of the reach it is a few pixels at the distances the arm puts the camera
  // (a 1 mm yardstick 0.5 m away is 3 px at f = 1500 px): no image measures it.
  constexpr double kTimesReach = 10.0, kFractionOfReach = 1e-3;
  const double reach = armReach(ds, nominal);
  if (ds.yardstick.length <= 0 || reach <= 0)
    return 0;
  if (ds.yardstick.length < kFractionOfReach * reach) {
    std::cerr << "error: " << dataset << ": the yardstick is " << ds.yardstick.length << " m long, under a "
              << "thousandth of the arm's reach in these views (the flange at most " << reach << " m from the base): "
              << "no image at the distances the arm puts the camera measures it, and its scale would contradict "
              << "the robot's motion; yardstick: length is in metres (a length in other units?)\n";
    return 1;
  }
  if (ds.yardstick.length <= kTimesReach * reach)
    return 0;
  std::cerr << "error: " << dataset << ": the yardstick is " << ds.yardstick.length << " m long, "
            << static_cast<int>(ds.yardstick.length / reach) << " times the arm's reach in these views (the flange at "
            << "most " << reach << " m from the base): the robot's motion cannot measure a scene that large, and "
            << "its scale would contradict the yardstick's; yardstick: length is in metres (a length in mm?)\n";
  return 1;
}

void noteYardstickLength(const vpSelfCalibDataset &ds, const vpKinematicChain &nominal,
                         const std::vector<vpSelfCalibDataCheck::Finding> &findings)
{
  const double reach = armReach(ds, nominal);
  if (ds.yardstick.length > reach && reach > 0) {
    std::cerr << "note: the yardstick (" << ds.yardstick.length << " m) is longer than the arm's reach in these "
              << "views (" << reach << " m): if its length is not in metres, that alone explains a failed or "
              << "doubtful run or its points rejected (its scale contradicts the robot's motion)\n";
    return;
  }
  // The bundle method takes its scale from the yardstick: a length a few % off scales every length
  // of the model by as much, and the link lengths' corrections then exceed their tolerance.
  // Parameters fixed by the user lead (leadWithFixedParameters): the yardstick is not named then.
  const auto has = [&findings](const char *code) {
    return std::any_of(findings.begin(), findings.end(),
                       [code](const vpSelfCalibDataCheck::Finding &f) { return f.code == code; });
  };
  if (has("correction-beyond-tolerance") && !has("fixed-parameters-misfit") && ds.yardstick.isSet())
    std::cerr << "note: the yardstick (points " << ds.yardstick.id_a << " and " << ds.yardstick.id_b << ", "
              << ds.yardstick.length << " m) sets this calibration's scale: if its length is a few % off, the "
              << "model's lengths are scaled by as much and their corrections exceed the tolerance as above: check "
              << "its length (measured, in metres)\n";
}

int checkControllerPoses(const std::string &dataset, const vpSelfCalibDataset &ds)
{
  // No robot arm or gantry puts its end-effector 100 m from its base: beyond, the translations are
  // in other units (mm typed as m), and the calibration would end doubtful for another reason.
  constexpr double kReach = 100.0;
  for (size_t k = 0; k < ds.views.size(); ++k) {
    if (!ds.views[k].has_fMe)
      continue;
    const double d = ds.views[k].fMe.getTranslationVector().frobeniusNorm();
    if (d > kReach) {
      std::cerr << "error: " << dataset << ": pose " << k << "'s fMe puts the end-effector " << d
                << " m from the robot's base: no robot reaches " << kReach << " m; fMe is (tx, ty, tz) in metres "
                << "and theta-u in radians (a translation in mm?)\n";
      return 1;
    }
  }
  return 0;
}

void noteRobotModel(const vpSelfCalibDataset &ds, vpRobotSelfCalibration::Method method)
{
  // A view gives joints or a controller pose, never both (the dataset's rule): on controller poses
  // alone, a wrong robot name changes nothing but eMc's start, and nothing else would say so.
  if (method == vpRobotSelfCalibration::HAND_EYE && controllerPosesOnly(ds))
    std::cerr << "... robot model " << ds.robot << ": its kinematics are not used: the hand-eye method takes the "
              << "views' controller poses (fMe) as they are (the model gives only the start of eMc)\n";
}

int checkMethodData(vpRobotSelfCalibration::Method method, const vpSelfCalibDataset &ds)
{
  if (method == vpRobotSelfCalibration::HAND_EYE)
    return 0;
  size_t without = 0, first = ds.views.size();
  for (size_t k = 0; k < ds.views.size(); ++k)
    if (ds.views[k].q.size() == 0) {
      ++without;
      first = std::min(first, k);
    }
  if (without == 0)
    return 0;
  std::cerr << "error: --method " << vpRobotSelfCalibration::methodName(method) << " calibrates the kinematic "
            << "model from joint readings, and " << without << " of the " << ds.views.size()
            << " views (view " << first << " the first) give a controller pose (fMe) instead: use --method "
            << "hand-eye (eMc and the camera from controller poses), or record the joints\n";
  return 1;
}
