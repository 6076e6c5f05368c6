// ROS messages of the safety filter: the status fields and the predicted footprint marker.
#pragma once

#include <visualization_msgs/Marker.h>

#include "sl_msgs/ObstacleStatus.h"
#include "sl_obstacle/safety_filter.h"

namespace sl_obstacle
{
using sl_msgs::ObstacleStatus;  // the status message lives in sl_msgs (shared with the tests and tools)

/// A geometry_msgs::Point (for marker vertices).
geometry_msgs::Point point(double x, double y, double z);

/// Fills the decision part of @p status (state, reason, command, filter fields) from one filter step
/// on the command @p input.
void fillFilterStatus(const FilterOutput& out, const Velocity& input, ObstacleStatus& status);

/// The footprint the output command sweeps before it must stop (the disc centre's arc over the
/// known-free travel beyond the clearance, and the disc of @p radius where it ends), as a LINE_LIST
/// in the frame of @p pose (the map's). Header, namespace and id are left to the caller.
void footprintMarker(const FilterOutput& out, const Pose2D& pose, double radius, visualization_msgs::Marker& marker);
}  // namespace sl_obstacle
