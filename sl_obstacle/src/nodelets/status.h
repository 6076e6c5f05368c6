// The obstacle node's status message, filled from the core's results.
#pragma once

#include "sl_msgs/ObstacleStatus.h"
#include "sl_obstacle/decision_maker.h"
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
}  // namespace sl_obstacle
