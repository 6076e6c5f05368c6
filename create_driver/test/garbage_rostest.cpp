// Done-when: garbage injected on the line is counted and survived (no reconnect, frames keep
// flowing, a distance goal still ends on target).
#include <gtest/gtest.h>

#include <actionlib/client/simple_action_client.h>
#include <std_srvs/Trigger.h>

#include <sl_msgs/DriveDistanceAction.h>

#include <sl_testing/rostest_main.h>

#include "rostest_helpers.h"

using namespace test_helpers;

TEST(Garbage, CountedAndSurvived)
{
  ros::NodeHandle nh;
  System sys(nh);
  ASSERT_TRUE(sys.waitRunning());
  const uint32_t connects0 = sys.mode.get().connects;
  double corrupt0 = 0, valid0 = 0;
  ASSERT_TRUE(sys.diag("Sensor stream", "corrupt frames", &corrupt0));
  ASSERT_TRUE(sys.diag("Sensor stream", "valid frames", &valid0));

  double corrupt = corrupt0;
  int injections = 0;
  // Inject until the corruption shows up in the diagnostics (each injection corrupts a frame).
  ASSERT_TRUE(waitUntil(
      [&]
      {
        if (injections < 50)
        {
          std_srvs::Trigger t;
          if (ros::service::call("create_sim/inject_garbage", t) && t.response.success)
            ++injections;
        }
        return diagValue(sys.diagnostics.get(), "Sensor stream", "corrupt frames", &corrupt) && corrupt > corrupt0;
      }))
      << "garbage not counted";
  EXPECT_GE(injections, 1);

  // Frames keep flowing and the link never dropped.
  double valid = valid0;
  ASSERT_TRUE(waitUntil(
      [&]
      { return diagValue(sys.diagnostics.get(), "Sensor stream", "valid frames", &valid) && valid > valid0 + 100; }));
  EXPECT_EQ(sys.mode.get().connects, connects0) << "garbage caused a reconnect";
  EXPECT_EQ(sys.mode.get().link_state, create_driver::Mode::LINK_RUNNING);

  // Still drives accurately.
  actionlib::SimpleActionClient<sl_msgs::DriveDistanceAction> client("drive_distance", true);
  ASSERT_TRUE(client.waitForServer(ros::Duration(kTimeout)));
  ASSERT_TRUE(sys.waitWheelsStopped());
  ASSERT_TRUE(sys.pose.waitMore(5));
  const double x0 = sys.pose.get().pose.position.x;
  sl_msgs::DriveDistanceGoal g;
  g.distance = 0.3;
  g.speed = 0.2;
  client.sendGoal(g);
  ASSERT_TRUE(client.waitForResult(ros::Duration(kTimeout)));
  EXPECT_EQ(client.getState(), actionlib::SimpleClientGoalState::SUCCEEDED);
  ASSERT_TRUE(sys.waitWheelsStopped());
  ASSERT_TRUE(sys.pose.waitMore(10));
  EXPECT_NEAR(sys.pose.get().pose.position.x - x0, 0.3, 0.005);
}

int main(int argc, char** argv)
{
  return sl_testing::runRostests(argc, argv, "garbage_test");
}
