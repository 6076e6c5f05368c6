#include "create_driver/driver_supervisor.h"

namespace create_driver
{
namespace
{
constexpr double kHazardsPeriod = 0.1;   // s, hazards also without a change
constexpr double kBatteryPeriod = 1.0;   // s
constexpr double kFeedbackPeriod = 0.1;  // s, goal feedback
}  // namespace

bool HazardReading::operator==(const HazardReading& o) const
{
  return bump_left == o.bump_left && bump_right == o.bump_right && wheel_drop_left == o.wheel_drop_left &&
         wheel_drop_right == o.wheel_drop_right && wheel_drop_caster == o.wheel_drop_caster &&
         cliff_left == o.cliff_left && cliff_front_left == o.cliff_front_left &&
         cliff_front_right == o.cliff_front_right && cliff_right == o.cliff_right && latched == o.latched &&
         latch_reason == o.latch_reason;
}

HazardReading hazardReading(const SensorState& s, const HazardLatch& latch)
{
  HazardReading h;
  h.bump_left = s.bumpLeft();
  h.bump_right = s.bumpRight();
  h.wheel_drop_left = s.wheelDropLeft();
  h.wheel_drop_right = s.wheelDropRight();
  h.wheel_drop_caster = s.wheelDropCaster();
  h.cliff_left = s.cliffLeft();
  h.cliff_front_left = s.cliffFrontLeft();
  h.cliff_front_right = s.cliffFrontRight();
  h.cliff_right = s.cliffRight();
  h.latched = latch.latched();
  h.latch_reason = latch.reason();
  return h;
}

GoalEnd goalEnd(StopReason reason)
{
  if (reason == StopReason::REACHED)
    return GoalEnd::SUCCEEDED;
  if (reason == StopReason::PREEMPTED)
    return GoalEnd::CANCELED;
  return GoalEnd::ABORTED;
}

DriverSupervisor::DriverSupervisor(const DriverConfig& config) : core_(config) {}

void DriverSupervisor::onOpen(double now, Bytes& out)
{
  queued_.clear();
  core_.onConnected(now, out);
}

FrameActions DriverSupervisor::onData(const uint8_t* data, size_t len, double now, Bytes& out)
{
  FrameActions a;
  a.frames = core_.onBytes(data, len, now, out);
  flushQueued(out);
  if (a.frames > 0)
  {
    a.snapshot = snapshot();
    schedule(a, now);
  }
  return a;
}

void DriverSupervisor::onTick(double now, Bytes& out)
{
  core_.control(now, out);
  flushQueued(out);
}

void DriverSupervisor::onLinkState(LinkState state, double now)
{
  link_state_ = state;
  if (state == LinkState::DISCONNECTED)
    core_.onDisconnected(now);
}

void DriverSupervisor::shutdown(Bytes& out)
{
  core_.shutdown(out);
}

bool DriverSupervisor::setVelocity(double linear, double angular, double now, std::string* error)
{
  return core_.setVelocity(linear, angular, now, error);
}

GoalStart DriverSupervisor::startGoal(double distance, double speed, double now)
{
  return core_.startGoal(distance, speed, now, queued_);
}

void DriverSupervisor::heartbeat(double now)
{
  core_.heartbeat(now);
}

void DriverSupervisor::cancelGoal(uint64_t id)
{
  core_.cancelGoal(id, StopReason::PREEMPTED, "cancelled");
}

bool DriverSupervisor::resetHazard(std::string* message)
{
  return core_.resetHazard(message);
}

void DriverSupervisor::takeEndedGoals(std::vector<GoalOutcome>& out)
{
  core_.takeOutcomes(out);
}

bool DriverSupervisor::takeWatchdogStop(std::string* why)
{
  const std::string& lost = core_.commandSourceLost();
  if (lost == reported_lost_)
    return false;
  reported_lost_ = lost;
  if (lost.empty())
    return false;  // a command came: nothing to report
  if (why)
    *why = lost;
  return true;
}

ModeReport DriverSupervisor::takeModeReport()
{
  ModeReport r;
  r.reported_mode = core_.haveSensors() ? core_.reportedMode() : -1;
  r.requested_mode = core_.config().mode;
  r.link_state = link_state_;
  published_mode_ = r.reported_mode;
  return r;
}

StreamReport DriverSupervisor::takeStreamReport(double now)
{
  StreamReport r;
  r.counters = core_.parserCounters();
  r.frames_estimated = core_.stats().frames_estimated;
  const double dt = stream_reported_ ? now - stream_time_ : 0.0;
  r.rate = dt > 0.0 ? (r.counters.valid_frames - stream_valid_) / dt : 0.0;
  r.new_corrupt = r.counters.corrupt_frames > stream_corrupt_;
  stream_reported_ = true;
  stream_time_ = now;
  stream_valid_ = r.counters.valid_frames;
  stream_corrupt_ = r.counters.corrupt_frames;
  return r;
}

void DriverSupervisor::flushQueued(Bytes& out)
{
  if (queued_.empty())
    return;
  out.insert(out.end(), queued_.begin(), queued_.end());
  queued_.clear();
}

DriverSnapshot DriverSupervisor::snapshot() const
{
  DriverSnapshot s;
  s.sensors = core_.sensors();
  s.pose = core_.odometry().pose();
  s.linear = core_.odometry().linearVelocity();
  s.angular = core_.odometry().angularVelocity();
  s.hazards = hazardReading(core_.sensors(), core_.latch());
  s.progress = core_.goalProgress();
  s.reported_mode = core_.reportedMode();
  return s;
}

void DriverSupervisor::schedule(FrameActions& a, double now)
{
  const DriverSnapshot& s = a.snapshot;
  if (s.hazards != published_hazards_ || now - hazards_time_ >= kHazardsPeriod)
  {
    a.hazards = true;
    published_hazards_ = s.hazards;
    hazards_time_ = now;
  }
  if (now - battery_time_ >= kBatteryPeriod)
  {
    a.battery = true;
    battery_time_ = now;
  }
  a.mode = s.reported_mode != published_mode_;
  if (s.progress.active && now - feedback_time_ >= kFeedbackPeriod)
  {
    a.feedback = true;
    feedback_time_ = now;
  }
}

}  // namespace create_driver
