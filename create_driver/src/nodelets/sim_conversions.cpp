#include "sim_conversions.h"

#include <cmath>

namespace create_driver
{
geometry_msgs::PoseStamped poseMessage(const Pose2D& p, const ros::Time& stamp, const std::string& world_frame)
{
  geometry_msgs::PoseStamped m;
  m.header.stamp = stamp;
  m.header.frame_id = world_frame;
  m.pose.position.x = p.x;
  m.pose.position.y = p.y;
  m.pose.orientation.z = std::sin(0.5 * p.yaw);
  m.pose.orientation.w = std::cos(0.5 * p.yaw);
  return m;
}

geometry_msgs::TransformStamped poseTransform(const geometry_msgs::PoseStamped& pose, const std::string& robot_frame)
{
  geometry_msgs::TransformStamped t;
  t.header = pose.header;
  t.child_frame_id = robot_frame;
  t.transform.translation.x = pose.pose.position.x;
  t.transform.translation.y = pose.pose.position.y;
  t.transform.rotation = pose.pose.orientation;
  return t;
}

SimStatus statusMessage(const SimRobot& robot, const std::string& pty_path, uint32_t pty_opens, const ros::Time& stamp,
                        const std::string& robot_frame)
{
  SimStatus s;
  s.header.stamp = stamp;
  s.header.frame_id = robot_frame;
  s.mode = static_cast<uint8_t>(robot.mode());
  s.mode_name = oiModeName(robot.mode());
  s.left_wheel_velocity = robot.commandedLeft();
  s.right_wheel_velocity = robot.commandedRight();
  s.linear_velocity = robot.trueLinearVelocity();
  s.angular_velocity = robot.trueAngularVelocity();
  s.streaming = robot.streaming();
  s.waiting = robot.waiting();
  s.contact = robot.contact();
  s.pty_path = pty_path;
  s.pty_opens = pty_opens;
  s.bytes_received = robot.bytesReceived();
  s.bytes_sent = robot.bytesSent();
  s.commands = robot.commands();
  s.refused_commands = robot.refusedCommands();
  s.last_refusal = robot.lastRefusal();
  s.watchdog_stops = robot.watchdogStops();
  return s;
}
}  // namespace create_driver
