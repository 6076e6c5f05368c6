// Done-when: a contact (camera simulator's topic) stops the robot and latches until
// reset_hazard or a backing-away command; a goal ends with BUMPER.
#include <gtest/gtest.h>

#include <actionlib/client/simple_action_client.h>
#include <std_msgs/UInt8.h>
#include <std_srvs/Trigger.h>

#include <sl_msgs/DriveDistanceAction.h>

#include <sl_testing/rostest_main.h>

#include "rostest_helpers.h"

using namespace test_helpers;

namespace
{
void setContact(ros::Publisher& pub, uint8_t bits)
{
  std_msgs::UInt8 m;
  m.data = bits;
  pub.publish(m);
}
}  // namespace

TEST(ContactLatch, ContactStopsAndLatchesUntilReset)
{
  ros::NodeHandle nh;
  System sys(nh);
  ros::Publisher contact = nh.advertise<std_msgs::UInt8>("contact", 10, true);
  ASSERT_TRUE(sys.waitRunning());
  ASSERT_TRUE(waitUntil([&] { return contact.getNumSubscribers() > 0; }));

  ASSERT_TRUE(sys.driveUntil(0.15, 0.0, [&] { return sys.wheels() > 0.1; })) << "robot did not start";
  setContact(contact, 1);  // right bumper
  // Keep commanding forward: the latch must win.
  ASSERT_TRUE(sys.driveUntil(0.15, 0.0,
                             [&]
                             {
                               const auto h = sys.hazards.get();
                               return h.latched && h.bump_right && sys.wheels() == 0.0;
                             }))
      << "contact did not stop and latch";
  EXPECT_EQ(sys.hazards.get().latch_reason, sl_msgs::Hazards::LATCH_BUMPER);

  // Contact released: still latched, forward commands still do nothing.
  setContact(contact, 0);
  ASSERT_TRUE(sys.driveUntil(0.15, 0.0, [&] { return !sys.hazards.get().bump_right; }));
  geometry_msgs::Twist fwd;
  fwd.linear.x = 0.15;
  EXPECT_EQ(sys.maxWheelOver(15, [&] { sys.cmd_pub.publish(fwd); }), 0.0) << "moved while latched";
  EXPECT_TRUE(sys.hazards.get().latched);

  std_srvs::Trigger reset;
  ASSERT_TRUE(ros::service::call("reset_hazard", reset));
  EXPECT_TRUE(reset.response.success) << reset.response.message;
  ASSERT_TRUE(sys.driveUntil(0.15, 0.0, [&] { return sys.wheels() > 0.1; })) << "no motion after reset";
  EXPECT_TRUE(waitUntil([&] { return !sys.hazards.get().latched; }));
  ASSERT_TRUE(sys.waitWheelsStopped());
}

TEST(ContactLatch, ResetRefusedWhilePressedAndBackingAwayReleases)
{
  ros::NodeHandle nh;
  System sys(nh);
  ros::Publisher contact = nh.advertise<std_msgs::UInt8>("contact", 10, true);
  ASSERT_TRUE(sys.waitRunning());
  ASSERT_TRUE(waitUntil([&] { return contact.getNumSubscribers() > 0; }));
  setContact(contact, 2);  // left bumper
  ASSERT_TRUE(waitUntil([&] { return sys.hazards.get().latched && sys.hazards.get().bump_left; }));
  std_srvs::Trigger reset;
  ASSERT_TRUE(ros::service::call("reset_hazard", reset));
  EXPECT_FALSE(reset.response.success) << "reset accepted while the bumper is pressed";

  // Back away: allowed while latched; once the bumper is free the latch clears.
  const double x0 = sys.pose.get().pose.position.x;
  ASSERT_TRUE(sys.driveUntil(-0.1, 0.0, [&] { return sys.pose.get().pose.position.x < x0 - 0.01; }))
      << "backing away was blocked";
  setContact(contact, 0);
  ASSERT_TRUE(sys.driveUntil(-0.1, 0.0, [&] { return !sys.hazards.get().latched; }));
  ASSERT_TRUE(sys.waitWheelsStopped());
}

TEST(ContactLatch, GoalEndsWithBumper)
{
  ros::NodeHandle nh;
  System sys(nh);
  ros::Publisher contact = nh.advertise<std_msgs::UInt8>("contact", 10, true);
  actionlib::SimpleActionClient<sl_msgs::DriveDistanceAction> client("drive_distance", true);
  ASSERT_TRUE(sys.waitRunning());
  ASSERT_TRUE(client.waitForServer(ros::Duration(kTimeout)));
  ASSERT_TRUE(waitUntil([&] { return !sys.hazards.get().latched; }));
  const double x0 = sys.pose.get().pose.position.x;
  sl_msgs::DriveDistanceGoal g;
  g.distance = 1.0;
  g.speed = 0.2;
  client.sendGoal(g);
  ASSERT_TRUE(waitUntil([&] { return sys.pose.get().pose.position.x > x0 + 0.05; }));
  setContact(contact, 3);
  ASSERT_TRUE(client.waitForResult(ros::Duration(kTimeout)));
  EXPECT_EQ(client.getState(), actionlib::SimpleClientGoalState::ABORTED);
  EXPECT_EQ(client.getResult()->reason, sl_msgs::DriveDistanceResult::BUMPER);
  EXPECT_TRUE(sys.waitWheelsStopped());
  setContact(contact, 0);
}

int main(int argc, char** argv)
{
  return sl_testing::runRostests(argc, argv, "contact_latch_test");
}
