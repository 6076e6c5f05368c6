#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "sl_rig/mono8.h"

using sl_rig::toMono8;

// By encoding name (image messages: the decoder, the calibration).

TEST(ToMono8, Mono8IsUsedAsIs)
{
  cv::Mat m(4, 5, CV_8UC1, cv::Scalar(7));
  bool converted = true;
  const cv::Mat out = toMono8(m, "mono8", converted);
  EXPECT_FALSE(converted);
  EXPECT_EQ(out.data, m.data);
}

TEST(ToMono8, ConvertsMono16ColourAndAlpha)
{
  bool converted = false;
  cv::Mat m16(2, 2, CV_16UC1, cv::Scalar(0));
  m16.at<uint16_t>(0, 0) = 65535;
  m16.at<uint16_t>(1, 1) = 32768;
  m16.at<uint16_t>(0, 1) = 4095;  // a 12-bit sensor's full scale, read as 16 bits: dark
  const cv::Mat a = toMono8(m16, "mono16", converted);
  EXPECT_TRUE(converted);
  ASSERT_EQ(a.type(), CV_8UC1);
  EXPECT_EQ(a.at<uint8_t>(0, 0), 255);
  EXPECT_EQ(a.at<uint8_t>(1, 1), 128);
  EXPECT_EQ(a.at<uint8_t>(0, 1), 16);
  // With the sensor's 12 significant bits its full scale is white; the frame's maximum plays no part.
  m16.at<uint16_t>(0, 0) = 0;
  m16.at<uint16_t>(1, 1) = 2048;
  const cv::Mat twelve = toMono8(m16, "mono16", converted, 12);
  EXPECT_EQ(twelve.at<uint8_t>(0, 1), 255);
  EXPECT_EQ(twelve.at<uint8_t>(1, 1), 128);
  EXPECT_EQ(toMono8(cv::Mat(2, 2, CV_16UC1, cv::Scalar(1024)), "16UC1", converted).at<uint8_t>(0, 0), 4);

  cv::Mat rgb(2, 2, CV_8UC3, cv::Scalar(255, 0, 0));  // pure red when read as rgb8
  const cv::Mat r = toMono8(rgb, "rgb8", converted);
  const cv::Mat b = toMono8(rgb, "bgr8", converted);
  EXPECT_NEAR(r.at<uint8_t>(0, 0), 76, 1);  // 0.299 * 255
  EXPECT_NEAR(b.at<uint8_t>(0, 0), 29, 1);  // 0.114 * 255
  cv::Mat rgba(2, 2, CV_8UC4, cv::Scalar(10, 10, 10, 255));
  EXPECT_EQ(toMono8(rgba, "bgra8", converted).at<uint8_t>(1, 1), 10);
  cv::Mat red_rgba(2, 2, CV_8UC4, cv::Scalar(255, 0, 0, 0));
  EXPECT_NEAR(toMono8(red_rgba, "rgba8", converted).at<uint8_t>(0, 0), 76, 1);
}

TEST(ToMono8, RejectsUnsupportedEncodingsByName)
{
  bool converted = false;
  cv::Mat f(2, 2, CV_32FC1, cv::Scalar(0.5));
  try
  {
    toMono8(f, "32FC1", converted);
    FAIL();
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_NE(std::string(e.what()).find("'32FC1'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(toMono8(cv::Mat(2, 2, CV_8UC3), "mono8", converted), std::invalid_argument);
  EXPECT_THROW(toMono8(cv::Mat(2, 2, CV_8UC1), "rgb8", converted), std::invalid_argument);
  EXPECT_THROW(toMono8(cv::Mat(2, 2, CV_8UC1), "bayer_rggb8", converted), std::invalid_argument);
  try
  {
    toMono8(cv::Mat(2, 2, CV_8UC1), "mono16", converted);
    FAIL();
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_EQ(std::string(e.what()), "image claims mono16 but is 8UC1, not 16UC1");
  }
}

// By type and significant bits (the camera drivers and the player).

TEST(CameraMono8, ConvertsSupportedTypesAndRejectsOthers)
{
  cv::Mat out;
  toMono8(cv::Mat(2, 2, CV_16UC1, cv::Scalar(4095)), out, 12);
  EXPECT_EQ(out.type(), CV_8UC1);
  EXPECT_EQ(out.at<uint8_t>(0, 0), 255);
  toMono8(cv::Mat(2, 2, CV_16UC1, cv::Scalar(1024)), out, 10);
  EXPECT_EQ(out.at<uint8_t>(0, 0), 255);
  toMono8(cv::Mat(2, 2, CV_32FC1, cv::Scalar(0.5)), out);
  EXPECT_NEAR(out.at<uint8_t>(0, 0), 128, 1);
  EXPECT_THROW(toMono8(cv::Mat(), out), std::invalid_argument);
  try
  {
    toMono8(cv::Mat(2, 2, CV_8UC2), out);
    FAIL();
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_NE(std::string(e.what()).find("8UC2"), std::string::npos) << e.what();
  }
}

TEST(CameraMono8, SixteenBitColourAndBadSignificantBits)
{
  cv::Mat out;
  // 16-bit BGR white at 12 bits and 16 bits.
  toMono8(cv::Mat(2, 2, CV_16UC3, cv::Scalar(4095, 4095, 4095)), out, 12);
  EXPECT_EQ(out.at<uint8_t>(1, 1), 255);
  toMono8(cv::Mat(2, 2, CV_16UC4, cv::Scalar(65535, 65535, 65535, 0)), out);
  EXPECT_EQ(out.at<uint8_t>(1, 1), 255);
  // Colour order: blue as BGR and as RGB.
  const cv::Mat blue(2, 2, CV_8UC3, cv::Scalar(255, 0, 0));
  toMono8(blue, out);
  EXPECT_NEAR(out.at<uint8_t>(0, 0), 29, 1);
  toMono8(blue, out, 16, sl_rig::ChannelOrder::Rgb);
  EXPECT_NEAR(out.at<uint8_t>(0, 0), 76, 1);
  EXPECT_THROW(toMono8(cv::Mat(2, 2, CV_16UC1), out, 7), std::invalid_argument);
  EXPECT_THROW(toMono8(cv::Mat(2, 2, CV_16UC1), out, 17), std::invalid_argument);
}
