// create_driver/sim: SimRobot behind a pseudo-terminal, stepped on a worker thread. The ROS side
// only converts: contact/cliff/wheel-drop topics in, true pose and status out, test services.
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>

#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <std_msgs/UInt8.h>
#include <std_msgs/UInt8MultiArray.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/transform_broadcaster.h>

#include "create_driver/SimStatus.h"
#include "create_driver/pty.h"
#include "create_driver/sim_robot.h"
#include "sl_params/params.h"

namespace create_driver
{
namespace
{
void require(bool ok, const std::string& message)
{
  if (!ok)
    throw std::invalid_argument(message);
}

// Seconds on the steady clock: the simulation's time base (wall-clock jumps do not move the robot).
double steadyNow()
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

/// @brief Nodelet create_driver/sim (see README.md: create_sim).
class SimNodelet : public nodelet::Nodelet
{
public:
  ~SimNodelet() override
  {
    running_ = false;
    if (thread_.joinable())
      thread_.join();
    std::lock_guard<std::mutex> lock(mutex_);
    pty_.unlink();
    pty_.close();
  }

private:
  void onInit() override
  {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    const SimParams p = readRobotParams(pnh);
    readNodeParams(pnh);
    robot_ = std::make_unique<SimRobot>(p);
    garbage_rng_.seed(p.seed + 1);
    openPty();  // throws naming ~link if the link cannot be made
    advertise(nh, pnh);
    running_ = true;
    thread_ = std::thread([this] { loop(); });
  }

  // The simulated robot's parameters (model, geometry, slip and noise).
  static SimParams readRobotParams(ros::NodeHandle& pnh)
  {
    SimParams p;
    const std::string model = sl_params::read<std::string>(pnh, "model", "create_1");
    if (model == "create_1" || model == "create")
      p.model = Model::CREATE_1;
    else if (model == "create_2" || model == "roomba_600")
      p.model = Model::CREATE_2;
    else
      throw std::invalid_argument("~model must be create_1 or create_2 (got '" + model + "')");
    p.wheel_base = sl_params::read<double>(pnh, "wheel_base", defaultWheelBase(p.model));
    require(p.wheel_base > 0.05 && p.wheel_base < 1.0, "~wheel_base must be in (0.05, 1) m");
    p.initial_pose.x = sl_params::read<double>(pnh, "x", 0.0);
    p.initial_pose.y = sl_params::read<double>(pnh, "y", 0.0);
    p.initial_pose.yaw = sl_params::read<double>(pnh, "yaw", 0.0);
    require(std::isfinite(p.initial_pose.x) && std::isfinite(p.initial_pose.y) && std::isfinite(p.initial_pose.yaw),
            "~x, ~y and ~yaw must be finite");
    p.max_wheel_accel = sl_params::read<double>(pnh, "max_wheel_accel", 0.0);
    require(p.max_wheel_accel >= 0.0, "~max_wheel_accel must be >= 0 (0 = instant)");
    p.slip_left = sl_params::read<double>(pnh, "slip_left", 0.0);
    require(p.slip_left >= 0.0 && p.slip_left < 1.0, "~slip_left must be in [0, 1)");
    p.slip_right = sl_params::read<double>(pnh, "slip_right", 0.0);
    require(p.slip_right >= 0.0 && p.slip_right < 1.0, "~slip_right must be in [0, 1)");
    p.slip_noise = sl_params::read<double>(pnh, "slip_noise", 0.0);
    require(p.slip_noise >= 0.0 && p.slip_noise < 1.0, "~slip_noise must be in [0, 1)");
    p.odom_noise = sl_params::read<double>(pnh, "odom_noise", 0.0);
    require(p.odom_noise >= 0.0 && p.odom_noise < 1.0, "~odom_noise must be in [0, 1)");
    const int seed = sl_params::read<int>(pnh, "seed", 1);
    require(seed >= 0, "~seed must be >= 0");
    p.seed = static_cast<uint32_t>(seed);
    p.block_on_contact = sl_params::read<bool>(pnh, "block_on_contact", true);
    p.command_watchdog = sl_params::read<double>(pnh, "command_watchdog", 0.0);
    require(p.command_watchdog == 0.0 || (p.command_watchdog >= 0.05 && p.command_watchdog <= 10.0),
            "~command_watchdog must be 0 (none, like the real Create) or in [0.05, 10] s");
    return p;
  }

  // The node's own parameters (rates, frames, link, garbage, reopen delay).
  void readNodeParams(ros::NodeHandle& pnh)
  {
    rate_ = sl_params::read<double>(pnh, "rate", 200.0);
    require(rate_ >= 50.0 && rate_ <= 2000.0, "~rate must be in [50, 2000] Hz");
    publish_rate_ = sl_params::read<double>(pnh, "publish_rate", 50.0);
    require(publish_rate_ > 0.0 && publish_rate_ <= rate_, "~publish_rate must be in (0, ~rate] Hz");
    world_frame_ = sl_params::read<std::string>(pnh, "world_frame", "world");
    robot_frame_ = sl_params::read<std::string>(pnh, "robot_frame", "base_footprint_true");
    require(!world_frame_.empty() && !robot_frame_.empty() && world_frame_ != robot_frame_,
            "~world_frame and ~robot_frame must be non-empty and different");
    link_path_ = sl_params::read<std::string>(pnh, "link", "");
    const int garbage = sl_params::read<int>(pnh, "garbage_bytes", 32);
    require(garbage > 0 && garbage <= 4096, "~garbage_bytes must be in [1, 4096]");
    garbage_bytes_ = static_cast<size_t>(garbage);
    reopen_delay_ = sl_params::read<double>(pnh, "reopen_delay", 0.5);
    require(reopen_delay_ >= 0.0 && reopen_delay_ <= 60.0, "~reopen_delay must be in [0, 60] s");
  }

  void advertise(ros::NodeHandle& nh, ros::NodeHandle& pnh)
  {
    pose_pub_ = nh.advertise<geometry_msgs::PoseStamped>("true_pose", 10);
    status_pub_ = pnh.advertise<SimStatus>("status", 10);
    contact_sub_ = nh.subscribe<std_msgs::UInt8>("contact", 10,
                                                 [this](const std_msgs::UInt8::ConstPtr& m)
                                                 {
                                                   std::lock_guard<std::mutex> lock(mutex_);
                                                   robot_->setContact(m->data);
                                                 });
    cliff_sub_ = nh.subscribe<std_msgs::UInt8>("cliff", 10,
                                               [this](const std_msgs::UInt8::ConstPtr& m)
                                               {
                                                 std::lock_guard<std::mutex> lock(mutex_);
                                                 robot_->setCliffs(m->data);
                                               });
    drop_sub_ = nh.subscribe<std_msgs::UInt8>("wheel_drop", 10,
                                              [this](const std_msgs::UInt8::ConstPtr& m)
                                              {
                                                std::lock_guard<std::mutex> lock(mutex_);
                                                robot_->setWheelDrops(m->data);
                                              });
    inject_sub_ = pnh.subscribe<std_msgs::UInt8MultiArray>("inject_bytes", 10,
                                                           [this](const std_msgs::UInt8MultiArray::ConstPtr& m)
                                                           {
                                                             std::lock_guard<std::mutex> lock(mutex_);
                                                             robot_->injectNow(Bytes(m->data.begin(), m->data.end()));
                                                           });
    reopen_srv_ = pnh.advertiseService("reopen", &SimNodelet::reopen, this);
    garbage_srv_ = pnh.advertiseService("inject_garbage", &SimNodelet::injectGarbage, this);
    power_srv_ = pnh.advertiseService("power_cycle", &SimNodelet::powerCycle, this);
  }

  void openPty()
  {
    std::string error;
    if (!pty_.open(&error))
      throw std::runtime_error("create_sim: cannot open a pseudo-terminal: " + error);
    if (!link_path_.empty() && !pty_.link(link_path_, &error))
      throw std::invalid_argument("~link: " + error);
    ++pty_opens_;
    NODELET_INFO("create_sim: simulated Create on %s%s%s", pty_.slavePath().c_str(),
                 link_path_.empty() ? "" : " linked at ", link_path_.c_str());
  }

  bool reopen(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res)
  {
    // Only the worker thread touches the pty's file descriptors: it closes and reopens.
    std::lock_guard<std::mutex> lock(mutex_);
    reopen_requested_ = true;
    res.success = true;
    res.message = "closing " + pty_.slavePath() + "; a new pty follows in " + std::to_string(reopen_delay_) + " s";
    return true;
  }

  bool injectGarbage(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res)
  {
    Bytes g(garbage_bytes_);
    std::uniform_int_distribution<int> byte(0, 255);
    for (auto& b : g)
      b = static_cast<uint8_t>(byte(garbage_rng_));
    g[0] = oi::STREAM_HEADER;  // a false header too
    std::lock_guard<std::mutex> lock(mutex_);
    robot_->injectIntoNextFrame(g);
    res.success = true;
    res.message = std::to_string(g.size()) + " garbage bytes go into the next stream frame";
    return true;
  }

  bool powerCycle(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    robot_->powerCycle();
    res.success = true;
    res.message = "robot power-cycled: mode off";
    return true;
  }

  void loop()
  {
    const double period = 1.0 / rate_;
    double last = steadyNow();
    double next_pose = last;
    double next_status = last;
    Bytes out;
    out.reserve(4096);
    while (running_ && ros::ok())
    {
      waitForInput(last + period);
      const double now = steadyNow();
      geometry_msgs::PoseStamped pose;
      SimStatus status;
      bool send_pose = false;
      bool send_status = false;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        reopenIfDue(now);
        exchangeWithRobot(now - last, out);
        last = now;
        if (now >= next_pose)
        {
          next_pose = std::max(next_pose + 1.0 / publish_rate_, now - 1.0 / publish_rate_);
          fillPose(pose);
          send_pose = true;
        }
        if (now >= next_status)
        {
          next_status = now + 0.1;
          fillStatus(status);
          send_status = true;
        }
      }
      if (send_pose)
        publishPose(pose);
      if (send_status)
        status_pub_.publish(status);
    }
  }

  // Waits until the client writes or the steady clock reaches @p until.
  void waitForInput(double until)
  {
    bool open = false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      open = pty_.isOpen();
    }
    const double wait_s = std::max(0.0, until - steadyNow());
    if (open)
      pty_.waitReadable(static_cast<int>(std::ceil(wait_s * 1000.0)));
    else
      std::this_thread::sleep_for(std::chrono::duration<double>(wait_s));
  }

  // Closes the pty when a reopen was requested and opens it again after reopen_delay (mutex_ held).
  void reopenIfDue(double now)
  {
    if (reopen_requested_)
    {
      reopen_requested_ = false;
      NODELET_INFO("create_sim: closing %s (reopen requested)", pty_.slavePath().c_str());
      pty_.unlink();
      pty_.close();
      reopen_pending_ = true;
      reopen_at_ = now + reopen_delay_;
    }
    if (reopen_pending_ && now >= reopen_at_)
    {
      reopen_pending_ = false;
      try
      {
        openPty();
      }
      catch (const std::exception& e)
      {
        NODELET_ERROR("create_sim: reopening failed: %s", e.what());
      }
    }
  }

  // Feeds the client's bytes to the robot, advances it by @p dt and writes its answer (mutex_ held).
  void exchangeWithRobot(double dt, Bytes& out)
  {
    uint8_t buf[512];
    long n;
    while (pty_.isOpen() && (n = pty_.read(buf, sizeof(buf))) > 0)
      robot_->receive(buf, static_cast<size_t>(n));
    robot_->step(dt);
    logRefusals();
    if (robot_->watchdogStops() != watchdog_logged_)
    {
      watchdog_logged_ = robot_->watchdogStops();
      NODELET_WARN("create_sim: no byte from the host for %.2f s (~command_watchdog): wheels stopped",
                   robot_->params().command_watchdog);
    }
    out.clear();
    robot_->takeOutput(out);
    if (!out.empty() && pty_.isOpen())
      pty_.write(out.data(), out.size());
  }

  // A client's command was refused (input or a script after a Wait): say why, at once for a new
  // reason, throttled for a client that repeats itself (mutex_ held).
  void logRefusals()
  {
    if (robot_->refusedCommands() == refused_logged_)
      return;
    refused_logged_ = robot_->refusedCommands();
    const unsigned long long count = refused_logged_;
    if (robot_->lastRefusal() != refusal_logged_)
    {
      refusal_logged_ = robot_->lastRefusal();
      NODELET_WARN("create_sim: %s (%llu commands refused so far)", refusal_logged_.c_str(), count);
    }
    else
    {
      NODELET_WARN_THROTTLE(1.0, "create_sim: %s (%llu commands refused so far)", refusal_logged_.c_str(), count);
    }
  }

  void publishPose(const geometry_msgs::PoseStamped& pose)
  {
    pose_pub_.publish(pose);
    geometry_msgs::TransformStamped t;
    t.header = pose.header;
    t.child_frame_id = robot_frame_;
    t.transform.translation.x = pose.pose.position.x;
    t.transform.translation.y = pose.pose.position.y;
    t.transform.rotation = pose.pose.orientation;
    tf_.sendTransform(t);
  }

  void fillPose(geometry_msgs::PoseStamped& m) const
  {
    const Pose2D& p = robot_->truePose();
    m.header.stamp = ros::Time::now();
    m.header.frame_id = world_frame_;
    m.pose.position.x = p.x;
    m.pose.position.y = p.y;
    m.pose.orientation.z = std::sin(0.5 * p.yaw);
    m.pose.orientation.w = std::cos(0.5 * p.yaw);
  }

  void fillStatus(SimStatus& s) const
  {
    s.header.stamp = ros::Time::now();
    s.header.frame_id = robot_frame_;
    s.mode = static_cast<uint8_t>(robot_->mode());
    s.mode_name = oiModeName(robot_->mode());
    s.left_wheel_velocity = robot_->commandedLeft();
    s.right_wheel_velocity = robot_->commandedRight();
    s.linear_velocity = robot_->trueLinearVelocity();
    s.angular_velocity = robot_->trueAngularVelocity();
    s.streaming = robot_->streaming();
    s.waiting = robot_->waiting();
    s.contact = robot_->contact();
    s.pty_path = pty_.isOpen() ? pty_.slavePath() : "";
    s.pty_opens = pty_opens_;
    s.bytes_received = robot_->bytesReceived();
    s.bytes_sent = robot_->bytesSent();
    s.commands = robot_->commands();
    s.refused_commands = robot_->refusedCommands();
    s.last_refusal = robot_->lastRefusal();
    s.watchdog_stops = robot_->watchdogStops();
  }

  double rate_ = 200.0;
  double publish_rate_ = 50.0;
  std::string world_frame_, robot_frame_, link_path_;
  size_t garbage_bytes_ = 32;
  double reopen_delay_ = 0.5;

  std::mutex mutex_;  // robot_, pty_, reopen state
  std::unique_ptr<SimRobot> robot_;
  Pty pty_;
  uint32_t pty_opens_ = 0;
  uint64_t refused_logged_ = 0;   // refusals already logged
  uint64_t watchdog_logged_ = 0;  // watchdog stops already logged
  std::string refusal_logged_;    // the reason last logged
  bool reopen_requested_ = false;
  bool reopen_pending_ = false;
  double reopen_at_ = 0.0;
  std::mt19937 garbage_rng_;

  std::atomic<bool> running_{ false };
  std::thread thread_;
  ros::Publisher pose_pub_, status_pub_;
  ros::Subscriber contact_sub_, cliff_sub_, drop_sub_, inject_sub_;
  ros::ServiceServer reopen_srv_, garbage_srv_, power_srv_;
  tf2_ros::TransformBroadcaster tf_;
};

}  // namespace create_driver

PLUGINLIB_EXPORT_CLASS(create_driver::SimNodelet, nodelet::Nodelet)
