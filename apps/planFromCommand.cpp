/*
 * visp-selfcalib plan --from DATASET: the poses to add to a dataset's views so that the parameters
 * they leave at nominal are determined (vpMeasurementPlanner::planAdditions on the dataset's
 * calibration).
 */
#include "commands.h"

#include <iomanip>
#include <iostream>
#include <sstream>

#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpKinematicIdentification.h>
#include <visp3/selfcalib/vpMeasurementPlanner.h>
#include <visp3/selfcalib/vpRobotSelfCalibration.h>
#include <visp3/selfcalib/vpSelfCalibFileWriter.h>
#include <visp3/selfcalib/vpSelfCalibImageCorrespondences.h>

#include "selfcalibCli.h"

namespace
{
//! The dataset's views all carry joint readings and the camera is on the effector; else why not (empty: fine).
std::string refusal(const std::string &dataset, const vpSelfCalibDataset &ds, unsigned int joints)
{
  if (ds.camera_mount == vpSelfCalibDataset::CAMERA_IN_WORLD)
    return dataset + ": the camera is fixed in the world (camera_mount: world); plan --from proposes poses for a camera "
                     "on the end-effector, whose kinematic parameters the views leave at nominal";
  for (size_t k = 0; k < ds.views.size(); ++k)
    if (ds.views[k].q.size() != joints)
      return dataset + ": view " + std::to_string(k) + (ds.views[k].q.size() == 0 ? " has no joint readings (controller pose fMe only)" : " has " + std::to_string(ds.views[k].q.size()) + " joint values, the model " + std::to_string(joints)) +
             ": plan --from plans in joint space from the joints of every view; record the joints (acquire, or the "
             "dataset's joints: key)";
  return "";
}

//! The calibration plan --from starts from: the bundle method on every view, the dataset's camera.
vpRobotSelfCalibration::Options calibrationOf(const PlanArgs &a, const vpSelfCalibDataset &ds)
{
  vpRobotSelfCalibration::Options po;
  po.method = vpRobotSelfCalibration::BUNDLE_ADJUSTMENT;
  po.num_calibration_poses = static_cast<unsigned int>(ds.views.size());
  const std::vector<double> &t = a.tolerance;
  if (t.size() == 1 || t.size() == 3 || t.size() > 4)
    throw CLI::ValidationError("--tolerance", "give 2 values (joint placements) or 4 (and eMc), not " +
                                                  std::to_string(t.size()));
  if (t.size() >= 2) {
    po.tolerance_translation = t[0];
    po.tolerance_rotation = t[1];
  }
  if (t.size() == 4) {
    po.tolerance_hand_eye_translation = t[2];
    po.tolerance_hand_eye_rotation = t[3];
  }
  return po;
}

//! One pose's comment: what it adds (the parameters it determines, the sd / tolerance of those left).
std::string whatItAdds(const vpMeasurementPlanner::AdditionResult &r, size_t k)
{
  const vpMeasurementPlanner::Addition &a = r.additions[k];
  std::ostringstream os;
  os << std::setprecision(2) << "pose " << k + 1 << ": " << a.visible << " scene points in view; ";
  if (a.determined.empty())
    os << "determines none alone";
  else {
    os << "determines";
    for (const std::string &n : a.determined)
      os << " " << n;
  }
  os << "; sd / tolerance:";
  for (size_t l = 0; l < r.left.size(); ++l) {
    const double before = k == 0 ? r.ratio_before[l] : r.additions[k - 1].ratio[l];
    if (a.ratio[l] < before)
      os << " " << r.left[l] << " " << (before >= 1e6 ? std::string("undetermined") : [&] {
        std::ostringstream b;
        b << std::setprecision(2) << before;
        return b.str();
      }()) << "->" << a.ratio[l];
  }
  return os.str();
}

std::string jointsFile(const std::string &dataset, const vpMeasurementPlanner::AdditionResult &r)
{
  std::ostringstream os;
  os << "# poses to add to " << dataset << " (visp-selfcalib plan --from): " << r.additions.size()
     << " joint vectors, rad; not determined by its views (left at nominal or held by the kinematic prior):";
  for (const std::string &n : r.left)
    os << " " << n;
  os << "\n";
  for (size_t k = 0; k < r.additions.size(); ++k) {
    os << "# " << whatItAdds(r, k) << "\n" << std::setprecision(17);
    const vpColVector &q = r.additions[k].q;
    for (unsigned int i = 0; i < q.size(); ++i)
      os << q[i] << (i + 1 < q.size() ? " " : "\n");
  }
  return os.str();
}
} // namespace

int planFrom(const PlanArgs &a)
{
  if (a.out_given)
    throw CLI::ValidationError("OUT.txt", "with --from the joints file is --out FILE (default: stdout), not OUT.txt");
  if (a.poses > 100)
    throw CLI::ValidationError("--poses", "with --from, at most 100 poses to add, got " + std::to_string(a.poses));
  if (!a.out_file.empty() && outputRefused(a.out_file, a.force))
    return 1;
  vpSelfCalibDataset ds = vpSelfCalibDataset::loadYaml(a.from);
  // Never over an input: the dataset, its robot model or one of its images.
  if (!a.out_file.empty() && !canonical(a.out_file).empty()) {
    std::vector<std::string> inputs = {a.from, ds.robot};
    for (const vpSelfCalibDataset::View &v : ds.views)
      inputs.push_back(v.image);
    for (const std::string &in : inputs)
      if (!in.empty() && canonical(in) == canonical(a.out_file)) {
        std::cerr << "error: '" << a.out_file << "' is an input of this plan ("
                  << (in == a.from ? "the dataset" : in == ds.robot ? "its robot model" : "one of its images")
                  << "); choose another --out\n";
        return 1;
      }
  }
  const vpKinematicChain nominal = vpKinematicChain::fromPresetOrFile(ds.robot);
  const vpRobotSelfCalibration::Options po = calibrationOf(a, ds);
  const std::string refused = refusal(a.from, ds, nominal.getNumJoints());
  if (!refused.empty()) {
    std::cerr << "error: " << refused << "\n";
    return 1;
  }
  if (vpSelfCalibImageCorrespondences::needsFrontEnd(ds)) {
    std::cerr << "... image front end (" << ds.views.size() << " images)\n";
    vpSelfCalibImageCorrespondences::Options co;
    co.prior = nominal;
    vpSelfCalibImageCorrespondences::fromDatasetImages(ds, co);
  }
  std::cerr << "... calibration of the " << ds.views.size() << " views (method bundle)\n";
  const vpRobotSelfCalibration::Result cal = vpRobotSelfCalibration::run(nominal, ds, po);
  if (cal.status != vpRobotSelfCalibration::OK && cal.status != vpRobotSelfCalibration::DOUBTFUL) {
    std::cerr << "error: the calibration of " << a.from << " failed (" << vpRobotSelfCalibration::statusName(cal.status)
              << "): " << cal.message << "\n";
    return 3;
  }
  // The parameters the data alone do not determine: left at nominal (results.yaml's estimated_set.left_by_data),
  // or, with the kinematic prior, held by it (estimated_set.held_by_prior).
  vpMeasurementPlanner::AdditionOptions o;
  for (const auto &u : cal.identifiability.unidentifiable)
    if (u.cause == vpKinematicIdentification::CAUSE_DATA)
      o.left.push_back(u.name);
  for (const auto &u : cal.identifiability.held_by_prior)
    o.left.push_back(u.name);
  if (o.left.empty()) {
    std::cout << "nothing to add: the views of " << a.from
              << " determine every parameter of the estimated set (none left at nominal by the data, none held by the "
                 "kinematic prior alone)\n";
    return 0;
  }
  vpPlannerScene scene;
  for (const auto &p : cal.bundle.points)
    scene.points.push_back(p.second);
  scene.cam = cal.camera;
  scene.width = ds.width;
  scene.height = ds.height;
  o.poses = a.poses;
  o.seed = a.so.seed;
  std::cerr << "... poses to add\n";
  const vpMeasurementPlanner planner(nominal, scene);
  const vpMeasurementPlanner::AdditionResult r =
      planner.planAdditions(ds.views, cal.camera, cal.bundle.points, ds.yardstick,
                            vpRobotSelfCalibration::bundleOptions(po, ds), cal.noise, o);
  if (r.status == vpMeasurementPlanner::INFEASIBLE) {
    std::cerr << "error: no pose to propose: " << r.message << "\n";
    return 3;
  }
  const std::string text = jointsFile(a.from, r);
  if (a.out_file.empty())
    std::cout << text;
  else {
    vpSelfCalibFileWriter::write(a.out_file, text, "plan");
    for (size_t k = 0; k < r.additions.size(); ++k)
      std::cout << whatItAdds(r, k) << "\n";
    std::cout << "wrote " << a.out_file << ": " << r.additions.size() << (r.additions.size() == 1 ? " pose" : " poses")
              << " to add\n";
  }
  if (r.status == vpMeasurementPlanner::UNDETERMINED)
    std::cerr << "warning: with these poses the data still leave at nominal:" << [&] {
      std::string s;
      for (const std::string &n : r.still_left)
        s += " " + n;
      return s;
    }() << " (more poses: --poses, or a joint that can move further)\n";
  return 0;
}
