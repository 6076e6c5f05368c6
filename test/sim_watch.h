// What the closed-loop system tests (closed_loop_rostest.cpp, room_rostest.cpp) watch while the
// simulation runs. Ground truth comes from the simulators, not from the system under test:
// create_sim's true pose (true_pose) and the camera simulator's bumper contact (contact), plus the
// driver's hazards and the obstacle node's decisions (obstacle_status).
#pragma once

#include <cmath>
#include <mutex>
#include <string>

#include <geometry_msgs/PoseStamped.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sl_msgs/Hazards.h>
#include <sl_obstacle/ObstacleStatus.h>
#include <std_msgs/UInt8.h>

#include <sl_testing/rostest_main.h>

namespace sl_bringup_test
{

/// A private parameter of the test node, or @p fallback.
inline double privateParam(const std::string& name, double fallback)
{
  double v = fallback;
  ros::param::get("~" + name, v);
  return v;
}

/// Yaw of a pose that only turns about z, rad.
inline double yawOf(const geometry_msgs::Pose& p)
{
  return 2.0 * std::atan2(p.orientation.z, p.orientation.w);
}

/// |@p a - @p b| of two yaws, wrapped to [0, pi], rad.
inline double yawDifference(double a, double b)
{
  return std::abs(std::remainder(a - b, 2.0 * M_PI));
}

/// How far the robot turned from pose @p b to pose @p a, in [0, pi], rad.
inline double turnBetween(const geometry_msgs::Pose& a, const geometry_msgs::Pose& b)
{
  return yawDifference(yawOf(a), yawOf(b));
}

/// Distance between the positions of two poses in the x-y plane, m.
inline double stepBetween(const geometry_msgs::Pose& a, const geometry_msgs::Pose& b)
{
  return std::hypot(a.position.x - b.position.x, a.position.y - b.position.y);
}

/**
 * Base fixture: subscribes the four topics, keeps the latest true pose, counts contact and hazard
 * messages, ORs the contact bits and latches a bumper. Subclasses see every pose and decision in
 * onPose() and onStatus(), which run with mutex_ held, as must every read of the members.
 */
class SimWatch : public ::testing::Test
{
protected:
  void SetUp() override
  {
    pose_sub_ = nh_.subscribe("true_pose", 100, &SimWatch::poseCallback, this);
    contact_sub_ = nh_.subscribe("contact", 50, &SimWatch::contactCallback, this);
    hazards_sub_ = nh_.subscribe("hazards", 50, &SimWatch::hazardsCallback, this);
    status_sub_ = nh_.subscribe("obstacle_status", 100, &SimWatch::statusCallback, this);
  }

  void TearDown() override
  {
    // No callback may run on the fixture once it is being destroyed.
    pose_sub_.shutdown();
    contact_sub_.shutdown();
    hazards_sub_.shutdown();
    status_sub_.shutdown();
  }

  /// A new true pose; @p previous is null for the first one. pose_ is updated after the call.
  virtual void onPose(const geometry_msgs::Pose* previous, const geometry_msgs::Pose& now) = 0;
  /// A decision of the obstacle node.
  virtual void onStatus(const sl_obstacle::ObstacleStatus& msg) = 0;

  /// Waits up to @p seconds for the system: a true pose and a decision. Call without mutex_ held.
  /// @return true when both arrived.
  bool waitForSystem(double seconds)
  {
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(seconds);
    while (ros::ok() && ros::WallTime::now() < deadline)
    {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (have_pose_ && status_messages_ > 0)
          return true;
      }
      ros::WallDuration(0.1).sleep();
    }
    std::lock_guard<std::mutex> lock(mutex_);
    return have_pose_ && status_messages_ > 0;
  }

  std::mutex mutex_;
  int status_messages_ = 0;
  bool have_pose_ = false;
  geometry_msgs::Pose pose_;
  int contact_messages_ = 0;
  int contact_bits_ = 0;  // OR of every contact message
  int hazard_messages_ = 0;
  bool bumped_ = false;

private:
  void poseCallback(const geometry_msgs::PoseStamped& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    onPose(have_pose_ ? &pose_ : nullptr, msg.pose);
    have_pose_ = true;
    pose_ = msg.pose;
  }

  void contactCallback(const std_msgs::UInt8& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++contact_messages_;
    if (msg.data != 0 && contact_bits_ == 0)
      ROS_ERROR("contact %d at (%.3f, %.3f)", msg.data, pose_.position.x, pose_.position.y);
    contact_bits_ |= msg.data;
  }

  void hazardsCallback(const sl_msgs::Hazards& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++hazard_messages_;
    bumped_ = bumped_ || msg.bump_left || msg.bump_right;
  }

  void statusCallback(const sl_obstacle::ObstacleStatus& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++status_messages_;
    onStatus(msg);
  }

  ros::NodeHandle nh_;
  ros::Subscriber pose_sub_, contact_sub_, hazards_sub_, status_sub_;
};

}  // namespace sl_bringup_test
