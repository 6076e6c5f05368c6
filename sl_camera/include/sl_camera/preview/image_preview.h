/**
 * @file
 * A small, slow copy of an image stream for a viewer on a slow link (rviz on a workstation over
 * Wi-Fi): every frame shrunk by an integer factor, at most a given number of frames per second.
 */
#pragma once

#include <opencv2/core.hpp>

namespace sl_camera
{

/** Settings of ImagePreview (the nodelet's `~scale` and `~rate`). */
struct PreviewConfig
{
  int scale = 2;      ///< width and height are divided by this, 1..16
  double rate = 2.0;  ///< most frames per second, (0, 1000]

  /** @throws std::invalid_argument naming the field ("scale", "rate") and its range. */
  void validate() const;
};

/** Picks the frames to show and shrinks them; ROS-free. */
class ImagePreview
{
public:
  /** @throws std::invalid_argument for an invalid @p config (PreviewConfig::validate()). */
  explicit ImagePreview(const PreviewConfig& config);

  /**
   * True when the frame of time @p t (s) is to be shown. The schedule advances by 1 / rate from the
   * first frame, so the average rate is the configured one even when frames arrive a little early or
   * late; a gap of more than one period or time running backwards (a bag played again) starts anew.
   */
  bool due(double t);

  /**
   * Writes @p in shrunk by the scale into @p out: each output pixel is the mean of a scale x scale
   * block (cv::INTER_AREA), the size rounded down and at least 1 x 1; same type as @p in.
   * @throws std::invalid_argument for an empty image.
   */
  void shrink(const cv::Mat& in, cv::Mat& out) const;

  const PreviewConfig& config() const { return config_; }

private:
  PreviewConfig config_;
  double period_;
  double next_ = 0.0;
  bool started_ = false;
};

}  // namespace sl_camera
