#include "sl_decoder/result_images.h"

#include <cmath>
#include <limits>
#include <string>

#include <opencv2/imgproc.hpp>

namespace sl_decoder
{

cv::Mat depthImage(const DecodeResult& result, int width, int height)
{
  cv::Mat depth(height, width, CV_32FC1, cv::Scalar(std::numeric_limits<float>::quiet_NaN()));
  for (const Blob& b : result.blobs)
  {
    if (!b.valid)
      continue;
    const int x = static_cast<int>(std::lround(b.u)), y = static_cast<int>(std::lround(b.v));
    if (x >= 0 && y >= 0 && x < depth.cols && y < depth.rows)
      depth.at<float>(y, x) = b.z;
  }
  return depth;
}

void drawDebugImage(const cv::Mat& mono, const DecodeResult& result, cv::Mat& bgr)
{
  cv::cvtColor(mono, bgr, cv::COLOR_GRAY2BGR);
  static const cv::Scalar kShapeColour[5] = { cv::Scalar(128, 128, 128), cv::Scalar(255, 80, 80),
                                              cv::Scalar(80, 220, 80), cv::Scalar(60, 60, 255),
                                              cv::Scalar(0, 220, 255) };
  for (const Blob& b : result.blobs)
  {
    const cv::Scalar& colour = kShapeColour[b.shape];
    cv::rectangle(bgr, cv::Rect(b.x0, b.y0, b.width(), b.height()), colour, 1);
    if (b.decoded())
    {
      cv::circle(bgr, cv::Point(static_cast<int>(b.u), static_cast<int>(b.v)), 2, cv::Scalar(255, 255, 255),
                 cv::FILLED);
      if (b.col % 4 == 0)  // every fourth column, or the labels cover the image
        cv::putText(bgr, std::to_string(b.row) + "," + std::to_string(b.col), cv::Point(b.x0, b.y0 - 2),
                    cv::FONT_HERSHEY_PLAIN, 0.6, cv::Scalar(255, 255, 255), 1);
    }
  }
}

}  // namespace sl_decoder
