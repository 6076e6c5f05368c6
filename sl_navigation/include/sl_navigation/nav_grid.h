/// @file nav_grid.h
/// @brief The navigation map: a persistent, bounded occupancy grid in odom, fused from the obstacle
/// node's rolling local map (ROS-free).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace sl_navigation
{
/// Parameters of the navigation map. validate() names the ROS parameter of a bad value.
struct GridParams
{
  double size = 20.0;                 ///< m, side of the square map centred on the first pose (map_size)
  double resolution = 0.05;           ///< m, side of a cell (map_resolution)
  double free_persistence = 600.0;    ///< s a cell last seen free stays free (free_persistence)
  double occupied_persistence = 60.0; ///< s a cell last seen occupied stays occupied (occupied_persistence)

  /// @throws std::invalid_argument naming the parameter.
  void validate() const;
};

/// State of a navigation map cell. Unknown may be planned through, never driven through unseen.
enum class Cell : std::uint8_t
{
  Unknown = 0,
  Free = 1,
  Occupied = 2
};

/// A view of one occupancy window (nav_msgs/OccupancyGrid layout: row-major from the lower left
/// corner, x fastest; -1 unknown, 0 free, 100 occupied, anything between: not free, not occupied).
struct OccupancyView
{
  const std::int8_t* data = nullptr;  ///< width * height values
  int width = 0;                      ///< cells along x
  int height = 0;                     ///< cells along y
  double resolution = 0.0;            ///< m per cell
  double origin_x = 0.0;              ///< m, x of the lower left corner (odom)
  double origin_y = 0.0;              ///< m, y of the lower left corner (odom)
};

/// True when @p view is usable: data, 1..4000 cells per side, cells of 0.005..1 m, finite origin.
bool validLayout(const OccupancyView& view);

/**
 * @brief Persistent occupancy grid of fixed size in odom.
 *
 * Each cell keeps the state it was last seen in and when. Fusing a local window (finer cells) sets a
 * cell occupied when any of its window cells is occupied, free when all of its window cells that were
 * seen are free and they cover at least half of it, and unknown when it held free or occupied and the
 * window now shows something in between (a suspect) there. A cell the window does not know keeps its
 * state: what was seen free stays free for free_persistence, an obstacle for occupied_persistence
 * (then the cell is unknown again). Memory: 11 bytes per cell, fixed at construction (1.8 MB for
 * 20 x 20 m at 0.05 m; the Planner adds about 40 bytes per cell).
 */
class NavGrid
{
public:
  /// An empty (all unknown) grid centred on (0, 0). @throws std::invalid_argument for bad params.
  explicit NavGrid(const GridParams& params = GridParams());

  /// Places the map so that it is centred on (x, y) and forgets everything.
  void reset(double x, double y);
  /// Fuses one local window seen at @p stamp (s). Windows with a bad layout are refused.
  /// @return false (nothing changed) when the view is empty, inconsistent or non-finite
  bool fuse(const OccupancyView& view, double stamp);
  /// Marks the cells whose centre lies within @p radius of (x, y) free at @p stamp (the robot's body).
  void markFree(double x, double y, double radius, double stamp);
  /// Calls @p f(ix, iy) for every cell of the map whose centre lies within @p radius of (x, y)
  /// (finite arguments; the radius is capped at the map's size).
  template <class F>
  void forEachCellInDisc(double x, double y, double radius, F f) const
  {
    const int r = static_cast<int>(std::ceil(std::min(radius, params_.size) / params_.resolution)) + 1;
    const int cx = indexX(x);
    const int cy = indexY(y);
    for (int iy = std::max(0, cy - r); iy <= std::min(n_ - 1, cy + r); ++iy)
    {
      for (int ix = std::max(0, cx - r); ix <= std::min(n_ - 1, cx + r); ++ix)
      {
        if (std::hypot(centerX(ix) - x, centerY(iy) - y) <= radius)
        {
          f(ix, iy);
        }
      }
    }
  }

  /// State of cell (ix, iy) at @p now; Unknown outside the map.
  Cell cell(int ix, int iy, double now) const;
  /// State of the cell holding (x, y) at @p now; Unknown outside the map or for NaN.
  Cell at(double x, double y, double now) const;
  /// True when (x, y) lies inside the map's bounds.
  bool contains(double x, double y) const;
  /// Cell index along x of coordinate @p x (may be outside [0, width())).
  int indexX(double x) const;
  /// Cell index along y of coordinate @p y.
  int indexY(double y) const;
  /// x of the centre of column @p ix.
  double centerX(int ix) const { return origin_x_ + (ix + 0.5) * params_.resolution; }
  /// y of the centre of row @p iy.
  double centerY(int iy) const { return origin_y_ + (iy + 0.5) * params_.resolution; }
  /// Cells per side.
  int width() const { return n_; }
  /// x of the lower left corner (m, odom).
  double originX() const { return origin_x_; }
  /// y of the lower left corner (m, odom).
  double originY() const { return origin_y_; }
  /// The parameters.
  const GridParams& params() const { return params_; }
  /// Changes whenever a cell's state changes (a version for caches).
  std::uint64_t version() const { return version_; }
  /// Every cell's state at @p now, row-major from the lower left corner (resized to width()^2).
  void snapshot(double now, std::vector<Cell>& out) const;
  /// The grid as OccupancyGrid data (-1, 0, 100), row-major from the lower left corner.
  void toOccupancy(double now, std::vector<std::int8_t>& out) const;

private:
  std::size_t index(int ix, int iy) const { return static_cast<std::size_t>(iy) * n_ + ix; }

  GridParams params_;
  int n_ = 0;
  double origin_x_ = 0.0;
  double origin_y_ = 0.0;
  std::vector<Cell> state_;
  std::vector<float> seen_;  // time the state was last confirmed (s after base_time_)
  double base_time_ = std::numeric_limits<double>::quiet_NaN();  // set by the first stamp
  float rel(double stamp);
  double age(std::size_t i, double now) const;
  // Scratch of fuse(): per touched cell, counts of window cells by kind.
  struct Tally
  {
    std::uint16_t free = 0, occupied = 0, other = 0;
  };
  std::vector<Tally> tally_;
  std::vector<std::uint32_t> touched_;
  std::uint64_t version_ = 0;
};
}  // namespace sl_navigation
