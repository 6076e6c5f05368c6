// The navigation nodelet: goals from move_base_simple/goal and the move_base action, the local map
// (local_map) fused into a persistent map, velocity commands on cmd_vel_in_stamped (through the
// obstacle node's safety filter, whose obstacle_status says how much of each command it let through),
// the plan, the map and the status. The logic is the ROS-free
// sl_navigation::Navigator; this file only converts and times.
#include <limits>
#include <memory>
#include <mutex>
#include <string>

#include <actionlib/server/simple_action_server.h>
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TwistStamped.h>
#include <move_base_msgs/MoveBaseAction.h>
#include <nav_msgs/OccupancyGrid.h>
#include <nav_msgs/Path.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sl_msgs/NavigationStatus.h>
#include <sl_msgs/ObstacleStatus.h>
#include <tf2/utils.h>
#include <tf2_geometry_msgs/tf2_geometry_msgs.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "conversions.h"
#include "params.h"
#include "sl_navigation/navigator.h"

namespace sl_navigation
{
using ActionServer = actionlib::SimpleActionServer<move_base_msgs::MoveBaseAction>;

class NavigationNodelet : public nodelet::Nodelet
{
private:
  void onInit() override;
  void onMap(const nav_msgs::OccupancyGrid::ConstPtr& msg);
  void onFilter(const sl_msgs::ObstacleStatus::ConstPtr& msg);
  void onSimpleGoal(const geometry_msgs::PoseStamped::ConstPtr& msg);
  void onActionGoal();
  void onActionPreempt();
  /// Transforms @p goal into the odom frame and hands it to the navigator. Caller holds mutex_.
  bool startGoal(const geometry_msgs::PoseStamped& goal, std::string& why);
  void onTimer(const ros::TimerEvent& e);
  bool lookupPose(Pose& pose, std::string& why) const;
  void publishCommand(double linear, double angular, const ros::Time& now);
  void publishMap(const ros::Time& now);
  void finishAction(const NavOutput& out);

  NodeParams params_;
  std::unique_ptr<Navigator> nav_;
  std::mutex mutex_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  std::unique_ptr<ActionServer> action_;
  bool action_goal_ = false;  // the running goal came from the action server
  geometry_msgs::PoseStamped goal_msg_;
  ros::Subscriber map_sub_, goal_sub_, filter_sub_;
  double speed_cap_ = std::numeric_limits<double>::infinity();  // the filter's limit of our last command
  ros::Time speed_cap_time_;
  ros::Publisher cmd_pub_, plan_pub_, status_pub_, map_pub_;
  ros::Timer timer_;
  ros::Time map_published_;
};

void NavigationNodelet::onInit()
{
  ros::NodeHandle& nh = getNodeHandle();
  ros::NodeHandle& pnh = getPrivateNodeHandle();
  try
  {
    params_ = readParams(pnh);
    nav_ = std::make_unique<Navigator>(params_.navigator);
  }
  catch (const std::exception& e)
  {
    NODELET_FATAL("%s", e.what());
    throw;
  }
  tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
  tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, nh);
  cmd_pub_ = nh.advertise<geometry_msgs::TwistStamped>("cmd_vel_in_stamped", 1);
  plan_pub_ = nh.advertise<nav_msgs::Path>("plan", 1, true);
  status_pub_ = nh.advertise<sl_msgs::NavigationStatus>("navigation_status", 10);
  map_pub_ = nh.advertise<nav_msgs::OccupancyGrid>("nav_map", 1);
  map_sub_ = nh.subscribe("local_map", 2, &NavigationNodelet::onMap, this);
  goal_sub_ = nh.subscribe("move_base_simple/goal", 1, &NavigationNodelet::onSimpleGoal, this);
  filter_sub_ = nh.subscribe("obstacle_status", 5, &NavigationNodelet::onFilter, this);
  action_ = std::make_unique<ActionServer>(nh, "move_base", false);
  action_->registerGoalCallback([this] { onActionGoal(); });
  action_->registerPreemptCallback([this] { onActionPreempt(); });
  action_->start();
  // getNodeHandle(): this nodelet's callbacks (timer, subscriptions, actionlib) run one at a time;
  // mutex_ guards against actionlib's own threads, which take their lock before ours.
  timer_ = nh.createTimer(ros::Duration(1.0 / params_.control_rate), &NavigationNodelet::onTimer, this);
  NODELET_INFO("navigation: map %.0f x %.0f m at %.2f m in %s, max_speed %.2f m/s, goal_tolerance %.2f m",
               params_.navigator.grid.size, params_.navigator.grid.size, params_.navigator.grid.resolution,
               params_.odom_frame.c_str(), params_.navigator.follower.max_speed,
               params_.navigator.follower.goal_tolerance);
}

void NavigationNodelet::onMap(const nav_msgs::OccupancyGrid::ConstPtr& msg)
{
  if (msg->header.frame_id != params_.odom_frame)
  {
    NODELET_ERROR_THROTTLE(5.0, "local_map in frame '%s', expected '%s' (~odom_frame): ignored",
                           msg->header.frame_id.c_str(), params_.odom_frame.c_str());
    return;
  }
  OccupancyView v;
  const bool sized = toView(*msg, v);
  std::lock_guard<std::mutex> lock(mutex_);
  if (!sized || !nav_->onMap(v, msg->header.stamp.toSec()))
  {
    NODELET_ERROR_THROTTLE(5.0, "local_map refused: %u x %u cells, %zu values, resolution %g, origin (%g, %g)",
                           msg->info.width, msg->info.height, msg->data.size(), msg->info.resolution, v.origin_x,
                           v.origin_y);
  }
}

void NavigationNodelet::onFilter(const sl_msgs::ObstacleStatus::ConstPtr& msg)
{
  // Only the filter's answers to commands on cmd_vel_in (teleop) that it scaled down count.
  std::lock_guard<std::mutex> lock(mutex_);
  const bool limited = msg->teleop && msg->input_linear > 0.0 && msg->command_scale < 0.999;
  speed_cap_ =
      limited ? std::max(0.0, msg->command_scale * msg->input_linear) : std::numeric_limits<double>::infinity();
  speed_cap_time_ = ros::Time::now();
}

bool NavigationNodelet::startGoal(const geometry_msgs::PoseStamped& goal, std::string& why)
{
  geometry_msgs::PoseStamped in_odom;
  try
  {
    geometry_msgs::PoseStamped latest = goal;
    latest.header.stamp = ros::Time(0);  // the goal is a place, not a moment: the latest transform
    in_odom = tf_buffer_->transform(latest, params_.odom_frame, ros::Duration(0.2));
  }
  catch (const tf2::TransformException& e)
  {
    why = "goal refused: cannot transform it from frame '" + goal.header.frame_id + "' to '" + params_.odom_frame +
          "': " + e.what();
    nav_->refuse(why);
    return false;
  }
  NavGoal g;
  g.x = in_odom.pose.position.x;
  g.y = in_odom.pose.position.y;
  const auto& q = in_odom.pose.orientation;
  const double norm = q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w;
  g.use_yaw = std::isfinite(norm) && norm > 0.5;
  g.yaw = g.use_yaw ? tf2::getYaw(in_odom.pose.orientation) : 0.0;
  why = nav_->setGoal(g, ros::Time::now().toSec());
  goal_msg_ = in_odom;
  return why.empty();
}

void NavigationNodelet::onSimpleGoal(const geometry_msgs::PoseStamped::ConstPtr& msg)
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (action_->isActive())
  {
    action_->setPreempted(move_base_msgs::MoveBaseResult(), "pre-empted by a goal on move_base_simple/goal");
  }
  action_goal_ = false;
  std::string why;
  if (!startGoal(*msg, why))
  {
    NODELET_WARN("%s", why.c_str());
  }
}

void NavigationNodelet::onActionGoal()
{
  std::lock_guard<std::mutex> lock(mutex_);
  const auto goal = action_->acceptNewGoal();
  if (!goal)
  {
    return;
  }
  action_goal_ = true;
  std::string why;
  if (!startGoal(goal->target_pose, why))
  {
    NODELET_WARN("%s", why.c_str());
    action_->setAborted(move_base_msgs::MoveBaseResult(), why);
    action_goal_ = false;
  }
}

void NavigationNodelet::onActionPreempt()
{
  std::lock_guard<std::mutex> lock(mutex_);
  nav_->cancel(ros::Time::now().toSec(), "cancelled by the move_base action client");
  if (action_->isActive())
  {
    action_->setPreempted(move_base_msgs::MoveBaseResult(), "cancelled");
  }
  action_goal_ = false;
}

bool NavigationNodelet::lookupPose(Pose& pose, std::string& why) const
{
  geometry_msgs::TransformStamped t;
  try
  {
    t = tf_buffer_->lookupTransform(params_.odom_frame, params_.robot_frame, ros::Time(0));
  }
  catch (const tf2::TransformException& e)
  {
    why = std::string("no odometry: ") + e.what();
    return false;
  }
  const double age = (ros::Time::now() - t.header.stamp).toSec();
  if (age > params_.pose_timeout)
  {
    why = "no odometry: " + params_.odom_frame + " -> " + params_.robot_frame + " is " + std::to_string(age) +
          " s old (pose_timeout " + std::to_string(params_.pose_timeout) + " s)";
    return false;
  }
  pose.x = t.transform.translation.x;
  pose.y = t.transform.translation.y;
  pose.yaw = tf2::getYaw(t.transform.rotation);
  return true;
}

void NavigationNodelet::onTimer(const ros::TimerEvent&)
{
  const ros::Time now = ros::Time::now();
  std::lock_guard<std::mutex> lock(mutex_);
  Pose pose;
  std::string why;
  if (!lookupPose(pose, why))
  {
    const bool active = nav_->state() == NavState::ACTIVE;
    if (nav_->noPose(now.toSec(), why))
    {
      publishCommand(0.0, 0.0, now);  // keep the filter fed with a stop while the pose is missing
    }
    if (active)
    {
      NODELET_WARN_THROTTLE(2.0, "%s: stopped", why.c_str());
    }
    if (action_goal_ && nav_->state() != NavState::ACTIVE)
    {
      NavOutput ended;
      ended.state = nav_->state();
      ended.reason = why;
      finishAction(ended);
    }
    return;
  }
  const bool cap_fresh = (now - speed_cap_time_).toSec() < 0.5;
  const NavOutput& out =
      nav_->step(pose, now.toSec(), cap_fresh ? speed_cap_ : std::numeric_limits<double>::infinity());
  if (out.command)
  {
    publishCommand(out.linear, out.angular, now);
  }
  if (out.plan_changed)
  {
    plan_pub_.publish(toPath(nav_->plan().points, params_.odom_frame, now));
  }
  if (action_goal_ && out.state != NavState::ACTIVE)
  {
    finishAction(out);
  }
  else if (action_goal_ && action_->isActive())
  {
    move_base_msgs::MoveBaseFeedback feedback;
    feedback.base_position = toPoseStamped(pose, params_.odom_frame, now);
    action_->publishFeedback(feedback);
  }
  status_pub_.publish(toStatus(out, goal_msg_, params_.odom_frame, now));
  publishMap(now);
}

void NavigationNodelet::finishAction(const NavOutput& out)
{
  action_goal_ = false;
  if (!action_->isActive())
  {
    return;
  }
  if (out.state == NavState::SUCCEEDED)
  {
    action_->setSucceeded(move_base_msgs::MoveBaseResult(), out.reason);
  }
  else if (out.state == NavState::CANCELLED)
  {
    action_->setPreempted(move_base_msgs::MoveBaseResult(), out.reason);
  }
  else
  {
    action_->setAborted(move_base_msgs::MoveBaseResult(), out.reason);
  }
}

void NavigationNodelet::publishCommand(double linear, double angular, const ros::Time& now)
{
  geometry_msgs::TwistStamped cmd;
  cmd.header.stamp = now;
  cmd.header.frame_id = params_.robot_frame;
  cmd.twist.linear.x = linear;
  cmd.twist.angular.z = angular;
  cmd_pub_.publish(cmd);
}

void NavigationNodelet::publishMap(const ros::Time& now)
{
  if (map_pub_.getNumSubscribers() == 0 || (now - map_published_).toSec() < params_.map_publish_period)
  {
    return;
  }
  map_published_ = now;
  nav_msgs::OccupancyGrid m;
  toGrid(nav_->grid(), now.toSec(), params_.odom_frame, now, m);
  map_pub_.publish(m);
}
}  // namespace sl_navigation

PLUGINLIB_EXPORT_CLASS(sl_navigation::NavigationNodelet, nodelet::Nodelet)
