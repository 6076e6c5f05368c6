// "No memory allocation per frame after warm-up": counts every heap allocation around decode().
// operator new alone misses OpenCV's buffers (cv::Mat::create goes through cv::fastMalloc, i.e.
// malloc or posix_memalign), so this binary defines the C allocator entry points itself and
// forwards them to glibc's (__libc_malloc, ...). The shared libraries (OpenCV, libstdc++, whose
// operator new calls malloc) bind to these definitions by ELF symbol interposition.
#include <gtest/gtest.h>

#include <malloc.h>

#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <iostream>

#include "sl_evaluation/evaluation.h"
#include "sl_decoder/ray_classifier.h"

#ifdef __SANITIZE_ADDRESS__
#define SKIP_UNDER_ASAN() GTEST_SKIP() << "AddressSanitizer owns malloc: no allocation counter"
namespace
{
std::atomic<long> g_allocations{ 0 };  // unused: the tests are skipped
}  // namespace
#else
#define SKIP_UNDER_ASAN() (void)0
#endif

// AddressSanitizer (make test-asan) replaces malloc itself: there the counter is left out and the
// tests below are skipped.
#ifndef __SANITIZE_ADDRESS__
extern "C"
{
  void* __libc_malloc(size_t size);
  void* __libc_calloc(size_t count, size_t size);
  void* __libc_realloc(void* p, size_t size);
  void* __libc_memalign(size_t alignment, size_t size);
  void* __libc_valloc(size_t size);
  void* __libc_pvalloc(size_t size);
  void __libc_free(void* p);
}

namespace
{
std::atomic<long> g_allocations{ 0 };

inline void count()
{
  g_allocations.fetch_add(1, std::memory_order_relaxed);
}
}  // namespace

extern "C"
{
  void* malloc(size_t size) noexcept
  {
    count();
    return __libc_malloc(size);
  }
  void* calloc(size_t n, size_t size) noexcept
  {
    count();
    return __libc_calloc(n, size);
  }
  // Counted even when it shrinks in place: a per-frame realloc is a per-frame allocation in waiting.
  void* realloc(void* p, size_t size) noexcept
  {
    count();
    return __libc_realloc(p, size);
  }
  void free(void* p) noexcept
  {
    __libc_free(p);
  }
  void* memalign(size_t alignment, size_t size) noexcept
  {
    count();
    return __libc_memalign(alignment, size);
  }
  void* aligned_alloc(size_t alignment, size_t size) noexcept
  {
    count();
    return __libc_memalign(alignment, size);
  }
  int posix_memalign(void** out, size_t alignment, size_t size) noexcept
  {
    count();
    // glibc's own checks: a power of two and a multiple of sizeof(void*).
    if (alignment % sizeof(void*) != 0 || (alignment & (alignment - 1)) != 0 || alignment == 0)
      return EINVAL;
    void* p = __libc_memalign(alignment, size);
    if (!p)
      return ENOMEM;
    *out = p;
    return 0;
  }
  void* valloc(size_t size) noexcept
  {
    count();
    return __libc_valloc(size);
  }
  void* pvalloc(size_t size) noexcept
  {
    count();
    return __libc_pvalloc(size);
  }
}
#endif  // __SANITIZE_ADDRESS__

// The counter must see what it is meant to see, or a zero below proves nothing.
TEST(AllocationCounter, SeesMallocOperatorNewAndOpenCv)
{
  SKIP_UNDER_ASAN();
  long before = g_allocations.load();
  void* volatile p = std::malloc(100);
  std::free(p);
  EXPECT_EQ(g_allocations.load() - before, 1) << "malloc";

  before = g_allocations.load();
  int* volatile q = new int[1000];
  delete[] q;
  EXPECT_GE(g_allocations.load() - before, 1) << "operator new";

  before = g_allocations.load();
  {
    cv::Mat m(480, 752, CV_8UC1);
    m.setTo(0);
  }
  EXPECT_GE(g_allocations.load() - before, 1) << "cv::Mat";
}

TEST(Decoder, NoAllocationPerFrameAfterWarmUp)
{
  SKIP_UNDER_ASAN();
  const sl_projector::Rig rig = sl_projector::loadRig(sl_evaluation::defaultRigFile());
  const sl_sim::Scene scene = sl_sim::loadScene(sl_evaluation::findScene({ "three_planes" }));
  sl_sim::Renderer renderer(rig);
  sl_decoder::Decoder decoder(rig);
  sl_sim::RenderOutput frame;
  renderer.render(scene, decoder.pattern().render(), sl_sim::cameraPoseInWorld(rig), 3, frame);
  sl_decoder::DecodeResult result;
  // The warm-up sizes the buffers, which the counter must see (measured: 92 allocations).
  const long cold = g_allocations.load();
  decoder.decode(frame.image, result);
  std::cout << "first decode: " << g_allocations.load() - cold << " allocations\n";
  EXPECT_GT(g_allocations.load() - cold, 0);
  decoder.decode(frame.image, result);
  const long before = g_allocations.load();
  for (int i = 0; i < 5; ++i)
    decoder.decode(frame.image, result);
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_GT(result.valid, 300);
}

TEST(RayClassifier, NoAllocationPerFrameAfterWarmUp)
{
  SKIP_UNDER_ASAN();
  const sl_projector::Rig rig = sl_projector::loadRig(sl_evaluation::defaultRigFile());
  const sl_sim::Scene scene = sl_sim::loadScene(sl_evaluation::findScene({ "room" }));
  sl_sim::Renderer renderer(rig);
  sl_decoder::Decoder decoder(rig);
  sl_decoder::RayClassifier rays(rig, decoder.config(), sl_decoder::RayConfig());
  sl_sim::RenderOutput frame;
  renderer.render(scene, decoder.pattern().render(), sl_sim::cameraPoseInWorld(rig), 3, frame);
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
