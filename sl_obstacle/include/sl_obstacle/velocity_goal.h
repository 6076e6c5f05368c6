/// @file velocity_goal.h
/// @brief Open-loop distance goal for the cmd_vel command mode.
#pragma once

#include <cmath>

namespace sl_obstacle
{
/// Runs a distance goal (forward, or backwards for a negative distance) as a constant velocity command, estimating the
/// distance travelled by integrating the commanded speed (open loop: the real robot accelerates, so it travels less
/// than estimated, which errs on the safe side).
class VelocityGoal
{
public:
  /// Starts (or replaces) a goal of @p distance metres (negative: backwards) at @p speed m/s (> 0) at
  /// time @p now.
  void start(double distance, double speed, double now);

  /// Stops the goal (no velocity).
  void stop();

  /// Advances the estimate to @p now. Time steps longer than @p max_step count as @p max_step (a
  /// stalled caller must not be credited with distance). @return true when the goal just completed.
  bool update(double now, double max_step = 0.25);

  /// True while a goal runs.
  bool active() const { return active_; }
  /// Distance still to go (m, signed like the goal).
  double remaining() const
  {
    return active_ ? (distance_ < 0.0 ? -1.0 : 1.0) * (std::abs(distance_) - travelled_) : 0.0;
  }
  /// Estimated distance travelled since start (m, unsigned).
  double travelled() const { return travelled_; }
  /// Speed to command now (m/s, unsigned; 0 when no goal runs).
  double speed() const { return active_ ? speed_ : 0.0; }
  /// Signed linear velocity to command now (m/s; negative backwards).
  double velocity() const { return distance_ < 0.0 ? -speed() : speed(); }

private:
  bool active_ = false;
  double distance_ = 0.0;
  double speed_ = 0.0;
  double travelled_ = 0.0;
  double last_ = 0.0;
};
}  // namespace sl_obstacle
