// The driver nodelet's parameters, read and checked in one place (ranges: validateConfig() and
// SerialLinkParams::validate()).
#pragma once

#include <string>

#include <ros/node_handle.h>

#include "create_driver/driver_core.h"
#include "create_driver/serial_link.h"

namespace create_driver
{
/// Everything the driver nodelet is configured with.
struct DriverNodeParams
{
  DriverConfig config;
  SerialLinkParams link;
  std::string model_name;  ///< as given in ~model
  std::string odom_frame = "odom";
  std::string base_frame = "base_link";
  bool publish_tf = true;
};

/// Reads the private parameters of the driver; throws std::invalid_argument naming the parameter.
DriverNodeParams readDriverParams(const ros::NodeHandle& pnh);
}  // namespace create_driver
