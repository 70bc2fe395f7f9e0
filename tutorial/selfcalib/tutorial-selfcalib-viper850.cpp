/*!
  \example tutorial-selfcalib-viper850.cpp

  Main job of ViSP SelfCalib, first version: builds the reference scenario on ViSP's simulated
  Viper850 and prints what self-calibration starts from: the robot, the true (seeded) errors of
  the simulated arm, the planned poses and what the camera sees at each, and how far the nominal
  model is from the true camera pose at each configuration.

    tutorial-selfcalib-viper850 [--robot viper850|puma560] [--seed N] [--poses N] [--noise PX] [-c] [-d] [-h]

  -c and -d are ViSP's tutorial flags (no click, no display); this program never opens a display.
*/
#include <chrono>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <memory>
#include <string>

#include <visp3/core/vpMath.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>
#include <visp3/selfcalib/vpSelfCalibSimulatorViper850.h>

namespace
{
void usage(const char *argv0)
{
  std::cout << "Usage: " << argv0 << " [options]\n"
            << "  --robot NAME   viper850 (through ViSP's simulator, default) or puma560\n"
            << "  --seed N       seed of the scenario (default 1)\n"
            << "  --poses N      number of configurations (default 25: 15 calibration + 10 verification)\n"
            << "  --noise PX     image noise sd in pixels (default 0.2, level I)\n"
            << "  -c, -d         accepted for ViSP's tutorial convention; nothing is displayed\n"
            << "  -h, --help     this help\n";
}

double number(int &i, int argc, char **argv)
{
  if (i + 1 >= argc)
    throw vpSelfCalibException(vpSelfCalibException::badValue, std::string(argv[i]) + " needs a value");
  char *end = nullptr;
  const double v = std::strtod(argv[++i], &end);
  if (!end || *end != '\0')
    throw vpSelfCalibException(vpSelfCalibException::badValue,
                               std::string(argv[i - 1]) + ": '" + argv[i] + "' is not a number");
  return v;
}
} // namespace

int main(int argc, char **argv)
{
  try {
    std::string robot_name = "viper850";
    vpSelfCalibSimulator::Options opt;
    unsigned int poses = 25;
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      if (a == "--robot" && i + 1 < argc)
        robot_name = argv[++i];
      else if (a == "--seed")
        opt.seed = static_cast<uint64_t>(number(i, argc, argv));
      else if (a == "--poses")
        poses = static_cast<unsigned int>(number(i, argc, argv));
      else if (a == "--noise")
        opt.pixel_noise_sd = number(i, argc, argv);
      else if (a == "-c" || a == "-d")
        continue;
      else if (a == "-h" || a == "--help") {
        usage(argv[0]);
        return EXIT_SUCCESS;
      } else {
        std::cerr << "Unknown option '" << a << "'\n";
        usage(argv[0]);
        return EXIT_FAILURE;
      }
    }
    if (poses < 2) {
      std::cerr << "--poses must be at least 2\n";
      return EXIT_FAILURE;
    }

    // The robot interface. For the Viper850 it is ViSP's simulator, headless and moved instantly;
    // its nominal model takes the simulator's joint limits and camera mounting.
    std::unique_ptr<vpSelfCalibSimulatorViper850> viper;
    vpKinematicChain nominal;
    if (robot_name == "viper850") {
      viper.reset(new vpSelfCalibSimulatorViper850());
      nominal = viper->getNominalChain();
    } else {
      nominal = vpKinematicChain::preset(robot_name);
    }
    const vpSelfCalibSimulator sim(nominal, opt);
    const vpKinematicChain &truth = sim.getTrueChain();

    std::cout << std::fixed;
    std::cout << "== Robot: " << nominal.getName() << " (" << nominal.getNumJoints() << " revolute joints, "
              << (nominal.getConvention() == vpKinematicChain::DH ? "standard DH" : "modified DH") << ")\n";
    std::cout << "   joint     a [m]     d [m]  alpha [deg]  offset [deg]   limits [deg]\n";
    for (unsigned int i = 0; i < nominal.getNumJoints(); ++i) {
      const vpKinematicChain::Joint &j = nominal.getJoints()[i];
      std::cout << "   " << std::setw(5) << i + 1 << std::setprecision(4) << std::setw(10) << j.a << std::setw(10)
                << j.d << std::setprecision(1) << std::setw(13) << vpMath::deg(j.alpha) << std::setw(14)
                << vpMath::deg(j.theta_offset) << "   [" << vpMath::deg(j.min) << ", " << vpMath::deg(j.max)
                << "]\n";
    }
    const vpSelfCalibDataset::Yardstick ys = sim.getYardstick();
    const vpColVector c = sim.getSceneCentre();
    std::cout << std::setprecision(3);
    std::cout << "== Camera: " << opt.width << "x" << opt.height << ", px = " << opt.px << ", py = " << opt.py
              << ", (u0, v0) = (" << opt.u0 << ", " << opt.v0 << "), noise sd " << opt.pixel_noise_sd << " px\n";
    std::cout << "== Scene: " << opt.num_points << " points in a " << opt.box_x << " x " << opt.box_y << " x "
              << opt.box_z << " m box centred at (" << c[0] << ", " << c[1] << ", " << c[2]
              << ") m; yardstick " << ys.length << " m between ids " << ys.id_a << " and " << ys.id_b << "\n";

    std::cout << "== True robot (seed " << opt.seed << "): 6-D errors [mm, mrad]\n";
    const std::vector<std::string> names = truth.getParameterNames();
    const vpColVector p = truth.getParameters();
    for (unsigned int b = 0; b < names.size() / 6; ++b) {
      const std::string block = names[6 * b].substr(0, names[6 * b].find('.'));
      std::cout << "   " << std::setw(5) << block << "  t = (" << std::setprecision(3);
      for (unsigned int k = 0; k < 3; ++k)
        std::cout << std::setw(7) << 1e3 * p[6 * b + k] << (k < 2 ? ", " : ")");
      std::cout << "  r = (";
      for (unsigned int k = 3; k < 6; ++k)
        std::cout << std::setw(7) << 1e3 * p[6 * b + k] << (k < 5 ? ", " : ")\n");
    }

    const auto t0 = std::chrono::steady_clock::now();
    const std::vector<vpColVector> q = sim.generateConfigurations(poses);
    const double t_plan = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const vpSelfCalibDataset ds = viper ? sim.acquire(*viper, q) : sim.makeDataset(q);
    std::cout << "== Poses: " << q.size() << " configurations generated in " << std::setprecision(2) << t_plan
              << " s" << (viper ? ", acquired through vpSimulatorViper850 (vpRobot interface)" : "") << "\n";

    std::cout << "   pose  points seen   nominal model error: absolute       relative to pose 1\n"
              << "                              position [mm] angle [mrad]  position [mm] angle [mrad]\n";
    const vpHomogeneousMatrix T0 = truth.get_fMc(ds.views[0].q), N0 = nominal.get_fMc(ds.views[0].q);
    double worst_rel = 0;
    size_t min_seen = ds.views[0].points.size();
    for (size_t k = 0; k < ds.views.size(); ++k) {
      const vpHomogeneousMatrix T = truth.get_fMc(ds.views[k].q), N = nominal.get_fMc(ds.views[k].q);
      const vpHomogeneousMatrix dA = T.inverse() * N;
      const vpHomogeneousMatrix dR = (T0.inverse() * T).inverse() * (N0.inverse() * N);
      const double rel_mm = 1e3 * dR.getTranslationVector().frobeniusNorm();
      worst_rel = std::max(worst_rel, rel_mm);
      min_seen = std::min(min_seen, ds.views[k].points.size());
      std::cout << "   " << std::setw(4) << k + 1 << std::setw(9) << ds.views[k].points.size() << "/"
                << sim.getScenePoints().size() << std::setprecision(3) << std::setw(18)
                << 1e3 * dA.getTranslationVector().frobeniusNorm() << std::setw(13)
                << 1e3 * dA.getThetaUVector().getTheta() << std::setw(15) << rel_mm << std::setw(13)
                << 1e3 * dR.getThetaUVector().getTheta() << "\n";
    }
    std::cout << "== Summary: every pose sees " << min_seen << " of " << sim.getScenePoints().size()
              << " scene points; the nominal model is off by up to " << std::setprecision(2) << worst_rel
              << " mm in relative camera position. Self-calibration (next steps) is to remove that error.\n";
    return EXIT_SUCCESS;
  } catch (const vpException &e) {
    std::cerr << "error: " << e.getStringMessage() << std::endl;
    return EXIT_FAILURE;
  }
}
