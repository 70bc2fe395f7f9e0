/*
 * ViSP SelfCalib: acquisition over any vpRobot and image source. See the header.
 */
#include <visp3/selfcalib/vpSelfCalibAcquisition.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include <visp3/core/vpTime.h>
#include <visp3/io/vpImageIo.h>

namespace fs = std::filesystem;

namespace
{
double distance(const vpColVector &a, const vpColVector &b) { return (a - b).frobeniusNorm(); }

std::vector<unsigned int> orderGroup(const std::vector<vpColVector> &q, unsigned int first, unsigned int end)
{
  // Nearest neighbour from `first`, ties to the lower index.
  std::vector<unsigned int> order;
  std::vector<bool> used(q.size(), false);
  unsigned int cur = first;
  order.push_back(cur);
  used[cur] = true;
  for (unsigned int k = first + 1; k < end; ++k) {
    unsigned int best = end;
    for (unsigned int j = first; j < end; ++j)
      if (!used[j] && (best == end || distance(q[cur], q[j]) < distance(q[cur], q[best])))
        best = j;
    order.push_back(best);
    used[best] = true;
    cur = best;
  }
  // 2-opt on the open path (the first pose stays first): reverse order[i..j] when it shortens it.
  bool improved = true;
  for (int pass = 0; improved && pass < 100; ++pass) {
    improved = false;
    for (size_t i = 1; i + 1 < order.size(); ++i)
      for (size_t j = i + 1; j < order.size(); ++j) {
        const double before = distance(q[order[i - 1]], q[order[i]]) +
                              (j + 1 < order.size() ? distance(q[order[j]], q[order[j + 1]]) : 0.0);
        const double after = distance(q[order[i - 1]], q[order[j]]) +
                             (j + 1 < order.size() ? distance(q[order[i]], q[order[j + 1]]) : 0.0);
        if (after < before - 1e-12) {
          std::reverse(order.begin() + static_cast<long>(i), order.begin() + static_cast<long>(j) + 1);
          improved = true;
        }
      }
  }
  return order;
}

std::string imageName(unsigned int k)
{
  std::ostringstream os;
  os << std::setw(4) << std::setfill('0') << k << ".png";
  return os.str();
}

std::string describe(const std::exception &e)
{
  if (const vpException *v = dynamic_cast<const vpException *>(&e))
    return v->getStringMessage();
  return e.what();
}
} // namespace

void vpSelfCalibAcquisition::Options::check() const
{
  if (dataset_file.empty())
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpSelfCalibAcquisition: no dataset file given");
  if (!(settle_time >= 0) || !(reach_tolerance > 0) || !(resume_tolerance > 0))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpSelfCalibAcquisition: settle_time >= 0 and positive tolerances are needed");
}

const char *vpSelfCalibAcquisition::statusName(Status s)
{
  switch (s) {
  case OK:
    return "ok";
  case ROBOT_ERROR:
    return "robot error";
  default:
    return "image error";
  }
}

vpSelfCalibAcquisition::vpSelfCalibAcquisition(vpRobot &robot, const vpKinematicChain &model, vpFrameGrabber &grabber,
                                               const Options &options)
  : vpSelfCalibAcquisition(robot, model, ImageSource([&grabber](vpImage<unsigned char> &I) { grabber.acquire(I); }),
                           options)
{
}

vpSelfCalibAcquisition::vpSelfCalibAcquisition(vpRobot &robot, const vpKinematicChain &model,
                                               const ImageSource &source, const Options &options)
  : m_robot(robot), m_model(model), m_source(source), m_opt(options)
{
  m_opt.check();
  if (!m_source)
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpSelfCalibAcquisition: no image source");
}

std::vector<unsigned int> vpSelfCalibAcquisition::shortTravelOrder(const std::vector<vpColVector> &q)
{
  if (q.empty())
    return {};
  return orderGroup(q, 0, static_cast<unsigned int>(q.size()));
}

double vpSelfCalibAcquisition::travel(const std::vector<vpColVector> &q, const std::vector<unsigned int> &order)
{
  double t = 0;
  for (size_t k = 1; k < order.size(); ++k)
    t += distance(q[order[k - 1]], q[order[k]]);
  return t;
}

vpSelfCalibDataset vpSelfCalibAcquisition::loadExisting() const
{
  std::error_code ec;
  if (!fs::exists(m_opt.dataset_file, ec)) {
    vpSelfCalibDataset ds = m_opt.header;
    ds.views.clear();
    return ds;
  }
  // Absolute: the paths in it are resolved to absolute ones, written back relative (see recordPose).
  vpSelfCalibDataset ds = vpSelfCalibDataset::loadYaml(fs::absolute(m_opt.dataset_file).lexically_normal().string());
  // The camera and the robot must be this acquisition's.
  const vpSelfCalibDataset &h = m_opt.header;
  if (ds.width != h.width || ds.height != h.height || ds.focal_known != h.focal_known ||
      std::fabs(ds.cam.get_u0() - h.cam.get_u0()) > 1e-9 || std::fabs(ds.cam.get_v0() - h.cam.get_v0()) > 1e-9 ||
      (h.focal_known && std::fabs(ds.cam.get_px() - h.cam.get_px()) > 1e-9))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpSelfCalibAcquisition: the existing dataset '" + m_opt.dataset_file +
                                   "' has another camera: remove it or choose another file");
  return ds;
}

vpSelfCalibAcquisition::Result vpSelfCalibAcquisition::recordPose(vpSelfCalibDataset &ds, const vpColVector *command,
                                                                   unsigned int index, const std::string &what)
{
  Result r;
  vpSelfCalibDataset::View v;
  try {
    if (command) {
      if (!m_model.isInJointLimits(*command))
        throw vpSelfCalibException(vpSelfCalibException::badValue, "the configuration is outside the joint limits");
      m_robot.setRobotState(vpRobot::STATE_POSITION_CONTROL);
      m_robot.setPosition(vpRobot::ARTICULAR_FRAME, *command);
    }
    if (m_opt.settle_time > 0)
      vpTime::wait(1000.0 * m_opt.settle_time);
    m_robot.getPosition(vpRobot::ARTICULAR_FRAME, v.q);
  } catch (const std::exception &e) {
    r.status = ROBOT_ERROR;
    r.message = what + ": the robot failed: " + describe(e);
    return r;
  }
  if (v.q.size() != m_model.getNumJoints()) {
    r.status = ROBOT_ERROR;
    r.message = what + ": the robot reports " + std::to_string(v.q.size()) + " joints, the model has " +
                std::to_string(m_model.getNumJoints());
    return r;
  }
  if (command) {
    for (unsigned int i = 0; i < v.q.size(); ++i)
      if (!(std::fabs(v.q[i] - (*command)[i]) <= m_opt.reach_tolerance)) {
        std::ostringstream os;
        os << what << ": the robot did not reach the configuration (joint " << i + 1 << " at " << v.q[i]
           << " rad, commanded " << (*command)[i] << ")";
        r.status = ROBOT_ERROR;
        r.message = os.str();
        return r;
      }
  } else if (!m_model.isInJointLimits(v.q)) {
    r.status = ROBOT_ERROR;
    r.message = what + ": the current joints are outside the model's joint limits; pose not recorded";
    return r;
  }
  vpImage<unsigned char> I;
  try {
    m_source(I);
  } catch (const std::exception &e) {
    r.status = IMAGE_ERROR;
    r.message = what + ": the image source failed: " + describe(e);
    return r;
  }
  if (I.getWidth() == 0 || I.getHeight() == 0) {
    r.status = IMAGE_ERROR;
    r.message = what + ": the image source gave an empty image";
    return r;
  }
  // Image first (atomically), then the dataset that lists it (atomically).
  const fs::path parent = fs::path(m_opt.dataset_file).parent_path();
  const fs::path dir = (parent.empty() ? fs::path(".") : parent) / m_opt.image_dir;
  std::error_code ec;
  fs::create_directories(dir, ec);
  const fs::path file = dir / imageName(index + 1), tmp = dir / (".tmp-" + imageName(index + 1));
  try {
    vpImageIo::write(I, tmp.string());
  } catch (const std::exception &e) {
    throw vpSelfCalibException(vpSelfCalibException::ioError,
                               "vpSelfCalibAcquisition: cannot write image '" + tmp.string() + "': " + describe(e));
  }
  fs::rename(tmp, file, ec);
  if (ec)
    throw vpSelfCalibException(vpSelfCalibException::ioError,
                               "vpSelfCalibAcquisition: cannot rename '" + tmp.string() + "' to '" + file.string() +
                                   "': " + ec.message());
  v.image = fs::absolute(file).lexically_normal().string();
  ds.views.push_back(v);
  // Absolute path: the images and the robot file are then written relative to the dataset's directory.
  ds.saveYaml(fs::absolute(m_opt.dataset_file).lexically_normal().string());
  r.acquired = 1;
  return r;
}

vpSelfCalibAcquisition::Result vpSelfCalibAcquisition::run(const std::vector<vpColVector> &plan,
                                                           const Progress &progress)
{
  const unsigned int n = static_cast<unsigned int>(plan.size());
  if (n == 0)
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpSelfCalibAcquisition::run: the plan is empty");
  for (unsigned int k = 0; k < n; ++k) {
    if (plan[k].size() != m_model.getNumJoints())
      throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                                 "vpSelfCalibAcquisition::run: configuration " + std::to_string(k + 1) + " has " +
                                     std::to_string(plan[k].size()) + " joints, the model " +
                                     std::to_string(m_model.getNumJoints()));
    if (!m_model.isInJointLimits(plan[k]))
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpSelfCalibAcquisition::run: configuration " + std::to_string(k + 1) +
                                     " is outside the joint limits of '" + m_model.getName() + "'; nothing moved");
  }
  Result r;
  // The visiting order: calibration poses first, then the rest, each in a short-travel order.
  const unsigned int split = m_opt.calibration_poses > 0 && m_opt.calibration_poses < n ? m_opt.calibration_poses : n;
  if (m_opt.reorder) {
    r.order = orderGroup(plan, 0, split);
    if (split < n) {
      const std::vector<unsigned int> rest = orderGroup(plan, split, n);
      r.order.insert(r.order.end(), rest.begin(), rest.end());
    }
  } else {
    for (unsigned int k = 0; k < n; ++k)
      r.order.push_back(k);
  }
  std::vector<unsigned int> identity(n);
  for (unsigned int k = 0; k < n; ++k)
    identity[k] = k;
  r.travel_plan_order = travel(plan, identity);
  r.travel = travel(plan, r.order);

  vpSelfCalibDataset ds = loadExisting();
  if (ds.views.size() > n)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpSelfCalibAcquisition::run: the existing dataset '" + m_opt.dataset_file + "' has " +
                                   std::to_string(ds.views.size()) + " poses, more than the plan's " +
                                   std::to_string(n));
  for (size_t k = 0; k < ds.views.size(); ++k) {
    const vpColVector &q = ds.views[k].q;
    if (q.size() != m_model.getNumJoints() ||
        (q - plan[r.order[k]]).getMaxValue() > m_opt.resume_tolerance ||
        (plan[r.order[k]] - q).getMaxValue() > m_opt.resume_tolerance)
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpSelfCalibAcquisition::run: pose " + std::to_string(k + 1) + " of the existing dataset '" +
                                     m_opt.dataset_file +
                                     "' is not the one this plan visits there: it is another acquisition");
  }
  r.resumed = static_cast<unsigned int>(ds.views.size());
  if (progress && r.resumed > 0)
    progress(r.resumed, n, "resumed: " + std::to_string(r.resumed) + " poses already in the dataset");
  for (unsigned int k = r.resumed; k < n; ++k) {
    const std::string what = "pose " + std::to_string(k + 1) + " of " + std::to_string(n) + " (plan configuration " +
                             std::to_string(r.order[k] + 1) + ")";
    const Result one = recordPose(ds, &plan[r.order[k]], k, what);
    if (one.status != OK) {
      r.status = one.status;
      r.message = one.message + "; the dataset keeps the " + std::to_string(ds.views.size()) + " poses recorded before";
      break;
    }
    ++r.acquired;
    if (progress)
      progress(k + 1, n, what + " recorded");
  }
  r.total = static_cast<unsigned int>(ds.views.size());
  r.dataset = ds;
  return r;
}

vpSelfCalibAcquisition::Result vpSelfCalibAcquisition::record(const Progress &progress)
{
  vpSelfCalibDataset ds = loadExisting();
  const unsigned int k = static_cast<unsigned int>(ds.views.size());
  const std::string what = "taught pose " + std::to_string(k + 1);
  Result r = recordPose(ds, nullptr, k, what);
  r.resumed = k;
  r.total = static_cast<unsigned int>(ds.views.size());
  r.dataset = ds;
  if (progress && r.status == OK)
    progress(r.total, r.total, what + " recorded");
  return r;
}
