#pragma once
/// @file nodelet_node.h
/// @brief The whole main() of a `<name>_node`, which runs one nodelet in a process of its own
/// (header-only; roscpp and nodelet).

#include <exception>
#include <string>

#include <nodelet/loader.h>
#include <ros/ros.h>

namespace sl_params
{
/**
 * @brief Runs nodelet @p type as node @p name (remappings and private parameters from the command
 * line) until ROS shuts down.
 *
 * A nodelet whose onInit throws logs why itself (NODELET_FATAL naming the parameter), since
 * nodelet::Loader drops the exception without a word; this adds which nodelet could not be loaded.
 * @return the exit status: 0 after a shutdown, 1 when the nodelet could not be loaded
 */
inline int runNodelet(int argc, char** argv, const std::string& name, const std::string& type)
{
  ros::init(argc, argv, name);
  // Held to the end: the failed nodelet's handle must not be the last one, whose end shuts roscpp
  // down, logging included, before the message below.
  const ros::NodeHandle nh;
  nodelet::Loader loader;
  const nodelet::M_string remappings(ros::names::getRemappings());
  const nodelet::V_string my_argv(argv + 1, argv + argc);
  bool loaded = false;
  try
  {
    loaded = loader.load(ros::this_node::getName(), type, remappings, my_argv);
  }
  catch (const std::exception& e)  // pluginlib: an unknown type or a library that does not load
  {
    ROS_FATAL("could not load the %s nodelet: %s", type.c_str(), e.what());
    return 1;
  }
  if (!loaded)
  {
    ROS_FATAL("could not load the %s nodelet (see the error above)", type.c_str());
    return 1;
  }
  ros::spin();
  return 0;
}
}  // namespace sl_params
