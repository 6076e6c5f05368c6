#include "sl_obstacle/velocity_goal.h"

#include <algorithm>
#include <cmath>

namespace sl_obstacle
{
void VelocityGoal::start(double distance, double speed, double now)
{
  active_ = distance != 0.0 && std::isfinite(distance) && speed > 0.0;
  distance_ = distance;
  speed_ = speed;
  travelled_ = 0.0;
  last_ = now;
}

void VelocityGoal::stop()
{
  active_ = false;
}

bool VelocityGoal::update(double now, double max_step)
{
  if (!active_)
  {
    return false;
  }
  const double dt = std::min(std::max(now - last_, 0.0), max_step);
  last_ = std::max(last_, now);
  travelled_ += speed_ * dt;
  if (travelled_ >= std::abs(distance_))
  {
    travelled_ = std::abs(distance_);
    active_ = false;
    return true;
  }
  return false;
}
}  // namespace sl_obstacle
