/*
 * ViSP SelfCalib: export of a calibrated model as URDF. See the header.
 */
#include <visp3/selfcalib/vpModelExport.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <cmath>
#include <iomanip>
#include <sstream>

#include "../core/vpSelfCalibMath.h"
#include "vpSelfCalibYaml.h"

using namespace vpSelfCalib;

namespace
{
std::string rpyXyz(const vpHomogeneousMatrix &M)
{
  const Rigid T = rigidFromVisp(M);
  const Eigen::Matrix3d &R = T.R;
  // URDF: R = Rz(yaw) Ry(pitch) Rx(roll).
  const double pitch = std::asin(std::max(-1.0, std::min(1.0, -R(2, 0))));
  const double roll = std::atan2(R(2, 1), R(2, 2)), yaw = std::atan2(R(1, 0), R(0, 0));
  std::ostringstream os;
  os << std::setprecision(17) << "xyz=\"" << T.t(0) << " " << T.t(1) << " " << T.t(2) << "\" rpy=\"" << roll << " "
     << pitch << " " << yaw << "\"";
  return os.str();
}
} // namespace

std::string vpModelExport::toURDF(const vpKinematicChain &model, const std::string &robot_name)
{
  return toURDF(model, robot_name, nullptr, nullptr);
}

std::string vpModelExport::toURDF(const vpKinematicChain &model, const std::string &robot_name,
                                  const vpHomogeneousMatrix *bMc, const vpHomogeneousMatrix *eMo)
{
  const std::vector<vpHomogeneousMatrix> M = model.getPlacements();
  const unsigned int n = model.getNumJoints();
  std::ostringstream os;
  os << std::setprecision(17);
  os << "<?xml version=\"1.0\"?>\n<!-- written by ViSP SelfCalib: the calibrated model's joint origins -->\n"
     << "<robot name=\"" << (robot_name.empty() ? model.getName() : robot_name) << "\">\n  <link name=\"base_link\"/>\n";
  for (unsigned int i = 1; i <= n; ++i)
    os << "  <link name=\"link" << i << "\"/>\n";
  os << "  <link name=\"flange\"/>\n  <link name=\"camera_optical_frame\"/>\n";
  if (eMo)
    os << "  <link name=\"target\"/>\n";
  for (unsigned int i = 0; i < n; ++i) {
    const vpKinematicChain::Joint &j = model.getJoints()[i];
    os << "  <joint name=\"joint" << i + 1 << "\" type=\"revolute\">\n    <parent link=\""
       << (i == 0 ? std::string("base_link") : "link" + std::to_string(i)) << "\"/>\n    <child link=\"link" << i + 1
       << "\"/>\n    <origin " << rpyXyz(M[i]) << "/>\n    <axis xyz=\"0 0 1\"/>\n    <limit lower=\"" << j.min
       << "\" upper=\"" << j.max << "\" effort=\"0\" velocity=\"0\"/>\n  </joint>\n";
  }
  os << "  <joint name=\"flange_joint\" type=\"fixed\">\n    <parent link=\"link" << n
     << "\"/>\n    <child link=\"flange\"/>\n    <origin " << rpyXyz(M[n]) << "/>\n  </joint>\n"
     << "  <joint name=\"camera_joint\" type=\"fixed\">\n    <parent link=\"" << (bMc ? "base_link" : "flange")
     << "\"/>\n    <child link=\"camera_optical_frame\"/>\n    <origin "
     << rpyXyz(bMc ? *bMc : model.get_eMc_corrected()) << "/>\n  </joint>\n";
  if (eMo)
    os << "  <joint name=\"target_joint\" type=\"fixed\">\n    <parent link=\"flange\"/>\n"
       << "    <child link=\"target\"/>\n    <origin " << rpyXyz(*eMo) << "/>\n  </joint>\n";
  os << "</robot>\n";
  return os.str();
}

void vpModelExport::saveURDF(const vpKinematicChain &model, const std::string &filename)
{
  writeFileAtomically(filename, toURDF(model), "URDF");
}

void vpModelExport::saveURDF(const vpKinematicChain &model, const std::string &filename, const vpHomogeneousMatrix *bMc,
                             const vpHomogeneousMatrix *eMo)
{
  writeFileAtomically(filename, toURDF(model, "", bMc, eMo), "URDF");
}
