/// @file serial_link.h
/// @brief Serial transport on a worker thread (Boost.Asio serial_port) supervised by
/// LinkSupervisor: open, start, detect loss (error, EOF, silence), back off, reconnect.
#pragma once

#include <array>
#include <atomic>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/serial_port.hpp>
#include <boost/asio/steady_timer.hpp>

#include "create_driver/link_supervisor.h"
#include "create_driver/oi_commands.h"

namespace create_driver
{
/// @brief Seconds on the steady (monotonic) clock.
double steadyNow();

/// Settings of SerialLink.
struct SerialLinkParams
{
  std::string port = "/dev/ttyUSB0";  ///< device path (or a symlink to one)
  unsigned baud = 57600;
  double tick_period = 0.01;        ///< s, period of the supervision / control tick
  LinkParams link;                  ///< backoff and timeouts
  size_t max_pending_write = 4096;  ///< bytes queued for writing before the link is declared stalled

  /// @brief Checks every field.
  /// @throws std::invalid_argument whose message starts with the driver's ROS parameter of the
  ///         offending field (port, baud, control_period, reconnect_initial_delay,
  ///         reconnect_max_delay, link_timeout, start_timeout).
  void validate() const;
};

/// Snapshot of SerialLink counters.
struct SerialLinkStats
{
  LinkState state = LinkState::DISCONNECTED;
  std::string last_error;
  uint64_t connects = 0;
  uint64_t disconnects = 0;
  uint64_t failed_attempts = 0;
  uint64_t bytes_read = 0;
  uint64_t bytes_written = 0;
  uint64_t ticks = 0;
  uint64_t overruns = 0;      ///< ticks that ran more than one period late
  double max_lateness = 0.0;  ///< s, worst tick lateness seen
  double backoff = 0.0;       ///< s, delay applied after the next failure
};

/// @brief Serial port owner running on its own thread.
///
/// All handlers run on the worker thread; bytes they append to @c out are written
/// asynchronously. Writes never block the thread: when more than max_pending_write bytes are
/// queued the link is considered stalled and reconnected.
class SerialLink
{
public:
  /// Handlers called on the worker thread.
  struct Handlers
  {
    /// Port opened: append the start sequence.
    std::function<void(double now, Bytes& out)> on_open;
    /// Bytes received: return the number of valid frames they completed.
    std::function<size_t(const uint8_t* data, size_t len, double now, Bytes& out)> on_data;
    /// Periodic tick (and requestControl()) while the port is open.
    std::function<void(double now, Bytes& out)> on_tick;
    /// State changed (reason is the error for DISCONNECTED).
    std::function<void(LinkState state, const std::string& reason)> on_state;
  };

  /// @brief Prepares the link; nothing happens before start().
  SerialLink(const SerialLinkParams& params, Handlers handlers);
  /// @brief Stops without sending anything (call stop() first for a clean shutdown).
  ~SerialLink();
  SerialLink(const SerialLink&) = delete;
  SerialLink& operator=(const SerialLink&) = delete;

  /// @brief Starts the worker thread; the first connection attempt follows at once. Never blocks.
  void start();
  /// @brief Writes @p final_bytes if connected (waiting at most @p timeout_s for them to leave),
  /// closes the port and joins the worker thread.
  void stop(const Bytes& final_bytes, double timeout_s = 0.5);
  /// @brief Asks for an immediate on_tick() on the worker thread (e.g. after a new command).
  void requestControl();
  /// @brief Thread-safe snapshot of the counters.
  SerialLinkStats stats() const;
  /// @brief Settings.
  const SerialLinkParams& params() const { return params_; }

private:
  void scheduleTick();
  void onTick();
  void doOpen(double now);
  void startRead();
  void write(Bytes& out);
  void startWrite();
  void ioFailure(const std::string& error);
  void closePort();
  void notify(LinkState state, const std::string& reason);
  void updateStats();
  void finishDrain();

  SerialLinkParams params_;
  Handlers handlers_;
  LinkSupervisor supervisor_;
  boost::asio::io_context io_;
  boost::asio::executor_work_guard<boost::asio::io_context::executor_type> work_;
  boost::asio::serial_port port_;
  boost::asio::steady_timer timer_;
  std::thread thread_;
  std::chrono::steady_clock::time_point next_tick_;
  std::array<uint8_t, 512> read_buf_{};
  Bytes out_;
  Bytes pending_;
  Bytes inflight_;
  bool writing_ = false;
  uint64_t generation_ = 0;
  bool stopping_ = false;
  std::shared_ptr<std::promise<void>> drain_done_;

  mutable std::mutex stats_mutex_;
  SerialLinkStats stats_;
};

}  // namespace create_driver
