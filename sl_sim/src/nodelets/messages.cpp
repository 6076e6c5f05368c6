#include "messages.h"

namespace sl_sim
{
sensor_msgs::ImagePtr toImageMsg(const cv::Mat& image, const std::string& encoding, const std_msgs::Header& header)
{
  sensor_msgs::ImagePtr msg(new sensor_msgs::Image);
  msg->header = header;
  msg->height = static_cast<uint32_t>(image.rows);
  msg->width = static_cast<uint32_t>(image.cols);
  msg->encoding = encoding;
  msg->is_bigendian = 0;
  msg->step = static_cast<uint32_t>(image.cols * image.elemSize());
  msg->data.assign(image.data, image.data + image.total() * image.elemSize());
  return msg;
}

sensor_msgs::CameraInfo toCameraInfo(const sl_projector::PinholeModel& c, const std::string& frame_id)
{
  sensor_msgs::CameraInfo info;
  info.header.frame_id = frame_id;
  info.width = static_cast<uint32_t>(c.width);
  info.height = static_cast<uint32_t>(c.height);
  info.distortion_model = "plumb_bob";
  info.D.assign(c.dist.begin(), c.dist.end());
  info.K = { c.fx, 0.0, c.cx, 0.0, c.fy, c.cy, 0.0, 0.0, 1.0 };
  info.R = { 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0 };
  info.P = { c.fx, 0.0, c.cx, 0.0, 0.0, c.fy, c.cy, 0.0, 0.0, 0.0, 1.0, 0.0 };
  return info;
}

sl_msgs::CollisionPtr toCollisionMsg(const CollisionReport& report, const ros::Time& stamp, const std::string& frame_id)
{
  sl_msgs::CollisionPtr msg(new sl_msgs::Collision);
  msg->header.stamp = stamp;
  msg->header.frame_id = frame_id;
  msg->colliding = report.colliding;
  msg->objects = report.names;
  msg->min_clearance = report.min_clearance;
  msg->nearest_object = report.nearest_name;
  return msg;
}
}  // namespace sl_sim
