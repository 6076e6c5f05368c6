#include "sl_camera/camera/start_gate.h"

namespace sl_camera
{

void StartGate::open()
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    open_ = true;
  }
  opened_.notify_all();
}

bool StartGate::isOpen() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return open_;
}

bool StartGate::waitFor(std::chrono::milliseconds timeout) const
{
  std::unique_lock<std::mutex> lock(mutex_);
  return opened_.wait_for(lock, timeout, [this] { return open_; });
}

bool shouldStartPlayback(int image_subscribers, int info_subscribers, double image_only_for, double image_only_grace)
{
  if (image_subscribers <= 0)
    return false;  // camera_info alone is no use without images
  return info_subscribers > 0 || image_only_for >= image_only_grace;
}

bool PlaybackStarter::update(int image_subscribers, int info_subscribers, double now)
{
  if (image_subscribers <= 0)
    image_subscribed_ = false;
  else if (!image_subscribed_)
  {
    image_subscribed_ = true;
    image_subscribed_since_ = now;
  }
  const double image_for = image_subscribers > 0 ? now - image_subscribed_since_ : 0.0;
  return shouldStartPlayback(image_subscribers, info_subscribers, image_for, image_only_grace_);
}

}  // namespace sl_camera
