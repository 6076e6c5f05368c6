#include "images.h"

#include <cv_bridge/cv_bridge.h>

#include "sl_rig/mono8.h"

namespace sl_calibration
{
cv::Mat toMono8Copy(const sensor_msgs::ImageConstPtr& msg)
{
  bool converted = false;
  const cv_bridge::CvImageConstPtr cv = cv_bridge::toCvShare(msg);
  return sl_rig::toMono8(cv->image, msg->encoding, converted).clone();
}
}  // namespace sl_calibration
