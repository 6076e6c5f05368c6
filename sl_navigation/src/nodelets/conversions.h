// Conversions between the navigation core's types and ROS messages (no state, no ROS node).
#pragma once

#include <string>
#include <vector>

#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/OccupancyGrid.h>
#include <nav_msgs/Path.h>
#include <ros/time.h>
#include <sl_msgs/NavigationStatus.h>

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
}  // namespace sl_navigation
