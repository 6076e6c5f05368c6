// Benchmark of the simulator: one 752 x 480 frame of the room scene with the default rig and
// settings, single thread. Besides Google Benchmark's mean times per iteration, the counters are
// medians over the frames of the run: `median_cpu_ms` (this thread's CPU time, what one core
// needs, unaffected by other processes; the figure the README quotes) and `median_wall_ms`.
//   rosrun sl_sim sl_sim_benchmark [--benchmark_repetitions=5] [benchmark flags]
// Environment: SL_SIM_BENCH_RIG and SL_SIM_BENCH_SCENE override the files.
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdlib>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "sl_sim/renderer.h"
#include "sl_sim/scene.h"
#include "sl_rig/pattern.h"
#include "sl_rig/rig.h"

namespace
{
std::string fromEnv(const char* name, const std::string& fallback)
{
  const char* v = std::getenv(name);
  return v && *v ? std::string(v) : fallback;
}

double threadCpuMs()
{
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

double median(std::vector<double> v)
{
  if (v.empty())
    return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

void renderFrame(benchmark::State& state, const std::string& scene_name, const sl_sim::SimSettings& settings)
{
  const sl_projector::Rig rig =
      sl_projector::loadRig(fromEnv("SL_SIM_BENCH_RIG", std::string(SL_PROJECTOR_CONFIG_DIR) + "/default_rig.yaml"));
  const sl_sim::Scene scene =
      sl_sim::loadScene(fromEnv("SL_SIM_BENCH_SCENE", std::string(SL_SIM_SCENES_DIR) + "/" + scene_name + ".yaml"));
  const cv::Mat pattern = sl_projector::Pattern(rig.pattern).render();
  sl_sim::Renderer renderer(rig, settings);
  sl_sim::RenderOutput out;
  const Eigen::Isometry3d pose = sl_sim::cameraPoseInWorld(rig);
  renderer.render(scene, pattern, pose, 0, out);  // warm-up: pattern pyramid, buffers
  std::vector<double> wall, cpu;
  uint64_t seed = 1;
  for (auto _ : state)
  {
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = threadCpuMs();
    renderer.render(scene, pattern, pose, seed++, out);
    benchmark::DoNotOptimize(out.image.data);
    cpu.push_back(threadCpuMs() - c0);
    wall.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  state.counters["median_cpu_ms"] = median(cpu);
  state.counters["median_wall_ms"] = median(wall);
}

void BM_RenderRoom(benchmark::State& state)
{
  renderFrame(state, "room", sl_sim::SimSettings());
}

void BM_RenderRoomNoAntialias(benchmark::State& state)
{
  sl_sim::SimSettings s;
  s.antialias = 1;
  renderFrame(state, "room", s);
}

void BM_RenderPlane700(benchmark::State& state)
{
  renderFrame(state, "plane_700", sl_sim::SimSettings());
}
}  // namespace

BENCHMARK(BM_RenderRoom)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(BM_RenderRoomNoAntialias)->Unit(benchmark::kMillisecond)->MinTime(1.0);
BENCHMARK(BM_RenderPlane700)->Unit(benchmark::kMillisecond)->MinTime(1.0);

BENCHMARK_MAIN();
