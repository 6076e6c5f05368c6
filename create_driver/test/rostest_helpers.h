// Helpers shared by the rostest clients: waiting for conditions (never fixed sleeps), keeping
// the latest message of a topic, and reading values out of /diagnostics.
#pragma once

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include <create_driver/Mode.h>
#include <create_driver/SimStatus.h>
#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/Twist.h>
#include <ros/ros.h>
#include <sl_msgs/Hazards.h>
#include <std_msgs/Empty.h>
#include <sl_testing/wait.h>

namespace test_helpers
{
using sl_testing::kTimeout;
using sl_testing::waitUntil;

/// @brief Keeps the latest message of a topic and how many arrived.
template <class M>
class Latest
{
public:
  Latest(ros::NodeHandle& nh, const std::string& topic)
  {
    sub_ = nh.subscribe<M>(topic, 50,
                           [this](const typename M::ConstPtr& m)
                           {
                             std::lock_guard<std::mutex> lock(mutex_);
                             msg_ = *m;
                             ++count_;
                             if (hook_)
                               hook_(*m);
                           });
  }
  // The subscription ends before the members its callback writes are destroyed (the test's spinner
  // threads may be running it); shutdown() waits for a callback in progress.
  ~Latest() { sub_.shutdown(); }
  Latest(const Latest&) = delete;
  Latest& operator=(const Latest&) = delete;
  M get() const
  {
    std::lock_guard<std::mutex> lock(mutex_);
    return msg_;
  }
  uint64_t count() const
  {
    std::lock_guard<std::mutex> lock(mutex_);
    return count_;
  }
  /// Called for every message (under the lock).
  void setHook(const std::function<void(const M&)>& hook)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    hook_ = hook;
  }
  /// Waits for @p n more messages.
  bool waitMore(uint64_t n, double timeout_s = kTimeout)
  {
    const uint64_t target = count() + n;
    return waitUntil([&] { return count() >= target; }, timeout_s);
  }

private:
  mutable std::mutex mutex_;
  ros::Subscriber sub_;
  M msg_;
  uint64_t count_ = 0;
  std::function<void(const M&)> hook_;
};

/// @brief The heartbeat of a drive_distance client: std_msgs/Empty on drive_distance/heartbeat every
/// 0.1 s while not paused (the driver aborts a goal whose heartbeat stops for command_timeout).
/// A thread of its own, joined by the destructor: nothing publishes once the object is gone.
class Heartbeat
{
public:
  explicit Heartbeat(ros::NodeHandle& nh) : pub_(nh.advertise<std_msgs::Empty>("drive_distance/heartbeat", 1))
  {
    thread_ = std::thread(
        [this]
        {
          while (running_ && ros::ok())
          {
            if (!paused_)
              pub_.publish(std_msgs::Empty());
            ros::WallDuration(0.1).sleep();
          }
        });
  }
  ~Heartbeat()
  {
    running_ = false;
    thread_.join();
  }
  Heartbeat(const Heartbeat&) = delete;
  Heartbeat& operator=(const Heartbeat&) = delete;
  /// Stops (true) or resumes (false) the heartbeat: a frozen client.
  void pause(bool paused) { paused_ = paused; }

private:
  ros::Publisher pub_;
  std::atomic<bool> running_{ true };
  std::atomic<bool> paused_{ false };
  std::thread thread_;  // last: started once the members it uses exist
};

/// @brief Value of @p key in the diagnostic status whose name ends with @p status_suffix.
/// @return false if not present in @p array
bool diagValue(const diagnostic_msgs::DiagnosticArray& array, const std::string& status_suffix, const std::string& key,
               double* value);

/// @brief Common fixture state: the driver's mode, the simulator's status and true pose, the
/// heartbeat of the test's goals.
struct System
{
  explicit System(ros::NodeHandle& nh)
    : mode(nh, "mode"),
      status(nh, "create_sim/status"),
      pose(nh, "true_pose"),
      hazards(nh, "hazards"),
      diagnostics(nh, "/diagnostics"),
      heartbeat(nh)
  {
    cmd_pub = nh.advertise<geometry_msgs::Twist>("cmd_vel", 10);
  }
  /// Waits until the driver reports a running link and a Safe robot.
  bool waitRunning(double timeout_s = kTimeout);
  /// Waits until the simulated wheels are commanded to stop.
  bool waitWheelsStopped(double timeout_s = kTimeout);
  /// Publishes cmd_vel at 10 Hz until @p cond holds.
  bool driveUntil(double linear, double angular, const std::function<bool()>& cond, double timeout_s = kTimeout);
  /// Largest |commanded wheel speed| over the next @p n simulator status messages; a test failure
  /// and +inf if fewer than @p n arrive (the usual timeout).
  double maxWheelOver(uint64_t n, const std::function<void()>& each_tick = {});
  /// Latest diagnostic value (waits for a /diagnostics message containing it).
  bool diag(const std::string& status_suffix, const std::string& key, double* value);
  double wheels() const
  {
    const auto s = status.get();
    return std::max(std::fabs(s.left_wheel_velocity), std::fabs(s.right_wheel_velocity));
  }

  Latest<create_driver::Mode> mode;
  Latest<create_driver::SimStatus> status;
  Latest<geometry_msgs::PoseStamped> pose;
  Latest<sl_msgs::Hazards> hazards;
  Latest<diagnostic_msgs::DiagnosticArray> diagnostics;
  Heartbeat heartbeat;  // for the drive_distance goals the tests send
  ros::Publisher cmd_pub;
};

}  // namespace test_helpers
