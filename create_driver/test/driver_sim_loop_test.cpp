// The driver core talking to the simulator core in-process: the same bytes as over a serial
// line, with a simulated line latency, but no pty, no threads and no wall clock.
#include <gtest/gtest.h>
#include <sl_testing/errors.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <functional>
#include <limits>

#include "create_driver/driver_core.h"
#include "create_driver/serial_link.h"
#include "create_driver/sim_robot.h"

using create_driver::Bytes;
namespace cd = create_driver;

namespace
{
class Loop
{
public:
  explicit Loop(const cd::DriverConfig& dc = cd::DriverConfig(), const cd::SimParams& sp = cd::SimParams())
    : sim(sp), drv(dc)
  {
  }

  void connect()
  {
    Bytes out;
    drv.onConnected(t, out);
    toRobot(out);
  }

  void disconnect()
  {
    drv.onDisconnected(t);
    to_robot_.clear();
    to_host_.clear();
  }

  void step()
  {
    t += dt;
    if (heartbeat_period > 0.0 && t >= next_heartbeat_)
    {
      drv.heartbeat(t);  // a running goal's sender is alive
      next_heartbeat_ = t + heartbeat_period;
    }
    // Deliver bytes whose latency has elapsed.
    while (!to_robot_.empty() && to_robot_.front().first <= t)
    {
      if (!drop_to_robot)
        sim.receive(to_robot_.front().second.data(), to_robot_.front().second.size());
      to_robot_.pop_front();
    }
    sim.step(dt);
    Bytes produced;
    sim.takeOutput(produced);
    if (!produced.empty())
      to_host_.emplace_back(t + latency, produced);
    Bytes out;
    while (!to_host_.empty() && to_host_.front().first <= t)
    {
      Bytes in = to_host_.front().second;
      to_host_.pop_front();
      if (corrupt_every > 0 && ++chunks_ % corrupt_every == 0)
        in.insert(in.begin() + static_cast<std::ptrdiff_t>(in.size() / 2), { 0x13, 0xAA, 0x08, 0x07 });
      drv.onBytes(in.data(), in.size(), t, out);
    }
    drv.control(t, out);
    toRobot(out);
    drv.takeOutcomes(outcomes);
  }

  void run(double seconds)
  {
    const int n = static_cast<int>(std::ceil(seconds / dt));
    for (int i = 0; i < n; ++i)
      step();
  }

  bool runUntil(const std::function<bool()>& cond, double max_seconds)
  {
    const int n = static_cast<int>(std::ceil(max_seconds / dt));
    for (int i = 0; i < n; ++i)
    {
      if (cond())
        return true;
      step();
    }
    return cond();
  }

  void toRobot(const Bytes& b)
  {
    if (!b.empty())
      to_robot_.emplace_back(t + latency, b);
  }

  /// Sets the simulator's contact bits (bumps::..., 0: none) and runs 0.1 s; true if the driver's
  /// hazard latch is set then.
  bool contact(uint8_t bits)
  {
    sim.setContact(bits);
    run(0.1);
    return drv.latch().latched();
  }

  /// drv.startGoal() now, its commands (wait-distance mode) queued for the robot; true if accepted.
  bool startGoal(double distance, double speed)
  {
    Bytes out;
    const bool accepted = drv.startGoal(distance, speed, t, out).accepted;
    toRobot(out);
    return accepted;
  }

  bool startUp()
  {
    connect();
    return runUntil([&] { return drv.haveSensors() && sim.mode() == cd::OiMode::SAFE; }, 2.0);
  }

  cd::SimRobot sim;
  cd::DriverCore drv;
  double t = 100.0;
  double dt = 0.005;
  double latency = 0.01;
  int corrupt_every = 0;
  bool drop_to_robot = false;
  double heartbeat_period = 0.1;  // s between heartbeats of the goal's sender; 0: it is silent
  std::vector<cd::GoalOutcome> outcomes;

private:
  std::deque<std::pair<double, Bytes>> to_robot_;
  std::deque<std::pair<double, Bytes>> to_host_;
  int chunks_ = 0;
  double next_heartbeat_ = 0.0;
};

cd::DriverConfig create2Config()
{
  cd::DriverConfig c;
  c.model = cd::Model::CREATE_2;
  c.limits.wheel_base = 0.235;
  c.odometry.wheel_base = 0.235;
  return c;
}

cd::SimParams create2Sim()
{
  cd::SimParams p;
  p.model = cd::Model::CREATE_2;
  return p;
}
}  // namespace

TEST(DriverSimLoop, StartSequence)
{
  Loop l;
  ASSERT_TRUE(l.startUp());
  EXPECT_TRUE(l.sim.streaming());
  l.run(0.1);
  EXPECT_EQ(l.drv.reportedMode(), 2);
  EXPECT_GT(l.drv.parserCounters().valid_frames, 3u);
  EXPECT_EQ(l.drv.parserCounters().corrupt_frames, 0u);
  EXPECT_EQ(l.drv.stats().start_sequences, 1u);
}

namespace
{
void validate(const cd::DriverConfig& c)
{
  cd::validateConfig(c);
}
void validate(const cd::SerialLinkParams& p)
{
  p.validate();
}

/// The message validate() throws for @p c ("" when it accepts it).
template <typename Config>
std::string refusal(const Config& c)
{
  return sl_testing::invalidArgumentOf([&] { validate(c); });
}
}  // namespace

TEST(DriverSimLoop, ConfigValidationNamesTheParameter)
{
  EXPECT_EQ(refusal(cd::DriverConfig()), "");
  cd::DriverConfig c;
  c.limits.max_speed = 0.0;
  EXPECT_EQ(refusal(c).rfind("max_speed", 0), 0u) << refusal(c);
  c = cd::DriverConfig();
  c.use_wait_distance = true;
  c.model = cd::Model::CREATE_2;
  EXPECT_EQ(refusal(c).rfind("use_wait_distance", 0), 0u) << refusal(c);
  c = cd::DriverConfig();
  c.command_timeout = -1;
  EXPECT_EQ(refusal(c).rfind("command_timeout", 0), 0u) << refusal(c);
  c = cd::DriverConfig();
  c.command_timeout = 0.31;
  EXPECT_EQ(refusal(c).rfind("command_timeout", 0), 0u) << refusal(c);
  c.command_timeout = cd::kMaxCommandTimeout;
  EXPECT_EQ(refusal(c), "");
  c = cd::DriverConfig();
  c.limits.wheel_base = 0.05;  // the bound the nodelet once checked apart, (0.05, 1) m
  EXPECT_EQ(refusal(c).rfind("wheel_base", 0), 0u) << refusal(c);
  c = cd::DriverConfig();
  c.drive_distance.max_heading_rate = std::nan("");
  EXPECT_EQ(refusal(c).rfind("drive_distance/max_heading_rate", 0), 0u) << refusal(c);

  EXPECT_EQ(refusal(cd::SerialLinkParams()), "");
  cd::SerialLinkParams p;
  p.port.clear();
  EXPECT_EQ(refusal(p).rfind("port", 0), 0u) << refusal(p);
  p = cd::SerialLinkParams();
  p.tick_period = 0.5;
  EXPECT_EQ(refusal(p).rfind("control_period", 0), 0u) << refusal(p);
  p = cd::SerialLinkParams();
  p.link.max_backoff = 0.1;
  EXPECT_EQ(refusal(p).rfind("reconnect_max_delay", 0), 0u) << refusal(p);
  p = cd::SerialLinkParams();
  p.link.frame_timeout = 0.01;
  EXPECT_EQ(refusal(p).rfind("link_timeout", 0), 0u) << refusal(p);
}

TEST(DriverSimLoop, StartSequenceIsRepeatedWhenUnanswered)
{
  Loop l;
  // The robot hears nothing for a while (e.g. still booting): what is sent is lost.
  l.drop_to_robot = true;
  l.connect();
  l.run(1.5);
  EXPECT_FALSE(l.drv.haveSensors());
  l.drop_to_robot = false;
  ASSERT_TRUE(l.runUntil([&] { return l.drv.haveSensors(); }, 5.0));
  EXPECT_GE(l.drv.stats().start_sequences, 2u);
}

TEST(DriverSimLoop, CmdVelDrivesAndWatchdogStops)
{
  Loop l;
  ASSERT_TRUE(l.startUp());
  const double x0 = l.sim.truePose().x;
  for (int i = 0; i < 10; ++i)
  {
    ASSERT_TRUE(l.drv.setVelocity(0.2, 0.0, l.t, nullptr));
    l.run(0.1);
  }
  EXPECT_NEAR(l.sim.commandedLeft(), 0.2, 1e-3);
  EXPECT_GT(l.sim.truePose().x - x0, 0.1);
  // No more commands: the watchdog stops the wheels command_timeout after the last one.
  const double last_command = l.t - 0.1;
  EXPECT_TRUE(l.drv.commandSourceLost().empty());
  ASSERT_TRUE(l.runUntil([&] { return l.sim.commandedLeft() == 0.0; }, 2.0));
  EXPECT_LE(l.t - last_command, l.drv.config().command_timeout + 0.011 + 2 * l.latency);
  EXPECT_EQ(l.drv.stats().watchdog_stops, 1u);
  EXPECT_EQ(l.drv.commandSourceLost().rfind("no cmd_vel for", 0), 0u) << l.drv.commandSourceLost();
  // At rest, odometry agrees with the true motion (no slip, no noise; 1 mm resolution).
  l.run(0.2);
  EXPECT_NEAR(l.drv.odometry().pose().x, l.sim.truePose().x - x0, 0.002);
}

TEST(DriverSimLoop, QuietAfterAStopIsNoWatchdogStop)
{
  Loop l;
  ASSERT_TRUE(l.startUp());
  for (int i = 0; i < 5; ++i)
  {
    l.drv.setVelocity(0.2, 0.0, l.t, nullptr);
    l.run(0.1);
  }
  l.drv.setVelocity(0.0, 0.0, l.t, nullptr);  // the sender stops the robot, then falls silent
  l.run(1.0);
  EXPECT_EQ(l.sim.commandedLeft(), 0.0);
  EXPECT_EQ(l.drv.stats().watchdog_stops, 0u);
  EXPECT_TRUE(l.drv.commandSourceLost().empty()) << l.drv.commandSourceLost();
}

TEST(DriverSimLoop, AccelerationIsLimited)
{
  cd::DriverConfig c;
  c.limits.max_accel = 0.5;
  Loop l(c);
  ASSERT_TRUE(l.startUp());
  l.drv.setVelocity(0.4, 0.0, l.t, nullptr);
  l.run(0.2);
  EXPECT_GT(l.sim.commandedLeft(), 0.0);
  EXPECT_LE(l.sim.commandedLeft(), 0.5 * 0.2 + 0.011);
  for (int i = 0; i < 7; ++i)
  {
    l.drv.setVelocity(0.4, 0.0, l.t, nullptr);
    l.run(0.1);
  }
  EXPECT_NEAR(l.sim.commandedLeft(), 0.4, 1e-3);
}

TEST(DriverSimLoop, GoalWithoutHeartbeatStopsAndAborts)
{
  Loop l;
  ASSERT_TRUE(l.startUp());
  ASSERT_TRUE(l.startGoal(2.0, 0.3));
  l.run(1.0);  // heartbeats every 0.1 s: the goal runs
  ASSERT_TRUE(l.outcomes.empty());
  EXPECT_NEAR(l.sim.commandedLeft(), 0.3, 0.01);
  EXPECT_TRUE(l.drv.commandSourceLost().empty());

  l.heartbeat_period = 0.0;  // the sender freezes
  const double frozen = l.t;
  const double x0 = l.sim.truePose().x;
  ASSERT_TRUE(l.runUntil([&] { return !l.outcomes.empty(); }, 1.0));
  EXPECT_EQ(l.outcomes[0].reason, cd::StopReason::HEARTBEAT_LOST);
  EXPECT_NE(l.outcomes[0].message.find("no heartbeat"), std::string::npos) << l.outcomes[0].message;
  // The last heartbeat came up to 0.1 s before the freeze.
  EXPECT_LE(l.t - frozen, l.drv.config().command_timeout + 0.011);
  ASSERT_TRUE(l.runUntil([&] { return l.sim.commandedLeft() == 0.0; }, 0.1));
  l.run(0.5);
  EXPECT_EQ(l.sim.commandedLeft(), 0.0);
  const double after = l.sim.truePose().x - x0;
  // 0.3 m/s for at most command_timeout plus the line's latency both ways.
  EXPECT_LE(after, 0.3 * (l.drv.config().command_timeout + 0.011 + 2 * l.latency) + 0.001);
  EXPECT_EQ(l.drv.stats().heartbeat_stops, 1u);
  EXPECT_EQ(l.drv.commandSourceLost().rfind("drive_distance goal aborted", 0), 0u) << l.drv.commandSourceLost();
  // A heartbeat without a goal keeps nothing alive; a command shows the source alive again.
  l.drv.heartbeat(l.t);
  EXPECT_FALSE(l.drv.commandSourceLost().empty());
  l.drv.setVelocity(0.0, 0.0, l.t, nullptr);
  EXPECT_TRUE(l.drv.commandSourceLost().empty());
}

TEST(DriverSimLoop, ConnectStopsBeforeStart)
{
  // A driver process that dies while the robot drives leaves the robot in Safe mode executing its
  // last command; the next process's first bytes are a stop, before Start.
  Loop l;
  ASSERT_TRUE(l.startUp());
  for (int i = 0; i < 3; ++i)
  {
    l.drv.setVelocity(0.3, 0.0, l.t, nullptr);
    l.run(0.1);
  }
  ASSERT_GT(l.sim.commandedLeft(), 0.2);
  cd::DriverCore next{ cd::DriverConfig() };
  Bytes out;
  next.onConnected(l.t, out);
  const Bytes stop = cd::encodeDriveDirect(0, 0);
  ASSERT_GE(out.size(), stop.size() + 1);
  EXPECT_TRUE(std::equal(stop.begin(), stop.end(), out.begin()));
  EXPECT_EQ(out[stop.size()], cd::oi::START);
  // Obeyed in Safe mode as such (without the Start behind it).
  l.sim.receive(stop.data(), stop.size());
  EXPECT_EQ(l.sim.commandedLeft(), 0.0);
  EXPECT_EQ(l.sim.mode(), cd::OiMode::SAFE);
}

TEST(DriverSimLoop, NonFiniteCommandsRejected)
{
  Loop l;
  ASSERT_TRUE(l.startUp());
  std::string err;
  EXPECT_FALSE(l.drv.setVelocity(std::numeric_limits<double>::quiet_NaN(), 0.0, l.t, &err));
  EXPECT_FALSE(l.drv.setVelocity(0.1, std::numeric_limits<double>::infinity(), l.t, &err));
  EXPECT_FALSE(err.empty());
  l.run(0.2);
  EXPECT_EQ(l.sim.commandedLeft(), 0.0);
  EXPECT_EQ(l.drv.stats().rejected_commands, 2u);
}

struct GoalCase
{
  double distance;
  double speed;
  bool create2;
  cd::DriveCommandType type;
};

class DriveDistanceLoop : public ::testing::TestWithParam<GoalCase>
{
};

TEST_P(DriveDistanceLoop, EndsWithin5mm)
{
  const GoalCase g = GetParam();
  cd::DriverConfig c = g.create2 ? create2Config() : cd::DriverConfig();
  c.drive_type = g.type;
  Loop l(c, g.create2 ? create2Sim() : cd::SimParams());
  ASSERT_TRUE(l.startUp());
  const double x0 = l.sim.truePose().x;
  Bytes out;
  const cd::GoalStart s = l.drv.startGoal(g.distance, g.speed, l.t, out);
  l.toRobot(out);
  ASSERT_TRUE(s.accepted) << s.message;
  ASSERT_TRUE(l.runUntil([&] { return !l.outcomes.empty(); }, 3.0 * std::fabs(g.distance) / g.speed + 10.0));
  ASSERT_EQ(l.outcomes.size(), 1u);
  EXPECT_EQ(l.outcomes[0].id, s.id);
  EXPECT_EQ(l.outcomes[0].reason, cd::StopReason::REACHED) << l.outcomes[0].message;
  l.run(0.5);  // come to rest
  EXPECT_EQ(l.sim.commandedLeft(), 0.0);
  EXPECT_NEAR(l.sim.truePose().x - x0, g.distance, 0.005);
  EXPECT_NEAR(l.outcomes[0].travelled, g.distance, 0.005);
  EXPECT_NEAR(l.sim.truePose().y, 0.0, 0.005);
}

INSTANTIATE_TEST_SUITE_P(Goals, DriveDistanceLoop,
                         ::testing::Values(GoalCase{ 0.5, 0.2, false, cd::DriveCommandType::DIRECT },
                                           GoalCase{ 0.5, 0.01, false, cd::DriveCommandType::DIRECT },
                                           GoalCase{ 0.5, 0.5, false, cd::DriveCommandType::DIRECT },
                                           GoalCase{ -0.5, 0.2, false, cd::DriveCommandType::DIRECT },
                                           GoalCase{ 0.5, 0.3, false, cd::DriveCommandType::RADIUS },
                                           GoalCase{ 0.5, 0.2, true, cd::DriveCommandType::DIRECT },
                                           GoalCase{ -0.3, 0.4, true, cd::DriveCommandType::DIRECT }));

TEST(DriverSimLoop, HeadingHoldKeepsLineDespiteNoisyOdometry)
{
  cd::SimParams p;
  p.odom_noise = 0.02;
  p.seed = 3;
  Loop l(cd::DriverConfig(), p);
  ASSERT_TRUE(l.startUp());
  ASSERT_TRUE(l.startGoal(0.5, 0.2));
  ASSERT_TRUE(l.runUntil([&] { return !l.outcomes.empty(); }, 20.0));
  EXPECT_EQ(l.outcomes[0].reason, cd::StopReason::REACHED);
  EXPECT_NEAR(l.sim.truePose().x, 0.5, 0.02);
}

TEST(DriverSimLoop, PreemptStopsPromptly)
{
  Loop l;
  ASSERT_TRUE(l.startUp());
  Bytes out;
  const cd::GoalStart s = l.drv.startGoal(1.0, 0.3, l.t, out);
  ASSERT_TRUE(s.accepted);
  ASSERT_TRUE(l.runUntil([&] { return l.sim.truePose().x > 0.1; }, 5.0));
  l.drv.cancelGoal(s.id, cd::StopReason::PREEMPTED, "cancelled");
  Bytes stop;
  l.drv.control(l.t, stop);
  l.toRobot(stop);
  l.run(0.05);  // line latency
  EXPECT_EQ(l.sim.commandedLeft(), 0.0);
  ASSERT_EQ(l.outcomes.size(), 1u);
  EXPECT_EQ(l.outcomes[0].reason, cd::StopReason::PREEMPTED);
  EXPECT_GT(l.outcomes[0].travelled, 0.09);
}

TEST(DriverSimLoop, NewGoalReplacesOld)
{
  Loop l;
  ASSERT_TRUE(l.startUp());
  Bytes out;
  const cd::GoalStart a = l.drv.startGoal(1.0, 0.2, l.t, out);
  l.run(0.5);
  const cd::GoalStart b = l.drv.startGoal(-0.05, 0.1, l.t, out);
  ASSERT_TRUE(a.accepted && b.accepted);
  ASSERT_TRUE(l.runUntil([&] { return l.outcomes.size() >= 2; }, 10.0));
  EXPECT_EQ(l.outcomes[0].id, a.id);
  EXPECT_EQ(l.outcomes[0].reason, cd::StopReason::PREEMPTED);
  EXPECT_EQ(l.outcomes[1].id, b.id);
  EXPECT_EQ(l.outcomes[1].reason, cd::StopReason::REACHED);
  EXPECT_NEAR(l.outcomes[1].travelled, -0.05, 0.005);
}

TEST(DriverSimLoop, CmdVelOverridesGoal)
{
  Loop l;
  ASSERT_TRUE(l.startUp());
  ASSERT_TRUE(l.startGoal(1.0, 0.2));
  l.run(0.3);
  l.drv.setVelocity(0.0, 0.5, l.t, nullptr);
  l.run(0.05);
  ASSERT_EQ(l.outcomes.size(), 1u);
  EXPECT_EQ(l.outcomes[0].reason, cd::StopReason::PREEMPTED);
}

TEST(DriverSimLoop, ZeroCmdVelLeavesGoalAlone)
{
  Loop l;
  ASSERT_TRUE(l.startUp());
  ASSERT_TRUE(l.startGoal(0.2, 0.2));
  for (int i = 0; i < 5; ++i)
  {
    EXPECT_TRUE(l.drv.setVelocity(0.0, 0.0, l.t, nullptr));
    l.run(0.1);
  }
  EXPECT_TRUE(l.outcomes.empty());
  ASSERT_TRUE(l.runUntil([&] { return !l.outcomes.empty(); }, 10.0));
  EXPECT_EQ(l.outcomes[0].reason, cd::StopReason::REACHED);
}

TEST(DriverSimLoop, CmdVelIgnoredDuringGoalWhenConfigured)
{
  cd::DriverConfig c;
  c.cmd_vel_preempts_goal = false;
  Loop l(c);
  ASSERT_TRUE(l.startUp());
  ASSERT_TRUE(l.startGoal(0.2, 0.2));
  std::string err;
  EXPECT_FALSE(l.drv.setVelocity(0.3, 1.0, l.t, &err));
  EXPECT_FALSE(err.empty());
  ASSERT_TRUE(l.runUntil([&] { return !l.outcomes.empty(); }, 10.0));
  EXPECT_EQ(l.outcomes[0].reason, cd::StopReason::REACHED);
  EXPECT_NEAR(l.sim.truePose().yaw, 0.0, 0.02);
}

TEST(DriverSimLoop, InvalidGoalsRejected)
{
  Loop l;
  Bytes out;
  EXPECT_EQ(l.drv.startGoal(0.5, 0.2, l.t, out).reason, cd::StopReason::DISCONNECTED);
  ASSERT_TRUE(l.startUp());
  EXPECT_EQ(l.drv.startGoal(std::numeric_limits<double>::quiet_NaN(), 0.2, l.t, out).reason,
            cd::StopReason::INVALID_GOAL);
  EXPECT_FALSE(l.drv.startGoal(0.5, 0.0, l.t, out).accepted);
  EXPECT_FALSE(l.drv.startGoal(0.5, -1.0, l.t, out).accepted);
}

TEST(DriverSimLoop, BumpStopsLatchesAndResets)
{
  Loop l;
  ASSERT_TRUE(l.startUp());
  auto drive = [&](double v, double seconds)
  {
    for (double s = 0; s < seconds; s += 0.1)
    {
      l.drv.setVelocity(v, 0.0, l.t, nullptr);
      l.run(0.1);
    }
  };
  drive(0.2, 0.5);
  ASSERT_GT(l.sim.commandedLeft(), 0.1);
  l.sim.setContact(cd::bumps::BUMP_LEFT);
  drive(0.2, 0.2);
  EXPECT_EQ(l.sim.commandedLeft(), 0.0);
  EXPECT_TRUE(l.drv.latch().latched());
  EXPECT_EQ(l.drv.latch().reason(), cd::Hazard::BUMPER);
  EXPECT_EQ(l.drv.stats().hazard_stops, 1u);
  // Contact gone: forward commands stay blocked (latched).
  l.sim.setContact(0);
  drive(0.2, 1.0);
  EXPECT_EQ(l.sim.commandedLeft(), 0.0);
  std::string msg;
  EXPECT_TRUE(l.drv.resetHazard(&msg)) << msg;
  drive(0.2, 0.5);
  EXPECT_GT(l.sim.commandedLeft(), 0.1);
}

TEST(DriverSimLoop, ResetRefusedWhileBumperPressed)
{
  Loop l;
  ASSERT_TRUE(l.startUp());
  ASSERT_TRUE(l.contact(cd::bumps::BUMP_RIGHT));
  std::string msg;
  EXPECT_FALSE(l.drv.resetHazard(&msg));
  EXPECT_NE(msg.find("bumper"), std::string::npos);
}

TEST(DriverSimLoop, BackingAwayReleasesBumpLatch)
{
  Loop l;
  ASSERT_TRUE(l.startUp());
  ASSERT_TRUE(l.contact(cd::bumps::BUMP_RIGHT));
  const double x0 = l.sim.truePose().x;
  for (int i = 0; i < 5; ++i)
  {
    l.drv.setVelocity(-0.1, 0.0, l.t, nullptr);
    l.run(0.1);
    l.sim.setContact(0);  // moved away from the obstacle
  }
  EXPECT_LT(l.sim.truePose().x, x0 - 0.02);
  EXPECT_FALSE(l.drv.latch().latched());
}

TEST(DriverSimLoop, GoalAbortedByBumper)
{
  Loop l;
  ASSERT_TRUE(l.startUp());
  Bytes out;
  ASSERT_TRUE(l.drv.startGoal(1.0, 0.2, l.t, out).accepted);
  ASSERT_TRUE(l.runUntil([&] { return l.sim.truePose().x > 0.2; }, 5.0));
  l.sim.setContact(cd::bumps::BUMP_LEFT | cd::bumps::BUMP_RIGHT);
  ASSERT_TRUE(l.runUntil([&] { return !l.outcomes.empty(); }, 1.0));
  EXPECT_EQ(l.outcomes[0].reason, cd::StopReason::BUMPER);
  l.run(0.1);
  EXPECT_EQ(l.sim.commandedLeft(), 0.0);
  // A forward goal is refused while latched; a backing one is allowed.
  EXPECT_EQ(l.drv.startGoal(0.1, 0.1, l.t, out).reason, cd::StopReason::BUMPER);
  EXPECT_TRUE(l.drv.startGoal(-0.05, 0.1, l.t, out).accepted);
}

TEST(DriverSimLoop, CliffInSafeModeThenBackAway)
{
  Loop l;
  ASSERT_TRUE(l.startUp());
  for (int i = 0; i < 3; ++i)
  {
    l.drv.setVelocity(0.2, 0.0, l.t, nullptr);
    l.run(0.1);
  }
  l.sim.setCliffs(0x02);
  l.drv.setVelocity(0.2, 0.0, l.t, nullptr);
  l.run(0.1);
  EXPECT_EQ(l.sim.mode(), cd::OiMode::PASSIVE);  // the robot's own Safe-mode reaction
  EXPECT_EQ(l.drv.latch().reason(), cd::Hazard::CLIFF);
  const double x0 = l.sim.truePose().x;
  // Backing away: the driver re-enters Safe mode and drives backwards.
  for (int i = 0; i < 6; ++i)
  {
    l.drv.setVelocity(-0.1, 0.0, l.t, nullptr);
    l.run(0.1);
    if (l.sim.truePose().x < x0 - 0.01)
      l.sim.setCliffs(0);
  }
  EXPECT_EQ(l.sim.mode(), cd::OiMode::SAFE);
  EXPECT_LT(l.sim.truePose().x, x0 - 0.02);
  EXPECT_FALSE(l.drv.latch().latched());
  EXPECT_GE(l.drv.stats().mode_reasserts, 1u);
}

TEST(DriverSimLoop, WheelDropLatches)
{
  Loop l;
  ASSERT_TRUE(l.startUp());
  l.sim.setWheelDrops(cd::bumps::WHEEL_DROP_CASTER);
  l.run(0.1);
  EXPECT_EQ(l.drv.latch().reason(), cd::Hazard::WHEEL_DROP);
  l.drv.setVelocity(-0.1, 0.0, l.t, nullptr);
  l.run(0.2);
  EXPECT_EQ(l.sim.commandedLeft(), 0.0);
}

TEST(DriverSimLoop, GarbageIsCountedAndSurvived)
{
  Loop l;
  l.corrupt_every = 3;
  ASSERT_TRUE(l.startUp());
  ASSERT_TRUE(l.startGoal(0.5, 0.2));
  ASSERT_TRUE(l.runUntil([&] { return !l.outcomes.empty(); }, 15.0));
  EXPECT_EQ(l.outcomes[0].reason, cd::StopReason::REACHED);
  l.run(0.3);
  // A third of the frames is lost: their distance increments are estimated from the velocity.
  EXPECT_NEAR(l.sim.truePose().x, 0.5, 0.02);
  EXPECT_GT(l.drv.stats().frames_estimated, 10u);
  EXPECT_GT(l.drv.parserCounters().corrupt_frames, 10u);
  EXPECT_GT(l.drv.parserCounters().valid_frames, 100u);
}

TEST(DriverSimLoop, ReconnectStopsRobot)
{
  cd::DriverConfig c;
  c.command_timeout = 100.0;  // beyond the parameter's range: only the reconnect may stop the robot
  Loop l(c);
  ASSERT_TRUE(l.startUp());
  l.drv.setVelocity(0.2, 0.0, l.t, nullptr);
  l.run(0.5);
  ASSERT_GT(l.sim.commandedLeft(), 0.1);
  l.disconnect();  // the cable drops: the robot keeps its last command
  l.run(0.5);
  EXPECT_GT(l.sim.commandedLeft(), 0.1);
  l.connect();  // reconnect: Start, Safe, stop, stream
  ASSERT_TRUE(l.runUntil([&] { return l.drv.haveSensors(); }, 3.0));
  l.run(0.2);
  EXPECT_EQ(l.sim.commandedLeft(), 0.0);
  EXPECT_EQ(l.sim.mode(), cd::OiMode::SAFE);
  // The old cmd_vel is not resumed.
  l.run(0.5);
  EXPECT_EQ(l.sim.commandedLeft(), 0.0);
}

TEST(DriverSimLoop, DisconnectAbortsGoal)
{
  Loop l;
  ASSERT_TRUE(l.startUp());
  ASSERT_TRUE(l.startGoal(1.0, 0.2));
  l.run(0.3);
  l.disconnect();
  l.drv.takeOutcomes(l.outcomes);
  ASSERT_EQ(l.outcomes.size(), 1u);
  EXPECT_EQ(l.outcomes[0].reason, cd::StopReason::DISCONNECTED);
}

TEST(DriverSimLoop, ShutdownLeavesRobotPassiveAndStill)
{
  Loop l;
  ASSERT_TRUE(l.startUp());
  l.drv.setVelocity(0.2, 0.0, l.t, nullptr);
  l.run(0.3);
  Bytes out;
  l.drv.shutdown(out);
  l.toRobot(out);
  l.run(0.1);
  EXPECT_EQ(l.sim.mode(), cd::OiMode::PASSIVE);
  EXPECT_EQ(l.sim.commandedLeft(), 0.0);
  EXPECT_FALSE(l.sim.streaming());
}

namespace
{
/// The driver with Wait Distance goals (use_wait_distance, opt-in).
cd::DriverConfig waitDistance()
{
  cd::DriverConfig c;
  c.use_wait_distance = true;
  return c;
}
}  // namespace

TEST(DriverSimLoop, WaitDistanceOptIn)
{
  Loop l(waitDistance());
  ASSERT_TRUE(l.startUp());
  ASSERT_TRUE(l.startGoal(0.3, 0.2));
  l.run(0.1);
  EXPECT_TRUE(l.sim.waiting());
  EXPECT_TRUE(l.drv.waitDistanceActive());
  ASSERT_TRUE(l.runUntil([&] { return !l.outcomes.empty(); }, 10.0));
  EXPECT_EQ(l.outcomes[0].reason, cd::StopReason::REACHED) << l.outcomes[0].message;
  l.run(0.3);
  EXPECT_FALSE(l.sim.waiting());
  EXPECT_EQ(l.sim.commandedLeft(), 0.0);
  EXPECT_NEAR(l.sim.truePose().x, 0.3, 0.005);
}

TEST(DriverSimLoop, WaitDistanceHeldBackTimesOutAndSaysSo)
{
  cd::DriverConfig c = waitDistance();
  c.drive_distance.stall_timeout = 1.0;
  Loop l(c);
  ASSERT_TRUE(l.startUp());
  l.contact(cd::bumps::BUMP_LEFT);
  l.contact(0);
  std::string msg;
  ASSERT_TRUE(l.drv.resetHazard(&msg));
  ASSERT_TRUE(l.startGoal(0.3, 0.2));
  l.run(0.3);
  // The robot runs into an obstacle that holds it back (the simulator stalls forward motion while
  // in contact). The host ends the goal on the bumper, but the robot itself stays blocked in its
  // Wait Distance: exactly the hazard that makes this mode opt-in.
  l.sim.setContact(cd::bumps::BUMP_LEFT);
  ASSERT_TRUE(l.runUntil([&] { return !l.outcomes.empty(); }, 10.0));
  EXPECT_EQ(l.outcomes[0].reason, cd::StopReason::BUMPER);
  EXPECT_NE(l.outcomes[0].message.find("Wait Distance"), std::string::npos) << l.outcomes[0].message;
  l.run(2.0);
  EXPECT_TRUE(l.sim.waiting()) << "the robot should still be blocked by Wait Distance";
}
