// Uses the installed headers and library: the PUMA 560 preset at qr, where the wrist is at
// (a3, -d3, a2 + d4) = (0.0203, -0.15005, 0.8636) m.
#include <cmath>
#include <iostream>

#include <visp3/selfcalib/vpKinematicChain.h>

int main()
{
  const vpKinematicChain puma = vpKinematicChain::preset("puma560");
  const vpHomogeneousMatrix fMe = puma.get_fMe(vpColVector({0, M_PI / 2, -M_PI / 2, 0, 0, 0}));
  const bool ok = std::fabs(fMe[0][3] - 0.0203) < 1e-12 && std::fabs(fMe[1][3] + 0.15005) < 1e-12 &&
                  std::fabs(fMe[2][3] - 0.8636) < 1e-12;
  std::cout << (ok ? "consumer: ok" : "consumer: wrong forward kinematics") << std::endl;
  return ok ? 0 : 1;
}
