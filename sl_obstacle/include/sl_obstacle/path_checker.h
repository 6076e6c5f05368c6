/// @file path_checker.h
/// @brief Swept-footprint checks of a disc robot on the LocalMap (doc/world_model.md, section 3).
#pragma once

#include <algorithm>
#include <limits>

#include "sl_obstacle/local_map.h"

namespace sl_obstacle
{
/// The robot's footprint: a disc around base_link.
struct FootprintParams
{
  /// Radius of the robot's disc (m); the iRobot Create's is 0.1675 m.
  double radius = 0.1675;
  /// Extra clearance on each side of the swept path (m).
  double lateral_margin = 0.02;

  /// Checks the values. @throws std::invalid_argument with a message that starts with the name of
  /// the offending field ("radius must be in (0, 2] (got 0)").
  void validate() const;

  /// Radius of the disc that is swept: radius + lateral_margin (m).
  double sweptRadius() const { return radius + lateral_margin; }
};

/// What a straight move would sweep.
///
/// A cell is swept when its centre comes within sweptRadius() of the moving disc centre. Its entry
/// distance is the travel at which that first happens. Cells the disc covers at s = 0 (the robot's
/// current disc, radius + lateral_margin) count as free: the robot is there, and turning in place
/// sweeps nothing new.
struct PathResult
{
  /// Largest s (m, <= max_distance) such that every cell swept over [0, s] is Free; i.e. the entry
  /// distance of the first cell that is not free, or max_distance when there is none.
  double free = 0.0;
  /// Entry distance of the first Occupied cell (m); +inf if none within max_distance.
  double obstacle = std::numeric_limits<double>::infinity();
  /// Entry distance of the first Unknown cell (m); +inf if none within max_distance.
  double unknown = std::numeric_limits<double>::infinity();
  /// Entry distance of the first Unknown cell that holds evidence (CellInfo::evidence: a suspect, or
  /// an obstacle decayed below occupied) (m); +inf if none. Unknown cells before it were never seen
  /// to hold anything.
  double evidence = std::numeric_limits<double>::infinity();
  /// Entry distance of the first cell not on the robot's trail (CellInfo::trail) (m); +inf if none.
  double off_trail = std::numeric_limits<double>::infinity();
  /// Entry distance of the first unknown cell without evidence whose centre lies farther than the
  /// sweep's blind_radius from its start (m); +inf if none (always, with blind_radius +inf).
  double unseen_far = std::numeric_limits<double>::infinity();
  /// Share of the cells swept over (0, max_distance] that are known (free or occupied); 1 when no
  /// cell is swept (max_distance 0).
  double known_fraction = 1.0;
  /// Number of cells swept over (0, max_distance].
  int swept_cells = 0;

  /// Travel until the first cell that is occupied, holds evidence or was never seen beyond
  /// blind_radius (m): the cells before it are free or never seen within blind_radius.
  double open() const { return std::min({ obstacle, evidence, unseen_far }); }
};

/// Sweeps the footprint along a straight line and reports free, obstacle and unknown distances.
///
/// Every candidate cell is visited once (row by row over the swept stadium), so the cost is the
/// stadium's area in cells. max_distance 0 (rotation in place) sweeps nothing: free = 0, obstacle
/// and unknown +inf, known_fraction 1: turning in place is always allowed.
/// @param x, y       base_link (disc centre) in odom (m)
/// @param yaw        heading in odom (rad)
/// @param direction  +1 forward along yaw, -1 in reverse
/// @param max_distance how far to look (m, >= 0)
/// @param now        time of the map's clock (s), for the decay
/// @param blind_radius never-seen cells farther than this from (x, y) count in PathResult::unseen_far
/// @throws std::invalid_argument for direction other than +-1, a non-finite pose or a negative or
///         non-finite max_distance
PathResult sweepStraight(const LocalMap& map, const FootprintParams& fp, double x, double y, double yaw, int direction,
                         double max_distance, double now,
                         double blind_radius = std::numeric_limits<double>::infinity());

/// True when the cells under the centre line straight ahead, from @p from to @p to beyond the front
/// edge (@p radius ahead of (x, y) along @p yaw), sampled every quarter cell, are Free up to the end
/// or up to an Occupied one (its shadow behind it is not asked for): the camera sees there, the
/// floor or an obstacle (the creep rule's view check, doc/world_model.md, section 3). An object
/// near the robot that the camera cannot see shadows it.
bool centreLineSeen(const LocalMap& map, double x, double y, double yaw, double radius, double from, double to,
                    double now);

/// Result of bestHeading().
struct HeadingChoice
{
  double turn = 0.0;  ///< relative angle to turn (rad, positive to the left), k * step
  PathResult path;    ///< the forward sweep along yaw + turn
};

/// The best forward heading among yaw + k * step, k = -n..n, by PathResult::free.
///
/// Headings whose free distance is within one map cell of the best count as equally good; among
/// them the smallest |turn| wins, and of +k and -k the left (+k) one.
/// @throws std::invalid_argument for n < 0, a non-finite step, or what sweepStraight() rejects
HeadingChoice bestHeading(const LocalMap& map, const FootprintParams& fp, double x, double y, double yaw, double step,
                          int n, double max_distance, double now);
}  // namespace sl_obstacle
