/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpPlannerScene.h
  \brief What the camera must see at every planned configuration (vpMeasurementPlanner's input): rough
  scene points in the reference frame f, the camera, the image size and the margins.
*/
#ifndef VP_PLANNER_SCENE_H
#define VP_PLANNER_SCENE_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <vector>

#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpColVector.h>

/*!
  \class vpPlannerScene
  \ingroup group_selfcalib_planning
  \brief What the camera must see at every planned configuration (vpMeasurementPlanner's input):
  rough scene points in the reference frame f, the camera, the image size and the margins. A plain
  description: whoever knows the scene (a user, or vpSelfCalibSimulator::getPlannerScene()) fills
  it without depending on the planner; vpMeasurementPlanner checks it.
*/
class VISP_SELFCALIB_EXPORT vpPlannerScene
{
public:
  std::vector<vpColVector> points; //!< in f: 3-vectors or homogeneous 4-vectors
  vpCameraParameters cam;          //!< pinhole (u0, v0, px, py)
  unsigned int width = 0, height = 0; //!< image size (px)
  double margin = 10;      //!< px kept free at the image border (acceptance)
  double min_depth = 0.05; //!< m, minimal depth of a point in the camera frame
  /*!
    Visibility rule. 0: every point inside the image (with the margin) and in front. N > 0 (partial
    views): at least N points and every point listed in `required` (indices into points, e.g. the
    yardstick ends); the planner then keeps the required points and the points' centroid in view.
  */
  unsigned int min_visible = 0;
  std::vector<unsigned int> required; //!< indices into points that every view must see (partial views)
};

#endif
