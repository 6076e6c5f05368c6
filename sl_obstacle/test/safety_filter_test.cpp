// Tests of the safety filter (SafetyFilter, sweepArc, arcContact) on given local maps: the speed
// limit v <= sqrt(2 a d) as a formula, arcs that graze a leg, turning in place, reverse along the
// trail, the blind near field after a turn, timeouts and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <sl_testing/errors.h>
#include "sl_obstacle/safety_filter.h"

namespace sl_obstacle
{
namespace
{
using sl_testing::validationError;

constexpr double kRes = 0.02;
constexpr double kBody = 0.1675;
constexpr double kInf = std::numeric_limits<double>::infinity();

/// Rays along x from x0 to x1 in both height slices, every half cell across [y0, y1].
void insertRect(LocalMap& map, float x0, float x1, float y0, float y1, RayKind kind)
{
  std::vector<MapRay> rays;
  for (float y = y0; y <= y1; y += 0.5F * static_cast<float>(kRes))
  {
    rays.push_back(MapRay{ x0, y, 0.05F, x1, y, 0.05F, kind });
    rays.push_back(MapRay{ x0, y, 0.13F, x1, y, 0.13F, kind });
  }
  map.insert(rays, 0.0);
}

/// Free space from x0 to a wall of decoded points at wall_x, |y| <= half.
void wallMap(LocalMap& map, double wall_x, double half = 0.6)
{
  insertRect(map, -0.4F, static_cast<float>(wall_x), static_cast<float>(-half), static_cast<float>(half), RayKind::Hit);
}

/// The wall as the cloud sees it: points on x = wall_x every 5 mm, in the robot's frame at robot_x.
std::vector<Point2> wallPoints(double wall_x, double robot_x)
{
  std::vector<Point2> points;
  for (double y = -0.3; y <= 0.3; y += 0.005)
  {
    points.push_back(Point2{ wall_x - robot_x, y });
  }
  return points;
}

FilterInput inputAt(double x, double y, double yaw, double v, double w)
{
  FilterInput in;
  in.now = 0.0;
  in.command = Velocity{ v, w };
  in.command_time = 0.0;
  in.localized = true;
  in.pose = Pose2D{ x, y, yaw };
  in.cloud_time = 0.0;
  return in;
}

/// Brute force: travel until a disc of radius r on the arc touches a point (1 mm steps).
double sampledContact(const std::vector<Point2>& pts, double r, int dir, double k, double length)
{
  for (double s = 0.0; s <= length; s += 0.001)
  {
    const double cx = std::abs(k) < 1e-12 ? dir * s : dir * std::sin(k * s) / k;
    const double cy = std::abs(k) < 1e-12 ? 0.0 : dir * (1.0 - std::cos(k * s)) / k;
    for (const Point2& p : pts)
    {
      if (std::hypot(p.x - cx, p.y - cy) <= r)
      {
        return s;
      }
    }
  }
  return kInf;
}

TEST(SafetyFilter, StraightAtAWallFollowsTheStoppingFormula)
{
  LocalMap map{ MapParams() };
  wallMap(map, 1.4);
  FilterParams p;
  p.clearance = 0.40;
  p.obstacle_clearance = 0.40;
  p.creep_view = 0.40;
  const SafetyFilter filter(p);
  for (double x = 0.0; x <= 0.9; x += 0.05)
  {
    const std::vector<Point2> wall = wallPoints(1.4, x);
    FilterInput in = inputAt(x, 0.0, 0.0, 0.3, 0.0);
    in.obstacles = &wall;
    const FilterOutput out = filter.filter(map, in);
    const double d = 1.4 - x - kBody - p.clearance;  // travel left before the clearance
    const double expected = d > 0.0 ? std::min(0.3, std::sqrt(2.0 * p.deceleration * d)) : 0.0;
    EXPECT_NEAR(out.command.linear, expected, 1e-6) << "at x " << x;
    if (d <= 0.2)  // the arc is checked up to the stopping distance at 0.3 m/s plus the clearance
    {
      EXPECT_NEAR(out.travel, d, 1e-6) << "at x " << x;
    }
    EXPECT_NEAR(out.scale, expected / 0.3, 1e-6);
    EXPECT_EQ(out.reason, expected == 0.3  ? FilterReason::PASSED
                          : expected > 0.0 ? FilterReason::LIMITED
                                           : FilterReason::STOPPED_OBSTACLE)
        << "at x " << x;
  }
}

TEST(SafetyFilter, KnownObstaclesKeepTheObstacleClearanceUnknownSpaceTheClearance)
{
  FilterParams p;
  p.clearance = 0.40;
  p.obstacle_clearance = 0.05;
  p.creep_speed = 0.0;  // the clearances alone
  const SafetyFilter filter(p);
  LocalMap walled{ MapParams() };
  wallMap(walled, 1.4);  // free up to a wall: unknown behind it, its shadow
  LocalMap open{ MapParams() };
  insertRect(open, -0.4F, 1.4F, -0.6F, 0.6F, RayKind::Free);  // free up to 1.4 m, unknown beyond
  for (double x = 0.5; x <= 1.2; x += 0.05)
  {
    const std::vector<Point2> wall = wallPoints(1.4, x);
    FilterInput in = inputAt(x, 0.0, 0.0, 0.3, 0.0);
    in.obstacles = &wall;
    const FilterOutput at_wall = filter.filter(walled, in);
    const double d_wall = 1.4 - x - kBody - p.obstacle_clearance;
    EXPECT_NEAR(at_wall.command.linear, d_wall > 0.0 ? std::min(0.3, std::sqrt(2.0 * p.deceleration * d_wall)) : 0.0,
                1e-6)
        << "at x " << x;
    // The same free space without the wall: the disc (with its lateral margin) must stop the
    // clearance before the first unknown cell (the rays' last cell, from 1.40 to 1.42 m, is free).
    const FilterOutput at_edge = filter.filter(open, inputAt(x, 0.0, 0.0, 0.3, 0.0));
    const double d_edge = 1.4 - x - kBody - p.footprint.lateral_margin - p.clearance;
    EXPECT_LE(at_edge.travel, d_edge + kRes + 1e-9) << "at x " << x;
    EXPECT_GE(at_edge.travel, std::min(d_edge, 0.0) - 2.5 * kRes) << "at x " << x;
    EXPECT_LT(at_edge.command.linear, at_wall.command.linear + 1e-9) << "at x " << x;
  }
}

TEST(SafetyFilter, EdgeRuleAsAFormula)
{
  // Cleaning along a wall the map knows: at no more than edge_speed the front edge may come to
  // edge_clearance of it; faster, obstacle_clearance holds. Unknown space keeps the clearance.
  FilterParams p;
  p.clearance = 0.15;
  p.obstacle_clearance = 0.10;
  p.edge_clearance = 0.05;
  p.edge_speed = 0.1;
  p.creep_speed = 0.0;
  const SafetyFilter filter(p);
  FilterParams off = p;
  off.edge_speed = 0.0;
  const SafetyFilter without(off);
  LocalMap map{ MapParams() };
  wallMap(map, 1.4);
  LocalMap open{ MapParams() };
  insertRect(open, -0.4F, 1.4F, -0.6F, 0.6F, RayKind::Free);  // free up to 1.4 m, unknown beyond
  const double a = p.deceleration;
  for (double x = 0.8; x <= 1.25; x += 0.01)
  {
    for (const double v : { 0.3, 0.08 })
    {
      const std::vector<Point2> wall = wallPoints(1.4, x);
      FilterInput in = inputAt(x, 0.0, 0.0, v, 0.0);
      in.obstacles = &wall;
      const double d_known = 1.4 - x - kBody - p.obstacle_clearance;
      const double d_edge = 1.4 - x - kBody - p.edge_clearance;
      const double known = d_known > 0.0 ? std::sqrt(2.0 * a * d_known) : 0.0;
      const double edge = d_edge > 0.0 ? std::min(p.edge_speed, std::sqrt(2.0 * a * d_edge)) : 0.0;
      const double expected = std::min(v, std::max(known, edge));
      const FilterOutput out = filter.filter(map, in);
      EXPECT_NEAR(out.command.linear, expected, 1e-6) << "at x " << x << ", " << v << " m/s";
      EXPECT_LE(out.command.linear, std::max(known, p.edge_speed) + 1e-9);  // faster only as fast as the formula
      EXPECT_NEAR(without.filter(map, in).command.linear, std::min(v, known), 1e-6) << "at x " << x;
      // Unknown space is no wall: no nearer approach there.
      const FilterOutput unknown = filter.filter(open, inputAt(x, 0.0, 0.0, v, 0.0));
      EXPECT_NEAR(unknown.command.linear, without.filter(open, inputAt(x, 0.0, 0.0, v, 0.0)).command.linear, 1e-9)
          << "at x " << x;
    }
  }
  // At 0.08 m/s the robot comes to edge_clearance, not nearer.
  const double x_stop = 1.4 - kBody - p.edge_clearance;
  const std::vector<Point2> wall = wallPoints(1.4, x_stop);
  FilterInput in = inputAt(x_stop, 0.0, 0.0, 0.08, 0.0);
  in.obstacles = &wall;
  EXPECT_EQ(filter.filter(map, in).reason, FilterReason::STOPPED_OBSTACLE);
  in = inputAt(x_stop - 0.02, 0.0, 0.0, 0.08, 0.0);
  const std::vector<Point2> wall2 = wallPoints(1.4, x_stop - 0.02);
  in.obstacles = &wall2;
  const FilterOutput near = filter.filter(map, in);
  EXPECT_GT(near.command.linear, 0.0);
  EXPECT_NE(near.text.find("edge_speed"), std::string::npos) << near.text;
}

TEST(SafetyFilter, WithoutTheCloudTheMapStopsEarlyNeverLate)
{
  LocalMap map{ MapParams() };
  wallMap(map, 1.4);
  const SafetyFilter filter;
  for (double x = 0.9; x <= 1.1; x += 0.02)
  {
    const FilterOutput out = filter.filter(map, inputAt(x, 0.0, 0.0, 0.3, 0.0));
    const double d = 1.4 - x - kBody - filter.params().clearance;
    EXPECT_LE(out.travel, d + 1e-9) << "at x " << x;
    EXPECT_GE(out.travel, d - 2.5 * kRes) << "at x " << x;
  }
}

TEST(SafetyFilter, AnArcThatGrazesALegIsSlowedByTheLegNotByTheWall)
{
  LocalMap map{ MapParams() };
  insertRect(map, -0.4F, 2.0F, -0.8F, 1.2F, RayKind::Free);
  insertRect(map, 1.6F, 1.62F, -0.8F, 1.2F, RayKind::Hit);  // a wall 1.6 m ahead
  map.markOccupiedDisc(0.61, 0.31, 0.011, 0.0);             // a 20 mm leg beside the straight path
  const std::vector<Point2> leg{ { 0.61, 0.31 } };
  FilterParams p;
  p.clearance = 0.40;
  p.obstacle_clearance = 0.40;
  p.creep_view = 0.40;
  const SafetyFilter filter(p);
  // Straight on, the leg stays outside the swept path: only the wall, far away, limits.
  FilterInput straight = inputAt(0.0, 0.0, 0.0, 0.3, 0.0);
  straight.obstacles = &leg;
  const FilterOutput s = filter.filter(map, straight);
  EXPECT_EQ(s.reason, FilterReason::PASSED);
  // Curving left at 0.8 rad/m the disc meets the leg after about 0.55 m, long before the wall: the
  // leg sets the limit, on the (tighter) arc actually driven.
  FilterInput arc = inputAt(0.0, 0.0, 0.0, 0.4, 0.32);
  arc.obstacles = &leg;
  EXPECT_LT(arcContact(leg, kBody, 1, 0.8, 2.0), 0.7);
  const FilterOutput a = filter.filter(map, arc);
  EXPECT_EQ(a.reason, FilterReason::LIMITED);
  EXPECT_GT(a.command.linear, 0.0);
  EXPECT_LT(a.command.linear, 0.4);
  EXPECT_DOUBLE_EQ(a.command.angular, 0.32);
  EXPECT_NEAR(a.curvature, 0.32 / a.command.linear, 1e-9);
  // The swept disc (with the lateral margin) reaches the leg's cell first; the sweep reports it up
  // to a quarter cell early.
  const double contact = arcContact(leg, p.footprint.sweptRadius(), 1, a.curvature, 2.0);
  ASSERT_LT(contact, 1.0);
  EXPECT_LE(a.travel, contact - p.clearance + 1e-9);
  EXPECT_GE(a.travel, contact - p.clearance - 0.25 * kRes - 1e-9);
  EXPECT_LE(a.command.linear, std::sqrt(2.0 * 0.25 * a.travel) + 1e-9);
}

TEST(SafetyFilter, TurningInPlacePassesEvenAgainstAnObstacle)
{
  LocalMap map{ MapParams() };
  wallMap(map, 0.25);  // the wall 0.08 m in front of the disc: well within the clearance
  const std::vector<Point2> wall = wallPoints(0.25, 0.0);
  const SafetyFilter filter;
  FilterInput in = inputAt(0.0, 0.0, 0.0, 0.0, 1.0);
  in.obstacles = &wall;
  FilterOutput out = filter.filter(map, in);
  EXPECT_EQ(out.reason, FilterReason::PASSED);
  EXPECT_DOUBLE_EQ(out.command.angular, 1.0);
  EXPECT_DOUBLE_EQ(out.command.linear, 0.0);
  // Forward into it: no forward speed, the turn still passes.
  in.command = Velocity{ 0.2, 0.8 };
  out = filter.filter(map, in);
  EXPECT_EQ(out.reason, FilterReason::STOPPED_OBSTACLE);
  EXPECT_DOUBLE_EQ(out.command.linear, 0.0);
  EXPECT_DOUBLE_EQ(out.command.angular, 0.8);
  EXPECT_DOUBLE_EQ(out.scale, 0.0);
}

/// The robot drove along x from @p x0 to @p x1: its trail (the disc plus half a cell) and the swept
/// ring beside it marked free, as WorldModel::updatePose() does.
void driveTrail(LocalMap& map, double x0, double x1, const FilterParams& p)
{
  map.markTrail(x0, 0.0, x1, 0.0, p.footprint.radius + 0.5 * kRes);
  for (double x = x0; x <= x1 + 1e-9; x += 0.01)
  {
    map.markFreeDisc(x, 0.0, p.footprint.sweptRadius() + 0.5 * kRes, 0.0);
  }
}

TEST(SafetyFilter, ReverseOnlyAlongTheTrail)
{
  LocalMap map{ MapParams() };
  const SafetyFilter filter;
  const FilterParams& p = filter.params();
  // Nothing known behind: reverse is refused.
  FilterOutput out = filter.filter(map, inputAt(0.0, 0.0, 0.0, -0.1, 0.0));
  EXPECT_EQ(out.reason, FilterReason::STOPPED_OBSTACLE);
  EXPECT_DOUBLE_EQ(out.command.linear, 0.0);
  // Free space that is not the trail (a start disc taken as free, cells seen free): still refused.
  map.markFreeDisc(0.0, 0.0, 0.6, 0.0);
  out = filter.filter(map, inputAt(0.0, 0.0, 0.0, -0.1, 0.0));
  EXPECT_EQ(out.reason, FilterReason::STOPPED_OBSTACLE);
  EXPECT_DOUBLE_EQ(out.command.linear, 0.0);
  // The robot came from x = -1.2: back along its trail it may go.
  driveTrail(map, -1.2, 0.0, p);
  out = filter.filter(map, inputAt(0.0, 0.0, 0.0, -0.1, 0.0));
  EXPECT_EQ(out.reason, FilterReason::PASSED);
  EXPECT_DOUBLE_EQ(out.command.linear, -0.1);
  // Faster backwards than the trail allows: |v| = sqrt(2 a d_trail), d_trail the travel until the
  // disc (0.1675) reaches a cell centre off the trail (0.1775 around x = -1.2: 0.01 m beyond its
  // start, up to half a cell on the lattice) less the lateral margin.
  for (const double x : { -1.15, -1.1, -1.0, -0.9 })
  {
    out = filter.filter(map, inputAt(x, 0.0, 0.0, -0.4, 0.0));
    const double d = x + 1.2;  // back to the start pose
    EXPECT_GE(out.travel, d - p.footprint.lateral_margin - 1e-9) << "at x " << x;
    EXPECT_LE(out.travel, d + 0.5 * kRes + 1e-9 - p.footprint.lateral_margin + 0.01) << "at x " << x;
    EXPECT_NEAR(out.command.linear, -std::sqrt(2.0 * p.deceleration * out.travel), 1e-9) << "at x " << x;
    EXPECT_EQ(out.reason, FilterReason::LIMITED);
  }
  // Turned across the trail, reverse ends where the disc reaches the first cell centres off the
  // trail (y = -0.19, at x -0.61 and -0.59), or the swept disc the first ones not free (y = -0.21),
  // whichever comes first (here the second, by 0.03 mm), less the lateral margin.
  out = filter.filter(map, inputAt(-0.6, 0.0, M_PI / 2.0, -0.1, 0.0));
  const double r = p.footprint.sweptRadius();
  const double off_trail = 0.19 - std::sqrt(kBody * kBody - 0.01 * 0.01);
  const double not_free = 0.21 - std::sqrt(r * r - 0.01 * 0.01);
  EXPECT_NEAR(out.travel, std::min(off_trail, not_free) - p.footprint.lateral_margin, 1e-9);
  EXPECT_NEAR(out.command.linear, -std::sqrt(2.0 * p.deceleration * out.travel), 1e-9);
}

TEST(SafetyFilter, UnknownNearFieldAfterATurnGivesNoForwardSpeed)
{
  LocalMap map{ MapParams() };
  // The robot saw the strip straight ahead (from farther back) and its own start area; the near
  // field toward 60 degrees to the left was never seen.
  insertRect(map, 0.0F, 1.5F, -0.3F, 0.3F, RayKind::Free);
  map.markFreeDisc(0.0, 0.0, 0.2, 0.0);
  const SafetyFilter filter;
  // The camera has not seen the floor along the new heading: no creep either.
  const FilterOutput out = filter.filter(map, inputAt(0.0, 0.0, M_PI / 3.0, 0.2, 0.3));
  EXPECT_EQ(out.reason, FilterReason::STOPPED_OBSTACLE);
  EXPECT_DOUBLE_EQ(out.command.linear, 0.0);
  EXPECT_DOUBLE_EQ(out.command.angular, 0.3);
  // Straight ahead, where it looked, it may drive.
  EXPECT_GT(filter.filter(map, inputAt(0.0, 0.0, 0.0, 0.2, 0.0)).command.linear, 0.0);
}

TEST(SafetyFilter, CreepRuleAsAFormula)
{
  // The robot at x stands 0.45 .. 0.7 m before a wall at x = 1.2 that the map and the cloud see;
  // the camera saw the floor free on a strip straight ahead (|y| <= 0.05, x 0.9 .. 1.2); around
  // its body nothing was ever seen (the ring the camera cannot see). Nothing on the path is known
  // free (d_known < 0): only the creep rule may move it,
  //   v_out = min(v, C min(creep_speed, sqrt(2 a d_open))), d_open = contact - clearance,
  //   C = 1 while the centre line is known (free or occupied) from the clearance to two cells
  //   beyond it.
  LocalMap map{ MapParams() };
  insertRect(map, 0.9F, 1.18F, -0.05F, 0.05F, RayKind::Free);
  insertRect(map, 1.19F, 1.2F, -0.8F, 0.8F, RayKind::Hit);
  FilterParams p;
  p.clearance = 0.40;
  p.obstacle_clearance = 0.40;
  p.creep_view = 0.40;
  const SafetyFilter filter(p);
  int crept = 0;
  for (int i = 0; i <= 25; ++i)
  {
    const double x = 0.45 + 0.01 * i;
    const std::vector<Point2> wall = wallPoints(1.2, x);
    const double contact = 1.2 - x - kBody;
    const double d_open = contact - p.clearance;
    // The centre line from x + 0.1675 + 0.40 to 0.04 m beyond lies on the seen strip up to the
    // wall's cell (its shadow behind it not asked for) until it starts behind that cell.
    const bool c = centreLineSeen(map, x, 0.0, 0.0, kBody, p.clearance, p.clearance + 2.0 * kRes, 0.0);
    EXPECT_EQ(c, x + kBody + p.clearance < 1.22) << "x " << x;
    for (const double v : { 0.02, 0.05, 0.1, 0.3 })
    {
      FilterInput in = inputAt(x, 0.0, 0.0, v, 0.0);
      in.obstacles = &wall;
      const FilterOutput out = filter.filter(map, in);
      const double expected =
          c && d_open > 0.0 ? std::min(v, std::min(p.creep_speed, std::sqrt(2.0 * p.deceleration * d_open))) : 0.0;
      EXPECT_NEAR(out.command.linear, expected, 1e-9) << "x " << x << " v " << v;
      EXPECT_EQ(out.reason, expected > 0.0 ? FilterReason::CREEPING : FilterReason::STOPPED_OBSTACLE)
          << "x " << x << " v " << v << ": " << out.text;
      EXPECT_LT(filter.travel(map, in, v, 0.0, 1.0), 0.0) << "nothing is known free";
      crept += expected > 0.0 ? 1 : 0;
    }
  }
  EXPECT_EQ(crept, 19 * 4) << "x 0.45 .. 0.63: up to the clearance (x = 0.6325)";
  // Without the strip seen (a robot 0.3 m to the side: the camera saw nothing there) no creep;
  // neither with the view ahead shadowed by something near (the strip starting beyond it).
  EXPECT_FALSE(centreLineSeen(map, 0.2, 0.0, 0.0, kBody, p.clearance, p.clearance + 2.0 * kRes, 0.0));
  EXPECT_DOUBLE_EQ(filter.filter(map, inputAt(0.2, 0.0, 0.0, 0.3, 0.0)).command.linear, 0.0);
  EXPECT_DOUBLE_EQ(filter.filter(map, inputAt(0.45, 0.3, 0.0, 0.3, 0.0)).command.linear, 0.0);
  // A smaller clearance to unknown space keeps the view check where the camera sees: at
  // creep_view, not in the blind ring at the clearance.
  FilterParams near_p = p;
  near_p.clearance = 0.15;
  const SafetyFilter near_filter(near_p);
  const double x_seen = 0.5;  // the strip from 0.9 m: the centre line at 0.40 from the front edge is seen
  EXPECT_FALSE(centreLineSeen(map, x_seen, 0.0, 0.0, kBody, 0.15, 0.15 + 2.0 * kRes, 0.0));
  EXPECT_GT(near_filter.filter(map, inputAt(x_seen, 0.0, 0.0, 0.3, 0.0)).command.linear, 0.0);
  near_p.creep_view = 0.15;
  EXPECT_DOUBLE_EQ(SafetyFilter(near_p).filter(map, inputAt(x_seen, 0.0, 0.0, 0.3, 0.0)).command.linear, 0.0);
  // A cell holding evidence (a lone lit end 0.65 m ahead of base_link) ends the open travel there,
  // within the clearance: no creep.
  LocalMap lit{ MapParams() };
  insertRect(lit, 0.6F, 1.2F, -0.05F, 0.05F, RayKind::Free);
  lit.insert({ MapRay{ 0.0F, 0.11F, 0.05F, 0.65F, 0.11F, 0.05F, RayKind::Suspect } }, 0.0);
  const FilterInput near = inputAt(0.0, 0.0, 0.0, 0.3, 0.0);
  const double entry = 0.65 - std::sqrt(std::pow(p.footprint.sweptRadius(), 2) - 0.11 * 0.11);
  EXPECT_NEAR(filter.openTravel(lit, near, 0.3, 0.0, 1.0), entry - p.clearance, kRes);
  EXPECT_DOUBLE_EQ(filter.filter(lit, near).command.linear, 0.0);
  // Where the path is known free, the creep gives way to the known-free speed.
  insertRect(lit, -0.4F, 1.2F, -0.6F, 0.6F, RayKind::Free);
  const FilterOutput k = filter.filter(lit, near);
  EXPECT_GT(k.command.linear, p.creep_speed);
  EXPECT_NE(k.reason, FilterReason::CREEPING);
  // creep_speed 0 switches the rule off.
  FilterParams off = p;
  off.creep_speed = 0.0;
  LocalMap view{ MapParams() };
  insertRect(view, 0.5F, 1.2F, -0.05F, 0.05F, RayKind::Free);
  const FilterInput start = inputAt(0.0, 0.0, 0.0, 0.3, 0.0);
  EXPECT_DOUBLE_EQ(SafetyFilter(off).filter(view, start).command.linear, 0.0);
  EXPECT_DOUBLE_EQ(SafetyFilter(p).filter(view, start).command.linear, p.creep_speed);
}

TEST(SafetyFilter, NanOrInfComponentsAreRefused)
{
  LocalMap map{ MapParams() };
  insertRect(map, -0.4F, 2.0F, -0.8F, 0.8F, RayKind::Free);
  const SafetyFilter filter;
  const double bad[] = { std::nan(""), kInf, -kInf };
  for (const double b : bad)
  {
    for (const Velocity v : { Velocity{ b, 0.0 }, Velocity{ 0.1, b } })
    {
      FilterInput in = inputAt(0.0, 0.0, 0.0, v.linear, v.angular);
      const FilterOutput out = filter.filter(map, in);
      EXPECT_EQ(out.reason, FilterReason::INVALID_COMMAND);
      EXPECT_DOUBLE_EQ(out.command.linear, 0.0);
      EXPECT_DOUBLE_EQ(out.command.angular, 0.0);
    }
  }
}

TEST(SafetyFilter, TimeoutsAndOdometry)
{
  LocalMap map{ MapParams() };
  insertRect(map, -0.4F, 2.0F, -0.8F, 0.8F, RayKind::Free);
  const SafetyFilter filter;
  FilterInput in = inputAt(0.0, 0.0, 0.0, 0.2, 0.5);
  in.now = 1.0;
  in.command_time = 1.0 - 0.6;  // older than input_timeout 0.5 s
  in.cloud_time = 1.0;
  EXPECT_EQ(filter.filter(map, in).reason, FilterReason::INPUT_TIMEOUT);
  EXPECT_DOUBLE_EQ(filter.filter(map, in).command.angular, 0.0);
  in.command_time = -kInf;  // never any command
  EXPECT_EQ(filter.filter(map, in).reason, FilterReason::INPUT_TIMEOUT);
  in.command_time = 1.0;
  in.cloud_time = 1.0 - 0.6;  // older than stale_timeout 0.5 s: forward stops, the turn passes
  FilterOutput out = filter.filter(map, in);
  EXPECT_EQ(out.reason, FilterReason::STALE_DATA);
  EXPECT_DOUBLE_EQ(out.command.linear, 0.0);
  EXPECT_DOUBLE_EQ(out.command.angular, 0.5);
  in.command = Velocity{ -0.1, 0.0 };  // reverse is checked on the map only (the trail)
  in.pose.x = 0.5;
  driveTrail(map, -0.5, 0.5, filter.params());
  EXPECT_EQ(filter.filter(map, in).reason, FilterReason::PASSED);
  in.localized = false;
  out = filter.filter(map, in);
  EXPECT_EQ(out.reason, FilterReason::NO_ODOMETRY);
  EXPECT_DOUBLE_EQ(out.command.linear, 0.0);
}

TEST(SafetyFilter, ArcContactMatchesSampledGeometry)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-1.2, 1.2);
  std::uniform_real_distribution<double> curv(-3.0, 3.0);
  for (int trial = 0; trial < 200; ++trial)
  {
    std::vector<Point2> pts;
    while (pts.size() < 3)
    {
      const Point2 p{ coord(rng), coord(rng) };
      if (std::hypot(p.x, p.y) > kBody + 0.01)
      {
        pts.push_back(p);
      }
    }
    const double k = trial % 5 == 0 ? 0.0 : curv(rng);
    const int dir = trial % 2 == 0 ? 1 : -1;
    const double exact = arcContact(pts, kBody, dir, k, 1.5);
    const double sampled = sampledContact(pts, kBody, dir, k, 1.5);
    if (std::isfinite(sampled) && sampled < 1.49)
    {
      EXPECT_NEAR(exact, sampled, 0.0015) << "trial " << trial << " k " << k << " dir " << dir;
    }
    else
    {
      EXPECT_TRUE(!std::isfinite(exact) || exact > 1.48) << "trial " << trial << ": " << exact;
    }
  }
  // A point under the disc: contact now if the motion goes into it, none if it leaves it.
  const std::vector<Point2> under{ { 0.1, 0.0 } };
  EXPECT_DOUBLE_EQ(arcContact(under, kBody, 1, 0.5, 1.0), 0.0);
  EXPECT_EQ(arcContact(under, kBody, -1, 0.5, 1.0), kInf);
}

TEST(SafetyFilter, SweptArcFindsCellsWhereTheDiscReachesThem)
{
  LocalMap map{ MapParams() };
  insertRect(map, -0.4F, 2.0F, -1.0F, 1.4F, RayKind::Free);
  map.markOccupiedDisc(0.61, 0.31, 0.005, 0.0);  // one occupied cell
  const Pose2D start{ 0.0, 0.0, 0.0 };
  for (const double k : { 0.0, 0.4, 0.8, -0.4 })
  {
    const ArcResult r = sweepArc(map, kBody, start, 1, k, 1.5, 0.0);
    const std::vector<Point2> centre{ { 0.61, 0.31 } };
    const double expected = arcContact(centre, kBody, 1, k, 1.5);
    if (std::isfinite(expected))
    {
      // The cell's centre is reached at `expected`; the sweep reports it up to a quarter cell early.
      EXPECT_LE(r.obstacle, expected + 1e-9) << "k " << k;
      EXPECT_GE(r.obstacle, expected - 0.25 * kRes - 1e-9) << "k " << k;
      EXPECT_DOUBLE_EQ(r.free, r.obstacle);
    }
    else
    {
      EXPECT_EQ(r.obstacle, kInf) << "k " << k;
      EXPECT_DOUBLE_EQ(r.free, 1.5) << "k " << k;
    }
  }
  EXPECT_THROW(sweepArc(map, kBody, start, 0, 0.1, 1.0, 0.0), std::invalid_argument);
  EXPECT_THROW(sweepArc(map, kBody, start, 1, std::nan(""), 1.0, 0.0), std::invalid_argument);
}

TEST(SafetyFilter, BadParametersAreNamed)
{
  FilterParams p;
  EXPECT_NO_THROW(p.validate());
  p.deceleration = -1.0;
  EXPECT_THROW(p.validate(), std::invalid_argument);
  EXPECT_EQ(validationError(p).rfind("deceleration", 0), 0U) << validationError(p);
  p = FilterParams();
  p.input_timeout = 0.0;
  EXPECT_EQ(validationError(p).rfind("input_timeout", 0), 0U) << validationError(p);
  p = FilterParams();
  p.creep_speed = 0.1;  // the creep is 0.05 m/s at most
  EXPECT_EQ(validationError(p).rfind("creep_speed", 0), 0U) << validationError(p);
  p = FilterParams();
  p.creep_view = 2.5;
  EXPECT_EQ(validationError(p).rfind("creep_view_distance", 0), 0U) << validationError(p);
  p = FilterParams();
  p.obstacle_clearance = -0.1;
  EXPECT_EQ(validationError(p).rfind("obstacle_margin", 0), 0U) << validationError(p);
  p = FilterParams();
  p.edge_speed = 0.2;  // the approach to edge_margin is 0.1 m/s at most
  EXPECT_EQ(validationError(p).rfind("edge_speed", 0), 0U) << validationError(p);
  p = FilterParams();
  p.edge_clearance = std::nan("");
  EXPECT_EQ(validationError(p).rfind("edge_margin", 0), 0U) << validationError(p);
  p = FilterParams();
  p.footprint.radius = 0.0;
  EXPECT_EQ(validationError(p).rfind("radius", 0), 0U) << validationError(p);
  EXPECT_THROW(SafetyFilter{ p }, std::invalid_argument);
}
}  // namespace
}  // namespace sl_obstacle

namespace sl_obstacle
{
TEST(Frames2D, ToParentAndToChildAreInverses)
{
  const Pose2D frame{ 1.0, -2.0, 0.5 * M_PI };  // x, y, yaw: the child's x axis along the parent's y
  const std::vector<Point2> child = { { 1.0, 0.0 }, { 0.0, 2.0 }, { -0.5, 0.25 } };
  std::vector<Point2> parent, back;
  toParent(child, frame, parent);
  ASSERT_EQ(parent.size(), 3U);
  EXPECT_NEAR(parent[0].x, 1.0, 1e-12);  // 1 m ahead of the frame: +y in the parent
  EXPECT_NEAR(parent[0].y, -1.0, 1e-12);
  EXPECT_NEAR(parent[1].x, -1.0, 1e-12);  // 2 m to its left: -x in the parent
  EXPECT_NEAR(parent[1].y, -2.0, 1e-12);
  toChild(parent, frame, back);
  ASSERT_EQ(back.size(), 3U);
  for (std::size_t i = 0; i < child.size(); ++i)
  {
    EXPECT_NEAR(back[i].x, child[i].x, 1e-12) << i;
    EXPECT_NEAR(back[i].y, child[i].y, 1e-12) << i;
  }
  toParent({}, frame, parent);
  EXPECT_TRUE(parent.empty()) << "the output holds only this call's points";
}
}  // namespace sl_obstacle
