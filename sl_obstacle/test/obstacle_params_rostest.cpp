// Rostest: the nodelet's parameters are read and validated in one place and fail fast.
#include <gtest/gtest.h>

#include <cstdio>
#include <stdexcept>
#include <string>

#include <ros/ros.h>
#include <sys/wait.h>

#include "params.h"

namespace sl_obstacle
{
namespace
{
/// Expects loadParams() on namespace @p ns to throw a message that names ~@p name.
void expectRejected(const std::string& ns, const std::string& name)
{
  try
  {
    loadParams(ros::NodeHandle(ns));
    ADD_FAILURE() << "no exception for a bad ~" << name;
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_NE(std::string(e.what()).find("parameter ~" + name), std::string::npos) << e.what();
  }
}

TEST(ObstacleParams, DefaultsAreValidAndEqualTheCoreDefaults)
{
  const NodeletParams p = loadParams(ros::NodeHandle("~defaults"));
  EXPECT_EQ(p.target_frame, "platform_edge");
  EXPECT_EQ(p.command_mode, CommandMode::ACTION);
  EXPECT_DOUBLE_EQ(p.control_rate, 10.0);
  // Obstacle.cfg's defaults and the core's defaults must agree.
  const Settings core;
  const Settings& s = p.settings;
  EXPECT_DOUBLE_EQ(s.checker.volume.width, core.checker.volume.width);
  EXPECT_DOUBLE_EQ(s.checker.volume.height, core.checker.volume.height);
  EXPECT_DOUBLE_EQ(s.checker.volume.depth, core.checker.volume.depth);
  EXPECT_DOUBLE_EQ(s.checker.volume.floor_margin, core.checker.volume.floor_margin);
  EXPECT_DOUBLE_EQ(s.checker.volume.max_range, core.checker.volume.max_range);
  EXPECT_DOUBLE_EQ(s.checker.min_confidence, core.checker.min_confidence);
  EXPECT_EQ(s.checker.sectors, core.checker.sectors);
  EXPECT_DOUBLE_EQ(s.checker.cell_size, core.checker.cell_size);
  EXPECT_EQ(s.checker.noise.min_cluster_size, core.checker.noise.min_cluster_size);
  EXPECT_DOUBLE_EQ(s.checker.noise.cluster_tolerance, core.checker.noise.cluster_tolerance);
  EXPECT_EQ(s.checker.noise.persistence_frames, core.checker.noise.persistence_frames);
  EXPECT_DOUBLE_EQ(s.checker.noise.persistence_tolerance, core.checker.noise.persistence_tolerance);
  EXPECT_EQ(s.decision.enabled, core.decision.enabled);
  EXPECT_DOUBLE_EQ(s.decision.safety_margin, core.decision.safety_margin);
  EXPECT_DOUBLE_EQ(s.decision.min_goal_distance, core.decision.min_goal_distance);
  EXPECT_DOUBLE_EQ(s.decision.slow_distance, core.decision.slow_distance);
  EXPECT_DOUBLE_EQ(s.decision.max_speed, core.decision.max_speed);
  EXPECT_DOUBLE_EQ(s.decision.min_speed, core.decision.min_speed);
  EXPECT_DOUBLE_EQ(s.decision.min_coverage, core.decision.min_coverage);
  EXPECT_DOUBLE_EQ(s.decision.full_speed_coverage, core.decision.full_speed_coverage);
  EXPECT_DOUBLE_EQ(s.decision.stale_timeout, core.decision.stale_timeout);
  EXPECT_DOUBLE_EQ(s.decision.preempt_tolerance, core.decision.preempt_tolerance);
  EXPECT_DOUBLE_EQ(s.decision.replan_distance, core.decision.replan_distance);
  EXPECT_DOUBLE_EQ(s.decision.speed_tolerance, core.decision.speed_tolerance);
  EXPECT_DOUBLE_EQ(s.decision.turn_speed, core.decision.turn_speed);
  EXPECT_DOUBLE_EQ(s.decision.turn_angle, core.decision.turn_angle);
  EXPECT_EQ(s.decision.max_turns, core.decision.max_turns);
  EXPECT_DOUBLE_EQ(s.decision.settle_time, core.decision.settle_time);
}

TEST(ObstacleParams, GivenValuesAreUsed)
{
  ros::NodeHandle nh("~given");
  nh.setParam("width", 0.4);
  nh.setParam("depth", 1);  // an int for a double parameter is fine
  nh.setParam("sectors", 7);
  nh.setParam("command_mode", "cmd_vel");
  nh.setParam("enabled", false);
  const NodeletParams p = loadParams(nh);
  EXPECT_DOUBLE_EQ(p.settings.checker.volume.width, 0.4);
  EXPECT_DOUBLE_EQ(p.settings.checker.volume.depth, 1.0);
  EXPECT_EQ(p.settings.checker.sectors, 7);
  EXPECT_EQ(p.command_mode, CommandMode::CMD_VEL);
  EXPECT_FALSE(p.settings.decision.enabled);
}

TEST(ObstacleParams, BadValuesFailNamingTheParameter)
{
  int n = 0;
  auto ns = [&n]() { return "~bad" + std::to_string(n++); };
  std::string s;

  s = ns(); ros::param::set(s + "/width", -1.0); expectRejected(s, "width");
  s = ns(); ros::param::set(s + "/width", 50.0); expectRejected(s, "width");
  s = ns(); ros::param::set(s + "/depth", 1.5); expectRejected(s, "depth");  // beyond max_range
  s = ns(); ros::param::set(s + "/min_speed", 0.3); expectRejected(s, "min_speed");  // above max_speed
  s = ns(); ros::param::set(s + "/sectors", 0); expectRejected(s, "sectors");
  s = ns(); ros::param::set(s + "/max_turns", 2.5); expectRejected(s, "max_turns");  // wrong type
  s = ns(); ros::param::set(s + "/enabled", std::string("yes")); expectRejected(s, "enabled");
  s = ns(); ros::param::set(s + "/safety_margin", 0.78); ros::param::set(s + "/slow_distance", 0.79);
  expectRejected(s, "safety_margin");  // margin + min_goal_distance >= depth
  s = ns(); ros::param::set(s + "/command_mode", std::string("fly")); expectRejected(s, "command_mode");
  s = ns(); ros::param::set(s + "/control_rate", 0.0); expectRejected(s, "control_rate");
  s = ns(); ros::param::set(s + "/target_frame", std::string("")); expectRejected(s, "target_frame");
}

TEST(ObstacleParams, ConfigValidationForReconfigure)
{
  ObstacleConfig c = ObstacleConfig::__getDefault__();
  EXPECT_EQ(validateConfig(c), "");
  c.min_speed = 0.4;
  EXPECT_EQ(validateConfig(c).rfind("min_speed", 0), 0U) << validateConfig(c);
  c = ObstacleConfig::__getDefault__();
  c.cell_size = 0.5;  // above the cfg's maximum
  EXPECT_EQ(validateConfig(c).rfind("cell_size", 0), 0U) << validateConfig(c);
}

TEST(ObstacleParams, NodeExitsOnABadParameter)
{
  // Run the node with a bad private parameter; it must exit with an error that names it.
  const std::string command =
      "timeout 90 rosrun sl_obstacle obstacle_node __name:=obstacle_bad_param _width:=-0.5 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string output;
  char buffer[512];
  while (fgets(buffer, sizeof(buffer), pipe) != nullptr)
  {
    output += buffer;
  }
  const int status = pclose(pipe);
  ASSERT_TRUE(WIFEXITED(status)) << output;
  EXPECT_NE(WEXITSTATUS(status), 0) << output;
  EXPECT_NE(WEXITSTATUS(status), 124) << "the node did not exit: " << output;
  EXPECT_NE(output.find("parameter ~width"), std::string::npos) << output;
}
}  // namespace
}  // namespace sl_obstacle

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "obstacle_params_rostest");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
