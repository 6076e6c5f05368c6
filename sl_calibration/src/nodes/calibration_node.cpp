// Runs the sl_calibration/calibration nodelet in its own process (with a multi-threaded spinner, so a
// capture service can wait for images).
#include <nodelet/loader.h>
#include <ros/ros.h>

int main(int argc, char** argv)
{
  ros::init(argc, argv, "calibration");
  nodelet::Loader loader;
  const nodelet::M_string remappings(ros::names::getRemappings());
  const nodelet::V_string my_argv(argv + 1, argv + argc);
  if (!loader.load(ros::this_node::getName(), "sl_calibration/calibration", remappings, my_argv))
  {
    ROS_FATAL("could not load the sl_calibration/calibration nodelet (see the error above)");
    return 1;
  }
  ros::spin();
  return 0;
}
