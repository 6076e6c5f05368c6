// Speed of the local map (LocalMap::insert of one cloud), of the swept-path checks, and of OctoMap's
// insertion of the same rays (when built with liboctomap-dev), on one core.
//   rosrun sl_obstacle sl_obstacle_benchmark --benchmark_repetitions=10
//       --benchmark_report_aggregates_only=true   (or: make bench)
#include <algorithm>
#include <cmath>
#include <vector>

#include <benchmark/benchmark.h>

#include "sl_obstacle/local_map.h"
#include "sl_obstacle/path_checker.h"

#ifdef SL_OBSTACLE_HAVE_OCTOMAP
#include <octomap/OcTree.h>
#endif

namespace
{
using sl_obstacle::MapRay;
using sl_obstacle::RayKind;

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
// The sensor's pose in odom (off the axes, so that no ray runs along a cell boundary).
constexpr double kSensorX = 0.31, kSensorY = -0.17, kSensorZ = 0.09, kYaw = 0.3;

/// The pattern's 16 x 64 fan from a sensor 0.09 m above the floor: the lower rows end on the floor
/// 0.5 .. 1.2 m away (floor: free), the upper rows on a wall 1.2 m ahead (decoded: hit); one ray in
/// 9 is lit (suspect) and one in 13 dark (free to 80 % of its length).
std::vector<MapRay> fan()
{
  std::vector<MapRay> rays;
  const double wall = 1.2;
  for (int row = 0; row < 16; ++row)
  {
    const double el = (-10.2 + 14.2 * row / 15.0) * kDeg;
    for (int col = 0; col < 64; ++col)
    {
      const double az = (-20.0 + 40.0 * col / 63.0) * kDeg;
      const double to_wall = wall / std::cos(az);  // horizontal range to the wall along the ray
      const double to_floor = el < 0.0 ? kSensorZ / std::tan(-el) : 1e9;
      const double range = std::min(to_wall, to_floor);
      const int i = row * 64 + col;
      RayKind kind = to_floor < to_wall ? RayKind::Free : RayKind::Hit;
      double f = 1.0;
      if (i % 9 == 4)
      {
        kind = RayKind::Suspect;
      }
      else if (i % 13 == 6)
      {
        kind = RayKind::Free;
        f = 0.8;
      }
      const double h = f * range;
      const double fx = h * std::cos(az), fy = h * std::sin(az);
      MapRay r;
      r.sx = static_cast<float>(kSensorX);
      r.sy = static_cast<float>(kSensorY);
      r.sz = static_cast<float>(kSensorZ);
      r.ex = static_cast<float>(kSensorX + fx * std::cos(kYaw) - fy * std::sin(kYaw));
      r.ey = static_cast<float>(kSensorY + fx * std::sin(kYaw) + fy * std::cos(kYaw));
      r.ez = static_cast<float>(kSensorZ + h * std::tan(el));
      r.kind = kind;
      rays.push_back(r);
    }
  }
  return rays;
}

void BM_LocalMapInsert1024(benchmark::State& state)
{
  const std::vector<MapRay> rays = fan();
  sl_obstacle::LocalMap map{ sl_obstacle::MapParams() };
  map.recenter(kSensorX, kSensorY);
  double stamp = 0.0;
  for (auto _ : state)
  {
    map.insert(rays, stamp);
    stamp += 0.1;
    benchmark::DoNotOptimize(map.state(kSensorX + 0.5, kSensorY, stamp));
  }
  state.counters["rays"] = static_cast<double>(rays.size());
}

/// A map as after a few clouds: the fan seen from three poses, the robot's trail free.
sl_obstacle::LocalMap seenMap()
{
  sl_obstacle::LocalMap map{ sl_obstacle::MapParams() };
  std::vector<MapRay> rays = fan();
  for (int k = 0; k < 3; ++k)
  {
    map.insert(rays, 0.1 * k);
    for (MapRay& r : rays)
    {
      r.sx += 0.05F;
      r.ex += 0.05F;
    }
  }
  for (double s = 0.0; s <= 0.5; s += 0.01)
  {
    map.markFreeDisc(kSensorX - s * std::cos(kYaw), kSensorY - s * std::sin(kYaw), 0.2, 0.3);
  }
  return map;
}

void BM_BestHeading25(benchmark::State& state)
{
  const sl_obstacle::LocalMap map = seenMap();
  const sl_obstacle::FootprintParams fp;
  for (auto _ : state)
  {
    const sl_obstacle::HeadingChoice c =
        sl_obstacle::bestHeading(map, fp, kSensorX, kSensorY, kYaw, 7.5 * kDeg, 12, 1.2, 0.4);
    benchmark::DoNotOptimize(c.path.free);
  }
  state.counters["headings"] = 25;
}

void BM_SweepStraight(benchmark::State& state)
{
  const sl_obstacle::LocalMap map = seenMap();
  const sl_obstacle::FootprintParams fp;
  int cells = 0;
  for (auto _ : state)
  {
    const sl_obstacle::PathResult r = sl_obstacle::sweepStraight(map, fp, kSensorX, kSensorY, kYaw, 1, 1.2, 0.4);
    benchmark::DoNotOptimize(r.free);
    cells = r.swept_cells;
  }
  state.counters["cells"] = cells;
}

#ifdef SL_OBSTACLE_HAVE_OCTOMAP
void octomapInsert(benchmark::State& state, bool discretize)
{
  const std::vector<MapRay> rays = fan();
  octomap::Pointcloud cloud;
  for (const MapRay& r : rays)
  {
    cloud.push_back(r.ex, r.ey, r.ez);
  }
  const octomap::point3d origin(static_cast<float>(kSensorX), static_cast<float>(kSensorY),
                                static_cast<float>(kSensorZ));
  octomap::OcTree tree(0.02);
  for (auto _ : state)
  {
    tree.insertPointCloud(cloud, origin, -1.0, false, discretize);
  }
  state.counters["rays"] = static_cast<double>(rays.size());
  state.counters["nodes"] = static_cast<double>(tree.size());
}

void BM_OctoMapInsertPointCloud1024(benchmark::State& state)
{
  octomapInsert(state, false);
}
void BM_OctoMapInsertPointCloud1024Discretized(benchmark::State& state)
{
  octomapInsert(state, true);
}
#endif
}  // namespace

BENCHMARK(BM_LocalMapInsert1024)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SweepStraight)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BestHeading25)->Unit(benchmark::kMillisecond);
#ifdef SL_OBSTACLE_HAVE_OCTOMAP
BENCHMARK(BM_OctoMapInsertPointCloud1024)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OctoMapInsertPointCloud1024Discretized)->Unit(benchmark::kMillisecond);
#endif
BENCHMARK_MAIN();
