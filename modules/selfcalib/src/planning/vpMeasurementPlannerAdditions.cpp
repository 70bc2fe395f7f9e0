/*
 * ViSP SelfCalib: measurement planning, the poses to add so that the parameters a calibration's views
 * leave at nominal are determined (the estimated set's information, NLopt for the refinement).
 */
#include <visp3/selfcalib/vpMeasurementPlanner.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <sstream>

#include <nlopt.hpp>

#include "../core/vpSelfCalibCamera.h"
#include "../core/vpSelfCalibGeometry.h"
#include "../core/vpSelfCalibRandom.h"

using namespace vpSelfCalib;

namespace
{
using MP = vpMeasurementPlanner;
using KBA = vpKinematicBundleAdjustment;
using View = vpSelfCalibDataset::View;

// Random stream of this file.
const uint64_t kAdditionCandidates = 0x504c414e04ULL;
// Ratio (sd / tolerance) that stands for "not determined", and the floor of the score's terms.
const double kUndetermined = 1e6, kFloor = 0.1;

//! What the search shares: the views, the scene, the calibration's settings, the parameters.
struct Problem {
  const vpKinematicChain *chain = nullptr;
  const std::vector<View> *views = nullptr;
  vpCameraParameters camera;
  const std::map<int, vpColVector> *points = nullptr;
  vpSelfCalibDataset::Yardstick yardstick;
  KBA::Options bundle;
  vpSelfCalibNoiseModel noise;
  std::vector<unsigned int> kept, left; // chain indices: estimated by the views, left at nominal
  const vpPlannerScene *scene = nullptr;
  unsigned int min_visible = 6;
};

double toleranceOf(unsigned int index, unsigned int n_joints, const KBA::Options &o)
{
  const bool eMc = index / vpKinematicChain::kBlockSize == n_joints + 1;
  const bool t = index % vpKinematicChain::kBlockSize < 3;
  return eMc ? (t ? o.tolerance_hand_eye_translation : o.tolerance_hand_eye_rotation)
             : (t ? o.tolerance_translation : o.tolerance_rotation);
}

//! The view at q: the scene points in the image (scene margin, in front) through the nominal model.
View simulatedView(const Problem &p, const vpColVector &q)
{
  View v;
  v.q = q;
  const Rigid cMf = rigidFromVisp(p.chain->get_fMc(q)).inverse();
  const CameraModel camera = CameraModel::fromVisp(p.camera);
  const double m = p.scene->margin;
  for (const auto &e : *p.points) {
    const Eigen::Vector3d X = cMf * vec3(e.second);
    if (X.z() < p.scene->min_depth)
      continue;
    const Eigen::Vector2d uv = camera.project(X);
    if (uv(0) < m || uv(1) < m || uv(0) > p.scene->width - 1 - m || uv(1) > p.scene->height - 1 - m)
      continue;
    vpSelfCalibDataset::Observation o;
    o.id = e.first;
    o.ip.set_uv(uv(0), uv(1));
    v.points.push_back(o);
  }
  return v;
}

/*
  The estimated set's walk over the parameters left, each with the kept ones and those admitted
  before it: its ratio is the largest sd / tolerance of that subset (its own, or one it would push
  beyond the tolerance, as the estimated set's test), with the views and the added ones.
*/
std::vector<double> ratios(const Problem &p, const std::vector<View> &added)
{
  std::vector<View> all = *p.views;
  all.insert(all.end(), added.begin(), added.end());
  std::vector<unsigned int> cols = p.kept;
  std::vector<double> r(p.left.size(), kUndetermined);
  for (size_t l = 0; l < p.left.size(); ++l) {
    std::vector<unsigned int> c = cols;
    c.push_back(p.left[l]);
    std::sort(c.begin(), c.end());
    const vpColVector sd = KBA::predictedSd(*p.chain, p.camera, all, p.yardstick, *p.points, c, p.bundle, p.noise);
    double worst = 0;
    for (unsigned int k = 0; k < sd.size(); ++k)
      worst = std::max(worst, sd[k] / toleranceOf(c[k], p.chain->getNumJoints(), p.bundle));
    if (std::isfinite(worst))
      r[l] = std::min(kUndetermined, worst);
    if (r[l] <= 1)
      cols = c;
  }
  return r;
}

double score(const std::vector<double> &r)
{
  double s = 0;
  for (double v : r)
    s += std::log(std::max(v, kFloor));
  return s;
}

//! The candidate's joints are distinct from every configuration given and valid (limits, view).
bool acceptable(const Problem &p, const MP &planner, const MP::AdditionOptions &o, const vpColVector &q,
                const std::vector<vpColVector> &taken)
{
  if (!p.chain->isInJointLimits(q, 1e-9))
    return false;
  for (const vpColVector &t : taken)
    if ((q - t).frobeniusNorm() < o.min_joint_distance)
      return false;
  return simulatedView(p, q).points.size() >= p.min_visible && planner.isVisible(q, p.scene->margin) &&
         planner.robustFailures({q}, o.robust) == 0;
}

/*
  Re-aim: the joints other than `held` moved by damped Gauss-Newton steps (numerical Jacobian) so
  that the optical axis passes through `centre` at `distance`. False when it does not converge.
*/
bool aim(const vpKinematicChain &chain, vpColVector &q, unsigned int held, const Eigen::Vector3d &centre, double distance)
{
  const unsigned int n = chain.getNumJoints();
  auto residual = [&](const vpColVector &x) {
    const Eigen::Vector3d Xc = rigidFromVisp(chain.get_fMc(x)).inverse() * centre;
    return Eigen::Vector3d(Xc.x() / Xc.z(), Xc.y() / Xc.z(), (Xc.z() - distance) / distance);
  };
  for (int it = 0; it < 30; ++it) {
    const Eigen::Vector3d r = residual(q);
    if (r.norm() < 1e-9)
      break;
    Eigen::MatrixXd J(3, n - 1);
    for (unsigned int j = 0, c = 0; j < n; ++j)
      if (j != held) {
        vpColVector qe = q;
        qe[j] += 1e-6;
        J.col(c++) = (residual(qe) - r) / 1e-6;
      }
    const Eigen::VectorXd step = J.completeOrthogonalDecomposition().solve(r);
    for (unsigned int j = 0, c = 0; j < n; ++j)
      if (j != held)
        q[j] -= std::max(-0.3, std::min(0.3, step(c++)));
  }
  return residual(q).norm() < 1e-6;
}

size_t pick(Random &rng, size_t n) { return std::min(n - 1, static_cast<size_t>(rng.uniform() * static_cast<double>(n))); }

//! The feasible candidates of one round: a view's joints, one joint moved, the others re-aimed.
std::vector<vpColVector> drawCandidates(const Problem &p, const MP &planner, const MP::AdditionOptions &o, Random &rng,
                                        const std::vector<vpColVector> &taken)
{
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const auto &e : *p.points)
    centre += vec3(e.second);
  centre /= static_cast<double>(p.points->size());
  const unsigned int n = p.chain->getNumJoints();
  std::vector<vpColVector> out;
  for (unsigned int c = 0; c < o.pool; ++c) {
    const View &v = (*p.views)[pick(rng, p.views->size())];
    vpColVector q = v.q;
    const unsigned int j = static_cast<unsigned int>(pick(rng, n));
    const vpKinematicChain::Joint &J = p.chain->getJoints()[j];
    q[j] = std::max(J.min, std::min(J.max, q[j] + rng.uniform(-o.step, o.step)));
    const double distance = (rigidFromVisp(p.chain->get_fMc(v.q)).inverse() * centre).z();
    if (distance > 0 && aim(*p.chain, q, j, centre, distance) && acceptable(p, planner, o, q, taken))
      out.push_back(q);
  }
  return out;
}

//! NLopt (LN_BOBYQA) refinement of one pose around q; an invalid configuration scores as undetermined.
vpColVector refine(const Problem &p, const MP &planner, const MP::AdditionOptions &o, const std::vector<View> &added,
                   const std::vector<vpColVector> &taken, const vpColVector &q, double &best)
{
  if (o.max_evaluations == 0)
    return q;
  const unsigned int n = q.size();
  std::vector<double> x(n), lb(n), ub(n);
  for (unsigned int j = 0; j < n; ++j) {
    const vpKinematicChain::Joint &J = p.chain->getJoints()[j];
    x[j] = q[j];
    lb[j] = std::max(J.min, q[j] - o.refine_step);
    ub[j] = std::min(J.max, q[j] + o.refine_step);
  }
  struct Context {
    const Problem *p;
    const MP *planner;
    const MP::AdditionOptions *o;
    const std::vector<View> *added;
    const std::vector<vpColVector> *taken;
    double best;
    vpColVector best_q;
  } ctx{&p, &planner, &o, &added, &taken, best, q};
  auto objective = [](const std::vector<double> &xv, std::vector<double> &, void *data) -> double {
    Context *c = static_cast<Context *>(data);
    const vpColVector qv(xv);
    if (!acceptable(*c->p, *c->planner, *c->o, qv, *c->taken))
      return score(std::vector<double>(c->p->left.size(), kUndetermined));
    std::vector<View> with = *c->added;
    with.push_back(simulatedView(*c->p, qv));
    const double s = score(ratios(*c->p, with));
    if (s < c->best) {
      c->best = s;
      c->best_q = qv;
    }
    return s;
  };
  nlopt::opt opt(nlopt::LN_BOBYQA, n);
  opt.set_lower_bounds(lb);
  opt.set_upper_bounds(ub);
  opt.set_min_objective(objective, &ctx);
  opt.set_maxeval(static_cast<int>(o.max_evaluations));
  opt.set_initial_step(0.25 * o.refine_step);
  double f = 0;
  try {
    opt.optimize(x, f);
  } catch (const std::exception &) {
    // The best valid point seen is kept whatever ended the search.
  }
  best = ctx.best;
  return ctx.best_q;
}

//! The parameters left at nominal by the data in an estimated set.
std::vector<unsigned int> leftByData(const vpKinematicIdentification::Identifiability &set)
{
  std::vector<unsigned int> left;
  for (const auto &u : set.unidentifiable)
    if (u.cause == vpKinematicIdentification::CAUSE_DATA)
      left.push_back(u.index);
  return left;
}

//! The named parameters, each a candidate of the model's rule for these views (else a caller mistake).
std::vector<unsigned int> leftOf(const vpKinematicChain &chain, const vpKinematicIdentification::Identifiability &set,
                                 const std::vector<std::string> &names)
{
  std::vector<unsigned int> out;
  for (const std::string &n : names) {
    const unsigned int i = chain.getParameterIndex(n);
    bool candidate = std::binary_search(set.identified.begin(), set.identified.end(), i);
    for (const auto &u : set.unidentifiable)
      candidate = candidate || (u.index == i && u.cause == vpKinematicIdentification::CAUSE_DATA);
    if (!candidate)
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpMeasurementPlanner::planAdditions: '" + n +
                                     "' cannot be determined by more poses (fixed, or redundant in the model's "
                                     "structure); name parameters the data leave at nominal");
    out.push_back(i);
  }
  return out;
}

std::string describe(const std::vector<std::string> &names, const std::vector<double> &ratio)
{
  std::ostringstream os;
  os << std::setprecision(2);
  for (size_t l = 0; l < names.size(); ++l) {
    os << (l ? ", " : "") << names[l] << " ";
    if (ratio[l] >= kUndetermined)
      os << "undetermined";
    else
      os << ratio[l] << "x";
  }
  return os.str();
}

/*
  Greedy: per pose, the best of a fresh pool of candidates, refined; until every parameter left is
  determined (o.poses 0) or o.poses are proposed.
*/
void addPoses(const Problem &p, const MP &planner, const MP::AdditionOptions &o, const MP::Progress &progress,
              std::vector<vpColVector> &taken, MP::AdditionResult &res)
{
  Random rng(o.seed, kAdditionCandidates);
  std::vector<View> added;
  std::vector<double> current = res.ratio_before;
  const unsigned int target = o.poses > 0 ? o.poses : o.max_poses;
  for (unsigned int k = 0; k < target; ++k) {
    if (o.poses == 0 && std::all_of(current.begin(), current.end(), [&o](double r) { return r <= o.target; }))
      break;
    if (progress)
      progress("poses to add", k, target);
    const std::vector<vpColVector> candidates = drawCandidates(p, planner, o, rng, taken);
    res.candidates += static_cast<unsigned int>(candidates.size());
    if (candidates.empty())
      break;
    double best = 0;
    size_t best_points = 0;
    vpColVector best_q;
    for (const vpColVector &c : candidates) {
      std::vector<View> with = added;
      with.push_back(simulatedView(p, c));
      const double s = score(ratios(p, with));
      const size_t n = with.back().points.size();
      if (best_q.size() == 0 || s < best - 1e-9 || (s <= best + 1e-9 && n > best_points)) {
        best = s;
        best_points = n;
        best_q = c;
      }
    }
    MP::Addition a;
    a.q = refine(p, planner, o, added, taken, best_q, best);
    added.push_back(simulatedView(p, a.q));
    a.visible = static_cast<unsigned int>(added.back().points.size());
    a.ratio = ratios(p, added);
    for (size_t l = 0; l < a.ratio.size(); ++l)
      if (a.ratio[l] <= o.target && current[l] > o.target)
        a.determined.push_back(res.left[l]);
    current = a.ratio;
    taken.push_back(a.q);
    res.additions.push_back(a);
  }
}
} // namespace

void vpMeasurementPlanner::AdditionOptions::check() const
{
  robust.check();
  if (!(target > 0 && target <= 1))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpMeasurementPlanner::AdditionOptions: target must be in (0, 1]");
  if (max_poses < 1 || poses > 100 || max_poses > 100 || pool < 1 || !(step > 0 && std::isfinite(step)) ||
      !(refine_step > 0 && std::isfinite(refine_step)) || !(min_joint_distance >= 0))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpMeasurementPlanner::AdditionOptions: poses and max_poses must be at most 100 "
                               "(max_poses at least 1), pool at least 1, step and refine_step positive, "
                               "min_joint_distance >= 0");
}

vpMeasurementPlanner::AdditionResult
vpMeasurementPlanner::planAdditions(const std::vector<vpSelfCalibDataset::View> &views, const vpCameraParameters &camera,
                                    const std::map<int, vpColVector> &points,
                                    const vpSelfCalibDataset::Yardstick &yardstick,
                                    const vpKinematicBundleAdjustment::Options &bundle,
                                    const vpSelfCalibNoiseModel &noise, const AdditionOptions &o,
                                    const Progress &progress) const
{
  const auto t0 = std::chrono::steady_clock::now();
  o.check();
  if (bundle.hand_eye_only)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpMeasurementPlanner::planAdditions: the bundle options are hand-eye-only; the poses "
                               "to add are for the full kinematic calibration (parameters left at nominal)");
  std::vector<vpColVector> taken;
  for (size_t k = 0; k < views.size(); ++k) {
    if (views[k].q.size() != m_chain.getNumJoints())
      throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                                 "vpMeasurementPlanner::planAdditions: view " + std::to_string(k) + " has " +
                                     std::to_string(views[k].q.size()) + " joint values, the model " +
                                     std::to_string(m_chain.getNumJoints()) +
                                     " (controller poses alone cannot be planned from: the joints are needed)");
    taken.push_back(views[k].q);
  }
  AdditionResult res;
  const std::vector<std::string> names = m_chain.getParameterNames();
  const vpKinematicIdentification::Identifiability set =
      KBA::estimatedSet(m_chain, camera, views, yardstick, points, bundle, noise);
  // In the walk's order (the preference order), as the estimated set admits them.
  res.left_index = o.left.empty() ? leftByData(set) : leftOf(m_chain, set, o.left);
  auto rank = [&set](unsigned int i) { return std::find(set.order.begin(), set.order.end(), i) - set.order.begin(); };
  std::stable_sort(res.left_index.begin(), res.left_index.end(),
                   [&rank](unsigned int a, unsigned int b) { return rank(a) < rank(b); });
  for (unsigned int i : res.left_index)
    res.left.push_back(names[i]);
  if (res.left.empty()) {
    res.status = OK;
    res.message = "the views determine every parameter of the estimated set: no pose to add";
    res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return res;
  }
  // The scene rule of the poses proposed: min_visible points, the margin, through sampled models.
  std::vector<size_t> counts;
  for (const View &v : views)
    counts.push_back(v.points.size());
  std::nth_element(counts.begin(), counts.begin() + counts.size() / 2, counts.end());
  vpPlannerScene scene = m_scene;
  scene.min_visible = o.min_visible > 0 ? o.min_visible
                                        : std::max<unsigned int>(6, static_cast<unsigned int>(counts[counts.size() / 2] / 2));
  scene.min_visible = std::min<unsigned int>(scene.min_visible, static_cast<unsigned int>(scene.points.size()));
  scene.required.clear();
  const vpMeasurementPlanner planner(m_chain, scene);
  Problem p;
  p.chain = &m_chain;
  p.views = &views;
  p.camera = camera;
  p.points = &points;
  p.yardstick = yardstick;
  p.bundle = bundle;
  p.noise = noise;
  for (unsigned int i : set.identified)
    if (std::find(res.left_index.begin(), res.left_index.end(), i) == res.left_index.end())
      p.kept.push_back(i);
  p.left = res.left_index;
  p.scene = &scene;
  p.min_visible = scene.min_visible;
  res.ratio_before = ratios(p, {});
  addPoses(p, planner, o, progress, taken, res);
  // What the views and the poses proposed leave, by the estimated set itself.
  std::vector<View> all = views;
  for (const Addition &a : res.additions)
    all.push_back(simulatedView(p, a.q));
  for (unsigned int i : leftByData(KBA::estimatedSet(m_chain, camera, all, yardstick, points, bundle, noise)))
    res.still_left.push_back(names[i]);
  std::ostringstream os;
  os << res.additions.size() << " pose(s) proposed from " << res.candidates << " feasible candidates; left at nominal: "
     << describe(res.left, res.ratio_before) << " (predicted sd / tolerance) -> "
     << (res.still_left.empty() ? std::string("none") : "still left: " + [&] {
          std::string s;
          for (const std::string &n : res.still_left)
            s += (s.empty() ? "" : " ") + n;
          return s;
        }());
  res.status = res.additions.empty() ? INFEASIBLE : res.still_left.empty() ? OK : UNDETERMINED;
  if (res.additions.empty())
    os << "; no candidate pose keeps " << scene.min_visible << " scene points in view within the joint limits "
       << "through the nominal model and the models sampled from its tolerance";
  res.message = os.str();
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}
