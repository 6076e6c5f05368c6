/// @file world_model.h
/// @brief The obstacle node's memory: a rolling LocalMap fed with the decoder's rays, the robot's
/// trail, bumps, and what the map says about the paths open to the robot at its current pose
/// (ROS-free).
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "sl_obstacle/decision_maker.h"
#include "sl_obstacle/local_map.h"
#include "sl_obstacle/path_checker.h"
#include "sl_obstacle/point.h"

namespace sl_obstacle
{
/// @brief A planar pose: base_link in the map (odom) frame.
struct Pose2D
{
  double x = 0.0;    ///< m
  double y = 0.0;    ///< m
  double yaw = 0.0;  ///< rad, counter-clockwise from +x
};

/// @brief Parameters of the world model.
struct WorldParams
{
  bool enabled = true;        ///< false: decisions use the latest cloud only (the old behaviour)
  MapParams map;              ///< the grid
  FootprintParams footprint;  ///< the robot's disc
  /// m around base_link at the first pose taken as free for forward paths (never the trail: no
  /// back-off or reverse crosses it). 0: nothing is assumed (the README says why).
  double start_free_radius = 0.0;
  double check_distance = 1.5;  ///< m, the farthest travel checked along a path
  double heading_step = 0.5;    ///< rad between the candidate headings
  int headings = 6;             ///< candidate headings on each side of the current one
  double bump_depth = 0.06;     ///< m in front of the bumper marked occupied after a bump
  /// m around base_link that no camera on the robot sees, whichever way it turns (the camera's
  /// offset ahead of base_link plus its nearest range): never-seen cells within it may be crept
  /// through (MapSummary::open); farther ones the robot has to look at first.
  double blind_radius = 0.45;
  /// m beyond the front edge where the centre line must be known for a creep (MapSummary::
  /// view_seen): the decisions' safety_margin
  double clearance = 0.15;

  /// @throws std::invalid_argument when invalid, its message starting with the offending parameter's name.
  void validate() const;
};

/// @brief What the map says at the robot's current pose. Distances are travel of base_link, m.
struct MapSummary
{
  double free = 0.0;  ///< straight ahead: known-free travel (see PathResult::free)
  double open = 0.0;  ///< straight ahead: PathResult::open() of the swept path with blind_radius: unknown
                      ///< cells never seen to hold anything pass within blind_radius of base_link
  double obstacle = std::numeric_limits<double>::infinity();  ///< straight ahead: travel until the robot's disc
                                                              ///< (without the lateral margin) reaches an occupied cell
  double unknown = std::numeric_limits<double>::infinity();   ///< straight ahead: travel to an unknown cell
  double creep_end = std::numeric_limits<double>::infinity();  ///< straight ahead: travel to the first unknown
                                                               ///< cell a creep may not enter (evidence, or never
                                                               ///< seen beyond blind_radius)
  double known_fraction = 0.0;     ///< straight ahead: share of the swept cells that are known
  double reverse_free = 0.0;       ///< straight back: travel along the trail (see WorldModel)
  double best_turn = 0.0;          ///< rad: relative heading with the longest open travel (see open)
  double best_turn_free = 0.0;     ///< its open travel
  double left_free = 0.0;          ///< longest open travel among the headings to the left
  double right_free = 0.0;         ///< ... and to the right
  double best_reverse_turn = 0.0;  ///< rad: relative heading whose reverse path is free the farthest
  double best_reverse_free = 0.0;  ///< its reverse travel along the trail
  bool view_seen = false;          ///< centreLineSeen() from clearance to two cells beyond it
};

/**
 * @brief Keeps the local map and answers path questions on it.
 *
 * Every cloud is inserted with the robot's pose at the cloud's stamp; every decision is taken at the
 * pose of now. The cells wholly under the robot's body are free wherever it has been, and the cells its
 * disc covered are its trail (LocalMap::markTrail(), trailRadius() around the path between poses).
 * Travel backwards is travel along the trail: until the disc (radius, no margin) covers a cell off
 * the trail or the swept disc a cell that is not free, less the lateral margin. A disc of
 * start_free_radius around the first pose is taken as free for forward paths only (default 0).
 * Turning in place sweeps no new space, so it is always allowed.
 */
class WorldModel
{
public:
  /// @throws std::invalid_argument for invalid parameters.
  explicit WorldModel(const WorldParams& params = WorldParams());

  /// @brief Forgets everything (the next pose is a new start).
  void reset();
  /// @brief The parameters.
  const WorldParams& params() const { return params_; }
  /// @brief Sets WorldParams::clearance (the map is kept). @throws std::invalid_argument outside [0, 5].
  void setClearance(double clearance);

  /// @brief The robot is at @p robot at time @p now: recentres the window, marks the cells under
  /// its body free (bodyFreeRadius()) and the path from the previous pose as trail (trailRadius()).
  void updatePose(const Pose2D& robot, double now);
  /// @brief Inserts the rays of one cloud (odom frame), taken at @p stamp.
  void addRays(const std::vector<MapRay>& rays, double stamp);
  /// @brief A bumper fired at @p robot: marks the space in front of the pressed side occupied.
  void markBump(const Pose2D& robot, bool left, bool right, double now);
  /**
   * @brief The paths open to the robot at @p robot, at time @p now.
   *
   * The candidate headings (best_turn, best_turn_free, left_free, right_free, best_reverse_turn,
   * best_reverse_free) take most of the sweeps. With @p turns false they are those of the last
   * summary that swept them, if it is at most kTurnsMaxAge old, was swept within 2 cm and 0.05 rad
   * of @p robot and no bump came since (a heading as long free as straight ahead is never worse
   * than straight ahead); the paths straight ahead and back are always swept.
   * The caller sweeps them on each map update; the decisions in between reuse them.
   */
  const MapSummary& summarize(const Pose2D& robot, double now, bool turns = true);

  /// @brief Age (s) up to which summarize() reuses the candidate headings.
  static constexpr double kTurnsMaxAge = 0.2;

  /// @brief The last summarize() result.
  const MapSummary& last() const { return summary_; }
  /// @brief The map (for publishing).
  const LocalMap& map() const { return map_; }
  /// @brief True once a pose was given.
  bool started() const { return started_; }
  /// @brief Radius (m) within which updatePose() marks cell centres free: the robot's radius less
  /// half a cell's diagonal, so that only cells wholly under the body are marked (never one that
  /// reaches past it, where a thin obstacle beside the robot may stand).
  double bodyFreeRadius() const;
  /// @brief Radius (m) within which updatePose() puts cell centres on the trail, around the path
  /// from the previous pose: the robot's radius plus half a cell, so that every cell the disc
  /// reached into is on it (the reverse check looks at the centres within the radius).
  double trailRadius() const;
  /// @brief Longest step (m) between two poses that is taken as driven (marked as trail between
  /// them); a longer one (odometry reset) marks only the new pose's disc.
  static constexpr double kMaxTrailStep = 0.15;

private:
  WorldParams params_;
  LocalMap map_;
  /// Sweeps the candidate headings of summary_ (its straight-ahead paths are set).
  void sweepTurns(const Pose2D& robot, double now);
  /// Travel backwards from @p robot turned to @p yaw along the trail (see the class comment), >= 0.
  double reverseTravel(const Pose2D& robot, double yaw, double now) const;

  MapSummary summary_;
  double turns_time_ = -std::numeric_limits<double>::infinity();  // when sweepTurns() last ran
  Pose2D turns_pose_;                                             // ... and from where
  Pose2D last_pose_;                                              // the previous updatePose()
  bool started_ = false;
};
/**
 * @brief The decisions' view when a map is used: the latest cloud's summary @p cloud (its nearest
 * obstacle still stops the robot at once) with the map's known-free travel, turn choices and
 * reverse path at the current pose. Where the map stops at an occupied cell within @p tolerance of
 * the cloud's nearest obstacle, both see the same thing and the cloud's exact distance is used
 * (the map's is quantised by its cells).
 */
FrameSummary withMap(FrameSummary cloud, const MapSummary& map, double tolerance);

/**
 * @brief Travel of a disc robot of @p radius straight ahead (+x) until it touches the nearest of
 * @p points[@p indices] (platform_edge: x from the front edge, y left): x + radius - sqrt(radius^2
 * - y^2). The clearance is kept on this travel, in the cloud as in the map. +inf when there is none.
 */
double contactTravel(const std::vector<Point>& points, const std::vector<std::uint32_t>& indices, double radius);
}  // namespace sl_obstacle
