// CaptureThread: the state machine against a fake source that is missing, fails, vanishes and comes
// back; counters; back-off; prompt stop.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "sl_camera/camera/capture_thread.h"

using sl_camera::CameraError;
using sl_camera::CaptureClock;
using sl_camera::CaptureEvent;
using sl_camera::CaptureOptions;
using sl_camera::CaptureState;
using sl_camera::CaptureStats;
using sl_camera::CaptureThread;
using sl_camera::Frame;
using sl_camera::FrameSource;
using sl_camera::GrabStatus;

namespace
{
/// One scripted result of grab().
struct Step
{
  enum Kind
  {
    Image,
    Bad,
    End
  } kind;
  std::uint64_t sequence = 0;
  bool has_sequence = true;
  double t = 0.0;  ///< stamp, s after the script's base time
};

/// What the test controls about the fake camera, shared with the source on the capture thread.
struct FakeDevice
{
  std::atomic<bool> present{ true };
  std::atomic<bool> stalled{ false };
  std::atomic<bool> holding{ false };  ///< delivers nothing on purpose (waiting() is true), like a held player
  std::atomic<int> opens{ 0 };
  std::atomic<int> closes{ 0 };
  std::atomic<bool> close_blocks{ false };  ///< close() waits until this is false again (a dead device)
  std::atomic<bool> closing{ false };       ///< close() is running
  double rate = 0.0;
  bool warn_on_open = false;
  bool free_run = true;  ///< after the script: frames forever (false: end of stream)
  std::mutex mutex;
  std::deque<Step> script;
};

class FakeSource : public FrameSource
{
public:
  explicit FakeSource(std::shared_ptr<FakeDevice> device)
    : FrameSource("fake camera /dev/fake0"), device_(std::move(device))
  {
  }
  void open() override
  {
    ++device_->opens;
    if (!device_->present)
      throw CameraError(CameraError::Kind::NotFound, "fake camera /dev/fake0 does not exist");
    open_ = true;
    setNominalRate(device_->rate);
    if (device_->warn_on_open)
      warn("fake camera /dev/fake0: gain ignored");
  }
  GrabStatus grab(Frame& frame, std::chrono::milliseconds timeout) override
  {
    if (!open_)
      throw CameraError(CameraError::Kind::Lost, "fake camera /dev/fake0: not open");
    if (!device_->present)
      throw CameraError(CameraError::Kind::Lost, "fake camera /dev/fake0 disappeared");
    if (device_->holding || device_->stalled)
    {
      std::this_thread::sleep_for(std::min(timeout, std::chrono::milliseconds(5)));
      return GrabStatus::Timeout;
    }
    frame.image.create(4, 4, CV_8UC1);
    Step step{ Step::Image, next_sequence_, true, 0.0 };
    bool scripted = false;
    {
      std::lock_guard<std::mutex> lock(device_->mutex);
      if (!device_->script.empty())
      {
        step = device_->script.front();
        device_->script.pop_front();
        scripted = true;
      }
    }
    if (!scripted)
    {
      if (!device_->free_run)
        return GrabStatus::EndOfStream;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    switch (step.kind)
    {
      case Step::Bad:
        throw CameraError(CameraError::Kind::Frame, "fake camera /dev/fake0: incomplete frame");
      case Step::End:
        return GrabStatus::EndOfStream;
      case Step::Image:
        break;
    }
    frame.sequence = step.sequence;
    frame.has_sequence = step.has_sequence;
    frame.stamp =
        scripted ? base_ + std::chrono::duration_cast<CaptureClock::duration>(std::chrono::duration<double>(step.t))
                 : CaptureClock::now();
    next_sequence_ = step.sequence + 1;
    return GrabStatus::Frame;
  }
  void close() override
  {
    device_->closing = true;
    while (device_->close_blocks)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    if (open_)
      ++device_->closes;
    open_ = false;
    device_->closing = false;
  }
  bool isOpen() const override { return open_; }
  bool waiting() const override { return open_ && device_->holding; }

private:
  std::shared_ptr<FakeDevice> device_;
  bool open_ = false;
  std::uint64_t next_sequence_ = 0;
  CaptureClock::time_point base_ = CaptureClock::now();
};

/// Polls @p done until it holds or a generous timeout passes (never a timing assertion).
bool waitUntil(const std::function<bool()>& done, double timeout_s = 20.0)
{
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < end)
  {
    if (done())
      return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return done();
}

/// @p o with retries after @p initial_backoff s, doubling up to @p max_backoff s.
CaptureOptions withBackoff(CaptureOptions o, double initial_backoff, double max_backoff)
{
  o.initial_backoff = initial_backoff;
  o.max_backoff = max_backoff;
  return o;
}

/// Short grabs and retries; stall and first-frame timeouts long enough never to fire by accident.
CaptureOptions fastOptions()
{
  CaptureOptions o;
  o.grab_timeout = 0.02;
  o.stall_timeout = 5.0;
  o.first_frame_timeout = 5.0;
  return withBackoff(o, 0.005, 0.02);
}

/// Records events and frames delivered by a CaptureThread.
struct Recorder
{
  std::mutex mutex;
  std::vector<CaptureEvent> events;
  std::vector<std::uint64_t> sequences;

  CaptureThread::FrameCallback frames()
  {
    return [this](const Frame& f)
    {
      std::lock_guard<std::mutex> lock(mutex);
      sequences.push_back(f.sequence);
    };
  }
  CaptureThread::EventCallback eventsCallback()
  {
    return [this](const CaptureEvent& e)
    {
      std::lock_guard<std::mutex> lock(mutex);
      events.push_back(e);
    };
  }
  std::vector<CaptureEvent> eventsOf(CaptureEvent::Type type)
  {
    std::lock_guard<std::mutex> lock(mutex);
    std::vector<CaptureEvent> out;
    for (const auto& e : events)
      if (e.type == type)
        out.push_back(e);
    return out;
  }
};

/// The fake camera of a test (device_), what its capture thread delivered (rec_), and the thread.
class CameraCaptureThread : public ::testing::Test
{
protected:
  std::unique_ptr<FrameSource> fakeSource() { return std::unique_ptr<FrameSource>(new FakeSource(device_)); }

  /// A capture thread on a FakeSource of device_ that records its frames and events in rec_.
  CaptureThread recordedCapture(const CaptureOptions& o = fastOptions())
  {
    return CaptureThread(fakeSource(), o, rec_.frames(), rec_.eventsCallback());
  }

  std::shared_ptr<FakeDevice> device_ = std::make_shared<FakeDevice>();
  Recorder rec_;
};
}  // namespace

TEST_F(CameraCaptureThread, MissingDeviceAtStartIsReportedAndRetriedUntilItAppears)
{
  device_->present = false;
  CaptureThread capture = recordedCapture();
  EXPECT_EQ(capture.state(), CaptureState::Idle);
  capture.start();  // returns at once; opening happens on the worker
  ASSERT_TRUE(waitUntil([&] { return capture.stats().open_failures >= 3; }));
  sl_camera::CaptureStats s = capture.stats();
  EXPECT_NE(s.state, CaptureState::Streaming);
  EXPECT_EQ(s.frames, 0u);
  EXPECT_NE(s.last_error.find("/dev/fake0 does not exist"), std::string::npos) << s.last_error;
  const auto errors = rec_.eventsOf(CaptureEvent::Type::Error);
  ASSERT_FALSE(errors.empty());
  EXPECT_NE(errors.front().message.find("/dev/fake0"), std::string::npos);
  EXPECT_EQ(errors.front().state, CaptureState::Reconnecting);

  device_->present = true;
  ASSERT_TRUE(waitUntil([&] { return capture.stats().frames >= 5; }));
  s = capture.stats();
  EXPECT_EQ(s.state, CaptureState::Streaming);
  EXPECT_EQ(s.reconnects, 0u) << "the first successful open is not a reconnect";
  EXPECT_EQ(s.dropped, 0u);
  capture.stop();
  EXPECT_EQ(capture.state(), CaptureState::Idle);
  EXPECT_EQ(device_->opens - 1, static_cast<int>(capture.stats().open_failures));
  EXPECT_EQ(device_->closes.load(), 1);
}

TEST_F(CameraCaptureThread, DeviceThatDisappearsIsReopenedWhenItComesBack)
{
  CaptureThread capture = recordedCapture();
  capture.start();
  ASSERT_TRUE(waitUntil([&] { return capture.stats().frames >= 3; }));
  EXPECT_EQ(device_->opens.load(), 1) << "one initialisation for the whole stream";

  device_->present = false;  // unplugged
  ASSERT_TRUE(waitUntil([&] { return capture.stats().open_failures >= 2; }));
  sl_camera::CaptureStats s = capture.stats();
  EXPECT_NE(s.state, CaptureState::Streaming);
  EXPECT_EQ(s.reconnects, 0u);
  const auto errors = rec_.eventsOf(CaptureEvent::Type::Error);
  ASSERT_FALSE(errors.empty());
  EXPECT_NE(errors.front().message.find("/dev/fake0 disappeared"), std::string::npos) << errors.front().message;
  EXPECT_GE(device_->closes.load(), 1) << "a lost device is closed before it is opened again";
  const std::uint64_t frames_before = s.frames;

  device_->present = true;  // plugged in again
  ASSERT_TRUE(waitUntil(
      [&]
      {
        const auto st = capture.stats();
        return st.reconnects == 1 && st.state == CaptureState::Streaming && st.frames >= frames_before + 3;
      }));
  capture.stop();
  s = capture.stats();
  EXPECT_EQ(s.reconnects, 1u);
  EXPECT_EQ(s.dropped, 0u);
  EXPECT_EQ(device_->opens.load(), static_cast<int>(2 + s.open_failures));
  // The worker closed what it opened.
  EXPECT_EQ(device_->closes.load(), 2);
}

TEST_F(CameraCaptureThread, CountsSequenceGapsAndBadFramesAsDropped)
{
  device_->free_run = false;
  for (std::uint64_t seq : { 10u, 11u, 12u, 15u, 16u })
    device_->script.push_back(Step{ Step::Image, seq, true, 0.0 });
  device_->script.push_back(Step{ Step::Bad, 0, true, 0.0 });
  device_->script.push_back(Step{ Step::Image, 17, true, 0.0 });
  device_->script.push_back(Step{ Step::Bad, 0, true, 0.0 });     // frame 18, incomplete
  device_->script.push_back(Step{ Step::Image, 19, true, 0.0 });  // its gap is that frame: counted once
  device_->script.push_back(Step{ Step::Image, 3, true, 0.0 });   // counter reset: not a loss
  device_->script.push_back(Step{ Step::Image, 4, true, 0.0 });
  CaptureThread capture = recordedCapture();
  capture.start();
  ASSERT_TRUE(waitUntil([&] { return capture.state() == CaptureState::Finished; }));
  const sl_camera::CaptureStats s = capture.stats();
  EXPECT_EQ(s.frames, 9u);
  EXPECT_EQ(s.dropped, 2u + 1u + 1u);
  EXPECT_EQ(s.reconnects, 0u);
  EXPECT_EQ(s.open_failures, 0u);
  EXPECT_NE(s.last_error.find("incomplete frame"), std::string::npos);
  EXPECT_EQ(rec_.eventsOf(CaptureEvent::Type::FrameError).size(), 2u);
  {
    std::lock_guard<std::mutex> lock(rec_.mutex);
    EXPECT_EQ(rec_.sequences, (std::vector<std::uint64_t>{ 10, 11, 12, 15, 16, 17, 19, 3, 4 }));
  }
  EXPECT_EQ(device_->opens.load(), 1) << "the end of a recording is not a failure";
  capture.stop();
  EXPECT_EQ(capture.state(), CaptureState::Idle);
}

TEST_F(CameraCaptureThread, CountsTimestampGapsWhenTheSourceHasNoSequence)
{
  device_->free_run = false;
  device_->rate = 100.0;  // 10 ms per frame
  for (double t : { 0.0, 0.010, 0.020, 0.050, 0.060, 0.071 })
    device_->script.push_back(Step{ Step::Image, 0, false, t });
  CaptureThread capture(fakeSource(), fastOptions(), nullptr);
  capture.start();
  ASSERT_TRUE(waitUntil([&] { return capture.state() == CaptureState::Finished; }));
  const sl_camera::CaptureStats s = capture.stats();
  EXPECT_EQ(s.frames, 6u);
  EXPECT_EQ(s.dropped, 2u);  // 20 -> 50 ms: two frames missing; 60 -> 71 ms is jitter
  EXPECT_DOUBLE_EQ(s.nominal_rate, 100.0);
}

TEST_F(CameraCaptureThread, BackoffDoublesUpToTheCap)
{
  device_->present = false;
  const CaptureOptions o = withBackoff(fastOptions(), 0.001, 0.004);
  CaptureThread capture(fakeSource(), o, nullptr, rec_.eventsCallback());
  capture.start();
  ASSERT_TRUE(waitUntil([&] { return rec_.eventsOf(CaptureEvent::Type::Error).size() >= 5; }));
  capture.stop();
  const auto errors = rec_.eventsOf(CaptureEvent::Type::Error);
  const std::vector<double> expected{ 0.001, 0.002, 0.004, 0.004, 0.004 };
  for (size_t i = 0; i < expected.size(); ++i)
    EXPECT_DOUBLE_EQ(errors[i].retry_in, expected[i]) << "attempt " << i;
}

TEST_F(CameraCaptureThread, StalledSourceIsTreatedAsLostAndReopened)
{
  CaptureOptions o = fastOptions();
  o.stall_timeout = 0.05;
  CaptureThread capture = recordedCapture(o);
  capture.start();
  ASSERT_TRUE(waitUntil([&] { return capture.stats().frames >= 2; }));
  device_->stalled = true;
  ASSERT_TRUE(waitUntil([&] { return capture.stats().last_error.find("no frame for") != std::string::npos; }));
  EXPECT_NE(capture.stats().last_error.find("/dev/fake0"), std::string::npos);
  const std::uint64_t frames_before = capture.stats().frames;
  device_->stalled = false;
  ASSERT_TRUE(waitUntil(
      [&]
      {
        const auto st = capture.stats();
        return st.reconnects >= 1 && st.state == CaptureState::Streaming && st.frames >= frames_before + 3;
      }));
  capture.stop();
  EXPECT_GE(device_->opens.load(), 2);
}

TEST_F(CameraCaptureThread, StopReturnsDuringALongBackoff)
{
  device_->present = false;
  const CaptureOptions o = withBackoff(fastOptions(), 3600.0, 3600.0);
  CaptureThread capture(fakeSource(), o, nullptr);
  capture.start();
  ASSERT_TRUE(waitUntil([&] { return capture.stats().open_failures >= 1; }));
  EXPECT_EQ(capture.state(), CaptureState::Reconnecting);
  EXPECT_DOUBLE_EQ(capture.stats().retry_in, 3600.0);
  capture.stop();  // would hang for an hour if the wait were not interruptible
  EXPECT_EQ(capture.state(), CaptureState::Idle);
  EXPECT_EQ(device_->opens.load(), 1);
  capture.stop();  // twice is fine
}

TEST_F(CameraCaptureThread, CallbackExceptionsAndWarningsAreReportedNotFatal)
{
  device_->warn_on_open = true;
  std::atomic<int> calls{ 0 };
  CaptureThread capture(
      fakeSource(), fastOptions(),
      [&](const Frame&)
      {
        if (calls++ == 0)
          throw std::runtime_error("subscriber exploded");
      },
      rec_.eventsCallback());
  capture.start();
  ASSERT_TRUE(waitUntil([&] { return calls >= 5; }));
  capture.stop();
  EXPECT_EQ(capture.stats().reconnects, 0u);
  const auto frame_errors = rec_.eventsOf(CaptureEvent::Type::FrameError);
  ASSERT_EQ(frame_errors.size(), 1u);
  EXPECT_NE(frame_errors[0].message.find("subscriber exploded"), std::string::npos);
  const auto warnings = rec_.eventsOf(CaptureEvent::Type::Warning);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].message, "fake camera /dev/fake0: gain ignored");
  // State changes went Opening -> Streaming -> Idle.
  std::vector<CaptureState> states;
  for (const auto& e : rec_.eventsOf(CaptureEvent::Type::StateChanged))
    states.push_back(e.state);
  EXPECT_EQ(states, (std::vector<CaptureState>{ CaptureState::Opening, CaptureState::Streaming, CaptureState::Idle }));
}

TEST_F(CameraCaptureThread, RejectsBadConstruction)
{
  EXPECT_THROW(CaptureThread(nullptr, CaptureOptions(), nullptr), std::invalid_argument);
  CaptureOptions o;
  o.grab_timeout = 0.0;
  try
  {
    CaptureThread(std::unique_ptr<FrameSource>(new FakeSource(std::make_shared<FakeDevice>())), o, nullptr);
    FAIL();
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_NE(std::string(e.what()).find("grab_timeout"), std::string::npos) << e.what();
  }
  EXPECT_STREQ(sl_camera::captureStateName(CaptureState::Reconnecting), "reconnecting");
}

TEST_F(CameraCaptureThread, ADeviceThatOpensButNeverDeliversIsOverdueAndNeverRecovered)
{
  device_->stalled = true;  // opens fine, streams nothing (a packet socket that receives nothing)
  CaptureOptions o = fastOptions();
  o.frame_overdue = 0.01;
  CaptureThread capture = recordedCapture(o);
  capture.start();
  // While open without frames, the stats say so (the diagnostics turn this into an error).
  ASSERT_TRUE(waitUntil(
      [&]
      {
        const auto st = capture.stats();
        return st.state == CaptureState::Streaming && st.overdue && !st.have_frame;
      }));
  capture.stop();
  EXPECT_TRUE(rec_.eventsOf(CaptureEvent::Type::FirstFrame).empty());
  EXPECT_EQ(capture.stats().frames, 0u);
}

TEST_F(CameraCaptureThread, RecoveryIsAnnouncedOnlyOnceFramesArriveAndBackoffGrowsUntilThen)
{
  device_->stalled = true;
  CaptureOptions o = withBackoff(fastOptions(), 0.001, 0.004);
  o.stall_timeout = 0.01;
  o.first_frame_timeout = 0.01;
  CaptureThread capture = recordedCapture(o);
  capture.start();
  ASSERT_TRUE(waitUntil([&] { return rec_.eventsOf(CaptureEvent::Type::Error).size() >= 4; }));
  EXPECT_TRUE(rec_.eventsOf(CaptureEvent::Type::FirstFrame).empty()) << "announced a recovery without a frame";
  {
    // Opening worked every time, but no frame came: the waits grow as for a missing device.
    const auto errors = rec_.eventsOf(CaptureEvent::Type::Error);
    EXPECT_DOUBLE_EQ(errors[0].retry_in, 0.001);
    EXPECT_DOUBLE_EQ(errors[1].retry_in, 0.002);
    EXPECT_DOUBLE_EQ(errors[2].retry_in, 0.004);
    EXPECT_NE(errors[0].message.find("no frame for"), std::string::npos) << errors[0].message;
  }
  device_->stalled = false;
  ASSERT_TRUE(waitUntil([&] { return capture.stats().frames >= 3; }));
  capture.stop();
  std::lock_guard<std::mutex> lock(rec_.mutex);
  // The first FirstFrame event comes after the last error and before any frame counted after it.
  size_t first_frame = rec_.events.size(), last_error = 0;
  for (size_t i = 0; i < rec_.events.size(); ++i)
  {
    if (rec_.events[i].type == CaptureEvent::Type::FirstFrame && first_frame == rec_.events.size())
      first_frame = i;
    if (rec_.events[i].type == CaptureEvent::Type::Error)
      last_error = i;
  }
  ASSERT_LT(first_frame, rec_.events.size());
  EXPECT_GT(first_frame, last_error);
  EXPECT_NE(rec_.events[first_frame].message.find("streaming from fake camera /dev/fake0"), std::string::npos);
}

TEST_F(CameraCaptureThread, ALossIsReportedBeforeTheSlowCloseOfTheDeadDevice)
{
  CaptureThread capture = recordedCapture();
  capture.start();
  ASSERT_TRUE(waitUntil([&] { return capture.stats().frames >= 2; }));
  device_->close_blocks = true;
  device_->present = false;
  // The state says Reconnecting while close() is still stuck on the dead device.
  ASSERT_TRUE(waitUntil([&] { return device_->closing.load(); }));
  const auto st = capture.stats();
  EXPECT_EQ(st.state, CaptureState::Reconnecting);
  EXPECT_NE(st.last_error.find("disappeared"), std::string::npos) << st.last_error;
  device_->close_blocks = false;
  capture.stop();
}

TEST_F(CameraCaptureThread, ASourceThatWaitsOnPurposeIsNeitherStalledNorOverdue)
{
  device_->holding = true;  // a player held before its start
  CaptureOptions o = fastOptions();
  o.stall_timeout = 0.02;
  o.first_frame_timeout = 0.02;
  o.frame_overdue = 0.01;
  CaptureThread capture = recordedCapture(o);
  capture.start();
  ASSERT_TRUE(waitUntil([&] { return capture.stats().waiting; }));
  // Many stall timeouts long (a wait, not a measurement): a stalled source would have been closed
  // and re-opened by now.
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  CaptureStats st = capture.stats();
  EXPECT_EQ(st.state, CaptureState::Streaming);
  EXPECT_TRUE(st.waiting);
  EXPECT_FALSE(st.overdue);
  EXPECT_EQ(device_->opens.load(), 1);
  EXPECT_TRUE(rec_.eventsOf(CaptureEvent::Type::Error).empty());

  device_->holding = false;
  ASSERT_TRUE(waitUntil([&] { return capture.stats().frames >= 3; }));
  st = capture.stats();
  EXPECT_FALSE(st.waiting);
  EXPECT_TRUE(st.have_frame);
  EXPECT_EQ(rec_.eventsOf(CaptureEvent::Type::FirstFrame).size(), 1u);
  capture.stop();
  std::lock_guard<std::mutex> lock(rec_.mutex);
  ASSERT_FALSE(rec_.sequences.empty());
  EXPECT_EQ(rec_.sequences.front(), 0u);
  EXPECT_EQ(device_->opens.load(), 1);
}
