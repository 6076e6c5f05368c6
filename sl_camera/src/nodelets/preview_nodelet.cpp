// The preview nodelet: `preview` is a shrunk, rate-limited copy of `image` (ImagePreview), for rviz
// on a workstation over a slow link. Subscribes `image` only while `preview` has a subscriber.
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>

#include <cv_bridge/cv_bridge.h>
#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>

#include "sl_camera/preview/image_preview.h"
#include "sl_params/params.h"

namespace sl_camera
{

class PreviewNodelet : public nodelet::Nodelet
{
private:
  void onInit() override
  {
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    PreviewConfig config;
    try
    {
      config.scale = sl_params::read(pnh, "scale", config.scale);
      config.rate = sl_params::read(pnh, "rate", config.rate);
      try
      {
        config.validate();
      }
      catch (const std::invalid_argument& e)
      {
        throw std::invalid_argument(std::string("~") + e.what());
      }
    }
    catch (const std::exception& e)
    {
      NODELET_FATAL("invalid parameter: %s", e.what());
      throw;
    }
    preview_.reset(new ImagePreview(config));
    it_.reset(new image_transport::ImageTransport(getNodeHandle()));
    const image_transport::SubscriberStatusCallback connect = [this](const image_transport::SingleSubscriberPublisher&)
    { updateSubscription(); };
    std::lock_guard<std::mutex> lock(mutex_);
    pub_ = it_->advertise("preview", 1, connect, connect);
    NODELET_INFO("preview of %s on %s: 1/%d size, at most %.1f Hz, while someone subscribes",
                 getNodeHandle().resolveName("image").c_str(), pub_.getTopic().c_str(), config.scale, config.rate);
  }

  void updateSubscription()
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (pub_.getNumSubscribers() > 0 && !sub_)
      sub_ = it_->subscribe("image", 1, &PreviewNodelet::onImage, this);
    else if (pub_.getNumSubscribers() == 0 && sub_)
      sub_.shutdown();
  }

  void onImage(const sensor_msgs::ImageConstPtr& msg)
  {
    if (!preview_->due(ros::Time::now().toSec()))
      return;
    if (sensor_msgs::image_encodings::isBayer(msg->encoding))
    {
      NODELET_ERROR_THROTTLE(5.0, "cannot shrink %s images (averaging would mix the colours of the mosaic)",
                             msg->encoding.c_str());
      return;
    }
    try
    {
      cv_bridge::CvImage out(msg->header, msg->encoding);
      preview_->shrink(cv_bridge::toCvShare(msg)->image, out.image);
      pub_.publish(out.toImageMsg());
    }
    catch (const std::exception& e)  // cv_bridge::Exception, cv::Exception, std::invalid_argument
    {
      NODELET_ERROR_THROTTLE(5.0, "dropping %s image: %s", msg->encoding.c_str(), e.what());
    }
  }

  std::unique_ptr<ImagePreview> preview_;
  std::unique_ptr<image_transport::ImageTransport> it_;
  image_transport::Publisher pub_;
  image_transport::Subscriber sub_;
  std::mutex mutex_;
};

}  // namespace sl_camera

PLUGINLIB_EXPORT_CLASS(sl_camera::PreviewNodelet, nodelet::Nodelet)
