/// @file noise_filter.h
/// @brief Rejects stray points in the box: minimum cluster size and persistence over frames.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "sl_obstacle/point.h"
#include "sl_obstacle/working_volume.h"

namespace sl_obstacle
{
/// Parameters of the noise rejection. Both tests apply; set a value to 1 to disable its test.
struct NoiseFilterParams
{
  /// A point is an obstacle only if its Euclidean cluster (links no longer than cluster_tolerance)
  /// among the in-box points has at least this many points. 1 disables the test.
  int min_cluster_size = 3;
  /// Largest distance between two points of one cluster (m).
  double cluster_tolerance = 0.03;
  /// A point is an obstacle only if its window cell held in-box points in this many consecutive
  /// frames (including this one), with the nearest x changing by at most persistence_tolerance from
  /// frame to frame. 1 disables the test.
  int persistence_frames = 2;
  /// Largest change of a cell's nearest x between consecutive frames that still counts as the same
  /// obstacle (m); covers the robot's own motion between frames.
  double persistence_tolerance = 0.05;

  /// @throws std::invalid_argument when invalid, its message starting with the offending parameter's name.
  void validate() const;
};

/// What the filter did with one frame's in-box points.
struct NoiseStats
{
  std::uint32_t candidates = 0;               ///< in-box points given to the filter
  std::uint32_t clusters = 0;                 ///< clusters found among them
  std::uint32_t accepted_clusters = 0;        ///< clusters with at least min_cluster_size points
  std::uint32_t largest_cluster = 0;          ///< size of the largest cluster
  std::uint32_t rejected_by_cluster = 0;      ///< points in clusters that are too small
  std::uint32_t rejected_by_persistence = 0;  ///< points in large enough clusters but not persistent
  std::uint32_t accepted = 0;                 ///< points accepted as obstacles
};

/// Stateful filter over the in-box points of consecutive frames. Memory is sized by configure() and
/// grows only when a frame has more candidates than any before (no per-frame allocation after that).
class NoiseFilter
{
public:
  /// Creates a filter with default parameters on the default volume and a 0.02 m cell grid.
  NoiseFilter();

  /// Sets the parameters and the persistence grid (the working window split into square cells of
  /// @p cell_size). Forgets the history. @throws std::invalid_argument on invalid parameters.
  void configure(const NoiseFilterParams& params, const WorkingVolume& volume, double cell_size);

  /// Forgets the persistence history (e.g. after a gap in the data).
  void reset();

  /// Filters one frame.
  /// @param points     all points of the frame
  /// @param candidates indices into @p points of the points inside the box
  /// @param accepted   output: the candidates accepted as obstacles, in the order of @p candidates
  /// @return statistics of this frame (valid until the next call)
  const NoiseStats& apply(const Point* points, const std::vector<std::uint32_t>& candidates,
                          std::vector<std::uint32_t>& accepted);

  /// The parameters in use.
  const NoiseFilterParams& params() const { return params_; }

  /// Per candidate of the last apply() call (same order): 1 when its cluster is large enough
  /// (whatever the persistence test said), 0 for points rejected as stray.
  const std::vector<std::uint8_t>& clusterPassed() const { return cluster_ok_; }

private:
  std::uint32_t findRoot(std::uint32_t i);
  int cellOf(const Point& p) const;

  NoiseFilterParams params_;
  WorkingVolume volume_;
  double cell_size_ = 0.02;
  int cols_ = 0;
  int rows_ = 0;

  // Clustering scratch (indexed by candidate position).
  std::vector<std::uint32_t> order_;
  std::vector<std::uint32_t> parent_;
  std::vector<std::uint32_t> size_;
  std::vector<std::uint8_t> cluster_ok_;
  // Persistence grid (indexed by cell).
  std::vector<std::uint16_t> count_;
  std::vector<float> previous_x_;
  std::vector<float> current_x_;
  NoiseStats stats_;
};
}  // namespace sl_obstacle
