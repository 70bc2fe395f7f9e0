/*
 * ViSP SelfCalib: the reference simulation scenario.
 */
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include <ceres/ceres.h>

#include "../core/vpSelfCalibCeres.h"
#include "../core/vpSelfCalibCamera.h"
#include "../core/vpSelfCalibMath.h"
#include "../core/vpSelfCalibRandom.h"

using namespace vpSelfCalib;

namespace
{
enum Stream : uint64_t { kErrors = 1, kScene = 2, kConfigurations = 3, kNoise = 1000 };

void require(bool ok, const std::string &what)
{
  if (!ok)
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpSelfCalibSimulator::Options: " + what);
}

bool nonNegative(double v) { return std::isfinite(v) && v >= 0; }

/*
  IK residual: r = [p(q) - p*; log(R(q) R*^T)] (position and rotation in f).
  Jacobian: [Jv; J_l(phi)^-1 Jw], exact, since R(q + dq) = exp([Jw dq]x) R(q) and
  exp([phi + dphi]x) = exp([J_l(phi) dphi]x) exp([phi]x).
*/
class PoseResidual : public ceres::CostFunction
{
public:
  PoseResidual(const vpKinematicChain &chain, const Rigid &target) : m_chain(chain), m_target(target)
  {
    set_num_residuals(6);
    mutable_parameter_block_sizes()->push_back(static_cast<int>(chain.getNumJoints()));
  }

  bool Evaluate(double const *const *parameters, double *residuals, double **jacobians) const override
  {
    const unsigned int n = m_chain.getNumJoints();
    vpColVector q(n);
    for (unsigned int i = 0; i < n; ++i)
      q[i] = parameters[0][i];
    const Rigid M = rigidFromVisp(m_chain.get_fMc(q));
    const Eigen::Vector3d dp = M.t - m_target.t;
    const Eigen::Vector3d phi = logSO3(M.R * m_target.R.transpose());
    for (int k = 0; k < 3; ++k) {
      residuals[k] = dp(k);
      residuals[3 + k] = phi(k);
    }
    if (jacobians && jacobians[0]) {
      const vpMatrix J = m_chain.getJointJacobian(q);
      const Eigen::Matrix3d Jli = leftJacobianSO3(phi).inverse();
      for (unsigned int i = 0; i < n; ++i) {
        const Eigen::Vector3d w(J[3][i], J[4][i], J[5][i]);
        const Eigen::Vector3d dphi = Jli * w;
        for (int k = 0; k < 3; ++k) {
          jacobians[0][k * n + i] = J[k][i];
          jacobians[0][(3 + k) * n + i] = dphi(k);
        }
      }
    }
    return true;
  }

private:
  const vpKinematicChain &m_chain;
  Rigid m_target;
};

vpColVector toVisp3(const Eigen::Vector3d &v)
{
  vpColVector c(3);
  for (int k = 0; k < 3; ++k)
    c[k] = v(k);
  return c;
}
} // namespace

void vpSelfCalibSimulator::Options::check() const
{
  for (double v : {joint_translation_sd, joint_rotation_sd, base_translation_sd, base_rotation_sd,
                   hand_eye_translation_sd, hand_eye_rotation_sd})
    require(nonNegative(v), "error standard deviations must be finite and >= 0");
  require(width > 0 && height > 0, "the image size must be positive");
  require(std::isfinite(px) && std::isfinite(py) && px > 0 && py > 0, "px and py must be positive");
  require(std::isfinite(u0) && std::isfinite(v0), "u0 and v0 must be finite");
  require(num_points >= 1, "num_points must be at least 1");
  require(std::isfinite(box_x) && std::isfinite(box_y) && std::isfinite(box_z) && box_x > 0 && box_y > 0 &&
              box_z > 0,
          "the box sizes must be positive");
  require(std::isfinite(yardstick_length) && yardstick_length > 0 &&
              yardstick_length <= std::min(box_x, box_y),
          "yardstick_length must be positive and fit in the box (<= min(box_x, box_y))");
  require(std::isfinite(distance_min) && std::isfinite(distance_max) && distance_min > 0 &&
              distance_min <= distance_max,
          "viewing distances must satisfy 0 < distance_min <= distance_max");
  require(std::isfinite(view_cone) && view_cone >= 0 && view_cone <= M_PI / 2, "view_cone must be in [0, pi/2]");
  require(nonNegative(roll_range) && roll_range <= M_PI, "roll_range must be in [0, pi]");
  require(nonNegative(image_margin) && 2 * image_margin < std::min(width, height),
          "image_margin must be >= 0 and leave part of the image");
  require(nonNegative(pixel_noise_sd), "pixel_noise_sd must be finite and >= 0");
  require(max_attempts >= 1, "max_attempts must be at least 1");
  require(min_visible_points <= num_points + 2,
          "min_visible_points must not exceed the number of scene points (num_points + 2 yardstick ends)");
}

vpSelfCalibSimulator::Options vpSelfCalibSimulator::sceneOptions(const std::string &name)
{
  Options o;
  if (name == "reference")
    return o;
  if (name == "paper") {
    // Wide lens (94 x 77 degree field of view), a large deep scene seen from wide views, partial views.
    o.px = o.py = 300;
    o.num_points = 250;
    o.box_x = 0.8;
    o.box_y = 0.9;
    o.box_z = 0.5;
    o.yardstick_length = 0.4;
    o.distance_min = 0.6;
    o.distance_max = 0.8;
    o.view_cone = 60 * M_PI / 180.0;
    o.min_visible_points = 40;
    return o;
  }
  throw vpSelfCalibException(vpSelfCalibException::badValue,
                             "vpSelfCalibSimulator::sceneOptions: unknown scene '" + name + "' (reference, paper)");
}

std::vector<std::string> vpSelfCalibSimulator::sceneNames() { return {"reference", "paper"}; }

vpSelfCalibSimulator::EyeToHandOptions vpSelfCalibSimulator::eyeToHandHd()
{
  EyeToHandOptions o;
  o.width = 1280;
  o.height = 720;
  o.px = o.py = 1000;
  o.u0 = 640;
  o.v0 = 360;
  return o;
}

vpColVector vpSelfCalibSimulator::homeConfiguration(const vpKinematicChain &chain)
{
  if (chain.getName() == "viper850")
    return vpColVector({0, -1.2, 2.4, 0, 0.4, 0});
  if (chain.getName() == "puma560")
    return vpColVector({0, M_PI / 4, -M_PI, 0, M_PI / 4, 0});
  return (chain.getJointMin() + chain.getJointMax()) * 0.5;
}

vpSelfCalibSimulator::vpSelfCalibSimulator(const vpKinematicChain &nominal, const Options &options)
  : m_opt(options), m_nominal(nominal.nominal()), m_true(nominal.nominal())
{
  m_opt.check();
  m_home = m_opt.home.size() ? m_opt.home : homeConfiguration(m_nominal);
  if (m_home.size() != m_nominal.getNumJoints() || !m_nominal.isInJointLimits(m_home))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpSelfCalibSimulator: the home configuration must have " +
                                   std::to_string(m_nominal.getNumJoints()) +
                                   " finite values inside the joint limits");

  // True robot: nominal + seeded 6-D errors on the base, every joint placement and eMc.
  Random err(m_opt.seed, kErrors);
  vpColVector p(m_true.getNumParameters());
  const unsigned int nblocks = m_true.getNumJoints() + 2;
  for (unsigned int b = 0; b < nblocks; ++b) {
    double tsd = m_opt.joint_translation_sd, rsd = m_opt.joint_rotation_sd;
    if (b == 0) {
      tsd = m_opt.base_translation_sd;
      rsd = m_opt.base_rotation_sd;
    } else if (b == nblocks - 1) {
      tsd = m_opt.hand_eye_translation_sd;
      rsd = m_opt.hand_eye_rotation_sd;
    }
    for (unsigned int k = 0; k < 6; ++k)
      p[6 * b + k] = err.normal(k < 3 ? tsd : rsd);
  }
  m_true.setParameters(p);

  // Scene: box centred on the point seen at mid distance along the home optical axis.
  const Rigid home = rigidFromVisp(m_nominal.get_fMc(m_home));
  const Eigen::Vector3d centre = home * Eigen::Vector3d(0, 0, 0.5 * (m_opt.distance_min + m_opt.distance_max));
  m_centre = toVisp3(centre);
  Random scene(m_opt.seed, kScene);
  for (unsigned int i = 0; i < m_opt.num_points; ++i) {
    const Eigen::Vector3d d(scene.uniform(-0.5, 0.5) * m_opt.box_x, scene.uniform(-0.5, 0.5) * m_opt.box_y,
                            scene.uniform(-0.5, 0.5) * m_opt.box_z);
    m_points.push_back(toVisp3(centre + d));
  }
  // Yardstick lying horizontally through the box centre (it fits: length <= min(box_x, box_y)).
  const double a = scene.uniform(0, 2 * M_PI);
  const Eigen::Vector3d half = 0.5 * m_opt.yardstick_length * Eigen::Vector3d(std::cos(a), std::sin(a), 0);
  m_points.push_back(toVisp3(centre - half));
  m_points.push_back(toVisp3(centre + half));
}

vpCameraParameters vpSelfCalibSimulator::getCamera() const
{
  return vpCameraParameters(m_opt.px, m_opt.py, m_opt.u0, m_opt.v0);
}

std::map<int, vpColVector> vpSelfCalibSimulator::getScenePointsById() const
{
  std::map<int, vpColVector> pts;
  for (size_t i = 0; i < m_points.size(); ++i)
    pts[static_cast<int>(i)] = m_points[i];
  return pts;
}

std::vector<vpHomogeneousMatrix>
vpSelfCalibSimulator::getTrueCameraPoses(const std::vector<vpSelfCalibDataset::View> &views) const
{
  std::vector<vpHomogeneousMatrix> T;
  for (const auto &v : views)
    T.push_back(m_true.get_fMc(v.q));
  return T;
}

vpSelfCalibDataset::Yardstick vpSelfCalibSimulator::getYardstick() const
{
  vpSelfCalibDataset::Yardstick y;
  y.length = m_opt.yardstick_length;
  y.id_a = static_cast<int>(m_opt.num_points);
  y.id_b = static_cast<int>(m_opt.num_points) + 1;
  return y;
}

bool vpSelfCalibSimulator::inverseKinematics(const vpHomogeneousMatrix &fMc, const vpColVector &q0,
                                             vpColVector &q) const
{
  const unsigned int n = m_nominal.getNumJoints();
  std::vector<double> x(q0.data, q0.data + n);
  ceres::Problem problem;
  problem.AddResidualBlock(new PoseResidual(m_nominal, rigidFromVisp(fMc)), nullptr, x.data());
  for (unsigned int i = 0; i < n; ++i) {
    problem.SetParameterLowerBound(x.data(), static_cast<int>(i), m_nominal.getJoints()[i].min);
    problem.SetParameterUpperBound(x.data(), static_cast<int>(i), m_nominal.getJoints()[i].max);
  }
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = 100;
  so.function_tolerance = 1e-16;
  so.gradient_tolerance = 1e-16;
  so.parameter_tolerance = 1e-14;
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  vpSelfCalib::solve(so, &problem, &summary);
  // Converged to the exact pose (cost = |r|^2 / 2): 1e-9 m and 1e-9 rad.
  if (!(summary.final_cost < 0.5e-18))
    return false;
  q.resize(n);
  for (unsigned int i = 0; i < n; ++i)
    q[i] = x[i];
  return m_nominal.isInJointLimits(q);
}

namespace
{
// Which scene points are inside the image (with the margin) and in front of the camera cMf.
std::vector<bool> inView(const Rigid &cMf, const std::vector<vpColVector> &points, const CameraModel &camera,
                         double m, unsigned int width, unsigned int height)
{
  std::vector<bool> in(points.size(), false);
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d Xc = cMf * vec3(points[i]);
    if (!(Xc.z() > 1e-3))
      continue;
    const Eigen::Vector2d uv = camera.project(Xc);
    const double u = uv(0), v = uv(1);
    in[i] = !(u < m || v < m || u > width - 1 - m || v > height - 1 - m);
  }
  return in;
}
} // namespace

bool vpSelfCalibSimulator::isVisible(const vpColVector &q) const { return isVisible(m_true, q); }

bool vpSelfCalibSimulator::isVisible(const vpKinematicChain &chain, const vpColVector &q) const
{
  const Rigid cMf = rigidFromVisp(chain.get_fMc(q)).inverse();
  const CameraModel camera = CameraModel::pinhole(m_opt.px, m_opt.py, m_opt.u0, m_opt.v0);
  const std::vector<bool> in = inView(cMf, m_points, camera, m_opt.image_margin, m_opt.width, m_opt.height);
  if (m_opt.min_visible_points == 0)
    return std::all_of(in.begin(), in.end(), [](bool b) { return b; });
  // Partial views: both yardstick ends (the last two points) and at least N points.
  if (!in[m_opt.num_points] || !in[m_opt.num_points + 1])
    return false;
  return static_cast<unsigned int>(std::count(in.begin(), in.end(), true)) >= m_opt.min_visible_points;
}

unsigned int vpSelfCalibSimulator::countVisible(const vpColVector &q) const
{
  const Rigid cMf = rigidFromVisp(m_true.get_fMc(q)).inverse();
  const CameraModel camera = CameraModel::pinhole(m_opt.px, m_opt.py, m_opt.u0, m_opt.v0);
  const std::vector<bool> in = inView(cMf, m_points, camera, m_opt.image_margin, m_opt.width, m_opt.height);
  return static_cast<unsigned int>(std::count(in.begin(), in.end(), true));
}

std::vector<vpColVector> vpSelfCalibSimulator::generateConfigurations(unsigned int m, const Progress &progress) const
{
  Random rng(m_opt.seed, kConfigurations);
  const Rigid home = rigidFromVisp(m_nominal.get_fMc(m_home));
  const Eigen::Vector3d centre = vec3(m_centre);
  const Eigen::Vector3d d0 = (home.t - centre).normalized();
  const Eigen::Vector3d e1 = d0.unitOrthogonal(), e2 = d0.cross(e1);
  std::vector<vpColVector> configs;
  for (unsigned int k = 0; k < m; ++k) {
    bool found = false;
    for (unsigned int attempt = 0; attempt < m_opt.max_attempts && !found; ++attempt) {
      // Direction uniform on the spherical cap of half-angle view_cone around d0.
      const double c = 1.0 - rng.uniform() * (1.0 - std::cos(m_opt.view_cone));
      const double s = std::sqrt(std::max(0.0, 1.0 - c * c)), phi = rng.uniform(0, 2 * M_PI);
      const Eigen::Vector3d d = c * d0 + s * (std::cos(phi) * e1 + std::sin(phi) * e2);
      const double dist = rng.uniform(m_opt.distance_min, m_opt.distance_max);
      const double roll = rng.uniform(-m_opt.roll_range, m_opt.roll_range);
      // Look-at pose: z towards the centre, x as close as possible to the home x axis, rolled.
      Rigid target;
      const Eigen::Vector3d z = -d;
      Eigen::Vector3d x = home.R.col(0) - home.R.col(0).dot(z) * z;
      if (x.norm() < 1e-6)
        x = z.unitOrthogonal();
      x = Eigen::AngleAxisd(roll, z) * x.normalized();
      target.R.col(0) = x;
      target.R.col(1) = z.cross(x);
      target.R.col(2) = z;
      target.t = centre + dist * d;
      vpColVector q;
      if (inverseKinematics(toVisp(target), m_home, q) && isVisible(q)) {
        configs.push_back(q);
        found = true;
      }
    }
    if (!found) {
      std::ostringstream os;
      os << "vpSelfCalibSimulator::generateConfigurations: no configuration found for pose " << k + 1 << " of "
         << m << " in " << m_opt.max_attempts
         << " viewpoint draws (scene out of reach, or view_cone, distances or image margin too tight)";
      throw vpSelfCalibException(vpSelfCalibException::badValue, os.str());
    }
    if (progress)
      progress(k + 1, m);
  }
  return configs;
}

std::vector<vpSelfCalibDataset::Observation> vpSelfCalibSimulator::observe(const vpColVector &q, unsigned int view_index,
                                                                           double noise_sd) const
{
  const double sd = noise_sd < 0 ? m_opt.pixel_noise_sd : noise_sd;
  if (!std::isfinite(sd))
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpSelfCalibSimulator::observe: non-finite noise");
  Random noise(m_opt.seed, kNoise + view_index);
  const Rigid cMf = rigidFromVisp(m_true.get_fMc(q)).inverse();
  const CameraModel camera = CameraModel::pinhole(m_opt.px, m_opt.py, m_opt.u0, m_opt.v0);
  std::vector<vpSelfCalibDataset::Observation> obs;
  for (size_t i = 0; i < m_points.size(); ++i) {
    const Eigen::Vector3d Xc = cMf * vec3(m_points[i]);
    // Draw the noise of every point, seen or not, so that point i's noise does not depend on the others.
    const double nu = noise.normal(sd), nv = noise.normal(sd);
    if (!(Xc.z() > 1e-3))
      continue;
    const Eigen::Vector2d uv = camera.project(Xc);
    const double u = uv(0) + nu, v = uv(1) + nv;
    if (u < 0 || v < 0 || u > m_opt.width - 1 || v > m_opt.height - 1)
      continue;
    vpSelfCalibDataset::Observation o;
    o.id = static_cast<int>(i);
    o.ip.set_uv(u, v);
    obs.push_back(o);
  }
  return obs;
}

vpSelfCalibDataset vpSelfCalibSimulator::makeDataset(const std::vector<vpColVector> &configurations) const
{
  vpSelfCalibDataset ds;
  ds.cam = getCamera();
  ds.width = m_opt.width;
  ds.height = m_opt.height;
  ds.focal_known = true;
  ds.robot = m_nominal.getName();
  ds.yardstick = getYardstick();
  for (size_t k = 0; k < configurations.size(); ++k) {
    vpSelfCalibDataset::View v;
    v.q = configurations[k];
    v.points = observe(configurations[k], static_cast<unsigned int>(k));
    ds.views.push_back(v);
  }
  return ds;
}

vpSelfCalibDataset vpSelfCalibSimulator::acquire(vpRobot &robot, const std::vector<vpColVector> &configurations,
                                                 const Progress &progress) const
{
  vpSelfCalibDataset ds = makeDataset({});
  for (size_t k = 0; k < configurations.size(); ++k) {
    robot.setPosition(vpRobot::ARTICULAR_FRAME, configurations[k]);
    vpSelfCalibDataset::View v;
    robot.getPosition(vpRobot::ARTICULAR_FRAME, v.q);
    if (v.q.size() != m_nominal.getNumJoints())
      throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                                 "vpSelfCalibSimulator::acquire: the robot reports " + std::to_string(v.q.size()) +
                                     " joints, the model has " + std::to_string(m_nominal.getNumJoints()));
    v.points = observe(v.q, static_cast<unsigned int>(k));
    ds.views.push_back(v);
    if (progress)
      progress(static_cast<unsigned int>(k + 1), static_cast<unsigned int>(configurations.size()));
  }
  return ds;
}

vpPlannerScene vpSelfCalibSimulator::getPlannerScene() const
{
  vpPlannerScene scene;
  scene.points = m_points;
  scene.cam = getCamera();
  scene.width = m_opt.width;
  scene.height = m_opt.height;
  scene.margin = m_opt.image_margin;
  scene.min_visible = m_opt.min_visible_points;
  if (m_opt.min_visible_points > 0)
    scene.required = {m_opt.num_points, m_opt.num_points + 1};
  return scene;
}

namespace
{
//! The camera at `from` looking at `to`, its image rows downwards (against the base's z).
vpSelfCalib::Rigid lookAt(const Eigen::Vector3d &from, const Eigen::Vector3d &to)
{
  vpSelfCalib::Rigid M;
  const Eigen::Vector3d z = (to - from).normalized();
  const Eigen::Vector3d x = Eigen::Vector3d(0, 0, -1).cross(z).normalized();
  M.R.col(0) = x;
  M.R.col(1) = z.cross(x);
  M.R.col(2) = z;
  M.t = from;
  return M;
}

//! The target's points in o: a grid on z = 0 from o (vpBoardDetector's chessboard layout), or natural features in a box about o.
std::map<int, vpColVector> eyeToHandLayout(const vpSelfCalibSimulator::EyeToHandOptions &o)
{
  if (!o.layout.empty())
    return o.layout;
  std::map<int, vpColVector> layout;
  vpSelfCalib::Random rng(o.seed, 11);
  if (o.board) {
    for (unsigned int r = 0; r < o.board_rows; ++r)
      for (unsigned int c = 0; c < o.board_cols; ++c)
        layout[o.board_id_offset + static_cast<int>(r * o.board_cols + c)] = vpColVector({c * o.board_spacing, r * o.board_spacing, 0.0});
  } else
    for (unsigned int i = 0; i < o.num_points; ++i)
      layout[static_cast<int>(i)] = vpColVector({rng.uniform(-0.5, 0.5) * o.box_size, rng.uniform(-0.5, 0.5) * o.box_size,
                                                 rng.uniform(-0.5, 0.5) * o.box_size});
  return layout;
}

//! The target's points projected through cMo with image noise; false unless every point is in the image.
bool observeTarget(const vpSelfCalibSimulator::EyeToHandOptions &o, const std::map<int, vpColVector> &layout,
                   const vpSelfCalib::Rigid &cMo, vpSelfCalib::Random &noise_rng, vpSelfCalibDataset::View &v)
{
  for (const auto &p : layout) {
    const Eigen::Vector3d X = cMo.R * Eigen::Vector3d(p.second[0], p.second[1], p.second[2]) + cMo.t;
    const double u = o.u0 + o.px * X(0) / X(2) + noise_rng.normal(o.pixel_noise_sd);
    const double w = o.v0 + o.py * X(1) / X(2) + noise_rng.normal(o.pixel_noise_sd);
    if (X(2) > 0 && u >= 0 && w >= 0 && u < o.width && w < o.height)
      v.points.push_back({p.first, vpImagePoint(w, u)});
  }
  return v.points.size() == layout.size();
}

//! A view's controller pose: the true bMe (kept in the truth) with the controller's error drawn
//! (EyeToHandOptions::pose_sd_translation, pose_sd_rotation).
void recordControllerPose(const vpSelfCalibSimulator::EyeToHandOptions &o, const vpSelfCalib::Rigid &bMe,
                          vpSelfCalib::Random &error_rng, vpSelfCalibDataset::View &v,
                          vpSelfCalibSimulator::EyeToHandTruth &truth)
{
  using namespace vpSelfCalib;
  const double d[6] = {error_rng.normal(o.pose_sd_translation), error_rng.normal(o.pose_sd_translation),
                       error_rng.normal(o.pose_sd_translation), error_rng.normal(o.pose_sd_rotation),
                       error_rng.normal(o.pose_sd_rotation),    error_rng.normal(o.pose_sd_rotation)};
  v.has_fMe = true;
  v.fMe = toVisp(bMe * rigidFromVector(d).inverse());
  truth.bMe.push_back(toVisp(bMe));
}

/*
  Eye-to-hand with joint readings (EyeToHandOptions::robot): the true robot, the camera facing the
  target at home, the views drawn about home; each view's joint readings and controller pose.
*/
void simulateEyeToHandJoints(const vpSelfCalibSimulator::EyeToHandOptions &o, vpSelfCalibSimulator::EyeToHandTruth &truth,
                             vpSelfCalibDataset &ds)
{
  using namespace vpSelfCalib;
  const vpKinematicChain nominal = vpKinematicChain::fromPresetOrFile(o.robot).nominal();
  const unsigned int n = nominal.getNumJoints();
  const vpColVector home = o.home.size() ? o.home : vpSelfCalibSimulator::homeConfiguration(nominal);
  if (home.size() != n || !nominal.isInJointLimits(home) || !(o.joint_spread > 0) || o.joint_sd < 0 ||
      o.robot_translation_sd < 0 || o.robot_rotation_sd < 0)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpSelfCalibSimulator::simulateEyeToHand: the robot '" + o.robot + "' needs a home of " +
                                   std::to_string(n) + " joint values inside its limits, a positive joint_spread "
                                   "and non-negative robot errors");
  truth.chain = nominal;
  Random err(o.seed, 15);
  vpColVector p(nominal.getNumParameters(), 0.0);
  for (unsigned int i = 0; i < p.size() - vpKinematicChain::kBlockSize; ++i) // the base and every joint
    p[i] = err.normal(i % vpKinematicChain::kBlockSize < 3 ? o.robot_translation_sd : o.robot_rotation_sd);
  truth.chain.setParameters(p);
  const Rigid eMo = rigidFromVisp(truth.eMo);
  // The camera facing the target's centre at home, on the target's z axis.
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const auto &l : truth.layout)
    centre += Eigen::Vector3d(l.second[0], l.second[1], l.second[2]) / static_cast<double>(truth.layout.size());
  Rigid oMc;
  oMc.R = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  oMc.t = centre + Eigen::Vector3d(0, 0, 0.5 * (o.distance_min + o.distance_max));
  const Rigid bMc = rigidFromVisp(truth.chain.get_fMe(home)) * eMo * oMc;
  truth.bMc = toVisp(bMc);
  ds.robot = o.robot;
  if (o.joint_sd > 0)
    ds.joint_sd = {o.joint_sd};
  const uint64_t noise = o.noise_seed ? (static_cast<uint64_t>(o.noise_seed) << 32) ^ o.seed : o.seed;
  Random pose_rng(o.seed, 12), noise_rng(noise, 13), error_rng(noise, 14), joint_rng(noise, 16);
  const vpColVector qmin = nominal.getJointMin(), qmax = nominal.getJointMax();
  for (unsigned int attempt = 0; ds.views.size() < o.num_views && attempt < 200 * o.num_views; ++attempt) {
    vpColVector q(n);
    for (unsigned int j = 0; j < n; ++j)
      q[j] = std::min(qmax[j], std::max(qmin[j], home[j] + pose_rng.uniform(-o.joint_spread, o.joint_spread)));
    const Rigid bMe = rigidFromVisp(truth.chain.get_fMe(q));
    const Rigid cMo = bMc.inverse() * bMe * eMo;
    vpSelfCalibDataset::View v;
    if (!(cMo.R(2, 2) < -0.3) || !observeTarget(o, truth.layout, cMo, noise_rng, v))
      continue;
    v.q = q;
    for (unsigned int j = 0; j < n; ++j)
      v.q[j] -= joint_rng.normal(o.joint_sd);
    recordControllerPose(o, bMe, error_rng, v, truth);
    truth.q.push_back(q);
    ds.views.push_back(v);
  }
}
} // namespace

vpSelfCalibDataset vpSelfCalibSimulator::simulateEyeToHand(const EyeToHandOptions &o, EyeToHandTruth &truth)
{
  using namespace vpSelfCalib;
  if (o.num_views < 3 || o.camera_position.size() != 3 || o.look_at.size() != 3 || !(o.px > 0) || !(o.py > 0) ||
      !(o.distance_min > 0) || o.distance_max < o.distance_min || o.pixel_noise_sd < 0 || o.pose_sd_translation < 0 ||
      o.pose_sd_rotation < 0 || (o.board && o.board_cols * o.board_rows < 4) || (!o.board && o.num_points < 6))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpSelfCalibSimulator::simulateEyeToHand: expected 3 views or more, 3-vectors for the "
                               "camera position and look-at point, positive focal lengths and distances, non-negative "
                               "noise, and 4 board points or 6 features or more");
  const Rigid bMc = lookAt(Eigen::Vector3d(o.camera_position[0], o.camera_position[1], o.camera_position[2]),
                           Eigen::Vector3d(o.look_at[0], o.look_at[1], o.look_at[2]));
  const Rigid eMo = rigidFromVisp(vpHomogeneousMatrix(o.eMo));
  truth = EyeToHandTruth();
  truth.bMc = toVisp(bMc);
  truth.eMo = toVisp(eMo);
  truth.layout = eyeToHandLayout(o);
  vpSelfCalibDataset ds;
  ds.camera_mount = vpSelfCalibDataset::CAMERA_IN_WORLD;
  ds.robot = "viper850";
  ds.width = o.width;
  ds.height = o.height;
  ds.cam.initPersProjWithoutDistortion(o.px, o.py, o.u0, o.v0);
  ds.pose_sd_translation = o.pose_sd_translation;
  ds.pose_sd_rotation = o.pose_sd_rotation;
  if (!o.robot.empty())
    simulateEyeToHandJoints(o, truth, ds);
  const uint64_t noise = o.noise_seed ? (static_cast<uint64_t>(o.noise_seed) << 32) ^ o.seed : o.seed;
  Random pose_rng(o.seed, 12), noise_rng(noise, 13), error_rng(noise, 14);
  Rigid facing;
  if (o.layout.empty()) // the target's z towards the camera
    facing.R = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  for (unsigned int attempt = 0; o.robot.empty() && ds.views.size() < o.num_views && attempt < 100 * o.num_views;
       ++attempt) {
    const Eigen::Vector3d axis =
        Eigen::Vector3d(pose_rng.normal(), pose_rng.normal(), pose_rng.normal()).normalized();
    Rigid cMo;
    cMo.R = Eigen::AngleAxisd(pose_rng.uniform(0, o.tilt), axis).toRotationMatrix() * facing.R;
    cMo.t = Eigen::Vector3d(pose_rng.uniform(-o.lateral, o.lateral), pose_rng.uniform(-o.lateral, o.lateral),
                            pose_rng.uniform(o.distance_min, o.distance_max));
    vpSelfCalibDataset::View v;
    if (!observeTarget(o, truth.layout, cMo, noise_rng, v) && (o.board || !o.layout.empty() || v.points.size() < 6))
      continue;
    const Rigid bMe = bMc * cMo * eMo.inverse();
    recordControllerPose(o, bMe, error_rng, v, truth);
    ds.views.push_back(v);
  }
  if (ds.views.size() < o.num_views)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpSelfCalibSimulator::simulateEyeToHand: the target leaves the image in most poses; " +
                                   std::string(o.robot.empty() ? "bring it nearer the camera's axis (lateral, tilt) or "
                                                                 "further away"
                                                               : "narrow joint_spread or move the camera further away "
                                                                 "(distance_min, distance_max)"));
  return ds;
}
