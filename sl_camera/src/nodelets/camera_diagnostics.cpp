#include "camera_diagnostics.h"

#include "sl_camera/camera/capture_status.h"

namespace sl_camera
{
namespace
{
/// Names shown in the diagnostics of the files the player could not read.
constexpr std::size_t kUnreadableNamesShown = 5;

using diagnostic_msgs::DiagnosticStatus;
static_assert(static_cast<int>(StatusLevel::Ok) == DiagnosticStatus::OK, "StatusLevel::Ok");
static_assert(static_cast<int>(StatusLevel::Warn) == DiagnosticStatus::WARN, "StatusLevel::Warn");
static_assert(static_cast<int>(StatusLevel::Error) == DiagnosticStatus::ERROR, "StatusLevel::Error");

void setSummary(const StatusSummary& s, diagnostic_updater::DiagnosticStatusWrapper& stat)
{
  stat.summary(static_cast<unsigned char>(s.level), s.message);
}

void addTransport(const AravisOptions& a, diagnostic_updater::DiagnosticStatusWrapper& stat)
{
  stat.add("packet socket", packetSocketModeName(a.packet_socket));
  stat.add("socket buffer (bytes)", a.socket_buffer > 0 ? std::to_string(a.socket_buffer) : std::string("auto"));
  stat.add("packet size (bytes)", a.packet_size > 0 ? std::to_string(a.packet_size) : std::string("auto"));
}
}  // namespace

void fillCaptureStatus(const CaptureStats& s, const CameraConfig& config, const std::string& device,
                       const UnreadableFiles* unreadable, diagnostic_updater::DiagnosticStatusWrapper& stat)
{
  const StatusSummary summary = captureSummary(s);
  setSummary(summary, stat);
  stat.add("state", captureStateName(s.state));
  stat.add("backend", cameraBackendName(config.backend));
  stat.add("device", device.empty() ? std::string("(first camera)") : device);
  stat.add("frames", s.frames);
  stat.add("dropped frames", s.dropped);
  stat.add("reconnects", s.reconnects);
  stat.add("failed opens", s.open_failures);
  stat.add("device rate (Hz)", s.nominal_rate);
  stat.add("last error", s.last_error.empty() ? std::string("none") : s.last_error);
  if (s.state == CaptureState::Streaming)
    stat.addf("since last frame (s)", "%.2f", s.since_frame);
  if (config.backend == CameraBackend::Aravis)
    addTransport(config.aravis, stat);
  if (unreadable)
  {
    // The names (the first few) are here as well as in the log, so they can be found later.
    const std::size_t n = unreadable->count();
    stat.add("unreadable files", unreadable->summary(kUnreadableNamesShown));
    stat.add("unreadable file count", n);
    setSummary(withUnreadableFiles(summary, n), stat);
  }
}

void fillRateStatus(const CaptureStats& stats, diagnostic_updater::FrequencyStatus& frequency,
                    diagnostic_updater::DiagnosticStatusWrapper& stat)
{
  frequency.run(stat);
  StatusSummary summary;
  if (rateSummary(stats, summary))
    setSummary(summary, stat);
}
}  // namespace sl_camera
