// The live calibration procedure: plane calibration (a plane at N >= 3 known distances) or full
// calibration (checkerboard and pattern images of >= 3 plane poses), driven by services, with a
// prompt per step on the console and on ~status. Decoding and fitting use sl_calibration_core.
#include <cstdint>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>
#include <std_msgs/Float64.h>
#include <std_msgs/String.h>
#include <std_srvs/Trigger.h>

#include "images.h"
#include "params.h"
#include "sl_calibration/live_procedure.h"

namespace sl_calibration
{
/**
 * Live calibration. Plane mode: for each distance (the list ~distances, or the last value on
 * ~distance), put the plane there and call ~capture; after the last listed distance (or on
 * ~calibrate) the tables are fitted and written. Full mode: per plane pose call ~capture_board
 * (lights on, projector dark) then ~capture_pattern (projector on, board covered); extra
 * ~capture_board calls add camera-only views; ~calibrate fits and writes.
 */
class CalibrationNodelet : public nodelet::Nodelet
{
public:
  ~CalibrationNodelet() override
  {
    if (spinner_)
      spinner_->stop();
  }

private:
  void onInit() override
  {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    try
    {
      p_ = readParams(pnh);
      if (p_.mode == "plane")
        plane_.reset(new PlaneSession(p_.rig, p_.plane, p_.distances, p_.epipolar_tolerance));
      else
      {
        full_.reset(new FullSession(p_.rig, p_.board, p_.epipolar_tolerance, p_.min_poses));
        if (!p_.camera_info_file.empty())
          full_->calibration().setCamera(loadCameraInfo(p_.camera_info_file));
      }
    }
    catch (const std::exception& e)
    {
      NODELET_FATAL("invalid parameter: %s", e.what());
      throw;
    }
    status_pub_ = pnh.advertise<std_msgs::String>("status", 10, true);
    next_distance_pub_ = pnh.advertise<std_msgs::Float64>("next_distance", 1, true);
    distance_sub_ = pnh.subscribe("distance", 1, &CalibrationNodelet::onDistance, this);
    // Images arrive on their own queue and thread, so that a capture service can wait for them.
    image_nh_ = nh;
    image_nh_.setCallbackQueue(&image_queue_);
    it_.reset(new image_transport::ImageTransport(image_nh_));
    image_sub_ = it_->subscribe("image_raw", 2, &CalibrationNodelet::onImage, this);
    spinner_.reset(new ros::AsyncSpinner(1, &image_queue_));
    spinner_->start();
    calibrate_srv_ = pnh.advertiseService("calibrate", &CalibrationNodelet::onCalibrate, this);
    reset_srv_ = pnh.advertiseService("reset", &CalibrationNodelet::onReset, this);
    if (p_.mode == "plane")
      capture_srv_ = pnh.advertiseService("capture", &CalibrationNodelet::onCapturePlane, this);
    else
    {
      board_srv_ = pnh.advertiseService("capture_board", &CalibrationNodelet::onCaptureBoard, this);
      pattern_srv_ = pnh.advertiseService("capture_pattern", &CalibrationNodelet::onCapturePattern, this);
    }
    service_prefix_ = pnh.getNamespace();
    prompt();
  }

  void onImage(const sensor_msgs::ImageConstPtr& msg)
  {
    try
    {
      collector_.offer(static_cast<std::int64_t>(msg->header.stamp.toNSec()), [&msg] { return toMono8Copy(msg); });
    }
    catch (const std::exception& e)
    {
      NODELET_ERROR_THROTTLE(5.0, "image_raw: cannot use the image (%s): %s", msg->encoding.c_str(), e.what());
    }
  }

  /// Waits for @p n images stamped after now and the settle time. @return false on timeout or
  /// images of the wrong size (@p res then fails with the message).
  bool grab(int n, std::vector<cv::Mat>& frames, std_srvs::Trigger::Response& res)
  {
    const ros::Time not_before = ros::Time::now() + ros::Duration(p_.settle_time);
    frames = collector_.collect(n, static_cast<std::int64_t>(not_before.toNSec()), p_.capture_timeout + p_.settle_time);
    if (static_cast<int>(frames.size()) < n)
      res.message = "timed out after " + std::to_string(p_.capture_timeout) + " s waiting for " + std::to_string(n) +
                    " image(s) on " + image_sub_.getTopic() + " (got " + std::to_string(frames.size()) + ")";
    else
      res.message = frameSizeError(frames, p_.rig.camera.width, p_.rig.camera.height);
    res.success = res.message.empty();
    return res.success;
  }

  void say(const std::string& text)
  {
    NODELET_INFO("%s", text.c_str());
    std_msgs::String s;
    s.data = text;
    status_pub_.publish(s);
  }

  void prompt()
  {
    if (full_)
    {
      say(full_->prompt(service_prefix_));
      return;
    }
    double d;
    if (plane_->steps().nextDistance(d))
    {
      std_msgs::Float64 m;
      m.data = d;
      next_distance_pub_.publish(m);
    }
    say(plane_->prompt(service_prefix_));
  }

  void onDistance(const std_msgs::Float64ConstPtr& msg)
  {
    if (!(msg->data > 0.0 && msg->data < 20.0))
    {
      NODELET_ERROR("~distance: %f is not a distance in metres (0, 20)", msg->data);
      return;
    }
    std::lock_guard<std::mutex> lock(work_mutex_);
    if (plane_)
    {
      plane_->steps().setDistance(msg->data);
      prompt();
    }
  }

  bool onCapturePlane(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res)
  {
    std::lock_guard<std::mutex> lock(work_mutex_);
    double d;
    if (!plane_->steps().nextDistance(d))
    {
      res.success = false;
      res.message = "no distance: every distance of ~distances is captured; publish one on " + service_prefix_ +
                    "/distance first, or call calibrate";
      return true;
    }
    std::vector<cv::Mat> frames;
    if (!grab(p_.frames_per_capture, frames, res))
    {
      NODELET_ERROR("capture: %s", res.message.c_str());
      return true;
    }
    const PlaneCapture capture = plane_->capture(d, frames);
    res.success = capture.least > 0;
    res.message = capture.message;
    say(capturedViewLine(plane_->steps().views(), p_.distances.size(), capture.message));
    if (p_.auto_calibrate && plane_->steps().listDone() && capture.least > 0)
    {
      std::string summary;
      res.success = runCalibration(summary);
      res.message += "; " + summary;
      return true;
    }
    prompt();
    return true;
  }

  bool onCaptureBoard(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res)
  {
    std::lock_guard<std::mutex> lock(work_mutex_);
    std::vector<cv::Mat> frames;
    if (!grab(1, frames, res))
      return true;
    std::size_t corners = 0;
    const int board = full_->addBoardImage(frames[0], corners);
    res.success = board > 0;
    if (!res.success)
    {
      res.message = boardNotFoundMessage(p_.board);
      NODELET_ERROR("capture_board: %s", res.message.c_str());
      return true;
    }
    res.message = "board " + std::to_string(board) + ": " + std::to_string(corners) + " corners found";
    say(res.message);
    prompt();
    return true;
  }

  bool onCapturePattern(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res)
  {
    std::lock_guard<std::mutex> lock(work_mutex_);
    if (!full_->steps().pendingBoard())
    {
      res.success = false;
      res.message = "capture the board image of this pose first (" + service_prefix_ + "/capture_board)";
      return true;
    }
    std::vector<cv::Mat> frames;
    if (!grab(1, frames, res))
      return true;
    try
    {
      std::string name;
      const std::size_t primitives = full_->steps().addPatternImage(frames[0], name);
      res.success = true;
      res.message = name + ": " + std::to_string(primitives) + " primitives decoded";
      say(capturedPoseLine(full_->calibration().planeViews(), p_.min_poses, primitives));
    }
    catch (const std::exception& e)
    {
      res.success = false;
      res.message = e.what();
      NODELET_ERROR("capture_pattern: %s", e.what());
    }
    prompt();
    return true;
  }

  bool onCalibrate(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res)
  {
    std::lock_guard<std::mutex> lock(work_mutex_);
    res.success = runCalibration(res.message);
    return true;
  }

  bool onReset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res)
  {
    std::lock_guard<std::mutex> lock(work_mutex_);
    if (plane_)
      plane_->reset();
    if (full_)
      full_->reset();
    res.success = true;
    res.message = "all captures forgotten";
    say(res.message);
    prompt();
    return true;
  }

  /// Fits and writes the output file; nothing is written on failure. @return success.
  bool runCalibration(std::string& message)
  {
    try
    {
      const WrittenCalibration written = plane_
                                             ? plane_->write(p_.output_file, p_.residuals_file)
                                             : full_->write(p_.output_file, p_.residuals_file, p_.camera_info_output);
      say(written.summary);
      message = written.message;
      say(message);
      return true;
    }
    catch (const std::exception& e)
    {
      message = std::string("calibration failed, nothing written: ") + e.what();
      NODELET_ERROR("%s", message.c_str());
      return false;
    }
  }

  CalibrationParams p_;
  std::unique_ptr<PlaneSession> plane_;  ///< plane mode only
  std::unique_ptr<FullSession> full_;    ///< full mode only
  std::string service_prefix_;

  std::mutex work_mutex_;  // captures and fits, one at a time

  FrameCollector collector_;  ///< images for the capture services, from the image thread

  ros::NodeHandle image_nh_;
  ros::CallbackQueue image_queue_;
  std::unique_ptr<ros::AsyncSpinner> spinner_;
  std::unique_ptr<image_transport::ImageTransport> it_;
  image_transport::Subscriber image_sub_;
  ros::Publisher status_pub_, next_distance_pub_;
  ros::Subscriber distance_sub_;
  ros::ServiceServer capture_srv_, board_srv_, pattern_srv_, calibrate_srv_, reset_srv_;
};

}  // namespace sl_calibration

PLUGINLIB_EXPORT_CLASS(sl_calibration::CalibrationNodelet, nodelet::Nodelet)
