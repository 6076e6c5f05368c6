// Tests of VelocityGoal, the open-loop distance goal of the cmd_vel command mode.
#include <gtest/gtest.h>

#include <cmath>

#include "sl_obstacle/velocity_goal.h"

namespace sl_obstacle
{
namespace
{
TEST(VelocityGoal, IntegratesTheCommandedSpeedUntilDone)
{
  VelocityGoal goal;
  EXPECT_FALSE(goal.active());
  EXPECT_DOUBLE_EQ(goal.speed(), 0.0);
  goal.start(0.3, 0.2, 10.0);
  EXPECT_TRUE(goal.active());
  EXPECT_DOUBLE_EQ(goal.speed(), 0.2);
  EXPECT_FALSE(goal.update(10.5, 1.0));
  EXPECT_NEAR(goal.travelled(), 0.1, 1e-12);
  EXPECT_NEAR(goal.remaining(), 0.2, 1e-12);
  EXPECT_FALSE(goal.update(11.0, 1.0));
  EXPECT_TRUE(goal.update(11.5, 1.0));  // 0.3 m after 1.5 s
  EXPECT_FALSE(goal.active());
  EXPECT_DOUBLE_EQ(goal.speed(), 0.0);
  EXPECT_DOUBLE_EQ(goal.remaining(), 0.0);
  EXPECT_FALSE(goal.update(12.0));  // done once only
}

TEST(VelocityGoal, LongPausesAreNotCreditedWithDistance)
{
  VelocityGoal goal;
  goal.start(1.0, 0.2, 0.0);
  goal.update(10.0, 0.25);  // a stalled caller: counts as 0.25 s
  EXPECT_NEAR(goal.travelled(), 0.05, 1e-12);
  goal.update(9.0);  // time going backwards adds nothing
  EXPECT_NEAR(goal.travelled(), 0.05, 1e-12);
}

TEST(VelocityGoal, StopAndRestart)
{
  VelocityGoal goal;
  goal.start(0.5, 0.1, 0.0);
  goal.update(1.0);
  goal.stop();
  EXPECT_FALSE(goal.active());
  EXPECT_FALSE(goal.update(2.0));
  goal.start(0.2, 0.1, 5.0);
  EXPECT_DOUBLE_EQ(goal.travelled(), 0.0);
  EXPECT_NEAR(goal.remaining(), 0.2, 1e-12);
}

TEST(VelocityGoal, DegenerateGoalsDoNotRun)
{
  VelocityGoal goal;
  goal.start(0.0, 0.2, 0.0);
  EXPECT_FALSE(goal.active());
  goal.start(0.3, 0.0, 0.0);
  EXPECT_FALSE(goal.active());
  goal.start(std::nan(""), 0.2, 0.0);
  EXPECT_FALSE(goal.active());
}

TEST(VelocityGoal, NegativeDistanceRunsBackwards)
{
  VelocityGoal goal;
  goal.start(-0.3, 0.1, 0.0);
  ASSERT_TRUE(goal.active());
  EXPECT_DOUBLE_EQ(goal.velocity(), -0.1);
  EXPECT_DOUBLE_EQ(goal.speed(), 0.1);
  EXPECT_FALSE(goal.update(1.0, 2.0));
  EXPECT_NEAR(goal.remaining(), -0.2, 1e-12);
  EXPECT_TRUE(goal.update(3.5, 3.0));
  EXPECT_FALSE(goal.active());
}
}  // namespace
}  // namespace sl_obstacle
