/*
 * The wrong guesses a start is tested from (testMeasuredStart.cpp, bench-start): an eMc guess turned
 * by 90 deg, a focal guess other than the truth. Not installed.
 */
#ifndef VP_SELFCALIB_TEST_START_GUESSES_H
#define VP_SELFCALIB_TEST_START_GUESSES_H

#include <cmath>

#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/core/vpPoseVector.h>
#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>

namespace selfcalib_test
{
//! The model with its eMc guess turned by 90 deg about the camera's x axis.
inline vpKinematicChain turned90(const vpKinematicChain &model)
{
  vpKinematicChain out = model;
  vpHomogeneousMatrix R;
  R.buildFrom(0, 0, 0, M_PI / 2, 0, 0);
  out.set_eMc(vpPoseVector(model.get_eMc() * R));
  return out;
}

//! The dataset with the focal length to be self-calibrated from the guess g (px; the aspect ratio kept).
inline vpSelfCalibDataset withGuess(vpSelfCalibDataset ds, double g)
{
  ds.focal_known = false;
  const double mu = ds.cam.get_py() / ds.cam.get_px();
  ds.cam.initPersProjWithoutDistortion(g, mu * g, ds.cam.get_u0(), ds.cam.get_v0());
  return ds;
}
} // namespace selfcalib_test

#endif
