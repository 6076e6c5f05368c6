// Runs the sl_navigation/navigation nodelet in its own process (nothing else).
#include <exception>

#include <nodelet/loader.h>
#include <ros/ros.h>

int main(int argc, char** argv)
{
  ros::init(argc, argv, "navigation");
  nodelet::Loader loader;
  const nodelet::M_string remappings(ros::names::getRemappings());
  const nodelet::V_string my_argv(argv + 1, argv + argc);
  bool loaded = false;
  try
  {
    loaded = loader.load(ros::this_node::getName(), "sl_navigation/navigation", remappings, my_argv);
  }
  catch (const std::exception& e)
  {
    ROS_FATAL("could not load the sl_navigation/navigation nodelet: %s", e.what());
    return 1;
  }
  if (!loaded)
  {
    ROS_FATAL("could not load the sl_navigation/navigation nodelet (see the error above)");
    return 1;
  }
  ros::spin();
  return 0;
}
