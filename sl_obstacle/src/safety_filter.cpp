#include "sl_obstacle/safety_filter.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "validation.h"

namespace sl_obstacle
{
void toParent(const std::vector<Point2>& points, const Pose2D& frame, std::vector<Point2>& out)
{
  const double c = std::cos(frame.yaw);
  const double s = std::sin(frame.yaw);
  out.clear();
  for (const Point2& p : points)
  {
    out.push_back(Point2{ frame.x + c * p.x - s * p.y, frame.y + s * p.x + c * p.y });
  }
}

void toChild(const std::vector<Point2>& points, const Pose2D& frame, std::vector<Point2>& out)
{
  const double c = std::cos(frame.yaw);
  const double s = std::sin(frame.yaw);
  out.clear();
  for (const Point2& p : points)
  {
    const double dx = p.x - frame.x;
    const double dy = p.y - frame.y;
    out.push_back(Point2{ c * dx + s * dy, -s * dx + c * dy });
  }
}

namespace
{
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kTwoPi = 2.0 * M_PI;
/// Below this speed (m/s) a command does not move the robot forward or back: a turn in place.
constexpr double kStill = 1e-3;
/// |curvature| * length below which an arc is swept as a straight line (m of sideways error ~ 1e-4 * L).
constexpr double kStraight = 1e-4;

bool isStraight(double curvature, double length)
{
  return std::abs(curvature) * length < kStraight;
}

/// Centre of the disc after travel s along the arc, in the robot's frame at the start.
void arcPoint(int direction, double curvature, double s, double& x, double& y)
{
  if (std::abs(curvature) < 1e-12)
  {
    x = direction * s;
    y = 0.0;
    return;
  }
  x = direction * std::sin(curvature * s) / curvature;
  y = direction * (1.0 - std::cos(curvature * s)) / curvature;
}

/// The robot frame's disc-contact travel for one point on a straight line (+inf: never).
double straightContact(const Point2& p, double r, int direction, double length)
{
  const double along = direction * p.x;
  if (along * along + p.y * p.y <= r * r)
  {
    return along > 0.0 ? 0.0 : kInf;  // under the disc now: contact if the motion goes into it
  }
  if (along <= 0.0 || std::abs(p.y) > r)
  {
    return kInf;
  }
  const double e = along - std::sqrt(r * r - p.y * p.y);
  return e <= length ? e : kInf;
}

double wrapPositive(double a)
{
  a = std::fmod(a, kTwoPi);
  return a < 0.0 ? a + kTwoPi : a;
}

double speedFor(double travel, double deceleration)
{
  if (travel <= 0.0)
  {
    return 0.0;
  }
  return deceleration > 0.0 ? std::sqrt(2.0 * deceleration * travel) : kInf;
}
}  // namespace

void FilterParams::validate() const
{
  footprint.validate();
  detail::requireInRange("safety_margin", clearance, 0.0, 2.0);
  detail::requireInRange("obstacle_margin", obstacle_clearance, 0.0, 2.0);
  detail::requireInRange("edge_margin", edge_clearance, 0.0, 2.0);
  detail::requireInRange("edge_speed", edge_speed, 0.0, 0.1);
  detail::requireInRange("deceleration", deceleration, 0.0, 10.0);
  detail::requireInRange("check_distance", horizon, 0.1, 10.0);
  detail::requireInRange("input_timeout", input_timeout, 0.01, 60.0);
  detail::requireInRange("stale_timeout", stale_timeout, 0.01, 60.0);
  detail::requireInRange("creep_speed", creep_speed, 0.0, 0.05);
  detail::requireInRange("creep_view_distance", creep_view, 0.0, 2.0);
}

const char* toString(FilterReason reason)
{
  switch (reason)
  {
    case FilterReason::PASSED:
      return "PASSED";
    case FilterReason::LIMITED:
      return "LIMITED";
    case FilterReason::CREEPING:
      return "CREEPING";
    case FilterReason::STOPPED_OBSTACLE:
      return "STOPPED_OBSTACLE";
    case FilterReason::INPUT_TIMEOUT:
      return "INPUT_TIMEOUT";
    case FilterReason::STALE_DATA:
      return "STALE_DATA";
    case FilterReason::NO_ODOMETRY:
      return "NO_ODOMETRY";
    case FilterReason::INVALID_COMMAND:
      return "INVALID_COMMAND";
  }
  return "?";
}

ArcResult sweepArc(const LocalMap& map, double radius, const Pose2D& pose, int direction, double curvature,
                   double length, double now)
{
  if (direction != 1 && direction != -1)
  {
    throw std::invalid_argument("direction must be +1 or -1 (got " + std::to_string(direction) + ")");
  }
  if (!std::isfinite(curvature) || !std::isfinite(length) || length < 0.0 || !std::isfinite(radius) || radius <= 0.0)
  {
    throw std::invalid_argument("curvature, length and radius must be finite, length >= 0 and radius > 0");
  }
  ArcResult out;
  if (isStraight(curvature, length))
  {
    FootprintParams disc;
    disc.radius = radius;
    disc.lateral_margin = 0.0;
    const PathResult p = sweepStraight(map, disc, pose.x, pose.y, pose.yaw, direction, length, now);
    out.free = p.free;
    out.obstacle = p.obstacle;
    out.unknown = p.unknown;
    out.evidence = p.evidence;
    out.off_trail = p.off_trail;
    return out;
  }
  const double res = map.params().resolution;
  const double ds = 0.25 * res;
  const double r2 = radius * radius;
  const double c = std::cos(pose.yaw);
  const double s = std::sin(pose.yaw);
  double px = pose.x;
  double py = pose.y;
  const int steps = static_cast<int>(std::ceil(length / ds));
  for (int k = 1; k <= steps && !std::isfinite(out.obstacle); ++k)
  {
    double lx = 0.0;
    double ly = 0.0;
    arcPoint(direction, curvature, std::min(k * ds, length), lx, ly);
    const double cx = pose.x + c * lx - s * ly;
    const double cy = pose.y + s * lx + c * ly;
    const double entry = (k - 1) * ds;  // the cell may have been entered just after the last sample
    for (int iy = map.cellIndex(cy - radius), y_end = map.cellIndex(cy + radius); iy <= y_end; ++iy)
    {
      const double yc = (iy + 0.5) * res;
      for (int ix = map.cellIndex(cx - radius), x_end = map.cellIndex(cx + radius); ix <= x_end; ++ix)
      {
        const double xc = (ix + 0.5) * res;
        const auto d2 = [&](double x, double y) { return (xc - x) * (xc - x) + (yc - y) * (yc - y); };
        if (d2(cx, cy) > r2 || d2(px, py) <= r2 || d2(pose.x, pose.y) <= r2)
        {
          continue;  // not under this disc, or counted at an earlier sample, or under the robot now
        }
        const CellInfo cell = map.cellInfo(ix, iy, now);
        if (!cell.trail)
        {
          out.off_trail = std::min(out.off_trail, entry);
        }
        if (cell.state == CellState::Occupied)
        {
          out.obstacle = std::min(out.obstacle, entry);
        }
        else if (cell.state == CellState::Unknown)
        {
          out.unknown = std::min(out.unknown, entry);
          if (cell.evidence)
          {
            out.evidence = std::min(out.evidence, entry);
          }
        }
      }
    }
    px = cx;
    py = cy;
  }
  out.free = std::min(length, std::min(out.obstacle, out.unknown));
  return out;
}

double arcContact(const std::vector<Point2>& points, double radius, int direction, double curvature, double length)
{
  double best = kInf;
  if (isStraight(curvature, length))
  {
    for (const Point2& p : points)
    {
      best = std::min(best, straightContact(p, radius, direction, length));
    }
    return best;
  }
  // The disc's centre turns about the instantaneous centre of curvature (0, icc_y) at radius |icc_y|,
  // its angle there growing by `curvature` per metre of travel.
  const double icc_y = direction / curvature;
  const double ra = std::abs(icc_y);
  const double start_angle = std::atan2(-icc_y, 0.0);
  const double sense = curvature > 0.0 ? 1.0 : -1.0;
  for (const Point2& p : points)
  {
    if (p.x * p.x + p.y * p.y <= radius * radius)
    {
      if (direction * p.x > 0.0)
      {
        return 0.0;  // under the disc and ahead of the motion
      }
      continue;
    }
    const double qx = p.x;
    const double qy = p.y - icc_y;
    const double rho = std::hypot(qx, qy);
    // The centre (on its circle) is within radius of the point while the angle between them is
    // at most half_width (law of cosines).
    const double cos_limit = (ra * ra + rho * rho - radius * radius) / (2.0 * ra * rho);
    if (!(cos_limit < 1.0))
    {
      continue;  // never that close (or rho 0: the point at the centre of curvature)
    }
    const double half_width = cos_limit <= -1.0 ? M_PI : std::acos(cos_limit);
    const double ahead = wrapPositive(sense * (std::atan2(qy, qx) - start_angle));
    const double s = std::max(0.0, ahead - half_width) / std::abs(curvature);
    if (s <= length)
    {
      best = std::min(best, s);
    }
  }
  return best;
}

SafetyFilter::SafetyFilter(const FilterParams& params) : params_(params)
{
  params_.validate();
}

SafetyFilter::Travels SafetyFilter::travels(const LocalMap& map, const FilterInput& in, double v, double w,
                                            double length) const
{
  const int direction = v > 0.0 ? 1 : -1;
  const double curvature = w / std::abs(v);
  const FootprintParams& fp = params_.footprint;
  const double res = map.params().resolution;
  const ArcResult swept = sweepArc(map, fp.sweptRadius(), in.pose, direction, curvature, length, in.now);
  const double cloud =
      in.obstacles != nullptr ? arcContact(*in.obstacles, fp.radius, direction, curvature, length) : kInf;
  Travels t;
  if (direction < 0)
  {
    // Backwards the camera sees nothing: the disc itself only over its trail, the margin beside it
    // over free cells, stopping the margin short of the trail's end.
    const double trail = sweepArc(map, fp.radius, in.pose, direction, curvature, length, in.now).off_trail;
    t.known = std::min({ swept.free, trail, cloud, length }) - fp.lateral_margin;
    t.open = t.known;
    t.edge = t.known;
    return t;
  }
  // Contact is a matter of the disc itself; widened by half a cell's diagonal, a cell counts from
  // its nearest corner (as WorldModel::summarize() does).
  const double body = sweepArc(map, fp.radius + 0.71 * res, in.pose, direction, curvature, length, in.now).obstacle;
  // Where the cloud sees the obstacle the map stops at, its exact distance replaces the cells'; the
  // unknown cells just behind that obstacle (no ray passed it) are reached only through it.
  const bool same = std::isfinite(cloud) && std::abs(body - cloud) <= 3.0 * res;
  const double obstacle = same ? cloud : std::min(swept.obstacle, cloud);
  // Unknown cells from a cell before the obstacle on are its shadow: reached only through it.
  const double shadow = same ? body : obstacle - res;
  // The travel to the first unknown cell counted (@p unknown) less the clearance, or to the obstacle
  // less @p keep, within what was checked.
  const auto travel = [&](double unknown, double keep)
  {
    const double to_unknown = (unknown >= shadow ? kInf : unknown) - params_.clearance;
    return std::min({ to_unknown, std::min(obstacle, length) - keep, length - std::max(params_.clearance, keep) });
  };
  t.known = travel(swept.unknown, params_.obstacle_clearance);
  t.open = travel(swept.evidence, params_.obstacle_clearance);
  t.edge = travel(swept.unknown, params_.edge_clearance);
  return t;
}

double SafetyFilter::travel(const LocalMap& map, const FilterInput& in, double v, double w, double length) const
{
  return travels(map, in, v, w, length).known;
}

double SafetyFilter::openTravel(const LocalMap& map, const FilterInput& in, double v, double w, double length) const
{
  return travels(map, in, v, w, length).open;
}

double SafetyFilter::limitSpeed(const LocalMap& map, const FilterInput& in, double v, double w, FilterOutput& out,
                                bool& creeping, bool& edging) const
{
  const double sign = v > 0.0 ? 1.0 : -1.0;
  const double a = params_.deceleration;
  const double margin = 2.0 * map.params().resolution;
  // The creep rule holds only forward, and only while the camera sees straight ahead at the
  // clearance (a working sensor, and nothing near in front of it that shadows the view): then what
  // the arc crosses unseen is the ring around the body the camera cannot see.
  const bool may_creep = v > 0.0 && params_.creep_speed > 0.0 &&
                         centreLineSeen(map, in.pose.x, in.pose.y, in.pose.yaw, params_.footprint.radius,
                                        params_.creep_view, params_.creep_view + 2.0 * map.params().resolution, in.now);
  // The edge rule: forward at no more than edge_speed, the map's obstacles may come to edge_clearance.
  const bool may_edge = v > 0.0 && params_.edge_speed > 0.0 && params_.edge_clearance < params_.obstacle_clearance;
  double speed = std::abs(v);
  creeping = false;
  edging = false;
  for (int iteration = 0; iteration < 8 && speed >= kStill; ++iteration)
  {
    // Only the stopping distance and the clearance need checking (plus a little, so that free
    // space there still allows the speed).
    const double stop = a > 0.0 ? speed * speed / (2.0 * a) : 0.0;
    const double length =
        std::min(params_.horizon, stop + std::max(params_.clearance, params_.obstacle_clearance) + margin);
    const Travels t = travels(map, in, sign * speed, w, length);
    const double known_limit = speedFor(t.known, a);
    const double creep_limit = may_creep ? std::min(params_.creep_speed, speedFor(t.open, a)) : 0.0;
    const double edge_limit = may_edge ? std::min(params_.edge_speed, speedFor(t.edge, a)) : 0.0;
    creeping = creep_limit > std::max(known_limit, edge_limit);
    edging = !creeping && edge_limit > known_limit;
    out.travel = creeping ? t.open : (edging ? t.edge : t.known);
    out.speed_limit = std::max({ known_limit, creep_limit, edge_limit });
    out.curvature = w / speed;
    if (speed <= out.speed_limit)
    {
      return sign * speed;
    }
    // On a curve a lower speed with the same turn rate is a tighter arc: check it again.
    speed = isStraight(w / speed, length) ? out.speed_limit : std::min(out.speed_limit, 0.7 * speed);
  }
  out.curvature = 0.0;
  creeping = false;
  edging = false;
  return 0.0;
}

FilterOutput SafetyFilter::filter(const LocalMap& map, const FilterInput& in) const
{
  FilterOutput out;
  const double v = in.command.linear;
  const double w = in.command.angular;
  char text[200];
  if (!std::isfinite(v) || !std::isfinite(w))
  {
    out.reason = FilterReason::INVALID_COMMAND;
    out.text = "command refused: linear and angular must be finite";
    return out;
  }
  if (!(in.now - in.command_time <= params_.input_timeout))
  {
    out.reason = FilterReason::INPUT_TIMEOUT;
    std::snprintf(text, sizeof(text), "no command for %.2f s (input_timeout %.2f s): stopped", in.now - in.command_time,
                  params_.input_timeout);
    out.text = text;
    return out;
  }
  if (!in.localized)
  {
    out.reason = FilterReason::NO_ODOMETRY;
    out.text = "robot pose unknown: stopped";
    return out;
  }
  out.command.angular = w;
  out.scale = 1.0;
  if (std::abs(v) < kStill)
  {
    out.reason = FilterReason::PASSED;
    out.text = w != 0.0 ? "turning in place sweeps nothing new: passed" : "no motion requested";
    return out;
  }
  if (v > 0.0 && !(in.now - in.cloud_time <= params_.stale_timeout))
  {
    out.reason = FilterReason::STALE_DATA;
    out.scale = 0.0;
    std::snprintf(text, sizeof(text), "no cloud for %.2f s (stale_timeout %.2f s): forward motion stopped",
                  in.now - in.cloud_time, params_.stale_timeout);
    out.text = text;
    return out;
  }
  bool creeping = false;
  bool edging = false;
  out.command.linear = limitSpeed(map, in, v, w, out, creeping, edging);
  const char* edge_note = edging ? " (near a known obstacle, at most edge_speed)" : "";
  out.scale = std::abs(out.command.linear) / std::abs(v);
  if (creeping)
  {
    out.reason = FilterReason::CREEPING;
    std::snprintf(text, sizeof(text),
                  "arc crosses cells never seen (%.3f m open beyond the clearance, the view at the clearance "
                  "known): %.3f m/s gives %.3f m/s (creep_speed %.3f m/s)",
                  out.travel, v, out.command.linear, params_.creep_speed);
  }
  else if (out.command.linear == v)
  {
    out.reason = FilterReason::PASSED;
    std::snprintf(text, sizeof(text), "%.3f m free on the arc beyond the clearance%s: %.3f m/s passed", out.travel,
                  edge_note, v);
  }
  else if (out.command.linear != 0.0)
  {
    out.reason = FilterReason::LIMITED;
    std::snprintf(text, sizeof(text), "%.3f m free on the arc beyond the clearance%s: %.3f m/s limited to %.3f m/s",
                  out.travel, edge_note, v, out.command.linear);
  }
  else
  {
    out.reason = FilterReason::STOPPED_OBSTACLE;
    std::snprintf(text, sizeof(text), "%s: %.3f m/s stopped%s",
                  v > 0.0 ? "obstacle or unknown space within the clearance on the arc"
                          : "end of the trail (or an obstacle) behind within the lateral margin",
                  v, w != 0.0 ? ", turning passed" : "");
  }
  out.text = text;
  return out;
}
}  // namespace sl_obstacle
