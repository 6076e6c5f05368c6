#include "params.h"

#include <stdexcept>

#include "sl_params/params.h"

namespace sl_navigation
{
namespace
{
template <typename T>
void get(const ros::NodeHandle& pnh, const std::string& name, T& value)
{
  value = sl_params::read(pnh, name, value);
}
}  // namespace

NodeParams readParams(const ros::NodeHandle& pnh)
{
  NodeParams p;
  NavigatorParams& n = p.navigator;
  get(pnh, "odom_frame", p.odom_frame);
  get(pnh, "robot_frame", p.robot_frame);
  get(pnh, "control_rate", p.control_rate);
  get(pnh, "pose_timeout", p.pose_timeout);
  get(pnh, "map_publish_period", p.map_publish_period);
  get(pnh, "map_size", n.grid.size);
  get(pnh, "map_resolution", n.grid.resolution);
  get(pnh, "free_persistence", n.grid.free_persistence);
  get(pnh, "occupied_persistence", n.grid.occupied_persistence);
  get(pnh, "robot_radius", n.planner.robot_radius);
  get(pnh, "lethal_margin", n.planner.lethal_margin);
  get(pnh, "inflation_radius", n.planner.inflation_radius);
  get(pnh, "obstacle_cost", n.planner.obstacle_cost);
  get(pnh, "unknown_cost", n.planner.unknown_cost);
  get(pnh, "escape_radius", n.planner.escape_radius);
  FollowerParams& f = n.follower;
  get(pnh, "max_speed", f.max_speed);
  get(pnh, "min_speed", f.min_speed);
  get(pnh, "max_angular_speed", f.max_angular);
  get(pnh, "turn_speed", f.turn_speed);
  get(pnh, "acceleration", f.acceleration);
  get(pnh, "deceleration", f.deceleration);
  get(pnh, "clearance", f.clearance);
  const double lateral_margin = sl_params::read(pnh, "lateral_margin", 0.02);
  if (!(lateral_margin >= 0.0 && lateral_margin <= 0.5))
  {
    throw std::invalid_argument("parameter ~lateral_margin must be in [0, 0.5] m (got " +
                                std::to_string(lateral_margin) + ")");
  }
  f.swept_radius = n.planner.robot_radius + lateral_margin;
  get(pnh, "lookahead", f.lookahead);
  get(pnh, "rotate_threshold", f.rotate_threshold);
  get(pnh, "look_distance", f.look_distance);
  get(pnh, "look_min_distance", f.look_min_distance);
  get(pnh, "view_angle", f.view_angle);
  get(pnh, "look_tolerance", f.look_tolerance);
  get(pnh, "look_time", f.look_time);
  get(pnh, "goal_tolerance", f.goal_tolerance);
  get(pnh, "yaw_tolerance", f.yaw_tolerance);
  get(pnh, "replan_period", n.replan_period);
  get(pnh, "progress_timeout", n.progress_timeout);
  get(pnh, "progress_distance", n.progress_distance);
  get(pnh, "refuse_time", n.refuse_time);
  get(pnh, "switch_gain", n.switch_gain);
  get(pnh, "max_detour", n.max_detour);
  get(pnh, "stuck_time", n.stuck_time);
  get(pnh, "look_around", n.look_around);
  get(pnh, "refused_memory", n.refused_memory);
  get(pnh, "map_timeout", n.map_timeout);
  get(pnh, "unseen_goal_distance", n.unseen_goal_distance);
  get(pnh, "unseen_goal_time", n.unseen_goal_time);
  get(pnh, "unseen_goal_clearance", n.unseen_goal_clearance);
  const std::string behaviour = sl_params::read(pnh, "behaviour", std::string("navigate"));
  p.cover = behaviour == "cover" || behaviour == "roam";
  CoverageParams& c = p.coverage;
  c.planner = n.planner;
  c.roam = behaviour == "roam";
  get(pnh, "roam_leg", c.roam_leg);
  get(pnh, "lane_spacing", c.lane_spacing);
  get(pnh, "lanes_along_x", c.lanes_along_x);
  get(pnh, "edge_clearance", c.edge_clearance);
  get(pnh, "edge_speed", c.edge_speed);
  get(pnh, "edges_first", c.edges_first);
  get(pnh, "coverage_png", p.coverage_png);
  try
  {
    if (behaviour != "navigate" && behaviour != "cover" && behaviour != "roam")
    {
      throw std::invalid_argument("behaviour must be navigate, cover or roam (got '" + behaviour + "')");
    }
    n.validate();
    c.validate();
    if (!(p.control_rate >= 2.0 && p.control_rate <= 100.0))
    {
      throw std::invalid_argument("control_rate must be in [2, 100] Hz (got " + std::to_string(p.control_rate) + ")");
    }
    if (!(p.pose_timeout > 0.0 && p.pose_timeout <= 5.0))
    {
      throw std::invalid_argument("pose_timeout must be in (0, 5] s (got " + std::to_string(p.pose_timeout) + ")");
    }
    if (!(p.map_publish_period >= 0.1 && p.map_publish_period <= 60.0))
    {
      throw std::invalid_argument("map_publish_period must be in [0.1, 60] s (got " +
                                  std::to_string(p.map_publish_period) + ")");
    }
    if (p.odom_frame.empty() || p.robot_frame.empty())
    {
      throw std::invalid_argument("odom_frame and robot_frame must not be empty");
    }
  }
  catch (const std::invalid_argument& e)
  {
    throw std::invalid_argument(std::string("parameter ~") + e.what());
  }
  return p;
}
}  // namespace sl_navigation
