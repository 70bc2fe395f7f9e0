/*
 * ViSP SelfCalib: the front end's detection step (private, not installed): each image's keypoints
 * and descriptors, in an order that does not depend on the threads.
 */
#ifndef VP_FEATURE_DETECTION_H
#define VP_FEATURE_DETECTION_H

#include <visp3/selfcalib/vpFeatureFrontEnd.h>

#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>

namespace vpSelfCalib::frontend
{
using FrontEnd = vpFeatureFrontEnd;

//! The worker threads of the options (0: cv::getNumThreads()).
unsigned int threadCount(const FrontEnd::Options &o);

//! A copy of the image as an OpenCV matrix (8 bits, one channel).
cv::Mat toMat(const vpImage<unsigned char> &I);

/*!
  The keypoints and descriptors of every image; the keypoints of image k are numbered from
  offset[k] in the union-find of the tracks.
*/
struct Features {
  std::vector<std::vector<cv::KeyPoint>> kp;
  std::vector<cv::Mat> desc;
  std::vector<size_t> offset;
  //! Per image, per feature: the squared descriptor distance to the nearest other feature of the
  //! same image (its distinctiveness; filled when a prior guides the matching).
  std::vector<std::vector<float>> self_nn;
};

/*!
  Step 1 of vpFeatureFrontEnd::process(): detection (none when opt.features is off), one image per
  thread, the keypoints sorted (position, then scale) with their descriptors; res.features gets
  the count per image.
*/
Features detectFeatures(const std::vector<cv::Mat> &mats, const std::vector<cv::Mat> &masks,
                        const FrontEnd::Options &opt, FrontEnd::Result &res);

/*!
  Squared descriptor distance of feature a of image i and feature b of image j: L2 for SIFT's float
  descriptors, Hamming (squared, to compare as L2's) for ORB's binary ones.
*/
float descriptorDistance2(const Features &f, size_t i, int a, size_t j, int b);
} // namespace vpSelfCalib::frontend

#endif
