// The threshold's kernels (private to sl_decoder_core): 16-bit sums modulo 2^16 give the 32-bit
// sums' masks and weights bit for bit, on every instruction set, up to the largest window they fit.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include <opencv2/core.hpp>

#include "../src/local_threshold.h"

using namespace sl_decoder::local_threshold;

namespace
{
/// The reference sums, one value at a time: out[x] = in[x] + add[x] - sub[x] (null rows: none).
template <class T>
void slideColumnSums(const T* in, const uint8_t* add, const uint8_t* sub, int w, T* out)
{
  for (int x = 0; x < w; ++x)
    out[x] = static_cast<T>(in[x] + (add != nullptr ? add[x] : 0) - (sub != nullptr ? sub[x] : 0));
}

/// pre[0] = 0, pre[x + 1] = pre[x] + v[x] (in T: modulo 2^16 for uint16_t).
template <class T>
void prefixSums(const T* v, T* pre, int w)
{
  pre[0] = 0;
  for (int x = 0; x < w; ++x)
    pre[x + 1] = static_cast<T>(pre[x] + v[x]);
}

/// Mask and weights of row @p y of @p image with sums of type T (windows clipped to the image).
template <class T>
void thresholdOf(const cv::Mat& image, int y, int window, Path path, std::vector<uint64_t>& bits,
                 std::vector<float>& weight)
{
  const int w = image.cols, h = image.rows, r = window / 2;
  std::vector<T> zero(static_cast<size_t>(w), 0), cols(static_cast<size_t>(w)), next(static_cast<size_t>(w));
  cols = zero;
  for (int yy = std::max(0, y - r); yy < std::min(h, y + r + 1); ++yy)
  {
    slideColumnSums(cols.data(), image.ptr<uint8_t>(yy), nullptr, w, next.data());
    cols.swap(next);
  }
  std::vector<T> pre(static_cast<size_t>(w + 1));
  prefixSums(cols.data(), pre.data(), w);
  RowInput in;
  in.src = image.ptr<uint8_t>(y);
  if constexpr (sizeof(T) == 2)
    in.pre16 = reinterpret_cast<const uint16_t*>(pre.data());
  else
    in.pre = reinterpret_cast<const int32_t*>(pre.data());
  in.w = w;
  in.r = r;
  in.rows = std::min(h, y + r + 1) - std::max(0, y - r);
  in.offset = 2.5f;
  bits.assign(static_cast<size_t>((w + 63) / 64 + 1), 0);
  weight.assign(static_cast<size_t>(w), 0.f);
  RowConstants constants;
  rowConstants(in, constants);
  thresholdRow(in, constants, path, bits.data(), weight.data());
}
}  // namespace

TEST(LocalThreshold, NarrowSumsFitUpToAWindowOf15)
{
  EXPECT_TRUE(narrowSumsFit(3));
  EXPECT_TRUE(narrowSumsFit(15));
  EXPECT_FALSE(narrowSumsFit(17));
  EXPECT_FALSE(narrowSumsFit(16)) << "an even window is one wider: 17 x 17";
}

TEST(LocalThreshold, SixteenBitSumsGiveTheThirtyTwoBitMasksAndWeights)
{
  cv::RNG rng(31);
  int compared = 0, foreground = 0;
  for (int trial = 0; trial < 40; ++trial)
  {
    const int w = rng.uniform(1, 300), h = rng.uniform(1, 40);
    cv::Mat image(h, w, CV_8UC1);
    if (trial % 4 == 0)
      image.setTo(255);  // the largest sums a window can have
    else
      rng.fill(image, cv::RNG::UNIFORM, 0, 256);
    const int window = 2 * rng.uniform(1, 8) + 1;  // 3 .. 15
    ASSERT_TRUE(narrowSumsFit(window));
    for (Path path : { Path::Portable, Path::Sse2, Path::Avx2 })
    {
      if (!supported(path))
        continue;
      const int y = rng.uniform(0, h);
      std::vector<uint64_t> bits32, bits16;
      std::vector<float> weight32, weight16;
      thresholdOf<int32_t>(image, y, window, path, bits32, weight32);
      thresholdOf<uint16_t>(image, y, window, path, bits16, weight16);
      ASSERT_EQ(bits32, bits16) << "trial " << trial;
      for (int x = 0; x < w; ++x)
        if ((bits32[static_cast<size_t>(x >> 6)] >> (x & 63)) & 1)
        {
          ASSERT_EQ(0, std::memcmp(&weight32[static_cast<size_t>(x)], &weight16[static_cast<size_t>(x)], sizeof(float)))
              << "trial " << trial << " x " << x;
          ++foreground;
        }
      ++compared;
    }
  }
  EXPECT_GE(compared, 80);
  EXPECT_GT(foreground, 1000);
}

namespace
{
/// slidePrefixSums() on every path against the reference sums, row after row, for sums of type T.
template <class T>
void expectSlidePrefixSumsAsSeparatePasses(cv::RNG& rng)
{
  const int w = rng.uniform(1, 200), n = rng.uniform(1, 7);
  cv::Mat rows(2 * n, w, CV_8UC1);
  rng.fill(rows, cv::RNG::UNIFORM, 0, 256);
  const std::vector<uint8_t> zeros(static_cast<size_t>(w), 0);
  std::vector<T> cols(static_cast<size_t>(w)), fused_cols;
  for (T& c : cols)
    c = static_cast<T>(rng.uniform(255 * n, 4 * 255 * n));  // never below what is dropped
  fused_cols = cols;
  std::vector<T> pre(static_cast<size_t>(n * (w + 1))), fused(pre.size());
  const uint8_t* add[8];
  const uint8_t* sub[8];
  T* fused_pre[8];
  for (int k = 0; k < n; ++k)
  {
    add[k] = k % 3 == 2 ? zeros.data() : rows.ptr<uint8_t>(2 * k);
    sub[k] = k % 4 == 3 ? zeros.data() : rows.ptr<uint8_t>(2 * k + 1);
    fused_pre[k] = fused.data() + static_cast<size_t>(k * (w + 1));
    std::vector<T> next(cols.size());
    slideColumnSums(cols.data(), add[k], sub[k], w, next.data());
    cols.swap(next);
    prefixSums(cols.data(), pre.data() + static_cast<size_t>(k * (w + 1)), w);
  }
  for (Path path : { Path::Portable, Path::Sse2, Path::Avx2 })
  {
    if (!supported(path))
      continue;
    std::vector<T> path_cols = fused_cols;
    std::fill(fused.begin(), fused.end(), T{ 0 });
    slidePrefixSums(path_cols.data(), add, sub, fused_pre, n, w, path);
    ASSERT_EQ(cols, path_cols) << "w " << w << " n " << n << " path " << static_cast<int>(path);
    ASSERT_EQ(pre, fused) << "w " << w << " n " << n << " path " << static_cast<int>(path);
  }
}
}  // namespace

TEST(LocalThreshold, SlidingAndPrefixSumsInOnePassGiveTheSeparatePassesSums)
{
  cv::RNG rng(7);
  for (int trial = 0; trial < 60; ++trial)
  {
    expectSlidePrefixSumsAsSeparatePasses<int32_t>(rng);
    expectSlidePrefixSumsAsSeparatePasses<uint16_t>(rng);
  }
}
