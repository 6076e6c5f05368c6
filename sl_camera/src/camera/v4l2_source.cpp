#include "sl_camera/camera/v4l2_source.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>

#include <sys/stat.h>
#include <unistd.h>

#include <opencv2/videoio.hpp>

#include "sl_rig/mono8.h"

namespace sl_camera
{

namespace
{
// V4L2 menu values of exposure_auto (V4L2_CID_EXPOSURE_AUTO), which OpenCV passes through unchanged.
constexpr double kV4l2ExposureManual = 1.0;
constexpr double kV4l2ExposureAperturePriority = 3.0;
// Consecutive failed reads after which the device counts as lost.
constexpr int kMaxFailuresInRow = 3;

bool isIndex(const std::string& s)
{
  if (s.empty() || s.size() > 4)
    return false;
  for (char c : s)
    if (c < '0' || c > '9')
      return false;
  return true;
}

bool nodeExists(const std::string& path)
{
  struct stat st;
  return ::stat(path.c_str(), &st) == 0;
}
}  // namespace

std::string V4l2Source::devicePath(const std::string& device)
{
  return isIndex(device) ? "/dev/video" + device : device;
}

V4l2Source::V4l2Source(const std::string& device, const SourceSettings& settings)
  : FrameSource("V4L2 device " + devicePath(device)), path_(devicePath(device)), settings_(settings)
{
}

V4l2Source::~V4l2Source()
{
  close();
}

void V4l2Source::open()
{
  close();
  struct stat st;
  if (path_.empty() || ::stat(path_.c_str(), &st) != 0)
  {
    const int err = errno;
    if (path_.empty() || err == ENOENT || err == ENOTDIR)
      throw CameraError(CameraError::Kind::NotFound,
                        description() + " does not exist (camera unplugged? `v4l2-ctl --list-devices` lists them)");
    throw CameraError(CameraError::Kind::Open, description() + ": " + std::strerror(err));
  }
  if (!S_ISCHR(st.st_mode))
    throw CameraError(CameraError::Kind::Open, description() + " is not a video device (not a character device)");
  if (::access(path_.c_str(), R_OK | W_OK) != 0)
  {
    const int err = errno;
    if (err == EACCES || err == EPERM)
      throw CameraError(CameraError::Kind::Open,
                        "no permission to open " + path_ + " (add the user to group video and log in again)");
    throw CameraError(CameraError::Kind::Open, description() + ": " + std::strerror(err));
  }

  // OpenCV waits 10 s for a frame of a stalled camera by default; keep it short so that a lost
  // device is noticed and the capture thread can stop promptly. Read once, at the first capture.
  ::setenv("OPENCV_VIDEOIO_V4L_SELECT_TIMEOUT", "2", 0);

  capture_.reset(new cv::VideoCapture());
  bool opened = false;
  try
  {
    opened = capture_->open(path_, cv::CAP_V4L2);
  }
  catch (const cv::Exception& e)
  {
    capture_.reset();
    throw CameraError(CameraError::Kind::Open, "cannot open " + description() + ": " + e.what());
  }
  if (!opened || !capture_->isOpened())
  {
    capture_.reset();
    throw CameraError(CameraError::Kind::Open,
                      "cannot open " + description() + " (busy in another program, or not a capture device)");
  }
  try
  {
    applySettings();
  }
  catch (const cv::Exception& e)
  {
    capture_.reset();
    throw CameraError(CameraError::Kind::Open, "cannot configure " + description() + ": " + e.what());
  }
  failures_in_row_ = 0;
}

void V4l2Source::applySettings()
{
  cv::VideoCapture& cap = *capture_;
  const SourceSettings& s = settings_;
  if (s.width > 0 || s.height > 0)
  {
    const int w = s.width > 0 ? s.width : static_cast<int>(cap.get(cv::CAP_PROP_FRAME_WIDTH));
    const int h = s.height > 0 ? s.height : static_cast<int>(cap.get(cv::CAP_PROP_FRAME_HEIGHT));
    cap.set(cv::CAP_PROP_FRAME_WIDTH, w);
    cap.set(cv::CAP_PROP_FRAME_HEIGHT, h);
    const int got_w = static_cast<int>(cap.get(cv::CAP_PROP_FRAME_WIDTH));
    const int got_h = static_cast<int>(cap.get(cv::CAP_PROP_FRAME_HEIGHT));
    if (got_w != w || got_h != h)
    {
      std::ostringstream msg;
      msg << description() << ": asked for " << w << " x " << h << " px, the driver delivers " << got_w << " x "
          << got_h << " px";
      warn(msg.str());
    }
  }
  if (s.rate > 0.0)
  {
    cap.set(cv::CAP_PROP_FPS, s.rate);
    setNominalRate(std::max(0.0, cap.get(cv::CAP_PROP_FPS)));
    if (nominalRate() > 0.0 && std::fabs(nominalRate() - s.rate) > 0.01 * s.rate)
    {
      std::ostringstream msg;
      msg << description() << ": asked for " << s.rate << " Hz, the driver runs at " << nominalRate() << " Hz";
      warn(msg.str());
    }
  }
  if (s.exposure > 0.0)
  {
    const double units = std::max(1.0, std::round(s.exposure * 1e4));  // exposure_absolute: 100 us
    if (!cap.set(cv::CAP_PROP_AUTO_EXPOSURE, kV4l2ExposureManual) || !cap.set(cv::CAP_PROP_EXPOSURE, units))
      warn(description() + ": the driver has no manual exposure control; exposure stays automatic");
  }
  else
  {
    cap.set(cv::CAP_PROP_AUTO_EXPOSURE, kV4l2ExposureAperturePriority);  // best effort
  }
  if (s.gain >= 0.0 && !cap.set(cv::CAP_PROP_GAIN, s.gain))
    warn(description() + ": the driver has no gain control; gain ignored");
}

GrabStatus V4l2Source::grab(Frame& frame, std::chrono::milliseconds /*timeout*/)
{
  if (!capture_)
    throw CameraError(CameraError::Kind::Lost, description() + ": not open");
  bool ok = false;
  std::string detail;
  try
  {
    ok = capture_->read(raw_) && !raw_.empty();
  }
  catch (const cv::Exception& e)
  {
    ok = false;
    detail = std::string(": ") + e.what();
  }
  if (!ok)
  {
    if (!nodeExists(path_))
      throw CameraError(CameraError::Kind::Lost, description() + " disappeared (unplugged?)");
    if (++failures_in_row_ >= kMaxFailuresInRow)
      throw CameraError(CameraError::Kind::Lost,
                        description() + ": " + std::to_string(failures_in_row_) + " reads in a row failed" + detail);
    throw CameraError(CameraError::Kind::Frame, description() + ": read failed" + detail);
  }
  failures_in_row_ = 0;
  try
  {
    sl_rig::toMono8(raw_, frame.image);
  }
  catch (const std::invalid_argument& e)
  {
    throw CameraError(CameraError::Kind::Frame, description() + ": " + e.what());
  }

  // The driver's buffer timestamp is on the monotonic clock (ms); move it to wall time.
  const auto wall_now = CaptureClock::now();
  frame.stamp = wall_now;
  const double buffer_ms = capture_->get(cv::CAP_PROP_POS_MSEC);
  if (buffer_ms > 0.0)
  {
    const double mono_now_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
    const double age_ms = mono_now_ms - buffer_ms;
    if (age_ms >= 0.0 && age_ms < 1000.0)
      frame.stamp = wall_now - std::chrono::duration_cast<CaptureClock::duration>(
                                   std::chrono::duration<double, std::milli>(age_ms));
  }
  frame.has_sequence = false;
  frame.sequence = 0;
  return GrabStatus::Frame;
}

void V4l2Source::close()
{
  if (capture_)
  {
    try
    {
      capture_->release();
    }
    catch (const cv::Exception&)
    {
      // releasing a vanished device may fail; nothing left to do
    }
    capture_.reset();
  }
}

bool V4l2Source::isOpen() const
{
  return capture_ != nullptr;
}

}  // namespace sl_camera
