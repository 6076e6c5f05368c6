// Conversions between the navigation core's types and ROS messages (no state, no ROS node).
#pragma once

#include <string>
#include <vector>

#include <actionlib/server/simple_action_server.h>
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TwistStamped.h>
#include <move_base_msgs/MoveBaseAction.h>
#include <nav_msgs/OccupancyGrid.h>
#include <nav_msgs/Path.h>
#include <ros/time.h>
#include <sl_msgs/NavigationStatus.h>
#include <tf2_ros/buffer.h>

#include "sl_navigation/navigator.h"

namespace sl_navigation
{
/// A view of @p msg's cells (valid while @p msg lives). @return false when its data size does not
/// match width * height.
bool toView(const nav_msgs::OccupancyGrid& msg, OccupancyView& view);

/// The plan as a path in @p frame.
nav_msgs::Path toPath(const std::vector<Point>& points, const std::string& frame, const ros::Time& stamp);

/// The navigator's step as a status message.
sl_msgs::NavigationStatus toStatus(const NavOutput& out, const geometry_msgs::PoseStamped& goal,
                                   const std::string& frame, const ros::Time& stamp);

/// The persistent map as an OccupancyGrid in @p frame.
void toGrid(const NavGrid& grid, double now, const std::string& frame, const ros::Time& stamp,
            nav_msgs::OccupancyGrid& msg);

/// A planar pose in @p frame.
geometry_msgs::PoseStamped toPoseStamped(const Pose& pose, const std::string& frame, const ros::Time& stamp);

/// A goal pose (already in the map frame) as a NavGoal; a quaternion far from unit length (e.g. all
/// zero) means "no heading".
NavGoal toNavGoal(const geometry_msgs::PoseStamped& goal);

/// @p goal in @p frame at the latest transform (a goal is a place, not a moment). @return false,
/// with the reason in @p why, when tf cannot transform it.
bool transformGoal(const tf2_ros::Buffer& tf, const geometry_msgs::PoseStamped& goal, const std::string& frame,
                   geometry_msgs::PoseStamped& out, std::string& why);

/// A velocity command in @p frame.
geometry_msgs::TwistStamped toTwist(double linear, double angular, const std::string& frame, const ros::Time& stamp);

/// The latest @p odom -> @p robot transform as a pose. @return false, with the reason in @p why,
/// when there is none or it is older than @p timeout (s).
bool lookupPose(const tf2_ros::Buffer& tf, const std::string& odom, const std::string& robot, double timeout,
                Pose& pose, std::string& why);

using ActionServer = actionlib::SimpleActionServer<move_base_msgs::MoveBaseAction>;
/// Ends @p action's active goal as the navigator's @p out ended (SUCCEEDED, CANCELLED: pre-empted,
/// else aborted), with its reason; nothing when no goal is active.
void finishAction(ActionServer& action, const NavOutput& out);
}  // namespace sl_navigation
