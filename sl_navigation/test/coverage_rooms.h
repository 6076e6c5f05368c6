// Furnished rooms of 14-15 m2 for the coverage tests (walls, a sofa, a table and chairs on legs, a
// narrow gap), the truth's reachable floor, and two cleaners run in them on the kinematic robot of
// test_world.h: the coverage runner (sensor -> Navigator) and a bump-and-turn baseline.
#pragma once

#include <cmath>
#include <cstdint>
#include <algorithm>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "sl_navigation/coverage_planner.h"
#include "test_world.h"

namespace sl_navigation_test
{
using sl_navigation::CoverageGrid;
using sl_navigation::CoverageParams;
using sl_navigation::CoveragePlanner;
using sl_navigation::CoverageRunner;
using sl_navigation::FloorCell;
using sl_navigation::NavGrid;
using sl_navigation::NavigatorParams;

constexpr double kCoverRadius = 0.1675;

/// A room with its inner bounds (for start poses) and its name.
struct Room
{
  std::string name;
  World world;
  double x0, y0, x1, y1;  // inside of the walls
};

inline void walls(World& w, double x0, double y0, double x1, double y1)
{
  w.box(x0 - 0.1, y0 - 0.1, x1 + 0.1, y0);
  w.box(x0 - 0.1, y1, x1 + 0.1, y1 + 0.1);
  w.box(x0 - 0.1, y0 - 0.1, x0, y1 + 0.1);
  w.box(x1, y0 - 0.1, x1 + 0.1, y1 + 0.1);
}

/// Four legs of radius @p r at the corners of a w x d piece of furniture centred on (x, y).
inline void legs(World& world, double x, double y, double w, double d, double r)
{
  for (const double sx : { -1.0, 1.0 })
  {
    for (const double sy : { -1.0, 1.0 })
    {
      world.post(x + sx * (0.5 * w - r), y + sy * (0.5 * d - r), r);
    }
  }
}

/// 4.0 x 3.5 m living room: sofa on the north wall, a cabinet 0.52 m beside it (a niche), a table
/// 1.2 x 0.8 m on legs the robot passes under, two chairs on legs.
inline Room livingRoom()
{
  Room r{ "living", World(), -2.0, -1.75, 2.0, 1.75 };
  walls(r.world, r.x0, r.y0, r.x1, r.y1);
  r.world.box(-1.6, 0.95, 0.2, 1.75);          // sofa
  r.world.box(0.72, 1.2, 1.3, 1.75);           // cabinet: a 0.52 m gap to the sofa
  legs(r.world, -0.4, -0.6, 1.2, 0.8, 0.025);  // table
  legs(r.world, 1.0, -0.8, 0.4, 0.4, 0.02);    // chair
  legs(r.world, -1.5, -1.2, 0.4, 0.4, 0.02);   // chair
  return r;
}

/// 4.5 x 3.2 m dining room: sofa on the west wall, a coffee table 0.52 m in front of it (a passage),
/// a dining table on legs with two chairs.
inline Room diningRoom()
{
  Room r{ "dining", World(), -2.25, -1.6, 2.25, 1.6 };
  walls(r.world, r.x0, r.y0, r.x1, r.y1);
  r.world.box(-2.25, -1.0, -1.5, 1.0);       // sofa
  r.world.box(-0.98, -0.5, -0.6, 0.5);       // coffee table (solid): a 0.52 m passage to the sofa
  legs(r.world, 1.0, 0.0, 1.2, 0.8, 0.025);  // dining table
  legs(r.world, 1.0, 0.8, 0.4, 0.4, 0.02);   // chairs
  legs(r.world, 1.0, -0.8, 0.4, 0.4, 0.02);
  return r;
}

/// 4 x 4 m room without its 1 x 1 m north-east corner (15 m2): a desk on legs on the south wall, a
/// chair, a sofa on the west wall, a shelf leaving a 0.52 m gap to the corner.
inline Room officeRoom()
{
  Room r{ "office", World(), -2.0, -2.0, 2.0, 2.0 };
  walls(r.world, r.x0, r.y0, r.x1, r.y1);
  r.world.box(1.0, 1.0, 2.0, 2.0);             // the missing corner
  r.world.box(-0.2, 1.3, 0.48, 2.0);           // shelf: a 0.52 m gap to the corner
  legs(r.world, 0.3, -1.65, 1.4, 0.7, 0.025);  // desk
  legs(r.world, 0.3, -0.95, 0.4, 0.4, 0.02);   // chair
  r.world.box(-2.0, -0.8, -1.2, 1.0);          // sofa
  return r;
}

/// The truth as a fully known NavGrid (map size @p size m, centred on the origin).
inline NavGrid truthGrid(const World& world, double size = 12.0)
{
  sl_navigation::GridParams gp;
  gp.size = size;
  NavGrid grid(gp);
  const int w = static_cast<int>(size / 0.02);
  std::vector<std::int8_t> data(static_cast<std::size_t>(w) * w);
  for (int iy = 0; iy < w; ++iy)
  {
    for (int ix = 0; ix < w; ++ix)
    {
      data[iy * w + ix] = world.occupied(-0.5 * size + (ix + 0.5) * 0.02, -0.5 * size + (iy + 0.5) * 0.02) ? 100 : 0;
    }
  }
  sl_navigation::OccupancyView v;
  v.data = data.data();
  v.width = v.height = w;
  v.resolution = 0.02;
  v.origin_x = v.origin_y = -0.5 * size;
  grid.fuse(v, 1.0);
  return grid;
}

/// A start pose in @p room drawn from @p rng, at least 0.3 m from everything.
inline Pose randomStart(const Room& room, std::mt19937& rng)
{
  std::uniform_real_distribution<double> ux(room.x0, room.x1), uy(room.y0, room.y1), uyaw(-M_PI, M_PI);
  Pose p;
  do
  {
    p.x = ux(rng);
    p.y = uy(rng);
  } while (room.world.clearance(p.x, p.y, kCoverRadius) < 0.3);
  p.yaw = uyaw(rng);
  return p;
}

/// What a cleaning run did: coverage of the truth's reachable floor at the report times.
struct CleanRun
{
  std::vector<double> coverage;      // at each report time
  int contacts = 0;                  // steps touching (bump-and-turn: bumps)
  double min_clearance = 1e9;        // m, disc to the nearest truth cell centre
  double travelled = 0.0;            // m
  double done_time = -1.0;           // s when the runner reported DONE (-1: not)
  double progress = 0.0;             // the runner's own figure (its map's floor)
  std::vector<double> travelled_at;  // m, at each report time
  int targets[6] = { 0, 0, 0, 0, 0, 0 };
  int rounds = 0;                              // exploring: rounds over the room begun
  double mode_time[6] = { 0, 0, 0, 0, 0, 0 };  // per FollowMode, and guarded/escaping (cover)
  int escapes = 0;
  double wall_band = 0.0;  // m, median uncovered band along the straight outer walls (cover)
};

/// Coverage of the truth floor by the discs at @p poses so far (kept in @p truth_cov).
struct TruthMeter
{
  NavGrid grid;
  CoverageGrid coverage;
  std::vector<FloorCell> floor;
  TruthMeter(const World& world, const Pose& start) : grid(truthGrid(world)), coverage(grid, kCoverRadius)
  {
    CoverageParams cp;
    CoveragePlanner planner(cp, grid.width());
    planner.update(grid, coverage, start, 1.0);
    floor = planner.floor();
  }
  double add(const Pose& p)
  {
    coverage.addPose(p);
    return coverage.progress(floor);
  }
};

/// Median (m) over points every 0.05 m along the room's outer walls (0.3 m from the corners) of the
/// distance from the wall to the first covered cell inward (up to 0.6 m); points whose way inward
/// meets furniture first are left out.
inline double wallBand(const Room& room, const TruthMeter& meter)
{
  std::vector<double> bands;
  auto probe = [&](double x, double y, double nx, double ny)
  {
    for (double d = 0.0; d <= 0.6; d += 0.01)
    {
      const double px = x + nx * (d + 0.005), py = y + ny * (d + 0.005);
      if (room.world.occupied(px, py))
      {
        return;  // furniture against the wall
      }
      if (meter.coverage.covered(meter.grid.indexX(px), meter.grid.indexY(py)))
      {
        bands.push_back(d);
        return;
      }
    }
    bands.push_back(0.6);
  };
  for (double x = room.x0 + 0.3; x <= room.x1 - 0.3; x += 0.05)
  {
    probe(x, room.y0 + 0.02, 0.0, 1.0);  // the walls' inner faces lie one truth cell inside the bounds
    probe(x, room.y1, 0.0, -1.0);
  }
  for (double y = room.y0 + 0.3; y <= room.y1 - 0.3; y += 0.05)
  {
    probe(room.x0 + 0.02, y, 1.0, 0.0);
    probe(room.x1, y, -1.0, 0.0);
  }
  if (bands.empty())
  {
    return 0.0;
  }
  std::nth_element(bands.begin(), bands.begin() + bands.size() / 2, bands.end());
  return bands[bands.size() / 2];
}

/// Records a step of @p world at @p pose in @p run; true when it touches.
inline bool record(const World& world, const Pose& before, const Pose& pose, CleanRun& run)
{
  const double c = world.clearance(pose.x, pose.y, kCoverRadius);
  run.min_clearance = std::min(run.min_clearance, c);
  run.travelled += std::hypot(pose.x - before.x, pose.y - before.y);
  return c <= 0.01;  // within half a truth cell of an obstacle cell's centre: touching
}

/// Navigator parameters for cleaning: obstacles kept for 600 s, arrival within 5 cm, headings of
/// frontier goals (yaw_tolerance), turning in place above 0.55 rad of heading error.
inline NavigatorParams cleaningNavigator()
{
  NavigatorParams p;
  p.grid.size = 12.0;
  p.grid.occupied_persistence = 600.0;  // a table leg seen once is not forgotten while cleaning around it
  p.follower.goal_tolerance = 0.05;
  p.follower.yaw_tolerance = 0.3;
  p.follower.rotate_threshold = 0.55;  // turn in place first: a wide arc swings the disc into furniture
  p.follower.max_speed = 0.3;          // core.launch's for cover
  return p;
}

/// The coverage runner on the kinematic robot for @p limit s; coverage reported at @p times (s).
inline CleanRun runCover(const Room& room, Pose pose, double limit, const std::vector<double>& times,
                         const CoverageParams& cp = CoverageParams(), const std::string& picture = "",
                         const NavigatorParams& np = cleaningNavigator())
{
  CleanRun run;
  CoverageRunner runner(np, cp);
  TruthMeter meter(room.world, pose);
  std::vector<std::int8_t> memory, data;
  OccupancyView view;
  const double dt = 0.05;
  std::size_t next_time = 0;
  double t = 0.0;
  sl_navigation::NavState last_state = sl_navigation::NavState::IDLE;
  for (int k = 0; t < limit + 1e-9; ++k, t += dt)
  {
    if (k % 4 == 0)  // the obstacle node's local map at 5 Hz (map_rate)
    {
      room.world.sense(pose, memory, data, view);
      runner.onMap(view, 100.0 + t);
    }
    const sl_navigation::NavOutput& out = runner.step(pose, 100.0 + t, dt);
    const Pose before = pose;
    World::move(pose, out.linear, out.angular, dt);
    if (std::getenv("COVER_TRACE") && out.state != last_state)
    {
      const auto& goal = runner.navigator().goal();
      std::printf("  t %.1f %s -> %s (%s goal %.2f, %.2f) at (%.2f, %.2f): %s\n", t, toString(last_state),
                  toString(out.state), toString(runner.mode()), goal.x, goal.y, pose.x, pose.y, out.reason.c_str());
    }
    last_state = out.state;
    const bool own = out.reason.rfind("coverage", 0) == 0;
    run.mode_time[own ? 5 : static_cast<int>(out.mode)] += dt;
    const bool touch = record(room.world, before, pose, run);
    run.contacts += touch;
    if (touch && std::getenv("COVER_TRACE"))
    {
      std::printf("  contact t %.1f at (%.2f, %.2f, %.2f) %s v %.2f w %.2f: %s\n", t, pose.x, pose.y, pose.yaw,
                  toString(runner.mode()), out.linear, out.angular, out.reason.c_str());
    }
    const double cov = meter.add(pose);
    if (runner.done() && run.done_time < 0.0)
    {
      run.done_time = t;
    }
    while (next_time < times.size() && t + dt > times[next_time] - 1e-9)
    {
      run.coverage.push_back(cov);
      run.travelled_at.push_back(run.travelled);
      ++next_time;
    }
  }
  if (!picture.empty())  // the map with the coverage at the end, as a PPM file
  {
    std::vector<std::uint8_t> rgb;
    runner.coverage().toRgb(runner.navigator().grid(), 100.0 + t, runner.planner().floor(), rgb);
    const int w = runner.coverage().width();
    sl_navigation::writePpm(picture.c_str(), rgb, w, w);
  }
  run.progress = runner.progress();
  run.wall_band = wallBand(room, meter);
  run.escapes = runner.escapes();
  std::copy(runner.targets(), runner.targets() + 6, run.targets);
  run.rounds = runner.rounds();
  return run;
}

/// Bump and turn: straight at 0.3 m/s until the bumper touches, back 0.05 m, turn a random angle of
/// 0.5..pi rad either way at 1 rad/s (a benchmark reference driving the robot directly).
inline CleanRun runBump(const Room& room, Pose pose, double limit, const std::vector<double>& times, unsigned seed)
{
  CleanRun run;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> turn(0.5, M_PI);
  TruthMeter meter(room.world, pose);
  const double dt = 0.05;
  double backing = 0.0;  // m left to back up
  double turning = 0.0;  // rad left to turn (signed)
  std::size_t next_time = 0;
  for (double t = 0.0; t < limit + 1e-9; t += dt)
  {
    double v = 0.3, w = 0.0;
    if (backing > 0.0)
    {
      v = -0.1;
      backing -= 0.1 * dt;
    }
    else if (std::abs(turning) > 1e-9)
    {
      v = 0.0;
      w = std::copysign(std::min(1.0, std::abs(turning) / dt), turning);
      turning -= w * dt;
    }
    Pose next = pose;
    World::move(next, v, w, dt);
    if (v > 0.0 && room.world.clearance(next.x, next.y, kCoverRadius) <= 0.01)
    {
      ++run.contacts;  // the bumper closes: stop here, back up, then turn
      backing = 0.05;
      turning = (rng() % 2 ? 1.0 : -1.0) * turn(rng);
      next = pose;
    }
    run.travelled += std::hypot(next.x - pose.x, next.y - pose.y);
    pose = next;
    const double cov = meter.add(pose);
    while (next_time < times.size() && t + dt > times[next_time] - 1e-9)
    {
      run.coverage.push_back(cov);
      ++next_time;
    }
  }
  return run;
}
}  // namespace sl_navigation_test
