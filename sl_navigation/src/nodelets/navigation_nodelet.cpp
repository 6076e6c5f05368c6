// The navigation nodelet: goals from move_base_simple/goal and the move_base action, the local map
// (local_map) fused into a persistent map, velocity commands on cmd_vel_in_stamped (through the
// obstacle node's safety filter, whose obstacle_status says how much of each command it let through),
// the plan, the map and the status; with ~behaviour cover, cleaning coverage instead of goals
// (coverage_output.h). The logic is the ROS-free sl_navigation::Navigator and CoverageRunner; this
// file only converts and times.
#include <cmath>
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
#include <tf2_geometry_msgs/tf2_geometry_msgs.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "conversions.h"
#include "coverage_output.h"
#include "params.h"
#include "sl_navigation/coverage_planner.h"

namespace sl_navigation
{
class NavigationNodelet : public nodelet::Nodelet
{
public:
  ~NavigationNodelet() override
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (cover_out_)
    {
      cover_out_->finish(*runner_, ros::Time::now());
    }
  }

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
  /// One cleaning step (cover); @p pose is NaN without odometry (@p why says why).
  void cover(const Pose& pose, const std::string& why, double speed_cap, const ros::Time& now);
  void publishOutput(const NavOutput& out, const ros::Time& now);
  void publishMap(const ros::Time& now);
  const Navigator& navigator() const { return runner_ ? runner_->navigator() : *nav_; }

  NodeParams params_;
  std::unique_ptr<Navigator> nav_;          // navigate
  std::unique_ptr<CoverageRunner> runner_;  // cover: holds its own navigator
  std::unique_ptr<CoverageOutput> cover_out_;
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
    if (params_.cover)
    {
      runner_ = std::make_unique<CoverageRunner>(params_.navigator, params_.coverage);
    }
    else
    {
      nav_ = std::make_unique<Navigator>(params_.navigator);
    }
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
  filter_sub_ = nh.subscribe("obstacle_status", 5, &NavigationNodelet::onFilter, this);
  if (params_.cover)
  {
    cover_out_ = std::make_unique<CoverageOutput>(nh, params_);
  }
  else
  {
    goal_sub_ = nh.subscribe("move_base_simple/goal", 1, &NavigationNodelet::onSimpleGoal, this);
    action_ = std::make_unique<ActionServer>(nh, "move_base", false);
    action_->registerGoalCallback([this] { onActionGoal(); });
    action_->registerPreemptCallback([this] { onActionPreempt(); });
    action_->start();
  }
  // getNodeHandle(): this nodelet's callbacks (timer, subscriptions, actionlib) run one at a time;
  // mutex_ guards against actionlib's own threads, which take their lock before ours.
  timer_ = nh.createTimer(ros::Duration(1.0 / params_.control_rate), &NavigationNodelet::onTimer, this);
  NODELET_INFO("navigation (%s): map %.0f x %.0f m at %.2f m in %s, max_speed %.2f m/s, goal_tolerance %.2f m",
               params_.cover ? "cover" : "navigate", params_.navigator.grid.size, params_.navigator.grid.size,
               params_.navigator.grid.resolution, params_.odom_frame.c_str(), params_.navigator.follower.max_speed,
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
  const double stamp = msg->header.stamp.toSec();
  if (!sized || !(runner_ ? runner_->onMap(v, stamp) : nav_->onMap(v, stamp)))
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
  if (!transformGoal(*tf_buffer_, goal, params_.odom_frame, goal_msg_, why))
  {
    nav_->refuse(why);
    return false;
  }
  why = nav_->setGoal(toNavGoal(goal_msg_), ros::Time::now().toSec());
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

void NavigationNodelet::onTimer(const ros::TimerEvent&)
{
  const ros::Time now = ros::Time::now();
  std::lock_guard<std::mutex> lock(mutex_);
  Pose pose;
  std::string why;
  const bool have_pose =
      lookupPose(*tf_buffer_, params_.odom_frame, params_.robot_frame, params_.pose_timeout, pose, why);
  const double cap = (now - speed_cap_time_).toSec() < 0.5 ? speed_cap_ : std::numeric_limits<double>::infinity();
  if (runner_)
  {
    cover(have_pose ? pose : Pose{ NAN, NAN, NAN }, why, cap, now);
    return;
  }
  if (!have_pose)
  {
    const bool active = nav_->state() == NavState::ACTIVE;
    if (nav_->noPose(now.toSec(), why))
    {
      cmd_pub_.publish(toTwist(0.0, 0.0, params_.robot_frame, now));  // a stop while the pose is missing
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
      action_goal_ = false;
      finishAction(*action_, ended);
    }
    return;
  }
  const NavOutput& out = nav_->step(pose, now.toSec(), cap);
  publishOutput(out, now);
  if (action_goal_ && out.state != NavState::ACTIVE)
  {
    action_goal_ = false;
    finishAction(*action_, out);
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

void NavigationNodelet::cover(const Pose& pose, const std::string& why, double speed_cap, const ros::Time& now)
{
  if (!why.empty())
  {
    NODELET_WARN_THROTTLE(2.0, "%s: stopped", why.c_str());
  }
  const NavOutput& out = runner_->step(pose, now.toSec(), 1.0 / params_.control_rate, speed_cap);
  publishOutput(out, now);
  status_pub_.publish(cover_out_->update(*runner_, out, why, now));
  publishMap(now);
}

void NavigationNodelet::publishOutput(const NavOutput& out, const ros::Time& now)
{
  if (out.command)
  {
    cmd_pub_.publish(toTwist(out.linear, out.angular, params_.robot_frame, now));
  }
  if (out.plan_changed)
  {
    plan_pub_.publish(toPath(navigator().plan().points, params_.odom_frame, now));
  }
}

void NavigationNodelet::publishMap(const ros::Time& now)
{
  if (map_pub_.getNumSubscribers() == 0 || (now - map_published_).toSec() < params_.map_publish_period)
  {
    return;
  }
  map_published_ = now;
  nav_msgs::OccupancyGrid m;
  toGrid(navigator().grid(), now.toSec(), params_.odom_frame, now, m);
  map_pub_.publish(m);
}
}  // namespace sl_navigation

PLUGINLIB_EXPORT_CLASS(sl_navigation::NavigationNodelet, nodelet::Nodelet)
