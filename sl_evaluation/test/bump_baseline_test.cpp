// The bump-and-turn baseline's state machine (sl_evaluation/bump_baseline.h): the phases, the
// latch handling, the seeded turns, bad settings and bad input; and a closed loop in a walled box.
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <sl_testing/errors.h>

#include "sl_evaluation/bump_baseline.h"

namespace sl_evaluation
{
namespace
{
using State = BumpBaseline::State;

BumpBaselineInput at(double t, double x, double y = 0.0, double yaw = 0.0, bool bumper = false, bool latched = false)
{
  BumpBaselineInput in;
  in.time = t;
  in.x = x;
  in.y = y;
  in.yaw = yaw;
  in.bumper = bumper;
  in.latched = latched;
  return in;
}

/// A robot on the x axis heading +x that integrates the commands at @p dt.
struct Robot
{
  double t = 0.0, x = 0.0, y = 0.0, yaw = 0.0;
  void move(const BumpBaselineCommand& c, double dt)
  {
    x += c.linear * std::cos(yaw) * dt;
    y += c.linear * std::sin(yaw) * dt;
    yaw = std::remainder(yaw + c.angular * dt, 2.0 * M_PI);
    t += dt;
  }
};

/// The turn targets of the first @p n contacts of @p seed.
std::vector<double> turns(unsigned seed, int n)
{
  BumpBaselineConfig c;
  c.seed = seed;
  BumpBaseline b(c);
  std::vector<double> out;
  double t = 0.0;
  for (int i = 0; i < n; ++i)
  {
    b.step(at(t += 0.01, 0.0, 0.0, 0.0, true, true));  // a contact: BACK
    out.push_back(b.turnTarget());
    b.step(at(t += 0.01, -0.06));                       // backed up and released: TURN
    b.step(at(t += 0.01, -0.06, 0.0, b.turnTarget()));  // turned: FORWARD
    EXPECT_EQ(b.state(), State::FORWARD);
  }
  return out;
}
}  // namespace

TEST(BumpBaseline, RefusesBadSettingsNamingThem)
{
  EXPECT_EQ(sl_testing::validationError(BumpBaselineConfig()), "");
  const auto refused = [](const std::string& name, void (*set)(BumpBaselineConfig&))
  { return sl_testing::refusedNaming<BumpBaselineConfig>(name, set); };
  EXPECT_TRUE(refused("forward_speed must be in (0, 0.5]", [](BumpBaselineConfig& c) { c.forward_speed = 0.0; }));
  EXPECT_TRUE(refused("forward_speed", [](BumpBaselineConfig& c) { c.forward_speed = NAN; }));
  EXPECT_TRUE(refused("back_speed", [](BumpBaselineConfig& c) { c.back_speed = 0.6; }));
  EXPECT_TRUE(refused("back_distance", [](BumpBaselineConfig& c) { c.back_distance = -0.05; }));
  EXPECT_TRUE(refused("max_back_distance", [](BumpBaselineConfig& c) { c.max_back_distance = 0.01; }));
  EXPECT_TRUE(refused("turn_speed", [](BumpBaselineConfig& c) { c.turn_speed = 5.0; }));
  EXPECT_TRUE(refused("min_turn", [](BumpBaselineConfig& c) { c.min_turn = 0.0; }));
  EXPECT_TRUE(refused("max_turn", [](BumpBaselineConfig& c) { c.max_turn = 0.4; }));
  EXPECT_TRUE(refused("max_turn", [](BumpBaselineConfig& c) { c.max_turn = 3.2; }));
  EXPECT_TRUE(refused("duration", [](BumpBaselineConfig& c) { c.duration = -1.0; }));
  EXPECT_TRUE(refused("duration", [](BumpBaselineConfig& c) { c.duration = INFINITY; }));
  EXPECT_TRUE(refused("reset_interval", [](BumpBaselineConfig& c) { c.reset_interval = 0.0; }));
  BumpBaselineConfig bad;
  bad.turn_speed = -1.0;
  EXPECT_THROW(BumpBaseline{ bad }, std::invalid_argument);
}

TEST(BumpBaseline, ForwardBackTurnForward)
{
  BumpBaselineConfig c;
  BumpBaseline b(c);
  Robot r;
  const double dt = 0.015;  // the Create's sensor stream, about 66 Hz
  BumpBaselineCommand cmd = b.step(at(r.t, r.x));
  EXPECT_EQ(b.state(), State::FORWARD);
  EXPECT_DOUBLE_EQ(cmd.linear, 0.3);
  EXPECT_DOUBLE_EQ(cmd.angular, 0.0);
  while (r.x < 1.0)  // a wall at 1 m
  {
    r.move(cmd, dt);
    cmd = b.step(at(r.t, r.x));
    ASSERT_EQ(b.state(), State::FORWARD);
  }
  // The bumper closes and the driver latches: back 0.05 m by odometry.
  cmd = b.step(at(r.t, r.x, 0.0, 0.0, true, true));
  EXPECT_EQ(b.state(), State::BACK);
  EXPECT_EQ(b.bumps(), 1);
  EXPECT_DOUBLE_EQ(cmd.linear, -0.1);
  EXPECT_FALSE(cmd.reset_hazard);
  const double contact_x = r.x;
  const double target = b.turnTarget();
  EXPECT_GE(std::abs(target), 0.5);
  EXPECT_LE(std::abs(target), M_PI);
  // Released after 2 cm of backing; the driver's latch clears itself while backing a frame later.
  while (b.state() == State::BACK)
  {
    r.move(cmd, dt);
    const bool pressed = contact_x - r.x < 0.02;
    cmd = b.step(at(r.t, r.x, 0.0, 0.0, pressed, contact_x - r.x < 0.025));
    ASSERT_LT(contact_x - r.x, 0.06);
  }
  EXPECT_NEAR(contact_x - r.x, 0.05, 0.002);
  EXPECT_EQ(b.state(), State::TURN);
  EXPECT_DOUBLE_EQ(cmd.linear, 0.0);
  EXPECT_EQ(cmd.angular > 0.0, target > 0.0);
  double start_yaw = r.yaw;
  double turned = 0.0;
  while (b.state() == State::TURN)
  {
    EXPECT_LE(std::abs(cmd.angular), 1.0 + 1e-12);
    const double before = r.yaw;
    r.move(cmd, dt);
    turned += std::remainder(r.yaw - before, 2.0 * M_PI);
    cmd = b.step(at(r.t, r.x, r.y, r.yaw));
    ASSERT_LT(r.t, 30.0);
  }
  EXPECT_NEAR(turned, target, 0.02);
  EXPECT_NEAR(std::remainder(r.yaw - start_yaw - target, 2.0 * M_PI), 0.0, 0.02);
  EXPECT_EQ(b.state(), State::FORWARD);
  EXPECT_DOUBLE_EQ(cmd.linear, 0.3);
  EXPECT_EQ(b.resets(), 0);
}

TEST(BumpBaseline, SameSeedSameTurnsBothSidesInRange)
{
  const std::vector<double> a = turns(1, 200), b = turns(1, 200), c = turns(2, 200);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  int left = 0;
  for (const double t : a)
  {
    EXPECT_GE(std::abs(t), 0.5);
    EXPECT_LE(std::abs(t), M_PI);
    left += t > 0.0 ? 1 : 0;
  }
  EXPECT_GT(left, 60);  // about half of the 200 to each side
  EXPECT_LT(left, 140);
}

TEST(BumpBaseline, LatchThatOutlivesTheContactIsReset)
{
  BumpBaselineConfig c;
  c.reset_interval = 0.5;
  BumpBaseline b(c);
  b.step(at(0.0, 1.0));
  b.step(at(0.1, 1.0, 0.0, 0.0, true, true));
  ASSERT_EQ(b.state(), State::BACK);
  // Backed the 0.05 m, the bumper released, the latch still set: back on and ask for a reset,
  // at most every reset_interval.
  BumpBaselineCommand cmd = b.step(at(0.6, 0.94, 0.0, 0.0, false, true));
  EXPECT_EQ(b.state(), State::BACK);
  EXPECT_DOUBLE_EQ(cmd.linear, -0.1);
  EXPECT_TRUE(cmd.reset_hazard);
  cmd = b.step(at(0.7, 0.93, 0.0, 0.0, false, true));
  EXPECT_FALSE(cmd.reset_hazard);
  cmd = b.step(at(1.2, 0.92, 0.0, 0.0, false, true));
  EXPECT_TRUE(cmd.reset_hazard);
  EXPECT_EQ(b.resets(), 2);
  // Still pressed: no reset (the driver refuses it), backing on up to max_back_distance, then stop.
  cmd = b.step(at(1.3, 0.91, 0.0, 0.0, true, true));
  EXPECT_FALSE(cmd.reset_hazard);
  EXPECT_DOUBLE_EQ(cmd.linear, -0.1);
  cmd = b.step(at(3.0, 0.69, 0.0, 0.0, true, true));
  EXPECT_EQ(b.state(), State::BACK);
  EXPECT_DOUBLE_EQ(cmd.linear, 0.0);
  EXPECT_DOUBLE_EQ(cmd.angular, 0.0);
  // Cleared: turn.
  cmd = b.step(at(3.1, 0.69));
  EXPECT_EQ(b.state(), State::TURN);
  EXPECT_NE(cmd.angular, 0.0);
  EXPECT_EQ(b.bumps(), 1);
}

TEST(BumpBaseline, LatchOrBumpWhileTurning)
{
  BumpBaseline b{ BumpBaselineConfig() };
  b.step(at(0.0, 0.0));
  b.step(at(0.1, 0.0, 0.0, 0.0, true, true));
  b.step(at(0.7, -0.06));
  ASSERT_EQ(b.state(), State::TURN);
  // The latch set again while turning: stand still, ask for a reset.
  BumpBaselineCommand cmd = b.step(at(0.8, -0.06, 0.0, 0.0, false, true));
  EXPECT_EQ(b.state(), State::TURN);
  EXPECT_DOUBLE_EQ(cmd.angular, 0.0);
  EXPECT_TRUE(cmd.reset_hazard);
  // The bumper pressed while turning: a new contact, back up again.
  cmd = b.step(at(0.9, -0.06, 0.0, 0.0, true, true));
  EXPECT_EQ(b.state(), State::BACK);
  EXPECT_EQ(b.bumps(), 2);
  EXPECT_DOUBLE_EQ(cmd.linear, -0.1);
}

TEST(BumpBaseline, NonFiniteInputStopsWithoutChangingState)
{
  BumpBaseline b{ BumpBaselineConfig() };
  b.step(at(0.0, 0.0));
  BumpBaselineCommand cmd = b.step(at(0.1, NAN));
  EXPECT_DOUBLE_EQ(cmd.linear, 0.0);
  EXPECT_DOUBLE_EQ(cmd.angular, 0.0);
  cmd = b.step(at(0.2, 0.0, 0.0, INFINITY, true, true));
  EXPECT_DOUBLE_EQ(cmd.linear, 0.0);
  EXPECT_EQ(b.state(), State::FORWARD);
  EXPECT_EQ(b.bumps(), 0);
  cmd = b.step(at(NAN, 0.0));
  EXPECT_DOUBLE_EQ(cmd.linear, 0.0);
  cmd = b.step(at(0.3, 0.03));
  EXPECT_DOUBLE_EQ(cmd.linear, 0.3);
  EXPECT_NEAR(b.travelled(), 0.03, 1e-12);
}

TEST(BumpBaseline, StopsAfterDuration)
{
  BumpBaselineConfig c;
  c.duration = 10.0;
  BumpBaseline b(c);
  EXPECT_DOUBLE_EQ(b.step(at(100.0, 0.0)).linear, 0.3);
  EXPECT_DOUBLE_EQ(b.step(at(109.9, 0.0)).linear, 0.3);
  const BumpBaselineCommand cmd = b.step(at(110.0, 0.0, 0.0, 0.0, true, true));
  EXPECT_EQ(b.state(), State::DONE);
  EXPECT_DOUBLE_EQ(cmd.linear, 0.0);
  EXPECT_DOUBLE_EQ(cmd.angular, 0.0);
  EXPECT_FALSE(cmd.reset_hazard);
}

// Closed loop: a 2 x 1.5 m box, the bumper closes when the robot's 0.1675 m disc reaches a wall in
// front (the driver's latch set with it, cleared while backing released): in 10 simulated minutes
// the robot stays inside, bumps many times, and visits all four quarters of the box.
TEST(BumpBaseline, ClosedLoopInABox)
{
  BumpBaselineConfig c;
  c.seed = 3;
  BumpBaseline b(c);
  Robot r;
  r.x = 1.0;
  r.y = 0.75;
  const double radius = 0.1675, dt = 0.015;
  bool latched = false;
  bool quarter[4] = { false, false, false, false };
  BumpBaselineCommand cmd;
  for (int i = 0; i < static_cast<int>(600.0 / dt); ++i)
  {
    // The bumper: a wall within the radius, ahead of the robot (within 90 degrees of the heading).
    const double hx = std::cos(r.yaw), hy = std::sin(r.yaw);
    const bool pressed = (r.x - radius <= 0.0 && hx < 0.0) || (r.x + radius >= 2.0 && hx > 0.0) ||
                         (r.y - radius <= 0.0 && hy < 0.0) || (r.y + radius >= 1.5 && hy > 0.0);
    // The driver's latch: set by a contact, cleared by backing with the bumper free or by a reset.
    if (pressed)
      latched = true;
    else if (cmd.linear < 0.0 || cmd.reset_hazard)
      latched = false;
    cmd = b.step(at(r.t, r.x, r.y, r.yaw, pressed, latched));
    // The driver: forward motion stalls against a wall (the Create's wheels stall on contact).
    BumpBaselineCommand applied = cmd;
    if (pressed && applied.linear > 0.0)
      applied.linear = 0.0;
    if (latched && applied.linear >= 0.0)
      applied = BumpBaselineCommand();
    r.move(applied, dt);
    ASSERT_GT(r.x, radius - 0.02);
    ASSERT_LT(r.x, 2.0 - radius + 0.02);
    ASSERT_GT(r.y, radius - 0.02);
    ASSERT_LT(r.y, 1.5 - radius + 0.02);
    quarter[(r.x > 1.0 ? 1 : 0) + (r.y > 0.75 ? 2 : 0)] = true;
  }
  EXPECT_GT(b.bumps(), 70);  // measured 119 bumps, 84.0 m
  EXPECT_TRUE(quarter[0] && quarter[1] && quarter[2] && quarter[3]);
  EXPECT_GT(b.travelled(), 50.0);
  std::printf("bump baseline in a 2 x 1.5 m box, 600 s: %d bumps, %.1f m travelled, %d resets\n", b.bumps(),
              b.travelled(), b.resets());
}

}  // namespace sl_evaluation
