#include "local_threshold.h"

#include <algorithm>
#include <cstring>

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
constexpr int kMaxRows = 4;  // rows slidePrefixVector() forms side by side

// Window sums from prefix sums: int32_t ones, or uint16_t ones taken modulo 2^16, which is exact
// while a window's sum stays below 65536 (narrowSumsFit()).
inline int32_t windowSum(const int32_t* pre, int a, int b)
{
  return pre[b] - pre[a];
}
inline int32_t windowSum(const uint16_t* pre, int a, int b)
{
  return static_cast<uint16_t>(pre[b] - pre[a]);
}

/// The constants of the pixels whose window lies inside the row: one area, one threshold.
template <class T>
struct Interior
{
  const uint8_t* src;
  const T* pre;
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
template <class T>
int interiorPortable(const Interior<T>& k, int x, int end)
{
  for (; x < end; ++x)
  {
    const float mean = static_cast<float>(windowSum(k.pre, x - k.r, x + k.r + 1)) * k.inv_area;
    const float value = static_cast<float>(k.src[x]);
    if (value > mean + k.off)
      k.bits[x >> 6] |= uint64_t{ 1 } << (x & 63);
    k.weight[x] = value - mean;
  }
  return x;
}

#if defined(SL_X86)
/// The window sums of the 4 pixels from x as int32 lanes (prefix sums at x - r and x + r + 1).
inline __m128i sums4(const int32_t* pre, int a, int b)
{
  return _mm_sub_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(pre + b)),
                       _mm_loadu_si128(reinterpret_cast<const __m128i*>(pre + a)));
}
inline __m128i sums4(const uint16_t* pre, int a, int b)
{
  const __m128i d = _mm_sub_epi16(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(pre + b)),
                                  _mm_loadl_epi64(reinterpret_cast<const __m128i*>(pre + a)));
  return _mm_unpacklo_epi16(d, _mm_setzero_si128());
}

template <class T>
int interiorSse2(const Interior<T>& k, int x, int end)
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
      const __m128 mean = _mm_mul_ps(_mm_cvtepi32_ps(sums4(k.pre, xq - k.r, xq + k.r + 1)), inv_area);
      const __m128 value = _mm_cvtepi32_ps(v32[q]);
      m |= static_cast<uint64_t>(_mm_movemask_ps(_mm_cmpgt_ps(value, _mm_add_ps(mean, off)))) << (4 * q);
      _mm_storeu_ps(k.weight + xq, _mm_sub_ps(value, mean));
    }
    orBits(k.bits, x, m, 16);
  }
  return x;
}

/// The window sums of the 8 pixels from x as int32 lanes.
__attribute__((target("avx2"))) inline __m256i sums8(const int32_t* pre, int a, int b)
{
  return _mm256_sub_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(pre + b)),
                          _mm256_loadu_si256(reinterpret_cast<const __m256i*>(pre + a)));
}
__attribute__((target("avx2"))) inline __m256i sums8(const uint16_t* pre, int a, int b)
{
  return _mm256_cvtepu16_epi32(_mm_sub_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(pre + b)),
                                             _mm_loadu_si128(reinterpret_cast<const __m128i*>(pre + a))));
}

// Only "avx2", not "fma": a fused multiply-add would round differently from the other paths.
template <class T>
__attribute__((target("avx2"))) int interiorAvx2(const Interior<T>& k, int x, int end)
{
  const __m256 inv_area = _mm256_set1_ps(k.inv_area), off = _mm256_set1_ps(k.off);
  for (; x + 32 <= end; x += 32)
  {
    uint64_t m = 0;
    for (int q = 0; q < 4; ++q)
    {
      const int xq = x + 8 * q;
      const __m256i v32 = _mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(k.src + xq)));
      const __m256 mean = _mm256_mul_ps(_mm256_cvtepi32_ps(sums8(k.pre, xq - k.r, xq + k.r + 1)), inv_area);
      const __m256 value = _mm256_cvtepi32_ps(v32);
      const __m256 above = _mm256_cmp_ps(value, _mm256_add_ps(mean, off), _CMP_GT_OQ);
      m |= static_cast<uint64_t>(static_cast<uint32_t>(_mm256_movemask_ps(above))) << (8 * q);
      _mm256_storeu_ps(k.weight + xq, _mm256_sub_ps(value, mean));
    }
    orBits(k.bits, x, m, 32);
  }
  return x;
}

/// Prefix sums of 8 uint16 lanes plus @p carry (lane 7 of the last step, in every lane).
inline __m128i prefixLanes8(__m128i a, __m128i& carry)
{
  a = _mm_add_epi16(a, _mm_slli_si128(a, 2));
  a = _mm_add_epi16(a, _mm_slli_si128(a, 4));
  a = _mm_add_epi16(a, _mm_slli_si128(a, 8));
  a = _mm_add_epi16(a, carry);
  const __m128i top = _mm_shufflehi_epi16(a, _MM_SHUFFLE(3, 3, 3, 3));  // lanes 4-7: lane 7
  carry = _mm_unpackhi_epi64(top, top);
  return a;
}

/// Prefix sums of 4 int32 lanes plus @p carry (lane 3 of the last step, in every lane).
inline __m128i prefixLanes4(__m128i a, __m128i& carry)
{
  a = _mm_add_epi32(a, _mm_slli_si128(a, 4));
  a = _mm_add_epi32(a, _mm_slli_si128(a, 8));
  a = _mm_add_epi32(a, carry);
  carry = _mm_shuffle_epi32(a, _MM_SHUFFLE(3, 3, 3, 3));
  return a;
}

#endif

/// slidePrefixSums() for the columns [x, w), one column at a time with the rows side by side.
template <class T>
void slidePrefixTail(T* cols, const uint8_t* const* add, const uint8_t* const* sub, T* const* pre, int n, int x, int w)
{
  for (; x < w; ++x)
  {
    T c = cols[x];
    for (int k = 0; k < n; ++k)
    {
      c = static_cast<T>(c + add[k][x] - sub[k][x]);
      pre[k][x + 1] = static_cast<T>(pre[k][x] + c);
    }
    cols[x] = c;
  }
}

#if defined(SL_X86)
// The lanes of slidePrefixSse2(), by the sums' type: 8 uint16_t or 4 int32_t.
inline __m128i pixelsSse2(const uint8_t* row, int x, uint16_t)
{
  return _mm_unpacklo_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(row + x)), _mm_setzero_si128());
}
inline __m128i pixelsSse2(const uint8_t* row, int x, int32_t)
{
  int32_t v;
  std::memcpy(&v, row + x, sizeof(v));
  const __m128i zero = _mm_setzero_si128();
  return _mm_unpacklo_epi16(_mm_unpacklo_epi8(_mm_cvtsi32_si128(v), zero), zero);
}
inline __m128i slideSse2(__m128i c, __m128i a, __m128i s, uint16_t)
{
  return _mm_sub_epi16(_mm_add_epi16(c, a), s);
}
inline __m128i slideSse2(__m128i c, __m128i a, __m128i s, int32_t)
{
  return _mm_sub_epi32(_mm_add_epi32(c, a), s);
}
inline __m128i broadcastSse2(uint16_t v)
{
  return _mm_set1_epi16(static_cast<int16_t>(v));
}
inline __m128i broadcastSse2(int32_t v)
{
  return _mm_set1_epi32(v);
}
inline __m128i prefixLanesSse2(__m128i a, __m128i& carry, uint16_t)
{
  return prefixLanes8(a, carry);
}
inline __m128i prefixLanesSse2(__m128i a, __m128i& carry, int32_t)
{
  return prefixLanes4(a, carry);
}

/// slidePrefixSums() of N rows from column x, 16 bytes of sums at a time; returns the first column left.
template <int N, class T>
int slidePrefixSse2(T* cols, const uint8_t* const* add, const uint8_t* const* sub, T* const* pre, int x, int w)
{
  constexpr int kLanes = 16 / sizeof(T);
  __m128i carry[N];  // N is a constant: the carries stay in registers
  for (int k = 0; k < N; ++k)
    carry[k] = broadcastSse2(pre[k][x]);
  for (; x + kLanes <= w; x += kLanes)
  {
    __m128i c = _mm_loadu_si128(reinterpret_cast<const __m128i*>(cols + x));
    for (int k = 0; k < N; ++k)
    {
      c = slideSse2(c, pixelsSse2(add[k], x, T{}), pixelsSse2(sub[k], x, T{}), T{});
      _mm_storeu_si128(reinterpret_cast<__m128i*>(pre[k] + x + 1), prefixLanesSse2(c, carry[k], T{}));
    }
    _mm_storeu_si128(reinterpret_cast<__m128i*>(cols + x), c);
  }
  return x;
}

/// Prefix sums of 16 uint16 lanes plus @p carry (lane 15 of the last step, in every lane).
__attribute__((target("avx2"))) inline __m256i prefixLanes16(__m256i a, __m256i& carry)
{
  a = _mm256_add_epi16(a, _mm256_slli_si256(a, 2));  // within each half
  a = _mm256_add_epi16(a, _mm256_slli_si256(a, 4));
  a = _mm256_add_epi16(a, _mm256_slli_si256(a, 8));
  const __m256i top = _mm256_shufflehi_epi16(a, _MM_SHUFFLE(3, 3, 3, 3));
  const __m256i last = _mm256_unpackhi_epi64(top, top);                  // each half's sum in all its lanes
  a = _mm256_add_epi16(a, _mm256_permute2x128_si256(last, last, 0x08));  // the high half adds the low one's
  a = _mm256_add_epi16(a, carry);
  const __m256i top2 = _mm256_shufflehi_epi16(a, _MM_SHUFFLE(3, 3, 3, 3));
  const __m256i last2 = _mm256_unpackhi_epi64(top2, top2);
  carry = _mm256_permute2x128_si256(last2, last2, 0x11);
  return a;
}

/// Prefix sums of 8 int32 lanes plus @p carry (lane 7 of the last step, in every lane).
__attribute__((target("avx2"))) inline __m256i prefixLanes8x32(__m256i a, __m256i& carry)
{
  a = _mm256_add_epi32(a, _mm256_slli_si256(a, 4));  // within each half
  a = _mm256_add_epi32(a, _mm256_slli_si256(a, 8));
  const __m256i last = _mm256_shuffle_epi32(a, _MM_SHUFFLE(3, 3, 3, 3));  // each half's sum in all its lanes
  a = _mm256_add_epi32(a, _mm256_permute2x128_si256(last, last, 0x08));   // the high half adds the low one's
  a = _mm256_add_epi32(a, carry);
  const __m256i last2 = _mm256_shuffle_epi32(a, _MM_SHUFFLE(3, 3, 3, 3));
  carry = _mm256_permute2x128_si256(last2, last2, 0x11);
  return a;
}

// The lanes of slidePrefixAvx2(), by the sums' type: 16 uint16_t or 8 int32_t.
__attribute__((target("avx2"))) inline __m256i pixelsAvx2(const uint8_t* row, int x, uint16_t)
{
  return _mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(row + x)));
}
__attribute__((target("avx2"))) inline __m256i pixelsAvx2(const uint8_t* row, int x, int32_t)
{
  return _mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(row + x)));
}
__attribute__((target("avx2"))) inline __m256i slideAvx2(__m256i c, __m256i a, __m256i s, uint16_t)
{
  return _mm256_sub_epi16(_mm256_add_epi16(c, a), s);
}
__attribute__((target("avx2"))) inline __m256i slideAvx2(__m256i c, __m256i a, __m256i s, int32_t)
{
  return _mm256_sub_epi32(_mm256_add_epi32(c, a), s);
}
__attribute__((target("avx2"))) inline __m256i broadcastAvx2(uint16_t v)
{
  return _mm256_set1_epi16(static_cast<int16_t>(v));
}
__attribute__((target("avx2"))) inline __m256i broadcastAvx2(int32_t v)
{
  return _mm256_set1_epi32(v);
}
__attribute__((target("avx2"))) inline __m256i prefixLanesAvx2(__m256i a, __m256i& carry, uint16_t)
{
  return prefixLanes16(a, carry);
}
__attribute__((target("avx2"))) inline __m256i prefixLanesAvx2(__m256i a, __m256i& carry, int32_t)
{
  return prefixLanes8x32(a, carry);
}

/// slidePrefixSse2() 32 bytes of sums at a time.
template <int N, class T>
__attribute__((target("avx2"))) int slidePrefixAvx2(T* cols, const uint8_t* const* add, const uint8_t* const* sub,
                                                    T* const* pre, int x, int w)
{
  constexpr int kLanes = 32 / sizeof(T);
  __m256i carry[N];
  for (int k = 0; k < N; ++k)
    carry[k] = broadcastAvx2(pre[k][x]);
  for (; x + kLanes <= w; x += kLanes)
  {
    __m256i c = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(cols + x));
    for (int k = 0; k < N; ++k)
    {
      c = slideAvx2(c, pixelsAvx2(add[k], x, T{}), pixelsAvx2(sub[k], x, T{}), T{});
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(pre[k] + x + 1), prefixLanesAvx2(c, carry[k], T{}));
    }
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(cols + x), c);
  }
  return x;
}

/// slidePrefixSums() of N rows on @p path from column 0; returns the first column left.
template <int N, class T>
int slidePrefixVector(T* cols, const uint8_t* const* add, const uint8_t* const* sub, T* const* pre, int w, Path path)
{
  int x = 0;
  if (path == Path::Avx2)
    x = slidePrefixAvx2<N, T>(cols, add, sub, pre, x, w);
  if (path != Path::Portable)
    x = slidePrefixSse2<N, T>(cols, add, sub, pre, x, w);
  return x;
}
#endif

template <class T>
void slidePrefixSumsT(T* cols, const uint8_t* const* add, const uint8_t* const* sub, T* const* pre, int n, int w,
                      Path path)
{
  if (n != kMaxRows && n > 1)  // row by row (only the image's last block is shorter)
  {
    for (int k = 0; k < n; ++k)
      slidePrefixSumsT(cols, add + k, sub + k, pre + k, 1, w, path);
    return;
  }
  for (int k = 0; k < n; ++k)
    pre[k][0] = 0;
  int x = 0;
#if defined(SL_X86)
  if (n == kMaxRows)
    x = slidePrefixVector<kMaxRows>(cols, add, sub, pre, w, path);
  else if (n == 1)
    x = slidePrefixVector<1>(cols, add, sub, pre, w, path);
#endif
  slidePrefixTail(cols, add, sub, pre, n, x, w);
}

template <class T>
void thresholdRowT(const RowInput& in, const T* pre, const RowConstants& c, Path path, uint64_t* bits, float* weight)
{
  std::fill(bits, bits + ((in.w + 63) >> 6) + 1, uint64_t{ 0 });
  const Interior<T> k{ in.src, pre, in.r, c.inv_area, c.off, bits, weight };
  int x = c.lo;
#if defined(SL_X86)
  if (path == Path::Avx2)
    x = interiorAvx2(k, x, c.hi);
  if (path != Path::Portable)
    x = interiorSse2(k, x, c.hi);
#endif
  interiorPortable(k, x, c.hi);
  // The borders, where the image edge cuts the window: each pixel has its own area.
  for (const RowConstants::Edge& e : c.edges)
  {
    const int32_t sum = windowSum(pre, e.xa, e.xb);
    // Only the foreground's weights are used: the division is skipped for the others.
    if (static_cast<int32_t>(in.src[e.x]) * e.area > sum + e.off)
    {
      bits[e.x >> 6] |= uint64_t{ 1 } << (e.x & 63);
      weight[e.x] = borderWeight(in.src[e.x], sum, e.area);
    }
  }
}
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

bool narrowSumsFit(int window)
{
  const int side = 2 * (window / 2) + 1;  // the window the threshold uses (an even one grows by 1)
  return side * side * 255 < 65536;
}

void slidePrefixSums(int32_t* cols, const uint8_t* const* add, const uint8_t* const* sub, int32_t* const* pre, int n,
                     int w, Path path)
{
  slidePrefixSumsT(cols, add, sub, pre, n, w, path);
}

void slidePrefixSums(uint16_t* cols, const uint8_t* const* add, const uint8_t* const* sub, uint16_t* const* pre, int n,
                     int w, Path path)
{
  slidePrefixSumsT(cols, add, sub, pre, n, w, path);
}

void rowConstants(const RowInput& in, RowConstants& c)
{
  // Interior: the window lies inside the row, one area for all (integer offset on that area).
  const int w = in.w, r = in.r;
  c.lo = std::min(r, w);
  c.hi = std::max(c.lo, w - r - 1);
  const int32_t area_in = in.rows * (2 * r + 1);
  const int32_t offset_in = static_cast<int32_t>(in.offset * static_cast<float>(area_in) + 0.5f);
  c.inv_area = 1.0f / static_cast<float>(area_in);
  c.off = static_cast<float>(offset_in) / static_cast<float>(area_in);
  c.edges.clear();
  for (int b = 0; b < w; ++b)
  {
    if (b >= c.lo && b < c.hi)
      b = c.hi;
    if (b >= w)
      break;
    const int xa = std::max(0, b - r), xb = std::min(w, b + r + 1);
    const int32_t area = in.rows * (xb - xa);
    const int32_t off = static_cast<int32_t>(in.offset * static_cast<float>(area) + 0.5f);
    c.edges.push_back(RowConstants::Edge{ b, xa, xb, area, off });
  }
}

void thresholdRow(const RowInput& in, const RowConstants& c, Path path, uint64_t* bits, float* weight)
{
  if (in.pre16 != nullptr)
    thresholdRowT(in, in.pre16, c, path, bits, weight);
  else
    thresholdRowT(in, in.pre, c, path, bits, weight);
}

}  // namespace local_threshold
}  // namespace sl_decoder
