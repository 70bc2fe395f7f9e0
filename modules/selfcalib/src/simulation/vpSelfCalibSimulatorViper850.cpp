/*
 * ViSP SelfCalib: headless, instantly moved Viper850 simulator.
 */
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibSimulatorViper850.h>

#include <cmath>
#include <optional>

#include "../core/vpSelfCalibSilentCout.h"

namespace
{
//! This thread's silence while a simulator is constructed (SilentCout serialises the threads).
thread_local std::optional<vpSelfCalib::SilentCout> g_quiet;

/*
  vpSimulatorViper850's constructor prints its default camera ("Get default camera parameters for
  camera ...") on std::cout, a text no caller asked for. std::cout is silent from this call
  (evaluated before the base class is constructed) to restoreCout(), in the constructor's body or
  when the base's constructor throws. Returns `display`.
*/
bool quietCout(bool display)
{
  g_quiet.emplace();
  return display;
}

void restoreCout() { g_quiet.reset(); }
} // namespace

vpSelfCalibSimulatorViper850::vpSelfCalibSimulatorViper850()
try : vpSimulatorViper850(quietCout(false)) {
  restoreCout();
  // In constant-sampling mode the simulator thread integrates joint velocities only after a
  // setVelocity() call; without one it never writes the joint coordinates we set.
  setConstantSamplingTimeMode(true);
} catch (...) {
  if (g_quiet)
    restoreCout();
  throw;
}

void vpSelfCalibSimulatorViper850::setPosition(const vpRobot::vpControlFrameType frame, const vpColVector &q)
{
  if (frame != vpRobot::ARTICULAR_FRAME)
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               "vpSelfCalibSimulatorViper850::setPosition: only ARTICULAR_FRAME is supported");
  if (q.size() != 6)
    throw vpSelfCalibException(vpSelfCalibException::dimensionError,
                               "vpSelfCalibSimulatorViper850::setPosition: expected 6 joint values, got " +
                                   std::to_string(q.size()));
  const vpColVector qmin = getJointMin(), qmax = getJointMax();
  for (unsigned int i = 0; i < 6; ++i)
    if (!std::isfinite(q[i]) || q[i] < qmin[i] || q[i] > qmax[i])
      throw vpSelfCalibException(vpSelfCalibException::badValue,
                                 "vpSelfCalibSimulatorViper850::setPosition: joint " + std::to_string(i + 1) +
                                     " value " + std::to_string(q[i]) + " is outside [" + std::to_string(qmin[i]) +
                                     ", " + std::to_string(qmax[i]) + "]");
  set_artCoord(q);
  compute_fMi();
}

vpKinematicChain vpSelfCalibSimulatorViper850::getNominalChain() const
{
  vpKinematicChain chain = vpKinematicChain::preset("viper850");
  chain.setJointLimits(getJointMin(), getJointMax());
  vpHomogeneousMatrix eMc_;
  get_eMc(eMc_);
  chain.set_eMc(vpPoseVector(eMc_));
  return chain;
}
