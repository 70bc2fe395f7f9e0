/*
 * ViSP SelfCalib: the geometry every layer shares (private, not installed): multi-ray triangulation
 * with cheirality, the relative-pose Jacobian, the homography (planarity) fit, the marginal
 * covariance of a bundle adjustment and the choice of robust loss.
 */
#ifndef VP_SELFCALIB_GEOMETRY_H
#define VP_SELFCALIB_GEOMETRY_H

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include <ceres/loss_function.h>
#include <ceres/problem.h>

#include "vpSelfCalibCamera.h"
#include "vpSelfCalibMath.h"

namespace vpSelfCalib
{
//! A ray of the scene: origin (camera centre) and unit direction, in one common frame.
struct Ray {
  Eigen::Vector3d origin;
  Eigen::Vector3d direction;
};

//! The ray through pixel uv of a camera at fMc (f: the common frame).
Ray rayThrough(const Rigid &fMc, const CameraModel &camera, const Eigen::Vector2d &uv);

/*!
  Linear multi-ray triangulation: the point closest to all rays in the least-squares sense,
  sum_i (I - d_i d_i^T) (X - o_i) = 0. False when fewer than two rays are given, the rays are
  (nearly) parallel, or the point is not in front of every camera (cheirality: d_i . (X - o_i) > 0).
*/
bool triangulateMidpoint(const std::vector<Ray> &rays, Eigen::Vector3d &X);

/*!
  One scene point's views for triangulate(): per view, the ray through the pixel (frame f), the
  camera pose cMf and the pixel uv. add() fills the three; LINEAR_DLT reads cMf and uv only.
*/
struct PointViews {
  std::vector<Ray> rays;
  std::vector<Rigid> cMf;
  std::vector<Eigen::Vector2d> uv;
  //! The view of a camera at fMc that sees the point at pixel `pixel`.
  void add(const Rigid &fMc, const CameraModel &camera, const Eigen::Vector2d &pixel);
};

//! How triangulate() finds the point of its views.
enum class Triangulation {
  //! triangulateMidpoint() on the rays.
  MIDPOINT,
  //! triangulateMidpoint(), then refineTriangulation() on the reprojection error.
  MIDPOINT_REFINED,
  /*!
    Linear DLT of exactly two views (OpenCV's triangulatePoints: the null vector of the 4 x 4 system
    of the projection matrices [R t] of cMf, by SVD) on the pixels' normalized coordinates
    (CameraModel::unproject), the homogeneous solution divided by its last coordinate. X is set
    whatever the result (the scale's finite differences read it); false when X is not finite or
    not in front of both cameras (z > 0 in each).
  */
  LINEAR_DLT
};

/*!
  The multi-ray triangulation every layer uses: the point X (frame f) of a scene point's views by
  `method`. False when fewer than two views are given, or as the method says (parallel rays, a
  point behind a camera, an unusable refinement); X may be written even then.
*/
bool triangulate(const CameraModel &camera, const PointViews &views, Triangulation method, Eigen::Vector3d &X);

/*!
  Refines X (frame f) on the reprojection error of its observations uv[i] in cameras cMf[i], by
  Ceres' TinySolver. False when the solve is not usable, X is not finite or not in front of every camera.
*/
bool refineTriangulation(const CameraModel &camera, const std::vector<Rigid> &cMf,
                         const std::vector<Eigen::Vector2d> &uv, Eigen::Vector3d &X);

/*!
  The rigid correction of one camera that best explains its observations uv[i] of points Xc[i]
  (camera frame) alone: Xc' = R(w) Xc + t, (t, w) in correction (m, angle-axis rad), refined from 0
  by Ceres' TinySolver on the reprojection error. cost: the final sum of squared errors (px^2).
  False when fewer than 4 observations are given or the solve is not usable.
*/
bool reposeCamera(const CameraModel &camera, const std::vector<Eigen::Vector3d> &Xc,
                  const std::vector<Eigen::Vector2d> &uv, Eigen::Matrix<double, 6, 1> &correction, double &cost);

/*!
  First-order change of the relative pose c_A M c_B = A^-1 B when two absolute poses A = fMc_A,
  B = fMc_B move by dA = J_A d rho, dB = J_B d rho. J_A, J_B: 6 x P, rows 0-2 the position change,
  rows 3-5 the rotation change (left perturbation exp([dphi]x) R, in the base frame), as
  vpKinematicChain::getJacobian gives. Output: Jt (3 x P) and Jr (3 x P) of the relative pose's
  translation and left rotation perturbation, expressed in frame A:
    dt = R_A^T (dt_B - dt_A + [t_B - t_A]x dphi_A),  dphi = R_A^T (dphi_B - dphi_A).
*/
void relativePoseJacobian(const Rigid &A, const Eigen::MatrixXd &JA, const Rigid &B, const Eigen::MatrixXd &JB,
                          Eigen::MatrixXd &Jt, Eigen::MatrixXd &Jr);

/*!
  The homography of matched pixels a -> b by OpenCV's classic RANSAC (findHomography, cv::RANSAC)
  with the given inlier threshold (px), sample cap and confidence; inliers: its RANSAC mask. False
  when OpenCV finds none (fewer than 4 points, or a degenerate sample set).
  Deterministic and thread-safe without a seed: the classic RANSAC draws its samples from a
  generator it creates in each call with a fixed seed (RNG((uint64)-1) in calib3d's ptsetreg.cpp),
  not from cv::theRNG() (cv::setRNGSeed has no effect on it), so there is no seed to pass. Not
  OpenCV's USAC, which is seedable: on the main job (tutorial-selfcalib-viper850 -c -d: a small,
  shallow scene 1.4 m away) USAC's homography (default settings, or RANSAC score without local
  optimisation) explains 95 % of the fundamental matrix's inliers in most pairs, so the two-view
  test called 10 of the 14 pairs planar (4 of 14 two-view poses instead of 13) and the calibration
  failed; the classic RANSAC keeps the verdicts the pipeline was tuned on.
*/
bool fitHomography(const std::vector<Eigen::Vector2d> &a, const std::vector<Eigen::Vector2d> &b,
                   double ransac_threshold, int max_iterations, double confidence, Eigen::Matrix3d &H,
                   std::vector<bool> &inliers);

/*!
  A camera motion a plane's homography allows: c_bMc_a with its translation over the plane's distance
  from camera a (t / d), and the plane's unit normal n in frame a (n . X = d for the plane's points X).
*/
struct PlaneMotion {
  Rigid bMa;
  Eigen::Vector3d normal;
};

/*!
  The motions of a homography H of pixels a -> b at the pinhole camera (fx, mu fx, u0, v0) that keep
  the given normalized points of both views (x / z, y / z: inliers of H) in front of the cameras:
  OpenCV's decomposition (decomposeHomographyMat: H = K (R + t n^T / d) K^-1, four solutions) filtered
  by filterHomographyDecompByVisibleRefpoints; usually two remain, one of them the true motion (the
  other has another normal). Empty when OpenCV finds none.
*/
std::vector<PlaneMotion> homographyMotions(const Eigen::Matrix3d &H, double fx, double u0, double v0, double mu,
                                           const std::vector<Eigen::Vector2d> &xa,
                                           const std::vector<Eigen::Vector2d> &xb);

/*!
  The pose cMw of a calibrated pinhole camera (K: fx, u0, v0, mu fx; no distortion) from 3-D points
  (frame w) and their pixels, by OpenCV's USAC PnP (solvePnPRansac with cv::UsacParams: P3P samples,
  local optimisation, final refinement on the inliers), inlier threshold in px, at most
  max_iterations samples; inliers: their indices. USAC's random generator state is
  usacSeed(seed, stream) (vpSelfCalibRandom.h): the same seed gives the same pose bit for bit,
  another seed another sample sequence; sequential (isParallel false), so the thread count does
  not matter. False when OpenCV finds no pose (fewer than 6 points, or a degenerate set).
*/
bool fitPoseRansac(const std::vector<Eigen::Vector3d> &X, const std::vector<Eigen::Vector2d> &uv, double fx, double u0,
                   double v0, double mu, double threshold, int max_iterations, uint64_t seed, uint64_t stream,
                   Rigid &cMw, std::vector<int> &inliers);

/*!
  The information (Schur complement of J^T J) of the `kept` blocks (in order, tangent coordinates)
  with the 3-D `eliminated` blocks marginalized, as marginalCovariance() computes it before inverting
  it; own: the kept parameters' own information (the diagonal of J^T J before the points are
  marginalized). False when the Jacobian cannot be evaluated or a residual involves two eliminated
  blocks.
*/
bool marginalInformation(ceres::Problem &problem, const std::vector<double *> &kept,
                         const std::vector<double *> &eliminated, Eigen::MatrixXd &H, Eigen::VectorXd &own,
                         int *points_left_out = nullptr);

/*!
  Covariance of the `kept` blocks (in order, tangent coordinates) with the 3-D `eliminated` blocks
  marginalized: the inverse of the Schur complement of J^T J, J from Problem::Evaluate on one
  thread. Computed here rather than by ceres::Covariance (SPARSE_QR): SuiteSparseQR runs on TBB's
  threads, and its sums, so the last digits of every standard deviation, changed from run to run
  once another library had started TBB workers. False when the information is singular (an
  eigenvalue of the complement, scaled by the kept parameters' own information, below 1e-10: the
  data leave less than 1e-10 of a direction's information once the points are free) or a residual
  involves two eliminated blocks. A point its own residuals do not determine (a 3 x 3 information
  block with an eigenvalue below 1e-12 of its largest: seen along one ray, at a camera centre, or so
  far that its information is rounding error) is left out with its residuals, which say nothing
  reliable about the kept blocks; points_left_out (when given) counts them. undetermined (when given and the information is singular):
  the directions of the kept parameters that the data do not determine, one unit column each in the
  diagonally scaled coordinates (the eigenvectors below the threshold; a parameter with no
  information at all is its own direction), so that the caller can name the parameters involved.
*/
bool marginalCovariance(ceres::Problem &problem, const std::vector<double *> &kept,
                        const std::vector<double *> &eliminated, Eigen::MatrixXd &cov,
                        Eigen::MatrixXd *undetermined = nullptr, int *points_left_out = nullptr);

//! Robust losses on whitened residuals. The values are those of vpMultiViewReconstruction::Loss.
enum class RobustLoss { NONE = 0, HUBER = 1, CAUCHY = 2 };
//! The Ceres loss of a robust option (nullptr: plain least squares); scale on whitened residuals.
ceres::LossFunction *makeLoss(RobustLoss loss, double scale);
} // namespace vpSelfCalib

#endif
