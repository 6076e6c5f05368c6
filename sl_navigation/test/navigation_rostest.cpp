// The navigation nodelet against bad and good goals, without a simulator: an all-free local map
// around the robot and a fixed odometry pose, published here.
#include <cmath>
#include <limits>
#include <mutex>
#include <string>

#include <actionlib/client/simple_action_client.h>
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/TwistStamped.h>
#include <gtest/gtest.h>
#include <move_base_msgs/MoveBaseAction.h>
#include <nav_msgs/OccupancyGrid.h>
#include <ros/ros.h>
#include <sl_msgs/NavigationStatus.h>
#include <sl_testing/rostest_main.h>
#include <sl_testing/wait.h>
#include <tf2_ros/transform_broadcaster.h>

namespace
{
using Client = actionlib::SimpleActionClient<move_base_msgs::MoveBaseAction>;

class NavigationNodelet : public ::testing::Test
{
protected:
  void SetUp() override
  {
    map_pub_ = nh_.advertise<nav_msgs::OccupancyGrid>("local_map", 1, true);
    goal_pub_ = nh_.advertise<geometry_msgs::PoseStamped>("move_base_simple/goal", 1);
    cmd_sub_ = nh_.subscribe<geometry_msgs::TwistStamped>("cmd_vel_in_stamped", 50,
                                                          [this](const geometry_msgs::TwistStamped::ConstPtr& m) {
                                                            std::lock_guard<std::mutex> lock(mutex_);
                                                            ++commands_;
                                                            last_cmd_ = *m;
                                                            max_linear_ = std::max(max_linear_, m->twist.linear.x);
                                                          });
    status_sub_ = nh_.subscribe<sl_msgs::NavigationStatus>("navigation_status", 50,
                                                           [this](const sl_msgs::NavigationStatus::ConstPtr& m) {
                                                             std::lock_guard<std::mutex> lock(mutex_);
                                                             status_ = *m;
                                                             ++statuses_;
                                                           });
    timer_ = nh_.createTimer(ros::Duration(0.05), [this](const ros::TimerEvent&) { publishWorld(); });
    client_ = std::make_unique<Client>("move_base", true);
    ASSERT_TRUE(client_->waitForServer(ros::Duration(30.0))) << "no move_base action server";
    ASSERT_TRUE(sl_testing::waitUntil(
        [this] {
          std::lock_guard<std::mutex> lock(mutex_);
          return statuses_ > 0;
        },
        30.0))
        << "no navigation_status";
  }

  void TearDown() override
  {
    timer_.stop();
    cmd_sub_.shutdown();
    status_sub_.shutdown();
  }

  /// odom -> base_link at the origin, and every second an all-free 4 x 4 m local map.
  void publishWorld()
  {
    geometry_msgs::TransformStamped t;
    t.header.stamp = ros::Time::now();
    t.header.frame_id = "odom";
    t.child_frame_id = "base_link";
    t.transform.rotation.w = 1.0;
    tf_.sendTransform(t);
    if ((ros::Time::now() - map_sent_).toSec() >= 1.0)
    {
      nav_msgs::OccupancyGrid m;
      m.header.stamp = ros::Time::now();
      m.header.frame_id = "odom";
      m.info.resolution = 0.02f;
      m.info.width = m.info.height = 200;
      m.info.origin.position.x = m.info.origin.position.y = -2.0;
      m.info.origin.orientation.w = 1.0;
      m.data.assign(200 * 200, 0);
      map_pub_.publish(m);
      map_sent_ = ros::Time::now();
    }
  }

  /// Sends @p goal through the action; @return its final state within @p timeout s.
  actionlib::SimpleClientGoalState sendAction(double x, double y, const std::string& frame, double timeout)
  {
    move_base_msgs::MoveBaseGoal goal;
    goal.target_pose.header.frame_id = frame;
    goal.target_pose.header.stamp = ros::Time::now();
    goal.target_pose.pose.position.x = x;
    goal.target_pose.pose.position.y = y;
    client_->sendGoal(goal);
    client_->waitForResult(ros::Duration(timeout));
    return client_->getState();
  }

  ros::NodeHandle nh_;
  ros::Publisher map_pub_, goal_pub_;
  ros::Subscriber cmd_sub_, status_sub_;
  ros::Timer timer_;
  tf2_ros::TransformBroadcaster tf_;
  ros::Time map_sent_;
  std::unique_ptr<Client> client_;
  std::mutex mutex_;
  int commands_ = 0;
  double max_linear_ = 0.0;
  geometry_msgs::TwistStamped last_cmd_;
  sl_msgs::NavigationStatus status_;
  int statuses_ = 0;
};

TEST_F(NavigationNodelet, RefusesBadGoalsWithTheirReasonAndNoMotion)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  struct Case
  {
    double x, y;
    std::string frame, why;
  };
  for (const Case& c : { Case{ nan, 0.0, "odom", "not finite" }, Case{ 1.0, 0.0, "nowhere", "cannot transform" },
                         Case{ 50.0, 0.0, "odom", "outside the map" } })
  {
    const auto state = sendAction(c.x, c.y, c.frame, 5.0);
    EXPECT_EQ(state, actionlib::SimpleClientGoalState::ABORTED) << c.why;
    EXPECT_NE(state.getText().find(c.why), std::string::npos) << state.getText();
  }
  std::lock_guard<std::mutex> lock(mutex_);
  EXPECT_EQ(max_linear_, 0.0);  // never a command that moves
  EXPECT_EQ(status_.state, sl_msgs::NavigationStatus::ABORTED);
}

TEST_F(NavigationNodelet, DrivesToAGoalAndStopsWhenCancelled)
{
  move_base_msgs::MoveBaseGoal goal;
  goal.target_pose.header.frame_id = "odom";
  goal.target_pose.pose.position.x = 1.2;
  client_->sendGoal(goal);
  ASSERT_TRUE(sl_testing::waitUntil(
      [this] {
        std::lock_guard<std::mutex> lock(mutex_);
        return last_cmd_.twist.linear.x > 0.0;
      },
      10.0))
      << "no forward command toward a goal 1.2 m ahead on a free map";
  client_->cancelGoal();
  ASSERT_TRUE(client_->waitForResult(ros::Duration(5.0)));
  EXPECT_EQ(client_->getState(), actionlib::SimpleClientGoalState::PREEMPTED);
  ros::Duration(0.3).sleep();
  std::lock_guard<std::mutex> lock(mutex_);
  EXPECT_EQ(last_cmd_.twist.linear.x, 0.0);  // the last command is a stop
  EXPECT_EQ(last_cmd_.twist.angular.z, 0.0);
  EXPECT_EQ(status_.state, sl_msgs::NavigationStatus::CANCELLED);
}

TEST_F(NavigationNodelet, ASimpleGoalPreemptsTheActionGoal)
{
  move_base_msgs::MoveBaseGoal goal;
  goal.target_pose.header.frame_id = "odom";
  goal.target_pose.pose.position.x = 1.5;
  client_->sendGoal(goal);
  ros::Duration(0.5).sleep();
  geometry_msgs::PoseStamped simple;
  simple.header.frame_id = "odom";
  simple.pose.position.y = 1.0;
  goal_pub_.publish(simple);
  ASSERT_TRUE(client_->waitForResult(ros::Duration(5.0)));
  EXPECT_EQ(client_->getState(), actionlib::SimpleClientGoalState::PREEMPTED);
  ASSERT_TRUE(sl_testing::waitUntil(
      [this] {
        std::lock_guard<std::mutex> lock(mutex_);
        return status_.state == sl_msgs::NavigationStatus::ACTIVE && std::abs(status_.goal.pose.position.y - 1.0) < 1e-9;
      },
      5.0));
}
}  // namespace

int main(int argc, char** argv)
{
  return sl_testing::runRostests(argc, argv, "navigation_rostest");
}
