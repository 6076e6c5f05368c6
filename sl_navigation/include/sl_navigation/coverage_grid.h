/// @file coverage_grid.h
/// @brief The cells of the navigation map that the robot's disc passed over, the share of the
/// reachable floor they make, and a picture of both (ROS-free).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "sl_navigation/nav_grid.h"
#include "sl_navigation/path_follower.h"

namespace sl_navigation
{
/// What a cell of the reachable floor is (see CoveragePlanner::update()).
enum class FloorCell : std::uint8_t
{
  None = 0,   ///< not reachable known floor (occupied, unknown, too narrow, or cut off)
  Swept = 1,  ///< known free, within robot_radius of a reachable centre cell: the disc can pass over it
  Centre = 2  ///< also a reachable centre: known free, centre_clearance from obstacles, connected to the robot
};

/**
 * @brief Coverage: the cells (same geometry as a NavGrid) whose centre the robot's disc passed over.
 *
 * addPose() marks the disc at each pose and along the straight segment from the previous pose, in
 * steps of half a cell, so fast motion between two poses leaves no gap. Memory: one byte per cell,
 * fixed at construction.
 */
class CoverageGrid
{
public:
  /// An empty coverage with the geometry of @p grid; @p robot_radius (m) is the disc that covers.
  /// @throws std::invalid_argument when robot_radius is not in (0, 1] m.
  CoverageGrid(const NavGrid& grid, double robot_radius);

  /// Takes the geometry of @p grid (after NavGrid::reset()) and forgets everything.
  void reset(const NavGrid& grid);
  /// Marks the disc at @p pose and along the segment from the previous pose (none after reset()).
  /// Non-finite poses are ignored and break the segment.
  void addPose(const Pose& pose);
  /// Marks the disc at (x, y) only.
  void markDisc(double x, double y);
  /// Marks the discs along the segment (x0, y0) -> (x1, y1), every half cell.
  void markSegment(double x0, double y0, double x1, double y1);

  /// True when the disc passed over cell (ix, iy) (false outside).
  bool covered(int ix, int iy) const;
  /// Cells covered in all (also outside the reachable floor).
  std::size_t coveredCells() const { return covered_count_; }
  /// Covered cells of @p floor (FloorCell per cell, width()^2) and the floor's cells; covered / floor
  /// is the progress (0 when the floor is empty).
  double progress(const std::vector<FloorCell>& floor, std::size_t* covered_floor = nullptr,
                  std::size_t* floor_cells = nullptr) const;

  /// The coverage as nav_msgs/OccupancyGrid data: 100 covered, 0 reachable floor not yet covered,
  /// -1 elsewhere; row-major from the lower left corner.
  void toOccupancy(const std::vector<FloorCell>& floor, std::vector<std::int8_t>& out) const;
  /// An 8-bit RGB picture (width()^2 * 3 bytes, top row first, north up) of @p grid at @p now with
  /// the coverage over it: occupied black, unknown grey, free white, covered blue, reachable floor
  /// not covered light red.
  void toRgb(const NavGrid& grid, double now, const std::vector<FloorCell>& floor,
             std::vector<std::uint8_t>& out) const;

  /// Cells per side.
  int width() const { return n_; }
  /// The disc's radius (m).
  double robotRadius() const { return radius_; }

private:
  std::size_t index(int ix, int iy) const { return static_cast<std::size_t>(iy) * n_ + ix; }

  double radius_;
  int n_ = 0;
  double resolution_ = 0.05;
  double origin_x_ = 0.0;
  double origin_y_ = 0.0;
  std::vector<std::uint8_t> covered_;
  std::size_t covered_count_ = 0;
  bool has_last_ = false;
  Pose last_;
};

/// Writes an RGB picture (as CoverageGrid::toRgb() makes it) as a binary PPM file.
/// @return false when the file cannot be written or the sizes do not match.
bool writePpm(const char* path, const std::vector<std::uint8_t>& rgb, int width, int height);
}  // namespace sl_navigation
