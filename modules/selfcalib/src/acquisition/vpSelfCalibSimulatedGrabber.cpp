/*
 * ViSP SelfCalib: a frame grabber that renders the simulated robot's camera. See the header.
 */
#include <visp3/selfcalib/vpSelfCalibSimulatedGrabber.h>

#include <cstdint>
#include <cstring>

#include <visp3/core/vpImageConvert.h>

vpSelfCalibSimulatedGrabber::vpSelfCalibSimulatedGrabber(vpRobot &robot, const vpSelfCalibRenderer &renderer)
  : m_robot(robot), m_renderer(renderer)
{
}

unsigned int vpSelfCalibSimulatedGrabber::viewIndex(const vpColVector &q)
{
  // FNV-1a over the bytes of the joint values.
  uint64_t h = 1469598103934665603ULL;
  for (unsigned int i = 0; i < q.size(); ++i) {
    unsigned char b[sizeof(double)];
    const double v = q[i] + 0.0;
    std::memcpy(b, &v, sizeof v);
    for (unsigned char c : b) {
      h ^= c;
      h *= 1099511628211ULL;
    }
  }
  return static_cast<unsigned int>(h ^ (h >> 32));
}

void vpSelfCalibSimulatedGrabber::acquire(vpImage<unsigned char> &I)
{
  vpColVector q;
  m_robot.getPosition(vpRobot::ARTICULAR_FRAME, q);
  I = m_renderer.render(q, viewIndex(q));
  width = I.getWidth();
  height = I.getHeight();
  init = true;
}

void vpSelfCalibSimulatedGrabber::acquire(vpImage<vpRGBa> &I)
{
  vpImage<unsigned char> G;
  acquire(G);
  vpImageConvert::convert(G, I);
}

void vpSelfCalibSimulatedGrabber::open(vpImage<unsigned char> &I) { acquire(I); }
void vpSelfCalibSimulatedGrabber::open(vpImage<vpRGBa> &I) { acquire(I); }
