// main() of the system tests (gtest clients of rostests in this folder).
#pragma once

#include <gtest/gtest.h>
#include <ros/ros.h>

namespace sl_bringup_test
{

/// Runs every test with gtest and ROS initialised and callbacks on two spinner threads.
inline int runSystemTests(int argc, char** argv, const char* node_name)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, node_name);
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const int result = RUN_ALL_TESTS();
  spinner.stop();
  ros::shutdown();
  return result;
}

}  // namespace sl_bringup_test
