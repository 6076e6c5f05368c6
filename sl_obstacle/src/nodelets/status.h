// The obstacle node's status message, filled from the core's results.
#pragma once

#include <string>

#include "sl_msgs/ObstacleStatus.h"
#include "sl_obstacle/decision_maker.h"
#include "sl_obstacle/supervisor.h"
#include "sl_obstacle/volume_checker.h"

namespace sl_obstacle
{
/// The working-volume check of the latest cloud: nearest obstacle, free distance (per sector),
/// point counts and coverage; with @p have_frame false (no cloud yet) nothing is known.
void fillCloudStatus(const VolumeResult& r, bool have_frame, sl_msgs::ObstacleStatus& s);

/// The map's part of the decision's input @p f (when @p mapped) and the travel to the nearest
/// occupied cell on the path @p map_obstacle (m); without the map: 0 known, obstacle at infinity.
void fillMapStatus(const FrameSummary& f, bool mapped, double map_obstacle, sl_msgs::ObstacleStatus& s);

/// The decision @p d: state, reason, command (autonomy; no teleoperation input).
void fillDecisionStatus(const Decision& d, sl_msgs::ObstacleStatus& s);

/// The whole status at @p now (header in @p frame) from @p sup: the newest cloud (captured at
/// @p cloud_stamp), the map (its newest image @p map_stamp) and, as @p kind says, the last decision
/// or the last safety-filter step.
void fillStatus(const Supervisor& sup, StatusKind kind, const ros::Time& now, const ros::Time& cloud_stamp,
                const ros::Time& map_stamp, const std::string& frame, sl_msgs::ObstacleStatus& s);
}  // namespace sl_obstacle
