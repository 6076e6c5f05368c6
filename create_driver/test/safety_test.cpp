#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "create_driver/oi_commands.h"
#include "create_driver/safety.h"

namespace cd = create_driver;

TEST(Safety, FiniteCheck)
{
  EXPECT_TRUE(cd::isFiniteCommand(0.1, -0.2));
  EXPECT_FALSE(cd::isFiniteCommand(std::numeric_limits<double>::quiet_NaN(), 0.0));
  EXPECT_FALSE(cd::isFiniteCommand(0.0, std::numeric_limits<double>::infinity()));
  EXPECT_FALSE(cd::isFiniteCommand(-std::numeric_limits<double>::infinity(), 0.0));
}

TEST(Safety, ClampTwist)
{
  cd::VelocityLimits l;
  l.max_speed = 0.3;
  l.max_angular_speed = 1.0;
  double v = 0.9, w = -5.0;
  cd::clampTwist(l, v, w);
  EXPECT_DOUBLE_EQ(v, 0.3);
  EXPECT_DOUBLE_EQ(w, -1.0);
}

TEST(Safety, TwistToWheels)
{
  auto w = cd::twistToWheels(0.2, 0.0, 0.258, 0.5);
  EXPECT_DOUBLE_EQ(w.left, 0.2);
  EXPECT_DOUBLE_EQ(w.right, 0.2);
  w = cd::twistToWheels(0.0, 1.0, 0.258, 0.5);
  EXPECT_NEAR(w.left, -0.129, 1e-12);
  EXPECT_NEAR(w.right, 0.129, 1e-12);
  // Saturation keeps the curvature: v = 0.5, w = 2 -> wheels 0.242 / 0.758, scaled by 0.5/0.758.
  w = cd::twistToWheels(0.5, 2.0, 0.258, 0.5);
  EXPECT_NEAR(w.right, 0.5, 1e-12);
  EXPECT_NEAR((w.right - w.left) / 0.258 / (0.5 * (w.left + w.right)), 2.0 / 0.5, 1e-9);
}

TEST(Safety, TwistToDriveRadiusSpecialCases)
{
  auto d = cd::twistToDriveRadius(0.2, 0.0, 0.258, 0.5);
  EXPECT_EQ(d.velocity_mm_s, 200);
  EXPECT_EQ(d.radius_mm, cd::oi::RADIUS_STRAIGHT);
  d = cd::twistToDriveRadius(0.0, 1.0, 0.258, 0.5);
  EXPECT_EQ(d.radius_mm, cd::oi::RADIUS_TURN_CCW);
  EXPECT_EQ(d.velocity_mm_s, 129);
  d = cd::twistToDriveRadius(0.0, -1.0, 0.258, 0.5);
  EXPECT_EQ(d.radius_mm, cd::oi::RADIUS_TURN_CW);
  EXPECT_EQ(d.velocity_mm_s, 129);
  // R = v / w = 0.2 / 0.4 = 0.5 m.
  d = cd::twistToDriveRadius(0.2, 0.4, 0.258, 0.5);
  EXPECT_EQ(d.velocity_mm_s, 200);
  EXPECT_EQ(d.radius_mm, 500);
  // Backwards while turning left (w > 0): negative radius.
  d = cd::twistToDriveRadius(-0.2, 0.4, 0.258, 0.5);
  EXPECT_EQ(d.velocity_mm_s, -200);
  EXPECT_EQ(d.radius_mm, -500);
  // Radius beyond 2 m: straight.
  d = cd::twistToDriveRadius(0.3, 0.1, 0.258, 0.5);
  EXPECT_EQ(d.radius_mm, cd::oi::RADIUS_STRAIGHT);
}

TEST(Safety, DriveRadiusToWheelsMatchesSpecConvention)
{
  // Positive velocity and positive radius: forward while turning left (right wheel faster).
  auto w = cd::driveRadiusToWheels(200, 500, 0.258);
  EXPECT_NEAR(w.left, 0.2 * (0.5 - 0.129) / 0.5, 1e-12);
  EXPECT_NEAR(w.right, 0.2 * (0.5 + 0.129) / 0.5, 1e-12);
  w = cd::driveRadiusToWheels(100, cd::oi::RADIUS_TURN_CW, 0.258);
  EXPECT_DOUBLE_EQ(w.left, 0.1);
  EXPECT_DOUBLE_EQ(w.right, -0.1);
  w = cd::driveRadiusToWheels(100, cd::oi::RADIUS_TURN_CCW, 0.258);
  EXPECT_DOUBLE_EQ(w.left, -0.1);
  EXPECT_DOUBLE_EQ(w.right, 0.1);
  w = cd::driveRadiusToWheels(-150, cd::oi::RADIUS_STRAIGHT, 0.258);
  EXPECT_DOUBLE_EQ(w.left, -0.15);
  EXPECT_DOUBLE_EQ(w.right, -0.15);
  w = cd::driveRadiusToWheels(150, cd::oi::RADIUS_STRAIGHT_ALT, 0.258);
  EXPECT_DOUBLE_EQ(w.left, 0.15);
  // Round trip with twistToDriveRadius.
  const auto d = cd::twistToDriveRadius(0.15, 0.5, 0.258, 0.5);
  w = cd::driveRadiusToWheels(d.velocity_mm_s, d.radius_mm, 0.258);
  EXPECT_NEAR(0.5 * (w.left + w.right), 0.15, 1e-3);
  EXPECT_NEAR((w.right - w.left) / 0.258, 0.5, 2e-3);
}

TEST(Safety, LimiterRampsAndResets)
{
  cd::VelocityLimits l;
  l.max_accel = 1.0;
  l.max_angular_accel = 2.0;
  cd::VelocityLimiter lim(l);
  double v = 0, w = 0;
  lim.limit(0.5, 1.0, 0.1, v, w);
  EXPECT_NEAR(v, 0.1, 1e-12);
  EXPECT_NEAR(w, 0.2, 1e-12);
  for (int i = 0; i < 10; ++i)
    lim.limit(0.5, 1.0, 0.1, v, w);
  EXPECT_NEAR(v, 0.5, 1e-12);
  EXPECT_NEAR(w, 1.0, 1e-12);
  lim.limit(0.0, 0.0, 0.1, v, w);  // decelerates at the same rate
  EXPECT_NEAR(v, 0.4, 1e-12);
  lim.reset();
  EXPECT_EQ(lim.linear(), 0.0);
  // Unlimited acceleration.
  l.max_accel = 0.0;
  lim.setLimits(l);
  lim.limit(0.3, 0.0, 0.01, v, w);
  EXPECT_NEAR(v, 0.3, 1e-12);
}

namespace
{
cd::SensorState sensors(uint8_t bumps_byte, bool cliff = false)
{
  cd::SensorState s;
  s.set(7, bumps_byte);
  s.set(10, cliff ? 1 : 0);
  return s;
}
}  // namespace

TEST(HazardLatch, BumpLatchesUntilReset)
{
  cd::HazardLatch h;
  EXPECT_FALSE(h.update(sensors(0), false));
  EXPECT_FALSE(h.latched());
  EXPECT_TRUE(h.update(sensors(cd::bumps::BUMP_LEFT), false));
  EXPECT_TRUE(h.latched());
  EXPECT_EQ(h.reason(), cd::Hazard::BUMPER);
  EXPECT_FALSE(h.allows(0.1));
  EXPECT_FALSE(h.allows(0.0));
  EXPECT_TRUE(h.allows(-0.1));
  // Bumper released, robot not backing: still latched.
  h.update(sensors(0), false);
  EXPECT_TRUE(h.latched());
  std::string why;
  EXPECT_FALSE(h.reset(sensors(cd::bumps::BUMP_RIGHT), &why));
  EXPECT_NE(why.find("bumper"), std::string::npos);
  EXPECT_TRUE(h.reset(sensors(0), &why));
  EXPECT_FALSE(h.latched());
}

TEST(HazardLatch, BackingAwayReleasesBumpAndCliff)
{
  cd::HazardLatch h;
  h.update(sensors(0, true), false);
  EXPECT_EQ(h.reason(), cd::Hazard::CLIFF);
  h.update(sensors(0, true), true);  // backing but the cliff is still seen
  EXPECT_TRUE(h.latched());
  h.update(sensors(0, false), true);  // backed off the edge
  EXPECT_FALSE(h.latched());
}

TEST(HazardLatch, WheelDropNeedsReset)
{
  cd::HazardLatch h;
  EXPECT_TRUE(h.update(sensors(cd::bumps::WHEEL_DROP_LEFT | cd::bumps::BUMP_RIGHT), false));
  EXPECT_EQ(h.reason(), cd::Hazard::WHEEL_DROP);
  EXPECT_FALSE(h.allows(-0.1));
  h.update(sensors(0), true);
  EXPECT_TRUE(h.latched());
  EXPECT_TRUE(h.reset(sensors(0), nullptr));
}

TEST(HazardLatch, WorseHazardUpgradesLatch)
{
  cd::HazardLatch h;
  EXPECT_TRUE(h.update(sensors(cd::bumps::BUMP_RIGHT), false));
  EXPECT_FALSE(h.update(sensors(cd::bumps::BUMP_RIGHT), false));
  EXPECT_TRUE(h.update(sensors(cd::bumps::WHEEL_DROP_CASTER), false));
  EXPECT_EQ(h.reason(), cd::Hazard::WHEEL_DROP);
  EXPECT_FALSE(h.update(sensors(cd::bumps::BUMP_RIGHT), false));
  EXPECT_EQ(h.reason(), cd::Hazard::WHEEL_DROP);
}
