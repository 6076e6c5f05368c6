// Reads a sensor_msgs/PointCloud2 into the core's points, applying a rigid transform.
#pragma once

#include <string>
#include <vector>

#include <geometry_msgs/Transform.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Header.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/message_filter.h>

#include "sl_msgs/ray_ends.h"
#include "sl_obstacle/local_map.h"
#include "sl_obstacle/point.h"
#include "sl_obstacle/world_model.h"

namespace sl_obstacle
{
/// Converts @p cloud (fields x, y, z as FLOAT32 or FLOAT64; optional `confidence`) into @p points,
/// transformed by @p transform (cloud frame -> working-volume frame). NaN/inf stay NaN/inf (the
/// checker counts them). @p points keeps its capacity between calls.
/// @return empty on success, otherwise a description of what is wrong with the cloud.
std::string convertCloud(const sensor_msgs::PointCloud2& cloud, const geometry_msgs::Transform& transform,
                         std::vector<Point>& points);

/// Why a tf2 message filter dropped a cloud, e.g. "older than the tf buffer".
const char* toString(tf2_ros::FilterFailureReason reason);

/// The planar part of @p t: translation x, y and the yaw of its rotation.
Pose2D toPose2D(const geometry_msgs::Transform& t);

/// Ray states of sl_decoder's `ray_ends` cloud (field `state`, UINT8), as sl_msgs/ray_ends.h defines them.
constexpr std::uint8_t kRayDecoded = sl_msgs::ray_ends::DECODED, kRayFloor = sl_msgs::ray_ends::FLOOR,
                       kRayDark = sl_msgs::ray_ends::DARK, kRayLit = sl_msgs::ray_ends::LIT,
                       kRayUnseen = sl_msgs::ray_ends::UNSEEN;

/// Appends the rays of one of the decoder's clouds to @p rays, transformed by @p transform (cloud
/// frame -> map frame). Every point needs x, y, z (the ray's end) and sx, sy, sz (the start of its
/// free part). The decoder's `points` (@p ray_ends false) become Hit rays; `ray_ends` (true) need
/// a UINT8 `state`: floor and dark become Free rays, lit Suspect rays, unseen ones are skipped.
/// Rays with NaN/inf coordinates are skipped. @return empty on success, else what is wrong (the
/// cloud adds nothing then, or only the rays read before the error).
std::string appendRays(const sensor_msgs::PointCloud2& cloud, const geometry_msgs::Transform& transform, bool ray_ends,
                       std::vector<MapRay>& rays);

/// The map rays of one image into @p rays (cleared first): its ray ends @p ray_ends and, when not
/// null and in the same frame, its decoded @p points, transformed by @p transform (appendRays()).
/// @return empty, or why the ray ends were refused (then nothing is to be inserted); @p points_error:
/// why the points added nothing (the ray ends are kept).
std::string imageRays(const sensor_msgs::PointCloud2& ray_ends, const sensor_msgs::PointCloud2* points,
                      const geometry_msgs::Transform& transform, std::vector<MapRay>& rays, std::string& points_error);
}  // namespace sl_obstacle
