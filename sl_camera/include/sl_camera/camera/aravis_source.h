/**
 * @file
 * GenICam cameras (USB3 Vision, GigE Vision) through the Aravis library. Compiled only when
 * pkg-config finds aravis-0.8 (see cameraBackendAvailable()).
 */
#ifndef SL_CAMERA_CAMERA_ARAVIS_SOURCE_H
#define SL_CAMERA_CAMERA_ARAVIS_SOURCE_H

#include <memory>
#include <string>

#include "sl_camera/camera/frame_source.h"

namespace sl_camera
{

/**
 * A GenICam camera read with Aravis' camera API and a stream of preallocated buffers.
 *
 * open() selects Mono8 when the camera offers it (otherwise Mono10/12/14/16, Bayer 8-bit, RGB8 and
 * BGR8 are converted to mono8), centres a width x height region on the sensor, and sets the frame
 * rate (AcquisitionFrameRate), exposure (ExposureTime in s, converted to us; auto when <= 0 and the
 * camera has ExposureAuto) and gain (Gain in dB; auto when < 0 and the camera has GainAuto).
 * Values outside the camera's bounds are clamped; refusals are reported through takeWarnings().
 *
 * Stamps are the host's arrival time of each buffer, sequence numbers the camera's frame ids (gaps
 * are lost frames). Incomplete buffers give a CameraError of kind Frame; a lost connection
 * (Aravis' control-lost signal) one of kind Lost.
 *
 * The camera id is Aravis' device id as listed by `arv-tool-0.8` (e.g. "Basler-21234567" or an IP
 * address); empty selects the first camera found. Ids starting with "Fake" enable Aravis' simulated
 * camera (e.g. "Fake_1"), useful to try the driver without hardware.
 */
class AravisSource : public FrameSource
{
public:
  /**
   * @param camera_id Aravis device id; empty: the first camera
   * @param settings size, rate, exposure and gain to apply
   */
  AravisSource(const std::string& camera_id, const SourceSettings& settings);
  ~AravisSource() override;

  std::string description() const override;
  /** @throws CameraError naming the camera: NotFound when absent, Open when it refuses to stream. */
  void open() override;
  GrabStatus grab(Frame& frame, std::chrono::milliseconds timeout) override;
  void close() override;
  bool isOpen() const override;
  double nominalRate() const override;

private:
  struct Impl;
  std::string camera_id_;
  SourceSettings settings_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sl_camera

#endif  // SL_CAMERA_CAMERA_ARAVIS_SOURCE_H
