// The projector nodelet: publishes the pattern (latched) and, on the robot, shows it full screen and
// sets up the DLP Pico. The pattern logic lives in the sl_projector core library, the window and the
// I2C set-up in the package's private device library (src/device/).
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>

#include "device/dlp_pico.h"
#include "device/projector_window.h"
#include "sl_rig/pattern.h"
#include "sl_rig/rig.h"
#include "sl_params/params.h"

namespace sl_projector
{

namespace
{
/// Everything the nodelet is configured with, read and validated in one place.
struct Params
{
  PatternConfig pattern;
  std::string frame_id = "projector_optical_frame";
  double fx = 753.0, fy = 781.0, cx = -1.0, cy = -1.0;  // cx, cy < 0: frame centre
  std::vector<double> D = std::vector<double>(5, 0.0);
  std::string calibration_file;
  bool show_window = false;
  std::string display;
  int window_x = 0, window_y = 0;
  bool dlp_setup = false;
  bool i2c_dry_run = false;
  std::string i2c_bus = "/dev/i2c-2";
  int i2c_address = 0x1b;
};

Params readParams(const ros::NodeHandle& pnh)
{
  Params p;
  PatternConfig& c = p.pattern;
  c.rows = sl_params::read(pnh, "rows", c.rows);
  c.cols = sl_params::read(pnh, "columns", c.cols);
  c.primitive_width = sl_params::read(pnh, "primitive_width", c.primitive_width);
  c.primitive_height = sl_params::read(pnh, "primitive_height", c.primitive_height);
  c.gap_x = sl_params::read(pnh, "gap_x", c.gap_x);
  c.gap_y = sl_params::read(pnh, "gap_y", c.gap_y);
  c.offset_x = sl_params::read(pnh, "offset_x", c.offset_x);
  c.offset_y = sl_params::read(pnh, "offset_y", c.offset_y);
  c.projector_width = sl_params::read(pnh, "projector_width", c.projector_width);
  c.projector_height = sl_params::read(pnh, "projector_height", c.projector_height);
  c.flip_x = sl_params::read(pnh, "flip_x", c.flip_x);
  c.flip_y = sl_params::read(pnh, "flip_y", c.flip_y);
  try
  {
    c.validate();
  }
  catch (const std::invalid_argument& e)
  {
    // PatternConfig names its fields; the parameter "columns" is the field "cols".
    std::string msg = e.what();
    if (msg.rfind("cols", 0) == 0)
      msg = "columns" + msg.substr(4);
    throw std::invalid_argument("~" + msg);
  }
  p.frame_id = sl_params::read(pnh, "frame_id", p.frame_id);
  p.fx = sl_params::read(pnh, "fx", p.fx);
  p.fy = sl_params::read(pnh, "fy", p.fy);
  p.cx = sl_params::read(pnh, "cx", (c.projector_width - 1) / 2.0);
  p.cy = sl_params::read(pnh, "cy", (c.projector_height - 1) / 2.0);
  p.calibration_file = sl_params::read(pnh, "calibration_file", p.calibration_file);
  if (!p.calibration_file.empty())
  {
    // The rig file is the single source of the pattern and the projector intrinsics.
    Rig rig;
    try
    {
      rig = loadRig(p.calibration_file);
    }
    catch (const RigFileError& e)
    {
      throw std::invalid_argument(std::string("~calibration_file: ") + e.what());
    }
    c = rig.pattern;  // the pattern parameters above are ignored then
    p.fx = rig.projector.fx;
    p.fy = rig.projector.fy;
    p.cx = rig.projector.cx;
    p.cy = rig.projector.cy;
    p.D.assign(rig.projector.dist.begin(), rig.projector.dist.end());
  }
  if (!(p.fx > 0.0) || !std::isfinite(p.fx))
    throw std::invalid_argument("~fx must be a finite focal length > 0 px");
  if (!(p.fy > 0.0) || !std::isfinite(p.fy))
    throw std::invalid_argument("~fy must be a finite focal length > 0 px");
  if (!std::isfinite(p.cx) || !std::isfinite(p.cy))
    throw std::invalid_argument("~cx and ~cy must be finite");
  if (p.frame_id.empty())
    throw std::invalid_argument("~frame_id must not be empty");
  p.show_window = sl_params::read(pnh, "show_window", p.show_window);
  p.display = sl_params::read(pnh, "display", p.display);
  p.window_x = sl_params::read(pnh, "window_x", p.window_x);
  p.window_y = sl_params::read(pnh, "window_y", p.window_y);
  p.dlp_setup = sl_params::read(pnh, "dlp_setup", p.dlp_setup);
  p.i2c_dry_run = sl_params::read(pnh, "i2c_dry_run", p.i2c_dry_run);
  p.i2c_bus = sl_params::read(pnh, "i2c_bus", p.i2c_bus);
  p.i2c_address = sl_params::read(pnh, "i2c_address", p.i2c_address);
  if (p.i2c_address < 0x03 || p.i2c_address > 0x77)
    throw std::invalid_argument("~i2c_address must be a 7-bit device address in 0x03..0x77, got " +
                                std::to_string(p.i2c_address));
  return p;
}
}  // namespace

/**
 * Publishes the structured-light pattern as a latched mono8 image on `pattern` with a latched
 * `camera_info` (projector intrinsics, frame `projector_optical_frame`); optionally shows it full
 * screen on the projector's X screen and sets the DLP Pico up over I2C.
 */
class ProjectorNodelet : public nodelet::Nodelet
{
public:
  ~ProjectorNodelet() override
  {
    window_timer_.stop();
    window_.close();
  }

private:
  void onInit() override
  {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    Params p;
    std::unique_ptr<Pattern> pattern;
    try
    {
      p = readParams(pnh);
      pattern.reset(new Pattern(p.pattern));
    }
    catch (const std::exception& e)
    {
      NODELET_FATAL("invalid parameter: %s", e.what());
      throw;
    }
    const cv::Mat frame = pattern->render();

    if (p.dlp_setup)
      setupDlp(p);

    if (p.show_window)
    {
      try
      {
        window_.open(p.display, p.window_x, p.window_y, frame);
        window_timer_ =
            nh.createWallTimer(ros::WallDuration(0.1), [this](const ros::WallTimerEvent&) { window_.spinOnce(); });
        NODELET_INFO("showing the pattern at (%d, %d) on display '%s'", p.window_x, p.window_y, p.display.c_str());
      }
      catch (const std::exception& e)
      {
        // Without the window the robot sees no pattern, but the topics stay useful (simulation,
        // debugging), so report it loudly and carry on.
        NODELET_ERROR("cannot show the pattern full screen: %s", e.what());
      }
    }

    const ros::Time stamp = ros::Time::now();
    sensor_msgs::Image image;
    image.header.stamp = stamp;
    image.header.frame_id = p.frame_id;
    image.height = static_cast<uint32_t>(frame.rows);
    image.width = static_cast<uint32_t>(frame.cols);
    image.encoding = sensor_msgs::image_encodings::MONO8;
    image.is_bigendian = 0;
    image.step = static_cast<uint32_t>(frame.cols);
    image.data.assign(frame.data, frame.data + frame.total());

    sensor_msgs::CameraInfo info;
    info.header = image.header;
    info.width = image.width;
    info.height = image.height;
    info.distortion_model = "plumb_bob";
    info.D = p.D;
    info.K = { p.fx, 0.0, p.cx, 0.0, p.fy, p.cy, 0.0, 0.0, 1.0 };
    info.R = { 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0 };
    info.P = { p.fx, 0.0, p.cx, 0.0, 0.0, p.fy, p.cy, 0.0, 0.0, 0.0, 1.0, 0.0 };

    pattern_pub_ = nh.advertise<sensor_msgs::Image>("pattern", 1, true);
    info_pub_ = nh.advertise<sensor_msgs::CameraInfo>("camera_info", 1, true);
    pattern_pub_.publish(image);
    info_pub_.publish(info);
    NODELET_INFO("publishing a %d x %d pattern of %d x %d primitives on %s", frame.cols, frame.rows, p.pattern.rows,
                 p.pattern.cols, pattern_pub_.getTopic().c_str());
  }

  void setupDlp(const Params& p)
  {
    const std::vector<I2cWrite> writes = dlpPicoSetup(true, true);
    const uint8_t address = static_cast<uint8_t>(p.i2c_address);
    if (p.i2c_dry_run)
    {
      NODELET_INFO_STREAM("DLP Pico set-up (dry run, nothing sent) on " << p.i2c_bus << ":\n"
                                                                        << formatWrites(address, writes));
      return;
    }
    try
    {
      sendI2cWrites(p.i2c_bus, address, writes);
      NODELET_INFO("DLP Pico set up on %s: both axes flipped, crop mode", p.i2c_bus.c_str());
    }
    catch (const std::exception& e)
    {
      NODELET_ERROR("DLP Pico set-up failed: %s", e.what());
    }
  }

  ProjectorWindow window_;
  ros::WallTimer window_timer_;
  ros::Publisher pattern_pub_;
  ros::Publisher info_pub_;
};

}  // namespace sl_projector

PLUGINLIB_EXPORT_CLASS(sl_projector::ProjectorNodelet, nodelet::Nodelet)
