// Decoder speed on rendered 752 x 480 frames, per stage and in total, on one core.
//   rosrun sl_decoder sl_decoder_benchmark --benchmark_repetitions=10 --benchmark_report_aggregates_only=true
#include <stdexcept>
#include <string>

#include <benchmark/benchmark.h>
#include <opencv2/core.hpp>

#include "sl_decoder/evaluation.h"

namespace
{
void decodeScene(benchmark::State& state, const std::vector<std::string>& parts)
{
  cv::setNumThreads(1);
  const sl_projector::Rig rig = sl_projector::loadRig(sl_decoder::defaultRigFile());
  const sl_camera::Scene scene = sl_camera::loadScene(sl_decoder::findScene(parts));
  sl_camera::Renderer renderer(rig);
  sl_decoder::Decoder decoder(rig);
  sl_camera::RenderOutput frame;
  renderer.render(scene, decoder.pattern().render(), sl_camera::cameraPoseInWorld(rig), 7, frame);
  sl_decoder::DecodeResult result;
  decoder.decode(frame.image, result);  // warm-up: buffers reach their size
  sl_decoder::StageTimes sum;
  for (auto _ : state)
  {
    decoder.decode(frame.image, result);
    benchmark::DoNotOptimize(result.valid);
    const sl_decoder::StageTimes& t = result.times;
    sum.detect += t.detect;
    sum.classify += t.classify;
    sum.candidates += t.candidates;
    sum.neighbours += t.neighbours;
    sum.correspond += t.correspond;
    sum.depth += t.depth;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["detect_ms"] = sum.detect / n;
  state.counters["classify_ms"] = sum.classify / n;
  state.counters["candidates_ms"] = sum.candidates / n;
  state.counters["neighbours_ms"] = sum.neighbours / n;
  state.counters["correspond_ms"] = sum.correspond / n;
  state.counters["depth_ms"] = sum.depth / n;
  state.counters["points"] = result.valid;
}

void BM_DecodePlane700(benchmark::State& state)
{
  decodeScene(state, { "plane_700" });
}
void BM_DecodeRoomView(benchmark::State& state)
{
  decodeScene(state, { "room" });
}
}  // namespace

BENCHMARK(BM_DecodePlane700)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DecodeRoomView)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
