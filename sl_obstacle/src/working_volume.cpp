#include "sl_obstacle/working_volume.h"

#include <cmath>

#include "validation.h"

namespace sl_obstacle
{
std::string WorkingVolume::validate() const
{
  using detail::complaint;
  std::string e;
  if (!(e = detail::inRange("width", width, 1e-3, 5.0)).empty() ||
      !(e = detail::inRange("height", height, 1e-3, 5.0)).empty() ||
      !(e = detail::inRange("depth", depth, 1e-3, 20.0)).empty() ||
      !(e = detail::inRange("floor_margin", floor_margin, 0.0, 1.0)).empty() ||
      !(e = detail::inRange("max_range", max_range, 1e-3, 20.0)).empty())
  {
    return e;
  }
  if (floor_margin >= height)
  {
    return complaint("floor_margin", "must be below height", floor_margin);
  }
  if (depth > max_range)
  {
    return complaint("depth", "must not exceed max_range", depth);
  }
  return std::string();
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
