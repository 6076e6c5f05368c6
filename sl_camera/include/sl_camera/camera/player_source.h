/**
 * @file
 * Replays a folder of images or a video file at a set rate (offline data).
 */
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "sl_camera/camera/frame_source.h"
#include "sl_camera/camera/start_gate.h"
#include "sl_camera/camera/unreadable_files.h"

namespace cv
{
class VideoCapture;
}

namespace sl_camera
{

/**
 * A FrameSource that replays recorded data:
 * - a folder: every image in it (extensions png, jpg, jpeg, pgm, ppm, pnm, bmp, tif, tiff, any
 *   case; other files are ignored) in byte-wise order of the file names, so number them with
 *   leading zeros;
 * - an image file: that one image;
 * - any other file: a video, read with OpenCV's FFmpeg back-end (or its own MJPEG reader).
 *
 * Frames are paced at @p rate Hz; at the end the player starts over when @p loop is set and
 * otherwise reports GrabStatus::EndOfStream. Images are converted to mono8 (colour to luma, 16 bit
 * to its top 8 bits). Stamps are the replay time; sequence numbers count the frames delivered.
 * An image that cannot be decoded gives a CameraError of kind Frame naming the file, and the file
 * is recorded in unreadableFiles(); the next grab() continues with the next image. An image that
 * no longer exists gives one of kind Lost (the capture thread then opens, i.e. lists, the folder
 * again).
 *
 * With a StartGate (setStartGate()), playback is held before frame 0 until the gate opens: grab()
 * returns Timeout and waiting() is true, so frame 0 goes to the subscriber that opened the gate.
 */
class PlayerSource : public FrameSource
{
public:
  /**
   * @param path folder, image file or video file
   * @param rate replay rate, Hz (> 0)
   * @param loop start over after the last frame
   * @throws std::invalid_argument when rate is not > 0
   */
  PlayerSource(const std::string& path, double rate, bool loop);
  ~PlayerSource() override;

  /** Lists the folder (or opens the video); @throws CameraError naming the path. */
  void open() override;
  GrabStatus grab(Frame& frame, std::chrono::milliseconds timeout) override;
  void close() override;
  bool isOpen() const override;
  /** True while a start gate is set and still closed (nothing played yet). */
  bool waiting() const override;

  /**
   * Holds playback before frame 0 until @p gate opens (nullptr: play at once, the default). The
   * gate stays in force across re-opens; once open, it no longer holds anything. Call before
   * the first grab().
   */
  void setStartGate(std::shared_ptr<const StartGate> gate);

  /**
   * Files that could not be decoded (or converted to mono8) so far, across re-opens. The record
   * is shared and thread-safe: read it from any thread while the capture thread plays.
   */
  std::shared_ptr<const UnreadableFiles> unreadableFiles() const { return unreadable_; }

  /** The images found by open(), in replay order (empty for a video). */
  const std::vector<std::string>& files() const { return files_; }

  /** True if @p path has one of the image extensions listed above. */
  static bool isImageFile(const std::string& path);

  /** Time source of the pacing (not of the stamps): steady_clock and real sleeps by default. */
  struct PacingClock
  {
    virtual ~PacingClock() = default;
    virtual std::chrono::steady_clock::time_point now() = 0;
    virtual void sleepUntil(std::chrono::steady_clock::time_point t) = 0;
  };
  /** Replaces the pacing clock (tests pace on a simulated clock); call before the first grab(). */
  void setPacingClock(std::shared_ptr<PacingClock> clock);

private:
  bool openVideo();
  bool readVideoFrame(cv::Mat& image);

  std::string path_;
  double rate_;
  bool loop_;
  bool open_ = false;
  std::vector<std::string> files_;
  std::unique_ptr<cv::VideoCapture> video_;
  cv::Mat video_frame_;
  std::size_t next_index_ = 0;
  std::uint64_t sequence_ = 0;
  bool started_ = false;
  std::chrono::steady_clock::time_point next_due_;
  std::shared_ptr<PacingClock> clock_;
  std::shared_ptr<const StartGate> gate_;
  std::shared_ptr<UnreadableFiles> unreadable_;
};

}  // namespace sl_camera
