#include "sl_obstacle/path_checker.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "slab.h"
#include "validation.h"

namespace sl_obstacle
{
namespace
{
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kMaxHeadingSteps = 360;

/// A closed interval of x (m); empty when lo > hi.
struct Span
{
  double lo = kInf;
  double hi = -kInf;
  void unite(double a, double b)
  {
    if (a <= b)
    {
      lo = std::min(lo, a);
      hi = std::max(hi, b);
    }
  }
};

/// Narrows [lo, hi] (values of px) to a * px + b in [min, max]; empty: lo = inf, hi = -inf.
void narrow(double a, double b, double min, double max, double& lo, double& hi)
{
  if (!detail::clipSlab(b, a, min, max, lo, hi))
  {
    lo = kInf;
    hi = -kInf;
  }
}

/// The straight sweep: segment from (ax, ay) along the unit vector (ux, uy) for length, radius r.
struct Sweep
{
  double ax, ay, ux, uy, length, r;

  /// x-range of the points of the line y = yc within r of the segment (a convex stadium).
  Span spanAt(double yc) const
  {
    Span s;
    discSpan(ax, ay, yc, s);
    discSpan(ax + length * ux, ay + length * uy, yc, s);
    // The rectangle: along = px ux + py uy in [0, length], lateral = ux py - uy px in [-r, r].
    const double py = yc - ay;
    double lo = -kInf, hi = kInf;
    narrow(ux, py * uy, 0.0, length, lo, hi);
    narrow(-uy, ux * py, -r, r, lo, hi);
    s.unite(ax + lo, ax + hi);
    return s;
  }

  /// Unites @p s with the x-range of the line y = yc inside the disc of radius r around (cx, cy).
  void discSpan(double cx, double cy, double yc, Span& s) const
  {
    const double dy = yc - cy;
    if (std::fabs(dy) <= r)
    {
      const double w = std::sqrt(r * r - dy * dy);
      s.unite(cx - w, cx + w);
    }
  }
};

/// Accumulates the swept cells into a PathResult; @p far: the cell lies beyond the blind radius.
void account(const CellInfo& cell, double entry, bool far, PathResult& out, int& known)
{
  ++out.swept_cells;
  if (!cell.trail)
  {
    out.off_trail = std::min(out.off_trail, entry);
  }
  if (cell.state == CellState::Occupied)
  {
    out.obstacle = std::min(out.obstacle, entry);
    ++known;
  }
  else if (cell.state == CellState::Unknown)
  {
    out.unknown = std::min(out.unknown, entry);
    if (cell.evidence)
    {
      out.evidence = std::min(out.evidence, entry);
    }
    else if (far)
    {
      out.unseen_far = std::min(out.unseen_far, entry);
    }
  }
  else
  {
    ++known;
  }
}
}  // namespace

void FootprintParams::validate() const
{
  detail::requireInRange("radius", radius, 1e-3, 2.0);
  detail::requireInRange("lateral_margin", lateral_margin, 0.0, 1.0);
}

PathResult sweepStraight(const LocalMap& map, const FootprintParams& fp, double x, double y, double yaw, int direction,
                         double max_distance, double now, double blind_radius)
{
  if (direction != 1 && direction != -1)
  {
    throw std::invalid_argument("direction must be +1 or -1 (got " + std::to_string(direction) + ")");
  }
  if (!std::isfinite(max_distance) || max_distance < 0.0)
  {
    throw std::invalid_argument(detail::complaint("max_distance", "must be finite and >= 0", max_distance));
  }
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(yaw))
  {
    throw std::invalid_argument("pose must be finite");
  }
  const double r = fp.sweptRadius();
  const Sweep sw{ x, y, direction * std::cos(yaw), direction * std::sin(yaw), max_distance, r };
  const double res = map.params().resolution;
  const double r2 = r * r;
  PathResult out;
  int known = 0;
  const double by = y + max_distance * sw.uy;
  for (int iy = map.cellIndex(std::min(y, by) - r), y_end = map.cellIndex(std::max(y, by) + r); iy <= y_end; ++iy)
  {
    const double yc = (iy + 0.5) * res;
    const Span span = sw.spanAt(yc);
    if (span.lo > span.hi)
    {
      continue;
    }
    const double py = yc - y;
    for (int ix = map.cellIndex(span.lo) - 1, x_end = map.cellIndex(span.hi) + 1; ix <= x_end; ++ix)
    {
      const double px = (ix + 0.5) * res - x;
      const double d2 = px * px + py * py;
      const double along = px * sw.ux + py * sw.uy;
      const double lateral2 = d2 - along * along;
      if (d2 <= r2 || lateral2 > r2)
      {
        continue;  // under the current disc, or never reached
      }
      const double entry = along - std::sqrt(r2 - lateral2);
      if (entry <= 0.0 || entry > max_distance)
      {
        continue;
      }
      account(map.cellInfo(ix, iy, now), entry, d2 > blind_radius * blind_radius, out, known);
    }
  }
  out.free = std::min(max_distance, std::min(out.obstacle, out.unknown));
  out.known_fraction = out.swept_cells > 0 ? static_cast<double>(known) / out.swept_cells : 1.0;
  return out;
}

bool centreLineSeen(const LocalMap& map, double x, double y, double yaw, double radius, double from, double to,
                    double now)
{
  const double step = 0.25 * map.params().resolution;
  const double c = std::cos(yaw);
  const double s = std::sin(yaw);
  for (double d = radius + from; d <= radius + to + 1e-9; d += step)
  {
    const CellState state = map.state(x + d * c, y + d * s, now);
    if (state != CellState::Free)
    {
      return state == CellState::Occupied;  // behind an obstacle lies its shadow
    }
  }
  return true;
}

HeadingChoice bestHeading(const LocalMap& map, const FootprintParams& fp, double x, double y, double yaw, double step,
                          int n, double max_distance, double now)
{
  if (n < 0 || n > kMaxHeadingSteps)
  {
    throw std::invalid_argument(detail::complaint("n", "must be in [0, 360]", n));
  }
  if (!std::isfinite(step))
  {
    throw std::invalid_argument(detail::complaint("step", "must be finite", step));
  }
  // Order of preference: 0, +1, -1, +2, -2, ... (smallest |turn| first, left before right).
  std::array<double, 2 * kMaxHeadingSteps + 1> free{};
  double best = -kInf;
  for (int i = 0; i <= 2 * n; ++i)
  {
    const int k = (i + 1) / 2 * (i % 2 == 1 ? 1 : -1);
    free[i] = sweepStraight(map, fp, x, y, yaw + k * step, 1, max_distance, now).free;
    best = std::max(best, free[i]);
  }
  const double tolerance = map.params().resolution;
  for (int i = 0; i <= 2 * n; ++i)
  {
    if (free[i] >= best - tolerance)
    {
      HeadingChoice c;
      c.turn = ((i + 1) / 2 * (i % 2 == 1 ? 1 : -1)) * step;
      c.path = sweepStraight(map, fp, x, y, yaw + c.turn, 1, max_distance, now);
      return c;
    }
  }
  return HeadingChoice();  // not reached: the best heading is within its own tolerance
}
}  // namespace sl_obstacle
