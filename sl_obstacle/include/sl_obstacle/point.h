/// @file point.h
/// @brief The point type the core library works on.
#pragma once

namespace sl_obstacle
{
/// One measured point in the working-volume frame (platform_edge: x forward, y left, z up, metres,
/// origin on the floor at the robot's front edge), with the decoder's confidence.
struct Point
{
  float x = 0.0F;           ///< forward distance from the front edge (m)
  float y = 0.0F;           ///< lateral offset, positive to the left (m)
  float z = 0.0F;           ///< height above the floor (m)
  float confidence = 1.0F;  ///< decoder confidence; 1 when the cloud has no confidence field
};

/// Builds a point; convenience for tests and conversions.
inline Point makePoint(float x, float y, float z, float confidence = 1.0F)
{
  Point p;
  p.x = x;
  p.y = y;
  p.z = z;
  p.confidence = confidence;
  return p;
}
}  // namespace sl_obstacle
