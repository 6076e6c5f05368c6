#include "sim_params.h"

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

// The simulated robot's parameters (model, geometry, slip and noise).
SimParams readRobotParams(const ros::NodeHandle& pnh)
{
  SimParams p;
  const std::string model = sl_params::read<std::string>(pnh, "model", "create_1");
  try
  {
    p.model = parseModel(model);
  }
  catch (const std::invalid_argument& e)
  {
    throw std::invalid_argument(std::string("~") + e.what());
  }
  p.wheel_base = sl_params::read<double>(pnh, "wheel_base", defaultWheelBase(p.model));
  p.initial_pose.x = sl_params::read<double>(pnh, "x", 0.0);
  p.initial_pose.y = sl_params::read<double>(pnh, "y", 0.0);
  p.initial_pose.yaw = sl_params::read<double>(pnh, "yaw", 0.0);
  p.max_wheel_accel = sl_params::read<double>(pnh, "max_wheel_accel", 0.0);
  p.slip_left = sl_params::read<double>(pnh, "slip_left", 0.0);
  p.slip_right = sl_params::read<double>(pnh, "slip_right", 0.0);
  p.slip_noise = sl_params::read<double>(pnh, "slip_noise", 0.0);
  p.odom_noise = sl_params::read<double>(pnh, "odom_noise", 0.0);
  const int seed = sl_params::read<int>(pnh, "seed", 1);
  require(seed >= 0, "~seed must be >= 0");
  p.seed = static_cast<uint32_t>(seed);
  p.block_on_contact = sl_params::read<bool>(pnh, "block_on_contact", true);
  p.command_watchdog = sl_params::read<double>(pnh, "command_watchdog", 0.0);
  return p;
}
}  // namespace

SimNodeParams readSimParams(const ros::NodeHandle& pnh)
{
  SimNodeParams p;
  p.config.robot = readRobotParams(pnh);
  p.config.rate = sl_params::read<double>(pnh, "rate", 200.0);
  p.config.publish_rate = sl_params::read<double>(pnh, "publish_rate", 50.0);
  p.world_frame = sl_params::read<std::string>(pnh, "world_frame", "world");
  p.robot_frame = sl_params::read<std::string>(pnh, "robot_frame", "base_footprint_true");
  require(!p.world_frame.empty() && !p.robot_frame.empty() && p.world_frame != p.robot_frame,
          "~world_frame and ~robot_frame must be non-empty and different");
  p.link_path = sl_params::read<std::string>(pnh, "link", "");
  const int garbage = sl_params::read<int>(pnh, "garbage_bytes", 32);
  require(garbage > 0, "~garbage_bytes must be in [1, 4096]");
  p.config.garbage_bytes = static_cast<size_t>(garbage);
  p.config.reopen_delay = sl_params::read<double>(pnh, "reopen_delay", 0.5);
  try
  {
    p.config.validate();
  }
  catch (const std::invalid_argument& e)
  {
    throw std::invalid_argument(std::string("~") + e.what());
  }
  return p;
}
}  // namespace create_driver
