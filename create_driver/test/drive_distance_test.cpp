#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>

#include "create_driver/drive_distance.h"

namespace cd = create_driver;

namespace
{
// A plant: the commanded speed is applied after a delay of `delay_steps`, odometry is quantised
// to whole millimetres (like packet 19) and reported every 15 ms.
struct SimRun
{
  cd::StopReason reason;
  double final_position;  // m, after the robot has come to rest
  double reported;        // travelled reported by the controller
  double max_speed_seen;
};

SimRun simulate(double goal, double speed, int delay_steps = 2, double blocked_after = 1e9)
{
  cd::DriveDistanceController c;
  const double dt = 0.015;
  double pos = 0.0;
  double reported_mm_total = 0.0;
  double acc_mm = 0.0;
  std::deque<double> pipeline(static_cast<size_t>(delay_steps), 0.0);
  std::string err;
  EXPECT_TRUE(c.start(goal, speed, 0.0, 0.0, 0.0, &err)) << err;
  SimRun r{ cd::StopReason::REACHED, 0.0, 0.0, 0.0 };
  double t = 0.0;
  double cmd = 0.0;
  bool finished = false;
  int after = 0;
  for (int i = 0; i < 200000; ++i)
  {
    t += dt;
    pipeline.push_back(cmd);
    const double v = pipeline.front();
    pipeline.pop_front();
    if (std::fabs(pos) < blocked_after)
    {
      pos += v * dt;
      acc_mm += v * dt * 1000.0;
    }
    r.max_speed_seen = std::max(r.max_speed_seen, std::fabs(v));
    const double rep = std::trunc(acc_mm);
    acc_mm -= rep;
    reported_mm_total += rep;
    if (!finished)
    {
      const auto o = c.update(reported_mm_total / 1000.0, 0.0, t);
      cmd = o.active ? o.linear : 0.0;
      if (o.finished)
      {
        finished = true;
        r.reason = o.reason;
        r.reported = c.travelled();
      }
    }
    else if (++after > delay_steps + 2)
    {
      break;  // the last non-zero command has left the pipeline
    }
  }
  r.final_position = pos;
  return r;
}
}  // namespace

class DriveDistanceSpeeds : public ::testing::TestWithParam<double>
{
};

TEST_P(DriveDistanceSpeeds, HalfMetreEndsWithin5mm)
{
  const double speed = GetParam();
  for (double goal : { 0.5, -0.5 })
  {
    const SimRun r = simulate(goal, speed);
    EXPECT_EQ(r.reason, cd::StopReason::REACHED) << "speed " << speed << " goal " << goal;
    EXPECT_NEAR(r.final_position, goal, 0.005) << "speed " << speed << " goal " << goal;
    EXPECT_NEAR(r.reported, goal, 0.005);
    EXPECT_LE(r.max_speed_seen, std::max(speed, 0.01) + 1e-9);
  }
}

INSTANTIATE_TEST_SUITE_P(CreateSpeeds, DriveDistanceSpeeds, ::testing::Values(0.01, 0.05, 0.2, 0.5));

TEST(DriveDistance, ShortGoalAtHighSpeedDoesNotOvershootMuch)
{
  const SimRun r = simulate(0.02, 0.5);
  EXPECT_EQ(r.reason, cd::StopReason::REACHED);
  EXPECT_NEAR(r.final_position, 0.02, 0.005);
}

TEST(DriveDistance, HeldBackTimesOut)
{
  const SimRun r = simulate(0.5, 0.2, 2, 0.1);  // the robot stops moving after 10 cm
  EXPECT_EQ(r.reason, cd::StopReason::TIMEOUT);
  EXPECT_NEAR(r.final_position, 0.1, 0.01);
}

TEST(DriveDistance, InvalidGoals)
{
  cd::DriveDistanceController c;
  std::string err;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(c.start(nan, 0.1, 0, 0, 0, &err));
  EXPECT_FALSE(err.empty());
  EXPECT_FALSE(c.start(0.5, inf, 0, 0, 0, &err));
  EXPECT_FALSE(c.start(0.5, 0.0, 0, 0, 0, &err));
  EXPECT_FALSE(c.start(0.5, -0.1, 0, 0, 0, &err));
  EXPECT_FALSE(c.active());
}

TEST(DriveDistance, SpeedIsClamped)
{
  cd::DriveDistanceController c;
  std::string err;
  ASSERT_TRUE(c.start(1.0, 3.0, 0, 0, 0, &err));
  EXPECT_DOUBLE_EQ(c.speed(), 0.5);
  ASSERT_TRUE(c.start(1.0, 0.001, 0, 0, 0, &err));
  EXPECT_DOUBLE_EQ(c.speed(), 0.01);
}

TEST(DriveDistance, AbortReportsReason)
{
  cd::DriveDistanceController c;
  std::string err;
  ASSERT_TRUE(c.start(1.0, 0.2, 10.0, 0, 0, &err));
  auto o = c.update(10.1, 0.0, 0.5);
  EXPECT_TRUE(o.active);
  EXPECT_GT(o.linear, 0.0);
  EXPECT_NEAR(c.travelled(), 0.1, 1e-12);
  EXPECT_NEAR(c.remaining(), 0.9, 1e-12);
  c.abort(cd::StopReason::BUMPER);
  EXPECT_FALSE(c.active());
  EXPECT_EQ(c.lastReason(), cd::StopReason::BUMPER);
  o = c.update(10.2, 0.0, 0.6);
  EXPECT_FALSE(o.active);
  EXPECT_FALSE(o.finished);
  EXPECT_EQ(o.linear, 0.0);
}

TEST(DriveDistance, HeadingHoldCorrectsDrift)
{
  cd::DriveDistanceController c;
  std::string err;
  ASSERT_TRUE(c.start(1.0, 0.2, 0.0, 0.5, 0.0, &err));
  // The robot has turned left (yaw above the start): correction turns right.
  auto o = c.update(0.1, 0.6, 0.5);
  EXPECT_LT(o.angular, 0.0);
  o = c.update(0.2, 0.4, 1.0);
  EXPECT_GT(o.angular, 0.0);
  // Bounded.
  o = c.update(0.3, 10.0, 1.5);
  EXPECT_NEAR(o.angular, -c.params().max_heading_rate, 1e-12);
}

TEST(DriveDistance, DeceleratesNearGoal)
{
  cd::DriveDistanceController c;
  std::string err;
  ASSERT_TRUE(c.start(0.5, 0.5, 0.0, 0.0, 0.0, &err));
  const double far = c.update(0.0, 0.0, 0.1).linear;
  c.update(0.3, 0.0, 0.7);
  c.update(0.45, 0.0, 1.0);
  const double near = c.update(0.48, 0.0, 1.2).linear;
  EXPECT_NEAR(far, 0.5, 0.001);
  EXPECT_LT(near, 0.1);
  EXPECT_GE(near, 0.01);
}

TEST(DriveDistance, ReasonNames)
{
  EXPECT_STREQ(cd::stopReasonName(cd::StopReason::REACHED), "reached");
  EXPECT_STREQ(cd::stopReasonName(cd::StopReason::INVALID_GOAL), "invalid goal");
}
