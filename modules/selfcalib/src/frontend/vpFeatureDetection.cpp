/*
 * ViSP SelfCalib: the front end's detection step: OpenCV SIFT or ORB keypoints and descriptors,
 * and each feature's distinctiveness in its own image.
 */
#include "vpFeatureDetection.h"

#include "../core/vpSelfCalibParallel.h"

#include <algorithm>
#include <limits>
#include <numeric>

#include <Eigen/Dense>
#include <opencv2/core/hal/hal.hpp>

namespace vpSelfCalib::frontend
{
unsigned int threadCount(const FrontEnd::Options &o)
{
  return o.threads ? o.threads : static_cast<unsigned int>(std::max(1, cv::getNumThreads()));
}

cv::Mat toMat(const vpImage<unsigned char> &I)
{
  return cv::Mat(static_cast<int>(I.getHeight()), static_cast<int>(I.getWidth()), CV_8UC1,
                 const_cast<unsigned char *>(I.bitmap))
      .clone();
}

namespace
{

/*
  Per descriptor (row), the squared distance to the nearest other row of the same matrix. Hamming
  (ORB): OpenCV's brute-force matcher. L2 (SIFT, float rows): |a|^2 + |b|^2 - 2 a.b with the dot
  products as an Eigen matrix product, 32 rows at a time (memory 32 x n floats; Eigen does not split
  a product of at most 32 rows over OpenMP threads, which would spin beside the front end's own),
  each pair once. OpenCV's SIFT descriptors are whole numbers up to 255 (128 of them), so every sum stays below
  2^24 and the squared distance is exact (the matcher's knnMatch gave its square root, squared back
  here before: the same tracks on bench-frontend's images); 2.7x less CPU than that knnMatch on its
  25 rendered images (0.65 against 1.75 s on one core; it was 40 % of the detection's time).
*/
std::vector<float> nearestOtherSquared(const cv::Mat &desc, bool l2)
{
  const int n = desc.rows;
  std::vector<float> out(static_cast<size_t>(n), std::numeric_limits<float>::infinity());
  if (!l2 || desc.type() != CV_32F || !desc.isContinuous()) {
    cv::BFMatcher matcher(l2 ? cv::NORM_L2 : cv::NORM_HAMMING);
    std::vector<std::vector<cv::DMatch>> nn;
    matcher.knnMatch(desc, desc, nn, 2);
    for (const auto &mm : nn)
      for (const cv::DMatch &d : mm)
        if (d.trainIdx != d.queryIdx)
          out[static_cast<size_t>(d.queryIdx)] = std::min(out[static_cast<size_t>(d.queryIdx)], d.distance * d.distance);
    return out;
  }
  using RowMajor = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const Eigen::Map<const RowMajor> A(desc.ptr<float>(), n, desc.cols);
  const Eigen::VectorXf norm2 = A.rowwise().squaredNorm();
  // The distances are symmetric: block q0 meets only the rows from q0 on, and each distance
  // updates both of its rows.
  constexpr int kBlock = 32;
  // block x (n - q0), row c: the dot products of row q0 + c with rows q0...
  Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor, kBlock, Eigen::Dynamic> G;
  for (int q0 = 0; q0 < n; q0 += kBlock) {
    const int b = std::min(kBlock, n - q0);
    G.noalias() = A.middleRows(q0, b) * A.bottomRows(n - q0).transpose();
    for (int c = 0; c < b; ++c) {
      const int q = q0 + c;
      float best = std::numeric_limits<float>::infinity();
      for (int r = 0; r < n - q0; ++r) {
        const int j = q0 + r;
        if (j == q)
          continue;
        const float d = norm2(j) + norm2(q) - 2.0f * G(c, r);
        best = std::min(best, d);
        float &oj = out[static_cast<size_t>(j)];
        oj = std::min(oj, d);
      }
      float &oq = out[static_cast<size_t>(q)];
      oq = std::min(oq, best);
    }
  }
  for (float &o : out)
    o = std::max(0.0f, o);
  return out;
}
} // namespace

// Step 1 of vpFeatureFrontEnd::process() (see the header).
Features detectFeatures(const std::vector<cv::Mat> &mats, const std::vector<cv::Mat> &masks,
                        const FrontEnd::Options &opt, FrontEnd::Result &res)
{
  const size_t m = mats.size();
  Features f;
  f.kp.resize(m);
  f.desc.resize(m);
  f.self_nn.resize(m);
  f.offset.assign(m + 1, 0);
  if (opt.features)
    parallelFor(m, threadCount(opt), [&](size_t k) {
      cv::Ptr<cv::Feature2D> det;
      if (opt.detector == FrontEnd::SIFT)
        det = cv::SIFT::create(static_cast<int>(opt.max_features), 3, opt.contrast_threshold);
      else
        det = cv::ORB::create(static_cast<int>(opt.max_features));
      const cv::Mat mask = masks.empty() ? cv::Mat() : masks[masks.size() == 1 ? 0 : k];
      // One pass (the scale space is built once for the keypoints and their descriptors). Detection
      // runs in parallel inside OpenCV and returns the keypoints in an order that depends on the
      // thread count: sorted here (position, then scale), descriptors with them, so that tracks, ids
      // and every sum downstream are the same whatever the threads.
      std::vector<cv::KeyPoint> kp;
      cv::Mat desc;
      det->detectAndCompute(mats[k], mask, kp, desc);
      std::vector<size_t> order(kp.size());
      std::iota(order.begin(), order.end(), size_t(0));
      std::sort(order.begin(), order.end(), [&kp](size_t ia, size_t ib) {
        const cv::KeyPoint &a = kp[ia], &b = kp[ib];
        if (a.pt.y != b.pt.y)
          return a.pt.y < b.pt.y;
        if (a.pt.x != b.pt.x)
          return a.pt.x < b.pt.x;
        if (a.size != b.size)
          return a.size < b.size;
        if (a.angle != b.angle)
          return a.angle < b.angle;
        return a.octave < b.octave;
      });
      f.kp[k].reserve(kp.size());
      f.desc[k].create(static_cast<int>(kp.size()), desc.cols, desc.type());
      for (size_t r = 0; r < order.size(); ++r) {
        f.kp[k].push_back(kp[order[r]]);
        desc.row(static_cast<int>(order[r])).copyTo(f.desc[k].row(static_cast<int>(r)));
      }
      // Distinctiveness, for the guided search's ratio test (see searchGuided).
      if (((opt.guided && (!opt.prior.empty() || opt.measure_prior)) || opt.complete_tracks) && f.kp[k].size() >= 2)
        f.self_nn[k] = nearestOtherSquared(f.desc[k], opt.detector == FrontEnd::SIFT);
    });
  for (size_t k = 0; k < m; ++k) {
    res.features.push_back(static_cast<unsigned int>(f.kp[k].size()));
    f.offset[k + 1] = f.offset[k] + f.kp[k].size();
  }
  return f;
}

float descriptorDistance2(const Features &f, size_t i, int a, size_t j, int b)
{
  const int len = f.desc[i].cols;
  if (f.desc[i].type() == CV_32F)
    return cv::hal::normL2Sqr_(f.desc[i].ptr<float>(a), f.desc[j].ptr<float>(b), len);
  const float d = static_cast<float>(cv::hal::normHamming(f.desc[i].ptr<uchar>(a), f.desc[j].ptr<uchar>(b), len));
  return d * d;
}
} // namespace vpSelfCalib::frontend
