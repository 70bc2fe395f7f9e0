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
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace bench
{
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
