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
#include "sl_camera/camera/player_source.h"
#include "sl_camera/camera/start_gate.h"
#include "sl_camera/camera/unreadable_files.h"
#include "sl_rig/rig.h"
#include "sl_params/params.h"

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
  std::string rig_file;                  ///< rig whose camera image size the camera must deliver ("": none)
  bool player_ignores_settings = false;  ///< width/height/exposure/gain were set (not default) for the player
  bool offsets_ignored = false;          ///< offset_x/offset_y set for a back-end without region offsets
};

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

/// `socket_buffer` and `packet_size`: "auto" (or 0) or a number of bytes.
int autoOrBytesParam(const ros::NodeHandle& pnh, const std::string& name)
{
  XmlRpc::XmlRpcValue v;
  if (!pnh.getParam(name, v))
    return 0;
  if (v.getType() == XmlRpc::XmlRpcValue::TypeInt)
    return static_cast<int>(v);
  if (v.getType() == XmlRpc::XmlRpcValue::TypeString)
  {
    const std::string text = static_cast<std::string>(v);
    if (text == "auto")
      return 0;
    try
    {
      size_t used = 0;
      const long bytes = std::stol(text, &used);
      if (used == text.size() && bytes >= 0 && bytes <= (1L << 30))
        return static_cast<int>(bytes);
    }
    catch (const std::exception&)
    {
      // reported below
    }
  }
  throw std::invalid_argument("~" + name + " must be auto or a number of bytes");
}

Params readParams(const ros::NodeHandle& pnh)
{
  Params p;
  CameraConfig& c = p.camera;
  try
  {
    c.backend = parseCameraBackend(sl_params::read<std::string>(pnh, "backend", "v4l2"));
  }
  catch (const std::invalid_argument& e)
  {
    throw std::invalid_argument(std::string("~") + e.what());
  }
  c.device = deviceParam(pnh);
  c.settings.width = sl_params::read(pnh, "width", c.settings.width);
  c.settings.height = sl_params::read(pnh, "height", c.settings.height);
  c.settings.rate = sl_params::read(pnh, "rate", c.settings.rate);
  c.settings.exposure = sl_params::read(pnh, "exposure", c.settings.exposure);
  c.settings.gain = sl_params::read(pnh, "gain", c.settings.gain);
  c.loop = sl_params::read(pnh, "loop", c.loop);
  c.settings.offset_x = sl_params::read(pnh, "offset_x", c.settings.offset_x);
  c.settings.offset_y = sl_params::read(pnh, "offset_y", c.settings.offset_y);
  c.reconnect_max_backoff = sl_params::read(pnh, "reconnect_max_backoff", c.reconnect_max_backoff);
  c.stall_timeout = sl_params::read(pnh, "stall_timeout", c.stall_timeout);
  try
  {
    c.aravis.packet_socket = parsePacketSocketMode(sl_params::read<std::string>(pnh, "packet_socket", "auto"));
  }
  catch (const std::invalid_argument& e)
  {
    throw std::invalid_argument(std::string("~") + e.what());
  }
  c.aravis.socket_buffer = autoOrBytesParam(pnh, "socket_buffer");
  c.aravis.packet_size = autoOrBytesParam(pnh, "packet_size");
  // One name for the rig file across the nodelets; ~rig_file is the deprecated former one.
  sl_params::readIfSetRenamed(pnh, "calibration_file", "rig_file", p.rig_file);
  try
  {
    c.validate();
    if (!p.rig_file.empty())
    {
      // The decoder triangulates with this rig: a camera image of another size cannot be decoded.
      sl_projector::Rig rig;
      try
      {
        rig = sl_projector::loadRig(p.rig_file);
      }
      catch (const std::exception& e)
      {
        throw std::invalid_argument(std::string("calibration_file: ") + e.what());
      }
      if (c.backend != CameraBackend::Player)
        c.applyRigSize(rig.camera.width, rig.camera.height, p.rig_file);
    }
  }
  catch (const std::invalid_argument& e)
  {
    throw std::invalid_argument(std::string("~") + e.what());
  }
  p.offsets_ignored = c.backend != CameraBackend::Aravis && (c.settings.offset_x >= 0 || c.settings.offset_y >= 0);
  p.player_ignores_settings =
      c.backend == CameraBackend::Player &&
      (c.settings.width != 0 || c.settings.height != 0 || c.settings.exposure > 0.0 || c.settings.gain >= 0.0);

  p.frame_id = sl_params::read(pnh, "frame_id", p.frame_id);
  if (p.frame_id.empty())
    throw std::invalid_argument("~frame_id must not be empty");
  p.camera_name = sl_params::read(pnh, "camera_name", p.camera_name);
  if (p.camera_name.empty())
    throw std::invalid_argument("~camera_name must not be empty");
  for (char ch : p.camera_name)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '_')
      throw std::invalid_argument("~camera_name must contain only letters, digits and '_', got '" + p.camera_name +
                                  "'");
  p.camera_info_url = sl_params::read(pnh, "camera_info_url", p.camera_info_url);
  const std::string& url = p.camera_info_url;
  if (!url.empty() && url.rfind("file://", 0) != 0 && url.rfind("package://", 0) != 0)
    throw std::invalid_argument("~camera_info_url must be empty, file:///path.yaml or package://pkg/path.yaml, got '" +
                                url + "'");
  return p;
}

/// A subscriber of image_raw alone (no camera_info) starts a held player after this long, s.
constexpr double kImageOnlyStartGrace = 0.5;
/// Unreadable files: names shown in the diagnostics, and the shortest interval between log lines.
constexpr std::size_t kUnreadableNamesShown = 5;
constexpr double kUnreadableLogInterval = 5.0;

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
 *
 * The player starts at once (listing the folder, so a missing one is reported) but holds frame 0
 * until the first subscriber is connected (lazy start, as image_pipeline subscribes lazily), then
 * plays on whether or not anyone listens: a subscriber that waits for the player gets frame 0.
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
      NODELET_WARN(
          "~width, ~height, ~exposure and ~gain have no effect with backend player (leave them at 0, 0, 0, -1)");
    if (params_.offsets_ignored)
      NODELET_WARN("~offset_x and ~offset_y have an effect with backend aravis only (leave them at -1)");
    if (!params_.rig_file.empty())
    {
      expected_width_ = config.backend == CameraBackend::Player ? 0 : config.settings.width;
      expected_height_ = config.backend == CameraBackend::Player ? 0 : config.settings.height;
    }

    // Calibration (a file read; quick). Without one, camera_info carries the image size only.
    camera_info_.reset(new camera_info_manager::CameraInfoManager(nh, params_.camera_name, params_.camera_info_url));
    if (!params_.camera_info_url.empty())
      camera_info_->loadCameraInfo(params_.camera_info_url);
    if (!camera_info_->isCalibrated())
    {
      const std::string why =
          params_.camera_info_url.empty()
              ? "~camera_info_url is empty and there is no ~/.ros/camera_info/" + params_.camera_name + ".yaml"
              : "~camera_info_url '" + params_.camera_info_url + "' could not be loaded";
      NODELET_WARN(
          "camera '%s' is not calibrated (%s): publishing camera_info with the image size only; calibrate "
          "with camera_calibration, which stores the result through set_camera_info",
          params_.camera_name.c_str(), why.c_str());
    }

    // The source exists before the topics are advertised: the player's start gate must be in place
    // when the first subscriber connects.
    std::unique_ptr<FrameSource> source = createFrameSource(config);
    if (auto* player = dynamic_cast<PlayerSource*>(source.get()))
    {
      start_gate_ = std::make_shared<StartGate>();
      player->setStartGate(start_gate_);
      unreadable_ = player->unreadableFiles();
    }

    image_transport_.reset(new image_transport::ImageTransport(nh));
    // Connection counts for the player's start (any transport counts as an image subscriber).
    auto image_connect = [this](const image_transport::SingleSubscriberPublisher&)
    {
      ++image_subscribers_;
      maybeStartPlayback();
    };
    auto image_disconnect = [this](const image_transport::SingleSubscriberPublisher&) { --image_subscribers_; };
    auto info_connect = [this](const ros::SingleSubscriberPublisher&)
    {
      ++info_subscribers_;
      maybeStartPlayback();
    };
    auto info_disconnect = [this](const ros::SingleSubscriberPublisher&) { --info_subscribers_; };
    publisher_ = image_transport_->advertiseCamera("image_raw", 1, image_connect, image_disconnect, info_connect,
                                                   info_disconnect);

    min_rate_ = max_rate_ = config.settings.rate;
    updater_.reset(new diagnostic_updater::Updater(nh, pnh, getName()));
    updater_->setHardwareID(std::string(cameraBackendName(config.backend)) + ":" +
                            (device_.empty() ? std::string("first camera") : device_));
    updater_->add("capture", this, &CameraNodelet::diagnoseCapture);
    frequency_.reset(new diagnostic_updater::FrequencyStatus(
        diagnostic_updater::FrequencyStatusParam(&min_rate_, &max_rate_, 0.1, 10), "frame rate"));
    updater_->add("frame rate", this, &CameraNodelet::diagnoseRate);
    diagnostics_timer_ = nh.createWallTimer(
        ros::WallDuration(0.25),
        [this](const ros::WallTimerEvent&)
        {
          const double rate = nominal_rate_.load();
          if (rate > 0.0)
            min_rate_ = max_rate_ = rate;  // the rate the device actually runs at
          maybeStartPlayback();            // a subscriber of the image alone starts the player after a grace time
          logUnreadableFiles();
          // A camera that stops (or starts) delivering is published at once, not at the next diagnostic_period.
          const bool failing = captureFailing();
          if (failing != published_failing_)
          {
            published_failing_ = failing;
            updater_->force_update();
          }
          else
          {
            updater_->update();
          }
        });

    // Device I/O happens on the capture thread only: onInit returns at once.
    capture_.reset(new CaptureThread(
        std::move(source), config.captureOptions(), [this](const Frame& frame) { publish(frame); },
        [this](const CaptureEvent& event) { log(event); }));
    NODELET_INFO("camera: %s, publishing %s and %s in frame '%s'", capture_->sourceDescription().c_str(),
                 publisher_.getTopic().c_str(), publisher_.getInfoTopic().c_str(), params_.frame_id.c_str());
    capture_->start();
  }

  /// Opens the player's start gate once a subscriber is there (callback and timer threads).
  void maybeStartPlayback()
  {
    if (!start_gate_ || start_gate_->isOpen())
      return;
    std::lock_guard<std::mutex> lock(start_mutex_);
    const int images = image_subscribers_.load();
    const ros::WallTime now = ros::WallTime::now();
    if (images <= 0)
      image_subscribed_since_ = ros::WallTime();
    else if (image_subscribed_since_.isZero())
      image_subscribed_since_ = now;
    const double image_for = images > 0 ? (now - image_subscribed_since_).toSec() : 0.0;
    if (!start_gate_->isOpen() &&
        shouldStartPlayback(images, info_subscribers_.load(), image_for, kImageOnlyStartGrace))
    {
      start_gate_->open();
      NODELET_INFO("a subscriber is connected: starting playback with frame 0");
    }
  }

  /// Timer thread: names the files the player could not read, new ones at most every few seconds.
  void logUnreadableFiles()
  {
    if (!unreadable_)
      return;
    const ros::WallTime now = ros::WallTime::now();
    if (!last_unreadable_log_.isZero() && (now - last_unreadable_log_).toSec() < kUnreadableLogInterval)
      return;
    const std::vector<std::string> fresh = unreadable_->from(unreadable_logged_);
    if (fresh.empty())
      return;
    unreadable_logged_ += fresh.size();
    last_unreadable_log_ = now;
    NODELET_WARN("player: skipping %zu unreadable file%s (%zu in all, see diagnostics): %s", fresh.size(),
                 fresh.size() == 1 ? "" : "s", unreadable_logged_, UnreadableFiles::join(fresh).c_str());
  }

  /// On the capture thread: one frame to ROS.
  void publish(const Frame& frame)
  {
    const cv::Mat& m = frame.image;
    if (expected_width_ > 0 && (m.cols != expected_width_ || m.rows != expected_height_))
    {
      // Thrown into the capture thread, which counts and reports it as an unusable frame.
      throw std::runtime_error("the camera delivers " + std::to_string(m.cols) + " x " + std::to_string(m.rows) +
                               " px but the rig file " + params_.rig_file + " is for " +
                               std::to_string(expected_width_) + " x " + std::to_string(expected_height_) + " px");
    }
    frequency_->tick();
    if (publisher_.getNumSubscribers() == 0)
      return;
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
      case CaptureEvent::Type::FirstFrame:
      {
        // Frames really arrive: only now is it a recovery, and only now may the same error be logged again.
        std::lock_guard<std::mutex> lock(log_mutex_);
        if (!last_logged_error_.empty())
          NODELET_INFO("recovered: %s", event.message.c_str());
        else
          NODELET_INFO("%s", event.message.c_str());
        last_logged_error_.clear();
        break;
      }
      case CaptureEvent::Type::StateChanged:
        if (event.state == CaptureState::Finished)
          NODELET_INFO("%s", event.message.c_str());
        else
          NODELET_DEBUG("%s", event.message.c_str());
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
          NODELET_ERROR("%s; retrying in %.2g s, then at least once every %.2g s", event.message.c_str(),
                        event.retry_in, params_.camera.reconnect_max_backoff);
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

  /// True when the capture diagnostic is an error: no device, or no frames.
  bool captureFailing() const
  {
    const CaptureStats s = capture_ ? capture_->stats() : CaptureStats();
    return s.state == CaptureState::Reconnecting || (s.state == CaptureState::Streaming && s.overdue) ||
           (s.state == CaptureState::Opening && (s.open_failures > 0 || !s.last_error.empty()));
  }

  void diagnoseCapture(diagnostic_updater::DiagnosticStatusWrapper& stat)
  {
    const CaptureStats s = capture_ ? capture_->stats() : CaptureStats();
    using diagnostic_msgs::DiagnosticStatus;
    switch (s.state)
    {
      case CaptureState::Streaming:
        // Open is not enough: without frames the camera is of no use (ERROR, not OK).
        if (s.waiting)
          stat.summary(DiagnosticStatus::OK, "waiting for a subscriber to start playback");
        else if (s.overdue && s.have_frame)
          stat.summaryf(DiagnosticStatus::ERROR, "no frame for %.1f s", s.since_frame);
        else if (s.overdue)
          stat.summaryf(DiagnosticStatus::ERROR, "opened, but no frame for %.1f s", s.since_frame);
        else if (!s.have_frame)
          stat.summary(DiagnosticStatus::WARN, "opened, waiting for the first frame");
        else
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
    if (s.state == CaptureState::Streaming)
      stat.addf("since last frame (s)", "%.2f", s.since_frame);
    if (params_.camera.backend == CameraBackend::Aravis)
    {
      const AravisOptions& a = params_.camera.aravis;
      stat.add("packet socket", packetSocketModeName(a.packet_socket));
      stat.add("socket buffer (bytes)", a.socket_buffer > 0 ? std::to_string(a.socket_buffer) : std::string("auto"));
      stat.add("packet size (bytes)", a.packet_size > 0 ? std::to_string(a.packet_size) : std::string("auto"));
    }
    if (unreadable_)
    {
      // The names (the first few) are here as well as in the log, so they can be found later.
      const std::size_t n = unreadable_->count();
      stat.add("unreadable files", unreadable_->summary(kUnreadableNamesShown));
      stat.add("unreadable file count", n);
      if (n > 0)
      {
        const std::string message = stat.message;
        const unsigned char warn = DiagnosticStatus::WARN;
        const unsigned char level = stat.level > warn ? stat.level : warn;
        stat.summaryf(level, "%s; %zu unreadable file%s skipped", message.c_str(), n, n == 1 ? "" : "s");
      }
    }
  }

  void diagnoseRate(diagnostic_updater::DiagnosticStatusWrapper& stat)
  {
    frequency_->run(stat);
    const CaptureStats s = capture_ ? capture_->stats() : CaptureStats();
    if (s.state == CaptureState::Finished)
      stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "end of playback, no more frames");
    else if (s.state == CaptureState::Streaming && s.waiting)
      stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "waiting for a subscriber to start playback");
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
  int expected_width_ = 0, expected_height_ = 0;  ///< the rig's image size (0: no rig given)
  bool published_failing_ = false;                ///< timer thread only
  // Player only (null otherwise): the gate that holds frame 0 until a subscriber is there, and the
  // files it could not read.
  std::shared_ptr<StartGate> start_gate_;
  std::shared_ptr<const UnreadableFiles> unreadable_;
  std::atomic<int> image_subscribers_{ 0 };
  std::atomic<int> info_subscribers_{ 0 };
  std::mutex start_mutex_;
  ros::WallTime image_subscribed_since_;    ///< guarded by start_mutex_
  std::size_t unreadable_logged_ = 0;       ///< timer thread only: names logged so far
  ros::WallTime last_unreadable_log_;       ///< timer thread only
  std::unique_ptr<CaptureThread> capture_;  // last: stopped first, before what its callbacks use
};

}  // namespace sl_camera

PLUGINLIB_EXPORT_CLASS(sl_camera::CameraNodelet, nodelet::Nodelet)
