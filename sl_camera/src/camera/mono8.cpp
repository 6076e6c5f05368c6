#include "sl_camera/camera/mono8.h"

#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace sl_camera
{

std::string matTypeName(int type)
{
  static const char* const depths[] = { "8U", "8S", "16U", "16S", "32S", "32F", "64F", "16F" };
  const int depth = CV_MAT_DEPTH(type);
  return std::string(depths[depth]) + "C" + std::to_string(CV_MAT_CN(type));
}

void toMono8(const cv::Mat& in, cv::Mat& out, int significant_bits)
{
  if (in.empty())
    throw std::invalid_argument("empty image");
  const int channels = in.channels();
  if (channels != 1 && channels != 3 && channels != 4)
    throw std::invalid_argument("cannot convert a " + matTypeName(in.type()) + " image to mono8");

  switch (in.depth())
  {
    case CV_8U:
      if (channels == 1)
        in.copyTo(out);
      else
        cv::cvtColor(in, out, channels == 3 ? cv::COLOR_BGR2GRAY : cv::COLOR_BGRA2GRAY);
      return;
    case CV_16U:
    {
      if (significant_bits < 8 || significant_bits > 16)
        throw std::invalid_argument("significant bits must be in 8..16, got " + std::to_string(significant_bits));
      const double scale = 1.0 / static_cast<double>(1 << (significant_bits - 8));
      if (channels == 1)
      {
        in.convertTo(out, CV_8U, scale);
      }
      else
      {
        cv::Mat grey16;
        cv::cvtColor(in, grey16, channels == 3 ? cv::COLOR_BGR2GRAY : cv::COLOR_BGRA2GRAY);
        grey16.convertTo(out, CV_8U, scale);
      }
      return;
    }
    case CV_32F:
    {
      if (channels == 1)
      {
        in.convertTo(out, CV_8U, 255.0);
      }
      else
      {
        cv::Mat grey;
        cv::cvtColor(in, grey, channels == 3 ? cv::COLOR_BGR2GRAY : cv::COLOR_BGRA2GRAY);
        grey.convertTo(out, CV_8U, 255.0);
      }
      return;
    }
    default:
      throw std::invalid_argument("cannot convert a " + matTypeName(in.type()) + " image to mono8");
  }
}

}  // namespace sl_camera
