/**
 * @file
 * Runs a FrameSource on a worker thread: one initialisation, continuous capture, recovery.
 */
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "sl_camera/camera/frame_source.h"

namespace sl_camera
{

/** States of the capture thread. */
enum class CaptureState
{
  Idle,          ///< not started, or stopped
  Opening,       ///< opening and configuring the source
  Streaming,     ///< grabbing frames
  Reconnecting,  ///< the source failed (or was not there); waiting the back-off before opening again
  Finished       ///< the source reached its end (player without loop); the thread idles until stop()
};

/** Name of a state, e.g. "streaming". */
const char* captureStateName(CaptureState state);

/** Timing of the capture thread (s). */
struct CaptureOptions
{
  /** Longest single wait inside the source; bounds how long stop() takes for well-behaved sources. */
  double grab_timeout = 0.1;
  /** First wait after a failure; doubled after every failed open, up to max_backoff. */
  double initial_backoff = 0.25;
  /** Longest wait between two attempts to open. */
  double max_backoff = 4.0;
  /** A streaming source that delivers nothing for this long is treated as lost (closed and re-opened). */
  double stall_timeout = 1.0;
  /** The same for the first frame after opening (>= stall_timeout). */
  double first_frame_timeout = 2.0;
  /** Time without a frame after which CaptureStats::overdue is set (for diagnostics), s. */
  double frame_overdue = 0.5;
  /** Frames counted as dropped when the gap between two stamps exceeds this many nominal periods. */
  double gap_tolerance = 1.5;

  /**
   * @throws std::invalid_argument naming the first field that is not finite and > 0 (or >= 1 for
   * gap_tolerance, >= stall_timeout for first_frame_timeout).
   */
  void validate() const;
};

/** Counters and state, as a consistent snapshot. */
struct CaptureStats
{
  CaptureState state = CaptureState::Idle;
  std::uint64_t frames = 0;         ///< frames delivered to the callback
  std::uint64_t dropped = 0;        ///< frames lost: sequence or timestamp gaps, and unusable frames
  std::uint64_t reconnects = 0;     ///< times the source was opened again after it had streamed and failed
  std::uint64_t open_failures = 0;  ///< failed attempts to open
  std::string last_error;           ///< the latest error message ("" if none yet)
  double nominal_rate = 0.0;        ///< rate the open source reports, Hz (0: unknown)
  double retry_in = 0.0;            ///< back-off of the current wait in Reconnecting, s
  bool have_frame = false;          ///< Streaming: a frame arrived since the source was opened
  double since_frame = 0.0;         ///< Streaming: s since the last frame (or since opening, without one)
  bool overdue = false;             ///< Streaming: since_frame > CaptureOptions::frame_overdue
  bool waiting = false;             ///< Streaming: the source holds back its frames on purpose (FrameSource::waiting)
};

/** Something worth logging that happened on the capture thread. */
struct CaptureEvent
{
  enum class Type
  {
    StateChanged,  ///< the state changed; message describes it
    FirstFrame,    ///< the first frame after opening arrived: the source really streams (again)
    Error,         ///< open failed, or the source was lost; message names the device
    FrameError,    ///< one frame was unusable; message names it (may come every frame: throttle)
    Warning        ///< a setting the device refused or adjusted
  };
  Type type;
  CaptureState state;  ///< state after the event
  std::string message;
  double retry_in = 0.0;  ///< for errors that lead to a retry: the wait before it, s
};

/**
 * Owns a FrameSource and drives it on a worker thread through the states
 * Idle -> Opening -> Streaming -> (failure) Reconnecting -> Opening -> ...,
 * with an exponential back-off (initial_backoff doubling up to max_backoff) between attempts.
 * The source is opened once and read continuously; it is only re-opened after it failed: a Lost
 * error, or no frame for stall_timeout (first_frame_timeout right after opening). The back-off
 * starts over only once a frame arrived, so a device that opens but never streams is retried
 * at the slow rate. A failure is reported (state Reconnecting, Error event) before the source is
 * closed, so a close that takes long does not delay the report.
 *
 * Frames and events are delivered through callbacks on the worker thread; the frame passed to the
 * frame callback is reused for the next grab, so copy what you keep. Exceptions thrown by the
 * callbacks are caught and reported as frame errors. Public methods never block for long: stop()
 * waits for the current grab (bounded by grab_timeout, or the back-end's own read timeout).
 */
class CaptureThread
{
public:
  /** Called with every frame (mono8). */
  using FrameCallback = std::function<void(const Frame&)>;
  /** Called with every event. */
  using EventCallback = std::function<void(const CaptureEvent&)>;

  /**
   * @param source the source to drive (not open)
   * @throws std::invalid_argument when source is null or options are invalid
   */
  CaptureThread(std::unique_ptr<FrameSource> source, const CaptureOptions& options, FrameCallback on_frame,
                EventCallback on_event = EventCallback());
  /** Stops the thread (see stop()). */
  ~CaptureThread();

  CaptureThread(const CaptureThread&) = delete;
  CaptureThread& operator=(const CaptureThread&) = delete;

  /** Starts the worker thread (returns at once; the source is opened on the worker). No-op if running. */
  void start();
  /** Asks the worker to stop, waits for it and closes the source. Safe to call more than once. */
  void stop();

  /** Current state. */
  CaptureState state() const;
  /** Snapshot of state and counters. */
  CaptureStats stats() const;
  /** Description of the source (from FrameSource::description()). */
  const std::string& sourceDescription() const { return description_; }

private:
  enum class OpenResult
  {
    Opened,
    Retry,  ///< failed; the back-off was waited
    Stop    ///< failed, and stop was requested while waiting
  };
  enum class StreamEnd
  {
    Stopped,   ///< stop requested
    Finished,  ///< end of a recording
    Lost       ///< the source failed or stalled
  };
  void run();
  /// One attempt to open the source; on failure it is reported and the back-off waited (and doubled).
  OpenResult openSource(double& backoff);
  /// After a successful open: stats, warnings, state Streaming. @return the source's nominal rate.
  double startStreaming();
  /// Grabs until stop, the end of a recording or a lost source (@p lost says why). @p backoff
  /// restarts and @p streamed is set at the first frame.
  StreamEnd stream(double rate, double& backoff, bool& streamed, std::string& lost);
  /// A frame was grabbed: stats, the first-frame event (first of this open), the gap count, the callback.
  void deliver(double rate, bool& have_frame, bool& streamed, double& backoff);
  bool stopping();
  void closeSource();
  void setState(CaptureState state, const std::string& message);
  void emit(const CaptureEvent& event);
  void fail(const std::string& message, double retry_in, bool count_open_failure);
  bool waitFor(double seconds);  ///< false when stop was requested
  void countGap(const Frame& frame);

  std::unique_ptr<FrameSource> source_;
  const std::string description_;
  const CaptureOptions options_;
  FrameCallback on_frame_;
  EventCallback on_event_;

  mutable std::mutex mutex_;  ///< guards stats_ and stop_requested_
  std::condition_variable wake_;
  CaptureStats stats_;
  bool stop_requested_ = false;
  std::thread thread_;

  // Worker-thread only.
  Frame frame_;
  bool have_previous_ = false;
  std::uint64_t previous_sequence_ = 0;
  CaptureClock::time_point previous_stamp_;
  std::uint64_t unusable_since_frame_ = 0;  ///< frame errors since the last good frame (part of its gap)

  // Guarded by mutex_: when the current stream was opened and when its last frame arrived.
  std::chrono::steady_clock::time_point opened_at_;
  std::chrono::steady_clock::time_point last_frame_at_;
  bool have_frame_ = false;
  bool waiting_ = false;  ///< the source was waiting at the latest grab
};

}  // namespace sl_camera
