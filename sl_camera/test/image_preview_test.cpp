// ImagePreview: the frames it picks keep the configured average rate, and shrinking averages blocks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <opencv2/core.hpp>

#include <sl_testing/errors.h>
#include "sl_camera/preview/image_preview.h"

using sl_camera::ImagePreview;
using sl_camera::PreviewConfig;
using sl_testing::refusedNaming;

namespace
{
PreviewConfig config(int scale, double rate)
{
  PreviewConfig c;
  c.scale = scale;
  c.rate = rate;
  return c;
}
}  // namespace

TEST(ImagePreview, RefusesSettingsNamingThem)
{
  EXPECT_TRUE(refusedNaming<PreviewConfig>("scale", [](PreviewConfig& c) { c.scale = 0; }));
  EXPECT_TRUE(refusedNaming<PreviewConfig>("scale", [](PreviewConfig& c) { c.scale = 17; }));
  EXPECT_TRUE(refusedNaming<PreviewConfig>("rate", [](PreviewConfig& c) { c.rate = 0.0; }));
  EXPECT_TRUE(refusedNaming<PreviewConfig>("rate", [](PreviewConfig& c) { c.rate = -1.0; }));
  EXPECT_TRUE(refusedNaming<PreviewConfig>("rate", [](PreviewConfig& c) { c.rate = 1e4; }));
  EXPECT_TRUE(refusedNaming<PreviewConfig>(
      "rate", [](PreviewConfig& c) { c.rate = std::numeric_limits<double>::quiet_NaN(); }));
  EXPECT_EQ(sl_testing::validationError(PreviewConfig()), "");
  EXPECT_THROW(ImagePreview(config(0, 2.0)), std::invalid_argument);
}

TEST(ImagePreview, KeepsTheAverageRateWithJitteredFrames)
{
  // 10 Hz frames, each up to 3 ms early or late, for 100 s: 2 Hz gives 200 frames, evenly apart.
  ImagePreview preview(config(2, 2.0));
  int shown = 0;
  double last = -1.0;
  double longest = 0.0;
  for (int i = 0; i < 1000; ++i)
  {
    const double t = 5.0 + 0.1 * i + 0.003 * std::sin(1.7 * i);
    if (!preview.due(t))
      continue;
    ++shown;
    if (last >= 0.0)
      longest = std::max(longest, t - last);
    last = t;
  }
  EXPECT_EQ(shown, 200);
  EXPECT_LT(longest, 0.61);
}

TEST(ImagePreview, ShowsEveryFrameBelowTheRate)
{
  ImagePreview preview(config(1, 30.0));
  for (int i = 0; i < 50; ++i)
    EXPECT_TRUE(preview.due(0.1 * i)) << i;
}

TEST(ImagePreview, StartsAnewAfterAGapOrWhenTimeRunsBack)
{
  ImagePreview preview(config(2, 1.0));
  EXPECT_TRUE(preview.due(100.0));
  EXPECT_FALSE(preview.due(100.5));
  EXPECT_TRUE(preview.due(101.0));
  EXPECT_TRUE(preview.due(110.0));   // a gap: shown at once, not ten frames late
  EXPECT_FALSE(preview.due(110.9));  // and the schedule restarts from it
  EXPECT_TRUE(preview.due(3.0));     // a bag played again: its first frame is shown
  EXPECT_FALSE(preview.due(3.5));
}

TEST(ImagePreview, ShrinksByAveragingBlocks)
{
  ImagePreview preview(config(2, 2.0));
  cv::Mat mono(480, 752, CV_8UC1, cv::Scalar(0));
  mono(cv::Rect(0, 0, 752, 240)).setTo(200);  // top half bright
  mono.at<uint8_t>(300, 10) = 255;            // one bright pixel: a quarter of its block's mean
  cv::Mat out;
  preview.shrink(mono, out);
  ASSERT_EQ(out.type(), CV_8UC1);
  EXPECT_EQ(out.cols, 376);
  EXPECT_EQ(out.rows, 240);
  EXPECT_EQ(out.at<uint8_t>(0, 0), 200);
  EXPECT_EQ(out.at<uint8_t>(239, 375), 0);
  EXPECT_NEAR(out.at<uint8_t>(150, 5), 64, 1);

  cv::Mat colour(480, 752, CV_8UC3, cv::Scalar(255, 0, 0));
  ImagePreview(config(3, 2.0)).shrink(colour, out);
  ASSERT_EQ(out.type(), CV_8UC3);
  EXPECT_EQ(out.cols, 250);  // rounded down
  EXPECT_EQ(out.rows, 160);
  EXPECT_EQ(out.at<cv::Vec3b>(80, 100), cv::Vec3b(255, 0, 0));
}

TEST(ImagePreview, KeepsTinyImagesAndRefusesEmptyOnes)
{
  ImagePreview preview(config(16, 2.0));
  cv::Mat out;
  preview.shrink(cv::Mat(4, 3, CV_32FC1, cv::Scalar(1.5f)), out);
  EXPECT_EQ(out.size(), cv::Size(1, 1));
  EXPECT_FLOAT_EQ(out.at<float>(0, 0), 1.5f);
  EXPECT_THROW(preview.shrink(cv::Mat(), out), std::invalid_argument);
  ImagePreview(config(1, 2.0)).shrink(cv::Mat(5, 7, CV_16UC1, cv::Scalar(1000)), out);
  EXPECT_EQ(out.size(), cv::Size(7, 5));
  EXPECT_EQ(out.at<uint16_t>(4, 6), 1000);
}
