// The simulated camera's messages, filled from the core's results.
#pragma once

#include <string>

#include <opencv2/core.hpp>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sl_msgs/Collision.h>

#include "sl_rig/rig.h"
#include "sl_sim/collision.h"

namespace sl_sim
{
/// A message holding a copy of the continuous image @p image (the renderer's outputs are).
sensor_msgs::ImagePtr toImageMsg(const cv::Mat& image, const std::string& encoding, const std_msgs::Header& header);

/// The camera_info of the rig's camera @p camera in frame @p frame_id (no stamp).
sensor_msgs::CameraInfo toCameraInfo(const sl_projector::PinholeModel& camera, const std::string& frame_id);

/// The ground-truth collision @p report in frame @p frame_id at @p stamp.
sl_msgs::CollisionPtr toCollisionMsg(const CollisionReport& report, const ros::Time& stamp,
                                     const std::string& frame_id);
}  // namespace sl_sim
