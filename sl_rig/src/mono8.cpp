#include "sl_rig/mono8.h"

#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace sl_rig
{

std::string matTypeName(int type)
{
  static const char* const depths[] = { "8U", "8S", "16U", "16S", "32S", "32F", "64F", "16F" };
  const int depth = CV_MAT_DEPTH(type);
  return std::string(depths[depth]) + "C" + std::to_string(CV_MAT_CN(type));
}

namespace
{
// Luma of a 3- or 4-channel image (any depth cvtColor takes), into @p grey.
void luma(const cv::Mat& in, cv::Mat& grey, ChannelOrder order)
{
  const bool rgb = order == ChannelOrder::Rgb;
  if (in.channels() == 3)
    cv::cvtColor(in, grey, rgb ? cv::COLOR_RGB2GRAY : cv::COLOR_BGR2GRAY);
  else
    cv::cvtColor(in, grey, rgb ? cv::COLOR_RGBA2GRAY : cv::COLOR_BGRA2GRAY);
}

// Grey of @p in at its own depth: @p in itself for one channel, else its luma in @p buffer.
const cv::Mat& grey(const cv::Mat& in, cv::Mat& buffer, ChannelOrder order)
{
  if (in.channels() == 1)
    return in;
  luma(in, buffer, order);
  return buffer;
}
}  // namespace

void toMono8(const cv::Mat& in, cv::Mat& out, int significant_bits, ChannelOrder order)
{
  if (in.empty())
    throw std::invalid_argument("empty image");
  const int channels = in.channels();
  if (channels != 1 && channels != 3 && channels != 4)
    throw std::invalid_argument("cannot convert a " + matTypeName(in.type()) + " image to mono8");

  cv::Mat buffer;
  switch (in.depth())
  {
    case CV_8U:
      if (channels == 1)
        in.copyTo(out);
      else
        luma(in, out, order);
      return;
    case CV_16U:
    {
      if (significant_bits < 8 || significant_bits > 16)
        throw std::invalid_argument("significant bits must be in 8..16, got " + std::to_string(significant_bits));
      const double scale = 1.0 / static_cast<double>(1 << (significant_bits - 8));
      grey(in, buffer, order).convertTo(out, CV_8U, scale);
      return;
    }
    case CV_32F:
      grey(in, buffer, order).convertTo(out, CV_8U, 255.0);
      return;
    default:
      throw std::invalid_argument("cannot convert a " + matTypeName(in.type()) + " image to mono8");
  }
}

cv::Mat toMono8(const cv::Mat& image, const std::string& encoding, bool& converted, int significant_bits)
{
  converted = false;
  // The type each encoding names, and its channel order.
  int type = -1;
  ChannelOrder order = ChannelOrder::Bgr;
  if (encoding == "mono8" || encoding == "8UC1")
    type = CV_8UC1;
  else if (encoding == "mono16" || encoding == "16UC1")
    type = CV_16UC1;
  else if (encoding == "rgb8" || encoding == "bgr8")
    type = CV_8UC3;
  else if (encoding == "rgba8" || encoding == "bgra8")
    type = CV_8UC4;
  else
    throw std::invalid_argument("unsupported image encoding '" + encoding +
                                "' (use mono8; mono16, rgb8, bgr8, rgba8 and bgra8 are converted)");
  if (encoding == "rgb8" || encoding == "rgba8")
    order = ChannelOrder::Rgb;
  if (image.type() != type)
    throw std::invalid_argument("image claims " + encoding + " but is " + matTypeName(image.type()) + ", not " +
                                matTypeName(type));
  if (type == CV_8UC1)
    return image;
  converted = true;
  cv::Mat out;
  toMono8(image, out, significant_bits, order);
  return out;
}

}  // namespace sl_rig
