// Done-when: drive_distance of 0.5 m over the pty ends within 5 mm of the goal (true pose from
// create_sim); pre-emption stops the wheels; a new goal replaces the old one; bad goals are
// rejected.
#include <gtest/gtest.h>

#include <actionlib/client/simple_action_client.h>

#include <sl_msgs/DriveDistanceAction.h>

#include <sl_testing/rostest_main.h>

#include "rostest_helpers.h"

using namespace test_helpers;
using Client = actionlib::SimpleActionClient<sl_msgs::DriveDistanceAction>;
using sl_msgs::DriveDistanceGoal;
using sl_msgs::DriveDistanceResult;

namespace
{
DriveDistanceGoal goal(double d, double v)
{
  DriveDistanceGoal g;
  g.distance = d;
  g.speed = v;
  return g;
}

// Waits until the robot is commanded to stop and the true pose has settled.
double restingX(System& sys)
{
  EXPECT_TRUE(sys.waitWheelsStopped());
  EXPECT_TRUE(sys.pose.waitMore(10));
  return sys.pose.get().pose.position.x;
}

/// The system and a client of drive_distance, both up (the driver running, the server there).
class DriveDistance : public testing::Test
{
protected:
  void SetUp() override
  {
    ASSERT_TRUE(sys.waitRunning());
    ASSERT_TRUE(client.waitForServer(ros::Duration(kTimeout)));
  }

  ros::NodeHandle nh;
  System sys{ nh };
  Client client{ "drive_distance", true };
};
}  // namespace

TEST_F(DriveDistance, HalfMetreWithin5mm)
{
  for (const double d : { 0.5, -0.5 })
  {
    const double x0 = restingX(sys);
    client.sendGoal(goal(d, 0.2));
    ASSERT_TRUE(client.waitForResult(ros::Duration(kTimeout)));
    EXPECT_EQ(client.getState(), actionlib::SimpleClientGoalState::SUCCEEDED) << client.getState().getText();
    const auto r = client.getResult();
    EXPECT_EQ(r->reason, DriveDistanceResult::REACHED) << r->message;
    EXPECT_NEAR(r->distance_travelled, d, 0.005);
    const double x1 = restingX(sys);
    ROS_INFO("drive_distance %+.3f m: reported %+.4f m, true displacement %+.4f m (error %+.1f mm)", d,
             r->distance_travelled, x1 - x0, 1000.0 * (x1 - x0 - d));
    EXPECT_NEAR(x1 - x0, d, 0.005) << "true displacement off the goal";
  }
}

TEST_F(DriveDistance, CancelStopsWheels)
{
  const double x0 = restingX(sys);
  client.sendGoal(goal(2.0, 0.2));
  ASSERT_TRUE(waitUntil([&] { return sys.pose.get().pose.position.x > x0 + 0.05; })) << "goal did not start";
  client.cancelGoal();
  ASSERT_TRUE(client.waitForResult(ros::Duration(kTimeout)));
  EXPECT_EQ(client.getState(), actionlib::SimpleClientGoalState::PREEMPTED);
  EXPECT_EQ(client.getResult()->reason, DriveDistanceResult::PREEMPTED);
  EXPECT_GT(client.getResult()->distance_travelled, 0.04);
  EXPECT_TRUE(sys.waitWheelsStopped(10.0)) << "wheels not stopped after cancel";
}

TEST_F(DriveDistance, HeartbeatLossStopsAndAborts)
{
  const double x0 = restingX(sys);
  client.sendGoal(goal(2.0, 0.2));
  ASSERT_TRUE(waitUntil([&] { return sys.pose.get().pose.position.x > x0 + 0.05; })) << "goal did not start";
  sys.heartbeat.pause(true);  // the client freezes
  const double x_frozen = sys.pose.get().pose.position.x;
  ASSERT_TRUE(client.waitForResult(ros::Duration(kTimeout)));
  sys.heartbeat.pause(false);
  EXPECT_EQ(client.getState(), actionlib::SimpleClientGoalState::ABORTED);
  EXPECT_EQ(client.getResult()->reason, DriveDistanceResult::HEARTBEAT_LOST) << client.getResult()->message;
  const double x1 = restingX(sys);
  ROS_INFO("heartbeat stopped at 0.2 m/s: %.3f m after (command_timeout 0.25 s)", x1 - x_frozen);
  EXPECT_LT(x1 - x_frozen, 0.2 * 0.3 + 0.03) << "driven on without a heartbeat";
  EXPECT_TRUE(waitUntil(
      [&]
      {
        double stops = 0;
        return diagValue(sys.diagnostics.get(), "Commands", "heartbeat stops", &stops) && stops >= 1.0;
      }))
      << "the heartbeat stop is not in the diagnostics";
}

TEST_F(DriveDistance, NewGoalReplacesOld)
{
  Client second("drive_distance", true);
  ASSERT_TRUE(second.waitForServer(ros::Duration(kTimeout)));
  const double x0 = restingX(sys);
  client.sendGoal(goal(2.0, 0.2));
  ASSERT_TRUE(waitUntil([&] { return sys.pose.get().pose.position.x > x0 + 0.05; }));
  second.sendGoal(goal(-0.1, 0.1));
  ASSERT_TRUE(client.waitForResult(ros::Duration(kTimeout)));
  EXPECT_EQ(client.getState(), actionlib::SimpleClientGoalState::PREEMPTED);
  EXPECT_EQ(client.getResult()->reason, DriveDistanceResult::PREEMPTED);
  ASSERT_TRUE(second.waitForResult(ros::Duration(kTimeout)));
  EXPECT_EQ(second.getState(), actionlib::SimpleClientGoalState::SUCCEEDED);
  EXPECT_NEAR(second.getResult()->distance_travelled, -0.1, 0.005);
}

TEST_F(DriveDistance, InvalidGoalsRejected)
{
  for (const auto& g : { goal(0.5, 0.0), goal(0.5, -0.1), goal(std::numeric_limits<double>::quiet_NaN(), 0.1) })
  {
    client.sendGoal(g);
    ASSERT_TRUE(client.waitForResult(ros::Duration(kTimeout)));
    EXPECT_EQ(client.getState(), actionlib::SimpleClientGoalState::REJECTED);
    EXPECT_EQ(client.getResult()->reason, DriveDistanceResult::INVALID_GOAL);
  }
}

int main(int argc, char** argv)
{
  return sl_testing::runRostests(argc, argv, "drive_distance_test");
}
