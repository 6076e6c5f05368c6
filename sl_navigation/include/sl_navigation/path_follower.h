/// @file path_follower.h
/// @brief Drives along a planned path: pure pursuit on arcs, speed from the known-free travel
/// (v <= sqrt(2 a (d - clearance))), and turning to look where the path ahead is unknown (ROS-free).
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "sl_navigation/nav_grid.h"
#include "sl_navigation/planner.h"

namespace sl_navigation
{
/// A planar pose of base_link in odom.
struct Pose
{
  double x = 0.0;    ///< m
  double y = 0.0;    ///< m
  double yaw = 0.0;  ///< rad, counter-clockwise from +x
};

/// Parameters of the path follower. validate() names the ROS parameter of a bad value.
struct FollowerParams
{
  double max_speed = 0.45;          ///< m/s (max_speed); the Create drives up to 0.5
  double min_speed = 0.05;          ///< m/s asked for at least while the path is not blocked (the filter decides)
  double max_angular = 1.2;         ///< rad/s while driving (max_angular_speed)
  double turn_speed = 0.9;          ///< rad/s, the fastest turn in place (turn_speed)
  double acceleration = 0.4;        ///< m/s^2, how fast the command's speed rises (acceleration)
  double deceleration = 0.25;       ///< m/s^2, the a of v <= sqrt(2 a d) (the safety filter's)
  double clearance = 0.1;           ///< m kept to occupied cells along the path (the safety filter's obstacle_margin)
  double swept_radius = 0.1875;     ///< m, robot radius + lateral margin (the safety filter's)
  double lookahead = 0.35;          ///< m, pure-pursuit look-ahead along the path
  double rotate_threshold = 0.8;    ///< rad: heading errors above this are turned in place first
  double look_distance = 1.2;       ///< m from base_link: unknown path cells up to this far are looked at
  double look_min_distance = 0.75;  ///< m from base_link: nearer cells are seen too close to tell the floor free
  double view_angle =
      0.15;  ///< rad, half the view in which the floor is seen free: unknown cells in it are not looked at
  double look_tolerance = 0.15;  ///< rad: facing an unknown cell this well counts as looking at it
  double look_time = 0.5;        ///< s to wait facing an unknown cell before driving on (the filter decides)
  double goal_tolerance = 0.10;  ///< m (goal_tolerance)
  double yaw_tolerance = 0.0;    ///< rad; 0: the goal's heading is ignored (yaw_tolerance)

  /// @throws std::invalid_argument naming the parameter.
  void validate() const;
};

/// The latest local occupancy window (the obstacle node's local map): what the safety filter sees.
class ExecWindow
{
public:
  /// Copies @p view (nav_msgs/OccupancyGrid layout). @return false for a bad layout (kept as it was).
  bool set(const OccupancyView& view);
  /// -1 unknown (also outside), 0 free, 100 occupied, other values: suspect.
  std::int8_t at(double x, double y) const;
  /// True once a window was set.
  bool valid() const { return width_ > 0; }
  /// The window's cell size (m).
  double resolution() const { return resolution_; }

private:
  std::vector<std::int8_t> data_;
  int width_ = 0;
  int height_ = 0;
  double resolution_ = 0.02;
  double origin_x_ = 0.0;
  double origin_y_ = 0.0;
};

/// What the follower does in a step.
enum class FollowMode : std::uint8_t
{
  DRIVE,    ///< driving along the path (arcs)
  ROTATE,   ///< turning in place toward the path (large heading error) or to the goal's heading
  LOOK,     ///< turning toward, or facing, an unknown part of the path ahead
  BLOCKED,  ///< an obstacle on the path within the clearance: stopped (the caller replans)
  ARRIVED   ///< within goal_tolerance (and yaw_tolerance)
};

/// Short upper-case name of a mode.
const char* toString(FollowMode mode);

/// One step's command and what it is based on.
struct FollowCommand
{
  FollowMode mode = FollowMode::DRIVE;
  double linear = 0.0;       ///< m/s
  double angular = 0.0;      ///< rad/s
  double free_travel = 0.0;  ///< m of the path ahead known free (swept disc) in the window
  double obstacle_travel = std::numeric_limits<double>::infinity();  ///< m to the first occupied cell on the path
  double remaining = 0.0;                                            ///< m of path left
  double goal_distance = 0.0;                                        ///< m, straight line to the goal
  std::string text;                                                  ///< a sentence with the numbers
};

/**
 * @brief Pure pursuit with the safety filter's rules.
 *
 * Each step projects the robot on the path (never backwards), sweeps the robot's disc along the path
 * on the ExecWindow and takes the known-free travel d (the first cell not free, cells under the robot
 * now excepted). Where an unknown cell of the path lies between look_min_distance and look_distance
 * from the robot and outside the camera's view (beyond view_angle of the heading: an unknown cell in
 * view is hidden or too far, looking would not help; nearer unknown cells do not hide farther ones), it
 * first turns to face it, waits look_time for the map and turns back in place toward the path (what
 * lay in the view at a look is not looked at again): with a camera of narrow view the
 * sides of the path are seen this way before the robot gets there. Otherwise it drives toward the look-ahead point on
 * an arc of curvature 2 sin(alpha) / L, with v <= max_speed, v <= sqrt(2 a (d_obstacle - clearance)) (d_obstacle:
 * travel to the first occupied cell of the window on the path), v <= max_angular / |curvature|, v <= the filter's last
 * limit plus the rise the acceleration allows, the rise limited by acceleration, and slowing toward
 * the goal as v <= sqrt(2 a (goal distance)). Unknown space is left to the safety filter, which
 * knows it at the moment of the command (the window is up to 0.5 s old); at least min_speed is
 * asked for while the path is not blocked.
 */
class PathFollower
{
public:
  /// @throws std::invalid_argument for bad parameters.
  explicit PathFollower(const FollowerParams& params = FollowerParams());

  /// Starts following @p path (start to goal); keeps the speed. @p goal_yaw is used when
  /// @p use_yaw and yaw_tolerance > 0. @p tolerance (m), when in (0, goal_tolerance), replaces
  /// goal_tolerance for this path: the end of a path to a goal the planner moved (Plan::goal_shift)
  /// must be reached closer, so that the requested goal is within goal_tolerance.
  void setPath(const std::vector<Point>& path, double goal_yaw, bool use_yaw, double tolerance = 0.0);
  /// Forgets the path and the looked-at cells; the next command starts from standstill.
  void reset();
  /// One control step at @p now (s) from @p pose on @p window. @p speed_cap (m/s) is what the safety
  /// filter let through of the last command when it limited it (+inf when it did not): the speed
  /// rises from there by the acceleration, so that the command and the filter's output stay close and
  /// the arc driven is the arc commanded. A refusal (below 0.01 m/s) with the path more than 0.15 rad
  /// off the heading turns the robot in place to face it first.
  const FollowCommand& step(const Pose& pose, const ExecWindow& window, double now,
                            double speed_cap = std::numeric_limits<double>::infinity());
  /// The parameters.
  const FollowerParams& params() const { return params_; }
  /// Index of the path point the robot last passed (the start of its current segment).
  std::size_t index() const { return index_; }
  /// Path length (m) from the robot's last projection on the path to its end (0 without a path).
  double remaining() const;

  /// The path being followed.
  const std::vector<Point>& path() const { return path_; }

private:
  struct Sweep
  {
    double free = 0.0;
    double obstacle = std::numeric_limits<double>::infinity();
    double unknown = std::numeric_limits<double>::infinity();
    /// The first unknown cell of the path the camera can see from here (between look_min_distance
    /// and look_distance from the robot) and not looked at yet: where to look.
    double look = std::numeric_limits<double>::infinity();
    Point look_at;
  };
  void project(const Pose& pose);
  Sweep sweep(const Pose& pose, const ExecWindow& window) const;
  Point pointAhead(double distance) const;
  bool lookAt(const Pose& pose, const Sweep& s, const ExecWindow& window, double now);
  void rotateTo(double error, FollowMode mode);
  void drive(const Pose& pose, const Sweep& s, double dt, double speed_cap);
  /// True when @p p lay in the camera's view (within view_angle, look_min_distance to look_distance)
  /// at one of the looks on this path: looking again would not show more.
  bool looked(const Point& p) const;
  /// True when the unknown cell @p p is worth turning to: within look_min_distance..look_distance,
  /// out of the view (beyond view_angle), not in view at an earlier look, and in sight.
  bool lookable(const Pose& pose, const Point& p, const ExecWindow& w) const;
  /// Records a look from @p pose and starts the turn back toward the path.
  void endLook(const Pose& pose);
  /// True when no occupied cell of @p w lies between the robot and @p p.
  bool inSight(const Pose& pose, const Point& p, const ExecWindow& w) const;

  FollowerParams params_;
  std::vector<Point> path_;
  std::vector<double> along_;  // path length from the start to each point
  std::size_t index_ = 0;      // the segment [index_, index_ + 1] the robot is on
  double offset_ = 0.0;        // the projection's travel within that segment
  double goal_yaw_ = 0.0;
  bool use_yaw_ = false;
  double tolerance_ = 0.10;  // arrival distance to the path's end for this path (m)
  double last_time_ = std::numeric_limits<double>::quiet_NaN();
  double speed_ = 0.0;  // last commanded linear speed
  bool facing_ = false;
  bool returning_ = false;  // turning back in place toward the path after a look
  bool looking_ = false;    // a look at look_target_ is under way (kept until it ends)
  Point look_target_;
  double facing_since_ = 0.0;
  std::vector<Pose> looks_;  // where the robot stood and faced when it looked, on this path
  FollowCommand out_;
};

/// Wraps an angle to (-pi, pi].
double wrapAngle(double a);

/// Turn rate in place toward a heading @p error (rad) away: 2 * error, at most @p max_rate, at
/// least 0.2 rad/s (so that the last bit of a turn still moves the robot).
double turnRate(double error, double max_rate);
}  // namespace sl_navigation
