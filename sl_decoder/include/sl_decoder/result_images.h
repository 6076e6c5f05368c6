#pragma once
/// @file result_images.h
/// @brief Images drawn from a decoding result: the depth image and the debug overlay (ROS-free).

#include <opencv2/core.hpp>

#include "sl_decoder/decoder.h"

namespace sl_decoder
{

/**
 * @brief The depth image of @p result (REP 118): @p width x @p height 32FC1 metres in the camera
 * frame, NaN where there is no measurement; each valid blob's depth at its rounded centroid (blobs
 * whose centroid rounds outside the image are left out).
 */
cv::Mat depthImage(const DecodeResult& result, int width, int height);

/**
 * @brief The debug overlay: @p mono (8-bit, one channel) as BGR in @p bgr, every blob's box in the
 * colour of its shape, a white dot at each decoded centroid and, every fourth pattern column,
 * the decoded "row,col" above the box.
 */
void drawDebugImage(const cv::Mat& mono, const DecodeResult& result, cv::Mat& bgr);

}  // namespace sl_decoder
