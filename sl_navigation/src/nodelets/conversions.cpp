#include "conversions.h"

#include <cmath>

#include <tf2/LinearMath/Quaternion.h>
#include <tf2/utils.h>
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

NavGoal toNavGoal(const geometry_msgs::PoseStamped& goal)
{
  NavGoal g;
  g.x = goal.pose.position.x;
  g.y = goal.pose.position.y;
  const auto& q = goal.pose.orientation;
  const double norm = q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w;
  g.use_yaw = std::isfinite(norm) && norm > 0.5;
  g.yaw = g.use_yaw ? tf2::getYaw(q) : 0.0;
  return g;
}

bool transformGoal(const tf2_ros::Buffer& tf, const geometry_msgs::PoseStamped& goal, const std::string& frame,
                   geometry_msgs::PoseStamped& out, std::string& why)
{
  try
  {
    geometry_msgs::PoseStamped latest = goal;
    latest.header.stamp = ros::Time(0);
    out = tf.transform(latest, frame, ros::Duration(0.2));
    return true;
  }
  catch (const tf2::TransformException& e)
  {
    why = "goal refused: cannot transform it from frame '" + goal.header.frame_id + "' to '" + frame + "': " + e.what();
    return false;
  }
}

geometry_msgs::TwistStamped toTwist(double linear, double angular, const std::string& frame, const ros::Time& stamp)
{
  geometry_msgs::TwistStamped cmd;
  cmd.header.stamp = stamp;
  cmd.header.frame_id = frame;
  cmd.twist.linear.x = linear;
  cmd.twist.angular.z = angular;
  return cmd;
}

bool lookupPose(const tf2_ros::Buffer& tf, const std::string& odom, const std::string& robot, double timeout,
                Pose& pose, std::string& why)
{
  geometry_msgs::TransformStamped t;
  try
  {
    t = tf.lookupTransform(odom, robot, ros::Time(0));
  }
  catch (const tf2::TransformException& e)
  {
    why = std::string("no odometry: ") + e.what();
    return false;
  }
  const double age = (ros::Time::now() - t.header.stamp).toSec();
  if (age > timeout)
  {
    why = "no odometry: " + odom + " -> " + robot + " is " + std::to_string(age) + " s old (pose_timeout " +
          std::to_string(timeout) + " s)";
    return false;
  }
  pose.x = t.transform.translation.x;
  pose.y = t.transform.translation.y;
  pose.yaw = tf2::getYaw(t.transform.rotation);
  return true;
}

void finishAction(ActionServer& action, const NavOutput& out)
{
  if (!action.isActive())
  {
    return;
  }
  if (out.state == NavState::SUCCEEDED)
  {
    action.setSucceeded(move_base_msgs::MoveBaseResult(), out.reason);
  }
  else if (out.state == NavState::CANCELLED)
  {
    action.setPreempted(move_base_msgs::MoveBaseResult(), out.reason);
  }
  else
  {
    action.setAborted(move_base_msgs::MoveBaseResult(), out.reason);
  }
}
}  // namespace sl_navigation
