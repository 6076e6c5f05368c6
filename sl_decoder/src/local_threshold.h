#pragma once
/// @file local_threshold.h
/// @brief The blob detector's per-row kernels (private to sl_decoder_core): sliding column sums,
/// their prefix sums and the local-mean threshold of one row.
///
/// The threshold has a portable, an SSE2 and an AVX2 path. All three compute every interior pixel
/// with the same float operations in the same order (no fused multiply-add), so they give
/// bit-identical masks and weights; `BlobDetector.VectorPathsGiveIdenticalBlobs` checks it.

#include <cstdint>
#include <vector>

namespace sl_decoder
{
namespace local_threshold
{

/// @brief The instruction sets a threshold can use.
enum class Path
{
  Portable,  ///< plain C++
  Sse2,      ///< 16 pixels at a time (x86-64 baseline)
  Avx2       ///< 32 pixels at a time, where the CPU has AVX2
};

/// @brief The fastest path this CPU runs.
Path fastestPath();

/// @brief True when this CPU can run @p path.
bool supported(Path path);

/// @brief True when the sums of a @p window x @p window window of 8-bit pixels fit in 16 bits:
/// then column and prefix sums may be uint16_t, taken modulo 2^16 (twice the lanes per vector).
bool narrowSumsFit(int window);

/**
 * @brief Slides the column sums @p cols down @p n rows and forms the prefix sums of each: for row k,
 * cols[x] += add[k][x] - sub[k][x], then pre[k][0] = 0 and pre[k][x + 1] = pre[k][x] + cols[x]
 * (in T: modulo 2^16 for uint16_t). One pass: the column sums of the rows between stay in registers.
 * @param cols w column sums; the last row's afterwards.
 * @param add, sub n image rows each (w pixels; a row of zeros where nothing is added or dropped).
 * @param pre n rows of w + 1 prefix sums.
 * @param path the instruction set (all give the same sums).
 */
void slidePrefixSums(int32_t* cols, const uint8_t* const* add, const uint8_t* const* sub, int32_t* const* pre, int n,
                     int w, Path path);
/// @brief The same modulo 2^16 (when narrowSumsFit()).
void slidePrefixSums(uint16_t* cols, const uint8_t* const* add, const uint8_t* const* sub, uint16_t* const* pre, int n,
                     int w, Path path);

/// @brief One row of the local-mean threshold.
struct RowInput
{
  const uint8_t* src = nullptr;     ///< the image row
  const int32_t* pre = nullptr;     ///< prefix sums of the row's column sums (w + 1 values), or:
  const uint16_t* pre16 = nullptr;  ///< the same modulo 2^16 (used when not null)
  int w = 0;                        ///< row length, px
  int r = 0;                        ///< half window, px
  int rows = 0;                     ///< image rows inside the window (fewer at the top and bottom)
  float offset = 0.f;               ///< grey levels above the local mean
};

/// @brief The constants of the rows whose windows have one row count: those of the interior (one
/// area) and those of each pixel whose window an end of the row cuts (its own area).
struct RowConstants
{
  /// A pixel near an end of the row: its window's columns [xa, xb), area and integer offset.
  struct Edge
  {
    int32_t x, xa, xb, area, off;
  };
  int lo = 0, hi = 0;    ///< the interior columns [lo, hi)
  float inv_area = 0.f;  ///< 1 / the interior's area
  float off = 0.f;       ///< the interior's offset, rounded to its integer grid, over its area
  std::vector<Edge> edges;
};

/// @brief Sets @p c for rows like @p in (its w, r, rows and offset; the pixels are not read).
void rowConstants(const RowInput& in, RowConstants& c);

/// @brief value - mean of a border pixel (the image edge cuts its window of @p area pixels): the
/// one division both thresholdRow() and weightOf() use.
inline float borderWeight(uint8_t value, int32_t sum, int32_t area)
{
  return static_cast<float>(value) - static_cast<float>(sum) / static_cast<float>(area);
}

/**
 * @brief value - mean of the pixel at column @p x of a row @p w wide: the same float operations as
 * thresholdRow() uses, so the same bits.
 * @param sum the sum of the pixel's window (the image's part of it), @p rows its rows
 */
inline float weightOf(uint8_t value, int32_t sum, int x, int w, int r, int rows)
{
  const float v = static_cast<float>(value);
  const int lo = r < w ? r : w, hi = w - r - 1 > lo ? w - r - 1 : lo;
  if (x >= lo && x < hi)  // the interior: one area, multiplied by its inverse
    return v - static_cast<float>(sum) * (1.0f / static_cast<float>(rows * (2 * r + 1)));
  const int xa = x - r > 0 ? x - r : 0, xb = x + r + 1 < w ? x + r + 1 : w;
  return borderWeight(value, sum, rows * (xb - xa));
}

/**
 * @brief Sets bit x of @p bits for the pixels brighter than their window's mean plus the offset,
 * and writes value - mean to weight[x] for those pixels (the others' weight is left unspecified).
 * @param c the constants of rows like @p in (the same w, r, rows and offset), from rowConstants().
 * @param bits (w + 63) / 64 + 1 words, cleared here.
 * @param weight w values.
 */
void thresholdRow(const RowInput& in, const RowConstants& c, Path path, uint64_t* bits, float* weight);

}  // namespace local_threshold
}  // namespace sl_decoder
