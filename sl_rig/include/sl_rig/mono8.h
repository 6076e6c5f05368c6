#pragma once
/// @file mono8.h
/// @brief Conversion of whatever a camera, an image file or an image message delivers to 8-bit grey,
/// the decoder's input (ROS-free; OpenCV only). The one conversion of the stack: the camera drivers,
/// the decoder, the calibration and their tools all go through it.
///
/// 16-bit values are scaled by their significant bits: the top 8 of @p significant_bits bits are
/// kept (12 for a Mono12 camera, 10 for Mono10, whose values fill only the low bits of 16), and of
/// all 16 bits when the source does not tell (a 16-bit PNG, a `mono16` image message). A pixel's grey
/// value so depends on its own value alone, never on the brightest pixel of the frame.

#include <string>

#include <opencv2/core.hpp>

namespace sl_rig
{

/// @brief Order of the colour channels of a 3- or 4-channel image (the 4th is alpha, ignored).
enum class ChannelOrder
{
  Bgr,  ///< OpenCV's order (cv::imread, cameras through OpenCV)
  Rgb   ///< e.g. the `rgb8` and `rgba8` encodings
};

/**
 * @brief Converts @p in to mono8 in @p out (reusing out's buffer when the size matches).
 *
 * Accepted: 8- or 16-bit images with 1 (grey), 3 or 4 channels, and 32-bit float grey or colour in
 * 0..1. Colour becomes luma (ITU-R BT.601 weights, as cv::cvtColor). 16-bit values keep their top 8 of
 * @p significant_bits bits (see the file comment).
 * @throws std::invalid_argument for an empty image or another type (naming it, e.g. "8UC2"), or
 *         @p significant_bits outside 8..16 with a 16-bit image.
 */
void toMono8(const cv::Mat& in, cv::Mat& out, int significant_bits = 16, ChannelOrder order = ChannelOrder::Bgr);

/**
 * @brief Converts an image that comes with a ROS encoding name (sensor_msgs/Image) to mono8.
 * @param encoding `mono8` or `8UC1` is used as is; `mono16` or `16UC1` (scaled by
 *        @p significant_bits, 16 when unknown), `rgb8`, `bgr8`, `rgba8` and `bgra8` are converted as
 *        toMono8() above.
 * @param[out] converted set to true when a conversion happened.
 * @return the mono8 image (shares the data for mono8).
 * @throws std::invalid_argument naming the encoding when it is not supported or the image's type is
 *         not the one the encoding names.
 */
cv::Mat toMono8(const cv::Mat& image, const std::string& encoding, bool& converted, int significant_bits = 16);

/// @brief Human-readable OpenCV type, e.g. "8UC3".
std::string matTypeName(int type);

}  // namespace sl_rig
