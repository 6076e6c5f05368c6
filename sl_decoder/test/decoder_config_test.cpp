#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>
#include <string>

#include <sl_testing/errors.h>

#include "sl_decoder/decoder_config.h"

using namespace sl_decoder;
using sl_testing::validationError;

TEST(DecoderConfig, DefaultsAreValid)
{
  EXPECT_EQ(validationError(DecoderConfig()), "");
}

TEST(DecoderConfig, ErrorsNameTheField)
{
  DecoderConfig c;
  c.threshold_window = 14;
  EXPECT_EQ(validationError(c).rfind("threshold_window", 0), 0u);
  c = DecoderConfig();
  c.max_depth = 0.1;
  EXPECT_EQ(validationError(c).rfind("max_depth", 0), 0u);
  c = DecoderConfig();
  c.epipolar_tolerance = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(validationError(c).rfind("epipolar_tolerance", 0), 0u);
  c = DecoderConfig();
  c.neighbour_along_max = 0.5;
  EXPECT_EQ(validationError(c).rfind("neighbour_along_max", 0), 0u);
  c = DecoderConfig();
  c.min_support = 0;
  EXPECT_EQ(validationError(c).rfind("min_support", 0), 0u);
  c = DecoderConfig();
  c.max_area = 3;
  EXPECT_EQ(validationError(c).rfind("max_area", 0), 0u);
}

TEST(DecoderConfig, DepthModes)
{
  EXPECT_EQ(parseDepthMode("triangulation"), DepthMode::Triangulation);
  EXPECT_EQ(parseDepthMode("rational"), DepthMode::Rational);
  EXPECT_EQ(parseDepthMode("linear"), DepthMode::Linear);
  EXPECT_STREQ(depthModeName(DepthMode::Rational), "rational");
  EXPECT_THROW(parseDepthMode("cubic"), std::invalid_argument);
}
