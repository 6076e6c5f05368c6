#include "driver_diagnostics.h"

#include <diagnostic_msgs/DiagnosticStatus.h>
#include <ros/time.h>

#include "create_driver/link_supervisor.h"
#include "create_driver/oi_commands.h"
#include "create_driver/safety.h"
#include "create_driver/sensor_packets.h"

namespace create_driver
{
namespace
{
using diagnostic_msgs::DiagnosticStatus;

// Summary of a diagnostic that is either fine or worth a warning.
void summarizeOkOrWarn(diagnostic_updater::DiagnosticStatusWrapper& st, bool warn, const std::string& warning)
{
  if (warn)
    st.summary(DiagnosticStatus::WARN, warning);
  else
    st.summary(DiagnosticStatus::OK, "ok");
}
}  // namespace

const char* reportedModeName(int mode)
{
  if (mode < 0 || mode > 3)
    return "unknown";
  return oiModeName(static_cast<OiMode>(mode));
}

void connectionStatus(const SerialLinkStats& ls, const SerialLinkParams& params, const std::string& model,
                      diagnostic_updater::DiagnosticStatusWrapper& st)
{
  if (ls.state == LinkState::RUNNING)
    st.summary(DiagnosticStatus::OK, "connected");
  else if (ls.state == LinkState::DISCONNECTED)
    st.summary(DiagnosticStatus::ERROR, "disconnected: " + ls.last_error);
  else
    st.summary(DiagnosticStatus::WARN, linkStateName(ls.state));
  st.add("port", params.port);
  st.add("baud", params.baud);
  st.add("model", model);
  st.add("state", linkStateName(ls.state));
  st.add("connects", ls.connects);
  st.add("disconnects", ls.disconnects);
  st.add("failed attempts", ls.failed_attempts);
  st.add("last error", ls.last_error);
  st.add("next backoff (s)", ls.backoff);
  st.add("bytes read", ls.bytes_read);
  st.add("bytes written", ls.bytes_written);
}

void streamStatus(const ParserCounters& c, std::uint64_t estimated, double rate, bool new_corrupt,
                  diagnostic_updater::DiagnosticStatusWrapper& st)
{
  summarizeOkOrWarn(st, new_corrupt, "corrupt frames on the line");
  st.add("valid frames", c.valid_frames);
  st.add("corrupt frames", c.corrupt_frames);
  st.add("total frames", c.totalFrames());
  st.add("resyncs", c.resyncs);
  st.add("discarded bytes", c.discarded_bytes);
  st.add("frames estimated", estimated);
  st.add("frame rate (Hz)", rate);
}

void controlStatus(const SerialLinkStats& ls, const DriverStats& ds, bool new_overruns,
                   diagnostic_updater::DiagnosticStatusWrapper& st)
{
  summarizeOkOrWarn(st, new_overruns, "control loop overruns");
  st.add("loop ticks", ls.ticks);
  st.add("loop overruns", ls.overruns);
  st.add("max lateness (s)", ls.max_lateness);
  st.add("commands sent", ds.commands_sent);
  st.add("rejected commands", ds.rejected_commands);
  st.add("watchdog stops", ds.watchdog_stops);
  st.add("start sequences", ds.start_sequences);
}

void safetyStatus(bool latched, Hazard reason, const DriverStats& ds, int reported_mode, OiMode requested_mode,
                  diagnostic_updater::DiagnosticStatusWrapper& st)
{
  summarizeOkOrWarn(st, latched, std::string("hazard latched: ") + hazardName(reason));
  st.add("latched", latched);
  st.add("latch reason", hazardName(reason));
  st.add("hazard stops", ds.hazard_stops);
  st.add("mode reported", reportedModeName(reported_mode));
  st.add("mode requested", oiModeName(requested_mode));
  st.add("mode re-assertions", ds.mode_reasserts);
}

void commandsStatus(const std::string& lost, double age, double command_timeout, const DriverStats& ds,
                    diagnostic_updater::DiagnosticStatusWrapper& st)
{
  if (!lost.empty())
    st.summary(DiagnosticStatus::ERROR, "robot stopped: " + lost);
  else
    st.summary(DiagnosticStatus::OK, age < 0.0 ? "no command yet" : "ok");
  st.add("command_timeout (s)", command_timeout);
  st.add("newest command age (s)", age);
  st.add("cmd_vel watchdog stops", ds.watchdog_stops);
  st.add("heartbeat stops", ds.heartbeat_stops);
}

void batteryStatus(const SensorState& s, bool have, diagnostic_updater::DiagnosticStatusWrapper& st)
{
  if (!have)
  {
    st.summary(DiagnosticStatus::STALE, "no data");
    return;
  }
  const double cap = s.get(packet::BATTERY_CAPACITY);
  const double pct = cap > 0 ? 100.0 * s.get(packet::BATTERY_CHARGE) / cap : 0.0;
  summarizeOkOrWarn(st, pct < 15.0, "battery low");
  st.add("voltage (V)", s.get(packet::VOLTAGE) / 1000.0);
  st.add("current (A)", s.get(packet::CURRENT) / 1000.0);
  st.add("charge (Ah)", s.get(packet::BATTERY_CHARGE) / 1000.0);
  st.add("capacity (Ah)", cap / 1000.0);
  st.add("percentage", pct);
  st.add("temperature (C)", s.get(packet::TEMPERATURE));
  st.add("charging state", s.get(packet::CHARGING_STATE));
}

DriverDiagnostics::DriverDiagnostics(diagnostic_updater::Updater& updater, const DiagnosticsSources& sources)
  : src_(sources)
{
  updater.setHardwareID("iRobot Create OI on " + src_.link_params.port);
  updater.add("Connection", this, &DriverDiagnostics::connection);
  updater.add("Sensor stream", this, &DriverDiagnostics::stream);
  updater.add("Control loop", this, &DriverDiagnostics::control);
  updater.add("Safety", this, &DriverDiagnostics::safety);
  updater.add("Commands", this, &DriverDiagnostics::commands);
  updater.add("Battery", this, &DriverDiagnostics::battery);
}

void DriverDiagnostics::connection(diagnostic_updater::DiagnosticStatusWrapper& st)
{
  connectionStatus(src_.link(), src_.link_params, src_.model_name, st);
}

void DriverDiagnostics::stream(diagnostic_updater::DiagnosticStatusWrapper& st)
{
  StreamReport r;
  {
    std::lock_guard<std::mutex> lock(*src_.mutex);
    r = src_.supervisor->takeStreamReport(ros::WallTime::now().toSec());
  }
  streamStatus(r.counters, r.frames_estimated, r.rate, r.new_corrupt, st);
}

void DriverDiagnostics::control(diagnostic_updater::DiagnosticStatusWrapper& st)
{
  const SerialLinkStats ls = src_.link();
  DriverStats ds;
  {
    std::lock_guard<std::mutex> lock(*src_.mutex);
    ds = src_.supervisor->core().stats();
  }
  const bool new_overruns = ls.overruns > last_overruns_;
  last_overruns_ = ls.overruns;
  controlStatus(ls, ds, new_overruns, st);
}

void DriverDiagnostics::safety(diagnostic_updater::DiagnosticStatusWrapper& st)
{
  std::lock_guard<std::mutex> lock(*src_.mutex);
  const DriverCore& core = src_.supervisor->core();
  const HazardLatch& l = core.latch();
  safetyStatus(l.latched(), l.reason(), core.stats(), core.reportedMode(), core.config().mode, st);
}

void DriverDiagnostics::commands(diagnostic_updater::DiagnosticStatusWrapper& st)
{
  std::string lost;
  double age = 0.0;
  DriverStats ds;
  double timeout = 0.0;
  {
    std::lock_guard<std::mutex> lock(*src_.mutex);
    const DriverCore& core = src_.supervisor->core();
    lost = core.commandSourceLost();
    age = core.commandAge(steadyNow());
    ds = core.stats();
    timeout = core.config().command_timeout;
  }
  commandsStatus(lost, age, timeout, ds, st);
}

void DriverDiagnostics::battery(diagnostic_updater::DiagnosticStatusWrapper& st)
{
  SensorState s;
  bool have = false;
  {
    std::lock_guard<std::mutex> lock(*src_.mutex);
    s = src_.supervisor->core().sensors();
    have = src_.supervisor->core().parserCounters().valid_frames > 0;
  }
  batteryStatus(s, have, st);
}
}  // namespace create_driver
