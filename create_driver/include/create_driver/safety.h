/// @file safety.h
/// @brief Velocity limits, twist-to-OI conversions and the hazard latch (the driver's control).
#pragma once

#include <string>

#include "create_driver/sensor_packets.h"

namespace create_driver
{
/// Limits applied to every motion command (SI units).
struct VelocityLimits
{
  double max_speed = 0.5;          ///< m/s, |linear|
  double max_angular_speed = 4.0;  ///< rad/s, |angular|
  double max_accel = 1.0;          ///< m/s^2, |d linear / dt| (0 = unlimited)
  double max_angular_accel = 6.0;  ///< rad/s^2, |d angular / dt| (0 = unlimited)
  double max_wheel_speed = 0.5;    ///< m/s, per wheel (the OI accepts 500 mm/s)
  double wheel_base = 0.258;       ///< m
};

/// A Drive command in OI units.
struct DriveRadius
{
  int velocity_mm_s = 0;
  int radius_mm = 0;  ///< may be one of the special radii
};

/// @brief True when both values are finite (not NaN, not infinite).
bool isFiniteCommand(double linear, double angular);

/// @brief Clamps linear and angular speed to the limits (no acceleration limit).
void clampTwist(const VelocityLimits& limits, double& linear, double& angular);

/// @brief Wheel speeds of a twist; if a wheel would exceed @p max_wheel_speed both are scaled
/// down by the same factor, so the path curvature is kept.
WheelSpeeds twistToWheels(double linear, double angular, double wheel_base, double max_wheel_speed);

/// @brief Drive velocity/radius of a twist, using the special radii: straight when the turn is
/// negligible or the radius exceeds 2 m, turn in place when the linear speed is negligible.
/// Wheel speeds are kept within @p max_wheel_speed like twistToWheels().
DriveRadius twistToDriveRadius(double linear, double angular, double wheel_base, double max_wheel_speed);

/// @brief Rate limiter on linear and angular velocity.
class VelocityLimiter
{
public:
  /// @brief Creates a limiter at rest.
  explicit VelocityLimiter(const VelocityLimits& limits = VelocityLimits());
  /// @brief Replaces the limits.
  void setLimits(const VelocityLimits& limits) { limits_ = limits; }
  /// @brief Forces the current output (e.g. to 0 for an emergency stop that bypasses ramps).
  void reset(double linear = 0.0, double angular = 0.0);
  /// @brief Moves the output towards the (clamped) target by at most accel * dt.
  void limit(double target_linear, double target_angular, double dt, double& linear, double& angular);
  /// @brief Current output linear speed.
  double linear() const { return linear_; }
  /// @brief Current output angular speed.
  double angular() const { return angular_; }

private:
  VelocityLimits limits_;
  double linear_ = 0.0;
  double angular_ = 0.0;
};

/// Hazards, in increasing severity.
enum class Hazard : uint8_t
{
  NONE = 0,
  BUMPER = 1,
  CLIFF = 2,
  WHEEL_DROP = 3
};

/// @brief Name of a hazard ("none", "bumper", "cliff", "wheel drop").
const char* hazardName(Hazard hazard);

/// @brief Worst hazard present in a sensor state (packets 7 and 9..12).
Hazard currentHazard(const SensorState& state);

/// @brief Latches bump, cliff and wheel-drop events until they are explicitly cleared.
///
/// Once set, commands that move forward or turn in place are blocked. A backing-away command
/// (linear < 0) is allowed for a bumper or cliff latch (not for a wheel drop); the latch clears
/// itself when such a command is executing and the sensors read clear. reset() clears it when no
/// hazard is present.
class HazardLatch
{
public:
  /// @brief Feeds the current sensor reading.
  /// @param backing true if the command being executed drives backwards
  /// @return true if the latch was newly set (or worsened) by this reading
  bool update(const SensorState& state, bool backing);
  /// @brief True while the latch is set.
  bool latched() const { return reason_ != Hazard::NONE; }
  /// @brief Worst hazard seen since the latch was set.
  Hazard reason() const { return reason_; }
  /// @brief Whether a command with this linear speed may be executed.
  bool allows(double linear) const;
  /// @brief Clears the latch if no hazard is present in @p state.
  /// @param why set to the blocking hazard on failure
  bool reset(const SensorState& state, std::string* why);
  /// @brief Clears unconditionally (used when the link restarts).
  void clear() { reason_ = Hazard::NONE; }

private:
  Hazard reason_ = Hazard::NONE;
};

}  // namespace create_driver
