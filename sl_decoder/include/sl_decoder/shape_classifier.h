#pragma once
/// @file shape_classifier.h
/// @brief Identifies which of the four primitive shapes a blob is (ROS-free).

#include <array>
#include <vector>

#include <opencv2/core.hpp>

#include "sl_decoder/blob.h"
#include "sl_decoder/decoder_config.h"

namespace sl_decoder
{

/**
 * @brief Resamples a blob's bounding box to the template grid and correlates it (zero-mean NCC)
 * with the four ideal shapes; the best one wins if it is clear enough.
 *
 * The templates are the shapes' area coverage of the grid, blurred a little, normalised to zero
 * mean and unit norm once, so each blob costs one bilinear resampling and four dot products.
 * Every sum runs in one fixed order (sixteen lanes, see the .cpp) on every path, so the
 * correlations are the same bits with and without AVX2 (and from version to version).
 */
class ShapeClassifier
{
public:
  /// @brief Builds the templates for primitives of @p box_width x @p box_height projector px.
  /// @throws std::invalid_argument naming template_width or template_height outside 3..64
  ShapeClassifier(const DecoderConfig& config = DecoderConfig(), int box_width = 5, int box_height = 9);

  /**
   * @brief Sets blob.shape (0 if unclear), blob.correlation and blob.margin.
   * @param image the CV_8UC1 image the blob was found in.
   */
  void classify(const cv::Mat& image, Blob& blob);

  /**
   * @brief Re-estimates blob.u, blob.v as the centroid of all the blob's light above the dark
   * level around it, over its box grown by @p margin px.
   *
   * The labelling's centroid only weighs pixels above the local threshold; cutting off the blurred
   * edges of the asymmetric shapes shifts it by about a seventh of a pixel, a millimetre of depth at
   * 0.7 m. Blur preserves the centroid of the whole light distribution, so summing all of it (minus
   * the dark level, measured on the grown box's rim) removes that bias.
   */
  void refineCentroid(const cv::Mat& image, Blob& blob, int margin = 2) const;

  /**
   * @brief Uses the AVX2 paths where the CPU has them (@p on, the default) or the portable ones
   * only; returns whether AVX2 is in use. Both give bit-identical results (the same float
   * operations in the same order); the choice is for tests and benchmarks.
   */
  bool useAvx2(bool on);

private:
  static constexpr int kMaxGrid = 64;  // DecoderConfig limits the template to 64 x 64
  static constexpr float kMergedMinCorrelation = 0.2f;  // at most, for parts of merged rows

  /// Source pixels and weights of the grid columns and rows for @p blob (ix_, ax_, iy_, ay_).
  void placeGrid(const cv::Mat& image, const Blob& blob);
  /// Bilinear samples of the grid into samples_, one grid row at a time.
  void sampleGrid(const cv::Mat& image);
  /// The sums of samples_ (sum, sum of squares, the four dot products) in the fixed order.
  void sumSamples(float sums[6]) const;
  /// classify() with AVX2, for a grid 8 samples wide.
  void classify8Avx2(const cv::Mat& image, Blob& blob);
  /// Correlations from the sums; sets blob.shape, blob.correlation, blob.margin.
  void decide(const float sums[6], Blob& blob) const;

  bool avx2_ = false;
  DecoderConfig config_;
  int tw_, th_;
  std::array<std::vector<float>, 4> templates_;  // zero mean, unit norm
  std::vector<float> rows_;                      // the same, grid row after grid row the four templates' rows (AVX2)
  std::vector<float> samples_;
  std::array<int, kMaxGrid> ix_{}, iy_{};    // sample grid: left/top source pixel
  std::array<float, kMaxGrid> ax_{}, ay_{};  // and the interpolation weights
};

}  // namespace sl_decoder
