#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "sl_decoder/decoder.h"

using sl_decoder::toMono8;

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
  m16.at<uint16_t>(0, 0) = 4095;  // a 12-bit sensor's full scale
  m16.at<uint16_t>(1, 1) = 2048;
  const cv::Mat a = toMono8(m16, "mono16", converted);
  EXPECT_TRUE(converted);
  ASSERT_EQ(a.type(), CV_8UC1);
  EXPECT_EQ(a.at<uint8_t>(0, 0), 255);
  EXPECT_NEAR(a.at<uint8_t>(1, 1), 128, 1);

  cv::Mat rgb(2, 2, CV_8UC3, cv::Scalar(255, 0, 0));  // pure red when read as rgb8
  const cv::Mat r = toMono8(rgb, "rgb8", converted);
  const cv::Mat b = toMono8(rgb, "bgr8", converted);
  EXPECT_NEAR(r.at<uint8_t>(0, 0), 76, 1);  // 0.299 * 255
  EXPECT_NEAR(b.at<uint8_t>(0, 0), 29, 1);  // 0.114 * 255
  cv::Mat rgba(2, 2, CV_8UC4, cv::Scalar(10, 10, 10, 255));
  EXPECT_EQ(toMono8(rgba, "bgra8", converted).at<uint8_t>(1, 1), 10);
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
}
