#include "sl_decoder/shape_classifier.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include "sl_rig/primitives.h"

// Summation order. Correlations are compared bit for bit across versions and machines, so every
// float sum here runs in one order, written out (this file is compiled without reassociation):
// - the templates' mean and norm (normalise()): double lanes of pairs i % 4 = 0, 2 and 1, 3;
// - a blob's six sums over its n samples: sample i goes to lane i % 16 of its chunk of 16, each
//   lane sums its chunks in turn; lanes fold to four as (k + k+8) + (k+4 + k+12); the groups of four
//   left over after the last whole chunk, then the single samples left, add to those four; the four
//   fold to one (foldFour()).
// That is the order GCC gave the first version's loops when it vectorised them; keeping it keeps
// every correlation's bits. The AVX2 path has the same lanes: a chunk is two grid rows of 8.

namespace sl_decoder
{

namespace
{
void normalise(std::vector<float>& v)
{
  const size_t n = v.size(), whole = n / 4 * 4;
  double lane0 = 0.0, lane1 = 0.0;
  for (size_t i = 0; i < whole; i += 4)
  {
    lane0 += static_cast<double>(v[i]) + static_cast<double>(v[i + 2]);
    lane1 += static_cast<double>(v[i + 1]) + static_cast<double>(v[i + 3]);
  }
  double mean = lane0 + lane1;
  for (size_t i = whole; i < n; ++i)
    mean += v[i];
  mean /= static_cast<double>(n);
  for (float& x : v)
    x = static_cast<float>(x - mean);
  auto sq = [&v](size_t i) { return static_cast<double>(v[i]) * v[i]; };
  lane0 = lane1 = 0.0;
  for (size_t i = 0; i < whole; i += 4)
  {
    lane0 += sq(i) + sq(i + 2);
    lane1 += sq(i + 1) + sq(i + 3);
  }
  double norm = lane0 + lane1;
  for (size_t i = whole; i < n; ++i)
    norm += sq(i);
  const float inv = norm > 0.0 ? static_cast<float>(1.0 / std::sqrt(norm)) : 0.f;
  for (float& x : v)
    x *= inv;
}

/// The last step of the six sums: four lane sums to one. The last two dot products fold in
/// another order than the other sums (the first version's vectorised code did so).
inline void foldFour(const float r[6][4], float sums[6])
{
  for (int q = 0; q < 6; ++q)
    sums[q] = q < 4 ? r[q][0] + ((r[q][1] + r[q][2]) + r[q][3]) : r[q][0] + ((r[q][1] + r[q][3]) + r[q][2]);
}

/// The first of @p count grid positions across [lo - 0.5, hi - 0.5] (a box edge to edge) and their
/// spacing.
inline std::pair<float, float> gridAxis(int lo, int hi, int count)
{
  const float s = static_cast<float>(hi - lo) / static_cast<float>(count);
  return { static_cast<float>(lo) - 0.5f + 0.5f * s, s };
}

/// Source pixel and weight of each of @p count grid positions o + i * s, clamped to [0, imax].
void placeAxis(float o, float s, int imax, int count, int* index, float* weight)
{
  for (int i = 0; i < count; ++i)
  {
    const float f = std::min(std::max(o + static_cast<float>(i) * s, 0.f), static_cast<float>(imax));
    const int x = std::min(static_cast<int>(f), std::max(0, imax - 1));
    index[i] = x;
    weight[i] = std::min(1.f, f - static_cast<float>(x));
  }
}

#if defined(__x86_64__)
/// placeAxis() eight positions at a time (@p count rounded up to 8: the arrays must hold that).
/// The same float operations: max/min operand order as std::max/min's, no FMA.
__attribute__((target("avx2"))) void placeAxisAvx2(float o, float s, int imax, int count, int* index, float* weight)
{
  const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.f), top = _mm256_set1_ps(static_cast<float>(imax));
  const __m256 vo = _mm256_set1_ps(o), vs = _mm256_set1_ps(s);
  const __m256i last = _mm256_set1_epi32(std::max(0, imax - 1)), eight = _mm256_set1_epi32(8);
  __m256i i = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  for (int k = 0; k < count; k += 8, i = _mm256_add_epi32(i, eight))
  {
    const __m256 p = _mm256_add_ps(vo, _mm256_mul_ps(_mm256_cvtepi32_ps(i), vs));
    const __m256 f = _mm256_min_ps(top, _mm256_max_ps(zero, p));
    const __m256i x = _mm256_min_epi32(_mm256_cvttps_epi32(f), last);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(index + k), x);
    _mm256_storeu_ps(weight + k, _mm256_min_ps(_mm256_sub_ps(f, _mm256_cvtepi32_ps(x)), one));
  }
}

/// Eight horizontal interpolations of one image row: left + wx * (right - left), the left and right
/// source bytes picked out of @p bytes by the two shuffles.
__attribute__((target("avx2"))) inline __m256 lerpRow8(__m128i bytes, __m128i pick_left, __m128i pick_right, __m256 wx)
{
  const __m256i a = _mm256_cvtepu8_epi32(_mm_shuffle_epi8(bytes, pick_left));
  const __m256i b = _mm256_cvtepu8_epi32(_mm_shuffle_epi8(bytes, pick_right));
  return _mm256_add_ps(_mm256_cvtepi32_ps(a), _mm256_mul_ps(wx, _mm256_cvtepi32_ps(_mm256_sub_epi32(b, a))));
}

/// Adds one grid row's samples @p s to the six lane sums (@p t: the four templates' rows).
__attribute__((target("avx2"))) inline void addRow(__m256* acc, __m256 s, const float* t)
{
  acc[0] = _mm256_add_ps(acc[0], s);
  acc[1] = _mm256_add_ps(acc[1], _mm256_mul_ps(s, s));
  for (int q = 0; q < 4; ++q)
    acc[2 + q] = _mm256_add_ps(acc[2 + q], _mm256_mul_ps(s, _mm256_loadu_ps(t + 8 * q)));
}

constexpr int kMaxSpan = 40;  // image rows sampleGrid8Avx2() interpolates once each

/// The AVX2 twin of the portable loop in ShapeClassifier::sampleGrid() for a grid 8 samples wide
/// whose source pixels ix[0] .. ix[7] + 1 lie within 16 bytes from ix[0] (in the image): each image
/// row is a 16-byte load and byte shuffles, then the same float operations as the loop (no FMA).
/// Grid rows share image rows (a box less than twice as high as the grid): each image row is
/// interpolated across once, and the grid rows are interpolated between those.
__attribute__((target("avx2"))) void sampleGrid8Avx2(const uint8_t* data, size_t step, size_t row_step, const int* ix,
                                                     const float* ax, const int* iy, const float* ay, int rows,
                                                     float* out)
{
  // Byte shuffles: bytes ix[i] - ix[0] (left) and one more (right) for i < 8, -1 (gives 0) after.
  const __m256i from_first =
      _mm256_sub_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(ix)), _mm256_set1_epi32(ix[0]));
  const __m128i left16 = _mm_packs_epi32(_mm256_castsi256_si128(from_first), _mm256_extracti128_si256(from_first, 1));
  const __m128i none = _mm_set1_epi16(-1);
  const __m128i pick_left = _mm_packs_epi16(left16, none);
  const __m128i pick_right = _mm_packs_epi16(_mm_add_epi16(left16, _mm_set1_epi16(1)), none);
  const __m256 wx = _mm256_loadu_ps(ax);
  const uint8_t* origin = data + ix[0];
  auto load = [](const uint8_t* p) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p)); };
  // iy rises with the grid row; the second source row is the next one (the same in a 1-row image).
  const int below = row_step != 0 ? 1 : 0, first = iy[0], span = iy[rows - 1] + below + 1 - first;
  if (span <= kMaxSpan && span <= 2 * rows)
  {
    __m256 across[kMaxSpan];
    for (int k = 0; k < span; ++k)
      across[k] = lerpRow8(load(origin + static_cast<size_t>(first + k) * step), pick_left, pick_right, wx);
    for (int j = 0; j < rows; ++j)
    {
      const __m256 top = across[iy[j] - first], bottom = across[iy[j] - first + below];
      _mm256_storeu_ps(out + 8 * j,
                       _mm256_add_ps(top, _mm256_mul_ps(_mm256_set1_ps(ay[j]), _mm256_sub_ps(bottom, top))));
    }
    return;
  }
  for (int j = 0; j < rows; ++j)
  {
    const uint8_t* r0 = origin + static_cast<size_t>(iy[j]) * step;
    const __m256 top = lerpRow8(load(r0), pick_left, pick_right, wx);
    const __m256 bottom = lerpRow8(load(r0 + row_step), pick_left, pick_right, wx);
    _mm256_storeu_ps(out + 8 * j, _mm256_add_ps(top, _mm256_mul_ps(_mm256_set1_ps(ay[j]), _mm256_sub_ps(bottom, top))));
  }
}

/// The AVX2 twin of ShapeClassifier::sumSamples() for a grid 8 samples wide: even grid rows are
/// lanes 0..7 of a chunk, odd rows lanes 8..15; an odd last row is the two groups of four left
/// over. Gives the four lane sums of each of the six sums.
__attribute__((target("avx2"))) void sumRows8Avx2(const float* samples, int rows, const float* templates, float r[6][4])
{
  const __m256 zero = _mm256_setzero_ps();
  __m256 even[6] = { zero, zero, zero, zero, zero, zero }, odd[6] = { zero, zero, zero, zero, zero, zero };
  for (int c = 0; c < rows / 2; ++c)
  {
    addRow(even, _mm256_loadu_ps(samples + 16 * c), templates + 64 * c);
    addRow(odd, _mm256_loadu_ps(samples + 16 * c + 8), templates + 64 * c + 32);
  }
  __m128 four[6];
  for (int q = 0; q < 6; ++q)
  {
    const __m256 h = _mm256_add_ps(even[q], odd[q]);
    four[q] = _mm_add_ps(_mm256_castps256_ps128(h), _mm256_extractf128_ps(h, 1));
  }
  if (rows % 2 != 0)
  {
    const __m256 s = _mm256_loadu_ps(samples + 8 * (rows - 1));
    __m256 x[6] = { s, _mm256_mul_ps(s, s) };
    for (int q = 0; q < 4; ++q)
      x[2 + q] = _mm256_mul_ps(s, _mm256_loadu_ps(templates + 32 * (rows - 1) + 8 * q));
    for (int q = 0; q < 6; ++q)
      four[q] = _mm_add_ps(_mm_add_ps(four[q], _mm256_castps256_ps128(x[q])), _mm256_extractf128_ps(x[q], 1));
  }
  for (int q = 0; q < 6; ++q)
    _mm_storeu_ps(r[q], four[q]);
}
#endif
}  // namespace

ShapeClassifier::ShapeClassifier(const DecoderConfig& config, int box_width, int box_height)
  : config_(config), tw_(config.template_width), th_(config.template_height)
{
  // The grid's columns and rows live in fixed arrays: a larger template must not reach them.
  if (tw_ < 3 || tw_ > kMaxGrid)
    throw std::invalid_argument("template_width: must be 3.." + std::to_string(kMaxGrid));
  if (th_ < 3 || th_ > kMaxGrid)
    throw std::invalid_argument("template_height: must be 3.." + std::to_string(kMaxGrid));
  for (int s = 1; s <= 4; ++s)
  {
    const cv::Mat t = sl_projector::shapeTemplate(s, tw_, th_, config.template_sigma, box_width, box_height);
    std::vector<float>& v = templates_[static_cast<size_t>(s - 1)];
    v.assign(t.begin<float>(), t.end<float>());
    normalise(v);
  }
  rows_.reserve(static_cast<size_t>(4 * tw_ * th_));
  for (int j = 0; j < th_; ++j)
    for (const std::vector<float>& t : templates_)
      rows_.insert(rows_.end(), t.begin() + j * tw_, t.begin() + (j + 1) * tw_);
  samples_.resize(static_cast<size_t>(tw_ * th_));
  useAvx2(true);
}

bool ShapeClassifier::useAvx2(bool on)
{
#if defined(__x86_64__)
  avx2_ = on && __builtin_cpu_supports("avx2");
#else
  avx2_ = false;
#endif
  return avx2_;
}

void ShapeClassifier::placeGrid(const cv::Mat& image, const Blob& blob)
{
  const std::pair<float, float> x = gridAxis(blob.x0, blob.x1, tw_), y = gridAxis(blob.y0, blob.y1, th_);
  placeAxis(x.first, x.second, image.cols - 1, tw_, ix_.data(), ax_.data());
  placeAxis(y.first, y.second, image.rows - 1, th_, iy_.data(), ay_.data());
}

void ShapeClassifier::sampleGrid(const cv::Mat& image)
{
  const int x_step = image.cols > 1 ? 1 : 0;
  const size_t row_step = image.rows > 1 ? image.step[0] : 0;
  float* out = samples_.data();
  for (int j = 0; j < th_; ++j)
  {
    const uint8_t* r0 = image.ptr<uint8_t>(iy_[static_cast<size_t>(j)]);
    const uint8_t* r1 = r0 + row_step;
    const float ay = ay_[static_cast<size_t>(j)];
    for (int i = 0; i < tw_; ++i)
    {
      const int x = ix_[static_cast<size_t>(i)];
      const float ax = ax_[static_cast<size_t>(i)];
      const float top = r0[x] + ax * static_cast<float>(r0[x + x_step] - r0[x]);
      const float bottom = r1[x] + ax * static_cast<float>(r1[x + x_step] - r1[x]);
      *out++ = top + ay * (bottom - top);
    }
  }
}

void ShapeClassifier::sumSamples(float sums[6]) const
{
  // Templates are zero-mean, so sum(s * t) needs no mean removal (see decide()).
  const size_t n = samples_.size(), chunks_end = n / 16 * 16, groups_end = n / 4 * 4;
  const float* s = samples_.data();
  const float* t[4] = { templates_[0].data(), templates_[1].data(), templates_[2].data(), templates_[3].data() };
  auto value = [&](int q, size_t i) { return q == 0 ? s[i] : q == 1 ? s[i] * s[i] : s[i] * t[q - 2][i]; };
  float lanes[6][16] = {};
  for (size_t c = 0; c < chunks_end; c += 16)
    for (int q = 0; q < 6; ++q)
      for (size_t k = 0; k < 16; ++k)
        lanes[q][k] += value(q, c + k);
  float r[6][4];
  for (int q = 0; q < 6; ++q)
  {
    for (size_t k = 0; k < 4; ++k)
      r[q][k] = (lanes[q][k] + lanes[q][k + 8]) + (lanes[q][k + 4] + lanes[q][k + 12]);
    for (size_t i = chunks_end; i < groups_end; ++i)
      r[q][i % 4] += value(q, i);
    for (size_t i = groups_end; i < n; ++i)
      r[q][0] += value(q, i);
  }
  foldFour(r, sums);
}

inline void ShapeClassifier::decide(const float sums[6], Blob& blob) const
{
  // The norm of s - mean is sqrt(sum s^2 - n mean^2).
  const float n = static_cast<float>(tw_ * th_);
  const float var = sums[1] - sums[0] * sums[0] / n;
  blob.shape = 0;
  blob.correlation = 0.f;
  blob.margin = 0.f;
  if (!(var > 1e-3f * n))
    return;
  const float inv = 1.f / std::sqrt(var);
  float best = -2.f, second = -2.f;
  int best_shape = 0;
  // Selected without branches (which template wins is a coin toss per blob): the same as
  // "if (c > best) second = best, best = c; else if (c > second) second = c", NaN and signed zeros
  // included. second <= best throughout, so a new best pushes the old one to second.
  for (int k = 0; k < 4; ++k)
  {
    const float c = sums[2 + k] * inv;
    const float above_second = c > second ? c : second;
    const int top = -static_cast<int>(c > best);  // all ones for a new best (a mask: GCC branched on a select)
    best_shape ^= top & (best_shape ^ (k + 1));
    second = best < above_second ? best : above_second;
    best = c > best ? c : best;
  }
  blob.correlation = best;
  blob.margin = best - second;
  // A part of a merged row is the pattern's light for sure (no speckle, no texture): blur and
  // overexposure lower its correlation, only the margin tells its shape.
  const float min_correlation = blob.level > 0
                                    ? std::min(static_cast<float>(config_.min_correlation), kMergedMinCorrelation)
                                    : static_cast<float>(config_.min_correlation);
  const bool clear = (best >= min_correlation) & (blob.margin >= config_.min_margin);
  blob.shape = best_shape & -static_cast<int>(clear);
}

#if defined(__x86_64__)
__attribute__((target("avx2"))) void ShapeClassifier::classify8Avx2(const cv::Mat& image, Blob& blob)
{
  float sums[6];
  const std::pair<float, float> x = gridAxis(blob.x0, blob.x1, 8), y = gridAxis(blob.y0, blob.y1, th_);
  placeAxisAvx2(x.first, x.second, image.cols - 1, 8, ix_.data(), ax_.data());
  placeAxisAvx2(y.first, y.second, image.rows - 1, th_, iy_.data(), ay_.data());
  // The AVX2 resampling reads 16 bytes from the first source column of each grid row.
  if (image.cols > 1 && ix_[7] + 1 - ix_[0] < 16 && ix_[0] + 16 <= image.cols)
    sampleGrid8Avx2(image.data, image.step[0], image.rows > 1 ? image.step[0] : 0, ix_.data(), ax_.data(), iy_.data(),
                    ay_.data(), th_, samples_.data());
  else
    sampleGrid(image);
  float r[6][4];
  sumRows8Avx2(samples_.data(), th_, rows_.data(), r);
  foldFour(r, sums);
  decide(sums, blob);
}
#endif

void ShapeClassifier::classify(const cv::Mat& image, Blob& blob)
{
#if defined(__x86_64__)
  if (avx2_ && tw_ == 8)
  {
    classify8Avx2(image, blob);
    return;
  }
#endif
  placeGrid(image, blob);
  sampleGrid(image);
  float sums[6];
  sumSamples(sums);
  decide(sums, blob);
}

}  // namespace sl_decoder

namespace sl_decoder
{
namespace
{
/// The sum of a box's rim: its top and bottom rows, and the first and last pixels of the rows
/// between. (An integer sum: the first version's float sum of the same integers was exact, for rims
/// of less than 65793 px.)
int rimSum(const uint8_t* origin, size_t step, int bw, int bh)
{
  const uint8_t* bottom = origin + static_cast<size_t>(bh - 1) * step;
  int sum = 0;
  for (int x = 0; x < bw; ++x)
    sum += origin[x] + bottom[x];
  for (const uint8_t* row = origin + step; row < bottom; row += step)
    sum += row[0] + row[bw - 1];
  return sum;
}

/// The dark level around a box: the mean of its rim (@p rim_sum), rounded.
int darkLevel(int rim_sum, int bw, int bh)
{
  const int n = 2 * bw + 2 * (bh - 2);
  return std::min(255, std::max(0, static_cast<int>(static_cast<float>(rim_sum) / static_cast<float>(n) + 0.5f)));
}

#if defined(__x86_64__)
/// The light sums of refineCentroid() over a box of @p bw x @p bh px from @p origin, sixteen
/// columns at a time: sum w, sum w (x - x0), sum w (y - y0) with w = max(0, value - dark). The
/// 16 bytes from each row's last group must be in the image; bw < 128 and bh <= 256 keep the sums
/// within int32.
__attribute__((target("avx2"))) void lightSumsAvx2(const uint8_t* origin, size_t step, int bw, int bh, int dark,
                                                   int64_t sums[3])
{
  const __m256i dark16 = _mm256_set1_epi16(static_cast<int16_t>(dark)), ones = _mm256_set1_epi16(1);
  const __m256i width = _mm256_set1_epi16(static_cast<int16_t>(bw));
  __m256i acc[3] = { _mm256_setzero_si256(), _mm256_setzero_si256(), _mm256_setzero_si256() };
  for (int g = 0; 16 * g < bw; ++g)
  {
    const __m256i col = _mm256_add_epi16(_mm256_setr_epi16(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15),
                                         _mm256_set1_epi16(static_cast<int16_t>(16 * g)));
    const __m256i inside = _mm256_cmpgt_epi16(width, col);
    const uint8_t* p = origin + 16 * g;
    __m256i dy = _mm256_setzero_si256();
    for (int y = 0; y < bh; ++y, p += step, dy = _mm256_add_epi16(dy, ones))
    {
      const __m256i v = _mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)));
      const __m256i w = _mm256_and_si256(_mm256_subs_epu16(v, dark16), inside);
      acc[0] = _mm256_add_epi32(acc[0], _mm256_madd_epi16(w, ones));
      acc[1] = _mm256_add_epi32(acc[1], _mm256_madd_epi16(w, col));
      acc[2] = _mm256_add_epi32(acc[2], _mm256_madd_epi16(w, dy));
    }
  }
  // Lane sums: [0..3] of acc[0], acc[1], acc[2], acc[2] in the low half, [4..7] in the high.
  const __m256i pairs = _mm256_hadd_epi32(_mm256_hadd_epi32(acc[0], acc[1]), _mm256_hadd_epi32(acc[2], acc[2]));
  const __m128i total = _mm_add_epi32(_mm256_castsi256_si128(pairs), _mm256_extracti128_si256(pairs, 1));
  sums[0] = _mm_cvtsi128_si32(total);
  sums[1] = _mm_extract_epi32(total, 1);
  sums[2] = _mm_extract_epi32(total, 2);
}

const uint8_t kZeroRow[16] = {};  // read in place of the row below an odd last row: weighs nothing

/// Rows @p top and @p bottom, 16 bytes from each, as one register.
__attribute__((target("avx2"))) inline __m256i loadRows16(const uint8_t* top, const uint8_t* bottom)
{
  return _mm256_inserti128_si256(_mm256_castsi128_si256(_mm_loadu_si128(reinterpret_cast<const __m128i*>(top))),
                                 _mm_loadu_si128(reinterpret_cast<const __m128i*>(bottom)), 1);
}

/// rimSum() for boxes 2 to 16 px wide and at least 2 high (the 16 bytes from each row's start in
/// the image): the top and bottom rows in one SAD, the rows between two at a time, their first and
/// last bytes picked by a mask.
__attribute__((target("avx2"))) int rimSum16Avx2(const uint8_t* origin, size_t step, int bw, int bh)
{
  const __m128i col = _mm_setr_epi8(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const __m128i ends = _mm_or_si128(_mm_cmpeq_epi8(col, _mm_setzero_si128()),
                                    _mm_cmpeq_epi8(col, _mm_set1_epi8(static_cast<char>(bw - 1))));
  const __m256i zero = _mm256_setzero_si256();
  const __m256i inside = _mm256_broadcastsi128_si256(_mm_cmpgt_epi8(_mm_set1_epi8(static_cast<char>(bw)), col));
  const __m256i sides = _mm256_broadcastsi128_si256(ends);
  const uint8_t* bottom = origin + static_cast<size_t>(bh - 1) * step;
  __m256i acc = _mm256_sad_epu8(_mm256_and_si256(loadRows16(origin, bottom), inside), zero);
  for (const uint8_t* row = origin + step; row < bottom; row += 2 * step)
  {
    const uint8_t* next = row + step < bottom ? row + step : kZeroRow;
    acc = _mm256_add_epi64(acc, _mm256_sad_epu8(_mm256_and_si256(loadRows16(row, next), sides), zero));
  }
  alignas(32) int64_t lanes[4];
  _mm256_store_si256(reinterpret_cast<__m256i*>(lanes), acc);
  return static_cast<int>(lanes[0] + lanes[1] + lanes[2] + lanes[3]);
}

/// lightSumsAvx2() for boxes at most 16 px wide, two rows at a time in bytes: w = the saturated
/// byte difference; sum w and each row's sum by a SAD, sum w (x - x0) by a multiply-add of bytes
/// (at most 2 * 255 * 15 per pair), sum w (y - y0) from the row sums. The 16 bytes from each row's
/// start must be in the image; bh <= 256.
__attribute__((target("avx2"))) void lightSums16Avx2(const uint8_t* origin, size_t step, int bw, int bh, int dark,
                                                     int64_t sums[3])
{
  const __m128i col = _mm_setr_epi8(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const __m256i cols = _mm256_broadcastsi128_si256(col), zero = _mm256_setzero_si256();
  const __m256i inside = _mm256_broadcastsi128_si256(_mm_cmpgt_epi8(_mm_set1_epi8(static_cast<char>(bw)), col));
  const __m256i dark8 = _mm256_set1_epi8(static_cast<char>(dark)), ones = _mm256_set1_epi16(1);
  __m256i acc_w = zero, acc_x = zero, acc_y = zero;
  __m256i dy = _mm256_setr_epi64x(0, 0, 1, 1);  // the row of each SAD lane: y in the low half, y + 1 high
  const __m256i two = _mm256_set1_epi64x(2);
  for (int y = 0; y < bh; y += 2, origin += 2 * step)
  {
    const __m256i v = loadRows16(origin, y + 1 < bh ? origin + step : kZeroRow);
    const __m256i w = _mm256_and_si256(_mm256_subs_epu8(v, dark8), inside);
    const __m256i row_sums = _mm256_sad_epu8(w, zero);
    acc_w = _mm256_add_epi64(acc_w, row_sums);
    acc_x = _mm256_add_epi32(acc_x, _mm256_madd_epi16(_mm256_maddubs_epi16(w, cols), ones));
    acc_y = _mm256_add_epi64(acc_y, _mm256_mul_epu32(row_sums, dy));
    dy = _mm256_add_epi64(dy, two);
  }
  alignas(32) int64_t w64[4], y64[4];
  alignas(32) int32_t x32[8];
  _mm256_store_si256(reinterpret_cast<__m256i*>(w64), acc_w);
  _mm256_store_si256(reinterpret_cast<__m256i*>(y64), acc_y);
  _mm256_store_si256(reinterpret_cast<__m256i*>(x32), acc_x);
  sums[0] = w64[0] + w64[1] + w64[2] + w64[3];
  sums[1] = 0;
  for (const int32_t x : x32)
    sums[1] += x;
  sums[2] = y64[0] + y64[1] + y64[2] + y64[3];
}
#endif

#if defined(__SSE2__)
/// lightSumsAvx2() eight columns at a time (the 8 bytes from each row's last group in the image).
void lightSumsSse2(const uint8_t* origin, size_t step, int bw, int bh, int dark, int64_t sums[3])
{
  const __m128i dark16 = _mm_set1_epi16(static_cast<int16_t>(dark)), ones = _mm_set1_epi16(1);
  const __m128i width = _mm_set1_epi16(static_cast<int16_t>(bw)), zero = _mm_setzero_si128();
  __m128i acc[3] = { zero, zero, zero };
  for (int g = 0; 8 * g < bw; ++g)
  {
    const __m128i col =
        _mm_add_epi16(_mm_setr_epi16(0, 1, 2, 3, 4, 5, 6, 7), _mm_set1_epi16(static_cast<int16_t>(8 * g)));
    const __m128i inside = _mm_cmplt_epi16(col, width);
    const uint8_t* p = origin + 8 * g;
    __m128i dy = zero;
    for (int y = 0; y < bh; ++y, p += step, dy = _mm_add_epi16(dy, ones))
    {
      const __m128i v = _mm_unpacklo_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p)), zero);
      const __m128i w = _mm_and_si128(_mm_subs_epu16(v, dark16), inside);
      acc[0] = _mm_add_epi32(acc[0], _mm_madd_epi16(w, ones));
      acc[1] = _mm_add_epi32(acc[1], _mm_madd_epi16(w, col));
      acc[2] = _mm_add_epi32(acc[2], _mm_madd_epi16(w, dy));
    }
  }
  for (int k = 0; k < 3; ++k)
  {
    alignas(16) int32_t lanes[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(lanes), acc[k]);
    sums[k] = static_cast<int64_t>(lanes[0]) + lanes[1] + lanes[2] + lanes[3];
  }
}
#endif

/// The portable light sums (any box).
void lightSums(const uint8_t* origin, size_t step, int bw, int bh, int dark, int64_t sums[3])
{
  sums[0] = sums[1] = sums[2] = 0;
  for (int y = 0; y < bh; ++y, origin += step)
  {
    int64_t rw = 0, rwx = 0;
    for (int x = 0; x < bw; ++x)
    {
      const int64_t w = std::max(0, static_cast<int>(origin[x]) - dark);
      rw += w;
      rwx += w * x;
    }
    sums[0] += rw;
    sums[1] += rwx;
    sums[2] += rw * y;
  }
}
}  // namespace

void ShapeClassifier::refineCentroid(const cv::Mat& image, Blob& blob, int margin) const
{
  const int x0 = std::max(0, blob.x0 - margin), x1 = std::min(image.cols, blob.x1 + margin);
  const int y0 = std::max(0, blob.y0 - margin), y1 = std::min(image.rows, blob.y1 + margin);
  if (x1 - x0 < 3 || y1 - y0 < 3)
    return;
  // Dark level: the mean of the rim of the grown box (the gaps around the primitive). Integer sums
  // (exact, so every path gives the same): weight = max(0, value - dark), columns and rows counted
  // from the box's corner.
  const int bw = x1 - x0, bh = y1 - y0;
  const uint8_t* origin = image.ptr<uint8_t>(y0) + x0;
  const size_t step = image.step[0];
  // The vector sums read whole groups of columns (in the image); box sizes keep their lanes in int32.
  const bool small = bw < 128 && bh <= 256;
#if defined(__x86_64__)
  const bool narrow = avx2_ && bw <= 16 && x0 + 16 <= image.cols;  // one group of 16 columns
  const int dark = darkLevel(narrow ? rimSum16Avx2(origin, step, bw, bh) : rimSum(origin, step, bw, bh), bw, bh);
#else
  const int dark = darkLevel(rimSum(origin, step, bw, bh), bw, bh);
#endif
  int64_t sums[3];
  bool summed = false;
#if defined(__x86_64__)
  if (avx2_ && small && x0 + (bw + 15) / 16 * 16 <= image.cols)
  {
    if (narrow)
      lightSums16Avx2(origin, step, bw, bh, dark, sums);
    else
      lightSumsAvx2(origin, step, bw, bh, dark, sums);
    summed = true;
  }
#endif
#if defined(__SSE2__)
  if (!summed && small && x0 + (bw + 7) / 8 * 8 <= image.cols)
  {
    lightSumsSse2(origin, step, bw, bh, dark, sums);
    summed = true;
  }
#endif
  if (!summed)
    lightSums(origin, step, bw, bh, dark, sums);
  if (sums[0] > 0)
  {
    const int64_t swx = sums[1] + sums[0] * x0, swy = sums[2] + sums[0] * y0;
    blob.u = static_cast<float>(static_cast<double>(swx) / static_cast<double>(sums[0]));
    blob.v = static_cast<float>(static_cast<double>(swy) / static_cast<double>(sums[0]));
  }
}
}  // namespace sl_decoder
