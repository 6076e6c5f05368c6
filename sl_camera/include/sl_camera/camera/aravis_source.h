/**
 * @file
 * GenICam cameras (USB3 Vision, GigE Vision) through the Aravis library. Compiled only when
 * pkg-config finds aravis-0.8 (see cameraBackendAvailable()).
 */
#pragma once

#include <memory>
#include <string>

#include "sl_camera/camera/aravis_options.h"
#include "sl_camera/camera/frame_source.h"

namespace sl_camera
{

/**
 * A GenICam camera read with Aravis' camera API and a stream of preallocated buffers.
 *
 * open() selects Mono8 when the camera offers it (otherwise Mono10/12/14/16, Bayer 8-bit, RGB8 and
 * BGR8 are converted to mono8), sets a width x height region at offset_x, offset_y on the sensor
 * (centred when an offset is < 0), and sets the frame rate (AcquisitionFrameRate), exposure
 * (ExposureTime or ExposureTimeAbs in s, converted to us; auto when <= 0 and the camera has
 * ExposureAuto) and gain (Gain in dB, or GainRaw in the camera's raw units; auto when < 0 and the
 * camera has GainAuto). Values outside the camera's bounds are clamped; refusals are reported
 * through takeWarnings().
 *
 * GigE Vision transport (AravisOptions): the packet socket is disabled for a camera on the
 * loopback interface (it receives nothing there) or when packet_socket is off; the socket buffer
 * is one payload (automatic) or socket_buffer bytes, capped by the kernel at net.core.rmem_max;
 * the packet size is packet_size, or else negotiated by Aravis (test packets), or on the loopback
 * interface the largest the camera and the MTU allow. Missing packets are re-requested (packet resend).
 *
 * Stamps are the host's arrival time of each buffer, sequence numbers the camera's frame ids (gaps
 * are lost frames). Incomplete buffers give a CameraError of kind Frame; a lost connection
 * (Aravis' control-lost signal) one of kind Lost.
 *
 * close() never waits long on a dead device: the teardown (stop acquisition, leave control, join
 * Aravis' threads, each of which may wait seconds for a camera that does not answer) runs on a
 * helper thread; close() waits for it at most kCloseWait (not at all after control-lost) and
 * otherwise lets it finish in the background.
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
   * @param settings size, offsets, rate, exposure and gain to apply
   * @param options GigE Vision transport settings
   */
  AravisSource(const std::string& camera_id, const SourceSettings& settings,
               const AravisOptions& options = AravisOptions());
  ~AravisSource() override;

  /** @throws CameraError naming the camera: NotFound when absent, Open when it refuses to stream. */
  void open() override;
  GrabStatus grab(Frame& frame, std::chrono::milliseconds timeout) override;
  void close() override;
  bool isOpen() const override;

  /** Longest time close() waits for the teardown of a camera that still answers, s. */
  static constexpr double kCloseWait = 0.5;

private:
  struct Impl;
  std::string camera_id_;
  SourceSettings settings_;
  AravisOptions options_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sl_camera
