// create_oi_probe: talks to a Create (or create_sim) on a serial device without ROS. It sends
// Start (Passive mode: the robot cannot move), streams the driver's packet list and prints the
// decoded frames and the link counters. Reconnects like the driver does.
//
//   create_oi_probe PORT [--model create_1|create_2] [--baud N] [--seconds S]
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>

#include "create_driver/driver_core.h"
#include "create_driver/serial_link.h"
#include "create_driver/stream_parser.h"

namespace
{
std::atomic<bool> g_stop{ false };

void onSignal(int)
{
  g_stop = true;
}

int usage()
{
  std::fprintf(stderr, "usage: create_oi_probe PORT [--model create_1|create_2] [--baud N] [--seconds S]\n");
  return 2;
}

struct Options
{
  std::string port;
  create_driver::Model model = create_driver::Model::CREATE_1;
  unsigned baud = 0;     // 0: the model's default
  double seconds = 0.0;  // 0: until SIGINT / SIGTERM
};

bool parseArgs(int argc, char** argv, Options& o)
{
  if (argc < 2)
    return false;
  o.port = argv[1];
  for (int i = 2; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--model" && i + 1 < argc)
    {
      const std::string m = argv[++i];
      if (m == "create_1")
        o.model = create_driver::Model::CREATE_1;
      else if (m == "create_2")
        o.model = create_driver::Model::CREATE_2;
      else
        return false;
    }
    else if (a == "--baud" && i + 1 < argc)
      o.baud = static_cast<unsigned>(std::stoul(argv[++i]));
    else if (a == "--seconds" && i + 1 < argc)
      o.seconds = std::stod(argv[++i]);
    else
      return false;
  }
  return true;
}

void printFrame(const create_driver::StreamParser& parser)
{
  using namespace create_driver;
  const SensorState& s = parser.state();
  std::printf(
      "mode %-7s bump L%d R%d  drop L%d R%d C%d  cliff %d%d%d%d  dist %4d mm  angle %4d deg  "
      "%5.2f V %6.3f A  %d/%d mAh  frames ok %llu bad %llu\n",
      s.oiMode() >= 0 && s.oiMode() <= 3 ? oiModeName(static_cast<OiMode>(s.oiMode())) : "?", s.bumpLeft(),
      s.bumpRight(), s.wheelDropLeft(), s.wheelDropRight(), s.wheelDropCaster(), s.cliffLeft(), s.cliffFrontLeft(),
      s.cliffFrontRight(), s.cliffRight(), s.distanceMm(), s.angleDeg(), s.get(packet::VOLTAGE) / 1000.0,
      s.get(packet::CURRENT) / 1000.0, s.get(packet::BATTERY_CHARGE), s.get(packet::BATTERY_CAPACITY),
      static_cast<unsigned long long>(parser.counters().valid_frames),
      static_cast<unsigned long long>(parser.counters().corrupt_frames));
  std::fflush(stdout);
}

// Runs until a signal arrives or @p seconds (if > 0) have passed.
void waitForEnd(double seconds)
{
  const auto start = std::chrono::steady_clock::now();
  while (!g_stop)
  {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (seconds > 0.0 && std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > seconds)
      break;
  }
}
}  // namespace

int main(int argc, char** argv)
{
  using namespace create_driver;
  Options opt;
  if (!parseArgs(argc, argv, opt))
    return usage();
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);

  const std::vector<uint8_t> ids = driverStreamIds(opt.model);
  StreamParser parser(opt.model);
  parser.setExpectedIds(ids);
  double last_print = 0.0;

  SerialLinkParams params;
  params.port = opt.port;
  params.baud = opt.baud ? opt.baud : defaultBaud(opt.model);
  SerialLink::Handlers h;
  h.on_open = [&](double, Bytes& out)
  {
    parser.clearBuffer();
    appendStart(out);
    appendStream(out, ids);
  };
  h.on_data = [&](const uint8_t* data, size_t len, double now, Bytes&)
  {
    const size_t n = parser.feed(data, len);
    if (n > 0 && now - last_print >= 0.2)
    {
      last_print = now;
      printFrame(parser);
    }
    return n;
  };
  h.on_state = [&](LinkState state, const std::string& reason)
  {
    std::printf("link %s%s%s\n", linkStateName(state), reason.empty() ? "" : ": ", reason.c_str());
    std::fflush(stdout);
  };
  SerialLink link(params, h);
  link.start();
  waitForEnd(opt.seconds);
  Bytes bye;
  appendPauseResumeStream(bye, false);
  link.stop(bye, 0.5);
  const SerialLinkStats st = link.stats();
  std::printf("connects %llu, valid frames %llu, corrupt frames %llu\n", static_cast<unsigned long long>(st.connects),
              static_cast<unsigned long long>(parser.counters().valid_frames),
              static_cast<unsigned long long>(parser.counters().corrupt_frames));
  return parser.counters().valid_frames > 0 ? 0 : 1;
}
