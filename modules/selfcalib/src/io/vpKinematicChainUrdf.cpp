/*
 * ViSP SelfCalib: URDF import (urdfdom). See the header for what is read and how.
 */
#include <visp3/selfcalib/vpKinematicChainUrdf.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>

#include <Eigen/Dense>
#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include "vpSelfCalibYaml.h" // kMaxJoints, readTextFile

namespace
{
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

// A rigid transform aMb: x_a = R x_b + t.
struct Frame {
  Mat3 R = Mat3::Identity();
  Vec3 t = Vec3::Zero();
  Frame operator*(const Frame &o) const { return Frame{R * o.R, R * o.t + t}; }
  Frame inverse() const { return Frame{R.transpose(), -(R.transpose() * t)}; }
  Vec3 x() const { return R.col(0); }
  Vec3 z() const { return R.col(2); }
};

Frame fromUrdfPose(const urdf::Pose &p)
{
  const Eigen::Quaterniond q(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z);
  Frame f;
  f.R = q.normalized().toRotationMatrix();
  f.t = Vec3(p.position.x, p.position.y, p.position.z);
  return f;
}

Frame rotZ(double q)
{
  Frame f;
  f.R = Eigen::AngleAxisd(q, Vec3::UnitZ()).toRotationMatrix();
  return f;
}

// A rotation that takes z to the unit axis a; exact (entries 0, +-1) for the six signed unit axes.
Mat3 zToAxis(const Vec3 &a)
{
  Mat3 R;
  if (a == Vec3::UnitZ())
    return Mat3::Identity();
  if (a == -Vec3::UnitZ())
    R << 1, 0, 0, 0, -1, 0, 0, 0, -1; // Rx(pi)
  else if (a == Vec3::UnitX())
    R << 0, 0, 1, 0, 1, 0, -1, 0, 0; // Ry(pi/2)
  else if (a == -Vec3::UnitX())
    R << 0, 0, -1, 0, 1, 0, 1, 0, 0; // Ry(-pi/2)
  else if (a == Vec3::UnitY())
    R << 1, 0, 0, 0, 0, 1, 0, -1, 0; // Rx(-pi/2)
  else if (a == -Vec3::UnitY())
    R << 1, 0, 0, 0, 0, -1, 0, 1, 0; // Rx(pi/2)
  else
    R = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), a).toRotationMatrix();
  return R;
}

// console_bridge is urdfdom's logger: its messages are collected (library code never prints) and
// become the exception's text.
class CollectingHandler : public console_bridge::OutputHandler
{
public:
  std::string text;
  void log(const std::string &message, console_bridge::LogLevel level, const char *, int) override
  {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_WARN)
      text += (text.empty() ? "" : "; ") + message;
  }
};

[[noreturn]] void fail(const std::string &source, const std::string &what,
                       vpSelfCalibException::errorCodeEnum code = vpSelfCalibException::badValue)
{
  throw vpSelfCalibException(code, "URDF " + source + ": " + what);
}

const char *jointTypeName(int type)
{
  switch (type) {
  case urdf::Joint::REVOLUTE:
    return "revolute";
  case urdf::Joint::CONTINUOUS:
    return "continuous";
  case urdf::Joint::PRISMATIC:
    return "prismatic";
  case urdf::Joint::FLOATING:
    return "floating";
  case urdf::Joint::PLANAR:
    return "planar";
  case urdf::Joint::FIXED:
    return "fixed";
  default:
    return "unknown";
  }
}

// One revolute joint of the chain at q = 0: its frame J in f (z on the axis, positive rotation
// about z), and what the URDF says from the parent link to the child link.
struct ChainJoint {
  Frame J;
  Frame origin; // parent link to joint origin
  Mat3 Ra;      // joint origin frame to J (z to the axis)
  double min = -M_PI, max = M_PI;
};

bool isParallel(const Vec3 &a, const Vec3 &b) { return a.cross(b).norm() < 1e-12; }

// The sign (+1 or -1) that makes dir closest to the hint.
double signFrom(const Vec3 &dir, const Vec3 &hint) { return dir.dot(hint) < 0 ? -1.0 : 1.0; }

// The frame whose z is `z`, origin `o`, x along `x` (orthogonalised to z).
Frame frameFrom(const Vec3 &o, const Vec3 &z, const Vec3 &x_hint)
{
  Vec3 x = x_hint - x_hint.dot(z) * z;
  if (x.norm() < 1e-9) // the hint is along z: any perpendicular
    x = z.unitOrthogonal();
  x.normalize();
  Frame f;
  f.R.col(0) = x;
  f.R.col(1) = z.cross(x);
  f.R.col(2) = z;
  f.t = o;
  return f;
}

// A line: a point and a unit direction.
struct Line {
  Vec3 o, z;
};

/*
  The common normal of lines A and B: its feet on A and on B. Skew or intersecting lines have one;
  parallel lines take the normal through `through_a` (a point of A); coaxial lines return
  coaxial = true.
*/
struct Normal {
  Vec3 foot_a, foot_b;
  bool coaxial = false;
};
Normal commonNormal(const Line &A, const Line &B, const Vec3 &through_a)
{
  Normal n;
  if (isParallel(A.z, B.z)) {
    n.foot_a = A.o + (through_a - A.o).dot(A.z) * A.z;
    n.foot_b = B.o + (n.foot_a - B.o).dot(B.z) * B.z;
    n.coaxial = (n.foot_b - n.foot_a).norm() < 1e-12;
    return n;
  }
  // Closest points A.o + s A.z and B.o + t B.z, through c = zA x zB (accurate for nearly parallel
  // axes, where 1 - (zA.zB)^2 cancels).
  const Vec3 c = A.z.cross(B.z), w = B.o - A.o;
  const double c2 = c.squaredNorm();
  const double s = w.cross(B.z).dot(c) / c2, t = w.cross(A.z).dot(c) / c2;
  n.foot_a = A.o + s * A.z;
  n.foot_b = B.o + t * B.z;
  return n;
}

// x of a frame on line A or B along the normal (from A to B), or along zA x zB when they intersect,
// with the sign of the hint.
Vec3 normalDirection(const Normal &n, const Line &A, const Line &B, const Vec3 &hint)
{
  const Vec3 ab = n.foot_b - n.foot_a;
  if (isParallel(A.z, B.z)) // the normal through a chosen point: from foot to foot
    return signFrom(ab.normalized(), hint) * ab.normalized();
  // Skew or intersecting: along zA x zB, which is accurate where the difference of two feet far
  // from the origin (nearly parallel axes) is not; the sign is the hint's (a may be negative).
  const Vec3 c = A.z.cross(B.z).normalized();
  return signFrom(c, hint) * c;
}

struct Row {
  double theta = 0, d = 0, a = 0, alpha = 0;
};

double angleAbout(const Vec3 &from, const Vec3 &to, const Vec3 &axis)
{
  return std::atan2(axis.dot(from.cross(to)), from.dot(to));
}

// DH: N = P Rz(theta) Tz(d) Tx(a) Rx(alpha); MDH: N = P Rx(alpha) Tx(a) Rz(theta) Tz(d).
Row rowBetween(const Frame &P, const Frame &N, bool mdh)
{
  const Vec3 dt = N.t - P.t;
  Row r;
  if (mdh) {
    r.alpha = angleAbout(P.z(), N.z(), P.x());
    r.a = dt.dot(P.x());
    r.theta = angleAbout(P.x(), N.x(), N.z());
    r.d = dt.dot(N.z());
  } else {
    r.theta = angleAbout(P.x(), N.x(), P.z());
    r.d = dt.dot(P.z());
    r.a = dt.dot(N.x());
    r.alpha = angleAbout(P.z(), N.z(), N.x());
  }
  return r;
}

Frame rowTransform(const Row &r, bool mdh)
{
  Frame Rz_ = rotZ(r.theta), Tz, Tx, Rx;
  Tz.t = Vec3(0, 0, r.d);
  Tx.t = Vec3(r.a, 0, 0);
  Rx.R = Eigen::AngleAxisd(r.alpha, Vec3::UnitX()).toRotationMatrix();
  return mdh ? Rx * Tx * Rz_ * Tz : Rz_ * Tz * Tx * Rx;
}

double frameDistance(const Frame &A, const Frame &B)
{
  return std::max((A.R - B.R).cwiseAbs().maxCoeff(), (A.t - B.t).cwiseAbs().maxCoeff());
}

// The table in one convention: frames 0..n, fMb = frame 0, nMe = frame n^-1 F.
struct Table {
  bool mdh = false;
  std::vector<Frame> frames;
  std::vector<Row> rows;
  double distance = 0; // sum over the joints of the distance between the URDF's joint frame and the table's
};

Table buildTable(const std::vector<ChainJoint> &joints, const Frame &F, bool mdh)
{
  const size_t n = joints.size();
  std::vector<Line> lines(n + 1);
  for (size_t i = 0; i < n; ++i)
    lines[i] = Line{joints[i].J.t, joints[i].J.z()};
  lines[n] = Line{F.t, F.z()}; // the flange's z: what follows the last joint
  const auto hintFrame = [&](size_t k) -> const Frame & { return k < n ? joints[k].J : F; };

  Table T;
  T.mdh = mdh;
  T.frames.resize(n + 1);
  if (!mdh) {
    // Frame i (i = 1..n) on line i (0-based: lines[i]), x along the normal from line i-1; frame 0 on line 0.
    const Frame I;
    const bool base_on_axis = (I.z() - lines[0].z).norm() < 1e-12 &&
                              (lines[0].o - lines[0].o.dot(lines[0].z) * lines[0].z).norm() < 1e-12;
    T.frames[0] = base_on_axis ? I : joints[0].J;
    for (size_t i = 1; i <= n; ++i) {
      const Line &A = lines[i - 1], &B = lines[i];
      const Frame &hint = hintFrame(i);
      const Normal nm = commonNormal(A, B, T.frames[i - 1].t);
      if (nm.coaxial)
        T.frames[i] = frameFrom(B.o + (hint.t - B.o).dot(B.z) * B.z, B.z, hint.x());
      else
        T.frames[i] = frameFrom(nm.foot_b, B.z, normalDirection(nm, A, B, hint.x()));
    }
  } else {
    // Frame i (i = 1..n) on line i-1 (0-based), x along the normal to line i; frame 0 before it.
    Vec3 previous_foot = joints[0].J.t;
    for (size_t i = 1; i <= n; ++i) {
      const Line &A = lines[i - 1], &B = lines[i];
      const Frame &hint = joints[i - 1].J;
      const Normal nm = commonNormal(A, B, previous_foot);
      if (nm.coaxial)
        T.frames[i] = frameFrom(A.o + (hint.t - A.o).dot(A.z) * A.z, A.z, hint.x());
      else
        T.frames[i] = frameFrom(nm.foot_a, A.z, normalDirection(nm, A, B, hint.x()));
      previous_foot = nm.foot_b;
    }
    // The base link is frame 0 when frame 1 is one modified-DH row from it.
    const Frame I;
    T.frames[0] = frameDistance(rowTransform(rowBetween(I, T.frames[1], true), true), T.frames[1]) < 1e-12
                      ? I
                      : T.frames[1];
  }
  for (size_t i = 1; i <= n; ++i)
    T.rows.push_back(rowBetween(T.frames[i - 1], T.frames[i], mdh));
  for (size_t i = 0; i < n; ++i)
    T.distance += frameDistance(mdh ? T.frames[i + 1] : T.frames[i], joints[i].J);
  return T;
}

vpHomogeneousMatrix toVisp(const Frame &f)
{
  vpHomogeneousMatrix M;
  for (unsigned int r = 0; r < 3; ++r) {
    for (unsigned int c = 0; c < 3; ++c)
      M[r][c] = f.R(r, c);
    M[r][3] = f.t(r);
  }
  return M;
}

/*
  The values computed from a file of decimals carry rounding (1e-16 relative). They are put back on
  a grid of 1e-13 (m or rad; multiples of pi/2 for angles near one), far below any physical
  meaning, so that a URDF written from a table gives that table back bit for bit (a calibration
  then takes the same decisions on both; a change in the last bit can change which of two equally
  good parameters the identifiability analysis keeps).
*/
double onGrid(double v)
{
  if (!(std::fabs(v) < 1e6))
    return v;
  return std::round(v * 1e13) / 1e13 + 0.0; // + 0.0: no negative zero
}
double cleanLength(double v) { return onGrid(v); }
double cleanAngle(double v)
{
  const double k = std::round(v / (M_PI / 2));
  if (std::fabs(v - k * (M_PI / 2)) < 1e-12) {
    if (k == 0)
      return 0.0;
    return (k == 1 ? M_PI / 2 : k == -1 ? -M_PI / 2 : k == 2 ? M_PI : k == -2 ? -M_PI : k * (M_PI / 2));
  }
  return onGrid(v);
}
vpPoseVector cleanPose(const vpHomogeneousMatrix &M)
{
  vpPoseVector p(M);
  for (unsigned int k = 0; k < 6; ++k)
    p[k] = k < 3 ? cleanLength(p[k]) : cleanAngle(p[k]);
  return p;
}

std::string lower(std::string s)
{
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// The links from `top` down to `bottom` (joints, top first); empty optional when bottom is not below top.
bool pathDown(const urdf::ModelInterface &model, const std::string &top, const std::string &bottom,
              std::vector<urdf::JointConstSharedPtr> &joints)
{
  joints.clear();
  urdf::LinkConstSharedPtr l = model.getLink(bottom);
  while (l && l->name != top) {
    const urdf::JointConstSharedPtr j = l->parent_joint;
    if (!j)
      return false;
    joints.push_back(j);
    l = model.getLink(j->parent_link_name);
  }
  std::reverse(joints.begin(), joints.end());
  return static_cast<bool>(l);
}

// Parses the text, urdfdom's messages collected (console_bridge's handler is global: one parse at a time).
urdf::ModelInterfaceSharedPtr parseModel(const std::string &urdf_text, const std::string &source)
{
  urdf::ModelInterfaceSharedPtr model;
  static std::mutex mutex;
  const std::lock_guard<std::mutex> lock(mutex);
  CollectingHandler handler;
  console_bridge::useOutputHandler(&handler);
  try {
    model = urdf::parseURDF(urdf_text);
  } catch (const std::exception &e) {
    handler.text += (handler.text.empty() ? "" : "; ") + std::string(e.what());
    model.reset();
  }
  console_bridge::restorePreviousOutputHandler();
  if (!model) {
    if (handler.text.find("No root link") != std::string::npos)
      fail(source, "the joints form a loop (no root link; a URDF must be a tree): " + handler.text);
    fail(source, "malformed URDF: " + (handler.text.empty() ? std::string("urdfdom could not parse it") : handler.text));
  }
  return model;
}

// A link that is the child of two joints closes a loop (urdfdom keeps the last one silently).
void checkTree(const urdf::ModelInterface &model, const std::string &source)
{
  std::map<std::string, std::string> parent_of;
  for (const auto &kv : model.joints_) {
    const std::string &child = kv.second->child_link_name;
    auto it = parent_of.find(child);
    if (it != parent_of.end())
      fail(source, "the joints form a loop: link '" + child + "' is the child of joints '" + it->second + "' and '" +
                       kv.first + "' (a URDF must be a tree; closed chains are not supported)");
    parent_of[child] = kv.first;
  }
}

/*
  The camera link and the tip link (given, or found: the "camera_optical_frame" link below the tip
  or the base, the camera link's parent, the end of the unbranched chain from the base), checked;
  path: the joints from the base down to the tip.
*/
void findLinks(const urdf::ModelInterface &model, const vpKinematicChainUrdf::Options &opt, const std::string &base,
               const std::string &source, std::string &camera, std::string &tip,
               std::vector<urdf::JointConstSharedPtr> &path)
{
  camera = opt.camera_link;
  tip = opt.tip_link;
  if (!camera.empty() && !model.getLink(camera))
    fail(source, "no link named '" + camera + "' (the camera link)");
  if (camera.empty() && model.getLink("camera_optical_frame") &&
      pathDown(model, tip.empty() ? base : tip, "camera_optical_frame", path))
    camera = "camera_optical_frame";
  if (tip.empty()) {
    if (!camera.empty()) {
      const urdf::JointConstSharedPtr j = model.getLink(camera)->parent_joint;
      if (!j)
        fail(source, "the camera link '" + camera + "' is the root link: give the tip link");
      tip = j->parent_link_name;
    } else {
      // The end of the unbranched chain from the base.
      urdf::LinkConstSharedPtr l = model.getLink(base);
      while (l->child_joints.size() == 1)
        l = model.getLink(l->child_joints[0]->child_link_name);
      tip = l->name;
    }
  }
  if (!model.getLink(tip))
    fail(source, "no link named '" + tip + "' (the tip link)");
  if (!pathDown(model, base, tip, path))
    fail(source, "the tip link '" + tip + "' is not below the base link '" + base + "'");
}

/*
  The chain's revolute joints at q = 0 along path (the fixed joints folded into the next one's
  origin); F: f to the tip link, tail: the last revolute joint's child link to the tip link.
*/
std::vector<ChainJoint> chainJoints(const std::vector<urdf::JointConstSharedPtr> &path, const std::string &base,
                                    const std::string &tip, const std::string &source, Frame &F, Frame &tail)
{
  std::vector<ChainJoint> joints;
  Frame T;     // f to the current link
  Frame since; // the last revolute joint's child link (f before the first) to the current link
  for (const urdf::JointConstSharedPtr &j : path) {
    const Frame origin = fromUrdfPose(j->parent_to_joint_origin_transform);
    if (j->type == urdf::Joint::FIXED) {
      T = T * origin;
      since = since * origin;
      continue;
    }
    if (j->type != urdf::Joint::REVOLUTE && j->type != urdf::Joint::CONTINUOUS)
      fail(source, "joint '" + j->name + "' between '" + base + "' and '" + tip + "' is " + jointTypeName(j->type) +
                       ": only revolute, continuous and fixed joints are supported");
    Vec3 axis(j->axis.x, j->axis.y, j->axis.z);
    if (!(axis.norm() > 1e-12) || !axis.allFinite())
      fail(source, "joint '" + j->name + "' has a zero axis");
    axis.normalize();
    ChainJoint c;
    c.origin = since * origin;
    c.Ra = zToAxis(axis);
    c.J = T * origin;
    c.J.R = c.J.R * c.Ra;
    if (j->type == urdf::Joint::REVOLUTE) {
      if (!j->limits)
        fail(source, "revolute joint '" + j->name + "' has no limits");
      c.min = j->limits->lower;
      c.max = j->limits->upper;
      if (!(c.min <= c.max) || !std::isfinite(c.min) || !std::isfinite(c.max))
        fail(source, "joint '" + j->name + "': limits lower > upper or not finite");
    }
    joints.push_back(c);
    T = T * origin;
    since = Frame();
  }
  if (joints.empty())
    fail(source, "no revolute joint between '" + base + "' and '" + tip + "'");
  F = T;
  tail = since;
  return joints;
}

// The camera: below the tip through fixed joints only (opt.eMc when no camera link).
vpPoseVector cameraPose(const urdf::ModelInterface &model, const vpKinematicChainUrdf::Options &opt,
                        const std::string &tip, const std::string &camera, const std::string &source)
{
  vpPoseVector eMc = opt.eMc;
  if (!camera.empty()) {
    std::vector<urdf::JointConstSharedPtr> cpath;
    if (!pathDown(model, tip, camera, cpath))
      fail(source, "the camera link '" + camera + "' is not below the tip link '" + tip + "'");
    Frame eMc_f;
    for (const urdf::JointConstSharedPtr &j : cpath) {
      if (j->type != urdf::Joint::FIXED)
        fail(source, "the camera link '" + camera + "' is reached from the tip link '" + tip + "' through " +
                         jointTypeName(j->type) + " joint '" + j->name + "': only fixed joints may follow the tip");
      eMc_f = eMc_f * fromUrdfPose(j->parent_to_joint_origin_transform);
    }
    eMc = cleanPose(toVisp(eMc_f));
  }
  return eMc;
}

// The table of the convention asked (or, automatic, the one closer to the URDF's frames).
Table chosenTable(const std::vector<ChainJoint> &joints, const Frame &F, vpKinematicChainUrdf::Convention convention)
{
  Table table;
  if (convention == vpKinematicChainUrdf::DH || convention == vpKinematicChainUrdf::MDH) {
    table = buildTable(joints, F, convention == vpKinematicChainUrdf::MDH);
  } else {
    const Table dh = buildTable(joints, F, false), mdh = buildTable(joints, F, true);
    table = mdh.distance < dh.distance - 1e-9 ? mdh : dh;
  }
  return table;
}

// The table's rows, rounded, with the joints' limits; size: the table's largest length (m, at least 1).
std::vector<vpKinematicChain::Joint> tableRows(const Table &table, const std::vector<ChainJoint> &joints, double &size)
{
  const size_t n = joints.size();
  std::vector<vpKinematicChain::Joint> rows(n);
  size = 1; // m: the table's largest length, which scales the rounding of its transforms
  for (size_t i = 0; i < n; ++i) {
    rows[i].theta_offset = cleanAngle(table.rows[i].theta);
    rows[i].d = cleanLength(table.rows[i].d);
    rows[i].a = cleanLength(table.rows[i].a);
    rows[i].alpha = cleanAngle(table.rows[i].alpha);
    rows[i].min = joints[i].min;
    rows[i].max = joints[i].max;
    size = std::max({size, std::fabs(rows[i].a), std::fabs(rows[i].d)});
  }
  return rows;
}

// The table's forward kinematics against the URDF's, at q = 0 and at another joint vector.
void checkForwardKinematics(const vpKinematicChain &chain, const std::vector<ChainJoint> &joints, const Frame &tail,
                            bool mdh, double size, const std::string &source)
{
  const size_t n = joints.size();
  for (int k = 0; k < 2; ++k) {
    vpColVector q(static_cast<unsigned int>(n));
    Frame U;
    for (size_t i = 0; i < n; ++i) {
      const unsigned int ui = static_cast<unsigned int>(i);
      q[ui] = k == 0 ? 0.0 : 0.3 + 0.37 * static_cast<double>(i);
      Frame Rq;
      Rq.R = joints[i].Ra * rotZ(q[ui]).R * joints[i].Ra.transpose();
      U = U * joints[i].origin * Rq;
    }
    const vpHomogeneousMatrix fMe_urdf = toVisp(U * tail), fMe = chain.get_fMe(q);
    double err = 0;
    for (unsigned int r = 0; r < 3; ++r)
      for (unsigned int c = 0; c < 4; ++c)
        err = std::max(err, std::fabs(fMe[r][c] - fMe_urdf[r][c]));
    if (!(err < 1e-10 * size)) {
      std::ostringstream os;
      os << "the " << (mdh ? "modified-DH" : "DH") << " table built from the joint axes does not reproduce the "
         << "URDF's forward kinematics (error " << err << " for lengths up to " << size
         << " m): the axes are numerically degenerate";
      fail(source, os.str());
    }
  }
}
} // namespace

bool vpKinematicChainUrdf::isUrdfFile(const std::string &filename)
{
  const std::string l = lower(filename);
  return l.size() > 5 && l.compare(l.size() - 5, 5, ".urdf") == 0;
}

vpKinematicChain vpKinematicChainUrdf::load(const std::string &filename) { return load(filename, Options()); }

vpKinematicChain vpKinematicChainUrdf::load(const std::string &filename, const Options &options)
{
  return fromString(vpSelfCalib::readTextFile(filename, "URDF"), options, "'" + filename + "'");
}

vpKinematicChain vpKinematicChainUrdf::fromString(const std::string &urdf_text, const Options &opt,
                                                  const std::string &source)
{
  const urdf::ModelInterfaceSharedPtr model = parseModel(urdf_text, source);
  checkTree(*model, source);

  const urdf::LinkConstSharedPtr root = model->getRoot();
  const std::string base = opt.base_link.empty() ? root->name : opt.base_link;
  if (!model->getLink(base))
    fail(source, "no link named '" + base + "' (the base link)");
  std::string camera, tip;
  std::vector<urdf::JointConstSharedPtr> path;
  findLinks(*model, opt, base, source, camera, tip, path);
  const size_t moving = static_cast<size_t>(std::count_if(
      path.begin(), path.end(), [](const urdf::JointConstSharedPtr &j) { return j->type != urdf::Joint::FIXED; }));
  if (moving > vpSelfCalib::kMaxJoints)
    fail(source, "the chain from '" + base + "' to '" + tip + "' has " + std::to_string(moving) + " joints: at most " +
                     std::to_string(vpSelfCalib::kMaxJoints) + " are read (as in a robot-model YAML)");

  // The chain at q = 0, the camera below its tip, the table.
  Frame F, tail;
  const std::vector<ChainJoint> joints = chainJoints(path, base, tip, source, F, tail);
  const vpPoseVector eMc = cameraPose(*model, opt, tip, camera, source);
  const Table table = chosenTable(joints, F, opt.convention);
  const size_t n = joints.size();
  double size = 1;
  const std::vector<vpKinematicChain::Joint> rows = tableRows(table, joints, size);
  const vpKinematicChain chain(opt.name.empty() ? model->getName() : opt.name,
                               table.mdh ? vpKinematicChain::MDH : vpKinematicChain::DH, rows,
                               cleanPose(toVisp(table.frames[0])), cleanPose(toVisp(table.frames[n].inverse() * F)),
                               eMc);
  checkForwardKinematics(chain, joints, tail, table.mdh, size, source);
  return chain;
}
