/*
 * ViSP SelfCalib: robot presets.
 */
#include <visp3/selfcalib/vpKinematicChain.h>
#include <visp3/selfcalib/vpSelfCalibException.h>

#include <cmath>

#include <visp3/core/vpMath.h>
#include <visp3/robot/vpViper850.h>

namespace
{
// vpViper keeps its geometric constants protected; a subclass reads them without copying values,
// so the preset follows whatever the installed ViSP says.
class ViperConstants : public vpViper850
{
public:
  double A1() const { return a1; }
  double D1() const { return d1; }
  double A2() const { return a2; }
  double A3() const { return a3; }
  double D4() const { return d4; }
  double D6() const { return d6; }
};

vpKinematicChain::Joint row(double a, double d, double alpha, double theta, double min_deg, double max_deg)
{
  vpKinematicChain::Joint j;
  j.a = a;
  j.d = d;
  j.alpha = alpha;
  j.theta_offset = theta;
  j.min = vpMath::rad(min_deg);
  j.max = vpMath::rad(max_deg);
  return j;
}

/*
  PUMA 560, standard DH (P. Corke's Robotics Toolbox model Puma560; limits after Wang & Chen 1991).
  The wrist camera guess eMc = (0, 0.06, 0.08, 0, 0, 0) is the one of the design document.
*/
vpKinematicChain puma560()
{
  std::vector<vpKinematicChain::Joint> j = {
      row(0, 0, M_PI / 2, 0, -160, 160),        row(0.4318, 0, 0, 0, -45, 225),
      row(0.0203, 0.15005, -M_PI / 2, 0, -225, 45), row(0, 0.4318, M_PI / 2, 0, -110, 170),
      row(0, 0, -M_PI / 2, 0, -100, 100),       row(0, 0, 0, 0, -266, 266)};
  return vpKinematicChain("puma560", vpKinematicChain::DH, j, vpPoseVector(), vpPoseVector(),
                          vpPoseVector(0, 0.06, 0.08, 0, 0, 0));
}

/*
  Viper850 from vpViper850 (default tool: PTGrey Flea2 camera), standard DH as documented in
  vpViper.h: J1 (a1, d1, -pi/2, q1), J2 (a2, 0, 0, q2), J3 (a3, 0, -pi/2, q3 - pi),
  J4 (0, d4, pi/2, q4), J5 (0, 0, -pi/2, q5), J6 (0, 0, 0, q6 - pi), then Tz(d6) to the flange.
*/
vpKinematicChain viper850()
{
  ViperConstants v;
  const vpColVector qmin = v.getJointMin(), qmax = v.getJointMax();
  std::vector<vpKinematicChain::Joint> j = {
      row(v.A1(), v.D1(), -M_PI / 2, 0, 0, 0), row(v.A2(), 0, 0, 0, 0, 0),
      row(v.A3(), 0, -M_PI / 2, -M_PI, 0, 0),  row(0, v.D4(), M_PI / 2, 0, 0, 0),
      row(0, 0, -M_PI / 2, 0, 0, 0),           row(0, 0, 0, -M_PI, 0, 0)};
  for (unsigned int i = 0; i < 6; ++i) {
    j[i].min = qmin[i];
    j[i].max = qmax[i];
  }
  vpHomogeneousMatrix eMc;
  v.get_eMc(eMc);
  return vpKinematicChain("viper850", vpKinematicChain::DH, j, vpPoseVector(),
                          vpPoseVector(0, 0, v.D6(), 0, 0, 0), vpPoseVector(eMc));
}
} // namespace

vpKinematicChain vpKinematicChain::preset(const std::string &name)
{
  if (name == "puma560")
    return puma560();
  if (name == "viper850")
    return viper850();
  std::string known;
  for (const std::string &p : presetNames())
    known += (known.empty() ? "" : ", ") + p;
  throw vpSelfCalibException(vpSelfCalibException::badValue,
                             "unknown robot preset '" + name + "' (known presets: " + known + ")");
}
