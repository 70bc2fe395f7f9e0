/*
 * Shared pieces of the benchmark programs: mean and SD, CSV output (their command lines are CLI11's,
 * with the checks of apps/cli/selfcalibCli.h).
 * Benchmarks are programs, not tests: they print tables whose figures go into the README.
 */
#ifndef VP_SELFCALIB_BENCH_COMMON_H
#define VP_SELFCALIB_BENCH_COMMON_H

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <visp3/core/vpThetaUVector.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>

namespace bench
{
//! Whether a run has the finding `code` (any severity).
inline bool hasFinding(const vpRobotSelfCalibration::Result &r, const std::string &code)
{
  for (const auto &f : r.findings)
    if (f.code == code)
      return true;
  return false;
}

//! The run's doubts' finding codes, space-separated ("" when none).
inline std::string doubtCodes(const vpRobotSelfCalibration::Result &r)
{
  std::string s;
  for (const auto &f : r.findings)
    if (f.severity == vpSelfCalibDataCheck::DOUBT)
      s += (s.empty() ? "" : " ") + f.code;
  return s;
}

//! RMS error of a model's camera motions (m, rad).
struct MotionRms {
  double t = 0, r = 0;
};

/*
  The RMS error of `model`'s camera motions c_a M c_b against `truth`'s over `pairs` pairs of
  configurations drawn uniformly within the joint limits (a fixed draw), the joints of `within` (the
  workspace check's Result::workspace.joints_within) mapped into their range: the truth of what the
  workspace check predicts.
*/
inline MotionRms workspaceError(const vpKinematicChain &model, const vpKinematicChain &truth,
                                const std::vector<vpRobotSelfCalibration::WorkspaceError::JointRange> &within = {},
                                unsigned int pairs = 500)
{
  std::mt19937_64 rng(7);
  const auto draw = [&]() {
    vpColVector q(truth.getNumJoints());
    for (unsigned int j = 0; j < q.size(); ++j)
      q[j] = std::uniform_real_distribution<double>(truth.getJoints()[j].min, truth.getJoints()[j].max)(rng);
    for (const auto &w : within) {
      const vpKinematicChain::Joint &joint = truth.getJoints()[w.index];
      q[w.index] = w.lo + (w.hi - w.lo) * (q[w.index] - joint.min) / (joint.max - joint.min);
    }
    return q;
  };
  double t2 = 0, r2 = 0;
  for (unsigned int k = 0; k < pairs; ++k) {
    const vpColVector qa = draw(), qb = draw();
    const vpHomogeneousMatrix m = model.get_fMc(qa).inverse() * model.get_fMc(qb),
                              t = truth.get_fMc(qa).inverse() * truth.get_fMc(qb);
    t2 += (m.getTranslationVector() - t.getTranslationVector()).sumSquare();
    r2 += std::pow(vpThetaUVector(m.getRotationMatrix().t() * t.getRotationMatrix()).getTheta(), 2);
  }
  return {std::sqrt(t2 / pairs), std::sqrt(r2 / pairs)};
}

//! Running mean and sample standard deviation.
struct Stats {
  std::vector<double> v;
  void add(double x) { v.push_back(x); }
  size_t count() const { return v.size(); }
  double mean() const
  {
    if (v.empty())
      return NAN;
    double s = 0;
    for (double x : v)
      s += x;
    return s / v.size();
  }
  double sd() const
  {
    if (v.size() < 2)
      return NAN;
    const double m = mean();
    double s = 0;
    for (double x : v)
      s += (x - m) * (x - m);
    return std::sqrt(s / (v.size() - 1));
  }
};

//! "mean / sd" of s times unit, fixed precision; "–" when empty, the mean alone for one value.
inline std::string meanSd(const Stats &s, double unit, int precision)
{
  if (!s.count())
    return "–";
  std::ostringstream os;
  os.setf(std::ios::fixed);
  os.precision(precision);
  os << unit * s.mean();
  if (s.count() > 1)
    os << " / " << unit * s.sd();
  return os.str();
}

//! CSV file opened only when a path is given; rows are written as they come.
class Csv
{
public:
  Csv(const std::string &path, const std::string &header)
  {
    if (path.empty())
      return;
    m_out.open(path);
    if (!m_out)
      throw std::runtime_error("cannot write " + path);
    m_out << header << "\n";
  }
  bool enabled() const { return m_out.is_open(); }
  std::ostream &row() { return m_out; }

private:
  std::ofstream m_out;
};
} // namespace bench

#endif
