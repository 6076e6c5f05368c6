#include "robot_link.h"

#include <geometry_msgs/Twist.h>
#include <ros/console.h>
#include <sensor_msgs/PointCloud2.h>

#include "cloud_conversion.h"
#include "status.h"

namespace sl_obstacle
{
RobotLink::RobotLink(ros::NodeHandle& nh, const std::string& name, const NodeletParams& params,
                     const tf2_ros::Buffer& tf, const DriveClient::ResultCallback& on_result,
                     const DriveClient::FeedbackCallback& on_feedback)
  : name_(name),
    params_(params),
    tf_(tf),
    cmd_vel_pub_(nh.advertise<geometry_msgs::Twist>("cmd_vel", 1)),
    status_pub_(nh.advertise<sl_msgs::ObstacleStatus>("obstacle_status", 10)),
    on_result_(on_result),
    on_feedback_(on_feedback)
{
  if (params.command_mode == CommandMode::ACTION)
  {
    drive_ = std::make_unique<DriveClient>(nh);
  }
}

void RobotLink::send(const Actions& actions, const Supervisor& sup, const ros::Time& now, const ros::Time& cloud_stamp,
                     const ros::Time& map_stamp)
{
  for (const Output& o : actions.outputs)
  {
    if (o.kind == Output::Kind::TWIST)
    {
      geometry_msgs::Twist twist;
      twist.linear.x = o.twist.linear;
      twist.angular.z = o.twist.angular;
      cmd_vel_pub_.publish(twist);
    }
    else if (o.kind == Output::Kind::GOAL && drive_)
    {
      drive_->send(o.goal_id, o.distance, o.speed, on_result_, on_feedback_);
    }
    else if (o.kind == Output::Kind::CANCEL_GOAL && drive_)
    {
      drive_->cancel();
    }
    else if (o.kind == Output::Kind::HEARTBEAT && drive_)
    {
      drive_->heartbeat();
    }
  }
  for (const Event& e : actions.events)
  {
    if (e.kind == Event::Kind::OBSTACLES_DROPPED)
    {
      ROS_WARN_THROTTLE_NAMED(5.0, name_, "%s", e.text.c_str());
    }
    else if (e.kind == Event::Kind::GOAL_FAILED)
    {
      ROS_WARN_THROTTLE_NAMED(5.0, name_, "%s", e.text.c_str());
    }
    else
    {
      ROS_INFO_NAMED(name_, "%s", e.text.c_str());
    }
  }
  if (actions.status != StatusKind::NONE)
  {
    fillStatus(sup, actions.status, now, cloud_stamp, map_stamp, params_.target_frame, status_);
    status_pub_.publish(status_);
  }
}

bool RobotLink::robotPose(Pose2D& pose, double& stamp)
{
  try
  {
    const auto t = tf_.lookupTransform(params_.odom_frame, params_.robot_frame, ros::Time(0));
    pose = toPose2D(t.transform);
    stamp = t.header.stamp.toSec();
    return true;
  }
  catch (const tf2::TransformException&)
  {
    return false;
  }
}

bool RobotLink::volumePose(const CloudHandle& cloud, Pose2D& pose, std::string& error)
{
  try
  {
    const ros::Time stamp = std::any_cast<sensor_msgs::PointCloud2::ConstPtr>(cloud)->header.stamp;
    pose = toPose2D(tf_.lookupTransform(params_.odom_frame, params_.target_frame, stamp).transform);
    return true;
  }
  catch (const tf2::TransformException& e)
  {
    error = e.what();
    return false;
  }
}

bool RobotLink::driverReady()
{
  return drive_ ? drive_->connected() : cmd_vel_pub_.getNumSubscribers() > 0;
}

bool transformAt(const tf2_ros::Buffer& tf, const std::string& target, const std_msgs::Header& header,
                 geometry_msgs::Transform& transform, std::string& error)
{
  try
  {
    transform = tf.lookupTransform(target, header.frame_id, header.stamp).transform;
    return true;
  }
  catch (const tf2::TransformException& e)
  {
    error = e.what();
    return false;
  }
}
}  // namespace sl_obstacle
