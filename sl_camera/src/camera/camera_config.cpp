#include "sl_camera/camera/camera_config.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "sl_camera/camera/player_source.h"
#include "sl_camera/camera/v4l2_source.h"
#ifdef SL_CAMERA_HAVE_ARAVIS
#include "sl_camera/camera/aravis_source.h"
#endif

namespace sl_camera
{

namespace
{
template <typename T>
std::string str(const T& value)
{
  std::ostringstream s;
  s << value;
  return s.str();
}

void require(bool ok, const std::string& message)
{
  if (!ok)
    throw std::invalid_argument(message);
}
}  // namespace

const char* cameraBackendName(CameraBackend backend)
{
  switch (backend)
  {
    case CameraBackend::V4l2:
      return "v4l2";
    case CameraBackend::Aravis:
      return "aravis";
    case CameraBackend::Player:
      return "player";
  }
  return "unknown";
}

const char* packetSocketModeName(PacketSocketMode mode)
{
  switch (mode)
  {
    case PacketSocketMode::Auto:
      return "auto";
    case PacketSocketMode::Off:
      return "off";
  }
  return "unknown";
}

PacketSocketMode parsePacketSocketMode(const std::string& name)
{
  for (PacketSocketMode m : { PacketSocketMode::Auto, PacketSocketMode::Off })
    if (name == packetSocketModeName(m))
      return m;
  throw std::invalid_argument("packet_socket must be auto or off; got '" + name + "'");
}

CameraBackend parseCameraBackend(const std::string& name)
{
  for (CameraBackend b : { CameraBackend::V4l2, CameraBackend::Aravis, CameraBackend::Player })
    if (name == cameraBackendName(b))
      return b;
  throw std::invalid_argument("backend must be one of v4l2, aravis, player; got '" + name + "'");
}

bool cameraBackendAvailable(CameraBackend backend)
{
#ifdef SL_CAMERA_HAVE_ARAVIS
  (void)backend;
  return true;
#else
  return backend != CameraBackend::Aravis;
#endif
}

void CameraConfig::validate() const
{
  require(cameraBackendAvailable(backend),
          std::string("backend ") + cameraBackendName(backend) +
              " is not available: sl_camera was built without Aravis (install libaravis-dev and rebuild)");
  require(backend != CameraBackend::Player || !device.empty(),
          "device must name a folder of images, an image or a video file for backend player");
  const SourceSettings& s = settings;
  require(s.width >= 0 && s.width <= 65535, "width must be in 0..65535 px (0: the device's), got " + str(s.width));
  require(s.height >= 0 && s.height <= 65535, "height must be in 0..65535 px (0: the device's), got " + str(s.height));
  require(s.rate > 0.0 && std::isfinite(s.rate) && s.rate <= 10000.0,
          "rate must be > 0 Hz (and at most 10000), got " + str(s.rate));
  require(s.offset_x >= -1 && s.offset_x <= 65535,
          "offset_x must be in -1..65535 px (-1: centred), got " + str(s.offset_x));
  require(s.offset_y >= -1 && s.offset_y <= 65535,
          "offset_y must be in -1..65535 px (-1: centred), got " + str(s.offset_y));
  require(std::isfinite(s.exposure) && s.exposure <= 10.0,
          "exposure must be a finite time <= 10 s (<= 0: automatic), got " + str(s.exposure));
  require(std::isfinite(s.gain), "gain must be finite (< 0: automatic), got " + str(s.gain));
  require(reconnect_max_backoff > 0.0 && std::isfinite(reconnect_max_backoff) && reconnect_max_backoff <= 3600.0,
          "reconnect_max_backoff must be in (0, 3600] s, got " + str(reconnect_max_backoff));
  require(stall_timeout > 0.0 && std::isfinite(stall_timeout) && stall_timeout <= 3600.0,
          "stall_timeout must be in (0, 3600] s, got " + str(stall_timeout));
  require(aravis.socket_buffer == 0 ||
              (aravis.socket_buffer >= kMinSocketBuffer && aravis.socket_buffer <= kMaxSocketBuffer),
          "socket_buffer must be auto (0) or " + str(kMinSocketBuffer) + ".." + str(kMaxSocketBuffer) + " bytes, got " +
              str(aravis.socket_buffer));
  require(aravis.packet_size == 0 || (aravis.packet_size >= kMinPacketSize && aravis.packet_size <= kMaxPacketSize),
          "packet_size must be auto (0) or " + str(kMinPacketSize) + ".." + str(kMaxPacketSize) + " bytes, got " +
              str(aravis.packet_size));
}

void CameraConfig::applyRigSize(int rig_width, int rig_height, const std::string& rig_file)
{
  SourceSettings& s = settings;
  if (rig_width <= 0 || rig_height <= 0)
    throw std::invalid_argument("calibration_file " + rig_file + " has no camera image size");
  if (s.width == 0 && s.height == 0)
  {
    s.width = rig_width;
    s.height = rig_height;
    return;
  }
  if (s.width != rig_width || s.height != rig_height)
    throw std::invalid_argument("width x height is " + str(s.width) + " x " + str(s.height) + " px but the rig file " +
                                rig_file + " is calibrated for " + str(rig_width) + " x " + str(rig_height) +
                                " px; set the camera to the rig's size (0 x 0 takes it) or use a rig calibrated at "
                                "this size");
}

std::string CameraConfig::resolvedDevice() const
{
  if (device.empty() && backend == CameraBackend::V4l2)
    return "/dev/video0";
  return device;
}

CaptureOptions CameraConfig::captureOptions() const
{
  CaptureOptions o;
  o.max_backoff = reconnect_max_backoff;
  o.initial_backoff = std::min(o.initial_backoff, reconnect_max_backoff);
  // Never sooner than three frame periods (and two exposures) without a frame: a slow camera is not lost.
  const double periods = 3.0 / settings.rate + 2.0 * std::max(0.0, settings.exposure);
  o.stall_timeout = std::max(stall_timeout, periods);
  // The first frame after opening may take longer (sensor start, automatic exposure settling).
  o.first_frame_timeout = std::max(o.stall_timeout, 2.0);
  // Diagnostics call a stream overdue after two and a half frame periods without a frame.
  o.frame_overdue = std::min(o.stall_timeout, std::max(0.25, 2.5 / settings.rate + std::max(0.0, settings.exposure)));
  return o;
}

std::unique_ptr<FrameSource> createFrameSource(const CameraConfig& config)
{
  switch (config.backend)
  {
    case CameraBackend::V4l2:
      return std::unique_ptr<FrameSource>(new V4l2Source(config.resolvedDevice(), config.settings));
    case CameraBackend::Aravis:
#ifdef SL_CAMERA_HAVE_ARAVIS
      return std::unique_ptr<FrameSource>(new AravisSource(config.resolvedDevice(), config.settings, config.aravis));
#else
      throw std::invalid_argument("backend aravis is not available: sl_camera was built without Aravis");
#endif
    case CameraBackend::Player:
      return std::unique_ptr<FrameSource>(new PlayerSource(config.resolvedDevice(), config.settings.rate, config.loop));
  }
  throw std::invalid_argument("unknown backend");
}

}  // namespace sl_camera
