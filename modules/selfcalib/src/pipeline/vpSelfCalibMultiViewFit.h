/*
 * ViSP SelfCalib: the assessment's test of the multi-view step's own fit (private to the pipeline).
 */
#ifndef VP_SELFCALIB_MULTIVIEW_FIT_H
#define VP_SELFCALIB_MULTIVIEW_FIT_H

#include <visp3/selfcalib/vpMultiViewReconstruction.h>

namespace vpSelfCalibPipeline
{
/*
  The multi-view step's own fit. Its poses are free, so at its minimum it explains the images at least
  as well as any kinematic model, and its outlier test runs at the noise its residuals measure (the
  median, robust to wrong matches): on image noise its sigma0 is near 1 and it rejects only wrong
  matches. Ended in a local minimum (on a plane of unknown layout, views on the wrong one of their
  homography's two motions: bent, most views 5-35 deg off) it leaves both marks: sigma0 2.1-2.4 and
  3-6 % of the observations rejected where the data had no wrong match (simulated ChArUco corners,
  0.2 px, the reconstruction from its two-view start alone). The kinematic bundle adjustment starts
  from it and fits the rest into a wrong model (eMc 180-230 sd off in those draws) with only a
  noise-mismatch warning. Both marks together are a misfit: sigma0 beyond kMultiViewSigma0Factor
  times its 99.9 % interval's upper bound and more than kMultiViewRejected of the observations
  rejected. A noise stated too small alone raises sigma0, not the rejections (the test runs at the
  measured noise); wrong matches alone raise the rejections, not sigma0; both at once also make it,
  which measuring the noise (sigma0 then near 1) clears. False for a reconstruction that failed.
  The assessment doubts a run on it when the bundle adjustment that started from it does not explain
  the images either (checkMultiViewFit).
*/
constexpr double kMultiViewSigma0Factor = 1.5, kMultiViewRejected = 0.01;

inline bool multiViewMisfit(const vpMultiViewReconstruction::Result &mv)
{
  const unsigned int total = mv.num_observations + mv.num_outliers;
  return mv.status == vpMultiViewReconstruction::OK && mv.sigma0_high > 0 && total > 0 &&
         mv.sigma0 > kMultiViewSigma0Factor * mv.sigma0_high && mv.num_outliers > kMultiViewRejected * total;
}
} // namespace vpSelfCalibPipeline

#endif
