// Reading the navigation nodelet's parameters (one place; each value typed and range-checked).
#pragma once

#include <string>

#include <ros/node_handle.h>

#include "sl_navigation/coverage_planner.h"

namespace sl_navigation
{
/// Everything the nodelet reads from its private namespace.
struct NodeParams
{
  NavigatorParams navigator;
  std::string odom_frame = "odom";  ///< the map's frame; goals are transformed into it
  std::string robot_frame = "base_link";
  double control_rate = 20.0;       ///< Hz of the control loop (commands on cmd_vel_in_stamped)
  double pose_timeout = 0.5;        ///< s: an odom -> base_link older than this stops the robot
  double map_publish_period = 1.0;  ///< s between nav_map and coverage messages (while subscribed)
  bool cover = false;               ///< ~behaviour cover or roam: the CoverageRunner instead of goals (navigate)
  CoverageParams coverage;          ///< the cleaning or exploring targets (coverage.roam: behaviour roam)
  std::string coverage_png;         ///< cover: the map with the coverage written here at the end (empty: none)
};

/// Reads and checks the parameters. @throws std::invalid_argument naming the parameter.
NodeParams readParams(const ros::NodeHandle& pnh);
}  // namespace sl_navigation
