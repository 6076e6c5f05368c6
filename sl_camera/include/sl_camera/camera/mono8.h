/**
 * @file
 * Conversion of whatever a camera or an image file delivers to 8-bit grey.
 */
#pragma once

#include <string>

#include <opencv2/core.hpp>

namespace sl_camera
{

/**
 * Converts @p in to mono8 in @p out (reusing out's buffer when the size matches).
 * Accepted: 8- or 16-bit images with 1 (grey), 3 (BGR) or 4 (BGRA) channels, and 32-bit float
 * grey/BGR in 0..1. Colour becomes luma (ITU-R BT.601 weights, as cv::cvtColor); 16-bit values keep
 * their top 8 of @p significant_bits bits (e.g. 12 for a Mono12 camera, 16 for a 16-bit PNG).
 * @throws std::invalid_argument for empty images or other types, naming the type.
 */
void toMono8(const cv::Mat& in, cv::Mat& out, int significant_bits = 16);

/** Human-readable OpenCV type, e.g. "8UC3". */
std::string matTypeName(int type);

}  // namespace sl_camera
