// The driver's /diagnostics statuses, filled from snapshots of the core and the serial link.
#pragma once

#include <cstdint>
#include <string>

#include <diagnostic_updater/DiagnosticStatusWrapper.h>

#include "create_driver/driver_core.h"
#include "create_driver/serial_link.h"

namespace create_driver
{
/// Name of a mode as the robot reports it (packet 35; "unknown" outside 0..3).
const char* reportedModeName(int mode);

/// *Connection*: the link state (OK running, ERROR disconnected, WARN in between) and its counters.
void connectionStatus(const SerialLinkStats& ls, const SerialLinkParams& params, const std::string& model,
                      diagnostic_updater::DiagnosticStatusWrapper& st);

/// *Sensor stream*: frame counters and @p rate (Hz); WARN when @p new_corrupt frames came since the last report.
void streamStatus(const ParserCounters& c, std::uint64_t estimated, double rate, bool new_corrupt,
                  diagnostic_updater::DiagnosticStatusWrapper& st);

/// *Control loop*: ticks, overruns (WARN when @p new_overruns) and command counters.
void controlStatus(const SerialLinkStats& ls, const DriverStats& ds, bool new_overruns,
                   diagnostic_updater::DiagnosticStatusWrapper& st);

/// *Safety*: the hazard latch (WARN while latched), hazard stops, the reported and requested modes.
void safetyStatus(bool latched, Hazard reason, const DriverStats& ds, int reported_mode, OiMode requested_mode,
                  diagnostic_updater::DiagnosticStatusWrapper& st);

/// *Commands*: ERROR "robot stopped: @p lost" after a watchdog stop (until the next command), the
/// newest command's @p age (s, negative: none yet) and the stop counters.
void commandsStatus(const std::string& lost, double age, double command_timeout, const DriverStats& ds,
                    diagnostic_updater::DiagnosticStatusWrapper& st);

/// *Battery*: from the sensors @p s (STALE without @p have data); WARN below 15 %.
void batteryStatus(const SensorState& s, bool have, diagnostic_updater::DiagnosticStatusWrapper& st);
}  // namespace create_driver
