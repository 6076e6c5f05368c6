// Fuzz target: sl_decoder's Decoder and RayClassifier built for arbitrary accepted rigs.
//
// Input: rig text. When parseRig() accepts it, a decoder and a ray classifier are built for it
// (std::invalid_argument is their documented refusal, e.g. a pattern out of view) and decode a
// black, a white, a noise image and the rig's own pattern on a plane at 0.4 and 0.8 m
// (plane_view.h); with depth tables also in the table depth modes. To keep one input fast, rigs
// with a camera over kMaxCameraPixels or a projector over kMaxProjectorPixels are skipped: sizes
// up to the limits of sl_rig/limits.h are accepted by design and only cost time.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "fuzz_input.h"
#include "plane_view.h"
#include "sl_decoder/decoder.h"
#include "sl_decoder/ray_classifier.h"
#include "sl_rig/rig.h"

namespace
{
constexpr int64_t kMaxCameraPixels = 320 * 240;
constexpr int64_t kMaxProjectorPixels = 1 << 20;

void decodeAll(const sl_projector::Rig& rig, const sl_decoder::DecoderConfig& config,
               const std::vector<cv::Mat>& images, bool classify_rays)
{
  std::unique_ptr<sl_decoder::Decoder> decoder;
  try
  {
    decoder.reset(new sl_decoder::Decoder(rig, config));
  }
  catch (const std::invalid_argument&)
  {
    return;  // documented refusal
  }
  std::unique_ptr<sl_decoder::RayClassifier> rays;
  if (classify_rays)
  {
    try
    {
      rays.reset(new sl_decoder::RayClassifier(rig, config, sl_decoder::RayConfig()));
    }
    catch (const std::invalid_argument&)
    {
    }
  }
  sl_decoder::DecodeResult result;
  std::vector<sl_decoder::RayOutcome> outcomes;
  const size_t primitives = static_cast<size_t>(rig.pattern.rows) * static_cast<size_t>(rig.pattern.cols);
  for (const cv::Mat& image : images)
  {
    decoder->decode(image, result);
    FUZZ_CHECK(result.valid <= result.decoded && result.decoded <= result.identified &&
               static_cast<size_t>(result.identified) <= result.blobs.size());
    for (const sl_decoder::Blob& b : result.blobs)
      if (b.valid)
        FUZZ_CHECK(std::isfinite(b.z) && b.z >= config.min_depth - 1e-6 && b.z <= config.max_depth + 1e-6);
    if (rays)
    {
      rays->classify(image, result, outcomes);
      FUZZ_CHECK(outcomes.size() == primitives);
    }
    if (std::getenv("SL_FUZZ_VERBOSE"))  // to see what a seed reaches
      std::fprintf(stderr, "%s: %zu blobs, %d identified, %d decoded, %d valid\n",
                   sl_decoder::depthModeName(config.depth_mode), result.blobs.size(), result.identified, result.decoded,
                   result.valid);
  }
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  const std::string text(reinterpret_cast<const char*>(data), size);
  sl_projector::Rig rig;
  try
  {
    rig = sl_projector::parseRig(text, "fuzz.yaml");
  }
  catch (const sl_projector::RigFileError&)
  {
    return 0;
  }
  if (static_cast<int64_t>(rig.camera.width) * rig.camera.height > kMaxCameraPixels ||
      static_cast<int64_t>(rig.projector.width) * rig.projector.height > kMaxProjectorPixels)
    return 0;

  const int w = rig.camera.width, h = rig.camera.height;
  std::vector<cv::Mat> images;
  images.emplace_back(h, w, CV_8UC1, cv::Scalar(0));
  images.emplace_back(h, w, CV_8UC1, cv::Scalar(255));
  cv::Mat noise(h, w, CV_8UC1);
  sl_fuzz::Lcg lcg(sl_fuzz::hashBytes(data, size));
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u)
      noise.at<uint8_t>(v, u) = static_cast<uint8_t>(lcg.next());
  images.push_back(noise);
  const cv::Mat pattern = sl_projector::Pattern(rig.pattern).render();
  const sl_fuzz::PlaneRenderer renderer(rig);
  for (double depth : { 0.4, 0.8 })
  {
    sl_fuzz::PlaneView view;
    view.depth = depth;
    cv::Mat image;
    renderer.render(pattern, view, image);
    images.push_back(image);
  }

  sl_decoder::DecoderConfig config;
  decodeAll(rig, config, images, true);
  const size_t cells = static_cast<size_t>(rig.pattern.rows) * static_cast<size_t>(rig.pattern.cols);
  if (rig.tables.rational.size() == cells)
  {
    config.depth_mode = sl_decoder::DepthMode::Rational;
    decodeAll(rig, config, images, false);
  }
  if (rig.tables.linear.size() == cells)
  {
    config.depth_mode = sl_decoder::DepthMode::Linear;
    decodeAll(rig, config, images, false);
  }
  return 0;
}
