// create_driver/driver: the ROS face of DriverSupervisor + SerialLink. Parameters: driver_params.cpp;
// messages: driver_conversions.cpp; diagnostics: driver_diagnostics.cpp.
#include <exception>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <diagnostic_updater/diagnostic_updater.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <std_msgs/Empty.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/transform_broadcaster.h>

#include "create_driver/driver_supervisor.h"
#include "create_driver/goal_registry.h"
#include "create_driver/serial_link.h"
#include "driver_conversions.h"
#include "driver_diagnostics.h"
#include "driver_params.h"

namespace create_driver
{
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
    locked([&] { sup_->shutdown(bye); });
    link_->stop(bye, 0.5);
    if (ros::ok())
      processOutcomes();
    // No goal callbacks after this point (the stopped link ignores requestControl()).
    server_.reset();
  }

private:
  using Server = actionlib::ActionServer<sl_msgs::DriveDistanceAction>;

  void onInit() override
  {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    try
    {
      params_ = readDriverParams(pnh);
      sup_ = std::make_unique<DriverSupervisor>(params_.config);
    }
    catch (const std::exception& e)
    {
      // nodelet::Loader drops what onInit throws without a word: say it here.
      NODELET_FATAL("invalid parameter: %s", e.what());
      throw;
    }

    odom_pub_ = nh.advertise<nav_msgs::Odometry>("odom", 10);
    hazards_pub_ = nh.advertise<sl_msgs::Hazards>("hazards", 10, true);
    battery_pub_ = nh.advertise<sensor_msgs::BatteryState>("battery", 1, true);
    mode_pub_ = nh.advertise<Mode>("mode", 1, true);
    if (params_.publish_tf)
      tf_ = std::make_unique<tf2_ros::TransformBroadcaster>();
    reset_srv_ = nh.advertiseService("reset_hazard", &DriverNodelet::resetHazard, this);
    cmd_sub_ = nh.subscribe("cmd_vel", 10, &DriverNodelet::cmdVel, this);
    // In the action's namespace, so that a remap of drive_distance moves it along.
    heartbeat_sub_ = ros::NodeHandle(nh, "drive_distance").subscribe("heartbeat", 10, &DriverNodelet::heartbeat, this);

    server_ = std::make_unique<Server>(
        nh, "drive_distance", [this](GoalHandle gh) { goalCallback(gh); },
        [this](GoalHandle gh) { cancelCallback(gh); }, false);
    server_->start();

    setupDiagnostics(nh, pnh);
    link_ = std::make_unique<SerialLink>(params_.link, linkHandlers());
    link_->start();
    NODELET_INFO("create_driver: %s on %s at %u baud, %s mode", params_.model_name.c_str(), params_.link.port.c_str(),
                 params_.link.baud, oiModeName(params_.config.mode));
  }

  SerialLink::Handlers linkHandlers()
  {
    SerialLink::Handlers h;
    h.on_open = [this](double now, Bytes& out) { locked([&] { sup_->onOpen(now, out); }); };
    h.on_data = [this](const uint8_t* data, size_t len, double now, Bytes& out)
    {
      const FrameActions a = locked([&] { return sup_->onData(data, len, now, out); });
      if (a.frames > 0)
        publish(a);
      reportWatchdog();
      processOutcomes();
      return a.frames;
    };
    h.on_tick = [this](double now, Bytes& out)
    {
      locked([&] { sup_->onTick(now, out); });
      reportWatchdog();
      processOutcomes();
    };
    h.on_state = [this](LinkState state, const std::string& reason) { linkState(state, reason); };
    return h;
  }

  // ---- ROS callbacks -----------------------------------------------------------------------

  void cmdVel(const geometry_msgs::Twist::ConstPtr& msg)
  {
    std::string error;
    if (!locked([&] { return sup_->setVelocity(commandedLinear(*msg), msg->angular.z, steadyNow(), &error); }))
      NODELET_ERROR_THROTTLE(1.0, "cmd_vel rejected: %s", error.c_str());
    processOutcomes();
    link_->requestControl();
  }

  void heartbeat(const std_msgs::Empty::ConstPtr&)
  {
    locked([&] { sup_->heartbeat(steadyNow()); });
  }

  void goalCallback(GoalHandle gh)
  {
    const auto goal = gh.getGoal();
    GoalStart start;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      start = sup_->startGoal(goal->distance, goal->speed, steadyNow());
      if (start.accepted)
        goals_.add(start.id, gh);
    }
    if (!start.accepted)
    {
      NODELET_WARN("drive_distance goal rejected: %s", start.message.c_str());
      gh.setRejected(goalResult(start.reason, 0.0, start.message), start.message);
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
      for (uint64_t id : goals_.idsOf(gh))
        sup_->cancelGoal(id);
    }
    processOutcomes();
    link_->requestControl();
  }

  bool resetHazard(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    res.success = sup_->resetHazard(&res.message);
    return true;
  }

  // ---- worker-thread side ------------------------------------------------------------------

  void linkState(LinkState state, const std::string& reason)
  {
    locked([&] { sup_->onLinkState(state, steadyNow()); });
    if (state == LinkState::DISCONNECTED)
      NODELET_WARN_THROTTLE(5.0, "create_driver: link to %s down: %s (retrying with backoff)",
                            params_.link.port.c_str(), reason.c_str());
    else if (state == LinkState::RUNNING)
      NODELET_INFO("create_driver: robot on %s is streaming", params_.link.port.c_str());
    processOutcomes();
    publishMode();
  }

  // Logs once when the command watchdog stops the robot (its sender froze or died).
  void reportWatchdog()
  {
    std::string lost;
    if (locked([&] { return sup_->takeWatchdogStop(&lost); }))
      NODELET_ERROR("create_driver: robot stopped: %s", lost.c_str());
  }

  void processOutcomes()
  {
    std::vector<GoalOutcome> outcomes;
    std::vector<GoalHandle> handles;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      sup_->takeEndedGoals(outcomes);
      for (const GoalOutcome& o : outcomes)
        handles.push_back(goals_.take(o.id).value_or(GoalHandle()));
    }
    for (size_t i = 0; i < outcomes.size(); ++i)
    {
      const GoalOutcome& o = outcomes[i];
      if (!handles[i].getGoal())
        continue;  // a goal of no client (already ended)
      if (goalEnd(o.reason) == GoalEnd::ABORTED)
        NODELET_WARN("drive_distance goal ended: %s (%s)", stopReasonName(o.reason), o.message.c_str());
      endGoal(handles[i], o);
    }
  }

  void publish(const FrameActions& a)
  {
    const ros::Time stamp = ros::Time::now();
    const DriverSnapshot& s = a.snapshot;
    const nav_msgs::Odometry odom = odometryMessage(s, stamp, params_.odom_frame, params_.base_frame);
    odom_pub_.publish(odom);
    if (tf_)
      tf_->sendTransform(odometryTransform(odom));
    if (a.hazards)
      hazards_pub_.publish(hazardsMessage(s.hazards, stamp, params_.base_frame));
    if (a.battery)
      battery_pub_.publish(batteryMessage(s.sensors, stamp));
    if (a.mode)
      publishMode();
    if (a.feedback)
    {
      GoalHandle gh = locked([&] { return goals_.find(s.progress.id).value_or(GoalHandle()); });
      if (gh.getGoal())
        gh.publishFeedback(goalFeedback(s.progress));
    }
  }

  void publishMode()
  {
    const uint64_t connects = link_ ? link_->stats().connects : 0;
    // One publisher at a time, so that the mode last noted is the mode last published.
    std::lock_guard<std::mutex> pub_lock(mode_pub_mutex_);
    const ModeReport r = locked([&] { return sup_->takeModeReport(); });
    mode_pub_.publish(modeMessage(r, params_.link.port, connects, ros::Time::now()));
  }

  // Runs @p f with mutex_ held and returns its result.
  template <typename F>
  auto locked(F f) -> decltype(f())
  {
    std::lock_guard<std::mutex> lock(mutex_);
    return f();
  }

  // ---- diagnostics -------------------------------------------------------------------------

  void setupDiagnostics(ros::NodeHandle& nh, ros::NodeHandle& pnh)
  {
    updater_ = std::make_unique<diagnostic_updater::Updater>(nh, pnh, getName());
    DiagnosticsSources src;
    src.mutex = &mutex_;
    src.supervisor = sup_.get();
    src.link = [this] { return link_->stats(); };
    src.link_params = params_.link;
    src.model_name = params_.model_name;
    diagnostics_ = std::make_unique<DriverDiagnostics>(*updater_, src);
    diag_timer_ = nh.createWallTimer(ros::WallDuration(0.5),
                                     [this](const ros::WallTimerEvent&)
                                     {
                                       updater_->update();
                                       publishMode();
                                     });
  }

  DriverNodeParams params_;

  // Shared state (mutex_).
  std::mutex mutex_;
  std::unique_ptr<DriverSupervisor> sup_;
  GoalRegistry<GoalHandle> goals_;
  std::mutex mode_pub_mutex_;  // taken before mutex_

  ros::Publisher odom_pub_, hazards_pub_, battery_pub_, mode_pub_;
  ros::Subscriber cmd_sub_, heartbeat_sub_;
  ros::ServiceServer reset_srv_;
  ros::WallTimer diag_timer_;
  std::unique_ptr<tf2_ros::TransformBroadcaster> tf_;
  std::unique_ptr<Server> server_;
  std::unique_ptr<DriverDiagnostics> diagnostics_;        // its callbacks are in updater_:
  std::unique_ptr<diagnostic_updater::Updater> updater_;  // destroyed before it
  std::unique_ptr<SerialLink> link_;                      // last: destroyed (and its thread joined) first
};

}  // namespace create_driver

PLUGINLIB_EXPORT_CLASS(create_driver::DriverNodelet, nodelet::Nodelet)
