#include "sl_navigation/coverage_planner.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace sl_navigation
{
namespace
{
constexpr int kSplitCells = 8;              // a lane is split where it gains nothing for this many cells (0.4 m)
constexpr int kMaxOffers = 3;               // a target offered this often is not offered again
constexpr double kSeedRadius = 0.4;         // m searched for a centre cell when the robot stands on none
constexpr double kFailRadius = 0.2;         // m around a failed goal not offered again
constexpr double kTriedRadius = 0.3;        // m around a looked-at frontier cell marked tried
constexpr int kEdgeTries = 40;              // ring cells tried as the start of an edge pass per call
constexpr double kTrackMargin = 0.05;       // m of the disc's rim a target does not count on (tracking errors)
constexpr double kLookAroundSpacing = 1.0;  // m between the places the robot turns around to look
constexpr double kGuardMargin = 0.045;      // m beyond robot_radius kept to occupied cell centres by the guard
constexpr double kBlockedTime = 2.0;        // s BLOCKED before an escape
constexpr double kEscapeReach = 0.6;        // m searched for the obstacle to turn away from
constexpr double kEscapeDistance = 0.15;    // m crept away
constexpr double kEscapeSpeed = 0.05;       // m/s
constexpr double kRoamMin = 0.4;            // m, the shortest ROAM leg (shorter ones where nothing lies farther)
constexpr double kRoamTurnWeight = 1.5;     // score lost by a ROAM target straight behind the robot
constexpr double kRoamUnknownWeight = 1.0;  // score lost by a ROAM leg over unknown floor only
constexpr double kRenewShare = 0.5;         // roam: driven-over share of the floor before a new round
constexpr double kHandover = 0.35;          // m before a ROAM goal where roaming takes the next one

/// Cell offsets whose distance (m, between cell centres) lies in [lo, hi].
std::vector<std::pair<int, int>> cellsWithin(double lo, double hi, double resolution)
{
  std::vector<std::pair<int, int>> out;
  const int reach = static_cast<int>(std::ceil(hi / resolution));
  for (int dy = -reach; dy <= reach; ++dy)
  {
    for (int dx = -reach; dx <= reach; ++dx)
    {
      const double d = std::hypot(dx, dy) * resolution;
      if (d >= lo && d <= hi)
      {
        out.emplace_back(dx, dy);
      }
    }
  }
  return out;
}

void require(bool ok, const char* name, const std::string& what)
{
  if (!ok)
  {
    throw std::invalid_argument(std::string(name) + " " + what);
  }
}
}  // namespace

void CoverageParams::validate() const
{
  planner.validate();
  const double d = 2.0 * planner.robot_radius;
  require(lane_spacing >= 0.05 && lane_spacing < d, "lane_spacing",
          "must be in [0.05, robot diameter " + std::to_string(d) + ") m, got " + std::to_string(lane_spacing));
  require(edge_clearance >= 0.0 && edge_clearance <= 0.5, "edge_clearance",
          "must be in [0, 0.5] m, got " + std::to_string(edge_clearance));
  require(edge_speed > 0.0 && edge_speed <= 0.5, "edge_speed",
          "must be in (0, 0.5] m/s, got " + std::to_string(edge_speed));
  require(edge_length > 0.0 && edge_length <= 50.0, "edge_length",
          "must be in (0, 50] m, got " + std::to_string(edge_length));
  require(waypoint_spacing >= 0.1 && waypoint_spacing <= 10.0, "waypoint_spacing",
          "must be in [0.1, 10] m, got " + std::to_string(waypoint_spacing));
  require(min_gain >= 1 && min_gain <= 10000, "min_gain", "must be in [1, 10000], got " + std::to_string(min_gain));
  require(roam_leg >= 0.3 && roam_leg <= 10.0, "roam_leg", "must be in [0.3, 10] m, got " + std::to_string(roam_leg));
  require(view_min >= 0.0 && view_max > view_min && view_max <= 5.0, "view_min/view_max",
          "must satisfy 0 <= view_min < view_max <= 5 m, got " + std::to_string(view_min) + ", " +
              std::to_string(view_max));
}

double CoverageParams::centreClearance(double resolution) const
{
  return std::max(planner.lethalDistance(), planner.robot_radius + edge_clearance + 0.5 * resolution);
}

const char* toString(CoverageMode mode)
{
  switch (mode)
  {
    case CoverageMode::LANE:
      return "LANE";
    case CoverageMode::EDGE:
      return "EDGE";
    case CoverageMode::SPOT:
      return "SPOT";
    case CoverageMode::FRONTIER:
      return "FRONTIER";
    case CoverageMode::ROAM:
      return "ROAM";
    case CoverageMode::DONE:
      return "DONE";
  }
  return "?";
}

CoveragePlanner::CoveragePlanner(const CoverageParams& params, int width)
  : params_((params.validate(), params)), planner_(params.planner, width), n_(width)
{
  const std::size_t cells = static_cast<std::size_t>(n_) * n_;
  floor_.assign(cells, FloorCell::None);
  dist_.assign(cells, -1);
  gain_.assign(cells, 0);
  blocked_.assign(cells, 0);
  offers_.assign(cells, 0);
  tried_.assign(cells, 0);
  ring_.assign(cells, 0);
  pass_.assign(cells, 0);
  queue_.reserve(cells);
}

bool CoveragePlanner::cellOf(double x, double y, int& ix, int& iy) const
{
  const double fx = std::floor((x - origin_x_) / resolution_);
  const double fy = std::floor((y - origin_y_) / resolution_);
  if (!(std::abs(fx) < 1e6 && std::abs(fy) < 1e6))  // NaN and far outside the map
  {
    return false;
  }
  ix = static_cast<int>(fx);
  iy = static_cast<int>(fy);
  return true;
}

bool CoveragePlanner::seed(const Pose& pose, int& sx, int& sy) const
{
  int cx = 0, cy = 0;
  if (!cellOf(pose.x, pose.y, cx, cy))
  {
    return false;
  }
  const int reach = static_cast<int>(std::ceil(kSeedRadius / resolution_));
  double best = std::numeric_limits<double>::infinity();
  for (int dy = -reach; dy <= reach; ++dy)
  {
    for (int dx = -reach; dx <= reach; ++dx)
    {
      const double d = std::hypot(dx, dy);
      if (d < best && inside(cx + dx, cy + dy) && pass_[index(cx + dx, cy + dy)] > 0)
      {
        best = d;
        sx = cx + dx;
        sy = cy + dy;
      }
    }
  }
  return best * resolution_ <= kSeedRadius;
}

void CoveragePlanner::flood(int sx, int sy)
{
  // Through known free and unknown cells that keep the centre clearance (as the planner plans
  // through unknown space); only the known free ones become centre cells.
  std::fill(dist_.begin(), dist_.end(), -1);
  queue_.clear();
  dist_[index(sx, sy)] = 0;
  queue_.push_back(static_cast<std::uint32_t>(index(sx, sy)));
  for (std::size_t head = 0; head < queue_.size(); ++head)
  {
    const std::uint32_t i = queue_[head];
    const int ix = static_cast<int>(i % n_);
    const int iy = static_cast<int>(i / n_);
    for (int dy = -1; dy <= 1; ++dy)
    {
      for (int dx = -1; dx <= 1; ++dx)
      {
        if (inside(ix + dx, iy + dy) && pass_[index(ix + dx, iy + dy)] > 0 && dist_[index(ix + dx, iy + dy)] < 0)
        {
          dist_[index(ix + dx, iy + dy)] = dist_[i] + 1;
          queue_.push_back(static_cast<std::uint32_t>(index(ix + dx, iy + dy)));
        }
      }
    }
  }
  std::fill(floor_.begin(), floor_.end(), FloorCell::None);
  centres_.clear();
  for (const std::uint32_t i : queue_)
  {
    if (pass_[i] == 2)
    {
      floor_[i] = FloorCell::Centre;
      centres_.push_back(i);
    }
  }
}

void CoveragePlanner::sweepFloor()
{
  for (const std::uint32_t i : centres_)
  {
    const int ix = static_cast<int>(i % n_);
    const int iy = static_cast<int>(i / n_);
    ring_[i] = planner_.clearance(ix, iy) < centre_clearance_ + resolution_ ? 1 : 0;
    for (const auto& o : disc_)
    {
      const int x = ix + o.first;
      const int y = iy + o.second;
      if (inside(x, y) && floor_[index(x, y)] == FloorCell::None && cells_[index(x, y)] == Cell::Free)
      {
        floor_[index(x, y)] = FloorCell::Swept;
      }
    }
  }
}

void CoveragePlanner::gains(const CoverageGrid& coverage)
{
  std::fill(gain_.begin(), gain_.end(), 0);
  for (const std::uint32_t i : centres_)
  {
    if (blocked_[i])
    {
      continue;
    }
    const int ix = static_cast<int>(i % n_);
    const int iy = static_cast<int>(i / n_);
    int g = 0;
    for (const auto& o : ring_[i] ? disc_ : inner_)  // edge passes are for the rim along obstacles
    {
      const int x = ix + o.first;
      const int y = iy + o.second;
      g += inside(x, y) && floor_[index(x, y)] != FloorCell::None && !coverage.covered(x, y);
    }
    gain_[i] = static_cast<std::uint16_t>(g);
  }
}

void CoveragePlanner::update(const NavGrid& grid, const CoverageGrid& coverage, const Pose& pose, double now)
{
  if (grid.width() != n_ || coverage.width() != n_)
  {
    throw std::invalid_argument("CoveragePlanner: a map of " + std::to_string(grid.width()) + " and a coverage of " +
                                std::to_string(coverage.width()) + " cells per side, the planner was made for " +
                                std::to_string(n_));
  }
  resolution_ = grid.params().resolution;
  origin_x_ = grid.originX();
  origin_y_ = grid.originY();
  centre_clearance_ = params_.centreClearance(resolution_);
  if (offsets_resolution_ != resolution_)
  {
    const double r = params_.planner.robot_radius;
    near_ = cellsWithin(0.0, centre_clearance_ - 1e-9, resolution_);
    disc_ = cellsWithin(0.0, r, resolution_);
    inner_ = cellsWithin(0.0, r - kTrackMargin, resolution_);
    view_ = cellsWithin(params_.view_min, params_.view_max, resolution_);
    offsets_resolution_ = resolution_;
  }
  planner_.update(grid, now);
  grid.snapshot(now, cells_);
  for (int iy = 0; iy < n_; ++iy)
  {
    for (int ix = 0; ix < n_; ++ix)
    {
      const Cell c = cells_[index(ix, iy)];
      const bool clear = planner_.clearance(ix, iy) >= centre_clearance_ - 1e-6;
      pass_[index(ix, iy)] = !clear ? 0 : c == Cell::Free ? (nearUnknown(ix, iy) ? 1 : 2) : c == Cell::Unknown ? 1 : 0;
    }
  }
  int sx = 0;
  int sy = 0;
  if (!std::isfinite(pose.x) || !std::isfinite(pose.y) || !seed(pose, sx, sy))
  {
    std::fill(floor_.begin(), floor_.end(), FloorCell::None);
    std::fill(gain_.begin(), gain_.end(), 0);
    queue_.clear();
    centres_.clear();
    return;
  }
  flood(sx, sy);
  sweepFloor();
  gains(coverage);
}

bool CoveragePlanner::nearUnknown(int ix, int iy) const
{
  for (const auto& o : near_)
  {
    const int x = ix + o.first;
    const int y = iy + o.second;
    if (inside(x, y) && cells_[index(x, y)] == Cell::Unknown)
    {
      return true;
    }
  }
  return false;
}

int CoveragePlanner::gain(int ix, int iy) const
{
  return inside(ix, iy) ? gain_[index(ix, iy)] : 0;
}

void CoveragePlanner::offered(std::size_t i)
{
  if (++offers_[i] >= kMaxOffers)
  {
    blocked_[i] = 1;
  }
}

void CoveragePlanner::markAround(std::vector<std::uint8_t>& mask, double x, double y, double radius)
{
  const int reach = static_cast<int>(std::ceil(radius / resolution_));
  int cx = 0, cy = 0;
  if (!cellOf(x, y, cx, cy))
  {
    return;
  }
  for (int dy = -reach; dy <= reach; ++dy)
  {
    for (int dx = -reach; dx <= reach; ++dx)
    {
      if (inside(cx + dx, cy + dy) && std::hypot(dx, dy) * resolution_ <= radius)
      {
        mask[index(cx + dx, cy + dy)] = 1;
      }
    }
  }
}

void CoveragePlanner::failed(const NavGoal& goal)
{
  if (std::isfinite(goal.x) && std::isfinite(goal.y))
  {
    markAround(blocked_, goal.x, goal.y, kFailRadius);
  }
}

void CoveragePlanner::forgetOffers()
{
  std::fill(blocked_.begin(), blocked_.end(), 0);
  std::fill(offers_.begin(), offers_.end(), 0);
}

void CoveragePlanner::emit(const NavGrid& grid, const std::vector<std::size_t>& cells, double spacing,
                           CoverageTarget& out)
{
  double along = 0.0;
  double last = -spacing;
  for (std::size_t k = 0; k < cells.size(); ++k)
  {
    if (k > 0)
    {
      const int ddx = static_cast<int>(cells[k] % n_) - static_cast<int>(cells[k - 1] % n_);
      const int ddy = static_cast<int>(cells[k] / n_) - static_cast<int>(cells[k - 1] / n_);
      along += std::hypot(ddx, ddy) * resolution_;
    }
    // Intermediate goals only near obstacles, where the planner's clearance cost would bend a long
    // straight path away from the lane; in open space the path is straight anyway, and each goal
    // costs a stop.
    const int ix = static_cast<int>(cells[k] % n_);
    const int iy = static_cast<int>(cells[k] / n_);
    const bool open = planner_.clearance(ix, iy) >= params_.planner.inflation_radius - 1e-6;
    if ((along - last >= spacing - 1e-9 && !open) || k == 0 || k + 1 == cells.size())
    {
      NavGoal g;
      g.x = grid.centerX(ix);
      g.y = grid.centerY(iy);
      out.goals.push_back(g);
      last = along;
    }
  }
  offered(cells.front());
  offered(cells.back());
}

bool CoveragePlanner::lane(const NavGrid& grid, CoverageTarget& out)
{
  const int step = std::max(1, static_cast<int>(std::floor(params_.lane_spacing / resolution_ + 1e-6)));
  const double diameter = 2.0 * params_.planner.robot_radius / resolution_;  // cells a disc stays on a cell
  std::int32_t best = std::numeric_limits<std::int32_t>::max();
  std::vector<std::size_t> cells;
  std::vector<std::size_t> best_cells;
  auto close = [&](double sum)
  {
    while (!cells.empty() && gain_[cells.back()] == 0)
    {
      cells.pop_back();
    }
    const bool gains = !cells.empty() && sum / diameter >= params_.min_gain;
    if (gains && std::min(dist_[cells.front()], dist_[cells.back()]) < best)
    {
      best = std::min(dist_[cells.front()], dist_[cells.back()]);
      best_cells = cells;
      out.gain = static_cast<int>(sum / diameter);
    }
    cells.clear();
  };
  for (int row = 0; row < n_; row += step)
  {
    double sum = 0.0;
    int zeros = 0;
    for (int k = 0; k <= n_; ++k)
    {
      const int ix = params_.lanes_along_x ? k : row;
      const int iy = params_.lanes_along_x ? row : k;
      const bool on = k < n_ && centre(ix, iy);
      const int g = on ? gain_[index(ix, iy)] : 0;
      zeros = g > 0 ? 0 : zeros + 1;
      if (!on || zeros >= kSplitCells)
      {
        close(sum);
        sum = 0.0;
        continue;
      }
      if (g > 0 || !cells.empty())
      {
        cells.push_back(index(ix, iy));
        sum += g;
      }
    }
  }
  if (best_cells.empty())
  {
    return false;
  }
  if (dist_[best_cells.back()] < dist_[best_cells.front()])
  {
    std::reverse(best_cells.begin(), best_cells.end());
  }
  out.mode = CoverageMode::LANE;
  emit(grid, best_cells, params_.waypoint_spacing, out);
  return true;
}

std::vector<std::size_t> CoveragePlanner::trace(std::size_t start) const
{
  std::vector<std::size_t> path{ start };
  const int max_cells = static_cast<int>(params_.edge_length / resolution_);
  int pdx = 0;
  int pdy = 0;
  int zeros = 0;
  while (static_cast<int>(path.size()) < max_cells && zeros < kSplitCells)
  {
    const int ix = static_cast<int>(path.back() % n_);
    const int iy = static_cast<int>(path.back() / n_);
    double best = -1e9;
    int bdx = 0;
    int bdy = 0;
    for (int dy = -1; dy <= 1; ++dy)
    {
      for (int dx = -1; dx <= 1; ++dx)
      {
        if ((dx == 0 && dy == 0) || !centre(ix + dx, iy + dy) || !ring_[index(ix + dx, iy + dy)] ||
            std::find(path.begin(), path.end(), index(ix + dx, iy + dy)) != path.end())
        {
          continue;
        }
        // Prefer gaining cells, then going straight on, then orthogonal steps (a thin contour).
        const double score =
            (gain_[index(ix + dx, iy + dy)] > 0 ? 10.0 : 0.0) + (dx * pdx + dy * pdy) - 0.1 * std::abs(dx * dy);
        if (score > best)
        {
          best = score;
          bdx = dx;
          bdy = dy;
        }
      }
    }
    if (best < -1e8)
    {
      break;
    }
    path.push_back(index(ix + bdx, iy + bdy));
    zeros = gain_[path.back()] > 0 ? 0 : zeros + 1;
    pdx = bdx;
    pdy = bdy;
  }
  while (path.size() > 1 && gain_[path.back()] == 0)
  {
    path.pop_back();
  }
  return path;
}

bool CoveragePlanner::edge(const NavGrid& grid, CoverageTarget& out)
{
  const double diameter = 2.0 * params_.planner.robot_radius / resolution_;
  std::vector<std::size_t> skipped;
  int tries = 0;
  for (const std::uint32_t i : centres_)
  {
    if (!ring_[i] || gain_[i] == 0 || std::find(skipped.begin(), skipped.end(), i) != skipped.end())
    {
      continue;
    }
    const std::vector<std::size_t> path = trace(i);
    double sum = 0.0;
    for (const std::size_t c : path)
    {
      sum += gain_[c];
    }
    if (sum / diameter >= params_.min_gain)
    {
      out.mode = CoverageMode::EDGE;
      out.gain = static_cast<int>(sum / diameter);
      out.speed_limit = params_.edge_speed;
      emit(grid, path, 0.3 * params_.waypoint_spacing, out);  // close: pure pursuit cuts corners
      return true;
    }
    skipped.insert(skipped.end(), path.begin(), path.end());
    if (++tries >= kEdgeTries)
    {
      break;
    }
  }
  return false;
}

bool CoveragePlanner::spot(const NavGrid& grid, CoverageTarget& out)
{
  for (const std::uint32_t i : centres_)
  {
    if (gain_[i] >= params_.min_gain)
    {
      out.mode = CoverageMode::SPOT;
      out.gain = gain_[i];
      emit(grid, { i }, params_.waypoint_spacing, out);
      return true;
    }
  }
  return false;
}

bool CoveragePlanner::roam(const NavGrid& grid, const Pose& pose, CoverageTarget& out)
{
  // Long legs ahead: the robot drives them without stopping, at the speed the known floor allows,
  // and turns in place only where nothing is left ahead.
  const double leg = params_.roam_leg;
  const double full = static_cast<double>(std::max<std::size_t>(disc_.size(), 1));
  double best = -std::numeric_limits<double>::infinity();
  std::size_t pick = 0;
  for (const std::uint32_t i : centres_)
  {
    const double d = dist_[i] * resolution_;  // flood steps: about the path's length
    if (blocked_[i] || gain_[i] < params_.min_gain || d < kRoamMin)
    {
      continue;
    }
    const double x = grid.centerX(static_cast<int>(i % n_));
    const double y = grid.centerY(static_cast<int>(i / n_));
    const double turn = std::abs(wrapAngle(std::atan2(y - pose.y, x - pose.x) - pose.yaw));
    const double base = std::min(d, 2.0 * leg) / leg + gain_[i] / full - kRoamTurnWeight * turn / M_PI;
    if (base <= best)
    {
      continue;
    }
    // Unknown floor on the way is looked at, and crept over: a leg over known floor is driven at speed.
    const double score = base - kRoamUnknownWeight * unknownShare(pose.x, pose.y, x, y);
    if (score > best)
    {
      best = score;
      pick = i;
    }
  }
  if (!std::isfinite(best))
  {
    return false;
  }
  out.mode = CoverageMode::ROAM;
  out.gain = gain_[pick];
  emit(grid, { pick }, params_.waypoint_spacing, out);
  return true;
}

double CoveragePlanner::unknownShare(double x0, double y0, double x1, double y1) const
{
  // The centre line and both sides of the disc, sampled every cell.
  const double length = std::hypot(x1 - x0, y1 - y0);
  const int steps = std::max(1, static_cast<int>(std::ceil(length / resolution_)));
  const double side = params_.planner.robot_radius;
  const double nx = length > 0.0 ? -(y1 - y0) / length : 0.0;
  const double ny = length > 0.0 ? (x1 - x0) / length : 0.0;
  int unknown = 0;
  int samples = 0;
  for (int k = 1; k <= steps; ++k)
  {
    const double t = static_cast<double>(k) / steps;
    for (const double o : { -side, 0.0, side })
    {
      int ix = 0, iy = 0;
      if (cellOf(x0 + t * (x1 - x0) + o * nx, y0 + t * (y1 - y0) + o * ny, ix, iy) && inside(ix, iy))
      {
        unknown += cells_[index(ix, iy)] == Cell::Unknown;
        ++samples;
      }
    }
  }
  return samples > 0 ? static_cast<double>(unknown) / samples : 0.0;
}

bool CoveragePlanner::sight(int x0, int y0, int x1, int y1) const
{
  const int steps = 2 * std::max(std::abs(x1 - x0), std::abs(y1 - y0));
  for (int k = 1; k < steps; ++k)
  {
    const double t = static_cast<double>(k) / steps;
    const int x = static_cast<int>(std::lround(x0 + t * (x1 - x0)));
    const int y = static_cast<int>(std::lround(y0 + t * (y1 - y0)));
    if (cells_[index(x, y)] == Cell::Occupied)
    {
      return false;
    }
  }
  return true;
}

void CoveragePlanner::unknownNormal(int ix, int iy, int& nx, int& ny) const
{
  static const int kSteps[4][2] = { { -1, 0 }, { 1, 0 }, { 0, -1 }, { 0, 1 } };
  for (const auto& d : kSteps)
  {
    if (inside(ix + d[0], iy + d[1]) && cells_[index(ix + d[0], iy + d[1])] == Cell::Unknown)
    {
      nx += d[0];
      ny += d[1];
    }
  }
}

bool CoveragePlanner::frontier(const NavGrid& grid, CoverageTarget& out)
{
  const auto& ring = view_;
  std::int32_t best = std::numeric_limits<std::int32_t>::max();
  int fx = 0, fy = 0, vx = 0, vy = 0;
  for (int iy = 0; iy < n_; ++iy)
  {
    for (int ix = 0; ix < n_; ++ix)
    {
      if (tried_[index(ix, iy)] || cells_[index(ix, iy)] != Cell::Free)
      {
        continue;
      }
      // The frontier's normal: toward its unknown neighbours. It is looked at along the normal
      // (within 60 degrees), so that the camera's ray goes on into the unknown.
      int nx = 0, ny = 0;
      unknownNormal(ix, iy, nx, ny);
      const double norm = std::hypot(nx, ny);
      for (std::size_t k = 0; norm > 0.0 && k < ring.size(); ++k)
      {
        const int x = ix - ring[k].first;
        const int y = iy - ring[k].second;
        const double along = (ring[k].first * nx + ring[k].second * ny) / norm;
        if (along >= 0.5 * std::hypot(ring[k].first, ring[k].second) && centre(x, y) && !blocked_[index(x, y)] &&
            dist_[index(x, y)] < best && sight(x, y, ix, iy))
        {
          best = dist_[index(x, y)];
          fx = ix, fy = iy, vx = x, vy = y;
        }
      }
    }
  }
  if (best == std::numeric_limits<std::int32_t>::max())
  {
    return false;
  }
  NavGoal g;
  g.x = grid.centerX(vx);
  g.y = grid.centerY(vy);
  g.yaw = std::atan2(grid.centerY(fy) - g.y, grid.centerX(fx) - g.x);
  g.use_yaw = true;
  out.mode = CoverageMode::FRONTIER;
  out.goals.push_back(g);
  offered(index(vx, vy));
  pending_frontier_ = true;
  frontier_seen_.x = grid.centerX(fx);
  frontier_seen_.y = grid.centerY(fy);
  return true;
}

bool CoveragePlanner::frontierNear(const Pose& pose, double radius) const
{
  const int reach = static_cast<int>(std::ceil(radius / resolution_));
  int cx = 0, cy = 0;
  if (!cellOf(pose.x, pose.y, cx, cy))
  {
    return false;
  }
  for (int iy = cy - reach; iy <= cy + reach; ++iy)
  {
    for (int ix = cx - reach; ix <= cx + reach; ++ix)
    {
      int nx = 0, ny = 0;
      if (inside(ix, iy) && cells_[index(ix, iy)] == Cell::Free && !tried_[index(ix, iy)] &&
          std::hypot(ix - cx, iy - cy) * resolution_ <= radius)
      {
        unknownNormal(ix, iy, nx, ny);
        if (nx != 0 || ny != 0)
        {
          return true;
        }
      }
    }
  }
  return false;
}

bool CoveragePlanner::lookAround(const Pose& pose, CoverageTarget& out)
{
  if (!std::isfinite(pose.x) || !std::isfinite(pose.y) || !frontierNear(pose, params_.view_max))
  {
    return false;
  }
  for (const Point& p : looked_around_)
  {
    if (std::hypot(p.x - pose.x, p.y - pose.y) < kLookAroundSpacing)
    {
      return false;
    }
  }
  looked_around_.push_back(Point{ pose.x, pose.y });
  for (int k = 1; k <= 3; ++k)
  {
    NavGoal g;
    g.x = pose.x;
    g.y = pose.y;
    g.yaw = wrapAngle(pose.yaw + k * 2.0 * M_PI / 3.0);
    g.use_yaw = true;
    out.goals.push_back(g);
  }
  out.mode = CoverageMode::FRONTIER;
  return true;
}

CoverageTarget CoveragePlanner::next(const NavGrid& grid, const CoverageGrid& coverage, const Pose& pose, double now)
{
  update(grid, coverage, pose, now);
  if (pending_frontier_)
  {
    markAround(tried_, frontier_seen_.x, frontier_seen_.y, kTriedRadius);
    pending_frontier_ = false;
  }
  CoverageTarget out;
  const bool found = params_.roam          ? roam(grid, pose, out)
                     : params_.edges_first ? (edge(grid, out) || lane(grid, out) || spot(grid, out))
                                           : (lane(grid, out) || edge(grid, out) || spot(grid, out));
  if (!found && !frontier(grid, out) && !lookAround(pose, out))
  {
    out = CoverageTarget();
  }
  std::size_t covered = 0;
  std::size_t cells = 0;
  const double p = coverage.progress(floor_, &covered, &cells);
  char text[200];
  std::snprintf(text, sizeof(text), "%s: %zu goals, gain %d cells; covered %zu of %zu floor cells (%.1f %%)",
                toString(out.mode), out.goals.size(), out.gain, covered, cells, 100.0 * p);
  out.text = text;
  return out;
}

CoverageRunner::CoverageRunner(const NavigatorParams& nav, const CoverageParams& coverage)
  : nav_(nav),
    planner_(
        [&]
        {
          CoverageParams c = coverage;
          c.planner = nav.planner;  // the same disc and lethal distance as the navigator's
          return c;
        }(),
        nav_.grid().width()),
    coverage_(nav_.grid(), nav.planner.robot_radius)
{
}

bool CoverageRunner::onMap(const OccupancyView& view, double stamp)
{
  const bool first = !nav_.hasMap();
  const bool ok = nav_.onMap(view, stamp);
  if (first && nav_.hasMap())
  {
    coverage_.reset(nav_.grid());  // the map was placed around the first window
  }
  return ok;
}

bool CoverageRunner::nextGoal(const Pose& pose, double now)
{
  bool renewed = false;
  for (int attempt = 0; attempt < 50; ++attempt)
  {
    if (goal_index_ >= target_.goals.size())
    {
      target_ = planner_.next(nav_.grid(), coverage_, pose, now);
      measure(now);
      ++targets_[static_cast<int>(target_.mode)];
      goal_index_ = 0;
      if (target_.mode == CoverageMode::DONE && planner_.params().roam && !renewed && progress_ >= kRenewShare)
      {
        // Roaming does not end: the floor known was driven over, so a new round begins.
        coverage_.reset(nav_.grid());
        planner_.forgetOffers();
        ++rounds_;
        renewed = true;
        continue;
      }
      if (target_.mode == CoverageMode::DONE)
      {
        return false;
      }
    }
    const NavGoal& goal = target_.goals[goal_index_++];
    if (nav_.setGoal(goal, now).empty())
    {
      goal_stucks_ = nav_.stucks();
      return true;
    }
    planner_.failed(goal);
    goal_index_ = target_.goals.size();
  }
  return false;
}

double CoverageRunner::obstacleDistance(double x, double y, double now, double reach) const
{
  const NavGrid& g = nav_.grid();
  const int cells = static_cast<int>(std::ceil(reach / g.params().resolution));
  const int cx = g.indexX(x);
  const int cy = g.indexY(y);
  double best = reach;
  for (int iy = cy - cells; iy <= cy + cells; ++iy)
  {
    for (int ix = cx - cells; ix <= cx + cells; ++ix)
    {
      if (g.cell(ix, iy, now) == Cell::Occupied)
      {
        best = std::min(best, std::hypot(g.centerX(ix) - x, g.centerY(iy) - y));
      }
    }
  }
  return best;
}

bool CoverageRunner::safe(const Pose& pose, double v, double w, double now) const
{
  const double limit = nav_.params().planner.robot_radius + kGuardMargin;
  const double here = obstacleDistance(pose.x, pose.y, now, limit + 0.05);
  Pose p = pose;
  for (int k = 0; k < 10; ++k)
  {
    p.x += v * std::cos(p.yaw + 0.025 * w) * 0.05;
    p.y += v * std::sin(p.yaw + 0.025 * w) * 0.05;
    p.yaw += w * 0.05;
    const double d = obstacleDistance(p.x, p.y, now, limit + 0.05);
    if (d < limit && d < here - 1e-3)
    {
      return false;
    }
  }
  return true;
}

bool CoverageRunner::startEscape(const Pose& pose, double now)
{
  const NavGrid& g = nav_.grid();
  const int cells = static_cast<int>(std::ceil(kEscapeReach / g.params().resolution));
  double best = kEscapeReach;
  double ax = 0.0, ay = 0.0;
  for (int iy = g.indexY(pose.y) - cells; iy <= g.indexY(pose.y) + cells; ++iy)
  {
    for (int ix = g.indexX(pose.x) - cells; ix <= g.indexX(pose.x) + cells; ++ix)
    {
      const double d = std::hypot(g.centerX(ix) - pose.x, g.centerY(iy) - pose.y);
      if (d < best && g.cell(ix, iy, now) == Cell::Occupied)
      {
        best = d;
        ax = pose.x - g.centerX(ix);
        ay = pose.y - g.centerY(iy);
      }
    }
  }
  if (best >= kEscapeReach)
  {
    return false;
  }
  escape_yaw_ = std::atan2(ay, ax);
  escape_phase_ = 1;
  escape_start_ = now;
  ++escapes_;
  return true;
}

bool CoverageRunner::escape(const Pose& pose, double now)
{
  out_.state = NavState::ACTIVE;
  out_.command = true;
  out_.linear = 0.0;
  out_.angular = 0.0;
  const double error = wrapAngle(escape_yaw_ - pose.yaw);
  if (escape_phase_ == 1 && std::abs(error) > 0.15 && now - escape_start_ < 10.0)
  {
    out_.angular = turnRate(error, nav_.params().follower.turn_speed);
    out_.reason = "coverage: blocked, turning away from the nearest obstacle";
    return true;
  }
  if (escape_phase_ == 1)
  {
    escape_phase_ = 2;
    escape_from_ = pose;
    escape_start_ = now;
  }
  const bool far = std::hypot(pose.x - escape_from_.x, pose.y - escape_from_.y) >= kEscapeDistance;
  if (far || now - escape_start_ > 6.0 || !safe(pose, kEscapeSpeed, 0.0, now))
  {
    escape_phase_ = 0;
    return false;
  }
  out_.linear = kEscapeSpeed;
  out_.reason = "coverage: blocked, creeping away from the nearest obstacle";
  return true;
}

void CoverageRunner::dropTarget()
{
  if (goal_index_ > 0)
  {
    planner_.failed(target_.goals[goal_index_ - 1]);
  }
  goal_index_ = target_.goals.size();
}

void CoverageRunner::measure(double now)
{
  std::size_t floor_cells = 0;
  progress_ = coverage_.progress(planner_.floor(), nullptr, &floor_cells);
  const double res = nav_.grid().params().resolution;
  floor_area_ = static_cast<double>(floor_cells) * res * res;
  progress_time_ = now;
}

std::string CoverageRunner::summary() const
{
  char text[160];
  const char* what = done_ ? "DONE" : (started_ ? toString(target_.mode) : "waiting for the map");
  if (planner_.params().roam)
  {
    std::snprintf(text, sizeof(text), "roaming: %.1f %% of %.2f m2 reachable floor driven over in round %d, %s",
                  100.0 * progress_, floor_area_, rounds_ + 1, what);
  }
  else
  {
    std::snprintf(text, sizeof(text), "coverage %.1f %% of %.2f m2 reachable floor, %s", 100.0 * progress_, floor_area_,
                  what);
  }
  return text;
}

const NavOutput& CoverageRunner::step(const Pose& pose, double now, double dt, double speed_cap)
{
  if (!nav_.hasMap() || !std::isfinite(pose.x) || !std::isfinite(pose.y) || !std::isfinite(pose.yaw))
  {
    coverage_.addPose(pose);  // a bad pose breaks the coverage's segment
    escape_phase_ = 0;
    out_ = nav_.step(pose, now);
    return out_;
  }
  coverage_.addPose(pose);
  if (escape_phase_ != 0 && escape(pose, now))
  {
    return out_;
  }
  const bool roaming = planner_.params().roam;
  if (!done_ && (!started_ || nav_.state() != NavState::ACTIVE) && (!roaming || now - retry_time_ >= 1.0))
  {
    if (started_ && nav_.state() == NavState::ABORTED && goal_index_ > 0)
    {
      dropTarget();
    }
    started_ = true;
    // Roaming never ends DONE: with nothing to go to (yet), it asks again a second later.
    const bool more = nextGoal(pose, now);
    done_ = !more && !roaming;
    retry_time_ = more ? -std::numeric_limits<double>::infinity() : now;
  }
  if (now - progress_time_ >= 2.0)
  {
    planner_.update(nav_.grid(), coverage_, pose, now);
    measure(now);
  }
  const double edge_cap = target_.mode == CoverageMode::EDGE && !done_
                              ? std::max(0.0, target_.speed_limit - nav_.params().follower.acceleration * dt)
                              : std::numeric_limits<double>::infinity();
  out_ = nav_.step(pose, now, std::min(edge_cap, speed_cap));
  if (roaming && target_.mode == CoverageMode::ROAM && out_.state == NavState::ACTIVE)
  {
    if (nav_.stucks() != goal_stucks_ && goal_index_ > 0)
    {
      // The safety filter holds the robot on this leg: another leg, rather than looking around
      // and backing off for a goal that is only one of many.
      dropTarget();
      nav_.cancel(now, "roam: stuck on this leg");
    }
    else if (goal_index_ >= target_.goals.size() && out_.remaining < kHandover)
    {
      nextGoal(pose, now);  // the next leg before this one's end: no stop between legs
    }
  }
  const bool guarded = out_.linear > 0.0 && !safe(pose, out_.linear, out_.angular, now);
  watchBlocked(pose, now, guarded);
  if (guarded && escape_phase_ == 0)
  {
    out_.linear = 0.0;  // the arc would cut toward a known obstacle: turn toward the path first
    out_.reason = "coverage guard: forward motion stopped near a known obstacle; " + out_.reason;
  }
  return out_;
}

void CoverageRunner::watchBlocked(const Pose& pose, double now, bool guarded)
{
  if (out_.state != NavState::ACTIVE || (out_.mode != FollowMode::BLOCKED && !guarded))
  {
    blocked_since_ = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  if (std::isnan(blocked_since_))
  {
    blocked_since_ = now;
  }
  if (now - blocked_since_ >= kBlockedTime && startEscape(pose, now))
  {
    blocked_since_ = std::numeric_limits<double>::quiet_NaN();
    dropTarget();
    nav_.cancel(now, "coverage: blocked");
    escape(pose, now);
  }
}
}  // namespace sl_navigation
