#include "driver_conversions.h"

#include <algorithm>
#include <cmath>

#include "driver_diagnostics.h"

namespace create_driver
{
using sl_msgs::DriveDistanceResult;

static_assert(DriveDistanceResult::REACHED == static_cast<uint8_t>(StopReason::REACHED), "result constants");
static_assert(DriveDistanceResult::PREEMPTED == static_cast<uint8_t>(StopReason::PREEMPTED), "result constants");
static_assert(DriveDistanceResult::BUMPER == static_cast<uint8_t>(StopReason::BUMPER), "result constants");
static_assert(DriveDistanceResult::CLIFF == static_cast<uint8_t>(StopReason::CLIFF), "result constants");
static_assert(DriveDistanceResult::WHEEL_DROP == static_cast<uint8_t>(StopReason::WHEEL_DROP), "result constants");
static_assert(DriveDistanceResult::TIMEOUT == static_cast<uint8_t>(StopReason::TIMEOUT), "result constants");
static_assert(DriveDistanceResult::DISCONNECTED == static_cast<uint8_t>(StopReason::DISCONNECTED), "result constants");
static_assert(DriveDistanceResult::INVALID_GOAL == static_cast<uint8_t>(StopReason::INVALID_GOAL), "result constants");
static_assert(DriveDistanceResult::HEARTBEAT_LOST == static_cast<uint8_t>(StopReason::HEARTBEAT_LOST),
              "result constants");

namespace
{
uint8_t linkStateToMsg(LinkState s)
{
  switch (s)
  {
    case LinkState::DISCONNECTED:
      return Mode::LINK_DISCONNECTED;
    case LinkState::CONNECTING:
      return Mode::LINK_CONNECTING;
    case LinkState::STARTING:
      return Mode::LINK_STARTING;
    case LinkState::RUNNING:
      return Mode::LINK_RUNNING;
  }
  return Mode::LINK_DISCONNECTED;
}

uint8_t powerSupplyStatus(int charging_state)
{
  using sensor_msgs::BatteryState;
  switch (charging_state)
  {
    case 0:
      return BatteryState::POWER_SUPPLY_STATUS_DISCHARGING;
    case 1:
    case 2:
    case 3:
      return BatteryState::POWER_SUPPLY_STATUS_CHARGING;
    case 4:
      return BatteryState::POWER_SUPPLY_STATUS_NOT_CHARGING;
    default:
      return BatteryState::POWER_SUPPLY_STATUS_UNKNOWN;
  }
}
}  // namespace

double commandedLinear(const geometry_msgs::Twist& t)
{
  const bool finite = std::isfinite(t.linear.x) && std::isfinite(t.linear.y) && std::isfinite(t.linear.z) &&
                      std::isfinite(t.angular.x) && std::isfinite(t.angular.y) && std::isfinite(t.angular.z);
  return finite ? t.linear.x : NAN;
}

nav_msgs::Odometry odometryMessage(const DriverSnapshot& s, const ros::Time& stamp, const std::string& odom_frame,
                                   const std::string& base_frame)
{
  nav_msgs::Odometry odom;
  odom.header.stamp = stamp;
  odom.header.frame_id = odom_frame;
  odom.child_frame_id = base_frame;
  odom.pose.pose.position.x = s.pose.x;
  odom.pose.pose.position.y = s.pose.y;
  odom.pose.pose.orientation.z = std::sin(0.5 * s.pose.yaw);
  odom.pose.pose.orientation.w = std::cos(0.5 * s.pose.yaw);
  odom.twist.twist.linear.x = s.linear;
  odom.twist.twist.angular.z = s.angular;
  const double big = 1e6;
  odom.pose.covariance = { 1e-3, 0, 0, 0,   0, 0, 0, 1e-3, 0, 0, 0,   0, 0, 0, big, 0, 0, 0,
                           0,    0, 0, big, 0, 0, 0, 0,    0, 0, big, 0, 0, 0, 0,   0, 0, 3e-3 };
  odom.twist.covariance = { 1e-4, 0, 0, 0,   0, 0, 0, 1e-4, 0, 0, 0,   0, 0, 0, big, 0, 0, 0,
                            0,    0, 0, big, 0, 0, 0, 0,    0, 0, big, 0, 0, 0, 0,   0, 0, 1e-3 };
  return odom;
}

geometry_msgs::TransformStamped odometryTransform(const nav_msgs::Odometry& odom)
{
  geometry_msgs::TransformStamped t;
  t.header = odom.header;
  t.child_frame_id = odom.child_frame_id;
  t.transform.translation.x = odom.pose.pose.position.x;
  t.transform.translation.y = odom.pose.pose.position.y;
  t.transform.rotation = odom.pose.pose.orientation;
  return t;
}

sl_msgs::Hazards hazardsMessage(const HazardReading& h, const ros::Time& stamp, const std::string& base_frame)
{
  sl_msgs::Hazards hz;
  hz.header.stamp = stamp;
  hz.header.frame_id = base_frame;
  hz.bump_left = h.bump_left;
  hz.bump_right = h.bump_right;
  hz.wheel_drop_left = h.wheel_drop_left;
  hz.wheel_drop_right = h.wheel_drop_right;
  hz.wheel_drop_caster = h.wheel_drop_caster;
  hz.cliff_left = h.cliff_left;
  hz.cliff_front_left = h.cliff_front_left;
  hz.cliff_front_right = h.cliff_front_right;
  hz.cliff_right = h.cliff_right;
  hz.latched = h.latched;
  hz.latch_reason = static_cast<uint8_t>(h.latch_reason);
  return hz;
}

sensor_msgs::BatteryState batteryMessage(const SensorState& s, const ros::Time& stamp)
{
  sensor_msgs::BatteryState b;
  b.header.stamp = stamp;
  b.voltage = static_cast<float>(s.get(packet::VOLTAGE) / 1000.0);
  b.current = static_cast<float>(s.get(packet::CURRENT) / 1000.0);
  b.charge = static_cast<float>(s.get(packet::BATTERY_CHARGE) / 1000.0);
  b.capacity = static_cast<float>(s.get(packet::BATTERY_CAPACITY) / 1000.0);
  b.design_capacity = NAN;
  b.percentage = b.capacity > 0.0f ? std::min(1.0f, b.charge / b.capacity) : NAN;
  b.temperature = static_cast<float>(s.get(packet::TEMPERATURE));
  b.power_supply_status = powerSupplyStatus(s.get(packet::CHARGING_STATE));
  b.power_supply_health = s.get(packet::CHARGING_STATE) == 5
                              ? sensor_msgs::BatteryState::POWER_SUPPLY_HEALTH_UNSPEC_FAILURE
                              : sensor_msgs::BatteryState::POWER_SUPPLY_HEALTH_UNKNOWN;
  b.power_supply_technology = sensor_msgs::BatteryState::POWER_SUPPLY_TECHNOLOGY_NIMH;
  b.present = true;
  return b;
}

Mode modeMessage(const ModeReport& r, const std::string& port, uint64_t connects, const ros::Time& stamp)
{
  Mode m;
  m.header.stamp = stamp;
  m.mode = r.reported_mode < 0 ? static_cast<uint8_t>(Mode::UNKNOWN) : static_cast<uint8_t>(r.reported_mode);
  m.mode_name = reportedModeName(r.reported_mode);
  m.requested_mode = static_cast<uint8_t>(r.requested_mode);
  m.link_state = linkStateToMsg(r.link_state);
  m.link_state_name = linkStateName(r.link_state);
  m.port = port;
  m.connects = static_cast<uint32_t>(connects);
  return m;
}

sl_msgs::DriveDistanceResult goalResult(StopReason reason, double travelled, const std::string& message)
{
  DriveDistanceResult r;
  r.distance_travelled = travelled;
  r.reason = static_cast<uint8_t>(reason);
  r.message = message;
  return r;
}

void endGoal(GoalHandle& gh, const GoalOutcome& o)
{
  const DriveDistanceResult r = goalResult(o.reason, o.travelled, o.message);
  switch (goalEnd(o.reason))
  {
    case GoalEnd::SUCCEEDED:
      gh.setSucceeded(r, o.message);
      break;
    case GoalEnd::CANCELED:
      gh.setCanceled(r, o.message);
      break;
    case GoalEnd::ABORTED:
      gh.setAborted(r, o.message);
      break;
  }
}

sl_msgs::DriveDistanceFeedback goalFeedback(const GoalProgress& progress)
{
  sl_msgs::DriveDistanceFeedback fb;
  fb.distance_travelled = progress.travelled;
  fb.distance_remaining = progress.remaining;
  return fb;
}
}  // namespace create_driver
