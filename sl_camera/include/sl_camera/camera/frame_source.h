/**
 * @file
 * The interface every camera back-end implements: open once, grab frames in a loop, close.
 */
#pragma once

#include <chrono>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

namespace sl_camera
{

/** Clock of capture timestamps: wall time (what ROS stamps real images with). */
using CaptureClock = std::chrono::system_clock;

/** One captured image. */
struct Frame
{
  /** The image, always CV_8UC1 (mono8). Reused between grabs: copy it if you keep it. */
  cv::Mat image;
  /** When the image was exposed (device timestamp when the back-end has one, else arrival time). */
  CaptureClock::time_point stamp;
  /** Frame counter of the device or the player; valid when has_sequence is true. */
  std::uint64_t sequence = 0;
  /** True when sequence comes from the device and gaps in it mean lost frames. */
  bool has_sequence = false;
};

/** What a call to FrameSource::grab() produced. */
enum class GrabStatus
{
  Frame,       ///< a new frame was written
  Timeout,     ///< no frame within the timeout; not an error by itself
  EndOfStream  ///< a player without loop reached its last image
};

/** Settings a back-end applies where the device supports them (SI units). */
struct SourceSettings
{
  int width = 0;          ///< image width, px; 0: keep the device's
  int height = 0;         ///< image height, px; 0: keep the device's
  int offset_x = -1;      ///< left edge of the region on the sensor, px; < 0: centred (Aravis only)
  int offset_y = -1;      ///< top edge of the region on the sensor, px; < 0: centred (Aravis only)
  double rate = 10.0;     ///< frame rate, Hz (> 0)
  double exposure = 0.0;  ///< exposure time, s; <= 0: automatic
  double gain = -1.0;  ///< gain in the device's units (Aravis: dB for Gain, raw for GainRaw; V4L2: raw); < 0: automatic
};

/**
 * Error of a frame source. The message is meant for a human: it names the device, folder or file
 * and says what went wrong.
 */
class CameraError : public std::runtime_error
{
public:
  /** How serious the error is, which decides what the capture thread does next. */
  enum class Kind
  {
    NotFound,  ///< the device, folder or file does not exist (at open); retried later
    Open,      ///< it exists but cannot be opened or configured; retried later
    Lost,      ///< the open source stopped working (unplugged, I/O error); closed and re-opened
    Frame      ///< one frame is unusable (corrupt file, incomplete buffer); the source stays open
  };

  /** An error of the given kind with a complete, human-readable message. */
  CameraError(Kind kind, const std::string& message) : std::runtime_error(message), kind_(kind) {}

  /** The kind of the error. */
  Kind kind() const { return kind_; }

private:
  Kind kind_;
};

/**
 * A camera or a recording that delivers mono8 frames. Use: open() once, grab() repeatedly, close().
 * Implementations are not thread-safe; one thread (the CaptureThread) drives a source.
 */
class FrameSource
{
public:
  virtual ~FrameSource() = default;

  /** Short description naming the back-end and the device, e.g. "V4L2 device /dev/video0". */
  const std::string& description() const { return description_; }

  /**
   * Opens and configures the device (one initialisation for the whole stream).
   * @throws CameraError (NotFound or Open) with a message naming the device.
   */
  virtual void open() = 0;

  /**
   * Waits for the next frame, at most about @p timeout (a back-end may exceed it by one
   * blocking device read, see its documentation).
   * @param frame receives the image (mono8), its timestamp and sequence number.
   * @throws CameraError (Lost or Frame).
   */
  virtual GrabStatus grab(Frame& frame, std::chrono::milliseconds timeout) = 0;

  /** Releases the device; safe to call when not open and more than once. */
  virtual void close() = 0;

  /** True between a successful open() and close(). */
  virtual bool isOpen() const = 0;

  /** Frame rate the open device runs at, Hz, or 0 when unknown (as the back-end last set it). */
  double nominalRate() const { return nominal_rate_; }

  /**
   * True while the open source holds back its frames on purpose (a player waiting for its start):
   * grab() then returns Timeout, which the capture thread does not take for a stall.
   */
  virtual bool waiting() const { return false; }

  /**
   * Notes gathered since the last call (settings the device refused or clamped), for the log.
   * Clears them.
   */
  std::vector<std::string> takeWarnings()
  {
    std::vector<std::string> out;
    out.swap(warnings_);
    return out;
  }

protected:
  /** @param description what description() returns: the back-end and the device, fixed for its life */
  explicit FrameSource(std::string description) : description_(std::move(description)) {}

  /** Records a note for takeWarnings(). */
  void warn(const std::string& message) { warnings_.push_back(message); }

  /** Sets what nominalRate() returns (when the device is opened or closed). */
  void setNominalRate(double rate) { nominal_rate_ = rate; }

private:
  std::string description_;
  double nominal_rate_ = 0.0;
  std::vector<std::string> warnings_;
};

}  // namespace sl_camera
