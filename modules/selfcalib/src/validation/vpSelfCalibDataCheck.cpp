/*
 * ViSP SelfCalib: checks of a calibration dataset, with findings that say what to do.
 */
#include <visp3/selfcalib/vpSelfCalibDataCheck.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include <Eigen/Eigenvalues>

#include "../core/vpSelfCalibFormat.h"
#include "../core/vpSelfCalibGeometry.h"
#include "../core/vpSelfCalibMath.h"

using namespace vpSelfCalib;

const char *vpSelfCalibDataCheck::severityName(Severity s)
{
  switch (s) {
  case WARNING:
    return "warning";
  case DEGENERATE:
    return "degenerate";
  case DOUBT:
    return "doubt";
  }
  return "unknown";
}

namespace
{
using vpSelfCalib::fixed;

double deg(double rad) { return rad * 180.0 / M_PI; }

[[noreturn]] void fail(const std::string &what)
{
  throw vpSelfCalibException(vpSelfCalibException::badValue, "dataset check: " + what);
}

// "joint 4", "joints 4 and 5", "joints 4-6", "joints 1, 3 and 5" (1-based).
std::string jointList(const std::vector<unsigned int> &j)
{
  std::ostringstream os;
  if (j.size() == 1) {
    os << "joint " << j[0] + 1;
    return os.str();
  }
  bool consecutive = true;
  for (size_t k = 1; k < j.size(); ++k)
    consecutive = consecutive && j[k] == j[k - 1] + 1;
  if (consecutive && j.size() > 2) {
    os << "joints " << j.front() + 1 << "-" << j.back() + 1;
    return os.str();
  }
  os << "joints ";
  for (size_t k = 0; k < j.size(); ++k)
    os << (k == 0 ? "" : (k + 1 == j.size() ? " and " : ", ")) << j[k] + 1;
  return os.str();
}

// The end-effector pose of a view: its controller pose, else the model's.
Rigid endEffector(const vpKinematicChain &nominal, const vpSelfCalibDataset::View &v)
{
  return rigidFromVisp(v.has_fMe ? v.fMe : nominal.get_fMe(v.q));
}

using Finding = vpSelfCalibDataCheck::Finding;
using Severity = vpSelfCalibDataCheck::Severity;
using View = vpSelfCalibDataset::View;

void add(std::vector<Finding> &out, Severity s, const std::string &code, const std::string &msg)
{
  out.push_back({s, code, msg});
}

//! Caller mistakes, on every view (the verification views too): thrown.
void checkInputs(const vpKinematicChain &nominal, const vpSelfCalibDataset &ds, const vpSelfCalibDataCheck::Options &opt)
{
  const unsigned int n = nominal.getNumJoints();
  for (size_t k = 0; k < ds.views.size(); ++k) {
    const auto &v = ds.views[k];
    const std::string pose = "pose " + std::to_string(k);
    if (v.q.size() != 0 && v.q.size() != n)
      fail(pose + " has " + std::to_string(v.q.size()) + " joint values, the robot model has " + std::to_string(n));
    for (unsigned int j = 0; j < v.q.size(); ++j) {
      const auto &J = nominal.getJoints()[j];
      if (!std::isfinite(v.q[j]))
        fail(pose + ": joint " + std::to_string(j + 1) + " is not a finite number");
      if (v.q[j] < J.min - opt.joint_limit_tolerance || v.q[j] > J.max + opt.joint_limit_tolerance)
        fail(pose + ": joint " + std::to_string(j + 1) + " = " + fixed(v.q[j], 4) + " rad is outside the model's limits [" +
             fixed(J.min, 4) + ", " + fixed(J.max, 4) +
             "]: check the joint readings (radians, in the model's joint order and zero) or the limits in the robot "
             "model");
    }
    if (v.has_fMe)
      for (unsigned int r = 0; r < 3; ++r)
        for (unsigned int c = 0; c < 4; ++c)
          if (!std::isfinite(v.fMe[r][c]))
            fail(pose + ": the controller pose fMe is not finite");
    for (const auto &o : v.points)
      if (!std::isfinite(o.ip.get_u()) || !std::isfinite(o.ip.get_v()))
        fail(pose + ": point " + std::to_string(o.id) + " has a non-finite pixel position");
  }

}

//! PnP's minimum: 4 coplanar points of a known layout place a view.
constexpr unsigned int kMinKnownPoints = 4;

//! Whether every point of a view is one of the known layout's (and it sees one at least).
bool onlyKnownPoints(const View &v, const vpSelfCalibDataCheck::Options &opt)
{
  return !v.points.empty() && std::all_of(v.points.begin(), v.points.end(), [&](const vpSelfCalibDataset::Observation &o) {
    return opt.known_points.count(o.id) > 0;
  });
}

//! Points: too few in a view (min_points, or 4 for a view of a known layout's points only), outside the image.
void checkPoints(const vpSelfCalibDataset &ds, const std::vector<View> &cal, const vpSelfCalibDataCheck::Options &opt,
                 std::vector<Finding> &out)
{
  std::vector<std::string> few, few_known;
  unsigned int outside = 0;
  std::string example;
  for (size_t k = 0; k < cal.size(); ++k) {
    const bool known = onlyKnownPoints(cal[k], opt);
    if (cal[k].points.size() < (known ? kMinKnownPoints : opt.min_points))
      (known ? few_known : few).push_back(std::to_string(k) + " (" + std::to_string(cal[k].points.size()) + ")");
    for (const auto &o : cal[k].points)
      if (ds.width > 0 && (o.ip.get_u() < -1 || o.ip.get_v() < -1 || o.ip.get_u() > ds.width ||
                           o.ip.get_v() > ds.height)) {
        if (outside++ == 0)
          example = "pose " + std::to_string(k) + ", point " + std::to_string(o.id) + " at (" +
                    fixed(o.ip.get_u(), 1) + ", " + fixed(o.ip.get_v(), 1) + ")";
      }
  }
  auto join = [](const std::vector<std::string> &items) {
    std::string list;
    for (const auto &f : items)
      list += (list.empty() ? "" : ", ") + f;
    return list;
  };
  if (!few.empty())
    add(out, vpSelfCalibDataCheck::WARNING, "few-points",
        "calibration poses with fewer than " + std::to_string(opt.min_points) + " image points: " + join(few) +
            "; such a pose cannot be placed by the reconstruction and adds little: aim the camera so that it sees "
            "more of the scene");
  if (!few_known.empty())
    add(out, vpSelfCalibDataCheck::WARNING, "few-points",
        "calibration poses with fewer than " + std::to_string(kMinKnownPoints) + " points of the known layout: " +
            join(few_known) + "; PnP needs 4 to place such a pose: aim the camera so that it sees more of the board");
  if (outside > 0)
    add(out, vpSelfCalibDataCheck::WARNING, "points-outside-image",
        std::to_string(outside) + " image points lie outside the " + std::to_string(ds.width) + " x " +
            std::to_string(ds.height) + " image (" + example +
            "): check that the camera size matches the images and that points are (u, v) = (column, row)");

}

//! Repeated poses; false (and a DEGENERATE finding) when fewer than two distinct poses remain.
bool checkRepeatedPoses(const vpKinematicChain &nominal, const std::vector<View> &cal,
                        const vpSelfCalibDataCheck::Options &opt, std::vector<Finding> &out)
{
  const unsigned int n = nominal.getNumJoints();
  unsigned int distinct = 0;
  {
    std::vector<std::string> repeats;
    for (size_t a = 0; a < cal.size(); ++a) {
      bool repeated = false;
      for (size_t b = 0; b < a && !repeated; ++b) {
        double d = 0;
        if (cal[a].q.size() == n && cal[b].q.size() == n) {
          for (unsigned int j = 0; j < n; ++j)
            d = std::max(d, std::fabs(cal[a].q[j] - cal[b].q[j]));
        } else {
          const Rigid A = endEffector(nominal, cal[a]), B = endEffector(nominal, cal[b]);
          d = std::max(logSO3(A.R.transpose() * B.R).norm(), (A.t - B.t).norm());
        }
        if (d <= opt.same_pose_tolerance) {
          repeated = true;
          repeats.push_back(std::to_string(b) + " and " + std::to_string(a));
        }
      }
      if (!repeated)
        ++distinct;
    }
    if (distinct < 2) {
      add(out, vpSelfCalibDataCheck::DEGENERATE, "identical-poses",
          "all calibration poses are the same robot configuration: nothing moves, so nothing can be calibrated; "
          "record poses that move every joint");
      return false;
    }
    if (!repeats.empty()) {
      std::string list;
      for (size_t k = 0; k < repeats.size() && k < 5; ++k)
        list += (list.empty() ? "" : ", ") + repeats[k];
      if (repeats.size() > 5)
        list += ", ...";
      add(out, vpSelfCalibDataCheck::WARNING, "repeated-poses",
          "poses " + list + " are the same configuration: a repeated pose only averages image noise and adds no "
          "geometry; use distinct configurations");
    }
  }
  return true;
}

//! Joints that barely move over the calibration views that have joints.
void checkJointMotion(const vpKinematicChain &nominal, const std::vector<View> &cal, bool hand_eye,
                      const vpSelfCalibDataCheck::Options &opt, std::vector<Finding> &out)
{
  const unsigned int n = nominal.getNumJoints();
  std::vector<unsigned int> with_joints;
  for (unsigned int k = 0; k < cal.size(); ++k)
    if (cal[k].q.size() == n)
      with_joints.push_back(k);
  if (with_joints.size() >= 2) {
    std::vector<unsigned int> still;
    std::string ranges;
    for (unsigned int j = 0; j < n; ++j) {
      double lo = cal[with_joints[0]].q[j], hi = lo;
      for (unsigned int k : with_joints) {
        lo = std::min(lo, cal[k].q[j]);
        hi = std::max(hi, cal[k].q[j]);
      }
      if (hi - lo < opt.min_joint_range) {
        still.push_back(j);
        ranges += (ranges.empty() ? "" : ", ") + fixed(deg(hi - lo), 2);
      }
    }
    if (!still.empty() && !hand_eye)
      add(out, vpSelfCalibDataCheck::WARNING, "joints-barely-move",
          jointList(still) + " barely move" + (still.size() == 1 ? "s" : "") + " (range " + ranges +
              " deg over the calibration poses): the parameters that need " + (still.size() == 1 ? "its" : "their") +
              " motion are unidentifiable or poorly determined; add poses with larger " + jointList(still) +
              " rotations (10 deg or more)");
  }

}

//! Camera rotation and the axes of the end-effector rotations.
void checkRotations(const vpKinematicChain &nominal, const std::vector<View> &cal, bool hand_eye,
                    const vpSelfCalibDataCheck::Options &opt, std::vector<Finding> &out)
{
  std::vector<Rigid> fMe;
  for (const auto &v : cal)
    fMe.push_back(endEffector(nominal, v));
  double max_rotation = 0;
  std::vector<Eigen::Vector3d> axes; // in f, of the rotations between view pairs
  for (size_t a = 0; a < fMe.size(); ++a)
    for (size_t b = a + 1; b < fMe.size(); ++b) {
      const Eigen::Vector3d r = logSO3(fMe[b].R * fMe[a].R.transpose());
      max_rotation = std::max(max_rotation, r.norm());
      if (r.norm() > 2 * opt.parallel_axes_tolerance)
        axes.push_back(r.normalized());
    }
  if (max_rotation < opt.min_rotation)
    add(out, vpSelfCalibDataCheck::WARNING, "barely-rotates",
        "the camera barely rotates between the calibration poses (largest relative rotation " +
            fixed(deg(max_rotation), 2) +
            " deg): the focal length, the hand-eye rotation and the joint offsets are poorly determined; add poses "
            "rotated by 10 deg or more about different axes");
  else if (hand_eye && !axes.empty()) {
    double spread = 0;
    for (const auto &x : axes)
      spread = std::max(spread, std::acos(std::min(1.0, std::fabs(x.dot(axes[0])))));
    if (spread < opt.parallel_axes_tolerance)
      add(out, vpSelfCalibDataCheck::WARNING, "parallel-rotation-axes",
          "every end-effector rotation is about the same axis direction (within " + fixed(deg(spread), 2) +
              " deg): the hand-eye translation along that axis is unobservable (see its standard deviation); add "
              "poses rotated about another axis");
  }

}

/*
  Parallax: a homography explaining the matches of every pair means no depth information. The
  verdict needs support: only a pair with at least kMinHomographyPoints (15) correspondences counts,
  since a homography (8 degrees of freedom, 4 points) fitted to a handful of matches explains them
  by construction, and few random matches (images of pure noise, a front end that found almost
  nothing) would otherwise read as "the scene is a plane". With n >= 15 points and 90 % of them
  within the threshold, a chance fit of random matches (about 4 of n) is ruled out. When no pair
  has that support the finding is about the correspondences, not the scene.
*/
constexpr unsigned int kMinHomographyPoints = 15; //!< correspondences of a pair that counts for the verdict

void checkParallax(const vpKinematicChain &nominal, const std::vector<View> &cal,
                   const vpSelfCalibDataCheck::Options &opt, double pixel_sd, std::vector<Finding> &out)
{
  // A known layout gives its points' depth: the parallax between views has nothing to add, and
  // one small tag's 4 corners are what it should be, not too few correspondences.
  if (std::all_of(cal.begin(), cal.end(), [&](const View &v) { return onlyKnownPoints(v, opt); }))
    return;
  const double threshold = std::max(1.0, 3.0 * pixel_sd);
  unsigned int pairs = 0, flat = 0, weak = 0;
  size_t most_shared = 0;
  double max_baseline = 0;
  const Rigid eMc = rigidFromVisp(nominal.get_eMc_corrected());
  const Rigid c0 = endEffector(nominal, cal[0]) * eMc;
  std::map<int, vpImagePoint> first;
  for (const auto &o : cal[0].points)
    first[o.id] = o.ip;
  for (size_t k = 1; k < cal.size(); ++k) {
    max_baseline = std::max(max_baseline, ((endEffector(nominal, cal[k]) * eMc).t - c0.t).norm());
    std::vector<Eigen::Vector2d> a, b;
    for (const auto &o : cal[k].points) {
      const auto it = first.find(o.id);
      if (it != first.end()) {
        a.emplace_back(it->second.get_u(), it->second.get_v());
        b.emplace_back(o.ip.get_u(), o.ip.get_v());
      }
    }
    most_shared = std::max(most_shared, a.size());
    if (a.size() < kMinHomographyPoints) {
      ++weak;
      continue;
    }
    // RANSAC with a loose threshold (a homography from 4 noisy points of a grazing plane
    // extrapolates poorly), then every point against the refined homography. 200 samples find a
    // homography that explains 90% of the points with probability 1 - (1 - 0.9^4)^200; a scene
    // with relief leaves RANSAC at that cap (2000 made the check cost 40 ms per pair).
    // Deterministic without a seed: OpenCV's classic RANSAC (fitHomography, core), which seeds its
    // own generator with a constant in each call (see fitHomography for why not USAC).
    Eigen::Matrix3d H;
    std::vector<bool> ransac_inliers;
    ++pairs;
    if (!fitHomography(a, b, 3 * threshold, 200, 0.999, H, ransac_inliers))
      continue;
    unsigned int explained = 0;
    for (size_t i = 0; i < a.size(); ++i)
      explained += ((H * a[i].homogeneous()).hnormalized() - b[i]).norm() < threshold;
    if (explained >= opt.homography_inliers * static_cast<double>(a.size()))
      ++flat;
  }
  if (pairs == 0 && weak > 0) {
    add(out, vpSelfCalibDataCheck::WARNING, "few-correspondences",
        "no calibration view shares " + std::to_string(kMinHomographyPoints) +
            " points or more with the first (at most " + std::to_string(most_shared) +
            "): too few correspondences to say anything about the scene's depth (images without texture or of "
            "another scene, pure noise, or matches that are few and random); check the images and the matching");
    return;
  }
  if (pairs > 0 && flat == pairs) {
    if (max_baseline < 0.01)
      add(out, vpSelfCalibDataCheck::DEGENERATE, "no-parallax",
          "the camera only rotates: its centre moves by " + fixed(max_baseline * 1e3, 1) +
              " mm at most, and a homography explains the matched points of every pair, so no depth can be "
              "measured; add poses that translate the camera (10% of the distance to the scene or more)");
    else
      // A plane seen from poses that translate is not degenerate for the estimate as a whole (with f
      // known it determines eMc and the kinematics; views at several tilts determine f, as in
      // Zhang's calibration): the bundle adjustment's information matrix decides, and names what is
      // not determined.
      add(out, vpSelfCalibDataCheck::WARNING, "planar-scene",
          "a homography explains the matched points of every pair (" + std::to_string(pairs) +
              " pairs): the scene is a plane (or far away compared with the camera's motion); not a refusal in "
              "itself: the adjustment's information matrix says whether the poses determine the calibration (a self-calibrated focal "
              "length needs the plane seen at several tilts); objects at other depths make it stronger");
  }

}

//! The yardstick needs each end in two calibration views to be triangulated.
/*
  A scene on a line: in every view the image points lie within kCollinearRatio of their spread from
  a line (the ratio of the small to the large principal axis of the centred points). A line in space
  projects to a line; its views do not determine the rotation about it, nor the camera poses. A
  real scene is never that thin in every image.
*/
constexpr double kCollinearRatio = 0.03;
//! Below this ratio in every view (but above kCollinearRatio) the scene is nearly a line: a warning.
constexpr double kNearlyCollinearRatio = 0.15;

void checkCollinear(const std::vector<View> &cal, std::vector<Finding> &out)
{
  double worst = 0;
  unsigned int views = 0;
  for (const View &v : cal) {
    if (v.points.size() < 3)
      continue;
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto &o : v.points)
      mean += Eigen::Vector2d(o.ip.get_u(), o.ip.get_v());
    mean /= static_cast<double>(v.points.size());
    Eigen::Matrix2d C = Eigen::Matrix2d::Zero();
    for (const auto &o : v.points) {
      const Eigen::Vector2d d = Eigen::Vector2d(o.ip.get_u(), o.ip.get_v()) - mean;
      C += d * d.transpose();
    }
    const Eigen::Vector2d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(C).eigenvalues(); // ascending
    if (!(ev(1) > 0))
      continue;
    worst = std::max(worst, std::sqrt(std::max(0.0, ev(0)) / ev(1)));
    ++views;
  }
  if (views < 2 || worst >= kNearlyCollinearRatio)
    return;
  const bool line = worst < kCollinearRatio;
  add(out, line ? vpSelfCalibDataCheck::DEGENERATE : vpSelfCalibDataCheck::WARNING, "collinear-scene",
      std::string("the scene points lie ") + (line ? "on" : "close to") +
          " a line in every calibration image (their spread across it is at most " + fixed(100.0 * worst, 1) +
          " % of their spread along it): views of a line do not determine the camera's rotation about it" +
          (line ? "" : ", and a thin scene determines it poorly") +
          "; add scene points off the line (a textured surface, a second object)");
}

void checkYardstick(const vpSelfCalibDataset &ds, const std::vector<View> &cal, std::vector<Finding> &out)
{
  if (ds.yardstick.isSet()) {
    unsigned int seen_a = 0, seen_b = 0;
    for (const auto &v : cal)
      for (const auto &o : v.points) {
        seen_a += o.id == ds.yardstick.id_a;
        seen_b += o.id == ds.yardstick.id_b;
      }
    const unsigned int seen = std::min(seen_a, seen_b);
    if (seen < 2)
      add(out, vpSelfCalibDataCheck::WARNING, "yardstick-unseen",
          std::string("the yardstick (points ") + std::to_string(ds.yardstick.id_a) + " and " +
              std::to_string(ds.yardstick.id_b) + ") is seen in " + std::to_string(seen) +
              " calibration pose" + (seen == 1 ? "" : "s") +
              ": two are needed to triangulate it, so it cannot set the scale (the bundle adjustment keeps the "
              "nominal model's scale; the paper's method fails); show both ends in two or more poses");
  }
}
} // namespace


void vpSelfCalibDataCheck::Options::check() const
{
  if (!(joint_limit_tolerance >= 0 && same_pose_tolerance >= 0 && min_joint_range >= 0 && min_rotation >= 0 &&
        parallel_axes_tolerance >= 0 && homography_inliers > 0 && homography_inliers <= 1))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpSelfCalibDataCheck::Options: tolerances must be non-negative and "
                               "homography_inliers in (0, 1]");
}

/*
  Eye-to-hand (camera_mount world; the views' fMe are then the inverted controller poses): the target
  must move with the robot. When the end-effector moves by 1 cm or more but the target's points stay
  within max(2, 3 pixel_sd) px of where the first view saw them (median over the shared points of
  each view), the target is not on the tool: a fixed camera and a fixed target determine nothing.
*/
void checkTargetMoves(const vpKinematicChain &nominal, const vpSelfCalibDataset &ds, const std::vector<View> &cal,
                      double pixel_sd, std::vector<Finding> &out)
{
  if (ds.camera_mount != vpSelfCalibDataset::CAMERA_IN_WORLD || cal.size() < 2)
    return;
  std::map<int, vpImagePoint> first;
  for (const auto &o : cal[0].points)
    first[o.id] = o.ip;
  const Eigen::Vector3d e0 = endEffector(nominal, cal[0]).inverse().t;
  double motion = 0, displacement = 0;
  for (size_t k = 1; k < cal.size(); ++k) {
    std::vector<double> d;
    for (const auto &o : cal[k].points) {
      const auto it = first.find(o.id);
      if (it != first.end())
        d.push_back(vpImagePoint::distance(it->second, o.ip));
    }
    if (d.empty())
      return; // other points: they moved
    std::nth_element(d.begin(), d.begin() + static_cast<long>(d.size() / 2), d.end());
    displacement = std::max(displacement, d[d.size() / 2]);
    motion = std::max(motion, (endEffector(nominal, cal[k]).inverse().t - e0).norm());
  }
  if (motion >= 0.01 && displacement < std::max(2.0, 3 * pixel_sd))
    add(out, vpSelfCalibDataCheck::DEGENERATE, "target-does-not-move",
        "camera_mount: world, but the target's points stay within " + fixed(displacement, 1) +
            " px of the first view while the end-effector moves by up to " + fixed(motion * 1e3, 0) +
            " mm: the target is not carried by the tool, and a fixed camera looking at a fixed target determines "
            "nothing; fix the target on the end-effector (or, with the camera on the end-effector, set "
            "camera_mount: effector)");
}

bool vpSelfCalibDataCheck::degenerate(const std::vector<Finding> &findings)
{
  return std::any_of(findings.begin(), findings.end(), [](const Finding &f) { return f.severity == DEGENERATE; });
}

std::vector<vpSelfCalibDataCheck::Finding> vpSelfCalibDataCheck::check(const vpKinematicChain &nominal,
                                                                       const vpSelfCalibDataset &ds,
                                                                       unsigned int num_calibration, bool hand_eye,
                                                                       const Options &opt,
                                                                       const vpSelfCalibNoiseModel &noise)
{
  opt.check();
  noise.check("vpSelfCalibDataCheck");
  const unsigned int N = std::min<unsigned int>(num_calibration, static_cast<unsigned int>(ds.views.size()));
  checkInputs(nominal, ds, opt);
  std::vector<Finding> out;
  const std::vector<vpSelfCalibDataset::View> cal(ds.views.begin(), ds.views.begin() + N);
  checkPoints(ds, cal, opt, out);
  checkTargetMoves(nominal, ds, cal, noise.pixel_sd, out);
  if (degenerate(out))
    return out;
  checkCollinear(cal, out);
  if (!checkRepeatedPoses(nominal, cal, opt, out))
    return out;
  checkJointMotion(nominal, cal, hand_eye, opt, out);
  checkRotations(nominal, cal, hand_eye, opt, out);
  checkParallax(nominal, cal, opt, noise.pixel_sd, out);
  checkYardstick(ds, cal, out);
  return out;
}
