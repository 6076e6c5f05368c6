#include "sl_obstacle/noise_filter.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "validation.h"

namespace sl_obstacle
{
void NoiseFilterParams::validate() const
{
  if (min_cluster_size < 1 || min_cluster_size > 1000)
  {
    detail::refuse("min_cluster_size", "must be in [1, 1000]", min_cluster_size);
  }
  if (persistence_frames < 1 || persistence_frames > 100)
  {
    detail::refuse("persistence_frames", "must be in [1, 100]", persistence_frames);
  }
  detail::requireInRange("cluster_tolerance", cluster_tolerance, 1e-4, 1.0);
  detail::requireInRange("persistence_tolerance", persistence_tolerance, 0.0, 1.0);
}

NoiseFilter::NoiseFilter()
{
  configure(NoiseFilterParams(), WorkingVolume(), 0.02);
}

void NoiseFilter::configure(const NoiseFilterParams& params, const WorkingVolume& volume, double cell_size)
{
  params.validate();
  volume.validate();
  detail::requireInRange("cell_size", cell_size, 1e-3, 1.0);
  params_ = params;
  volume_ = volume;
  cell_size_ = cell_size;
  // The window spans -floor_margin <= z <= height; cells start at z = 0, points below fall into row 0.
  cols_ = std::max(1, static_cast<int>(std::ceil(volume.width / cell_size - 1e-9)));
  rows_ = std::max(1, static_cast<int>(std::ceil(volume.height / cell_size - 1e-9)));
  const std::size_t cells = static_cast<std::size_t>(cols_) * static_cast<std::size_t>(rows_);
  count_.assign(cells, 0);
  previous_x_.assign(cells, std::numeric_limits<float>::infinity());
  current_x_.assign(cells, std::numeric_limits<float>::infinity());
}

void NoiseFilter::reset()
{
  std::fill(count_.begin(), count_.end(), 0);
  std::fill(previous_x_.begin(), previous_x_.end(), std::numeric_limits<float>::infinity());
}

int NoiseFilter::cellOf(const Point& p) const
{
  int col = static_cast<int>(std::floor((p.y + 0.5 * volume_.width) / cell_size_));
  int row = static_cast<int>(std::floor(p.z / cell_size_));
  col = std::min(std::max(col, 0), cols_ - 1);
  row = std::min(std::max(row, 0), rows_ - 1);
  return row * cols_ + col;
}

std::uint32_t NoiseFilter::findRoot(std::uint32_t i)
{
  while (parent_[i] != i)
  {
    parent_[i] = parent_[parent_[i]];  // path halving
    i = parent_[i];
  }
  return i;
}

const NoiseStats& NoiseFilter::apply(const Point* points, const std::vector<std::uint32_t>& candidates,
                                     std::vector<std::uint32_t>& accepted)
{
  stats_ = NoiseStats();
  accepted.clear();
  const std::size_t n = candidates.size();
  stats_.candidates = static_cast<std::uint32_t>(n);

  // --- Euclidean clustering: union-find over pairs closer than the tolerance, sweeping along y.
  if (order_.size() < n)
  {
    // Grows only when a frame has more in-box points than any before.
    order_.resize(n);
    parent_.resize(n);
    size_.resize(n);
  }
  cluster_ok_.resize(n);  // no allocation once the capacity is reached
  for (std::uint32_t k = 0; k < n; ++k)
  {
    order_[k] = k;
    parent_[k] = k;
    size_[k] = 1;
  }
  std::sort(order_.begin(), order_.begin() + static_cast<std::ptrdiff_t>(n),
            [&](std::uint32_t a, std::uint32_t b) { return points[candidates[a]].y < points[candidates[b]].y; });
  const float tol = static_cast<float>(params_.cluster_tolerance);
  const float tol2 = tol * tol;
  for (std::size_t a = 0; a < n; ++a)
  {
    const Point& pa = points[candidates[order_[a]]];
    for (std::size_t b = a + 1; b < n; ++b)
    {
      const Point& pb = points[candidates[order_[b]]];
      const float dy = pb.y - pa.y;
      if (dy > tol)
      {
        break;
      }
      const float dx = pb.x - pa.x;
      const float dz = pb.z - pa.z;
      if (dx * dx + dy * dy + dz * dz <= tol2)
      {
        std::uint32_t ra = findRoot(order_[a]);
        std::uint32_t rb = findRoot(order_[b]);
        if (ra != rb)
        {
          if (size_[ra] < size_[rb])
          {
            std::swap(ra, rb);
          }
          parent_[rb] = ra;
          size_[ra] += size_[rb];
        }
      }
    }
  }
  for (std::uint32_t k = 0; k < n; ++k)
  {
    if (findRoot(k) == k)
    {
      ++stats_.clusters;
      stats_.largest_cluster = std::max(stats_.largest_cluster, size_[k]);
      if (size_[k] >= static_cast<std::uint32_t>(params_.min_cluster_size))
      {
        ++stats_.accepted_clusters;
      }
    }
  }

  // --- Persistence: per window cell, count consecutive frames with in-box points at a similar x.
  std::fill(current_x_.begin(), current_x_.end(), std::numeric_limits<float>::infinity());
  for (std::uint32_t k = 0; k < n; ++k)
  {
    const Point& p = points[candidates[k]];
    float& cx = current_x_[static_cast<std::size_t>(cellOf(p))];
    cx = std::min(cx, p.x);
  }
  const float ptol = static_cast<float>(params_.persistence_tolerance);
  for (std::size_t c = 0; c < count_.size(); ++c)
  {
    if (std::isfinite(current_x_[c]))
    {
      const bool same = count_[c] > 0 && std::fabs(current_x_[c] - previous_x_[c]) <= ptol;
      count_[c] = same ? static_cast<std::uint16_t>(std::min<int>(count_[c] + 1, 60000)) : 1;
      previous_x_[c] = current_x_[c];
    }
    else
    {
      count_[c] = 0;
      previous_x_[c] = std::numeric_limits<float>::infinity();
    }
  }

  // --- Accept the points that pass both tests.
  const std::uint32_t min_size = static_cast<std::uint32_t>(params_.min_cluster_size);
  const int min_frames = params_.persistence_frames;
  for (std::uint32_t k = 0; k < n; ++k)
  {
    cluster_ok_[k] = size_[findRoot(k)] >= min_size ? 1 : 0;
    if (cluster_ok_[k] == 0)
    {
      ++stats_.rejected_by_cluster;
      continue;
    }
    if (count_[static_cast<std::size_t>(cellOf(points[candidates[k]]))] < min_frames)
    {
      ++stats_.rejected_by_persistence;
      continue;
    }
    accepted.push_back(candidates[k]);
  }
  stats_.accepted = static_cast<std::uint32_t>(accepted.size());
  return stats_;
}
}  // namespace sl_obstacle
