#include "sl_navigation/planner.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "validation.h"

namespace sl_navigation
{
namespace
{
constexpr float kOccupied = -1.0f;  // factor of an occupied cell: never entered
constexpr float kLethal = 0.0f;     // factor of a lethal cell: entered only to escape from the start
constexpr float kSqrt2 = 1.41421356f;
constexpr int kDx[8] = { 1, -1, 0, 0, 1, 1, -1, -1 };  // the four sides first, then the diagonals
constexpr int kDy[8] = { 0, 0, 1, -1, 1, -1, 1, -1 };
constexpr double kEnclosureReach = 1.5;  // m searched from an unknown goal for the walls of an object around it
}  // namespace

void PlannerParams::validate() const
{
  detail::requireRange("robot_radius", robot_radius, 0.01, 2.0);
  detail::requireRange("lethal_margin", lethal_margin, 0.0, 1.0);
  detail::requireRange("inflation_radius", inflation_radius, lethalDistance(), 5.0);
  detail::requireRange("obstacle_cost", obstacle_cost, 0.0, 1000.0);
  detail::requireRange("unknown_cost", unknown_cost, 0.0, 1000.0);
  detail::requireRange("escape_radius", escape_radius, 0.0, 2.0);
  detail::requireRange("heuristic_weight", heuristic_weight, 1.0, 5.0);
}

const char* toString(PlanStatus status)
{
  switch (status)
  {
    case PlanStatus::OK:
      return "OK";
    case PlanStatus::START_OUTSIDE:
      return "START_OUTSIDE";
    case PlanStatus::GOAL_OUTSIDE:
      return "GOAL_OUTSIDE";
    case PlanStatus::GOAL_BLOCKED:
      return "GOAL_BLOCKED";
    case PlanStatus::NO_PATH:
      return "NO_PATH";
  }
  return "?";
}

Planner::Planner(const PlannerParams& params, int width) : params_(params), n_(width)
{
  params_.validate();
  if (width <= 0)
  {
    detail::requireRange("map_size", width, 1, 1e9);
  }
  const std::size_t cells = static_cast<std::size_t>(n_) * n_;
  dist_.assign(cells, 0.0f);
  near_.assign(cells, 0);
  factor_.assign(cells, 1.0f);
  unknown_.assign(cells, 1);
  queue_.reserve(cells);
  g_.assign(cells, 0.0f);
  parent_.assign(cells, 0);
  gen_.assign(cells, 0);
  closed_.assign(cells, 0);
  buckets_.resize(1024);
}

void Planner::brushfire(const NavGrid& grid)
{
  // Distances to the obstacle cell's centre come from a table of sqrt(dx^2 + dy^2) in cells.
  const float cap = static_cast<float>(params_.inflation_radius);
  const float res = static_cast<float>(grid.params().resolution);
  const int reach = static_cast<int>(std::ceil(params_.inflation_radius / grid.params().resolution)) + 1;
  if (static_cast<int>(root_.size()) != 2 * reach * reach + 1)
  {
    root_.resize(2 * reach * reach + 1);
    for (std::size_t k = 0; k < root_.size(); ++k)
    {
      root_[k] = res * std::sqrt(static_cast<float>(k));
    }
  }
  std::fill(dist_.begin(), dist_.end(), cap);
  for (std::uint32_t i : queue_)
  {
    dist_[i] = 0.0f;
    near_[i] = i;
  }
  std::size_t head = 0;
  while (head < queue_.size())
  {
    const std::uint32_t i = queue_[head++];
    const int ix = static_cast<int>(i % n_);
    const int iy = static_cast<int>(i / n_);
    const std::uint32_t o = near_[i];
    const int ox = static_cast<int>(o % n_);
    const int oy = static_cast<int>(o / n_);
    for (int dy = -1; dy <= 1; ++dy)
    {
      const int ny = iy + dy;
      if (ny < 0 || ny >= n_)
      {
        continue;
      }
      for (int dx = -1; dx <= 1; ++dx)
      {
        const int nx = ix + dx;
        if ((dx == 0 && dy == 0) || nx < 0 || nx >= n_)
        {
          continue;
        }
        const int ex = std::abs(nx - ox);
        const int ey = std::abs(ny - oy);
        if (ex >= reach || ey >= reach)
        {
          continue;
        }
        const std::size_t j = index(nx, ny);
        const float d = root_[ex * ex + ey * ey];
        if (d < dist_[j] && d < cap)
        {
          dist_[j] = d;
          near_[j] = o;
          queue_.push_back(static_cast<std::uint32_t>(j));
        }
      }
    }
  }
}

void Planner::update(const NavGrid& grid, double now)
{
  if (grid.width() != n_)
  {
    detail::requireRange("map_size (grid and planner differ)", grid.width(), n_, n_);
  }
  resolution_ = grid.params().resolution;
  grid.snapshot(now, cells_);
  applyBlocked(grid);
  queue_.clear();
  for (std::size_t i = 0; i < cells_.size(); ++i)
  {
    unknown_[i] = cells_[i] == Cell::Unknown ? 1 : 0;
    if (cells_[i] == Cell::Occupied)
    {
      queue_.push_back(static_cast<std::uint32_t>(i));
    }
  }
  const std::size_t occupied = queue_.size();
  brushfire(grid);
  const float lethal = static_cast<float>(params_.lethalDistance());
  const float inflation = static_cast<float>(params_.inflation_radius);
  const float slope = static_cast<float>(params_.obstacle_cost) / std::max(1e-3f, inflation - lethal);
  const float unknown_extra = static_cast<float>(params_.unknown_cost);
  for (std::size_t i = 0; i < factor_.size(); ++i)
  {
    const float d = dist_[i];
    const float near = std::max(0.0f, inflation - d) * slope;
    factor_[i] = d < lethal ? kLethal : 1.0f + near + (unknown_[i] ? unknown_extra : 0.0f);
  }
  for (std::size_t q = 0; q < occupied; ++q)
  {
    factor_[queue_[q]] = kOccupied;
  }
  // The map's border ring is never entered: the search needs no bounds checks.
  for (int k = 0; k < n_; ++k)
  {
    factor_[index(k, 0)] = factor_[index(k, n_ - 1)] = factor_[index(0, k)] = factor_[index(n_ - 1, k)] = kOccupied;
  }
}

void Planner::applyBlocked(const NavGrid& grid)
{
  for (const Disc& d : blocked_)
  {
    if (!std::isfinite(d.x) || !std::isfinite(d.y) || !(d.radius > 0.0) || !grid.contains(d.x, d.y))
    {
      continue;
    }
    grid.forEachCellInDisc(d.x, d.y, d.radius, [this](int ix, int iy) { cells_[index(ix, iy)] = Cell::Occupied; });
  }
}

double Planner::clearance(int ix, int iy) const
{
  if (ix < 0 || iy < 0 || ix >= n_ || iy >= n_)
  {
    return 0.0;
  }
  return dist_[index(ix, iy)];
}

bool Planner::lethal(int ix, int iy) const
{
  return ix < 0 || iy < 0 || ix >= n_ || iy >= n_ || factor_[index(ix, iy)] <= 0.0f;
}

bool Planner::unknown(int ix, int iy) const
{
  return ix < 0 || iy < 0 || ix >= n_ || iy >= n_ || unknown_[index(ix, iy)] != 0;
}

double Planner::pathCost(const NavGrid& grid, const std::vector<Point>& points, std::size_t first) const
{
  double cost = 0.0;
  for (std::size_t k = first + 1; k < points.size(); ++k)
  {
    const Point& a = points[k - 1];
    const Point& b = points[k];
    const double len = std::hypot(b.x - a.x, b.y - a.y);
    const int steps = std::max(1, static_cast<int>(std::ceil(len / (0.5 * resolution_))));
    for (int j = 1; j <= steps; ++j)
    {
      const double x = a.x + (b.x - a.x) * j / steps;
      const double y = a.y + (b.y - a.y) * j / steps;
      if (!grid.contains(x, y))
      {
        return std::numeric_limits<double>::infinity();
      }
      const float f = factor_[index(grid.indexX(x), grid.indexY(y))];
      const bool escaping = std::hypot(x - points[first].x, y - points[first].y) <= params_.escape_radius;
      if (f == kOccupied || (f <= 0.0f && !escaping))
      {
        return std::numeric_limits<double>::infinity();
      }
      cost += len / steps * std::max(1.0f, f);
    }
  }
  return cost;
}

bool Planner::insideObject(int gix, int giy) const
{
  if (!unknown(gix, giy))
  {
    return false;
  }
  // Eight rays from the goal: each must meet an obstacle before a free cell, within kEnclosureReach.
  const int reach = static_cast<int>(std::ceil(kEnclosureReach / resolution_));
  for (int dir = 0; dir < 8; ++dir)
  {
    const int dx = dir == 0 || dir == 1 || dir == 7 ? 1 : (dir >= 3 && dir <= 5 ? -1 : 0);
    const int dy = dir >= 1 && dir <= 3 ? 1 : (dir >= 5 ? -1 : 0);
    bool closed = false;
    for (int k = 1; k <= reach; ++k)
    {
      const int x = gix + k * dx;
      const int y = giy + k * dy;
      if (x < 0 || y < 0 || x >= n_ || y >= n_)
      {
        break;
      }
      const std::size_t i = index(x, y);
      if (cells_[i] == Cell::Occupied)
      {
        closed = true;
        break;
      }
      if (!unknown_[i])
      {
        break;
      }
    }
    if (!closed)
    {
      return false;
    }
  }
  return true;
}

bool Planner::nearestClear(const NavGrid& grid, double gx, double gy, double radius, int& ix, int& iy) const
{
  const int r = static_cast<int>(std::ceil(radius / resolution_));
  const int cx = grid.indexX(gx);
  const int cy = grid.indexY(gy);
  double best = std::numeric_limits<double>::infinity();
  double best_clearance = 0.0;
  for (int y = std::max(1, cy - r); y <= std::min(n_ - 2, cy + r); ++y)
  {
    for (int x = std::max(1, cx - r); x <= std::min(n_ - 2, cx + r); ++x)
    {
      const double d = std::hypot(grid.centerX(x) - gx, grid.centerY(y) - gy);
      if (d > radius || lethal(x, y) || unknown(x, y) || d > best + 1e-9 || (d > best - 1e-9 && clearance(x, y) <= best_clearance))
      {
        continue;
      }
      best = d;
      best_clearance = clearance(x, y);
      ix = x;
      iy = y;
    }
  }
  return std::isfinite(best);
}

Plan Planner::plan(const NavGrid& grid, double sx, double sy, double gx, double gy, double tolerance)
{
  Plan out;
  char text[200];
  const auto on_border = [this](int ix, int iy) { return ix <= 0 || iy <= 0 || ix >= n_ - 1 || iy >= n_ - 1; };
  if (!grid.contains(sx, sy) || on_border(grid.indexX(sx), grid.indexY(sy)))
  {
    out.status = PlanStatus::START_OUTSIDE;
    std::snprintf(text, sizeof(text), "start (%.2f, %.2f) lies outside the map", sx, sy);
    out.text = text;
    return out;
  }
  if (!grid.contains(gx, gy) || on_border(grid.indexX(gx), grid.indexY(gy)))
  {
    out.status = PlanStatus::GOAL_OUTSIDE;
    std::snprintf(text, sizeof(text), "goal (%.2f, %.2f) lies outside the map (%.1f m around (%.2f, %.2f))", gx, gy,
                  grid.params().size, grid.originX() + 0.5 * grid.params().size,
                  grid.originY() + 0.5 * grid.params().size);
    out.text = text;
    return out;
  }
  int gix = grid.indexX(gx);
  int giy = grid.indexY(gy);
  const double requested_x = gx;
  const double requested_y = gy;
  if (lethal(gix, giy) && tolerance > 0.0 && nearestClear(grid, gx, gy, tolerance, gix, giy))
  {
    gx = grid.centerX(gix);
    gy = grid.centerY(giy);
    out.goal_shift = std::hypot(gx - requested_x, gy - requested_y);
  }
  if (lethal(gix, giy))
  {
    out.status = PlanStatus::GOAL_BLOCKED;
    std::snprintf(text, sizeof(text), "goal (%.2f, %.2f) is %.2f m from an obstacle: the robot needs %.2f m", gx, gy,
                  clearance(gix, giy), params_.lethalDistance());
    out.text = text;
    return out;
  }
  if (insideObject(gix, giy))
  {
    out.status = PlanStatus::GOAL_BLOCKED;
    std::snprintf(text, sizeof(text),
                  "goal (%.2f, %.2f) lies in unseen space enclosed by obstacles in every direction (inside an "
                  "object)",
                  gx, gy);
    out.text = text;
    return out;
  }
  const std::size_t start = index(grid.indexX(sx), grid.indexY(sy));
  const std::size_t goal = index(gix, giy);
  if (++generation_ == 0)
  {
    std::fill(gen_.begin(), gen_.end(), 0);
    std::fill(closed_.begin(), closed_.end(), 0);
    generation_ = 1;
  }
  std::ptrdiff_t offset[8];
  for (int k = 0; k < 8; ++k)
  {
    offset[k] = static_cast<std::ptrdiff_t>(kDy[k]) * n_ + kDx[k];
  }
  const int six = static_cast<int>(start % n_);
  const int siy = static_cast<int>(start / n_);
  const float res = static_cast<float>(resolution_);
  const float escape_cells = static_cast<float>(params_.escape_radius / resolution_);
  const float escape_factor = 1.0f + 2.0f * static_cast<float>(params_.obstacle_cost) + 1.0f;
  auto heuristic = [&](int ix, int iy) {
    const float dx = static_cast<float>(std::abs(ix - gix));
    const float dy = static_cast<float>(std::abs(iy - giy));
    return res * (std::max(dx, dy) + (kSqrt2 - 1.0f) * std::min(dx, dy));
  };
  // A bucket queue on f (buckets of a quarter cell of cost): O(1) per push and pop; entries of one
  // bucket come out in any order, so a path may cost up to a quarter cell more than the cheapest.
  const float weight = static_cast<float>(params_.heuristic_weight);
  const float f0 = weight * heuristic(six, siy);
  const float inv_width = 4.0f / res;
  std::size_t current = 0;
  std::size_t pending = 0;
  auto push = [&](float f, float g, std::uint32_t cell) {
    const std::size_t b = std::max(current, static_cast<std::size_t>(std::max(0.0f, (f - f0) * inv_width)));
    if (b >= buckets_.size())
    {
      buckets_.resize(b + 64);
    }
    buckets_[b].push_back({ f, g, cell });
    ++pending;
  };
  g_[start] = 0.0f;
  parent_[start] = static_cast<std::uint32_t>(start);
  gen_[start] = generation_;
  push(f0, 0.0f, static_cast<std::uint32_t>(start));
  int expansions = 0;
  bool found = false;
  while (pending > 0)
  {
    while (buckets_[current].empty())
    {
      ++current;
    }
    const Open top = buckets_[current].back();
    buckets_[current].pop_back();
    --pending;
    const std::uint32_t i = top.i;
    const int ix = static_cast<int>(i % n_);
    const int iy = static_cast<int>(i / n_);
    const float gi = g_[i];
    if (top.g > gi || closed_[i] == generation_)
    {
      continue;  // a stale entry, or expanded already (a weighted search does not reopen cells)
    }
    closed_[i] = generation_;
    ++expansions;
    if (i == goal)
    {
      found = true;
      break;
    }
    const float fi = std::max(factor_[i], 1.0f);
    for (int k = 0; k < 8; ++k)
    {
      const int nx = ix + kDx[k];
      const int ny = iy + kDy[k];
      const std::size_t j = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(i) + offset[k]);
      float f = factor_[j];
      if (f <= 0.0f)
      {
        const float ex = static_cast<float>(nx - six);
        const float ey = static_cast<float>(ny - siy);
        if (f == kOccupied || ex * ex + ey * ey > escape_cells * escape_cells || factor_[i] > 0.0f)
        {
          continue;  // lethal: only a start inside a lethal zone may leave it
        }
        f = escape_factor;
      }
      const float gj = gi + (k < 4 ? res : res * kSqrt2) * 0.5f * (f + fi);
      if (gen_[j] == generation_ && (gj >= g_[j] || closed_[j] == generation_))
      {
        continue;
      }
      gen_[j] = generation_;
      g_[j] = gj;
      parent_[j] = i;
      push(gj + weight * heuristic(nx, ny), gj, static_cast<std::uint32_t>(j));
    }
  }
  for (std::size_t b = current; b < buckets_.size(); ++b)
  {
    buckets_[b].clear();  // what a found goal left behind (capacity kept)
  }
  out.expansions = expansions;
  if (!found)
  {
    out.status = PlanStatus::NO_PATH;
    std::snprintf(text, sizeof(text),
                  "no path to (%.2f, %.2f): the %d cells reachable from the start do not hold it (the goal is "
                  "enclosed)",
                  gx, gy, expansions);
    out.text = text;
    return out;
  }
  extract(grid, start, goal, out);
  out.cost = g_[goal];
  out.points.front() = { sx, sy };
  out.points.back() = { gx, gy };
  out.length = 0.0;
  for (std::size_t k = 1; k < out.points.size(); ++k)
  {
    out.length += std::hypot(out.points[k].x - out.points[k - 1].x, out.points[k].y - out.points[k - 1].y);
  }
  out.status = PlanStatus::OK;
  std::snprintf(text, sizeof(text), "path of %.2f m to (%.2f, %.2f), %d unknown cells, %d cells searched",
                out.length, gx, gy, out.unknown_cells, expansions);
  out.text = text;
  if (out.goal_shift > 0.0)
  {
    std::snprintf(text, sizeof(text), " (the goal (%.2f, %.2f) moved %.2f m clear of an obstacle)", requested_x,
                  requested_y, out.goal_shift);
    out.text += text;
  }
  return out;
}

void Planner::extract(const NavGrid& grid, std::size_t start, std::size_t goal, Plan& out) const
{
  out.points.clear();
  out.unknown_cells = 0;
  std::size_t i = goal;
  for (;;)
  {
    const int ix = static_cast<int>(i % n_);
    const int iy = static_cast<int>(i / n_);
    out.points.push_back({ grid.centerX(ix), grid.centerY(iy) });
    out.unknown_cells += unknown_[i];
    if (i == start)
    {
      break;
    }
    i = parent_[i];
  }
  std::reverse(out.points.begin(), out.points.end());
  if (out.points.size() == 1)
  {
    out.points.push_back(out.points.front());
  }
}
}  // namespace sl_navigation
