/*
 * ViSP SelfCalib: vpKinematicChain, nominal model, error model, forward kinematics, Jacobians.
 */
#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <cmath>
#include <sstream>

#include "../core/vpSelfCalibMath.h"
#include "../core/vpSelfCalibRange.h"

using namespace vpSelfCalib;

namespace
{
const char *const kComponentNames[6] = {"tx", "ty", "tz", "rx", "ry", "rz"};
}

struct vpKinematicChain::Frames {
  // For each correction block k: rotation of the prefix A_k in f and origin of A_k D_k in f.
  std::vector<Eigen::Matrix3d> R_prefix;
  std::vector<Eigen::Vector3d> origin;
  // For each joint i: axis and origin of its (corrected) rotation in f.
  std::vector<Eigen::Vector3d> joint_axis, joint_origin;
  Rigid fMe, fMc;
};

vpKinematicChain::vpKinematicChain() : m_name("empty"), m_convention(DH) {}

vpKinematicChain::vpKinematicChain(const std::string &name, Convention convention,
                                   const std::vector<Joint> &joints, const vpPoseVector &fMb,
                                   const vpPoseVector &nMe, const vpPoseVector &eMc)
  : m_name(name), m_convention(convention), m_joints(joints), m_fMb(fMb), m_nMe(nMe), m_eMc(eMc)
{
  if (joints.empty())
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicChain '" + name + "': the joint list is empty");
  for (size_t i = 0; i < joints.size(); ++i) {
    const Joint &j = joints[i];
    std::ostringstream where;
    where << "vpKinematicChain '" << name << "': joint " << i + 1 << ": ";
    for (double v : {j.a, j.d, j.alpha, j.theta_offset, j.min, j.max})
      if (!std::isfinite(v))
        throw vpSelfCalibException(vpSelfCalibException::badValue, where.str() + "non-finite value");
    if (j.min > j.max) {
      where << "joint limit min (" << j.min << ") is greater than max (" << j.max << ")";
      throw vpSelfCalibException(vpSelfCalibException::badValue, where.str());
    }
  }
  for (const vpPoseVector *p : {&fMb, &nMe, &eMc})
    for (unsigned int k = 0; k < 6; ++k)
      if (!std::isfinite((*p)[k]))
        throw vpSelfCalibException(vpSelfCalibException::badValue,
                                   "vpKinematicChain '" + name + "': non-finite base, flange or eMc pose");
  m_params.resize(getNumParameters(), true);
  // Finite but absurd values (a link of 1e308 m) overflow the forward kinematics.
  vpSelfCalib::checkChain(*this, "vpKinematicChain '" + name + "'");
  buildPlacements();
}

void vpKinematicChain::buildPlacements()
{
  const size_t n = m_joints.size();
  std::vector<Rigid> P(n);
  Rigid L;
  if (m_convention == DH) {
    // A_i = Rz(q_i) [Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)]: the bracket follows joint i.
    for (size_t i = 0; i < n; ++i) {
      const Joint &j = m_joints[i];
      Rigid after = rotZ(j.theta_offset) * trans(0, 0, j.d) * trans(j.a, 0, 0) * rotX(j.alpha);
      if (i + 1 < n)
        P[i + 1] = after;
      else
        L = after;
    }
  } else {
    // A_i = [Rx(alpha_i) Tx(a_i) Rz(theta_i) Tz(d_i)] Rz(q_i): the bracket precedes joint i.
    for (size_t i = 0; i < n; ++i) {
      const Joint &j = m_joints[i];
      P[i] = rotX(j.alpha) * trans(j.a, 0, 0) * rotZ(j.theta_offset) * trans(0, 0, j.d);
    }
  }
  m_P.resize(n);
  for (size_t i = 0; i < n; ++i)
    m_P[i] = toVisp(P[i]);
  m_L = toVisp(L);
}

std::vector<std::string> vpKinematicChain::presetNames() { return {"puma560", "viper850", "panda", "ur5"}; }

vpColVector vpKinematicChain::getJointMin() const
{
  vpColVector q(getNumJoints());
  for (unsigned int i = 0; i < q.size(); ++i)
    q[i] = m_joints[i].min;
  return q;
}

vpColVector vpKinematicChain::getJointMax() const
{
  vpColVector q(getNumJoints());
  for (unsigned int i = 0; i < q.size(); ++i)
    q[i] = m_joints[i].max;
  return q;
}

void vpKinematicChain::setJointLimits(const vpColVector &qmin, const vpColVector &qmax)
{
  if (qmin.size() != getNumJoints() || qmax.size() != getNumJoints())
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               "vpKinematicChain::setJointLimits: expected two vectors of size " +
                                   std::to_string(getNumJoints()));
  for (unsigned int i = 0; i < getNumJoints(); ++i) {
    if (!std::isfinite(qmin[i]) || !std::isfinite(qmax[i]) || qmin[i] > qmax[i])
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpKinematicChain::setJointLimits: joint " + std::to_string(i + 1) +
                                     ": limits must be finite with min <= max");
  }
  for (unsigned int i = 0; i < getNumJoints(); ++i) {
    m_joints[i].min = qmin[i];
    m_joints[i].max = qmax[i];
  }
}

bool vpKinematicChain::isInJointLimits(const vpColVector &q, double tolerance) const
{
  if (q.size() != getNumJoints())
    return false;
  for (unsigned int i = 0; i < q.size(); ++i)
    if (!std::isfinite(q[i]) || q[i] < m_joints[i].min - tolerance || q[i] > m_joints[i].max + tolerance)
      return false;
  return true;
}

std::vector<std::string> vpKinematicChain::getParameterNames() const
{
  std::vector<std::string> names;
  names.reserve(getNumParameters());
  const unsigned int nblocks = getNumJoints() + 2;
  for (unsigned int b = 0; b < nblocks; ++b) {
    std::string block = b == 0 ? "base" : (b == nblocks - 1 ? "eMc" : "j" + std::to_string(b));
    for (const char *c : kComponentNames)
      names.push_back(block + "." + c);
  }
  return names;
}

unsigned int vpKinematicChain::getParameterIndex(const std::string &name) const
{
  const std::vector<std::string> names = getParameterNames();
  for (unsigned int i = 0; i < names.size(); ++i)
    if (names[i] == name)
      return i;
  throw vpSelfCalibException(vpSelfCalibException::badValue,
                             "vpKinematicChain '" + m_name + "': unknown parameter '" + name +
                                 "' (expected base.*, j1.* .. j" + std::to_string(getNumJoints()) +
                                 ".* or eMc.* with * one of tx ty tz rx ry rz)");
}

void vpKinematicChain::setParameters(const vpColVector &p)
{
  if (p.size() != getNumParameters())
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               "vpKinematicChain::setParameters: expected " +
                                   std::to_string(getNumParameters()) + " values, got " +
                                   std::to_string(p.size()));
  if (!allFinite(p))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicChain::setParameters: non-finite value");
  m_params = p;
}

double vpKinematicChain::getParameter(const std::string &name) const { return m_params[getParameterIndex(name)]; }

void vpKinematicChain::setParameter(const std::string &name, double value)
{
  if (!std::isfinite(value))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpKinematicChain::setParameter: non-finite value for '" + name + "'");
  m_params[getParameterIndex(name)] = value;
}

void vpKinematicChain::resetParameters() { m_params = 0; }

vpKinematicChain vpKinematicChain::nominal() const
{
  vpKinematicChain c(*this);
  c.resetParameters();
  return c;
}

vpHomogeneousMatrix vpKinematicChain::correction(const double *v) { return toVisp(rigidFromVector(v)); }

void vpKinematicChain::checkJoints(const vpColVector &q, const char *where) const
{
  if (m_joints.empty())
    throw vpSelfCalibException(vpSelfCalibException::notInitialized,
                               std::string("vpKinematicChain::") + where + ": the chain has no joints");
  if (q.size() != getNumJoints())
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               std::string("vpKinematicChain::") + where + ": expected " +
                                   std::to_string(getNumJoints()) + " joint values, got " +
                                   std::to_string(q.size()));
  if (!allFinite(q))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               std::string("vpKinematicChain::") + where + ": non-finite joint value");
}

/*
  One pass along fMc(q) = fMb D_base prod_i [P_i D_i Rz(q_i)] L nMe eMc D_eMc, keeping for each
  correction block the rotation of what precedes it and the origin of the frame it moves.
*/
void vpKinematicChain::forward(const vpColVector &q, Frames &out, bool keep) const
{
  const unsigned int n = getNumJoints();
  const double *p = m_params.data;
  if (keep) {
    out.R_prefix.resize(n + 2);
    out.origin.resize(n + 2);
    out.joint_axis.resize(n);
    out.joint_origin.resize(n);
  }
  Rigid T = rigidFromPose(m_fMb);
  auto apply = [&](unsigned int block) {
    if (keep)
      out.R_prefix[block] = T.R;
    T = T * rigidFromVector(p + kBlockSize * block);
    if (keep)
      out.origin[block] = T.t;
  };
  apply(0);
  for (unsigned int i = 0; i < n; ++i) {
    T = T * rigidFromVisp(m_P[i]);
    apply(i + 1);
    if (keep) {
      out.joint_axis[i] = T.R.col(2);
      out.joint_origin[i] = T.t;
    }
    T = T * rotZ(q[i]);
  }
  T = T * rigidFromVisp(m_L) * rigidFromPose(m_nMe);
  out.fMe = T;
  T = T * rigidFromPose(m_eMc);
  apply(n + 1);
  out.fMc = T;
}

vpHomogeneousMatrix vpKinematicChain::get_fMe(const vpColVector &q) const
{
  checkJoints(q, "get_fMe");
  Frames f;
  forward(q, f, false);
  return toVisp(f.fMe);
}

vpHomogeneousMatrix vpKinematicChain::get_fMc(const vpColVector &q) const
{
  checkJoints(q, "get_fMc");
  Frames f;
  forward(q, f, false);
  return toVisp(f.fMc);
}

std::vector<vpHomogeneousMatrix> vpKinematicChain::getPlacements() const
{
  const unsigned int n = getNumJoints();
  if (n == 0)
    throw vpSelfCalibException(vpSelfCalibException::notInitialized, "vpKinematicChain::getPlacements: no joints");
  const double *p = m_params.data;
  std::vector<vpHomogeneousMatrix> M;
  Rigid T = rigidFromPose(m_fMb) * rigidFromVector(p);
  for (unsigned int i = 0; i < n; ++i) {
    T = T * rigidFromVisp(m_P[i]) * rigidFromVector(p + kBlockSize * (i + 1));
    M.push_back(toVisp(T));
    T = Rigid();
  }
  M.push_back(toVisp(rigidFromVisp(m_L) * rigidFromPose(m_nMe)));
  return M;
}

vpHomogeneousMatrix vpKinematicChain::get_eMc_corrected() const
{
  return toVisp(rigidFromPose(m_eMc) * rigidFromVector(m_params.data + kBlockSize * (getNumJoints() + 1)));
}

/*
  For a block D(t, r) between prefix A and suffix B (fMc = A D B), with F = A D:
    d p_c / dt = R_A                         d phi / dt = 0
    d p_c / dr = -[p_c - p_F]x R_A J_l(r)    d phi / dr = R_A J_l(r)
  where J_l is the left Jacobian of SO(3) (exp([r + dr]x) = exp([J_l dr]x) exp([r]x)).
*/
vpMatrix vpKinematicChain::getJacobian(const vpColVector &q) const
{
  checkJoints(q, "getJacobian");
  Frames f;
  forward(q, f, true);
  const unsigned int nblocks = getNumJoints() + 2;
  vpMatrix J(6, getNumParameters());
  const Eigen::Vector3d pc = f.fMc.t;
  for (unsigned int b = 0; b < nblocks; ++b) {
    const double *v = m_params.data + kBlockSize * b;
    const Eigen::Matrix3d &RA = f.R_prefix[b];
    const Eigen::Matrix3d Jr = RA * leftJacobianSO3(Eigen::Vector3d(v[3], v[4], v[5]));
    const Eigen::Matrix3d Jp = -skew(pc - f.origin[b]) * Jr;
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j) {
        J[i][kBlockSize * b + j] = RA(i, j);
        J[i][kBlockSize * b + 3 + j] = Jp(i, j);
        J[3 + i][kBlockSize * b + 3 + j] = Jr(i, j);
      }
  }
  return J;
}

vpMatrix vpKinematicChain::getJointJacobian(const vpColVector &q) const
{
  checkJoints(q, "getJointJacobian");
  Frames f;
  forward(q, f, true);
  vpMatrix J(6, getNumJoints());
  for (unsigned int i = 0; i < getNumJoints(); ++i) {
    const Eigen::Vector3d v = f.joint_axis[i].cross(f.fMc.t - f.joint_origin[i]);
    for (unsigned int k = 0; k < 3; ++k) {
      J[k][i] = v(k);
      J[3 + k][i] = f.joint_axis[i](k);
    }
  }
  return J;
}
