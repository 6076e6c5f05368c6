/**
 * @file
 * What the camera's diagnostics say about the capture thread, and which capture errors reach the
 * log (ROS-free).
 */
#pragma once

#include <cstddef>
#include <string>

#include "sl_camera/camera/capture_thread.h"

namespace sl_camera
{

/** Level of a status, in the order of diagnostic_msgs/DiagnosticStatus (OK, WARN, ERROR). */
enum class StatusLevel
{
  Ok = 0,
  Warn = 1,
  Error = 2
};

/** A level and the one line that goes with it. */
struct StatusSummary
{
  StatusLevel level = StatusLevel::Ok;
  std::string message;
};

/** True when the capture is an error: no device, a device that fails to open, or no frames. */
bool captureFailing(const CaptureStats& stats);

/**
 * The capture's status: streaming (OK), waiting for a subscriber (OK), opened without frames yet
 * (WARN), no frame for too long (ERROR), end of playback (OK), opening (OK, or ERROR after a
 * failure), no camera (ERROR), stopped (WARN).
 */
StatusSummary captureSummary(const CaptureStats& stats);

/**
 * @p summary with the player's @p unreadable files (count): unchanged for none, otherwise at
 * least WARN and "<message>; N unreadable file(s) skipped".
 */
StatusSummary withUnreadableFiles(StatusSummary summary, std::size_t unreadable);

/**
 * The frame-rate status where the capture's state explains the missing frames (end of playback,
 * waiting for a subscriber: both OK). @return false when the measured rate is the status.
 */
bool rateSummary(const CaptureStats& stats, StatusSummary& summary);

/**
 * Why a frame of @p width x @p height px cannot be used with the rig file @p rig_file, whose camera
 * is @p rig_width x @p rig_height px (0 x 0: any size); "" when it can.
 */
std::string frameSizeError(int width, int height, int rig_width, int rig_height, const std::string& rig_file);

/**
 * Which capture errors reach the log: a new error at once, the same error again at most every
 * @p repeat_interval (the diagnostics carry it meanwhile). Times are seconds of any one clock.
 */
class ErrorLogThrottle
{
public:
  /** @param repeat_interval shortest interval between two log lines of the same error, s */
  explicit ErrorLogThrottle(double repeat_interval = 60.0) : repeat_interval_(repeat_interval) {}

  /** True (and remembered) when @p message is to be logged at @p now. */
  bool shouldLog(const std::string& message, double now);

  /**
   * Frames really arrive: the error is over, and the same error may be logged again at once.
   * @return true when an error was logged before (a recovery)
   */
  bool recover();

private:
  double repeat_interval_;
  std::string last_;
  double last_time_ = 0.0;
  bool logged_ = false;
};

}  // namespace sl_camera
