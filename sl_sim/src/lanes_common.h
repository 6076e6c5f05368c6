#pragma once
// Internal: what the kernel files (lanes_*.cpp) share: the dispatch attributes, small branch-free
// maths and the run-time AVX2 check. Included only by them (built with -fno-math-errno and
// -fno-trapping-math, see CMakeLists.txt).
#include <cmath>
#include <cstdint>
#include <limits>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(SL_SIM_NO_CLONES)
#define SL_SIMD __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define SL_SIMD
#endif
#define SL_INLINE inline __attribute__((always_inline))

#if defined(__x86_64__) && defined(__GNUC__) && !defined(SL_SIM_NO_CLONES)
// The kernels that need gathers have AVX2 versions written out, chosen at run time.
#define SL_HAVE_AVX2_KERNELS 1
#endif

namespace sl_sim
{
namespace sim
{
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

SL_INLINE float fmin2(float a, float b)
{
  return a < b ? a : b;
}
SL_INLINE float fmax2(float a, float b)
{
  return a > b ? a : b;
}

// floor without a library call (vectorises without SSE4.1 rounding): |x| < 2^31.
SL_INLINE float floorFast(float x)
{
  const float t = static_cast<float>(static_cast<int32_t>(x));
  return t - static_cast<float>(x < t);
}

// log2 to about 0.005 (exponent plus a quadratic in the mantissa); x > 0.
SL_INLINE float log2Approx(float x)
{
  const int32_t bits = __builtin_bit_cast(int32_t, x);
  const float e = static_cast<float>((bits >> 23) - 127);
  const float m = __builtin_bit_cast(float, (bits & 0x007fffff) | 0x3f800000);
  const float f = m - 1.f;
  return e + f * (1.3465f - 0.3465f * f);
}

// 2^x to about 0.2 % for x in [-126, 0]; 0 below.
SL_INLINE float exp2Approx(float x)
{
  const float xc = fmax2(x, -126.f);
  const float fl = floorFast(xc);
  const float f = xc - fl;
  const float p = 1.f + f * (0.6565f + f * (0.2228f + f * 0.0792f));  // 2^f on [0, 1)
  const float scale = __builtin_bit_cast(float, (static_cast<int32_t>(fl) + 127) << 23);
  return x < -126.f ? 0.f : p * scale;
}

// atan2 to about 1e-3 rad (for texture coordinates only).
SL_INLINE float atan2Approx(float y, float x)
{
  const float ax = std::fabs(x), ay = std::fabs(y);
  const float mx = fmax2(ax, ay), mn = fmin2(ax, ay);
  const float a = mn / fmax2(mx, 1e-30f);
  const float s = a * a;
  float r = ((-0.0464964749f * s + 0.15931422f) * s - 0.327622764f) * s * a + a;
  r = ay > ax ? 1.57079637f - r : r;
  r = x < 0.f ? 3.14159274f - r : r;
  return y < 0.f ? -r : r;
}

#ifdef SL_HAVE_AVX2_KERNELS
// True if the CPU runs the written-out AVX2 kernels.
inline bool haveAvx2()
{
  static const bool have = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return have;
}
#endif

}  // namespace sim
}  // namespace sl_sim
