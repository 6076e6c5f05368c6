// main() of a rostest's gtest client.
#pragma once

#include <gtest/gtest.h>
#include <ros/ros.h>

namespace sl_testing
{
/**
 * @brief Runs every test with gtest and ROS initialised as node @p node_name.
 * @param spinner_threads threads of an AsyncSpinner that runs the callbacks while the tests run; 0:
 *        none (the tests wait for messages with ros::topic::waitForMessage or spin themselves)
 * @return RUN_ALL_TESTS()'s result
 */
inline int runRostests(int argc, char** argv, const char* node_name, unsigned spinner_threads = 2)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, node_name);
  ros::NodeHandle nh;  // the node stays up between tests that make and drop their own handles
  ros::AsyncSpinner spinner(spinner_threads);
  if (spinner_threads > 0)
    spinner.start();
  const int result = RUN_ALL_TESTS();
  spinner.stop();
  ros::shutdown();
  return result;
}
}  // namespace sl_testing
