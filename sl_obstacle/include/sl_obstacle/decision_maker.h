/// @file decision_maker.h
/// @brief Driving decisions from the working-volume analysis: drive, slow, stop, turn, stale.
#pragma once

#include <cstdint>
#include <limits>
#include <string>

#include "sl_obstacle/volume_checker.h"

namespace sl_obstacle
{
/// Parameters of the decision maker (SI units).
struct DecisionParams
{
  bool enabled = true;               ///< false: always stopped (reason DISABLED)
  double safety_margin = 0.15;       ///< distance kept to obstacles and to unknown space (m)
  double min_goal_distance = 0.05;   ///< shortest forward goal worth sending (m)
  double slow_distance = 0.6;        ///< free distance from which max_speed is allowed (m)
  double max_speed = 0.2;            ///< forward speed with free_distance >= slow_distance (m/s)
  double min_speed = 0.05;           ///< forward speed at free_distance = safety_margin (m/s)
  double min_coverage = 0.3;         ///< below this coverage the robot does not start a goal
  double full_speed_coverage = 0.8;  ///< from this coverage on, speed is not reduced for coverage
  double stale_timeout = 0.5;        ///< no cloud newer than this: stop (s)
  double preempt_tolerance = 0.02;   ///< pre-empt a goal whose remaining distance exceeds the new limit by this (m)
  double replan_distance = 0.15;     ///< extend a running goal when this much more is free (m)
  double speed_tolerance = 0.03;     ///< re-send a goal when the allowed speed fell by this (m/s)
  double turn_speed = 0.5;           ///< in-place turn rate (rad/s)
  double turn_angle = 0.5;           ///< angle of one turn step (rad)
  int max_turns = 12;                ///< turn steps before giving up; 0 disables turning
  double settle_time = 0.3;          ///< wait after stopping / turning before looking again (s)
  double deceleration = 0.25;        ///< the driver's braking deceleration a: speed <= sqrt(2 a d) (m/s^2)
  int max_backoffs = 3;              ///< back-offs along the trail before giving up (map only; 0: none)
  double backoff_distance = 0.3;     ///< longest back-off (m)
  double backoff_speed = 0.08;       ///< back-off speed (m/s)
  /// Forward speed (m/s, in [0, 0.05]) of a goal over cells never seen to hold anything (map only), while
  /// the camera sees straight ahead at safety_margin (FrameSummary::view_seen): the
  /// ring around the body the camera cannot see. 0: never; then such space is refused like any
  /// unknown space.
  double creep_speed = 0.05;

  /// @throws std::invalid_argument when invalid, its message starting with the offending parameter's name.
  void validate() const;
};

/// Decision state (values equal the ObstacleStatus message constants; src/nodelets/status_codes.h checks it).
enum class State : std::uint8_t
{
  STALE = 0,
  STOPPED = 1,
  BLOCKED = 2,
  TURNING = 3,
  SLOWING = 4,
  DRIVING = 5,
  BACKING_OFF = 6
};

/// Why (values equal the ObstacleStatus REASON_* constants; src/nodelets/status_codes.h checks it).
enum class Reason : std::uint8_t
{
  NO_DATA = 0,
  STALE_DATA = 1,
  DISABLED = 2,
  DRIVER_UNAVAILABLE = 3,
  DRIVER_FAILED = 4,
  DRIVER_HAZARD = 5,
  LOW_COVERAGE = 6,
  OBSTACLE = 7,
  UNKNOWN_AHEAD = 8,
  TURNING = 9,
  LOOKING = 10,
  NO_FREE_DIRECTION = 11,
  WAITING_FOR_FRAME = 12,
  PATH_FREE = 13,
  SHORT_FREE_DISTANCE = 14,
  PARTIAL_COVERAGE = 15,
  NEARER_OBSTACLE = 16,
  EXTENDING = 17,
  GOAL_RUNNING = 18,
  BACKING_OFF = 19,
  NO_ODOMETRY = 20,
  CREEPING = 26  ///< a goal at creep_speed over cells never seen (the safety filter's reasons are 21..25)
};

/// What the robot is told (values equal the ObstacleStatus COMMAND_* constants; checked as State).
enum class Command : std::uint8_t
{
  NONE = 0,   ///< keep going (the running goal continues)
  STOP = 1,   ///< cancel any goal, zero velocity
  DRIVE = 2,  ///< new forward goal (replaces a running one)
  TURN = 3    ///< turn in place at angular_speed (re-issued every step while turning)
};

/// How the driver ended a goal.
enum class GoalEnd : std::uint8_t
{
  REACHED,    ///< distance travelled
  CANCELLED,  ///< pre-empted or cancelled (by us or someone else)
  HAZARD,     ///< bumper, cliff or wheel drop
  FAILED      ///< timeout, disconnected, invalid goal, lost server
};

/// Short upper-case name of a state, e.g. "DRIVING".
const char* toString(State state);
/// Short upper-case name of a reason, e.g. "OBSTACLE".
const char* toString(Reason reason);
/// Short upper-case name of a command, e.g. "DRIVE".
const char* toString(Command command);

/// The part of a frame analysis the decisions use.
struct FrameSummary
{
  double stamp = 0.0;  ///< capture time of the cloud (s, same clock as step()'s now)
  double nearest_obstacle = std::numeric_limits<double>::infinity();  ///< m
  double free_distance = 0.0;                                         ///< m, includes unknown space (see VolumeResult)
  double coverage = 0.0;                                              ///< 0..1
  double left_free = 0.0;   ///< mean free distance left of centre (m); from a map: best heading to the left
  double right_free = 0.0;  ///< mean free distance right of centre (m); from a map: best heading to the right
  // Filled when the summary comes from the local map (WorldModel) at the robot's current pose.
  bool from_map = false;           ///< free_distance is the map's known-free travel: no coverage gating
  double reverse_free = 0.0;       ///< known-free travel straight back (m)
  double best_turn = 0.0;          ///< relative heading with the longest known-free travel (rad)
  double best_turn_free = 0.0;     ///< that travel (m)
  double best_reverse_turn = 0.0;  ///< relative heading whose reverse path is free the farthest (rad)
  double best_reverse_free = 0.0;  ///< that reverse travel (m)
  /// Travel through free cells and cells never seen to hold anything (m; from a map: the swept path
  /// up to the first occupied cell or cell holding evidence, or the nearest obstacle; else
  /// free_distance). Creeping goals (creep_speed) may use it.
  double open_distance = 0.0;
  /// From a map: the centre line straight ahead is known (free or occupied) from safety_margin to two
  /// cells beyond it (the camera sees there). Creeping needs it.
  bool view_seen = false;
};

/// Extracts the summary of @p result, captured at @p stamp.
FrameSummary summarize(const VolumeResult& result, double stamp);

/// What the robot is doing, as known to the caller (driver feedback or the open-loop runner).
struct MotionState
{
  bool driver_ready = true;              ///< the motion interface can take goals
  const char* driver_detail = "";        ///< why it cannot (a string literal; shown in the reason)
  bool goal_active = false;              ///< a forward goal is running
  double goal_remaining = 0.0;           ///< distance still to drive of that goal (m)
  double goal_speed = 0.0;               ///< its speed (m/s)
  bool localized = true;                 ///< the robot's current pose is known (needed by map decisions)
  const char* localization_detail = "";  ///< why it is not (a string literal; shown in the reason)
};

/// One decision.
struct Decision
{
  State state = State::STALE;
  Reason reason = Reason::NO_DATA;
  std::string text;  ///< human-readable reason with the numbers
  Command command = Command::STOP;
  double distance = 0.0;       ///< DRIVE: goal distance (m); negative: backwards (a back-off)
  double speed = 0.0;          ///< DRIVE: goal speed (m/s)
  double angular_speed = 0.0;  ///< TURN: rate (rad/s), positive = left
  bool blocked = false;        ///< the way ahead is blocked (BLOCKED, TURNING, no free direction)
};

/// State machine that turns frame summaries and motion feedback into commands.
///
/// No clock of its own: every call takes the time. Frames are fed with onFrame(); step() is called
/// after each frame and at a steady control rate (e.g. 10 Hz, which also keeps a cmd_vel watchdog
/// fed while turning). Planning a new goal needs a frame taken after the robot last stopped.
class DecisionMaker
{
public:
  /// @throws std::invalid_argument on invalid parameters.
  explicit DecisionMaker(const DecisionParams& params = DecisionParams());

  /// Replaces the parameters; keeps the current state. @throws std::invalid_argument.
  void setParams(const DecisionParams& params);

  /// The parameters in use.
  const DecisionParams& params() const { return params_; }

  /// Forgets everything (no data, no turn cycle).
  void reset();

  /// Feeds the analysis of a new cloud.
  void onFrame(const FrameSummary& frame);

  /// Tells that the driver ended the running goal at @p now; @p what describes it (may be empty).
  /// Not needed for goals this class stopped itself.
  void onGoalEnded(GoalEnd end, double now, const std::string& what);

  /// Decides at time @p now. @return the decision (valid until the next call).
  const Decision& step(double now, const MotionState& motion);

  /// The last decision.
  const Decision& last() const { return decision_; }

  /// True once a frame was received.
  bool hasFrame() const { return has_frame_; }

  /// The latest frame summary.
  const FrameSummary& frame() const { return frame_; }

private:
  enum class Phase
  {
    NONE,     // not in a turn cycle
    SETTLE,   // blocked: stopped, waiting before the first turn
    TURN,     // turning
    LOOK,     // turn done: stopped, waiting for a fresh frame
    ALIGN,    // turning toward the heading whose reverse path is free, before a back-off
    BACKOFF,  // driving backwards along known-free cells
    GAVE_UP   // max_turns (and max_backoffs) reached without a free direction
  };

  struct Assessment
  {
    enum Kind
    {
      DRIVE,
      OBSTACLE,
      UNKNOWN_AHEAD,
      LOW_COVERAGE
    } kind = DRIVE;
    double distance = 0.0;
    double speed = 0.0;
    Reason reason = Reason::PATH_FREE;
    bool creep = false;  // a DRIVE over cells never seen (creep_speed)
  };

  Assessment assess(const FrameSummary& f) const;
  double speedForFree(double free) const;
  double coverageFactor(double coverage) const;
  void describe(const Assessment& a, const FrameSummary& f);
  void set(State state, Reason reason, Command command);
  void setText(const char* format, ...) __attribute__((format(printf, 2, 3)));
  void drive(const Assessment& a, const FrameSummary& f);
  void startCycle(double now, Reason reason, const char* why);
  void startTurn(double now);
  void stepCycle(double now, const MotionState& motion);
  bool startBackoff(double now);
  bool stepBackoff(double now, const MotionState& motion);
  void stepRunningGoal(double now, const MotionState& motion);
  void stepCreep(double now, const MotionState& motion);
  void stepIdle(double now, const MotionState& motion);
  void decide(double now, const MotionState& motion);
  void stopHere(double now);

  DecisionParams params_;
  Decision decision_;
  FrameSummary frame_;
  bool has_frame_ = false;

  double motion_end_ = -std::numeric_limits<double>::infinity();  // time the robot last stopped
  bool goal_was_active_ = false;
  GoalEnd end_kind_ = GoalEnd::REACHED;
  double end_time_ = 0.0;     // time of the last onGoalEnded()
  bool end_pending_ = false;  // an onGoalEnded() not yet reflected in a decision
  std::string end_text_;

  Phase phase_ = Phase::NONE;
  double phase_start_ = 0.0;
  double turn_end_ = 0.0;
  double look_after_ = 0.0;
  int turns_done_ = 0;
  int turn_dir_ = 1;  // +1 left, -1 right
  int backoffs_done_ = 0;
  bool backoff_sent_ = false;
  bool creeping_ = false;  // the running goal is a creep goal
  Reason cycle_reason_ = Reason::OBSTACLE;
  Reason start_reason_ = Reason::OBSTACLE;  // why the turn cycle began
  std::string cycle_text_;
};
}  // namespace sl_obstacle
