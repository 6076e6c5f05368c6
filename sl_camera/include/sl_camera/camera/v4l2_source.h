/**
 * @file
 * Video4Linux2 cameras (USB UVC and others) through OpenCV's V4L2 back-end.
 */
#pragma once

#include <memory>
#include <string>

#include "sl_camera/camera/frame_source.h"

namespace cv
{
class VideoCapture;
}

namespace sl_camera
{

/**
 * A V4L2 device read with cv::VideoCapture (cv::CAP_V4L2), converted to mono8.
 *
 * open() applies the SourceSettings where the driver offers the control: frame size, frame rate
 * (OpenCV rounds it to whole Hz), exposure (V4L2 exposure_absolute, units of 100 us; manual mode
 * when exposure > 0, aperture-priority auto otherwise) and gain (V4L2 has no unit for gain: the value
 * is passed as the driver's raw gain, see `v4l2-ctl -d /dev/video0 -l`). Refused or adjusted
 * settings are reported through takeWarnings().
 *
 * grab() blocks until the driver delivers a frame, at most the V4L2 select timeout, which this class
 * sets to 2 s through OPENCV_VIDEOIO_V4L_SELECT_TIMEOUT unless that is already set in the
 * environment. Stamps come from the driver's buffer timestamps (converted to wall time) when they
 * are plausible, otherwise from the arrival time. A vanished device node or three failed reads in a
 * row give a CameraError of kind Lost.
 */
class V4l2Source : public FrameSource
{
public:
  /**
   * @param device device path ("/dev/video0", "/dev/v4l/by-id/...") or index ("0")
   * @param settings size, rate, exposure and gain to apply
   */
  V4l2Source(const std::string& device, const SourceSettings& settings);
  ~V4l2Source() override;

  /** @throws CameraError naming the device: NotFound when absent, Open when busy or not permitted. */
  void open() override;
  GrabStatus grab(Frame& frame, std::chrono::milliseconds timeout) override;
  void close() override;
  bool isOpen() const override;

  /** The device path for @p device: an index n becomes "/dev/video<n>", a path stays. */
  static std::string devicePath(const std::string& device);

private:
  void applySettings();

  std::string path_;
  SourceSettings settings_;
  std::unique_ptr<cv::VideoCapture> capture_;
  cv::Mat raw_;
  int failures_in_row_ = 0;
};

}  // namespace sl_camera
