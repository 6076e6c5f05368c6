#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "coverage_rooms.h"
#include "sl_navigation/coverage_planner.h"

using namespace sl_navigation;
using namespace sl_navigation_test;

namespace
{
/// A NavGrid (12 x 12 m) of @p world, known only where x <= @p known_x within 0.2 m of the room
/// [0, x1] x [0, y1] (unknown elsewhere).
NavGrid partlyKnown(const World& world, double known_x, double x1, double y1)
{
  NavGrid grid = truthGrid(world);
  std::vector<std::int8_t> data(600 * 600, -1);
  for (int iy = 0; iy < 600; ++iy)
  {
    for (int ix = 0; ix < 600; ++ix)
    {
      const double x = -6.0 + (ix + 0.5) * 0.02;
      const double y = -6.0 + (iy + 0.5) * 0.02;
      data[iy * 600 + ix] = x > known_x ? 0 : (world.occupied(x, y) ? 100 : 0);
    }
  }
  GridParams gp;
  gp.size = 12.0;
  NavGrid out(gp);
  OccupancyView v;
  v.data = data.data();
  v.width = v.height = 600;
  v.resolution = 0.02;
  v.origin_x = v.origin_y = -6.0;
  out.fuse(v, 1.0);
  // Forget what lies beyond known_x: a window of suspects (50) there makes those cells unknown.
  for (std::int8_t& c : data)
  {
    c = -1;
  }
  for (int iy = 0; iy < 600; ++iy)
  {
    for (int ix = 0; ix < 600; ++ix)
    {
      const double x = -6.0 + (ix + 0.5) * 0.02;
      const double y = -6.0 + (iy + 0.5) * 0.02;
      const bool room = x >= -0.2 && y >= -0.2 && x <= x1 + 0.2 && y <= y1 + 0.2;
      data[iy * 600 + ix] = x > known_x || !room ? 50 : -1;
    }
  }
  out.fuse(v, 1.0);
  return out;
}

World closedRoom(double x1, double y1)
{
  World w;
  walls(w, 0.0, 0.0, x1, y1);
  return w;
}

/// Drives every goal of each target in straight lines until DONE (or @p max targets); marks coverage.
std::vector<CoverageTarget> sweepAll(CoveragePlanner& planner, const NavGrid& grid, CoverageGrid& cov, Pose& pose,
                                     int max_targets = 200)
{
  std::vector<CoverageTarget> done;
  cov.addPose(pose);
  for (int k = 0; k < max_targets; ++k)
  {
    CoverageTarget t = planner.next(grid, cov, pose, 2.0);
    done.push_back(t);
    if (t.mode == CoverageMode::DONE || t.mode == CoverageMode::FRONTIER)
    {
      break;
    }
    for (const NavGoal& g : t.goals)
    {
      pose.x = g.x;
      pose.y = g.y;
      cov.addPose(pose);
    }
  }
  return done;
}

/// Distance (m) from (x, y) to the nearest point of an occupied cell of @p grid (within 1 m).
double nearestOccupied(const NavGrid& grid, double x, double y)
{
  const double h = 0.5 * grid.params().resolution;
  double best = 1.0;
  for (int iy = grid.indexY(y - 1.0); iy <= grid.indexY(y + 1.0); ++iy)
  {
    for (int ix = grid.indexX(x - 1.0); ix <= grid.indexX(x + 1.0); ++ix)
    {
      if (grid.cell(ix, iy, 2.0) == Cell::Occupied)
      {
        const double dx = std::max(0.0, std::abs(grid.centerX(ix) - x) - h);
        const double dy = std::max(0.0, std::abs(grid.centerY(iy) - y) - h);
        best = std::min(best, std::hypot(dx, dy));
      }
    }
  }
  return best;
}

int count(const std::vector<CoverageTarget>& targets, CoverageMode mode)
{
  int n = 0;
  for (const CoverageTarget& t : targets)
  {
    n += t.mode == mode;
  }
  return n;
}
}  // namespace

TEST(CoverageGrid, MarksTheDiscAlongFastMotionWithoutGaps)
{
  GridParams gp;
  gp.size = 4.0;
  const NavGrid grid(gp);
  CoverageGrid cov(grid, 0.1675);
  Pose p;
  p.x = -1.0;
  cov.addPose(p);
  p.x = 1.0;  // 2 m in one step
  cov.addPose(p);
  for (double x = -0.975; x <= 0.975; x += 0.05)
  {
    ASSERT_TRUE(cov.covered(grid.indexX(x), grid.indexY(0.125))) << x;  // within the disc's half width
    ASSERT_TRUE(cov.covered(grid.indexX(x), grid.indexY(-0.125))) << x;
    ASSERT_FALSE(cov.covered(grid.indexX(x), grid.indexY(0.225))) << x;  // beyond it
  }
  const double expected = (2.0 * 0.30 + M_PI * 0.1675 * 0.1675) / (0.05 * 0.05);  // rectangle + two half discs
  EXPECT_NEAR(static_cast<double>(cov.coveredCells()), expected, 0.1 * expected);
  p.x = std::nan("");
  cov.addPose(p);  // ignored, and breaks the segment
  p.x = 1.5;
  p.y = 1.5;
  cov.addPose(p);
  EXPECT_FALSE(cov.covered(grid.indexX(1.25), grid.indexY(0.75)));
  EXPECT_THROW(CoverageGrid(grid, 0.0), std::invalid_argument);
}

TEST(CoverageGrid, ProgressIsCoveredFloorOverFloor)
{
  GridParams gp;
  gp.size = 1.0;
  const NavGrid grid(gp);
  CoverageGrid cov(grid, 0.09);
  std::vector<FloorCell> floor(grid.width() * grid.width(), FloorCell::None);
  EXPECT_EQ(cov.progress(floor), 0.0);  // an empty floor
  for (int ix = 0; ix < grid.width(); ++ix)
  {
    floor[10 * grid.width() + ix] = FloorCell::Swept;  // one row of 20 cells
  }
  cov.markDisc(grid.centerX(0), grid.centerY(10));  // covers 2 cells of the row, and some off the floor
  std::size_t covered = 0, cells = 0;
  EXPECT_DOUBLE_EQ(cov.progress(floor, &covered, &cells), 0.1);
  EXPECT_EQ(covered, 2u);
  EXPECT_EQ(cells, 20u);
  std::vector<std::int8_t> occ;
  cov.toOccupancy(floor, occ);
  EXPECT_EQ(occ[10 * grid.width()], 100);
  EXPECT_EQ(occ[10 * grid.width() + 5], 0);
  EXPECT_EQ(occ[0], -1);
  std::vector<std::uint8_t> rgb;
  cov.toRgb(grid, 1.0, floor, rgb);
  EXPECT_EQ(rgb.size(), static_cast<std::size_t>(3 * grid.width() * grid.width()));
}

TEST(CoveragePlanner, LanesCoverAFreeRectangleThenDone)
{
  const World world = closedRoom(3.0, 2.0);
  const NavGrid grid = truthGrid(world);
  CoverageParams cp;
  CoveragePlanner planner(cp, grid.width());
  CoverageGrid cov(grid, cp.planner.robot_radius);
  Pose pose;
  pose.x = 0.5;
  pose.y = 0.5;
  const std::vector<CoverageTarget> targets = sweepAll(planner, grid, cov, pose);
  std::size_t covered = 0, cells = 0;
  const double p = cov.progress(planner.floor(), &covered, &cells);
  std::printf("3 x 2 m room: %zu targets (%d lanes, %d edges, %d spots), covered %zu of %zu floor cells (%.3f)\n",
              targets.size(), count(targets, CoverageMode::LANE), count(targets, CoverageMode::EDGE),
              count(targets, CoverageMode::SPOT), covered, cells, p);
  ASSERT_FALSE(targets.empty());
  EXPECT_EQ(targets.back().mode, CoverageMode::DONE) << targets.back().text;
  EXPECT_GE(p, 0.99);
  // The floor: the room less a band where the disc cannot reach (centreClearance - robot_radius).
  const double band = cp.centreClearance(0.05) - cp.planner.robot_radius;
  const double floor_area = (3.0 - 2 * band) * (2.0 - 2 * band);
  EXPECT_NEAR(cells * 0.0025, floor_area, 0.1 * floor_area);
  EXPECT_GE(count(targets, CoverageMode::LANE), 6);  // 2 m / 0.25 m lanes, less the walls' bands
  EXPECT_LE(count(targets, CoverageMode::LANE), 10);
}

TEST(CoveragePlanner, EdgePassesKeepTheClearanceAndTheEdgeSpeed)
{
  const World world = closedRoom(3.0, 2.0);
  const NavGrid grid = truthGrid(world);
  CoverageParams cp;
  cp.edges_first = true;
  CoveragePlanner planner(cp, grid.width());
  CoverageGrid cov(grid, cp.planner.robot_radius);
  Pose pose;
  pose.x = 1.5;
  pose.y = 1.0;
  const CoverageTarget t = planner.next(grid, cov, pose, 2.0);
  ASSERT_EQ(t.mode, CoverageMode::EDGE) << t.text;
  EXPECT_DOUBLE_EQ(t.speed_limit, cp.edge_speed);
  ASSERT_GE(t.goals.size(), 2u);
  for (const NavGoal& g : t.goals)
  {
    // The gap between the disc and the near side of the nearest occupied cell of the map.
    const double gap = nearestOccupied(grid, g.x, g.y) - cp.planner.robot_radius;
    EXPECT_GE(gap, cp.edge_clearance - 1e-6) << g.x << ", " << g.y;
    EXPECT_LE(gap, cp.edge_clearance + grid.params().resolution + 1e-6) << g.x << ", " << g.y;
  }
  Pose end = pose;
  const std::vector<CoverageTarget> rest = sweepAll(planner, grid, cov, end);
  EXPECT_EQ(rest.back().mode, CoverageMode::DONE);
  EXPECT_GE(cov.progress(planner.floor()), 0.98);  // measured 0.988: slivers under 0.05 m are left
  EXPECT_THROW(
      []
      {
        CoverageParams bad;
        bad.lane_spacing = 0.4;
        bad.validate();
      }(),
      std::invalid_argument);
}

TEST(CoveragePlanner, ExploresAFrontierWhenTheKnownFloorIsCovered)
{
  const World world = closedRoom(4.0, 2.0);
  const NavGrid grid = partlyKnown(world, 2.0, 4.0, 2.0);  // the east half unknown
  CoverageParams cp;
  CoveragePlanner planner(cp, grid.width());
  CoverageGrid cov(grid, cp.planner.robot_radius);
  Pose pose;
  pose.x = 0.5;
  pose.y = 0.5;
  const std::vector<CoverageTarget> targets = sweepAll(planner, grid, cov, pose);
  ASSERT_EQ(targets.back().mode, CoverageMode::FRONTIER) << targets.back().text;
  EXPECT_GE(cov.progress(planner.floor()), 0.99);  // the known floor is covered first
  const NavGoal& g = targets.back().goals.at(0);
  std::printf("frontier goal (%.3f, %.3f, yaw %.2f): %s\n", g.x, g.y, g.yaw, targets.back().text.c_str());
  EXPECT_TRUE(g.use_yaw);
  EXPECT_LT(g.x, 2.0);
  EXPECT_LT(std::abs(std::remainder(g.yaw, 2.0 * M_PI)), 1.2);  // looking east, at the unknown half
  // Each frontier is looked at once: asking again and again ends with DONE.
  CoverageTarget t;
  int frontiers = 0;
  for (int k = 0; k < 500; ++k)
  {
    t = planner.next(grid, cov, pose, 2.0);
    if (t.mode != CoverageMode::FRONTIER)
    {
      break;
    }
    ++frontiers;
  }
  std::printf("frontier looks until done: %d\n", frontiers);
  EXPECT_EQ(t.mode, CoverageMode::DONE) << t.text;
}

TEST(CoveragePlanner, DoesNotCountUnreachablePockets)
{
  World world = closedRoom(3.0, 2.0);
  walls(world, 2.0, 0.6, 2.9, 1.5);  // a closed box inside the room, with free floor within
  const NavGrid grid = truthGrid(world);
  CoverageParams cp;
  CoveragePlanner planner(cp, grid.width());
  CoverageGrid cov(grid, cp.planner.robot_radius);
  Pose pose;
  pose.x = 0.5;
  pose.y = 0.5;
  planner.update(grid, cov, pose, 2.0);
  const auto& floor = planner.floor();
  EXPECT_EQ(floor[grid.indexY(1.05) * grid.width() + grid.indexX(2.45)], FloorCell::None);  // inside the box
  EXPECT_EQ(floor[grid.indexY(1.0) * grid.width() + grid.indexX(1.0)], FloorCell::Centre);
  const std::vector<CoverageTarget> targets = sweepAll(planner, grid, cov, pose);
  EXPECT_EQ(targets.back().mode, CoverageMode::DONE);
  EXPECT_GE(cov.progress(planner.floor()), 0.99);
  EXPECT_FALSE(cov.covered(grid.indexX(2.45), grid.indexY(1.05)));
  Pose far;
  far.x = 1e9;
  planner.update(grid, cov, far, 2.0);  // outside the map: no floor
  EXPECT_EQ(cov.progress(planner.floor()), 0.0);
  EXPECT_EQ(planner.next(grid, cov, far, 2.0).mode, CoverageMode::DONE);
  planner.failed(NavGoal{ 1e12, -1e12, 0.0, false });  // ignored
  GridParams small;
  small.size = 2.0;
  const NavGrid other(small);
  EXPECT_THROW(planner.update(other, cov, pose, 2.0), std::invalid_argument);
}

TEST(CoverageRunner, StopsForABadPoseAndDrivesOnWithAGoodOne)
{
  NavigatorParams np = cleaningNavigator();
  CoverageRunner runner(np, CoverageParams());
  const World world = closedRoom(3.0, 2.0);
  std::vector<std::int8_t> memory, data;
  OccupancyView view;
  Pose pose;
  pose.x = 1.0;
  pose.y = 1.0;
  EXPECT_FALSE(runner.step(pose, 1.0, 0.05).command);  // no map yet: nothing to send
  world.sense(pose, memory, data, view);
  ASSERT_TRUE(runner.onMap(view, 1.0));
  Pose bad = pose;
  bad.yaw = std::nan("");
  const NavOutput& out = runner.step(bad, 1.05, 0.05);
  EXPECT_EQ(out.linear, 0.0);
  EXPECT_FALSE(runner.done());  // a bad pose does not end the cleaning
  double moved = 0.0;
  for (double t = 1.1; t < 20.0; t += 0.05)
  {
    if (std::fmod(t, 0.5) < 0.05)
    {
      world.sense(pose, memory, data, view);
      runner.onMap(view, t);
    }
    const NavOutput& o = runner.step(pose, t, 0.05);
    const Pose before = pose;
    World::move(pose, o.linear, o.angular, 0.05);
    moved += std::hypot(pose.x - before.x, pose.y - before.y);
  }
  std::printf("20 s in a 3 x 2 m room: %.2f m driven, progress %.3f\n", moved, runner.progress());
  EXPECT_GT(moved, 2.7);               // measured 3.95 m
  EXPECT_GT(runner.progress(), 0.25);  // measured 0.359
}

TEST(CoverageRunner, KeepsTheFilterSpeedCapAndSummarisesTheProgress)
{
  CoverageRunner runner(cleaningNavigator(), CoverageParams());
  const World world = closedRoom(3.0, 2.0);
  std::vector<std::int8_t> memory, data;
  OccupancyView view;
  Pose pose;
  pose.x = 1.0;
  pose.y = 1.0;
  EXPECT_EQ(runner.summary(), "coverage 0.0 % of 0.00 m2 reachable floor, waiting for the map");
  double fastest = 0.0, moved = 0.0;
  for (double t = 1.0; t < 15.0; t += 0.05)
  {
    if (std::fmod(t, 0.5) < 0.05)
    {
      world.sense(pose, memory, data, view);
      runner.onMap(view, t);
    }
    const NavOutput& o = runner.step(pose, t, 0.05, 0.08);  // the filter let 0.08 m/s through
    fastest = std::max(fastest, o.linear);
    const Pose before = pose;
    World::move(pose, o.linear, o.angular, 0.05);
    moved += std::hypot(pose.x - before.x, pose.y - before.y);
  }
  const std::string line = runner.summary();
  std::printf("capped at 0.08 m/s: fastest %.3f m/s, %.2f m driven; %s\n", fastest, moved, line.c_str());
  // The follower adds the rise its acceleration allows in a step to what the filter let through.
  EXPECT_LE(fastest, 0.08 + runner.navigator().params().follower.acceleration * 0.05 + 1e-9);
  EXPECT_GT(moved, 0.8);  // measured 1.36 m
  EXPECT_GT(runner.floorArea(), 1.0);
  char expected[80];
  std::snprintf(expected, sizeof(expected), "coverage %.1f %% of %.2f m2", 100.0 * runner.progress(),
                runner.floorArea());
  EXPECT_EQ(line.rfind(expected, 0), 0u) << line;
}

// Cover against bump and turn in three furnished rooms, 10 simulated minutes from the same start
// (COVER_SEEDS seeds each, default 3; COVER_EDGES_FIRST=1: edge passes before lanes; COVER_TRACE=1:
// each goal's end and each contact; COVER_PICTURE=<dir>: the first seed's map and coverage as PPM).
// Coverage is of the truth's reachable floor (TruthMeter).
TEST(CoverageLoop, CleansFurnishedRoomsWithoutTouching)
{
  const std::vector<double> times = { 60.0, 120.0, 300.0, 600.0 };
  const int seeds = std::getenv("COVER_SEEDS") ? std::atoi(std::getenv("COVER_SEEDS")) : 3;
  std::printf(
      "room   seed | cover %% at 1, 2, 5, 10 min | bump and turn %% at 1, 2, 5, 10 min | ratio at 5 min | "
      "contacts | done s | lanes edges spots frontiers | min clearance m\n");
  for (const Room& room : { livingRoom(), diningRoom(), officeRoom() })
  {
    for (int seed = 1; seed <= seeds; ++seed)
    {
      std::mt19937 rng(seed);
      const Pose start = randomStart(room, rng);
      CoverageParams cp;
      cp.edges_first = std::getenv("COVER_EDGES_FIRST") != nullptr;
      const char* dir = std::getenv("COVER_PICTURE");
      const std::string picture = dir && seed == 1 ? std::string(dir) + "/coverage_" + room.name + ".ppm" : "";
      const CleanRun c = runCover(room, start, times.back(), times, cp, picture);
      const CleanRun b = runBump(room, start, times.back(), times, seed);
      std::printf(
          "%-6s %4d | %5.1f %5.1f %5.1f %5.1f     | %5.1f %5.1f %5.1f %5.1f               | %14.2f | %3d, %3d | "
          "%6.0f | %5d %5d %5d %9d | %.3f\n",
          room.name.c_str(), seed, 100 * c.coverage[0], 100 * c.coverage[1], 100 * c.coverage[2], 100 * c.coverage[3],
          100 * b.coverage[0], 100 * b.coverage[1], 100 * b.coverage[2], 100 * b.coverage[3],
          c.coverage[2] / std::max(b.coverage[2], 1e-9), c.contacts, b.contacts, c.done_time, c.targets[0],
          c.targets[1], c.targets[2], c.targets[3], c.min_clearance);
      std::printf(
          "            time per mode: drive %.0f s, rotate %.0f, look %.0f, blocked %.0f, arrived %.0f, "
          "guard/escape %.0f (%d escapes); %.1f m (bump and turn %.1f m); "
          "median uncovered band along the walls %.2f m\n",
          c.mode_time[0], c.mode_time[1], c.mode_time[2], c.mode_time[3], c.mode_time[4], c.mode_time[5], c.escapes,
          c.travelled, b.travelled, c.wall_band);
      EXPECT_EQ(c.contacts, 0) << room.name << " seed " << seed;
      EXPECT_GE(c.coverage.back(), 0.8) << room.name << " seed " << seed;        // measured 0.908..0.985
      EXPECT_GE(c.coverage[2], b.coverage[2]) << room.name << " seed " << seed;  // measured 1.05..1.40 times
      EXPECT_LE(c.wall_band, 0.10) << room.name << " seed " << seed;  // the cleaning bound; measured 0.05..0.10
    }
  }
}

TEST(CoverageLoop, ExploresFurnishedRoomsInLongLegs)
{
  // behaviour roam: ROAM legs and frontiers with the navigator's default parameters, forever.
  const std::vector<double> times = { 90.0, 300.0 };
  const int seeds = std::getenv("COVER_SEEDS") ? std::atoi(std::getenv("COVER_SEEDS")) : 2;
  std::printf(
      "room   seed | m in 90 s, 300 s | m/min over 300 s | driven over %% at 90, 300 s | rounds | roam frontier "
      "targets | contacts | min clearance m\n");
  for (const Room& room : { livingRoom(), diningRoom(), officeRoom() })
  {
    for (int seed = 1; seed <= seeds; ++seed)
    {
      std::mt19937 rng(seed);
      const Pose start = randomStart(room, rng);
      CoverageParams cp;
      cp.roam = true;
      NavigatorParams np;  // navigate's, but frontier goals are looked at (their heading)
      np.grid.size = 12.0;
      np.follower.yaw_tolerance = 0.3;
      const CleanRun e = runCover(room, start, times.back(), times, cp, "", np);
      std::printf(
          "%-6s %4d | %5.1f %6.1f     | %5.2f            | %5.1f %5.1f               | %6d | %4d %8d "
          "        | %3d      | %.3f\n",
          room.name.c_str(), seed, e.travelled_at[0], e.travelled_at[1], e.travelled_at[1] / 5.0, 100 * e.coverage[0],
          100 * e.coverage[1], e.rounds, e.targets[5], e.targets[3], e.contacts, e.min_clearance);
      std::printf(
          "            time per mode: drive %.0f s, rotate %.0f, look %.0f, blocked %.0f, arrived %.0f, "
          "guard/escape %.0f (%d escapes)\n",
          e.mode_time[0], e.mode_time[1], e.mode_time[2], e.mode_time[3], e.mode_time[4], e.mode_time[5], e.escapes);
      EXPECT_EQ(e.contacts, 0) << room.name << " seed " << seed;
      EXPECT_GT(e.min_clearance, 0.0) << room.name << " seed " << seed;
      EXPECT_GE(e.travelled_at[1] / 5.0, 11.0) << room.name << " seed " << seed;  // m/min; measured 16.6..20.2
    }
  }
}
