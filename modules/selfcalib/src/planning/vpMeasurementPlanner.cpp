/*
 * ViSP SelfCalib: measurement planning, the paper's optimal trajectory (eqs. 22-39) with NLopt and
 * observability-optimal selection from a pool.
 */
#include <visp3/selfcalib/vpKinematicIdentification.h>
#include <visp3/selfcalib/vpMeasurementPlanner.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <nlopt.hpp>

#include "../core/vpSelfCalibCamera.h"
#include "../core/vpSelfCalibGeometry.h"
#include "../core/vpSelfCalibMath.h"
#include "../core/vpSelfCalibRandom.h"
#include "../core/vpSelfCalibRange.h"

using namespace vpSelfCalib;

namespace
{
using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Random streams of this file.
const uint64_t kGenericConfigurations = 0x504c414e01ULL, kMultistart = 0x504c414e02ULL,
               kModelSamples = 0x504c414e03ULL;
// Central-difference step (rad) of the per-pair blocks with respect to the joints.
const double kStep = 1e-6;
// cond(J) used in the cost when J is rank deficient (finite, so the optimizer can move away).
const double kSingularCondition = 1e12;

// Camera pose and identification Jacobian (identifiable columns) at one configuration.
struct PoseKin {
  Rigid T;
  Eigen::MatrixXd J; // 6 x K: rows 0-2 dp in f, rows 3-5 dphi in f
};

PoseKin poseKin(const vpKinematicChain &chain, const std::vector<unsigned int> &cols, const vpColVector &q)
{
  PoseKin p;
  p.T = rigidFromVisp(chain.get_fMc(q));
  const vpMatrix J = chain.getJacobian(q);
  p.J.resize(6, static_cast<Eigen::Index>(cols.size()));
  for (unsigned int r = 0; r < 6; ++r)
    for (size_t c = 0; c < cols.size(); ++c)
      p.J(r, static_cast<Eigen::Index>(c)) = J[r][cols[c]];
  return p;
}

// The pair block of (q_0, q_i): t of c_iMc_0, its derivative Dt and the rotation derivative Dr
// (in c_i) with respect to the identifiable parameters (see vpKinematicIdentification).
struct Block {
  Eigen::Vector3d t;
  Eigen::MatrixXd Dt, Dr; // 3 x K

  Block operator-(const Block &o) const { return {t - o.t, Dt - o.Dt, Dr - o.Dr}; }
  Block operator*(double s) const { return {t * s, Dt * s, Dr * s}; }
};

Block pairBlock(const PoseKin &A, const PoseKin &B)
{
  Block b;
  b.t = A.T.R.transpose() * (B.T.t - A.T.t);
  relativePoseJacobian(A.T, A.J, B.T, B.J, b.Dt, b.Dr);
  return b;
}

// The 6 rows of a pair in J: translation divided by direction_sd |t|, rotation by rotation_sd.
Eigen::MatrixXd weightedRows(const Block &b, double direction_sd, double rotation_sd)
{
  Eigen::MatrixXd rows(6, b.Dt.cols());
  rows.topRows(3) = b.Dt / (direction_sd * b.t.norm());
  rows.bottomRows(3) = b.Dr / rotation_sd;
  return rows;
}

vpColVector perturbed(const vpColVector &q, unsigned int j, double h)
{
  vpColVector p = q;
  p[j] += h;
  return p;
}

std::vector<double> singularValuesOfInformation(const Eigen::MatrixXd &info)
{
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(info, Eigen::EigenvaluesOnly);
  std::vector<double> s;
  for (Eigen::Index k = 0; k < es.eigenvalues().size(); ++k)
    s.push_back(std::sqrt(std::max(0.0, es.eigenvalues()(k))));
  return s;
}

double indexValue(const vpObservabilityIndices &o, vpMeasurementPlanner::Index index)
{
  switch (index) {
  case vpMeasurementPlanner::INDEX_O1:
    return o.O1;
  case vpMeasurementPlanner::INDEX_O2:
    return o.O2;
  case vpMeasurementPlanner::INDEX_O3:
    return o.O3;
  case vpMeasurementPlanner::INDEX_O4:
    return o.O4;
  case vpMeasurementPlanner::INDEX_O5:
    return o.O5;
  }
  return 0;
}
} // namespace

const char *vpMeasurementPlanner::statusName(Status s)
{
  switch (s) {
  case OK:
    return "ok";
  case TOO_FEW_CONFIGURATIONS:
    return "too few configurations";
  case INFEASIBLE:
    return "infeasible";
  case FAILED:
    return "failed";
  case UNDETERMINED:
    return "undetermined";
  }
  return "unknown";
}

vpMeasurementPlanner::Algorithm vpMeasurementPlanner::algorithmFromName(const std::string &name)
{
  if (name == "mma")
    return ALGO_MMA;
  if (name == "slsqp")
    return ALGO_SLSQP;
  if (name == "lbfgs")
    return ALGO_LBFGS;
  if (name == "bobyqa")
    return ALGO_BOBYQA;
  throw vpSelfCalibException(vpSelfCalibException::badValue,
                             "vpMeasurementPlanner: unknown algorithm '" + name + "' (mma, slsqp, lbfgs, bobyqa)");
}

vpMeasurementPlanner::Index vpMeasurementPlanner::indexFromName(const std::string &name)
{
  const std::string n = name.size() == 2 && (name[0] == 'o' || name[0] == 'O') ? std::string("O") + name[1] : name;
  if (n == "O1")
    return INDEX_O1;
  if (n == "O2")
    return INDEX_O2;
  if (n == "O3")
    return INDEX_O3;
  if (n == "O4")
    return INDEX_O4;
  if (n == "O5")
    return INDEX_O5;
  throw vpSelfCalibException(vpSelfCalibException::badValue,
                             "vpMeasurementPlanner: unknown observability index '" + name + "' (O1 .. O5)");
}

void vpMeasurementPlanner::TrajectoryOptions::check() const
{
  auto bad = [](const std::string &what) {
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpMeasurementPlanner: " + what);
  };
  if (!(lambda >= 0 && std::isfinite(lambda)))
    bad("lambda must be >= 0");
  if (!(multistart_sd >= 0) || !std::isfinite(planning_margin) || !(visibility_weight > 0) ||
      !(min_joint_distance >= 0) || !(joint_distance_margin >= 0 && std::isfinite(joint_distance_margin)) ||
      !(distinct_weight > 0))
    bad("multistart_sd, min_joint_distance, joint_distance_margin must be >= 0, planning_margin finite and the "
        "penalty weights > 0");
  for (double v : {tolerance_translation, tolerance_rotation, tolerance_hand_eye_translation,
                   tolerance_hand_eye_rotation})
    if (!(v >= 0 && std::isfinite(v)))
      bad("the model tolerances must be finite and >= 0");
  if (!(robust_factor >= 1 && std::isfinite(robust_factor)))
    bad("robust_factor must be >= 1");
  if (!(direction_sd > 0 && rotation_sd > 0))
    bad("direction_sd and rotation_sd must be positive");
  if (max_evaluations < 1 || !(relative_tolerance > 0))
    bad("max_evaluations must be >= 1 and relative_tolerance > 0");
}

void vpMeasurementPlanner::SelectionOptions::check() const
{
  if (!(direction_sd > 0 && rotation_sd > 0) || !(min_joint_distance >= 0))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpMeasurementPlanner: direction_sd, rotation_sd must be > 0, min_joint_distance >= 0");
}

vpMeasurementPlanner::vpMeasurementPlanner(const vpKinematicChain &nominal, const Scene &scene)
  : m_chain(nominal), m_scene(scene)
{
  vpSelfCalib::checkChain(nominal, "vpMeasurementPlanner: the nominal model '" + nominal.getName() + "'");
  vpSelfCalib::checkCamera(scene.cam, "vpMeasurementPlanner: the scene's camera");
  if (scene.points.empty())
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpMeasurementPlanner: the scene has no point");
  for (size_t i = 0; i < scene.points.size(); ++i) {
    const vpColVector &P = scene.points[i];
    if (!(P.size() == 3 || P.size() == 4) || !allFinite(P))
      throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                                 "vpMeasurementPlanner: scene point " + std::to_string(i) +
                                     " must be a finite 3-vector (or homogeneous 4-vector)");
  }
  if (!(scene.cam.get_px() > 0 && scene.cam.get_py() > 0) || scene.width == 0 || scene.height == 0)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpMeasurementPlanner: the scene needs a camera with a focal length and an image size");
  if (!(scene.margin >= 0) || !(scene.min_depth > 0))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpMeasurementPlanner: margin must be >= 0 and min_depth > 0");
  for (vpColVector &P : m_scene.points)
    if (P.size() == 4)
      P = vpColVector({P[0] / P[3], P[1] / P[3], P[2] / P[3]});
  if (scene.min_visible > scene.points.size())
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpMeasurementPlanner: min_visible exceeds the number of scene points");
  for (unsigned int r : scene.required)
    if (r >= scene.points.size())
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpMeasurementPlanner: required point " + std::to_string(r) + " is not a scene point");
  if (scene.min_visible == 0)
    m_constrained = m_scene.points;
  else {
    // Partial views: the required points and the centroid (which keeps the bulk of the scene in view).
    vpColVector c(3, 0.0);
    for (const vpColVector &P : m_scene.points)
      c += P;
    c /= static_cast<double>(m_scene.points.size());
    for (unsigned int r : scene.required)
      m_constrained.push_back(m_scene.points[r]);
    m_constrained.push_back(c);
  }
  m_chain.resetParameters();

  // The parameters identifiable from relative poses: structural, so taken at generic configurations.
  m_identified = vpKinematicIdentification::analyseConfigurations(
                     m_chain, vpKinematicIdentification::randomConfigurations(m_chain, 13, 1, kGenericConfigurations),
                     vpKinematicIdentification::Options())
                     .identified;
}

void vpMeasurementPlanner::checkConfigurations(const std::vector<vpColVector> &q, const char *where,
                                               bool limits) const
{
  for (size_t k = 0; k < q.size(); ++k) {
    if (q[k].size() != m_chain.getNumJoints() || !allFinite(q[k]))
      throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                                 std::string("vpMeasurementPlanner::") + where + ": configuration " + std::to_string(k) +
                                     " must have " + std::to_string(m_chain.getNumJoints()) + " finite joint values");
    if (limits && !m_chain.isInJointLimits(q[k], 1e-9))
      throw vpSelfCalibException(vpSelfCalibException::badValue, std::string("vpMeasurementPlanner::") + where +
                                                                     ": configuration " + std::to_string(k) +
                                                                     " is outside the joint limits");
  }
}

bool vpMeasurementPlanner::isVisible(const vpColVector &q, double margin) const
{
  return visibleWith(m_chain, q, margin, nullptr);
}

bool vpMeasurementPlanner::isVisible(const vpKinematicChain &chain, const vpColVector &q, double margin) const
{
  return visibleWith(chain, q, margin, nullptr);
}

bool vpMeasurementPlanner::visibleWith(const vpKinematicChain &chain, const vpColVector &q, double margin,
                                       std::string *why) const
{
  const Rigid cMf = rigidFromVisp(chain.get_fMc(q)).inverse();
  const CameraModel camera = CameraModel::fromVisp(m_scene.cam);
  std::vector<bool> in(m_scene.points.size(), false);
  std::ostringstream first;
  for (size_t i = 0; i < m_scene.points.size(); ++i) {
    const Eigen::Vector3d X = cMf * vec3(m_scene.points[i]);
    if (X.z() < m_scene.min_depth) {
      if (first.tellp() == 0)
        first << "point " << i << " at depth " << X.z() << " m (minimum " << m_scene.min_depth << ")";
      continue;
    }
    const Eigen::Vector2d uv = camera.project(X);
    const double u = uv(0), v = uv(1);
    in[i] = !(u < margin || v < margin || u > m_scene.width - 1 - margin || v > m_scene.height - 1 - margin);
    if (!in[i] && first.tellp() == 0)
      first << "point " << i << " projects at (" << u << ", " << v << ") px, outside the image with margin "
            << margin << " px";
  }
  if (m_scene.min_visible > 0) {
    for (unsigned int r : m_scene.required)
      if (!in[r]) {
        if (why)
          *why = "required point " + std::to_string(r) + " not in view";
        return false;
      }
    const size_t count = static_cast<size_t>(std::count(in.begin(), in.end(), true));
    if (count < m_scene.min_visible && why)
      *why = std::to_string(count) + " points in view, " + std::to_string(m_scene.min_visible) + " needed";
    return count >= m_scene.min_visible;
  }
  const bool ok = std::all_of(in.begin(), in.end(), [](bool b) { return b; });
  if (!ok && why)
    *why = first.str();
  return ok;
}

std::vector<vpKinematicChain> vpMeasurementPlanner::sampleModels(const TrajectoryOptions &o) const
{
  Random rng(o.seed, kModelSamples);
  std::vector<vpKinematicChain> models;
  const unsigned int nblocks = m_chain.getNumParameters() / 6;
  for (unsigned int s = 0; s < o.robust_samples; ++s) {
    vpKinematicChain c = m_chain;
    vpColVector p(m_chain.getNumParameters(), 0.0);
    for (unsigned int b = 0; b < nblocks; ++b) {
      const bool eye = b == nblocks - 1;
      for (unsigned int k = 0; k < 6; ++k)
        p[6 * b + k] = rng.normal(k < 3 ? (eye ? o.tolerance_hand_eye_translation : o.tolerance_translation)
                                        : (eye ? o.tolerance_hand_eye_rotation : o.tolerance_rotation));
    }
    c.setParameters(p);
    models.push_back(c);
  }
  return models;
}

double vpMeasurementPlanner::robustMargin(const std::vector<vpColVector> &q, const TrajectoryOptions &o) const
{
  o.check();
  checkConfigurations(q, "robustMargin", false);
  const std::vector<vpKinematicChain> models = sampleModels(o);
  const CameraModel camera = CameraModel::fromVisp(m_scene.cam);
  double worst = 0;
  for (const vpColVector &qk : q) {
    const Rigid cMf = rigidFromVisp(m_chain.get_fMc(qk)).inverse();
    for (const vpKinematicChain &model : models) {
      const Rigid cMf_s = rigidFromVisp(model.get_fMc(qk)).inverse();
      for (const vpColVector &P : m_constrained) {
        const Eigen::Vector3d X = cMf * vec3(P), Xs = cMf_s * vec3(P);
        if (X.z() < m_scene.min_depth || Xs.z() < m_scene.min_depth)
          continue;
        worst = std::max(worst, (camera.project(Xs) - camera.project(X)).lpNorm<Eigen::Infinity>());
      }
    }
  }
  return o.robust_factor * worst;
}

unsigned int vpMeasurementPlanner::robustFailures(const std::vector<vpColVector> &q, const TrajectoryOptions &o,
                                                  std::string *why) const
{
  o.check();
  checkConfigurations(q, "robustFailures", false);
  const std::vector<vpKinematicChain> models = sampleModels(o);
  unsigned int failures = 0;
  for (size_t k = 0; k < q.size(); ++k)
    for (size_t s = 0; s < models.size(); ++s) {
      std::string w;
      if (!visibleWith(models[s], q[k], m_scene.margin, why && failures == 0 ? &w : nullptr)) {
        if (why && failures == 0)
          *why = "configuration " + std::to_string(k) + " through sampled model " + std::to_string(s) + ": " + w;
        ++failures;
      }
    }
  return failures;
}

std::vector<vpColVector> vpMeasurementPlanner::smoothTrajectory(const vpColVector &centre, const vpColVector &amplitude,
                                                                unsigned int m, double margin, std::string *why) const
{
  const unsigned int n = m_chain.getNumJoints();
  if (centre.size() != n || amplitude.size() != n || m < 2)
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               "vpMeasurementPlanner::smoothTrajectory: centre and amplitude need one value per joint, "
                               "and m at least 2");
  auto fail = [&](const std::string &w) {
    if (why)
      *why = w;
    return std::vector<vpColVector>();
  };
  if (!m_chain.isInJointLimits(centre, 0))
    return fail("the centre configuration is outside the joint limits");
  if (margin < 0)
    margin = m_scene.margin + robustMargin({centre}, TrajectoryOptions());
  {
    std::string w;
    if (!visibleWith(m_chain, centre, margin, &w)) {
      std::ostringstream os;
      os << "the view at the centre configuration is not valid with a margin of " << margin << " px (" << w
         << "): the scene does not fit in the image there; give a smaller margin or another centre";
      return fail(os.str());
    }
  }
  // Each joint's amplitude first shrunk until moving that joint alone by +-a keeps the scene in view
  // (a shoulder turns the view far more than a wrist roll), then one common scale for the loop.
  vpColVector a = amplitude;
  for (unsigned int j = 0; j < n; ++j)
    for (int halving = 0; halving < 20; ++halving) {
      vpColVector lo = centre, hi = centre;
      lo[j] -= a[j];
      hi[j] += a[j];
      if (m_chain.isInJointLimits(lo, 0) && m_chain.isInJointLimits(hi, 0) && isVisible(lo, margin) &&
          isVisible(hi, margin))
        break;
      a[j] *= 0.5;
    }
  for (double s = 1; s > 1e-3; s *= 0.8) {
    std::vector<vpColVector> q(m, centre);
    bool ok = true;
    for (unsigned int k = 0; k < m && ok; ++k) {
      for (unsigned int j = 0; j < n; ++j)
        q[k][j] += s * a[j] * std::sin(2 * M_PI * k / m + 2 * M_PI * j / n);
      ok = m_chain.isInJointLimits(q[k], 0) && isVisible(q[k], margin);
    }
    if (ok) {
      if (why)
        why->clear();
      return q;
    }
  }
  return fail("no common scale (down to 1e-3) of the amplitudes keeps every configuration of the loop within the "
              "limits and in view");
}

std::vector<vpColVector> vpMeasurementPlanner::ratioSensitivities(const std::vector<vpColVector> &q) const
{
  checkConfigurations(q, "ratioSensitivities", false);
  std::vector<vpColVector> g;
  if (q.size() < 2)
    return g;
  const PoseKin P0 = poseKin(m_chain, m_identified, q[0]);
  for (size_t i = 1; i < q.size(); ++i) {
    const Block b = pairBlock(poseKin(m_chain, m_identified, q[i]), P0);
    const Eigen::RowVectorXd gi = b.t.transpose() * b.Dt / b.t.squaredNorm();
    vpColVector v(static_cast<unsigned int>(gi.size()));
    for (Eigen::Index k = 0; k < gi.size(); ++k)
      v[static_cast<unsigned int>(k)] = gi(k);
    g.push_back(v);
  }
  return g;
}

vpObservabilityIndices vpMeasurementPlanner::observability(const std::vector<vpColVector> &q, double direction_sd,
                                                           double rotation_sd) const
{
  checkConfigurations(q, "observability", false);
  if (q.size() < 2)
    throw vpSelfCalibException(vpSelfCalibException::badValue, "vpMeasurementPlanner::observability: 2 configurations at least");
  const PoseKin P0 = poseKin(m_chain, m_identified, q[0]);
  const Eigen::Index K = static_cast<Eigen::Index>(m_identified.size());
  Eigen::MatrixXd info = Eigen::MatrixXd::Zero(K, K);
  for (size_t i = 1; i < q.size(); ++i) {
    const Eigen::MatrixXd rows =
        weightedRows(pairBlock(poseKin(m_chain, m_identified, q[i]), P0), direction_sd, rotation_sd);
    info += rows.transpose() * rows;
  }
  return vpObservabilityIndices::fromSingularValues(singularValuesOfInformation(info),
                                                    static_cast<unsigned int>(q.size() - 1));
}

/*
  The pair blocks of a trajectory (pair i = 1..m-1: block (t_i, Dt_i, Dr_i) of (q_0, q_i)) and, for
  the gradient, their derivatives with respect to the joints.
*/
struct vpMeasurementPlanner::PairBlocks {
  std::vector<PoseKin> P;
  std::vector<Block> F;                    // F[i], i >= 1
  std::vector<std::vector<Block>> dF, dF0; // see pairBlocks()

  // Adds sum over pairs of <W_i, dX_i/dx> for a per-pair function X of the blocks, to the gradient:
  // `directional` is the derivative of X_i along a derivative of block i.
  void chain(size_t i, std::vector<double> &gradient, const std::function<double(const Block &)> &directional) const
  {
    const size_t n = dF[i].size();
    for (unsigned int j = 0; j < n; ++j) {
      gradient[i * n + j] += directional(dF[i][j]);
      gradient[j] += directional(dF0[i][j]);
    }
  }
};

vpMeasurementPlanner::PairBlocks vpMeasurementPlanner::pairBlocks(const std::vector<vpColVector> &q, bool grad) const
{
  const size_t m = q.size(), n = m_chain.getNumJoints();
  PairBlocks B;
  std::vector<PoseKin> &P = B.P;
  std::vector<Block> &F = B.F;
  std::vector<std::vector<Block>> &dF = B.dF, &dF0 = B.dF0;
  P.resize(m);
  for (size_t k = 0; k < m; ++k)
    P[k] = poseKin(m_chain, m_identified, q[k]);
  F.resize(m);
  for (size_t i = 1; i < m; ++i)
    F[i] = pairBlock(P[i], P[0]);
  // dF[i][j]: derivative of block i w.r.t. joint j of q_i; dF0[i][j]: w.r.t. joint j of q_0.
  dF.resize(m);
  dF0.resize(m);
  if (grad && m >= 2) {
    std::vector<PoseKin> P0p(n), P0m(n);
    for (unsigned int j = 0; j < n; ++j) {
      P0p[j] = poseKin(m_chain, m_identified, perturbed(q[0], j, kStep));
      P0m[j] = poseKin(m_chain, m_identified, perturbed(q[0], j, -kStep));
    }
    for (size_t i = 1; i < m; ++i) {
      dF[i].resize(n);
      dF0[i].resize(n);
      for (unsigned int j = 0; j < n; ++j) {
        const PoseKin pp = poseKin(m_chain, m_identified, perturbed(q[i], j, kStep));
        const PoseKin pm = poseKin(m_chain, m_identified, perturbed(q[i], j, -kStep));
        dF[i][j] = (pairBlock(pp, P[0]) - pairBlock(pm, P[0])) * (0.5 / kStep);
        dF0[i][j] = (pairBlock(P[i], P0p[j]) - pairBlock(P[i], P0m[j])) * (0.5 / kStep);
      }
    }
  }
  return B;
}

void vpMeasurementPlanner::ratioTerm(const PairBlocks &B, const TrajectoryOptions &o, CostTerms &ct,
                                     std::vector<double> *gradient) const
{
  const size_t m = B.F.size();
  const Eigen::Index K = static_cast<Eigen::Index>(m_identified.size());
  const bool grad = gradient != nullptr;
  const std::vector<Block> &F = B.F;
  // Ratio term.
  if (m >= 3) {
    std::vector<Eigen::RowVectorXd> g(m);
    for (size_t i = 1; i < m; ++i)
      g[i] = F[i].t.transpose() * F[i].Dt / F[i].t.squaredNorm();
    std::vector<Eigen::RowVectorXd> G(m, Eigen::RowVectorXd::Zero(K)); // d ratio / d g_i
    if (o.ratio_cost == RATIO_CONSECUTIVE) {
      for (size_t i = 2; i < m; ++i) {
        const Eigen::RowVectorXd d = g[i] - g[i - 1];
        ct.ratio += d.squaredNorm();
        G[i] += 2 * d;
        G[i - 1] -= 2 * d;
      }
    } else {
      Eigen::RowVectorXd mean = Eigen::RowVectorXd::Zero(K);
      for (size_t i = 1; i < m; ++i)
        mean += g[i];
      mean /= static_cast<double>(m - 1);
      for (size_t i = 1; i < m; ++i) {
        const Eigen::RowVectorXd d = g[i] - mean;
        ct.ratio += d.squaredNorm();
        G[i] = 2 * d; // the mean's own derivative cancels: sum_i (g_i - mean) = 0
      }
    }
    if (grad)
      for (size_t i = 1; i < m; ++i) {
        const Block &b = F[i];
        const double s = b.t.squaredNorm();
        B.chain(i, *gradient, [&](const Block &d) {
          const Eigen::RowVectorXd dg = (d.t.transpose() * b.Dt + b.t.transpose() * d.Dt) / s -
                                        g[i] * (2 * b.t.dot(d.t) / s);
          return G[i].dot(dg);
        });
      }
  }
}

void vpMeasurementPlanner::conditionTerm(const PairBlocks &B, const TrajectoryOptions &o, CostTerms &ct,
                                         std::vector<double> *gradient) const
{
  const size_t m = B.F.size();
  const Eigen::Index K = static_cast<Eigen::Index>(m_identified.size());
  const bool grad = gradient != nullptr;
  const std::vector<Block> &F = B.F;
  // cond(J) of the weighted relative-pose Jacobian.
  if (m >= 2) {
    const Eigen::Index rows = static_cast<Eigen::Index>(6 * (m - 1));
    Eigen::MatrixXd J(rows, K);
    for (size_t i = 1; i < m; ++i)
      J.middleRows(6 * (i - 1), 6) = weightedRows(F[i], o.direction_sd, o.rotation_sd);
    if (rows >= K) {
      Eigen::JacobiSVD<Eigen::MatrixXd> svd(J, Eigen::ComputeThinU | Eigen::ComputeThinV);
      const Eigen::VectorXd &sv = svd.singularValues();
      const double s1 = sv(0), sK = sv(K - 1);
      if (sK > s1 * 1e-12) {
        ct.condition = s1 / sK;
        if (grad && o.lambda > 0)
          for (size_t i = 1; i < m; ++i) {
            const Block &b = F[i];
            const double tn = b.t.norm();
            const Eigen::VectorXd u1 = svd.matrixU().col(0).segment(6 * (i - 1), 6);
            const Eigen::VectorXd uK = svd.matrixU().col(K - 1).segment(6 * (i - 1), 6);
            const Eigen::VectorXd v1 = svd.matrixV().col(0), vK = svd.matrixV().col(K - 1);
            B.chain(i, *gradient, [&](const Block &d) {
              Eigen::MatrixXd dJ(6, K);
              dJ.topRows(3) = (d.Dt - b.Dt * (b.t.dot(d.t) / (tn * tn))) / (o.direction_sd * tn);
              dJ.bottomRows(3) = d.Dr / o.rotation_sd;
              const double ds1 = u1.dot(dJ * v1), dsK = uK.dot(dJ * vK);
              return o.lambda * (ds1 * sK - s1 * dsK) / (sK * sK);
            });
          }
      } else
        ct.condition = std::numeric_limits<double>::infinity();
    } else
      ct.condition = std::numeric_limits<double>::infinity();
  }
}

void vpMeasurementPlanner::visibilityTerm(const std::vector<vpColVector> &q, const PairBlocks &B,
                                          const TrajectoryOptions &o, CostTerms &ct,
                                          std::vector<double> *gradient) const
{
  const size_t m = q.size(), n = m_chain.getNumJoints();
  const bool grad = gradient != nullptr;
  const std::vector<PoseKin> &P = B.P;
  // Visibility: squared hinges in px on the image bounds (with the planning margin) and on depth.
  const vpCameraParameters &cam = m_scene.cam;
  const CameraModel camera = CameraModel::fromVisp(cam);
  // A negative (derived) planning margin is resolved by planTrajectory(); here it counts as 0.
  const double lo = m_scene.margin + std::max(0.0, o.planning_margin);
  const double hiU = m_scene.width - 1 - lo, hiV = m_scene.height - 1 - lo;
  for (size_t k = 0; k < m; ++k) {
    const Rigid &T = P[k].T;
    const Eigen::Matrix3d Rt = T.R.transpose();
    RowMajor Jq;
    if (grad) {
      const vpMatrix Jv = m_chain.getJointJacobian(q[k]);
      Jq = Eigen::Map<const RowMajor>(Jv.data, Jv.getRows(), Jv.getCols());
    }
    for (const vpColVector &Pf : m_constrained) {
      const Eigen::Vector3d a = vec3(Pf) - T.t;
      const Eigen::Vector3d X = Rt * a;
      // Hinges h >= 0 in px and their derivatives with respect to X.
      double h[5];
      Eigen::Vector3d dh[5];
      const double z = X.z();
      // Projections are only meaningful in front: the point is held at min_depth (no z derivative)
      // when it is closer.
      const double zs = std::max(z, m_scene.min_depth);
      Eigen::Vector2d uv;
      Eigen::Matrix<double, 2, 3> J;
      camera.project(Eigen::Vector3d(X.x(), X.y(), zs), uv, &J, nullptr);
      if (!(z > m_scene.min_depth))
        J.col(2).setZero();
      const double u = uv(0), v = uv(1);
      const Eigen::Vector3d du = J.row(0).transpose(), dv = J.row(1).transpose();
      h[0] = lo - u, dh[0] = -du;
      h[1] = u - hiU, dh[1] = du;
      h[2] = lo - v, dh[2] = -dv;
      h[3] = v - hiV, dh[3] = dv;
      h[4] = (m_scene.min_depth - z) * cam.get_px(), dh[4] = Eigen::Vector3d(0, 0, -cam.get_px());
      for (int c = 0; c < 5; ++c) {
        if (h[c] <= 0)
          continue;
        ct.visibility += o.visibility_weight * h[c] * h[c];
        if (grad) {
          // dX = R^T ([a]x omega - v) for the camera velocity (v, omega) in f.
          const Eigen::RowVector3d w = 2 * o.visibility_weight * h[c] * dh[c].transpose() * Rt;
          for (unsigned int j = 0; j < n; ++j) {
            const Eigen::Vector3d vel = Jq.block(0, j, 3, 1), om = Jq.block(3, j, 3, 1);
            (*gradient)[k * n + j] += w.dot(a.cross(om) - vel);
          }
        }
      }
    }
  }
}

void vpMeasurementPlanner::distinctTerm(const std::vector<vpColVector> &q, const TrajectoryOptions &o, CostTerms &ct,
                                        std::vector<double> *gradient) const
{
  const size_t m = q.size(), n = m_chain.getNumJoints();
  const bool grad = gradient != nullptr;
  // Distinct configurations.
  for (size_t k = 0; k < m; ++k)
    for (size_t l = k + 1; l < m; ++l) {
      double d2 = 0;
      for (unsigned int j = 0; j < n; ++j)
        d2 += (q[k][j] - q[l][j]) * (q[k][j] - q[l][j]);
      const double d = std::sqrt(d2), h = o.min_joint_distance + o.joint_distance_margin - d;
      if (h <= 0)
        continue;
      ct.distinct += o.distinct_weight * h * h;
      if (grad && d > 0)
        for (unsigned int j = 0; j < n; ++j) {
          const double gj = -2 * o.distinct_weight * h * (q[k][j] - q[l][j]) / d;
          (*gradient)[k * n + j] += gj;
          (*gradient)[l * n + j] -= gj;
        }
    }
}

/*
  The whole cost and, if gradient is given, its gradient. See the class description; the notation
  follows it: pair i = 1..m-1, block (t_i, Dt_i, Dr_i), g_i = t_i^T Dt_i / |t_i|^2.
*/
double vpMeasurementPlanner::evaluate(const std::vector<vpColVector> &q, const TrajectoryOptions &o, CostTerms *terms,
                                      std::vector<double> *gradient) const
{
  const size_t m = q.size(), n = m_chain.getNumJoints();
  const bool grad = gradient != nullptr;
  if (grad)
    gradient->assign(n * m, 0.0);
  CostTerms ct;
  const PairBlocks B = pairBlocks(q, grad);
  ratioTerm(B, o, ct, gradient);
  conditionTerm(B, o, ct, gradient);
  visibilityTerm(q, B, o, ct, gradient);
  distinctTerm(q, o, ct, gradient);

  const double cond = std::isfinite(ct.condition) ? ct.condition : kSingularCondition;
  ct.total = ct.ratio + o.lambda * cond + ct.visibility + ct.distinct;
  if (terms)
    *terms = ct;
  return ct.total;
}

vpMeasurementPlanner::CostTerms vpMeasurementPlanner::cost(const std::vector<vpColVector> &q,
                                                           const TrajectoryOptions &o) const
{
  o.check();
  checkConfigurations(q, "cost", false);
  CostTerms t;
  evaluate(q, o, &t, nullptr);
  return t;
}

double vpMeasurementPlanner::costAndGradient(const std::vector<vpColVector> &q, const TrajectoryOptions &o,
                                             vpColVector &gradient) const
{
  o.check();
  checkConfigurations(q, "costAndGradient", false);
  std::vector<double> g;
  const double c = evaluate(q, o, nullptr, &g);
  gradient.resize(static_cast<unsigned int>(g.size()), false);
  for (size_t i = 0; i < g.size(); ++i)
    gradient[static_cast<unsigned int>(i)] = g[i];
  return c;
}

namespace
{
using TrajectoryOptions = vpMeasurementPlanner::TrajectoryOptions;

//! The NLopt algorithm of the options' choice.
nlopt::algorithm nloptAlgorithm(vpMeasurementPlanner::Algorithm a)
{
  nlopt::algorithm algo = nlopt::LD_MMA;
  if (a == vpMeasurementPlanner::ALGO_SLSQP)
    algo = nlopt::LD_SLSQP;
  else if (a == vpMeasurementPlanner::ALGO_LBFGS)
    algo = nlopt::LD_LBFGS;
  else if (a == vpMeasurementPlanner::ALGO_BOBYQA)
    algo = nlopt::LN_BOBYQA;
  return algo;
}

//! The optimizer's variables: m configurations of n joints one after the other, with their bounds
//! (the joint limits) and start (the initial configurations).
struct JointVariables {
  size_t m = 0, n = 0;
  std::vector<double> lb, ub, x0;
  std::vector<vpColVector> configurations(const std::vector<double> &x) const
  {
    std::vector<vpColVector> q(m, vpColVector(static_cast<unsigned int>(n)));
    for (size_t k = 0; k < m; ++k)
      for (unsigned int j = 0; j < n; ++j)
        q[k][j] = x[k * n + j];
    return q;
  }
};

JointVariables jointVariables(const vpKinematicChain &chain, const std::vector<vpColVector> &initial)
{
  JointVariables v;
  v.m = initial.size();
  v.n = chain.getNumJoints();
  const size_t m = v.m, n = v.n;
  const vpColVector qmin = chain.getJointMin(), qmax = chain.getJointMax();
  v.lb.resize(n * m);
  v.ub.resize(n * m);
  v.x0.resize(n * m);
  for (size_t k = 0; k < m; ++k)
    for (unsigned int j = 0; j < n; ++j) {
      v.lb[k * n + j] = qmin[j];
      v.ub[k * n + j] = qmax[j];
      v.x0[k * n + j] = initial[k][j];
    }
  return v;
}

//! The optimizer of one start: bounds, objective, tolerance and evaluation budget.
void configureOptimizer(nlopt::opt &opt, nlopt::algorithm algo, const JointVariables &v, nlopt::vfunc objective,
                        void *data, const TrajectoryOptions &o)
{
  opt.set_lower_bounds(v.lb);
  opt.set_upper_bounds(v.ub);
  opt.set_min_objective(objective, data);
  opt.set_ftol_rel(o.relative_tolerance);
  opt.set_maxeval(static_cast<int>(o.max_evaluations));
  if (algo == nlopt::LN_BOBYQA)
    opt.set_initial_step(0.02);
}

/*
  A plan's configurations are valid: the view valid (scene margin) through the nominal model, the
  configurations min_joint_distance apart, and the view valid through every sampled model.
*/
bool isFeasible(const vpMeasurementPlanner &planner, const std::vector<vpColVector> &q, const TrajectoryOptions &o,
                double margin)
{
  const size_t m = q.size();
  bool feasible = true;
  for (size_t k = 0; k < m && feasible; ++k)
    feasible = planner.isVisible(q[k], margin);
  // Distinct at the checked distance (the penalty's hinge is joint_distance_margin beyond it).
  for (size_t k = 0; k < m && feasible; ++k)
    for (size_t l = k + 1; l < m && feasible; ++l)
      feasible = (q[k] - q[l]).frobeniusNorm() >= o.min_joint_distance;
  // Robust: visible through every model sampled from the nominal model's tolerance.
  feasible = feasible && planner.robustFailures(q, o) == 0;
  return feasible;
}

//! Why no start gave a valid plan (q: the best of them); robust_failures: its failures through the
//! sampled models.
std::string infeasibleMessage(const vpMeasurementPlanner &planner, const std::vector<vpColVector> &q,
                              const TrajectoryOptions &o, double margin, unsigned int &robust_failures)
{
  const size_t m = q.size();
  std::ostringstream os;
  os << "no start ended with a valid view (margin " << margin
     << " px) at every configuration through the nominal model and the " << o.robust_samples
     << " models sampled from its tolerance, and configurations " << o.min_joint_distance
     << " rad apart; first violation at configuration ";
  size_t k = 0;
  while (k < m && planner.isVisible(q[k], margin))
    ++k;
  std::string why;
  robust_failures = planner.robustFailures(q, o, &why);
  if (k < m)
    os << k;
  else if (robust_failures)
    os << "(sampled models: " << why << ")";
  else
    os << "(joint distance)";
  os << " (the scene may be out of reach or wider than the field of view; planning margin "
     << o.planning_margin << " px)";
  return os.str();
}

//! The information of each candidate's pair with the reference pool[0]; usable: not the reference
//! itself nor a pure rotation about the optical centre.
void pairInformation(const vpKinematicChain &chain, const std::vector<unsigned int> &identified,
                     const std::vector<vpColVector> &pool, const vpMeasurementPlanner::SelectionOptions &o,
                     std::vector<Eigen::MatrixXd> &info, std::vector<bool> &usable)
{
  const PoseKin P0 = poseKin(chain, identified, pool[0]);
  info.assign(pool.size(), Eigen::MatrixXd());
  usable.assign(pool.size(), false);
  for (size_t i = 1; i < pool.size(); ++i) {
    const Block b = pairBlock(poseKin(chain, identified, pool[i]), P0);
    if (!(b.t.norm() > 1e-9))
      continue; // the reference itself, or a pure rotation about the optical centre
    const Eigen::MatrixXd rows = weightedRows(b, o.direction_sd, o.rotation_sd);
    info[i] = rows.transpose() * rows;
    usable[i] = true;
  }
}

/*
  The score of a selection of information I over its pairs: full rank sets by the index, the others
  (only during the first additions) by log det(I + info / eps), which favours what fills the most
  new directions.
*/
std::pair<double, double> selectionScore(const Eigen::MatrixXd &I, unsigned int pairs, vpMeasurementPlanner::Index index)
{
  const std::vector<double> s = singularValuesOfInformation(I);
  const double smax = *std::max_element(s.begin(), s.end()), smin = *std::min_element(s.begin(), s.end());
  if (smin > smax * 1e-9)
    return std::make_pair(1.0, indexValue(vpObservabilityIndices::fromSingularValues(s, pairs), index));
  double ld = 0;
  for (double v : s)
    ld += std::log1p(v * v / (1e-6 * smax * smax + 1e-300));
  return std::make_pair(0.0, ld);
}

//! Lexicographic (full rank first), with a relative tolerance so that round-off cannot cycle.
bool betterScore(const std::pair<double, double> &a, const std::pair<double, double> &b)
{
  return a.first > b.first || (a.first == b.first && a.second > b.second + 1e-9 * std::fabs(b.second));
}
} // namespace

vpMeasurementPlanner::Result vpMeasurementPlanner::planTrajectory(const std::vector<vpColVector> &initial) const
{
  return planTrajectory(initial, TrajectoryOptions());
}

vpMeasurementPlanner::Result vpMeasurementPlanner::planTrajectory(const std::vector<vpColVector> &initial,
                                                                  const TrajectoryOptions &given,
                                                                  const Progress &progress) const
{
  const auto t0 = std::chrono::steady_clock::now();
  given.check();
  checkConfigurations(initial, "planTrajectory", true);
  // The planning margin: given, or derived from the model's tolerance at the initial configurations.
  TrajectoryOptions o = given;
  if (o.planning_margin < 0)
    o.planning_margin = robustMargin(initial, given);
  Result res;
  res.planning_margin = o.planning_margin;
  res.configurations = initial;
  const size_t m = initial.size();
  if (m < 2 || 6 * (m - 1) <= m_identified.size()) {
    res.status = TOO_FEW_CONFIGURATIONS;
    res.message = std::to_string(m) + " configurations give " + std::to_string(6 * (m > 0 ? m - 1 : 0)) +
                  " equations for " + std::to_string(m_identified.size()) +
                  " identifiable parameters; 6 (m - 1) must exceed it";
    res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return res;
  }
  evaluate(initial, o, &res.before, nullptr);
  res.observability_before = observability(initial, o.direction_sd, o.rotation_sd);

  const JointVariables vars = jointVariables(m_chain, initial);
  auto toConfigurations = [&](const std::vector<double> &x) { return vars.configurations(x); };
  struct Context {
    const vpMeasurementPlanner *self;
    const TrajectoryOptions *o;
    std::function<std::vector<vpColVector>(const std::vector<double> &)> unpack;
    unsigned int evaluations = 0;
  } ctx{this, &o, toConfigurations, 0};
  auto objective = [](const std::vector<double> &x, std::vector<double> &grad, void *data) -> double {
    Context *c = static_cast<Context *>(data);
    ++c->evaluations;
    return c->self->evaluate(c->unpack(x), *c->o, nullptr, grad.empty() ? nullptr : &grad);
  };
  const nlopt::algorithm algo = nloptAlgorithm(o.algorithm);

  Random rng(o.seed, kMultistart);
  bool have_feasible = false, have_any = false;
  double best = std::numeric_limits<double>::infinity();
  std::vector<double> best_x;
  std::string last_error;
  for (unsigned int s = 0; s <= o.multistart; ++s) {
    if (progress)
      progress("trajectory optimization", s, o.multistart + 1);
    std::vector<double> x = vars.x0;
    if (s > 0)
      for (size_t i = 0; i < x.size(); ++i)
        x[i] = std::min(vars.ub[i], std::max(vars.lb[i], x[i] + rng.normal(o.multistart_sd)));
    nlopt::opt opt(algo, static_cast<unsigned int>(x.size()));
    configureOptimizer(opt, algo, vars, objective, &ctx, o);
    double f = 0;
    try {
      opt.optimize(x, f);
    } catch (const nlopt::roundoff_limited &) {
      f = evaluate(toConfigurations(x), o, nullptr, nullptr); // x is the last good point
    } catch (const std::exception &e) {
      last_error = e.what();
      continue;
    }
    ++res.starts;
    const std::vector<vpColVector> q = toConfigurations(x);
    CostTerms t;
    evaluate(q, o, &t, nullptr);
    const bool feasible = isFeasible(*this, q, o, m_scene.margin);
    // A feasible plan beats any infeasible one; among equals the lower cost wins.
    if (!have_any || (feasible && !have_feasible) || (feasible == have_feasible && t.total < best)) {
      best = t.total;
      best_x = x;
      have_feasible = feasible;
      have_any = true;
    }
  }
  res.evaluations = ctx.evaluations;
  if (!have_any) {
    res.status = FAILED;
    res.message = "the optimizer failed on every start: " + last_error;
  } else if (!have_feasible) {
    res.status = INFEASIBLE;
    res.message = infeasibleMessage(*this, toConfigurations(best_x), o, m_scene.margin, res.robust_failures);
  } else {
    res.status = OK;
    res.configurations = toConfigurations(best_x);
    evaluate(res.configurations, o, &res.after, nullptr);
    res.observability_after = observability(res.configurations, o.direction_sd, o.rotation_sd);
    std::ostringstream os;
    os << "ok: ratio term " << res.before.ratio << " -> " << res.after.ratio << ", cond(J) " << res.before.condition
       << " -> " << res.after.condition << " (" << res.starts << " starts, " << res.evaluations
       << " evaluations; planning margin " << o.planning_margin << " px, visible through " << o.robust_samples
       << " sampled models)";
    res.message = os.str();
  }
  if (res.status != OK)
    res.after = res.before, res.observability_after = res.observability_before;
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

vpMeasurementPlanner::Result vpMeasurementPlanner::selectObservable(const std::vector<vpColVector> &pool,
                                                                    unsigned int m) const
{
  return selectObservable(pool, m, SelectionOptions());
}

vpMeasurementPlanner::Result vpMeasurementPlanner::selectObservable(const std::vector<vpColVector> &pool,
                                                                    unsigned int m, const SelectionOptions &o,
                                                                    const Progress &progress) const
{
  const auto t0 = std::chrono::steady_clock::now();
  o.check();
  checkConfigurations(pool, "selectObservable", false);
  if (m < 2 || m > pool.size())
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpMeasurementPlanner::selectObservable: m = " + std::to_string(m) +
                                   " must be in [2, pool size = " + std::to_string(pool.size()) + "]");
  Result res;
  res.configurations.assign(pool.begin(), pool.begin() + m);
  const Eigen::Index K = static_cast<Eigen::Index>(m_identified.size());
  if (6 * (m - 1) <= m_identified.size()) {
    res.status = TOO_FEW_CONFIGURATIONS;
    res.message = std::to_string(m) + " configurations give " + std::to_string(6 * (m - 1)) + " equations for " +
                  std::to_string(K) + " identifiable parameters; 6 (m - 1) must exceed it";
    res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return res;
  }
  // Information of each candidate's pair with the reference pool[0].
  std::vector<Eigen::MatrixXd> info;
  std::vector<bool> usable;
  pairInformation(m_chain, m_identified, pool, o, info, usable);
  auto score = [&](const Eigen::MatrixXd &I, unsigned int pairs) { return selectionScore(I, pairs, o.index); };
  auto distance = [&](size_t a, size_t b) { return (pool[a] - pool[b]).frobeniusNorm(); };
  std::vector<size_t> sel = {0};
  Eigen::MatrixXd I = Eigen::MatrixXd::Zero(K, K);
  auto tooClose = [&](size_t c, const std::vector<size_t> &s, size_t except) {
    for (size_t k = 0; k < s.size(); ++k)
      if (k != except && distance(c, s[k]) < o.min_joint_distance)
        return true;
    return false;
  };
  auto taken = [&](size_t c) { return std::find(sel.begin(), sel.end(), c) != sel.end(); };
  // Greedy additions.
  while (sel.size() < m) {
    if (progress)
      progress("observability selection (greedy)", static_cast<unsigned int>(sel.size()), m);
    size_t best = 0;
    std::pair<double, double> best_score(-1, -std::numeric_limits<double>::infinity());
    for (size_t c = 1; c < pool.size(); ++c) {
      if (!usable[c] || taken(c) || tooClose(c, sel, sel.size()))
        continue;
      const auto sc = score(I + info[c], static_cast<unsigned int>(sel.size()));
      if (betterScore(sc, best_score)) {
        best_score = sc;
        best = c;
      }
    }
    if (best == 0) {
      res.status = INFEASIBLE;
      res.message = "the pool has only " + std::to_string(sel.size()) +
                    " usable, distinct configurations (min_joint_distance " + std::to_string(o.min_joint_distance) +
                    " rad); " + std::to_string(m) + " were asked";
      res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      return res;
    }
    sel.push_back(best);
    I += info[best];
  }
  // Exchanges: the best improving swap of a selected (not the reference) with an unselected one.
  for (unsigned int pass = 0; pass < o.max_exchange_passes; ++pass) {
    if (progress)
      progress("observability selection (exchange)", pass, o.max_exchange_passes);
    const auto current = score(I, m - 1);
    auto best_score = current;
    size_t best_out = 0, best_in = 0;
    for (size_t k = 1; k < sel.size(); ++k)
      for (size_t c = 1; c < pool.size(); ++c) {
        if (!usable[c] || taken(c) || tooClose(c, sel, k))
          continue;
        const auto sc = score(I - info[sel[k]] + info[c], m - 1);
        if (betterScore(sc, best_score)) {
          best_score = sc;
          best_out = k;
          best_in = c;
        }
      }
    if (best_out == 0)
      break;
    I += info[best_in] - info[sel[best_out]];
    sel[best_out] = best_in;
  }
  res.configurations.clear();
  for (size_t c : sel)
    res.configurations.push_back(pool[c]);
  const std::vector<vpColVector> first(pool.begin(), pool.begin() + m);
  // The cost terms (cond(J) among them) with the caller's row weights and joint distance, as the
  // selection and its indices (the other settings are the trajectory cost's own).
  TrajectoryOptions to;
  to.direction_sd = o.direction_sd;
  to.rotation_sd = o.rotation_sd;
  to.min_joint_distance = o.min_joint_distance;
  evaluate(first, to, &res.before, nullptr);
  evaluate(res.configurations, to, &res.after, nullptr);
  res.observability_before = observability(first, o.direction_sd, o.rotation_sd);
  res.observability_after = observability(res.configurations, o.direction_sd, o.rotation_sd);
  res.status = OK;
  std::ostringstream os;
  os << "ok: O" << static_cast<int>(o.index) + 1 << " " << indexValue(res.observability_before, o.index) << " -> "
     << indexValue(res.observability_after, o.index) << " (first " << m << " of the pool -> selected)";
  res.message = os.str();
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}
