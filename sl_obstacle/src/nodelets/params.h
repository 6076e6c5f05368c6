// Parameters of the sl_obstacle/obstacle nodelet: read and validated in one place.
#pragma once

#include <string>

#include <ros/node_handle.h>

#include "sl_obstacle/ObstacleConfig.h"
#include "sl_obstacle/settings.h"
#include "sl_obstacle/supervisor.h"  // CommandMode

namespace sl_obstacle
{
/// Everything the nodelet reads from its private namespace.
struct NodeletParams
{
  std::string target_frame = "platform_edge";      ///< ~target_frame: frame of the working volume
  std::string odom_frame = "odom";                 ///< ~odom_frame: frame the local map is kept in
  std::string robot_frame = "base_link";           ///< ~robot_frame: centre of the robot's disc
  CommandMode command_mode = CommandMode::ACTION;  ///< ~command_mode: "action", "cmd_vel" or "filter"
  double control_rate = 10.0;                      ///< ~control_rate: decision steps per second without clouds (Hz)
  double map_rate = 5.0;                           ///< ~map_rate: local_map messages per second at most (Hz)
  ObstacleConfig config;                           ///< the reconfigurable parameters (same names as in Obstacle.cfg)
  Settings settings;                               ///< config converted to the core's parameter structs
};

/// Converts the reconfigurable parameters into the core's settings (no validation).
Settings toSettings(const ObstacleConfig& config);

/// True if @p a and @p b differ in a value the local map depends on (geometry, decay, footprint,
/// headings, the height band).
bool changesWorld(const ObstacleConfig& a, const ObstacleConfig& b);

/// Checks a reconfigurable configuration: every value inside its Obstacle.cfg range and the core's
/// rules (Settings::validate). @throws std::invalid_argument "<name> ..." naming the parameter.
void validateConfig(const ObstacleConfig& config);

/// Why a reconfiguration from @p old to @p config is refused (validateConfig(), or a parameter read
/// at start-up only that changed); empty when it is accepted.
std::string reconfigureError(const ObstacleConfig& config, const ObstacleConfig& old);

/// Reads every private parameter of @p pnh (defaults from Obstacle.cfg), checks types, ranges and
/// relations. @throws std::invalid_argument with a message "parameter ~<name>: ..." on the first
/// invalid value.
NodeletParams loadParams(const ros::NodeHandle& pnh);
}  // namespace sl_obstacle
