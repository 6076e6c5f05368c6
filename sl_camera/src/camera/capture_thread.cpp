#include "sl_camera/camera/capture_thread.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace sl_camera
{

const char* captureStateName(CaptureState state)
{
  switch (state)
  {
    case CaptureState::Idle:
      return "idle";
    case CaptureState::Opening:
      return "opening";
    case CaptureState::Streaming:
      return "streaming";
    case CaptureState::Reconnecting:
      return "reconnecting";
    case CaptureState::Finished:
      return "finished";
  }
  return "unknown";
}

void CaptureOptions::validate() const
{
  auto positive = [](double v, const char* name)
  {
    if (!(v > 0.0) || !std::isfinite(v))
      throw std::invalid_argument(std::string(name) + " must be a finite time > 0 s, got " + std::to_string(v));
  };
  positive(grab_timeout, "grab_timeout");
  positive(initial_backoff, "initial_backoff");
  positive(max_backoff, "max_backoff");
  positive(stall_timeout, "stall_timeout");
  positive(first_frame_timeout, "first_frame_timeout");
  positive(frame_overdue, "frame_overdue");
  if (first_frame_timeout < stall_timeout)
    throw std::invalid_argument("first_frame_timeout must be >= stall_timeout (" + std::to_string(stall_timeout) +
                                " s), got " + std::to_string(first_frame_timeout));
  if (!(gap_tolerance >= 1.0) || !std::isfinite(gap_tolerance))
    throw std::invalid_argument("gap_tolerance must be a finite number >= 1, got " + std::to_string(gap_tolerance));
}

CaptureThread::CaptureThread(std::unique_ptr<FrameSource> source, const CaptureOptions& options, FrameCallback on_frame,
                             EventCallback on_event)
  : source_(std::move(source)),
    description_(source_ ? source_->description() : std::string()),
    options_(options),
    on_frame_(std::move(on_frame)),
    on_event_(std::move(on_event))
{
  if (!source_)
    throw std::invalid_argument("CaptureThread needs a frame source");
  options_.validate();
}

CaptureThread::~CaptureThread()
{
  stop();
  source_->close();
}

void CaptureThread::start()
{
  if (thread_.joinable())
    return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_requested_ = false;
  }
  thread_ = std::thread(&CaptureThread::run, this);
}

void CaptureThread::stop()
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_requested_ = true;
  }
  wake_.notify_all();
  // From a callback (the worker itself) only ask; the owner joins later.
  if (thread_.joinable() && thread_.get_id() != std::this_thread::get_id())
    thread_.join();
}

CaptureState CaptureThread::state() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return stats_.state;
}

CaptureStats CaptureThread::stats() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  CaptureStats s = stats_;
  if (s.state == CaptureState::Streaming)
  {
    s.have_frame = have_frame_;
    const auto since = std::chrono::steady_clock::now() - (have_frame_ ? last_frame_at_ : opened_at_);
    s.since_frame = std::max(0.0, std::chrono::duration<double>(since).count());
    s.waiting = waiting_;
    s.overdue = !waiting_ && s.since_frame > options_.frame_overdue;
  }
  return s;
}

void CaptureThread::emit(const CaptureEvent& event)
{
  if (!on_event_)
    return;
  try
  {
    on_event_(event);
  }
  catch (...)
  {
    // A logging callback must not take the capture down.
  }
}

void CaptureThread::setState(CaptureState state, const std::string& message)
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.state = state;
    if (state != CaptureState::Reconnecting)
      stats_.retry_in = 0.0;
  }
  emit(CaptureEvent{ CaptureEvent::Type::StateChanged, state, message, 0.0 });
}

void CaptureThread::fail(const std::string& message, double retry_in, bool count_open_failure)
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.state = CaptureState::Reconnecting;
    stats_.last_error = message;
    stats_.retry_in = retry_in;
    if (count_open_failure)
      ++stats_.open_failures;
  }
  emit(CaptureEvent{ CaptureEvent::Type::Error, CaptureState::Reconnecting, message, retry_in });
}

bool CaptureThread::waitFor(double seconds)
{
  std::unique_lock<std::mutex> lock(mutex_);
  if (std::isinf(seconds))
    wake_.wait(lock, [this] { return stop_requested_; });
  else
    wake_.wait_for(lock, std::chrono::duration<double>(seconds), [this] { return stop_requested_; });
  return !stop_requested_;
}

void CaptureThread::countGap(const Frame& frame)
{
  std::uint64_t lost = 0;
  if (have_previous_)
  {
    if (frame.has_sequence)
    {
      // Counters that go backwards (wrap-around, camera reset) or jump absurdly are not losses.
      const std::uint64_t step = frame.sequence - previous_sequence_;
      if (frame.sequence > previous_sequence_ && step > 1 && step < 100000)
        lost = step - 1;
    }
    else
    {
      double rate = 0.0;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        rate = stats_.nominal_rate;
      }
      const double dt = std::chrono::duration<double>(frame.stamp - previous_stamp_).count();
      const double periods = dt * rate;
      if (rate > 0.0 && periods > options_.gap_tolerance)
        lost = static_cast<std::uint64_t>(std::llround(periods)) - 1;
    }
  }
  // Unusable frames were counted already; a sequence gap includes them.
  lost = lost > unusable_since_frame_ ? lost - unusable_since_frame_ : 0;
  unusable_since_frame_ = 0;
  have_previous_ = true;
  previous_sequence_ = frame.sequence;
  previous_stamp_ = frame.stamp;
  std::lock_guard<std::mutex> lock(mutex_);
  stats_.dropped += lost;
  ++stats_.frames;
}

bool CaptureThread::stopping()
{
  std::lock_guard<std::mutex> lock(mutex_);
  return stop_requested_;
}

void CaptureThread::closeSource()
{
  try
  {
    source_->close();
  }
  catch (...)
  {
    // closing a broken device may fail; it is released either way
  }
}

CaptureThread::OpenResult CaptureThread::openSource(double& backoff)
{
  setState(CaptureState::Opening, "opening " + description_);
  try
  {
    source_->open();
    return OpenResult::Opened;
  }
  catch (const std::exception& e)
  {
    closeSource();
    const CameraError* ce = dynamic_cast<const CameraError*>(&e);
    fail(ce ? std::string(e.what()) : "cannot open " + description_ + ": " + e.what(), backoff, true);
  }
  if (!waitFor(backoff))
    return OpenResult::Stop;
  backoff = std::min(2.0 * backoff, options_.max_backoff);
  return OpenResult::Retry;
}

double CaptureThread::startStreaming()
{
  for (const std::string& w : source_->takeWarnings())
    emit(CaptureEvent{ CaptureEvent::Type::Warning, CaptureState::Opening, w, 0.0 });
  const double rate = source_->nominalRate();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.nominal_rate = rate;
    opened_at_ = std::chrono::steady_clock::now();
    have_frame_ = false;
    waiting_ = false;
  }
  std::ostringstream msg;
  msg << "opened " << description_;
  if (rate > 0.0)
    msg << " at " << rate << " Hz";
  setState(CaptureState::Streaming, msg.str());
  have_previous_ = false;
  unusable_since_frame_ = 0;
  return rate;
}

void CaptureThread::deliver(double rate, bool& have_frame, bool& streamed, double& backoff)
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    last_frame_at_ = std::chrono::steady_clock::now();
    have_frame_ = true;
    if (!have_frame && streamed)
      ++stats_.reconnects;  // counted once frames flow again, not when a dead device merely opens
  }
  if (!have_frame)
  {
    // Only now is the source known to work: the back-off starts over, and "recovered" may be said.
    have_frame = true;
    streamed = true;
    backoff = options_.initial_backoff;
    std::ostringstream first;
    first << "streaming from " << description_;
    if (rate > 0.0)
      first << " at " << rate << " Hz";
    emit(CaptureEvent{ CaptureEvent::Type::FirstFrame, CaptureState::Streaming, first.str(), 0.0 });
  }
  countGap(frame_);
  if (on_frame_)
  {
    try
    {
      on_frame_(frame_);
    }
    catch (const std::exception& e)
    {
      emit(CaptureEvent{ CaptureEvent::Type::FrameError, CaptureState::Streaming,
                         std::string("frame callback failed: ") + e.what(), 0.0 });
    }
  }
}

CaptureThread::StreamEnd CaptureThread::stream(double rate, double& backoff, bool& streamed, std::string& lost)
{
  using Clock = std::chrono::steady_clock;
  const auto grab_timeout = std::chrono::milliseconds(std::max<long>(1, std::lround(options_.grab_timeout * 1000.0)));
  Clock::time_point last_frame = Clock::now();
  bool have_frame = false;
  bool waiting = false;
  while (!stopping())
  {
    GrabStatus status = GrabStatus::Timeout;
    try
    {
      status = source_->grab(frame_, grab_timeout);
    }
    catch (const CameraError& e)
    {
      if (e.kind() != CameraError::Kind::Frame)
      {
        lost = e.what();
        return StreamEnd::Lost;
      }
      {
        std::lock_guard<std::mutex> lock(mutex_);
        ++stats_.dropped;
        stats_.last_error = e.what();
      }
      ++unusable_since_frame_;
      // An unusable frame still shows that the device is there: not a stall (the diagnostics
      // still see no good frame).
      last_frame = Clock::now();
      emit(CaptureEvent{ CaptureEvent::Type::FrameError, CaptureState::Streaming, e.what(), 0.0 });
    }
    catch (const std::exception& e)
    {
      lost = description_ + ": " + e.what();
      return StreamEnd::Lost;
    }

    const Clock::time_point now = Clock::now();
    const bool now_waiting = status == GrabStatus::Timeout && source_->waiting();
    if (now_waiting || waiting)
    {
      // Held on purpose (a player before its start): no stall, and the wait for the first frame
      // counts from the end of the hold.
      std::lock_guard<std::mutex> lock(mutex_);
      waiting_ = now_waiting;
      if (now_waiting)
        opened_at_ = now;
    }
    waiting = now_waiting;
    if (waiting)
    {
      last_frame = now;
      continue;
    }
    if (status == GrabStatus::Frame)
    {
      last_frame = now;
      deliver(rate, have_frame, streamed, backoff);
    }
    else if (status == GrabStatus::EndOfStream)
    {
      return StreamEnd::Finished;
    }
    const double limit = have_frame ? options_.stall_timeout : options_.first_frame_timeout;
    if (std::chrono::duration<double>(now - last_frame).count() > limit)
    {
      std::ostringstream stall;
      stall << description_ << ": no frame for " << limit << " s";
      if (!have_frame)
        stall << " after opening";
      lost = stall.str();
      return StreamEnd::Lost;
    }
  }
  return StreamEnd::Stopped;
}

void CaptureThread::run()
{
  using Clock = std::chrono::steady_clock;
  double backoff = options_.initial_backoff;
  bool streamed = false;  // has the source delivered frames before (so that a new open is a reconnect)?
  while (!stopping())
  {
    const OpenResult opened = openSource(backoff);
    if (opened == OpenResult::Stop)
      break;
    if (opened == OpenResult::Retry)
      continue;
    const double rate = startStreaming();
    std::string lost;
    const StreamEnd end = stream(rate, backoff, streamed, lost);
    if (end == StreamEnd::Finished)
    {
      closeSource();
      setState(CaptureState::Finished, "end of " + description_);
      waitFor(std::numeric_limits<double>::infinity());
      break;
    }
    if (end == StreamEnd::Stopped)
    {
      closeSource();
      break;
    }
    // Report first: closing a device that is gone may take a while.
    fail(lost, backoff, false);
    const Clock::time_point close_start = Clock::now();
    closeSource();
    const double close_time = std::chrono::duration<double>(Clock::now() - close_start).count();
    if (!waitFor(std::max(0.0, backoff - close_time)))
      break;
    backoff = std::min(2.0 * backoff, options_.max_backoff);
  }
  closeSource();
  setState(CaptureState::Idle, "stopped capturing from " + description_);
}

}  // namespace sl_camera
