// The create_sim nodelet's parameters, read in one place (ranges: SimNodeConfig::validate()).
#pragma once

#include <string>

#include <ros/node_handle.h>

#include "create_driver/sim_supervisor.h"

namespace create_driver
{
/// Everything the create_sim nodelet is configured with.
struct SimNodeParams
{
  SimNodeConfig config;
  std::string world_frame = "world";
  std::string robot_frame = "base_footprint_true";
  std::string link_path;  ///< symlink to the pty's slave ("" none)
};

/// Reads the private parameters of create_sim; throws std::invalid_argument naming the parameter.
SimNodeParams readSimParams(const ros::NodeHandle& pnh);
}  // namespace create_driver
