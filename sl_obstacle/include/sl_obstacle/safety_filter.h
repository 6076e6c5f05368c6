/// @file safety_filter.h
/// @brief Limits a velocity command (teleoperation or any planner) to what stops before obstacles
/// and unknown space on its arc: v <= sqrt(2 a d), creeping through the ring the camera cannot see,
/// reversing only along the trail (doc/world_model.md, section 4). ROS-free.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "sl_obstacle/local_map.h"
#include "sl_obstacle/path_checker.h"
#include "sl_obstacle/world_model.h"

namespace sl_obstacle
{
/// A planar point (m).
struct Point2
{
  double x = 0.0;
  double y = 0.0;
};

/// @p points given in the frame whose pose in the parent frame is @p frame, into the parent frame
/// (written to @p out, which keeps its capacity).
void toParent(const std::vector<Point2>& points, const Pose2D& frame, std::vector<Point2>& out);

/// @p points given in the parent frame, into the frame whose pose there is @p frame (the inverse of
/// toParent(); written to @p out, which keeps its capacity).
void toChild(const std::vector<Point2>& points, const Pose2D& frame, std::vector<Point2>& out);

/// A velocity command: forward speed (m/s, negative backwards) and turn rate (rad/s, positive left).
struct Velocity
{
  double linear = 0.0;
  double angular = 0.0;
};

/// Parameters of the safety filter. validate() names the ROS parameter of a bad value.
struct FilterParams
{
  FootprintParams footprint;   ///< the robot's disc and the lateral margin of its swept path
  double clearance = 0.15;     ///< m kept between the disc and unknown space (safety_margin)
  /// m kept between the disc and occupied cells or cloud points (obstacle_margin): what the map
  /// knows is approached by its cells and the odometry, so it may be nearer than unknown space
  double obstacle_clearance = 0.15;
  /// m kept to occupied cells or cloud points while the forward speed is at most edge_speed
  /// (edge_margin): a slow approach to what the map knows, for cleaning along walls (used only
  /// when below obstacle_clearance)
  double edge_clearance = 0.05;
  double edge_speed = 0.0;  ///< m/s, in [0, 0.1]: the fastest approach to edge_clearance; 0: none (edge_speed)
  double deceleration = 0.25;  ///< a in v <= sqrt(2 a d) (m/s^2); 0: stop only at d = 0
  double horizon = 1.5;        ///< m, the longest arc checked (check_distance)
  double input_timeout = 0.5;  ///< s without a command before the robot stops
  double stale_timeout = 0.5;  ///< s without a fresh cloud before forward motion stops
  /// m/s, in [0, 0.05]: the forward speed allowed over cells never seen to hold anything, while the
  /// camera sees straight ahead at the clearance (0: never)
  double creep_speed = 0.05;
  /// m ahead of the front edge where the centre line must be known for the creep
  /// (creep_view_distance): where the camera sees the floor, not in its blind ring
  double creep_view = 0.15;

  /// @throws std::invalid_argument when invalid, its message starting with the offending parameter's name.
  void validate() const;
};

/// Why the filter gave its output.
enum class FilterReason : std::uint8_t
{
  PASSED,            ///< the command is safe as it is (or it only turns in place)
  LIMITED,           ///< forward or reverse speed scaled down to stop within the known-free arc
  CREEPING,          ///< forward speed held to creep_speed: the arc crosses cells never seen
  STOPPED_OBSTACLE,  ///< no travel left on the arc (obstacle or unknown space within clearance)
  INPUT_TIMEOUT,     ///< no command within input_timeout (or none yet)
  STALE_DATA,        ///< no fresh cloud: forward motion stopped (turning and reverse still pass)
  NO_ODOMETRY,       ///< the robot's pose is unknown: stopped
  INVALID_COMMAND    ///< a NaN or inf component: stopped
};

/// Short upper-case name of a reason, e.g. "LIMITED".
const char* toString(FilterReason reason);

/// Travel along an arc until the swept disc meets cells that are not free (see sweepArc()).
struct ArcResult
{
  double free = 0.0;  ///< m: first cell that is not free (or the length checked)
  double obstacle = std::numeric_limits<double>::infinity();   ///< m: first occupied cell
  double unknown = std::numeric_limits<double>::infinity();    ///< m: first unknown cell
  double evidence = std::numeric_limits<double>::infinity();   ///< m: first unknown cell holding evidence
  double off_trail = std::numeric_limits<double>::infinity();  ///< m: first cell off the robot's trail
};

/**
 * @brief Sweeps a disc of @p radius along the arc driven with constant (v, w) from @p pose.
 *
 * The arc turns by @p curvature rad per metre of travel (w / |v|, positive left), moving forward
 * (@p direction +1) or backwards (-1). Cells under the disc at the start are not counted (the robot
 * is there, so it may always leave). A straight arc (|curvature| * length < 1e-4) is swept exactly by
 * sweepStraight(); a curved one is sampled every quarter cell, a cell counting from the sample
 * before the one whose disc first holds its centre (early, never late).
 * @throws std::invalid_argument for direction other than +-1 or non-finite input
 */
ArcResult sweepArc(const LocalMap& map, double radius, const Pose2D& pose, int direction, double curvature,
                   double length, double now);

/**
 * @brief Travel along the same arc until a disc of @p radius first touches one of @p points
 * (given in the robot's frame: x forward, y left, origin at the disc's centre); exact, by the
 * geometry of two circles. A point already under the disc counts as contact at 0 if it lies ahead
 * of the motion, and is ignored if the motion leaves it. +inf if none within @p length.
 */
double arcContact(const std::vector<Point2>& points, double radius, int direction, double curvature, double length);

/// What the filter knows at one step.
struct FilterInput
{
  double now = 0.0;                                                ///< s
  Velocity command;                                                ///< the requested command
  double command_time = -std::numeric_limits<double>::infinity();  ///< s, when it was given
  bool localized = false;                                          ///< pose is the robot's current pose
  Pose2D pose;                                                     ///< base_link in the map's frame, now
  double cloud_time = -std::numeric_limits<double>::infinity();    ///< s, capture time of the newest cloud
  /// The newest cloud's obstacle points in the robot's frame now (exact distances; may be empty).
  const std::vector<Point2>* obstacles = nullptr;
};

/// The filter's answer.
struct FilterOutput
{
  Velocity command;  ///< what to send to the driver
  FilterReason reason = FilterReason::INPUT_TIMEOUT;
  double scale = 0.0;        ///< |output linear| / |requested linear| (1 when nothing moves forward)
  double travel = 0.0;       ///< m: travel on the output's arc less the clearance (creeping: open travel;
                             ///< reverse: trail travel less the lateral margin)
  double speed_limit = 0.0;  ///< m/s: sqrt(2 a travel) (inf with a = 0 and travel > 0)
  double curvature = 0.0;    ///< rad/m of the output's arc (0 for a straight line or no motion)
  std::string text;          ///< a sentence with the numbers
};

/**
 * @brief The safety filter: for each command, the swept footprint along its arc is checked on the
 * local map (and against the newest cloud's obstacle points, whose distances are exact) and the
 * speed is limited (doc/world_model.md, section 4):
 *
 *   forward: |v| <= max(sqrt(2 a d_known), C min(creep_speed, sqrt(2 a d_open)), min(edge_speed, sqrt(2 a d_edge)))
 *   reverse: |v| <= sqrt(2 a d_trail)
 *
 * d_known: the travel to the first unknown cell less the clearance, or to the first occupied cell or
 * contact with a cloud point less the obstacle clearance, whichever is shorter (unknown cells within a
 * cell of an obstacle ahead, its shadow, are reached only through it and count as the obstacle); d_open: the same, except that unknown cells without evidence (never seen to hold
 * anything: the ring the camera cannot see) pass; d_edge: d_known with edge_clearance in place of the
 * obstacle clearance (a slow approach nearer to what the map knows); C = 1 when the map knows the centre line straight
 * ahead from creep_view to two cells beyond it (centreLineSeen(): free or occupied, the camera
 * sees where an obstacle would stop the robot), else 0; d_trail: travel until the disc (radius, no margin) covers a
 * cell off its trail or the swept disc a cell that is not free, less the lateral margin.
 *
 * Turning in place sweeps nothing new and always passes (unless stopped for timeout, bad input or
 * missing odometry). A limited command keeps its turn rate: the speed is lowered until the tighter
 * arc it then drives is safe too, down to turning in place, so turning away from an obstacle stays
 * possible.
 */
class SafetyFilter
{
public:
  /// @throws std::invalid_argument for invalid parameters.
  explicit SafetyFilter(const FilterParams& params = FilterParams());

  /// The parameters in use.
  const FilterParams& params() const { return params_; }

  /// Filters one command on @p map (in the frame of FilterInput::pose).
  FilterOutput filter(const LocalMap& map, const FilterInput& in) const;

  /// Travel on the arc of (v, w) from the input's pose, checked up to @p length (m; may be
  /// negative): forward d_known, reverse d_trail (see the class comment).
  double travel(const LocalMap& map, const FilterInput& in, double v, double w, double length) const;

  /// Forward travel through cells never seen to hold anything, d_open (see the class comment), of
  /// the arc of (v > 0, w), checked up to @p length (m; may be negative).
  double openTravel(const LocalMap& map, const FilterInput& in, double v, double w, double length) const;

private:
  /// d_known (or d_trail) and d_open of one arc.
  struct Travels
  {
    double known = 0.0;
    double open = 0.0;
    double edge = 0.0;  // known, with edge_clearance to obstacles
  };
  Travels travels(const LocalMap& map, const FilterInput& in, double v, double w, double length) const;
  /// The largest speed <= |v| (same sign) that stops within the travel of its own arc with w; sets
  /// @p creeping when only the creep rule allows it, @p edging when only the edge rule does.
  double limitSpeed(const LocalMap& map, const FilterInput& in, double v, double w, FilterOutput& out,
                    bool& creeping, bool& edging) const;

  FilterParams params_;
};
}  // namespace sl_obstacle
