/// @file working_volume.h
/// @brief The box the robot sweeps when it drives forward, and the sensor range.
#pragma once

#include "sl_obstacle/point.h"

namespace sl_obstacle
{
/// Geometry of the working volume in the platform_edge frame (all in metres).
///
/// The box spans 0 < x <= depth, -width/2 <= y <= width/2, floor_margin <= z <= height (faces
/// inclusive). Points with z < floor_margin are floor, never obstacles. Points with x > max_range are
/// not trusted and ignored. The working window is the y-z rectangle width x height in front of the
/// robot; coverage is measured on it.
struct WorkingVolume
{
  double width = 0.331;         ///< W: lateral extent, centred on y = 0 (m)
  double height = 0.173;        ///< H: top of the box above the floor (m)
  double depth = 0.8;           ///< B: pass-through depth, extent of the box along x (m)
  double floor_margin = 0.015;  ///< points below this height are floor (m)
  double max_range = 1.0;       ///< points farther than this along x are ignored (m)

  /// Checks the values. @throws std::invalid_argument when invalid, with a message that starts with
  /// the name of the offending parameter (e.g. "width must be in [0.001, 5] (got -0.1)").
  void validate() const;

  /// True when the point lies inside the box (faces inclusive; x = 0 excluded). NaN is never inside.
  bool contains(const Point& p) const;

  /// True when the point's (y, z) lies in the working window (|y| <= W/2, -floor_margin <= z <= H).
  bool inWindow(const Point& p) const;
};
}  // namespace sl_obstacle
