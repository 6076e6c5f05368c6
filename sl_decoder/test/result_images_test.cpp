// Images drawn from a decoding result, and the node's counters and summary.
#include <gtest/gtest.h>

#include <cmath>

#include <opencv2/core.hpp>

#include "sl_decoder/decoder_stats.h"
#include "sl_decoder/result_images.h"

using namespace sl_decoder;

namespace
{
Blob blobAt(float u, float v, bool valid, float z, int row = -1, int col = -1)
{
  Blob b;
  b.u = u;
  b.v = v;
  b.x0 = static_cast<int>(u) - 2;
  b.y0 = static_cast<int>(v) - 2;
  b.x1 = b.x0 + 5;
  b.y1 = b.y0 + 5;
  b.valid = valid;
  b.z = z;
  b.row = row;
  b.col = col;
  b.shape = row >= 0 ? 2 : 0;
  return b;
}
}  // namespace

TEST(DepthImage, EachValidBlobAtItsRoundedCentroidNaNElsewhere)
{
  DecodeResult r;
  r.blobs = { blobAt(10.4f, 5.6f, true, 0.7f, 1, 1), blobAt(20.f, 8.f, false, 0.9f, 1, 2),
              blobAt(39.6f, 29.4f, true, 0.5f, 2, 2) };
  const cv::Mat d = depthImage(r, 40, 30);
  ASSERT_EQ(d.type(), CV_32FC1);
  ASSERT_EQ(d.cols, 40);
  ASSERT_EQ(d.rows, 30);
  EXPECT_FLOAT_EQ(d.at<float>(6, 10), 0.7f);
  EXPECT_TRUE(std::isnan(d.at<float>(8, 20)));  // not valid: no depth
  EXPECT_EQ(cv::countNonZero(d == d), 1);       // the centroid at (40, 29) rounds outside: left out
}

TEST(DepthImage, AnEmptyResultIsAllNaN)
{
  const cv::Mat d = depthImage(DecodeResult(), 8, 4);
  EXPECT_EQ(cv::countNonZero(d == d), 0);
}

TEST(DebugImage, GreyImageWithBoxesAndDecodedCentres)
{
  cv::Mat mono(40, 60, CV_8UC1, cv::Scalar(50));
  DecodeResult r;
  r.blobs = { blobAt(15.f, 20.f, true, 0.7f, 3, 4), blobAt(45.f, 20.f, false, 0.f) };
  cv::Mat bgr;
  drawDebugImage(mono, r, bgr);
  ASSERT_EQ(bgr.type(), CV_8UC3);
  ASSERT_EQ(bgr.size(), mono.size());
  EXPECT_EQ(bgr.at<cv::Vec3b>(0, 0), cv::Vec3b(50, 50, 50));                       // untouched: the grey image
  EXPECT_EQ(bgr.at<cv::Vec3b>(20, 15), cv::Vec3b(255, 255, 255));                  // decoded centroid: white dot
  EXPECT_EQ(bgr.at<cv::Vec3b>(18, 43), cv::Vec3b(128, 128, 128));                  // unidentified blob's box: grey
  EXPECT_EQ(bgr.at<cv::Vec3b>(20, 45), cv::Vec3b(50, 50, 50));                     // not decoded: no dot
  EXPECT_EQ(bgr.at<cv::Vec3b>(18, 13), cv::Vec3b(80, 220, 80));                    // shape 2's box colour
  EXPECT_GT(cv::countNonZero(bgr(cv::Rect(13, 0, 20, 17)).reshape(1) == 255), 0);  // the label above
}

TEST(DecoderStats, IdleThenDecodingThenNoPoints)
{
  DecoderStats s;
  EXPECT_EQ(s.level(), DecoderStats::Level::Ok);
  EXPECT_EQ(s.summary(), "no image decoded yet (idle until someone subscribes)");
  EXPECT_EQ(s.validFraction(), 0.0);

  DecodeResult r;
  r.blobs.resize(4);
  r.decoded = 3;
  r.valid = 2;
  r.times.total = 7.5;
  s.recordFrame(r);
  EXPECT_EQ(s.frames, 1);
  EXPECT_EQ(s.last_blobs, 4);
  EXPECT_EQ(s.last_decoded, 3);
  EXPECT_EQ(s.last_valid, 2);
  EXPECT_DOUBLE_EQ(s.last_ms, 7.5);
  EXPECT_DOUBLE_EQ(s.validFraction(), 0.5);
  EXPECT_EQ(s.level(), DecoderStats::Level::Ok);
  EXPECT_EQ(s.summary(), "decoding");

  s.recordFrame(DecodeResult());
  EXPECT_EQ(s.frames, 2);
  EXPECT_EQ(s.validFraction(), 0.0);
  EXPECT_EQ(s.level(), DecoderStats::Level::Warn);
  EXPECT_EQ(s.summary(), "no points in the last image");
}
