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
#include <visp3/selfcalib/vpBoardDetector.h>
#include <visp3/selfcalib/vpFeatureFrontEnd.h>
#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibDataset.h>

/*!
  \class vpSelfCalibImageCorrespondences
  \ingroup group_selfcalib_frontend
  \brief What comes between acquiring images and calibrating: the image front end
  (vpFeatureFrontEnd) fills the dataset's observations and the yardstick's ends, the views where
  it found nothing are left out (they cannot be used), and the calibration method is chosen.

  A calibration board (Options::board, vpBoardDetector) can be the observations instead of, or
  besides, the natural features: every image is searched for it, its points get the board's ids
  (id_offset + row * cols + col for the grids; a ChArUco board's corners and AprilTags' corners as
  vpBoardDetector numbers them, those in view only), and an image where it is not found gets a warning (with the
  reason) and, when nothing else was found in it, is left out. The feature front end runs besides
  it only when Options::front_end asks for natural features or dot grids; the board's ids must not
  collide with the front end's (the default offset, 2000000, is above them: vpBoardDetector).

  Yardstick rule: when the dataset's yardstick is not set after the front end (no length declared,
  or its dots not found) and the board was found in two or more images, the board is the
  yardstick: the two ends of its first row (ids id_offset and id_offset + cols - 1), their distance
  on the board apart (vpBoardDetector::getYardstick(): for a ChArUco board its first row of inner
  corners, for AprilTags the first tag's top edge). A declared length whose dots were not found
  is replaced, with a warning.

  visp-selfcalib calibrate and the tutorial both go through here, so that a dataset on disk and
  images in memory are prepared the same way. Nothing is printed: the result says what happened
  (front-end statistics, the board, the views left out, warnings) for the caller to report.
*/
class VISP_SELFCALIB_EXPORT vpSelfCalibImageCorrespondences
{
public:
  //! Settings of vpSelfCalibImageCorrespondences (the defaults are the member initialisers).
  struct Options {
    vpFeatureFrontEnd::Options front_end;
    //! A calibration board to find in every image (see the class); unset: none.
    std::optional<vpBoardDetector::Options> board;
    /*!
      With a board: the board is found only to be masked out, a target-free calibration in a scene
      that has one (to compare with the board's own result on the same images). In each image where
      it is found, its region (boardMask()) is excluded from the feature front end (on top of
      front_end.masks); its points are not observations and it is not the yardstick. An image where
      it is not found is not masked, with a warning. Needs the front end's natural features.
    */
    bool mask_board = false;
    double mask_margin = 15; //!< px: the board's mask reaches this far beyond its outer points
    /*!
      The nominal robot model as the front end's kinematic prior (vpFeatureFrontEnd, step 2), when
      set and front_end.prior is empty. With the camera on the effector (and front_end.guided), the
      prior is measured from the images, not taken from the guess: the front end's pilot (the
      reference view with every other image, matched without a prior) gives tracks from which
      measurePrior() measures eMc and, when it is self-calibrated, the focal length (the measured
      start of the calibration: the camera's motions against the robot's), and every view's camera
      pose is predicted from the model's end-effector poses and that eMc. When they cannot be
      measured, makePrior() predicts from the model's eMc guess and the dataset's focal length, with
      a warning. The camera in the world: makePrior(). The matching falls back to unguided, with a
      warning, when the images disagree with the prior. Unset: every pair matched without a prior.
    */
    std::optional<vpKinematicChain> prior;
    //! The calibration method. Unset (default): HAND_EYE when a view (after leaving out those
    //! without correspondences) has a controller pose fMe and no joints, else BUNDLE_ADJUSTMENT.
    std::optional<vpRobotSelfCalibration::Method> method;
  };

  //! A view left out because the front end found nothing in its image.
  struct DroppedView {
    unsigned int index = 0; //!< its index in the dataset as given
    std::string image;      //!< its image file (empty for images given in memory)
  };

  //! The result of vpSelfCalibImageCorrespondences: what it computed, and what the caller needs to judge it.
  struct Result {
    //! The feature front end ran (front_end holds its result); false when the dataset's views came
    //! with their points, or when a board alone was looked for.
    bool front_end_ran = false;
    vpFeatureFrontEnd::Result front_end; //!< when it ran
    unsigned int yardstick_images = 0;   //!< images where the yardstick's two dots were found
    unsigned int grids_found = 0;        //!< dot grids found, summed over the images
    std::vector<DroppedView> dropped;    //!< views left out, by increasing index
    bool board_ran = false;                       //!< a board was looked for in the images
    std::vector<vpBoardDetector::Result> board;   //!< per image of the dataset as given, when board_ran
    unsigned int board_images = 0;                //!< images where the board was found
    bool board_yardstick = false;                 //!< the board became the yardstick (see the class)
    //! What the caller should tell the user: images where the board was not found (view, image
    //! and reason), a declared yardstick replaced by the board, the front end's warnings (a
    //! kinematic prior rejected).
    std::vector<std::string> warnings;
    //! What the front end's prior was made from (Options::prior): measured from the images, or the
    //! model's guess and why; empty when there was none.
    std::string prior;
    vpRobotSelfCalibration::Method method = vpRobotSelfCalibration::BUNDLE_ADJUSTMENT;
  };

  /*!
    The front end's prior from a model: each view's predicted camera pose, its joints through the
    model (get_fMc) or, without joints, its controller pose fMe times the model's eMc, and the
    dataset's camera (a guess when the focal length is not known). Empty (no prior) when a view has
    neither joints nor fMe, or the joints do not fit the model.
  */
  static vpFeatureFrontEnd::Prior makePrior(const vpKinematicChain &model, const vpSelfCalibDataset &dataset);

  /*!
    The front end's prior measured from a pilot's observations (per view of the dataset, ids shared
    across views; at most 400 of the ids, every n-th, are used): the measured start of the calibration (two-view motions against the
    end-effector's, OpenCV's hand-eye closed forms, a self-calibrated focal length where the two
    agree best) on the views' end-effector poses (the model's forward kinematics at the joints, or
    the controller poses fMe), at RANSAC threshold threshold_px; then eMc refined (Ceres) on the
    epipolar distances of the matches of every pair of views through the robot's motions, at that
    focal length (Cauchy loss, 2 px). Each view's camera pose is its
    end-effector pose times the measured eMc; the camera is the dataset's, its focal length the
    measured one when the dataset's is not known. Depends on neither the model's eMc nor the
    dataset's focal guess. Empty when they cannot be measured (too few views sharing points, the
    end-effector rotating about one axis only); `how` says what measured them or why not. Throws
    vpSelfCalibException when pilot has not one entry per view.
  */
  static vpFeatureFrontEnd::Prior measurePrior(const vpKinematicChain &model, const vpSelfCalibDataset &dataset,
                                               const std::vector<std::vector<vpSelfCalibDataset::Observation>> &pilot,
                                               double threshold_px, std::string &how);

  /*!
    The mask (255: features may be found, 0: not) of a board found in an image of height x width:
    the convex hull of its points, widened by margin px. All 255 when it was not found.
  */
  static vpImage<unsigned char> boardMask(const vpBoardDetector::Result &board, unsigned int height,
                                          unsigned int width, double margin);

  //! True when a view has an image file and no points: the front end has to run on the images.
  static bool needsFrontEnd(const vpSelfCalibDataset &dataset);

  /*!
    A dataset as read from a file: when needsFrontEnd(), the front end runs on the views' image files
    (vpFeatureFrontEnd::fillDataset, or readImages() then as fromImages() with a board: every view
    needs a readable image of the camera's size) and the views where it finds nothing are removed
    from the dataset; otherwise the views are kept as they are. Then the method is chosen. Throws
    vpSelfCalibException as fillDataset and readImages() do, or when the board's ids collide with
    the front end's.
  */
  static Result fromDatasetImages(vpSelfCalibDataset &dataset, const Options &options);

  /*!
    Every view's image file, read as grey (vpImageIo). Throws vpSelfCalibException naming the view
    and the file when a view has no image, or its image is missing, unreadable or not of the
    camera's size.
  */
  static std::vector<vpImage<unsigned char>> readImages(const vpSelfCalibDataset &dataset);

  /*!
    Images in memory, one per view of the dataset in order (a simulated or live acquisition): the
    front end runs on them, replaces every view's points, sets the yardstick's end ids (its length
    stays the dataset's) and the views where it finds nothing are removed. With a board, its points
    are added (see the class). Then the method is chosen. Throws vpSelfCalibException when the
    number of images is not the number of views, as vpFeatureFrontEnd::process does, or when the
    board's ids collide with the front end's.
  */
  static Result fromImages(vpSelfCalibDataset &dataset, const std::vector<vpImage<unsigned char>> &images,
                           const Options &options);

private:
  //! The front end (features and dot grids, a board) on the images, into the views' points.
  static void runOnImages(vpSelfCalibDataset &dataset, const std::vector<vpImage<unsigned char>> &images,
                          const Options &options, Result &result);
  //! The board on every image: its points added to the views', the yardstick rule, warnings.
  static void addBoard(vpSelfCalibDataset &dataset, const std::vector<vpImage<unsigned char>> &images,
                       const Options &options, Result &result);
  //! Statistics, views left out, method: what both entry points do after the front end.
  static void finish(vpSelfCalibDataset &dataset, const Options &options, Result &result);
};

#endif
