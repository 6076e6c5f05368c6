// The camera nodelet's diagnostics, filled from the capture thread's statistics.
#pragma once

#include <string>

#include <diagnostic_updater/DiagnosticStatusWrapper.h>
#include <diagnostic_updater/update_functions.h>

#include "sl_camera/camera/camera_config.h"
#include "sl_camera/camera/capture_thread.h"
#include "sl_camera/camera/unreadable_files.h"

namespace sl_camera
{
/// The "capture" status: its summary (core: captureSummary), counters, the device and its
/// transport, and the player's unreadable files (@p unreadable, null for other back-ends).
void fillCaptureStatus(const CaptureStats& stats, const CameraConfig& config, const std::string& device,
                       const UnreadableFiles* unreadable, diagnostic_updater::DiagnosticStatusWrapper& stat);

/// The "frame rate" status: the measured rate of @p frequency, unless the capture's state
/// explains the missing frames (core: rateSummary).
void fillRateStatus(const CaptureStats& stats, diagnostic_updater::FrequencyStatus& frequency,
                    diagnostic_updater::DiagnosticStatusWrapper& stat);
}  // namespace sl_camera
