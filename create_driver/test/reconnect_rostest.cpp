// Done-when: closing and reopening the pty leads to a reconnect and a stop. The robot keeps its
// last command while the line is down (like an unplugged cable); after the reconnect the driver
// has re-sent Start, Safe and a stop, and does not resume the old cmd_vel.
#include <gtest/gtest.h>

#include <atomic>

#include <std_srvs/Trigger.h>

#include <sl_testing/rostest_main.h>

#include "rostest_helpers.h"

using namespace test_helpers;

TEST(Reconnect, ReopenedPtyReconnectsAndStops)
{
  ros::NodeHandle nh;
  System sys(nh);
  std::atomic<bool> saw_down{ false };
  sys.mode.setHook(
      [&](const create_driver::Mode& m)
      {
        if (m.link_state != create_driver::Mode::LINK_RUNNING)
          saw_down = true;
      });
  ASSERT_TRUE(sys.waitRunning());
  saw_down = false;
  const uint32_t connects0 = sys.mode.get().connects;
  const uint32_t opens0 = sys.status.get().pty_opens;

  // One command: the robot drives until the command watchdog (command_timeout) or the reconnect
  // stops it (the reconnect's own stop, before the watchdog's time: driver_sim_loop_test).
  ASSERT_TRUE(sys.driveUntil(0.1, 0.0, [&] { return sys.wheels() > 0.05; }));

  std_srvs::Trigger reopen;
  ASSERT_TRUE(ros::service::call("create_sim/reopen", reopen));
  ASSERT_TRUE(reopen.response.success);

  ASSERT_TRUE(waitUntil([&] { return saw_down.load(); })) << "driver never noticed the link going down";
  ASSERT_TRUE(waitUntil(
      [&]
      {
        const auto m = sys.mode.get();
        return m.connects > connects0 && m.link_state == create_driver::Mode::LINK_RUNNING;
      }))
      << "no reconnect";
  EXPECT_GT(sys.status.get().pty_opens, opens0);

  // Reconnected: Start + Safe + stop were sent.
  ASSERT_TRUE(waitUntil(
      [&]
      {
        const auto s = sys.status.get();
        return s.mode == create_driver::Mode::SAFE && sys.wheels() == 0.0;
      }))
      << "robot not stopped in Safe mode after the reconnect";
  EXPECT_EQ(sys.maxWheelOver(15), 0.0) << "the old cmd_vel was resumed";

  double disconnects = 0;
  ASSERT_TRUE(sys.diag("Connection", "disconnects", &disconnects));
  EXPECT_GE(disconnects, 1.0);

  // Still drivable afterwards.
  ASSERT_TRUE(sys.driveUntil(0.1, 0.0, [&] { return sys.wheels() > 0.05; }));
  geometry_msgs::Twist stop;
  sys.cmd_pub.publish(stop);
  ASSERT_TRUE(sys.driveUntil(0.0, 0.0, [&] { return sys.wheels() == 0.0; }));
}

TEST(Reconnect, PowerCycledRobotIsRestarted)
{
  ros::NodeHandle nh;
  System sys(nh);
  ASSERT_TRUE(sys.waitRunning());
  // The robot drops to Off and stops streaming: the link times out and the start sequence is
  // sent again.
  std_srvs::Trigger power;
  ASSERT_TRUE(ros::service::call("create_sim/power_cycle", power));
  ASSERT_TRUE(waitUntil([&] { return sys.status.get().mode == create_driver::Mode::OFF; }));
  ASSERT_TRUE(waitUntil(
      [&]
      {
        const auto s = sys.status.get();
        return s.mode == create_driver::Mode::SAFE && s.streaming;
      }))
      << "driver did not restart a power-cycled robot";
  ASSERT_TRUE(sys.waitRunning());
}

int main(int argc, char** argv)
{
  return sl_testing::runRostests(argc, argv, "reconnect_test");
}
