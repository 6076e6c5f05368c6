#include "conversions.h"

#include <tf2/LinearMath/Quaternion.h>
#include <tf2_geometry_msgs/tf2_geometry_msgs.h>

namespace sl_navigation
{
bool toView(const nav_msgs::OccupancyGrid& msg, OccupancyView& view)
{
  view.data = msg.data.data();
  view.width = static_cast<int>(msg.info.width);
  view.height = static_cast<int>(msg.info.height);
  view.resolution = msg.info.resolution;
  view.origin_x = msg.info.origin.position.x;
  view.origin_y = msg.info.origin.position.y;
  return msg.data.size() == static_cast<std::size_t>(msg.info.width) * msg.info.height && validLayout(view);
}

nav_msgs::Path toPath(const std::vector<Point>& points, const std::string& frame, const ros::Time& stamp)
{
  nav_msgs::Path path;
  path.header.stamp = stamp;
  path.header.frame_id = frame;
  path.poses.reserve(points.size());
  for (const Point& p : points)
  {
    geometry_msgs::PoseStamped s;
    s.header = path.header;
    s.pose.position.x = p.x;
    s.pose.position.y = p.y;
    s.pose.orientation.w = 1.0;
    path.poses.push_back(s);
  }
  return path;
}

sl_msgs::NavigationStatus toStatus(const NavOutput& out, const geometry_msgs::PoseStamped& goal,
                                   const std::string& frame, const ros::Time& stamp)
{
  sl_msgs::NavigationStatus s;
  s.header.stamp = stamp;
  s.header.frame_id = frame;
  s.state = static_cast<std::uint8_t>(out.state);
  s.mode = out.state == NavState::ACTIVE ? toString(out.mode) : "";
  s.reason = out.reason;
  s.goal = goal;
  s.goal_distance = out.goal_distance;
  s.remaining = out.remaining;
  s.elapsed = out.elapsed;
  s.travelled = out.travelled;
  s.linear = out.linear;
  s.angular = out.angular;
  return s;
}

void toGrid(const NavGrid& grid, double now, const std::string& frame, const ros::Time& stamp,
            nav_msgs::OccupancyGrid& msg)
{
  msg.header.stamp = stamp;
  msg.header.frame_id = frame;
  msg.info.map_load_time = stamp;
  msg.info.resolution = static_cast<float>(grid.params().resolution);
  msg.info.width = static_cast<unsigned>(grid.width());
  msg.info.height = static_cast<unsigned>(grid.width());
  msg.info.origin.position.x = grid.originX();
  msg.info.origin.position.y = grid.originY();
  msg.info.origin.orientation.w = 1.0;
  grid.toOccupancy(now, msg.data);
}

geometry_msgs::PoseStamped toPoseStamped(const Pose& pose, const std::string& frame, const ros::Time& stamp)
{
  geometry_msgs::PoseStamped p;
  p.header.stamp = stamp;
  p.header.frame_id = frame;
  p.pose.position.x = pose.x;
  p.pose.position.y = pose.y;
  tf2::Quaternion q;
  q.setRPY(0.0, 0.0, pose.yaw);
  p.pose.orientation = tf2::toMsg(q);
  return p;
}
}  // namespace sl_navigation
