#include "sl_decoder/blob_detector.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "local_threshold.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace sl_decoder
{
namespace
{
void setPrefix(local_threshold::RowInput& row, const int32_t* pre)
{
  row.pre = pre;
}
void setPrefix(local_threshold::RowInput& row, const uint16_t* pre)
{
  row.pre16 = pre;
}

/// The largest of the weights w[x0, x1) and 0 (w readable up to x1 + 7). The weights of a run are
/// positive, so their maximum is exact in any order: 8 at a time gives the same peak as one at a time.
inline float peakOf(const float* w, int x0, int x1)
{
#if defined(__SSE2__)
  // Two accumulators, and the last 0-7 weights masked without a branch: runs of a near frame are long.
  __m128 m0 = _mm_setzero_ps(), m1 = _mm_setzero_ps();
  int x = x0;
  for (; x + 8 <= x1; x += 8)
  {
    m0 = _mm_max_ps(m0, _mm_loadu_ps(w + x));
    m1 = _mm_max_ps(m1, _mm_loadu_ps(w + x + 4));
  }
  const __m128i lane = _mm_add_epi32(_mm_set1_epi32(x), _mm_setr_epi32(0, 1, 2, 3));
  const __m128i end = _mm_set1_epi32(x1);
  const __m128 inside0 = _mm_castsi128_ps(_mm_cmplt_epi32(lane, end));
  const __m128 inside1 = _mm_castsi128_ps(_mm_cmplt_epi32(_mm_add_epi32(lane, _mm_set1_epi32(4)), end));
  m0 = _mm_max_ps(m0, _mm_and_ps(_mm_loadu_ps(w + x), inside0));
  m1 = _mm_max_ps(m1, _mm_and_ps(_mm_loadu_ps(w + x + 4), inside1));
  __m128 m = _mm_max_ps(m0, m1);
  m = _mm_max_ps(m, _mm_shuffle_ps(m, m, _MM_SHUFFLE(1, 0, 3, 2)));
  m = _mm_max_ps(m, _mm_shuffle_ps(m, m, _MM_SHUFFLE(2, 3, 0, 1)));
  return _mm_cvtss_f32(m);
#else
  float peak = 0.f;
  for (int x = x0; x < x1; ++x)
    peak = std::max(peak, w[x]);
  return peak;
#endif
}

/// Lowers @p lo and raises @p hi to the darkest and brightest pixel of @p box (not empty) in @p image.
void boxMinMax(const cv::Mat& image, const Blob& box, int& lo, int& hi)
{
  const int w = box.width();
#if defined(__SSE2__)
  if (w >= 16)
  {
    // 16 at a time, a row's last 16 overlapping the ones before: the same extremes.
    __m128i mn = _mm_set1_epi8(static_cast<char>(0xff)), mx = _mm_setzero_si128();
    for (int y = box.y0; y < box.y1; ++y)
    {
      const uint8_t* row = image.ptr<uint8_t>(y) + box.x0;
      for (int x = 0;; x += 16)
      {
        const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(row + std::min(x, w - 16)));
        mn = _mm_min_epu8(mn, v);
        mx = _mm_max_epu8(mx, v);
        if (x + 16 >= w)
          break;
      }
    }
    // The byte shift takes a constant (clang insists): halves, quarters, eighths, sixteenths.
    mn = _mm_min_epu8(mn, _mm_srli_si128(mn, 8));
    mx = _mm_max_epu8(mx, _mm_srli_si128(mx, 8));
    mn = _mm_min_epu8(mn, _mm_srli_si128(mn, 4));
    mx = _mm_max_epu8(mx, _mm_srli_si128(mx, 4));
    mn = _mm_min_epu8(mn, _mm_srli_si128(mn, 2));
    mx = _mm_max_epu8(mx, _mm_srli_si128(mx, 2));
    mn = _mm_min_epu8(mn, _mm_srli_si128(mn, 1));
    mx = _mm_max_epu8(mx, _mm_srli_si128(mx, 1));
    lo = std::min(lo, _mm_cvtsi128_si32(mn) & 0xff);
    hi = std::max(hi, _mm_cvtsi128_si32(mx) & 0xff);
    return;
  }
#endif
  for (int y = box.y0; y < box.y1; ++y)
  {
    const uint8_t* row = image.ptr<uint8_t>(y) + box.x0;
    for (int x = 0; x < w; ++x)
    {
      lo = std::min(lo, static_cast<int>(row[x]));
      hi = std::max(hi, static_cast<int>(row[x]));
    }
  }
}
}  // namespace

BlobDetector::BlobDetector(const DecoderConfig& config)
  : config_(config), simd_(static_cast<Simd>(local_threshold::fastestPath()))
{
}

BlobDetector::~BlobDetector() = default;
BlobDetector::BlobDetector(const BlobDetector&) = default;
BlobDetector::BlobDetector(BlobDetector&&) noexcept = default;
BlobDetector& BlobDetector::operator=(const BlobDetector&) = default;
BlobDetector& BlobDetector::operator=(BlobDetector&&) noexcept = default;

BlobDetector::Simd BlobDetector::useSimd(Simd simd)
{
  // Simd and local_threshold::Path list the same instruction sets in the same order.
  auto path = static_cast<local_threshold::Path>(simd);
  while (!local_threshold::supported(path))
    path = static_cast<local_threshold::Path>(static_cast<int>(path) - 1);
  simd_ = static_cast<Simd>(path);
  return simd_;
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

void BlobDetector::linkRows(int prev_begin, int prev_end, int cur_begin, int cur_end)
{
  // Two-pointer sweep: [a, b) and [c, d) are 8-connected when a <= d and c <= b.
  // A current run is still its own root when it meets its first run above: it joins that run's
  // root directly, which is older (the same as unite(), one find() less).
  int p = prev_begin;
  for (int c = cur_begin; c < cur_end; ++c)
  {
    Run& cr = runs_[static_cast<size_t>(c)];
    while (p < prev_end && runs_[static_cast<size_t>(p)].x1 < cr.x0)
      ++p;
    int q = p;
    if (q < prev_end && runs_[static_cast<size_t>(q)].x0 <= cr.x1)
      cr.parent = find(q++);
    for (; q < prev_end && runs_[static_cast<size_t>(q)].x0 <= cr.x1; ++q)
      unite(c, q);
  }
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

void BlobDetector::thresholdAndLink(const cv::Mat& image)
{
  // 16-bit sums where every window's sum fits: twice the pixels per vector, the same sums.
  if (local_threshold::narrowSumsFit(config_.threshold_window))
    thresholdAndLink(image, col_sums16_, prefix16_);
  else
    thresholdAndLink(image, col_sums_, prefix_);
}

template <class T>
void BlobDetector::thresholdAndLink(const cv::Mat& image, std::vector<T>& col_sums, std::vector<T>& prefix)
{
  const int w = image.cols, h = image.rows;
  const int r = config_.threshold_window / 2;
  const size_t ws = static_cast<size_t>(w);
  // Column sums over the window of the current row, and the prefix sums of kRowBlock rows' ones.
  col_sums.assign(ws, 0);
  prefix.resize(kRowBlock * (ws + 1));
  zero_row_.assign(ws, 0);
  bits_.resize(static_cast<size_t>((w + 63) >> 6) + 1);
  weight_.resize(ws + 8);  // peakOf() reads 8 at a time
  // The rows above the first window's centre.
  for (int y = 0; y < std::min(h, r); ++y)
  {
    const uint8_t* src = image.ptr<uint8_t>(y);
    for (int x = 0; x < w; ++x)
      col_sums[static_cast<size_t>(x)] = static_cast<T>(col_sums[static_cast<size_t>(x)] + src[x]);
  }
  local_threshold::RowInput row;
  row.w = w;
  row.r = r;
  row.offset = static_cast<float>(config_.threshold_offset);
  const auto path = static_cast<local_threshold::Path>(simd_);
  // A window has at most 2 r + 1 rows; only the first and last r rows have fewer.
  row_constants_.resize(static_cast<size_t>(2 * r + 2));
  row_constants_set_.assign(row_constants_.size(), 0);
  int prev_begin = 0, prev_end = 0;
  for (int y0 = 0; y0 < h; y0 += kRowBlock)
  {
    const int n = std::min(kRowBlock, h - y0);
    const uint8_t* add[kRowBlock];
    const uint8_t* sub[kRowBlock];
    T* pre[kRowBlock];
    for (int j = 0; j < n; ++j)
    {
      // The window of row y: add row y + r, drop row y - r - 1.
      const int y = y0 + j;
      add[j] = y + r < h ? image.ptr<uint8_t>(y + r) : zero_row_.data();
      sub[j] = y - r - 1 >= 0 ? image.ptr<uint8_t>(y - r - 1) : zero_row_.data();
      pre[j] = prefix.data() + static_cast<size_t>(j) * (ws + 1);
    }
    local_threshold::slidePrefixSums(col_sums.data(), add, sub, pre, n, w, path);
    for (int j = 0; j < n; ++j)
    {
      const int y = y0 + j;
      row.src = image.ptr<uint8_t>(y);
      setPrefix(row, pre[j]);
      row.rows = std::min(h, y + r + 1) - std::max(0, y - r);
      local_threshold::thresholdRow(row, constantsOf(row), path, bits_.data(), weight_.data());
      const int cur_begin = static_cast<int>(runs_.size());
      extractRuns(y, w);
      const int cur_end = static_cast<int>(runs_.size());
      linkRows(prev_begin, prev_end, cur_begin, cur_end);
      prev_begin = cur_begin;
      prev_end = cur_end;
    }
  }
}

const local_threshold::RowConstants& BlobDetector::constantsOf(const local_threshold::RowInput& row)
{
  const auto k = static_cast<size_t>(row.rows);
  if (!row_constants_set_[k])
  {
    local_threshold::rowConstants(row, row_constants_[k]);
    row_constants_set_[k] = 1;
  }
  return row_constants_[k];
}

void BlobDetector::extractRuns(int y, int w)
{
  // Bit x of m ^ (m << 1 | carry) is set where pixel x differs from pixel x - 1: starts and ends
  // of runs alternate there. Bits at and past w are clear, so a run open after the last word ends at w.
  const size_t first = runs_.size();
  runs_.resize(first + static_cast<size_t>((w + 1) / 2));  // at most a run per two pixels (Run() is empty)
  Run* const begin = runs_.data();
  Run* out = begin + first;
  const uint64_t* bits = bits_.data();
  const int words = (w + 63) >> 6;
  uint64_t carry = 0;
  int x0 = -1;  // the start of the open run, if any
  for (int k = 0; k < words; ++k)
  {
    const uint64_t m = bits[k];
    uint64_t t = m ^ (m << 1 | carry);
    carry = m >> 63;
    while (t != 0)
    {
      if (x0 < 0)
      {
        x0 = (k << 6) + __builtin_ctzll(t);
        t &= t - 1;
        if (t == 0)
          break;
      }
      const int x1 = (k << 6) + __builtin_ctzll(t);
      t &= t - 1;
      out = putRun(out, begin, y, x0, x1);
      x0 = -1;
    }
  }
  if (x0 >= 0)
    out = putRun(out, begin, y, x0, w);
  runs_.resize(static_cast<size_t>(out - begin));
}

inline BlobDetector::Run* BlobDetector::putRun(Run* out, const Run* begin, int y, int x0, int x1) const
{
  out->y = y;
  out->x0 = x0;
  out->x1 = x1;
  out->parent = static_cast<int32_t>(out - begin);
  // Only each run's peak weight is kept: most blobs get the classifier's centroid, and
  // centroids() forms the weights of the few others again.
  out->peak = peakOf(weight_.data(), x0, x1);
  return out + 1;
}

void BlobDetector::detect(const cv::Mat& image, std::vector<Blob>& blobs)
{
  detectBoxes(image, blobs);
  centroids(blobs);
}

void BlobDetector::detectBoxes(const cv::Mat& image, std::vector<Blob>& blobs)
{
  CV_Assert(image.type() == CV_8UC1);
  blobs.clear();
  runs_.swap(component_runs_);  // back: each buffer keeps its role (and its capacity) frame after frame
  runs_.clear();
  component_runs_.clear();
  kept_component_.clear();
  image_ = image;
  boxes_.clear();
  split_pixels_ = 0;
  if (image.empty())
  {
    runs_.swap(component_runs_);  // the roles as after a labelling
    return;
  }
  thresholdAndLink(image);
  formComponents();
  // Filter; oversized components with contrast are split afterwards. Every foreground pixel's
  // weight is above the offset (>= 0), so a component's weight sum is positive.
  oversized_.clear();
  oversized_component_.clear();
  for (size_t i = 0; i < boxes_.size(); ++i)
  {
    const Box& box = boxes_[i];
    if (box.peak < config_.min_contrast || box.area < config_.min_area)
      continue;
    Blob b;
    b.x0 = box.x0;
    b.x1 = box.x1;
    b.y0 = box.y0;
    b.y1 = box.y1;
    b.area = box.area;
    b.contrast = box.peak;
    b.u = b.v = std::numeric_limits<float>::quiet_NaN();  // centroids() sets it where it is still needed
    const bool split = config_.split_merged;
    if (primitiveSized(b) && !(split && merged(b)))
    {
      blobs.push_back(b);
      kept_component_.push_back(static_cast<int32_t>(i));
    }
    else if (split && (merged(b) || b.width() > config_.max_width || b.height() > config_.max_height ||
                       b.area > config_.max_area || static_cast<double>(b.width()) > config_.max_aspect * b.height()))
    {
      oversized_component_.push_back(static_cast<int32_t>(i));
      oversized_.push_back(Region{ b, 0, 0, b.area });
    }
  }
  collectSpans();
  // Splitting labels again in runs_: the image's runs move to component_runs_ for centroids().
  component_runs_.swap(runs_);
  for (const Region& r : oversized_)
    splitOversized(image, r, blobs);
}

void BlobDetector::centroids(std::vector<Blob>& blobs)
{
  const size_t n = std::min(kept_component_.size(), blobs.size());
  // Blob after blob, each one's runs in row order (between its first and last run): the order the
  // sums were always formed in.
  for (size_t k = 0; k < n; ++k)
  {
    if (!std::isnan(blobs[k].u))
      continue;
    const int32_t c = kept_component_[k];
    const Box& box = boxes_[static_cast<size_t>(c)];
    const Integral sums = integrateAround(box);
    Acc acc{ 0.f, 0.f, 0.f };
    for (int32_t i = box.first; i <= box.last; ++i)
      if (component_of_[static_cast<size_t>(i)] == c)
        accumulate(component_runs_[static_cast<size_t>(i)], sums, acc);
    blobs[k].u = acc.swx / acc.sw;
    blobs[k].v = acc.swy / acc.sw;
  }
}

BlobDetector::Integral BlobDetector::integrateAround(const Box& c)
{
  // The box grown by the window, clipped to the image: every window of its pixels.
  const int r = config_.threshold_window / 2;
  const int x0 = c.x0, x1 = c.x1, y0 = c.y0, y1 = c.y1;
  const Integral g{ std::max(0, x0 - r), std::max(0, y0 - r), std::min(image_.cols, x1 + r) - std::max(0, x0 - r) + 1 };
  const int rows = std::min(image_.rows, y1 + r) - g.y0;
  box_sums_.assign(static_cast<size_t>((rows + 1) * g.stride), 0);
  for (int j = 0; j < rows; ++j)
  {
    const uint8_t* src = image_.ptr<uint8_t>(g.y0 + j) + g.x0;
    const int32_t* above = box_sums_.data() + j * g.stride;
    int32_t* out = box_sums_.data() + (j + 1) * g.stride;
    int32_t row_sum = 0;
    for (int i = 1; i < g.stride; ++i)
    {
      row_sum += src[i - 1];
      out[i] = above[i] + row_sum;
    }
  }
  return g;
}

void BlobDetector::accumulate(const Run& run, const Integral& sums, Acc& acc) const
{
  const int r = config_.threshold_window / 2, w = image_.cols;
  const int ya = std::max(0, run.y - r), yb = std::min(image_.rows, run.y + r + 1);
  const int32_t* top = box_sums_.data() + (ya - sums.y0) * sums.stride;
  const int32_t* bottom = box_sums_.data() + (yb - sums.y0) * sums.stride;
  const uint8_t* src = image_.ptr<uint8_t>(run.y);
  float sw = 0.f, swx = 0.f;
  for (int x = run.x0; x < run.x1; ++x)
  {
    const int xa = std::max(0, x - r) - sums.x0, xb = std::min(w, x + r + 1) - sums.x0;
    const int32_t sum = bottom[xb] - bottom[xa] - top[xb] + top[xa];
    const float wx = local_threshold::weightOf(src[x], sum, x, w, r, yb - ya);
    sw += wx;
    swx += wx * static_cast<float>(x);
  }
  acc.sw += sw;
  acc.swx += swx;
  acc.swy += sw * static_cast<float>(run.y);
}

void BlobDetector::formComponents()
{
  // A run's parent is never a later run (unite() and find() only point back), so one forward pass
  // labels them all: a root starts a component, any other run joins its parent's.
  const size_t n = runs_.size();
  boxes_.resize(n);  // at most a component per run (Box() is empty)
  component_of_.resize(n);
  const Run* runs = runs_.data();
  int32_t* component_of = component_of_.data();
  Box* boxes = boxes_.data();
  int32_t count = 0;
  for (size_t i = 0; i < n; ++i)
  {
    const Run& run = runs[i];
    int32_t c;
    if (run.parent == static_cast<int32_t>(i))
    {
      c = count++;
      startBox(boxes[c], run, static_cast<int32_t>(i));
    }
    else
      c = component_of[run.parent];
    component_of[i] = c;
    Box& b = boxes[c];
    b.x0 = std::min(b.x0, run.x0);
    b.x1 = std::max(b.x1, run.x1);
    b.y1 = run.y + 1;
    b.area += run.x1 - run.x0;
    b.peak = std::max(b.peak, run.peak);
    b.last = static_cast<int32_t>(i);
  }
  boxes_.resize(static_cast<size_t>(count));
}

inline void BlobDetector::startBox(Box& b, const Run& run, int32_t first)
{
  b.x0 = run.x0;
  b.x1 = run.x1;
  b.y0 = run.y;
  b.y1 = run.y + 1;
  b.area = 0;
  b.peak = 0.f;
  b.first = first;
  b.last = 0;
}

void BlobDetector::collectSpans()
{
  spans_.clear();
  if (oversized_.empty())
    return;
  // Each region's runs in row order, region after region: a counting sort over the runs between
  // the regions' first and last run (one pass to count, one to place), not a pass per region.
  region_of_component_.assign(boxes_.size(), -1);
  int32_t first = std::numeric_limits<int32_t>::max(), last = -1;
  for (size_t k = 0; k < oversized_.size(); ++k)
  {
    const Box& box = boxes_[static_cast<size_t>(oversized_component_[k])];
    region_of_component_[static_cast<size_t>(oversized_component_[k])] = static_cast<int32_t>(k);
    first = std::min(first, box.first);
    last = std::max(last, box.last);
    oversized_[k].end = 0;
  }
  for (int32_t i = first; i <= last; ++i)
  {
    const int32_t k = region_of_component_[static_cast<size_t>(component_of_[static_cast<size_t>(i)])];
    if (k >= 0)
      ++oversized_[static_cast<size_t>(k)].end;
  }
  int32_t next = 0;
  for (Region& r : oversized_)
  {
    r.begin = next;
    next += r.end;
    r.end = r.begin;
  }
  spans_.resize(static_cast<size_t>(next));
  for (int32_t i = first; i <= last; ++i)
  {
    const int32_t k = region_of_component_[static_cast<size_t>(component_of_[static_cast<size_t>(i)])];
    if (k < 0)
      continue;
    const Run& run = runs_[static_cast<size_t>(i)];
    spans_[static_cast<size_t>(oversized_[static_cast<size_t>(k)].end++)] = Span(run.y, run.x0, run.x1);
  }
}

void BlobDetector::appendSpans(std::vector<Region>& regions)
{
  // Counting sort: each region's end holds its run count; runs_ are in row order, so each
  // region's spans are too.
  int32_t next = static_cast<int32_t>(spans_.size());
  for (Region& r : regions)
  {
    r.begin = next;
    next += r.end;
    r.end = r.begin;
    r.span_area = r.box.area;
  }
  spans_.resize(static_cast<size_t>(next));
  for (size_t i = 0; i < runs_.size(); ++i)
  {
    const Run& run = runs_[i];
    const int32_t r = part_of_label_[static_cast<size_t>(run.parent)];
    spans_[static_cast<size_t>(regions[static_cast<size_t>(r)].end++)] = Span(run.y, run.x0, run.x1);
  }
}

bool BlobDetector::primitiveSized(const Blob& b) const
{
  const int bw = b.width(), bh = b.height();
  return b.area >= config_.min_area && b.area <= config_.max_area && bw >= config_.min_width &&
         bh >= config_.min_height && bw <= config_.max_width && bh <= config_.max_height &&
         static_cast<double>(bw) <= config_.max_aspect * bh && b.area >= config_.min_fill * bw * bh;
}

void BlobDetector::splitOversized(const cv::Mat& image, const Region& component, std::vector<Blob>& blobs)
{
  // Fractions of the component's grey range, from just above the local threshold to near its peak.
  static constexpr float kLevels[kLastLevel] = { 0.5f, 0.65f, 0.78f, 0.88f, 0.95f };
  const Blob& box = component.box;
  int lo = 255, hi = 0;  // the box's darkest and brightest pixel
  boxMinMax(image, box, lo, hi);
  pending_.clear();
  pending_.push_back(component);
  pending_.back().box.level = 0;
  // Breadth first: each oversized part is re-thresholded at the next level, over its own pixels.
  for (size_t k = 0; k < pending_.size(); ++k)
  {
    const Region region = pending_[k];  // a copy: pending_ grows below
    const int level = region.box.level + 1;
    if (level > kLastLevel)
      continue;
    const int threshold = lo + static_cast<int>(kLevels[level - 1] * static_cast<float>(hi - lo) + 0.5f);
    if (hi - threshold < config_.min_contrast)
      continue;
    labelAbove(image, region, threshold);
    for (Region& region_part : parts_)
    {
      Blob& part = region_part.box;
      part.level = level;
      const bool small =
          primitive_w_ <= 0.0 || (part.width() <= 1.4 * primitive_w_ && part.height() <= 1.4 * primitive_h_);
      if (primitiveSized(part) && small)
      {
        if (weighAbove(image, region_part, threshold))
          blobs.push_back(part);
      }
      else if (level == kLastLevel && primitive_w_ > 0.0 && !cutByPitch(image, part, threshold, blobs))
        cellsOfBand(image, part, (lo + hi) / 2, blobs);
      else if (part.area > config_.min_area)
        pending_.push_back(region_part);
    }
  }
}

bool BlobDetector::cutByPitch(const cv::Mat& image, const Blob& part, int threshold, std::vector<Blob>& blobs)
{
  // Saturated bridges do not split at any threshold: a row of primitives one pattern row tall is
  // cut into equal pieces of the pattern's pitch (their shapes and centroids are checked later).
  // A tilted row is one row tall along its tilt.
  if (part.height() > 1.4 * primitive_h_ + std::abs(slope_) * part.width() || pitch_ <= 0.0)
    return false;
  // k primitives merged span (k - 1) pitches plus one primitive (widened by the bridges' light).
  const double w = part.width();
  const int k = static_cast<int>(std::lround((w - primitive_w_) / pitch_)) + 1;
  if (k < 2 || k > 6 || std::abs(w - primitive_w_ - (k - 1) * pitch_) > 0.4 * pitch_)
    return false;
  const double first = part.x0 + 0.5 * (w - (k - 1) * pitch_);  // centre of the first primitive
  for (int i = 0; i < k; ++i)
  {
    Blob piece;
    const double c = first + i * pitch_;
    piece.x0 = std::max(part.x0, static_cast<int>(std::lround(c - 0.5 * pitch_)));
    piece.x1 = std::min(part.x1, static_cast<int>(std::lround(c + 0.5 * pitch_)));
    // Its rows: the part's, along its tilt (the height it would have untilted, around its centre line).
    const double line = 0.5 * (part.y0 + part.y1) + slope_ * (c - 0.5 * (part.x0 + part.x1));
    const double half = 0.5 * (part.height() - std::abs(slope_) * part.width());
    piece.y0 = std::max(part.y0, static_cast<int>(std::floor(line - half)));
    piece.y1 = std::min(part.y1, static_cast<int>(std::ceil(line + half)));
    if (!weighAbove(image, piece, threshold))
      continue;
    piece.level = kLastLevel + 1;
    if (primitiveSized(piece))
      blobs.push_back(piece);
  }
  return true;
}

namespace
{
// Where each column x0 + i, i in [i0, i1), crosses @p t going outwards from row y_in (up for step
// -1, down for +1), with linear interpolation between the two pixels, into edge[i]; NaN if not
// within @p reach rows. The columns are walked side by side, row after row: a column walk's
// unpredictable end per column cost more than the rows it saves.
void edgesFrom(const cv::Mat& image, int x0, int i0, int i1, int y_in, int step, int reach, int t, float* edge)
{
  std::fill(edge + i0, edge + i1, std::numeric_limits<float>::quiet_NaN());
  const int last = std::min(reach, step < 0 ? y_in : image.rows - 1 - y_in);
  const uint8_t* prev_row = image.ptr<uint8_t>(y_in) + x0;
  int open = i1 - i0;  // columns without an edge yet
  for (int k = 1; k <= last && open > 0; ++k)
  {
    const int y = y_in + step * k;
    const uint8_t* row = image.ptr<uint8_t>(y) + x0;
    auto cross = [&](int i)  // column i goes below t between prev_row and row
    {
      if (!std::isnan(edge[i]))
        return;
      const int v = row[i], prev = prev_row[i];
      edge[i] = static_cast<float>(y - step) +
                static_cast<float>(step) * static_cast<float>(prev - t) / static_cast<float>(prev - v);
      --open;
    };
    int i = i0;
#if defined(__SSE2__)
    // 16 columns at a time (few cross in a row): unsigned bytes compared as signed after flipping the top bit.
    const __m128i bias = _mm_set1_epi8(static_cast<char>(0x80));
    const __m128i tt = _mm_set1_epi8(static_cast<char>(t ^ 0x80));
    for (; i + 16 <= i1; i += 16)
    {
      const __m128i v = _mm_xor_si128(_mm_loadu_si128(reinterpret_cast<const __m128i*>(row + i)), bias);
      const __m128i prev = _mm_xor_si128(_mm_loadu_si128(reinterpret_cast<const __m128i*>(prev_row + i)), bias);
      for (int bits = _mm_movemask_epi8(_mm_andnot_si128(_mm_cmpgt_epi8(v, tt), _mm_cmpgt_epi8(prev, tt))); bits != 0;
           bits &= bits - 1)
        cross(i + __builtin_ctz(static_cast<unsigned>(bits)));
    }
#endif
    for (; i < i1; ++i)
      if (row[i] <= t && prev_row[i] > t)
        cross(i);
    prev_row = row;
  }
}
}  // namespace

void BlobDetector::cellsOfBand(const cv::Mat& image, const Blob& band, int t, std::vector<Blob>& blobs)
{
  // A saturated row of primitives: only its outline is left. Every shape lights its middle column
  // from top to bottom, so the band's height peaks at the primitives' centres (their horizontal
  // centroids): the phase of that periodic profile places them. Each shape has exactly one
  // lopsided band at the top or the bottom (1: W L R, 2: W R L, 3: L R W, 4: R L W), so which edge
  // is lopsided, and to which side, names the shape.
  // A tilted band is followed along its tilt.
  if (pitch_ <= 0.0 || band.width() < 3 * pitch_ ||
      band.height() > 2.0 * primitive_h_ + std::abs(slope_) * band.width())
    return;
  const int n = band.width();
  const double x_centre = 0.5 * (band.x0 + band.x1 - 1), y_centre = 0.5 * (band.y0 + band.y1);
  const int reach = static_cast<int>(std::ceil(primitive_h_));
  top_.resize(static_cast<size_t>(n));
  bottom_.resize(static_cast<size_t>(n));
  // Outwards from the band's centre line, over the columns that share its row.
  auto midRow = [&](int i)
  { return std::min(band.y1 - 1, std::max(band.y0, static_cast<int>(y_centre + slope_ * (band.x0 + i - x_centre)))); };
  for (int i0 = 0; i0 < n;)
  {
    const int y_mid = midRow(i0);
    int i1 = i0 + 1;
    while (i1 < n && midRow(i1) == y_mid)
      ++i1;
    edgesFrom(image, band.x0, i0, i1, y_mid, -1, reach, t, top_.data());
    edgesFrom(image, band.x0, i0, i1, y_mid, 1, reach, t, bottom_.data());
    i0 = i1;
  }
  // The phase of the height profile at the pattern's pitch, over +-3 pitches around x: from prefix
  // sums of its products with the cosine and sine (one pair of them per column, not per window).
  const double omega = 2.0 * M_PI / pitch_;
  formWaveTable(omega, image.cols);
  phase_re_.resize(static_cast<size_t>(n) + 1);
  phase_im_.resize(static_cast<size_t>(n) + 1);
  // The running sums stay in registers: a sum read back from the store it was just written to
  // waited for it, column after column.
  double re = 0.0, im = 0.0;
  phase_re_[0] = phase_im_[0] = 0.0;
  for (int i = 0; i < n; ++i)
  {
    const float h = bottom_[static_cast<size_t>(i)] - top_[static_cast<size_t>(i)];
    const bool finite = std::isfinite(h);
    const size_t x = static_cast<size_t>(band.x0 + i);
    re += finite ? h * cos_[x] : 0.0;
    im += finite ? h * sin_[x] : 0.0;
    phase_re_[static_cast<size_t>(i) + 1] = re;
    phase_im_[static_cast<size_t>(i) + 1] = im;
  }
  auto centreNear = [&](double x)
  {
    const int i0 = std::max(0, static_cast<int>(x - band.x0 - 3.0 * pitch_));
    const int i1 = std::max(i0, std::min(n, static_cast<int>(x - band.x0 + 3.0 * pitch_)));
    const double re = phase_re_[static_cast<size_t>(i1)] - phase_re_[static_cast<size_t>(i0)];
    const double im = phase_im_[static_cast<size_t>(i1)] - phase_im_[static_cast<size_t>(i0)];
    const double phase = std::atan2(im, re) / omega;  // a centre, modulo the pitch
    return phase + std::round((x - phase) / pitch_) * pitch_;
  };
  auto mean = [&](const std::vector<float>& edge, double a, double b)
  {
    double sum = 0.0;
    int count = 0;
    for (int i = std::max(0, static_cast<int>(std::ceil(a)) - band.x0);
         i <= std::min(n - 1, static_cast<int>(std::floor(b)) - band.x0); ++i)
      if (std::isfinite(edge[static_cast<size_t>(i)]))
      {
        sum += edge[static_cast<size_t>(i)];
        ++count;
      }
    return count > 0 ? sum / count : std::numeric_limits<double>::quiet_NaN();
  };
  const double half = 0.5 * pitch_;
  for (double x = band.x0 + half; x < band.x1 - half; x += pitch_)
  {
    const double c = centreNear(x);
    if (c - half < band.x0 || c + half > band.x1)
      continue;
    x = c;  // follow the local phase
    // Up is negative: a top edge higher on the left is a left top band. The row's tilt raises the
    // right window's edges by slope * 0.6 pitch: taken out.
    const double tilt = slope_ * 0.6 * pitch_;
    const double top_lr =
        mean(top_, c - 0.45 * pitch_, c - 0.15 * pitch_) - mean(top_, c + 0.15 * pitch_, c + 0.45 * pitch_) + tilt;
    const double bottom_lr = mean(bottom_, c - 0.45 * pitch_, c - 0.15 * pitch_) -
                             mean(bottom_, c + 0.15 * pitch_, c + 0.45 * pitch_) + tilt;
    const double yt = mean(top_, c - 1.0, c + 1.0), yb = mean(bottom_, c - 1.0, c + 1.0);
    if (!std::isfinite(top_lr) || !std::isfinite(bottom_lr) || !std::isfinite(yt) || !std::isfinite(yb))
      continue;
    const bool top_lopsided = std::abs(top_lr) > std::abs(bottom_lr);
    Blob cell;
    cell.shape = top_lopsided ? (top_lr < 0.0 ? 3 : 4) : (bottom_lr > 0.0 ? 2 : 1);
    // The lopsided edge against the straight one, in pixels.
    cell.margin = static_cast<float>(std::abs(std::abs(top_lr) - std::abs(bottom_lr)));
    cell.correlation = static_cast<float>(std::max(std::abs(top_lr), std::abs(bottom_lr)));
    if (cell.margin < kBandMinMargin)
      continue;
    cell.u = static_cast<float>(c);
    cell.v = static_cast<float>(0.5 * (yt + yb));  // the box centre; the decoder adds the shape's offset
    cell.x0 = static_cast<int>(std::lround(c - 0.5 * primitive_w_));
    cell.x1 = static_cast<int>(std::lround(c + 0.5 * primitive_w_));
    cell.y0 = static_cast<int>(std::floor(yt));
    cell.y1 = static_cast<int>(std::ceil(yb)) + 1;
    cell.area = cell.width() * cell.height();
    cell.contrast = static_cast<float>(band.contrast);
    cell.level = kBandLevel;
    blobs.push_back(cell);
  }
}

void BlobDetector::formWaveTable(double omega, int cols)
{
  // The same for every band of every image until the pitch changes: formed once, not per column per band.
  if (wave_omega_ == omega && cos_.size() == static_cast<size_t>(cols))
    return;
  wave_omega_ = omega;
  cos_.resize(static_cast<size_t>(cols));
  sin_.resize(static_cast<size_t>(cols));
  for (int x = 0; x < cols; ++x)
  {
    const double a = omega * x;
    cos_[static_cast<size_t>(x)] = std::cos(a);
    sin_[static_cast<size_t>(x)] = std::sin(a);
  }
}

namespace
{
#if defined(__SSE2__)
/// weighAbove()'s sums 16 pixels at a time: integer lanes, so exactly the sums of one at a time.
struct WeighSimd
{
  explicit WeighSimd(int threshold) : t(_mm_set1_epi8(static_cast<char>(threshold))) {}

  /// Adds the weights max(0, row[x] - threshold) of [x0, x1) to @p sum, times x to @p sum_x; the
  /// largest byte-wise to @p peaks (row readable up to x1 + 15). Returns x1.
  int weigh(const uint8_t* row, int x0, int x1, int64_t& sum, int64_t& sum_x, __m128i& peaks) const
  {
    const __m128i zero = _mm_setzero_si128();
    __m128i w_sums = zero, w_at = zero;  // per 8 lanes: sum of weights, times the chunk's first x
    __m128i w_lane = zero;               // sums of weight times its lane (0..15)
    for (int x = x0; x < x1; x += 16)
    {
      // Saturating subtraction is max(0, value - threshold); lanes past x1 count as 0.
      const __m128i inside = _mm_cmpgt_epi8(_mm_set1_epi8(static_cast<char>(std::min(x1 - x, 16))), lanes);
      const __m128i w =
          _mm_and_si128(_mm_subs_epu8(_mm_loadu_si128(reinterpret_cast<const __m128i*>(row + x)), t), inside);
      peaks = _mm_max_epu8(peaks, w);
      const __m128i chunk = _mm_sad_epu8(w, zero);
      w_sums = _mm_add_epi64(w_sums, chunk);
      w_at = _mm_add_epi64(w_at, _mm_mul_epu32(chunk, _mm_set1_epi32(x)));
      w_lane = _mm_add_epi32(w_lane, _mm_madd_epi16(_mm_unpacklo_epi8(w, zero), lanes_lo));
      w_lane = _mm_add_epi32(w_lane, _mm_madd_epi16(_mm_unpackhi_epi8(w, zero), lanes_hi));
    }
    w_lane = _mm_add_epi32(w_lane, _mm_shuffle_epi32(w_lane, _MM_SHUFFLE(1, 0, 3, 2)));
    w_lane = _mm_add_epi32(w_lane, _mm_shuffle_epi32(w_lane, _MM_SHUFFLE(2, 3, 0, 1)));
    sum += low64(w_sums) + low64(_mm_unpackhi_epi64(w_sums, w_sums));
    sum_x += low64(w_at) + low64(_mm_unpackhi_epi64(w_at, w_at)) + _mm_cvtsi128_si32(w_lane);
    return x1;
  }

  /// The largest of the 16 bytes of @p peaks.
  static int largest(__m128i peaks)
  {
    peaks = _mm_max_epu8(peaks, _mm_srli_si128(peaks, 8));
    peaks = _mm_max_epu8(peaks, _mm_srli_si128(peaks, 4));
    peaks = _mm_max_epu8(peaks, _mm_srli_si128(peaks, 2));
    peaks = _mm_max_epu8(peaks, _mm_srli_si128(peaks, 1));
    return _mm_cvtsi128_si32(peaks) & 0xff;
  }

  static int64_t low64(__m128i v)
  {
    int64_t out;
    _mm_storel_epi64(reinterpret_cast<__m128i*>(&out), v);
    return out;
  }

  const __m128i t;
  const __m128i lanes = _mm_setr_epi8(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const __m128i lanes_lo = _mm_setr_epi16(0, 1, 2, 3, 4, 5, 6, 7);
  const __m128i lanes_hi = _mm_setr_epi16(8, 9, 10, 11, 12, 13, 14, 15);
};
#endif

// Bit i = (p[i] > threshold) for i < min(n, 64), the rest clear. All 16 (n <= 16) or 64 bytes are
// read (one vector pass, no branch per pixel) when they lie before @p limit, the end of the image's buffer.
inline uint64_t maskAbove64(const uint8_t* p, int n, int threshold, const uint8_t* limit)
{
  const uint64_t valid = n >= 64 ? ~uint64_t{ 0 } : (uint64_t{ 1 } << n) - 1;
#if defined(__SSE2__)
  // Unsigned bytes compared as signed after flipping the top bit.
  const __m128i bias = _mm_set1_epi8(static_cast<char>(0x80));
  const __m128i t = _mm_set1_epi8(static_cast<char>(threshold ^ 0x80));
  if (n <= 16 && limit - p >= 16)  // most spans of a merged row: one load
  {
    const __m128i v = _mm_xor_si128(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)), bias);
    return static_cast<uint64_t>(static_cast<uint32_t>(_mm_movemask_epi8(_mm_cmpgt_epi8(v, t)))) & valid;
  }
  if (limit - p >= 64)
  {
    uint64_t m = 0;
    for (int i = 0; i < 64; i += 16)
    {
      const __m128i v = _mm_xor_si128(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p + i)), bias);
      m |= static_cast<uint64_t>(static_cast<uint32_t>(_mm_movemask_epi8(_mm_cmpgt_epi8(v, t)))) << i;
    }
    return m & valid;
  }
#endif
  uint64_t m = 0;
  for (int i = 0; i < std::min(n, 64); ++i)
    m |= static_cast<uint64_t>(p[i] > threshold) << i;
  return m;
}
}  // namespace

void BlobDetector::labelAbove(const cv::Mat& image, const Region& region, int threshold)
{
  // Runs above the threshold inside the region's spans, row by row, each joined 8-connected to the
  // row above as it is found, by union-find over labels (whose run buffers are free again by now).
  parts_.clear();
  labels_.clear();
  label_boxes_.clear();
  split_pixels_ += region.box.area;
  // At most a run per two pixels of each span (Run() is empty: no writes).
  runs_.resize(static_cast<size_t>(region.span_area + (region.end - region.begin) + 1) / 2);
  LinkCursor c{ runs_.data(), runs_.data(), runs_.data(), runs_.data(), -2 };
  const uint8_t* const limit = image.datalimit;
  for (const Span *s = spans_.data() + region.begin, *end = spans_.data() + region.end; s < end; ++s)
  {
    if (s->y != c.y)
      nextRow(c, s->y);
    const uint8_t* row = image.ptr<uint8_t>(s->y) + s->x0;
    const int n = s->x1 - s->x0;
    if (n < 64)
    {
      // Bits past n are clear: a run's start and end are the mask's changes, in pairs.
      const uint64_t m = maskAbove64(row, n, threshold, limit);
      for (uint64_t t = m ^ (m << 1); t != 0;)
      {
        const int a = __builtin_ctzll(t);
        t &= t - 1;
        const int b = __builtin_ctzll(t);
        t &= t - 1;
        linkRun(c, s->x0 + a, s->x0 + b);
      }
      continue;
    }
    uint64_t carry = 0;
    int x0 = -1;
    for (int k = 0; k < n; k += 64)
    {
      const uint64_t m = maskAbove64(row + k, n - k, threshold, limit);
      uint64_t t = m ^ (m << 1 | carry);
      carry = m >> 63;
      for (; t != 0; t &= t - 1)
      {
        const int x = s->x0 + k + __builtin_ctzll(t);
        if (x0 < 0)
          x0 = x;
        else
        {
          linkRun(c, x0, x);
          x0 = -1;
        }
      }
    }
    if (x0 >= 0)
      linkRun(c, x0, s->x1);
  }
  runs_.resize(static_cast<size_t>(c.out - runs_.data()));
  groupRunsIntoParts(region);
}

inline void BlobDetector::nextRow(LinkCursor& c, int y) const
{
  // The runs written since the last row change are the row above when it was y - 1.
  c.prev = c.y == y - 1 ? c.row_begin : c.out;
  c.prev_end = c.out;
  c.row_begin = c.out;
  c.y = y;
}

inline void BlobDetector::linkRun(LinkCursor& c, int x0, int x1)
{
  // linkRows()'s sweep, one run at a time: the run takes the label of the first run above it that
  // it touches (or a new one), and labels that meet are united: the union-find runs over the few
  // labels (hot in cache), not over every run. Each label's box grows with its runs.
  while (c.prev < c.prev_end && c.prev->x1 < x0)
    ++c.prev;
  const Run* q = c.prev;
  int32_t label;
  if (q < c.prev_end && q->x0 <= x1)
  {
    label = (q++)->parent;  // any label of the set: its root is found when needed
    for (; q < c.prev_end && q->x0 <= x1; ++q)
    {
      const int a = findLabel(label), b = findLabel(q->parent);
      label = std::min(a, b);
      labels_[static_cast<size_t>(std::max(a, b))] = label;
    }
  }
  else
  {
    label = static_cast<int32_t>(labels_.size());
    labels_.push_back(label);
    Box& b = label_boxes_.emplace_back();
    b.x0 = x0;
    b.x1 = x1;
    b.y0 = c.y;
    b.area = 0;
    b.last = 0;  // its run count
  }
  Run& run = *c.out++;
  run.y = c.y;
  run.x0 = x0;
  run.x1 = x1;
  run.parent = label;
  Box& b = label_boxes_[static_cast<size_t>(label)];
  b.x0 = std::min(b.x0, x0);
  b.x1 = std::max(b.x1, x1);
  b.y1 = c.y + 1;
  b.area += x1 - x0;
  ++b.last;
}

inline int BlobDetector::findLabel(int l)
{
  while (labels_[static_cast<size_t>(l)] != l)
  {
    int32_t& parent = labels_[static_cast<size_t>(l)];
    parent = labels_[static_cast<size_t>(parent)];  // path halving
    l = parent;
  }
  return l;
}

void BlobDetector::groupRunsIntoParts(const Region& region)
{
  // A part per root label, in the order of their first runs: a set's root is its smallest label,
  // the one its first run was given. Then the runs copied into spans_ grouped by part.
  part_of_label_.resize(labels_.size());
  for (size_t l = 0; l < labels_.size(); ++l)
  {
    const int root = findLabel(static_cast<int>(l));  // at most l
    const Box& b = label_boxes_[l];
    if (root == static_cast<int>(l))
    {
      part_of_label_[l] = static_cast<int32_t>(parts_.size());
      Region r{ Blob(), 0, b.last, 0 };
      r.box.x0 = b.x0;
      r.box.x1 = b.x1;
      r.box.y0 = b.y0;
      r.box.y1 = b.y1;
      r.box.area = b.area;
      parts_.push_back(r);
      continue;
    }
    const int32_t index = part_of_label_[static_cast<size_t>(root)];
    part_of_label_[l] = index;
    Region& r = parts_[static_cast<size_t>(index)];
    r.box.x0 = std::min(r.box.x0, b.x0);
    r.box.x1 = std::max(r.box.x1, b.x1);
    r.box.y1 = std::max(r.box.y1, b.y1);
    r.box.area += b.area;
    r.end += b.last;
  }
  if (parts_.size() == 1)
  {
    // All of the region above the threshold: the region's spans serve the next level as well (its
    // pixels at or below the threshold are below the next threshold too).
    parts_[0].begin = region.begin;
    parts_[0].end = region.end;
    parts_[0].span_area = region.span_area;
    return;
  }
  appendSpans(parts_);
}

bool BlobDetector::weighAbove(const cv::Mat& image, Blob& b, int threshold) const
{
  // Integer sums: exact, so the same as summing in double (every partial sum is far below 2^53).
  int64_t sw = 0, swx = 0, swy = 0;
  int peak = 0, area = 0;
  for (int y = b.y0; y < b.y1; ++y)
  {
    const uint8_t* row = image.ptr<uint8_t>(y);
    int64_t row_w = 0;
    for (int x = b.x0; x < b.x1; ++x)
    {
      const int w = std::max(0, static_cast<int>(row[x]) - threshold);
      row_w += w;
      swx += static_cast<int64_t>(w) * x;
      peak = std::max(peak, w);
      area += w > 0;
    }
    sw += row_w;
    swy += row_w * y;
  }
  b.area = area;
  return setWeighted(sw, swx, swy, peak, b);
}

bool BlobDetector::weighAbove(const cv::Mat& image, Region& part, int threshold) const
{
  // The part is its spans' pixels above the threshold (all of them unless it kept its region's
  // spans): weights max(0, value - threshold). Integer sums, exact, as above.
  int64_t sw = 0, swx = 0, swy = 0;
  int peak = 0;
#if defined(__SSE2__)
  const WeighSimd k(threshold);
  __m128i peaks = _mm_setzero_si128();
#endif
  for (int s = part.begin; s < part.end; ++s)
  {
    const Span& span = spans_[static_cast<size_t>(s)];
    const uint8_t* row = image.ptr<uint8_t>(span.y);
    int64_t span_w = 0, span_wx = 0;
    int x = span.x0;
#if defined(__SSE2__)
    if (image.datalimit - (row + span.x1) >= 15)  // every 16-pixel load lies in the image's buffer
      x = k.weigh(row, span.x0, span.x1, span_w, span_wx, peaks);
#endif
    for (; x < span.x1; ++x)
    {
      const int w = std::max(0, static_cast<int>(row[x]) - threshold);
      span_w += w;
      span_wx += static_cast<int64_t>(w) * x;
      peak = std::max(peak, w);
    }
    sw += span_w;
    swx += span_wx;
    swy += span_w * span.y;
  }
#if defined(__SSE2__)
  peak = std::max(peak, WeighSimd::largest(peaks));
#endif
  return setWeighted(sw, swx, swy, peak, part.box);
}

bool BlobDetector::setWeighted(int64_t sw, int64_t swx, int64_t swy, int peak, Blob& b)
{
  if (sw <= 0)
    return false;
  b.u = static_cast<float>(static_cast<double>(swx) / static_cast<double>(sw));
  b.v = static_cast<float>(static_cast<double>(swy) / static_cast<double>(sw));
  b.contrast = static_cast<float>(peak);
  return true;
}

}  // namespace sl_decoder
