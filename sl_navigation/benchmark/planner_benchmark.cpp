// Speed of one replan on a 20 x 20 m map at 0.05 m (400 x 400 cells): update() (obstacles, the
// brushfire, the cost factors) and plan() (A*), on a furnished map with half of it unknown, across
// it; and the worst case: an enclosed goal, where the search exhausts every reachable cell.
#include <cmath>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "sl_navigation/nav_grid.h"
#include "sl_navigation/planner.h"

namespace
{
using namespace sl_navigation;

/// 20 x 20 m: rooms of 4 m with doors, 300 random posts (furniture legs); the right half unknown.
NavGrid furnished(bool enclose_goal)
{
  GridParams gp;
  NavGrid grid(gp);
  const int n = 400;
  std::vector<std::int8_t> data(n * n, 0);
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> cell(0, n - 1);
  for (int i = 0; i < n; ++i)
  {
    for (int wall = 80; wall < n; wall += 80)
    {
      const bool door = (i % 80) > 30 && (i % 80) < 50;
      if (!door)
      {
        data[i * n + wall] = 100;  // walls along y with doors
        data[wall * n + i] = 100;  // walls along x with doors
      }
    }
  }
  for (int k = 0; k < 300; ++k)
  {
    data[cell(rng) * n + cell(rng)] = 100;
  }
  for (int y = 0; y < n; ++y)
  {
    for (int x = n / 2; x < n; ++x)
    {
      if (data[y * n + x] == 0)
      {
        data[y * n + x] = -1;
      }
    }
  }
  if (enclose_goal)
  {
    for (int y = 341; y < 380; ++y)  // a closed, known-free room around the goal
    {
      for (int x = 341; x < 380; ++x)
      {
        data[y * n + x] = 0;
      }
    }
    for (int i = 340; i <= 380; ++i)
    {
      data[340 * n + i] = data[380 * n + i] = data[i * n + 340] = data[i * n + 380] = 100;
    }
  }
  OccupancyView v;
  v.data = data.data();
  v.width = v.height = n;
  v.resolution = 0.05;
  v.origin_x = v.origin_y = -10.0;
  grid.fuse(v, 0.0);
  return grid;
}

void BM_Update(benchmark::State& state)
{
  const NavGrid grid = furnished(false);
  Planner planner(PlannerParams(), grid.width());
  for (auto _ : state)
  {
    planner.update(grid, 1.0);
  }
}
BENCHMARK(BM_Update)->Unit(benchmark::kMillisecond);

void BM_ReplanAcross(benchmark::State& state)
{
  const NavGrid grid = furnished(false);
  PlannerParams params;
  params.heuristic_weight = state.range(0) / 10.0;
  Planner planner(params, grid.width());
  double length = 0.0;
  int expansions = 0;
  for (auto _ : state)
  {
    planner.update(grid, 1.0);
    const Plan p = planner.plan(grid, -9.0, -9.0, 9.0, 9.0);
    length = p.length;
    expansions = p.expansions;
    benchmark::DoNotOptimize(p.points.data());
  }
  state.counters["path_m"] = length;
  state.counters["expansions"] = expansions;
}
BENCHMARK(BM_ReplanAcross)->Unit(benchmark::kMillisecond)->Arg(10)->Arg(15);

void BM_ReplanEnclosedGoal(benchmark::State& state)
{
  const NavGrid grid = furnished(true);
  Planner planner(PlannerParams(), grid.width());
  int expansions = 0;
  for (auto _ : state)
  {
    planner.update(grid, 1.0);
    const Plan p = planner.plan(grid, -9.0, -9.0, 8.0, 8.0);
    expansions = p.expansions;
  }
  state.counters["expansions"] = expansions;
}
BENCHMARK(BM_ReplanEnclosedGoal)->Unit(benchmark::kMillisecond);
}  // namespace

BENCHMARK_MAIN();
