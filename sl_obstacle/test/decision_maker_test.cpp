// Tests of DecisionMaker: drive, slow, stop, stale, coverage, pre-emption, turning, reasons; and the
// whole core (VolumeChecker + DecisionMaker) on synthetic clouds.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <sl_testing/errors.h>
#include "sl_obstacle/decision_maker.h"
#include "sl_obstacle/settings.h"
#include "sl_obstacle/volume_checker.h"
#include "synthetic_clouds.h"

namespace sl_obstacle
{
namespace
{
using sl_testing::validationError;

const double kInf = std::numeric_limits<double>::infinity();

FrameSummary frame(double stamp, double nearest, double free, double coverage = 1.0, double left = -1.0,
                   double right = -1.0)
{
  FrameSummary f;
  f.stamp = stamp;
  f.nearest_obstacle = nearest;
  f.free_distance = free;
  f.coverage = coverage;
  f.left_free = left < 0.0 ? free : left;
  f.right_free = right < 0.0 ? free : right;
  return f;
}

MotionState idle()
{
  return MotionState();
}

MotionState running(double remaining, double speed)
{
  MotionState m;
  m.goal_active = true;
  m.goal_remaining = remaining;
  m.goal_speed = speed;
  return m;
}

DecisionParams noTurning()
{
  DecisionParams p;
  p.max_turns = 0;
  return p;
}

/// Turn steps of @p turn_angle at 1 rad/s (one step takes turn_angle s), at most @p max_turns, no settle time.
DecisionParams quickTurns(double turn_angle, int max_turns = DecisionParams().max_turns)
{
  DecisionParams p;
  p.settle_time = 0.0;
  p.turn_angle = turn_angle;
  p.turn_speed = 1.0;
  p.max_turns = max_turns;
  return p;
}

/// Steps @p dm at t = 1 s on a frame with the way free: the command it gives (DRIVE).
Command driveOnAFreeWay(DecisionMaker& dm)
{
  dm.onFrame(frame(1.0, kInf, 0.8));
  return dm.step(1.0, idle()).command;
}

bool contains(const std::string& text, const char* part)
{
  return text.find(part) != std::string::npos;
}

/// Whether @p d is a turn whose text says @p why, for EXPECT_TRUE.
::testing::AssertionResult turnsSaying(const Decision& d, const char* why)
{
  if (d.command == Command::TURN && contains(d.text, why))
    return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "expected a turn saying \"" << why << "\", got " << toString(d.command)
                                       << ": \"" << d.text << "\"";
}

TEST(DecisionMaker, NoDataIsStale)
{
  DecisionMaker dm;
  const Decision& d = dm.step(0.0, idle());
  EXPECT_EQ(d.state, State::STALE);
  EXPECT_EQ(d.reason, Reason::NO_DATA);
  EXPECT_EQ(d.command, Command::STOP);
  EXPECT_FALSE(d.text.empty());
}

TEST(DecisionMaker, OpenSpaceDrivesAtFullSpeed)
{
  DecisionMaker dm;
  dm.onFrame(frame(1.0, kInf, 0.8));
  const Decision& d = dm.step(1.05, idle());
  EXPECT_EQ(d.state, State::DRIVING);
  EXPECT_EQ(d.reason, Reason::PATH_FREE);
  EXPECT_EQ(d.command, Command::DRIVE);
  EXPECT_NEAR(d.distance, 0.8 - dm.params().safety_margin, 1e-9);
  EXPECT_NEAR(d.speed, dm.params().max_speed, 1e-9);
  EXPECT_FALSE(d.blocked);
  EXPECT_TRUE(contains(d.text, "free")) << d.text;
}

TEST(DecisionMaker, SpeedFallsAsTheFreeDistanceShrinks)
{
  DecisionMaker dm;
  double previous_speed = kInf;
  double previous_distance = kInf;
  for (double free = 0.8; free > 0.2; free -= 0.05)
  {
    dm.onFrame(frame(1.0, free, free));
    const Decision& d = dm.step(1.0, idle());
    ASSERT_EQ(d.command, Command::DRIVE) << "free " << free;
    EXPECT_LE(d.speed, previous_speed + 1e-12) << "free " << free;
    EXPECT_LT(d.distance, previous_distance) << "free " << free;
    EXPECT_GE(d.speed, dm.params().min_speed - 1e-12);
    EXPECT_NEAR(d.distance, free - dm.params().safety_margin, 1e-9);
    if (free < dm.params().slow_distance - 1e-9)
    {
      EXPECT_EQ(d.state, State::SLOWING) << "free " << free;
      EXPECT_EQ(d.reason, Reason::SHORT_FREE_DISTANCE);
      EXPECT_LT(d.speed, dm.params().max_speed);
    }
    previous_speed = d.speed;
    previous_distance = d.distance;
  }
}

TEST(DecisionMaker, StopsWhenTheFreeDistanceIsBelowTheMargin)
{
  DecisionMaker dm(noTurning());
  dm.onFrame(frame(1.0, 0.12, 0.12));
  const Decision& d = dm.step(1.0, idle());
  EXPECT_EQ(d.state, State::BLOCKED);
  EXPECT_EQ(d.reason, Reason::OBSTACLE);
  EXPECT_EQ(d.command, Command::STOP);
  EXPECT_TRUE(d.blocked);
  EXPECT_TRUE(contains(d.text, "obstacle at 0.120 m")) << d.text;
  // Staying blocked while nothing changes.
  dm.onFrame(frame(1.1, 0.12, 0.12));
  EXPECT_EQ(dm.step(1.1, idle()).state, State::BLOCKED);
}

TEST(DecisionMaker, UnknownSpaceAheadBlocksLikeAnObstacle)
{
  DecisionMaker dm(noTurning());
  dm.onFrame(frame(1.0, kInf, 0.1, 0.9));
  const Decision& d = dm.step(1.0, idle());
  EXPECT_EQ(d.state, State::BLOCKED);
  EXPECT_EQ(d.reason, Reason::UNKNOWN_AHEAD);
  EXPECT_EQ(d.command, Command::STOP);
  EXPECT_TRUE(contains(d.text, "unknown") || contains(d.text, "measured")) << d.text;
}

TEST(DecisionMaker, StaleDataStops)
{
  DecisionMaker dm;
  dm.onFrame(frame(1.0, kInf, 0.8));
  EXPECT_EQ(dm.step(1.1, idle()).command, Command::DRIVE);
  // The goal runs; then clouds stop coming.
  EXPECT_EQ(dm.step(1.4, running(0.5, 0.2)).command, Command::NONE);
  const Decision& d = dm.step(1.0 + dm.params().stale_timeout + 0.01, running(0.45, 0.2));
  EXPECT_EQ(d.state, State::STALE);
  EXPECT_EQ(d.reason, Reason::STALE_DATA);
  EXPECT_EQ(d.command, Command::STOP);
  EXPECT_TRUE(contains(d.text, "no cloud for")) << d.text;
  // Fresh data: drives again (the frame is newer than the stop).
  dm.onFrame(frame(2.0, kInf, 0.8));
  EXPECT_EQ(dm.step(2.05, idle()).command, Command::DRIVE);
}

TEST(DecisionMaker, LowCoverageStopsAndPartialCoverageSlows)
{
  DecisionMaker dm;
  dm.onFrame(frame(1.0, kInf, 0.8, 0.2));
  const Decision& low = dm.step(1.0, idle());
  EXPECT_EQ(low.state, State::STOPPED);
  EXPECT_EQ(low.reason, Reason::LOW_COVERAGE);
  EXPECT_EQ(low.command, Command::STOP);
  EXPECT_TRUE(contains(low.text, "coverage 0.20")) << low.text;

  dm.onFrame(frame(1.1, kInf, 0.8, 0.55));
  const Decision& partial = dm.step(1.1, idle());
  EXPECT_EQ(partial.state, State::SLOWING);
  EXPECT_EQ(partial.reason, Reason::PARTIAL_COVERAGE);
  EXPECT_EQ(partial.command, Command::DRIVE);
  const double partial_speed = partial.speed;
  EXPECT_LT(partial_speed, dm.params().max_speed);
  EXPECT_GT(partial_speed, dm.params().min_speed);

  dm.onFrame(frame(1.2, kInf, 0.8, 0.9));
  EXPECT_GT(dm.step(1.2, idle()).speed, partial_speed);
}

TEST(DecisionMaker, NearerObstaclePreemptsTheRunningGoal)
{
  DecisionMaker dm;
  ASSERT_EQ(driveOnAFreeWay(dm), Command::DRIVE);
  // An obstacle appears at 0.4 m while 0.6 m remain.
  dm.onFrame(frame(1.2, 0.4, 0.4));
  const Decision& d = dm.step(1.2, running(0.6, 0.2));
  EXPECT_EQ(d.command, Command::DRIVE);
  EXPECT_EQ(d.reason, Reason::NEARER_OBSTACLE);
  EXPECT_NEAR(d.distance, 0.4 - dm.params().safety_margin, 1e-9);
  EXPECT_LT(d.speed, 0.2);
  // Consistent afterwards: the new goal continues.
  dm.onFrame(frame(1.3, 0.38, 0.38));
  const Decision& next = dm.step(1.3, running(0.23, d.speed));
  EXPECT_EQ(next.command, Command::NONE);
  EXPECT_EQ(next.reason, Reason::GOAL_RUNNING);
}

TEST(DecisionMaker, ObstacleWithinTheMarginStopsTheRunningGoal)
{
  DecisionMaker dm;
  dm.onFrame(frame(1.0, 0.16, 0.16));
  const Decision& d = dm.step(1.0, running(0.3, 0.2));
  EXPECT_EQ(d.command, Command::STOP);
  EXPECT_EQ(d.state, State::BLOCKED);
  EXPECT_EQ(d.reason, Reason::OBSTACLE);
  EXPECT_TRUE(d.blocked);
}

TEST(DecisionMaker, RunningGoalSlowsDownNearItsEnd)
{
  DecisionMaker dm;
  dm.onFrame(frame(1.0, 0.8, 0.8));
  const Decision& first = dm.step(1.0, idle());
  ASSERT_EQ(first.command, Command::DRIVE);
  double speed = first.speed;
  double remaining = first.distance;
  int resends = 0;
  double t = 1.0;
  // The obstacle comes closer as the robot drives; the goal is re-sent at lower speeds.
  while (remaining > 0.08)
  {
    t += 0.1;
    remaining -= 0.02;
    dm.onFrame(frame(t, remaining + dm.params().safety_margin, remaining + dm.params().safety_margin));
    const Decision& d = dm.step(t, running(remaining, speed));
    ASSERT_NE(d.command, Command::STOP) << "remaining " << remaining;
    if (d.command == Command::DRIVE)
    {
      EXPECT_EQ(d.reason, Reason::SHORT_FREE_DISTANCE);
      EXPECT_LT(d.speed, speed);
      EXPECT_NEAR(d.distance, remaining, 1e-9);
      speed = d.speed;
      ++resends;
    }
  }
  EXPECT_GE(resends, 3);
  EXPECT_LT(speed, 0.1);
}

TEST(DecisionMaker, RunningGoalIsExtendedWhenMoreSpaceIsFree)
{
  DecisionMaker dm;
  dm.onFrame(frame(1.0, kInf, 0.8));
  const Decision& d = dm.step(1.0, running(0.1, 0.2));
  EXPECT_EQ(d.command, Command::DRIVE);
  EXPECT_EQ(d.reason, Reason::EXTENDING);
  EXPECT_NEAR(d.distance, 0.65, 1e-9);
}

TEST(DecisionMaker, BlockedTurnsTowardTheFreerSideAndLooksAgain)
{
  DecisionParams p;
  p.settle_time = 0.3;
  p.turn_angle = 0.5;
  p.turn_speed = 0.5;  // 1 s per turn step
  p.stale_timeout = 50.0;
  DecisionMaker dm(p);
  // Blocked; the left is freer.
  dm.onFrame(frame(1.0, 0.1, 0.1, 1.0, 0.5, 0.1));
  const Decision& settle = dm.step(1.0, idle());
  EXPECT_EQ(settle.state, State::BLOCKED);
  EXPECT_EQ(settle.command, Command::STOP);
  EXPECT_TRUE(settle.blocked);
  EXPECT_TRUE(contains(settle.text, "left")) << settle.text;
  EXPECT_EQ(dm.step(1.2, idle()).command, Command::STOP);  // still settling
  const Decision& turn = dm.step(1.35, idle());
  EXPECT_EQ(turn.state, State::TURNING);
  EXPECT_EQ(turn.reason, Reason::TURNING);
  EXPECT_EQ(turn.command, Command::TURN);
  EXPECT_NEAR(turn.angular_speed, p.turn_speed, 1e-12);
  EXPECT_EQ(dm.step(2.0, idle()).command, Command::TURN);  // turn takes turn_angle / turn_speed
  // Turn over: stopped, waiting for a cloud taken after settle_time.
  const Decision& look = dm.step(2.4, idle());
  EXPECT_EQ(look.state, State::BLOCKED);
  EXPECT_EQ(look.reason, Reason::LOOKING);
  EXPECT_EQ(look.command, Command::STOP);
  dm.onFrame(frame(2.5, kInf, 0.8));  // taken too early (during settling)
  EXPECT_EQ(dm.step(2.5, idle()).reason, Reason::LOOKING);
  dm.onFrame(frame(2.8, kInf, 0.8));  // fresh and free
  const Decision& go = dm.step(2.8, idle());
  EXPECT_EQ(go.command, Command::DRIVE);
  EXPECT_EQ(go.state, State::DRIVING);
  EXPECT_FALSE(go.blocked);
}

TEST(DecisionMaker, TurnsRightWhenTheRightIsFreer)
{
  DecisionParams p;
  p.settle_time = 0.0;
  DecisionMaker dm(p);
  dm.onFrame(frame(1.0, 0.1, 0.1, 1.0, 0.1, 0.6));
  const Decision& d = dm.step(1.0, idle());
  EXPECT_EQ(d.command, Command::TURN);
  EXPECT_LT(d.angular_speed, 0.0);
  EXPECT_TRUE(contains(d.text, "right")) << d.text;
}

TEST(DecisionMaker, GivesUpAfterMaxTurnsAndDrivesWhenTheWayClears)
{
  DecisionParams p = quickTurns(0.1, 2);
  p.stale_timeout = 50.0;
  DecisionMaker dm(p);
  double t = 0.0;
  dm.onFrame(frame(t, 0.1, 0.1));
  int turn_steps = 0;
  Decision d;
  for (int i = 0; i < 100; ++i)
  {
    t += 0.05;
    dm.onFrame(frame(t, 0.1, 0.1));  // still blocked in every direction
    d = dm.step(t, idle());
    if (d.command == Command::TURN)
    {
      ++turn_steps;
    }
    if (d.reason == Reason::NO_FREE_DIRECTION)
    {
      break;
    }
  }
  EXPECT_EQ(d.state, State::STOPPED);
  EXPECT_EQ(d.reason, Reason::NO_FREE_DIRECTION);
  EXPECT_TRUE(d.blocked);
  EXPECT_TRUE(contains(d.text, "2 turns")) << d.text;
  EXPECT_GE(turn_steps, 2);
  // Stays stopped (does not turn forever) ...
  t += 1.0;
  dm.onFrame(frame(t, 0.1, 0.1));
  EXPECT_EQ(dm.step(t, idle()).command, Command::STOP);
  // ... until a cloud shows free space.
  t += 0.1;
  dm.onFrame(frame(t, kInf, 0.8));
  EXPECT_EQ(dm.step(t, idle()).command, Command::DRIVE);
}

TEST(DecisionMaker, LowCoverageAfterATurnMeansTurnAgain)
{
  DecisionMaker dm(quickTurns(0.1));
  dm.onFrame(frame(1.0, 0.1, 0.1));
  EXPECT_EQ(dm.step(1.0, idle()).command, Command::TURN);
  EXPECT_EQ(dm.step(1.2, idle()).reason, Reason::LOOKING);
  dm.onFrame(frame(1.25, kInf, 0.8, 0.05));  // nothing seen
  EXPECT_TRUE(turnsSaying(dm.step(1.25, idle()), "coverage"));
}

TEST(DecisionMaker, WaitsForAFreshFrameAfterAGoalEnds)
{
  DecisionMaker dm;
  ASSERT_EQ(driveOnAFreeWay(dm), Command::DRIVE);
  dm.onFrame(frame(4.0, kInf, 0.8));
  EXPECT_EQ(dm.step(4.05, running(0.6, 0.2)).command, Command::NONE);
  dm.onGoalEnded(GoalEnd::REACHED, 4.1, "reached");
  const Decision& wait = dm.step(4.1, idle());
  EXPECT_EQ(wait.state, State::STOPPED);
  EXPECT_EQ(wait.reason, Reason::WAITING_FOR_FRAME);
  EXPECT_EQ(wait.command, Command::STOP);
  dm.onFrame(frame(4.15, kInf, 0.8));
  EXPECT_EQ(dm.step(4.15, idle()).command, Command::DRIVE);
}

TEST(DecisionMaker, ObstacleInAnOldFrameBlocksAtOnce)
{
  DecisionMaker dm(noTurning());
  dm.onFrame(frame(1.0, 0.12, 0.12));
  dm.onGoalEnded(GoalEnd::REACHED, 1.05, "reached");
  EXPECT_EQ(dm.step(1.05, idle()).state, State::BLOCKED);
}

TEST(DecisionMaker, DriverHazardStartsATurn)
{
  DecisionParams p;
  p.settle_time = 0.0;
  DecisionMaker dm(p);
  ASSERT_EQ(driveOnAFreeWay(dm), Command::DRIVE);
  dm.onGoalEnded(GoalEnd::HAZARD, 1.1, "bumper");
  EXPECT_TRUE(turnsSaying(dm.step(1.1, idle()), "bumper"));
}

TEST(DecisionMaker, DriverFailureIsReported)
{
  DecisionMaker dm;
  ASSERT_EQ(driveOnAFreeWay(dm), Command::DRIVE);
  dm.onGoalEnded(GoalEnd::FAILED, 1.1, "timeout");
  const Decision& d = dm.step(1.1, idle());
  EXPECT_EQ(d.state, State::STOPPED);
  EXPECT_EQ(d.reason, Reason::DRIVER_FAILED);
  EXPECT_TRUE(contains(d.text, "timeout")) << d.text;
  // No immediate retry even with a fresh cloud; a while later it tries again.
  dm.onFrame(frame(1.2, kInf, 0.8));
  EXPECT_EQ(dm.step(1.2, idle()).reason, Reason::DRIVER_FAILED);
  double t = 1.2;
  Command command = Command::STOP;
  while (command != Command::DRIVE && t < 10.0)
  {
    t += 0.1;
    dm.onFrame(frame(t, kInf, 0.8));
    command = dm.step(t, idle()).command;
  }
  EXPECT_EQ(command, Command::DRIVE);
}

TEST(DecisionMaker, DisabledAndDriverNotReadyStop)
{
  DecisionParams p;
  p.enabled = false;
  DecisionMaker dm(p);
  dm.onFrame(frame(1.0, kInf, 0.8));
  const Decision& off = dm.step(1.0, idle());
  EXPECT_EQ(off.state, State::STOPPED);
  EXPECT_EQ(off.reason, Reason::DISABLED);
  EXPECT_EQ(off.command, Command::STOP);

  dm.setParams(DecisionParams());
  MotionState no_driver;
  no_driver.driver_ready = false;
  const Decision& d = dm.step(1.0, no_driver);
  EXPECT_EQ(d.state, State::STOPPED);
  EXPECT_EQ(d.reason, Reason::DRIVER_UNAVAILABLE);
  EXPECT_EQ(d.command, Command::STOP);
  EXPECT_EQ(dm.step(1.0, idle()).command, Command::DRIVE);
}

TEST(DecisionMaker, EveryDecisionHasAReasonText)
{
  DecisionMaker dm(quickTurns(0.05, 1));
  double t = 0.0;
  const double frees[] = { 0.8, 0.4, 0.1, 0.8, 0.05, 0.05, 0.05, 0.8 };
  for (int i = 0; i < 200; ++i)
  {
    t += 0.05;
    if (i % 4 != 3)  // sometimes no cloud
    {
      const double free = frees[(i / 20) % 8];
      dm.onFrame(frame(t, free, free, (i % 7) / 6.0));
    }
    const Decision& d = dm.step(t, i % 5 == 0 ? running(0.3, 0.1) : idle());
    EXPECT_FALSE(d.text.empty()) << "step " << i;
    EXPECT_STRNE(toString(d.state), "?");
    EXPECT_STRNE(toString(d.reason), "?");
    EXPECT_STRNE(toString(d.command), "?");
  }
}

TEST(DecisionMaker, BadParametersAreRejectedNamingTheParameter)
{
  struct BadCase
  {
    const char* name;
    void (*spoil)(DecisionParams&);
  };
  const BadCase cases[] = {
    { "safety_margin", [](DecisionParams& p) { p.safety_margin = -0.1; } },
    { "min_goal_distance", [](DecisionParams& p) { p.min_goal_distance = 0.0; } },
    { "slow_distance", [](DecisionParams& p) { p.slow_distance = 0.1; } },  // not above the margin
    { "max_speed", [](DecisionParams& p) { p.max_speed = 2.0; } },
    { "min_speed", [](DecisionParams& p) { p.min_speed = 0.3; } },  // above max_speed
    { "min_coverage", [](DecisionParams& p) { p.min_coverage = 1.5; } },
    { "full_speed_coverage", [](DecisionParams& p) { p.full_speed_coverage = 0.1; } },  // below min
    { "stale_timeout", [](DecisionParams& p) { p.stale_timeout = std::nan(""); } },
    { "stale_timeout", [](DecisionParams& p) { p.stale_timeout = 0.0; } },
    { "turn_speed", [](DecisionParams& p) { p.turn_speed = -0.5; } },
    { "turn_angle", [](DecisionParams& p) { p.turn_angle = 0.0; } },
    { "max_turns", [](DecisionParams& p) { p.max_turns = -1; } },
    { "settle_time", [](DecisionParams& p) { p.settle_time = -1.0; } },
    { "creep_speed", [](DecisionParams& p) { p.creep_speed = 0.06; } },  // the creep is 0.05 m/s at most
    { "creep_speed", [](DecisionParams& p) { p.creep_speed = -0.01; } },
  };
  for (const BadCase& c : cases)
  {
    DecisionParams p;
    c.spoil(p);
    EXPECT_THROW(p.validate(), std::invalid_argument) << c.name;
    EXPECT_EQ(validationError(p).rfind(c.name, 0), 0U) << c.name << ": " << validationError(p);
    EXPECT_THROW(DecisionMaker dm(p), std::invalid_argument) << c.name;
  }
  EXPECT_NO_THROW(DecisionParams().validate());
  DecisionMaker dm;
  DecisionParams bad;
  bad.max_speed = 0.0;
  EXPECT_THROW(dm.setParams(bad), std::invalid_argument);
  EXPECT_DOUBLE_EQ(dm.params().max_speed, DecisionParams().max_speed);  // unchanged
}

TEST(Settings, RelationsBetweenVolumeAndDecisions)
{
  Settings s;
  EXPECT_NO_THROW(s.validate());
  s.decision.safety_margin = 0.78;
  s.decision.slow_distance = 0.79;
  EXPECT_THROW(s.validate(), std::invalid_argument);
  EXPECT_EQ(validationError(s).rfind("safety_margin", 0), 0U) << validationError(s);
  s = Settings();
  s.decision.slow_distance = 0.9;
  EXPECT_EQ(validationError(s).rfind("slow_distance", 0), 0U) << validationError(s);
  s = Settings();
  s.checker.volume.width = -1.0;
  EXPECT_EQ(validationError(s).rfind("width", 0), 0U) << validationError(s);
}

// --- The whole core on synthetic clouds -------------------------------------------------------

/// Runs the checker on @p frames clouds of the same scene, 0.1 s apart, then decides with a fresh
/// decision maker (turning disabled) on the last one.
Decision run(VolumeChecker& checker, const std::vector<Point>& cloud, int frames = 3)
{
  DecisionMaker dm(noTurning());
  double t = 100.0;
  for (int i = 0; i < frames; ++i)
  {
    t += 0.1;
    dm.onFrame(summarize(checker.analyze(cloud), t));
  }
  return dm.step(t + 0.01, idle());
}

TEST(Core, SyntheticScenes)
{
  using test::operator+;
  using test::render;
  using test::Scene;
  VolumeChecker checker;

  const Decision open = run(checker, render(Scene().wall(0.95)));
  EXPECT_EQ(open.state, State::DRIVING) << open.text;
  EXPECT_NEAR(open.distance, 0.8 - 0.15, 1e-6);

  const Decision wall = run(checker, render(Scene().wall(0.5)));
  EXPECT_EQ(wall.command, Command::DRIVE) << wall.text;
  EXPECT_NEAR(wall.distance, 0.5 - 0.15, 1e-3);
  EXPECT_EQ(wall.state, State::SLOWING);

  const Decision close = run(checker, render(Scene().wall(0.12)));
  EXPECT_EQ(close.state, State::BLOCKED) << close.text;
  EXPECT_EQ(close.reason, Reason::OBSTACLE);

  const Decision leg = run(checker, render(Scene().wall(0.95).leg(0.17, 0.0)));
  EXPECT_EQ(leg.state, State::BLOCKED) << leg.text;

  const Decision floor = run(checker, render(Scene().wall(0.95)) + test::patch(0.3, -0.15, 0.15, 0.0, 0.01));
  EXPECT_EQ(floor.state, State::DRIVING) << floor.text;

  std::vector<Point> strays = render(Scene().wall(0.95));
  strays.push_back(makePoint(0.1F, 0.0F, 0.1F));
  strays.push_back(makePoint(0.2F, 0.1F, 0.05F));
  const Decision stray = run(checker, strays);
  EXPECT_EQ(stray.state, State::DRIVING) << stray.text;

  const Decision empty = run(checker, std::vector<Point>());
  EXPECT_EQ(empty.state, State::STOPPED) << empty.text;
  EXPECT_EQ(empty.reason, Reason::LOW_COVERAGE);

  const Decision half = run(checker, test::patch(0.95, -0.05, 0.1655, 0.0, 0.173));
  EXPECT_NE(half.command, Command::DRIVE) << half.text;  // right side unmeasured
}
}  // namespace
}  // namespace sl_obstacle
