// The driver nodelet's messages, made from the supervisor's snapshots and reports.
#pragma once

#include <string>

#include <actionlib/server/action_server.h>
#include <geometry_msgs/Twist.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/BatteryState.h>

#include <sl_msgs/DriveDistanceAction.h>
#include <sl_msgs/Hazards.h>

#include "create_driver/Mode.h"
#include "create_driver/driver_supervisor.h"

namespace create_driver
{
/// The linear speed of a cmd_vel for DriverSupervisor::setVelocity(): NaN when any component is
/// not finite (the command is then rejected).
double commandedLinear(const geometry_msgs::Twist& twist);

/// Odometry of @p s; planar covariances (x, y, yaw grow with travel; z, roll, pitch unused).
nav_msgs::Odometry odometryMessage(const DriverSnapshot& s, const ros::Time& stamp, const std::string& odom_frame,
                                   const std::string& base_frame);

/// The transform odom -> base of an odometry message.
geometry_msgs::TransformStamped odometryTransform(const nav_msgs::Odometry& odom);

/// The hazards message of @p h, in @p base_frame.
sl_msgs::Hazards hazardsMessage(const HazardReading& h, const ros::Time& stamp, const std::string& base_frame);

/// The battery state of sensor packets 21..26 (NiMH; charging state 5 = failure).
sensor_msgs::BatteryState batteryMessage(const SensorState& s, const ros::Time& stamp);

/// The mode message of @p r on @p port, after @p connects connections.
Mode modeMessage(const ModeReport& r, const std::string& port, uint64_t connects, const ros::Time& stamp);

/// The action result of an ended goal.
sl_msgs::DriveDistanceResult goalResult(StopReason reason, double travelled, const std::string& message);

/// The drive_distance action's goal handle.
using GoalHandle = actionlib::ServerGoalHandle<sl_msgs::DriveDistanceAction>;

/// Ends @p gh as goalEnd() says (succeeded, canceled or aborted), with the result of @p o.
void endGoal(GoalHandle& gh, const GoalOutcome& o);

/// The feedback of an active goal.
sl_msgs::DriveDistanceFeedback goalFeedback(const GoalProgress& progress);
}  // namespace create_driver
