#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "sl_navigation/nav_grid.h"
#include "sl_navigation/planner.h"

using namespace sl_navigation;

namespace
{
/// A 10 x 10 m map, all free, into which walls are drawn as occupied 0.05 m cells.
class Map
{
public:
  /// With x0 < x1, the box [x0, x1] x [y0, y1] stays unknown (never seen).
  explicit Map(double x0 = 0.0, double y0 = 0.0, double x1 = 0.0, double y1 = 0.0) : grid_(params())
  {
    std::vector<std::int8_t> free(200 * 200, 0);
    for (int iy = 0; iy < 200; ++iy)
    {
      for (int ix = 0; ix < 200; ++ix)
      {
        const double x = -5.0 + (ix + 0.5) * 0.05;
        const double y = -5.0 + (iy + 0.5) * 0.05;
        free[iy * 200 + ix] = x > x0 && x < x1 && y > y0 && y < y1 ? -1 : 0;
      }
    }
    OccupancyView v;
    v.data = free.data();
    v.width = v.height = 200;
    v.resolution = 0.05;
    v.origin_x = v.origin_y = -5.0;
    grid_.fuse(v, 0.0);
  }
  static GridParams params()
  {
    GridParams p;
    p.size = 10.0;
    return p;
  }
  /// Occupies [x0, x1] x [y0, y1].
  void wall(double x0, double y0, double x1, double y1)
  {
    std::vector<std::int8_t> data;
    OccupancyView v;
    v.resolution = 0.05;
    v.origin_x = x0;
    v.origin_y = y0;
    v.width = std::max(1, static_cast<int>(std::lround((x1 - x0) / 0.05)));
    v.height = std::max(1, static_cast<int>(std::lround((y1 - y0) / 0.05)));
    data.assign(v.width * v.height, 100);
    v.data = data.data();
    grid_.fuse(v, 0.0);
  }
  NavGrid& grid() { return grid_; }

private:
  NavGrid grid_;
};

/// Smallest clearance of the plan's cells.
double minClearance(const Planner& planner, const NavGrid& grid, const Plan& plan)
{
  double best = 1e9;
  for (std::size_t i = 1; i + 1 < plan.points.size(); ++i)
  {
    best = std::min(best, planner.clearance(grid.indexX(plan.points[i].x), grid.indexY(plan.points[i].y)));
  }
  return best;
}
}  // namespace

TEST(Planner, StraightAcrossAFreeMap)
{
  Map m;
  Planner planner(PlannerParams(), m.grid().width());
  planner.update(m.grid(), 0.0);
  const Plan p = planner.plan(m.grid(), -3.0, 0.02, 3.0, 0.02);
  ASSERT_EQ(p.status, PlanStatus::OK) << p.text;
  EXPECT_NEAR(p.length, 6.0, 0.1);
  EXPECT_EQ(p.unknown_cells, 0);
  EXPECT_DOUBLE_EQ(p.points.front().x, -3.0);
  EXPECT_DOUBLE_EQ(p.points.back().x, 3.0);
}

TEST(Planner, GoesThroughTheGapOfAWallAndKeepsClearOfItsEdges)
{
  Map m;
  m.wall(-0.1, -5.0, 0.1, -0.4);  // a wall across the map with a 0.8 m gap at y in (-0.4, 0.4)
  m.wall(-0.1, 0.4, 0.1, 5.0);
  PlannerParams pp;
  Planner planner(pp, m.grid().width());
  planner.update(m.grid(), 0.0);
  const Plan p = planner.plan(m.grid(), -2.0, 2.0, 2.0, 2.0);
  ASSERT_EQ(p.status, PlanStatus::OK) << p.text;
  EXPECT_GT(p.length, 2.0 * std::hypot(2.0, 2.0));  // down to the gap and back up
  EXPECT_GE(minClearance(planner, m.grid(), p), pp.lethalDistance());
  bool through_gap = false;
  for (const Point& q : p.points)
  {
    through_gap |= std::abs(q.x) < 0.1 && std::abs(q.y) < 0.2;
  }
  EXPECT_TRUE(through_gap);
}

TEST(Planner, ABlockedDiscClosesAGapUntilItIsTakenAway)
{
  Map m;
  m.wall(-0.1, -5.0, 0.1, -0.4);  // the wall with its 0.8 m gap at y in (-0.4, 0.4)
  m.wall(-0.1, 0.4, 0.1, 5.0);
  Planner planner(PlannerParams(), m.grid().width());
  planner.setBlocked({ Disc{ 0.0, 0.0, 0.1 } });  // where the robot was refused, in the gap
  planner.update(m.grid(), 0.0);
  const Plan closed = planner.plan(m.grid(), -2.0, 0.0, 2.0, 0.0);
  EXPECT_EQ(closed.status, PlanStatus::NO_PATH) << closed.text;
  const Plan inside = planner.plan(m.grid(), -2.0, 0.0, 0.02, 0.02);
  EXPECT_EQ(inside.status, PlanStatus::GOAL_BLOCKED) << inside.text;
  planner.setBlocked({ Disc{ std::nan(""), 0.0, 0.1 }, Disc{ 0.0, 0.0, 0.0 }, Disc{ 50.0, 0.0, 1.0 } });  // ignored
  planner.update(m.grid(), 0.0);
  const Plan open = planner.plan(m.grid(), -2.0, 0.0, 2.0, 0.0);
  EXPECT_EQ(open.status, PlanStatus::OK) << open.text;
  EXPECT_NEAR(open.length, 4.0, 0.1);
}

TEST(Planner, AGoalInsideAnObstacleOrTooNearIsBlocked)
{
  Map m;
  m.wall(1.0, -1.0, 2.0, 1.0);
  Planner planner(PlannerParams(), m.grid().width());
  planner.update(m.grid(), 0.0);
  EXPECT_EQ(planner.plan(m.grid(), -2.0, 0.0, 1.5, 0.0).status, PlanStatus::GOAL_BLOCKED);
  const Plan near = planner.plan(m.grid(), -2.0, 0.0, 0.9, 0.0);  // 0.1 m from the box
  EXPECT_EQ(near.status, PlanStatus::GOAL_BLOCKED);
  EXPECT_NE(near.text.find("from an obstacle"), std::string::npos) << near.text;
  EXPECT_EQ(planner.plan(m.grid(), -2.0, 0.0, 0.7, 0.0).status, PlanStatus::OK);  // 0.3 m from it
}

TEST(Planner, AGoalTooNearAnObstacleMovesWithinTheToleranceOnly)
{
  Map m;
  m.wall(1.0, -1.0, 2.0, 1.0);
  PlannerParams pp;
  Planner planner(pp, m.grid().width());
  planner.update(m.grid(), 0.0);
  const Plan near = planner.plan(m.grid(), -2.0, 0.0, 0.83, 0.0, 0.075);  // 0.17 m from the box
  ASSERT_EQ(near.status, PlanStatus::OK) << near.text;
  EXPECT_GT(near.goal_shift, 0.0);
  EXPECT_LE(near.goal_shift, 0.075);
  EXPECT_NEAR(std::hypot(near.points.back().x - 0.83, near.points.back().y), near.goal_shift, 1e-9);
  EXPECT_FALSE(planner.lethal(m.grid().indexX(near.points.back().x), m.grid().indexY(near.points.back().y)));
  EXPECT_NE(near.text.find("moved"), std::string::npos) << near.text;
  const Plan exact = planner.plan(m.grid(), -2.0, 0.0, 0.5, 0.0, 0.075);  // clear: not moved
  ASSERT_EQ(exact.status, PlanStatus::OK) << exact.text;
  EXPECT_EQ(exact.goal_shift, 0.0);
  EXPECT_DOUBLE_EQ(exact.points.back().x, 0.5);
  // Farther in than the tolerance reaches: refused as before.
  EXPECT_EQ(planner.plan(m.grid(), -2.0, 0.0, 0.9, 0.0, 0.075).status, PlanStatus::GOAL_BLOCKED);
  EXPECT_EQ(planner.plan(m.grid(), -2.0, 0.0, 1.5, 0.0, 0.075).status, PlanStatus::GOAL_BLOCKED);
  EXPECT_EQ(planner.plan(m.grid(), -2.0, 0.0, 0.83, 0.0).status, PlanStatus::GOAL_BLOCKED);  // no tolerance
}

TEST(Planner, AGoalIsNeverMovedIntoUnseenSpace)
{
  // A box seen only from its front (x = 1.0): a goal 0.2 m inside it is too near that face, and the
  // cells farther in are unseen. Moving the goal there would send the robot around to look for a way in.
  Map m(1.05, -1.0, 3.0, 1.0);
  m.wall(1.0, -1.0, 1.05, 1.0);
  Planner planner(PlannerParams(), m.grid().width());
  planner.update(m.grid(), 0.0);
  const Plan inside = planner.plan(m.grid(), -2.0, 0.0, 1.22, 0.0, 0.075);
  EXPECT_EQ(inside.status, PlanStatus::GOAL_BLOCKED) << inside.text;
}

TEST(Planner, AnEnclosedGoalHasNoPath)
{
  Map m;
  m.wall(1.0, -1.0, 3.0, -0.9);  // a closed room of 2 x 2 m
  m.wall(1.0, 0.9, 3.0, 1.0);
  m.wall(1.0, -1.0, 1.1, 1.0);
  m.wall(2.9, -1.0, 3.0, 1.0);
  Planner planner(PlannerParams(), m.grid().width());
  planner.update(m.grid(), 0.0);
  const Plan p = planner.plan(m.grid(), -2.0, 0.0, 2.0, 0.0);
  EXPECT_EQ(p.status, PlanStatus::NO_PATH) << p.text;
  EXPECT_GT(p.expansions, 1000);
}

TEST(Planner, UnknownSpaceIsPlannedThroughButKnownFreeIsPreferred)
{
  // A free corridor around an unknown square: with unknown_cost 0 the path crosses the square,
  // with a high unknown cost it goes around (longer but known).
  GridParams gp;
  gp.size = 10.0;
  NavGrid grid(gp);
  std::vector<std::int8_t> data(200 * 200, 0);
  for (int iy = 80; iy < 120; ++iy)
  {
    for (int ix = 90; ix < 110; ++ix)
    {
      data[iy * 200 + ix] = -1;
    }
  }
  OccupancyView v;
  v.data = data.data();
  v.width = v.height = 200;
  v.resolution = 0.05;
  v.origin_x = v.origin_y = -5.0;
  grid.fuse(v, 0.0);
  PlannerParams cheap;
  cheap.unknown_cost = 0.0;
  Planner a(cheap, grid.width());
  a.update(grid, 0.0);
  const Plan through = a.plan(grid, -2.0, 0.0, 2.0, 0.0);
  ASSERT_EQ(through.status, PlanStatus::OK);
  EXPECT_GT(through.unknown_cells, 10);
  PlannerParams dear;
  dear.unknown_cost = 5.0;
  Planner b(dear, grid.width());
  b.update(grid, 0.0);
  const Plan around = b.plan(grid, -2.0, 0.0, 2.0, 0.0);
  ASSERT_EQ(around.status, PlanStatus::OK);
  EXPECT_EQ(around.unknown_cells, 0);
  EXPECT_GT(around.length, through.length);
}

TEST(Planner, AStartInsideALethalZoneLeavesIt)
{
  Map m;
  m.wall(-0.05, 0.1, 0.05, 3.0);  // the robot stands 0.1 m beside a wall
  Planner planner(PlannerParams(), m.grid().width());
  planner.update(m.grid(), 0.0);
  ASSERT_TRUE(planner.lethal(m.grid().indexX(0.0), m.grid().indexY(0.0)));
  const Plan p = planner.plan(m.grid(), 0.0, 0.0, 2.0, -1.0);
  EXPECT_EQ(p.status, PlanStatus::OK) << p.text;
}

TEST(Planner, OutsideTheMapIsRefusedByName)
{
  Map m;
  Planner planner(PlannerParams(), m.grid().width());
  planner.update(m.grid(), 0.0);
  const Plan p = planner.plan(m.grid(), 0.0, 0.0, 30.0, 0.0);
  EXPECT_EQ(p.status, PlanStatus::GOAL_OUTSIDE);
  EXPECT_NE(p.text.find("outside the map"), std::string::npos);
  EXPECT_EQ(planner.plan(m.grid(), -30.0, 0.0, 0.0, 0.0).status, PlanStatus::START_OUTSIDE);
}

TEST(Planner, TheMapsBorderRingIsOutsideForStartAndGoal)
{
  Map m;  // 10 x 10 m: cells of the outermost ring have centres within 0.05 m of +-5
  Planner planner(PlannerParams(), m.grid().width());
  planner.update(m.grid(), 0.0);
  EXPECT_EQ(planner.plan(m.grid(), 0.0, -4.99, 1.0, 0.0).status, PlanStatus::START_OUTSIDE);
  EXPECT_EQ(planner.plan(m.grid(), 0.0, 4.99, 1.0, 0.0).status, PlanStatus::START_OUTSIDE);
  EXPECT_EQ(planner.plan(m.grid(), 0.0, 0.0, 4.99, 4.99).status, PlanStatus::GOAL_OUTSIDE);
  EXPECT_EQ(planner.plan(m.grid(), 0.0, 0.0, 1e300, 0.0).status, PlanStatus::GOAL_OUTSIDE);
  EXPECT_EQ(planner.plan(m.grid(), 0.0, 0.0, 4.5, 4.5).status, PlanStatus::OK);
}

TEST(Planner, ValidationNamesTheParameter)
{
  PlannerParams p;
  p.inflation_radius = 0.1;  // inside the lethal distance
  try
  {
    Planner planner(p, 10);
    FAIL();
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_EQ(std::string(e.what()).rfind("inflation_radius", 0), 0u) << e.what();
  }
  p = PlannerParams();
  p.robot_radius = -1.0;
  EXPECT_THROW(Planner(p, 10), std::invalid_argument);
}
