#include "sl_decoder/shape_classifier.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include "sl_projector/primitives.h"

namespace sl_decoder
{

namespace
{
void normalise(std::vector<float>& v)
{
  double mean = 0.0;
  for (float x : v)
    mean += x;
  mean /= static_cast<double>(v.size());
  double norm = 0.0;
  for (float& x : v)
  {
    x = static_cast<float>(x - mean);
    norm += static_cast<double>(x) * x;
  }
  const float inv = norm > 0.0 ? static_cast<float>(1.0 / std::sqrt(norm)) : 0.f;
  for (float& x : v)
    x *= inv;
}
}  // namespace

ShapeClassifier::ShapeClassifier(const DecoderConfig& config, int box_width, int box_height)
  : config_(config), tw_(config.template_width), th_(config.template_height)
{
  for (int s = 1; s <= 4; ++s)
  {
    const cv::Mat t = sl_projector::shapeTemplate(s, tw_, th_, config.template_sigma, box_width, box_height);
    std::vector<float>& v = templates_[static_cast<size_t>(s - 1)];
    v.assign(t.begin<float>(), t.end<float>());
    normalise(v);
  }
  samples_.resize(static_cast<size_t>(tw_ * th_));
  useAvx2(true);
}

bool ShapeClassifier::useAvx2(bool on)
{
#if defined(__x86_64__)
  avx2_ = on && tw_ == 8 && __builtin_cpu_supports("avx2");
#else
  avx2_ = false;
#endif
  return avx2_;
}

namespace
{
#if defined(__x86_64__)
/// Eight horizontal interpolations of one image row: left + wx * (right - left), the left and right
/// source bytes picked out of @p bytes by the two shuffles.
__attribute__((target("avx2"))) inline __m256 lerpRow8(__m128i bytes, __m128i pick_left, __m128i pick_right, __m256 wx)
{
  const __m256i a = _mm256_cvtepu8_epi32(_mm_shuffle_epi8(bytes, pick_left));
  const __m256i b = _mm256_cvtepu8_epi32(_mm_shuffle_epi8(bytes, pick_right));
  return _mm256_add_ps(_mm256_cvtepi32_ps(a), _mm256_mul_ps(wx, _mm256_cvtepi32_ps(_mm256_sub_epi32(b, a))));
}

/// The AVX2 twin of the portable loop in ShapeClassifier::sampleGrid() for a grid 8 samples wide
/// whose source pixels ix[0] .. ix[7] + 1 lie within 16 bytes from ix[0] (in the image): each grid
/// row is two 16-byte loads and byte shuffles, then the same float operations as the loop (no FMA).
__attribute__((target("avx2"))) void sampleGrid8Avx2(const uint8_t* data, size_t step, size_t row_step, const int* ix,
                                                     const float* ax, const int* iy, const float* ay, int rows,
                                                     float* out)
{
  alignas(16) int8_t left[16], right[16];
  for (int i = 0; i < 16; ++i)
  {
    left[i] = static_cast<int8_t>(i < 8 ? ix[i] - ix[0] : -1);  // -1: the shuffle gives 0
    right[i] = static_cast<int8_t>(i < 8 ? ix[i] + 1 - ix[0] : -1);
  }
  const __m128i pick_left = _mm_load_si128(reinterpret_cast<const __m128i*>(left));
  const __m128i pick_right = _mm_load_si128(reinterpret_cast<const __m128i*>(right));
  const __m256 wx = _mm256_loadu_ps(ax);
  for (int j = 0; j < rows; ++j)
  {
    const uint8_t* r0 = data + static_cast<size_t>(iy[j]) * step + ix[0];
    const __m256 top = lerpRow8(_mm_loadu_si128(reinterpret_cast<const __m128i*>(r0)), pick_left, pick_right, wx);
    const __m256 bottom =
        lerpRow8(_mm_loadu_si128(reinterpret_cast<const __m128i*>(r0 + row_step)), pick_left, pick_right, wx);
    const __m256 wy = _mm256_set1_ps(ay[j]);
    _mm256_storeu_ps(out + 8 * j, _mm256_add_ps(top, _mm256_mul_ps(wy, _mm256_sub_ps(bottom, top))));
  }
}
#endif
}  // namespace

void ShapeClassifier::sampleGrid(const cv::Mat& image)
{
  const int wmax = image.cols - 1, hmax = image.rows - 1;
  const int x_step = wmax > 0 ? 1 : 0;
  const size_t row_step = hmax > 0 ? image.step[0] : 0;
#if defined(__x86_64__)
  if (avx2_ && x_step == 1 && ix_[7] + 1 - ix_[0] < 16 && ix_[0] + 16 <= image.cols)
  {
    sampleGrid8Avx2(image.data, image.step[0], row_step, ix_.data(), ax_.data(), iy_.data(), ay_.data(), th_,
                    samples_.data());
    return;
  }
#endif
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

void ShapeClassifier::classify(const cv::Mat& image, Blob& blob)
{
  // Sample the box edge to edge: the shape spans [x0 - 0.5, x1 - 0.5] in pixel coordinates.
  const float sx = static_cast<float>(blob.width()) / static_cast<float>(tw_);
  const float sy = static_cast<float>(blob.height()) / static_cast<float>(th_);
  const float ox = static_cast<float>(blob.x0) - 0.5f + 0.5f * sx;
  const float oy = static_cast<float>(blob.y0) - 0.5f + 0.5f * sy;
  const int wmax = image.cols - 1, hmax = image.rows - 1;
  ix_.resize(static_cast<size_t>(tw_));
  ax_.resize(static_cast<size_t>(tw_));
  iy_.resize(static_cast<size_t>(th_));
  ay_.resize(static_cast<size_t>(th_));
  // Source pixels and weights per grid column and row, clamped at the image border once.
  for (int i = 0; i < tw_; ++i)
  {
    const float fx = std::min(std::max(ox + static_cast<float>(i) * sx, 0.f), static_cast<float>(wmax));
    const int x = std::min(static_cast<int>(fx), std::max(0, wmax - 1));
    ix_[static_cast<size_t>(i)] = x;
    ax_[static_cast<size_t>(i)] = std::min(1.f, fx - static_cast<float>(x));
  }
  for (int j = 0; j < th_; ++j)
  {
    const float fy = std::min(std::max(oy + static_cast<float>(j) * sy, 0.f), static_cast<float>(hmax));
    const int y = std::min(static_cast<int>(fy), std::max(0, hmax - 1));
    iy_[static_cast<size_t>(j)] = y;
    ay_[static_cast<size_t>(j)] = std::min(1.f, fy - static_cast<float>(y));
  }
  sampleGrid(image);
  // Templates are zero-mean, so sum(s * t) needs no mean removal; the norm of s - mean is
  // sqrt(sum s^2 - n mean^2). Independent partial sums keep the loops free of long dependency chains.
  const size_t n = samples_.size();
  const float* sp = samples_.data();
  const float* t0 = templates_[0].data();
  const float* t1 = templates_[1].data();
  const float* t2 = templates_[2].data();
  const float* t3 = templates_[3].data();
  float s1[4] = { 0.f, 0.f, 0.f, 0.f }, s2[4] = { 0.f, 0.f, 0.f, 0.f };
  float d0[4] = { 0.f, 0.f, 0.f, 0.f }, d1[4] = { 0.f, 0.f, 0.f, 0.f };
  float d2[4] = { 0.f, 0.f, 0.f, 0.f }, d3[4] = { 0.f, 0.f, 0.f, 0.f };
  size_t i = 0;
  for (; i + 4 <= n; i += 4)
    for (size_t k = 0; k < 4; ++k)
    {
      const float v = sp[i + k];
      s1[k] += v;
      s2[k] += v * v;
      d0[k] += v * t0[i + k];
      d1[k] += v * t1[i + k];
      d2[k] += v * t2[i + k];
      d3[k] += v * t3[i + k];
    }
  for (; i < n; ++i)
  {
    const float v = sp[i];
    s1[0] += v;
    s2[0] += v * v;
    d0[0] += v * t0[i];
    d1[0] += v * t1[i];
    d2[0] += v * t2[i];
    d3[0] += v * t3[i];
  }
  const float sum = s1[0] + s1[1] + s1[2] + s1[3];
  const float sum_sq = s2[0] + s2[1] + s2[2] + s2[3];
  const float dots[4] = { d0[0] + d0[1] + d0[2] + d0[3], d1[0] + d1[1] + d1[2] + d1[3], d2[0] + d2[1] + d2[2] + d2[3],
                          d3[0] + d3[1] + d3[2] + d3[3] };
  const float var = sum_sq - sum * sum / static_cast<float>(n);
  blob.shape = 0;
  blob.correlation = 0.f;
  blob.margin = 0.f;
  if (!(var > 1e-3f * static_cast<float>(n)))
    return;
  const float inv = 1.f / std::sqrt(var);
  float best = -2.f, second = -2.f;
  int best_shape = 0;
  for (int k = 0; k < 4; ++k)
  {
    const float c = dots[k] * inv;
    if (c > best)
    {
      second = best;
      best = c;
      best_shape = k + 1;
    }
    else if (c > second)
      second = c;
  }
  blob.correlation = best;
  blob.margin = best - second;
  if (best >= config_.min_correlation && blob.margin >= config_.min_margin)
    blob.shape = best_shape;
}

}  // namespace sl_decoder

namespace sl_decoder
{
void ShapeClassifier::refineCentroid(const cv::Mat& image, Blob& blob, int margin) const
{
  const int x0 = std::max(0, blob.x0 - margin), x1 = std::min(image.cols, blob.x1 + margin);
  const int y0 = std::max(0, blob.y0 - margin), y1 = std::min(image.rows, blob.y1 + margin);
  if (x1 - x0 < 3 || y1 - y0 < 3)
    return;
  // Dark level: the mean of the rim of the grown box (the gaps around the primitive).
  float rim = 0.f;
  int rim_n = 0;
  for (int x = x0; x < x1; ++x)
  {
    rim += image.at<uint8_t>(y0, x) + image.at<uint8_t>(y1 - 1, x);
    rim_n += 2;
  }
  for (int y = y0 + 1; y < y1 - 1; ++y)
  {
    rim += image.at<uint8_t>(y, x0) + image.at<uint8_t>(y, x1 - 1);
    rim_n += 2;
  }
  const int dark = static_cast<int>(rim / static_cast<float>(rim_n) + 0.5f);
  // Integer sums (exact): weight = max(0, value - dark). Columns are counted from x0, so eight
  // pixels go through one SSE2 multiply-add; the last group of a row is masked to the box. Boxes
  // wider than 127 px or whose last group would read past the image's right edge take the scalar
  // loop below.
  int64_t sw = 0, swx = 0, swy = 0;
  const int bw = x1 - x0;
  bool vector_done = false;
#if defined(__SSE2__)
  const int groups = (bw + 7) / 8;
  if (bw < 128 && x0 + 8 * groups <= image.cols)
  {
    vector_done = true;
    const __m128i dark16 = _mm_set1_epi16(static_cast<int16_t>(std::min(255, std::max(0, dark))));
    const __m128i zero = _mm_setzero_si128(), ones = _mm_set1_epi16(1);
    const __m128i step = _mm_set1_epi16(8), width = _mm_set1_epi16(static_cast<int16_t>(bw));
    const __m128i first = _mm_setr_epi16(0, 1, 2, 3, 4, 5, 6, 7);
    for (int y = y0; y < y1; ++y)
    {
      const uint8_t* row = image.ptr<uint8_t>(y) + x0;
      __m128i acc_w = zero, acc_wx = zero, col = first;
      for (int g = 0; g < groups; ++g)
      {
        const __m128i v = _mm_unpacklo_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(row + 8 * g)), zero);
        // max(0, v - dark), and 0 for the columns past the box
        const __m128i w = _mm_and_si128(_mm_subs_epu16(v, dark16), _mm_cmplt_epi16(col, width));
        acc_w = _mm_add_epi32(acc_w, _mm_madd_epi16(w, ones));
        acc_wx = _mm_add_epi32(acc_wx, _mm_madd_epi16(w, col));
        col = _mm_add_epi16(col, step);
      }
      alignas(16) int32_t lw[4], lwx[4];
      _mm_store_si128(reinterpret_cast<__m128i*>(lw), acc_w);
      _mm_store_si128(reinterpret_cast<__m128i*>(lwx), acc_wx);
      const int64_t rw = static_cast<int64_t>(lw[0]) + lw[1] + lw[2] + lw[3];
      const int64_t rwx = static_cast<int64_t>(lwx[0]) + lwx[1] + lwx[2] + lwx[3];
      sw += rw;
      swx += rwx + rw * x0;
      swy += rw * y;
    }
  }
#endif
  if (!vector_done)
    for (int y = y0; y < y1; ++y)
    {
      const uint8_t* row = image.ptr<uint8_t>(y);
      int32_t rw = 0, rwx = 0;
      for (int x = x0; x < x1; ++x)
      {
        const int32_t w = std::max(0, static_cast<int32_t>(row[x]) - dark);
        rw += w;
        rwx += w * x;
      }
      sw += rw;
      swx += rwx;
      swy += static_cast<int64_t>(rw) * y;
    }
  if (sw > 0)
  {
    blob.u = static_cast<float>(static_cast<double>(swx) / static_cast<double>(sw));
    blob.v = static_cast<float>(static_cast<double>(swy) / static_cast<double>(sw));
  }
}
}  // namespace sl_decoder
