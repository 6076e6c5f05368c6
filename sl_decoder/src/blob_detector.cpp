#include "sl_decoder/blob_detector.h"

#include <algorithm>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace sl_decoder
{

namespace
{
// sums[x] += sign * row[x]; restrict lets the compiler vectorise it.
void addRow(int32_t* __restrict sums, const uint8_t* __restrict row, int w, int32_t sign)
{
  for (int x = 0; x < w; ++x)
    sums[x] += sign * static_cast<int32_t>(row[x]);
}
}  // namespace

BlobDetector::BlobDetector(const DecoderConfig& config) : config_(config)
{
}

int BlobDetector::find(int i)
{
  while (runs_[static_cast<size_t>(i)].parent != i)
  {
    Run& r = runs_[static_cast<size_t>(i)];
    r.parent = runs_[static_cast<size_t>(r.parent)].parent;  // path halving
    i = r.parent;
  }
  return i;
}

void BlobDetector::unite(int a, int b)
{
  a = find(a);
  b = find(b);
  if (a == b)
    return;
  // The older run becomes the root: roots stay the first run of their component.
  if (a < b)
    runs_[static_cast<size_t>(b)].parent = a;
  else
    runs_[static_cast<size_t>(a)].parent = b;
}

void BlobDetector::detect(const cv::Mat& image, std::vector<Blob>& blobs)
{
  CV_Assert(image.type() == CV_8UC1);
  blobs.clear();
  runs_.clear();
  if (image.empty())
    return;
  const int w = image.cols, h = image.rows;
  const int r = config_.threshold_window / 2;
  const float offset = static_cast<float>(config_.threshold_offset);
  col_sum_.assign(static_cast<size_t>(w), 0);
  prefix_.resize(static_cast<size_t>(w) + 1);
  mask_.resize(static_cast<size_t>(w) + 16);
  int32_t* cs = col_sum_.data();
  int32_t* pre = prefix_.data();
  for (int y = 0; y < std::min(h, r); ++y)
    addRow(cs, image.ptr<uint8_t>(y), w, 1);

  // Threshold, extract runs and link them to the runs of the previous row.
  int prev_begin = 0, prev_end = 0;
  for (int y = 0; y < h; ++y)
  {
    // Slide the window's rows: add row y + r, drop row y - r - 1.
    // (restrict: the byte rows could alias the sums as far as the compiler knows)
    if (y + r < h)
      addRow(cs, image.ptr<uint8_t>(y + r), w, 1);
    if (y - r - 1 >= 0)
      addRow(cs, image.ptr<uint8_t>(y - r - 1), w, -1);
    const int rows = std::min(h, y + r + 1) - std::max(0, y - r);
    pre[0] = 0;
    for (int x = 0; x < w; ++x)
      pre[x + 1] = pre[x] + cs[x];
    // Foreground test value > mean + offset as value * area > sum + offset * area, in integers.
    // The interior has a constant window area, so that loop vectorises.
    const uint8_t* src = image.ptr<uint8_t>(y);
    uint8_t* mask = mask_.data();
    const int lo = std::min(r, w), hi = std::max(lo, w - r - 1);
    const int32_t area_in = rows * (2 * r + 1);
    const int32_t offset_in = static_cast<int32_t>(offset * static_cast<float>(area_in) + 0.5f);
    int x_in = lo;
#if defined(__SSE2__)
    // 16 pixels at a time: value > (sum + offset * area) / area, in floats.
    {
      const __m128 inv_area = _mm_set1_ps(1.0f / static_cast<float>(area_in));
      const __m128 off = _mm_set1_ps(static_cast<float>(offset_in) / static_cast<float>(area_in));
      const __m128i zero = _mm_setzero_si128();
      const __m128i one = _mm_set1_epi8(1);
      for (; x_in + 16 <= hi; x_in += 16)
      {
        const __m128i v8 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(src + x_in));
        const __m128i lo16 = _mm_unpacklo_epi8(v8, zero), hi16 = _mm_unpackhi_epi8(v8, zero);
        __m128i cmp[4];
        const __m128i v32[4] = { _mm_unpacklo_epi16(lo16, zero), _mm_unpackhi_epi16(lo16, zero),
                                 _mm_unpacklo_epi16(hi16, zero), _mm_unpackhi_epi16(hi16, zero) };
        for (int k = 0; k < 4; ++k)
        {
          const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(pre + x_in + 4 * k + r + 1));
          const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(pre + x_in + 4 * k - r));
          const __m128 thr = _mm_add_ps(_mm_mul_ps(_mm_cvtepi32_ps(_mm_sub_epi32(a, b)), inv_area), off);
          cmp[k] = _mm_castps_si128(_mm_cmpgt_ps(_mm_cvtepi32_ps(v32[k]), thr));
        }
        const __m128i packed = _mm_packs_epi16(_mm_packs_epi32(cmp[0], cmp[1]), _mm_packs_epi32(cmp[2], cmp[3]));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(mask + x_in), _mm_and_si128(packed, one));
      }
    }
#endif
    for (int x = x_in; x < hi; ++x)
      mask[x] = static_cast<int32_t>(src[x]) * area_in > pre[x + r + 1] - pre[x - r] + offset_in ? 1 : 0;
    for (int x = 0; x < w; ++x)
    {
      if (x >= lo && x < hi)
        x = hi;
      if (x >= w)
        break;
      const int xa = std::max(0, x - r), xb = std::min(w, x + r + 1);
      const int32_t area = rows * (xb - xa);
      const int32_t off = static_cast<int32_t>(offset * static_cast<float>(area) + 0.5f);
      mask[x] = static_cast<int32_t>(src[x]) * area > pre[xb] - pre[xa] + off ? 1 : 0;
    }
    std::memset(mask + w, 0, 8);  // sentinel for the word-wise skip
    // Local mean of a foreground pixel (only those need it, for the centroid weights).
    const float inv_area_in = 1.0f / static_cast<float>(area_in);
    auto meanAt = [&](int x) {
      if (x >= lo && x < hi)
        return static_cast<float>(pre[x + r + 1] - pre[x - r]) * inv_area_in;
      const int xa = std::max(0, x - r), xb = std::min(w, x + r + 1);
      return static_cast<float>(pre[xb] - pre[xa]) / static_cast<float>(rows * (xb - xa));
    };

    const int cur_begin = static_cast<int>(runs_.size());
    int x = 0;
    while (x < w)
    {
      // Skip background eight pixels at a time, then collect one run.
      uint64_t word;
      std::memcpy(&word, mask + x, 8);
      if (word == 0)
      {
        x += 8;
        continue;
      }
      while (!mask[x])
        ++x;
      if (x >= w)
        break;
      Run run{ y, x, x, static_cast<int32_t>(runs_.size()), 0.f, 0.f, 0.f };
      while (mask[x])
      {
        const float weight = static_cast<float>(src[x]) - meanAt(x);
        run.sw += weight;
        run.swx += weight * static_cast<float>(x);
        run.peak = std::max(run.peak, weight);
        ++x;
      }
      run.x1 = x;
      runs_.push_back(run);
    }
    const int cur_end = static_cast<int>(runs_.size());
    // Two-pointer sweep: [a, b) and [c, d) are 8-connected when a <= d and c <= b.
    int p = prev_begin;
    for (int c = cur_begin; c < cur_end; ++c)
    {
      const Run& cr = runs_[static_cast<size_t>(c)];
      while (p < prev_end && runs_[static_cast<size_t>(p)].x1 < cr.x0)
        ++p;
      for (int q = p; q < prev_end && runs_[static_cast<size_t>(q)].x0 <= cr.x1; ++q)
        unite(c, q);
    }
    prev_begin = cur_begin;
    prev_end = cur_end;
  }

  // Accumulate runs into components (roots are the first run of each component).
  blob_of_root_.assign(runs_.size(), -1);
  std::vector<Acc>& acc = acc_;
  acc.clear();
  components_ = 0;
  for (size_t i = 0; i < runs_.size(); ++i)
  {
    const int root = find(static_cast<int>(i));
    int32_t& index = blob_of_root_[static_cast<size_t>(root)];
    const Run& run = runs_[i];
    if (index < 0)
    {
      index = static_cast<int32_t>(blobs.size());
      Blob b;
      b.x0 = run.x0;
      b.x1 = run.x1;
      b.y0 = run.y;
      b.y1 = run.y + 1;
      blobs.push_back(b);
      acc.push_back(Acc{ 0.f, 0.f, 0.f, 0.f });
      ++components_;
    }
    Blob& b = blobs[static_cast<size_t>(index)];
    Acc& a = acc[static_cast<size_t>(index)];
    b.x0 = std::min(b.x0, run.x0);
    b.x1 = std::max(b.x1, run.x1);
    b.y1 = run.y + 1;
    b.area += run.x1 - run.x0;
    a.sw += run.sw;
    a.swx += run.swx;
    a.swy += run.sw * static_cast<float>(run.y);
    a.peak = std::max(a.peak, run.peak);
  }

  // Filter and finish in place.
  size_t kept = 0;
  for (size_t i = 0; i < blobs.size(); ++i)
  {
    Blob b = blobs[i];
    const Acc& a = acc[i];
    const int bw = b.width(), bh = b.height();
    if (b.area < config_.min_area || b.area > config_.max_area || bw < config_.min_width ||
        bh < config_.min_height || bw > config_.max_width || bh > config_.max_height)
      continue;
    if (static_cast<double>(bw) > config_.max_aspect * bh)
      continue;
    if (b.area < config_.min_fill * bw * bh)
      continue;
    if (a.peak < config_.min_contrast || a.sw <= 0.f)
      continue;
    b.u = a.swx / a.sw;
    b.v = a.swy / a.sw;
    b.contrast = a.peak;
    blobs[kept++] = b;
  }
  blobs.resize(kept);
}

}  // namespace sl_decoder
