// CloudPairing: each image's ray ends go in once, after its points when they come, in either order.
#include <gtest/gtest.h>

#include <optional>
#include <string>

#include "sl_obstacle/cloud_pairing.h"

using sl_obstacle::CloudPairing;
using Pairing = CloudPairing<std::string, int>;

TEST(CloudPairing, RaysAfterTheirPointsGoInAtOnceWithThem)
{
  Pairing p;
  EXPECT_FALSE(p.onPoints("points1", 1));
  std::optional<std::string> older;
  const auto in = p.onRays("rays1", 1, older);
  ASSERT_TRUE(in);
  EXPECT_EQ(in->rays, "rays1");
  ASSERT_TRUE(in->points);
  EXPECT_EQ(*in->points, "points1");
  EXPECT_FALSE(older);
  EXPECT_FALSE(p.waiting());
}

TEST(CloudPairing, RaysBeforeTheirPointsWaitForThem)
{
  Pairing p;
  std::optional<std::string> older;
  EXPECT_FALSE(p.onRays("rays1", 1, older));
  EXPECT_TRUE(p.waiting());
  const auto in = p.onPoints("points1", 1);
  ASSERT_TRUE(in);
  EXPECT_EQ(in->rays, "rays1");
  ASSERT_TRUE(in->points);
  EXPECT_EQ(*in->points, "points1");
  EXPECT_FALSE(p.waiting());
  EXPECT_FALSE(p.onPoints("points2", 2)) << "nothing waits any more";
}

TEST(CloudPairing, RaysWhosePointsNeverCameGoInAloneWhenNewerOnesArrive)
{
  Pairing p;
  std::optional<std::string> older;
  EXPECT_FALSE(p.onRays("rays1", 1, older));
  EXPECT_FALSE(p.onRays("rays2", 2, older));
  ASSERT_TRUE(older) << "the first image's points never came (gated)";
  EXPECT_EQ(*older, "rays1");
  // Newer points release the waiting rays, without points of another image.
  const auto in = p.onPoints("points3", 3);
  ASSERT_TRUE(in);
  EXPECT_EQ(in->rays, "rays2");
  EXPECT_FALSE(in->points);
}

TEST(CloudPairing, OlderPointsNeitherReleaseNorPairNewerRays)
{
  Pairing p;
  std::optional<std::string> older;
  EXPECT_FALSE(p.onPoints("points1", 1));
  EXPECT_FALSE(p.onRays("rays2", 2, older)) << "its points are still to come";
  EXPECT_FALSE(p.onPoints("points0", 0)) << "late points of an older image";
  EXPECT_TRUE(p.waiting());
  // Rays older than the newest points go in at once, alone.
  Pairing q;
  EXPECT_FALSE(q.onPoints("points5", 5));
  const auto in = q.onRays("rays4", 4, older);
  ASSERT_TRUE(in);
  EXPECT_EQ(in->rays, "rays4");
  EXPECT_FALSE(in->points);
}
