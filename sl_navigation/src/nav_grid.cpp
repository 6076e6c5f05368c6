#include "sl_navigation/nav_grid.h"

#include <algorithm>
#include <cmath>

#include "validation.h"

namespace sl_navigation
{
void GridParams::validate() const
{
  detail::requireRange("map_resolution", resolution, 0.01, 0.5);
  detail::requireRange("map_size", size, 1.0, 200.0);
  if (size / resolution > 4000.0)
  {
    detail::requireRange("map_size", size, 1.0, 4000.0 * resolution);  // at most 4000 cells per side
  }
  detail::requireRange("free_persistence", free_persistence, 1.0, 1e7);
  detail::requireRange("occupied_persistence", occupied_persistence, 1.0, 1e7);
}

NavGrid::NavGrid(const GridParams& params) : params_(params)
{
  params_.validate();
  n_ = static_cast<int>(std::lround(params_.size / params_.resolution));
  const std::size_t cells = static_cast<std::size_t>(n_) * n_;
  state_.assign(cells, Cell::Unknown);
  seen_.assign(cells, 0.0f);
  tally_.assign(cells, Tally());
  touched_.reserve(4096);
  reset(0.0, 0.0);
}

void NavGrid::reset(double x, double y)
{
  if (!std::isfinite(x) || !std::isfinite(y))
  {
    x = 0.0;
    y = 0.0;
  }
  origin_x_ = x - 0.5 * n_ * params_.resolution;
  origin_y_ = y - 0.5 * n_ * params_.resolution;
  std::fill(state_.begin(), state_.end(), Cell::Unknown);
  std::fill(seen_.begin(), seen_.end(), 0.0f);
  base_time_ = std::numeric_limits<double>::quiet_NaN();
  ++version_;
}

float NavGrid::rel(double stamp)
{
  if (std::isnan(base_time_))
  {
    base_time_ = stamp;
  }
  return static_cast<float>(stamp - base_time_);
}

double NavGrid::age(std::size_t i, double now) const
{
  return std::isnan(base_time_) ? 0.0 : (now - base_time_) - static_cast<double>(seen_[i]);
}

namespace
{
/// floor(v) as an int, clamped to [-2^30, 2^30] (NaN: the lower end): never an undefined cast.
int safeFloor(double v)
{
  constexpr double kLimit = 1073741824.0;
  return v >= -kLimit ? (v <= kLimit ? static_cast<int>(std::floor(v)) : static_cast<int>(kLimit))
                      : -static_cast<int>(kLimit);
}
}  // namespace

bool validLayout(const OccupancyView& v)
{
  // Cells of 5 mm .. 1 m and at most 4000 per side: the per-cell loops stay bounded.
  return v.data != nullptr && v.width > 0 && v.height > 0 && v.width <= 4000 && v.height <= 4000 &&
         std::isfinite(v.resolution) && v.resolution >= 0.005 && v.resolution <= 1.0 && std::isfinite(v.origin_x) &&
         std::isfinite(v.origin_y) && std::abs(v.origin_x) < 1e6 && std::abs(v.origin_y) < 1e6;
}

int NavGrid::indexX(double x) const
{
  return safeFloor((x - origin_x_) / params_.resolution);
}

int NavGrid::indexY(double y) const
{
  return safeFloor((y - origin_y_) / params_.resolution);
}

bool NavGrid::contains(double x, double y) const
{
  if (!std::isfinite(x) || !std::isfinite(y))
  {
    return false;
  }
  const int ix = indexX(x);
  const int iy = indexY(y);
  return ix >= 0 && iy >= 0 && ix < n_ && iy < n_;
}

Cell NavGrid::cell(int ix, int iy, double now) const
{
  if (ix < 0 || iy < 0 || ix >= n_ || iy >= n_)
  {
    return Cell::Unknown;
  }
  const std::size_t i = index(ix, iy);
  const Cell c = state_[i];
  if (c == Cell::Unknown)
  {
    return c;
  }
  const double limit = c == Cell::Free ? params_.free_persistence : params_.occupied_persistence;
  return age(i, now) > limit ? Cell::Unknown : c;
}

Cell NavGrid::at(double x, double y, double now) const
{
  if (!contains(x, y))
  {
    return Cell::Unknown;
  }
  return cell(indexX(x), indexY(y), now);
}

bool NavGrid::fuse(const OccupancyView& v, double stamp)
{
  if (!validLayout(v) || !std::isfinite(stamp))
  {
    return false;
  }
  touched_.clear();
  for (int ly = 0; ly < v.height; ++ly)
  {
    const int iy = indexY(v.origin_y + (ly + 0.5) * v.resolution);
    if (iy < 0 || iy >= n_)
    {
      continue;
    }
    const std::int8_t* row = v.data + static_cast<std::size_t>(ly) * v.width;
    for (int lx = 0; lx < v.width; ++lx)
    {
      const std::int8_t value = row[lx];
      if (value < 0)
      {
        continue;  // unknown in the window: says nothing
      }
      const int ix = indexX(v.origin_x + (lx + 0.5) * v.resolution);
      if (ix < 0 || ix >= n_)
      {
        continue;
      }
      const std::size_t i = index(ix, iy);
      Tally& t = tally_[i];
      if (t.free == 0 && t.occupied == 0 && t.other == 0)
      {
        touched_.push_back(static_cast<std::uint32_t>(i));
      }
      if (value == 0)
      {
        ++t.free;
      }
      else if (value >= 100)
      {
        ++t.occupied;
      }
      else
      {
        ++t.other;
      }
    }
  }
  // Window cells per map cell; at least half of them must be seen free to call the cell free.
  const double per_cell = std::pow(params_.resolution / v.resolution, 2.0);
  const int min_free = std::max(1, static_cast<int>(std::ceil(0.5 * per_cell - 1e-9)));
  const float t_rel = rel(stamp);
  bool changed = false;
  for (std::uint32_t i : touched_)
  {
    Tally& t = tally_[i];
    const Cell before = state_[i];
    if (t.occupied > 0)
    {
      state_[i] = Cell::Occupied;
      seen_[i] = t_rel;
    }
    else if (t.other > 0)
    {
      state_[i] = Cell::Unknown;  // a suspect: neither free nor occupied any more
    }
    else if (t.free >= min_free)
    {
      state_[i] = Cell::Free;
      seen_[i] = t_rel;
    }
    changed |= state_[i] != before;
    t = Tally();
  }
  version_ += changed ? 1 : 0;
  return true;
}

void NavGrid::markFree(double x, double y, double radius, double stamp)
{
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(radius) || radius < 0.0 || !std::isfinite(stamp))
  {
    return;
  }
  const float t_rel = rel(stamp);
  bool changed = false;
  forEachCellInDisc(x, y, radius,
                    [&](int ix, int iy)
                    {
                      changed |= state_[index(ix, iy)] != Cell::Free;
                      state_[index(ix, iy)] = Cell::Free;
                      seen_[index(ix, iy)] = t_rel;
                    });
  version_ += changed ? 1 : 0;
}

void NavGrid::snapshot(double now, std::vector<Cell>& out) const
{
  out.resize(state_.size());
  const double base = std::isnan(base_time_) ? now : base_time_;
  const float t = static_cast<float>(now - base);
  const float free_limit = static_cast<float>(params_.free_persistence);
  const float occupied_limit = static_cast<float>(params_.occupied_persistence);
  for (std::size_t i = 0; i < state_.size(); ++i)
  {
    const Cell c = state_[i];
    const float age = t - seen_[i];
    const bool expired = c == Cell::Free ? age > free_limit : (c == Cell::Occupied && age > occupied_limit);
    out[i] = expired ? Cell::Unknown : c;
  }
}

void NavGrid::toOccupancy(double now, std::vector<std::int8_t>& out) const
{
  out.resize(state_.size());
  for (int iy = 0; iy < n_; ++iy)
  {
    for (int ix = 0; ix < n_; ++ix)
    {
      const Cell c = cell(ix, iy, now);
      out[index(ix, iy)] = c == Cell::Free ? 0 : (c == Cell::Occupied ? 100 : -1);
    }
  }
}
}  // namespace sl_navigation
