// Done-when: cmd_vel drives the simulated robot over the pty and the watchdog stops it.
#include <gtest/gtest.h>

#include <limits>

#include <nav_msgs/Odometry.h>

#include <sl_testing/rostest_main.h>

#include "rostest_helpers.h"

using namespace test_helpers;

TEST(CmdVelWatchdog, DrivesThenWatchdogStops)
{
  ros::NodeHandle nh;
  System sys(nh);
  Latest<nav_msgs::Odometry> odom(nh, "odom");
  ASSERT_TRUE(sys.waitRunning()) << "driver never reached a running link with the robot in Safe mode";
  ASSERT_TRUE(odom.waitMore(1));
  const double x0 = sys.pose.get().pose.position.x;
  const double odom0 = odom.get().pose.pose.position.x;

  // Drive while commands keep coming.
  ASSERT_TRUE(sys.driveUntil(0.2, 0.0, [&] { return sys.pose.get().pose.position.x > x0 + 0.08; }))
      << "the robot did not move under cmd_vel";
  EXPECT_NEAR(sys.status.get().left_wheel_velocity, 0.2, 0.01);
  EXPECT_GT(odom.get().pose.pose.position.x - odom0, 0.05) << "odometry did not follow";

  // Stop publishing: the watchdog must stop the wheels.
  ASSERT_TRUE(sys.waitWheelsStopped(30.0)) << "wheels still turning after cmd_vel stopped";
  // And they stay stopped.
  EXPECT_EQ(sys.maxWheelOver(15), 0.0);
  double stops = 0;
  ASSERT_TRUE(sys.diag("Control loop", "watchdog stops", &stops));
  EXPECT_GE(stops, 1.0);
  EXPECT_TRUE(waitUntil(
      [&]
      {
        double n = 0;
        return diagValue(sys.diagnostics.get(), "Commands", "cmd_vel watchdog stops", &n) && n >= 1.0;
      }))
      << "the watchdog stop is not in the diagnostics";

  // At rest, odometry matches the true displacement (no slip or noise configured).
  ASSERT_TRUE(odom.waitMore(5));
  EXPECT_NEAR(odom.get().pose.pose.position.x - odom0, sys.pose.get().pose.position.x - x0, 0.003);
}

TEST(CmdVelWatchdog, NonFiniteCommandsAreRejected)
{
  ros::NodeHandle nh;
  System sys(nh);
  ASSERT_TRUE(sys.waitRunning());
  ASSERT_TRUE(sys.waitWheelsStopped());
  double rejected0 = 0;
  ASSERT_TRUE(sys.diag("Control loop", "rejected commands", &rejected0));
  geometry_msgs::Twist t;
  t.linear.x = std::numeric_limits<double>::quiet_NaN();
  t.angular.z = 0.5;
  const double worst = sys.maxWheelOver(15, [&] { sys.cmd_pub.publish(t); });
  EXPECT_EQ(worst, 0.0) << "a NaN command moved the wheels";
  EXPECT_TRUE(waitUntil(
      [&]
      {
        double r = 0;
        return diagValue(sys.diagnostics.get(), "Control loop", "rejected commands", &r) && r > rejected0;
      }))
      << "rejected commands not counted";
}

int main(int argc, char** argv)
{
  return sl_testing::runRostests(argc, argv, "cmd_vel_watchdog_test");
}
