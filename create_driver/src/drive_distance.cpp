#include "create_driver/drive_distance.h"

#include <algorithm>
#include <cmath>

namespace create_driver
{
const char* stopReasonName(StopReason reason)
{
  switch (reason)
  {
    case StopReason::REACHED:
      return "reached";
    case StopReason::PREEMPTED:
      return "preempted";
    case StopReason::BUMPER:
      return "bumper";
    case StopReason::CLIFF:
      return "cliff";
    case StopReason::WHEEL_DROP:
      return "wheel drop";
    case StopReason::TIMEOUT:
      return "timeout";
    case StopReason::DISCONNECTED:
      return "disconnected";
    case StopReason::INVALID_GOAL:
      return "invalid goal";
    case StopReason::HEARTBEAT_LOST:
      return "heartbeat lost";
  }
  return "unknown";
}

DriveDistanceController::DriveDistanceController(const DriveDistanceParams& params) : params_(params) {}

bool DriveDistanceController::start(double distance, double speed, double odom_distance, double odom_yaw, double now,
                                    std::string* error)
{
  auto fail = [&](const char* why)
  {
    if (error)
      *error = why;
    return false;
  };
  if (!std::isfinite(distance))
    return fail("distance is not a finite number");
  if (!std::isfinite(speed))
    return fail("speed is not a finite number");
  if (speed <= 0.0)
    return fail("speed must be > 0");
  if (!std::isfinite(odom_distance) || !std::isfinite(odom_yaw))
    return fail("odometry is not valid");
  active_ = true;
  goal_ = distance;
  speed_ = std::clamp(speed, params_.min_speed, params_.max_speed);
  start_distance_ = odom_distance;
  start_yaw_ = odom_yaw;
  start_time_ = now;
  travelled_ = 0.0;
  best_progress_ = 0.0;
  progress_time_ = now;
  last_command_ = 0.0;
  return true;
}

DriveDistanceController::Output DriveDistanceController::update(double odom_distance, double odom_yaw, double now)
{
  Output out;
  if (!active_)
    return out;
  travelled_ = odom_distance - start_distance_;
  const double dir = goal_ < 0.0 ? -1.0 : 1.0;
  const double progress = travelled_ * dir;
  const double remaining = std::fabs(goal_) - progress;

  if (progress > best_progress_ + 0.002)
  {
    best_progress_ = progress;
    progress_time_ = now;
  }

  const double stop_margin = params_.tolerance + std::fabs(last_command_) * params_.latency;
  if (remaining <= stop_margin)
  {
    finish(StopReason::REACHED);
  }
  else if (now - progress_time_ > params_.stall_timeout ||
           now - start_time_ > params_.time_factor * std::fabs(goal_) / speed_ + params_.time_margin)
  {
    finish(StopReason::TIMEOUT);
  }
  if (!active_)
  {
    out.finished = true;
    out.reason = last_reason_;
    return out;
  }

  double v = std::min(speed_, std::sqrt(2.0 * params_.decel * std::max(0.0, remaining - params_.tolerance)));
  v = std::max(v, params_.min_speed);
  last_command_ = dir * v;
  const double heading_error = odom_yaw - start_yaw_;
  out.active = true;
  out.linear = last_command_;
  out.angular = std::clamp(-params_.heading_gain * heading_error, -params_.max_heading_rate, params_.max_heading_rate);
  return out;
}

void DriveDistanceController::abort(StopReason reason)
{
  if (active_)
    finish(reason);
}

void DriveDistanceController::finish(StopReason reason)
{
  active_ = false;
  last_reason_ = reason;
  last_command_ = 0.0;
}

}  // namespace create_driver
