// create_driver/driver: the ROS face of DriverCore + SerialLink. Parameters are read and
// checked in loadParameters(); everything else is message conversion.
#include <atomic>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>

#include <actionlib/server/action_server.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/Twist.h>
#include <nav_msgs/Odometry.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/BatteryState.h>
#include <std_msgs/Empty.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/transform_broadcaster.h>

#include <sl_msgs/DriveDistanceAction.h>
#include <sl_msgs/Hazards.h>

#include "create_driver/Mode.h"
#include "create_driver/driver_core.h"
#include "create_driver/serial_link.h"
#include "driver_diagnostics.h"
#include "sl_params/params.h"

namespace create_driver
{
// The drive_distance action and the hazards message are shared with their users (sl_msgs).
using sl_msgs::DriveDistanceAction;
using sl_msgs::DriveDistanceFeedback;
using sl_msgs::DriveDistanceResult;
using sl_msgs::Hazards;

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
void require(bool ok, const std::string& message)
{
  if (!ok)
    throw std::invalid_argument(message);
}

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

}  // namespace

/// @brief Nodelet create_driver/driver (see README.md for its ROS interface).
class DriverNodelet : public nodelet::Nodelet
{
public:
  ~DriverNodelet() override
  {
    if (!link_)
      return;
    // No more ROS input; then stop the wheels, pause the stream and leave the robot in Passive
    // so it can charge, and only then stop the worker thread.
    diag_timer_.stop();
    cmd_sub_.shutdown();
    heartbeat_sub_.shutdown();
    reset_srv_.shutdown();
    Bytes bye;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      core_->shutdown(bye);
    }
    link_->stop(bye, 0.5);
    if (ros::ok())
      processOutcomes();
    // No goal callbacks after this point (the stopped link ignores requestControl()).
    server_.reset();
  }

private:
  using Server = actionlib::ActionServer<DriveDistanceAction>;
  using GoalHandle = Server::GoalHandle;

  /// Snapshot of what is published after frames, taken under the lock.
  struct Snapshot
  {
    SensorState sensors;
    Pose2D pose;
    double v = 0.0, w = 0.0;
    bool latched = false;
    Hazard latch_reason = Hazard::NONE;
    GoalProgress progress;
    int reported_mode = -1;
  };

  void onInit() override
  {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    loadParameters(pnh);
    core_ = std::make_unique<DriverCore>(config_);

    odom_pub_ = nh.advertise<nav_msgs::Odometry>("odom", 10);
    hazards_pub_ = nh.advertise<Hazards>("hazards", 10, true);
    battery_pub_ = nh.advertise<sensor_msgs::BatteryState>("battery", 1, true);
    mode_pub_ = nh.advertise<Mode>("mode", 1, true);
    if (publish_tf_)
      tf_ = std::make_unique<tf2_ros::TransformBroadcaster>();
    reset_srv_ = nh.advertiseService("reset_hazard", &DriverNodelet::resetHazard, this);
    cmd_sub_ = nh.subscribe("cmd_vel", 10, &DriverNodelet::cmdVel, this);
    // In the action's namespace, so that a remap of drive_distance moves it along.
    heartbeat_sub_ = ros::NodeHandle(nh, "drive_distance").subscribe("heartbeat", 10, &DriverNodelet::heartbeat, this);

    server_ = std::make_unique<Server>(
        nh, "drive_distance", [this](GoalHandle gh) { goalCallback(gh); },
        [this](GoalHandle gh) { cancelCallback(gh); }, false);
    server_->start();

    updater_ = std::make_unique<diagnostic_updater::Updater>(nh, pnh, getName());
    updater_->setHardwareID("iRobot Create OI on " + link_params_.port);
    updater_->add("Connection", this, &DriverNodelet::diagConnection);
    updater_->add("Sensor stream", this, &DriverNodelet::diagStream);
    updater_->add("Control loop", this, &DriverNodelet::diagControl);
    updater_->add("Safety", this, &DriverNodelet::diagSafety);
    updater_->add("Commands", this, &DriverNodelet::diagCommands);
    updater_->add("Battery", this, &DriverNodelet::diagBattery);
    diag_timer_ = nh.createWallTimer(ros::WallDuration(0.5),
                                     [this](const ros::WallTimerEvent&)
                                     {
                                       updater_->update();
                                       publishMode();
                                     });

    SerialLink::Handlers h;
    h.on_open = [this](double now, Bytes& out)
    {
      std::lock_guard<std::mutex> lock(mutex_);
      pending_out_.clear();
      core_->onConnected(now, out);
    };
    h.on_data = [this](const uint8_t* data, size_t len, double now, Bytes& out)
    {
      size_t n = 0;
      Snapshot snap;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        n = core_->onBytes(data, len, now, out);
        flushPending(out);
        if (n > 0)
          snap = snapshot();
      }
      if (n > 0)
        publish(snap, now);
      reportWatchdog();
      processOutcomes();
      return n;
    };
    h.on_tick = [this](double now, Bytes& out)
    {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        core_->control(now, out);
        flushPending(out);
      }
      reportWatchdog();
      processOutcomes();
    };
    h.on_state = [this](LinkState state, const std::string& reason) { linkState(state, reason); };
    link_ = std::make_unique<SerialLink>(link_params_, h);
    link_->start();
    NODELET_INFO("create_driver: %s on %s at %u baud, %s mode", model_name_.c_str(), link_params_.port.c_str(),
                 link_params_.baud, oiModeName(config_.mode));
  }

  void loadParameters(const ros::NodeHandle& pnh)
  {
    model_name_ = sl_params::read<std::string>(pnh, "model", "create_1");
    if (model_name_ == "create_1" || model_name_ == "create")
      config_.model = Model::CREATE_1;
    else if (model_name_ == "create_2" || model_name_ == "roomba_600")
      config_.model = Model::CREATE_2;
    else
      throw std::invalid_argument("~model must be create_1 or create_2 (got '" + model_name_ + "')");

    link_params_.port = sl_params::read<std::string>(pnh, "port", "/dev/ttyUSB0");
    link_params_.baud = sl_params::read<unsigned>(pnh, "baud", defaultBaud(config_.model));

    const std::string mode = sl_params::read<std::string>(pnh, "oi_mode", "safe");
    if (mode == "safe")
      config_.mode = OiMode::SAFE;
    else if (mode == "full")
      config_.mode = OiMode::FULL;
    else if (mode == "passive")
      config_.mode = OiMode::PASSIVE;
    else
      throw std::invalid_argument("~oi_mode must be safe, full or passive (got '" + mode + "')");

    const std::string drive = sl_params::read<std::string>(pnh, "drive_command", "direct");
    if (drive == "direct")
      config_.drive_type = DriveCommandType::DIRECT;
    else if (drive == "radius")
      config_.drive_type = DriveCommandType::RADIUS;
    else
      throw std::invalid_argument("~drive_command must be direct or radius (got '" + drive + "')");

    // Ranges: validateConfig() and SerialLinkParams::validate() below, the only place they live.
    const double wheel_base = sl_params::read<double>(pnh, "wheel_base", defaultWheelBase(config_.model));
    config_.limits.wheel_base = wheel_base;
    config_.odometry.wheel_base = wheel_base;
    config_.limits.max_speed = sl_params::read<double>(pnh, "max_speed", 0.5);
    config_.limits.max_angular_speed = sl_params::read<double>(pnh, "max_angular_speed", 2.0 * 0.5 / wheel_base);
    config_.limits.max_accel = sl_params::read<double>(pnh, "max_accel", 1.0);
    config_.limits.max_angular_accel = sl_params::read<double>(pnh, "max_angular_accel", 6.0);

    require(!pnh.hasParam("cmd_vel_timeout"),
            "~cmd_vel_timeout is not a parameter of this driver: ~command_timeout (at most 0.3 s) bounds cmd_vel "
            "and drive_distance heartbeats alike");
    config_.command_timeout = sl_params::read<double>(pnh, "command_timeout", 0.25);
    config_.cmd_vel_preempts_goal = sl_params::read<bool>(pnh, "cmd_vel_preempts_goal", true);
    config_.use_wait_distance = sl_params::read<bool>(pnh, "use_wait_distance", false);
    config_.command_refresh = sl_params::read<double>(pnh, "command_refresh", 0.2);

    DriveDistanceParams& d = config_.drive_distance;
    d.max_speed = config_.limits.max_speed;
    d.min_speed = sl_params::read<double>(pnh, "drive_distance/min_speed", 0.01);
    d.decel = sl_params::read<double>(pnh, "drive_distance/decel", 0.25);
    d.tolerance = sl_params::read<double>(pnh, "drive_distance/tolerance", 0.001);
    d.latency = sl_params::read<double>(pnh, "drive_distance/latency", 0.03);
    d.stall_timeout = sl_params::read<double>(pnh, "drive_distance/stall_timeout", 3.0);
    d.heading_gain = sl_params::read<double>(pnh, "drive_distance/heading_gain", 1.0);
    d.max_heading_rate = sl_params::read<double>(pnh, "drive_distance/max_heading_rate", 0.3);

    odom_frame_ = sl_params::read<std::string>(pnh, "odom_frame", "odom");
    base_frame_ = sl_params::read<std::string>(pnh, "base_frame", "base_link");
    require(!odom_frame_.empty() && !base_frame_.empty() && odom_frame_ != base_frame_,
            "~odom_frame and ~base_frame must be non-empty and different");
    publish_tf_ = sl_params::read<bool>(pnh, "publish_tf", true);

    link_params_.link.initial_backoff = sl_params::read<double>(pnh, "reconnect_initial_delay", 0.25);
    link_params_.link.max_backoff = sl_params::read<double>(pnh, "reconnect_max_delay", 4.0);
    link_params_.link.frame_timeout = sl_params::read<double>(pnh, "link_timeout", 1.0);
    link_params_.link.start_timeout = sl_params::read<double>(pnh, "start_timeout", 3.0);
    link_params_.tick_period = sl_params::read<double>(pnh, "control_period", 0.01);

    try
    {
      validateConfig(config_);
      link_params_.validate();
    }
    catch (const std::invalid_argument& e)
    {
      throw std::invalid_argument(std::string("~") + e.what());
    }
  }

  // ---- ROS callbacks -----------------------------------------------------------------------

  void cmdVel(const geometry_msgs::Twist::ConstPtr& msg)
  {
    const bool finite = std::isfinite(msg->linear.x) && std::isfinite(msg->linear.y) && std::isfinite(msg->linear.z) &&
                        std::isfinite(msg->angular.x) && std::isfinite(msg->angular.y) && std::isfinite(msg->angular.z);
    std::string error;
    bool ok = false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ok = core_->setVelocity(finite ? msg->linear.x : NAN, msg->angular.z, steadyNow(), &error);
    }
    if (!ok)
      NODELET_ERROR_THROTTLE(1.0, "cmd_vel rejected: %s", error.c_str());
    processOutcomes();
    link_->requestControl();
  }

  void heartbeat(const std_msgs::Empty::ConstPtr&)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    core_->heartbeat(steadyNow());
  }

  void goalCallback(GoalHandle gh)
  {
    const auto goal = gh.getGoal();
    GoalStart start;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      start = core_->startGoal(goal->distance, goal->speed, steadyNow(), pending_out_);
      if (start.accepted)
        goals_[start.id] = gh;
    }
    if (!start.accepted)
    {
      DriveDistanceResult r;
      r.reason = static_cast<uint8_t>(start.reason);
      r.message = start.message;
      r.distance_travelled = 0.0;
      NODELET_WARN("drive_distance goal rejected: %s", start.message.c_str());
      gh.setRejected(r, start.message);
    }
    else
    {
      gh.setAccepted();
    }
    processOutcomes();  // the replaced goal, or a zero-distance goal that is already done
    link_->requestControl();
  }

  void cancelCallback(GoalHandle gh)
  {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      for (const auto& kv : goals_)
        if (kv.second == gh)
          core_->cancelGoal(kv.first, StopReason::PREEMPTED, "cancelled");
    }
    processOutcomes();
    link_->requestControl();
  }

  bool resetHazard(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    res.success = core_->resetHazard(&res.message);
    return true;
  }

  // ---- worker-thread side ------------------------------------------------------------------

  void flushPending(Bytes& out)
  {
    if (!pending_out_.empty())
    {
      out.insert(out.end(), pending_out_.begin(), pending_out_.end());
      pending_out_.clear();
    }
  }

  Snapshot snapshot() const
  {
    Snapshot s;
    s.sensors = core_->sensors();
    s.pose = core_->odometry().pose();
    s.v = core_->odometry().linearVelocity();
    s.w = core_->odometry().angularVelocity();
    s.latched = core_->latch().latched();
    s.latch_reason = core_->latch().reason();
    s.progress = core_->goalProgress();
    s.reported_mode = core_->reportedMode();
    return s;
  }

  void linkState(LinkState state, const std::string& reason)
  {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      link_state_ = state;
      if (state == LinkState::DISCONNECTED)
        core_->onDisconnected(steadyNow());
    }
    if (state == LinkState::DISCONNECTED)
      NODELET_WARN_THROTTLE(5.0, "create_driver: link to %s down: %s (retrying with backoff)",
                            link_params_.port.c_str(), reason.c_str());
    else if (state == LinkState::RUNNING)
      NODELET_INFO("create_driver: robot on %s is streaming", link_params_.port.c_str());
    processOutcomes();
    publishMode();
  }

  // Logs once when the command watchdog stops the robot (its sender froze or died).
  void reportWatchdog()
  {
    std::string lost;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      lost = core_->commandSourceLost();
      if (lost == reported_lost_)
        return;
      reported_lost_ = lost;
    }
    if (!lost.empty())
      NODELET_ERROR("create_driver: robot stopped: %s", lost.c_str());
  }

  void processOutcomes()
  {
    std::vector<GoalOutcome> outcomes;
    std::vector<GoalHandle> handles;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      core_->takeOutcomes(outcomes);
      for (const GoalOutcome& o : outcomes)
      {
        auto it = goals_.find(o.id);
        handles.push_back(it != goals_.end() ? it->second : GoalHandle());
        if (it != goals_.end())
          goals_.erase(it);
      }
    }
    for (size_t i = 0; i < outcomes.size(); ++i)
    {
      const GoalOutcome& o = outcomes[i];
      GoalHandle& gh = handles[i];
      if (!gh.getGoal())
        continue;
      DriveDistanceResult r;
      r.distance_travelled = o.travelled;
      r.reason = static_cast<uint8_t>(o.reason);
      r.message = o.message;
      if (o.reason == StopReason::REACHED)
        gh.setSucceeded(r, o.message);
      else if (o.reason == StopReason::PREEMPTED)
        gh.setCanceled(r, o.message);
      else
      {
        NODELET_WARN("drive_distance goal ended: %s (%s)", stopReasonName(o.reason), o.message.c_str());
        gh.setAborted(r, o.message);
      }
    }
  }

  void publish(const Snapshot& s, double now)
  {
    const ros::Time stamp = ros::Time::now();
    publishOdometry(s, stamp);
    publishHazards(s, stamp, now);
    if (now - last_battery_time_ >= 1.0)
    {
      last_battery_time_ = now;
      battery_pub_.publish(batteryMessage(s.sensors, stamp));
    }
    if (s.reported_mode != last_published_mode_)
      publishMode();
    publishGoalFeedback(s, now);
  }

  // Odometry and its transform (when publish_tf).
  void publishOdometry(const Snapshot& s, const ros::Time& stamp)
  {
    nav_msgs::Odometry odom;
    odom.header.stamp = stamp;
    odom.header.frame_id = odom_frame_;
    odom.child_frame_id = base_frame_;
    odom.pose.pose.position.x = s.pose.x;
    odom.pose.pose.position.y = s.pose.y;
    odom.pose.pose.orientation.z = std::sin(0.5 * s.pose.yaw);
    odom.pose.pose.orientation.w = std::cos(0.5 * s.pose.yaw);
    odom.twist.twist.linear.x = s.v;
    odom.twist.twist.angular.z = s.w;
    // Planar robot: x, y, yaw uncertain in proportion to travel; z, roll, pitch unused.
    const double big = 1e6;
    odom.pose.covariance = { 1e-3, 0, 0, 0,   0, 0, 0, 1e-3, 0, 0, 0,   0, 0, 0, big, 0, 0, 0,
                             0,    0, 0, big, 0, 0, 0, 0,    0, 0, big, 0, 0, 0, 0,   0, 0, 3e-3 };
    odom.twist.covariance = { 1e-4, 0, 0, 0,   0, 0, 0, 1e-4, 0, 0, 0,   0, 0, 0, big, 0, 0, 0,
                              0,    0, 0, big, 0, 0, 0, 0,    0, 0, big, 0, 0, 0, 0,   0, 0, 1e-3 };
    odom_pub_.publish(odom);
    if (tf_)
    {
      geometry_msgs::TransformStamped t;
      t.header = odom.header;
      t.child_frame_id = base_frame_;
      t.transform.translation.x = s.pose.x;
      t.transform.translation.y = s.pose.y;
      t.transform.rotation = odom.pose.pose.orientation;
      tf_->sendTransform(t);
    }
  }

  // Hazards when they change, else at 10 Hz.
  void publishHazards(const Snapshot& s, const ros::Time& stamp, double now)
  {
    Hazards hz;
    hz.header.stamp = stamp;
    hz.header.frame_id = base_frame_;
    hz.bump_left = s.sensors.bumpLeft();
    hz.bump_right = s.sensors.bumpRight();
    hz.wheel_drop_left = s.sensors.wheelDropLeft();
    hz.wheel_drop_right = s.sensors.wheelDropRight();
    hz.wheel_drop_caster = s.sensors.wheelDropCaster();
    hz.cliff_left = s.sensors.cliffLeft();
    hz.cliff_front_left = s.sensors.cliffFrontLeft();
    hz.cliff_front_right = s.sensors.cliffFrontRight();
    hz.cliff_right = s.sensors.cliffRight();
    hz.latched = s.latched;
    hz.latch_reason = static_cast<uint8_t>(s.latch_reason);
    const bool changed =
        hz.bump_left != last_hazards_.bump_left || hz.bump_right != last_hazards_.bump_right ||
        hz.wheel_drop_left != last_hazards_.wheel_drop_left || hz.wheel_drop_right != last_hazards_.wheel_drop_right ||
        hz.wheel_drop_caster != last_hazards_.wheel_drop_caster || hz.cliff_left != last_hazards_.cliff_left ||
        hz.cliff_front_left != last_hazards_.cliff_front_left ||
        hz.cliff_front_right != last_hazards_.cliff_front_right || hz.cliff_right != last_hazards_.cliff_right ||
        hz.latched != last_hazards_.latched || hz.latch_reason != last_hazards_.latch_reason;
    if (changed || now - last_hazards_time_ >= 0.1)
    {
      hazards_pub_.publish(hz);
      last_hazards_ = hz;
      last_hazards_time_ = now;
    }
  }

  // Feedback of the active distance goal at 10 Hz.
  void publishGoalFeedback(const Snapshot& s, double now)
  {
    if (s.progress.active && now - last_feedback_time_ >= 0.1)
    {
      last_feedback_time_ = now;
      GoalHandle gh;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        auto it = goals_.find(s.progress.id);
        if (it != goals_.end())
          gh = it->second;
      }
      if (gh.getGoal())
      {
        DriveDistanceFeedback fb;
        fb.distance_travelled = s.progress.travelled;
        fb.distance_remaining = s.progress.remaining;
        gh.publishFeedback(fb);
      }
    }
  }

  sensor_msgs::BatteryState batteryMessage(const SensorState& s, const ros::Time& stamp) const
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
    switch (s.get(packet::CHARGING_STATE))
    {
      case 0:
        b.power_supply_status = sensor_msgs::BatteryState::POWER_SUPPLY_STATUS_DISCHARGING;
        break;
      case 1:
      case 2:
      case 3:
        b.power_supply_status = sensor_msgs::BatteryState::POWER_SUPPLY_STATUS_CHARGING;
        break;
      case 4:
        b.power_supply_status = sensor_msgs::BatteryState::POWER_SUPPLY_STATUS_NOT_CHARGING;
        break;
      default:
        b.power_supply_status = sensor_msgs::BatteryState::POWER_SUPPLY_STATUS_UNKNOWN;
        break;
    }
    b.power_supply_health = s.get(packet::CHARGING_STATE) == 5
                                ? sensor_msgs::BatteryState::POWER_SUPPLY_HEALTH_UNSPEC_FAILURE
                                : sensor_msgs::BatteryState::POWER_SUPPLY_HEALTH_UNKNOWN;
    b.power_supply_technology = sensor_msgs::BatteryState::POWER_SUPPLY_TECHNOLOGY_NIMH;
    b.present = true;
    return b;
  }

  void publishMode()
  {
    Mode m;
    int reported = -1;
    LinkState state;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      reported = core_->haveSensors() ? core_->reportedMode() : -1;
      state = link_state_;
    }
    m.header.stamp = ros::Time::now();
    m.mode = reported < 0 ? static_cast<uint8_t>(Mode::UNKNOWN) : static_cast<uint8_t>(reported);
    m.mode_name = reportedModeName(reported);
    m.requested_mode = static_cast<uint8_t>(config_.mode);
    m.link_state = linkStateToMsg(state);
    m.link_state_name = linkStateName(state);
    m.port = link_params_.port;
    m.connects = static_cast<uint32_t>(link_ ? link_->stats().connects : 0);
    std::lock_guard<std::mutex> lock(mode_pub_mutex_);
    last_published_mode_ = reported;
    mode_pub_.publish(m);
  }

  // ---- diagnostics -------------------------------------------------------------------------

  void diagConnection(diagnostic_updater::DiagnosticStatusWrapper& st)
  {
    connectionStatus(link_->stats(), link_params_, model_name_, st);
  }

  void diagStream(diagnostic_updater::DiagnosticStatusWrapper& st)
  {
    ParserCounters c;
    uint64_t estimated = 0;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      c = core_->parserCounters();
      estimated = core_->stats().frames_estimated;
    }
    const ros::WallTime now = ros::WallTime::now();
    const double dt = last_diag_time_.isZero() ? 0.0 : (now - last_diag_time_).toSec();
    const double rate = dt > 0.0 ? (c.valid_frames - last_valid_frames_) / dt : 0.0;
    const bool new_corrupt = c.corrupt_frames > last_corrupt_frames_;
    last_diag_time_ = now;
    last_valid_frames_ = c.valid_frames;
    last_corrupt_frames_ = c.corrupt_frames;
    streamStatus(c, estimated, rate, new_corrupt, st);
  }

  void diagControl(diagnostic_updater::DiagnosticStatusWrapper& st)
  {
    const SerialLinkStats ls = link_->stats();
    DriverStats ds;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ds = core_->stats();
    }
    const bool new_overruns = ls.overruns > last_overruns_;
    last_overruns_ = ls.overruns;
    controlStatus(ls, ds, new_overruns, st);
  }

  void diagSafety(diagnostic_updater::DiagnosticStatusWrapper& st)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const HazardLatch& l = core_->latch();
    safetyStatus(l.latched(), l.reason(), core_->stats(), core_->reportedMode(), config_.mode, st);
  }

  void diagCommands(diagnostic_updater::DiagnosticStatusWrapper& st)
  {
    std::string lost;
    double age = 0.0;
    DriverStats ds;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      lost = core_->commandSourceLost();
      age = core_->commandAge(steadyNow());
      ds = core_->stats();
    }
    commandsStatus(lost, age, config_.command_timeout, ds, st);
  }

  void diagBattery(diagnostic_updater::DiagnosticStatusWrapper& st)
  {
    SensorState s;
    bool have = false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      s = core_->sensors();
      have = core_->parserCounters().valid_frames > 0;
    }
    batteryStatus(s, have, st);
  }

  // Configuration.
  DriverConfig config_;
  SerialLinkParams link_params_;
  std::string model_name_;
  std::string odom_frame_, base_frame_;
  bool publish_tf_ = true;

  // Shared state (mutex_).
  std::mutex mutex_;
  std::unique_ptr<DriverCore> core_;
  Bytes pending_out_;
  std::map<uint64_t, GoalHandle> goals_;
  LinkState link_state_ = LinkState::DISCONNECTED;
  std::string reported_lost_;  // the watchdog stop last logged

  // Publication state (worker thread, except the mode which has its own lock).
  Hazards last_hazards_;
  double last_hazards_time_ = 0.0;
  double last_battery_time_ = 0.0;
  double last_feedback_time_ = 0.0;
  std::mutex mode_pub_mutex_;
  std::atomic<int> last_published_mode_{ -2 };

  // Diagnostics state (timer thread).
  ros::WallTime last_diag_time_;
  uint64_t last_valid_frames_ = 0;
  uint64_t last_corrupt_frames_ = 0;
  uint64_t last_overruns_ = 0;

  ros::Publisher odom_pub_, hazards_pub_, battery_pub_, mode_pub_;
  ros::Subscriber cmd_sub_, heartbeat_sub_;
  ros::ServiceServer reset_srv_;
  ros::WallTimer diag_timer_;
  std::unique_ptr<tf2_ros::TransformBroadcaster> tf_;
  std::unique_ptr<Server> server_;
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  std::unique_ptr<SerialLink> link_;  // last: destroyed (and its thread joined) first
};

}  // namespace create_driver

PLUGINLIB_EXPORT_CLASS(create_driver::DriverNodelet, nodelet::Nodelet)
