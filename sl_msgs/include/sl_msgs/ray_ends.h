/// @file ray_ends.h
/// @brief The layout of the decoder's `ray_ends` cloud (sensor_msgs/PointCloud2): one point per
/// projector ray that was not decoded. Plain C++ (no ROS): the decoder writes the cloud with it, the
/// obstacle node reads the state values (it finds the fields by name).
#pragma once

#include <cstddef>
#include <cstdint>

namespace sl_msgs
{
namespace ray_ends
{
/// Values of the UINT8 field `state`: what the ray says about the space it crosses.
enum State : std::uint8_t
{
  DECODED = 0,  ///< decoded (in the `points` cloud, never in `ray_ends`)
  FLOOR = 1,    ///< its light is where it meets the floor: free up to there
  DARK = 2,     ///< no light on the checked part: free from the start to the end
  LIT = 3,      ///< unexplained light that may be its own: free up to a suspect end
  UNSEEN = 4    ///< nothing of it could be checked (NaN coordinates)
};

/// One point of the cloud: the ray's end and the start of its free part (FLOAT32, m, in the
/// cloud's frame), the state, and the primitive's pattern row and column (UINT16).
struct Point
{
  float x, y, z;     ///< end
  float sx, sy, sz;  ///< start of the free part
  std::uint8_t state;
  std::uint8_t reserved0;
  std::uint16_t row, col;
  std::uint16_t reserved1;
};
static_assert(sizeof(Point) == 32, "ray_ends point_step is 32 bytes");

constexpr std::uint32_t kPointStep = sizeof(Point);
constexpr std::uint32_t kStateOffset = offsetof(Point, state);
constexpr std::uint32_t kRowOffset = offsetof(Point, row);
constexpr std::uint32_t kColOffset = offsetof(Point, col);
}  // namespace ray_ends
}  // namespace sl_msgs
