/// @file sim_supervisor.h
/// @brief The create_sim node's decisions around SimRobot, without ROS and without I/O: when to
/// close and reopen the pty, how far to step the robot, when the true pose and the status are due,
/// which refusals and hardware stops to log, and the garbage bytes of a noise test.
#pragma once

#include <cstddef>
#include <cstdint>
#include <random>
#include <string>

#include "create_driver/sim_robot.h"

namespace create_driver
{
/// Settings of the simulator node: the robot's and the node's own (SI units).
struct SimNodeConfig
{
  /// @brief The defaults of create_sim (a Create with its wheel base).
  SimNodeConfig() { robot.wheel_base = defaultWheelBase(robot.model); }

  SimParams robot;             ///< wheel_base set (its 0 = model default is not a create_sim value)
  double rate = 200.0;         ///< Hz, simulation steps (and reads of the client's bytes)
  double publish_rate = 50.0;  ///< Hz, true pose
  double status_period = 0.1;  ///< s between status reports
  size_t garbage_bytes = 32;   ///< bytes of one inject_garbage
  double reopen_delay = 0.5;   ///< s between closing the pty and opening a new one

  /// @brief Checks every field.
  /// @throws std::invalid_argument whose message starts with the create_sim parameter of the
  ///         offending field (wheel_base, x, max_wheel_accel, slip_left, ..., rate, reopen_delay).
  void validate() const;
};

/// What the node does with its pty before a step.
struct PtyActions
{
  bool close = false;  ///< a reopen was requested: unlink and close the pty (clients see EOF)
  bool open = false;   ///< reopen_delay has passed since: open a new pty (and link it)
};

/// What the node reports after a step.
struct SimStepActions
{
  bool publish_pose = false;    ///< the true pose is due (publish_rate)
  bool publish_status = false;  ///< the status is due (status_period)
  /// The robot refused commands since the last step: log SimRobot::lastRefusal() with
  /// SimRobot::refusedCommands() (a new reason at once, a repeated one throttled).
  bool refusal = false;
  bool new_refusal_reason = false;  ///< the reason differs from the reason last logged
  bool watchdog_stop = false;       ///< SimParams::command_watchdog stopped the wheels since the last step
};

/// @brief The create_sim node's logic (see file comment). Times on the steady clock, s. Not
/// thread-safe: the caller serialises access.
class SimSupervisor
{
public:
  /// @brief Creates the robot; @p config must pass validate(). Steps are counted from @p now.
  SimSupervisor(const SimNodeConfig& config, double now);

  /// @brief The simulated robot (contact, cliffs, injected bytes, power cycle, state).
  SimRobot& robot() { return robot_; }
  /// @brief The simulated robot.
  const SimRobot& robot() const { return robot_; }
  /// @brief Configuration in use.
  const SimNodeConfig& config() const { return config_; }

  /// @brief Asks for the pty to be closed at the next step and reopened reopen_delay later.
  void requestReopen() { reopen_requested_ = true; }
  /// @brief What to do with the pty at @p now (before reading it).
  PtyActions ptyActions(double now);
  /// @brief Time until which the node waits for the client's bytes before the next step.
  double nextStep() const { return last_ + 1.0 / config_.rate; }

  /// @brief Advances the robot to @p now, appends what it sent to @p out, and says what to report.
  SimStepActions step(double now, Bytes& out);

  /// @brief Makes garbage_bytes random bytes, the first a false stream header (19), and puts them
  /// into the middle of the robot's next stream frame.
  /// @return the number of bytes
  size_t injectGarbage();

private:
  SimNodeConfig config_;
  SimRobot robot_;
  std::mt19937 garbage_rng_;
  double last_;
  double next_pose_;
  double next_status_;
  bool reopen_requested_ = false;
  bool reopen_pending_ = false;
  double reopen_at_ = 0.0;
  uint64_t refused_logged_ = 0;
  uint64_t watchdog_logged_ = 0;
  std::string refusal_logged_;
};

}  // namespace create_driver
