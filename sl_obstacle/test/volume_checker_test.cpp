// Tests of VolumeChecker on synthetic clouds: empty scene, walls, thin leg, stray points, floor,
// coverage, sectors, points just outside each face, NaN/inf, confidence, range, bad parameters.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <sl_testing/errors.h>
#include "sl_obstacle/volume_checker.h"
#include "synthetic_clouds.h"

namespace sl_obstacle
{
namespace
{
using sl_testing::validationError;

using test::patch;
using test::render;
using test::Scene;

const double kInf = std::numeric_limits<double>::infinity();

/// Parameters with the noise filter switched off: pure geometry.
CheckerParams geometryOnly()
{
  CheckerParams p;
  p.noise.min_cluster_size = 1;
  p.noise.persistence_frames = 1;
  return p;
}

/// Runs the same cloud enough times for persistence to settle.
const VolumeResult& analyzeSettled(VolumeChecker& checker, const std::vector<Point>& cloud)
{
  for (int i = 0; i < checker.params().noise.persistence_frames - 1; ++i)
  {
    checker.analyze(cloud);
  }
  return checker.analyze(cloud);
}

TEST(VolumeChecker, EmptyCloudIsUnknownNotFree)
{
  VolumeChecker checker;
  const VolumeResult& r = checker.analyze(std::vector<Point>());
  EXPECT_EQ(r.total_points, 0U);
  EXPECT_EQ(r.in_box_points, 0U);
  EXPECT_EQ(r.obstacle_points, 0U);
  EXPECT_EQ(r.nearest_distance, kInf);
  EXPECT_EQ(r.nearest_index, -1);
  EXPECT_DOUBLE_EQ(r.coverage, 0.0);
  EXPECT_EQ(r.measured_cells, 0U);
  // Nothing measured: nothing is known to be free.
  EXPECT_DOUBLE_EQ(r.free_distance, 0.0);
  ASSERT_EQ(r.sectors.size(), 5U);
  for (const SectorResult& s : r.sectors)
  {
    EXPECT_DOUBLE_EQ(s.measured_extent, 0.0);
    EXPECT_DOUBLE_EQ(s.free_distance, 0.0);
  }
}

TEST(VolumeChecker, EmptySceneWithBackgroundIsFreeToDepth)
{
  // Nothing in the box; a wall beyond the box (0.8 m) but within max_range (1.0 m) and the floor.
  VolumeChecker checker;
  const std::vector<Point> cloud = render(Scene().wall(0.95));
  ASSERT_GT(cloud.size(), 500U);
  const VolumeResult& r = analyzeSettled(checker, cloud);
  EXPECT_EQ(r.in_box_points, 0U);
  EXPECT_EQ(r.obstacle_points, 0U);
  EXPECT_EQ(r.nearest_distance, kInf);
  EXPECT_GT(r.floor_points, 0U);
  EXPECT_GT(r.coverage, 0.95);
  EXPECT_DOUBLE_EQ(r.free_distance, checker.params().volume.depth);
  for (const SectorResult& s : r.sectors)
  {
    EXPECT_DOUBLE_EQ(s.free_distance, checker.params().volume.depth);
    EXPECT_EQ(s.nearest_obstacle, kInf);
  }
}

TEST(VolumeChecker, WallInsideTheBox)
{
  VolumeChecker checker;
  const std::vector<Point> cloud = render(Scene().wall(0.6));
  const VolumeResult& r = analyzeSettled(checker, cloud);
  EXPECT_GT(r.in_box_points, 300U);
  EXPECT_EQ(r.obstacle_points, r.in_box_points);
  EXPECT_NEAR(r.nearest_distance, 0.6, 1e-4);
  ASSERT_GE(r.nearest_index, 0);
  EXPECT_NEAR(cloud[static_cast<std::size_t>(r.nearest_index)].x, 0.6, 1e-4);
  EXPECT_NEAR(r.free_distance, 0.6, 1e-4);
  for (const SectorResult& s : r.sectors)
  {
    EXPECT_NEAR(s.free_distance, 0.6, 1e-4);
    EXPECT_GT(s.obstacle_points, 0U);
  }
  EXPECT_NEAR(r.left_free, r.right_free, 1e-6);
  // The pattern covers the whole window from 0.675 m on; at 0.6 m most of it.
  EXPECT_GT(r.coverage, 0.7);
  EXPECT_LT(r.coverage, 1.0);
}

TEST(VolumeChecker, CoverageShrinksAsTheWallComesCloser)
{
  VolumeChecker checker(geometryOnly());
  double previous = 2.0;
  for (double x : { 0.7, 0.5, 0.35, 0.2, 0.1 })
  {
    const double coverage = checker.analyze(render(Scene().wall(x))).coverage;
    EXPECT_LT(coverage, previous) << "wall at " << x;
    previous = coverage;
  }
  EXPECT_LT(previous, 0.3);
}

TEST(VolumeChecker, ThinLegYieldsFewPointsAndIsAnObstacle)
{
  // A 20 mm leg at 0.675 m in front of a background plane beyond the box (the prototype's example,
  // with the plane moved behind the box so that only the leg is an obstacle).
  VolumeChecker checker;
  const std::vector<Point> cloud = render(Scene().wall(0.95).leg(0.675, 0.03));
  const VolumeResult& r = analyzeSettled(checker, cloud);
  EXPECT_GE(r.in_box_points, 3U);
  EXPECT_LE(r.in_box_points, 120U);
  EXPECT_EQ(r.obstacle_points, r.in_box_points);
  EXPECT_NEAR(r.nearest_distance, 0.675, 1e-3);
  EXPECT_NEAR(r.free_distance, 0.675, 1e-3);
  // The leg is at y = 0.03: the centre sector (index 2 of 5, |y| < 0.033) sees it, the outer ones don't.
  EXPECT_NEAR(r.sectors[2].nearest_obstacle, 0.675, 1e-3);
  EXPECT_EQ(r.sectors[0].nearest_obstacle, kInf);
  EXPECT_DOUBLE_EQ(r.sectors[0].free_distance, checker.params().volume.depth);
}

TEST(VolumeChecker, HandfulOfConsistentLegPointsIsAnObstacle)
{
  // 2 columns x 3 rows of dots (5 mm x 11 mm apart): a very thin obstacle, seen twice.
  VolumeChecker checker;
  const std::vector<Point> leg = patch(0.5, 0.0, 0.005, 0.05, 0.072);
  ASSERT_EQ(leg.size(), 6U);
  checker.analyze(leg);
  const VolumeResult& r = checker.analyze(leg);
  EXPECT_EQ(r.obstacle_points, 6U);
  EXPECT_NEAR(r.nearest_distance, 0.5, 1e-6);
}

TEST(VolumeChecker, StrayPointsDoNotMakeObstacles)
{
  VolumeChecker checker;
  const std::vector<Point> background = render(Scene().wall(0.95));
  // Isolated points, each far from the others, different in every frame.
  for (int frame = 0; frame < 5; ++frame)
  {
    std::vector<Point> cloud = background;
    cloud.push_back(makePoint(0.3F + 0.05F * frame, -0.1F, 0.05F));
    cloud.push_back(makePoint(0.5F, 0.12F - 0.02F * frame, 0.15F));
    cloud.push_back(makePoint(0.2F, 0.0F, 0.1F - 0.01F * frame));
    const VolumeResult& r = checker.analyze(cloud);
    EXPECT_EQ(r.in_box_points, 3U);
    EXPECT_EQ(r.obstacle_points, 0U);
    EXPECT_EQ(r.rejected_points, 3U);
    EXPECT_EQ(r.nearest_distance, kInf);
    EXPECT_DOUBLE_EQ(r.free_distance, checker.params().volume.depth);
  }
}

TEST(VolumeChecker, FloorPointsAreNotObstacles)
{
  VolumeChecker checker(geometryOnly());
  std::vector<Point> floor;
  for (double x = 0.05; x < 0.8; x += 0.02)
  {
    for (double y = -0.16; y <= 0.16; y += 0.02)
    {
      floor.push_back(makePoint(static_cast<float>(x), static_cast<float>(y), 0.01F));    // below margin
      floor.push_back(makePoint(static_cast<float>(x), static_cast<float>(y), -0.005F));  // noise below 0
    }
  }
  const VolumeResult& r = checker.analyze(floor);
  EXPECT_EQ(r.floor_points, floor.size());
  EXPECT_EQ(r.in_box_points, 0U);
  EXPECT_EQ(r.nearest_distance, kInf);
  // Only the bottom row of the window is measured.
  EXPECT_NEAR(r.coverage, 1.0 / r.grid_rows, 1e-9);
  // The floor shows the box free as far as it was seen.
  EXPECT_NEAR(r.free_distance, 0.79, 0.011);
}

TEST(VolumeChecker, RenderedFloorIsNotAnObstacle)
{
  VolumeChecker checker;
  const VolumeResult& r = analyzeSettled(checker, render(Scene()));  // floor only
  EXPECT_GT(r.floor_points, 0U);
  EXPECT_EQ(r.obstacle_points, 0U);
}

TEST(VolumeChecker, LowCoverageWhenHalfTheWindowIsUnmeasured)
{
  // Only the left half of the window returns points (a background beyond the box).
  VolumeChecker checker;
  const std::vector<Point> cloud = patch(0.95, 0.0, 0.1655, 0.0, 0.173);
  const VolumeResult& r = analyzeSettled(checker, cloud);
  EXPECT_EQ(r.obstacle_points, 0U);
  EXPECT_NEAR(r.coverage, 0.5, 0.06);
  // Right sectors unmeasured: unknown, so the free distance is 0, and the right is less free.
  EXPECT_DOUBLE_EQ(r.sectors[0].free_distance, 0.0);
  EXPECT_DOUBLE_EQ(r.sectors[4].free_distance, checker.params().volume.depth);
  EXPECT_DOUBLE_EQ(r.free_distance, 0.0);
  EXPECT_GT(r.left_free, r.right_free);
}

TEST(VolumeChecker, ObstacleOnOneSideSetsThatSectorsFreeDistance)
{
  VolumeChecker checker;
  // Right part (-y) blocked at 0.4 m, the rest free to the background.
  const std::vector<Point> cloud = render(Scene().wall(0.95).wallPart(0.4, -1.0, -0.1));
  const VolumeResult& r = analyzeSettled(checker, cloud);
  EXPECT_NEAR(r.nearest_distance, 0.4, 1e-3);
  EXPECT_NEAR(r.sectors[0].free_distance, 0.4, 1e-3);
  EXPECT_DOUBLE_EQ(r.sectors[4].free_distance, checker.params().volume.depth);
  EXPECT_GT(r.left_free, r.right_free);
  EXPECT_NEAR(r.free_distance, 0.4, 1e-3);
}

TEST(VolumeChecker, StrayPointsAreNotMeasurements)
{
  // Left half measured (background); a stray point on the unmeasured right must not make it "free".
  VolumeChecker with_stray;
  VolumeChecker without;
  const std::vector<Point> background = patch(0.95, 0.0, 0.1655, 0.0, 0.173);
  std::vector<Point> cloud = background;
  cloud.push_back(makePoint(0.4F, -0.13F, 0.1F));
  const VolumeResult& a = analyzeSettled(with_stray, cloud);
  const VolumeResult& b = analyzeSettled(without, background);
  EXPECT_EQ(a.rejected_points, 1U);
  EXPECT_DOUBLE_EQ(a.coverage, b.coverage);
  EXPECT_DOUBLE_EQ(a.sectors[0].measured_extent, 0.0);
  EXPECT_DOUBLE_EQ(a.sectors[0].free_distance, 0.0);
}

TEST(VolumeChecker, UnconfirmedWallLimitsTheFreeDistanceBeforeItIsAnObstacle)
{
  // First frame of a wall with persistence 2: not yet an obstacle, but measured: the box is known
  // free only up to it.
  VolumeChecker checker;
  const VolumeResult& first = checker.analyze(render(Scene().wall(0.7)));
  EXPECT_EQ(first.obstacle_points, 0U);
  EXPECT_GT(first.noise.rejected_by_persistence, 0U);
  EXPECT_EQ(first.nearest_distance, kInf);
  EXPECT_NEAR(first.free_distance, 0.7, 1e-3);
  EXPECT_GT(first.coverage, 0.95);
  const VolumeResult& second = checker.analyze(render(Scene().wall(0.7)));
  EXPECT_NEAR(second.nearest_distance, 0.7, 1e-3);
}

/// One point and its expected box membership.
struct FaceCase
{
  const char* name;
  float x, y, z;
  bool inside;
};

TEST(VolumeChecker, PointsJustOutsideEachFaceAreNotInTheBox)
{
  const CheckerParams params = geometryOnly();
  const WorkingVolume& v = params.volume;
  const float e = 0.001F;
  const float depth = static_cast<float>(v.depth);
  const float half = static_cast<float>(0.5 * v.width);
  const float top = static_cast<float>(v.height);
  const float floor = static_cast<float>(v.floor_margin);
  const FaceCase cases[] = {
    { "beyond the far face (x > depth)", depth + e, 0.0F, 0.1F, false },
    { "just before the far face", depth - e, 0.0F, 0.1F, true },
    { "behind the front face (x < 0)", -e, 0.0F, 0.1F, false },
    { "on the front face (x = 0)", 0.0F, 0.0F, 0.1F, false },
    { "just in front of the robot", e, 0.0F, 0.1F, true },
    { "left of the left face", 0.4F, half + e, 0.1F, false },
    { "just inside the left face", 0.4F, half - e, 0.1F, true },
    { "right of the right face", 0.4F, -half - e, 0.1F, false },
    { "just inside the right face", 0.4F, -half + e, 0.1F, true },
    { "above the top face", 0.4F, 0.0F, top + e, false },
    { "just below the top face", 0.4F, 0.0F, top - e, true },
    { "below the bottom face (floor)", 0.4F, 0.0F, floor - e, false },
    { "just above the bottom face", 0.4F, 0.0F, floor + e, true },
  };
  for (const FaceCase& c : cases)
  {
    VolumeChecker checker(params);
    const std::vector<Point> cloud{ makePoint(c.x, c.y, c.z) };
    const VolumeResult& r = checker.analyze(cloud);
    EXPECT_EQ(r.in_box_points, c.inside ? 1U : 0U) << c.name;
    EXPECT_EQ(r.obstacle_points, c.inside ? 1U : 0U) << c.name;
    EXPECT_EQ(std::isfinite(r.nearest_distance), c.inside) << c.name;
    EXPECT_EQ(v.contains(cloud[0]), c.inside) << c.name;
  }
}

TEST(VolumeChecker, NanAndInfPointsAreIgnoredAndCounted)
{
  VolumeChecker clean_checker;
  VolumeChecker dirty_checker;
  const std::vector<Point> clean = render(Scene().wall(0.95).leg(0.5, 0.0));
  std::vector<Point> dirty = clean;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  dirty.push_back(makePoint(nan, 0.0F, 0.1F));
  dirty.push_back(makePoint(0.3F, nan, 0.1F));
  dirty.push_back(makePoint(0.3F, 0.0F, nan));
  dirty.push_back(makePoint(inf, 0.0F, 0.1F));
  dirty.push_back(makePoint(0.3F, -inf, 0.1F));
  dirty.push_back(makePoint(-inf, 0.0F, 0.1F));
  const VolumeResult& a = analyzeSettled(clean_checker, clean);
  const VolumeResult& b = analyzeSettled(dirty_checker, dirty);
  EXPECT_EQ(a.invalid_points, 0U);
  EXPECT_EQ(b.invalid_points, 6U);
  EXPECT_EQ(b.total_points, a.total_points + 6U);
  EXPECT_EQ(b.in_box_points, a.in_box_points);
  EXPECT_EQ(b.obstacle_points, a.obstacle_points);
  EXPECT_DOUBLE_EQ(b.nearest_distance, a.nearest_distance);
  EXPECT_DOUBLE_EQ(b.free_distance, a.free_distance);
  EXPECT_DOUBLE_EQ(b.coverage, a.coverage);
}

TEST(VolumeChecker, AllInvalidCloud)
{
  VolumeChecker checker;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<Point> cloud(100, makePoint(nan, nan, nan));
  const VolumeResult& r = checker.analyze(cloud);
  EXPECT_EQ(r.invalid_points, 100U);
  EXPECT_EQ(r.in_box_points, 0U);
  EXPECT_DOUBLE_EQ(r.coverage, 0.0);
  EXPECT_DOUBLE_EQ(r.free_distance, 0.0);
}

TEST(VolumeChecker, LowConfidenceAndOutOfRangePointsAreIgnored)
{
  CheckerParams params = geometryOnly();
  params.min_confidence = 0.5;
  VolumeChecker checker(params);
  const std::vector<Point> cloud{
    makePoint(0.3F, 0.0F, 0.1F, 0.2F),           // low confidence
    makePoint(0.3F, 0.0F, 0.1F, std::nanf("")),  // NaN confidence
    makePoint(1.2F, 0.0F, 0.1F, 1.0F),           // beyond max_range
    makePoint(0.4F, 0.0F, 0.1F, 0.9F),           // valid obstacle
  };
  const VolumeResult& r = checker.analyze(cloud);
  EXPECT_EQ(r.low_confidence_points, 2U);
  EXPECT_EQ(r.out_of_range_points, 1U);
  EXPECT_EQ(r.in_box_points, 1U);
  EXPECT_NEAR(r.nearest_distance, 0.4, 1e-6);
}

TEST(VolumeChecker, BuffersAreReusedAfterWarmUp)
{
  VolumeChecker checker;
  const std::vector<Point> cloud = render(Scene().wall(0.5));
  checker.analyze(cloud);
  const VolumeResult& r = checker.result();
  const std::uint32_t* in_box = r.in_box_indices.data();
  const std::uint32_t* obstacles = r.obstacle_indices.data();
  const std::size_t capacity = r.in_box_indices.capacity();
  for (int i = 0; i < 3; ++i)
  {
    checker.analyze(render(Scene().wall(0.4 + 0.1 * i)));
    EXPECT_EQ(r.in_box_indices.data(), in_box);
    EXPECT_EQ(r.obstacle_indices.data(), obstacles);
    EXPECT_EQ(r.in_box_indices.capacity(), capacity);
  }
}

TEST(VolumeChecker, BadParametersAreRejectedNamingTheParameter)
{
  struct BadCase
  {
    const char* name;
    void (*spoil)(CheckerParams&);
  };
  const BadCase cases[] = {
    { "width", [](CheckerParams& p) { p.volume.width = 0.0; } },
    { "width", [](CheckerParams& p) { p.volume.width = -0.3; } },
    { "height", [](CheckerParams& p) { p.volume.height = std::nan(""); } },
    { "depth", [](CheckerParams& p) { p.volume.depth = -1.0; } },
    { "depth", [](CheckerParams& p) { p.volume.depth = 1.5; } },  // beyond max_range
    { "floor_margin", [](CheckerParams& p) { p.volume.floor_margin = -0.01; } },
    { "floor_margin", [](CheckerParams& p) { p.volume.floor_margin = 0.2; } },  // above height
    { "max_range", [](CheckerParams& p) { p.volume.max_range = std::numeric_limits<double>::infinity(); } },
    { "sectors", [](CheckerParams& p) { p.sectors = 0; } },
    { "cell_size", [](CheckerParams& p) { p.cell_size = 0.0; } },
    { "cell_size", [](CheckerParams& p) { p.cell_size = 0.5; } },  // larger than the window
    { "min_confidence", [](CheckerParams& p) { p.min_confidence = -1.0; } },
    { "min_cluster_size", [](CheckerParams& p) { p.noise.min_cluster_size = 0; } },
    { "cluster_tolerance", [](CheckerParams& p) { p.noise.cluster_tolerance = 0.0; } },
    { "persistence_frames", [](CheckerParams& p) { p.noise.persistence_frames = 0; } },
    { "persistence_tolerance", [](CheckerParams& p) { p.noise.persistence_tolerance = -0.1; } },
  };
  for (const BadCase& c : cases)
  {
    CheckerParams params;
    c.spoil(params);
    EXPECT_THROW(params.validate(), std::invalid_argument) << c.name;
    const std::string message = validationError(params);
    EXPECT_EQ(message.rfind(c.name, 0), 0U) << "expected a message about " << c.name << ", got: " << message;
    try
    {
      VolumeChecker checker(params);
      ADD_FAILURE() << "no exception for bad " << c.name;
    }
    catch (const std::invalid_argument& e)
    {
      EXPECT_NE(std::string(e.what()).find(c.name), std::string::npos) << e.what();
    }
  }
  EXPECT_NO_THROW(CheckerParams().validate());
}

TEST(VolumeChecker, SetParamsChangesTheBox)
{
  VolumeChecker checker(geometryOnly());
  const std::vector<Point> cloud{ makePoint(0.4F, 0.0F, 0.2F) };  // above the default height
  EXPECT_EQ(checker.analyze(cloud).in_box_points, 0U);
  CheckerParams taller = geometryOnly();
  taller.volume.height = 0.25;
  taller.sectors = 3;
  checker.setParams(taller);
  EXPECT_EQ(checker.analyze(cloud).in_box_points, 1U);
  EXPECT_EQ(checker.result().sectors.size(), 3U);
}
}  // namespace
}  // namespace sl_obstacle
