// What the camera nodelet reports and logs, decided by the core: the capture's status, the error
// log's throttle, the player's start and the log of unreadable files.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "sl_camera/camera/capture_status.h"
#include "sl_camera/camera/start_gate.h"
#include "sl_camera/camera/unreadable_files.h"

using namespace sl_camera;

namespace
{
CaptureStats stats(CaptureState state)
{
  CaptureStats s;
  s.state = state;
  return s;
}
}  // namespace

TEST(CameraStatus, StreamingIsOkOnlyWithFrames)
{
  CaptureStats s = stats(CaptureState::Streaming);
  EXPECT_EQ(captureSummary(s).level, StatusLevel::Warn);
  EXPECT_EQ(captureSummary(s).message, "opened, waiting for the first frame");
  EXPECT_FALSE(captureFailing(s));
  s.overdue = true;
  s.since_frame = 2.345;
  EXPECT_EQ(captureSummary(s).level, StatusLevel::Error);
  EXPECT_EQ(captureSummary(s).message, "opened, but no frame for 2.3 s");
  EXPECT_TRUE(captureFailing(s));
  s.have_frame = true;
  EXPECT_EQ(captureSummary(s).message, "no frame for 2.3 s");
  s.overdue = false;
  EXPECT_EQ(captureSummary(s).level, StatusLevel::Ok);
  EXPECT_EQ(captureSummary(s).message, "streaming");
  s.waiting = true;
  EXPECT_EQ(captureSummary(s).message, "waiting for a subscriber to start playback");
}

TEST(CameraStatus, OpeningReconnectingFinishedIdle)
{
  CaptureStats s = stats(CaptureState::Opening);
  EXPECT_EQ(captureSummary(s).level, StatusLevel::Ok);
  EXPECT_FALSE(captureFailing(s));
  s.last_error = "no device /dev/video9";
  EXPECT_EQ(captureSummary(s).level, StatusLevel::Error);
  EXPECT_EQ(captureSummary(s).message, "opening again after: no device /dev/video9");
  EXPECT_TRUE(captureFailing(s));
  s.state = CaptureState::Reconnecting;
  EXPECT_EQ(captureSummary(s).level, StatusLevel::Error);
  EXPECT_EQ(captureSummary(s).message, "no camera: no device /dev/video9");
  EXPECT_TRUE(captureFailing(s));
  EXPECT_EQ(captureSummary(stats(CaptureState::Finished)).level, StatusLevel::Ok);
  EXPECT_FALSE(captureFailing(stats(CaptureState::Finished)));
  EXPECT_EQ(captureSummary(stats(CaptureState::Idle)).level, StatusLevel::Warn);
  EXPECT_EQ(captureSummary(stats(CaptureState::Idle)).message, "stopped");
}

TEST(CameraStatus, UnreadableFilesRaiseToWarnAndAreCounted)
{
  const StatusSummary ok{ StatusLevel::Ok, "streaming" };
  EXPECT_EQ(withUnreadableFiles(ok, 0).message, "streaming");
  EXPECT_EQ(withUnreadableFiles(ok, 0).level, StatusLevel::Ok);
  EXPECT_EQ(withUnreadableFiles(ok, 1).message, "streaming; 1 unreadable file skipped");
  EXPECT_EQ(withUnreadableFiles(ok, 1).level, StatusLevel::Warn);
  const StatusSummary error{ StatusLevel::Error, "no camera: x" };
  EXPECT_EQ(withUnreadableFiles(error, 3).message, "no camera: x; 3 unreadable files skipped");
  EXPECT_EQ(withUnreadableFiles(error, 3).level, StatusLevel::Error);
}

TEST(CameraStatus, RateIsExplainedAtTheEndAndWhileHeld)
{
  StatusSummary s;
  EXPECT_FALSE(rateSummary(stats(CaptureState::Streaming), s));
  EXPECT_FALSE(rateSummary(stats(CaptureState::Reconnecting), s));
  EXPECT_TRUE(rateSummary(stats(CaptureState::Finished), s));
  EXPECT_EQ(s.message, "end of playback, no more frames");
  CaptureStats held = stats(CaptureState::Streaming);
  held.waiting = true;
  EXPECT_TRUE(rateSummary(held, s));
  EXPECT_EQ(s.level, StatusLevel::Ok);
}

TEST(CameraStatus, FramesOfAnotherSizeThanTheRigsAreRefusedNamingBoth)
{
  EXPECT_EQ(frameSizeError(640, 480, 0, 0, ""), "");
  EXPECT_EQ(frameSizeError(752, 480, 752, 480, "rig.yaml"), "");
  EXPECT_EQ(frameSizeError(640, 480, 752, 480, "rig.yaml"),
            "the camera delivers 640 x 480 px but the rig file rig.yaml is for 752 x 480 px");
  EXPECT_NE(frameSizeError(752, 479, 752, 480, "rig.yaml"), "");
}

TEST(CameraErrorLog, NewErrorsAtOnceTheSameAtMostEveryInterval)
{
  ErrorLogThrottle log(60.0);
  EXPECT_TRUE(log.shouldLog("lost", 1000.0));
  EXPECT_FALSE(log.shouldLog("lost", 1010.0));
  EXPECT_FALSE(log.shouldLog("lost", 1060.0));
  EXPECT_TRUE(log.shouldLog("lost", 1060.5));
  EXPECT_TRUE(log.shouldLog("gone", 1061.0)) << "another error at once";
  EXPECT_TRUE(log.shouldLog("lost", 1062.0));
}

TEST(CameraErrorLog, AFirstFrameIsARecoveryOnlyAfterAnErrorAndClearsIt)
{
  ErrorLogThrottle log(60.0);
  EXPECT_FALSE(log.recover());
  EXPECT_TRUE(log.shouldLog("lost", 5.0));
  EXPECT_TRUE(log.recover());
  EXPECT_FALSE(log.recover());
  EXPECT_TRUE(log.shouldLog("lost", 6.0)) << "the same error after a recovery is new";
}

TEST(CameraStartGate, StarterWaitsTheGraceForAnImageOnlySubscriber)
{
  PlaybackStarter starter(0.5);
  EXPECT_FALSE(starter.update(0, 0, 10.0));
  EXPECT_FALSE(starter.update(0, 1, 10.1)) << "camera_info alone";
  EXPECT_FALSE(starter.update(1, 0, 10.2));
  EXPECT_FALSE(starter.update(1, 0, 10.6));
  EXPECT_TRUE(starter.update(1, 0, 10.7));
  EXPECT_FALSE(starter.update(0, 0, 10.8));
  EXPECT_FALSE(starter.update(1, 0, 11.0)) << "the grace starts over with a new subscriber";
  EXPECT_TRUE(starter.update(1, 1, 11.0)) << "a camera subscriber: at once";
}

TEST(CameraUnreadableFiles, LogNamesEachOnceAtMostEveryInterval)
{
  UnreadableFiles files;
  UnreadableFilesLog log(5.0);
  EXPECT_TRUE(log.due(files, 0.0).empty());
  files.add("a.png");
  files.add("b.png");
  EXPECT_EQ(log.due(files, 1.0), (std::vector<std::string>{ "a.png", "b.png" }));
  files.add("c.png");
  EXPECT_TRUE(log.due(files, 3.0).empty()) << "within the interval";
  EXPECT_EQ(log.due(files, 6.0), std::vector<std::string>{ "c.png" });
  EXPECT_TRUE(log.due(files, 20.0).empty()) << "nothing new";
  EXPECT_EQ(log.logged(), 3u);
}
