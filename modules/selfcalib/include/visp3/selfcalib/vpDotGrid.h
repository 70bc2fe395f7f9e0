/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpDotGrid.h
  \brief What a dot target is, as the image front end looks for it: an asymmetric circle grid in OpenCV's
  layout, `rows` rows of `cols` dots, odd rows shifted by half a step, and the scene point ids of
  its dots.
*/
#ifndef VP_DOT_GRID_H
#define VP_DOT_GRID_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

/*!
  \class vpDotGrid
  \ingroup group_selfcalib_frontend
  \brief What a dot target is, as the image front end looks for it: an asymmetric circle grid in
  OpenCV's layout, `rows` rows of `cols` dots, odd rows shifted by half a step, and the scene point
  ids of its dots.

  Dot k is in row i = k / cols and column j = k % cols, at (x(k), y(k)) = (2 j + i % 2, i) in units
  of the grid's step (the distance between two rows) in the target's plane; it gets the id
  first_id + k. A plain description shared by whoever draws a target (vpSelfCalibRenderer) and
  whoever finds it (vpFeatureFrontEnd): neither depends on the other.
*/
class VISP_SELFCALIB_EXPORT vpDotGrid
{
public:
  //! Default first id: far above the ids of the image front end's feature tracks.
  static constexpr int kDefaultFirstId = 1000000;

  unsigned int cols = 4, rows = 5;
  int first_id = kDefaultFirstId; //!< id of dot 0; dot k has first_id + k

  //! Number of dots.
  unsigned int size() const { return cols * rows; }
  //! Place of dot k along the rows, in steps: 2 j + i % 2.
  unsigned int x(unsigned int k) const { return 2 * (k % cols) + (k / cols) % 2; }
  //! Place of dot k across the rows (its row), in steps: i.
  unsigned int y(unsigned int k) const { return k / cols; }
};

#endif
