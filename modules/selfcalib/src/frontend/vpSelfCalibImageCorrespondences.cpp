/*
 * ViSP SelfCalib: from images to the observations a calibration runs on (front end, views left
 * out, method choice).
 */
#include <visp3/selfcalib/vpSelfCalibImageCorrespondences.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

#include <visp3/io/vpImageIo.h>

#include <opencv2/imgproc.hpp>

bool vpSelfCalibImageCorrespondences::needsFrontEnd(const vpSelfCalibDataset &dataset)
{
  for (const vpSelfCalibDataset::View &v : dataset.views)
    if (v.points.empty() && !v.image.empty())
      return true;
  return false;
}

vpFeatureFrontEnd::Prior vpSelfCalibImageCorrespondences::makePrior(const vpKinematicChain &model,
                                                                   const vpSelfCalibDataset &dataset)
{
  vpFeatureFrontEnd::Prior prior;
  for (const vpSelfCalibDataset::View &v : dataset.views) {
    if (v.q.size() == model.getNumJoints() && v.q.size() > 0)
      prior.fMc.push_back(model.get_fMc(v.q));
    else if (v.q.size() == 0 && v.has_fMe)
      prior.fMc.push_back(v.fMe * model.get_eMc());
    else
      return vpFeatureFrontEnd::Prior();
  }
  prior.cam = dataset.cam;
  return prior;
}

namespace
{
// The front end's options with the model's prior when the caller asked for one.
vpFeatureFrontEnd::Options withPrior(const vpSelfCalibImageCorrespondences::Options &options,
                                     const vpSelfCalibDataset &dataset)
{
  vpFeatureFrontEnd::Options fo = options.front_end;
  // The yardstick's dots are looked for only when the dataset declares a yardstick: dots found in a
  // scene that has none would be a false yardstick.
  fo.yardstick = fo.yardstick && dataset.yardstick.length > 0;
  if (options.prior && fo.prior.empty() && fo.features) {
    const vpFeatureFrontEnd::Prior p = vpSelfCalibImageCorrespondences::makePrior(*options.prior, dataset);
    fo.prior.fMc = p.fMc;
    fo.prior.cam = p.cam;
  }
  return fo;
}
// Options that cannot work, refused before any image is read.
void checkOptions(const vpSelfCalibImageCorrespondences::Options &options)
{
  if (options.mask_board) {
    if (!options.board)
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpSelfCalibImageCorrespondences: mask_board needs a board to mask");
    if (!options.front_end.features)
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpSelfCalibImageCorrespondences: mask_board leaves only natural features, and "
                                 "the front end's features are off");
    if (!(options.mask_margin >= 0 && options.mask_margin < 1e4))
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpSelfCalibImageCorrespondences: mask_margin must be in [0, 1e4) px");
  }
}
} // namespace

vpSelfCalibImageCorrespondences::Result vpSelfCalibImageCorrespondences::fromDatasetImages(vpSelfCalibDataset &dataset,
                                                                                           const Options &options)
{
  checkOptions(options);
  Result result;
  if (needsFrontEnd(dataset)) {
    if (options.board)
      runOnImages(dataset, readImages(dataset), options, result);
    else {
      result.front_end = vpFeatureFrontEnd::fillDataset(dataset, withPrior(options, dataset));
      result.front_end_ran = true;
      result.warnings.insert(result.warnings.end(), result.front_end.warnings.begin(), result.front_end.warnings.end());
    }
  }
  finish(dataset, options, result);
  return result;
}

std::vector<vpImage<unsigned char>> vpSelfCalibImageCorrespondences::readImages(const vpSelfCalibDataset &dataset)
{
  return vpFeatureFrontEnd::readImages(dataset, "vpSelfCalibImageCorrespondences");
}

vpSelfCalibImageCorrespondences::Result
vpSelfCalibImageCorrespondences::fromImages(vpSelfCalibDataset &dataset,
                                            const std::vector<vpImage<unsigned char>> &images, const Options &options)
{
  if (images.size() != dataset.views.size())
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               "vpSelfCalibImageCorrespondences: " + std::to_string(images.size()) + " images for " +
                                   std::to_string(dataset.views.size()) + " views");
  checkOptions(options);
  Result result;
  runOnImages(dataset, images, options, result);
  finish(dataset, options, result);
  return result;
}

void vpSelfCalibImageCorrespondences::runOnImages(vpSelfCalibDataset &dataset,
                                                  const std::vector<vpImage<unsigned char>> &images,
                                                  const Options &options, Result &result)
{
  // The board only masked: found in every image, its region out of the front end's masks.
  vpFeatureFrontEnd::Options front_end = withPrior(options, dataset);
  front_end.masks = vpFeatureFrontEnd::viewMasks(dataset, front_end.masks, "vpSelfCalibImageCorrespondences");
  if (options.board && options.mask_board) {
    const vpBoardDetector detector(*options.board);
    const std::vector<vpImage<unsigned char>> user = front_end.masks;
    front_end.masks.clear();
    result.board_ran = true;
    for (size_t k = 0; k < images.size(); ++k) {
      result.board.push_back(detector.detect(images[k]));
      const vpBoardDetector::Result &b = result.board.back();
      vpImage<unsigned char> mask = boardMask(b, images[k].getHeight(), images[k].getWidth(), options.mask_margin);
      if (!user.empty()) {
        const vpImage<unsigned char> &u = user[user.size() == 1 ? 0 : std::min(k, user.size() - 1)];
        if (u.getHeight() == mask.getHeight() && u.getWidth() == mask.getWidth())
          for (unsigned int i = 0; i < mask.getSize(); ++i)
            mask.bitmap[i] = u.bitmap[i] ? mask.bitmap[i] : 0;
        else // the front end's own check names the wrong size
          mask = u;
      }
      front_end.masks.push_back(mask);
      if (b.found)
        ++result.board_images;
      else
        result.warnings.push_back("view " + std::to_string(k) +
                                  (dataset.views[k].image.empty() ? std::string() : " (" + dataset.views[k].image + ")") +
                                  ": board not found, so not masked: " + b.message);
    }
  }
  // Without a board the feature front end always runs (and refuses options that find nothing).
  if (!options.board || options.mask_board || options.front_end.features || !options.front_end.dot_grids.empty()) {
    result.front_end = vpFeatureFrontEnd::process(images, front_end);
    result.front_end_ran = true;
    result.warnings.insert(result.warnings.end(), result.front_end.warnings.begin(), result.front_end.warnings.end());
    for (size_t k = 0; k < dataset.views.size(); ++k)
      dataset.views[k].points = result.front_end.observations[k];
    dataset.yardstick.id_a = result.front_end.yardstick_a;
    dataset.yardstick.id_b = result.front_end.yardstick_b;
  } else {
    // The board alone: the views' points are the board's, the yardstick's ends are not known yet.
    for (vpSelfCalibDataset::View &v : dataset.views)
      v.points.clear();
    dataset.yardstick.id_a = dataset.yardstick.id_b = -1;
  }
  if (options.board && !options.mask_board)
    addBoard(dataset, images, options, result);
}

vpImage<unsigned char> vpSelfCalibImageCorrespondences::boardMask(const vpBoardDetector::Result &board,
                                                                  unsigned int height, unsigned int width,
                                                                  double margin)
{
  vpImage<unsigned char> mask(height, width, 255);
  if (!board.found || board.corners.empty())
    return mask;
  std::vector<cv::Point> pts, hull;
  for (const auto &o : board.corners)
    pts.emplace_back(static_cast<int>(std::lround(o.ip.get_u())), static_cast<int>(std::lround(o.ip.get_v())));
  cv::convexHull(pts, hull);
  cv::Mat m(static_cast<int>(height), static_cast<int>(width), CV_8UC1, mask.bitmap);
  cv::fillConvexPoly(m, hull, cv::Scalar(0));
  const int thickness = static_cast<int>(std::lround(2 * margin));
  if (thickness > 0)
    cv::polylines(m, hull, true, cv::Scalar(0), thickness);
  return mask;
}

void vpSelfCalibImageCorrespondences::addBoard(vpSelfCalibDataset &dataset,
                                               const std::vector<vpImage<unsigned char>> &images,
                                               const Options &options, Result &result)
{
  const vpBoardDetector detector(*options.board);
  const int first = options.board->id_offset,
            last = first + options.board->numIds() - 1;
  auto collision = [&](const std::string &what) {
    return vpSelfCalibException(vpSelfCalibException::badValue,
                                "vpSelfCalibImageCorrespondences: the board's ids (" + std::to_string(first) + " to " +
                                    std::to_string(last) + ") collide with " + what +
                                    ": choose another board id offset");
  };
  for (const vpFeatureFrontEnd::DotGrid &g : options.front_end.dot_grids)
    if (g.first_id <= last && first < g.first_id + static_cast<int>(g.cols * g.rows))
      throw collision("a dot grid's (from " + std::to_string(g.first_id) + ")");
  for (const vpSelfCalibDataset::View &v : dataset.views)
    for (const vpSelfCalibDataset::Observation &o : v.points)
      if (o.id >= first && o.id <= last)
        throw collision("the front end's point " + std::to_string(o.id));

  result.board_ran = true;
  for (size_t k = 0; k < images.size(); ++k) {
    result.board.push_back(detector.detect(images[k]));
    const vpBoardDetector::Result &b = result.board.back();
    if (b.found) {
      ++result.board_images;
      std::vector<vpSelfCalibDataset::Observation> &points = dataset.views[k].points;
      points.insert(points.end(), b.corners.begin(), b.corners.end());
    } else
      result.warnings.push_back("view " + std::to_string(k) +
                                (dataset.views[k].image.empty() ? std::string() : " (" + dataset.views[k].image + ")") +
                                ": board not found: " + b.message);
  }
  // The yardstick rule (see the class).
  if (!dataset.yardstick.isSet() && result.board_images >= 2) {
    if (dataset.yardstick.length > 0) {
      std::ostringstream w;
      w << "the dataset's yardstick (" << dataset.yardstick.length
        << " m) was not found in the images: the board's first row is the yardstick instead";
      result.warnings.push_back(w.str());
    }
    dataset.yardstick = detector.getYardstick();
    result.board_yardstick = true;
  }
}

void vpSelfCalibImageCorrespondences::finish(vpSelfCalibDataset &dataset, const Options &options, Result &result)
{
  if (result.front_end_ran || result.board_ran) {
    for (bool seen : result.front_end.yardstick_seen)
      result.yardstick_images += seen;
    for (const std::vector<bool> &grid : result.front_end.grid_seen)
      for (bool seen : grid)
        result.grids_found += seen;
    // A view where the front end found nothing (no track, no grid, no yardstick dot, no board) cannot
    // be used.
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
