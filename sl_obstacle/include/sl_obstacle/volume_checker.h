/// @file volume_checker.h
/// @brief Per-frame working-volume analysis: obstacles, free distance per sector, coverage.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "sl_obstacle/noise_filter.h"
#include "sl_obstacle/point.h"
#include "sl_obstacle/working_volume.h"

namespace sl_obstacle
{
/// Parameters of the analysis.
struct CheckerParams
{
  WorkingVolume volume;         ///< box geometry and sensor range
  int sectors = 5;              ///< lateral sectors across the width (index 0 at -y, the right)
  double cell_size = 0.02;      ///< edge of the square coverage cells on the window (m)
  double min_confidence = 0.0;  ///< points with lower (or NaN) confidence are ignored
  NoiseFilterParams noise;      ///< stray-point rejection

  /// @throws std::invalid_argument when invalid, its message starting with the offending parameter's name.
  void validate() const;
};

/// Result for one lateral sector of the box.
struct SectorResult
{
  double y_min = 0.0;             ///< right border of the sector (m)
  double y_max = 0.0;             ///< left border of the sector (m)
  double nearest_obstacle = 0.0;  ///< x of the nearest accepted obstacle point, +inf if none (m)
  /// Farthest x measured in the sector's part of the window (floor, background or in-box points,
  /// except strays rejected by the cluster test), capped at depth; 0 when nothing was measured (m).
  double measured_extent = 0.0;
  /// min(nearest_obstacle, measured_extent): how far the sector is known to be free (m).
  double free_distance = 0.0;
  std::uint32_t obstacle_points = 0;  ///< accepted obstacle points in the sector
};

/// Everything the analysis found in one frame. Vectors keep their capacity between frames.
struct VolumeResult
{
  std::uint32_t total_points = 0;           ///< points given
  std::uint32_t invalid_points = 0;         ///< NaN or infinite coordinates
  std::uint32_t low_confidence_points = 0;  ///< confidence below min_confidence (or NaN)
  std::uint32_t out_of_range_points = 0;    ///< x <= 0 (behind the front edge) or x > max_range
  std::uint32_t floor_points = 0;           ///< valid points with z < floor_margin
  std::uint32_t in_box_points = 0;          ///< valid points inside the box (before noise rejection)
  std::uint32_t obstacle_points = 0;        ///< in-box points accepted as obstacles
  std::uint32_t rejected_points = 0;        ///< in-box points rejected as noise

  std::vector<std::uint32_t> in_box_indices;    ///< indices of the in-box points
  std::vector<std::uint32_t> obstacle_indices;  ///< indices of the accepted obstacle points

  double nearest_distance = 0.0;    ///< x of the nearest obstacle point, +inf if none (m)
  std::int64_t nearest_index = -1;  ///< its index in the input, -1 if none
  Point nearest_point;              ///< the point itself (zero if none)

  std::vector<SectorResult> sectors;  ///< one per lateral sector, right (-y) to left (+y)
  double free_distance = 0.0;         ///< min over sectors of SectorResult::free_distance (m)
  double left_free = 0.0;             ///< mean free distance of the sectors left of the centre line (m)
  double right_free = 0.0;            ///< mean free distance of the sectors right of the centre line (m)

  int grid_cols = 0;                        ///< coverage grid columns (along y, from -W/2)
  int grid_rows = 0;                        ///< coverage grid rows (along z, from the floor)
  std::vector<std::uint8_t> cell_measured;  ///< row-major grid, 1 when the cell was measured
  std::uint32_t measured_cells = 0;         ///< cells with at least one valid point
  double coverage = 0.0;                    ///< measured_cells / (grid_cols * grid_rows), 0..1

  NoiseStats noise;  ///< what the noise filter did
};

/// Analyses frames against the working volume.
///
/// Per frame: classifies every point (invalid, low confidence, out of range, floor, in box,
/// background), marks the coverage cells, filters the in-box points for noise (stateful: persistence
/// uses earlier frames), and computes the nearest obstacle and the free distance per sector.
///
/// Coverage: the window (|y| <= W/2, -floor_margin <= z <= H) is split into square cells of
/// cell_size; a cell is measured when at least one valid point with 0 < x <= max_range has its (y, z)
/// in the cell, whatever its x (floor, obstacle, background beyond the box). In-box points rejected as
/// strays by the cluster test are not measurements; points that only wait for persistence are.
class VolumeChecker
{
public:
  /// Creates a checker. @throws std::invalid_argument on invalid parameters.
  explicit VolumeChecker(const CheckerParams& params = CheckerParams());

  /// Replaces the parameters and forgets the noise history. @throws std::invalid_argument.
  void setParams(const CheckerParams& params);

  /// The parameters in use.
  const CheckerParams& params() const { return params_; }

  /// Forgets the noise filter's history (call after a gap in the data).
  void reset();

  /// Analyses one frame of @p count points in the working-volume frame.
  /// @return the result, valid until the next call.
  const VolumeResult& analyze(const Point* points, std::size_t count);

  /// Convenience overload.
  const VolumeResult& analyze(const std::vector<Point>& points) { return analyze(points.data(), points.size()); }

  /// The result of the last analyze() call.
  const VolumeResult& result() const { return result_; }

private:
  int sectorOf(double y) const;
  void markMeasured(const Point& p);

  CheckerParams params_;
  NoiseFilter filter_;
  VolumeResult result_;
};
}  // namespace sl_obstacle
