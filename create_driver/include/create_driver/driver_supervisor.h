/// @file driver_supervisor.h
/// @brief The driver node's decisions around DriverCore, without ROS: which link events reach the
/// core, when odometry, hazards, battery, mode and goal feedback are due, how an ended goal is
/// reported, when a watchdog stop is logged, and the stream rate the diagnostics show.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "create_driver/driver_core.h"
#include "create_driver/link_supervisor.h"

namespace create_driver
{
/// Hazard flags as the `hazards` topic carries them.
struct HazardReading
{
  bool bump_left = false;
  bool bump_right = false;
  bool wheel_drop_left = false;
  bool wheel_drop_right = false;
  bool wheel_drop_caster = false;
  bool cliff_left = false;
  bool cliff_front_left = false;
  bool cliff_front_right = false;
  bool cliff_right = false;
  bool latched = false;
  Hazard latch_reason = Hazard::NONE;

  /// @brief True when every flag and the latch are the same.
  bool operator==(const HazardReading& other) const;
  /// @brief Negation of operator==.
  bool operator!=(const HazardReading& other) const { return !(*this == other); }
};

/// @brief The hazard flags of sensor state @p s (packets 7, 9..12) and the latch.
HazardReading hazardReading(const SensorState& s, const HazardLatch& latch);

/// State published after sensor frames.
struct DriverSnapshot
{
  SensorState sensors;
  Pose2D pose;           ///< odometry frame
  double linear = 0.0;   ///< m/s, odometry
  double angular = 0.0;  ///< rad/s, odometry
  HazardReading hazards;
  GoalProgress progress;
  int reported_mode = -1;  ///< as the robot reports it (packet 35), -1 unknown
};

/// What to publish after received bytes.
struct FrameActions
{
  size_t frames = 0;        ///< valid frames in the bytes; 0: nothing to publish
  DriverSnapshot snapshot;  ///< valid when frames > 0: odometry (and its transform) always
  bool hazards = false;     ///< hazards changed, or 0.1 s passed since they were last published
  bool battery = false;     ///< 1 s passed since the battery was last published
  bool mode = false;        ///< the reported mode differs from the mode last published
  bool feedback = false;    ///< a goal is active and its feedback is due (10 Hz)
};

/// How the action server ends a goal.
enum class GoalEnd : uint8_t
{
  SUCCEEDED,  ///< REACHED
  CANCELED,   ///< PREEMPTED (cancelled, replaced, overridden by cmd_vel)
  ABORTED     ///< every other reason (logged as a warning)
};

/// @brief The action server's end of a goal that stopped for @p reason.
GoalEnd goalEnd(StopReason reason);

/// Content of the `mode` topic.
struct ModeReport
{
  int reported_mode = -1;  ///< -1 until a frame arrived since the last connection
  OiMode requested_mode = OiMode::SAFE;
  LinkState link_state = LinkState::DISCONNECTED;
};

/// The sensor stream between two diagnostics reports.
struct StreamReport
{
  ParserCounters counters;
  uint64_t frames_estimated = 0;
  double rate = 0.0;         ///< valid frames per second since the previous report (0 at the first)
  bool new_corrupt = false;  ///< corrupt frames arrived since the previous report
};

/// @brief The driver node's logic around DriverCore (see file comment). Stamped inputs (times on the
/// steady clock, s) from the serial link's worker thread and from the command callbacks; it
/// answers with bytes to write and what to publish or report. Not thread-safe: the caller
/// serialises access.
class DriverSupervisor
{
public:
  /// @brief Creates the supervisor; @p config must pass validateConfig().
  explicit DriverSupervisor(const DriverConfig& config);

  /// @brief The port was (re)opened: bytes queued by startGoal() are dropped, the core starts.
  void onOpen(double now, Bytes& out);
  /// @brief Received bytes: feeds the core, appends its answer and the queued bytes.
  FrameActions onData(const uint8_t* data, size_t len, double now, Bytes& out);
  /// @brief Periodic tick of an open port: runs the core's control and appends the queued bytes.
  void onTick(double now, Bytes& out);
  /// @brief The link changed state; DISCONNECTED ends the active goal.
  void onLinkState(LinkState state, double now);
  /// @brief Appends the shutdown sequence (DriverCore::shutdown()).
  void shutdown(Bytes& out);

  /// @brief New cmd_vel (DriverCore::setVelocity()); @p linear is NaN for a twist with a
  /// non-finite component.
  bool setVelocity(double linear, double angular, double now, std::string* error);
  /// @brief Starts a distance goal (DriverCore::startGoal()); its bytes leave with the next
  /// onData() or onTick().
  GoalStart startGoal(double distance, double speed, double now);
  /// @brief Heartbeat of the goal's sender (DriverCore::heartbeat()).
  void heartbeat(double now);
  /// @brief The client cancelled goal @p id: it ends with PREEMPTED ("cancelled").
  void cancelGoal(uint64_t id);
  /// @brief Clears the hazard latch if no hazard is present (DriverCore::resetHazard()).
  bool resetHazard(std::string* message);

  /// @brief Moves the goals that ended into @p out (appending); goalEnd() says how to end each.
  void takeEndedGoals(std::vector<GoalOutcome>& out);
  /// @brief True once for each watchdog stop (DriverCore::commandSourceLost()), with its reason.
  bool takeWatchdogStop(std::string* why);
  /// @brief The mode topic's content, noted as published (onData() compares with it).
  ModeReport takeModeReport();
  /// @brief The stream's counters and rate since the previous call at @p now (s).
  StreamReport takeStreamReport(double now);

  /// @brief The driver logic (counters, latch, sensors) for the diagnostics.
  const DriverCore& core() const { return core_; }
  /// @brief The link state last passed to onLinkState().
  LinkState linkState() const { return link_state_; }

private:
  void flushQueued(Bytes& out);
  DriverSnapshot snapshot() const;
  void schedule(FrameActions& a, double now);

  DriverCore core_;
  Bytes queued_;  // startGoal()'s bytes, written from the worker thread
  LinkState link_state_ = LinkState::DISCONNECTED;
  std::string reported_lost_;  // the watchdog stop last reported
  int published_mode_ = -2;    // -2: none published yet
  HazardReading published_hazards_;
  double hazards_time_ = 0.0;
  double battery_time_ = 0.0;
  double feedback_time_ = 0.0;
  bool stream_reported_ = false;
  double stream_time_ = 0.0;
  uint64_t stream_valid_ = 0;
  uint64_t stream_corrupt_ = 0;
};

}  // namespace create_driver
