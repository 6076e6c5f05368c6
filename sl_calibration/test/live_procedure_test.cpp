// The live calibration's steps without ROS: the distances of a plane calibration, the pairing of
// board and pattern images, the prompts and the writing of the results.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

#include "sl_calibration/live_procedure.h"
#include "test_rig.h"

using namespace sl_calibration;

namespace
{
std::vector<cv::Point2f> boardCorners(const Board& board)
{
  std::vector<cv::Point2f> corners;
  for (int r = 0; r < board.rows; ++r)
    for (int c = 0; c < board.cols; ++c)
      corners.emplace_back(100.f + 20.f * c, 80.f + 20.f * r);
  return corners;
}

std::string tempPath(const std::string& name)
{
  return "/tmp/sl_calibration_live_" + std::to_string(getpid()) + "_" + name;
}

bool exists(const std::string& path)
{
  return std::ifstream(path).good();
}
}  // namespace

TEST(CalibrationPlaneSteps, ListedDistancesInOrderTheOperatorsFirst)
{
  PlaneSteps steps({ 0.5, 0.7 });
  double d = 0.0;
  ASSERT_TRUE(steps.nextDistance(d));
  EXPECT_EQ(d, 0.5);
  EXPECT_FALSE(steps.listDone());
  steps.setDistance(0.62);  // the operator's distance comes first and does not advance the list
  ASSERT_TRUE(steps.nextDistance(d));
  EXPECT_EQ(d, 0.62);
  steps.captured(0.62);
  ASSERT_TRUE(steps.nextDistance(d));
  EXPECT_EQ(d, 0.5);
  steps.captured(0.5);
  steps.captured(0.7);
  EXPECT_TRUE(steps.listDone());
  EXPECT_EQ(steps.views(), 3u);
  EXPECT_FALSE(steps.nextDistance(d));
  steps.reset();
  EXPECT_EQ(steps.views(), 0u);
  ASSERT_TRUE(steps.nextDistance(d));
  EXPECT_EQ(d, 0.5);
}

TEST(CalibrationPlaneSteps, WithoutAListOnlyTheOperatorsDistance)
{
  PlaneSteps steps;
  double d = 0.0;
  EXPECT_FALSE(steps.nextDistance(d));
  steps.setDistance(0.8);
  ASSERT_TRUE(steps.nextDistance(d));
  EXPECT_EQ(d, 0.8);
  steps.captured(0.8);
  EXPECT_FALSE(steps.nextDistance(d)) << "a given distance is used once";
  EXPECT_FALSE(steps.listDone()) << "nothing listed: the operator calls calibrate";
}

TEST(CalibrationFullSteps, BoardThenPatternIsAPoseABoardAloneACameraView)
{
  const Board board = parseBoardSize("8x5", 0.02);
  FullCalibration full(trueRig(), board);
  FullSteps steps(full);
  EXPECT_THROW(steps.addPattern("pose 1", {}), CalibrationError);
  EXPECT_EQ(steps.addBoard(boardCorners(board)), 1);
  EXPECT_TRUE(steps.pendingBoard());
  EXPECT_EQ(full.boardViews(), 0);
  EXPECT_EQ(steps.addBoard(boardCorners(board)), 2);  // the first board had no pattern image
  EXPECT_EQ(full.boardViews(), 1);
  EXPECT_EQ(steps.nextPoseName(), "pose 1");
  const std::vector<PrimitiveSample> samples(FullCalibrationOptions().projector.min_points_per_view,
                                             PrimitiveSample{ 1, 2, 300.0, 200.0 });
  EXPECT_THROW(steps.addPattern("pose 1", {}), CalibrationError) << "too few primitives";
  EXPECT_TRUE(steps.pendingBoard()) << "the board still waits for a usable pattern image";
  steps.addPattern("pose 1", samples);
  EXPECT_FALSE(steps.pendingBoard());
  EXPECT_EQ(full.planeViews(), 1);
  EXPECT_EQ(full.boardViews(), 2);
  EXPECT_EQ(steps.nextPoseName(), "pose 2");
  steps.addBoard(boardCorners(board));
  steps.flush();  // before the fit, a waiting board is a camera view
  EXPECT_FALSE(steps.pendingBoard());
  EXPECT_EQ(full.boardViews(), 3);
  steps.reset();
  full.clear();
  EXPECT_EQ(steps.addBoard(boardCorners(board)), 1);
}

TEST(CalibrationPrompts, SayWhatComesNextAndWhere)
{
  PlaneCalibrationOptions options;
  options.normal = PlaneNormal::Camera;
  options.reference = DistanceReference::Camera;
  PlaneSteps steps({ 0.5 });
  EXPECT_EQ(planePrompt(steps, options, 0, "/cal"),
            "plane calibration: put the plane at 0.500 m (perpendicular to the camera's optical axis, measured from "
            "the camera's optical centre), then: rosservice call /cal/capture");
  steps.captured(0.5);
  EXPECT_EQ(planePrompt(steps, options, 1, "/cal"),
            "plane calibration: 1 distance(s) captured; publish the next distance (m) on /cal/distance and call "
            "/cal/capture, or call /cal/calibrate");

  const Board board = parseBoardSize("8x5", 0.02);
  FullCalibration full(trueRig(), board);
  FullSteps full_steps(full);
  const std::string first = fullPrompt(full, full_steps, 3, "/cal");
  EXPECT_NE(first.find("0 plane pose(s) of >= 3, 0 board view(s)"), std::string::npos) << first;
  EXPECT_NE(first.find("board 8x5 inner corners"), std::string::npos) << first;
  EXPECT_NE(first.find("/cal/capture_board"), std::string::npos) << first;
  EXPECT_EQ(first.find("/cal/calibrate"), std::string::npos) << "too few poses to fit: " << first;
  full_steps.addBoard(boardCorners(board));
  EXPECT_NE(fullPrompt(full, full_steps, 3, "/cal").find("/cal/capture_pattern"), std::string::npos);
}

TEST(CalibrationOutput, PlaneTablesAndResidualsAreWrittenNothingOnAnUnwritableFile)
{
  PlaneCalibrationOptions options;
  options.normal = PlaneNormal::Camera;
  PlaneCalibration cal(trueRig(), options);
  for (double z : { 0.5, 0.6, 0.7, 0.8 })
    cal.addSamples(z, { PrimitiveSample{ 0, 0, 300.0 + 80.0 / z, 200.0 } }, "synthetic");
  const PlaneCalibrationResult result = cal.fit();
  ASSERT_EQ(result.calibrated, 1);

  const std::string rig = tempPath("rig.yaml"), csv = tempPath("residuals.csv");
  const WrittenCalibration w = writePlaneCalibration(result, trueRig(), rig, csv);
  EXPECT_EQ(w.message.rfind("wrote " + rig + ": 1 primitives calibrated, rms ", 0), 0u) << w.message;
  EXPECT_EQ(w.summary.rfind("plane calibration:\n", 0), 0u);
  EXPECT_TRUE(sl_projector::loadRig(rig).tables.rational.at(0).valid);
  EXPECT_TRUE(exists(csv));
  std::remove(rig.c_str());

  try
  {
    writePlaneCalibration(result, trueRig(), rig, "/nonexistent_dir/residuals.csv");
    FAIL() << "an unwritable residuals file must fail";
  }
  catch (const CalibrationError& e)
  {
    EXPECT_NE(std::string(e.what()).find("/nonexistent_dir/residuals.csv"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(exists(rig)) << "nothing is written when a file fails";
  std::remove(csv.c_str());
}

TEST(CalibrationFrameCollector, KeepsOnlyWantedImagesStampedAfterTheSettleTime)
{
  FrameCollector collector;
  int made = 0;
  auto make = [&made]
  {
    ++made;
    return cv::Mat(4, 6, CV_8UC1, cv::Scalar(made));
  };
  EXPECT_FALSE(collector.offer(100, make)) << "no capture waits";
  EXPECT_EQ(made, 0) << "nothing is converted that nobody wants";
  std::vector<cv::Mat> frames;
  std::thread capture([&] { frames = collector.collect(2, 1000, 30.0); });
  // Offered until the capture has taken both (it may start waiting after the first offers).
  while (made < 2)
  {
    collector.offer(999, make);  // before the settle time: ignored
    if (collector.offer(1000, make) && made < 2)
      collector.offer(2000, make);
    std::this_thread::yield();
  }
  capture.join();
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[0].at<uint8_t>(0, 0), 1);
  EXPECT_EQ(frames[1].at<uint8_t>(0, 0), 2);
  EXPECT_TRUE(collector.collect(1, 0, 0.01).empty()) << "a timeout returns what came (nothing)";
  EXPECT_THROW(
      {
        std::thread t([&] { collector.collect(1, 0, 30.0); });
        try
        {
          while (!collector.offer(5, []() -> cv::Mat { throw std::runtime_error("bad encoding"); }))
            std::this_thread::yield();
        }
        catch (...)
        {
          collector.offer(5, [] { return cv::Mat(4, 6, CV_8UC1); });  // let the capture end
          t.join();
          throw;
        }
        t.join();
      },
      std::runtime_error)
      << "a conversion that fails keeps nothing and reports";
}

TEST(CalibrationFrameCollector, FramesOfAnotherSizeAreNamed)
{
  const std::vector<cv::Mat> frames{ cv::Mat(480, 752, CV_8UC1), cv::Mat(240, 376, CV_8UC1) };
  EXPECT_EQ(frameSizeError({ frames[0] }, 752, 480), "");
  EXPECT_EQ(frameSizeError(frames, 752, 480), "the images are 376 x 240 px, the rig's camera 752 x 480");
}

TEST(CalibrationSessions, APlaneCaptureOfDarkImagesWarnsAndCountsTheStep)
{
  PlaneSession session(trueRig(), PlaneCalibrationOptions(), { 0.6, 0.8 }, kCalibrationEpipolarTolerance);
  const cv::Mat dark(trueRig().camera.height, trueRig().camera.width, CV_8UC1, cv::Scalar(0));
  const PlaneCapture c = session.capture(0.6, { dark, dark });
  EXPECT_EQ(c.least, 0);
  EXPECT_EQ(c.message.rfind("0.600 m: 0 primitives per image from 2 image(s) (WARNING: an image decoded nothing", 0),
            0u)
      << c.message;
  EXPECT_EQ(session.steps().views(), 1u);
  EXPECT_NE(session.prompt("/cal").find("put the plane at 0.800 m"), std::string::npos);
  EXPECT_THROW(session.write(tempPath("never.yaml"), ""), CalibrationError) << "nothing to fit";
  EXPECT_FALSE(exists(tempPath("never.yaml")));
  session.reset();
  EXPECT_NE(session.prompt("/cal").find("put the plane at 0.600 m"), std::string::npos);
}

TEST(CalibrationSessions, ABoardImageWithoutABoardIsRefused)
{
  FullSession session(trueRig(), parseBoardSize("8x5", 0.02), kCalibrationEpipolarTolerance, 3);
  std::size_t corners = 7;
  const cv::Mat grey(trueRig().camera.height, trueRig().camera.width, CV_8UC1, cv::Scalar(128));
  EXPECT_EQ(session.addBoardImage(grey, corners), 0);
  EXPECT_EQ(corners, 0u);
  EXPECT_FALSE(session.steps().pendingBoard());
  EXPECT_THROW(session.write(tempPath("never.yaml"), "", ""), CalibrationError) << "no views";
  EXPECT_FALSE(exists(tempPath("never.yaml")));
  EXPECT_EQ(boardNotFoundMessage(parseBoardSize("8x5", 0.02)),
            "checkerboard of 8x5 inner corners not found in the image (the whole board must be visible, lit and in "
            "focus)");
}

TEST(CalibrationPrompts, CaptureLines)
{
  EXPECT_EQ(capturedViewLine(2, 3, "0.700 m: 5"), "captured view 2 of 3, plane at 0.700 m: 5");
  EXPECT_EQ(capturedViewLine(4, 3, "x"), "captured view 4, plane at x");
  EXPECT_EQ(capturedViewLine(1, 0, "x"), "captured view 1, plane at x");
  EXPECT_EQ(capturedPoseLine(2, 3, 900), "captured plane pose 2 of 3: 900 primitives decoded");
  EXPECT_EQ(capturedPoseLine(4, 3, 900), "captured plane pose 4 (3 needed): 900 primitives decoded");
}
