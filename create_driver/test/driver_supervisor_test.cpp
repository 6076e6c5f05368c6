// DriverSupervisor against the simulator core in-process (no pty, no threads, no wall clock):
// what the node publishes and reports, and the bytes it queues; GoalRegistry; the named
// parameter values.
#include <gtest/gtest.h>
#include <sl_testing/errors.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "create_driver/driver_supervisor.h"
#include "create_driver/goal_registry.h"
#include "create_driver/sim_robot.h"

using create_driver::Bytes;
namespace cd = create_driver;

namespace
{
// The supervisor wired to a SimRobot the way SerialLink wires it to a port.
class Rig
{
public:
  explicit Rig(const cd::DriverConfig& c = cd::DriverConfig()) : sup(c) {}

  void open()
  {
    Bytes out;
    sup.onOpen(t, out);
    sim.receive(out.data(), out.size());
    sup.onLinkState(cd::LinkState::STARTING, t);
  }

  // One control period: the robot's bytes reach the supervisor, then the tick; actions kept.
  void step()
  {
    t += dt;
    sim.step(dt);
    Bytes in;
    Bytes out;
    sim.takeOutput(in);
    if (!in.empty())
    {
      const cd::FrameActions a = sup.onData(in.data(), in.size(), t, out);
      if (a.frames > 0)
        frames.push_back(a);
    }
    sup.onTick(t, out);
    sent += out.size();
    sim.receive(out.data(), out.size());
  }

  void run(double seconds)
  {
    for (double end = t + seconds; t < end;)
      step();
  }

  bool runUntil(const std::function<bool()>& cond, double max_seconds)
  {
    for (double end = t + max_seconds; t < end && !cond();)
      step();
    return cond();
  }

  bool startUp()
  {
    open();
    const bool up = runUntil([&] { return sup.core().haveSensors(); }, 2.0);
    sup.onLinkState(cd::LinkState::RUNNING, t);
    return up;
  }

  // How many of the frame actions since the last call published @p what.
  int count(bool cd::FrameActions::*what)
  {
    int n = 0;
    for (const cd::FrameActions& a : frames)
      n += a.*what ? 1 : 0;
    return n;
  }

  cd::SimRobot sim;
  cd::DriverSupervisor sup;
  double t = 50.0;
  double dt = 0.005;
  size_t sent = 0;
  std::vector<cd::FrameActions> frames;
};
}  // namespace

TEST(DriverSupervisor, HazardReadingFollowsThePacketsAndTheLatch)
{
  cd::SensorState s;
  s.set(cd::packet::BUMPS_WHEEL_DROPS, cd::bumps::BUMP_LEFT | cd::bumps::WHEEL_DROP_CASTER);
  s.set(cd::packet::CLIFF_FRONT_RIGHT, 1);
  cd::HazardLatch latch;
  const cd::HazardReading h = cd::hazardReading(s, latch);
  EXPECT_TRUE(h.bump_left);
  EXPECT_FALSE(h.bump_right);
  EXPECT_TRUE(h.wheel_drop_caster);
  EXPECT_FALSE(h.wheel_drop_left);
  EXPECT_TRUE(h.cliff_front_right);
  EXPECT_FALSE(h.cliff_left);
  EXPECT_FALSE(h.latched);
  latch.update(s, false);
  const cd::HazardReading latched = cd::hazardReading(s, latch);
  EXPECT_TRUE(latched.latched);
  EXPECT_EQ(latched.latch_reason, cd::Hazard::WHEEL_DROP);
  EXPECT_NE(h, latched);
  EXPECT_EQ(latched, cd::hazardReading(s, latch));
}

TEST(DriverSupervisor, GoalEndOfEachReason)
{
  EXPECT_EQ(cd::goalEnd(cd::StopReason::REACHED), cd::GoalEnd::SUCCEEDED);
  EXPECT_EQ(cd::goalEnd(cd::StopReason::PREEMPTED), cd::GoalEnd::CANCELED);
  for (cd::StopReason r :
       { cd::StopReason::BUMPER, cd::StopReason::CLIFF, cd::StopReason::WHEEL_DROP, cd::StopReason::TIMEOUT,
         cd::StopReason::DISCONNECTED, cd::StopReason::INVALID_GOAL, cd::StopReason::HEARTBEAT_LOST })
    EXPECT_EQ(cd::goalEnd(r), cd::GoalEnd::ABORTED) << cd::stopReasonName(r);
}

TEST(DriverSupervisor, FirstFramePublishesEverything)
{
  Rig r;
  ASSERT_TRUE(r.startUp());
  ASSERT_FALSE(r.frames.empty());
  const cd::FrameActions& first = r.frames.front();
  EXPECT_TRUE(first.hazards);
  EXPECT_TRUE(first.battery);
  EXPECT_TRUE(first.mode);
  EXPECT_FALSE(first.feedback);  // no goal
}

TEST(DriverSupervisor, HazardsAtTenHertzAndAtOnceOnAChange)
{
  Rig r;
  ASSERT_TRUE(r.startUp());
  r.run(0.1);
  r.frames.clear();
  r.run(1.0);  // 66 frames without a change
  const int quiet = r.count(&cd::FrameActions::hazards);
  EXPECT_GE(quiet, 9);
  EXPECT_LE(quiet, 11);
  r.frames.clear();
  r.sim.setContact(cd::bumps::BUMP_RIGHT);
  ASSERT_TRUE(r.runUntil([&] { return !r.frames.empty() && r.frames.back().snapshot.hazards.bump_right; }, 0.1));
  EXPECT_TRUE(r.frames.back().hazards) << "a change is published with its frame";
  EXPECT_TRUE(r.frames.back().snapshot.hazards.latched);
}

TEST(DriverSupervisor, BatteryOncePerSecond)
{
  Rig r;
  ASSERT_TRUE(r.startUp());
  r.frames.clear();
  r.run(3.0);
  const int n = r.count(&cd::FrameActions::battery);
  EXPECT_GE(n, 2);
  EXPECT_LE(n, 3);
}

TEST(DriverSupervisor, ModeWhenItDiffersFromTheModePublished)
{
  Rig r;
  ASSERT_TRUE(r.startUp());
  ASSERT_TRUE(r.frames.back().mode) << "nothing published yet";
  const cd::ModeReport m = r.sup.takeModeReport();
  EXPECT_EQ(m.reported_mode, 2);
  EXPECT_EQ(m.requested_mode, cd::OiMode::SAFE);
  EXPECT_EQ(m.link_state, cd::LinkState::RUNNING);
  r.frames.clear();
  r.run(0.2);
  EXPECT_EQ(r.count(&cd::FrameActions::mode), 0);
  // A wheel drop in Safe mode makes the robot fall back to Passive.
  r.sim.setWheelDrops(cd::bumps::WHEEL_DROP_LEFT);
  ASSERT_TRUE(r.runUntil([&] { return r.sup.core().reportedMode() == 1; }, 0.5));
  EXPECT_TRUE(r.frames.back().mode);
  EXPECT_EQ(r.sup.takeModeReport().reported_mode, 1);
  r.frames.clear();
  r.run(0.1);
  EXPECT_EQ(r.count(&cd::FrameActions::mode), 0);
}

TEST(DriverSupervisor, ModeIsUnknownUntilAFrameArrives)
{
  Rig r;
  r.open();
  const cd::ModeReport m = r.sup.takeModeReport();
  EXPECT_EQ(m.reported_mode, -1);
  EXPECT_EQ(m.link_state, cd::LinkState::STARTING);
}

TEST(DriverSupervisor, FeedbackAtTenHertzWhileAGoalRuns)
{
  Rig r;
  ASSERT_TRUE(r.startUp());
  r.frames.clear();
  const cd::GoalStart g = r.sup.startGoal(0.5, 0.2, r.t);
  ASSERT_TRUE(g.accepted) << g.message;
  for (int i = 0; i < 10; ++i)  // 1 s with the sender's heartbeat
  {
    r.sup.heartbeat(r.t);
    r.run(0.1);
  }
  const int n = r.count(&cd::FrameActions::feedback);
  EXPECT_GE(n, 9);
  EXPECT_LE(n, 11);
  EXPECT_EQ(r.frames.back().snapshot.progress.id, g.id);
  EXPECT_GT(r.frames.back().snapshot.progress.travelled, 0.1);
}

TEST(DriverSupervisor, WatchdogStopReportedOncePerStop)
{
  Rig r;
  ASSERT_TRUE(r.startUp());
  std::string why;
  EXPECT_FALSE(r.sup.takeWatchdogStop(&why));
  ASSERT_TRUE(r.sup.setVelocity(0.2, 0.0, r.t, nullptr));
  r.run(0.4);  // the sender went quiet
  ASSERT_TRUE(r.sup.takeWatchdogStop(&why));
  EXPECT_NE(why.find("no cmd_vel for"), std::string::npos) << why;
  EXPECT_FALSE(r.sup.takeWatchdogStop(&why)) << "reported once";
  ASSERT_TRUE(r.sup.setVelocity(0.2, 0.0, r.t, nullptr));
  EXPECT_FALSE(r.sup.takeWatchdogStop(&why)) << "a command came";
  r.run(0.4);
  EXPECT_TRUE(r.sup.takeWatchdogStop(&why)) << "the next stop";
}

TEST(DriverSupervisor, NonFiniteCommandRejected)
{
  Rig r;
  ASSERT_TRUE(r.startUp());
  std::string error;
  EXPECT_FALSE(r.sup.setVelocity(NAN, 0.0, r.t, &error));
  EXPECT_NE(error.find("NaN"), std::string::npos) << error;
  EXPECT_EQ(r.sup.core().stats().rejected_commands, 1u);
}

TEST(DriverSupervisor, CancelEndsTheGoalPreempted)
{
  Rig r;
  ASSERT_TRUE(r.startUp());
  const cd::GoalStart g = r.sup.startGoal(0.5, 0.2, r.t);
  ASSERT_TRUE(g.accepted);
  r.sup.cancelGoal(g.id + 1);  // not running: nothing ends
  std::vector<cd::GoalOutcome> ended;
  r.sup.takeEndedGoals(ended);
  EXPECT_TRUE(ended.empty());
  r.sup.cancelGoal(g.id);
  r.sup.takeEndedGoals(ended);
  ASSERT_EQ(ended.size(), 1u);
  EXPECT_EQ(ended[0].id, g.id);
  EXPECT_EQ(ended[0].reason, cd::StopReason::PREEMPTED);
  EXPECT_EQ(ended[0].message, "cancelled");
}

TEST(DriverSupervisor, DisconnectEndsTheGoal)
{
  Rig r;
  ASSERT_TRUE(r.startUp());
  const cd::GoalStart g = r.sup.startGoal(0.5, 0.2, r.t);
  ASSERT_TRUE(g.accepted);
  r.sup.onLinkState(cd::LinkState::DISCONNECTED, r.t);
  EXPECT_EQ(r.sup.linkState(), cd::LinkState::DISCONNECTED);
  std::vector<cd::GoalOutcome> ended;
  r.sup.takeEndedGoals(ended);
  ASSERT_EQ(ended.size(), 1u);
  EXPECT_EQ(ended[0].reason, cd::StopReason::DISCONNECTED);
  EXPECT_EQ(r.sup.takeModeReport().reported_mode, -1);
}

TEST(DriverSupervisor, GoalBytesLeaveWithTheNextTickAndNotAfterAReopen)
{
  cd::DriverConfig c;
  c.use_wait_distance = true;
  Rig r(c);
  ASSERT_TRUE(r.startUp());
  ASSERT_TRUE(r.sup.startGoal(0.1, 0.2, r.t).accepted);
  Bytes out;
  r.sup.onTick(r.t, out);
  // Safe, Drive 200 mm/s straight, Wait Distance 100 mm, Drive 0 (the robot runs it alone).
  const Bytes script = { cd::oi::SAFE, cd::oi::DRIVE, 0, 200, 0x80, 0, cd::oi::WAIT_DISTANCE, 0,
                         100,          cd::oi::DRIVE, 0, 0,   0x80, 0 };
  EXPECT_EQ(out, script);
  Bytes again;
  r.sup.onTick(r.t, again);
  EXPECT_TRUE(again.empty()) << "sent once; the robot ignores commands meanwhile";

  ASSERT_TRUE(r.sup.startGoal(0.1, 0.2, r.t).accepted);
  Bytes opened;
  r.sup.onOpen(r.t, opened);  // the port reopened before the bytes left: a new start instead
  Bytes tick;
  r.sup.onTick(r.t + 0.01, tick);
  EXPECT_TRUE(tick.empty());
}

TEST(DriverSupervisor, StreamRateBetweenReports)
{
  Rig r;
  ASSERT_TRUE(r.startUp());
  const cd::StreamReport first = r.sup.takeStreamReport(r.t);
  EXPECT_EQ(first.rate, 0.0);
  r.run(1.0);
  const cd::StreamReport second = r.sup.takeStreamReport(r.t);
  EXPECT_NEAR(second.rate, 1.0 / 0.015, 3.0);  // a frame every 15 ms
  EXPECT_FALSE(second.new_corrupt);
  r.sim.injectIntoNextFrame({ 19, 0x55, 0x07, 0x33 });
  r.run(0.2);
  const cd::StreamReport third = r.sup.takeStreamReport(r.t);
  EXPECT_TRUE(third.new_corrupt);
  EXPECT_GT(third.counters.corrupt_frames, 0u);
}

TEST(GoalRegistry, KeepsTakesAndFindsHandles)
{
  cd::GoalRegistry<std::string> goals;
  goals.add(1, "a");
  goals.add(2, "b");
  goals.add(3, "a");
  EXPECT_EQ(goals.find(2).value_or(""), "b");
  EXPECT_EQ(goals.idsOf("a"), (std::vector<uint64_t>{ 1, 3 }));
  EXPECT_EQ(goals.take(1).value_or(""), "a");
  EXPECT_FALSE(goals.take(1).has_value()) << "taken once";
  EXPECT_FALSE(goals.find(7).has_value());
  EXPECT_EQ(goals.size(), 2u);
}

TEST(DriverParams, NamedValuesParseOrNameTheParameter)
{
  EXPECT_EQ(cd::parseModel("create"), cd::Model::CREATE_1);
  EXPECT_EQ(cd::parseModel("create_1"), cd::Model::CREATE_1);
  EXPECT_EQ(cd::parseModel("roomba_600"), cd::Model::CREATE_2);
  EXPECT_EQ(cd::parseModel("create_2"), cd::Model::CREATE_2);
  EXPECT_EQ(cd::parseOiMode("full"), cd::OiMode::FULL);
  EXPECT_EQ(cd::parseOiMode("passive"), cd::OiMode::PASSIVE);
  EXPECT_EQ(cd::parseDriveCommand("radius"), cd::DriveCommandType::RADIUS);
  EXPECT_EQ(sl_testing::invalidArgumentOf([] { cd::parseModel("create_3"); }),
            "model must be create_1 or create_2 (got 'create_3')");
  EXPECT_EQ(sl_testing::invalidArgumentOf([] { cd::parseOiMode("off"); }).rfind("oi_mode must be", 0), 0u);
  EXPECT_EQ(sl_testing::invalidArgumentOf([] { cd::parseDriveCommand("fast"); }).rfind("drive_command must be", 0), 0u);
}
