#include "camera_image.h"

#include <algorithm>
#include <chrono>

#include <boost/make_shared.hpp>
#include <sensor_msgs/image_encodings.h>

namespace sl_camera
{
ros::Time toRosTime(CaptureClock::time_point t)
{
  const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
  ros::Time stamp;
  stamp.fromNSec(static_cast<uint64_t>(ns > 0 ? ns : 0));
  return stamp;
}

sensor_msgs::ImagePtr toImageMsg(const cv::Mat& m, const std_msgs::Header& header)
{
  // A new message per frame: subscribers in the same process keep a pointer to it.
  auto image = boost::make_shared<sensor_msgs::Image>();
  image->header = header;
  image->height = static_cast<uint32_t>(m.rows);
  image->width = static_cast<uint32_t>(m.cols);
  image->encoding = sensor_msgs::image_encodings::MONO8;
  image->is_bigendian = 0;
  image->step = static_cast<uint32_t>(m.cols);
  image->data.resize(static_cast<size_t>(m.rows) * m.cols);
  for (int r = 0; r < m.rows; ++r)
    std::copy(m.ptr<uint8_t>(r), m.ptr<uint8_t>(r) + m.cols, image->data.begin() + static_cast<size_t>(r) * m.cols);
  return image;
}

sensor_msgs::CameraInfoPtr cameraInfoFor(const sensor_msgs::CameraInfo& calibrated, const sensor_msgs::Image& image,
                                         bool& size_differs)
{
  auto info = boost::make_shared<sensor_msgs::CameraInfo>(calibrated);
  size_differs = false;
  if (info->width == 0 && info->height == 0)
  {
    info->width = image.width;  // uncalibrated: the size is all we know
    info->height = image.height;
  }
  else
  {
    size_differs = info->width != image.width || info->height != image.height;
  }
  info->header = image.header;
  return info;
}
}  // namespace sl_camera
