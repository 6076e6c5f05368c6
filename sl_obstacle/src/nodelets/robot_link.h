// The obstacle node's side toward the robot: sends what the supervisor decided (cmd_vel, the
// drive_distance action, obstacle_status) and answers its questions from tf and the connections.
#pragma once

#include <memory>
#include <string>

#include <ros/node_handle.h>
#include <ros/publisher.h>
#include <geometry_msgs/Transform.h>
#include <std_msgs/Header.h>
#include <tf2_ros/buffer.h>

#include "drive_client.h"
#include "params.h"
#include "sl_msgs/ObstacleStatus.h"
#include "sl_obstacle/supervisor.h"

namespace sl_obstacle
{
/// The transform of @p header's frame into @p target at its stamp from @p tf; false with @p error
/// when tf does not know it.
bool transformAt(const tf2_ros::Buffer& tf, const std::string& target, const std_msgs::Header& header,
                 geometry_msgs::Transform& transform, std::string& error);

/// Carries out the supervisor's outputs, status and events (logged as @p name); the supervisor's
/// SupervisorSource.
class RobotLink : public SupervisorSource
{
public:
  /// Advertises `cmd_vel` and `obstacle_status` in @p nh and, in command_mode action, connects to
  /// `drive_distance`; the driver's results and feedback go to @p on_result and @p on_feedback (from
  /// actionlib's thread). @p params and @p tf must outlive this.
  RobotLink(ros::NodeHandle& nh, const std::string& name, const NodeletParams& params, const tf2_ros::Buffer& tf,
            const DriveClient::ResultCallback& on_result, const DriveClient::FeedbackCallback& on_feedback);

  /// Sends the outputs of @p actions in order, logs their events, then publishes the status they ask
  /// for, at @p now from @p sup
  /// (the newest cloud captured at @p cloud_stamp, the map's newest image at @p map_stamp).
  void send(const Actions& actions, const Supervisor& sup, const ros::Time& now, const ros::Time& cloud_stamp,
            const ros::Time& map_stamp);

  /// ~robot_frame in ~odom_frame, the newest transform.
  bool robotPose(Pose2D& pose, double& stamp) override;
  /// ~target_frame in ~odom_frame at the stamp of @p cloud (a sensor_msgs::PointCloud2::ConstPtr).
  bool volumePose(const CloudHandle& cloud, Pose2D& pose, std::string& error) override;
  /// The action server is connected (command_mode action), else someone subscribes cmd_vel.
  bool driverReady() override;

private:
  std::string name_;
  const NodeletParams& params_;
  const tf2_ros::Buffer& tf_;
  ros::Publisher cmd_vel_pub_;
  ros::Publisher status_pub_;
  std::unique_ptr<DriveClient> drive_;  // command_mode action
  DriveClient::ResultCallback on_result_;
  DriveClient::FeedbackCallback on_feedback_;
  sl_msgs::ObstacleStatus status_;
};
}  // namespace sl_obstacle
