#include "create_driver/driver_core.h"

#include <stdexcept>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace create_driver
{
namespace
{
constexpr double kDegToRad = M_PI / 180.0;
constexpr double kBackingEps = 1e-3;  // m/s

bool positive(double v)
{
  return std::isfinite(v) && v > 0.0;
}
}  // namespace

void validateConfig(const DriverConfig& c)
{
  const VelocityLimits& l = c.limits;
  if (!positive(l.max_speed) || l.max_speed > 0.5)
    throw std::invalid_argument("max_speed must be in (0, 0.5] m/s");
  if (!positive(l.max_angular_speed))
    throw std::invalid_argument("max_angular_speed must be > 0");
  if (!std::isfinite(l.max_accel) || l.max_accel < 0.0)
    throw std::invalid_argument("max_accel must be >= 0 (0 = unlimited)");
  if (!std::isfinite(l.max_angular_accel) || l.max_angular_accel < 0.0)
    throw std::invalid_argument("max_angular_accel must be >= 0 (0 = unlimited)");
  if (!positive(l.max_wheel_speed) || l.max_wheel_speed > 0.5)
    throw std::invalid_argument("max_wheel_speed must be in (0, 0.5] m/s");
  if (!(l.wheel_base > 0.05 && l.wheel_base < 1.0))
    throw std::invalid_argument("wheel_base must be in (0.05, 1) m");
  if (!positive(c.command_timeout) || c.command_timeout > kMaxCommandTimeout)
    throw std::invalid_argument("command_timeout must be in (0, 0.3] s");
  if (!positive(c.command_refresh))
    throw std::invalid_argument("command_refresh must be > 0");
  const DriveDistanceParams& d = c.drive_distance;
  if (!positive(d.min_speed) || d.min_speed > l.max_speed)
    throw std::invalid_argument("drive_distance/min_speed must be in (0, max_speed]");
  if (!positive(d.max_speed))
    throw std::invalid_argument("drive_distance max speed must be > 0");
  if (!positive(d.decel))
    throw std::invalid_argument("drive_distance/decel must be > 0");
  if (!std::isfinite(d.tolerance) || d.tolerance < 0.0 || d.tolerance > 0.05)
    throw std::invalid_argument("drive_distance/tolerance must be in [0, 0.05] m");
  if (!std::isfinite(d.latency) || d.latency < 0.0 || d.latency > 1.0)
    throw std::invalid_argument("drive_distance/latency must be in [0, 1] s");
  if (!positive(d.stall_timeout))
    throw std::invalid_argument("drive_distance/stall_timeout must be > 0");
  if (!std::isfinite(d.heading_gain) || d.heading_gain < 0.0)
    throw std::invalid_argument("drive_distance/heading_gain must be >= 0");
  if (!std::isfinite(d.max_heading_rate) || d.max_heading_rate < 0.0)
    throw std::invalid_argument("drive_distance/max_heading_rate must be >= 0");
  if (c.use_wait_distance && c.model != Model::CREATE_1)
    throw std::invalid_argument("use_wait_distance is only available on the Create 1 (model create_1)");
  if (c.mode == OiMode::OFF)
    throw std::invalid_argument("oi_mode must be passive, safe or full");
  if (!positive(c.odometry.wheel_base))
    throw std::invalid_argument("wheel_base must be > 0");
}

OiMode parseOiMode(const std::string& name)
{
  if (name == "safe")
    return OiMode::SAFE;
  if (name == "full")
    return OiMode::FULL;
  if (name == "passive")
    return OiMode::PASSIVE;
  throw std::invalid_argument("oi_mode must be safe, full or passive (got '" + name + "')");
}

DriveCommandType parseDriveCommand(const std::string& name)
{
  if (name == "direct")
    return DriveCommandType::DIRECT;
  if (name == "radius")
    return DriveCommandType::RADIUS;
  throw std::invalid_argument("drive_command must be direct or radius (got '" + name + "')");
}

std::vector<uint8_t> driverStreamIds(Model model)
{
  std::vector<uint8_t> ids = {
    packet::BUMPS_WHEEL_DROPS, packet::CLIFF_LEFT,       packet::CLIFF_FRONT_LEFT, packet::CLIFF_FRONT_RIGHT,
    packet::CLIFF_RIGHT,       packet::BUTTONS,          packet::DISTANCE,         packet::ANGLE,
    packet::CHARGING_STATE,    packet::VOLTAGE,          packet::CURRENT,          packet::TEMPERATURE,
    packet::BATTERY_CHARGE,    packet::BATTERY_CAPACITY, packet::OI_MODE
  };
  if (model == Model::CREATE_2)
  {
    ids.push_back(packet::LEFT_ENCODER_COUNTS);
    ids.push_back(packet::RIGHT_ENCODER_COUNTS);
  }
  return ids;
}

DriverCore::DriverCore(const DriverConfig& config)
  : config_(config),
    stream_ids_(driverStreamIds(config.model)),
    parser_(config.model),
    odometry_(config.odometry),
    limiter_(config.limits),
    dd_(config.drive_distance)
{
  parser_.setExpectedIds(stream_ids_);
  outcomes_.reserve(4);
}

void DriverCore::onConnected(double now, Bytes& out)
{
  connected_ = true;
  have_frame_ = false;
  parser_.clearBuffer();
  corrupt_seen_ = parser_.counters().corrupt_frames;
  frames_lost_ = false;
  odometry_.resetEncoderBaseline();
  cmd_active_ = false;
  limiter_.reset();
  force_stop_ = false;
  have_sent_ = false;
  reported_mode_ = -1;
  last_control_ = now;
  // First a stop: a robot whose OI still runs (Safe or Full, e.g. the previous driver process was
  // killed while it drove) obeys it at once; in Off or Passive it is ignored.
  appendMotion(0.0, 0.0, out);
  appendStart(out);
  start_phase_ = 1;
  start_time_ = now;
  ++stats_.start_sequences;
}

void DriverCore::onDisconnected(double /*now*/)
{
  if (dd_.active())
    finishGoal(StopReason::DISCONNECTED, "serial link lost");
  connected_ = false;
  have_frame_ = false;
  start_phase_ = 0;
  cmd_active_ = false;
  wd_active_ = false;
  limiter_.reset();
  reported_mode_ = -1;
  have_sent_ = false;
}

void DriverCore::shutdown(Bytes& out)
{
  if (dd_.active())
    finishGoal(StopReason::DISCONNECTED, "driver shutting down");
  cmd_active_ = false;
  limiter_.reset();
  appendDriveDirect(out, 0, 0);
  appendDrive(out, 0, oi::RADIUS_STRAIGHT);
  appendPauseResumeStream(out, false);
  appendPassive(out);
}

size_t DriverCore::onBytes(const uint8_t* data, size_t len, double now, Bytes& out)
{
  const size_t n = parser_.feed(data, len);
  const auto& updates = parser_.updates();
  // Frames were lost to line noise if corrupt frames were seen since the last good one.
  if (parser_.counters().corrupt_frames != corrupt_seen_)
    frames_lost_ = true;
  corrupt_seen_ = parser_.counters().corrupt_frames;
  for (size_t i = 0; i < n; ++i)
  {
    // Frames that arrived in one read are 15 ms apart on the wire.
    const double stamp = now - static_cast<double>(n - 1 - i) * oi::STREAM_PERIOD_S;
    if (i == 0 && frames_lost_)
      fillLostFrames(stamp);
    frames_lost_ = false;
    processFrame(updates[i], stamp);
    last_frame_stamp_ = stamp;
  }
  if (n > 0)
    control(now, out);
  return n;
}

void DriverCore::fillLostFrames(double stamp)
{
  // Distance and angle (packets 19, 20) count since the previous report, so a frame lost to
  // noise loses its increment. Estimate it from the velocity over the gap. Encoder counts
  // (Create 2) are absolute and need no estimate.
  if (!have_frame_ || config_.model == Model::CREATE_2)
    return;
  const double gap = stamp - last_frame_stamp_;
  const long missed = std::clamp(std::lround(gap / oi::STREAM_PERIOD_S) - 1, 0L, 5L);
  if (missed == 0)
    return;
  const double span = static_cast<double>(missed) * oi::STREAM_PERIOD_S;
  odometry_.updateDistanceAngle(odometry_.linearVelocity() * span, odometry_.angularVelocity() * span,
                                stamp - oi::STREAM_PERIOD_S);
  stats_.frames_estimated += static_cast<uint64_t>(missed);
}

void DriverCore::processFrame(const SensorState& s, double stamp)
{
  have_frame_ = true;
  if (config_.model == Model::CREATE_2 && s.has(packet::LEFT_ENCODER_COUNTS) && s.has(packet::RIGHT_ENCODER_COUNTS))
  {
    odometry_.updateEncoders(static_cast<uint16_t>(s.get(packet::LEFT_ENCODER_COUNTS)),
                             static_cast<uint16_t>(s.get(packet::RIGHT_ENCODER_COUNTS)), stamp);
  }
  else if (s.has(packet::DISTANCE) && s.has(packet::ANGLE))
  {
    odometry_.updateDistanceAngle(s.distanceMm() / 1000.0, s.angleDeg() * kDegToRad, stamp);
  }
  if (s.has(packet::OI_MODE))
    reported_mode_ = s.oiMode();

  const bool backing = limiter_.linear() < -kBackingEps;
  if (latch_.update(s, backing))
  {
    ++stats_.hazard_stops;
    force_stop_ = true;
    if (dd_.active() && !latch_.allows(dd_.goal()))
    {
      std::ostringstream msg;
      msg << hazardName(latch_.reason()) << " detected";
      finishGoal(hazardReason(latch_.reason()), msg.str());
    }
    if (cmd_active_ && !latch_.allows(cmd_linear_))
      cmd_active_ = false;
  }
}

void DriverCore::control(double now, Bytes& out)
{
  if (!connected_)
    return;
  if (!runStartSequence(now, out))
    return;
  const double dt = std::clamp(now - last_control_, 0.0, 0.1);
  last_control_ = now;
  bool emergency = force_stop_;
  force_stop_ = false;
  double v = 0.0;
  double w = 0.0;
  if (!commandedVelocity(now, emergency, v, w))
    return;  // the robot executes the Wait Distance script by itself and ignores commands meanwhile
  limitVelocity(dt, emergency, v, w);
  reassertMode(v, w, now, out);
  sendMotionIfDue(v, w, now, out);
}

bool DriverCore::runStartSequence(double now, Bytes& out)
{
  if (start_phase_ == 1 && now - start_time_ >= config_.start_gap)
  {
    if (config_.mode != OiMode::PASSIVE)
      appendMode(out, config_.mode);
    appendMotion(0.0, 0.0, out);
    appendStream(out, stream_ids_);
    start_phase_ = 2;
    last_mode_sent_ = now;
  }
  if (have_frame_)
    return true;
  if (start_phase_ == 2 && now - start_time_ >= config_.start_retry)
  {
    appendStart(out);
    start_phase_ = 1;
    start_time_ = now;
    ++stats_.start_sequences;
  }
  last_control_ = now;
  return false;
}

bool DriverCore::commandedVelocity(double now, bool& emergency, double& v, double& w)
{
  if (dd_.active() && now - goal_refresh_ > config_.command_timeout)
  {
    std::ostringstream msg;
    msg << std::fixed << std::setprecision(2) << "no heartbeat for " << now - goal_refresh_ << " s (command_timeout "
        << config_.command_timeout << " s): the goal's sender is frozen or gone";
    finishGoal(StopReason::HEARTBEAT_LOST, msg.str());
    ++stats_.heartbeat_stops;
    watchdogStop("drive_distance goal aborted: " + msg.str(), emergency);
  }
  else if (dd_.active())
  {
    const DriveDistanceController::Output o = dd_.update(odometry_.distance(), odometry_.yawContinuous(), now);
    if (o.finished)
    {
      finishGoal(o.reason,
                 o.reason == StopReason::REACHED ? "reached" : "no progress (robot held back?) or goal took too long");
      emergency = true;
    }
    else if (wd_active_)
    {
      return false;
    }
    else
    {
      v = o.linear;
      w = o.angular;
    }
  }
  else if (cmd_active_)
  {
    if (now - cmd_time_ > config_.command_timeout && cmd_linear_ == 0.0 && cmd_angular_ == 0.0)
    {
      cmd_active_ = false;  // the sender stopped the robot and went quiet: nothing to stop
    }
    else if (now - cmd_time_ > config_.command_timeout)
    {
      cmd_active_ = false;
      ++stats_.watchdog_stops;
      std::ostringstream msg;
      msg << std::fixed << std::setprecision(2) << "no cmd_vel for " << now - cmd_time_ << " s (command_timeout "
          << config_.command_timeout << " s): the sender is frozen or gone";
      watchdogStop(msg.str(), emergency);
    }
    else
    {
      v = cmd_linear_;
      w = cmd_angular_;
    }
  }
  return true;
}

void DriverCore::limitVelocity(double dt, bool emergency, double& v, double& w)
{
  if (latch_.latched() && !latch_.allows(v))
  {
    v = 0.0;
    w = 0.0;
  }
  if (config_.mode == OiMode::PASSIVE)
  {
    v = 0.0;
    w = 0.0;
  }
  if (emergency || (v == 0.0 && w == 0.0))
  {
    // A stop is executed at once: the ramps shape starts and changes of speed, never a stop (a
    // frozen camera's stop, a released teleop key).
    limiter_.reset();
    v = 0.0;
    w = 0.0;
  }
  else
  {
    limiter_.limit(v, w, dt, v, w);
  }
}

void DriverCore::reassertMode(double v, double w, double now, Bytes& out)
{
  const bool moving = std::fabs(v) > 1e-4 || std::fabs(w) > 1e-4;
  if (moving && config_.mode != OiMode::PASSIVE && reported_mode_ >= 0 &&
      reported_mode_ != static_cast<int>(config_.mode) && now - last_mode_sent_ >= config_.mode_retry)
  {
    appendMode(out, config_.mode);
    last_mode_sent_ = now;
    ++stats_.mode_reasserts;
    have_sent_ = false;  // follow the mode change with the motion command
  }
}

void DriverCore::sendMotionIfDue(double v, double w, double now, Bytes& out)
{
  // The command as encoded on the wire: sent when it changed or is due for a refresh.
  int a = 0;
  int b = 0;
  if (config_.drive_type == DriveCommandType::DIRECT)
  {
    const WheelSpeeds ws = twistToWheels(v, w, config_.limits.wheel_base, config_.limits.max_wheel_speed);
    a = static_cast<int>(std::lround(ws.left * 1000.0));
    b = static_cast<int>(std::lround(ws.right * 1000.0));
  }
  else
  {
    const DriveRadius d = twistToDriveRadius(v, w, config_.limits.wheel_base, config_.limits.max_wheel_speed);
    a = d.velocity_mm_s;
    b = d.radius_mm;
  }
  if (!have_sent_ || a != last_key_a_ || b != last_key_b_ || now - last_sent_time_ >= config_.command_refresh)
  {
    appendMotion(v, w, out);
    have_sent_ = true;
    last_key_a_ = a;
    last_key_b_ = b;
    last_sent_time_ = now;
  }
}

void DriverCore::appendMotion(double linear, double angular, Bytes& out)
{
  const WheelSpeeds ws = twistToWheels(linear, angular, config_.limits.wheel_base, config_.limits.max_wheel_speed);
  if (config_.drive_type == DriveCommandType::DIRECT)
  {
    last_left_ = static_cast<int>(std::lround(ws.left * 1000.0));
    last_right_ = static_cast<int>(std::lround(ws.right * 1000.0));
    appendDriveDirect(out, last_right_, last_left_);
  }
  else
  {
    const DriveRadius d =
        twistToDriveRadius(linear, angular, config_.limits.wheel_base, config_.limits.max_wheel_speed);
    const WheelSpeeds sent = driveRadiusToWheels(d.velocity_mm_s, d.radius_mm, config_.limits.wheel_base);
    last_left_ = static_cast<int>(std::lround(sent.left * 1000.0));
    last_right_ = static_cast<int>(std::lround(sent.right * 1000.0));
    appendDrive(out, d.velocity_mm_s, d.radius_mm);
  }
  ++stats_.commands_sent;
}

bool DriverCore::setVelocity(double linear, double angular, double now, std::string* error)
{
  if (!isFiniteCommand(linear, angular))
  {
    ++stats_.rejected_commands;
    if (error)
      *error = "cmd_vel contains NaN or infinite values; ignored";
    return false;
  }
  commandSeen(now);
  if (dd_.active())
  {
    // A zero twist (idle teleop, or a "stop turning" sent just before a goal) leaves the goal
    // alone; cancel the goal to stop it.
    if (linear == 0.0 && angular == 0.0)
      return true;
    if (!config_.cmd_vel_preempts_goal)
    {
      ++stats_.rejected_commands;
      if (error)
        *error = "cmd_vel ignored while a drive_distance goal is active";
      return false;
    }
    finishGoal(StopReason::PREEMPTED, "overridden by cmd_vel");
    if (wd_active_)
      wd_active_ = false;
  }
  cmd_active_ = true;
  cmd_linear_ = linear;
  cmd_angular_ = angular;
  cmd_time_ = now;
  if (latch_.latched() && !latch_.allows(linear))
    force_stop_ = true;
  return true;
}

GoalStart DriverCore::startGoal(double distance, double speed, double now, Bytes& out)
{
  GoalStart r;
  r.id = next_goal_id_++;
  auto reject = [&](StopReason reason, const std::string& msg)
  {
    r.accepted = false;
    r.reason = reason;
    r.message = msg;
    return r;
  };
  if (!std::isfinite(distance) || !std::isfinite(speed) || speed <= 0.0)
    return reject(StopReason::INVALID_GOAL, "distance and speed must be finite and speed > 0");
  if (config_.mode == OiMode::PASSIVE)
    return reject(StopReason::INVALID_GOAL, "the driver runs in passive mode (oi_mode), the robot cannot drive");
  if (!connected_ || !have_frame_)
    return reject(StopReason::DISCONNECTED, "robot not connected");
  if (latch_.latched() && !latch_.allows(distance))
    return reject(hazardReason(latch_.reason()),
                  std::string(hazardName(latch_.reason())) + " latched: call reset_hazard or back away first");
  if (dd_.active())
    finishGoal(StopReason::PREEMPTED, "replaced by a new goal");
  cmd_active_ = false;
  wd_active_ = false;

  std::string error;
  if (!dd_.start(distance, speed, odometry_.distance(), odometry_.yawContinuous(), now, &error))
    return reject(StopReason::INVALID_GOAL, error);
  goal_id_ = r.id;
  goal_refresh_ = now;
  commandSeen(now);
  r.accepted = true;
  r.reason = StopReason::REACHED;
  if (config_.use_wait_distance && distance != 0.0)
  {
    const int dir = distance < 0.0 ? -1 : 1;
    const int v_mm = dir * static_cast<int>(std::lround(std::min(dd_.speed(), config_.limits.max_speed) * 1000.0));
    appendMode(out, config_.mode);
    appendDrive(out, v_mm, oi::RADIUS_STRAIGHT);
    appendWaitDistance(out, static_cast<int>(std::lround(distance * 1000.0)));
    appendDrive(out, 0, oi::RADIUS_STRAIGHT);
    wd_active_ = true;
    ++stats_.commands_sent;
  }
  if (distance == 0.0)
  {
    finishGoal(StopReason::REACHED, "zero distance");
  }
  return r;
}

void DriverCore::heartbeat(double now)
{
  if (!dd_.active())
    return;  // the sender's goal has ended: nothing to keep alive
  goal_refresh_ = now;
  commandSeen(now);
}

void DriverCore::commandSeen(double now)
{
  last_command_time_ = now;
  source_lost_.clear();
}

void DriverCore::watchdogStop(const std::string& why, bool& emergency)
{
  source_lost_ = why;
  emergency = true;
}

void DriverCore::cancelGoal(uint64_t id, StopReason reason, const std::string& message)
{
  if (!dd_.active() || id != goal_id_)
    return;
  finishGoal(reason, message);
}

bool DriverCore::resetHazard(std::string* message)
{
  if (!latch_.latched())
  {
    if (message)
      *message = "no hazard latched";
    return true;
  }
  std::string why;
  if (!latch_.reset(parser_.state(), &why))
  {
    if (message)
      *message = why;
    return false;
  }
  if (message)
    *message = "hazard latch cleared";
  return true;
}

void DriverCore::takeOutcomes(std::vector<GoalOutcome>& out)
{
  out.insert(out.end(), outcomes_.begin(), outcomes_.end());
  outcomes_.clear();
}

GoalProgress DriverCore::goalProgress() const
{
  GoalProgress p;
  p.active = dd_.active();
  p.id = goal_id_;
  p.travelled = dd_.active() ? dd_.travelledAt(odometry_.distance()) : dd_.travelled();
  p.remaining = dd_.goal() - p.travelled;
  return p;
}

void DriverCore::finishGoal(StopReason reason, const std::string& message)
{
  const double travelled = dd_.active() ? dd_.travelledAt(odometry_.distance()) : dd_.travelled();
  dd_.abort(reason);
  GoalOutcome o;
  o.id = goal_id_;
  o.reason = reason;
  o.travelled = travelled;
  o.message = message;
  if (wd_active_ && reason != StopReason::REACHED)
    o.message += "; the robot ignores all commands until its Wait Distance is covered";
  outcomes_.push_back(o);
  wd_active_ = false;
  force_stop_ = true;
}

StopReason DriverCore::hazardReason(Hazard hazard)
{
  switch (hazard)
  {
    case Hazard::BUMPER:
      return StopReason::BUMPER;
    case Hazard::CLIFF:
      return StopReason::CLIFF;
    case Hazard::WHEEL_DROP:
      return StopReason::WHEEL_DROP;
    case Hazard::NONE:
      break;
  }
  return StopReason::INVALID_GOAL;
}

}  // namespace create_driver
