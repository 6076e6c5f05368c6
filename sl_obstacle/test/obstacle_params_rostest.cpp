// Rostest: the nodelet's parameters are read and validated in one place and fail fast.
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <ros/ros.h>
#include <sl_testing/errors.h>
#include <sl_testing/process.h>
#include <sl_testing/rostest_main.h>

#include "cloud_conversion.h"
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
  EXPECT_DOUBLE_EQ(p.map_rate, 5.0);
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
  // ~name alone set to value in a fresh namespace: refused, naming it.
  const auto rejects = [&](const std::string& name, const auto& value)
  {
    const std::string space = ns();
    ros::param::set(space + "/" + name, value);
    expectRejected(space, name);
  };
  std::string s;

  rejects("width", -1.0);
  rejects("width", 50.0);
  rejects("depth", 1.5);      // beyond max_range
  rejects("min_speed", 0.3);  // above max_speed
  rejects("sectors", 0);
  rejects("max_turns", 2.5);  // wrong type
  rejects("enabled", std::string("yes"));
  s = ns();
  ros::param::set(s + "/safety_margin", 0.78);
  ros::param::set(s + "/slow_distance", 0.79);
  expectRejected(s, "safety_margin");  // margin + min_goal_distance >= depth
  rejects("command_mode", std::string("fly"));
  rejects("control_rate", 0.0);
  rejects("map_rate", 20.0);  // above control_rate
  rejects("map_rate", std::string("often"));
  rejects("target_frame", std::string(""));
  rejects("odom_frame", 3);  // wrong type
  rejects("map_resolution", 0.5);
  rejects("map_slices", 0);
  rejects("check_distance", 3.0);  // > map_size / 2
  rejects("deceleration", -1.0);
  rejects("use_map", 1.0);  // wrong type
}

TEST(ObstacleParams, FilterDefaultsEqualTheCoreDefaultsAndBadValuesAreNamed)
{
  const NodeletParams p = loadParams(ros::NodeHandle("~defaults"));
  const Settings core;
  const FilterParams& f = p.settings.filter;
  EXPECT_DOUBLE_EQ(f.input_timeout, core.filter.input_timeout);
  EXPECT_DOUBLE_EQ(f.clearance, p.settings.decision.safety_margin);
  EXPECT_DOUBLE_EQ(f.clearance, core.filter.clearance);
  EXPECT_DOUBLE_EQ(f.deceleration, core.filter.deceleration);
  EXPECT_DOUBLE_EQ(f.horizon, p.settings.world.check_distance);
  EXPECT_DOUBLE_EQ(f.stale_timeout, p.settings.decision.stale_timeout);
  EXPECT_DOUBLE_EQ(f.footprint.radius, p.settings.world.footprint.radius);
  EXPECT_DOUBLE_EQ(p.settings.teleop_hold, core.teleop_hold);

  ros::NodeHandle given("~filter_given");
  given.setParam("command_mode", "filter");
  given.setParam("input_timeout", 0.3);
  given.setParam("teleop_hold", 1);
  const NodeletParams q = loadParams(given);
  EXPECT_EQ(q.command_mode, CommandMode::FILTER);
  EXPECT_DOUBLE_EQ(q.settings.filter.input_timeout, 0.3);
  EXPECT_DOUBLE_EQ(q.settings.teleop_hold, 1.0);

  ros::param::set("~filter_bad0/input_timeout", 0.0);
  expectRejected("~filter_bad0", "input_timeout");
  ros::param::set("~filter_bad5/creep_speed", 0.06);  // the creep is 0.05 m/s at most
  expectRejected("~filter_bad5", "creep_speed");
  ros::param::set("~filter_bad1/teleop_hold", -1.0);
  expectRejected("~filter_bad1", "teleop_hold");
  ros::param::set("~filter_bad2/command_mode", std::string("filter"));
  ros::param::set("~filter_bad2/use_map", false);
  expectRejected("~filter_bad2", "command_mode");  // the filter needs the map
  ros::param::set("~filter_bad3/command_mode", 2);
  expectRejected("~filter_bad3", "command_mode");  // wrong type, not silently "action"
  ros::param::set("~filter_bad4/control_rate", std::string("fast"));
  expectRejected("~filter_bad4", "control_rate");
}

TEST(ObstacleParams, MapDefaultsEqualTheCoreDefaults)
{
  const NodeletParams p = loadParams(ros::NodeHandle("~defaults"));
  const Settings core;
  const WorldParams& w = p.settings.world;
  EXPECT_EQ(p.odom_frame, "odom");
  EXPECT_EQ(p.robot_frame, "base_link");
  EXPECT_EQ(w.enabled, core.world.enabled);
  EXPECT_DOUBLE_EQ(w.map.size, core.world.map.size);
  EXPECT_DOUBLE_EQ(w.map.resolution, core.world.map.resolution);
  EXPECT_EQ(w.map.slices, core.world.map.slices);
  EXPECT_DOUBLE_EQ(w.map.decay, core.world.map.decay);
  EXPECT_DOUBLE_EQ(w.map.z_min, p.settings.checker.volume.floor_margin);
  EXPECT_DOUBLE_EQ(w.map.z_max, p.settings.checker.volume.height);
  EXPECT_DOUBLE_EQ(w.footprint.radius, core.world.footprint.radius);
  EXPECT_DOUBLE_EQ(w.footprint.lateral_margin, core.world.footprint.lateral_margin);
  EXPECT_DOUBLE_EQ(w.start_free_radius, core.world.start_free_radius);
  EXPECT_DOUBLE_EQ(w.blind_radius, core.world.blind_radius);
  EXPECT_DOUBLE_EQ(w.clearance, p.settings.decision.safety_margin);
  EXPECT_DOUBLE_EQ(p.settings.decision.creep_speed, core.decision.creep_speed);
  EXPECT_DOUBLE_EQ(p.settings.filter.creep_speed, core.filter.creep_speed);
  EXPECT_DOUBLE_EQ(w.check_distance, core.world.check_distance);
  EXPECT_EQ(w.headings, core.world.headings);
  EXPECT_DOUBLE_EQ(w.heading_step, p.settings.decision.turn_angle);
  EXPECT_DOUBLE_EQ(p.settings.decision.deceleration, core.decision.deceleration);
  EXPECT_EQ(p.settings.decision.max_backoffs, core.decision.max_backoffs);
  EXPECT_DOUBLE_EQ(p.settings.decision.backoff_distance, core.decision.backoff_distance);
  EXPECT_DOUBLE_EQ(p.settings.decision.backoff_speed, core.decision.backoff_speed);
}

/// A cloud of @p n points with FLOAT32 fields x, y, z, sx, sy, sz and, if @p state, UINT8 state.
sensor_msgs::PointCloud2 rayCloud(const std::vector<std::array<float, 7>>& points, bool state = true, bool start = true)
{
  sensor_msgs::PointCloud2 c;
  const char* names[6] = { "x", "y", "z", "sx", "sy", "sz" };
  uint32_t offset = 0;
  for (int i = 0; i < (start ? 6 : 3); ++i, offset += 4)
  {
    sensor_msgs::PointField f;
    f.name = names[i];
    f.offset = offset;
    f.datatype = sensor_msgs::PointField::FLOAT32;
    f.count = 1;
    c.fields.push_back(f);
  }
  if (state)
  {
    sensor_msgs::PointField f;
    f.name = "state";
    f.offset = offset;
    f.datatype = sensor_msgs::PointField::UINT8;
    f.count = 1;
    c.fields.push_back(f);
    offset += 1;
  }
  c.point_step = offset;
  c.width = static_cast<uint32_t>(points.size());
  c.height = 1;
  c.row_step = c.point_step * c.width;
  c.data.resize(c.row_step);
  for (std::size_t k = 0; k < points.size(); ++k)
  {
    uint8_t* p = c.data.data() + k * c.point_step;
    for (int i = 0; i < (start ? 6 : 3); ++i)
    {
      std::memcpy(p + 4 * i, &points[k][static_cast<std::size_t>(i)], 4);
    }
    if (state)
    {
      p[offset - 1] = static_cast<uint8_t>(points[k][6]);
    }
  }
  return c;
}

TEST(RayConversion, StatesBecomeMapRays)
{
  geometry_msgs::Transform shift;
  shift.rotation.w = 1.0;
  shift.translation.x = 1.0;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const sensor_msgs::PointCloud2 c = rayCloud({ { 1, 0, 0.1F, 0, 0, 0.09F, kRayFloor },
                                                { 2, 0, 0.1F, 0.3F, 0, 0.09F, kRayDark },
                                                { 0.5F, 0, 0.1F, 0.3F, 0, 0.09F, kRayLit },
                                                { nan, nan, nan, nan, nan, nan, kRayUnseen },
                                                { nan, 0, 0.1F, 0.3F, 0, 0.09F, kRayDark } });
  std::vector<MapRay> rays;
  ASSERT_EQ(appendRays(c, shift, true, rays), "");
  ASSERT_EQ(rays.size(), 3U) << "unseen and NaN rays add nothing";
  EXPECT_EQ(rays[0].kind, RayKind::Free);
  EXPECT_EQ(rays[1].kind, RayKind::Free);
  EXPECT_EQ(rays[2].kind, RayKind::Suspect);
  EXPECT_FLOAT_EQ(rays[1].ex, 3.0F);
  EXPECT_FLOAT_EQ(rays[1].sx, 1.3F);
  // The decoded points: every one is a Hit ray.
  rays.clear();
  ASSERT_EQ(appendRays(rayCloud({ { 1, 0, 0.1F, 0, 0, 0.09F, 0 } }, false), shift, false, rays), "");
  ASSERT_EQ(rays.size(), 1U);
  EXPECT_EQ(rays[0].kind, RayKind::Hit);
}

TEST(RayConversion, MissingFieldsAreNamed)
{
  geometry_msgs::Transform identity;
  identity.rotation.w = 1.0;
  std::vector<MapRay> rays;
  const std::string no_state = appendRays(rayCloud({ { 1, 0, 0, 0, 0, 0, 0 } }, false), identity, true, rays);
  EXPECT_NE(no_state.find("state"), std::string::npos) << no_state;
  const std::string no_start = appendRays(rayCloud({ { 1, 0, 0, 0, 0, 0, 0 } }, true, false), identity, true, rays);
  EXPECT_NE(no_start.find("sx"), std::string::npos) << no_start;
  sensor_msgs::PointCloud2 short_data = rayCloud({ { 1, 0, 0, 0, 0, 0, 2 }, { 1, 0, 0, 0, 0, 0, 2 } });
  short_data.data.resize(5);
  EXPECT_NE(appendRays(short_data, identity, true, rays).find("data size"), std::string::npos);
  EXPECT_TRUE(rays.empty()) << "a refused cloud adds nothing";
}

// Found by fuzz/cloud_conversion_fuzz.cpp (corpus: empty_cloud_4e9_rows_hang): a cloud of width 0
// passed the layout check whatever its height, and appendRays() walked every empty row: 3 s per
// cloud of height 4e9 in a release build, over 10 s in the fuzz build. Ten seconds of such clouds
// at 10 Hz (100 calls) ran past this rostest's time limit.
TEST(RayConversion, EmptyCloudOfAnyHeightAddsNothingAtOnce)
{
  geometry_msgs::Transform identity;
  identity.rotation.w = 1.0;
  sensor_msgs::PointCloud2 c = rayCloud({ { 1, 0, 0, 0, 0, 0, kRayDark } });
  c.width = 0;
  c.height = std::numeric_limits<uint32_t>::max();
  std::vector<MapRay> rays;
  for (int i = 0; i < 100; ++i)
  {
    ASSERT_EQ(appendRays(c, identity, i % 2 == 0, rays), "");
  }
  EXPECT_TRUE(rays.empty());
  std::vector<Point> points;
  EXPECT_EQ(convertCloud(c, identity, points), "");
  EXPECT_TRUE(points.empty());
}

// Found by fuzz/cloud_conversion_fuzz.cpp (corpus: state_offset_4294967295_oob_read): the state
// field's offset + 1 wrapped to 0 in 32 bits, passed the point_step check, and each ray's state was
// read from the byte before its point.
TEST(RayConversion, StateOffsetOutsideThePointIsRefused)
{
  geometry_msgs::Transform identity;
  identity.rotation.w = 1.0;
  sensor_msgs::PointCloud2 c = rayCloud({ { 1, 0, 0, 0, 0, 0, kRayDark }, { 2, 0, 0, 0, 0, 0, kRayLit } });
  c.fields.back().offset = std::numeric_limits<uint32_t>::max();
  std::vector<MapRay> rays;
  const std::string e = appendRays(c, identity, true, rays);
  EXPECT_NE(e.find("field state must be UINT8 inside point_step"), std::string::npos) << e;
  EXPECT_TRUE(rays.empty());
}

TEST(ObstacleParams, ConfigValidationForReconfigure)
{
  const auto error = [](const ObstacleConfig& c) { return sl_testing::invalidArgumentOf([&] { validateConfig(c); }); };
  ObstacleConfig c = ObstacleConfig::__getDefault__();
  EXPECT_EQ(error(c), "");
  c.min_speed = 0.4;
  EXPECT_EQ(error(c).rfind("min_speed", 0), 0U) << error(c);
  c = ObstacleConfig::__getDefault__();
  c.cell_size = 0.5;  // above the cfg's maximum
  EXPECT_EQ(error(c).rfind("cell_size", 0), 0U) << error(c);
}

TEST(ObstacleParams, NodeExitsOnABadParameter)
{
  // Run the node with a bad private parameter; it must exit with an error that names it.
  const std::string command =
      "timeout 90 rosrun sl_obstacle obstacle_node __name:=obstacle_bad_param _width:=-0.5 2>&1";
  std::string output;
  const int status = sl_testing::runShell(command, output);
  ASSERT_GE(status, 0) << output;
  EXPECT_NE(status, 0) << output;
  EXPECT_NE(status, 124) << "the node did not exit: " << output;
  EXPECT_NE(output.find("parameter ~width"), std::string::npos) << output;
}
}  // namespace
}  // namespace sl_obstacle

int main(int argc, char** argv)
{
  return sl_testing::runRostests(argc, argv, "obstacle_params_rostest", 0);
}
