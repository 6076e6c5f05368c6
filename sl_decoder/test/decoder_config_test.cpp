#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>
#include <string>

#include <sl_testing/errors.h>

#include "sl_decoder/decoder_config.h"

using namespace sl_decoder;
using sl_testing::refusedNaming;
using sl_testing::validationError;

TEST(DecoderConfig, DefaultsAreValid)
{
  EXPECT_EQ(validationError(DecoderConfig()), "");
}

TEST(DecoderConfig, ErrorsNameTheField)
{
  EXPECT_TRUE(refusedNaming<DecoderConfig>("threshold_window", [](auto& c) { c.threshold_window = 14; }));
  EXPECT_TRUE(refusedNaming<DecoderConfig>("max_depth", [](auto& c) { c.max_depth = 0.1; }));
  EXPECT_TRUE(refusedNaming<DecoderConfig>(
      "epipolar_tolerance", [](auto& c) { c.epipolar_tolerance = std::numeric_limits<double>::quiet_NaN(); }));
  EXPECT_TRUE(refusedNaming<DecoderConfig>("neighbour_along_max", [](auto& c) { c.neighbour_along_max = 0.5; }));
  EXPECT_TRUE(refusedNaming<DecoderConfig>("min_support", [](auto& c) { c.min_support = 0; }));
  EXPECT_TRUE(refusedNaming<DecoderConfig>("max_area", [](auto& c) { c.max_area = 3; }));
}

TEST(DecoderConfig, DepthModes)
{
  EXPECT_EQ(parseDepthMode("triangulation"), DepthMode::Triangulation);
  EXPECT_EQ(parseDepthMode("rational"), DepthMode::Rational);
  EXPECT_EQ(parseDepthMode("linear"), DepthMode::Linear);
  EXPECT_STREQ(depthModeName(DepthMode::Rational), "rational");
  EXPECT_THROW(parseDepthMode("cubic"), std::invalid_argument);
}
