// Runs the create_driver/sim nodelet (simulated Create on a pty) in its own process (nothing else).
#include <exception>

#include <nodelet/loader.h>
#include <ros/ros.h>

int main(int argc, char** argv)
{
  ros::init(argc, argv, "create_sim");
  // Held to the end: when a nodelet fails in onInit, the end of its NodeHandle would otherwise be the
  // last one and shut roscpp down, logging included, before the message below.
  const ros::NodeHandle nh;
  nodelet::Loader loader(false);
  const nodelet::M_string remappings(ros::names::getRemappings());
  const nodelet::V_string my_argv;
  bool loaded = false;
  try
  {
    loaded = loader.load(ros::this_node::getName(), "create_driver/sim", remappings, my_argv);
  }
  catch (const std::exception& e)
  {
    ROS_FATAL("could not load the create_driver/sim nodelet: %s", e.what());
    return 1;
  }
  if (!loaded)
  {
    ROS_FATAL("could not load the create_driver/sim nodelet (see the error above)");
    return 1;
  }
  ros::spin();
  return 0;
}
