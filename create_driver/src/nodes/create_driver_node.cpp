// Runs the create_driver/driver nodelet in its own process (nothing else).
#include <nodelet/loader.h>
#include <ros/ros.h>

int main(int argc, char** argv)
{
  ros::init(argc, argv, "create_driver");
  nodelet::Loader loader(false);
  const nodelet::M_string remappings(ros::names::getRemappings());
  const nodelet::V_string my_argv;
  if (!loader.load(ros::this_node::getName(), "create_driver/driver", remappings, my_argv))
    return 1;
  ros::spin();
  return 0;
}
