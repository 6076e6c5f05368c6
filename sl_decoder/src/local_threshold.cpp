#include "local_threshold.h"

#include <algorithm>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define SL_X86 1
#endif

namespace sl_decoder
{
namespace local_threshold
{

namespace
{
/// The constants of the pixels whose window lies inside the row: one area, one threshold.
struct Interior
{
  const uint8_t* src;
  const int32_t* pre;
  int r;
  float inv_area;  ///< 1 / area
  float off;       ///< offset rounded to the area's integer grid, over the area
  uint64_t* bits;
  float* weight;
};

/// ORs the @p n-bit group @p m into the row mask at bit @p x (the mask has one spare word).
inline void orBits(uint64_t* bits, int x, uint64_t m, int n)
{
  if (m == 0)
    return;
  const int shift = x & 63;
  bits[x >> 6] |= m << shift;
  if (shift > 64 - n)
    bits[(x >> 6) + 1] |= m >> (64 - shift);
}

// Every path computes mean = float(sum) * inv_area, the test value > mean + off and the weight
// value - mean, lane for lane the same operations: the results are bit-identical.
int interiorPortable(const Interior& k, int x, int end)
{
  for (; x < end; ++x)
  {
    const float mean = static_cast<float>(k.pre[x + k.r + 1] - k.pre[x - k.r]) * k.inv_area;
    const float value = static_cast<float>(k.src[x]);
    if (value > mean + k.off)
      k.bits[x >> 6] |= uint64_t{ 1 } << (x & 63);
    k.weight[x] = value - mean;
  }
  return x;
}

#if defined(SL_X86)
int interiorSse2(const Interior& k, int x, int end)
{
  const __m128 inv_area = _mm_set1_ps(k.inv_area), off = _mm_set1_ps(k.off);
  const __m128i zero = _mm_setzero_si128();
  for (; x + 16 <= end; x += 16)
  {
    const __m128i v8 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(k.src + x));
    const __m128i lo16 = _mm_unpacklo_epi8(v8, zero), hi16 = _mm_unpackhi_epi8(v8, zero);
    const __m128i v32[4] = { _mm_unpacklo_epi16(lo16, zero), _mm_unpackhi_epi16(lo16, zero),
                             _mm_unpacklo_epi16(hi16, zero), _mm_unpackhi_epi16(hi16, zero) };
    uint64_t m = 0;
    for (int q = 0; q < 4; ++q)
    {
      const int xq = x + 4 * q;
      const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(k.pre + xq + k.r + 1));
      const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(k.pre + xq - k.r));
      const __m128 mean = _mm_mul_ps(_mm_cvtepi32_ps(_mm_sub_epi32(a, b)), inv_area);
      const __m128 value = _mm_cvtepi32_ps(v32[q]);
      m |= static_cast<uint64_t>(_mm_movemask_ps(_mm_cmpgt_ps(value, _mm_add_ps(mean, off)))) << (4 * q);
      _mm_storeu_ps(k.weight + xq, _mm_sub_ps(value, mean));
    }
    orBits(k.bits, x, m, 16);
  }
  return x;
}

// Only "avx2", not "fma": a fused multiply-add would round differently from the other paths.
__attribute__((target("avx2"))) int interiorAvx2(const Interior& k, int x, int end)
{
  const __m256 inv_area = _mm256_set1_ps(k.inv_area), off = _mm256_set1_ps(k.off);
  for (; x + 32 <= end; x += 32)
  {
    uint64_t m = 0;
    for (int q = 0; q < 4; ++q)
    {
      const int xq = x + 8 * q;
      const __m256i v32 = _mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(k.src + xq)));
      const __m256i a = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(k.pre + xq + k.r + 1));
      const __m256i b = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(k.pre + xq - k.r));
      const __m256 mean = _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_sub_epi32(a, b)), inv_area);
      const __m256 value = _mm256_cvtepi32_ps(v32);
      const __m256 above = _mm256_cmp_ps(value, _mm256_add_ps(mean, off), _CMP_GT_OQ);
      m |= static_cast<uint64_t>(static_cast<uint32_t>(_mm256_movemask_ps(above))) << (8 * q);
      _mm256_storeu_ps(k.weight + xq, _mm256_sub_ps(value, mean));
    }
    orBits(k.bits, x, m, 32);
  }
  return x;
}

/// Prefix sums of four rows in one loop: four independent carry chains.
void prefix4(const int32_t* const* v, int32_t* const* pre, int w)
{
  __m128i carry[4];
  for (int k = 0; k < 4; ++k)
  {
    pre[k][0] = 0;
    carry[k] = _mm_setzero_si128();
  }
  int x = 0;
  for (; x + 4 <= w; x += 4)
    for (int k = 0; k < 4; ++k)
    {
      __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(v[k] + x));
      a = _mm_add_epi32(a, _mm_slli_si128(a, 4));
      a = _mm_add_epi32(a, _mm_slli_si128(a, 8));
      a = _mm_add_epi32(a, carry[k]);
      _mm_storeu_si128(reinterpret_cast<__m128i*>(pre[k] + x + 1), a);
      carry[k] = _mm_shuffle_epi32(a, _MM_SHUFFLE(3, 3, 3, 3));
    }
  for (int k = 0; k < 4; ++k)
    for (int i = x; i < w; ++i)
      pre[k][i + 1] = pre[k][i] + v[k][i];
}
#endif
}  // namespace

bool supported(Path path)
{
#if defined(SL_X86)
  if (path == Path::Avx2)
    return __builtin_cpu_supports("avx2");
  return true;
#else
  return path == Path::Portable;
#endif
}

Path fastestPath()
{
  if (supported(Path::Avx2))
    return Path::Avx2;
  return supported(Path::Sse2) ? Path::Sse2 : Path::Portable;
}

void slideColumnSums(const int32_t* __restrict in, const uint8_t* __restrict add, const uint8_t* __restrict sub, int w,
                     int32_t* __restrict out)
{
  // One loop per case, each simple enough for the compiler to vectorise.
  if (add != nullptr && sub != nullptr)
    for (int x = 0; x < w; ++x)
      out[x] = in[x] + static_cast<int32_t>(add[x]) - static_cast<int32_t>(sub[x]);
  else if (add != nullptr)
    for (int x = 0; x < w; ++x)
      out[x] = in[x] + static_cast<int32_t>(add[x]);
  else if (sub != nullptr)
    for (int x = 0; x < w; ++x)
      out[x] = in[x] - static_cast<int32_t>(sub[x]);
  else
    std::copy(in, in + w, out);
}

void prefixSums(const int32_t* const* v, int32_t* const* pre, int n, int w)
{
  int k = 0;
#if defined(SL_X86)
  for (; k + 4 <= n; k += 4)
    prefix4(v + k, pre + k, w);
#endif
  for (; k < n; ++k)
  {
    pre[k][0] = 0;
    for (int x = 0; x < w; ++x)
      pre[k][x + 1] = pre[k][x] + v[k][x];
  }
}

void thresholdRow(const RowInput& in, Path path, uint64_t* bits, float* weight)
{
  const int w = in.w, r = in.r;
  std::fill(bits, bits + ((w + 63) >> 6) + 1, uint64_t{ 0 });
  // Interior: the window lies inside the row, one area for all (integer offset on that area).
  const int lo = std::min(r, w), hi = std::max(lo, w - r - 1);
  const int32_t area_in = in.rows * (2 * r + 1);
  const int32_t offset_in = static_cast<int32_t>(in.offset * static_cast<float>(area_in) + 0.5f);
  const Interior k{
    in.src, in.pre, r, 1.0f / static_cast<float>(area_in), static_cast<float>(offset_in) / static_cast<float>(area_in),
    bits,   weight
  };
  int x = lo;
#if defined(SL_X86)
  if (path == Path::Avx2)
    x = interiorAvx2(k, x, hi);
  if (path != Path::Portable)
    x = interiorSse2(k, x, hi);
#endif
  interiorPortable(k, x, hi);
  // The borders, where the image edge cuts the window: each pixel has its own area.
  const int32_t* pre = in.pre;
  for (int b = 0; b < w; ++b)
  {
    if (b >= lo && b < hi)
      b = hi;
    if (b >= w)
      break;
    const int xa = std::max(0, b - r), xb = std::min(w, b + r + 1);
    const int32_t area = in.rows * (xb - xa);
    const int32_t off = static_cast<int32_t>(in.offset * static_cast<float>(area) + 0.5f);
    // Only the foreground's weights are used: the division is skipped for the others.
    if (static_cast<int32_t>(in.src[b]) * area > pre[xb] - pre[xa] + off)
    {
      bits[b >> 6] |= uint64_t{ 1 } << (b & 63);
      weight[b] = weightOf(in.src[b], pre[xb] - pre[xa], b, w, r, in.rows);
    }
  }
}

}  // namespace local_threshold
}  // namespace sl_decoder
