// The driver's /diagnostics statuses, filled from snapshots of the core and the serial link.
#pragma once

#include <cstdint>
#include <functional>
#include <mutex>
#include <string>

#include <diagnostic_updater/diagnostic_updater.h>

#include "create_driver/driver_core.h"
#include "create_driver/driver_supervisor.h"
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

/// What the driver's diagnostics read (the supervisor under its mutex).
struct DiagnosticsSources
{
  std::mutex* mutex = nullptr;
  DriverSupervisor* supervisor = nullptr;
  std::function<SerialLinkStats()> link;  ///< the serial link's counters
  SerialLinkParams link_params;
  std::string model_name;
};

/// The six statuses above, added to an updater and filled from @p sources at each update.
class DriverDiagnostics
{
public:
  DriverDiagnostics(diagnostic_updater::Updater& updater, const DiagnosticsSources& sources);

private:
  void connection(diagnostic_updater::DiagnosticStatusWrapper& st);
  void stream(diagnostic_updater::DiagnosticStatusWrapper& st);
  void control(diagnostic_updater::DiagnosticStatusWrapper& st);
  void safety(diagnostic_updater::DiagnosticStatusWrapper& st);
  void commands(diagnostic_updater::DiagnosticStatusWrapper& st);
  void battery(diagnostic_updater::DiagnosticStatusWrapper& st);

  DiagnosticsSources src_;
  uint64_t last_overruns_ = 0;
};
}  // namespace create_driver
