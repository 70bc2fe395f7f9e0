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
/*
  Franka Emika Panda, Craig's modified DH as in Franka's public documentation (the robot's
  kinematic table): a (0, 0, 0, 0.0825, -0.0825, 0, 0.088), d (0.333, 0, 0.316, 0, 0.384, 0, 0),
  alpha (0, -pi/2, pi/2, pi/2, -pi/2, pi/2, pi/2), flange Tz(0.107); its joint limits. The camera
  guess eMc = (0, 0, 0.05): a camera in front of the flange, along its axis.
*/
vpKinematicChain panda()
{
  const double l = 166.0031; // deg, joints 1, 3, 5, 7 (+-2.8973 rad)
  std::vector<vpKinematicChain::Joint> j = {
      row(0, 0.333, 0, 0, -l, l),          row(0, 0, -M_PI / 2, 0, -101, 101),
      row(0, 0.316, M_PI / 2, 0, -l, l),   row(0.0825, 0, M_PI / 2, 0, -176, -4),
      row(-0.0825, 0.384, -M_PI / 2, 0, -l, l), row(0, 0, M_PI / 2, 0, -1, 215),
      row(0.088, 0, M_PI / 2, 0, -l, l)};
  return vpKinematicChain("panda", vpKinematicChain::MDH, j, vpPoseVector(), vpPoseVector(0, 0, 0.107, 0, 0, 0),
                          vpPoseVector(0, 0, 0.05, 0, 0, 0));
}

/*
  Universal Robots UR5, standard DH from Universal Robots' published parameters: d1 0.089159,
  a2 -0.425, a3 -0.39225, d4 0.10915, d5 0.09465, d6 0.0823, alpha (pi/2, 0, 0, pi/2, -pi/2, 0);
  joints +-360 deg. Camera guess as for the PUMA.
*/
vpKinematicChain ur5()
{
  std::vector<vpKinematicChain::Joint> j = {
      row(0, 0.089159, M_PI / 2, 0, -360, 360), row(-0.425, 0, 0, 0, -360, 360),
      row(-0.39225, 0, 0, 0, -360, 360),      row(0, 0.10915, M_PI / 2, 0, -360, 360),
      row(0, 0.09465, -M_PI / 2, 0, -360, 360), row(0, 0.0823, 0, 0, -360, 360)};
  return vpKinematicChain("ur5", vpKinematicChain::DH, j, vpPoseVector(), vpPoseVector(),
                          vpPoseVector(0, 0.06, 0.08, 0, 0, 0));
}
} // namespace

vpKinematicChain vpKinematicChain::preset(const std::string &name)
{
  if (name == "puma560")
    return puma560();
  if (name == "viper850")
    return viper850();
  if (name == "panda")
    return panda();
  if (name == "ur5")
    return ur5();
  std::string known;
  for (const std::string &p : presetNames())
    known += (known.empty() ? "" : ", ") + p;
  throw vpSelfCalibException(vpSelfCalibException::badValue,
                             "unknown robot preset '" + name + "' (known presets: " + known + ")");
}
