/// @file navigator.h
/// @brief The navigation supervisor: goals in, velocity commands out, on a persistent map fused from
/// the local map; plans, replans, follows, and refuses what cannot be reached (ROS-free).
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "sl_navigation/nav_grid.h"
#include "sl_navigation/path_follower.h"
#include "sl_navigation/planner.h"

namespace sl_navigation
{
/// Parameters of the navigator. validate() names the ROS parameter of a bad value.
struct NavigatorParams
{
  GridParams grid;                 ///< the persistent map
  PlannerParams planner;           ///< inflation and costs
  FollowerParams follower;         ///< driving
  double replan_period = 1.0;      ///< s between replans while the map changes (replan_period)
  double progress_timeout = 30.0;  ///< s without getting progress_distance nearer: aborted (progress_timeout)
  double progress_distance = 0.1;  ///< m of remaining path that count as progress
  double refuse_time = 2.0;        ///< s a blocked or enclosed goal must stay so before it is aborted (refuse_time)
  double switch_gain = 0.15;       ///< a new plan replaces a still passable one only when this much cheaper (share)
  /// A detour forced by an obstacle on the path restarts the progress count while it is at most this
  /// many times the goal's first straight-line distance d (max_detour); a goal not reached after
  /// driving max_detour x d + 1 m is ABORTED (the search for a way is bounded)
  double max_detour = 3.5;
  double stuck_time = 3.0;   ///< s commanding forward motion without moving 2 cm: look around (stuck_time)
  double look_around = 0.6;  ///< rad turned to each side when stuck, to let the camera see the sides (look_around)
  /// s the planner takes the way ahead as blocked where the robot was stuck three times in the same
  /// place (the safety filter refuses what the map shows passable); 0: never (refused_memory)
  double refused_memory = 120.0;
  double map_timeout = 2.0;  ///< s without a local map before the robot stops (map_timeout)
  /// A goal whose map cell stays unknown while the robot is within unseen_goal_distance (m) of it
  /// for unseen_goal_time (s) in all is ABORTED: from that near the camera sees an open goal at
  /// once, so one still unseen lies inside or behind something (a sofa whose inside is never seen).
  /// 0: off (unseen_goal_distance)
  double unseen_goal_distance = 0.8;
  double unseen_goal_time = 20.0;  ///< s, see unseen_goal_distance (unseen_goal_time)
  /// A goal never seen free with something the map knows within unseen_goal_clearance (m) may lie
  /// inside it: toward it, a detour does not restart the progress count and nearer in a straight
  /// line is no progress, so the search for a way in ends after progress_timeout without a plan
  /// shorter than any before. 0: off (unseen_goal_clearance)
  double unseen_goal_clearance = 0.4;

  /// @throws std::invalid_argument naming the parameter.
  void validate() const;
};

/// Where the navigator stands.
enum class NavState : std::uint8_t
{
  IDLE = 0,       ///< no goal yet
  ACTIVE = 1,     ///< driving to a goal
  SUCCEEDED = 2,  ///< the last goal was reached
  ABORTED = 3,    ///< the last goal was refused or could not be reached (see the reason)
  CANCELLED = 4   ///< the last goal was cancelled or pre-empted
};

/// Short upper-case name of a state.
const char* toString(NavState state);

/// A goal in odom.
struct NavGoal
{
  double x = 0.0;        ///< m
  double y = 0.0;        ///< m
  double yaw = 0.0;      ///< rad (used with use_yaw and yaw_tolerance > 0)
  bool use_yaw = false;  ///< the goal's heading matters
};

/// One step's result.
struct NavOutput
{
  NavState state = NavState::IDLE;
  FollowMode mode = FollowMode::ARRIVED;
  bool command = false;       ///< true: send (linear, angular); false: send nothing (idle)
  double linear = 0.0;        ///< m/s
  double angular = 0.0;       ///< rad/s
  std::string reason;         ///< a sentence with the numbers
  bool plan_changed = false;  ///< a new plan was made in this step
  double goal_distance = std::numeric_limits<double>::quiet_NaN();  ///< m, straight line
  double remaining = std::numeric_limits<double>::quiet_NaN();      ///< m of path left
  double elapsed = 0.0;                                             ///< s since the goal was accepted
  double travelled = 0.0;                                           ///< m driven since the goal was accepted
};

/**
 * @brief Goal bookkeeping over the NavGrid, the Planner and the PathFollower.
 *
 * onMap() fuses each local window into the persistent map and keeps it as the execution window.
 * step() plans when there is no plan, when the map changed and replan_period passed, or when the
 * follower finds the path blocked; drives the plan; and ends the goal: SUCCEEDED within
 * goal_tolerance, ABORTED when the goal is inside an obstacle or enclosed for refuse_time, or after
 * progress_timeout without progress: neither the straight-line distance to the goal nor the path
 * left shrank by progress_distance. A periodic replan replaces a plan that is still passable only
 * when it is switch_gain cheaper, so the robot does not swing between two routes of similar cost.
 * When the robot does not move while it is told to go forward for stuck_time (the safety filter
 * refuses: the sides of the path just ahead are unseen, or something the local map shows), it looks
 * around: turns look_around to the left, to the right, and back (turning in place always passes the
 * filter), so that the camera sees the sides of the way ahead, then replans and drives on. Stuck
 * again within 0.15 m of that place, it backs off 0.3 m along its trail (reverse passes the filter
 * over the trail), faces the point it was refused, now far enough for the camera, and drives on;
 * stuck a third time there, a disc of 0.1 m on the path just ahead of its body is taken as occupied
 * by the planner for refused_memory (across goals), and it replans another way (or the goal ends as
 * the planner finds none). setGoal() refuses at once
 * a non-finite goal or one outside the map. A new goal replaces the old one (which ends CANCELLED).
 * Before refuse_time counts, the robot faces the goal once and waits look_time (confirmLook()).
 */
class Navigator
{
public:
  /// @throws std::invalid_argument for bad parameters.
  explicit Navigator(const NavigatorParams& params = NavigatorParams());

  /// A local occupancy window seen at @p stamp (s). @return false for a bad layout (ignored).
  bool onMap(const OccupancyView& view, double stamp);
  /// A new goal at @p now. @return empty when accepted, else the reason (the state is then ABORTED).
  std::string setGoal(const NavGoal& goal, double now);
  /// Cancels the running goal (the state becomes CANCELLED; the next step sends a stop).
  void cancel(double now, const std::string& why);
  /// Refuses a goal the caller could not take (e.g. no transform): the state becomes ABORTED with
  /// @p why, any running goal ends, the next step sends a stop.
  void refuse(const std::string& why);
  /// The caller cannot give a pose at @p now (no odometry): a running goal waits, stopped, and is
  /// aborted after progress_timeout; @return true when a stop is to be sent.
  bool noPose(double now, const std::string& why);
  /// One control step from @p pose (base_link in odom) at @p now; @p speed_cap: see PathFollower::step().
  const NavOutput& step(const Pose& pose, double now, double speed_cap = std::numeric_limits<double>::infinity());

  /// The state.
  NavState state() const { return out_.state; }
  /// The persistent map.
  const NavGrid& grid() const { return grid_; }
  /// The current plan (empty when none).
  const Plan& plan() const { return plan_; }
  /// The active or last goal.
  const NavGoal& goal() const { return goal_; }
  /// The parameters.
  const NavigatorParams& params() const { return params_; }
  /// True once a local window arrived.
  bool hasMap() const { return has_map_; }
  /// Places taken as blocked so far (stuck three times in the same place; see refused_memory).
  std::size_t blockedPlaces() const { return blocked_places_; }
  /// Back-offs along the trail so far (stuck twice in the same place).
  std::size_t backoffs() const { return backoffs_; }
  /// Times the robot was found stuck (told to drive without moving for stuck_time) so far.
  std::size_t stucks() const { return stucks_; }

private:
  void end(NavState state, const std::string& reason);
  // end() with the stop sent in this step's output; returns it.
  const NavOutput& endNow(NavState state, const std::string& reason);
  /// Plans anew; with @p force a new plan replaces the current one even when that is still passable.
  bool replan(const Pose& pose, double now, bool force = false);
  void track(const Pose& pose, double now);

  NavigatorParams params_;
  NavGrid grid_;
  Planner planner_;
  PathFollower follower_;
  ExecWindow window_;
  bool has_map_ = false;
  double map_time_ = -std::numeric_limits<double>::infinity();  // stamp of the newest local window
  NavGoal goal_;
  Plan plan_;
  NavOutput out_;
  bool stop_pending_ = false;  // an ended goal still owes the driver one stop
  double goal_time_ = 0.0;
  double plan_time_ = -std::numeric_limits<double>::infinity();
  std::uint64_t plan_version_ = 0;
  double refuse_since_ = std::numeric_limits<double>::quiet_NaN();
  double best_remaining_ = std::numeric_limits<double>::infinity();  // path left
  double best_distance_ = std::numeric_limits<double>::infinity();   // straight line to the goal
  bool goal_seen_ = false;                                           // the plan's end was once known free
  double goal_distance_ = 0.0;  // straight line from the first pose after setGoal() to the goal
  double progress_time_ = 0.0;
  bool has_last_pose_ = false;
  Pose last_pose_;
  Pose still_pose_;           // where the robot stood when it was last seen to move
  double still_since_ = 0.0;  // since when it stands there while told to drive
  bool told_to_drive_ = false;
  double unseen_time_ = 0.0;  // s the goal stayed unknown while the robot was near it
  double last_step_ = std::numeric_limits<double>::quiet_NaN();
  /// Adds the time since the last step while the goal's cell is unknown and the robot within
  /// unseen_goal_distance of it; true once that passes unseen_goal_time.
  bool goalStaysUnseen(const Pose& pose, double now);
  /// True while the plan's end was never seen free and the map knows something within
  /// unseen_goal_clearance of it (see NavigatorParams::unseen_goal_clearance).
  bool mayBeInside(double now);
  /// Where the robot is to stop: the plan's end, or the goal without a plan.
  Point pathEnd() const;
  /// Starts a look-around when the robot does not follow its commands.
  void checkStuck(const Pose& pose, double now);
  /// One step of the look-around; false once it is done.
  bool lookAround(const Pose& pose, double now);
  /// Stuck a second time in one place: starts backing off along the trail, to look at @p refused
  /// (refusedPoint()) afterwards; false when the trail is too short for it.
  bool startBackoff(const Pose& pose, const Point& refused, double now);
  /// One step of the back-off (turn so the trail lies behind, reverse along it, face the refused
  /// point, wait look_time); false once it is over.
  bool backoff(const Pose& pose, double now);
  /// Stuck a third time in one place (the way not ending at the goal): blocks the way ahead for
  /// the planner and replans: a disc around @p c (refusedPoint()).
  void blockAhead(const Pose& pose, const Point& c, double now);
  /// No plan (the goal blocked or enclosed): the first time in an episode of failed plans, turns to
  /// face the goal and waits look_time for the map, so that a passage closed by a spurious cell is
  /// seen again; refuse_time counts from the end of it. @return true while it commands the robot.
  bool confirmLook(const Pose& pose, double now);
  /// The point of the path just beyond the robot's body (where the filter refused to go).
  Point refusedPoint(const Pose& pose) const;
  /// True when a blocked disc at @p c would make the goal itself unplannable.
  bool blocksGoal(const Point& c) const;
  /// Keeps the last few metres the robot drove (the trail a back-off reverses along).
  void recordTrail(const Pose& pose);
  /// The blocked discs still within refused_memory, handed to the planner.
  void pruneBlocked(double now);
  struct Refused
  {
    Disc disc;
    double until = 0.0;
  };
  std::vector<Refused> refused_;  // the ways blocked where the robot was stuck twice
  Pose stuck_at_;                 // where the robot was first stuck in this place
  double stuck_at_time_ = -std::numeric_limits<double>::infinity();
  int stuck_count_ = 0;           // times stuck there: 1 look around, 2 back off, 3 block the way
  std::vector<Point> trail_;      // positions the robot drove through, 0.05 m apart, newest last
  int backoff_phase_ = 0;         // 0: none; 1 turn, 2 reverse, 3 face the refused point, 4 wait
  Point backoff_target_;          // the trail point to reverse to
  Point backoff_look_;            // the refused point to look at afterwards
  double backoff_started_ = 0.0;  // start of the current phase
  std::size_t backoffs_ = 0;
  std::size_t stucks_ = 0;
  std::string blocked_text_;  // the last blockAhead(), said in the reason for a while
  double blocked_time_ = -std::numeric_limits<double>::infinity();
  std::size_t blocked_places_ = 0;
  int look_step_ = -1;          // -1: not looking around; else the index of the heading turned to
  double look_base_yaw_ = 0.0;  // the heading the look-around started from
  double look_started_ = 0.0;
  enum class Confirm : std::uint8_t
  {
    NONE,     // no failed plan in this episode yet
    TURNING,  // turning to face the goal
    WAITING,  // facing it, waiting look_time for the map
    DONE      // looked: refuse_time runs
  };
  Confirm confirm_ = Confirm::NONE;  // confirmLook()'s phase
  double confirm_started_ = 0.0;
};
}  // namespace sl_navigation
