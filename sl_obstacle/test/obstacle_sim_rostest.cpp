// Rostest client: the obstacle nodelet drives the simulated Create (create_sim + create_driver)
// toward a wall seen by the fake cloud source (fake_wall_cloud).
//
// The tests run in order on one simulated robot:
//  1. the robot starts driving toward the wall;
//  2. the cloud source stops: the status turns STALE and the robot stops early, short of its goal;
//  3. the source restarts and the robot drives on; then the wall is moved nearer: the running goal is
//     pre-empted (reason NEARER_OBSTACLE);
//  4. the robot stops before the wall, the status says why (BLOCKED, reason OBSTACLE, nearest distance
//     matching the true pose);
//  5. turning is enabled through dynamic_reconfigure: the robot turns in place, never touching the wall.
// Waits use generous wall-clock timeouts; nothing asserts how long anything took.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <mutex>
#include <string>

#include <dynamic_reconfigure/Reconfigure.h>
#include <geometry_msgs/PoseStamped.h>
#include <ros/ros.h>
#include <std_srvs/SetBool.h>
#include <tf2/utils.h>

#include "sl_msgs/ObstacleStatus.h"

namespace
{
using sl_msgs::ObstacleStatus;

class Observer
{
public:
  Observer()
  {
    ros::NodeHandle pnh("~");
    pnh.param("wall_x", wall_x, 1.0);
    pnh.param("robot_radius", robot_radius, 0.1675);
    pnh.param("edge_offset", edge_offset, 0.1675);
    status_sub_ = nh_.subscribe("obstacle_status", 50, &Observer::onStatus, this);
    pose_sub_ = nh_.subscribe("true_pose", 50, &Observer::onPose, this);
  }

  /// Waits until @p condition (called under the lock) holds; false on timeout.
  bool waitFor(const std::function<bool()>& condition, double timeout)
  {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout);
    while (ros::ok() && ros::WallTime::now() < end)
    {
      {
        std::lock_guard<std::mutex> lock(mutex);
        if (condition())
        {
          return true;
        }
      }
      ros::WallDuration(0.02).sleep();
    }
    return false;
  }

  /// Waits until the true pose has moved less than @p tolerance over @p window seconds.
  bool waitUntilStill(double window, double tolerance, double timeout)
  {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout);
    while (ros::ok() && ros::WallTime::now() < end)
    {
      double x0, y0, yaw0;
      {
        std::lock_guard<std::mutex> lock(mutex);
        x0 = x;
        y0 = y;
        yaw0 = yaw;
      }
      ros::WallDuration(window).sleep();
      std::lock_guard<std::mutex> lock(mutex);
      if (std::hypot(x - x0, y - y0) < tolerance && std::fabs(yaw - yaw0) < 0.02)
      {
        return true;
      }
    }
    return false;
  }

  std::mutex mutex;
  ObstacleStatus status;
  bool have_status = false;
  bool have_pose = false;
  double x = 0.0, y = 0.0, yaw = 0.0;
  double start_yaw = std::numeric_limits<double>::quiet_NaN();
  double max_extent_x = -std::numeric_limits<double>::infinity();  // max over time of x + radius
  bool saw_turning = false;
  bool saw_nearer = false;
  double wall_x = 1.0;
  double robot_radius = 0.1675;
  double edge_offset = 0.1675;

private:
  void onStatus(const ObstacleStatus::ConstPtr& msg)
  {
    std::lock_guard<std::mutex> lock(mutex);
    status = *msg;
    have_status = true;
    saw_turning = saw_turning || msg->state == ObstacleStatus::TURNING;
    saw_nearer = saw_nearer || msg->reason_code == ObstacleStatus::REASON_NEARER_OBSTACLE;
  }

  void onPose(const geometry_msgs::PoseStamped::ConstPtr& msg)
  {
    std::lock_guard<std::mutex> lock(mutex);
    x = msg->pose.position.x;
    y = msg->pose.position.y;
    yaw = tf2::getYaw(msg->pose.orientation);
    if (!have_pose)
    {
      start_yaw = yaw;
    }
    have_pose = true;
    max_extent_x = std::max(max_extent_x, x + robot_radius);
  }

  ros::NodeHandle nh_;
  ros::Subscriber status_sub_;
  ros::Subscriber pose_sub_;
};

Observer* observer = nullptr;

std::string describe(const ObstacleStatus& s)
{
  return "state " + std::to_string(s.state) + " reason_code " + std::to_string(s.reason_code) + " \"" + s.reason +
         "\" nearest " + std::to_string(s.nearest_distance) + " free " + std::to_string(s.free_distance) +
         " coverage " + std::to_string(s.coverage);
}

bool setCloudSource(bool enabled)
{
  std_srvs::SetBool srv;
  srv.request.data = enabled;
  if (!ros::service::waitForService("fake_wall_cloud/set_enabled", ros::Duration(30.0)))
  {
    return false;
  }
  return ros::service::call("fake_wall_cloud/set_enabled", srv) && srv.response.success;
}

TEST(ObstacleSim, A_DrivesTowardTheWall)
{
  Observer& o = *observer;
  ASSERT_TRUE(o.waitFor([&] { return o.have_pose && o.have_status; }, 120.0))
      << "no true_pose or obstacle_status (is create_sim running?)";
  ASSERT_TRUE(o.waitFor(
      [&] {
        return (o.status.state == ObstacleStatus::DRIVING || o.status.state == ObstacleStatus::SLOWING) && o.x > 0.03;
      },
      120.0))
      << "the robot did not start driving: " << describe(o.status) << ", x " << o.x;
  std::lock_guard<std::mutex> lock(o.mutex);
  ROS_INFO("A: driving at x %.3f: %s", o.x, describe(o.status).c_str());
  EXPECT_FALSE(o.status.blocked);
  EXPECT_GT(o.status.coverage, 0.5);
  EXPECT_FALSE(o.status.reason.empty());
}

TEST(ObstacleSim, B_StaleDataStopsTheRobot)
{
  Observer& o = *observer;
  ASSERT_TRUE(setCloudSource(false));
  ASSERT_TRUE(o.waitFor(
      [&]
      { return o.status.state == ObstacleStatus::STALE && o.status.reason_code == ObstacleStatus::REASON_STALE_DATA; },
      60.0))
      << "no STALE status after the clouds stopped: " << describe(o.status);
  {
    std::lock_guard<std::mutex> lock(o.mutex);
    EXPECT_NE(o.status.reason.find("no cloud"), std::string::npos) << o.status.reason;
    EXPECT_EQ(o.status.command, ObstacleStatus::COMMAND_STOP);
  }
  ASSERT_TRUE(o.waitUntilStill(1.5, 0.005, 60.0)) << "the robot did not stop on stale data";
  std::lock_guard<std::mutex> lock(o.mutex);
  ROS_INFO("B: stopped at x %.3f: %s", o.x, describe(o.status).c_str());
  EXPECT_EQ(o.status.state, ObstacleStatus::STALE) << describe(o.status);
  // It stopped well short of where its first goal would have ended (the front about 0.15 m from the
  // wall): the stop came from the stale data, not from the goal or the wall.
  EXPECT_LT(o.x + o.edge_offset, o.wall_x - 0.3) << "x " << o.x;
}

TEST(ObstacleSim, C_PreemptsTheGoalWhenTheWallComesNearer)
{
  Observer& o = *observer;
  double x_stopped;
  {
    std::lock_guard<std::mutex> lock(o.mutex);
    x_stopped = o.x;
    o.saw_nearer = false;
  }
  ASSERT_TRUE(setCloudSource(true));
  ASSERT_TRUE(o.waitFor(
      [&] { return o.status.reason_code == ObstacleStatus::REASON_GOAL_RUNNING && o.x > x_stopped + 0.01; }, 120.0))
      << "the robot did not drive on: " << describe(o.status) << ", x " << o.x;
  double new_wall;
  {
    std::lock_guard<std::mutex> lock(o.mutex);
    ASSERT_FALSE(o.saw_nearer);
    // 0.15 m nearer than the wall the running goal was planned for.
    new_wall = o.wall_x - 0.15;
    ASSERT_GT(new_wall, o.x + o.robot_radius + 0.3) << "the robot is already too close for this test";
    o.wall_x = new_wall;
  }
  ros::param::set("fake_wall_cloud/wall_x", new_wall);
  ASSERT_TRUE(o.waitFor([&] { return o.saw_nearer; }, 60.0))
      << "the running goal was not pre-empted: " << describe(o.status);
}

TEST(ObstacleSim, D_StopsBeforeTheWallAndSaysWhy)
{
  Observer& o = *observer;
  ASSERT_TRUE(o.waitFor(
      [&]
      {
        return o.status.state == ObstacleStatus::BLOCKED && o.status.blocked &&
               o.status.reason_code == ObstacleStatus::REASON_OBSTACLE;
      },
      180.0))
      << "the robot was not blocked by the wall: " << describe(o.status) << ", x " << o.x;
  ASSERT_TRUE(o.waitUntilStill(1.5, 0.005, 60.0)) << "the robot did not stop before the wall";
  std::lock_guard<std::mutex> lock(o.mutex);
  const double front = o.x + o.edge_offset;
  ROS_INFO("D: stopped at x %.3f (front %.3f, wall %.3f): %s", o.x, front, o.wall_x, describe(o.status).c_str());
  EXPECT_EQ(o.status.state, ObstacleStatus::BLOCKED) << describe(o.status);
  EXPECT_TRUE(o.status.blocked);
  EXPECT_NE(o.status.reason.find("obstacle at"), std::string::npos) << o.status.reason;
  EXPECT_EQ(o.status.command, ObstacleStatus::COMMAND_STOP);
  // Stopped before the wall, close to it (it did drive up), and the status matches the true distance.
  EXPECT_LT(front, o.wall_x - 0.05) << "front edge at " << front;
  EXPECT_GT(front, o.wall_x - 0.35) << "front edge at " << front;
  EXPECT_NEAR(o.status.nearest_distance, o.wall_x - front, 0.03) << describe(o.status);
  EXPECT_LT(o.max_extent_x, o.wall_x) << "the robot touched the wall";
}

TEST(ObstacleSim, E_TurnsInPlaceWhenAllowed)
{
  Observer& o = *observer;
  dynamic_reconfigure::Reconfigure srv;
  dynamic_reconfigure::IntParameter turns;
  turns.name = "max_turns";
  turns.value = 12;
  srv.request.config.ints.push_back(turns);
  ASSERT_TRUE(ros::service::waitForService("obstacle/set_parameters", ros::Duration(30.0)));
  ASSERT_TRUE(ros::service::call("obstacle/set_parameters", srv));
  double yaw_before;
  {
    std::lock_guard<std::mutex> lock(o.mutex);
    yaw_before = o.yaw;
  }
  ASSERT_TRUE(o.waitFor([&] { return o.saw_turning; }, 60.0)) << "no TURNING state: " << describe(o.status);
  ASSERT_TRUE(o.waitFor([&] { return std::fabs(std::remainder(o.yaw - yaw_before, 2.0 * M_PI)) > 0.3; }, 120.0))
      << "the robot did not turn: yaw " << o.yaw << " before " << yaw_before;
  std::lock_guard<std::mutex> lock(o.mutex);
  ROS_INFO("E: yaw %.3f (before %.3f), x %.3f, farthest extent %.3f: %s", o.yaw, yaw_before, o.x, o.max_extent_x,
           describe(o.status).c_str());
  // The wall (x = wall_x, the fake cloud's only obstacle; no scene, no camera simulator) is an
  // infinite plane: the disc's clearance to it is exactly wall_x - max(x + radius).
  ROS_INFO("min clearance %.4f m (wall at x = %.3f)", o.wall_x - o.max_extent_x, o.wall_x);
  EXPECT_LT(o.max_extent_x, o.wall_x) << "the robot touched the wall";
}
}  // namespace

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "obstacle_sim_rostest");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  Observer o;
  observer = &o;
  const int result = RUN_ALL_TESTS();
  observer = nullptr;
  spinner.stop();
  return result;
}
