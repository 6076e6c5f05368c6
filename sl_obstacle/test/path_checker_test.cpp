// Tests of the swept-footprint checks (sweepStraight, bestHeading) on given local maps.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "sl_obstacle/local_map.h"
#include "sl_obstacle/path_checker.h"

namespace sl_obstacle
{
namespace
{
constexpr double kRes = 0.02;
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
const FootprintParams kFp;            // radius 0.1675 + margin 0.02
const double kR = kFp.sweptRadius();  // 0.1875

/// Rays along x from x0 to x1 in both height slices, every half cell across [y0, y1].
std::vector<MapRay> rectRays(float x0, float x1, float y0, float y1, RayKind kind)
{
  std::vector<MapRay> rays;
  for (float y = y0; y <= y1; y += 0.5F * static_cast<float>(kRes))
  {
    rays.push_back(MapRay{ x0, y, 0.05F, x1, y, 0.05F, kind });
    rays.push_back(MapRay{ x0, y, 0.13F, x1, y, 0.13F, kind });
  }
  return rays;
}

/// Free space seen by the sensor: x in [x0, x1], y in [y0, y1].
void clearRect(LocalMap& map, float x0, float x1, float y0, float y1)
{
  map.insert(rectRays(x0, x1, y0, y1, RayKind::Free), 0.0);
}

/// The trail of a robot that drove from (0, 0) to (length, 0): footprints every 0.01 m, marked with
/// the swept radius plus half a cell.
void driveTrail(LocalMap& map, double length)
{
  for (double x = 0.0; x <= length + 1e-9; x += 0.01)
  {
    map.markFreeDisc(x, 0.0, kR + 0.5 * kRes, 0.0);
  }
}

TEST(PathChecker, OpenFreeSpaceIsDrivenAsFarAsItWasCleared)
{
  LocalMap map{ MapParams() };
  clearRect(map, -0.3F, 1.5F, -0.5F, 0.5F);
  const PathResult near = sweepStraight(map, kFp, 0.0, 0.0, 0.0, 1, 1.0, 0.0);
  EXPECT_DOUBLE_EQ(near.free, 1.0);
  EXPECT_EQ(near.obstacle, std::numeric_limits<double>::infinity());
  EXPECT_EQ(near.unknown, std::numeric_limits<double>::infinity());
  EXPECT_DOUBLE_EQ(near.known_fraction, 1.0);
  EXPECT_GE(near.swept_cells, 880);  // 18 rows of cell centres within 0.1875, 50 cells long
  EXPECT_LE(near.swept_cells, 960);
  // Beyond x = 1.5 nothing was seen: the disc's front reaches it after 1.5 - 0.1875 m.
  const PathResult far = sweepStraight(map, kFp, 0.0, 0.0, 0.0, 1, 2.0, 0.0);
  EXPECT_NEAR(far.free, 1.5 - kR, kRes);
  EXPECT_NEAR(far.unknown, 1.5 - kR, kRes);
  // Known: the rectangle up to x = 1.5 less the disc's front half, (0.5625 - 0.0552) / 0.75 = 0.68.
  EXPECT_GT(far.known_fraction, 0.63);
  EXPECT_LT(far.known_fraction, 0.73);
  // Sideways the cleared strip ends at |y| = 0.5.
  EXPECT_NEAR(sweepStraight(map, kFp, 0.0, 0.0, kPi / 2, 1, 2.0, 0.0).free, 0.5 - kR, kRes);
  EXPECT_NEAR(sweepStraight(map, kFp, 0.0, 0.0, kPi / 2, -1, 2.0, 0.0).free, 0.5 - kR, kRes);
}

TEST(PathChecker, WallAheadGivesTheObstacleDistance)
{
  LocalMap map{ MapParams() };
  // Decoded points on a wall at x = 0.8 .. 0.82 (free in front of it), free space seen behind it.
  map.insert(rectRays(-0.3F, 0.81F, -0.5F, 0.5F, RayKind::Hit), 0.0);
  clearRect(map, 0.83F, 1.5F, -0.5F, 0.5F);
  const PathResult r = sweepStraight(map, kFp, 0.0, 0.0, 0.0, 1, 1.5, 0.0);
  EXPECT_NEAR(r.obstacle, 0.81 - kR, kRes);
  EXPECT_NEAR(r.free, r.obstacle, 1e-9);
  EXPECT_NEAR(r.unknown, 1.5 - kR, kRes);  // beyond x = 1.5
  // From another pose and in reverse: the wall is then behind the robot.
  EXPECT_NEAR(sweepStraight(map, kFp, 0.3, 0.1, 0.0, 1, 1.5, 0.0).obstacle, 0.51 - kR, kRes);
  EXPECT_NEAR(sweepStraight(map, kFp, 1.3, 0.0, kPi, 1, 1.5, 0.0).obstacle, 1.3 - 0.81 - kR, kRes);
  EXPECT_NEAR(sweepStraight(map, kFp, 1.3, 0.0, 0.0, -1, 1.5, 0.0).obstacle, 1.3 - 0.81 - kR, kRes);
  // Driving along the wall (it stays beside the path) does not touch it.
  EXPECT_EQ(sweepStraight(map, kFp, 0.5, 0.0, kPi / 2, 1, 0.25, 0.0).obstacle, std::numeric_limits<double>::infinity());
}

TEST(PathChecker, ObstacleDistanceInAnyDirection)
{
  for (const double yaw : { 0.0, 0.7, 2.0, -2.5, kPi / 4 })
  {
    for (const int dir : { 1, -1 })
    {
      LocalMap map{ MapParams() };
      const double d = 0.9;
      map.markOccupiedDisc(0.13 + dir * d * std::cos(yaw), -0.21 + dir * d * std::sin(yaw), 0.015, 0.0);
      const PathResult r = sweepStraight(map, kFp, 0.13, -0.21, yaw, dir, 1.5, 0.0);
      EXPECT_NEAR(r.obstacle, d - kR, 1.5 * kRes) << "yaw " << yaw << " direction " << dir;
      EXPECT_LT(r.unknown, kRes);  // everything else is unknown
      EXPECT_NEAR(r.free, 0.0, kRes);
    }
  }
}

TEST(PathChecker, TurnedTowardANeverSeenZoneTheNearFieldIsUnknown)
{
  LocalMap map{ MapParams() };
  map.markFreeDisc(0.0, 0.0, kR, 0.0);      // the robot's own footprint
  clearRect(map, 0.5F, 1.5F, -0.5F, 0.5F);  // the sensor sees from 0.5 m on
  const PathResult r = sweepStraight(map, kFp, 0.0, 0.0, 0.0, 1, 1.2, 0.0);
  EXPECT_LT(r.free, kRes);
  EXPECT_LT(r.unknown, kRes);
  EXPECT_EQ(r.obstacle, std::numeric_limits<double>::infinity());
  EXPECT_LT(r.known_fraction, 0.8);
  EXPECT_GT(r.known_fraction, 0.3);
}

TEST(PathChecker, RotationInPlaceNeedsNothing)
{
  LocalMap map{ MapParams() };
  // Unknown all around and an obstacle right at the disc's edge.
  map.markOccupiedDisc(kR + 0.02, 0.0, 0.015, 0.0);
  for (const double yaw : { 0.0, 1.0, -2.0 })
  {
    const PathResult r = sweepStraight(map, kFp, 0.0, 0.0, yaw, 1, 0.0, 0.0);
    EXPECT_EQ(r.free, 0.0);
    EXPECT_EQ(r.obstacle, std::numeric_limits<double>::infinity());
    EXPECT_EQ(r.unknown, std::numeric_limits<double>::infinity());
    EXPECT_EQ(r.known_fraction, 1.0);
    EXPECT_EQ(r.swept_cells, 0);
  }
  // Cells under the current disc count as free, even occupied ones.
  LocalMap open{ MapParams() };
  clearRect(open, -0.5F, 1.5F, -0.5F, 0.5F);
  open.markOccupiedDisc(0.05, 0.05, 0.03, 0.0);
  EXPECT_DOUBLE_EQ(sweepStraight(open, kFp, 0.0, 0.0, 0.0, 1, 1.0, 0.0).free, 1.0);
}

TEST(PathChecker, ReverseAlongTheTrail)
{
  LocalMap map{ MapParams() };
  driveTrail(map, 1.0);
  const PathResult back = sweepStraight(map, kFp, 1.0, 0.0, 0.0, -1, 0.8, 0.0);
  EXPECT_DOUBLE_EQ(back.free, 0.8);
  EXPECT_DOUBLE_EQ(back.known_fraction, 1.0);
  // The trail starts at x = 0: behind it nothing is known.
  const PathResult all = sweepStraight(map, kFp, 1.0, 0.0, 0.0, -1, 1.5, 0.0);
  EXPECT_GE(all.free, 1.0 - kRes);
  EXPECT_LE(all.free, 1.0 + 2 * kRes);
  // Forward, off the trail: unknown at once (the trail's half-cell extra ends within two cells).
  EXPECT_LT(sweepStraight(map, kFp, 1.0, 0.0, 0.0, 1, 0.8, 0.0).free, 2 * kRes);
}

TEST(PathChecker, TrailAndEvidenceDistances)
{
  LocalMap map{ MapParams() };
  map.markTrail(0.0, 0.0, 1.0, 0.0, kFp.radius + 0.5 * kRes);
  FootprintParams disc = kFp;
  disc.lateral_margin = 0.0;
  // Backwards along the trail the disc (radius 0.1675) reaches the end cap's last cells (0.1775
  // around the start) after 1.0 m and up to one cell more; forward it leaves the trail at once.
  const PathResult back = sweepStraight(map, disc, 1.0, 0.0, 0.0, -1, 1.5, 0.0);
  EXPECT_GE(back.off_trail, 1.0);
  EXPECT_LE(back.off_trail, 1.0 + kRes);
  EXPECT_LT(sweepStraight(map, disc, 1.0, 0.0, 0.0, 1, 0.5, 0.0).off_trail, kRes);
  // Sideways the disc reaches the first row of centres off the trail (y = -0.19, 0.1775 being the
  // trail's half width) at the centres (0.49, -0.19) and (0.51, -0.19).
  EXPECT_NEAR(sweepStraight(map, disc, 0.5, 0.0, kPi / 2.0, -1, 0.5, 0.0).off_trail,
              0.19 - std::sqrt(disc.radius * disc.radius - 0.01 * 0.01), 1e-9);

  // A low ray ending in a lit (suspect) point at x = 0.61: the cells it crossed are unknown without
  // evidence (the high slice was never crossed), its end is unknown with evidence.
  LocalMap seen{ MapParams() };
  seen.insert({ MapRay{ 0.0F, 0.01F, 0.05F, 0.61F, 0.01F, 0.05F, RayKind::Suspect } }, 0.0);
  const PathResult ahead = sweepStraight(seen, kFp, 0.0, 0.0, 0.0, 1, 1.0, 0.0);
  EXPECT_LT(ahead.unknown, kRes);
  const double entry = 0.61 - std::sqrt(kR * kR - 0.01 * 0.01);  // the end cell's centre (0.61, 0.01)
  EXPECT_NEAR(ahead.evidence, entry, 1e-9);
  EXPECT_EQ(ahead.obstacle, std::numeric_limits<double>::infinity());
  EXPECT_EQ(ahead.unseen_far, std::numeric_limits<double>::infinity()) << "no blind_radius given";
  EXPECT_NEAR(ahead.open(), entry, 1e-9);
  // With a blind radius, never-seen cells beyond it end the open travel: here (nothing but the low
  // ray was seen) the first one lies straight ahead, just beyond 0.3 m from the start.
  const PathResult ring = sweepStraight(seen, kFp, 0.0, 0.0, 0.0, 1, 1.0, 0.0, 0.3);
  EXPECT_NEAR(ring.unseen_far, 0.3 - kR, kRes);
  EXPECT_DOUBLE_EQ(ring.open(), ring.unseen_far);
  EXPECT_DOUBLE_EQ(ring.evidence, ahead.evidence);
}

TEST(PathChecker, BoxedInOnlyTheTrailIsFree)
{
  LocalMap map{ MapParams() };
  driveTrail(map, 1.0);
  // Walls just outside the disc, from 100 degrees left to 100 degrees right of the heading.
  for (double a = -100.0; a <= 100.0; a += 2.0)
  {
    const double ring = kR + 0.02;
    map.markOccupiedDisc(1.0 + ring * std::cos(a * kDeg), ring * std::sin(a * kDeg), 0.015, 0.0);
  }
  for (int k = -6; k <= 6; ++k)
  {
    const PathResult r = sweepStraight(map, kFp, 1.0, 0.0, k * 15.0 * kDeg, 1, 1.0, 0.0);
    EXPECT_LT(r.free, 2 * kRes) << "heading " << k * 15 << " deg";
    EXPECT_LT(r.obstacle, 3 * kRes) << "heading " << k * 15 << " deg";
  }
  const HeadingChoice best = bestHeading(map, kFp, 1.0, 0.0, 0.0, 15.0 * kDeg, 6, 1.0, 0.0);
  EXPECT_LT(best.path.free, 2 * kRes);
  EXPECT_DOUBLE_EQ(sweepStraight(map, kFp, 1.0, 0.0, 0.0, -1, 0.8, 0.0).free, 0.8);
}

TEST(PathChecker, BestHeadingFindsTheFreeCorridor)
{
  LocalMap map{ MapParams() };
  map.markFreeDisc(0.0, 0.0, kR + kRes, 0.0);
  // A corridor 0.6 m wide toward -30 degrees (right), seen up to 1.5 m.
  const double a = -30.0 * kDeg;
  std::vector<MapRay> rays;
  for (double off = -0.3; off <= 0.3; off += 0.005)
  {
    const float sx = static_cast<float>(-off * std::sin(a)), sy = static_cast<float>(off * std::cos(a));
    const float ex = sx + static_cast<float>(1.5 * std::cos(a));
    const float ey = sy + static_cast<float>(1.5 * std::sin(a));
    rays.push_back(MapRay{ sx, sy, 0.05F, ex, ey, 0.05F, RayKind::Free });
    rays.push_back(MapRay{ sx, sy, 0.13F, ex, ey, 0.13F, RayKind::Free });
  }
  map.insert(rays, 0.0);
  const HeadingChoice c = bestHeading(map, kFp, 0.0, 0.0, 0.0, 15.0 * kDeg, 6, 1.0, 0.0);
  EXPECT_NEAR(c.turn, a, 1e-9);
  EXPECT_DOUBLE_EQ(c.path.free, 1.0);
  // Everything free: no turn (ties go to the smallest turn).
  LocalMap open{ MapParams() };
  open.markFreeDisc(0.0, 0.0, 1.5, 0.0);
  const HeadingChoice o = bestHeading(open, kFp, 0.0, 0.0, 0.3, 15.0 * kDeg, 6, 1.0, 0.0);
  EXPECT_EQ(o.turn, 0.0);
  EXPECT_DOUBLE_EQ(o.path.free, 1.0);
  // n = 0: only the current heading.
  EXPECT_EQ(bestHeading(map, kFp, 0.0, 0.0, 0.0, 15.0 * kDeg, 0, 1.0, 0.0).turn, 0.0);
}

TEST(PathChecker, DecayedMapIsUnknownAgain)
{
  LocalMap map{ MapParams() };
  clearRect(map, -0.3F, 1.5F, -0.5F, 0.5F);  // -0.4 at t = 0: free for 8.6 s
  EXPECT_DOUBLE_EQ(sweepStraight(map, kFp, 0.0, 0.0, 0.0, 1, 1.0, 5.0).free, 1.0);
  EXPECT_LT(sweepStraight(map, kFp, 0.0, 0.0, 0.0, 1, 1.0, 20.0).free, kRes);
}

TEST(PathChecker, BadParametersThrowNamingTheField)
{
  const auto message = [](const FootprintParams& fp)
  {
    try
    {
      fp.validate();
    }
    catch (const std::invalid_argument& e)
    {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(message(FootprintParams()), "");
  FootprintParams fp;
  fp.radius = 0.0;
  EXPECT_EQ(message(fp).rfind("radius", 0), 0U) << message(fp);
  fp = FootprintParams();
  fp.lateral_margin = -0.01;
  EXPECT_EQ(message(fp).rfind("lateral_margin", 0), 0U) << message(fp);
  fp.lateral_margin = std::nan("");
  EXPECT_EQ(message(fp).rfind("lateral_margin", 0), 0U) << message(fp);
  const LocalMap map{ MapParams() };
  EXPECT_THROW(sweepStraight(map, kFp, 0.0, 0.0, 0.0, 0, 1.0, 0.0), std::invalid_argument);
  EXPECT_THROW(sweepStraight(map, kFp, 0.0, 0.0, 0.0, 1, -1.0, 0.0), std::invalid_argument);
  EXPECT_THROW(sweepStraight(map, kFp, 0.0, 0.0, 0.0, 1, std::nan(""), 0.0), std::invalid_argument);
  EXPECT_THROW(sweepStraight(map, kFp, std::nan(""), 0.0, 0.0, 1, 1.0, 0.0), std::invalid_argument);
  EXPECT_THROW(bestHeading(map, kFp, 0.0, 0.0, 0.0, 0.1, -1, 1.0, 0.0), std::invalid_argument);
}
}  // namespace
}  // namespace sl_obstacle
