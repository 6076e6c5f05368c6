#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "sl_navigation/path_follower.h"

using namespace sl_navigation;

namespace
{
/// A 6 x 6 m window of 0.02 m cells around the origin, all @p value.
struct Window
{
  std::vector<std::int8_t> data = std::vector<std::int8_t>(300 * 300, 0);
  ExecWindow exec;
  explicit Window(std::int8_t value = 0) { std::fill(data.begin(), data.end(), value); }
  void box(double x0, double y0, double x1, double y1, std::int8_t value)
  {
    for (int iy = 0; iy < 300; ++iy)
    {
      for (int ix = 0; ix < 300; ++ix)
      {
        const double x = -3.0 + (ix + 0.5) * 0.02;
        const double y = -3.0 + (iy + 0.5) * 0.02;
        if (x >= x0 && x <= x1 && y >= y0 && y <= y1)
        {
          data[iy * 300 + ix] = value;
        }
      }
    }
  }
  const ExecWindow& get()
  {
    OccupancyView v;
    v.data = data.data();
    v.width = v.height = 300;
    v.resolution = 0.02;
    v.origin_x = v.origin_y = -3.0;
    EXPECT_TRUE(exec.set(v));
    return exec;
  }
};

std::vector<Point> straight(double length)
{
  std::vector<Point> p;
  for (double x = 0.0; x <= length + 1e-9; x += 0.05)
  {
    p.push_back({ x, 0.0 });
  }
  return p;
}

/// Steps the follower @p n times at 20 Hz from a fixed pose; returns the last command.
FollowCommand run(PathFollower& f, const Pose& pose, const ExecWindow& w, int n = 40)
{
  FollowCommand c;
  for (int i = 0; i < n; ++i)
  {
    c = f.step(pose, w, 0.05 * i);
  }
  return c;
}
}  // namespace

TEST(PathFollower, DrivesAKnownFreeStraightPathAtMaxSpeedAfterTheRamp)
{
  Window w;
  PathFollower f;
  f.setPath(straight(2.5), 0.0, false);
  const FollowCommand first = f.step(Pose(), w.get(), 0.0);
  EXPECT_EQ(first.mode, FollowMode::DRIVE);
  EXPECT_GT(first.linear, 0.0);  // the first command moves
  EXPECT_LE(first.linear, f.params().acceleration * 0.1 + 1e-9);
  const FollowCommand c = run(f, Pose(), w.get());
  EXPECT_EQ(c.mode, FollowMode::DRIVE);
  EXPECT_NEAR(c.linear, f.params().max_speed, 1e-9);
  EXPECT_NEAR(c.angular, 0.0, 1e-9);
}

TEST(PathFollower, SpeedObeysTheStoppingDistanceRule)
{
  // v <= sqrt(2 a (d - clearance)), d the known-free travel to a wall across the path.
  for (double wall : { 0.5, 0.6, 0.75, 0.95 })
  {
    Window w;
    w.box(wall + 0.1875, -1.0, wall + 0.3, 1.0, 100);  // the disc reaches it after `wall` m
    PathFollower f;
    f.setPath(straight(2.5), 0.0, false);
    const FollowCommand c = run(f, Pose(), w.get());
    const FollowerParams& p = f.params();
    const double limit = std::sqrt(2.0 * p.deceleration * std::max(0.0, c.free_travel - p.clearance));
    EXPECT_NEAR(c.free_travel, wall, 0.06) << "wall " << wall;
    EXPECT_LE(c.linear, std::min(limit, p.max_speed) + 1e-9) << "wall " << wall;
    EXPECT_GE(c.linear, std::min(limit, p.max_speed) - 1e-9) << "wall " << wall;
  }
}

TEST(PathFollower, FacesThePathInPlaceWhenTheFilterRefusesAnArc)
{
  Window w;
  // A path 0.5 rad to the left of the heading: driven as an arc, unless the filter refuses it.
  std::vector<Point> path;
  for (double s = 0.0; s <= 1.5; s += 0.05)
  {
    path.push_back({ s * std::cos(0.5), s * std::sin(0.5) });
  }
  PathFollower f;
  f.setPath(path, 0.0, false);
  const FollowCommand arc = run(f, Pose(), w.get(), 5);
  EXPECT_EQ(arc.mode, FollowMode::DRIVE) << arc.text;
  EXPECT_GT(arc.linear, 0.0);
  // Refused (speed cap 0): it turns toward the path at the turn speed, and keeps turning although
  // the next answer (to a turn) is no refusal, until the path lies within 0.15 rad of the heading.
  Pose pose;
  FollowCommand c = f.step(pose, w.get(), 1.0, 0.0);
  EXPECT_EQ(c.mode, FollowMode::ROTATE) << c.text;
  EXPECT_EQ(c.linear, 0.0);
  EXPECT_GT(c.angular, arc.angular);
  int turns = 0;
  for (int i = 1; i < 40 && c.mode == FollowMode::ROTATE; ++i, ++turns)
  {
    pose.yaw += c.angular * 0.05;
    c = f.step(pose, w.get(), 1.0 + 0.05 * i);
  }
  EXPECT_EQ(c.mode, FollowMode::DRIVE) << c.text;
  EXPECT_GT(turns, 2);
  EXPECT_GT(pose.yaw, 0.2);
  EXPECT_LT(pose.yaw, 0.5);
  // A refusal with the path ahead changes nothing: the filter and the stuck handling decide.
  EXPECT_EQ(f.step(pose, w.get(), 3.5, 0.0).mode, FollowMode::DRIVE);
}

TEST(PathFollower, StopsAsBlockedWithAnObstacleWithinTheClearance)
{
  Window w;
  w.box(0.3, -0.5, 0.4, 0.5, 100);
  PathFollower f;
  f.setPath(straight(2.0), 0.0, false);
  const FollowCommand c = f.step(Pose(), w.get(), 0.0);
  EXPECT_EQ(c.mode, FollowMode::BLOCKED);
  EXPECT_EQ(c.linear, 0.0);
  EXPECT_EQ(c.angular, 0.0);
}

TEST(PathFollower, TurnsToLookWhereThePathAheadIsUnknownThenWaitsAndDrivesOn)
{
  Window w;
  w.box(0.6, -3.0, 3.0, 3.0, -1);  // nothing seen beyond 0.6 m ahead or to the left
  w.box(-3.0, 0.6, 3.0, 3.0, -1);
  // A path that turns left: its unknown part lies ahead-left.
  std::vector<Point> path;
  for (double s = 0.0; s <= 1.5; s += 0.05)
  {
    path.push_back({ s * std::cos(0.7), s * std::sin(0.7) });
  }
  PathFollower f;
  f.setPath(path, 0.0, false);
  const FollowCommand c = f.step(Pose(), w.get(), 0.0);
  EXPECT_EQ(c.mode, FollowMode::LOOK) << c.text;
  EXPECT_GT(c.angular, 0.0);
  EXPECT_EQ(c.linear, 0.0);
  // Turning with its commands it comes to face the unknown cell, waits look_time there, then drives
  // on (the safety filter decides).
  Pose pose;
  double t = 0.0;
  FollowCommand turning = c;
  for (; t < 5.0 && turning.angular != 0.0; t += 0.05)
  {
    pose.yaw += turning.angular * 0.05;
    turning = f.step(pose, w.get(), t);
  }
  EXPECT_EQ(turning.mode, FollowMode::LOOK) << turning.text;
  EXPECT_GT(pose.yaw, 0.2);
  EXPECT_EQ(turning.linear, 0.0);
  // Then it turns back in place (an arc back would sweep the unseen side), looks at the other side of
  // the path if that is out of view too, and drives on: the window here never changes, and what was in
  // view at a look is not looked at again.
  t += f.params().look_time + 0.01;
  FollowCommand after = f.step(pose, w.get(), t);
  int looks = 1;
  int turns_back = 0;
  FollowMode last = FollowMode::LOOK;
  for (int i = 0; i < 1000 && after.mode != FollowMode::DRIVE; ++i, t += 0.05)
  {
    EXPECT_EQ(after.linear, 0.0) << after.text;
    looks += after.mode == FollowMode::LOOK && last != FollowMode::LOOK ? 1 : 0;
    turns_back += after.mode == FollowMode::ROTATE && last != FollowMode::ROTATE ? 1 : 0;
    last = after.mode;
    pose.yaw += after.angular * 0.05;
    after = f.step(pose, w.get(), t);
  }
  EXPECT_EQ(after.mode, FollowMode::DRIVE) << after.text;
  EXPECT_GT(after.linear, 0.0);
  EXPECT_LE(looks, 3);
  EXPECT_GE(turns_back, 1);
  EXPECT_NEAR(pose.yaw, 0.7, 0.25);  // back on the path's heading
}

TEST(PathFollower, TurnsInPlaceTowardAPathBehind)
{
  Window w;
  std::vector<Point> path;
  for (double x = 0.0; x >= -2.0; x -= 0.05)
  {
    path.push_back({ x, 0.0 });
  }
  PathFollower f;
  f.setPath(path, 0.0, false);
  const FollowCommand c = f.step(Pose(), w.get(), 0.0);
  EXPECT_EQ(c.mode, FollowMode::ROTATE);
  EXPECT_EQ(c.linear, 0.0);
  EXPECT_NEAR(std::abs(c.angular), f.params().turn_speed, 1e-9);
}

TEST(PathFollower, ArcsTowardTheLookAheadPoint)
{
  Window w;
  std::vector<Point> path;
  for (double a = 0.0; a <= 1.5; a += 0.02)
  {
    path.push_back({ std::sin(a), 1.0 - std::cos(a) });  // a left circle of radius 1 m
  }
  PathFollower f;
  f.setPath(path, 0.0, false);
  const FollowCommand c = run(f, Pose(), w.get());
  ASSERT_EQ(c.mode, FollowMode::DRIVE) << c.text;
  const double curvature = c.angular / c.linear;
  EXPECT_NEAR(curvature, 1.0, 0.1);  // a chord's pursuit of a circle drives the circle
}

TEST(PathFollower, ArrivesWithinTheToleranceAndTurnsToTheHeadingWhenAsked)
{
  Window w;
  PathFollower f;
  f.setPath(straight(1.0), 1.0, false);
  Pose at;
  at.x = 0.95;
  EXPECT_EQ(f.step(at, w.get(), 0.0).mode, FollowMode::ARRIVED);
  FollowerParams p;
  p.yaw_tolerance = 0.1;
  PathFollower g(p);
  g.setPath(straight(1.0), 1.0, true);
  const FollowCommand c = g.step(at, w.get(), 0.0);
  EXPECT_EQ(c.mode, FollowMode::ROTATE);
  EXPECT_GT(c.angular, 0.0);
  at.yaw = 0.95;
  EXPECT_EQ(g.step(at, w.get(), 0.1).mode, FollowMode::ARRIVED);
}

TEST(PathFollower, ValidationNamesTheParameter)
{
  FollowerParams p;
  p.max_speed = 0.9;
  try
  {
    PathFollower f(p);
    FAIL();
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_EQ(std::string(e.what()).rfind("max_speed", 0), 0u) << e.what();
  }
}
