#include "sl_camera/camera/aravis_source.h"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <functional>
#include <sstream>
#include <utility>
#include <thread>

#include <ifaddrs.h>
#include <net/if.h>
#include <netinet/in.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstring>

#include <arv.h>
#include <opencv2/imgproc.hpp>

#include "sl_rig/mono8.h"

namespace sl_camera
{

namespace
{
// Buffers queued in the stream: enough to ride out a slow consumer for a few frames.
constexpr int kStreamBuffers = 8;

/** Takes the message out of a GError (and frees it); "" when there was none. */
std::string takeError(GError*& error)
{
  if (!error)
    return std::string();
  std::string message = error->message ? error->message : "unknown error";
  g_clear_error(&error);
  return message;
}

const char* bufferStatusName(ArvBufferStatus status)
{
  switch (status)
  {
    case ARV_BUFFER_STATUS_SUCCESS:
      return "success";
    case ARV_BUFFER_STATUS_CLEARED:
      return "cleared";
    case ARV_BUFFER_STATUS_TIMEOUT:
      return "timeout before all packets arrived";
    case ARV_BUFFER_STATUS_MISSING_PACKETS:
      return "missing packets";
    case ARV_BUFFER_STATUS_WRONG_PACKET_ID:
      return "wrong packet id";
    case ARV_BUFFER_STATUS_SIZE_MISMATCH:
      return "image larger than the buffer";
    case ARV_BUFFER_STATUS_FILLING:
      return "still filling";
    case ARV_BUFFER_STATUS_ABORTED:
      return "aborted";
    default:
      return "unknown status";
  }
}

void onControlLost(ArvDevice* /*device*/, gpointer flag)
{
  static_cast<std::atomic<bool>*>(flag)->store(true);
}

/** True when @p address (a GInetSocketAddress) is a loopback address. */
bool isLoopback(GSocketAddress* address)
{
  if (!address || !G_IS_INET_SOCKET_ADDRESS(address))
    return false;
  GInetAddress* inet = g_inet_socket_address_get_address(G_INET_SOCKET_ADDRESS(address));
  return inet && g_inet_address_get_is_loopback(inet);
}

/**
 * For a camera on this host (its address is a loopback address or one of this host's, so its
 * packets travel through the loopback interface whichever interface Aravis found it on): the MTU
 * of that loopback interface. 0 for a camera elsewhere, or when unknown.
 */
int localCameraMtu(GSocketAddress* device_address)
{
  if (!device_address || !G_IS_INET_SOCKET_ADDRESS(device_address))
    return 0;
  GInetAddress* inet = g_inet_socket_address_get_address(G_INET_SOCKET_ADDRESS(device_address));
  if (!inet || g_inet_address_get_family(inet) != G_SOCKET_FAMILY_IPV4)
    return 0;
  const guint8* bytes = g_inet_address_to_bytes(inet);
  bool local = g_inet_address_get_is_loopback(inet);
  std::string loopback_name = "lo";
  ifaddrs* list = nullptr;
  if (::getifaddrs(&list) != 0)
    return 0;
  for (ifaddrs* i = list; i; i = i->ifa_next)
  {
    if (!i->ifa_addr || i->ifa_addr->sa_family != AF_INET)
      continue;
    if ((i->ifa_flags & IFF_LOOPBACK) != 0)
      loopback_name = i->ifa_name;
    const auto* in = reinterpret_cast<const sockaddr_in*>(i->ifa_addr);
    local = local || std::memcmp(&in->sin_addr, bytes, 4) == 0;
  }
  ::freeifaddrs(list);
  if (!local)
    return 0;
  int mtu = 0;
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  if (fd >= 0)
  {
    ifreq request{};
    std::strncpy(request.ifr_name, loopback_name.c_str(), IFNAMSIZ - 1);
    if (::ioctl(fd, SIOCGIFMTU, &request) == 0)
      mtu = request.ifr_mtu;
    ::close(fd);
  }
  return mtu;
}

/** Completion flag of one background teardown. */
struct TeardownState
{
  std::mutex mutex;
  std::condition_variable done_cv;
  bool done = false;
};
/** One camera's settings applied through Aravis, each step warning (never failing) on what the
 *  camera does not take. */
class Configurer
{
public:
  Configurer(ArvCamera* camera, std::string description, std::function<void(const std::string&)> warn)
    : camera_(camera),
      device_(arv_camera_get_device(camera)),
      description_(std::move(description)),
      warn_(std::move(warn))
  {
  }

  /** Mono8 when the camera offers it. */
  void pixelFormat()
  {
    guint n = 0;
    const char** formats = arv_camera_dup_available_pixel_formats_as_strings(camera_, &n, &error_);
    bool has_mono8 = false;
    for (guint i = 0; formats && i < n; ++i)
      has_mono8 = has_mono8 || (formats[i] && std::string(formats[i]) == "Mono8");
    g_free(formats);
    takeError(error_);
    if (has_mono8)
    {
      arv_camera_set_pixel_format(camera_, ARV_PIXEL_FORMAT_MONO_8, &error_);
      note("cannot select Mono8");
    }
  }

  /** The region of interest (negative offsets: centred on the sensor). */
  void region(const SourceSettings& s)
  {
    if (s.width <= 0 && s.height <= 0)
      return;
    gint sensor_w = 0, sensor_h = 0, x = 0, y = 0, w = 0, h = 0;
    arv_camera_get_sensor_size(camera_, &sensor_w, &sensor_h, &error_);
    takeError(error_);
    arv_camera_get_region(camera_, &x, &y, &w, &h, &error_);
    takeError(error_);
    const gint want_w = s.width > 0 ? s.width : w;
    const gint want_h = s.height > 0 ? s.height : h;
    gint want_x = std::max(0, s.offset_x), want_y = std::max(0, s.offset_y);
    const bool offsets = arv_camera_is_region_offset_available(camera_, &error_);
    takeError(error_);
    if (offsets)
    {
      const gint inc_x = std::max(1, static_cast<int>(arv_camera_get_x_offset_increment(camera_, nullptr)));
      const gint inc_y = std::max(1, static_cast<int>(arv_camera_get_y_offset_increment(camera_, nullptr)));
      if (s.offset_x < 0)
        want_x = sensor_w >= want_w ? (sensor_w - want_w) / 2 / inc_x * inc_x : 0;
      if (s.offset_y < 0)
        want_y = sensor_h >= want_h ? (sensor_h - want_h) / 2 / inc_y * inc_y : 0;
    }
    else if (s.offset_x > 0 || s.offset_y > 0)
    {
      warn_(description_ + ": the camera has no region offsets; offset_x and offset_y ignored");
      want_x = want_y = 0;
    }
    arv_camera_set_region(camera_, want_x, want_y, want_w, want_h, &error_);
    note("cannot set the region");
    arv_camera_get_region(camera_, &x, &y, &w, &h, &error_);
    takeError(error_);
    if (w != want_w || h != want_h)
    {
      std::ostringstream msg;
      msg << description_ << ": asked for " << want_w << " x " << want_h << " px, the camera delivers " << w << " x "
          << h << " px";
      warn_(msg.str());
    }
    if (offsets && (x != want_x || y != want_y))
    {
      std::ostringstream msg;
      msg << description_ << ": asked for the region at offset " << want_x << ", " << want_y << " px, the camera uses "
          << x << ", " << y << " px (sensor " << sensor_w << " x " << sensor_h << " px)";
      warn_(msg.str());
    }
  }

  /** The frame rate (clamped to the camera's bounds); @return the rate the camera reports. */
  double frameRate(double requested)
  {
    if (arv_camera_is_frame_rate_available(camera_, &error_))
    {
      double lo = 0.0, hi = 0.0;
      arv_camera_get_frame_rate_bounds(camera_, &lo, &hi, &error_);
      takeError(error_);
      double rate = requested;
      if (hi > lo && (rate < lo || rate > hi))
      {
        rate = std::min(std::max(rate, lo), hi);
        std::ostringstream msg;
        msg << description_ << ": frame rate " << requested << " Hz outside " << lo << ".." << hi << " Hz, using "
            << rate;
        warn_(msg.str());
      }
      arv_camera_set_frame_rate(camera_, rate, &error_);
      note("cannot set the frame rate");
    }
    else
    {
      takeError(error_);
      warn_(description_ + ": no frame rate control; the camera runs at its own rate");
    }
    const double actual = std::max(0.0, arv_camera_get_frame_rate(camera_, &error_));
    takeError(error_);
    return actual;
  }

  /** How one feature with an automatic mode is driven through Aravis (exposure, gain). */
  struct AutoFeature
  {
    const char* name;        ///< "exposure"
    const char* value_name;  ///< "the exposure time"
    const char* control;     ///< "exposure time": "no exposure time control"
    double scale;            ///< the camera's unit per the setting's (1e6: s -> us)
    std::string unit;        ///< " s"
    std::string note;        ///< added to a clamping warning
    gboolean (*auto_available)(ArvCamera*, GError**);
    void (*set_auto)(ArvCamera*, ArvAuto, GError**);
    gboolean (*available)(ArvCamera*, GError**);
    void (*bounds)(ArvCamera*, double*, double*, GError**);
    void (*set)(ArvCamera*, double, GError**);
  };

  /** With @p fixed: automatic mode off and @p value (clamped to the bounds); else automatic mode on. */
  void autoFeature(const AutoFeature& f, bool fixed, double value)
  {
    const bool has_auto = f.auto_available(camera_, &error_);
    takeError(error_);
    if (!fixed)
    {
      if (has_auto)
      {
        f.set_auto(camera_, ARV_AUTO_CONTINUOUS, &error_);
        note(std::string("cannot switch ") + f.name + " auto on");
      }
      return;
    }
    if (has_auto)
    {
      f.set_auto(camera_, ARV_AUTO_OFF, &error_);
      note(std::string("cannot switch ") + f.name + " auto off");
    }
    if (!f.available(camera_, &error_))
    {
      takeError(error_);
      warn_(description_ + ": no " + f.control + " control; " + f.name + " ignored");
      return;
    }
    double lo = 0.0, hi = 0.0;
    f.bounds(camera_, &lo, &hi, &error_);
    takeError(error_);
    double v = value * f.scale;
    if (hi > lo && (v < lo || v > hi))
    {
      v = std::min(std::max(v, lo), hi);
      std::ostringstream msg;
      msg << description_ << ": " << f.name << " " << value << f.unit << " outside " << lo / f.scale << ".."
          << hi / f.scale << f.unit << f.note << ", using " << v / f.scale << f.unit;
      warn_(msg.str());
    }
    f.set(camera_, v, &error_);
    note(std::string("cannot set ") + f.value_name);
  }

  /** Exposure (GenICam ExposureTime is in us); 0 or less: automatic. */
  void exposure(double seconds)
  {
    const AutoFeature f{ "exposure",
                         "the exposure time",
                         "exposure time",
                         1e6,
                         " s",
                         "",
                         arv_camera_is_exposure_auto_available,
                         arv_camera_set_exposure_time_auto,
                         arv_camera_is_exposure_time_available,
                         arv_camera_get_exposure_time_bounds,
                         arv_camera_set_exposure_time };
    autoFeature(f, seconds > 0.0, seconds);
  }

  /** Gain: GenICam's Gain is in dB; cameras with GainRaw only have no unit for it. Negative: automatic. */
  void gain(double value)
  {
    const bool db = device_ && arv_device_is_feature_available(device_, "Gain", nullptr);
    const AutoFeature f{ "gain",
                         "the gain",
                         "gain",
                         1.0,
                         db ? " dB" : "",
                         db ? "" : " (GainRaw, the camera's raw units)",
                         arv_camera_is_gain_auto_available,
                         arv_camera_set_gain_auto,
                         arv_camera_is_gain_available,
                         arv_camera_get_gain_bounds,
                         arv_camera_set_gain };
    autoFeature(f, value >= 0.0, value);
  }

  /** GigE Vision transport: packet socket, packet size (negotiated, or the loopback MTU); @return
   *  true for a GigE Vision camera. */
  bool transport(const AravisOptions& o)
  {
    if (!arv_camera_is_gv_device(camera_))
      return false;
    ArvGvDevice* gv_device = ARV_GV_DEVICE(device_);
    // A packet socket (used when the process has CAP_NET_RAW) sees no packets on the loopback interface.
    const int local_mtu = localCameraMtu(arv_gv_device_get_device_address(gv_device));
    const bool loopback = local_mtu > 0 || isLoopback(arv_gv_device_get_interface_address(gv_device)) ||
                          isLoopback(arv_gv_device_get_device_address(gv_device));
    const bool packet_socket = o.packet_socket == PacketSocketMode::Auto && !loopback;
    arv_camera_gv_set_stream_options(
        camera_, packet_socket ? ARV_GV_STREAM_OPTION_NONE : ARV_GV_STREAM_OPTION_PACKET_SOCKET_DISABLED);
    if (o.packet_size > 0)
    {
      arv_camera_gv_set_packet_size(camera_, o.packet_size, &error_);
      note("cannot set the packet size to " + std::to_string(o.packet_size) + " bytes");
      const guint actual = arv_camera_gv_get_packet_size(camera_, &error_);
      takeError(error_);
      if (actual != 0 && static_cast<int>(actual) != o.packet_size)
        warn_(description_ + ": packet_size " + std::to_string(o.packet_size) + " bytes, the camera uses " +
              std::to_string(actual));
    }
    else if (!loopback)
    {
      // Aravis fires test packets of decreasing size and keeps the largest that arrives unfragmented.
      arv_camera_gv_auto_packet_size(camera_, &error_);
      note("packet size negotiation failed (set packet_size)");
    }
    else
    {
      // Loopback: nothing between host and camera fragments or drops large packets, and a camera
      // there (a simulator) may not answer test packets; take the largest packet the interface's
      // MTU and the camera allow (GevSCPSPacketSize counts the IP and UDP headers). Fewer packets
      // per frame also mean fewer incomplete frames when packets are lost.
      const int mtu = local_mtu;
      gint64 lo = 0, hi = 0;
      arv_device_get_integer_feature_bounds(device_, "GevSCPSPacketSize", &lo, &hi, &error_);
      takeError(error_);
      const gint64 current = arv_camera_gv_get_packet_size(camera_, &error_);
      takeError(error_);
      gint64 size = std::min<gint64>(mtu, kMaxPacketSize);
      if (hi > 0)
        size = std::min(size, hi);
      if (mtu > 0 && size > current && size >= std::max<gint64>(lo, kMinPacketSize))
      {
        arv_camera_gv_set_packet_size(camera_, static_cast<gint>(size), &error_);
        note("cannot set the packet size to the interface MTU (" + std::to_string(size) + " bytes)");
      }
    }
    return true;
  }

private:
  void note(const std::string& what)
  {
    const std::string m = takeError(error_);
    if (!m.empty())
      warn_(description_ + ": " + what + ": " + m);
  }

  ArvCamera* camera_;
  ArvDevice* device_;
  std::string description_;
  std::function<void(const std::string&)> warn_;
  GError* error_ = nullptr;
};
}  // namespace

struct AravisSource::Impl
{
  ArvCamera* camera = nullptr;
  ArvStream* stream = nullptr;
  gulong lost_handler = 0;
  // Shared with the teardown: Aravis' heartbeat thread may set it until the device is finalised.
  std::shared_ptr<std::atomic<bool>> control_lost = std::make_shared<std::atomic<bool>>(false);
  cv::Mat converted;
};

AravisSource::AravisSource(const std::string& camera_id, const SourceSettings& settings, const AravisOptions& options)
  : FrameSource(camera_id.empty() ? std::string("Aravis camera (first found)") : "Aravis camera " + camera_id),
    camera_id_(camera_id),
    settings_(settings),
    options_(options),
    impl_(new Impl)
{
}

AravisSource::~AravisSource()
{
  close();
}

bool AravisSource::isOpen() const
{
  return impl_->camera != nullptr;
}

void AravisSource::open()
{
  close();
  GError* error = nullptr;
  ArvCamera* camera = nullptr;
  {
    // Aravis' interface and device lists are process-wide: one discovery at a time.
    static std::mutex discovery_mutex;
    std::lock_guard<std::mutex> lock(discovery_mutex);
    if (camera_id_.rfind("Fake", 0) == 0)
      arv_enable_interface("Fake");
    camera = arv_camera_new(camera_id_.empty() ? nullptr : camera_id_.c_str(), &error);
  }
  if (!camera)
  {
    const bool not_found = error && error->domain == ARV_DEVICE_ERROR && error->code == ARV_DEVICE_ERROR_NOT_FOUND;
    const std::string message = takeError(error);
    if (not_found || message.empty())
      throw CameraError(CameraError::Kind::NotFound,
                        (camera_id_.empty() ? std::string("no GenICam camera found") : description() + " not found") +
                            " (`arv-tool-0.8` lists the cameras Aravis sees)");
    throw CameraError(CameraError::Kind::Open, "cannot open " + description() + ": " + message);
  }
  impl_->camera = camera;
  impl_->control_lost = std::make_shared<std::atomic<bool>>(false);
  ArvDevice* device = arv_camera_get_device(camera);
  if (device)
    impl_->lost_handler =
        g_signal_connect(device, "control-lost", G_CALLBACK(onControlLost), impl_->control_lost.get());

  const SourceSettings& s = settings_;
  auto note = [this](const std::string& what, GError*& e)
  {
    const std::string m = takeError(e);
    if (!m.empty())
      warn(description() + ": " + what + ": " + m);
  };
  Configurer configure(camera, description(), [this](const std::string& m) { warn(m); });
  configure.pixelFormat();
  configure.region(s);
  setNominalRate(configure.frameRate(s.rate));
  configure.exposure(s.exposure);
  configure.gain(s.gain);

  const bool gv = configure.transport(options_);

  // Stream: one set of buffers for the whole run, continuous acquisition.
  arv_camera_set_acquisition_mode(camera, ARV_ACQUISITION_MODE_CONTINUOUS, &error);
  note("cannot select continuous acquisition", error);
  impl_->stream = arv_camera_create_stream(camera, nullptr, nullptr, &error);
  if (!impl_->stream)
  {
    const std::string message = takeError(error);
    close();
    throw CameraError(CameraError::Kind::Open, "cannot create a stream for " + description() + ": " + message);
  }
  if (gv && ARV_IS_GV_STREAM(impl_->stream))
  {
    // Automatic: one payload (Aravis sets it per buffer); the kernel caps either at net.core.rmem_max.
    if (options_.socket_buffer > 0)
      g_object_set(impl_->stream, "socket-buffer", ARV_GV_STREAM_SOCKET_BUFFER_FIXED, "socket-buffer-size",
                   options_.socket_buffer, nullptr);
    else
      g_object_set(impl_->stream, "socket-buffer", ARV_GV_STREAM_SOCKET_BUFFER_AUTO, "socket-buffer-size", 0, nullptr);
    g_object_set(impl_->stream, "packet-resend", ARV_GV_STREAM_PACKET_RESEND_ALWAYS, nullptr);
  }
  const guint payload = arv_camera_get_payload(camera, &error);
  const std::string payload_error = takeError(error);
  if (payload == 0)
  {
    close();
    throw CameraError(CameraError::Kind::Open, description() + ": cannot read the payload size: " + payload_error);
  }
  for (int i = 0; i < kStreamBuffers; ++i)
    arv_stream_push_buffer(impl_->stream, arv_buffer_new_allocate(payload));
  arv_camera_start_acquisition(camera, &error);
  const std::string start_error = takeError(error);
  if (!start_error.empty())
  {
    close();
    throw CameraError(CameraError::Kind::Open, "cannot start acquisition on " + description() + ": " + start_error);
  }
}

GrabStatus AravisSource::grab(Frame& frame, std::chrono::milliseconds timeout)
{
  if (!impl_->camera || !impl_->stream)
    throw CameraError(CameraError::Kind::Lost, description() + ": not open");
  if (*impl_->control_lost)
    throw CameraError(CameraError::Kind::Lost, description() + ": connection lost");

  const guint64 timeout_us = static_cast<guint64>(std::max<std::int64_t>(0, timeout.count())) * 1000u;
  ArvBuffer* buffer = arv_stream_timeout_pop_buffer(impl_->stream, timeout_us);
  if (!buffer)
  {
    if (*impl_->control_lost)
      throw CameraError(CameraError::Kind::Lost, description() + ": connection lost");
    return GrabStatus::Timeout;
  }
  // Give the buffer back to the stream however this ends.
  struct Requeue
  {
    ArvStream* stream;
    ArvBuffer* buffer;
    ~Requeue() { arv_stream_push_buffer(stream, buffer); }
  } requeue{ impl_->stream, buffer };

  const ArvBufferStatus status = arv_buffer_get_status(buffer);
  if (status != ARV_BUFFER_STATUS_SUCCESS)
    throw CameraError(CameraError::Kind::Frame,
                      description() + ": incomplete frame (" + bufferStatusName(status) + ")");
  size_t size = 0;
  const void* data = arv_buffer_get_image_data(buffer, &size);
  const int width = arv_buffer_get_image_width(buffer);
  const int height = arv_buffer_get_image_height(buffer);
  const ArvPixelFormat format = arv_buffer_get_image_pixel_format(buffer);
  if (!data || width <= 0 || height <= 0)
    throw CameraError(CameraError::Kind::Frame, description() + ": buffer without an image");

  int cv_type = CV_8UC1;
  int bits = 8;
  int bayer = -1;
  int colour = -1;
  switch (format)
  {
    case ARV_PIXEL_FORMAT_MONO_8:
      break;
    case ARV_PIXEL_FORMAT_MONO_10:
      cv_type = CV_16UC1, bits = 10;
      break;
    case ARV_PIXEL_FORMAT_MONO_12:
      cv_type = CV_16UC1, bits = 12;
      break;
    case ARV_PIXEL_FORMAT_MONO_14:
      cv_type = CV_16UC1, bits = 14;
      break;
    case ARV_PIXEL_FORMAT_MONO_16:
      cv_type = CV_16UC1, bits = 16;
      break;
    // GenICam names the first two pixels of the first row, OpenCV the second and third of the second.
    case ARV_PIXEL_FORMAT_BAYER_RG_8:
      bayer = cv::COLOR_BayerBG2GRAY;
      break;
    case ARV_PIXEL_FORMAT_BAYER_BG_8:
      bayer = cv::COLOR_BayerRG2GRAY;
      break;
    case ARV_PIXEL_FORMAT_BAYER_GR_8:
      bayer = cv::COLOR_BayerGB2GRAY;
      break;
    case ARV_PIXEL_FORMAT_BAYER_GB_8:
      bayer = cv::COLOR_BayerGR2GRAY;
      break;
    case ARV_PIXEL_FORMAT_RGB_8_PACKED:
      cv_type = CV_8UC3, colour = cv::COLOR_RGB2GRAY;
      break;
    case ARV_PIXEL_FORMAT_BGR_8_PACKED:
      cv_type = CV_8UC3, colour = cv::COLOR_BGR2GRAY;
      break;
    default:
    {
      std::ostringstream msg;
      msg << description() << ": pixel format 0x" << std::hex << format
          << " is not supported; select Mono8 (or Mono10/12/14/16, Bayer 8 bit, RGB8, BGR8) on the camera";
      throw CameraError(CameraError::Kind::Frame, msg.str());
    }
  }
  const size_t row_bytes = static_cast<size_t>(width) * CV_ELEM_SIZE(cv_type);
  if (size < row_bytes * static_cast<size_t>(height))
    throw CameraError(CameraError::Kind::Frame, description() + ": buffer smaller than its image");
  const cv::Mat raw(height, width, cv_type, const_cast<void*>(data), row_bytes);
  if (bayer >= 0)
    cv::cvtColor(raw, frame.image, bayer);
  else if (colour >= 0)
    cv::cvtColor(raw, frame.image, colour);
  else
    sl_rig::toMono8(raw, frame.image, bits);

  const guint64 system_ns = arv_buffer_get_system_timestamp(buffer);
  frame.stamp = system_ns > 0 ? CaptureClock::time_point(std::chrono::duration_cast<CaptureClock::duration>(
                                    std::chrono::nanoseconds(system_ns)))
                              : CaptureClock::now();
  frame.sequence = arv_buffer_get_frame_id(buffer);
  frame.has_sequence = true;
  return GrabStatus::Frame;
}

void AravisSource::close()
{
  Impl& d = *impl_;
  setNominalRate(0.0);
  if (!d.camera && !d.stream)
    return;
  ArvCamera* camera = d.camera;
  ArvStream* stream = d.stream;
  const gulong handler = d.lost_handler;
  std::shared_ptr<std::atomic<bool>> lost = d.control_lost;
  d.camera = nullptr;
  d.stream = nullptr;
  d.lost_handler = 0;
  d.control_lost = std::make_shared<std::atomic<bool>>(false);

  // Every step below may wait seconds on a camera that does not answer (Aravis retries each
  // command, and joins its heartbeat thread): do them on a helper thread and wait only briefly.
  const bool dead = lost->load();
  auto state = std::make_shared<TeardownState>();
  std::thread worker(
      [camera, stream, handler, lost, dead, state]
      {
        GError* error = nullptr;
        if (camera && stream && !dead)
        {
          arv_camera_stop_acquisition(camera, &error);
          takeError(error);  // a camera that went away cannot be stopped; nothing else to do
        }
        if (stream)
          g_object_unref(stream);  // stops the stream thread, frees the buffers
        if (camera)
        {
          ArvDevice* device = arv_camera_get_device(camera);
          if (device && handler)
            g_signal_handler_disconnect(device, handler);
          g_object_unref(camera);  // leaves control, joins the heartbeat thread (the last user of *lost)
        }
        std::lock_guard<std::mutex> lock(state->mutex);
        state->done = true;
        state->done_cv.notify_all();
      });
  bool done = false;
  {
    std::unique_lock<std::mutex> lock(state->mutex);
    const auto wait = std::chrono::duration<double>(dead ? 0.0 : kCloseWait);
    done = state->done_cv.wait_for(lock, wait, [&state] { return state->done; });
  }
  if (done)
    worker.join();
  else
    worker.detach();  // it owns everything it touches and finishes on its own
}

}  // namespace sl_camera
