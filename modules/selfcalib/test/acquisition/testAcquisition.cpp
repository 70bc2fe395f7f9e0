/*
 * Tests of vpSelfCalibAcquisition on ViSP's simulated Viper850 with the rendering grabber: order,
 * interrupted and resumed runs give the uninterrupted run's dataset, robot errors keep the dataset,
 * joint limits are checked before anything moves, teach mode.
 */
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <set>
#include <unistd.h>
#include <fstream>
#include <memory>
#include <string>

#include <visp3/selfcalib/vpSelfCalibAcquisition.h>
#include <visp3/selfcalib/vpSelfCalibException.h>
#include <visp3/selfcalib/vpSelfCalibRenderer.h>
#include <visp3/selfcalib/vpSelfCalibSimulatedGrabber.h>
#include <visp3/selfcalib/vpSelfCalibSimulator.h>
#include <visp3/selfcalib/vpSelfCalibSimulatorViper850.h>

namespace fs = std::filesystem;

namespace
{
// The simulated Viper850 made to throw at its move number `fail_at` (1-based; 0: never).
class FailingViper : public vpSelfCalibSimulatorViper850
{
public:
  unsigned int fail_at = 0, moves = 0;
  bool stuck = false; //!< ignores the moves
  using vpSelfCalibSimulatorViper850::setPosition;
  void setPosition(const vpRobot::vpControlFrameType frame, const vpColVector &q) override
  {
    if (stuck)
      return;
    if (++moves == fail_at)
      throw vpRobotException(vpRobotException::communicationError, "simulated controller fault");
    vpSelfCalibSimulatorViper850::setPosition(frame, q);
  }
};

std::string readFile(const fs::path &p)
{
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

struct Scenario {
  FailingViper robot;
  vpKinematicChain nominal;
  std::unique_ptr<vpSelfCalibSimulator> sim;
  std::unique_ptr<vpSelfCalibRenderer> renderer;
  std::unique_ptr<vpSelfCalibSimulatedGrabber> grabber;
  std::vector<vpColVector> plan;
  Scenario(unsigned int poses)
  {
    nominal = robot.getNominalChain();
    vpSelfCalibSimulator::Options so;
    so.seed = 31;
    sim.reset(new vpSelfCalibSimulator(nominal, so));
    vpSelfCalibRenderer::Options ro;
    ro.seed = 31;
    renderer.reset(new vpSelfCalibRenderer(*sim, ro));
    grabber.reset(new vpSelfCalibSimulatedGrabber(robot, *renderer));
    plan = sim->generateConfigurations(poses);
  }
  vpSelfCalibAcquisition::Options options(const fs::path &dir) const
  {
    vpSelfCalibAcquisition::Options o;
    o.dataset_file = (dir / "ds.yaml").string();
    o.header = sim->makeDataset({});
    o.header.robot = "viper850";
    o.header.yardstick.length = renderer->getYardstickLength();
    o.header.yardstick.id_a = o.header.yardstick.id_b = -1;
    o.calibration_poses = 4;
    return o;
  }
};

fs::path freshDir(const std::string &name)
{
  const fs::path d = fs::temp_directory_path() / ("selfcalib-acq-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}
} // namespace

// The short-travel order is a permutation, never longer than the plan order, and keeps the
// calibration poses first.
TEST(Acquisition, OrderKeepsTravelShortAndCalibrationPosesFirst)
{
  std::vector<vpColVector> q;
  for (int k = 0; k < 12; ++k)
    q.push_back(vpColVector({std::cos(2.4 * k), std::sin(1.7 * k), 0.1 * k, 0, 0, 0}));
  const std::vector<unsigned int> o = vpSelfCalibAcquisition::shortTravelOrder(q);
  ASSERT_EQ(o.size(), q.size());
  EXPECT_EQ(o[0], 0u);
  EXPECT_EQ(std::set<unsigned int>(o.begin(), o.end()).size(), q.size());
  std::vector<unsigned int> id(q.size());
  for (unsigned int k = 0; k < id.size(); ++k)
    id[k] = k;
  EXPECT_LT(vpSelfCalibAcquisition::travel(q, o), 0.8 * vpSelfCalibAcquisition::travel(q, id));
}

// An interrupted acquisition (the robot throws at move 4) keeps the 3 poses recorded before,
// in a readable dataset; resumed, it gives byte for byte the uninterrupted run's dataset and images.
TEST(Acquisition, InterruptedAndResumedRunEqualsAnUninterruptedOne)
{
  const fs::path a = freshDir("a"), b = freshDir("b");
  Scenario s(7);
  {
    vpSelfCalibAcquisition acq(s.robot, s.nominal, *s.grabber, s.options(a));
    unsigned int calls = 0;
    const auto r = acq.run(s.plan, [&](unsigned int, unsigned int, const std::string &) { ++calls; });
    ASSERT_EQ(r.status, vpSelfCalibAcquisition::OK) << r.message;
    EXPECT_EQ(r.total, 7u);
    EXPECT_EQ(calls, 7u);
    EXPECT_LE(r.travel, r.travel_plan_order);
    // Calibration poses (plan 0-3) first, then the held-out ones.
    for (unsigned int k = 0; k < 7; ++k)
      EXPECT_EQ(r.order[k] < 4, k < 4);
    // The joints recorded are the robot's, the images exist.
    for (unsigned int k = 0; k < 7; ++k) {
      EXPECT_LT((r.dataset.views[k].q - s.plan[r.order[k]]).frobeniusNorm(), 1e-12);
      EXPECT_TRUE(fs::exists(r.dataset.views[k].image));
    }
  }
  {
    s.robot.fail_at = 4;
    s.robot.moves = 0;
    vpSelfCalibAcquisition acq(s.robot, s.nominal, *s.grabber, s.options(b));
    const auto r = acq.run(s.plan);
    EXPECT_EQ(r.status, vpSelfCalibAcquisition::ROBOT_ERROR);
    EXPECT_NE(r.message.find("pose 4 of 7"), std::string::npos) << r.message;
    EXPECT_NE(r.message.find("simulated controller fault"), std::string::npos) << r.message;
    EXPECT_NE(r.message.find("the dataset keeps the 3 poses recorded before"), std::string::npos) << r.message;
    EXPECT_EQ(vpSelfCalibDataset::loadYaml((b / "ds.yaml").string()).views.size(), 3u);
  }
  {
    s.robot.fail_at = 0;
    vpSelfCalibAcquisition acq(s.robot, s.nominal, *s.grabber, s.options(b));
    const auto r = acq.run(s.plan);
    ASSERT_EQ(r.status, vpSelfCalibAcquisition::OK) << r.message;
    EXPECT_EQ(r.resumed, 3u);
    EXPECT_EQ(r.acquired, 4u);
  }
  EXPECT_EQ(readFile(a / "ds.yaml"), readFile(b / "ds.yaml"));
  for (int k = 1; k <= 7; ++k) {
    const std::string name = "images/000" + std::to_string(k) + ".png";
    EXPECT_EQ(readFile(a / name), readFile(b / name)) << name;
  }
  // Nothing left behind but the dataset and its images.
  unsigned int files = 0;
  for (const auto &e : fs::recursive_directory_iterator(b))
    files += e.is_regular_file() ? 1 : 0;
  EXPECT_EQ(files, 8u);
  // Resuming with another plan is refused.
  std::vector<vpColVector> other = s.plan;
  std::swap(other[0], other[1]);
  vpSelfCalibAcquisition acq(s.robot, s.nominal, *s.grabber, s.options(b));
  EXPECT_THROW(acq.run(other), vpSelfCalibException);
  fs::remove_all(a);
  fs::remove_all(b);
}

// A configuration outside the joint limits is refused before anything moves; a robot that stops
// short of its command is an error; teach mode records the current pose.
TEST(Acquisition, LimitsRefusalsAndTeachMode)
{
  const fs::path d = freshDir("c");
  Scenario s(3);
  std::vector<vpColVector> bad = s.plan;
  bad[2][1] = s.nominal.getJointMax()[1] + 0.1;
  s.robot.moves = 0;
  vpSelfCalibAcquisition acq(s.robot, s.nominal, *s.grabber, s.options(d));
  try {
    acq.run(bad);
    ADD_FAILURE() << "no exception";
  } catch (const vpSelfCalibException &e) {
    EXPECT_NE(e.getStringMessage().find("configuration 3 is outside the joint limits"), std::string::npos);
  }
  EXPECT_EQ(s.robot.moves, 0u);
  EXPECT_FALSE(fs::exists(d / "ds.yaml"));

  // Teach mode: the person moved the arm to plan[1]; record it, then plan[2].
  s.robot.setPosition(vpRobot::ARTICULAR_FRAME, s.plan[1]);
  auto r = acq.record();
  ASSERT_EQ(r.status, vpSelfCalibAcquisition::OK) << r.message;
  s.robot.setPosition(vpRobot::ARTICULAR_FRAME, s.plan[2]);
  r = acq.record();
  ASSERT_EQ(r.status, vpSelfCalibAcquisition::OK) << r.message;
  const vpSelfCalibDataset ds = vpSelfCalibDataset::loadYaml((d / "ds.yaml").string());
  ASSERT_EQ(ds.views.size(), 2u);
  EXPECT_LT((ds.views[1].q - s.plan[2]).frobeniusNorm(), 1e-12);

  // A robot that reports joints other than the commanded ones is an error naming the joint.
  fs::remove_all(d);
  fs::create_directories(d);
  s.robot.stuck = true;
  vpSelfCalibAcquisition a2(s.robot, s.nominal, [](vpImage<unsigned char> &I) { I.resize(4, 4, 0); }, s.options(d));
  const auto r2 = a2.run(s.plan);
  EXPECT_EQ(r2.status, vpSelfCalibAcquisition::ROBOT_ERROR);
  EXPECT_NE(r2.message.find("did not reach the configuration"), std::string::npos) << r2.message;
  EXPECT_FALSE(fs::exists(d / "ds.yaml"));
  fs::remove_all(d);
}
