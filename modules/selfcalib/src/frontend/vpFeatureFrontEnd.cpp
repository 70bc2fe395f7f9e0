/*
 * ViSP SelfCalib: correspondences across views from images (OpenCV features), yardstick dots.
 * The steps are in files of their own beside this one: detection (vpFeatureDetection), matching
 * and geometric verification (vpFeatureMatching), tracks (vpFeatureTracks), dot grids and the
 * yardstick (vpDotTargets).
 */
#include <visp3/selfcalib/vpFeatureFrontEnd.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include "../core/vpSelfCalibFiles.h" // checkImageFile
#include "vpDotTargets.h"
#include "vpFeatureDetection.h"
#include "vpFeatureMatching.h"
#include "vpFeatureTracks.h"

#include <chrono>
#include <cmath>
#include <set>

#include <visp3/io/vpImageIo.h>

using namespace vpSelfCalib::frontend;

const char *vpFeatureFrontEnd::detectorName(Detector d) { return d == ORB ? "orb" : "sift"; }

vpFeatureFrontEnd::Detector vpFeatureFrontEnd::detectorFromName(const std::string &name)
{
  if (name == "sift")
    return SIFT;
  if (name == "orb")
    return ORB;
  throw vpSelfCalibException(vpSelfCalibException::badValue, "feature detector '" + name + "': use sift or orb");
}

void vpFeatureFrontEnd::Options::check() const
{
  if (max_features < 8 || !(ratio > 0 && ratio <= 1) || !(ransac_threshold > 0) || min_matches < 8 ||
      !(dot_min_radius > 0 && dot_max_radius > dot_min_radius))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpFeatureFrontEnd: max_features >= 8, ratio in (0, 1], ransac_threshold > 0, "
                               "min_matches >= 8 and 0 < dot_min_radius < dot_max_radius are needed");
  if (!(contrast_threshold > 0) || neighbours < 1 || !(guided_ratio > 0 && guided_ratio <= 1) ||
      !(track_tolerance > 0) || !(min_overlap >= 0 && min_overlap <= 1) ||
      !(min_prior_agreement >= 0 && min_prior_agreement <= 1))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpFeatureFrontEnd: contrast_threshold > 0, neighbours >= 1, guided_ratio in (0, 1], "
                               "track_tolerance > 0, min_overlap and "
                               "min_prior_agreement in [0, 1] are needed");
  if (!prior.empty() && (!(prior.cam.get_px() > 0) || !(prior.cam.get_py() > 0) || !(prior.rotation_sd >= 0) ||
                         !(prior.translation_sd >= 0) || !(prior.depth >= 0) || !std::isfinite(prior.depth)))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpFeatureFrontEnd: the prior needs px, py > 0 and non-negative sd and depth");
  if (!features && dot_grids.empty())
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpFeatureFrontEnd: neither natural features nor dot grids to find");
  std::set<unsigned int> sizes;
  for (const DotGrid &g : dot_grids) {
    if (g.cols < 2 || g.rows < 3 || g.first_id < 0)
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpFeatureFrontEnd: a dot grid needs 2 or more columns, 3 or more rows and a "
                                 "non-negative first id");
    for (const DotGrid &h : dot_grids)
      if (&h != &g && g.first_id <= h.first_id && h.first_id < g.first_id + static_cast<int>(g.size()))
        throw vpSelfCalibException(vpSelfCalibException::badValue,
                                   "vpFeatureFrontEnd: the dot grids' id ranges overlap");
    if (!sizes.insert(g.size()).second)
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpFeatureFrontEnd: the dot grids must have different numbers of dots (a group of "
                                 "dots is recognised by its size)");
  }
}

namespace
{
void checkImages(const std::vector<vpImage<unsigned char>> &images)
{
  const size_t m = images.size();
  if (m < 2)
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpFeatureFrontEnd: at least 2 images are needed");
  for (size_t k = 0; k < m; ++k)
    if (images[k].getWidth() != images[0].getWidth() || images[k].getHeight() != images[0].getHeight() ||
        images[k].getSize() == 0)
      throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                                 "vpFeatureFrontEnd: image " + std::to_string(k) + " is " +
                                     std::to_string(images[k].getWidth()) + " x " +
                                     std::to_string(images[k].getHeight()) + ", image 0 is " +
                                     std::to_string(images[0].getWidth()) + " x " +
                                     std::to_string(images[0].getHeight()));
}

// The masks as OpenCV matrices: none, one for every image, or one per image, each of the images' size.
std::vector<cv::Mat> toMasks(const std::vector<vpImage<unsigned char>> &images, const FrontEnd::Options &opt)
{
  const size_t m = images.size();
  std::vector<cv::Mat> masks;
  if (!opt.masks.empty() && opt.masks.size() != 1 && opt.masks.size() != m)
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               "vpFeatureFrontEnd: " + std::to_string(opt.masks.size()) + " masks for " +
                                   std::to_string(m) + " images (give none, one, or one per image)");
  for (size_t k = 0; k < opt.masks.size(); ++k) {
    if (opt.masks[k].getWidth() != images[0].getWidth() || opt.masks[k].getHeight() != images[0].getHeight())
      throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                                 "vpFeatureFrontEnd: mask " + std::to_string(k) + " is " +
                                     std::to_string(opt.masks[k].getWidth()) + " x " +
                                     std::to_string(opt.masks[k].getHeight()) + ", the images " +
                                     std::to_string(images[0].getWidth()) + " x " +
                                     std::to_string(images[0].getHeight()));
    masks.push_back(toMat(opt.masks[k]));
    if (cv::countNonZero(masks.back()) == 0)
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpFeatureFrontEnd: mask " + std::to_string(k) +
                                     " is black all over: it hides every pixel, so no feature can be found "
                                     "(a mask is white where features are looked for, black where they are not)");
  }
  return masks;
}
} // namespace

vpFeatureFrontEnd::Result vpFeatureFrontEnd::process(const std::vector<vpImage<unsigned char>> &images,
                                                     const Options &opt)
{
  opt.check();
  const auto t0 = std::chrono::steady_clock::now();
  checkImages(images);
  const size_t m = images.size();
  std::vector<cv::Mat> mats(m);
  for (size_t k = 0; k < m; ++k)
    mats[k] = toMat(images[k]);
  const std::vector<cv::Mat> masks = toMasks(images, opt);
  if (!opt.prior.empty() && opt.prior.fMc.size() != m)
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               "vpFeatureFrontEnd: the prior has " + std::to_string(opt.prior.fMc.size()) +
                                   " camera poses for " + std::to_string(m) + " images");
  Result res;
  const Features features = detectFeatures(mats, masks, opt, res);
  const auto t1 = std::chrono::steady_clock::now();
  res.seconds_detection = std::chrono::duration<double>(t1 - t0).count();
  std::vector<std::pair<size_t, size_t>> pairs;
  std::vector<std::vector<Match>> verified;
  if (opt.features)
    matchImages(features, opt, images[0].getWidth(), images[0].getHeight(), pairs, verified, res);
  else
    res.matches.assign(m, std::vector<unsigned int>(m, 0));
  res.seconds_matching = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  TrackOptions track_options;
  track_options.tolerance = opt.track_tolerance;
  track_options.seed = opt.seed;
  track_options.complete = opt.complete_tracks;
  track_options.ratio = opt.ratio;
  track_options.guided_ratio = opt.guided_ratio;
  track_options.threads = threadCount(opt);
  buildTracks(features, pairs, verified, track_options, res);

  for (const DotGrid &g : opt.dot_grids)
    if (g.first_id < static_cast<int>(res.num_tracks) + 2)
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpFeatureFrontEnd: dot grid ids from " + std::to_string(g.first_id) +
                                     " collide with the " + std::to_string(res.num_tracks) +
                                     " feature tracks' ids: use a larger first_id");
  res.grid_seen.assign(opt.dot_grids.size(), std::vector<bool>(m, false));
  std::vector<std::vector<Dot>> loose(m);
  if (opt.yardstick || !opt.dot_grids.empty())
    for (size_t k = 0; k < m; ++k)
      loose[k] = findGrids(images[k], mats[k], opt, res.observations[k], res.grid_seen, k);

  res.yardstick_seen.assign(m, false);
  if (opt.yardstick)
    findYardstick(loose, res);
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

namespace
{
/*
  One image file of a dataset, checked before and after decoding: the file and its header's size
  (a directory, a device, a size that is not the camera's, or a decompression bomb are refused
  without reading the pixels), then the decoded size. `view` names the view ("who: view 3"),
  `kind` the file ("image", "mask").
*/
vpImage<unsigned char> readChecked(const std::string &file, const std::string &view, const std::string &kind,
                                   const vpSelfCalibDataset &ds)
{
  const std::string what = view + ": " + kind;
  auto wrongSize = [&](unsigned long long w, unsigned long long h) {
    return vpSelfCalibException(vpSelfCalibException::dimensionError,
                                what + " '" + file + "' is " + std::to_string(w) + " x " + std::to_string(h) +
                                    ", the camera says " + std::to_string(ds.width) + " x " +
                                    std::to_string(ds.height));
  };
  const vpSelfCalib::ImageHeader h = vpSelfCalib::checkImageFile(file, view + ": cannot read " + kind + " '" + file + "'");
  if (h.known && (h.width != ds.width || h.height != ds.height))
    throw wrongSize(h.width, h.height);
  vpImage<unsigned char> I;
  try {
    vpImageIo::read(I, file);
  } catch (const vpException &e) {
    throw vpSelfCalibException(vpSelfCalibException::ioError,
                               view + ": cannot read " + kind + " '" + file + "': " + e.getStringMessage());
  }
  if (I.getWidth() != ds.width || I.getHeight() != ds.height)
    throw wrongSize(I.getWidth(), I.getHeight());
  return I;
}
} // namespace

std::vector<vpImage<unsigned char>> vpFeatureFrontEnd::readImages(const vpSelfCalibDataset &ds, const std::string &who)
{
  std::vector<vpImage<unsigned char>> images(ds.views.size());
  for (size_t k = 0; k < ds.views.size(); ++k) {
    const std::string view = who + ": view " + std::to_string(k);
    if (ds.views[k].image.empty())
      throw vpSelfCalibException(vpSelfCalibException::badValue, view + " has no image");
    images[k] = readChecked(ds.views[k].image, view, "image", ds);
  }
  return images;
}

std::vector<vpImage<unsigned char>> vpFeatureFrontEnd::viewMasks(const vpSelfCalibDataset &ds,
                                                                 const std::vector<vpImage<unsigned char>> &masks,
                                                                 const std::string &who)
{
  bool any = false;
  for (const vpSelfCalibDataset::View &v : ds.views)
    any = any || !v.mask.empty();
  if (!any)
    return masks;
  const size_t m = ds.views.size();
  if (masks.size() > 1 && masks.size() != m)
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               who + ": " + std::to_string(masks.size()) + " masks for " + std::to_string(m) +
                                   " views (give none, one, or one per view)");
  std::vector<vpImage<unsigned char>> out(m);
  for (size_t k = 0; k < m; ++k) {
    const vpImage<unsigned char> *other = masks.empty() ? nullptr : &masks[masks.size() == 1 ? 0 : k];
    if (other && (other->getWidth() != ds.width || other->getHeight() != ds.height))
      throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                                 who + ": the mask for view " + std::to_string(k) + " is " +
                                     std::to_string(other->getWidth()) + " x " + std::to_string(other->getHeight()) +
                                     ", the camera says " + std::to_string(ds.width) + " x " +
                                     std::to_string(ds.height));
    if (ds.views[k].mask.empty()) {
      out[k] = other ? *other : vpImage<unsigned char>(ds.height, ds.width, 255);
      continue;
    }
    out[k] = readChecked(ds.views[k].mask, who + ": view " + std::to_string(k), "mask", ds);
    if (other) // both: a pixel is searched where both allow it
      for (unsigned int i = 0; i < out[k].getSize(); ++i)
        out[k].bitmap[i] = other->bitmap[i] ? out[k].bitmap[i] : 0;
  }
  return out;
}

vpImage<unsigned char> vpFeatureFrontEnd::readImage(const std::string &file, const std::string &context)
{
  vpSelfCalib::checkImageFile(file, context);
  vpImage<unsigned char> image;
  try {
    vpImageIo::read(image, file);
  } catch (const vpException &e) {
    throw vpSelfCalibException(vpSelfCalibException::ioError, context + ": " + e.getStringMessage());
  }
  return image;
}

vpFeatureFrontEnd::Result vpFeatureFrontEnd::fillDataset(vpSelfCalibDataset &ds, const Options &opt)
{
  const std::vector<vpImage<unsigned char>> images = readImages(ds);
  Options with_masks = opt;
  with_masks.masks = viewMasks(ds, opt.masks);
  const Result r = process(images, with_masks);
  for (size_t k = 0; k < ds.views.size(); ++k)
    ds.views[k].points = r.observations[k];
  ds.yardstick.id_a = r.yardstick_a;
  ds.yardstick.id_b = r.yardstick_b;
  return r;
}
