#include "driver_params.h"

#include <stdexcept>

#include "sl_params/params.h"

namespace create_driver
{
namespace
{
void require(bool ok, const std::string& message)
{
  if (!ok)
    throw std::invalid_argument(message);
}

// A core check's error (naming the parameter without its "~") as the nodelet's error.
template <typename F>
void privateParam(F check)
{
  try
  {
    check();
  }
  catch (const std::invalid_argument& e)
  {
    throw std::invalid_argument(std::string("~") + e.what());
  }
}

// Model, port, mode and drive command: named values.
void readChoices(const ros::NodeHandle& pnh, DriverNodeParams& p)
{
  p.model_name = sl_params::read<std::string>(pnh, "model", "create_1");
  privateParam([&] { p.config.model = parseModel(p.model_name); });
  p.link.port = sl_params::read<std::string>(pnh, "port", "/dev/ttyUSB0");
  p.link.baud = sl_params::read<unsigned>(pnh, "baud", defaultBaud(p.config.model));
  const std::string mode = sl_params::read<std::string>(pnh, "oi_mode", "safe");
  privateParam([&] { p.config.mode = parseOiMode(mode); });
  const std::string drive = sl_params::read<std::string>(pnh, "drive_command", "direct");
  privateParam([&] { p.config.drive_type = parseDriveCommand(drive); });
}

// Limits, the command watchdog and the distance controller.
void readControl(const ros::NodeHandle& pnh, DriverConfig& c)
{
  const double wheel_base = sl_params::read<double>(pnh, "wheel_base", defaultWheelBase(c.model));
  c.limits.wheel_base = wheel_base;
  c.odometry.wheel_base = wheel_base;
  c.limits.max_speed = sl_params::read<double>(pnh, "max_speed", 0.5);
  c.limits.max_angular_speed = sl_params::read<double>(pnh, "max_angular_speed", 2.0 * 0.5 / wheel_base);
  c.limits.max_accel = sl_params::read<double>(pnh, "max_accel", 1.0);
  c.limits.max_angular_accel = sl_params::read<double>(pnh, "max_angular_accel", 6.0);

  require(!pnh.hasParam("cmd_vel_timeout"),
          "~cmd_vel_timeout is not a parameter of this driver: ~command_timeout (at most 0.3 s) bounds cmd_vel "
          "and drive_distance heartbeats alike");
  c.command_timeout = sl_params::read<double>(pnh, "command_timeout", 0.25);
  c.cmd_vel_preempts_goal = sl_params::read<bool>(pnh, "cmd_vel_preempts_goal", true);
  c.use_wait_distance = sl_params::read<bool>(pnh, "use_wait_distance", false);
  c.command_refresh = sl_params::read<double>(pnh, "command_refresh", 0.2);

  DriveDistanceParams& d = c.drive_distance;
  d.max_speed = c.limits.max_speed;
  d.min_speed = sl_params::read<double>(pnh, "drive_distance/min_speed", 0.01);
  d.decel = sl_params::read<double>(pnh, "drive_distance/decel", 0.25);
  d.tolerance = sl_params::read<double>(pnh, "drive_distance/tolerance", 0.001);
  d.latency = sl_params::read<double>(pnh, "drive_distance/latency", 0.03);
  d.stall_timeout = sl_params::read<double>(pnh, "drive_distance/stall_timeout", 3.0);
  d.heading_gain = sl_params::read<double>(pnh, "drive_distance/heading_gain", 1.0);
  d.max_heading_rate = sl_params::read<double>(pnh, "drive_distance/max_heading_rate", 0.3);
}
}  // namespace

DriverNodeParams readDriverParams(const ros::NodeHandle& pnh)
{
  DriverNodeParams p;
  readChoices(pnh, p);
  readControl(pnh, p.config);

  p.odom_frame = sl_params::read<std::string>(pnh, "odom_frame", "odom");
  p.base_frame = sl_params::read<std::string>(pnh, "base_frame", "base_link");
  require(!p.odom_frame.empty() && !p.base_frame.empty() && p.odom_frame != p.base_frame,
          "~odom_frame and ~base_frame must be non-empty and different");
  p.publish_tf = sl_params::read<bool>(pnh, "publish_tf", true);

  LinkParams& l = p.link.link;
  l.initial_backoff = sl_params::read<double>(pnh, "reconnect_initial_delay", 0.25);
  l.max_backoff = sl_params::read<double>(pnh, "reconnect_max_delay", 4.0);
  l.frame_timeout = sl_params::read<double>(pnh, "link_timeout", 1.0);
  l.start_timeout = sl_params::read<double>(pnh, "start_timeout", 3.0);
  p.link.tick_period = sl_params::read<double>(pnh, "control_period", 0.01);

  privateParam(
      [&]
      {
        validateConfig(p.config);
        p.link.validate();
      });
  return p;
}
}  // namespace create_driver
