#include "create_driver/sim_supervisor.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace create_driver
{
namespace
{
void require(bool ok, const char* message)
{
  if (!ok)
    throw std::invalid_argument(message);
}

// A fraction of wheel travel: in [0, 1).
bool fraction(double v)
{
  return v >= 0.0 && v < 1.0;
}
}  // namespace

void SimNodeConfig::validate() const
{
  const SimParams& p = robot;
  require(p.wheel_base > 0.05 && p.wheel_base < 1.0, "wheel_base must be in (0.05, 1) m");
  require(std::isfinite(p.initial_pose.x) && std::isfinite(p.initial_pose.y) && std::isfinite(p.initial_pose.yaw),
          "x, ~y and ~yaw must be finite");
  require(p.max_wheel_accel >= 0.0, "max_wheel_accel must be >= 0 (0 = instant)");
  require(fraction(p.slip_left), "slip_left must be in [0, 1)");
  require(fraction(p.slip_right), "slip_right must be in [0, 1)");
  require(fraction(p.slip_noise), "slip_noise must be in [0, 1)");
  require(fraction(p.odom_noise), "odom_noise must be in [0, 1)");
  require(p.command_watchdog == 0.0 || (p.command_watchdog >= 0.05 && p.command_watchdog <= 10.0),
          "command_watchdog must be 0 (none, like the real Create) or in [0.05, 10] s");
  require(rate >= 50.0 && rate <= 2000.0, "rate must be in [50, 2000] Hz");
  require(publish_rate > 0.0 && publish_rate <= rate, "publish_rate must be in (0, ~rate] Hz");
  require(garbage_bytes > 0 && garbage_bytes <= 4096, "garbage_bytes must be in [1, 4096]");
  require(reopen_delay >= 0.0 && reopen_delay <= 60.0, "reopen_delay must be in [0, 60] s");
  require(status_period > 0.0, "status_period must be > 0 s");
}

SimSupervisor::SimSupervisor(const SimNodeConfig& config, double now)
  : config_(config), robot_(config.robot), last_(now), next_pose_(now), next_status_(now)
{
  garbage_rng_.seed(config.robot.seed + 1);
}

PtyActions SimSupervisor::ptyActions(double now)
{
  PtyActions a;
  if (reopen_requested_)
  {
    reopen_requested_ = false;
    a.close = true;
    reopen_pending_ = true;
    reopen_at_ = now + config_.reopen_delay;
  }
  if (reopen_pending_ && now >= reopen_at_)
  {
    reopen_pending_ = false;
    a.open = true;
  }
  return a;
}

SimStepActions SimSupervisor::step(double now, Bytes& out)
{
  SimStepActions a;
  robot_.step(now - last_);
  last_ = now;
  if (robot_.refusedCommands() != refused_logged_)
  {
    refused_logged_ = robot_.refusedCommands();
    a.refusal = true;
    a.new_refusal_reason = robot_.lastRefusal() != refusal_logged_;
    refusal_logged_ = robot_.lastRefusal();
  }
  if (robot_.watchdogStops() != watchdog_logged_)
  {
    watchdog_logged_ = robot_.watchdogStops();
    a.watchdog_stop = true;
  }
  out.clear();
  robot_.takeOutput(out);
  if (now >= next_pose_)
  {
    const double period = 1.0 / config_.publish_rate;
    next_pose_ = std::max(next_pose_ + period, now - period);
    a.publish_pose = true;
  }
  if (now >= next_status_)
  {
    next_status_ = now + config_.status_period;
    a.publish_status = true;
  }
  return a;
}

size_t SimSupervisor::injectGarbage()
{
  Bytes g(config_.garbage_bytes);
  std::uniform_int_distribution<int> byte(0, 255);
  for (auto& b : g)
    b = static_cast<uint8_t>(byte(garbage_rng_));
  g[0] = oi::STREAM_HEADER;  // a false header too
  robot_.injectIntoNextFrame(g);
  return g.size();
}

}  // namespace create_driver
