/// @file driver_core.h
/// @brief The driver without ROS and without I/O: bytes in, bytes out, commands and state.
///
/// DriverCore owns the stream parser, odometry, hazard latch, velocity limiter, command watchdog
/// and the distance controller. The caller feeds it received bytes and a monotonic time, calls
/// control() periodically, and writes the bytes it appends. The same class runs against the real
/// serial link (SerialLink), against create_sim over a pty, and against SimRobot in-process in
/// the unit tests.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "create_driver/drive_distance.h"
#include "create_driver/odometry.h"
#include "create_driver/oi_commands.h"
#include "create_driver/safety.h"
#include "create_driver/sensor_packets.h"
#include "create_driver/stream_parser.h"

namespace create_driver
{
/// How motion is encoded on the wire.
enum class DriveCommandType : uint8_t
{
  DIRECT,  ///< Drive Direct [145]: exact wheel speeds (default)
  RADIUS   ///< Drive [137] with velocity and radius (special radii for straight / in place)
};

/// Configuration of DriverCore (SI units unless stated).
struct DriverConfig
{
  Model model = Model::CREATE_1;
  OiMode mode = OiMode::SAFE;  ///< SAFE, FULL, or PASSIVE (sensors only, no motion)
  DriveCommandType drive_type = DriveCommandType::DIRECT;
  VelocityLimits limits;
  /// s, watchdog: the wheels stop when the newest cmd_vel, or a running goal's newest heartbeat,
  /// is older than this (at most kMaxCommandTimeout)
  double command_timeout = 0.25;
  double command_refresh = 0.2;  ///< s, an unchanged drive command is re-sent this often
  double start_gap = 0.05;       ///< s between Start and the mode/stream commands
  double start_retry = 1.0;      ///< s, the start sequence is repeated while no frame arrives
  double mode_retry = 0.5;       ///< s, minimum interval between mode re-assertions
  DriveDistanceParams drive_distance;
  bool use_wait_distance = false;     ///< Create 1 only: distance goals use Wait Distance [156]
  bool cmd_vel_preempts_goal = true;  ///< a non-zero cmd_vel ends an active goal (else it is ignored)
  Odometry::Params odometry;
};

/// Longest command_timeout accepted, s: a frozen sender stops the robot within about this.
constexpr double kMaxCommandTimeout = 0.3;

/// @brief Checks a configuration: the one place where the driver's ranges live.
/// @throws std::invalid_argument whose message starts with the offending field, named as the
///         driver's ROS parameter (max_speed, drive_distance/decel, ...).
void validateConfig(const DriverConfig& config);

/// @brief The mode called @p name: safe, full or passive.
/// @throws std::invalid_argument starting with "oi_mode must be"
OiMode parseOiMode(const std::string& name);

/// @brief The drive command called @p name: direct or radius.
/// @throws std::invalid_argument starting with "drive_command must be"
DriveCommandType parseDriveCommand(const std::string& name);

/// @brief Packet ids the driver streams for a model (7, 9..12, 18..26, 35; plus 43, 44 on the
/// Create 2).
std::vector<uint8_t> driverStreamIds(Model model);

/// End of a distance goal.
struct GoalOutcome
{
  uint64_t id = 0;
  StopReason reason = StopReason::REACHED;
  double travelled = 0.0;  ///< m, signed
  std::string message;
};

/// Answer to DriverCore::startGoal().
struct GoalStart
{
  bool accepted = false;
  uint64_t id = 0;
  StopReason reason = StopReason::INVALID_GOAL;  ///< why it was rejected
  std::string message;
};

/// Progress of the active goal.
struct GoalProgress
{
  bool active = false;
  uint64_t id = 0;
  double travelled = 0.0;  ///< m, signed
  double remaining = 0.0;  ///< m, signed
};

/// Event counters of DriverCore.
struct DriverStats
{
  uint64_t commands_sent = 0;      ///< drive commands written
  uint64_t rejected_commands = 0;  ///< cmd_vel with NaN/inf (or ignored during a goal)
  uint64_t watchdog_stops = 0;     ///< stops because a non-zero cmd_vel timed out
  uint64_t heartbeat_stops = 0;    ///< goals aborted (and wheels stopped) because the heartbeat stopped
  uint64_t hazard_stops = 0;       ///< stops because the hazard latch was set
  uint64_t mode_reasserts = 0;     ///< mode commands re-sent because the robot left the mode
  uint64_t start_sequences = 0;    ///< start sequences sent
  uint64_t frames_estimated = 0;   ///< frames lost to noise whose odometry was estimated (Create 1)
};

/// @brief The driver logic (see file comment). Not thread-safe: the caller serialises access.
class DriverCore
{
public:
  /// @brief Creates the core; @p config must pass validateConfig().
  explicit DriverCore(const DriverConfig& config);

  /// @brief Ids requested with Stream.
  const std::vector<uint8_t>& streamIds() const { return stream_ids_; }
  /// @brief Configuration in use.
  const DriverConfig& config() const { return config_; }

  /// @brief The port was (re)opened: appends a stop (obeyed at once if the robot's OI still runs
  /// from a previous connection or driver process) and Start; mode, a stop and the Stream request
  /// follow from control() after config.start_gap. Any previous cmd_vel is forgotten.
  void onConnected(double now, Bytes& out);
  /// @brief The port was closed or lost: the active goal ends with DISCONNECTED.
  void onDisconnected(double now);
  /// @brief Appends the shutdown sequence (stop wheels, pause the stream, Passive so the robot
  /// can charge) and ends the active goal.
  void shutdown(Bytes& out);

  /// @brief Feeds received bytes; processes every committed frame and runs control() if there
  /// was one.
  /// @return the number of valid frames
  size_t onBytes(const uint8_t* data, size_t len, double now, Bytes& out);
  /// @brief Runs the watchdog, the distance controller, the hazard checks and the limits, and
  /// appends a drive command when it changed or is due for a refresh.
  void control(double now, Bytes& out);

  /// @brief New velocity command (cmd_vel). Rejected (and counted) if not finite. While a
  /// distance goal runs, a zero command is ignored and a non-zero one ends the goal with
  /// PREEMPTED (or is rejected when config.cmd_vel_preempts_goal is false).
  /// @param error set when rejected
  bool setVelocity(double linear, double angular, double now, std::string* error);
  /// @brief Starts a distance goal (ending the active one with PREEMPTED). The goal runs while
  /// heartbeat() refreshes it at least every config.command_timeout; else it ends with
  /// HEARTBEAT_LOST and the wheels stop. May append bytes (the Wait Distance script when that
  /// option is on).
  GoalStart startGoal(double distance, double speed, double now, Bytes& out);
  /// @brief The goal's sender is alive: refreshes the active goal's watchdog (ignored without one).
  void heartbeat(double now);
  /// @brief Ends the goal @p id (if active) with @p reason; the wheels stop at the next control().
  void cancelGoal(uint64_t id, StopReason reason, const std::string& message);
  /// @brief Clears the hazard latch if no hazard is present.
  bool resetHazard(std::string* message);

  /// @brief Moves the finished-goal outcomes into @p out (appending).
  void takeOutcomes(std::vector<GoalOutcome>& out);
  /// @brief Progress of the active goal.
  GoalProgress goalProgress() const;

  /// @brief Latest committed sensor state.
  const SensorState& sensors() const { return parser_.state(); }
  /// @brief Odometry.
  const Odometry& odometry() const { return odometry_; }
  /// @brief Stream parser counters.
  const ParserCounters& parserCounters() const { return parser_.counters(); }
  /// @brief Hazard latch.
  const HazardLatch& latch() const { return latch_; }
  /// @brief Event counters.
  const DriverStats& stats() const { return stats_; }
  /// @brief True once a valid frame arrived since the last onConnected().
  bool haveSensors() const { return have_frame_; }
  /// @brief Mode reported by the robot, or -1 if unknown.
  int reportedMode() const { return reported_mode_; }
  /// @brief Left wheel speed of the last drive command sent, mm/s.
  int lastLeftMmS() const { return last_left_; }
  /// @brief Right wheel speed of the last drive command sent, mm/s.
  int lastRightMmS() const { return last_right_; }
  /// @brief True while a Wait Distance goal holds the robot's command input.
  bool waitDistanceActive() const { return wd_active_; }
  /// @brief Why the watchdog last stopped the robot, while no command has come since; "" otherwise
  /// (the command source is then alive or was never needed).
  const std::string& commandSourceLost() const { return source_lost_; }
  /// @brief Age of the newest motion command at @p now (cmd_vel, goal or heartbeat), s; negative
  /// before the first one.
  double commandAge(double now) const { return last_command_time_ < 0.0 ? -1.0 : now - last_command_time_; }

private:
  void processFrame(const SensorState& state, double stamp);
  void fillLostFrames(double stamp);
  void finishGoal(StopReason reason, const std::string& message);
  /// A command arrived at @p now: the source is alive.
  void commandSeen(double now);
  /// The watchdog stopped the robot: counts it and keeps @p why for commandSourceLost().
  void watchdogStop(const std::string& why, bool& emergency);
  // The phases of control(), in order.
  /// Start, then mode, a stop and Stream after start_gap; Start again every start_retry while no
  /// frame arrives. False until a frame arrived.
  bool runStartSequence(double now, Bytes& out);
  /// The velocity asked for by the active goal or cmd_vel (0 if none); ends a goal that finished
  /// and a cmd_vel that timed out (setting @p emergency). False while a Wait Distance script runs.
  bool commandedVelocity(double now, bool& emergency, double& v, double& w);
  /// Zero when the hazard latch, passive mode or an emergency forbids motion, or when a stop is
  /// asked for (no ramp); else the limiter.
  void limitVelocity(double dt, bool emergency, double& v, double& w);
  /// Sends the mode again when the robot left it while it should move.
  void reassertMode(double v, double w, double now, Bytes& out);
  /// Appends the drive command when it changed on the wire or is due for a refresh.
  void sendMotionIfDue(double v, double w, double now, Bytes& out);
  void appendMotion(double linear, double angular, Bytes& out);
  static StopReason hazardReason(Hazard hazard);

  DriverConfig config_;
  std::vector<uint8_t> stream_ids_;
  StreamParser parser_;
  Odometry odometry_;
  HazardLatch latch_;
  VelocityLimiter limiter_;
  DriveDistanceController dd_;
  DriverStats stats_;

  bool connected_ = false;
  bool have_frame_ = false;
  int start_phase_ = 0;  // 0 idle, 1 Start sent, 2 mode + stream sent
  double start_time_ = 0.0;
  int reported_mode_ = -1;
  double last_frame_stamp_ = 0.0;
  uint64_t corrupt_seen_ = 0;
  bool frames_lost_ = false;
  double last_mode_sent_ = -1e300;

  bool cmd_active_ = false;
  double cmd_linear_ = 0.0;
  double cmd_angular_ = 0.0;
  double cmd_time_ = 0.0;
  bool force_stop_ = false;

  uint64_t next_goal_id_ = 1;
  uint64_t goal_id_ = 0;
  double goal_refresh_ = 0.0;  // start or newest heartbeat of the active goal
  double last_command_time_ = -1.0;
  std::string source_lost_;
  bool wd_active_ = false;
  std::vector<GoalOutcome> outcomes_;

  double last_control_ = -1.0;
  bool have_sent_ = false;
  int last_key_a_ = 0;
  int last_key_b_ = 0;
  int last_left_ = 0;
  int last_right_ = 0;
  double last_sent_time_ = 0.0;
};

}  // namespace create_driver
