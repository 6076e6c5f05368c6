// The camera nodelet: a real camera (V4L2, GenICam through Aravis) or a player of recorded images,
// published through image_transport with camera_info from camera_info_manager. Device I/O runs on
// the core's CaptureThread; this file only reads parameters and converts to ROS.
#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>

#include <boost/make_shared.hpp>
#include <camera_info_manager/camera_info_manager.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <diagnostic_updater/update_functions.h>
#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>

#include "sl_camera/camera/camera_config.h"
#include "sl_camera/camera/capture_thread.h"

namespace sl_camera
{

namespace
{
/// Everything the nodelet is configured with, read and validated in one place.
struct Params
{
  CameraConfig camera;
  std::string frame_id = "camera_optical_frame";
  std::string camera_name = "camera";
  std::string camera_info_url;
  bool player_ignores_settings = false;  ///< width/height/exposure/gain were set (not default) for the player
};

template <typename T>
T param(const ros::NodeHandle& pnh, const std::string& name, const T& fallback)
{
  T value;
  pnh.param(name, value, fallback);
  return value;
}

/// `device` may be given as a number in a launch file ("0" becomes an int parameter).
std::string deviceParam(const ros::NodeHandle& pnh)
{
  XmlRpc::XmlRpcValue v;
  if (!pnh.getParam("device", v))
    return std::string();
  switch (v.getType())
  {
    case XmlRpc::XmlRpcValue::TypeString:
      return static_cast<std::string>(v);
    case XmlRpc::XmlRpcValue::TypeInt:
      return std::to_string(static_cast<int>(v));
    default:
      throw std::invalid_argument("~device must be a string (path, index or camera id)");
  }
}

Params readParams(const ros::NodeHandle& pnh)
{
  Params p;
  CameraConfig& c = p.camera;
  try
  {
    c.backend = parseCameraBackend(param<std::string>(pnh, "backend", "v4l2"));
  }
  catch (const std::invalid_argument& e)
  {
    throw std::invalid_argument(std::string("~") + e.what());
  }
  c.device = deviceParam(pnh);
  c.settings.width = param(pnh, "width", c.settings.width);
  c.settings.height = param(pnh, "height", c.settings.height);
  c.settings.rate = param(pnh, "rate", c.settings.rate);
  c.settings.exposure = param(pnh, "exposure", c.settings.exposure);
  c.settings.gain = param(pnh, "gain", c.settings.gain);
  c.loop = param(pnh, "loop", c.loop);
  c.reconnect_max_backoff = param(pnh, "reconnect_max_backoff", c.reconnect_max_backoff);
  try
  {
    c.validate();
  }
  catch (const std::invalid_argument& e)
  {
    throw std::invalid_argument(std::string("~") + e.what());
  }
  p.player_ignores_settings = c.backend == CameraBackend::Player &&
                              (c.settings.width != 0 || c.settings.height != 0 || c.settings.exposure > 0.0 ||
                               c.settings.gain >= 0.0);

  p.frame_id = param(pnh, "frame_id", p.frame_id);
  if (p.frame_id.empty())
    throw std::invalid_argument("~frame_id must not be empty");
  p.camera_name = param(pnh, "camera_name", p.camera_name);
  if (p.camera_name.empty())
    throw std::invalid_argument("~camera_name must not be empty");
  for (char ch : p.camera_name)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '_')
      throw std::invalid_argument("~camera_name must contain only letters, digits and '_', got '" + p.camera_name + "'");
  p.camera_info_url = param(pnh, "camera_info_url", p.camera_info_url);
  const std::string& url = p.camera_info_url;
  if (!url.empty() && url.rfind("file://", 0) != 0 && url.rfind("package://", 0) != 0)
    throw std::invalid_argument("~camera_info_url must be empty, file:///path.yaml or package://pkg/path.yaml, got '" +
                                url + "'");
  return p;
}

ros::Time toRosTime(CaptureClock::time_point t)
{
  const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
  ros::Time stamp;
  stamp.fromNSec(static_cast<uint64_t>(ns > 0 ? ns : 0));
  return stamp;
}
}  // namespace

/**
 * Publishes a camera's images (`image_raw`, mono8) with `camera_info` through an image_transport
 * camera publisher. Back-ends: V4L2, GenICam (Aravis), and a player for recorded images or video.
 * The device is opened and read on a worker thread; a missing or lost device is reported and
 * retried with a back-off, without a restart. Diagnostics: state, frame rate, dropped frames,
 * reconnects, last error.
 */
class CameraNodelet : public nodelet::Nodelet
{
public:
  ~CameraNodelet() override
  {
    diagnostics_timer_.stop();
    if (capture_)
      capture_->stop();
  }

private:
  void onInit() override
  {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    try
    {
      params_ = readParams(pnh);
    }
    catch (const std::exception& e)
    {
      NODELET_FATAL("invalid parameter: %s", e.what());
      throw;
    }
    const CameraConfig& config = params_.camera;
    device_ = config.resolvedDevice();
    if (params_.player_ignores_settings)
      NODELET_WARN("~width, ~height, ~exposure and ~gain have no effect with backend player (leave them at 0, 0, 0, -1)");

    // Calibration (a file read; quick). Without one, camera_info carries the image size only.
    camera_info_.reset(new camera_info_manager::CameraInfoManager(nh, params_.camera_name, params_.camera_info_url));
    if (!params_.camera_info_url.empty())
      camera_info_->loadCameraInfo(params_.camera_info_url);
    if (!camera_info_->isCalibrated())
    {
      const std::string why = params_.camera_info_url.empty() ?
                                  "~camera_info_url is empty and there is no ~/.ros/camera_info/" +
                                      params_.camera_name + ".yaml" :
                                  "~camera_info_url '" + params_.camera_info_url + "' could not be loaded";
      NODELET_WARN("camera '%s' is not calibrated (%s): publishing camera_info with the image size only; calibrate "
                   "with camera_calibration, which stores the result through set_camera_info",
                   params_.camera_name.c_str(), why.c_str());
    }

    image_transport_.reset(new image_transport::ImageTransport(nh));
    publisher_ = image_transport_->advertiseCamera("image_raw", 1);

    min_rate_ = max_rate_ = config.settings.rate;
    updater_.reset(new diagnostic_updater::Updater(nh, pnh, getName()));
    updater_->setHardwareID(std::string(cameraBackendName(config.backend)) + ":" +
                            (device_.empty() ? std::string("first camera") : device_));
    updater_->add("capture", this, &CameraNodelet::diagnoseCapture);
    frequency_.reset(new diagnostic_updater::FrequencyStatus(
        diagnostic_updater::FrequencyStatusParam(&min_rate_, &max_rate_, 0.1, 10), "frame rate"));
    updater_->add("frame rate", this, &CameraNodelet::diagnoseRate);
    diagnostics_timer_ = nh.createWallTimer(ros::WallDuration(0.25), [this](const ros::WallTimerEvent&) {
      const double rate = nominal_rate_.load();
      if (rate > 0.0)
        min_rate_ = max_rate_ = rate;  // the rate the device actually runs at
      updater_->update();
    });

    // Device I/O happens on the capture thread only: onInit returns at once.
    capture_.reset(new CaptureThread(
        createFrameSource(config), config.captureOptions(), [this](const Frame& frame) { publish(frame); },
        [this](const CaptureEvent& event) { log(event); }));
    NODELET_INFO("camera: %s, publishing %s and %s in frame '%s'", capture_->sourceDescription().c_str(),
                 publisher_.getTopic().c_str(), publisher_.getInfoTopic().c_str(), params_.frame_id.c_str());
    capture_->start();
  }

  /// On the capture thread: one frame to ROS.
  void publish(const Frame& frame)
  {
    frequency_->tick();
    if (publisher_.getNumSubscribers() == 0)
      return;
    const cv::Mat& m = frame.image;
    // A new message per frame: subscribers in the same process keep a pointer to it.
    auto image = boost::make_shared<sensor_msgs::Image>();
    image->header.stamp = ros::Time::isSimTime() ? ros::Time::now() : toRosTime(frame.stamp);
    image->header.frame_id = params_.frame_id;
    image->height = static_cast<uint32_t>(m.rows);
    image->width = static_cast<uint32_t>(m.cols);
    image->encoding = sensor_msgs::image_encodings::MONO8;
    image->is_bigendian = 0;
    image->step = static_cast<uint32_t>(m.cols);
    image->data.resize(static_cast<size_t>(m.rows) * m.cols);
    for (int r = 0; r < m.rows; ++r)
      std::copy(m.ptr<uint8_t>(r), m.ptr<uint8_t>(r) + m.cols, image->data.begin() + static_cast<size_t>(r) * m.cols);

    auto info = boost::make_shared<sensor_msgs::CameraInfo>(camera_info_->getCameraInfo());
    if (info->width == 0 && info->height == 0)
    {
      info->width = image->width;  // uncalibrated: the size is all we know
      info->height = image->height;
    }
    else if (info->width != image->width || info->height != image->height)
    {
      NODELET_WARN_THROTTLE(30.0, "calibration is for %u x %u px but the camera delivers %u x %u px", info->width,
                            info->height, image->width, image->height);
    }
    info->header = image->header;
    publisher_.publish(image, info);
  }

  /// On the capture thread: state changes and errors to the log (diagnostics show them too).
  void log(const CaptureEvent& event)
  {
    switch (event.type)
    {
      case CaptureEvent::Type::StateChanged:
        if (event.state == CaptureState::Streaming || event.state == CaptureState::Finished)
        {
          std::lock_guard<std::mutex> lock(log_mutex_);
          if (!last_logged_error_.empty())
            NODELET_INFO("recovered: %s", event.message.c_str());
          else
            NODELET_INFO("%s", event.message.c_str());
          last_logged_error_.clear();
        }
        else
        {
          NODELET_DEBUG("%s", event.message.c_str());
        }
        if (event.state == CaptureState::Streaming)
          nominal_rate_ = capture_ ? capture_->stats().nominal_rate : 0.0;
        break;
      case CaptureEvent::Type::Error:
      {
        // A new error at once; the same error again at most once a minute (diagnostics carry it).
        std::lock_guard<std::mutex> lock(log_mutex_);
        const ros::WallTime now = ros::WallTime::now();
        if (event.message != last_logged_error_ || (now - last_error_time_).toSec() > 60.0)
        {
          NODELET_ERROR("%s; retrying in %.2g s, then at least once every %.2g s", event.message.c_str(), event.retry_in,
                        params_.camera.reconnect_max_backoff);
          last_logged_error_ = event.message;
          last_error_time_ = now;
        }
        break;
      }
      case CaptureEvent::Type::FrameError:
        NODELET_WARN_THROTTLE(5.0, "dropped a frame: %s", event.message.c_str());
        break;
      case CaptureEvent::Type::Warning:
        NODELET_WARN("%s", event.message.c_str());
        break;
    }
  }

  void diagnoseCapture(diagnostic_updater::DiagnosticStatusWrapper& stat)
  {
    const CaptureStats s = capture_ ? capture_->stats() : CaptureStats();
    using diagnostic_msgs::DiagnosticStatus;
    switch (s.state)
    {
      case CaptureState::Streaming:
        stat.summary(DiagnosticStatus::OK, "streaming");
        break;
      case CaptureState::Finished:
        stat.summary(DiagnosticStatus::OK, "end of playback");
        break;
      case CaptureState::Opening:
        if (s.open_failures > 0 || !s.last_error.empty())
          stat.summaryf(DiagnosticStatus::ERROR, "opening again after: %s", s.last_error.c_str());
        else
          stat.summary(DiagnosticStatus::OK, "opening");
        break;
      case CaptureState::Reconnecting:
        stat.summaryf(DiagnosticStatus::ERROR, "no camera: %s", s.last_error.c_str());
        break;
      case CaptureState::Idle:
        stat.summary(DiagnosticStatus::WARN, "stopped");
        break;
    }
    stat.add("state", captureStateName(s.state));
    stat.add("backend", cameraBackendName(params_.camera.backend));
    stat.add("device", device_.empty() ? std::string("(first camera)") : device_);
    stat.add("frames", s.frames);
    stat.add("dropped frames", s.dropped);
    stat.add("reconnects", s.reconnects);
    stat.add("failed opens", s.open_failures);
    stat.add("device rate (Hz)", s.nominal_rate);
    stat.add("last error", s.last_error.empty() ? std::string("none") : s.last_error);
  }

  void diagnoseRate(diagnostic_updater::DiagnosticStatusWrapper& stat)
  {
    frequency_->run(stat);
    if (capture_ && capture_->state() == CaptureState::Finished)
      stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "end of playback, no more frames");
  }

  Params params_;
  std::string device_;
  std::shared_ptr<camera_info_manager::CameraInfoManager> camera_info_;
  std::shared_ptr<image_transport::ImageTransport> image_transport_;
  image_transport::CameraPublisher publisher_;
  std::shared_ptr<diagnostic_updater::Updater> updater_;
  std::shared_ptr<diagnostic_updater::FrequencyStatus> frequency_;
  double min_rate_ = 0.0, max_rate_ = 0.0;  // read by frequency_ on the timer thread only
  std::atomic<double> nominal_rate_{ 0.0 };
  ros::WallTimer diagnostics_timer_;
  std::mutex log_mutex_;
  std::string last_logged_error_;
  ros::WallTime last_error_time_;
  std::unique_ptr<CaptureThread> capture_;  // last: stopped first, before what its callbacks use
};

}  // namespace sl_camera

PLUGINLIB_EXPORT_CLASS(sl_camera::CameraNodelet, nodelet::Nodelet)
