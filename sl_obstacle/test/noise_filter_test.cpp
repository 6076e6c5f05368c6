// Tests of NoiseFilter: minimum cluster size, cluster tolerance, persistence over frames.
#include <gtest/gtest.h>

#include <cstdint>
#include <numeric>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "sl_obstacle/noise_filter.h"

namespace sl_obstacle
{
namespace
{
std::vector<std::uint32_t> allIndices(const std::vector<Point>& points)
{
  std::vector<std::uint32_t> indices(points.size());
  std::iota(indices.begin(), indices.end(), 0U);
  return indices;
}

NoiseFilter makeFilter(int min_cluster_size, int persistence_frames, double tolerance = 0.03)
{
  NoiseFilterParams p;
  p.min_cluster_size = min_cluster_size;
  p.persistence_frames = persistence_frames;
  p.cluster_tolerance = tolerance;
  NoiseFilter filter;
  filter.configure(p, WorkingVolume(), 0.02);
  return filter;
}

/// What apply() makes of all points of a frame.
struct Applied
{
  NoiseStats stats;
  std::vector<std::uint32_t> accepted;
};

Applied applyAll(NoiseFilter& filter, const std::vector<Point>& points)
{
  Applied out;
  out.stats = filter.apply(points.data(), allIndices(points), out.accepted);
  return out;
}

std::size_t acceptedCount(NoiseFilter& filter, const std::vector<Point>& points)
{
  return applyAll(filter, points).accepted.size();
}

TEST(NoiseFilter, SingleStrayPointIsRejected)
{
  NoiseFilter filter = makeFilter(3, 1);
  const std::vector<Point> points{ makePoint(0.4F, 0.0F, 0.1F) };
  const Applied applied = applyAll(filter, points);
  EXPECT_TRUE(applied.accepted.empty());
  EXPECT_EQ(applied.stats.candidates, 1U);
  EXPECT_EQ(applied.stats.clusters, 1U);
  EXPECT_EQ(applied.stats.accepted_clusters, 0U);
  EXPECT_EQ(applied.stats.rejected_by_cluster, 1U);
}

TEST(NoiseFilter, MinimumClusterSize)
{
  NoiseFilter filter = makeFilter(3, 1);
  std::vector<Point> points{ makePoint(0.4F, 0.0F, 0.1F), makePoint(0.4F, 0.005F, 0.1F) };
  EXPECT_EQ(acceptedCount(filter, points), 0U);
  points.push_back(makePoint(0.4F, 0.0F, 0.111F));
  EXPECT_EQ(acceptedCount(filter, points), 3U);
}

TEST(NoiseFilter, ClustersAreTransitiveWithinTheTolerance)
{
  NoiseFilter filter = makeFilter(3, 1, 0.03);
  // A chain with 25 mm links is one cluster although its ends are 50 mm apart.
  const std::vector<Point> chain{ makePoint(0.4F, 0.0F, 0.1F), makePoint(0.4F, 0.025F, 0.1F),
                                  makePoint(0.4F, 0.05F, 0.1F) };
  EXPECT_EQ(acceptedCount(filter, chain), 3U);
  // 40 mm links: three single points.
  const std::vector<Point> spread{ makePoint(0.4F, 0.0F, 0.1F), makePoint(0.4F, 0.04F, 0.1F),
                                   makePoint(0.4F, 0.08F, 0.1F) };
  const Applied applied = applyAll(filter, spread);
  EXPECT_TRUE(applied.accepted.empty());
  EXPECT_EQ(applied.stats.clusters, 3U);
  // Distance is 3D: points close in y but apart in x are not linked.
  const std::vector<Point> deep{ makePoint(0.3F, 0.0F, 0.1F), makePoint(0.4F, 0.001F, 0.1F),
                                 makePoint(0.5F, 0.002F, 0.1F) };
  EXPECT_EQ(acceptedCount(filter, deep), 0U);
}

TEST(NoiseFilter, StrayPointsBesideAnObstacleAreRejectedAlone)
{
  NoiseFilter filter = makeFilter(3, 1);
  std::vector<Point> points;
  for (int i = 0; i < 10; ++i)
  {
    points.push_back(makePoint(0.5F, 0.0F, 0.05F + 0.011F * i));  // a leg, one column
  }
  points.push_back(makePoint(0.2F, 0.1F, 0.1F));  // stray
  const Applied applied = applyAll(filter, points);
  EXPECT_EQ(applied.accepted.size(), 10U);
  EXPECT_EQ(applied.stats.clusters, 2U);
  EXPECT_EQ(applied.stats.largest_cluster, 10U);
  for (std::uint32_t i : applied.accepted)
  {
    EXPECT_LT(i, 10U);
  }
}

TEST(NoiseFilter, PersistenceNeedsConsecutiveFrames)
{
  NoiseFilter filter = makeFilter(1, 3);
  const std::vector<Point> leg{ makePoint(0.5F, 0.0F, 0.1F), makePoint(0.5F, 0.0F, 0.111F) };
  EXPECT_EQ(acceptedCount(filter, leg), 0U);
  EXPECT_EQ(acceptedCount(filter, leg), 0U);
  EXPECT_EQ(acceptedCount(filter, leg), 2U);
  EXPECT_EQ(acceptedCount(filter, leg), 2U);
  // A frame without it breaks the chain.
  EXPECT_EQ(acceptedCount(filter, std::vector<Point>()), 0U);
  EXPECT_EQ(acceptedCount(filter, leg), 0U);
}

TEST(NoiseFilter, PersistenceFollowsAnApproachingObstacle)
{
  NoiseFilter filter = makeFilter(1, 2);
  // The robot drives toward it: x shrinks 20 mm per frame (within persistence_tolerance 50 mm).
  std::size_t last = 0;
  for (int frame = 0; frame < 5; ++frame)
  {
    const float x = 0.6F - 0.02F * frame;
    last = acceptedCount(filter, { makePoint(x, 0.0F, 0.1F) });
    EXPECT_EQ(last, frame == 0 ? 0U : 1U) << "frame " << frame;
  }
  // A jump of 200 mm in the same cell is a different thing: starts over.
  EXPECT_EQ(acceptedCount(filter, { makePoint(0.3F, 0.0F, 0.1F) }), 0U);
}

TEST(NoiseFilter, RandomStrayPointsNeverPersist)
{
  NoiseFilter filter = makeFilter(1, 3);
  std::mt19937 rng(42);
  std::uniform_real_distribution<float> x(0.05F, 0.8F);
  std::uniform_real_distribution<float> y(-0.16F, 0.16F);
  std::uniform_real_distribution<float> z(0.02F, 0.17F);
  std::size_t accepted = 0;
  for (int frame = 0; frame < 50; ++frame)
  {
    std::vector<Point> points;
    for (int i = 0; i < 3; ++i)
    {
      points.push_back(makePoint(x(rng), y(rng), z(rng)));
    }
    accepted += acceptedCount(filter, points);
  }
  EXPECT_EQ(accepted, 0U);
}

TEST(NoiseFilter, BothTestsCombine)
{
  NoiseFilter filter = makeFilter(3, 2);
  const std::vector<Point> leg{ makePoint(0.5F, 0.0F, 0.1F), makePoint(0.5F, 0.005F, 0.1F),
                                makePoint(0.5F, 0.0F, 0.111F) };
  const Applied applied = applyAll(filter, leg);
  EXPECT_TRUE(applied.accepted.empty());
  EXPECT_EQ(applied.stats.rejected_by_persistence, 3U);
  EXPECT_EQ(applied.stats.rejected_by_cluster, 0U);
  EXPECT_EQ(acceptedCount(filter, leg), 3U);
  filter.reset();
  EXPECT_EQ(acceptedCount(filter, leg), 0U);
}

TEST(NoiseFilter, DisabledAcceptsEverything)
{
  NoiseFilter filter = makeFilter(1, 1);
  const std::vector<Point> points{ makePoint(0.2F, 0.1F, 0.1F), makePoint(0.7F, -0.1F, 0.05F) };
  EXPECT_EQ(acceptedCount(filter, points), 2U);
}

TEST(NoiseFilter, OnlyCandidatesAreConsidered)
{
  NoiseFilter filter = makeFilter(2, 1);
  const std::vector<Point> points{ makePoint(0.5F, 0.0F, 0.1F), makePoint(0.5F, 0.005F, 0.1F),
                                   makePoint(0.5F, 0.01F, 0.1F) };
  std::vector<std::uint32_t> accepted;
  filter.apply(points.data(), { 0U, 2U }, accepted);
  ASSERT_EQ(accepted.size(), 2U);
  EXPECT_EQ(accepted[0], 0U);
  EXPECT_EQ(accepted[1], 2U);
}

TEST(NoiseFilter, BadParametersThrowNamingTheParameter)
{
  const WorkingVolume volume;
  const char* names[] = { "min_cluster_size", "persistence_frames", "cluster_tolerance", "persistence_tolerance" };
  for (int k = 0; k < 4; ++k)
  {
    NoiseFilterParams p;
    switch (k)
    {
      case 0:
        p.min_cluster_size = -2;
        break;
      case 1:
        p.persistence_frames = 0;
        break;
      case 2:
        p.cluster_tolerance = std::nan("");
        break;
      default:
        p.persistence_tolerance = 5.0;
        break;
    }
    NoiseFilter filter;
    try
    {
      filter.configure(p, volume, 0.02);
      ADD_FAILURE() << "no exception for " << names[k];
    }
    catch (const std::invalid_argument& e)
    {
      EXPECT_EQ(std::string(e.what()).rfind(names[k], 0), 0U) << e.what();
    }
  }
  NoiseFilter filter;
  EXPECT_THROW(filter.configure(NoiseFilterParams(), volume, 0.0), std::invalid_argument);
}
}  // namespace
}  // namespace sl_obstacle
