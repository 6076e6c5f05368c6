/// @file drive_distance.h
/// @brief Host-side "drive this far" controller, run from odometry.
#pragma once

#include <cstdint>
#include <string>

namespace create_driver
{
/// Why a distance goal ended. Numeric values equal the DriveDistance result constants.
enum class StopReason : uint8_t
{
  REACHED = 0,
  PREEMPTED = 1,
  BUMPER = 2,
  CLIFF = 3,
  WHEEL_DROP = 4,
  TIMEOUT = 5,
  DISCONNECTED = 6,
  INVALID_GOAL = 7,
  HEARTBEAT_LOST = 8  ///< the goal's sender stopped refreshing it for command_timeout
};

/// @brief Name of a stop reason ("reached", "preempted", ...).
const char* stopReasonName(StopReason reason);

/// Tuning of the distance controller.
struct DriveDistanceParams
{
  double min_speed = 0.01;        ///< m/s, slowest commanded speed (the Create crawls at 10 mm/s)
  double max_speed = 0.5;         ///< m/s, goal speeds are clamped to this
  double decel = 0.25;            ///< m/s^2, planned deceleration towards the goal
  double tolerance = 0.001;       ///< m, stop when this close (plus the latency allowance)
  double latency = 0.03;          ///< s, command latency; the stop is sent v * latency early
  double stall_timeout = 3.0;     ///< s without 2 mm of progress -> TIMEOUT
  double time_factor = 3.0;       ///< goal time limit = time_factor * |d| / speed + time_margin
  double time_margin = 5.0;       ///< s
  double heading_gain = 1.0;      ///< 1/s, heading hold: w = -gain * heading error
  double max_heading_rate = 0.3;  ///< rad/s, bound of the heading correction
};

/// @brief Drives a signed distance along the start heading, using odometry for progress.
///
/// Speed profile: min(goal speed, sqrt(2 * decel * remaining)), never below min_speed, so the
/// robot arrives at a crawl and stops within a millimetre or two of the goal. A heading-hold term
/// keeps the path straight against wheel slip. The class is pure: it gets odometry and time, and
/// returns the velocity to command.
class DriveDistanceController
{
public:
  /// Result of one update.
  struct Output
  {
    bool active = false;    ///< a goal is running (after this update)
    bool finished = false;  ///< the goal ended in this update (reason is valid)
    StopReason reason = StopReason::REACHED;
    double linear = 0.0;   ///< m/s to command
    double angular = 0.0;  ///< rad/s to command
  };

  /// @brief Creates an idle controller.
  explicit DriveDistanceController(const DriveDistanceParams& params = DriveDistanceParams());

  /// @brief Replaces the tuning (does not affect a running goal's speed clamp).
  void setParams(const DriveDistanceParams& params) { params_ = params; }
  /// @brief Tuning in use.
  const DriveDistanceParams& params() const { return params_; }

  /// @brief Validates and starts a goal.
  /// @param distance m, signed; @param speed m/s, > 0 (clamped to [min_speed, max_speed])
  /// @param odom_distance odometry path length now; @param odom_yaw unwrapped heading now
  /// @param error set to a reason when the goal is invalid (NaN/inf, speed <= 0)
  /// @return false for an invalid goal (the controller stays idle)
  bool start(double distance, double speed, double odom_distance, double odom_yaw, double now, std::string* error);

  /// @brief Advances the controller with fresh odometry.
  Output update(double odom_distance, double odom_yaw, double now);

  /// @brief Ends the goal from outside (pre-emption, hazard, disconnect).
  void abort(StopReason reason);

  /// @brief True while a goal runs.
  bool active() const { return active_; }
  /// @brief Signed distance travelled along the goal, m.
  double travelled() const { return travelled_; }
  /// @brief Signed distance travelled along the goal at odometry path length @p odom_distance.
  double travelledAt(double odom_distance) const { return odom_distance - start_distance_; }
  /// @brief Signed remaining distance (goal - travelled), m.
  double remaining() const { return goal_ - travelled_; }
  /// @brief Signed goal distance, m.
  double goal() const { return goal_; }
  /// @brief Speed in use (after clamping), m/s.
  double speed() const { return speed_; }
  /// @brief Reason of the last finished goal.
  StopReason lastReason() const { return last_reason_; }

private:
  void finish(StopReason reason);

  DriveDistanceParams params_;
  bool active_ = false;
  double goal_ = 0.0;
  double speed_ = 0.0;
  double start_distance_ = 0.0;
  double start_yaw_ = 0.0;
  double start_time_ = 0.0;
  double travelled_ = 0.0;
  double best_progress_ = 0.0;
  double progress_time_ = 0.0;
  double last_command_ = 0.0;
  StopReason last_reason_ = StopReason::REACHED;
};

}  // namespace create_driver
