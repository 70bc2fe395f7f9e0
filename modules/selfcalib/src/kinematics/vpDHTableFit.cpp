/*
 * ViSP SelfCalib: vpDHTableFit, a corrected DH or modified-DH table fitted to a calibrated model. See the header.
 */
#include <visp3/selfcalib/vpDHTableFit.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <cmath>
#include <iomanip>
#include <sstream>

#include <ceres/ceres.h>

#include "../core/vpSelfCalibCeres.h"
#include "../core/vpSelfCalibMath.h"
#include "../core/vpSelfCalibRandom.h"

using namespace vpSelfCalib;

namespace
{
// x = per joint (theta_offset, d, a, alpha), then the base pose vector, then the eMc pose vector.
vpKinematicChain tableFrom(const vpKinematicChain &model, vpKinematicChain::Convention conv, const double *x)
{
  std::vector<vpKinematicChain::Joint> joints = model.getJoints();
  const unsigned int n = model.getNumJoints();
  for (unsigned int i = 0; i < n; ++i) {
    joints[i].theta_offset = x[4 * i];
    joints[i].d = x[4 * i + 1];
    joints[i].a = x[4 * i + 2];
    joints[i].alpha = x[4 * i + 3];
  }
  vpPoseVector base, eMc;
  for (unsigned int k = 0; k < 6; ++k) {
    base[k] = x[4 * n + k];
    eMc[k] = x[4 * n + 6 + k];
  }
  return vpKinematicChain(model.getName(), conv, joints, base, model.get_nMe_pose(), eMc);
}

// Pose difference of the table against the model at every sample: position (m), rotation (rad).
struct TableResidual {
  const vpKinematicChain *model;
  vpKinematicChain::Convention conv;
  const std::vector<vpColVector> *q;
  const std::vector<Rigid> *target;
  bool operator()(double const *const *x, double *r) const
  {
    const vpKinematicChain t = tableFrom(*model, conv, x[0]);
    for (size_t s = 0; s < q->size(); ++s) {
      const Rigid E = (*target)[s].inverse() * rigidFromVisp(t.get_fMc((*q)[s]));
      const Eigen::Vector3d w = logSO3(E.R);
      for (int a = 0; a < 3; ++a) {
        r[6 * s + a] = E.t(a);
        r[6 * s + 3 + a] = w(a);
      }
    }
    return true;
  }
};

} // namespace

void vpDHTableFit::Options::check() const
{
  if (samples < 3 || max_iterations == 0 || !(tolerance_position > 0) || !(tolerance_rotation > 0))
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpDHTableFit: samples >= 3, max_iterations >= 1 and positive tolerances are needed");
}

vpDHTableFit::Result vpDHTableFit::fit(const vpKinematicChain &model, vpKinematicChain::Convention convention)
{
  return fit(model, convention, Options());
}

vpDHTableFit::Result vpDHTableFit::fit(const vpKinematicChain &model, vpKinematicChain::Convention convention,
                                          const Options &opt)
{
  opt.check();
  const QuietCeres quiet;
  const unsigned int n = model.getNumJoints();
  if (n == 0)
    throw vpSelfCalibException(vpSelfCalibException::notInitialized, "vpDHTableFit::fit: the model has no joints");
  Random rng(opt.seed, 31);
  std::vector<vpColVector> q(opt.samples, vpColVector(n));
  std::vector<Rigid> target;
  for (auto &qs : q) {
    for (unsigned int i = 0; i < n; ++i)
      qs[i] = rng.uniform(model.getJoints()[i].min, model.getJoints()[i].max);
    target.push_back(rigidFromVisp(model.get_fMc(qs)));
  }
  // Start: the model's own rows (its nominal table when it has the same convention), base and eMc
  // with their corrections folded in.
  // Rows in the other convention: the twist and length of link i move to row i + 1 (DH to MDH) or
  // i - 1 (MDH to DH); what falls off an end goes into the base or the hand-eye transform.
  std::vector<vpKinematicChain::Joint> rows = model.getJoints();
  Rigid base_start = rigidFromPose(model.get_fMb_pose()) * rigidFromVector(model.getParameters().data);
  Rigid eMc_start = rigidFromVisp(model.get_eMc_corrected());
  if (model.getConvention() == vpKinematicChain::DH && convention == vpKinematicChain::MDH) {
    const Rigid nMe = rigidFromPose(model.get_nMe_pose());
    eMc_start = nMe.inverse() * trans(rows[n - 1].a, 0, 0) * rotX(rows[n - 1].alpha) * nMe * eMc_start;
    for (unsigned int i = n; i-- > 0;) {
      rows[i].a = i > 0 ? rows[i - 1].a : 0;
      rows[i].alpha = i > 0 ? rows[i - 1].alpha : 0;
    }
  } else if (model.getConvention() == vpKinematicChain::MDH && convention == vpKinematicChain::DH) {
    base_start = base_start * rotX(rows[0].alpha) * trans(rows[0].a, 0, 0);
    for (unsigned int i = 0; i < n; ++i) {
      rows[i].a = i + 1 < n ? rows[i + 1].a : 0;
      rows[i].alpha = i + 1 < n ? rows[i + 1].alpha : 0;
    }
  }
  std::vector<double> x(4 * n + 12, 0.0);
  for (unsigned int i = 0; i < n; ++i) {
    x[4 * i] = rows[i].theta_offset;
    x[4 * i + 1] = rows[i].d;
    x[4 * i + 2] = rows[i].a;
    x[4 * i + 3] = rows[i].alpha;
  }
  const vpPoseVector base(toVisp(base_start)), eMc(toVisp(eMc_start));
  for (unsigned int k = 0; k < 6; ++k) {
    x[4 * n + k] = base[k];
    x[4 * n + 6 + k] = eMc[k];
  }
  auto *cost = new ceres::DynamicNumericDiffCostFunction<TableResidual, ceres::CENTRAL>(
      new TableResidual{&model, convention, &q, &target});
  cost->AddParameterBlock(static_cast<int>(x.size()));
  cost->SetNumResiduals(static_cast<int>(6 * q.size()));
  ceres::Problem problem;
  problem.AddResidualBlock(cost, nullptr, x.data());
  ceres::Solver::Options so = solverOptions(opt.max_iterations, true);
  ceres::Solver::Summary summary;
  vpSelfCalib::solve(so, &problem, &summary);

  Result fit;
  fit.table = tableFrom(model, convention, x.data());
  for (size_t s = 0; s < q.size(); ++s) {
    const vpHomogeneousMatrix A = toVisp(target[s]), B = fit.table.get_fMc(q[s]);
    fit.max_position_error = std::max(fit.max_position_error, translationDistance(A, B));
    fit.max_rotation_error = std::max(fit.max_rotation_error, rotationDistance(A, B));
  }
  fit.representable =
      fit.max_position_error <= opt.tolerance_position && fit.max_rotation_error <= opt.tolerance_rotation;
  std::ostringstream os;
  os << (convention == vpKinematicChain::DH ? "DH" : "modified DH") << " table "
     << (fit.representable ? "reproduces the model" : "does NOT reproduce the model") << ": largest difference "
     << std::setprecision(3) << fit.max_position_error << " m, " << fit.max_rotation_error << " rad over "
     << q.size() << " joint vectors";
  // Exact but absurd: near-parallel consecutive axes put the common normal far away (lengths of
  // metres that cancel), which no controller should be given.
  double nominal_length = 0.1;
  for (const auto &j : model.getJoints())
    nominal_length = std::max(nominal_length, std::max(std::fabs(j.a), std::fabs(j.d)));
  for (unsigned int i = 0; i < n; ++i) {
    const vpKinematicChain::Joint &j = fit.table.getJoints()[i];
    if (std::max(std::fabs(j.a), std::fabs(j.d)) > 10 * nominal_length) {
      fit.well_conditioned = false;
      os << "; row " << i + 1 << " has a = " << j.a << " m, d = " << j.d << " m";
    }
  }
  if (!fit.well_conditioned)
    os << ": exact but ill-conditioned (nearly parallel consecutive axes push the common normal far away; "
       << "lengths that large cancel each other and amplify rounding): prefer the robot-model YAML or the URDF";
  if (!fit.representable) {
    for (unsigned int i = 0; i + 1 < n; ++i)
      if (std::fabs(std::sin(model.getJoints()[model.getConvention() == vpKinematicChain::DH ? i : i + 1].alpha)) < 1e-6)
        os << "; joints " << i + 1 << " and " << i + 2 << " are parallel in the nominal model: a tilt between "
           << "them has no small " << (convention == vpKinematicChain::DH ? "DH" : "modified DH")
           << " equivalent (use the robot-model YAML or the URDF)";
  }
  fit.message = os.str();
  return fit;
}
