// Reads a sensor_msgs/PointCloud2 into the core's points, applying a rigid transform.
#ifndef SL_OBSTACLE_NODELETS_CLOUD_CONVERSION_H
#define SL_OBSTACLE_NODELETS_CLOUD_CONVERSION_H

#include <string>
#include <vector>

#include <geometry_msgs/Transform.h>
#include <sensor_msgs/PointCloud2.h>

#include "sl_obstacle/point.h"

namespace sl_obstacle
{
/// Converts @p cloud (fields x, y, z as FLOAT32 or FLOAT64; optional `confidence`) into @p points,
/// transformed by @p transform (cloud frame -> working-volume frame). NaN/inf stay NaN/inf (the
/// checker counts them). @p points keeps its capacity between calls.
/// @return empty on success, otherwise a description of what is wrong with the cloud.
std::string convertCloud(const sensor_msgs::PointCloud2& cloud, const geometry_msgs::Transform& transform,
                         std::vector<Point>& points);
}  // namespace sl_obstacle

#endif  // SL_OBSTACLE_NODELETS_CLOUD_CONVERSION_H
