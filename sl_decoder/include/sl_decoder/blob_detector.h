#pragma once
/// @file blob_detector.h
/// @brief Local thresholding and 8-connected run-based labelling in one pass (ROS-free).

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "sl_decoder/blob.h"
#include "sl_decoder/decoder_config.h"

namespace sl_decoder
{

/**
 * @brief Finds candidate primitives: pixels brighter than their local mean by an offset, grouped
 * into 8-connected components, filtered for speckles, bands and oversized patches.
 *
 * Thresholding, run extraction and the centroid sums happen in one pass over the image, with the
 * local mean from running column sums; components are formed by union-find over runs. All buffers are reused across
 * calls: after the first image of a given size, detect() does not allocate.
 */
class BlobDetector
{
public:
  /// @brief Uses @p config (validated by the caller).
  explicit BlobDetector(const DecoderConfig& config = DecoderConfig());

  /// @brief Replaces the configuration.
  void setConfig(const DecoderConfig& config) { config_ = config; }

  /**
   * @brief Detects blobs in a CV_8UC1 image.
   * @param image mono8 image.
   * @param[out] blobs cleared and filled (capacity reused).
   */
  void detect(const cv::Mat& image, std::vector<Blob>& blobs);

  /// @brief Number of components found before filtering in the last call.
  int componentCount() const { return components_; }

private:
  struct Run
  {
    int32_t y, x0, x1;  // [x0, x1)
    int32_t parent;     // union-find over runs
    float sw, swx;      // sum of weights, sum of weight * x
    float peak;         // max weight
  };

  struct Acc
  {
    float sw, swx, swy, peak;
  };

  // Inline (defined in blob_detector.cpp, the only user): called per run, a call through the shared
  // library's PLT cost more than the work.
  inline int find(int i);
  inline void unite(int a, int b);

  DecoderConfig config_;
  std::vector<int32_t> col_sum_;    // column sums over the window rows of the current row
  std::vector<int32_t> prefix_;     // prefix sums of col_sum_
  std::vector<uint64_t> bits_;      // foreground flags of the current row, one bit per pixel
  std::vector<float> weight_;       // value minus local mean of the current row's pixels
  std::vector<Run> runs_;
  std::vector<int32_t> blob_of_root_;
  std::vector<Acc> acc_;
  int components_ = 0;
};

}  // namespace sl_decoder
