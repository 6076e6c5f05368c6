#include "sl_obstacle/settings.h"

#include "validation.h"

namespace sl_obstacle
{
void Settings::validate() const
{
  checker.validate();
  decision.validate();
  world.validate();
  filter.validate();
  detail::requireInRange("teleop_hold", teleop_hold, 0.0, 60.0);
  if (decision.safety_margin + decision.min_goal_distance >= checker.volume.depth)
  {
    detail::refuse("safety_margin", "+ min_goal_distance must be below depth", decision.safety_margin);
  }
  if (decision.slow_distance > checker.volume.depth)
  {
    detail::refuse("slow_distance", "must not exceed depth", decision.slow_distance);
  }
}
}  // namespace sl_obstacle
