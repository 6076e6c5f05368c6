#include <gtest/gtest.h>

#include <set>
#include <stdexcept>
#include <string>

#include <sl_testing/errors.h>

#include "sl_rig/checked_yaml.h"

using sl_rig::checkKeys;
using sl_rig::nearestKey;
using sl_testing::invalidArgumentOf;

namespace
{
const std::set<std::string> kPinholeKeys = { "width", "height", "K", "D" };
}  // namespace

TEST(CheckedYaml, KnownKeysPass)
{
  EXPECT_NO_THROW(checkKeys(YAML::Load("{width: 3, K: [1], D: 2}"), kPinholeKeys, "camera."));
  EXPECT_NO_THROW(checkKeys(YAML::Load("{}"), kPinholeKeys));
}

TEST(CheckedYaml, UnknownKeyIsNamedWithTheNearestAndTheAllowedOnes)
{
  EXPECT_EQ(invalidArgumentOf([] { checkKeys(YAML::Load("{width: 3, Kx: 1}"), kPinholeKeys, "camera."); }),
            "camera.Kx: unknown key, did you mean 'K'? (allowed: D, K, height, width)");
  EXPECT_EQ(invalidArgumentOf([] { checkKeys(YAML::Load("{hieght: 3}"), kPinholeKeys, "camera."); }),
            "camera.hieght: unknown key, did you mean 'height'? (allowed: D, K, height, width)");
  EXPECT_EQ(invalidArgumentOf([] { checkKeys(YAML::Load("{lens: 3}"), kPinholeKeys); }),
            "lens: unknown key (allowed: D, K, height, width)");
}

TEST(CheckedYaml, KeysThatAreNoNamesAndNoMappingAreRefused)
{
  EXPECT_EQ(invalidArgumentOf([] { checkKeys(YAML::Load("[1]: 2"), kPinholeKeys); }),
            "[1]: a key must be a name, not a list or a mapping (line 1)");
  EXPECT_EQ(invalidArgumentOf([] { checkKeys(YAML::Load("width: 1\n~: 2\n"), kPinholeKeys, "camera."); }),
            "camera.<empty key>: a key must be a name, not empty (line 2)");
  EXPECT_EQ(invalidArgumentOf([] { checkKeys(YAML::Load("? :"), kPinholeKeys); }),
            "{~: ~}: a key must be a name, not a list or a mapping (line 1)");
  EXPECT_EQ(invalidArgumentOf([] { checkKeys(YAML::Load("[1, 2]"), kPinholeKeys, "camera."); }),
            "camera: must be a mapping");
  EXPECT_EQ(invalidArgumentOf([] { checkKeys(YAML::Load("3"), kPinholeKeys); }), "<top level>: must be a mapping");
}

TEST(CheckedYaml, NearestKeyOnlyWhenCloseAndUnique)
{
  const std::set<std::string> pattern = { "rows", "cols", "gap_x", "gap_y", "flip_x", "flip_y", "primitive_width" };
  EXPECT_EQ(nearestKey("rosw", pattern), "rows");  // neighbours swapped: one edit
  EXPECT_EQ(nearestKey("primitive_widht", pattern), "primitive_width");
  EXPECT_EQ(nearestKey("primitve_width", pattern), "primitive_width");
  EXPECT_EQ(nearestKey("gap", pattern), "");     // two edits from gap_x: too far for 3 characters
  EXPECT_EQ(nearestKey("gap_z", pattern), "");   // as near to both
  EXPECT_EQ(nearestKey("colour", pattern), "");  // too far from everything
  EXPECT_EQ(nearestKey("", pattern), "");
  EXPECT_EQ(nearestKey("rows", {}), "");
}
