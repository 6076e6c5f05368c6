// PlayerSource: replays folders of images (generated here) and video files, paced, looped, in mono8.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "sl_camera/camera/player_source.h"
#include "sl_camera/camera/start_gate.h"
#include "sl_camera/camera/unreadable_files.h"

namespace fs = std::filesystem;
using sl_camera::CameraError;
using sl_camera::Frame;
using sl_camera::GrabStatus;
using sl_camera::PlayerSource;

namespace
{
/// A fresh directory under the system temp dir, removed with everything in it at the end.
class TempDir
{
public:
  TempDir()
  {
    std::string pattern = (fs::temp_directory_path() / "sl_camera_player_XXXXXX").string();
    if (!::mkdtemp(&pattern[0]))
      throw std::runtime_error("mkdtemp failed");
    path_ = pattern;
  }
  ~TempDir()
  {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  std::string file(const std::string& name) const { return (fs::path(path_) / name).string(); }
  const std::string& path() const { return path_; }

private:
  std::string path_;
};

/// Writes a uniform grey 8-bit image of the given value.
void writeGrey(const std::string& file, int value, int width = 16, int height = 12)
{
  ASSERT_TRUE(cv::imwrite(file, cv::Mat(height, width, CV_8UC1, cv::Scalar(value)))) << file;
}

/// Grabs the next frame, waiting through Timeouts (generous bound: the test must not hang).
GrabStatus grabNext(PlayerSource& player, Frame& frame)
{
  for (int i = 0; i < 1000; ++i)
  {
    const GrabStatus s = player.grab(frame, std::chrono::milliseconds(50));
    if (s != GrabStatus::Timeout)
      return s;
  }
  return GrabStatus::Timeout;
}

int valueOf(const Frame& frame)
{
  return frame.image.at<uint8_t>(0, 0);
}
}  // namespace

TEST(CameraPlayer, ReplaysFolderInNameOrderIgnoringOtherFiles)
{
  TempDir dir;
  // Written out of order; upper-case and other extensions are images too; text files are not.
  writeGrey(dir.file("frame_03.png"), 30);
  writeGrey(dir.file("frame_01.png"), 10);
  writeGrey(dir.file("frame_02.PNG"), 20);
  writeGrey(dir.file("frame_04.pgm"), 40);
  writeGrey(dir.file("frame_05.tiff"), 50);
  writeGrey(dir.file("frame_06.jpg"), 60);  // lossy, but a uniform image decodes close to its value
  std::ofstream(dir.file("notes.txt")) << "not an image";
  fs::create_directory(dir.file("sub.png"));  // a folder named like an image is skipped

  PlayerSource player(dir.path(), 200.0, false);
  player.open();
  ASSERT_EQ(player.files().size(), 6u);
  EXPECT_EQ(fs::path(player.files().front()).filename(), "frame_01.png");
  EXPECT_EQ(fs::path(player.files().back()).filename(), "frame_06.jpg");

  Frame frame;
  std::vector<int> values;
  std::vector<uint64_t> sequences;
  while (grabNext(player, frame) == GrabStatus::Frame)
  {
    ASSERT_EQ(frame.image.type(), CV_8UC1);
    EXPECT_EQ(frame.image.cols, 16);
    EXPECT_EQ(frame.image.rows, 12);
    EXPECT_TRUE(frame.has_sequence);
    values.push_back(valueOf(frame));
    sequences.push_back(frame.sequence);
    ASSERT_LE(values.size(), 6u) << "no end of stream without loop";
  }
  ASSERT_EQ(values.size(), 6u);
  for (int i = 0; i < 5; ++i)
    EXPECT_EQ(values[i], 10 * (i + 1));
  EXPECT_NEAR(values[5], 60, 2);
  EXPECT_EQ(sequences, (std::vector<uint64_t>{ 0, 1, 2, 3, 4, 5 }));
  // Stays at the end.
  EXPECT_EQ(player.grab(frame, std::chrono::milliseconds(10)), GrabStatus::EndOfStream);
}

TEST(CameraPlayer, LoopStartsOver)
{
  TempDir dir;
  for (int i = 0; i < 3; ++i)
    writeGrey(dir.file("img" + std::to_string(i) + ".png"), 100 + i);
  PlayerSource player(dir.path(), 500.0, true);
  player.open();
  Frame frame;
  std::vector<int> values;
  for (int i = 0; i < 8; ++i)
  {
    ASSERT_EQ(grabNext(player, frame), GrabStatus::Frame);
    values.push_back(valueOf(frame));
    EXPECT_EQ(frame.sequence, static_cast<uint64_t>(i));
  }
  EXPECT_EQ(values, (std::vector<int>{ 100, 101, 102, 100, 101, 102, 100, 101 }));
}

/// Simulated time for the pacing: sleeping moves it on at once by exactly the time asked for.
class FakePacingClock : public PlayerSource::PacingClock
{
public:
  std::chrono::steady_clock::time_point now() override { return now_; }
  void sleepUntil(std::chrono::steady_clock::time_point t) override { now_ = std::max(now_, t); }
  void advance(std::chrono::steady_clock::duration d) { now_ += d; }

private:
  std::chrono::steady_clock::time_point now_{ std::chrono::hours(1) };
};

TEST(CameraPlayer, PacesAtTheRate)
{
  using std::chrono::milliseconds;
  TempDir dir;
  writeGrey(dir.file("a.png"), 1);
  const double rate = 40.0;
  const std::chrono::steady_clock::duration period = milliseconds(25);  // 1 / rate
  PlayerSource player(dir.path(), rate, true);
  auto clock = std::make_shared<FakePacingClock>();
  player.setPacingClock(clock);
  player.open();
  EXPECT_DOUBLE_EQ(player.nominalRate(), rate);
  Frame frame;
  ASSERT_EQ(player.grab(frame, milliseconds(0)), GrabStatus::Frame);  // the first is due at once
  const auto first = clock->now();
  // Each further frame exactly one period after the previous one: the player sleeps until it is due.
  for (int i = 1; i < 6; ++i)
  {
    ASSERT_EQ(player.grab(frame, milliseconds(1000)), GrabStatus::Frame);
    EXPECT_EQ(clock->now() - first, i * period) << "frame " << i;
  }
  // Not due yet: a timeout shorter than the wait gives Timeout after sleeping the timeout.
  const auto t = clock->now();
  EXPECT_EQ(player.grab(frame, milliseconds(0)), GrabStatus::Timeout);
  EXPECT_EQ(clock->now(), t);
  EXPECT_EQ(player.grab(frame, milliseconds(5)), GrabStatus::Timeout);
  EXPECT_EQ(clock->now(), t + milliseconds(5));
  // A consumer that fell behind by ten periods gets one frame at once, then the pace again: no burst.
  clock->advance(10 * period);
  EXPECT_EQ(player.grab(frame, milliseconds(0)), GrabStatus::Frame);
  const auto late = clock->now();
  EXPECT_EQ(player.grab(frame, milliseconds(0)), GrabStatus::Timeout);
  ASSERT_EQ(player.grab(frame, milliseconds(1000)), GrabStatus::Frame);
  EXPECT_EQ(clock->now() - late, period);
  EXPECT_EQ(frame.sequence, 7u);

  // The real clock is the default: the next frame of a 0.1 Hz player is 10 s away.
  PlayerSource slow(dir.path(), 0.1, true);
  slow.open();
  ASSERT_EQ(slow.grab(frame, milliseconds(1)), GrabStatus::Frame);
  EXPECT_EQ(slow.grab(frame, milliseconds(0)), GrabStatus::Timeout);
  EXPECT_EQ(slow.grab(frame, milliseconds(5)), GrabStatus::Timeout);
  EXPECT_THROW(slow.setPacingClock(nullptr), std::invalid_argument);
}

TEST(CameraPlayer, ConvertsColourAnd16BitToMono8)
{
  TempDir dir;
  cv::Mat colour(4, 6, CV_8UC3, cv::Scalar(30, 200, 90));  // B, G, R
  ASSERT_TRUE(cv::imwrite(dir.file("1_colour.png"), colour));
  cv::Mat deep(4, 6, CV_16UC1, cv::Scalar(100 * 256 + 100));
  deep.at<uint16_t>(0, 1) = 65535;
  deep.at<uint16_t>(0, 2) = 0;
  ASSERT_TRUE(cv::imwrite(dir.file("2_deep.png"), deep));
  cv::Mat rgba(4, 6, CV_8UC4, cv::Scalar(255, 255, 255, 128));
  ASSERT_TRUE(cv::imwrite(dir.file("3_rgba.png"), rgba));

  PlayerSource player(dir.path(), 500.0, false);
  player.open();
  Frame frame;
  ASSERT_EQ(grabNext(player, frame), GrabStatus::Frame);
  ASSERT_EQ(frame.image.type(), CV_8UC1);
  cv::Mat expected;
  cv::cvtColor(colour, expected, cv::COLOR_BGR2GRAY);
  EXPECT_EQ(valueOf(frame), expected.at<uint8_t>(0, 0));
  EXPECT_NEAR(valueOf(frame), 0.114 * 30 + 0.587 * 200 + 0.299 * 90, 1.0);

  ASSERT_EQ(grabNext(player, frame), GrabStatus::Frame);
  ASSERT_EQ(frame.image.type(), CV_8UC1);
  EXPECT_EQ(frame.image.at<uint8_t>(0, 0), 100);  // the top 8 bits
  EXPECT_EQ(frame.image.at<uint8_t>(0, 1), 255);
  EXPECT_EQ(frame.image.at<uint8_t>(0, 2), 0);

  ASSERT_EQ(grabNext(player, frame), GrabStatus::Frame);
  ASSERT_EQ(frame.image.type(), CV_8UC1);
  EXPECT_EQ(valueOf(frame), 255);
}

TEST(CameraPlayer, MissingAndEmptyFoldersAreClearErrors)
{
  TempDir dir;
  const std::string missing = dir.file("no_such_folder");
  PlayerSource gone(missing, 10.0, false);
  try
  {
    gone.open();
    FAIL() << "opening a missing folder must fail";
  }
  catch (const CameraError& e)
  {
    EXPECT_EQ(e.kind(), CameraError::Kind::NotFound);
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
  }
  EXPECT_FALSE(gone.isOpen());

  std::ofstream(dir.file("readme.txt")) << "no images here";
  PlayerSource empty(dir.path(), 10.0, false);
  try
  {
    empty.open();
    FAIL() << "opening a folder without images must fail";
  }
  catch (const CameraError& e)
  {
    EXPECT_EQ(e.kind(), CameraError::Kind::Open);
    EXPECT_NE(std::string(e.what()).find(dir.path()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("no images"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(empty.isOpen());
  EXPECT_THROW(PlayerSource(dir.path(), 0.0, false), std::invalid_argument);
}

TEST(CameraPlayer, CorruptFileIsAFrameErrorNamingItAndPlaybackContinues)
{
  TempDir dir;
  writeGrey(dir.file("a.png"), 11);
  std::ofstream(dir.file("b.png"), std::ios::binary) << "\x89PNG this is not really a PNG";
  writeGrey(dir.file("c.png"), 33);
  PlayerSource player(dir.path(), 500.0, false);
  player.open();
  Frame frame;
  ASSERT_EQ(grabNext(player, frame), GrabStatus::Frame);
  EXPECT_EQ(valueOf(frame), 11);
  try
  {
    grabNext(player, frame);
    FAIL() << "a corrupt image must be reported";
  }
  catch (const CameraError& e)
  {
    EXPECT_EQ(e.kind(), CameraError::Kind::Frame);
    EXPECT_NE(std::string(e.what()).find(dir.file("b.png")), std::string::npos) << e.what();
  }
  ASSERT_EQ(grabNext(player, frame), GrabStatus::Frame);
  EXPECT_EQ(valueOf(frame), 33);
  EXPECT_EQ(grabNext(player, frame), GrabStatus::EndOfStream);
}

TEST(CameraPlayer, UnreadableFilesAreRecordedOnceEachAcrossLoops)
{
  TempDir dir;
  writeGrey(dir.file("a.png"), 11);
  std::ofstream(dir.file("b.png"), std::ios::binary) << "\x89PNG this is not really a PNG";
  writeGrey(dir.file("c.png"), 33);
  std::ofstream(dir.file("d.jpg"), std::ios::binary);  // empty
  PlayerSource player(dir.path(), 1000.0, true);
  const std::shared_ptr<const sl_camera::UnreadableFiles> unreadable = player.unreadableFiles();
  ASSERT_TRUE(unreadable);
  EXPECT_EQ(unreadable->count(), 0u);
  player.open();
  Frame frame;
  std::vector<int> values;
  int errors = 0;
  for (int i = 0; i < 12; ++i)  // three loops of four files
  {
    try
    {
      ASSERT_EQ(grabNext(player, frame), GrabStatus::Frame);
      values.push_back(valueOf(frame));
    }
    catch (const CameraError& e)
    {
      EXPECT_EQ(e.kind(), CameraError::Kind::Frame) << e.what();
      ++errors;
    }
  }
  EXPECT_EQ(values, (std::vector<int>{ 11, 33, 11, 33, 11, 33 }));
  EXPECT_EQ(errors, 6);
  // Each bad file once, in the order met, whatever the number of loops.
  EXPECT_EQ(unreadable->count(), 2u);
  EXPECT_EQ(unreadable->first(10), (std::vector<std::string>{ dir.file("b.png"), dir.file("d.jpg") }));
  // The record outlives a re-open (the capture thread re-opens after a loss).
  player.open();
  EXPECT_EQ(unreadable->count(), 2u);
}

TEST(CameraUnreadableFiles, CountsDistinctNamesAndSummarises)
{
  sl_camera::UnreadableFiles files;
  EXPECT_EQ(files.summary(3), "none");
  EXPECT_TRUE(files.from(0).empty());
  EXPECT_TRUE(files.add("/d/1.png"));
  EXPECT_FALSE(files.add("/d/1.png"));
  EXPECT_TRUE(files.add("/d/2.png"));
  EXPECT_EQ(files.count(), 2u);
  EXPECT_EQ(files.summary(3), "/d/1.png, /d/2.png");
  for (int i = 3; i <= 6; ++i)
    files.add("/d/" + std::to_string(i) + ".png");
  EXPECT_EQ(files.count(), 6u);
  EXPECT_EQ(files.summary(3), "/d/1.png, /d/2.png, /d/3.png and 3 more");
  EXPECT_EQ(files.summary(0), "6 more");
  EXPECT_EQ(files.first(2), (std::vector<std::string>{ "/d/1.png", "/d/2.png" }));
  // A reader keeping its own count sees every name exactly once.
  EXPECT_EQ(files.from(4), (std::vector<std::string>{ "/d/5.png", "/d/6.png" }));
  EXPECT_TRUE(files.from(6).empty());
  EXPECT_TRUE(files.from(100).empty());
  EXPECT_EQ(sl_camera::UnreadableFiles::join({ "a", "b" }), "a, b");
}

TEST(CameraPlayer, StartGateHoldsFrameZeroUntilOpened)
{
  TempDir dir;
  for (int i = 0; i < 3; ++i)
    writeGrey(dir.file("f" + std::to_string(i) + ".png"), 10 * (i + 1));
  PlayerSource player(dir.path(), 1000.0, false);
  auto gate = std::make_shared<sl_camera::StartGate>();
  player.setStartGate(gate);
  EXPECT_FALSE(player.waiting()) << "not open yet: nothing to wait with";
  player.open();
  Frame frame;
  for (int i = 0; i < 5; ++i)
  {
    EXPECT_EQ(player.grab(frame, std::chrono::milliseconds(1)), GrabStatus::Timeout);
    EXPECT_TRUE(player.waiting());
  }
  gate->open();
  EXPECT_FALSE(player.waiting());
  std::vector<int> values;
  std::vector<uint64_t> sequences;
  while (grabNext(player, frame) == GrabStatus::Frame)
  {
    values.push_back(valueOf(frame));
    sequences.push_back(frame.sequence);
    ASSERT_LE(values.size(), 3u);
  }
  // Nothing was skipped while held: frame 0 first.
  EXPECT_EQ(values, (std::vector<int>{ 10, 20, 30 }));
  EXPECT_EQ(sequences, (std::vector<uint64_t>{ 0, 1, 2 }));
}

TEST(CameraPlayer, StartGateOpenedFromAnotherThreadWakesAWaitingGrab)
{
  TempDir dir;
  writeGrey(dir.file("f.png"), 77);
  PlayerSource player(dir.path(), 10.0, false);
  auto gate = std::make_shared<sl_camera::StartGate>();
  player.setStartGate(gate);
  player.open();
  std::thread opener([gate] { gate->open(); });
  Frame frame;
  // The grab may start before or after the other thread opens the gate: either way it gets frame 0.
  EXPECT_EQ(grabNext(player, frame), GrabStatus::Frame);
  opener.join();
  EXPECT_EQ(valueOf(frame), 77);
  EXPECT_EQ(frame.sequence, 0u);
}

TEST(CameraStartGate, PlaybackStartsWithACameraSubscriberOrAnImageOnlyOneAfterTheGrace)
{
  using sl_camera::shouldStartPlayback;
  EXPECT_FALSE(shouldStartPlayback(0, 0, 0.0, 0.5));
  EXPECT_FALSE(shouldStartPlayback(0, 3, 0.0, 0.5)) << "camera_info alone does not start";
  EXPECT_TRUE(shouldStartPlayback(1, 1, 0.0, 0.5)) << "image and camera_info: at once";
  EXPECT_FALSE(shouldStartPlayback(1, 0, 0.1, 0.5)) << "image alone: camera_info may still be connecting";
  EXPECT_TRUE(shouldStartPlayback(1, 0, 0.5, 0.5));
  EXPECT_TRUE(shouldStartPlayback(2, 0, 7.0, 0.5));

  sl_camera::StartGate gate;
  EXPECT_FALSE(gate.isOpen());
  EXPECT_FALSE(gate.waitFor(std::chrono::milliseconds(1)));
  gate.open();
  gate.open();  // idempotent
  EXPECT_TRUE(gate.isOpen());
  EXPECT_TRUE(gate.waitFor(std::chrono::milliseconds(0)));
  EXPECT_TRUE(sl_camera::StartGate(true).isOpen());
}

TEST(CameraPlayer, ImageThatDisappearsMeansTheRecordingIsLost)
{
  TempDir dir;
  writeGrey(dir.file("a.png"), 1);
  writeGrey(dir.file("b.png"), 2);
  PlayerSource player(dir.path(), 500.0, true);
  player.open();
  Frame frame;
  ASSERT_EQ(grabNext(player, frame), GrabStatus::Frame);
  fs::remove(dir.file("b.png"));
  try
  {
    grabNext(player, frame);
    FAIL() << "a vanished image must be reported";
  }
  catch (const CameraError& e)
  {
    EXPECT_EQ(e.kind(), CameraError::Kind::Lost);
    EXPECT_NE(std::string(e.what()).find(dir.file("b.png")), std::string::npos) << e.what();
  }
  // Opening again lists what is there now.
  player.open();
  EXPECT_EQ(player.files().size(), 1u);
}

TEST(CameraPlayer, SingleImageFile)
{
  TempDir dir;
  writeGrey(dir.file("only.png"), 77);
  PlayerSource player(dir.file("only.png"), 500.0, true);
  player.open();
  Frame frame;
  for (int i = 0; i < 3; ++i)
  {
    ASSERT_EQ(grabNext(player, frame), GrabStatus::Frame);
    EXPECT_EQ(valueOf(frame), 77);
  }
}

TEST(CameraPlayer, ReplaysAVideoFileAndLoops)
{
  TempDir dir;
  const std::string video = dir.file("clip.avi");
  {
    // OpenCV's built-in MJPEG writer needs no external codec.
    cv::VideoWriter writer(video, cv::CAP_OPENCV_MJPEG, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 10.0,
                           cv::Size(32, 24), true);
    ASSERT_TRUE(writer.isOpened());
    for (int i = 0; i < 4; ++i)
      writer.write(cv::Mat(24, 32, CV_8UC3, cv::Scalar::all(40 + 50 * i)));
  }
  PlayerSource player(video, 500.0, true);
  player.open();
  EXPECT_TRUE(player.files().empty());
  Frame frame;
  std::vector<int> values;
  for (int i = 0; i < 6; ++i)
  {
    ASSERT_EQ(grabNext(player, frame), GrabStatus::Frame);
    ASSERT_EQ(frame.image.type(), CV_8UC1);
    EXPECT_EQ(frame.image.cols, 32);
    EXPECT_EQ(frame.image.rows, 24);
    values.push_back(valueOf(frame));
  }
  const std::vector<int> expected{ 40, 90, 140, 190, 40, 90 };
  for (size_t i = 0; i < expected.size(); ++i)
    EXPECT_NEAR(values[i], expected[i], 4) << "frame " << i;

  // Without loop the video ends.
  PlayerSource once(video, 500.0, false);
  once.open();
  int n = 0;
  while (grabNext(once, frame) == GrabStatus::Frame && n < 10)
    ++n;
  EXPECT_EQ(n, 4);
}

TEST(CameraPlayer, UnreadableVideoIsAClearError)
{
  TempDir dir;
  const std::string bogus = dir.file("clip.avi");
  std::ofstream(bogus) << "not a video";
  PlayerSource player(bogus, 10.0, false);
  try
  {
    player.open();
    FAIL() << "a file that is neither image nor video must fail";
  }
  catch (const CameraError& e)
  {
    EXPECT_NE(std::string(e.what()).find(bogus), std::string::npos) << e.what();
  }
}
