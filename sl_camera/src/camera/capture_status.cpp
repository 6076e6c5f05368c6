#include "sl_camera/camera/capture_status.h"

#include <algorithm>
#include <cstdio>

namespace sl_camera
{
namespace
{
/** "<text> <seconds with one decimal> s". */
std::string withSeconds(const char* text, double seconds)
{
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.1f", seconds);
  return std::string(text) + buffer + " s";
}

StatusSummary streamingSummary(const CaptureStats& s)
{
  // Open is not enough: without frames the camera is of no use (ERROR, not OK).
  if (s.waiting)
    return { StatusLevel::Ok, "waiting for a subscriber to start playback" };
  if (s.overdue && s.have_frame)
    return { StatusLevel::Error, withSeconds("no frame for ", s.since_frame) };
  if (s.overdue)
    return { StatusLevel::Error, withSeconds("opened, but no frame for ", s.since_frame) };
  if (!s.have_frame)
    return { StatusLevel::Warn, "opened, waiting for the first frame" };
  return { StatusLevel::Ok, "streaming" };
}
}  // namespace

bool captureFailing(const CaptureStats& s)
{
  return s.state == CaptureState::Reconnecting || (s.state == CaptureState::Streaming && s.overdue) ||
         (s.state == CaptureState::Opening && (s.open_failures > 0 || !s.last_error.empty()));
}

StatusSummary captureSummary(const CaptureStats& s)
{
  switch (s.state)
  {
    case CaptureState::Streaming:
      return streamingSummary(s);
    case CaptureState::Finished:
      return { StatusLevel::Ok, "end of playback" };
    case CaptureState::Opening:
      if (s.open_failures > 0 || !s.last_error.empty())
        return { StatusLevel::Error, "opening again after: " + s.last_error };
      return { StatusLevel::Ok, "opening" };
    case CaptureState::Reconnecting:
      return { StatusLevel::Error, "no camera: " + s.last_error };
    case CaptureState::Idle:
      break;
  }
  return { StatusLevel::Warn, "stopped" };
}

StatusSummary withUnreadableFiles(StatusSummary summary, std::size_t unreadable)
{
  if (unreadable == 0)
    return summary;
  summary.level = std::max(summary.level, StatusLevel::Warn);
  summary.message += "; " + std::to_string(unreadable) + " unreadable file" + (unreadable == 1 ? "" : "s") + " skipped";
  return summary;
}

bool rateSummary(const CaptureStats& s, StatusSummary& summary)
{
  if (s.state == CaptureState::Finished)
    summary = { StatusLevel::Ok, "end of playback, no more frames" };
  else if (s.state == CaptureState::Streaming && s.waiting)
    summary = { StatusLevel::Ok, "waiting for a subscriber to start playback" };
  else
    return false;
  return true;
}

std::string frameSizeError(int width, int height, int rig_width, int rig_height, const std::string& rig_file)
{
  if (rig_width <= 0 || (width == rig_width && height == rig_height))
    return std::string();
  return "the camera delivers " + std::to_string(width) + " x " + std::to_string(height) + " px but the rig file " +
         rig_file + " is for " + std::to_string(rig_width) + " x " + std::to_string(rig_height) + " px";
}

bool ErrorLogThrottle::shouldLog(const std::string& message, double now)
{
  if (logged_ && message == last_ && now - last_time_ <= repeat_interval_)
    return false;
  last_ = message;
  last_time_ = now;
  logged_ = true;
  return true;
}

bool ErrorLogThrottle::recover()
{
  const bool recovered = !last_.empty();
  last_.clear();
  logged_ = false;
  return recovered;
}

}  // namespace sl_camera
