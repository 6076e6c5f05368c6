// The create_sim nodelet's messages, made from the simulated robot.
#pragma once

#include <cstdint>
#include <string>

#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>

#include "create_driver/SimStatus.h"
#include "create_driver/sim_robot.h"

namespace create_driver
{
/// The true pose @p p in @p world_frame.
geometry_msgs::PoseStamped poseMessage(const Pose2D& p, const ros::Time& stamp, const std::string& world_frame);

/// The transform world -> @p robot_frame of a pose message.
geometry_msgs::TransformStamped poseTransform(const geometry_msgs::PoseStamped& pose, const std::string& robot_frame);

/// The status of @p robot behind the pty @p pty_path ("" while closed), opened @p pty_opens times.
SimStatus statusMessage(const SimRobot& robot, const std::string& pty_path, uint32_t pty_opens, const ros::Time& stamp,
                        const std::string& robot_frame);
}  // namespace create_driver
