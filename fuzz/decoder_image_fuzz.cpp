// Fuzz target: sl_decoder's Decoder and RayClassifier on arbitrary camera images of the default
// rig (sl_projector/config/default_rig.yaml, 752 x 480).
//
// Input: [flags] [depth] [tilt x] [tilt y] [gain] [background] then patches, each
//   [op] [x lo] [x hi] [y lo] [y hi] [w] [h] [w * h grey levels], w and h taken % 64 + 1;
//   op % 4: 0 paste, 1 add (saturating), 2 darken (minimum), 3 tile over the whole image.
//   flags bit 0: start from a plane lit by the pattern (plane_view.h; depth 0.2..2.7 m, tilts
//   -1..1, gain 0..510, background 0..255); else from the background level. bit 1: add noise.
// Besides the sanitizers it checks the result's bookkeeping: counts, valid points within the
// depth range, one outcome per primitive whose decoded blobs exist.
// SL_FUZZ_DUMP=<file.pgm> writes the image an input makes (to look at a finding).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "fuzz_input.h"
#include "plane_view.h"
#include "sl_decoder/decoder.h"
#include "sl_decoder/ray_classifier.h"
#include "sl_rig/rig.h"

namespace
{
struct Fixture
{
  sl_projector::Rig rig;
  sl_decoder::DecoderConfig config;
  std::unique_ptr<sl_decoder::Decoder> decoder;
  std::unique_ptr<sl_decoder::RayClassifier> rays;
  std::unique_ptr<sl_fuzz::PlaneRenderer> renderer;
  cv::Mat pattern;
  sl_fuzz::PlaneView base_view;  // what `base` shows: most mutations keep the header
  cv::Mat base;
  cv::Mat image;
  sl_decoder::DecodeResult result;
  std::vector<sl_decoder::RayOutcome> outcomes;
};

Fixture* fixture = nullptr;

void applyPatch(cv::Mat& image, int op, int x, int y, int w, int h, const std::vector<uint8_t>& pixels)
{
  if (pixels.empty())
    return;
  auto patch = [&](int i, int j) { return pixels[static_cast<size_t>(j * w + i) % pixels.size()]; };
  if (op == 3)
  {
    for (int v = 0; v < image.rows; ++v)
      for (int u = 0; u < image.cols; ++u)
        image.at<uint8_t>(v, u) = patch((u + x) % w, (v + y) % h);
    return;
  }
  for (int j = 0; j < h && y + j < image.rows; ++j)
    for (int i = 0; i < w && x + i < image.cols; ++i)
    {
      uint8_t& p = image.at<uint8_t>(y + j, x + i);
      const int q = patch(i, j);
      p = static_cast<uint8_t>(op == 0 ? q : (op == 1 ? std::min(255, p + q) : std::min<int>(p, q)));
    }
}

void checkResult(const Fixture& f)
{
  const sl_decoder::DecodeResult& r = f.result;
  int identified = 0, decoded = 0, valid = 0;
  for (const sl_decoder::Blob& b : r.blobs)
  {
    identified += b.shape > 0;
    decoded += b.decoded();
    if (b.valid)
    {
      ++valid;
      FUZZ_CHECK(b.decoded());
      FUZZ_CHECK(std::isfinite(b.x) && std::isfinite(b.y) && std::isfinite(b.z));
      FUZZ_CHECK(b.z >= f.config.min_depth - 1e-6 && b.z <= f.config.max_depth + 1e-6);
    }
    if (b.decoded())
      FUZZ_CHECK(b.row < f.rig.pattern.rows && b.col < f.rig.pattern.cols);
  }
  FUZZ_CHECK(identified == r.identified && decoded == r.decoded && valid == r.valid);
  const size_t primitives = static_cast<size_t>(f.rig.pattern.rows) * static_cast<size_t>(f.rig.pattern.cols);
  FUZZ_CHECK(f.outcomes.size() == primitives);
  int total = 0;
  for (int n : f.rays->lastCounts())
    total += n;
  FUZZ_CHECK(static_cast<size_t>(total) == primitives);
  for (const sl_decoder::RayOutcome& o : f.outcomes)
    if (o.state == sl_decoder::RayState::Decoded)
      FUZZ_CHECK(o.blob >= 0 && static_cast<size_t>(o.blob) < r.blobs.size() &&
                 r.blobs[static_cast<size_t>(o.blob)].valid);
}
}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***)
{
  fixture = new Fixture;
  fixture->rig = sl_projector::loadRig(SL_PROJECTOR_CONFIG_DIR "/default_rig.yaml");
  fixture->decoder.reset(new sl_decoder::Decoder(fixture->rig, fixture->config));
  fixture->rays.reset(new sl_decoder::RayClassifier(fixture->rig, fixture->config, sl_decoder::RayConfig()));
  fixture->renderer.reset(new sl_fuzz::PlaneRenderer(fixture->rig));
  fixture->pattern = fixture->decoder->pattern().render();
  // Warm up (first-use allocations in OpenCV are not per-input leaks).
  fixture->renderer->render(fixture->pattern, sl_fuzz::PlaneView(), fixture->image);
  fixture->decoder->decode(fixture->image, fixture->result);
  fixture->rays->classify(fixture->image, fixture->result, fixture->outcomes);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  Fixture& f = *fixture;
  sl_fuzz::FuzzInput in(data, size);
  const uint8_t flags = in.u8();
  sl_fuzz::PlaneView view;
  view.depth = in.range(0.2, 2.7);
  view.tilt_x = in.range(-1.0, 1.0);
  view.tilt_y = in.range(-1.0, 1.0);
  view.gain = in.range(0.0, 510.0);
  view.background = in.u8();
  if (flags & 1)
  {
    if (f.base.empty() || !(view == f.base_view))
    {
      f.renderer->render(f.pattern, view, f.base);
      f.base_view = view;
    }
    f.base.copyTo(f.image);
  }
  else
    f.image = cv::Mat(f.rig.camera.height, f.rig.camera.width, CV_8UC1, cv::Scalar(view.background));
  while (!in.empty())
  {
    const int op = in.u8() % 4;
    const int x = in.u16() % f.image.cols;
    const int y = in.u16() % f.image.rows;
    const int w = in.u8() % 64 + 1, h = in.u8() % 64 + 1;
    applyPatch(f.image, op, x, y, w, h, in.bytes(static_cast<size_t>(w * h)));
  }
  if (flags & 2)
  {
    sl_fuzz::Lcg lcg(sl_fuzz::hashBytes(data, size));
    for (int v = 0; v < f.image.rows; ++v)
      for (int u = 0; u < f.image.cols; ++u)
      {
        uint8_t& p = f.image.at<uint8_t>(v, u);
        p = static_cast<uint8_t>(std::min(255, std::max(0, p + static_cast<int>(lcg.next() % 9) - 4)));
      }
  }
  if (const char* dump = std::getenv("SL_FUZZ_DUMP"))  // the image an input makes, as a PGM
  {
    if (FILE* out = std::fopen(dump, "wb"))
    {
      std::fprintf(out, "P5\n%d %d\n255\n", f.image.cols, f.image.rows);
      for (int v = 0; v < f.image.rows; ++v)
        std::fwrite(f.image.ptr<uint8_t>(v), 1, static_cast<size_t>(f.image.cols), out);
      std::fclose(out);
    }
  }
  f.decoder->decode(f.image, f.result);
  f.rays->classify(f.image, f.result, f.outcomes);
  checkResult(f);
  if (std::getenv("SL_FUZZ_VERBOSE"))  // to see what a seed reaches
    std::fprintf(stderr,
                 "%zu blobs, %d identified, %d decoded, %d valid; rays: %d decoded, %d floor, %d dark, %d lit\n",
                 f.result.blobs.size(), f.result.identified, f.result.decoded, f.result.valid,
                 f.rays->lastCount(sl_decoder::RayState::Decoded), f.rays->lastCount(sl_decoder::RayState::Floor),
                 f.rays->lastCount(sl_decoder::RayState::Dark), f.rays->lastCount(sl_decoder::RayState::Lit));
  return 0;
}
