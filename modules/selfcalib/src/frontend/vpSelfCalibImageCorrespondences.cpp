/*
 * ViSP SelfCalib: from images to the observations a calibration runs on (front end, views left
 * out, method choice).
 */
#include <visp3/selfcalib/vpSelfCalibImageCorrespondences.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <utility>

bool vpSelfCalibImageCorrespondences::needsFrontEnd(const vpSelfCalibDataset &dataset)
{
  for (const vpSelfCalibDataset::View &v : dataset.views)
    if (v.points.empty() && !v.image.empty())
      return true;
  return false;
}

vpSelfCalibImageCorrespondences::Result vpSelfCalibImageCorrespondences::fromDatasetImages(vpSelfCalibDataset &dataset,
                                                                                           const Options &options)
{
  Result result;
  if (needsFrontEnd(dataset)) {
    result.front_end = vpFeatureFrontEnd::fillDataset(dataset, options.front_end);
    result.front_end_ran = true;
  }
  finish(dataset, options, result);
  return result;
}

vpSelfCalibImageCorrespondences::Result
vpSelfCalibImageCorrespondences::fromImages(vpSelfCalibDataset &dataset,
                                            const std::vector<vpImage<unsigned char>> &images, const Options &options)
{
  if (images.size() != dataset.views.size())
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               "vpSelfCalibImageCorrespondences: " + std::to_string(images.size()) + " images for " +
                                   std::to_string(dataset.views.size()) + " views");
  Result result;
  result.front_end = vpFeatureFrontEnd::process(images, options.front_end);
  result.front_end_ran = true;
  for (size_t k = 0; k < dataset.views.size(); ++k)
    dataset.views[k].points = result.front_end.observations[k];
  dataset.yardstick.id_a = result.front_end.yardstick_a;
  dataset.yardstick.id_b = result.front_end.yardstick_b;
  finish(dataset, options, result);
  return result;
}

void vpSelfCalibImageCorrespondences::finish(vpSelfCalibDataset &dataset, const Options &options, Result &result)
{
  if (result.front_end_ran) {
    for (bool seen : result.front_end.yardstick_seen)
      result.yardstick_images += seen;
    for (const std::vector<bool> &grid : result.front_end.grid_seen)
      for (bool seen : grid)
        result.grids_found += seen;
    // A view where the front end found nothing (no track, no grid, no yardstick dot) cannot be used.
    std::vector<vpSelfCalibDataset::View> kept;
    for (size_t k = 0; k < dataset.views.size(); ++k) {
      if (dataset.views[k].points.empty()) {
        DroppedView d;
        d.index = static_cast<unsigned int>(k);
        d.image = dataset.views[k].image;
        result.dropped.push_back(d);
      } else
        kept.push_back(std::move(dataset.views[k]));
    }
    dataset.views = std::move(kept);
  }
  if (options.method) {
    result.method = *options.method;
    return;
  }
  result.method = vpRobotSelfCalibration::BUNDLE_ADJUSTMENT;
  for (const vpSelfCalibDataset::View &v : dataset.views)
    if (v.q.size() == 0 && v.has_fMe)
      result.method = vpRobotSelfCalibration::HAND_EYE;
}
