// The calibration nodelet's image conversion.
#pragma once

#include <opencv2/core.hpp>
#include <sensor_msgs/Image.h>

namespace sl_calibration
{
/// An 8-bit grey copy of @p msg (sl_rig::toMono8). @throws std::exception for an encoding it cannot convert.
cv::Mat toMono8Copy(const sensor_msgs::ImageConstPtr& msg);
}  // namespace sl_calibration
