#include <gtest/gtest.h>

#include <cmath>

#include "create_driver/odometry.h"

namespace cd = create_driver;

namespace
{
/// The encoders' default step, m per count.
const double kMetresPerCount = cd::Odometry::Params().encoder_m_per_count;

/// The default parameters with wheels @p wheel_base m apart.
cd::Odometry::Params wheelBase(double wheel_base)
{
  cd::Odometry::Params params;
  params.wheel_base = wheel_base;
  return params;
}
}  // namespace

TEST(Odometry, NormalizeAngle)
{
  EXPECT_NEAR(cd::normalizeAngle(3 * M_PI), M_PI, 1e-12);
  EXPECT_NEAR(cd::normalizeAngle(-M_PI), M_PI, 1e-12);
  EXPECT_NEAR(cd::normalizeAngle(2 * M_PI + 0.1), 0.1, 1e-12);
  EXPECT_NEAR(cd::normalizeAngle(-2 * M_PI - 0.1), -0.1, 1e-12);
}

TEST(Odometry, EncoderDeltaWraps)
{
  EXPECT_EQ(cd::encoderDelta(10, 65530), 16);
  EXPECT_EQ(cd::encoderDelta(65530, 10), -16);
  EXPECT_EQ(cd::encoderDelta(100, 40), 60);
  EXPECT_EQ(cd::encoderDelta(40, 100), -60);
}

TEST(Odometry, StraightFromDistanceAngle)
{
  cd::Odometry o;
  double t = 0.0;
  for (int i = 0; i < 100; ++i)
    o.updateDistanceAngle(0.003, 0.0, t += 0.015);
  EXPECT_NEAR(o.pose().x, 0.3, 1e-9);
  EXPECT_NEAR(o.pose().y, 0.0, 1e-12);
  EXPECT_NEAR(o.distance(), 0.3, 1e-9);
  EXPECT_NEAR(o.linearVelocity(), 0.2, 1e-6);
  EXPECT_NEAR(o.angularVelocity(), 0.0, 1e-9);
}

TEST(Odometry, BackwardsCountsNegative)
{
  cd::Odometry o;
  o.updateDistanceAngle(-0.1, 0.0, 0.1);
  EXPECT_NEAR(o.pose().x, -0.1, 1e-12);
  EXPECT_NEAR(o.distance(), -0.1, 1e-12);
}

TEST(Odometry, QuarterCircleArc)
{
  // Radius 1 m, quarter turn counter-clockwise in 1000 steps: ends at (1, 1) with yaw pi/2.
  cd::Odometry o;
  const int n = 1000;
  const double dtheta = (M_PI / 2) / n;
  for (int i = 0; i < n; ++i)
    o.updateDistanceAngle(1.0 * dtheta, dtheta, i * 0.01);
  EXPECT_NEAR(o.pose().x, 1.0, 1e-6);
  EXPECT_NEAR(o.pose().y, 1.0, 1e-6);
  EXPECT_NEAR(o.pose().yaw, M_PI / 2, 1e-9);
}

TEST(Odometry, FullTurnsWrapYawButNotContinuousYaw)
{
  cd::Odometry o;
  for (int i = 0; i < 720; ++i)
    o.updateDistanceAngle(0.0, M_PI / 180.0, i * 0.01);  // two full turns in place
  EXPECT_NEAR(o.pose().yaw, 0.0, 1e-9);
  EXPECT_NEAR(o.yawContinuous(), 4 * M_PI, 1e-9);
  EXPECT_NEAR(o.pose().x, 0.0, 1e-12);
  EXPECT_GT(o.pose().yaw, -M_PI);
  EXPECT_LE(o.pose().yaw, M_PI);
}

TEST(Odometry, EncodersWithWrapAround)
{
  cd::Odometry o(wheelBase(0.235));
  // Baseline just below the wrap; both wheels advance 100 counts, crossing 65535 -> 0.
  o.updateEncoders(65500, 65500, 0.0);
  EXPECT_NEAR(o.distance(), 0.0, 1e-12);
  o.updateEncoders(64, 64, 0.1);
  EXPECT_NEAR(o.distance(), 100 * kMetresPerCount, 1e-9);
  EXPECT_NEAR(o.pose().x, 100 * kMetresPerCount, 1e-9);
  // Going backwards across the wrap again.
  o.updateEncoders(65500, 65500, 0.2);
  EXPECT_NEAR(o.distance(), 0.0, 1e-9);
}

TEST(Odometry, EncodersTurnInPlace)
{
  cd::Odometry o(wheelBase(0.235));
  o.updateEncoders(1000, 1000, 0.0);
  // Left -n counts, right +n counts: rotation 2 n mpc / b, no translation.
  const int n = 200;
  o.updateEncoders(static_cast<uint16_t>(1000 - n), static_cast<uint16_t>(1000 + n), 0.5);
  EXPECT_NEAR(o.pose().yaw, 2 * n * kMetresPerCount / 0.235, 1e-9);
  EXPECT_NEAR(o.distance(), 0.0, 1e-12);
}

TEST(Odometry, BaselineResetIgnoresJump)
{
  cd::Odometry o;
  o.updateEncoders(100, 100, 0.0);
  o.resetEncoderBaseline();
  o.updateEncoders(30000, 12, 0.1);  // e.g. the robot was power-cycled: no jump
  EXPECT_NEAR(o.distance(), 0.0, 1e-12);
  EXPECT_NEAR(o.pose().yaw, 0.0, 1e-12);
}
