#include "params.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include <dynamic_reconfigure/Config.h>

#include "sl_params/params.h"

namespace sl_obstacle
{
namespace
{
[[noreturn]] void fail(const std::string& what)
{
  throw std::invalid_argument("parameter ~" + what);
}

template <typename Value>
const Value* findByName(const std::vector<Value>& values, const std::string& name)
{
  for (const Value& v : values)
  {
    if (v.name == name)
    {
      return &v;
    }
  }
  return nullptr;
}

/// Runs @p check, a type check of sl_params; its message gets this node's "parameter " prefix.
template <class F>
void checkTypes(F check)
{
  try
  {
    check();
  }
  catch (const std::invalid_argument& e)
  {
    throw std::invalid_argument(std::string("parameter ") + e.what());
  }
}

/// Fails unless the parameter server value of a parameter has the right type (the value itself is
/// read afterwards, by the caller or __fromServer__).
void checkType(const ros::NodeHandle& pnh, const std::string& name, const std::string& type)
{
  checkTypes([&] { sl_params::checkReconfigureType(pnh, name, type); });
}

/// Reads the rate @p name (a double, Hz) into @p value when set; fails naming it unless it lies in
/// [lo, hi] (@p hi_name: the parameter that sets hi, for the message; empty: none).
void readRate(const ros::NodeHandle& pnh, const std::string& name, double lo, double hi, const std::string& hi_name,
              double& value)
{
  checkType(pnh, name, "double");
  pnh.getParam(name, value);
  if (!(value >= lo && value <= hi))
  {
    std::ostringstream s;
    s << name << " must be in [" << lo << ", " << (hi_name.empty() ? "" : hi_name + " = ") << hi << "] Hz (got "
      << value << ")";
    fail(s.str());
  }
}
}  // namespace

Settings toSettings(const ObstacleConfig& c)
{
  Settings s;
  WorkingVolume& v = s.checker.volume;
  v.width = c.width;
  v.height = c.height;
  v.depth = c.depth;
  v.floor_margin = c.floor_margin;
  v.max_range = c.max_range;
  s.checker.min_confidence = c.min_confidence;
  s.checker.sectors = c.sectors;
  s.checker.cell_size = c.cell_size;
  s.checker.noise.min_cluster_size = c.min_cluster_size;
  s.checker.noise.cluster_tolerance = c.cluster_tolerance;
  s.checker.noise.persistence_frames = c.persistence_frames;
  s.checker.noise.persistence_tolerance = c.persistence_tolerance;
  DecisionParams& d = s.decision;
  d.enabled = c.enabled;
  d.safety_margin = c.safety_margin;
  d.min_goal_distance = c.min_goal_distance;
  d.slow_distance = c.slow_distance;
  d.max_speed = c.max_speed;
  d.min_speed = c.min_speed;
  d.min_coverage = c.min_coverage;
  d.full_speed_coverage = c.full_speed_coverage;
  d.stale_timeout = c.stale_timeout;
  d.preempt_tolerance = c.preempt_tolerance;
  d.replan_distance = c.replan_distance;
  d.speed_tolerance = c.speed_tolerance;
  d.turn_speed = c.turn_speed;
  d.turn_angle = c.turn_angle;
  d.max_turns = c.max_turns;
  d.settle_time = c.settle_time;
  d.deceleration = c.deceleration;
  d.max_backoffs = c.max_backoffs;
  d.backoff_distance = c.backoff_distance;
  d.backoff_speed = c.backoff_speed;
  d.creep_speed = c.creep_speed;
  WorldParams& w = s.world;
  w.enabled = c.use_map;
  w.map.size = c.map_size;
  w.map.resolution = c.map_resolution;
  w.map.slices = c.map_slices;
  w.map.decay = c.map_decay;
  w.map.z_min = c.floor_margin;
  w.map.z_max = c.height;
  w.footprint.radius = c.robot_radius;
  w.footprint.lateral_margin = c.lateral_margin;
  w.start_free_radius = c.start_free_radius;
  w.check_distance = c.check_distance;
  w.heading_step = c.turn_angle;
  w.clearance = c.safety_margin;
  w.blind_radius = c.blind_radius;
  w.headings = c.headings;
  FilterParams& f = s.filter;
  f.footprint = w.footprint;
  f.clearance = c.safety_margin;
  f.obstacle_clearance = c.obstacle_margin < 0.0 ? c.safety_margin : c.obstacle_margin;
  f.creep_view = c.creep_view_distance < 0.0 ? c.safety_margin : c.creep_view_distance;
  f.deceleration = c.deceleration;
  f.horizon = c.check_distance;
  f.input_timeout = c.input_timeout;
  f.stale_timeout = c.stale_timeout;
  f.creep_speed = c.creep_speed;
  f.edge_clearance = c.edge_margin;
  f.edge_speed = c.edge_speed;
  s.teleop_hold = c.teleop_hold;
  return s;
}

bool changesWorld(const ObstacleConfig& a, const ObstacleConfig& b)
{
  return a.map_size != b.map_size || a.map_resolution != b.map_resolution || a.map_slices != b.map_slices ||
         a.map_decay != b.map_decay || a.start_free_radius != b.start_free_radius || a.blind_radius != b.blind_radius ||
         a.robot_radius != b.robot_radius || a.lateral_margin != b.lateral_margin ||
         a.check_distance != b.check_distance || a.headings != b.headings || a.turn_angle != b.turn_angle ||
         a.floor_margin != b.floor_margin || a.height != b.height;
}

void validateConfig(const ObstacleConfig& config)
{
  // Ranges of Obstacle.cfg: compare with the clamped copy, parameter by parameter.
  ObstacleConfig clamped = config;
  clamped.__clamp__();
  dynamic_reconfigure::Config given;
  dynamic_reconfigure::Config limited;
  dynamic_reconfigure::Config low;
  dynamic_reconfigure::Config high;
  config.__toMessage__(given);
  clamped.__toMessage__(limited);
  ObstacleConfig::__getMin__().__toMessage__(low);
  ObstacleConfig::__getMax__().__toMessage__(high);
  for (const auto& d : given.doubles)
  {
    const auto* l = findByName(limited.doubles, d.name);
    if (!std::isfinite(d.value) || (l != nullptr && l->value != d.value))
    {
      std::ostringstream s;
      s << d.name << " must be in [" << findByName(low.doubles, d.name)->value << ", "
        << findByName(high.doubles, d.name)->value << "] (got " << d.value << ")";
      throw std::invalid_argument(s.str());
    }
  }
  for (const auto& i : given.ints)
  {
    const auto* l = findByName(limited.ints, i.name);
    if (l != nullptr && l->value != i.value)
    {
      std::ostringstream s;
      s << i.name << " must be in [" << findByName(low.ints, i.name)->value << ", "
        << findByName(high.ints, i.name)->value << "] (got " << i.value << ")";
      throw std::invalid_argument(s.str());
    }
  }
  toSettings(config).validate();
}

namespace
{
/// Reads a non-empty string parameter; a value of another type is an error, not the default.
void readFrame(const ros::NodeHandle& pnh, const std::string& name, std::string& value)
{
  checkType(pnh, name, "str");
  pnh.getParam(name, value);
  if (value.empty())
  {
    fail(name + " must not be empty");
  }
}
}  // namespace

std::string reconfigureError(const ObstacleConfig& config, const ObstacleConfig& old)
{
  try
  {
    validateConfig(config);
  }
  catch (const std::invalid_argument& invalid)
  {
    return invalid.what();
  }
  return config.use_map != old.use_map ? "use_map is read at start-up only" : "";
}

NodeletParams loadParams(const ros::NodeHandle& pnh)
{
  NodeletParams p;
  readFrame(pnh, "target_frame", p.target_frame);
  readFrame(pnh, "odom_frame", p.odom_frame);
  readFrame(pnh, "robot_frame", p.robot_frame);
  std::string mode = "action";
  checkType(pnh, "command_mode", "str");
  pnh.getParam("command_mode", mode);
  if (mode == "action")
  {
    p.command_mode = CommandMode::ACTION;
  }
  else if (mode == "cmd_vel")
  {
    p.command_mode = CommandMode::CMD_VEL;
  }
  else if (mode == "filter")
  {
    p.command_mode = CommandMode::FILTER;
  }
  else
  {
    fail("command_mode must be \"action\", \"cmd_vel\" or \"filter\" (got \"" + mode + "\")");
  }
  readRate(pnh, "control_rate", 1.0, 100.0, "", p.control_rate);
  readRate(pnh, "map_rate", 0.1, p.control_rate, "control_rate", p.map_rate);  // published on the timer's steps

  p.config = ObstacleConfig::__getDefault__();
  checkTypes([&] { sl_params::checkReconfigureTypes<ObstacleConfig>(pnh); });
  ros::NodeHandle copy(pnh);
  p.config.__fromServer__(copy);
  try
  {
    validateConfig(p.config);
  }
  catch (const std::invalid_argument& e)
  {
    fail(e.what());
  }
  p.settings = toSettings(p.config);
  if (p.command_mode == CommandMode::FILTER && !p.config.use_map)
  {
    fail("command_mode filter needs use_map true (the filter checks paths on the local map)");
  }
  return p;
}
}  // namespace sl_obstacle
