// The decoder's clouds (points, ray_ends), filled from the core's results.
#pragma once

#include <vector>

#include <Eigen/Geometry>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Header.h>

#include "sl_decoder/decoder.h"
#include "sl_decoder/ray_classifier.h"

namespace sl_decoder
{
/// The points cloud: x, y, z, confidence, row, col, u, v and the projector centre sx, sy, sz (where
/// the free part of each decoded ray starts) of every valid blob of @p result, moved by
/// @p to_target. @p organized: one point per primitive of the @p rows x @p cols pattern, NaN where
/// none was decoded; otherwise the valid points only. @p header: the stamp and the target frame.
sensor_msgs::PointCloud2Ptr toPointsCloud(const DecodeResult& result, const Eigen::Isometry3d& to_target,
                                          const Eigen::Vector3d& projector_centre, int rows, int cols, bool organized,
                                          const std_msgs::Header& header);

/// The ray_ends cloud (layout: sl_msgs/ray_ends.h): one point per ray of @p outcomes (one per
/// primitive of a pattern of @p cols columns) that was not decoded (@p decoded rays are left out),
/// moved by @p to_target.
sensor_msgs::PointCloud2Ptr toRayEndsCloud(const std::vector<RayOutcome>& outcomes, int decoded,
                                           const Eigen::Isometry3d& to_target, int cols,
                                           const std_msgs::Header& header);
}  // namespace sl_decoder
