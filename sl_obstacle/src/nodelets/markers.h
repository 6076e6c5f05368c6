// rviz markers of the obstacle node: the working volume and what the check found in it.
#pragma once

#include <string>
#include <vector>

#include <ros/time.h>
#include <visualization_msgs/MarkerArray.h>

#include "sl_obstacle/point.h"
#include "sl_obstacle/volume_checker.h"
#include "sl_obstacle/working_volume.h"

namespace sl_obstacle
{
/// Fills @p out with six markers in @p frame at @p stamp: [0] the box of @p v (red when @p blocked,
/// green otherwise), [1] the nearest obstacle point, [2] the accepted obstacle points and [3] the
/// in-box points rejected as noise (of @p points, as @p r indexes them), [4] the free distance of
/// each sector on the floor; [5] is left for the caller (the safety filter's footprint), with the
/// common header fields set.
void volumeMarkers(const VolumeResult& r, const WorkingVolume& v, const std::vector<Point>& points, bool blocked,
                   const std::string& frame, const ros::Time& stamp, visualization_msgs::MarkerArray& out);

/// Turns POINTS markers without points into DELETE (rviz draws nothing for them then).
void deleteEmptyPointMarkers(visualization_msgs::MarkerArray& markers);
}  // namespace sl_obstacle
