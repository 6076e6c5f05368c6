// create_driver/sim: SimSupervisor (a SimRobot) behind a pseudo-terminal, stepped on a worker
// thread. The ROS side only converts: contact/cliff/wheel-drop topics in, true pose and status
// out, test services. Parameters: sim_params.cpp; messages: sim_conversions.cpp.
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <std_msgs/UInt8.h>
#include <std_msgs/UInt8MultiArray.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/transform_broadcaster.h>

#include "create_driver/pty.h"
#include "create_driver/sim_supervisor.h"
#include "sim_conversions.h"
#include "sim_params.h"

namespace create_driver
{
namespace
{
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
    try
    {
      params_ = readSimParams(pnh);
      sup_ = std::make_unique<SimSupervisor>(params_.config, steadyNow());
      openPty();  // throws naming ~link if the link cannot be made
    }
    catch (const std::exception& e)
    {
      // nodelet::Loader drops what onInit throws without a word: say it here.
      NODELET_FATAL("%s", e.what());
      throw;
    }
    advertise(nh, pnh);
    running_ = true;
    thread_ = std::thread([this] { loop(); });
  }

  // A subscriber that passes a UInt8 topic's bits to the robot.
  ros::Subscriber bitsInput(ros::NodeHandle& nh, const std::string& topic, void (SimRobot::*set)(uint8_t))
  {
    return nh.subscribe<std_msgs::UInt8>(topic, 10,
                                         [this, set](const std_msgs::UInt8::ConstPtr& m)
                                         {
                                           std::lock_guard<std::mutex> lock(mutex_);
                                           (sup_->robot().*set)(m->data);
                                         });
  }

  void advertise(ros::NodeHandle& nh, ros::NodeHandle& pnh)
  {
    pose_pub_ = nh.advertise<geometry_msgs::PoseStamped>("true_pose", 10);
    status_pub_ = pnh.advertise<SimStatus>("status", 10);
    contact_sub_ = bitsInput(nh, "contact", &SimRobot::setContact);
    cliff_sub_ = bitsInput(nh, "cliff", &SimRobot::setCliffs);
    drop_sub_ = bitsInput(nh, "wheel_drop", &SimRobot::setWheelDrops);
    inject_sub_ =
        pnh.subscribe<std_msgs::UInt8MultiArray>("inject_bytes", 10,
                                                 [this](const std_msgs::UInt8MultiArray::ConstPtr& m)
                                                 {
                                                   std::lock_guard<std::mutex> lock(mutex_);
                                                   sup_->robot().injectNow(Bytes(m->data.begin(), m->data.end()));
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
    if (!params_.link_path.empty() && !pty_.link(params_.link_path, &error))
      throw std::invalid_argument("~link: " + error);
    ++pty_opens_;
    NODELET_INFO("create_sim: simulated Create on %s%s%s", pty_.slavePath().c_str(),
                 params_.link_path.empty() ? "" : " linked at ", params_.link_path.c_str());
  }

  bool reopen(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res)
  {
    // Only the worker thread touches the pty's file descriptors: it closes and reopens.
    std::lock_guard<std::mutex> lock(mutex_);
    sup_->requestReopen();
    res.success = true;
    res.message =
        "closing " + pty_.slavePath() + "; a new pty follows in " + std::to_string(params_.config.reopen_delay) + " s";
    return true;
  }

  bool injectGarbage(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const size_t n = sup_->injectGarbage();
    res.success = true;
    res.message = std::to_string(n) + " garbage bytes go into the next stream frame";
    return true;
  }

  bool powerCycle(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    sup_->robot().powerCycle();
    res.success = true;
    res.message = "robot power-cycled: mode off";
    return true;
  }

  void loop()
  {
    Bytes out;
    out.reserve(4096);
    while (running_ && ros::ok())
    {
      waitForInput();
      const double now = steadyNow();
      geometry_msgs::PoseStamped pose;
      SimStatus status;
      SimStepActions a;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        handlePty(sup_->ptyActions(now));
        a = exchangeWithRobot(now, out);
        const ros::Time stamp = ros::Time::now();
        if (a.publish_pose)
          pose = poseMessage(sup_->robot().truePose(), stamp, params_.world_frame);
        if (a.publish_status)
          status = statusMessage(sup_->robot(), pty_.isOpen() ? pty_.slavePath() : "", pty_opens_, stamp,
                                 params_.robot_frame);
      }
      if (a.publish_pose)
      {
        pose_pub_.publish(pose);
        tf_.sendTransform(poseTransform(pose, params_.robot_frame));
      }
      if (a.publish_status)
        status_pub_.publish(status);
    }
  }

  // Waits until the client writes or the next step is due.
  void waitForInput()
  {
    bool open = false;
    double until = 0.0;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      open = pty_.isOpen();
      until = sup_->nextStep();
    }
    const double wait_s = std::max(0.0, until - steadyNow());
    if (open)
      pty_.waitReadable(static_cast<int>(std::ceil(wait_s * 1000.0)));
    else
      std::this_thread::sleep_for(std::chrono::duration<double>(wait_s));
  }

  // Closes the pty for a reopen, opens the new one when it is due (mutex_ held).
  void handlePty(const PtyActions& a)
  {
    if (a.close)
    {
      NODELET_INFO("create_sim: closing %s (reopen requested)", pty_.slavePath().c_str());
      pty_.unlink();
      pty_.close();
    }
    if (!a.open)
      return;
    try
    {
      openPty();
    }
    catch (const std::exception& e)
    {
      NODELET_ERROR("create_sim: reopening failed: %s", e.what());
    }
  }

  // Feeds the client's bytes to the robot, steps it to @p now, writes its answer and logs what the
  // supervisor reports (mutex_ held).
  SimStepActions exchangeWithRobot(double now, Bytes& out)
  {
    uint8_t buf[512];
    long n;
    while (pty_.isOpen() && (n = pty_.read(buf, sizeof(buf))) > 0)
      sup_->robot().receive(buf, static_cast<size_t>(n));
    const SimStepActions a = sup_->step(now, out);
    const SimRobot& robot = sup_->robot();
    // A client's command was refused: why, at once for a new reason, throttled when repeated.
    const unsigned long long refused = robot.refusedCommands();
    if (a.refusal && a.new_refusal_reason)
      NODELET_WARN("create_sim: %s (%llu commands refused so far)", robot.lastRefusal().c_str(), refused);
    else if (a.refusal)
      NODELET_WARN_THROTTLE(1.0, "create_sim: %s (%llu commands refused so far)", robot.lastRefusal().c_str(), refused);
    if (a.watchdog_stop)
      NODELET_WARN("create_sim: no byte from the host for %.2f s (~command_watchdog): wheels stopped",
                   robot.params().command_watchdog);
    if (!out.empty() && pty_.isOpen())
      pty_.write(out.data(), out.size());
    return a;
  }

  SimNodeParams params_;

  std::mutex mutex_;  // sup_, pty_
  std::unique_ptr<SimSupervisor> sup_;
  Pty pty_;
  uint32_t pty_opens_ = 0;

  std::atomic<bool> running_{ false };
  std::thread thread_;
  ros::Publisher pose_pub_, status_pub_;
  ros::Subscriber contact_sub_, cliff_sub_, drop_sub_, inject_sub_;
  ros::ServiceServer reopen_srv_, garbage_srv_, power_srv_;
  tf2_ros::TransformBroadcaster tf_;
};

}  // namespace create_driver

PLUGINLIB_EXPORT_CLASS(create_driver::SimNodelet, nodelet::Nodelet)
