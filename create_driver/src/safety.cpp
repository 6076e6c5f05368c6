#include "create_driver/safety.h"

#include <algorithm>
#include <cmath>

#include "create_driver/oi_commands.h"

namespace create_driver
{
namespace
{
constexpr double kEpsLinear = 1e-4;   // m/s
constexpr double kEpsAngular = 1e-4;  // rad/s

// Moves current towards target by at most max_step; a negative max_step means no limit.
double moveTowards(double current, double target, double max_step)
{
  if (max_step < 0.0)
    return target;
  return current + std::clamp(target - current, -max_step, max_step);
}
}  // namespace

bool isFiniteCommand(double linear, double angular)
{
  return std::isfinite(linear) && std::isfinite(angular);
}

void clampTwist(const VelocityLimits& limits, double& linear, double& angular)
{
  linear = std::clamp(linear, -limits.max_speed, limits.max_speed);
  angular = std::clamp(angular, -limits.max_angular_speed, limits.max_angular_speed);
}

WheelSpeeds twistToWheels(double linear, double angular, double wheel_base, double max_wheel_speed)
{
  WheelSpeeds w;
  w.left = linear - 0.5 * angular * wheel_base;
  w.right = linear + 0.5 * angular * wheel_base;
  const double largest = std::max(std::fabs(w.left), std::fabs(w.right));
  if (largest > max_wheel_speed && largest > 0.0)
  {
    const double k = max_wheel_speed / largest;
    w.left *= k;
    w.right *= k;
  }
  return w;
}

DriveRadius twistToDriveRadius(double linear, double angular, double wheel_base, double max_wheel_speed)
{
  DriveRadius d;
  const WheelSpeeds w = twistToWheels(linear, angular, wheel_base, max_wheel_speed);
  const double v = 0.5 * (w.left + w.right);
  const double omega = (w.right - w.left) / wheel_base;
  if (std::fabs(omega) < kEpsAngular)
  {
    d.velocity_mm_s = static_cast<int>(std::lround(v * 1000.0));
    d.radius_mm = oi::RADIUS_STRAIGHT;
    return d;
  }
  if (std::fabs(v) < kEpsLinear)
  {
    d.velocity_mm_s = static_cast<int>(std::lround(std::fabs(w.right) * 1000.0));
    d.radius_mm = omega > 0.0 ? oi::RADIUS_TURN_CCW : oi::RADIUS_TURN_CW;
    return d;
  }
  const double radius_mm = v / omega * 1000.0;
  d.velocity_mm_s = static_cast<int>(std::lround(v * 1000.0));
  if (std::fabs(radius_mm) > oi::MAX_RADIUS_MM)
    d.radius_mm = oi::RADIUS_STRAIGHT;
  else if (std::fabs(radius_mm) < 1.5)
  {
    // Rounds to the special values +-1: turn in place at the outer wheel speed instead.
    d.velocity_mm_s = static_cast<int>(std::lround(std::max(std::fabs(w.left), std::fabs(w.right)) * 1000.0));
    d.radius_mm = omega > 0.0 ? oi::RADIUS_TURN_CCW : oi::RADIUS_TURN_CW;
  }
  else
    d.radius_mm = static_cast<int>(std::lround(radius_mm));
  return d;
}

VelocityLimiter::VelocityLimiter(const VelocityLimits& limits) : limits_(limits) {}

void VelocityLimiter::reset(double linear, double angular)
{
  linear_ = linear;
  angular_ = angular;
}

void VelocityLimiter::limit(double target_linear, double target_angular, double dt, double& linear, double& angular)
{
  clampTwist(limits_, target_linear, target_angular);
  dt = std::max(0.0, dt);
  linear_ = moveTowards(linear_, target_linear, limits_.max_accel > 0.0 ? limits_.max_accel * dt : -1.0);
  angular_ =
      moveTowards(angular_, target_angular, limits_.max_angular_accel > 0.0 ? limits_.max_angular_accel * dt : -1.0);
  linear = linear_;
  angular = angular_;
}

const char* hazardName(Hazard hazard)
{
  switch (hazard)
  {
    case Hazard::NONE:
      return "none";
    case Hazard::BUMPER:
      return "bumper";
    case Hazard::CLIFF:
      return "cliff";
    case Hazard::WHEEL_DROP:
      return "wheel drop";
  }
  return "unknown";
}

Hazard currentHazard(const SensorState& state)
{
  if (state.anyWheelDrop())
    return Hazard::WHEEL_DROP;
  if (state.anyCliff())
    return Hazard::CLIFF;
  if (state.anyBump())
    return Hazard::BUMPER;
  return Hazard::NONE;
}

bool HazardLatch::update(const SensorState& state, bool backing)
{
  const Hazard now = currentHazard(state);
  if (now != Hazard::NONE)
  {
    if (static_cast<int>(now) > static_cast<int>(reason_))
    {
      reason_ = now;
      return true;
    }
    return false;
  }
  // Sensors are clear: a backing-away manoeuvre releases a bumper or cliff latch.
  if (backing && (reason_ == Hazard::BUMPER || reason_ == Hazard::CLIFF))
    reason_ = Hazard::NONE;
  return false;
}

bool HazardLatch::allows(double linear) const
{
  if (reason_ == Hazard::NONE)
    return true;
  if (reason_ == Hazard::WHEEL_DROP)
    return false;
  return linear < 0.0;
}

bool HazardLatch::reset(const SensorState& state, std::string* why)
{
  const Hazard now = currentHazard(state);
  if (now != Hazard::NONE)
  {
    if (why)
      *why = std::string(hazardName(now)) + " still active";
    return false;
  }
  reason_ = Hazard::NONE;
  return true;
}

}  // namespace create_driver
