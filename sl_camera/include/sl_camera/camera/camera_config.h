/**
 * @file
 * Configuration of a camera (back-end, device, settings), its validation, and the factory that
 * turns it into a FrameSource.
 */
#pragma once

#include <memory>
#include <string>

#include "sl_camera/camera/aravis_options.h"
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
   * A streaming device that delivers no frame for this long is closed and opened again, s. The
   * capture thread waits at least three frame periods plus two exposures (see captureOptions()).
   */
  double stall_timeout = 1.0;
  /** GigE Vision transport (Aravis back-end only). */
  AravisOptions aravis;

  /**
   * Checks every field; @throws std::invalid_argument whose message starts with the field's name,
   * e.g. "rate must be > 0 Hz, got -1".
   */
  void validate() const;

  /** The device to open: `device`, or the back-end's default ("/dev/video0" for V4L2) when empty. */
  std::string resolvedDevice() const;

  /** Capture-thread timing derived from the rate, exposure, stall_timeout and reconnect_max_backoff. */
  CaptureOptions captureOptions() const;

  /**
   * Reconciles the image size with the camera image of a rig (calibration) file: width and height
   * both 0 take the rig's size; a size that differs from the rig's is an error.
   * @param rig_width, rig_height the rig's camera image, px
   * @param rig_file the file's name, for the message
   * @throws std::invalid_argument naming width/height and the rig file with both sizes
   */
  void applyRigSize(int rig_width, int rig_height, const std::string& rig_file);
};

/**
 * Creates the (unopened) source for a validated @p config.
 * @throws std::invalid_argument if the back-end is not available in this build.
 */
std::unique_ptr<FrameSource> createFrameSource(const CameraConfig& config);

}  // namespace sl_camera
