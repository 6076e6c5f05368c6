// The camera nodelet: a real camera (V4L2, GenICam through Aravis) or a player of recorded images,
// published through image_transport with camera_info from camera_info_manager. Device I/O runs on
// the core's CaptureThread; this file only reads parameters and converts to ROS.
#include <atomic>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include <camera_info_manager/camera_info_manager.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <diagnostic_updater/update_functions.h>
#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>

#include "camera_diagnostics.h"
#include "camera_image.h"
#include "camera_params.h"
#include "sl_camera/camera/camera_config.h"
#include "sl_camera/camera/capture_status.h"
#include "sl_camera/camera/capture_thread.h"
#include "sl_camera/camera/player_source.h"
#include "sl_camera/camera/start_gate.h"
#include "sl_camera/camera/unreadable_files.h"

namespace sl_camera
{
namespace
{
/// A subscriber of image_raw alone (no camera_info) starts a held player after this long, s.
constexpr double kImageOnlyStartGrace = 0.5;
/// Unreadable files: the shortest interval between log lines, s.
constexpr double kUnreadableLogInterval = 5.0;

/// Seconds of the wall clock, for the core's throttles.
double wallNow()
{
  return ros::WallTime::now().toSec();
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
      params_ = readCameraParams(pnh);
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
    loadCalibration(nh);

    // The source exists before the topics are advertised: the player's start gate must be in place
    // when the first subscriber connects.
    std::unique_ptr<FrameSource> source = createFrameSource(config);
    if (auto* player = dynamic_cast<PlayerSource*>(source.get()))
    {
      start_gate_ = std::make_shared<StartGate>();
      player->setStartGate(start_gate_);
      unreadable_ = player->unreadableFiles();
    }
    advertise(nh);
    startDiagnostics(nh, pnh);

    // Device I/O happens on the capture thread only: onInit returns at once.
    capture_.reset(new CaptureThread(
        std::move(source), config.captureOptions(), [this](const Frame& frame) { publish(frame); },
        [this](const CaptureEvent& event) { log(event); }));
    NODELET_INFO("camera: %s, publishing %s and %s in frame '%s'", capture_->sourceDescription().c_str(),
                 publisher_.getTopic().c_str(), publisher_.getInfoTopic().c_str(), params_.frame_id.c_str());
    capture_->start();
  }

  /// The calibration (a file read; quick). Without one, camera_info carries the image size only.
  void loadCalibration(ros::NodeHandle& nh)
  {
    camera_info_.reset(new camera_info_manager::CameraInfoManager(nh, params_.camera_name, params_.camera_info_url));
    if (!params_.camera_info_url.empty())
      camera_info_->loadCameraInfo(params_.camera_info_url);
    if (camera_info_->isCalibrated())
      return;
    NODELET_WARN(
        "camera '%s' is not calibrated (%s): publishing camera_info with the image size only; calibrate "
        "with camera_calibration, which stores the result through set_camera_info",
        params_.camera_name.c_str(), uncalibratedReason(params_).c_str());
  }

  /// image_raw and camera_info, counting their subscribers for the player's start (any transport
  /// counts as an image subscriber).
  void advertise(ros::NodeHandle& nh)
  {
    image_transport_.reset(new image_transport::ImageTransport(nh));
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
  }

  void startDiagnostics(ros::NodeHandle& nh, ros::NodeHandle& pnh)
  {
    const CameraConfig& config = params_.camera;
    min_rate_ = max_rate_ = config.settings.rate;
    updater_.reset(new diagnostic_updater::Updater(nh, pnh, getName()));
    updater_->setHardwareID(std::string(cameraBackendName(config.backend)) + ":" +
                            (device_.empty() ? std::string("first camera") : device_));
    updater_->add("capture", [this](diagnostic_updater::DiagnosticStatusWrapper& stat)
                  { fillCaptureStatus(captureStats(), params_.camera, device_, unreadable_.get(), stat); });
    frequency_.reset(new diagnostic_updater::FrequencyStatus(
        diagnostic_updater::FrequencyStatusParam(&min_rate_, &max_rate_, 0.1, 10), "frame rate"));
    updater_->add("frame rate", [this](diagnostic_updater::DiagnosticStatusWrapper& stat)
                  { fillRateStatus(captureStats(), *frequency_, stat); });
    diagnostics_timer_ =
        nh.createWallTimer(ros::WallDuration(0.25), [this](const ros::WallTimerEvent&) { onDiagnosticsTimer(); });
  }

  void onDiagnosticsTimer()
  {
    const double rate = nominal_rate_.load();
    if (rate > 0.0)
      min_rate_ = max_rate_ = rate;  // the rate the device actually runs at
    maybeStartPlayback();            // a subscriber of the image alone starts the player after a grace time
    logUnreadableFiles();
    // A camera that stops (or starts) delivering is published at once, not at the next diagnostic_period.
    const bool failing = captureFailing(captureStats());
    if (failing != published_failing_)
    {
      published_failing_ = failing;
      updater_->force_update();
    }
    else
    {
      updater_->update();
    }
  }

  /// Opens the player's start gate once a subscriber is there (callback and timer threads).
  void maybeStartPlayback()
  {
    if (!start_gate_ || start_gate_->isOpen())
      return;
    std::lock_guard<std::mutex> lock(start_mutex_);
    if (starter_.update(image_subscribers_.load(), info_subscribers_.load(), wallNow()) && !start_gate_->isOpen())
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
    const std::vector<std::string> fresh = unreadable_log_.due(*unreadable_, wallNow());
    if (!fresh.empty())
      NODELET_WARN("player: skipping %zu unreadable file%s (%zu in all, see diagnostics): %s", fresh.size(),
                   fresh.size() == 1 ? "" : "s", unreadable_log_.logged(), UnreadableFiles::join(fresh).c_str());
  }

  /// On the capture thread: one frame to ROS.
  void publish(const Frame& frame)
  {
    const cv::Mat& m = frame.image;
    const std::string size_error =
        frameSizeError(m.cols, m.rows, params_.rig_width, params_.rig_height, params_.rig_file);
    if (!size_error.empty())
      throw std::runtime_error(size_error);  // the capture thread counts and reports it as an unusable frame
    frequency_->tick();
    if (publisher_.getNumSubscribers() == 0)
      return;
    std_msgs::Header header;
    header.stamp = ros::Time::isSimTime() ? ros::Time::now() : toRosTime(frame.stamp);
    header.frame_id = params_.frame_id;
    const sensor_msgs::ImagePtr image = toImageMsg(m, header);
    bool size_differs = false;
    const sensor_msgs::CameraInfoPtr info = cameraInfoFor(camera_info_->getCameraInfo(), *image, size_differs);
    if (size_differs)
      NODELET_WARN_THROTTLE(30.0, "calibration is for %u x %u px but the camera delivers %u x %u px", info->width,
                            info->height, image->width, image->height);
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
        if (error_log_.recover())
          NODELET_INFO("recovered: %s", event.message.c_str());
        else
          NODELET_INFO("%s", event.message.c_str());
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
        if (error_log_.shouldLog(event.message, wallNow()))
          NODELET_ERROR("%s; retrying in %.2g s, then at least once every %.2g s", event.message.c_str(),
                        event.retry_in, params_.camera.reconnect_max_backoff);
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

  CaptureStats captureStats() const { return capture_ ? capture_->stats() : CaptureStats(); }

  CameraParams params_;
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
  ErrorLogThrottle error_log_;      ///< guarded by log_mutex_
  bool published_failing_ = false;  ///< timer thread only
  // Player only (null otherwise): the gate that holds frame 0 until a subscriber is there, and the
  // files it could not read.
  std::shared_ptr<StartGate> start_gate_;
  std::shared_ptr<const UnreadableFiles> unreadable_;
  std::atomic<int> image_subscribers_{ 0 };
  std::atomic<int> info_subscribers_{ 0 };
  std::mutex start_mutex_;
  PlaybackStarter starter_{ kImageOnlyStartGrace };              ///< guarded by start_mutex_
  UnreadableFilesLog unreadable_log_{ kUnreadableLogInterval };  ///< timer thread only
  std::unique_ptr<CaptureThread> capture_;                       // last: stopped first, before what its callbacks use
};

}  // namespace sl_camera

PLUGINLIB_EXPORT_CLASS(sl_camera::CameraNodelet, nodelet::Nodelet)
