/// @file planner.h
/// @brief Global path planning on the navigation map: obstacles inflated by the robot's disc, A* on
/// an 8-connected grid with a clearance cost; unknown cells are planned through at a premium
/// (ROS-free).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sl_navigation/nav_grid.h"

namespace sl_navigation
{
/// A point in odom (m).
struct Point
{
  double x = 0.0;
  double y = 0.0;
};

/// Parameters of the planner. validate() names the ROS parameter of a bad value.
struct PlannerParams
{
  double robot_radius = 0.1675;   ///< m, the robot's disc (robot_radius)
  double lethal_margin = 0.06;    ///< m: a centre nearer than robot_radius + this to an obstacle is lethal
                                  ///< (the follower's lateral margin plus half a cell's diagonal)
  double inflation_radius = 0.6;  ///< m from an obstacle where the clearance cost ends
  double obstacle_cost = 3.0;     ///< extra cost factor at the lethal edge, falling linearly to 0 at inflation_radius
  double unknown_cost = 1.0;      ///< extra cost factor of an unknown cell (0: unknown planned as free)
  double escape_radius = 0.3;     ///< m around the start where lethal (not occupied) cells may be crossed to get out
  double heuristic_weight = 1.0;  ///< weight of the A* heuristic: paths cost at most this times the cheapest

  /// @throws std::invalid_argument naming the parameter.
  void validate() const;
  /// Distance (m) from an obstacle inside which a robot centre is lethal.
  double lethalDistance() const { return robot_radius + lethal_margin; }
};

/// Outcome of a planning request.
enum class PlanStatus : std::uint8_t
{
  OK,             ///< a path was found
  START_OUTSIDE,  ///< the start lies outside the map
  GOAL_OUTSIDE,   ///< the goal lies outside the map
  GOAL_BLOCKED,   ///< the goal is occupied, nearer than lethalDistance() to an obstacle, or unseen space
                  ///< that obstacles enclose in all eight directions (inside an object)
  NO_PATH         ///< every cell reachable from the start was searched: the goal is enclosed
};

/// Short upper-case name of a status, e.g. "NO_PATH".
const char* toString(PlanStatus status);

/// A disc in odom (m) that the planner treats as occupied.
struct Disc
{
  double x = 0.0;
  double y = 0.0;
  double radius = 0.0;
};

/// A planned path.
struct Plan
{
  PlanStatus status = PlanStatus::NO_PATH;
  std::vector<Point> points;  ///< start to goal, one point per cell (start and goal exact)
  double length = 0.0;        ///< m
  double cost = 0.0;          ///< m weighted by the cells' cost factors (what the search minimised)
  int unknown_cells = 0;      ///< cells of the path that are unknown
  int expansions = 0;         ///< cells the search expanded
  double goal_shift = 0.0;    ///< m from the requested goal to the path's end (see Planner::plan())
  std::string text;           ///< a sentence with the numbers
};

/**
 * @brief A* on the NavGrid with inflated obstacles.
 *
 * update() takes the grid's state at a time: a brushfire from every occupied cell gives each cell
 * the distance to its nearest obstacle (exact to the obstacle cell's centre, within
 * inflation_radius). A cell is lethal within lethalDistance(); moving through a cell costs its
 * length times 1 + obstacle_cost * (inflation_radius - d) / (inflation_radius - lethalDistance())
 * (near obstacles) + unknown_cost (unknown). The heuristic is the octile distance, admissible since
 * every factor is >= 1 (heuristic_weight > 1 trades that bound for speed). The search is bounded by
 * the map: an enclosed goal is refused after at most one pass over the cells reachable from the start. All memory is allocated at construction.
 */
class Planner
{
public:
  /// @throws std::invalid_argument for bad parameters.
  Planner(const PlannerParams& params, int width);

  /// Takes the state of @p grid at @p now (obstacles, unknown cells, distances); the cells of the
  /// blocked discs (setBlocked()) count as occupied.
  void update(const NavGrid& grid, double now);
  /// Discs taken as occupied from the next update() on (places where the robot was refused that
  /// the map shows passable); replaces the previous set.
  void setBlocked(const std::vector<Disc>& discs) { blocked_ = discs; }
  /// Plans from (sx, sy) to (gx, gy) on the last update()'s state of @p grid. A goal nearer than
  /// lethalDistance() to an obstacle is moved to the nearest cell centre within @p tolerance (m) that
  /// is known free and not lethal (as navfn's tolerance): a goal beside furniture, or a lone cell seen
  /// occupied next to it, is approached as far as it is safe instead of refused; Plan::goal_shift says
  /// how far it moved. Unknown cells are no candidates: a goal inside furniture would move into the
  /// furniture's unseen inside. With no such cell, or @p tolerance 0, the goal is refused (GOAL_BLOCKED).
  Plan plan(const NavGrid& grid, double sx, double sy, double gx, double gy, double tolerance = 0.0);

  /// Cost (as Plan::cost) of the polyline @p points from index @p first on, on the last update();
  /// +inf where it crosses an occupied or lethal cell (lethal ones within escape_radius of
  /// points[first] excepted) or leaves the map.
  double pathCost(const NavGrid& grid, const std::vector<Point>& points, std::size_t first) const;
  /// Distance (m) from cell (ix, iy) to its nearest obstacle, capped at inflation_radius.
  double clearance(int ix, int iy) const;
  /// True when a robot centred in cell (ix, iy) would touch an obstacle.
  bool lethal(int ix, int iy) const;
  /// True when cell (ix, iy) is unknown in the last update().
  bool unknown(int ix, int iy) const;
  /// The parameters.
  const PlannerParams& params() const { return params_; }

private:
  std::size_t index(int ix, int iy) const { return static_cast<std::size_t>(iy) * n_ + ix; }
  void brushfire(const NavGrid& grid);
  float stepFactor(std::size_t i) const { return factor_[i]; }
  /// True when unknown cell (gix, giy) meets an obstacle before any free cell in all eight directions.
  bool insideObject(int gix, int giy) const;
  /// The known-free, not lethal cell nearest (gx, gy) within @p radius (m, centre distance), ties to
  /// the larger clearance; false when there is none.
  bool nearestClear(const NavGrid& grid, double gx, double gy, double radius, int& ix, int& iy) const;
  void extract(const NavGrid& grid, std::size_t start, std::size_t goal, Plan& out) const;

  /// Marks the cells of the blocked discs occupied in cells_.
  void applyBlocked(const NavGrid& grid);

  PlannerParams params_;
  std::vector<Disc> blocked_;
  int n_ = 0;
  double resolution_ = 0.05;
  std::vector<float> dist_;         // m to the nearest obstacle (capped)
  std::vector<std::uint32_t> near_;  // index of that obstacle cell
  std::vector<float> factor_;       // cost factor per cell (<= 0: lethal)
  std::vector<std::uint8_t> unknown_;
  std::vector<Cell> cells_;   // the grid's states at the last update()
  std::vector<float> root_;   // resolution * sqrt(k), k = dx^2 + dy^2 in cells
  std::vector<std::uint32_t> queue_;
  // A* state, reused: g cost, parent, and a generation stamp instead of clearing.
  std::vector<float> g_;
  std::vector<std::uint32_t> parent_;
  std::vector<std::uint32_t> gen_;
  std::vector<std::uint32_t> closed_;  // generation in which the cell was expanded
  std::uint32_t generation_ = 0;
  struct Open
  {
    float f;  // g + weighted heuristic
    float g;  // cost to the cell when the entry was made
    std::uint32_t i;
  };
  std::vector<std::vector<Open>> buckets_;  // the open list, by f
};
}  // namespace sl_navigation
