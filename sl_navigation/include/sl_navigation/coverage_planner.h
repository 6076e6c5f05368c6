/// @file coverage_planner.h
/// @brief Cleaning coverage on the navigation map: the reachable floor, the next targets that sweep
/// it (lanes, edge passes along known walls, spots) or explore it (frontiers), and a runner that
/// feeds them to a Navigator (ROS-free).
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "sl_navigation/coverage_grid.h"
#include "sl_navigation/navigator.h"

namespace sl_navigation
{
/// Parameters of the coverage planner. validate() names the ROS parameter of a bad value.
struct CoverageParams
{
  PlannerParams planner;          ///< the navigator's (robot_radius, lethal_margin): targets keep its lethal clearance
  double lane_spacing = 0.25;     ///< m between lanes (whole cells), below the robot's diameter (lane_spacing)
  bool lanes_along_x = true;      ///< lanes run along odom x (else along y) (lanes_along_x)
  double edge_clearance = 0.05;   ///< m, disc to known occupied cells on an edge pass (edge_clearance)
  double edge_speed = 0.1;        ///< m/s, the most an edge pass drives (edge_speed)
  double edge_length = 3.0;       ///< m of wall contour per edge pass
  bool edges_first = false;       ///< offer edge passes before lanes (edges_first)
  double waypoint_spacing = 0.5;  ///< m between the goals of a lane; an edge pass's are 0.3 times this
  int min_gain = 6;               ///< uncovered floor cells a target must sweep to be offered
  double view_min = 0.5;          ///< m, nearest a frontier is looked at from (the camera's blind ring)
  double view_max = 1.1;          ///< m, farthest a frontier is looked at from
  /// Exploring instead of cleaning (behaviour roam): ROAM targets (long legs to floor not yet
  /// driven over, ahead of the robot rather than behind, over known floor rather than unknown) and
  /// frontiers, no lanes or edge passes, and never DONE: once the floor known was driven over, the
  /// coverage starts anew
  bool roam = false;
  double roam_leg = 1.5;  ///< m of path to a ROAM target: legs up to twice it are preferred (roam_leg)

  /// @throws std::invalid_argument naming the parameter.
  void validate() const;
  /// Distance (m) a target centre keeps from the centres of occupied cells of @p resolution:
  /// max(lethalDistance(), robot_radius + edge_clearance + resolution / 2), i.e. the disc keeps at
  /// least edge_clearance from the near side of every occupied cell and the navigator's lethal distance.
  double centreClearance(double resolution) const;
};

/// Kind of a coverage target.
enum class CoverageMode : std::uint8_t
{
  LANE,      ///< a straight lane of the boustrophedon pattern through uncovered floor
  EDGE,      ///< a pass along the contour of known obstacles at centreClearance(), at edge_speed
  SPOT,      ///< one goal over an uncovered patch no lane or edge pass reaches
  FRONTIER,  ///< look at known free floor next to unknown space (goal with a heading)
  DONE,      ///< no uncovered reachable floor and no frontier left
  ROAM       ///< exploring: one goal far ahead on floor not yet driven over
};

/// Short upper-case name of a mode.
const char* toString(CoverageMode mode);

/// The next targets for the navigator, to be driven in order.
struct CoverageTarget
{
  CoverageMode mode = CoverageMode::DONE;
  std::vector<NavGoal> goals;                                    ///< in odom; empty for DONE
  double speed_limit = std::numeric_limits<double>::infinity();  ///< m/s (edge_speed for EDGE)
  int gain = 0;                                                  ///< uncovered floor cells the target sweeps (estimate)
  std::string text;                                              ///< a sentence with the numbers
};

/**
 * @brief Chooses where to clean next on a NavGrid, given what a CoverageGrid holds.
 *
 * update() finds the reachable floor: the centre cells are the known free cells at least
 * centreClearance() from every occupied and every unknown cell (distances between cell centres:
 * a disc there sweeps only what the map knows is free) that connect to the
 * robot (8-connected flood fill from the robot's cell, or the nearest such cell within 0.4 m, through
 * known free and unknown cells that keep centreClearance(): the navigator plans through unknown space); the
 * floor (the denominator of the progress) is the known free cells within robot_radius of a centre
 * cell: what the disc can sweep while its centre stays on centre cells. Unknown cells are never
 * floor; free pockets the disc cannot reach (behind a gap narrower than 2 centreClearance()) are not
 * counted. The gain of a centre cell is the number of uncovered floor cells under a disc there, less
 * its outer 0.05 m (a rim a driven disc may miss by its tracking error: lanes are not driven again
 * for a sliver), except on the ring of centre cells next to obstacles, whose edge passes are there
 * for that rim.
 *
 * next() offers, nearest first by the flood fill's distance: lanes (runs of centre cells on rows
 * lane_spacing apart, trimmed to where they gain, split where they gain nothing for 0.4 m), edge
 * passes (the outermost ring of centre cells, traced from the nearest gaining cell for up to
 * edge_length), spots (the nearest cell gaining min_gain); only when none is left, a frontier
 * (known free cell beside unknown space) seen from a centre cell view_min..view_max from it, facing
 * it; when a frontier lies within view_max but has no viewpoint (at the start, when the camera has
 * seen too little), a turn in place in three steps, once per metre; DONE when none of these is left. Each frontier is
 * looked at once; targets that fail (failed()) or are offered three times are not offered again.
 */
class CoveragePlanner
{
public:
  /// @throws std::invalid_argument for bad parameters.
  CoveragePlanner(const CoverageParams& params, int width);

  /// Computes the reachable floor and the gains from @p grid at @p now, @p coverage and @p pose. A pose
  /// that is not finite or lies outside the map gives an empty floor.
  /// @throws std::invalid_argument when the grid or the coverage has another width than the planner.
  void update(const NavGrid& grid, const CoverageGrid& coverage, const Pose& pose, double now);
  /// update() and then the next target.
  CoverageTarget next(const NavGrid& grid, const CoverageGrid& coverage, const Pose& pose, double now);
  /// The goal @p goal could not be reached: centre cells within 0.2 m of it are not offered again.
  void failed(const NavGoal& goal);
  /// Forgets the targets offered and failed (exploring: a new round over the same room); the
  /// frontiers looked at stay so.
  void forgetOffers();

  /// The reachable floor of the last update() (FloorCell per cell, row-major from the lower left).
  const std::vector<FloorCell>& floor() const { return floor_; }
  /// Uncovered floor cells under a disc centred on cell (ix, iy), its outer 0.05 m excepted (0 off the centre cells).
  int gain(int ix, int iy) const;
  /// The parameters.
  const CoverageParams& params() const { return params_; }

private:
  std::size_t index(int ix, int iy) const { return static_cast<std::size_t>(iy) * n_ + ix; }
  bool inside(int ix, int iy) const { return ix >= 0 && iy >= 0 && ix < n_ && iy < n_; }
  /// True when an unknown cell lies nearer than the centre clearance to cell (ix, iy).
  bool nearUnknown(int ix, int iy) const;
  bool centre(int ix, int iy) const { return inside(ix, iy) && floor_[index(ix, iy)] == FloorCell::Centre; }
  /// The cell of (x, y) (may lie outside the map); false for NaN or beyond a million cells.
  bool cellOf(double x, double y, int& ix, int& iy) const;
  bool seed(const Pose& pose, int& sx, int& sy) const;
  void flood(int sx, int sy);
  void sweepFloor();
  void gains(const CoverageGrid& coverage);
  bool lane(const NavGrid& grid, CoverageTarget& out);
  bool edge(const NavGrid& grid, CoverageTarget& out);
  bool spot(const NavGrid& grid, CoverageTarget& out);
  bool frontier(const NavGrid& grid, CoverageTarget& out);
  /// Exploring: the centre cell not driven over that is far (up to 2 roam_leg of path) and ahead of
  /// @p pose, preferring long legs; false when none lies at least 0.4 m away.
  bool roam(const NavGrid& grid, const Pose& pose, CoverageTarget& out);
  /// True when a frontier cell not looked at lies within @p radius of the robot.
  bool frontierNear(const Pose& pose, double radius) const;
  /// A turn in place in three steps (a FRONTIER target), once per place: when no frontier has a viewpoint.
  bool lookAround(const Pose& pose, CoverageTarget& out);
  /// Sum of the unit steps from cell (ix, iy) to its unknown 4-neighbours (0, 0: not a frontier).
  void unknownNormal(int ix, int iy, int& nx, int& ny) const;
  /// Share of unknown cells on the straight way from (x0, y0) to (x1, y1), sampled on the centre
  /// line and both sides of the robot's disc (the grid's states at the last update()).
  double unknownShare(double x0, double y0, double x1, double y1) const;
  /// True when no occupied cell lies between cells (x0, y0) and (x1, y1).
  bool sight(int x0, int y0, int x1, int y1) const;
  std::vector<std::size_t> trace(std::size_t start) const;
  void emit(const NavGrid& grid, const std::vector<std::size_t>& cells, double spacing, CoverageTarget& out);
  void offered(std::size_t i);
  void markAround(std::vector<std::uint8_t>& mask, double x, double y, double radius);

  CoverageParams params_;
  Planner planner_;
  int n_ = 0;
  double resolution_ = 0.05;
  double origin_x_ = 0.0;
  double origin_y_ = 0.0;
  double centre_clearance_ = 0.0;
  std::vector<FloorCell> floor_;
  std::vector<std::int32_t> dist_;          // flood-fill steps from the robot (-1: not reached)
  std::vector<std::uint16_t> gain_;         // per centre cell
  std::vector<std::uint8_t> blocked_;       // 1: failed or offered too often, not offered again
  std::vector<std::uint8_t> offers_;        // targets starting or ending here so far
  std::vector<std::uint8_t> tried_;         // frontier cells looked at
  std::vector<std::uint8_t> ring_;          // outermost centre cells (edge passes), per update()
  std::vector<std::uint8_t> pass_;          // 2: known free centre, 1: unknown passable, 0: neither
  std::vector<std::uint32_t> queue_;        // the flood fill, in order of distance
  std::vector<std::uint32_t> centres_;      // the reached centre cells, in order of distance
  std::vector<std::pair<int, int>> disc_;   // cell offsets within robot_radius
  std::vector<std::pair<int, int>> inner_;  // cell offsets within robot_radius - 0.05 m (what a target counts)
  std::vector<std::pair<int, int>> near_;   // cell offsets nearer than the centre clearance
  std::vector<std::pair<int, int>> view_;   // cell offsets view_min..view_max away
  double offsets_resolution_ = 0.0;         // the resolution the offsets were made for
  std::vector<Cell> cells_;                 // the grid's states at the last update()
  std::vector<Point> looked_around_;        // where lookAround() was offered
  bool pending_frontier_ = false;
  NavGoal frontier_seen_;  // the frontier of the last FRONTIER target (marked tried at the next call)
};

/**
 * @brief Cleaning with a Navigator: asks the CoveragePlanner for targets, feeds their goals one by
 * one, and keeps the CoverageGrid from the poses.
 *
 * Edge passes are driven at edge_speed: the speed cap given to Navigator::step() is edge_speed
 * minus the rise the follower's acceleration allows in a step. A goal the navigator aborts is
 * reported to the planner (failed()) and the rest of its target dropped.
 *
 * Two guards for known obstacles, since pure pursuit's arcs cut inside the planned path: a forward
 * command whose arc over the next 0.5 s brings the robot's centre nearer than robot_radius + 0.045 m
 * (half a cell's diagonal and 1 cm) to the centre of an occupied cell of the map, and nearer than it
 * is now, is replaced by its turn alone; and a goal BLOCKED or so guarded for 2 s is cancelled (failed()), the robot
 * turns away from the nearest occupied cell within 0.6 m and creeps 0.15 m at 0.05 m/s (guarded), then
 * takes the next target.
 */
class CoverageRunner
{
public:
  /// @throws std::invalid_argument for bad parameters.
  CoverageRunner(const NavigatorParams& nav, const CoverageParams& coverage);

  /// A local occupancy window (see Navigator::onMap()).
  bool onMap(const OccupancyView& view, double stamp);
  /// One control step from @p pose at @p now; @p dt (s) is the control period; @p speed_cap (m/s):
  /// what the safety filter let through (see PathFollower::step()), combined with the edge speed.
  /// Before the first map, or for a non-finite pose, the navigator alone answers (it stops) and no
  /// target is taken.
  const NavOutput& step(const Pose& pose, double now, double dt,
                        double speed_cap = std::numeric_limits<double>::infinity());

  /// True once the planner reported DONE.
  bool done() const { return done_; }
  /// covered / reachable floor at the last planner update (0..1).
  double progress() const { return progress_; }
  /// The reachable floor at the last planner update, m^2.
  double floorArea() const { return floor_area_; }
  /// One line for a status: "coverage 42.3 % of 7.91 m2 reachable floor, LANE" (DONE once done); roaming:
  /// "roaming: 42.3 % of 7.91 m2 reachable floor driven over in round 1, ROAM".
  std::string summary() const;
  /// The mode of the target being driven.
  CoverageMode mode() const { return target_.mode; }
  /// The navigator.
  const Navigator& navigator() const { return nav_; }
  /// The coverage.
  const CoverageGrid& coverage() const { return coverage_; }
  /// The planner (its floor() is the progress' denominator).
  const CoveragePlanner& planner() const { return planner_; }
  /// Targets per mode so far (indexed by CoverageMode).
  const int* targets() const { return targets_; }
  /// Exploring: the rounds begun over the room (each forgets where the robot drove).
  int rounds() const { return rounds_; }

private:
  bool nextGoal(const Pose& pose, double now);
  /// The current goal failed: reported to the planner (failed()), and the rest of its target dropped.
  void dropTarget();
  /// Distance (m) from (x, y) to the nearest occupied cell centre of the map within @p reach (else reach).
  double obstacleDistance(double x, double y, double now, double reach) const;
  /// False when (v, w) for 0.5 s from @p pose brings the robot too near a known obstacle.
  bool safe(const Pose& pose, double v, double w, double now) const;
  /// Starts an escape (cancels the goal); false when no obstacle is near.
  bool startEscape(const Pose& pose, double now);
  /// One step of the escape into out_; false once it is over.
  bool escape(const Pose& pose, double now);
  /// Starts an escape when the goal has been BLOCKED (or @p guarded) for 2 s.
  void watchBlocked(const Pose& pose, double now, bool guarded);

  Navigator nav_;
  CoveragePlanner planner_;
  CoverageGrid coverage_;
  CoverageTarget target_;
  std::size_t goal_index_ = 0;
  bool done_ = false;
  bool started_ = false;
  /// Takes progress_ and floor_area_ from the planner's last update.
  void measure(double now);

  double progress_ = 0.0;
  double floor_area_ = 0.0;
  double progress_time_ = -std::numeric_limits<double>::infinity();
  int targets_[6] = { 0, 0, 0, 0, 0, 0 };
  NavOutput out_;
  int rounds_ = 0;
  std::size_t goal_stucks_ = 0;  // the navigator's stucks() when the current goal was set
  double retry_time_ = -std::numeric_limits<double>::infinity();  // exploring: when nothing was found last
  double blocked_since_ = std::numeric_limits<double>::quiet_NaN();
  int escape_phase_ = 0;  // 0: none, 1: turning away, 2: creeping
  double escape_yaw_ = 0.0;
  double escape_start_ = 0.0;
  Pose escape_from_;
  int escapes_ = 0;

public:
  /// Escapes started so far.
  int escapes() const { return escapes_; }
};
}  // namespace sl_navigation
