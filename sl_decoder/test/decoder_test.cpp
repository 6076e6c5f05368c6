// The decoder on images and rigs that need no rendering: bad images, rigs it must refuse.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <utility>

#include <opencv2/core.hpp>

#include "sl_decoder/decoder.h"
#include "sl_decoder/epipolar_index.h"
#include "sl_projector/rig.h"

using namespace sl_decoder;

namespace
{
const sl_projector::Rig& defaultRig()
{
  static const sl_projector::Rig rig = sl_projector::loadRig(SL_PROJECTOR_CONFIG_DIR "/default_rig.yaml");
  return rig;
}
}  // namespace

TEST(Decoder, BadImagesAreHandled)
{
  Decoder decoder(defaultRig());
  DecodeResult result;
  for (int level : { 0, 255, 128 })
  {
    decoder.decode(cv::Mat(480, 752, CV_8UC1, cv::Scalar(level)), result);
    EXPECT_EQ(result.valid, 0) << level;
    EXPECT_EQ(result.decoded, 0) << level;
  }
  EXPECT_THROW(decoder.decode(cv::Mat(480, 640, CV_8UC1, cv::Scalar(0)), result), std::invalid_argument);
  EXPECT_THROW(decoder.decode(cv::Mat(480, 752, CV_16UC1, cv::Scalar(0)), result), std::invalid_argument);
  EXPECT_THROW(decoder.decode(cv::Mat(), result), std::invalid_argument);
}

// A rig with a 262144 x 262144 camera made sl_decode segfault: the table sizes overflowed int and
// the buffers came out too small. Both entry points refuse it before allocating anything.
TEST(Decoder, HugeCamerasAreRefusedNotOverflowed)
{
  for (const auto& size : { std::make_pair(262144, 262144), std::make_pair(400000, 300000) })
  {
    sl_projector::Rig rig = defaultRig();
    rig.camera.width = size.first;
    rig.camera.height = size.second;
    EXPECT_THROW(Decoder{ rig }, std::invalid_argument) << size.first;
    // The index checks its own sizes too (it does not rely on the rig having been validated).
    try
    {
      EpipolarIndex index(rig, DecoderConfig());
      ADD_FAILURE() << "a " << size.first << " x " << size.second << " camera was accepted";
    }
    catch (const std::invalid_argument& e)
    {
      EXPECT_EQ(std::string(e.what()).rfind("camera image: ", 0), 0u) << e.what();
    }
  }
}

TEST(Decoder, DepthTablesAreRequiredForTableModes)
{
  DecoderConfig c;
  c.depth_mode = DepthMode::Rational;
  EXPECT_THROW(Decoder(defaultRig(), c), std::invalid_argument);
  c.depth_mode = DepthMode::Linear;
  EXPECT_THROW(Decoder(defaultRig(), c), std::invalid_argument);
  c = DecoderConfig();
  c.min_depth = -1.0;
  EXPECT_THROW(Decoder(defaultRig(), c), std::invalid_argument);
}
