// The camera nodelet's messages: a captured frame as sensor_msgs/Image and its camera_info.
#pragma once

#include <opencv2/core.hpp>
#include <ros/time.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include "sl_camera/camera/capture_thread.h"

namespace sl_camera
{
/// The capture clock's @p t as a ROS time (times before the epoch become 0).
ros::Time toRosTime(CaptureClock::time_point t);

/// A new mono8 message holding a copy of @p mono (8-bit, one channel, any row padding).
sensor_msgs::ImagePtr toImageMsg(const cv::Mat& mono, const std_msgs::Header& header);

/// The camera_info of @p image: the calibration @p calibrated with the image's header, or the
/// image size alone when uncalibrated (size 0 x 0). @p size_differs: calibrated for another size.
sensor_msgs::CameraInfoPtr cameraInfoFor(const sensor_msgs::CameraInfo& calibrated, const sensor_msgs::Image& image,
                                         bool& size_differs);
}  // namespace sl_camera
