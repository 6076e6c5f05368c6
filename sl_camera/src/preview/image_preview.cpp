#include "sl_camera/preview/image_preview.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <opencv2/imgproc.hpp>

namespace sl_camera
{

void PreviewConfig::validate() const
{
  if (scale < 1 || scale > 16)
    throw std::invalid_argument("scale must be in 1..16, got " + std::to_string(scale));
  if (!(rate > 0.0 && rate <= 1000.0))  // also refuses NaN
    throw std::invalid_argument("rate must be in (0, 1000] Hz, got " + std::to_string(rate));
}

ImagePreview::ImagePreview(const PreviewConfig& config) : config_(config)
{
  config_.validate();
  period_ = 1.0 / config_.rate;
}

bool ImagePreview::due(double t)
{
  const bool restart = !started_ || t >= next_ + period_ || t < next_ - 2.0 * period_;
  if (restart)
  {
    started_ = true;
    next_ = t + period_;
    return true;
  }
  if (t < next_)
    return false;
  next_ += period_;
  return true;
}

void ImagePreview::shrink(const cv::Mat& in, cv::Mat& out) const
{
  if (in.empty())
    throw std::invalid_argument("ImagePreview::shrink: empty image");
  if (config_.scale == 1)
  {
    in.copyTo(out);
    return;
  }
  const cv::Size size(std::max(1, in.cols / config_.scale), std::max(1, in.rows / config_.scale));
  cv::resize(in, out, size, 0.0, 0.0, cv::INTER_AREA);
}

}  // namespace sl_camera
