// Benchmark reference only, not a product mode: the bump-and-turn baseline (sl_evaluation/
// bump_baseline.h) driving a Create directly through create_driver, with no obstacle node in the
// loop. Reads the driver's odometry and hazards, sends cmd_vel at every odometry message (about
// 66 Hz, well inside the driver's 0.25 s command watchdog) and calls reset_hazard when the driver's
// latch outlives a contact.
#include <atomic>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>

#include <geometry_msgs/Twist.h>
#include <nav_msgs/Odometry.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sl_msgs/Hazards.h>
#include <std_msgs/String.h>
#include <std_srvs/Trigger.h>

#include "sl_evaluation/bump_baseline.h"
#include "sl_params/params.h"

namespace sl_evaluation
{

/**
 * Nodelet `sl_evaluation/bump_baseline`: subscribes `odom` (nav_msgs/Odometry) and `hazards`
 * (sl_msgs/Hazards), publishes `cmd_vel` (geometry_msgs/Twist) and `~status` (std_msgs/String,
 * latched: "<STATE> bumps <n> resets <n> travelled <m> m", at every change of state), calls
 * `reset_hazard` (std_srvs/Trigger). Starts driving at the first odometry message after the first
 * hazards message. Parameters (private, every one in launch/bump_baseline.launch): those of
 * BumpBaselineConfig, of the same names.
 */
class BumpBaselineNodelet : public nodelet::Nodelet
{
private:
  void onInit() override
  {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    BumpBaselineConfig config;
    try
    {
      sl_params::readIfSet(pnh, "forward_speed", config.forward_speed);
      sl_params::readIfSet(pnh, "back_speed", config.back_speed);
      sl_params::readIfSet(pnh, "back_distance", config.back_distance);
      sl_params::readIfSet(pnh, "max_back_distance", config.max_back_distance);
      sl_params::readIfSet(pnh, "turn_speed", config.turn_speed);
      sl_params::readIfSet(pnh, "min_turn", config.min_turn);
      sl_params::readIfSet(pnh, "max_turn", config.max_turn);
      config.seed = static_cast<std::uint32_t>(sl_params::readInRange<int>(pnh, "seed", 1, 0, 2147483647));
      sl_params::readIfSet(pnh, "duration", config.duration);
      sl_params::readIfSet(pnh, "reset_interval", config.reset_interval);
      try
      {
        policy_ = std::make_unique<BumpBaseline>(config);  // validates, naming the parameter
      }
      catch (const std::invalid_argument& e)
      {
        throw std::invalid_argument(std::string("~") + e.what());
      }
    }
    catch (const std::exception& e)
    {
      NODELET_FATAL("invalid parameter: %s", e.what());
      throw;
    }
    cmd_pub_ = nh.advertise<geometry_msgs::Twist>("cmd_vel", 10);
    status_pub_ = pnh.advertise<std_msgs::String>("status", 10, true);
    reset_client_ = nh.serviceClient<std_srvs::Trigger>("reset_hazard");
    hazards_sub_ = nh.subscribe("hazards", 10, &BumpBaselineNodelet::onHazards, this);
    odom_sub_ = nh.subscribe("odom", 10, &BumpBaselineNodelet::onOdom, this);
    NODELET_INFO(
        "bump-and-turn baseline: %.2f m/s until the bumper touches, back %.3f m at %.2f m/s, turn %.2f..%.2f "
        "rad at %.2f rad/s, seed %u%s",
        config.forward_speed, config.back_distance, config.back_speed, config.min_turn, config.max_turn,
        config.turn_speed, config.seed, config.duration > 0.0 ? ", for a limited time" : "");
  }

  void onHazards(const sl_msgs::Hazards& msg)
  {
    have_hazards_ = true;
    bumper_ = msg.bump_left || msg.bump_right;
    latched_ = msg.latched;
  }

  void onOdom(const nav_msgs::Odometry& msg)
  {
    if (!have_hazards_)
    {
      NODELET_INFO_THROTTLE(5.0, "waiting for the driver's hazards before driving");
      return;
    }
    const geometry_msgs::Quaternion& q = msg.pose.pose.orientation;
    BumpBaselineInput in;
    in.time = (msg.header.stamp.isZero() ? ros::Time::now() : msg.header.stamp).toSec();
    in.x = msg.pose.pose.position.x;
    in.y = msg.pose.pose.position.y;
    in.yaw = std::atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
    in.bumper = bumper_;
    in.latched = latched_;
    const bool finite = std::isfinite(in.x) && std::isfinite(in.y) && std::isfinite(in.yaw);
    if (!finite)
      NODELET_ERROR_THROTTLE(5.0, "odom: non-finite pose ignored (the robot is stopped meanwhile)");
    const BumpBaselineCommand cmd = policy_->step(in);
    geometry_msgs::Twist twist;
    twist.linear.x = cmd.linear;
    twist.angular.z = cmd.angular;
    cmd_pub_.publish(twist);
    if (cmd.reset_hazard)
      resetHazard();
    if (finite && (!published_ || policy_->state() != last_state_))  // the first status: the start
    {
      published_ = true;
      last_state_ = policy_->state();
      std_msgs::String status;
      char text[160];
      std::snprintf(text, sizeof(text), "%s bumps %d resets %d travelled %.2f m", BumpBaseline::stateName(last_state_),
                    policy_->bumps(), policy_->resets(), policy_->travelled());
      status.data = text;
      status_pub_.publish(status);
      NODELET_DEBUG("%s", text);
    }
  }

  void resetHazard()
  {
    std_srvs::Trigger srv;
    if (!reset_client_.call(srv))
      NODELET_WARN_THROTTLE(5.0, "reset_hazard: the service %s did not answer", reset_client_.getService().c_str());
    else if (!srv.response.success)
      NODELET_INFO_THROTTLE(5.0, "reset_hazard refused: %s", srv.response.message.c_str());
  }

  std::unique_ptr<BumpBaseline> policy_;
  // Written by the hazards callback, read by the odometry one (the manager's threads may differ).
  std::atomic<bool> have_hazards_{ false };
  std::atomic<bool> bumper_{ false };
  std::atomic<bool> latched_{ false };
  bool published_ = false;
  BumpBaseline::State last_state_ = BumpBaseline::State::FORWARD;
  ros::Publisher cmd_pub_, status_pub_;
  ros::ServiceClient reset_client_;
  ros::Subscriber hazards_sub_, odom_sub_;
};

}  // namespace sl_evaluation

PLUGINLIB_EXPORT_CLASS(sl_evaluation::BumpBaselineNodelet, nodelet::Nodelet)
