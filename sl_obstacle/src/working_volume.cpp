#include "sl_obstacle/working_volume.h"

#include <cmath>

#include "validation.h"

namespace sl_obstacle
{
void WorkingVolume::validate() const
{
  using detail::requireInRange;
  requireInRange("width", width, 1e-3, 5.0);
  requireInRange("height", height, 1e-3, 5.0);
  requireInRange("depth", depth, 1e-3, 20.0);
  requireInRange("floor_margin", floor_margin, 0.0, 1.0);
  requireInRange("max_range", max_range, 1e-3, 20.0);
  if (floor_margin >= height)
  {
    detail::refuse("floor_margin", "must be below height", floor_margin);
  }
  if (depth > max_range)
  {
    detail::refuse("depth", "must not exceed max_range", depth);
  }
}

bool WorkingVolume::contains(const Point& p) const
{
  const double half = 0.5 * width;
  // Written so that NaN compares false everywhere.
  return p.x > 0.0 && p.x <= depth && p.y >= -half && p.y <= half && p.z >= floor_margin && p.z <= height;
}

bool WorkingVolume::inWindow(const Point& p) const
{
  const double half = 0.5 * width;
  return p.y >= -half && p.y <= half && p.z >= -floor_margin && p.z <= height;
}
}  // namespace sl_obstacle
