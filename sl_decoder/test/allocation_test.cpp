// "No memory allocation per frame after warm-up": counts operator new calls around decode().
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "sl_decoder/evaluation.h"
#include "sl_decoder/ray_classifier.h"

namespace
{
std::atomic<long> g_allocations{ 0 };
}

void* operator new(std::size_t size)
{
  ++g_allocations;
  if (void* p = std::malloc(size ? size : 1))
    return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept
{
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept
{
  std::free(p);
}

TEST(Decoder, NoAllocationPerFrameAfterWarmUp)
{
  const sl_projector::Rig rig = sl_projector::loadRig(sl_decoder::defaultRigFile());
  const sl_camera::Scene scene = sl_camera::loadScene(sl_decoder::findScene({ "three_planes" }));
  sl_camera::Renderer renderer(rig);
  sl_decoder::Decoder decoder(rig);
  sl_camera::RenderOutput frame;
  renderer.render(scene, decoder.pattern().render(), sl_camera::cameraPoseInWorld(rig), 3, frame);
  sl_decoder::DecodeResult result;
  decoder.decode(frame.image, result);
  decoder.decode(frame.image, result);
  const long before = g_allocations.load();
  for (int i = 0; i < 5; ++i)
    decoder.decode(frame.image, result);
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_GT(result.valid, 300);
}

TEST(RayClassifier, NoAllocationPerFrameAfterWarmUp)
{
  const sl_projector::Rig rig = sl_projector::loadRig(sl_decoder::defaultRigFile());
  const sl_camera::Scene scene = sl_camera::loadScene(sl_decoder::findScene({ "room" }));
  sl_camera::Renderer renderer(rig);
  sl_decoder::Decoder decoder(rig);
  sl_decoder::RayClassifier rays(rig, decoder.config(), sl_decoder::RayConfig());
  sl_camera::RenderOutput frame;
  renderer.render(scene, decoder.pattern().render(), sl_camera::cameraPoseInWorld(rig), 3, frame);
  sl_decoder::DecodeResult result;
  std::vector<sl_decoder::RayOutcome> outcomes;
  decoder.decode(frame.image, result);
  rays.classify(frame.image, result, outcomes);
  const long before = g_allocations.load();
  for (int i = 0; i < 5; ++i)
  {
    decoder.decode(frame.image, result);
    rays.classify(frame.image, result, outcomes);
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_EQ(outcomes.size(), static_cast<size_t>(rig.pattern.rows * rig.pattern.cols));
  EXPECT_GT(rays.lastCount(sl_decoder::RayState::Dark), 100);
}
