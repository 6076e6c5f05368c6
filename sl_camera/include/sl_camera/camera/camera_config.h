/**
 * @file
 * Configuration of a camera (back-end, device, settings), its validation, and the factory that
 * turns it into a FrameSource.
 */
#ifndef SL_CAMERA_CAMERA_CAMERA_CONFIG_H
#define SL_CAMERA_CAMERA_CAMERA_CONFIG_H

#include <memory>
#include <string>

#include "sl_camera/camera/capture_thread.h"
#include "sl_camera/camera/frame_source.h"

namespace sl_camera
{

/** Camera back-ends. */
enum class CameraBackend
{
  V4l2,    ///< Video4Linux2 device through OpenCV
  Aravis,  ///< GenICam USB3 / GigE Vision camera through Aravis
  Player   ///< folder of images, image or video file
};

/** Parameter spelling of a back-end: "v4l2", "aravis" or "player". */
const char* cameraBackendName(CameraBackend backend);

/** Parses "v4l2", "aravis" or "player"; @throws std::invalid_argument naming `backend` otherwise. */
CameraBackend parseCameraBackend(const std::string& name);

/** False for Aravis when sl_camera was built without libaravis; true otherwise. */
bool cameraBackendAvailable(CameraBackend backend);

/**
 * Everything a camera is configured with. The field names are the parameter names of the camera
 * nodelet, and validate() names them in its messages.
 */
struct CameraConfig
{
  CameraBackend backend = CameraBackend::V4l2;
  /** V4L2 path or index; Aravis device id (empty: first camera); player folder, image or video. */
  std::string device;
  /** Size, rate (Hz), exposure (s) and gain (dB) to apply. */
  SourceSettings settings;
  /** Player: start over after the last frame. */
  bool loop = false;
  /** Longest wait between two attempts to (re)open the device, s. */
  double reconnect_max_backoff = 4.0;

  /**
   * Checks every field; @throws std::invalid_argument whose message starts with the field's name,
   * e.g. "rate must be > 0 Hz, got -1".
   */
  void validate() const;

  /** The device to open: `device`, or the back-end's default ("/dev/video0" for V4L2) when empty. */
  std::string resolvedDevice() const;

  /** Capture-thread timing derived from the rate, exposure and reconnect_max_backoff. */
  CaptureOptions captureOptions() const;
};

/**
 * Creates the (unopened) source for a validated @p config.
 * @throws std::invalid_argument if the back-end is not available in this build.
 */
std::unique_ptr<FrameSource> createFrameSource(const CameraConfig& config);

}  // namespace sl_camera

#endif  // SL_CAMERA_CAMERA_CAMERA_CONFIG_H
