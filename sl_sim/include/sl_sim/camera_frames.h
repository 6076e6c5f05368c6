#pragma once
/// @file camera_frames.h
/// @brief What the simulated camera decides per frame, without ROS: the default poses when tf has
/// none, the noise seed of a frame and the stamp of an exposure.

#include <cstdint>

#include <Eigen/Geometry>

#include "sl_rig/rig.h"

namespace sl_sim
{

/// @brief The robot (base footprint) in the world without tf: platform_edge at the world origin, so
/// the robot's centre lies @p robot_radius (m) behind it on the x axis.
Eigen::Isometry3d defaultRobotInWorld(double robot_radius);

/// @brief The camera's optical frame in the robot's base frame without tf: the rig's mount, placed
/// at platform_edge (@p robot_radius, m, ahead of the base frame's origin).
Eigen::Isometry3d defaultCameraInBase(const sl_projector::Rig& rig, double robot_radius);

/// @brief The noise seed of frame @p frame for the user's seed @p seed (>= 0): a different seed every
/// frame, the same sequence for the same @p seed.
std::uint64_t frameSeed(int seed, std::uint64_t frame);

/**
 * @brief Chooses the stamp of each rendered image: the time of the robot pose it is rendered from
 * (so that a consumer's tf lookup at the stamp finds the pose of the exposure), or now when that
 * pose is missing, from the future, older than kMaxPoseAge or not newer than the last stamp given.
 * Stamps never go back. Times are nanoseconds since the clock's epoch; 0 means no pose.
 */
class ExposureStamper
{
public:
  /// The oldest pose whose time is still used, ns (0.2 s).
  static constexpr std::int64_t kMaxPoseAge = 200000000;

  /// @brief The stamp of an image rendered at @p now_ns from a pose of time @p pose_ns (0: none).
  std::int64_t stamp(std::int64_t pose_ns, std::int64_t now_ns);

private:
  std::int64_t last_ = 0;
};

}  // namespace sl_sim
