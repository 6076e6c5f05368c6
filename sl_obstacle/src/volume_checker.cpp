#include "sl_obstacle/volume_checker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "validation.h"

namespace sl_obstacle
{
void CheckerParams::validate() const
{
  volume.validate();
  if (sectors < 1 || sectors > 64)
  {
    detail::refuse("sectors", "must be in [1, 64]", sectors);
  }
  detail::requireInRange("cell_size", cell_size, 1e-3, 1.0);
  detail::requireInRange("min_confidence", min_confidence, 0.0, 1e6);
  if (cell_size > volume.width || cell_size > volume.height)
  {
    detail::refuse("cell_size", "must not exceed width or height", cell_size);
  }
  noise.validate();
}

VolumeChecker::VolumeChecker(const CheckerParams& params)
{
  setParams(params);
}

void VolumeChecker::setParams(const CheckerParams& params)
{
  params.validate();
  filter_.configure(params.noise, params.volume, params.cell_size);
  params_ = params;

  VolumeResult& r = result_;
  r = VolumeResult();
  r.sectors.resize(static_cast<std::size_t>(params.sectors));
  const double half = 0.5 * params.volume.width;
  const double step = params.volume.width / params.sectors;
  for (int s = 0; s < params.sectors; ++s)
  {
    r.sectors[static_cast<std::size_t>(s)].y_min = -half + s * step;
    r.sectors[static_cast<std::size_t>(s)].y_max = -half + (s + 1) * step;
  }
  r.grid_cols = std::max(1, static_cast<int>(std::ceil(params.volume.width / params.cell_size - 1e-9)));
  r.grid_rows = std::max(1, static_cast<int>(std::ceil(params.volume.height / params.cell_size - 1e-9)));
  r.cell_measured.assign(static_cast<std::size_t>(r.grid_cols) * static_cast<std::size_t>(r.grid_rows), 0);
  r.nearest_distance = std::numeric_limits<double>::infinity();
}

void VolumeChecker::reset()
{
  filter_.reset();
}

int VolumeChecker::sectorOf(double y) const
{
  const double half = 0.5 * params_.volume.width;
  const int s = static_cast<int>(std::floor((y + half) / params_.volume.width * params_.sectors));
  return std::min(std::max(s, 0), params_.sectors - 1);
}

void VolumeChecker::markMeasured(const Point& p)
{
  VolumeResult& r = result_;
  const double half = 0.5 * params_.volume.width;
  int col = static_cast<int>(std::floor((p.y + half) / params_.cell_size));
  int row = static_cast<int>(std::floor(p.z / params_.cell_size));
  col = std::min(std::max(col, 0), r.grid_cols - 1);
  row = std::min(std::max(row, 0), r.grid_rows - 1);
  std::uint8_t& m = r.cell_measured[static_cast<std::size_t>(row * r.grid_cols + col)];
  if (m == 0)
  {
    m = 1;
    ++r.measured_cells;
  }
  SectorResult& s = r.sectors[static_cast<std::size_t>(sectorOf(p.y))];
  s.measured_extent = std::max(s.measured_extent, std::min<double>(p.x, params_.volume.depth));
}

const VolumeResult& VolumeChecker::analyze(const Point* points, std::size_t count)
{
  const WorkingVolume& v = params_.volume;
  const double inf = std::numeric_limits<double>::infinity();
  VolumeResult& r = result_;

  r.total_points = static_cast<std::uint32_t>(count);
  r.invalid_points = r.low_confidence_points = r.out_of_range_points = 0;
  r.floor_points = r.in_box_points = r.obstacle_points = r.rejected_points = 0;
  r.in_box_indices.clear();
  r.obstacle_indices.clear();
  if (r.in_box_indices.capacity() < count)
  {
    // Grows to the largest cloud seen; no allocation once warmed up.
    r.in_box_indices.reserve(count);
    r.obstacle_indices.reserve(count);
  }
  r.nearest_distance = inf;
  r.nearest_index = -1;
  r.nearest_point = Point();
  r.nearest_point.confidence = 0.0F;
  for (SectorResult& s : r.sectors)
  {
    s.nearest_obstacle = inf;
    s.measured_extent = 0.0;
    s.free_distance = 0.0;
    s.obstacle_points = 0;
  }
  std::fill(r.cell_measured.begin(), r.cell_measured.end(), 0);
  r.measured_cells = 0;

  for (std::size_t i = 0; i < count; ++i)
  {
    const Point& p = points[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
    {
      ++r.invalid_points;
      continue;
    }
    if (!(p.confidence >= params_.min_confidence))
    {
      ++r.low_confidence_points;
      continue;
    }
    if (p.x <= 0.0F || p.x > v.max_range)
    {
      ++r.out_of_range_points;
      continue;
    }
    if (v.contains(p))
    {
      r.in_box_indices.push_back(static_cast<std::uint32_t>(i));  // measured unless noise (below)
      continue;
    }
    if (p.z < v.floor_margin)
    {
      ++r.floor_points;
    }
    if (v.inWindow(p))
    {
      markMeasured(p);
    }
  }
  r.in_box_points = static_cast<std::uint32_t>(r.in_box_indices.size());

  r.noise = filter_.apply(points, r.in_box_indices, r.obstacle_indices);
  // In-box points count as measurements unless rejected as strays by the cluster test.
  const std::vector<std::uint8_t>& clustered = filter_.clusterPassed();
  for (std::size_t k = 0; k < r.in_box_indices.size(); ++k)
  {
    if (clustered[k] != 0)
    {
      markMeasured(points[r.in_box_indices[k]]);
    }
  }
  r.coverage = static_cast<double>(r.measured_cells) / static_cast<double>(r.cell_measured.size());
  r.obstacle_points = static_cast<std::uint32_t>(r.obstacle_indices.size());
  r.rejected_points = r.in_box_points - r.obstacle_points;

  for (const std::uint32_t i : r.obstacle_indices)
  {
    const Point& p = points[i];
    SectorResult& s = r.sectors[static_cast<std::size_t>(sectorOf(p.y))];
    s.nearest_obstacle = std::min<double>(s.nearest_obstacle, p.x);
    ++s.obstacle_points;
    if (p.x < r.nearest_distance)
    {
      r.nearest_distance = p.x;
      r.nearest_index = static_cast<std::int64_t>(i);
      r.nearest_point = p;
    }
  }

  r.free_distance = inf;
  double left_sum = 0.0;
  double right_sum = 0.0;
  int left_n = 0;
  int right_n = 0;
  for (SectorResult& s : r.sectors)
  {
    s.free_distance = std::min(s.nearest_obstacle, s.measured_extent);
    r.free_distance = std::min(r.free_distance, s.free_distance);
    const double centre = 0.5 * (s.y_min + s.y_max);
    if (centre > 1e-9)
    {
      left_sum += s.free_distance;
      ++left_n;
    }
    else if (centre < -1e-9)
    {
      right_sum += s.free_distance;
      ++right_n;
    }
  }
  r.left_free = left_n > 0 ? left_sum / left_n : r.free_distance;
  r.right_free = right_n > 0 ? right_sum / right_n : r.free_distance;
  return r;
}
}  // namespace sl_obstacle
