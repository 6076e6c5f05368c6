#include "sl_rig/primitives.h"

#include <stdexcept>
#include <string>

#include <opencv2/imgproc.hpp>

namespace sl_projector
{

std::array<Band, 3> shapeBands(int value)
{
  switch (value)
  {
    case 1:
      return { Band::Wide, Band::Left, Band::Right };
    case 2:
      return { Band::Wide, Band::Right, Band::Left };
    case 3:
      return { Band::Left, Band::Right, Band::Wide };
    case 4:
      return { Band::Right, Band::Left, Band::Wide };
    default:
      throw std::invalid_argument("shape value must be 1..4, got " + std::to_string(value));
  }
}

cv::Mat shapeBitmap(int value, int width, int height)
{
  if (width < 3 || height < 3)
    throw std::invalid_argument("primitive size must be at least 3 x 3, got " + std::to_string(width) + " x " +
                                std::to_string(height));
  const std::array<Band, 3> bands = shapeBands(value);
  cv::Mat m(height, width, CV_8U, cv::Scalar(0));
  // Left covers [0, width/2], Right covers [(width-1)/2, width-1]: they share the middle column
  // (two columns for even widths) so the bands stay connected.
  const int left_end = width / 2;
  const int right_begin = (width - 1) / 2;
  for (int y = 0; y < height; ++y)
  {
    const Band b = bands[static_cast<size_t>(std::min(2, y * 3 / height))];
    for (int x = 0; x < width; ++x)
    {
      const bool on = b == Band::Wide || (b == Band::Left && x <= left_end) || (b == Band::Right && x >= right_begin);
      m.at<uint8_t>(y, x) = on ? 255 : 0;
    }
  }
  return m;
}

cv::Point2d shapeCentroid(int value, int width, int height)
{
  const cv::Moments mo = cv::moments(shapeBitmap(value, width, height), true);
  return { mo.m10 / mo.m00, mo.m01 / mo.m00 };
}

cv::Mat shapeTemplate(int value, int tw, int th, double sigma, int box_width, int box_height)
{
  if (tw < 1 || th < 1)
    throw std::invalid_argument("template size must be positive");
  // Rasterise at a multiple of the box size and average down: exact area coverage.
  constexpr int kOversample = 8;
  cv::Mat bitmap;
  shapeBitmap(value, box_width, box_height).convertTo(bitmap, CV_32F, 1.0 / 255.0);
  cv::Mat fine;
  cv::resize(bitmap, fine, cv::Size(tw * kOversample, th * kOversample), 0, 0, cv::INTER_NEAREST);
  cv::Mat t;
  cv::resize(fine, t, cv::Size(tw, th), 0, 0, cv::INTER_AREA);
  if (sigma > 0.0)
    cv::GaussianBlur(t, t, cv::Size(0, 0), sigma, sigma, cv::BORDER_REPLICATE);
  return t;
}

double normalizedCrossCorrelation(const cv::Mat& a, const cv::Mat& b)
{
  CV_Assert(a.size() == b.size() && a.channels() == 1 && b.channels() == 1);
  cv::Mat fa, fb;
  a.convertTo(fa, CV_64F);
  b.convertTo(fb, CV_64F);
  const double n = static_cast<double>(fa.total());
  const double ma = cv::sum(fa)[0] / n;
  const double mb = cv::sum(fb)[0] / n;
  fa -= ma;
  fb -= mb;
  const double saa = fa.dot(fa), sbb = fb.dot(fb);
  if (saa <= 1e-12 * n || sbb <= 1e-12 * n)
    return 0.0;
  return fa.dot(fb) / std::sqrt(saa * sbb);
}

}  // namespace sl_projector
