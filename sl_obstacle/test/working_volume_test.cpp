// Tests of WorkingVolume: box membership, window membership, validation.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include <sl_testing/errors.h>
#include "sl_obstacle/working_volume.h"

namespace sl_obstacle
{
namespace
{
using sl_testing::validationError;

TEST(WorkingVolume, DefaultsAreThePrototypesWindow)
{
  const WorkingVolume v;
  EXPECT_DOUBLE_EQ(v.width, 0.331);
  EXPECT_DOUBLE_EQ(v.height, 0.173);
  EXPECT_NO_THROW(v.validate());
}

TEST(WorkingVolume, ContainsAndWindow)
{
  const WorkingVolume v;
  EXPECT_TRUE(v.contains(makePoint(0.4F, 0.0F, 0.1F)));
  EXPECT_FALSE(v.contains(makePoint(0.4F, 0.0F, 0.005F)));  // floor
  EXPECT_TRUE(v.inWindow(makePoint(0.4F, 0.0F, 0.005F)));   // but measured
  EXPECT_TRUE(v.inWindow(makePoint(0.4F, 0.0F, -0.01F)));   // floor noise below 0
  EXPECT_FALSE(v.inWindow(makePoint(0.4F, 0.0F, -0.05F)));  // below the floor margin under 0
  EXPECT_FALSE(v.inWindow(makePoint(0.4F, 0.2F, 0.1F)));    // beside the window
  EXPECT_TRUE(v.inWindow(makePoint(2.0F, 0.0F, 0.1F)));     // x does not matter for the window
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(v.contains(makePoint(nan, 0.0F, 0.1F)));
  EXPECT_FALSE(v.contains(makePoint(0.4F, nan, 0.1F)));
  EXPECT_FALSE(v.contains(makePoint(0.4F, 0.0F, nan)));
  EXPECT_FALSE(v.inWindow(makePoint(0.4F, nan, 0.1F)));
}

TEST(WorkingVolume, ValidationNamesTheParameter)
{
  WorkingVolume v;
  v.height = 0.0;
  EXPECT_THROW(v.validate(), std::invalid_argument);
  EXPECT_EQ(validationError(v).rfind("height", 0), 0U) << validationError(v);
  v = WorkingVolume();
  v.max_range = std::nan("");
  EXPECT_EQ(validationError(v).rfind("max_range", 0), 0U) << validationError(v);
  v = WorkingVolume();
  v.max_range = 0.5;  // below depth
  EXPECT_EQ(validationError(v).rfind("depth", 0), 0U) << validationError(v);
  EXPECT_NE(validationError(v).find("got 0.8"), std::string::npos) << validationError(v);
}
}  // namespace
}  // namespace sl_obstacle
