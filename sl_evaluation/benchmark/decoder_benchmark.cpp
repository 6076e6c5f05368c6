// Decoder speed on rendered 752 x 480 frames, per stage and in total, on one core; also decode plus
// the per-ray outcomes (RayClassifier), the decode against one labelling pass (ratio), and near-range
// planes against the 0.70 m plane (ratio; `--rig FILE` for another rig).
//   rosrun sl_evaluation sl_decoder_benchmark --benchmark_repetitions=10 --benchmark_report_aggregates_only=true
#include <iostream>
#include <stdexcept>
#include <string>

#include <benchmark/benchmark.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <chrono>
#include <utility>
#include <vector>

#include "sl_evaluation/evaluation.h"
#include "sl_decoder/ray_classifier.h"

namespace
{
/// Decodes a rendered frame of the scene per iteration; with @p rays also classifies every
/// primitive's ray (RayClassifier), the cost of the nodelet's `ray_ends`.
/// The frame of the scene found by @p parts, rendered with @p decoder's pattern (noise seed 7).
sl_sim::RenderOutput renderScene(const sl_projector::Rig& rig, const sl_decoder::Decoder& decoder,
                                 const std::vector<std::string>& parts)
{
  const sl_sim::Scene scene = sl_sim::loadScene(sl_evaluation::findScene(parts));
  sl_sim::Renderer renderer(rig);
  sl_sim::RenderOutput frame;
  renderer.render(scene, decoder.pattern().render(), sl_sim::cameraPoseInWorld(rig), 7, frame);
  return frame;
}

void decodeScene(benchmark::State& state, const std::vector<std::string>& parts, bool rays = false)
{
  cv::setNumThreads(1);
  const sl_projector::Rig rig = sl_projector::loadRig(sl_evaluation::defaultRigFile());
  sl_decoder::Decoder decoder(rig);
  const sl_sim::RenderOutput frame = renderScene(rig, decoder, parts);
  sl_decoder::DecodeResult result;
  sl_decoder::RayClassifier classifier(rig, decoder.config(), sl_decoder::RayConfig());
  std::vector<sl_decoder::RayOutcome> outcomes;
  decoder.decode(frame.image, result);  // warm-up: buffers reach their size
  classifier.classify(frame.image, result, outcomes);
  sl_decoder::StageTimes sum;
  double rays_ms = 0.0;
  for (auto _ : state)
  {
    decoder.decode(frame.image, result);
    benchmark::DoNotOptimize(result.valid);
    if (rays)
    {
      const auto start = std::chrono::steady_clock::now();
      classifier.classify(frame.image, result, outcomes);
      rays_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      benchmark::DoNotOptimize(outcomes.data());
    }
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
  if (rays)
  {
    state.counters["rays_ms"] = rays_ms / n;
    state.counters["dark"] = classifier.lastCount(sl_decoder::RayState::Dark);
    state.counters["lit"] = classifier.lastCount(sl_decoder::RayState::Lit);
    state.counters["floor"] = classifier.lastCount(sl_decoder::RayState::Floor);
  }
}

/// Runs @p first then @p second in every iteration of @p state, so that a noisy machine slows both
/// alike. @return their mean times, ms.
template <class First, class Second>
std::pair<double, double> timeInTurn(benchmark::State& state, First first, Second second)
{
  double first_ms = 0.0, second_ms = 0.0;
  for (auto _ : state)
  {
    const auto t0 = std::chrono::steady_clock::now();
    first();
    const auto t1 = std::chrono::steady_clock::now();
    second();
    const auto t2 = std::chrono::steady_clock::now();
    first_ms += std::chrono::duration<double, std::milli>(t1 - t0).count();
    second_ms += std::chrono::duration<double, std::milli>(t2 - t1).count();
  }
  const double n = static_cast<double>(state.iterations());
  return { first_ms / n, second_ms / n };
}

/// The decode of the 700 mm plane against one labelling pass on the same frame, in the same run:
/// cv::connectedComponents (8-connected, Spaghetti) of its Otsu binarisation. Both are timed in every
/// iteration, one after the other, so that a noisy machine slows both alike; ratio = decode / label.
void BM_DecodeVsLabellingPlane700(benchmark::State& state)
{
  cv::setNumThreads(1);
  const sl_projector::Rig rig = sl_projector::loadRig(sl_evaluation::defaultRigFile());
  sl_decoder::Decoder decoder(rig);
  const sl_sim::RenderOutput frame = renderScene(rig, decoder, { "plane_700" });
  cv::Mat binary, labels;
  cv::threshold(frame.image, binary, 0, 255, cv::THRESH_BINARY | cv::THRESH_OTSU);
  sl_decoder::DecodeResult result;
  decoder.decode(frame.image, result);
  cv::connectedComponents(binary, labels, 8, CV_32S, cv::CCL_SPAGHETTI);
  const auto [decode_ms, label_ms] = timeInTurn(
      state,
      [&]
      {
        decoder.decode(frame.image, result);
        benchmark::DoNotOptimize(result.valid);
      },
      [&] { benchmark::DoNotOptimize(cv::connectedComponents(binary, labels, 8, CV_32S, cv::CCL_SPAGHETTI)); });
  state.counters["decode_ms"] = decode_ms;
  state.counters["label_ms"] = label_ms;
  state.counters["ratio"] = decode_ms / label_ms;
}

/// The rig of the near-range benchmarks: the default rig, or `--rig FILE` before the benchmark flags.
std::string& nearRigFile()
{
  static std::string file = sl_evaluation::defaultRigFile();
  return file;
}

/// The decode of a plane state.range(0) mm from the camera against the plane 700 mm from it (both
/// placed by planeScene for the rig of nearRigFile()), one after the other in every iteration, so that
/// a noisy machine slows both alike; ratio = near / 700 mm.
void BM_DecodeNearVsPlane700(benchmark::State& state)
{
  cv::setNumThreads(1);
  const sl_projector::Rig rig = sl_projector::loadRig(nearRigFile());
  sl_decoder::Decoder decoder(rig);
  sl_sim::Renderer renderer(rig);
  sl_sim::RenderOutput near, far;
  const cv::Mat pattern = decoder.pattern().render();
  const double distance = static_cast<double>(state.range(0)) / 1000.0;
  renderer.render(sl_evaluation::planeScene(rig, distance), pattern, sl_sim::cameraPoseInWorld(rig), 7, near);
  renderer.render(sl_evaluation::planeScene(rig, 0.70), pattern, sl_sim::cameraPoseInWorld(rig), 7, far);
  sl_decoder::DecodeResult near_result, far_result;
  decoder.decode(near.image, near_result);  // warm-up: buffers reach their size
  decoder.decode(far.image, far_result);
  const auto decodeOf = [&decoder](const cv::Mat& image, sl_decoder::DecodeResult& result)
  {
    return [&decoder, &image, &result]
    {
      decoder.decode(image, result);
      benchmark::DoNotOptimize(result.valid);
    };
  };
  const auto [near_ms, far_ms] = timeInTurn(state, decodeOf(near.image, near_result), decodeOf(far.image, far_result));
  state.counters["near_ms"] = near_ms;
  state.counters["far_ms"] = far_ms;
  state.counters["ratio"] = near_ms / far_ms;
  state.counters["near_points"] = near_result.valid;
  // Where a near frame's time goes (the last iteration's stages).
  state.counters["near_detect_ms"] = near_result.times.detect;
  state.counters["near_classify_ms"] = near_result.times.classify;
  state.counters["near_rest_ms"] = near_result.times.total - near_result.times.detect - near_result.times.classify;
  state.counters["far_points"] = far_result.valid;
}

void BM_DecodePlane700(benchmark::State& state)
{
  decodeScene(state, { "plane_700" });
}
void BM_DecodeRoomView(benchmark::State& state)
{
  decodeScene(state, { "room" });
}
void BM_DecodeAndRaysPlane700(benchmark::State& state)
{
  decodeScene(state, { "plane_700" }, true);
}
void BM_DecodeAndRaysRoomView(benchmark::State& state)
{
  decodeScene(state, { "room" }, true);
}
}  // namespace

BENCHMARK(BM_DecodeVsLabellingPlane700)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DecodePlane700)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DecodeRoomView)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DecodeAndRaysPlane700)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DecodeAndRaysRoomView)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DecodeNearVsPlane700)->Arg(350)->Arg(400)->Arg(450)->Unit(benchmark::kMillisecond);

int main(int argc, char** argv)
{
  // `--rig FILE` (or --rig=FILE) sets the rig of the near-range benchmarks; the rest is Google Benchmark's.
  std::vector<char*> args;
  for (int i = 0; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--rig" || a.rfind("--rig=", 0) == 0)
    {
      if (a == "--rig" && i + 1 >= argc)
      {
        std::cerr << "sl_decoder_benchmark: --rig needs a rig file\n";
        return 2;
      }
      nearRigFile() = a == "--rig" ? argv[++i] : a.substr(6);
      continue;
    }
    args.push_back(argv[i]);
  }
  try
  {
    sl_projector::loadRig(nearRigFile());
  }
  catch (const std::exception& e)
  {
    std::cerr << "sl_decoder_benchmark: --rig: " << e.what() << "\n";
    return 2;
  }
  int n = static_cast<int>(args.size());
  benchmark::Initialize(&n, args.data());
  if (benchmark::ReportUnrecognizedArguments(n, args.data()))
    return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
