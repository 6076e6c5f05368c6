#pragma once
/// @file primitives.h
/// @brief The four binary primitive shapes and their matching templates (ROS-free).
///
/// Each primitive is three horizontal bands of equal height. A band is Wide (every column),
/// Left (left half including the middle column) or Right (right half including the middle
/// column). The four shapes are
///   1: W L R    2: W R L    3: L R W    4: R L W
/// Left and Right bands always share the middle column, so every shape is one 8-connected (in fact
/// 4-connected) component whose bounding box is the full primitive box, and all four have the same
/// area and the same horizontal centroid (the middle column). They differ in where their mass sits
/// at the scale of a band (3 projector pixels tall, 2-3 wide), which survives defocus blur and
/// down-sampling far better than one-pixel details; a search over all band combinations with the
/// decoder's bounding-box matching picked this set for the largest worst-case margin between the
/// correlation with the right template and with the best wrong one (see primitives_test.cpp).

#include <array>

#include <opencv2/core.hpp>

namespace sl_projector
{

/// @brief Number of primitive shapes (the alphabet size P of the pattern).
constexpr int kNumShapes = 4;

/// @brief Band kinds of a primitive.
enum class Band
{
  Wide,
  Left,
  Right
};

/// @brief The three bands (top, middle, bottom) of shape @p value (1..4).
/// @throws std::invalid_argument for a value outside 1..4.
std::array<Band, 3> shapeBands(int value);

/**
 * @brief Binary bitmap of shape @p value at @p width x @p height pixels (CV_8U, 0 or 255).
 * @param value shape 1..4.
 * @param width box width (>= 3, default 5).
 * @param height box height (>= 3, default 9).
 * @throws std::invalid_argument for a bad value or size.
 */
cv::Mat shapeBitmap(int value, int width = 5, int height = 9);

/**
 * @brief Centroid of shape @p value's bitmap in box pixel coordinates (pixel centres at integers).
 *
 * This is the point of the primitive that the decoder locates (intensity centroid), so the
 * projector-side coordinate of a decoded primitive is its box origin plus this offset.
 */
cv::Point2d shapeCentroid(int value, int width = 5, int height = 9);

/**
 * @brief Matching template of shape @p value: the coverage of a @p tw x @p th grid by the shape's
 * @p box_width x @p box_height bitmap (area-weighted, CV_32F in [0,1]), optionally blurred by
 * @p sigma template pixels.
 *
 * The decoder resamples each candidate blob's bounding box to this grid and correlates it with
 * the four templates.
 */
cv::Mat shapeTemplate(int value, int tw, int th, double sigma = 0.0, int box_width = 5, int box_height = 9);

/**
 * @brief Zero-mean normalised cross-correlation of two equally sized single-channel images.
 * @return NCC in [-1, 1], or 0 when either image is constant.
 */
double normalizedCrossCorrelation(const cv::Mat& a, const cv::Mat& b);

}  // namespace sl_projector
