// Rostest of obstacle_unload.test: the obstacle nodelet is loaded into a manager and unloaded again,
// three times; the manager must still answer afterwards (it aborted at every unload when the
// nodelet's destructor released a tf filter's input subscriber before the filter).
#include <gtest/gtest.h>

#include <atomic>
#include <string>

#include <nodelet/NodeletList.h>
#include <nodelet/NodeletLoad.h>
#include <nodelet/NodeletUnload.h>
#include <ros/ros.h>
#include <sl_testing/rostest_main.h>

#include "sl_msgs/ObstacleStatus.h"

namespace
{
const std::string kManager = "/unload_manager";

/// True once the nodelet publishes its status (its onInit ran) within @p seconds.
bool waitForStatus(double seconds)
{
  ros::NodeHandle nh;
  std::atomic<bool> seen{ false };
  ros::Subscriber sub = nh.subscribe<sl_msgs::ObstacleStatus>(
      "obstacle_status", 1, [&seen](const sl_msgs::ObstacleStatusConstPtr&) { seen = true; });
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
  while (!seen && ros::ok() && ros::WallTime::now() < end)
  {
    ros::WallDuration(0.02).sleep();  // the spinner of runRostests() delivers
  }
  return seen;
}

TEST(ObstacleUnload, ManagerSurvivesUnloading)
{
  ASSERT_TRUE(ros::service::waitForService(kManager + "/load_nodelet", ros::Duration(20.0)));
  for (int round = 0; round < 3; ++round)
  {
    nodelet::NodeletLoad load;
    load.request.name = "/obstacle";
    load.request.type = "sl_obstacle/obstacle";
    ASSERT_TRUE(ros::service::call(kManager + "/load_nodelet", load)) << "round " << round;
    ASSERT_TRUE(load.response.success) << "round " << round;
    EXPECT_TRUE(waitForStatus(10.0)) << "round " << round << ": no obstacle_status from the loaded nodelet";

    nodelet::NodeletUnload unload;
    unload.request.name = "/obstacle";
    ASSERT_TRUE(ros::service::call(kManager + "/unload_nodelet", unload)) << "round " << round;
    EXPECT_TRUE(unload.response.success) << "round " << round;
    ros::WallDuration(0.5).sleep();

    nodelet::NodeletList list;
    ASSERT_TRUE(ros::service::exists(kManager + "/list", false))
        << "round " << round << ": the manager is gone after the unload";
    ASSERT_TRUE(ros::service::call(kManager + "/list", list)) << "round " << round << ": the manager does not answer";
    EXPECT_TRUE(list.response.nodelets.empty()) << "round " << round;
  }
}
}  // namespace

int main(int argc, char** argv)
{
  return sl_testing::runRostests(argc, argv, "obstacle_unload_test");
}
