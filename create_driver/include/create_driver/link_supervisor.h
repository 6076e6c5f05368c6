/// @file link_supervisor.h
/// @brief State machine of the serial link: connect, start, run, detect loss, back off, retry.
#pragma once

#include <cstdint>
#include <string>

namespace create_driver
{
/// States of the serial link.
enum class LinkState : uint8_t
{
  DISCONNECTED = 0,  ///< port closed; waiting for the next attempt
  CONNECTING = 1,    ///< opening the port
  STARTING = 2,      ///< port open, start sequence sent, waiting for the first valid frame
  RUNNING = 3        ///< valid frames arrive
};

/// @brief Name of a link state ("disconnected", ...).
const char* linkStateName(LinkState state);

/// Timing of the link supervision, s.
struct LinkParams
{
  double initial_backoff = 0.25;  ///< delay before the first retry after a failure
  double max_backoff = 4.0;       ///< cap of the exponential backoff
  double start_timeout = 3.0;     ///< STARTING without a valid frame for this long -> reconnect
  double frame_timeout = 1.0;     ///< RUNNING without a valid frame for this long -> reconnect
};

/// @brief Pure state machine (time is passed in) driving the serial link.
///
/// DISCONNECTED -> CONNECTING (tick() returns OPEN once the backoff delay has passed) ->
/// STARTING (openSucceeded) -> RUNNING (validFrame). Open failures, I/O errors and frame
/// timeouts go back to DISCONNECTED and double the delay up to max_backoff; reaching RUNNING
/// resets it.
class LinkSupervisor
{
public:
  /// What the owner of the port must do after tick().
  enum class Action
  {
    NONE,
    OPEN,  ///< try to open the port, then call openSucceeded() or openFailed()
    CLOSE  ///< close the port (the state is already DISCONNECTED)
  };

  /// @brief Creates a supervisor that attempts its first connection at the first tick().
  explicit LinkSupervisor(const LinkParams& params = LinkParams());

  /// @brief Advances time; returns the action to perform.
  Action tick(double now);
  /// @brief The port is open; the start sequence is being sent.
  void openSucceeded(double now);
  /// @brief The port could not be opened.
  void openFailed(double now, const std::string& error);
  /// @brief A read/write error or EOF on the open port (the owner closes it).
  void ioError(double now, const std::string& error);
  /// @brief A valid frame arrived.
  void validFrame(double now);

  /// @brief Current state.
  LinkState state() const { return state_; }
  /// @brief Delay that will be applied after the next failure, s.
  double backoff() const { return backoff_; }
  /// @brief Time of the next connection attempt (valid in DISCONNECTED).
  double nextAttempt() const { return next_attempt_; }
  /// @brief Number of times RUNNING was reached.
  uint64_t connects() const { return connects_; }
  /// @brief Number of times an open link (STARTING or RUNNING) was lost.
  uint64_t disconnects() const { return disconnects_; }
  /// @brief Number of failed open attempts.
  uint64_t failedAttempts() const { return failed_attempts_; }
  /// @brief Description of the last failure.
  const std::string& lastError() const { return last_error_; }

private:
  void fail(double now, const std::string& error);

  LinkParams params_;
  LinkState state_ = LinkState::DISCONNECTED;
  double backoff_;
  double next_attempt_ = -1e300;
  double state_since_ = 0.0;
  double last_frame_ = 0.0;
  uint64_t connects_ = 0;
  uint64_t disconnects_ = 0;
  uint64_t failed_attempts_ = 0;
  std::string last_error_;
};

}  // namespace create_driver
