// Tests of LocalMap: marking, clearing, decay, suspect ends, height slices, the rolling window,
// clipping, bad input and parameter validation.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <sl_testing/errors.h>
#include "sl_obstacle/local_map.h"

namespace sl_obstacle
{
namespace
{
// Default band 0.015 .. 0.173 in two slices: slice 0 below 0.094, slice 1 above.
constexpr float kLow = 0.05F;
constexpr float kHigh = 0.13F;

MapRay ray(float sx, float sy, float sz, float ex, float ey, float ez, RayKind kind)
{
  return MapRay{ sx, sy, sz, ex, ey, ez, kind };
}

/// Two horizontal rays (one per slice) from (sx, y) to (ex, y).
std::vector<MapRay> bothSlices(float sx, float ex, float y, RayKind kind)
{
  return { ray(sx, y, kLow, ex, y, kLow, kind), ray(sx, y, kHigh, ex, y, kHigh, kind) };
}

/// @p clouds clouds 0.1 s apart from @p t0, each the two rays of bothSlices(sx, ex, y, kind).
void insertClouds(LocalMap& map, int clouds, double t0, float sx, float ex, float y, RayKind kind)
{
  for (int i = 0; i < clouds; ++i)
  {
    map.insert(bothSlices(sx, ex, y, kind), t0 + 0.1 * i);
  }
}

int countCells(const LocalMap& map, double now, std::int8_t value)
{
  std::vector<std::int8_t> data;
  double ox = 0.0, oy = 0.0;
  int width = 0;
  map.toOccupancy(now, data, ox, oy, width);
  int n = 0;
  for (const std::int8_t v : data)
  {
    n += v == value ? 1 : 0;
  }
  return n;
}

TEST(LocalMap, StartsUnknown)
{
  const LocalMap map{ MapParams() };
  EXPECT_EQ(map.width(), 200);
  EXPECT_EQ(map.state(0.0, 0.0, 0.0), CellState::Unknown);
  EXPECT_EQ(map.state(1.9, -1.9, 100.0), CellState::Unknown);
  EXPECT_EQ(countCells(map, 0.0, -1), 200 * 200);
}

TEST(LocalMap, HitMarksEndOccupiedAndPathFree)
{
  LocalMap map{ MapParams() };
  map.insert(bothSlices(0.0F, 1.01F, 0.01F, RayKind::Hit), 0.0);
  EXPECT_EQ(map.state(1.01, 0.01, 0.0), CellState::Occupied);
  EXPECT_EQ(map.state(0.5, 0.01, 0.0), CellState::Free);
  EXPECT_EQ(map.state(0.01, 0.01, 0.0), CellState::Free);
  EXPECT_EQ(map.state(1.05, 0.01, 0.0), CellState::Unknown);  // beyond the surface
  EXPECT_EQ(map.state(0.5, 0.05, 0.0), CellState::Unknown);   // the next row
  EXPECT_EQ(countCells(map, 0.0, 100), 1);
}

TEST(LocalMap, OneSliceFreeIsNotFree)
{
  LocalMap map{ MapParams() };
  map.insert({ ray(0.0F, 0.01F, kLow, 1.0F, 0.01F, kLow, RayKind::Free) }, 0.0);
  EXPECT_EQ(map.state(0.5, 0.01, 0.0), CellState::Unknown);  // the upper slice was not seen
  map.insert({ ray(0.0F, 0.01F, kHigh, 1.0F, 0.01F, kHigh, RayKind::Free) }, 0.0);
  EXPECT_EQ(map.state(0.5, 0.01, 0.0), CellState::Free);
}

TEST(LocalMap, FloorAndAboveBandMarkNothing)
{
  LocalMap map{ MapParams() };
  // Below the band (floor points) and above it: nothing is free, nothing occupied.
  map.insert({ ray(0.0F, 0.01F, 0.01F, 1.0F, 0.01F, 0.0F, RayKind::Hit),
               ray(0.0F, 0.01F, 0.2F, 1.0F, 0.01F, 0.25F, RayKind::Hit) },
             0.0);
  EXPECT_EQ(countCells(map, 0.0, -1), 200 * 200);
}

TEST(LocalMap, FreeRaysClearAnObstacleOverSeveralClouds)
{
  LocalMap map{ MapParams() };
  map.insert(bothSlices(0.0F, 0.51F, 0.01F, RayKind::Hit), 0.0);
  ASSERT_EQ(map.state(0.51, 0.01, 0.0), CellState::Occupied);
  // 0.85 - 0.4 = 0.45: no longer occupied, not yet free.
  map.insert(bothSlices(0.0F, 1.0F, 0.01F, RayKind::Free), 0.0);
  EXPECT_EQ(map.state(0.51, 0.01, 0.0), CellState::Unknown);
  map.insert(bothSlices(0.0F, 1.0F, 0.01F, RayKind::Free), 0.0);
  EXPECT_EQ(map.state(0.51, 0.01, 0.0), CellState::Unknown);  // 0.05
  map.insert(bothSlices(0.0F, 1.0F, 0.01F, RayKind::Free), 0.0);
  EXPECT_EQ(map.state(0.51, 0.01, 0.0), CellState::Free);  // -0.35
}

TEST(LocalMap, RaysBesideAThinObstacleInItsCellDoNotEraseIt)
{
  // A leg seen once at y = 0.013 in the cell [0.50, 0.52) x [0.00, 0.02); rays then pass through
  // the same cell 8 mm beside it, cloud after cloud (a turn sweeps them past it): beyond the quarter
  // cell around the hit, they say nothing about it.
  MapParams no_decay;
  no_decay.decay = 1e6;
  LocalMap map{ no_decay };
  map.insert(bothSlices(0.0F, 0.51F, 0.013F, RayKind::Hit), 0.0);
  ASSERT_EQ(map.state(0.51, 0.01, 0.0), CellState::Occupied);
  for (int i = 0; i < 30; ++i)
  {
    map.insert(bothSlices(0.0F, 1.0F, 0.005F, RayKind::Free), 0.1 * i);
  }
  EXPECT_EQ(map.state(0.51, 0.01, 3.0), CellState::Occupied);
  EXPECT_EQ(map.state(0.8, 0.01, 3.0), CellState::Free) << "the rest of the rays' path is free";
  // Rays through the place of the hit erase it (the object moved away), and then the cell has no
  // hit left: rays anywhere through it count again.
  for (int i = 0; i < 3; ++i)
  {
    map.insert(bothSlices(0.0F, 1.0F, 0.012F, RayKind::Free), 3.0);
  }
  EXPECT_EQ(map.state(0.51, 0.01, 3.0), CellState::Free);
  // A hit in the free cell makes it occupied at once (the free log-odds are dropped first).
  map.insert(bothSlices(0.0F, 0.51F, 0.013F, RayKind::Hit), 3.0);
  EXPECT_EQ(map.state(0.51, 0.01, 3.0), CellState::Occupied);
  for (int i = 0; i < 2; ++i)  // 0.85 - 2 * 0.4 = 0.05: unknown, the hit still held
  {
    map.insert(bothSlices(0.0F, 1.0F, 0.013F, RayKind::Free), 3.0);  // its very place
  }
  map.insert(bothSlices(0.0F, 1.0F, 0.002F, RayKind::Free), 3.0);
  EXPECT_EQ(map.state(0.51, 0.01, 3.0), CellState::Unknown) << "a ray beside a held hit says nothing";
  map.insert(bothSlices(0.0F, 1.0F, 0.013F, RayKind::Free), 3.0);  // -0.35: free, the hit forgotten
  EXPECT_EQ(map.state(0.51, 0.01, 3.0), CellState::Free);
}

/// A leg's face decoded across the cell [0.50, 0.52) x [0.00, 0.02) in @p clouds clouds from x = -0.04.
void insertLegFace(LocalMap& map, int clouds)
{
  for (int i = 0; i < clouds; ++i)
  {
    std::vector<MapRay> rays;
    for (float y : { 0.004F, 0.010F, 0.016F })
    {
      rays.push_back(ray(-0.04F, y, kLow, 0.505F, y, kLow, RayKind::Hit));
      rays.push_back(ray(-0.04F, y, kHigh, 0.505F, y, kHigh, RayKind::Hit));
    }
    map.insert(rays, 0.1 * i);
  }
}

/// 20 clouds of floor rays from @p sx through the middle of that cell, from @p t0.
void insertRaysThroughLeg(LocalMap& map, float sx, double t0)
{
  for (int i = 0; i < 20; ++i)
  {
    map.insert(bothSlices(sx, 1.0F, 0.010F, RayKind::Free), t0 + 0.1 * i);
  }
}

TEST(LocalMap, RaysStillNearTheProjectorDoNotEraseADecodedLeg)
{
  // A leg decoded from 0.55 m in five clouds, then left alone for 60 s (decayed, still evidence);
  // the robot comes to face it from 0.18 m, too near to decode it, and floor rays of 20 clouds pass
  // through its cell (a centimetre of misregistration is enough). Near the projector those rays do
  // not erase it; from farther away the same rays do, and near ones erase a stray decoding.
  LocalMap map{ MapParams() };
  insertLegFace(map, 5);
  ASSERT_EQ(map.state(0.51, 0.01, 0.5), CellState::Occupied);
  insertRaysThroughLeg(map, 0.33F, 60.0);
  const CellInfo near = map.cellInfo(map.cellIndex(0.51), map.cellIndex(0.01), 62.0);
  EXPECT_NE(near.state, CellState::Free) << "erased by rays 0.18 m from their start";
  EXPECT_TRUE(near.evidence);
  EXPECT_EQ(map.state(0.8, 0.01, 62.0), CellState::Free) << "the floor beyond is free";
  insertRaysThroughLeg(map, -0.04F, 62.0);  // from 0.55 m: their free part counts there
  EXPECT_EQ(map.state(0.51, 0.01, 64.0), CellState::Free);
  MapParams off;
  off.near_free = 0.0;  // the rule off: the near rays erase it
  LocalMap plain{ off };
  insertLegFace(plain, 5);
  insertRaysThroughLeg(plain, 0.33F, 60.0);
  EXPECT_EQ(plain.state(0.51, 0.01, 62.0), CellState::Free);
  LocalMap stray{ MapParams() };  // decoded in one cloud only (2 pairs): near rays erase it
  insertLegFace(stray, 1);
  ASSERT_EQ(stray.state(0.51, 0.01, 0.5), CellState::Occupied);
  insertRaysThroughLeg(stray, 0.33F, 60.0);
  EXPECT_EQ(stray.state(0.51, 0.01, 62.0), CellState::Free);
}

TEST(LocalMap, AStrayHitIsErasedByRaysNearItAConfirmedSurfaceOnlyThroughIt)
{
  // One decoded point (a stray decoding, both slices): rays 4 mm beside it, within a quarter cell,
  // erase it. The same point decoded in five clouds (ten hits) is a surface: the same rays leave it,
  // rays through its place erase it.
  MapParams no_decay;
  no_decay.decay = 1e6;
  LocalMap stray{ no_decay }, surface{ no_decay };
  insertClouds(stray, 1, 0.0, 0.0F, 0.513F, 0.013F, RayKind::Hit);
  insertClouds(surface, 5, 0.0, 0.0F, 0.513F, 0.013F, RayKind::Hit);
  ASSERT_EQ(stray.state(0.51, 0.01, 0.5), CellState::Occupied);
  ASSERT_EQ(surface.state(0.51, 0.01, 0.5), CellState::Occupied);
  insertClouds(stray, 12, 1.0, 0.0F, 1.0F, 0.017F, RayKind::Free);
  insertClouds(surface, 12, 1.0, 0.0F, 1.0F, 0.017F, RayKind::Free);
  EXPECT_EQ(stray.state(0.51, 0.01, 3.0), CellState::Free);
  EXPECT_EQ(surface.state(0.51, 0.01, 3.0), CellState::Occupied);
  insertClouds(surface, 12, 3.0, 0.0F, 1.0F, 0.013F, RayKind::Free);
  EXPECT_EQ(surface.state(0.51, 0.01, 5.0), CellState::Free);
}

TEST(LocalMap, OneCloudDoesNotConfirmASurfaceAndDecayEndsTheConfirmation)
{
  // Twenty decoded points at one place in one image (a cluster of wrong decodings): still a few,
  // erased by the rays 4 mm beside it.
  MapParams no_decay;
  no_decay.decay = 1e6;
  LocalMap burst{ no_decay };
  burst.insert(std::vector<MapRay>(20, ray(0.0F, 0.013F, kLow, 0.513F, 0.013F, kLow, RayKind::Hit)), 0.0);
  ASSERT_EQ(burst.state(0.51, 0.01, 0.5), CellState::Occupied);
  insertClouds(burst, 12, 1.0, 0.0F, 1.0F, 0.017F, RayKind::Free);
  EXPECT_EQ(burst.state(0.51, 0.01, 3.0), CellState::Free);
  // A surface seen in five clouds keeps out the rays beside it while occupied; a minute later
  // (decay 30 s) it is below occupied, and they erase it: the place of an object that went away
  // does not stay unknown.
  LocalMap faded{ MapParams() };
  insertClouds(faded, 5, 0.0, 0.0F, 0.513F, 0.013F, RayKind::Hit);
  insertClouds(faded, 12, 1.0, 0.0F, 1.0F, 0.017F, RayKind::Free);
  EXPECT_EQ(faded.state(0.51, 0.01, 3.0), CellState::Occupied);
  ASSERT_EQ(faded.state(0.51, 0.01, 62.0), CellState::Unknown);
  insertClouds(faded, 12, 62.0, 0.0F, 1.0F, 0.017F, RayKind::Free);
  EXPECT_EQ(faded.state(0.51, 0.01, 64.0), CellState::Free);
}

namespace
{
/// Rays from (sx, sy) that graze a cylinder of radius r at (cx, cy), passing @p gap beside it on
/// both sides, and end @p beyond past it; both slices.
std::vector<MapRay> grazingRays(double sx, double sy, double cx, double cy, double r, double gap, double beyond)
{
  const double dx = cx - sx, dy = cy - sy, d = std::hypot(dx, dy);
  std::vector<MapRay> rays;
  for (const double side : { -1.0, 1.0 })
  {
    // Direction at the angle whose perpendicular distance to the centre is r + gap.
    const double a = std::atan2(dy, dx) + side * std::asin((r + gap) / d);
    const double len = std::sqrt(d * d - (r + gap) * (r + gap)) + beyond;
    const auto ex = static_cast<float>(sx + len * std::cos(a)), ey = static_cast<float>(sy + len * std::sin(a));
    rays.push_back(ray(float(sx), float(sy), kLow, ex, ey, kLow, RayKind::Free));
    rays.push_back(ray(float(sx), float(sy), kHigh, ex, ey, kHigh, RayKind::Free));
  }
  return rays;
}
}  // namespace

TEST(LocalMap, RaysGrazingALegFromAnotherSideDoNotEraseIt)
{
  // A 22 mm leg on a cell corner (as in test/scenes/leg_beside_wall.yaml) is decoded from the west;
  // later, from the south-east and the south-west, rays pass its flanks at 1 to 9 mm, cloud after
  // cloud. They cross the corners of the box around the hits but never its middle: every cell that
  // holds the leg's hits stays occupied. Rays through the leg's place, once it is gone, erase it.
  MapParams no_decay;
  no_decay.decay = 1e6;
  LocalMap map{ no_decay };
  const double cx = 0.7675, cy = 0.28, r = 0.011;
  std::vector<MapRay> front;
  for (double a = -80.0; a <= 80.0; a += 4.0)  // the face seen from (0, 0.28)
  {
    const auto hx = static_cast<float>(cx - r * std::cos(a * M_PI / 180.0));
    const auto hy = static_cast<float>(cy + r * std::sin(a * M_PI / 180.0));
    front.push_back(ray(0.0F, 0.28F, kLow, hx, hy, kLow, RayKind::Hit));
    front.push_back(ray(0.0F, 0.28F, kHigh, hx, hy, kHigh, RayKind::Hit));
  }
  for (int i = 0; i < 5; ++i)
  {
    map.insert(front, 0.1 * i);
  }
  const double corners[][2] = {
    { cx - r, cy - 0.005 }, { cx - r, cy + 0.005 }, { cx - 0.005, cy - r }, { cx - 0.005, cy + r }
  };
  for (const auto& c : corners)
  {
    ASSERT_EQ(map.state(c[0], c[1], 0.5), CellState::Occupied) << c[0] << ", " << c[1];
  }
  for (int i = 0; i < 40; ++i)
  {
    std::vector<MapRay> rays;
    for (const double gap : { 0.001, 0.003, 0.005, 0.007, 0.009 })
    {
      for (const auto& rs : grazingRays(1.0, -0.2, cx, cy, r, gap, 0.3))
        rays.push_back(rs);
      for (const auto& rs : grazingRays(0.45, -0.1, cx, cy, r, gap, 0.3))
        rays.push_back(rs);
    }
    map.insert(rays, 1.0 + 0.1 * i);
  }
  for (const auto& c : corners)
  {
    EXPECT_EQ(map.state(c[0], c[1], 5.0), CellState::Occupied) << "erased at " << c[0] << ", " << c[1];
  }
  // The leg is taken away: the view from the west that saw it now sees through its place.
  std::vector<MapRay> through;
  for (const MapRay& h : front)
  {
    // Along the same line, on past the place of the hit.
    through.push_back(
        ray(h.sx, h.sy, h.sz, h.sx + 1.4F * (h.ex - h.sx), h.sy + 1.4F * (h.ey - h.sy), h.ez, RayKind::Free));
  }
  for (int i = 0; i < 12; ++i)
  {
    map.insert(through, 5.0 + 0.1 * i);
  }
  for (const auto& c : corners)
  {
    EXPECT_EQ(map.state(c[0], c[1], 7.0), CellState::Free) << "kept at " << c[0] << ", " << c[1];
  }
}

namespace
{
/// A robot turning in place back and forth (turn rate cos(2 pi t / 4 s) rad/s, 10 clouds/s) before
/// a leg, with its clouds placed in odom at the pose of a clock 60 ms off (yaw error turn rate *
/// 60 ms, up to 0.06 rad: 48 mm at 0.8 m), plus a uniform yaw jitter of +-0.02 rad and +-5 mm.
/// Rays: 16 rows (-14 to -2 degrees) x 64 columns (+-0.45 rad) from 0.12 m above the floor, 0.15 m
/// ahead of the robot's centre; a ray that meets the leg within 1 m and within 70 % of its radius
/// of its axis is decoded there (Hit), one that meets its flanks or a farther leg is not decoded
/// (no ray); the others end on the floor (Free, up to 3 m).
struct TurningView
{
  double leg_x, leg_y, leg_r;
  std::uint32_t state;  // xorshift32

  double uniform()  // in [-1, 1)
  {
    state ^= state << 13;
    state ^= state >> 17;
    state ^= state << 5;
    return state / 2147483648.0 - 1.0;
  }

  std::vector<MapRay> cloud(double t, bool leg_there)
  {
    const double yaw = std::sin(2.0 * M_PI * t / 4.0) * 4.0 / (2.0 * M_PI);
    const double error = std::cos(2.0 * M_PI * t / 4.0) * 0.06 + 0.02 * uniform();
    const double ex = 0.005 * uniform(), ey = 0.005 * uniform();
    const double sx = 0.15 * std::cos(yaw), sy = 0.15 * std::sin(yaw), sz = 0.12;
    const auto place = [&](double x, double y, float& px, float& py)
    {
      px = static_cast<float>(std::cos(error) * x - std::sin(error) * y + ex);
      py = static_cast<float>(std::sin(error) * x + std::cos(error) * y + ey);
    };
    std::vector<MapRay> rays;
    for (int row = 0; row < 16; ++row)
    {
      const double el = (-14.0 + 12.0 * row / 15.0) * M_PI / 180.0;
      for (int col = 0; col < 64; ++col)
      {
        const double az = yaw - 0.45 + 0.9 * col / 63.0, dx = std::cos(az), dy = std::sin(az);
        double range = sz / std::tan(-el);  // to the floor
        RayKind kind = RayKind::Free;
        const double fx = sx - leg_x, fy = sy - leg_y, b = fx * dx + fy * dy;
        const double disc = b * b - (fx * fx + fy * fy - leg_r * leg_r);
        if (leg_there && disc > 0.0 && -b - std::sqrt(disc) < range)
        {
          range = -b - std::sqrt(disc);
          if (range > 1.0 || std::fabs(fx * dy - fy * dx) > 0.7 * leg_r)
          {
            continue;
          }
          kind = RayKind::Hit;
        }
        if (range > 3.0)
        {
          continue;
        }
        MapRay r;
        place(sx, sy, r.sx, r.sy);
        place(sx + range * dx, sy + range * dy, r.ex, r.ey);
        r.sz = static_cast<float>(sz);
        r.ez = static_cast<float>(sz + range * std::tan(el));
        r.kind = kind;
        rays.push_back(r);
      }
    }
    return rays;
  }
};

/// Occupied cells whose centre lies within 0.1 m of (x, y).
int occupiedNear(const LocalMap& map, double x, double y, double now)
{
  int n = 0;
  for (int ix = map.cellIndex(x - 0.1); ix <= map.cellIndex(x + 0.1); ++ix)
  {
    for (int iy = map.cellIndex(y - 0.1); iy <= map.cellIndex(y + 0.1); ++iy)
    {
      const double res = map.params().resolution;
      const bool near = std::hypot((ix + 0.5) * res - x, (iy + 0.5) * res - y) <= 0.1;
      n += near && map.cellState(ix, iy, now) == CellState::Occupied ? 1 : 0;
    }
  }
  return n;
}
}  // namespace

TEST(LocalMap, ALegSeenFromATurningRobotWithAClockOffStaysMapped)
{
  // While the robot turns, its clouds land in odom rotated by up to 0.06 rad, a different amount each
  // cloud: the leg's hits spread over cells 4 to 5 apart at 0.8 m, and the free rays of each cloud
  // cross the cells where the others put it. Once the leg was mapped, it must be there (an occupied
  // cell within 0.1 m) in every cloud but a few; taken away, its place must be empty within 20 s
  // (measured: 2 to 16 s; the decay alone takes a clamped cell below occupied in 53 s).
  int clouds = 0, missing = 0;
  for (const double leg_r : { 0.011, 0.02 })
  {
    for (const double distance : { 0.5, 0.8 })
    {
      for (std::uint32_t seed = 1; seed <= 4; ++seed)
      {
        LocalMap map{ MapParams() };
        TurningView view{ 0.15 + distance + 0.003 * seed, 0.007 * seed, leg_r, 2463534242U * seed };
        bool mapped = false;
        int run_missing = 0;
        for (int k = 0; k < 80; ++k)
        {
          map.insert(view.cloud(0.1 * k, true), 0.1 * k);
          const int n = occupiedNear(map, view.leg_x, view.leg_y, 0.1 * k);
          mapped = mapped || n >= 2;
          clouds += mapped ? 1 : 0;
          run_missing += mapped && n == 0 ? 1 : 0;
        }
        ASSERT_TRUE(mapped) << "leg " << 2000 * leg_r << " mm at " << distance << " m, seed " << seed;
        missing += run_missing;
        // The leg is taken away; the robot goes on turning.
        int k = 80;
        while (k < 330 && occupiedNear(map, view.leg_x, view.leg_y, 0.1 * (k - 1)) > 0)
        {
          map.insert(view.cloud(0.1 * k, false), 0.1 * k);
          ++k;
        }
        std::printf("leg %2.0f mm at %.1f m, seed %u: missing in %d clouds, emptied %.1f s after removal\n",
                    2000 * leg_r, distance, seed, run_missing, 0.1 * (k - 80));
        EXPECT_LE(k - 80, 200) << "leg " << 2000 * leg_r << " mm at " << distance << " m, seed " << seed;
      }
    }
  }
  std::printf("the leg missing in %d of %d clouds after it was mapped\n", missing, clouds);
  EXPECT_LE(missing, clouds / 100);
}

TEST(LocalMap, TheTrailKeepsWhatWasSeenBesideTheBody)
{
  LocalMap map{ MapParams() };
  map.insert(bothSlices(0.0F, 0.51F, 0.013F, RayKind::Hit), 0.0);
  map.markFreeDiscExceptSeen(0.51, -0.17, 0.2, 0.0);
  EXPECT_EQ(map.state(0.51, 0.01, 0.0), CellState::Occupied);
  EXPECT_EQ(map.state(0.51, -0.17, 0.0), CellState::Free);
  EXPECT_EQ(map.state(0.51, 0.02, 0.0), CellState::Free) << "unknown cells of the disc are marked";
  map.markFreeDisc(0.51, -0.17, 0.2, 0.0);
  EXPECT_EQ(map.state(0.51, 0.01, 0.0), CellState::Free) << "markFreeDisc overrides everything";
}

TEST(LocalMap, TheTrailHoldsTheCellsTheDiscCovered)
{
  LocalMap map{ MapParams() };
  // A disc of 0.1775 m driven from (0, 0) to (0.5, 0): cell centres within 0.1775 of the segment.
  map.markTrail(0.0, 0.0, 0.5, 0.0, 0.1775);
  const auto trail = [&](double x, double y) { return map.cellInfo(map.cellIndex(x), map.cellIndex(y), 0.0).trail; };
  EXPECT_TRUE(trail(0.25, 0.17));    // centre (0.25, 0.17): 0.17 from the segment
  EXPECT_FALSE(trail(0.25, 0.19));   // centre (0.25, 0.19): 0.19
  EXPECT_TRUE(trail(0.67, 0.01));    // beyond the end: 0.170 from (0.5, 0)
  EXPECT_FALSE(trail(0.69, 0.01));   // 0.190
  EXPECT_TRUE(trail(-0.17, -0.01));  // behind the start
  // The trail changes no log-odds: an unknown cell stays unknown, without evidence.
  const CellInfo c = map.cellInfo(map.cellIndex(0.25), map.cellIndex(0.0), 0.0);
  EXPECT_EQ(c.state, CellState::Unknown);
  EXPECT_FALSE(c.evidence);
  // A point (a standing robot) marks its disc; non-finite input and negative radii are ignored.
  map.markTrail(-1.0, 1.0, -1.0, 1.0, 0.05);
  EXPECT_TRUE(trail(-0.99, 1.01));
  EXPECT_FALSE(trail(-0.93, 1.01));
  map.markTrail(std::nan(""), 0.0, 1.0, 1.0, 0.5);
  map.markTrail(1.0, 1.0, 1.0, 1.0, -0.5);
  EXPECT_FALSE(trail(1.01, 1.01));
  // The trail is forgotten with the cell: when the window moves past it, and by clear().
  map.recenter(10.0, 0.0);
  map.recenter(0.0, 0.0);
  EXPECT_FALSE(trail(0.25, 0.0));
  map.markTrail(0.0, 0.0, 0.5, 0.0, 0.1775);
  map.clear();
  EXPECT_FALSE(trail(0.25, 0.0));
  EXPECT_FALSE(map.cellInfo(100000, 0, 0.0).trail) << "outside the window";
}

TEST(LocalMap, EvidenceTellsNeverSeenFromSeenToHoldSomething)
{
  LocalMap map{ MapParams() };
  const auto info = [&](double x, double y, double now)
  { return map.cellInfo(map.cellIndex(x), map.cellIndex(y), now); };
  EXPECT_FALSE(info(0.5, 0.01, 0.0).evidence) << "never seen";
  // One low ray: its cells are free in the low slice only (no ray crossed the high one): unknown,
  // but nothing was found there. Its lit end is a lone suspect: unknown with evidence.
  map.insert({ ray(0.0F, 0.01F, kLow, 0.61F, 0.01F, kLow, RayKind::Suspect) }, 0.0);
  EXPECT_EQ(info(0.3, 0.01, 0.0).state, CellState::Unknown);
  EXPECT_FALSE(info(0.3, 0.01, 0.0).evidence);
  EXPECT_EQ(info(0.61, 0.01, 0.0).state, CellState::Unknown);
  EXPECT_TRUE(info(0.61, 0.01, 0.0).evidence);
  // An occupied cell decayed below occupied_threshold keeps its evidence; a free one has none.
  map.insert(bothSlices(0.0F, 1.01F, -0.31F, RayKind::Hit), 0.0);
  EXPECT_EQ(info(1.01, -0.31, 0.0).state, CellState::Occupied);
  EXPECT_EQ(info(1.01, -0.31, 20.0).state, CellState::Unknown);
  EXPECT_TRUE(info(1.01, -0.31, 20.0).evidence);
  EXPECT_EQ(info(0.5, -0.31, 0.0).state, CellState::Free);
  EXPECT_FALSE(info(0.5, -0.31, 0.0).evidence);
}

TEST(LocalMap, OccupiedWinsOverFreeInOneCloud)
{
  LocalMap map{ MapParams() };
  std::vector<MapRay> rays = bothSlices(0.0F, 0.51F, 0.01F, RayKind::Hit);
  const std::vector<MapRay> through = bothSlices(0.0F, 1.0F, 0.01F, RayKind::Free);
  rays.insert(rays.end(), through.begin(), through.end());
  map.insert(rays, 0.0);
  EXPECT_EQ(map.state(0.51, 0.01, 0.0), CellState::Occupied);
  EXPECT_EQ(map.state(0.8, 0.01, 0.0), CellState::Free);
}

TEST(LocalMap, ManyRaysThroughOneCellCountOncePerCloud)
{
  LocalMap map{ MapParams() };
  std::vector<MapRay> rays;
  for (int i = 0; i < 100; ++i)
  {
    const std::vector<MapRay> r = bothSlices(0.0F, 1.0F, 0.01F, RayKind::Free);
    rays.insert(rays.end(), r.begin(), r.end());
  }
  map.insert(rays, 0.0);
  ASSERT_EQ(map.state(0.5, 0.01, 0.0), CellState::Free);
  // One cloud's -0.4 decays above -0.3 after 30 * ln(4/3) = 8.6 s; 100 separate updates would not.
  EXPECT_EQ(map.state(0.5, 0.01, 10.0), CellState::Unknown);
}

TEST(LocalMap, DecaysToUnknown)
{
  LocalMap map{ MapParams() };
  map.insert(bothSlices(0.0F, 1.01F, 0.01F, RayKind::Hit), 100.0);
  // Occupied while 0.85 exp(-dt / 30) > 0.6 (dt < 10.4 s); free while 0.4 exp(-dt / 30) > 0.3 (8.6 s).
  EXPECT_EQ(map.state(1.01, 0.01, 105.0), CellState::Occupied);
  EXPECT_EQ(map.state(0.5, 0.01, 105.0), CellState::Free);
  EXPECT_EQ(map.state(1.01, 0.01, 112.0), CellState::Unknown);
  EXPECT_EQ(map.state(0.5, 0.01, 112.0), CellState::Unknown);
  // The decay is applied before the next update: a second hit 20 s later gives
  // 0.85 exp(-20 / 30) + 0.85 = 1.29, occupied for another 30 ln(1.29 / 0.6) = 23 s.
  map.insert(bothSlices(0.0F, 1.01F, 0.01F, RayKind::Hit), 120.0);
  EXPECT_EQ(map.state(1.01, 0.01, 140.0), CellState::Occupied);
  EXPECT_EQ(map.state(1.01, 0.01, 146.0), CellState::Unknown);
  // Reading earlier than the last update does not amplify.
  EXPECT_EQ(map.state(1.01, 0.01, 0.0), CellState::Occupied);
}

TEST(LocalMap, SuspectNeedsTwoCloudsAndOwnFreePartDoesNotCancelIt)
{
  LocalMap map{ MapParams() };
  const std::vector<MapRay> lit = { ray(0.0F, 0.01F, kLow, 0.61F, 0.01F, kLow, RayKind::Suspect) };
  map.insert(lit, 0.0);
  EXPECT_EQ(map.state(0.61, 0.01, 0.0), CellState::Unknown);  // 0.5 < 0.6
  EXPECT_EQ(countCells(map, 0.0, 50), 1);                     // shown as suspect
  map.insert(lit, 0.0);
  EXPECT_EQ(map.state(0.61, 0.01, 0.0), CellState::Occupied);  // 1.0
}

TEST(LocalMap, TwoLitEndsBeatAFreeRayOfTheSameCloud)
{
  // A thin lit object (a dark leg) shares its cell with rays that pass beside it to the wall: where
  // two lit rays end in one voxel they win over those free rays, so the leg is not erased.
  LocalMap map{ MapParams() };
  const MapRay lit1 = ray(0.0F, 0.01F, kLow, 0.61F, 0.01F, kLow, RayKind::Suspect);
  const MapRay lit2 = ray(0.0F, 0.012F, kLow, 0.612F, 0.012F, kLow, RayKind::Suspect);
  const MapRay past = ray(0.0F, 0.01F, kLow, 1.0F, 0.01F, kLow, RayKind::Free);
  const MapRay high = ray(0.0F, 0.01F, kHigh, 1.0F, 0.01F, kHigh, RayKind::Free);
  map.insert({ lit1, lit2, past, high }, 0.0);
  EXPECT_EQ(map.state(0.61, 0.01, 0.0), CellState::Unknown);  // not free
  map.insert({ lit1, lit2, past, high }, 0.0);
  EXPECT_EQ(map.state(0.61, 0.01, 0.0), CellState::Occupied);
  EXPECT_EQ(map.state(0.81, 0.01, 0.0), CellState::Free);  // beyond it the free rays count
  // Once the light is gone (the object moved), free rays clear the cell.
  for (int i = 0; i < 4; ++i)
  {
    map.insert({ past, high }, 0.0);
  }
  EXPECT_EQ(map.state(0.61, 0.01, 0.0), CellState::Free);
}

TEST(LocalMap, ALoneLitEndLosesAgainstAFreeRayOfTheSameCloud)
{
  LocalMap map{ MapParams() };
  const std::vector<MapRay> batch = { ray(0.0F, 0.01F, kLow, 0.61F, 0.01F, kLow, RayKind::Suspect),
                                      ray(0.0F, 0.01F, kLow, 1.0F, 0.01F, kLow, RayKind::Free),
                                      ray(0.0F, 0.01F, kHigh, 1.0F, 0.01F, kHigh, RayKind::Free) };
  for (int i = 0; i < 4; ++i)
  {
    map.insert(batch, 0.0);
  }
  EXPECT_EQ(map.state(0.61, 0.01, 0.0), CellState::Free);
  // The same lit end with the free ray in separate clouds: the suspect counts.
  LocalMap split{ MapParams() };
  for (int i = 0; i < 4; ++i)
  {
    split.insert({ batch[0] }, 0.0);
  }
  split.insert({ batch[1], batch[2] }, 0.0);
  EXPECT_EQ(split.state(0.61, 0.01, 0.0), CellState::Occupied);  // min(2.0, 3.5) - 0.4
}

TEST(LocalMap, RayAboveALowObjectDoesNotClearIt)
{
  LocalMap map{ MapParams() };
  // A 40 mm object at x = 0.51: its top is seen (decoded) in the low slice.
  map.insert({ ray(0.0F, 0.01F, 0.09F, 0.51F, 0.01F, 0.03F, RayKind::Hit) }, 0.0);
  ASSERT_EQ(map.state(0.51, 0.01, 0.0), CellState::Occupied);
  // Rays of the sensor at 0.09 m rising to 0.17 m at 1 m pass above it (z ~ 0.13 there).
  for (int i = 0; i < 10; ++i)
  {
    map.insert({ ray(0.0F, 0.01F, 0.09F, 1.0F, 0.01F, 0.17F, RayKind::Free) }, 0.0);
  }
  EXPECT_EQ(map.state(0.51, 0.01, 0.0), CellState::Occupied);
  EXPECT_EQ(map.state(0.8, 0.01, 0.0), CellState::Unknown);  // only the upper slice is known there
}

TEST(LocalMap, DiagonalRayMarksEveryCellOnItsLine)
{
  LocalMap map{ MapParams() };
  const float sx = -0.73F, sy = 0.37F, ex = 1.29F, ey = -0.91F;
  map.insert({ ray(sx, sy, kLow, ex, ey, kLow, RayKind::Free), ray(sx, sy, kHigh, ex, ey, kHigh, RayKind::Free) }, 0.0);
  int free = 0;
  for (int i = 1; i < 1000; ++i)
  {
    const double t = i / 1000.0;
    free += map.state(sx + t * (ex - sx), sy + t * (ey - sy), 0.0) == CellState::Free ? 1 : 0;
  }
  EXPECT_EQ(free, 999);
  // The cells a line crosses: about |dx| + |dy| cells of 0.02 m, no more.
  EXPECT_LE(countCells(map, 0.0, 0), static_cast<int>((2.02 + 1.28) / 0.02) + 2);
  EXPECT_GE(countCells(map, 0.0, 0), static_cast<int>((2.02 + 1.28) / 0.02) - 2);
}

TEST(LocalMap, RaysAreClippedAtTheWindowEdge)
{
  LocalMap map{ MapParams() };  // window [-2, 2)^2
  // Through the whole window, both ends outside; a Hit end outside marks nothing.
  map.insert(bothSlices(-7.0F, 5.0F, 0.11F, RayKind::Hit), 0.0);
  EXPECT_EQ(map.state(-1.99, 0.11, 0.0), CellState::Free);
  EXPECT_EQ(map.state(1.99, 0.11, 0.0), CellState::Free);
  EXPECT_EQ(map.state(0.0, 0.11, 0.0), CellState::Free);
  EXPECT_EQ(countCells(map, 0.0, 100), 0);
  EXPECT_EQ(countCells(map, 0.0, 0), 200);
  // From far outside to an end inside.
  map.insert(bothSlices(-30.0F, 1.01F, -0.31F, RayKind::Hit), 0.0);
  EXPECT_EQ(map.state(1.01, -0.31, 0.0), CellState::Occupied);
  EXPECT_EQ(map.state(-1.99, -0.31, 0.0), CellState::Free);
  // Entirely outside.
  map.insert(bothSlices(-30.0F, 30.0F, 2.5F, RayKind::Hit), 0.0);
  EXPECT_EQ(countCells(map, 0.0, 100), 1);
  EXPECT_EQ(countCells(map, 0.0, 0), 200 + 150);
}

TEST(LocalMap, NonFiniteInputIsIgnored)
{
  LocalMap map{ MapParams() };
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<MapRay> rays = { ray(nan, 0.0F, kLow, 1.0F, 0.0F, kLow, RayKind::Hit),
                               ray(0.0F, 0.0F, kLow, 1.0F, nan, kLow, RayKind::Free),
                               ray(0.0F, 0.0F, kLow, 1.0F, 0.0F, nan, RayKind::Suspect),
                               ray(0.0F, 0.0F, kLow, inf, 0.0F, kLow, RayKind::Free) };
  const std::vector<MapRay> good = bothSlices(0.0F, 1.01F, 0.51F, RayKind::Hit);
  rays.insert(rays.end(), good.begin(), good.end());
  map.insert(rays, 0.0);
  EXPECT_EQ(map.invalidRays(), 4U);
  EXPECT_EQ(map.state(1.01, 0.51, 0.0), CellState::Occupied);
  EXPECT_EQ(countCells(map, 0.0, 100), 1);
  map.recenter(std::nan(""), 0.0);
  map.markFreeDisc(0.0, std::nan(""), 0.2, 0.0);
  map.markOccupiedDisc(0.0, 0.0, std::nan(""), 0.0);
  map.markOccupiedDisc(0.0, 0.0, -1.0, 0.0);
  EXPECT_EQ(map.state(1.01, 0.51, 0.0), CellState::Occupied);
  EXPECT_EQ(map.state(std::nan(""), 0.0, 0.0), CellState::Unknown);
  EXPECT_EQ(countCells(map, 0.0, 100), 1);
}

TEST(LocalMap, DiscsMarkEverySlice)
{
  LocalMap map{ MapParams() };
  map.markFreeDisc(0.0, 0.0, 0.2, 0.0);
  EXPECT_EQ(map.state(0.0, 0.0, 0.0), CellState::Free);
  EXPECT_EQ(map.state(0.19, 0.0, 0.0), CellState::Free);
  EXPECT_EQ(map.state(0.13, 0.13, 0.0), CellState::Free);
  EXPECT_EQ(map.state(0.15, 0.15, 0.0), CellState::Unknown);  // centre 0.21 from (0, 0)
  EXPECT_EQ(map.state(0.21, 0.0, 0.0), CellState::Unknown);
  map.markOccupiedDisc(0.19, 0.0, 0.03, 1.0);  // a bump overrides certain free space
  EXPECT_EQ(map.state(0.19, 0.0, 1.0), CellState::Occupied);
  EXPECT_EQ(map.state(0.0, 0.0, 1.0), CellState::Free);
  map.clear();
  EXPECT_EQ(countCells(map, 1.0, -1), 200 * 200);
}

TEST(LocalMap, MovingTheWindowForgetsWhatLeavesAndKeepsWhatStays)
{
  LocalMap map{ MapParams() };  // window [-2, 2)^2
  map.markOccupiedDisc(1.51, 0.51, 0.005, 0.0);
  map.markOccupiedDisc(-1.91, 0.51, 0.005, 0.0);
  map.markOccupiedDisc(0.51, -1.91, 0.005, 0.0);
  ASSERT_EQ(countCells(map, 0.0, 100), 3);
  map.recenter(1.0, 0.5);  // window [-1, 3) x [-1.5, 2.5)
  EXPECT_EQ(map.state(1.51, 0.51, 0.0), CellState::Occupied);
  EXPECT_EQ(map.state(-1.91, 0.51, 0.0), CellState::Unknown);  // outside
  EXPECT_EQ(map.state(2.09, 0.51, 0.0), CellState::Unknown);   // reuses the slot of (-1.91, 0.51)
  EXPECT_EQ(map.state(0.51, 2.09, 0.0), CellState::Unknown);   // reuses the slot of (0.51, -1.91)
  EXPECT_EQ(countCells(map, 0.0, 100), 1);
  std::vector<std::int8_t> data;
  double ox = 0.0, oy = 0.0;
  int width = 0;
  map.toOccupancy(0.0, data, ox, oy, width);
  EXPECT_NEAR(ox, -1.0, 1e-9);
  EXPECT_NEAR(oy, -1.5, 1e-9);
  EXPECT_EQ(width, 200);
  const std::size_t row = (0.51 + 1.5) / 0.02, col = (1.51 + 1.0) / 0.02;  // 100, 125
  EXPECT_EQ(data[row * 200 + col], 100);
  map.recenter(0.0, 0.0);  // back: what left stays forgotten
  EXPECT_EQ(map.state(-1.91, 0.51, 0.0), CellState::Unknown);
  EXPECT_EQ(map.state(0.51, -1.91, 0.0), CellState::Unknown);
  EXPECT_EQ(map.state(1.51, 0.51, 0.0), CellState::Occupied);
}

TEST(LocalMap, FarMovesForgetEverything)
{
  LocalMap map{ MapParams() };
  map.markOccupiedDisc(0.51, 0.51, 0.005, 0.0);
  map.recenter(100.0, -250.0);
  EXPECT_EQ(countCells(map, 0.0, 100), 0);
  map.markOccupiedDisc(100.51, -249.49, 0.005, 0.0);
  EXPECT_EQ(map.state(100.51, -249.49, 0.0), CellState::Occupied);
  map.recenter(0.0, 0.0);
  EXPECT_EQ(map.state(0.51, 0.51, 0.0), CellState::Unknown);
  EXPECT_EQ(countCells(map, 0.0, 100), 0);
  // Small steps add up: 20 moves of 3 cells forget what is left behind, nothing else.
  map.markOccupiedDisc(0.51, 0.51, 0.005, 0.0);
  map.markOccupiedDisc(-1.99, 0.51, 0.005, 0.0);
  for (int i = 1; i <= 20; ++i)
  {
    map.recenter(0.06 * i, 0.0);
  }
  EXPECT_EQ(map.state(0.51, 0.51, 0.0), CellState::Occupied);
  EXPECT_EQ(map.state(-1.99, 0.51, 0.0), CellState::Unknown);
  EXPECT_EQ(countCells(map, 0.0, 100), 1);
}

TEST(LocalMap, BadParametersThrowNamingTheField)
{
  const auto bad = [](auto change)
  {
    MapParams p;
    change(p);
    return sl_testing::invalidArgumentOf([&] { LocalMap map(p); });
  };
  EXPECT_EQ(sl_testing::invalidArgumentOf([] { MapParams().validate(); }), "");
  EXPECT_EQ(bad([](MapParams& p) { p.resolution = 0.3; }).rfind("map_resolution must be in (0.005, 0.2]", 0), 0U);
  EXPECT_EQ(bad([](MapParams& p) { p.resolution = 0.005; }).rfind("map_resolution", 0), 0U);
  EXPECT_EQ(bad([](MapParams& p) { p.size = std::nan(""); }).rfind("map_size", 0), 0U);
  EXPECT_EQ(bad([](MapParams& p) { p.size = 0.01; }).rfind("map_size", 0), 0U);  // one cell
  EXPECT_EQ(bad([](MapParams& p) { p.slices = 0; }).rfind("map_slices", 0), 0U);
  EXPECT_EQ(bad([](MapParams& p) { p.z_max = 0.01; }).rfind("map_z_max", 0), 0U);
  EXPECT_EQ(bad([](MapParams& p) { p.decay = 0.0; }).rfind("map_decay", 0), 0U);
  EXPECT_EQ(bad([](MapParams& p) { p.hit = 0.0; }).rfind("map_hit", 0), 0U);
  EXPECT_EQ(bad([](MapParams& p) { p.miss = -0.4; }).rfind("map_miss", 0), 0U);
  EXPECT_EQ(bad([](MapParams& p) { p.suspect = 5.0; }).rfind("map_suspect", 0), 0U);
  EXPECT_EQ(bad([](MapParams& p) { p.clamp = 0.0; }).rfind("map_clamp", 0), 0U);
  EXPECT_EQ(bad([](MapParams& p) { p.near_free = -0.1; }).rfind("map_near_free", 0), 0U);
  EXPECT_EQ(bad([](MapParams& p) { p.near_free = std::nan(""); }).rfind("map_near_free", 0), 0U);
  EXPECT_EQ(bad([](MapParams& p) { p.occupied_threshold = 4.0; }).rfind("map_occupied_threshold", 0), 0U);
  EXPECT_EQ(bad([](MapParams& p) { p.free_threshold = 0.1; }).rfind("map_free_threshold", 0), 0U);
  EXPECT_NE(bad([](MapParams& p) { p.resolution = 0.3; }).find("got 0.3"), std::string::npos);
}

TEST(LocalMap, OtherGeometries)
{
  MapParams p;
  p.size = 1.0;
  p.resolution = 0.05;
  p.slices = 4;
  LocalMap map(p);
  EXPECT_EQ(map.width(), 20);
  // One rising ray crosses all four slices, but each cell only the slices of its own piece.
  map.insert({ ray(-0.45F, 0.02F, 0.0F, 0.46F, 0.02F, 0.19F, RayKind::Free) }, 0.0);
  EXPECT_EQ(countCells(map, 0.0, 0), 0);
  for (float z = 0.02F; z < 0.17F; z += 0.01F)
  {
    map.insert({ ray(-0.45F, 0.02F, z, 0.46F, 0.02F, z, RayKind::Free) }, 0.0);
  }
  EXPECT_EQ(countCells(map, 0.0, 0), 19);  // the cells from -0.45 to 0.46
}

TEST(LocalMap, OccupiedByLitEndsAlonePublishesAsSuspect)
{
  // To the decisions a voxel that pairs of lit ends made occupied is occupied; in the published
  // grid it is 50 (a suspect): only a decoded point (or a bump) makes 100.
  LocalMap map{ MapParams() };
  const MapRay lit1 = ray(0.0F, 0.01F, kLow, 0.61F, 0.01F, kLow, RayKind::Suspect);
  const MapRay lit2 = ray(0.0F, 0.012F, kLow, 0.612F, 0.012F, kLow, RayKind::Suspect);
  map.insert({ lit1, lit2 }, 0.0);
  map.insert({ lit1, lit2 }, 0.0);
  ASSERT_EQ(map.state(0.61, 0.01, 0.0), CellState::Occupied);
  EXPECT_EQ(countCells(map, 0.0, 100), 0);
  EXPECT_EQ(countCells(map, 0.0, 50), 1);
  map.insert({ ray(0.0F, 0.01F, kLow, 0.615F, 0.01F, kLow, RayKind::Hit) }, 0.0);
  EXPECT_EQ(countCells(map, 0.0, 100), 1);
}
}  // namespace
}  // namespace sl_obstacle
