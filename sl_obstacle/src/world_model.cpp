#include "sl_obstacle/world_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "validation.h"

namespace sl_obstacle
{
void WorldParams::validate() const
{
  map.validate();
  footprint.validate();
  detail::requireInRange("start_free_radius", start_free_radius, 0.0, 2.0);
  detail::requireInRange("check_distance", check_distance, 0.1, 10.0);
  detail::requireInRange("heading_step", heading_step, 0.01, 2.0 * M_PI);
  detail::requireInRange("bump_depth", bump_depth, 0.0, 0.5);
  detail::requireInRange("safety_margin", clearance, 0.0, 5.0);
  detail::requireInRange("blind_radius", blind_radius, 0.0, 2.0);
  if (headings < 0 || headings > 64)
  {
    detail::refuse("headings", "must be in [0, 64]", headings);
  }
  if (check_distance > 0.5 * map.size - footprint.radius - footprint.lateral_margin)
  {
    detail::refuse("check_distance", "must fit in half the map (map_size / 2 - robot_radius - lateral_margin)",
                   check_distance);
  }
}

namespace
{
WorldParams checked(const WorldParams& p)
{
  p.validate();
  return p;
}
}  // namespace

WorldModel::WorldModel(const WorldParams& params) : params_(checked(params)), map_(params_.map) {}

void WorldModel::reset()
{
  map_.clear();
  summary_ = MapSummary();
  turns_time_ = -std::numeric_limits<double>::infinity();
  started_ = false;
}

void WorldModel::setClearance(double clearance)
{
  detail::requireInRange("safety_margin", clearance, 0.0, 5.0);
  params_.clearance = clearance;
}

void WorldModel::updatePose(const Pose2D& robot, double now)
{
  map_.recenter(robot.x, robot.y);
  if (!started_)
  {
    map_.markFreeDisc(robot.x, robot.y, params_.start_free_radius, now);
    last_pose_ = robot;
    started_ = true;
  }
  // The trail: where the disc itself has been, between this pose and the last (a longer jump is an
  // odometry reset, not a drive).
  const bool driven = std::hypot(robot.x - last_pose_.x, robot.y - last_pose_.y) <= kMaxTrailStep;
  const Pose2D& from = driven ? last_pose_ : robot;
  map_.markTrail(from.x, from.y, robot.x, robot.y, trailRadius());
  last_pose_ = robot;
  // Out to the swept radius the trail is free where nothing was seen: the robot only drove where
  // the path checks found it free. Only cells wholly under the body are certainly free: one that
  // reaches past it may hold a thin obstacle passed at a few millimetres, and erasing that would
  // let the next arc in.
  map_.markFreeDiscExceptSeen(robot.x, robot.y, params_.footprint.sweptRadius() + 0.5 * params_.map.resolution, now);
  map_.markFreeDisc(robot.x, robot.y, bodyFreeRadius(), now);
}

double WorldModel::bodyFreeRadius() const
{
  return std::max(0.0, params_.footprint.radius - M_SQRT1_2 * params_.map.resolution);
}

double WorldModel::trailRadius() const
{
  return params_.footprint.radius + 0.5 * params_.map.resolution;
}

void WorldModel::addRays(const std::vector<MapRay>& rays, double stamp)
{
  map_.insert(rays, stamp);
}

void WorldModel::markBump(const Pose2D& robot, bool left, bool right, double now)
{
  turns_time_ = -std::numeric_limits<double>::infinity();  // the map changed: sweep the turns again
  // A disc of bump_depth just beyond the bumper, straight ahead or 40 degrees to the pressed side.
  const double r = params_.footprint.radius + 0.5 * params_.bump_depth;
  const double side = left && !right ? 0.7 : (right && !left ? -0.7 : 0.0);
  const double a = robot.yaw + side;
  map_.markOccupiedDisc(robot.x + r * std::cos(a), robot.y + r * std::sin(a), 0.5 * params_.bump_depth + 0.02, now);
}

const MapSummary& WorldModel::summarize(const Pose2D& robot, double now, bool turns)
{
  MapSummary& s = summary_;
  const double reach = params_.check_distance;
  const PathResult ahead =
      sweepStraight(map_, params_.footprint, robot.x, robot.y, robot.yaw, 1, reach, now, params_.blind_radius);
  s.free = ahead.free;
  s.open = std::min(reach, ahead.open());
  s.creep_end = std::min(ahead.evidence, ahead.unseen_far);
  const double c = params_.clearance;
  s.view_seen = centreLineSeen(map_, robot.x, robot.y, robot.yaw, params_.footprint.radius, c,
                               c + 2.0 * params_.map.resolution, now);
  // Contact is a matter of the disc itself; the lateral margin only asks for free space beside it.
  // The disc is widened by half a cell's diagonal: a cell counts when its nearest corner is reached,
  // not its centre, so an obstacle known only to the map stops the robot early by up to a cell,
  // never late.
  FootprintParams body = params_.footprint;
  body.lateral_margin = 0.71 * params_.map.resolution;
  s.obstacle = sweepStraight(map_, body, robot.x, robot.y, robot.yaw, 1, reach, now).obstacle;
  s.unknown = ahead.unknown;
  s.known_fraction = ahead.known_fraction;
  s.reverse_free = reverseTravel(robot, robot.yaw, now);
  // Reused only while they are recent and were swept from about here (they are relative headings).
  const bool recent = now >= turns_time_ && now - turns_time_ <= kTurnsMaxAge &&
                      std::hypot(robot.x - turns_pose_.x, robot.y - turns_pose_.y) <= 0.02 &&
                      std::abs(std::remainder(robot.yaw - turns_pose_.yaw, 2.0 * M_PI)) <= 0.05;
  if (turns || !recent)
  {
    sweepTurns(robot, now);
  }
  else
  {
    // Straight ahead (turn 0) may have become the best heading since.
    if (s.open > s.best_turn_free + 1e-6)
    {
      s.best_turn_free = s.open;
      s.best_turn = 0.0;
    }
    if (s.reverse_free > s.best_reverse_free + 1e-6)
    {
      s.best_reverse_free = s.reverse_free;
      s.best_reverse_turn = 0.0;
    }
  }
  return s;
}

double WorldModel::reverseTravel(const Pose2D& robot, double yaw, double now) const
{
  const double reach = params_.check_distance;
  const double free = sweepStraight(map_, params_.footprint, robot.x, robot.y, yaw, -1, reach, now).free;
  FootprintParams disc = params_.footprint;
  disc.lateral_margin = 0.0;
  const double trail = sweepStraight(map_, disc, robot.x, robot.y, yaw, -1, reach, now).off_trail;
  return std::max(0.0, std::min({ free, trail, reach }) - params_.footprint.lateral_margin);
}

void WorldModel::sweepTurns(const Pose2D& robot, double now)
{
  MapSummary& s = summary_;
  const double reach = params_.check_distance;
  s.best_turn = 0.0;
  s.best_turn_free = s.open;
  s.left_free = s.right_free = 0.0;
  s.best_reverse_turn = 0.0;
  s.best_reverse_free = s.reverse_free;
  for (int k = 1; k <= params_.headings; ++k)
  {
    for (const int sign : { 1, -1 })
    {
      const double turn = sign * k * params_.heading_step;
      if (std::abs(turn) > M_PI + 1e-9)
      {
        continue;
      }
      const double yaw = robot.yaw + turn;
      // Open travel: the known-free path, or one the robot may creep along (never-seen cells within
      // blind_radius only: farther ones it can look at by turning).
      const double f = std::min(
          reach,
          sweepStraight(map_, params_.footprint, robot.x, robot.y, yaw, 1, reach, now, params_.blind_radius).open());
      double& side = sign > 0 ? s.left_free : s.right_free;
      side = std::max(side, f);
      // Strictly longer wins, so ties keep the smaller turn.
      if (f > s.best_turn_free + 1e-6)
      {
        s.best_turn_free = f;
        s.best_turn = turn;
      }
      const double r = reverseTravel(robot, yaw, now);
      if (r > s.best_reverse_free + 1e-6)
      {
        s.best_reverse_free = r;
        s.best_reverse_turn = turn;
      }
    }
  }
  turns_time_ = now;
  turns_pose_ = robot;
}
FrameSummary withMap(FrameSummary f, const MapSummary& m, double tolerance)
{
  f.from_map = true;
  const bool same_obstacle = std::abs(m.obstacle - f.nearest_obstacle) <= tolerance;
  if (same_obstacle)
  {
    // The cloud sees the obstacle the map stops at: its distance is exact, the map's is quantised.
    f.free_distance = std::min(f.nearest_obstacle, m.unknown);
    f.open_distance = std::min(f.nearest_obstacle, m.creep_end);
  }
  else
  {
    f.nearest_obstacle = std::min(f.nearest_obstacle, m.obstacle);
    f.free_distance = std::min(m.free, f.nearest_obstacle);
    f.open_distance = std::min(m.open, f.nearest_obstacle);
  }
  f.coverage = m.known_fraction;
  f.left_free = m.left_free;
  f.right_free = m.right_free;
  f.reverse_free = m.reverse_free;
  f.best_turn = m.best_turn;
  f.best_turn_free = m.best_turn_free;
  f.best_reverse_turn = m.best_reverse_turn;
  f.best_reverse_free = m.best_reverse_free;
  f.view_seen = m.view_seen;
  return f;
}
double contactTravel(const std::vector<Point>& points, const std::vector<std::uint32_t>& indices, double radius)
{
  double best = std::numeric_limits<double>::infinity();
  for (const std::uint32_t i : indices)
  {
    const double y = std::min(std::abs(static_cast<double>(points[i].y)), radius);
    best = std::min(best, points[i].x + radius - std::sqrt(radius * radius - y * y));
  }
  return best;
}
}  // namespace sl_obstacle
