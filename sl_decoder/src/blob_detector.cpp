#include "sl_decoder/blob_detector.h"

#include <algorithm>

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

// sums[x] += add[x] - sub[x]: the window slides by one row in one pass.
void slideRows(int32_t* __restrict sums, const uint8_t* __restrict add, const uint8_t* __restrict sub, int w)
{
  for (int x = 0; x < w; ++x)
    sums[x] += static_cast<int32_t>(add[x]) - static_cast<int32_t>(sub[x]);
}

// pre[0] = 0, pre[x + 1] = pre[x] + v[x]. The serial chain of a scalar loop is the slowest part of
// the threshold; four lanes at a time (two shifted adds, then the carry) shorten it fourfold.
void prefixSum(const int32_t* __restrict v, int32_t* __restrict pre, int w)
{
  pre[0] = 0;
  int x = 0;
#if defined(__SSE2__)
  __m128i carry = _mm_setzero_si128();
  for (; x + 4 <= w; x += 4)
  {
    __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(v + x));
    a = _mm_add_epi32(a, _mm_slli_si128(a, 4));
    a = _mm_add_epi32(a, _mm_slli_si128(a, 8));
    a = _mm_add_epi32(a, carry);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(pre + x + 1), a);
    carry = _mm_shuffle_epi32(a, _MM_SHUFFLE(3, 3, 3, 3));
  }
#endif
  for (; x < w; ++x)
    pre[x + 1] = pre[x] + v[x];
}
}  // namespace

BlobDetector::BlobDetector(const DecoderConfig& config) : config_(config)
{
}

inline int BlobDetector::find(int i)
{
  while (runs_[static_cast<size_t>(i)].parent != i)
  {
    Run& r = runs_[static_cast<size_t>(i)];
    r.parent = runs_[static_cast<size_t>(r.parent)].parent;  // path halving
    i = r.parent;
  }
  return i;
}

inline void BlobDetector::unite(int a, int b)
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
  const int words = (w + 63) >> 6;
  bits_.resize(static_cast<size_t>(words) + 1);  // + 1: a 16-bit group may spill past the last word
  weight_.resize(static_cast<size_t>(w));
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
    if (y + r < h && y - r - 1 >= 0)
      slideRows(cs, image.ptr<uint8_t>(y + r), image.ptr<uint8_t>(y - r - 1), w);
    else if (y + r < h)
      addRow(cs, image.ptr<uint8_t>(y + r), w, 1);
    else if (y - r - 1 >= 0)
      addRow(cs, image.ptr<uint8_t>(y - r - 1), w, -1);
    const int rows = std::min(h, y + r + 1) - std::max(0, y - r);
    prefixSum(cs, pre, w);
    // Foreground test value > mean + offset as value * area > sum + offset * area, in integers.
    // The interior has a constant window area, so that loop vectorises.
    const uint8_t* src = image.ptr<uint8_t>(y);
    uint64_t* bits = bits_.data();
    float* weight = weight_.data();
    std::fill(bits, bits + words + 1, uint64_t{ 0 });
    auto setBit = [bits](int x) { bits[x >> 6] |= uint64_t{ 1 } << (x & 63); };
    const int lo = std::min(r, w), hi = std::max(lo, w - r - 1);
    const int32_t area_in = rows * (2 * r + 1);
    const int32_t offset_in = static_cast<int32_t>(offset * static_cast<float>(area_in) + 0.5f);
    int x_in = lo;
#if defined(__SSE2__)
    // 16 pixels at a time: value > (sum + offset * area) / area, in floats; the 16 flags go into the
    // row's bit mask at once, the weights value - mean into weight_.
    {
      const __m128 inv_area = _mm_set1_ps(1.0f / static_cast<float>(area_in));
      const __m128 off = _mm_set1_ps(static_cast<float>(offset_in) / static_cast<float>(area_in));
      const __m128i zero = _mm_setzero_si128();
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
          const __m128 mean = _mm_mul_ps(_mm_cvtepi32_ps(_mm_sub_epi32(a, b)), inv_area);
          const __m128 value = _mm_cvtepi32_ps(v32[k]);
          cmp[k] = _mm_castps_si128(_mm_cmpgt_ps(value, _mm_add_ps(mean, off)));
          _mm_storeu_ps(weight + x_in + 4 * k, _mm_sub_ps(value, mean));
        }
        const __m128i packed = _mm_packs_epi16(_mm_packs_epi32(cmp[0], cmp[1]), _mm_packs_epi32(cmp[2], cmp[3]));
        const uint64_t m = static_cast<uint32_t>(_mm_movemask_epi8(packed));
        if (m != 0)
        {
          const int shift = x_in & 63;
          bits[x_in >> 6] |= m << shift;
          if (shift > 48)
            bits[(x_in >> 6) + 1] |= m >> (64 - shift);
        }
      }
    }
#endif
    const float inv_area_in = 1.0f / static_cast<float>(area_in);
    for (int x = x_in; x < hi; ++x)
    {
      if (static_cast<int32_t>(src[x]) * area_in > pre[x + r + 1] - pre[x - r] + offset_in)
        setBit(x);
      weight[x] = static_cast<float>(src[x]) - static_cast<float>(pre[x + r + 1] - pre[x - r]) * inv_area_in;
    }
    // The borders, where the window is cut by the image edge.
    for (int x = 0; x < w; ++x)
    {
      if (x >= lo && x < hi)
        x = hi;
      if (x >= w)
        break;
      const int xa = std::max(0, x - r), xb = std::min(w, x + r + 1);
      const int32_t area = rows * (xb - xa);
      const int32_t off = static_cast<int32_t>(offset * static_cast<float>(area) + 0.5f);
      if (static_cast<int32_t>(src[x]) * area > pre[xb] - pre[xa] + off)
        setBit(x);
      weight[x] = static_cast<float>(src[x]) - static_cast<float>(pre[xb] - pre[xa]) / static_cast<float>(area);
    }

    // Runs from the bit mask: the first set bit starts a run, the first clear bit after it ends it.
    const int cur_begin = static_cast<int>(runs_.size());
    int k = 0;
    uint64_t m = bits[0];
    for (;;)
    {
      while (m == 0 && ++k < words)
        m = bits[k];
      if (m == 0)
        break;
      const int b0 = __builtin_ctzll(m);
      const int x0 = (k << 6) + b0;
      uint64_t z = ~m & (~uint64_t{ 0 } << b0);
      while (z == 0 && ++k < words)
      {
        m = bits[k];
        z = ~m;
      }
      int x1 = w;
      m = 0;
      if (z != 0)
      {
        const int b1 = __builtin_ctzll(z);
        x1 = (k << 6) + b1;
        m = bits[k] & (~uint64_t{ 0 } << b1);  // the later runs of this word
      }
      float sw = 0.f, swx = 0.f, peak = 0.f;
      for (int x = x0; x < x1; ++x)
      {
        const float wx = weight[x];
        sw += wx;
        swx += wx * static_cast<float>(x);
        peak = std::max(peak, wx);
      }
      // Filled in place: a Run assembled on the stack and copied stalls on store forwarding.
      runs_.emplace_back();
      Run& run = runs_.back();
      run.y = y;
      run.x0 = x0;
      run.x1 = x1;
      run.parent = static_cast<int32_t>(runs_.size() - 1);
      run.sw = sw;
      run.swx = swx;
      run.peak = peak;
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
