/*
 * ViSP SelfCalib: self-calibration of camera-equipped robot manipulators.
 * SPDX-License-Identifier: GPL-2.0-or-later
 */
/*!
  \file vpSelfCalibImageCorrespondences.h
  \brief What comes between acquiring images and calibrating: the image front end (vpFeatureFrontEnd)
  fills the dataset's observations and the yardstick's ends, the views where it found nothing are
  left out (they cannot be used), and the calibration method is chosen.
*/
#ifndef VP_SELFCALIB_IMAGE_CORRESPONDENCES_H
#define VP_SELFCALIB_IMAGE_CORRESPONDENCES_H

#include <visp3/selfcalib/vpSelfCalibExport.h>

#include <optional>
#include <string>
#include <vector>

#include <visp3/core/vpImage.h>
#include <visp3/selfcalib/vpFeatureFrontEnd.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>

/*!
  \class vpSelfCalibImageCorrespondences
  \ingroup group_selfcalib_frontend
  \brief What comes between acquiring images and calibrating: the image front end
  (vpFeatureFrontEnd) fills the dataset's observations and the yardstick's ends, the views where
  it found nothing are left out (they cannot be used), and the calibration method is chosen.

  visp-selfcalib calibrate and the tutorial both go through here, so that a dataset on disk and
  images in memory are prepared the same way. Nothing is printed: the result says what happened
  (front-end statistics, the views left out) for the caller to report.
*/
class VISP_SELFCALIB_EXPORT vpSelfCalibImageCorrespondences
{
public:
  struct Options {
    vpFeatureFrontEnd::Options front_end;
    //! The calibration method. Unset (default): HAND_EYE when a view (after leaving out those
    //! without correspondences) has a controller pose fMe and no joints, else BUNDLE_ADJUSTMENT.
    std::optional<vpRobotSelfCalibration::Method> method;
  };

  //! A view left out because the front end found nothing in its image.
  struct DroppedView {
    unsigned int index = 0; //!< its index in the dataset as given
    std::string image;      //!< its image file (empty for images given in memory)
  };

  struct Result {
    bool front_end_ran = false;          //!< false when the dataset's views came with their points
    vpFeatureFrontEnd::Result front_end; //!< when it ran
    unsigned int yardstick_images = 0;   //!< images where the yardstick's two dots were found
    unsigned int grids_found = 0;        //!< dot grids found, summed over the images
    std::vector<DroppedView> dropped;    //!< views left out, by increasing index
    vpRobotSelfCalibration::Method method = vpRobotSelfCalibration::BUNDLE_ADJUSTMENT;
  };

  //! True when a view has an image file and no points: the front end has to run on the images.
  static bool needsFrontEnd(const vpSelfCalibDataset &dataset);

  /*!
    A dataset as read from a file: when needsFrontEnd(), the front end runs on the views' image files
    (vpFeatureFrontEnd::fillDataset: every view needs a readable image of the camera's size) and the
    views where it finds nothing are removed from the dataset; otherwise the views are kept as they
    are. Then the method is chosen. Throws vpSelfCalibException as fillDataset does.
  */
  static Result fromDatasetImages(vpSelfCalibDataset &dataset, const Options &options);

  /*!
    Images in memory, one per view of the dataset in order (a simulated or live acquisition): the
    front end runs on them, replaces every view's points, sets the yardstick's end ids (its length
    stays the dataset's) and the views where it finds nothing are removed. Then the method is
    chosen. Throws vpSelfCalibException when the number of images is not the number of views, or
    as vpFeatureFrontEnd::process does.
  */
  static Result fromImages(vpSelfCalibDataset &dataset, const std::vector<vpImage<unsigned char>> &images,
                           const Options &options);

private:
  //! Statistics, views left out, method: what both entry points do after the front end.
  static void finish(vpSelfCalibDataset &dataset, const Options &options, Result &result);
};

#endif
