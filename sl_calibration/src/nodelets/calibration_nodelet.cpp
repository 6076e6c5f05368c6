// The live calibration procedure: plane calibration (a plane at N >= 3 known distances) or full
// calibration (checkerboard and pattern images of >= 3 plane poses), driven by services, with a
// prompt per step on the console and on ~status. Decoding and fitting use sl_calibration_core.
#include <chrono>
#include <condition_variable>
#include <fstream>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include <cv_bridge/cv_bridge.h>
#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>
#include <std_msgs/Float64.h>
#include <std_msgs/String.h>
#include <std_srvs/Trigger.h>

#include "sl_calibration/full_calibration.h"
#include "sl_calibration/plane_calibration.h"
#include "sl_calibration/residual_plot.h"
#include "sl_params/params.h"
#include "sl_rig/mono8.h"
#include "sl_rig/ros/rig_param.h"

namespace sl_calibration
{
namespace
{

/// Every parameter of the nodelet, read and validated in one place.
struct CalibrationParams
{
  std::string mode = "plane";
  std::string output_file;
  double epipolar_tolerance = kCalibrationEpipolarTolerance;
  double capture_timeout = 10.0;
  double settle_time = 0.5;
  int frames_per_capture = 3;
  bool auto_calibrate = true;
  // Plane calibration.
  std::vector<double> distances;
  PlaneCalibrationOptions plane;
  std::string residuals_file;
  // Full calibration.
  std::string board_size = "8x5";
  double square = 0.02;
  int min_poses = 3;
  std::string camera_info_file;
  std::string camera_info_output;

  sl_projector::Rig rig;
  Board board;
};

CalibrationParams readParams(const ros::NodeHandle& pnh)
{
  CalibrationParams p;
  sl_params::readIfSet(pnh, "mode", p.mode);
  if (p.mode != "plane" && p.mode != "full")
    throw std::invalid_argument("~mode: must be 'plane' or 'full', got '" + p.mode + "'");
  p.rig = sl_projector::loadRigParam(pnh).rig;  // the rig to start from
  if (!sl_params::readIfSet(pnh, "output_file", p.output_file) || p.output_file.empty())
    throw std::invalid_argument("~output_file: required (where the calibrated rig file is written)");
  sl_params::readIfSet(pnh, "epipolar_tolerance", p.epipolar_tolerance);
  if (!(p.epipolar_tolerance > 0.0 && p.epipolar_tolerance <= 50.0))
    throw std::invalid_argument("~epipolar_tolerance: must be in (0, 50] px");
  sl_params::readIfSet(pnh, "capture_timeout", p.capture_timeout);
  if (!(p.capture_timeout > 0.0 && p.capture_timeout <= 600.0))
    throw std::invalid_argument("~capture_timeout: must be in (0, 600] s");
  sl_params::readIfSet(pnh, "settle_time", p.settle_time);
  if (!(p.settle_time >= 0.0 && p.settle_time <= 60.0))
    throw std::invalid_argument("~settle_time: must be in [0, 60] s");
  sl_params::readIfSet(pnh, "frames_per_capture", p.frames_per_capture);
  if (p.frames_per_capture < 1 || p.frames_per_capture > 100)
    throw std::invalid_argument("~frames_per_capture: must be 1..100");
  sl_params::readIfSet(pnh, "auto_calibrate", p.auto_calibrate);

  sl_params::readIfSet(pnh, "distances", p.distances);
  for (double d : p.distances)
    if (!(d > 0.0 && d < 20.0))
      throw std::invalid_argument("~distances: every distance must be in (0, 20) m, got " + std::to_string(d));
  std::string reference = "camera", normal = "robot";
  sl_params::readIfSet(pnh, "reference", reference);
  sl_params::readIfSet(pnh, "normal", normal);
  sl_params::readIfSet(pnh, "min_distances", p.plane.min_distances);
  sl_params::readIfSet(pnh, "max_rms", p.plane.max_rational_rms);
  sl_params::readIfSet(pnh, "residuals_file", p.residuals_file);
  try
  {
    p.plane.reference = parseDistanceReference(reference);
    p.plane.normal = parsePlaneNormal(normal);
    p.plane.validate();
  }
  catch (const std::invalid_argument& e)
  {
    throw std::invalid_argument(std::string("~reference / ~normal / ~min_distances / ~max_rms: ") + e.what());
  }

  sl_params::readIfSet(pnh, "board_size", p.board_size);
  sl_params::readIfSet(pnh, "square", p.square);
  try
  {
    p.board = parseBoardSize(p.board_size, p.square);
  }
  catch (const std::invalid_argument& e)
  {
    throw std::invalid_argument(std::string("~board_size / ~square: ") + e.what());
  }
  sl_params::readIfSet(pnh, "min_poses", p.min_poses);
  if (p.min_poses < 3)
    throw std::invalid_argument("~min_poses: must be >= 3");
  sl_params::readIfSet(pnh, "camera_info_file", p.camera_info_file);
  sl_params::readIfSet(pnh, "camera_info_output", p.camera_info_output);
  if (p.mode == "full" && !p.residuals_file.empty() && !isPngPath(p.residuals_file))
    throw std::invalid_argument("~residuals_file: in full mode a picture, the name must end in .png, got '" +
                                p.residuals_file + "'");
  return p;
}
}  // namespace

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
      {
        plane_.reset(new PlaneCalibration(p_.rig, p_.plane));
        decoder_.reset(new sl_decoder::Decoder(p_.rig, calibrationDecoderConfig(p_.epipolar_tolerance)));
      }
      else
      {
        FullCalibrationOptions options;
        options.epipolar_tolerance = p_.epipolar_tolerance;
        options.projector.min_views = p_.min_poses;
        full_.reset(new FullCalibration(p_.rig, p_.board, options));
        if (!p_.camera_info_file.empty())
          full_->setCamera(loadCameraInfo(p_.camera_info_file));
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

  // --- images --------------------------------------------------------------------------------
  void onImage(const sensor_msgs::ImageConstPtr& msg)
  {
    std::lock_guard<std::mutex> lock(image_mutex_);
    if (wanted_ <= 0 || msg->header.stamp < not_before_)
      return;
    try
    {
      bool converted = false;
      cv_bridge::CvImageConstPtr cv = cv_bridge::toCvShare(msg);
      frames_.push_back(sl_rig::toMono8(cv->image, msg->encoding, converted).clone());
      --wanted_;
    }
    catch (const std::exception& e)
    {
      NODELET_ERROR_THROTTLE(5.0, "image_raw: cannot use the image (%s): %s", msg->encoding.c_str(), e.what());
      return;
    }
    image_cv_.notify_all();
  }

  /// Waits for @p n images stamped after now. @return false on timeout or images of the wrong size
  /// (@p res then fails with the message).
  bool grab(int n, std::vector<cv::Mat>& frames, std_srvs::Trigger::Response& res)
  {
    std::unique_lock<std::mutex> lock(image_mutex_);
    frames_.clear();
    wanted_ = n;
    not_before_ = ros::Time::now() + ros::Duration(p_.settle_time);
    const bool ok = image_cv_.wait_for(lock, std::chrono::duration<double>(p_.capture_timeout + p_.settle_time),
                                       [&] { return wanted_ <= 0; });
    wanted_ = 0;
    frames = frames_;
    frames_.clear();
    if (!ok)
    {
      res.success = false;
      res.message = "timed out after " + std::to_string(p_.capture_timeout) + " s waiting for " + std::to_string(n) +
                    " image(s) on " + image_sub_.getTopic() + " (got " + std::to_string(frames.size()) + ")";
      return false;
    }
    for (const cv::Mat& f : frames)
      if (f.cols != p_.rig.camera.width || f.rows != p_.rig.camera.height)
      {
        res.success = false;
        res.message = "the images are " + std::to_string(f.cols) + " x " + std::to_string(f.rows) +
                      " px, the rig's camera " + std::to_string(p_.rig.camera.width) + " x " +
                      std::to_string(p_.rig.camera.height);
        return false;
      }
    return true;
  }

  // --- prompts -------------------------------------------------------------------------------
  void say(const std::string& text)
  {
    NODELET_INFO("%s", text.c_str());
    std_msgs::String s;
    s.data = text;
    status_pub_.publish(s);
  }

  bool nextDistance(double& d) const
  {
    if (override_distance_ > 0.0)
    {
      d = override_distance_;
      return true;
    }
    if (next_index_ < p_.distances.size())
    {
      d = p_.distances[next_index_];
      return true;
    }
    return false;
  }

  void prompt()
  {
    std::ostringstream o;
    if (p_.mode == "plane")
    {
      double d;
      if (nextDistance(d))
      {
        std_msgs::Float64 m;
        m.data = d;
        next_distance_pub_.publish(m);
        o << "plane calibration: put the plane at " << fixed(d, 3) << " m ("
          << (p_.plane.normal == PlaneNormal::Camera ? "perpendicular to the camera's optical axis"
                                                     : "perpendicular to the robot's x axis")
          << ", measured from the "
          << (p_.plane.reference == DistanceReference::Camera ? "camera's optical centre" : "robot's front edge")
          << "), then: rosservice call " << service_prefix_ << "/capture";
      }
      else
        o << "plane calibration: " << plane_->distances().size() << " distance(s) captured; publish the next distance "
          << "(m) on " << service_prefix_ << "/distance and call " << service_prefix_ << "/capture, or call "
          << service_prefix_ << "/calibrate";
    }
    else
    {
      o << "full calibration: " << full_->planeViews() << " plane pose(s) of >= " << p_.min_poses << ", "
        << full_->boardViews() << " board view(s). ";
      if (pending_board_)
        o << "Now the pattern image of the same pose: projector on, board covered, lights dimmed; then: rosservice "
             "call "
          << service_prefix_ << "/capture_pattern (or capture_board again to keep the last board as a camera view)";
      else
        o << "Put the plane (board " << p_.board.cols << "x" << p_.board.rows << " inner corners) in a new pose, "
          << "lights on and projector dark; then: rosservice call " << service_prefix_ << "/capture_board"
          << (full_->planeViews() >= p_.min_poses ? " (or " + service_prefix_ + "/calibrate)" : std::string());
    }
    say(o.str());
  }

  void onDistance(const std_msgs::Float64ConstPtr& msg)
  {
    if (!(msg->data > 0.0 && msg->data < 20.0))
    {
      NODELET_ERROR("~distance: %f is not a distance in metres (0, 20)", msg->data);
      return;
    }
    std::lock_guard<std::mutex> lock(work_mutex_);
    override_distance_ = msg->data;
    if (p_.mode == "plane")
      prompt();
  }

  // --- services ------------------------------------------------------------------------------
  bool onCapturePlane(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res)
  {
    std::lock_guard<std::mutex> lock(work_mutex_);
    double d;
    if (!nextDistance(d))
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
    int total = 0, least = 1 << 30;
    sl_decoder::DecodeResult result;
    for (size_t i = 0; i < frames.size(); ++i)
    {
      decoder_->decode(frames[i], result);
      const int n = plane_->addImage(d, result, "image " + std::to_string(i) + " at " + fixed(d, 3) + " m");
      total += n;
      least = std::min(least, n);
    }
    std::ostringstream o;
    o << fixed(d, 3) << " m: " << total / static_cast<int>(frames.size()) << " primitives per image from "
      << frames.size() << " image(s)";
    if (least == 0)
      o << " (WARNING: an image decoded nothing: projector off, plane out of view, or the wrong rig file?)";
    override_distance_ = 0.0;
    if (next_index_ < p_.distances.size() && std::abs(p_.distances[next_index_] - d) < 1e-9)
      ++next_index_;
    res.success = least > 0;
    res.message = o.str();
    ++views_;
    say("captured view " + std::to_string(views_) +
        (views_ <= p_.distances.size() ? " of " + std::to_string(p_.distances.size()) : std::string()) + ", plane at " +
        o.str());
    if (p_.auto_calibrate && !p_.distances.empty() && next_index_ >= p_.distances.size() && least > 0)
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
    std::vector<cv::Point2f> corners;
    if (!findBoardCorners(frames[0], p_.board, corners))
    {
      res.success = false;
      res.message = "checkerboard of " + std::to_string(p_.board.cols) + "x" + std::to_string(p_.board.rows) +
                    " inner corners not found in the image (the whole board must be visible, lit and in focus)";
      NODELET_ERROR("capture_board: %s", res.message.c_str());
      return true;
    }
    ++board_count_;
    if (pending_board_)  // the previous board image had no pattern image: a camera view
      full_->addCameraCorners("board " + std::to_string(board_count_ - 1), pending_corners_);
    pending_corners_ = corners;
    pending_board_ = true;
    res.success = true;
    res.message = "board " + std::to_string(board_count_) + ": " + std::to_string(corners.size()) + " corners found";
    say(res.message);
    prompt();
    return true;
  }

  bool onCapturePattern(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res)
  {
    std::lock_guard<std::mutex> lock(work_mutex_);
    if (!pending_board_)
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
      const std::string name = "pose " + std::to_string(full_->planeViews() + 1);
      const std::vector<PrimitiveSample> samples = full_->decode(name, frames[0]);
      full_->addPlaneSamples(name, pending_corners_, samples);
      pending_board_ = false;
      res.success = true;
      res.message = name + ": " + std::to_string(samples.size()) + " primitives decoded";
      say("captured plane pose " + std::to_string(full_->planeViews()) +
          (full_->planeViews() <= p_.min_poses ? " of " + std::to_string(p_.min_poses)
                                               : " (" + std::to_string(p_.min_poses) + " needed)") +
          ": " + std::to_string(samples.size()) + " primitives decoded");
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
      plane_->clear();
    if (full_)
      full_->clear();
    next_index_ = 0;
    views_ = 0;
    override_distance_ = 0.0;
    pending_board_ = false;
    board_count_ = 0;
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
      if (plane_)
      {
        const PlaneCalibrationResult r = plane_->fit();
        if (isPngPath(p_.residuals_file))
          writePlaneResidualPlot(p_.residuals_file, r, cv::Size(p_.rig.camera.width, p_.rig.camera.height));
        else if (!p_.residuals_file.empty())
        {
          std::ofstream csv(p_.residuals_file);
          if (!csv || !(csv << r.residualsCsv()))
            throw CalibrationError(p_.residuals_file + ": cannot write the residuals");
        }
        sl_projector::saveRig(withTables(p_.rig, r), p_.output_file);
        say("plane calibration:\n" + r.summary());
        message = "wrote " + p_.output_file + ": " + std::to_string(r.calibrated) + " primitives calibrated, rms " +
                  fixed(1000.0 * r.rational_rms, 3) + " mm (rational), " + fixed(1000.0 * r.linear_rms, 3) +
                  " mm (linear)";
      }
      else
      {
        if (pending_board_)
        {
          full_->addCameraCorners("board " + std::to_string(board_count_), pending_corners_);
          pending_board_ = false;
        }
        const FullCalibrationResult r = full_->calibrate();
        if (!p_.residuals_file.empty())
          writeCameraResidualPlot(p_.residuals_file, r);
        if (!p_.camera_info_output.empty())
          saveCameraInfo(r.rig.camera, p_.camera_info_output);
        sl_projector::saveRig(r.rig, p_.output_file);
        say("full calibration:\n" + r.summary());
        message = "wrote " + p_.output_file + ": camera " + fixed(r.camera.rms, 3) + " px, projector " +
                  fixed(r.projector.rms, 3) + " px rms reprojection error";
      }
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
  std::unique_ptr<PlaneCalibration> plane_;
  std::unique_ptr<FullCalibration> full_;
  std::unique_ptr<sl_decoder::Decoder> decoder_;
  std::string service_prefix_;

  std::mutex work_mutex_;  // captures and fits, one at a time
  size_t next_index_ = 0;
  size_t views_ = 0;  // plane captures so far
  double override_distance_ = 0.0;
  bool pending_board_ = false;
  std::vector<cv::Point2f> pending_corners_;
  int board_count_ = 0;

  std::mutex image_mutex_;
  std::condition_variable image_cv_;
  int wanted_ = 0;
  ros::Time not_before_;
  std::vector<cv::Mat> frames_;

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
