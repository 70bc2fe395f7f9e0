/*
 * ViSP SelfCalib: private helpers on image observations shared by the bundle adjustments (not installed).
 */
#ifndef VP_SELFCALIB_OBSERVATIONS_H
#define VP_SELFCALIB_OBSERVATIONS_H

#include <algorithm>
#include <map>
#include <vector>

#include <Eigen/Core>


namespace vpSelfCalib
{
/*!
  A point with fewer than two kept observations is not determined (free along its ray) and would
  make the normal equations singular: its remaining observation is dropped too. O has a member id.
*/
template <class O> void dropPoorlyObservedPoints(const std::vector<O> &obs, std::vector<bool> &kept)
{
  std::map<int, unsigned int> count;
  for (size_t n = 0; n < obs.size(); ++n)
    if (kept[n])
      ++count[obs[n].id];
  for (size_t n = 0; n < obs.size(); ++n)
    if (kept[n] && count[obs[n].id] < 2)
      kept[n] = false;
}
/*!
  The successive solves of a robust bundle adjustment. scales: the robust loss scale of each solve
  (in noise sd; 0 is plain least squares); trim_after: the solve after which the outliers are
  tested (-1: never). A start far from the solution (median whitened error well above the loss
  scale) first gets a solve with a wide loss (3 times the robust spread of the start errors), so that
  the narrow loss does not treat every observation as an outlier; after the narrow robust solve
  the outliers are dropped and a plain least-squares solve gives the Gauss-Newton covariance.
*/
struct RobustSchedule {
  std::vector<double> scales;
  int trim_after = -1;
};

inline RobustSchedule robustSchedule(bool robust, double loss_scale, double trim_threshold,
                                     std::vector<double> start_errors)
{
  RobustSchedule s;
  if (robust) {
    if (!start_errors.empty()) {
      const size_t h = start_errors.size() / 2;
      std::nth_element(start_errors.begin(), start_errors.begin() + h, start_errors.end());
      // The median of the norm of a 2-D standard normal is sqrt(2 ln 2) = 1.1774.
      const double wide = 3 * start_errors[h] / 1.1774;
      if (wide > 1.5 * loss_scale)
        s.scales.push_back(wide);
    }
    s.scales.push_back(loss_scale);
  } else
    s.scales.push_back(0);
  if (robust || trim_threshold > 0) {
    if (trim_threshold > 0)
      s.trim_after = static_cast<int>(s.scales.size()) - 1;
    s.scales.push_back(0);
  }
  return s;
}
/*!
  Scene points in one contiguous array in id order. Ceres orders the parameter blocks it eliminates
  by address; with points in separately allocated map nodes that order, hence the rounding of every
  sum, would depend on where the allocator put them (on other threads' allocations, for one), and
  the same data could give different last digits. Built once; no point is added afterwards (the
  addresses handed to Ceres stay valid).
*/
class PointStore
{
public:
  explicit PointStore(const std::map<int, Eigen::Vector3d> &points)
  {
    for (const auto &e : points) {
      m_index[e.first] = m_points.size();
      m_points.push_back(e.second);
    }
  }
  Eigen::Vector3d &operator[](int id) { return m_points[m_index.at(id)]; }
  size_t count(int id) const { return m_index.count(id); }
  size_t size() const { return m_points.size(); }
  //! id -> position, in id order.
  const std::map<int, size_t> &index() const { return m_index; }

private:
  std::vector<Eigen::Vector3d> m_points;
  std::map<int, size_t> m_index;
};

} // namespace vpSelfCalib

#endif
