#include "sl_obstacle/settings.h"

#include "validation.h"

namespace sl_obstacle
{
std::string Settings::validate() const
{
  std::string e = checker.validate();
  if (e.empty())
  {
    e = decision.validate();
  }
  if (e.empty())
  {
    e = world.validate();
  }
  if (e.empty())
  {
    e = filter.validate();
  }
  if (e.empty())
  {
    e = detail::inRange("teleop_hold", teleop_hold, 0.0, 60.0);
  }
  if (!e.empty())
  {
    return e;
  }
  if (decision.safety_margin + decision.min_goal_distance >= checker.volume.depth)
  {
    return detail::complaint("safety_margin", "+ min_goal_distance must be below depth", decision.safety_margin);
  }
  if (decision.slow_distance > checker.volume.depth)
  {
    return detail::complaint("slow_distance", "must not exceed depth", decision.slow_distance);
  }
  return std::string();
}
}  // namespace sl_obstacle
