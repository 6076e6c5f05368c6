#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <future>
#include <memory>
#include <string>
#include <thread>

#include "create_driver/sim_robot.h"
#include "create_driver/stream_parser.h"

using create_driver::Bytes;
namespace cd = create_driver;

namespace
{
void send(cd::SimRobot& r, const Bytes& b)
{
  r.receive(b.data(), b.size());
}

Bytes output(cd::SimRobot& r)
{
  Bytes out;
  r.takeOutput(out);
  return out;
}

// Advances in 10 ms steps (step() caps a single call at 1 s, like a stalled host).
void advance(cd::SimRobot& r, double seconds)
{
  const int n = static_cast<int>(seconds / 0.01);
  for (int i = 0; i < n; ++i)
    r.step(0.01);
  r.step(seconds - n * 0.01);
}

cd::SimRobot safeRobot(cd::SimParams p = cd::SimParams())
{
  cd::SimRobot r(p);
  send(r, { 128, 131 });
  return r;
}

// Runs @p f on a thread of its own: false if it has not returned within @p seconds, so a hang
// fails the test instead of stalling the run (the stuck thread is left behind).
bool returnsWithin(double seconds, const std::function<void()>& f)
{
  auto done = std::make_shared<std::promise<void>>();
  std::future<void> finished = done->get_future();
  std::thread(
      [f, done]()
      {
        f();
        done->set_value();
      })
      .detach();
  return finished.wait_for(std::chrono::duration<double>(seconds)) == std::future_status::ready;
}

// True if every stream frame in @p out is [19][n][n bytes][checksum] with a zero byte sum and n
// == @p payload.
bool framesValid(const Bytes& out, size_t payload)
{
  const size_t frame = payload + 3;
  if (out.empty() || out.size() % frame != 0)
    return false;
  for (size_t f = 0; f < out.size(); f += frame)
  {
    uint8_t sum = 0;
    for (size_t i = 0; i < frame; ++i)
      sum = static_cast<uint8_t>(sum + out[f + i]);
    if (out[f] != 19 || out[f + 1] != payload || sum != 0)
      return false;
  }
  return true;
}
}  // namespace

TEST(SimRobot, OffModeIgnoresEverythingButStart)
{
  cd::SimRobot r;
  EXPECT_EQ(r.mode(), cd::OiMode::OFF);
  send(r, cd::encodeDriveDirect(200, 200));
  send(r, { 142, 7 });
  r.step(0.1);
  EXPECT_EQ(r.commandedLeft(), 0.0);
  EXPECT_TRUE(output(r).empty());
  send(r, { 128 });
  EXPECT_EQ(r.mode(), cd::OiMode::PASSIVE);
}

TEST(SimRobot, PassiveIgnoresActuators)
{
  cd::SimRobot r;
  send(r, { 128 });
  send(r, cd::encodeDrive(200, cd::oi::RADIUS_STRAIGHT));
  r.step(0.5);
  EXPECT_EQ(r.commandedLeft(), 0.0);
  EXPECT_NEAR(r.truePose().x, 0.0, 1e-12);
  // Sensors still work in Passive.
  send(r, { 142, 35 });
  EXPECT_EQ(output(r), (Bytes{ 1 }));
}

TEST(SimRobot, ModeTransitions)
{
  cd::SimRobot r;
  send(r, { 128, 131 });
  EXPECT_EQ(r.mode(), cd::OiMode::SAFE);
  send(r, { 132 });
  EXPECT_EQ(r.mode(), cd::OiMode::FULL);
  send(r, cd::encodeDriveDirect(100, 100));
  EXPECT_DOUBLE_EQ(r.commandedLeft(), 0.1);
  send(r, { 128 });  // Start returns to Passive and stops the wheels
  EXPECT_EQ(r.mode(), cd::OiMode::PASSIVE);
  EXPECT_DOUBLE_EQ(r.commandedLeft(), 0.0);
  send(r, { 130 });  // Control = Safe
  EXPECT_EQ(r.mode(), cd::OiMode::SAFE);
}

TEST(SimRobot, DriveStraightAndDirect)
{
  cd::SimRobot r = safeRobot();
  send(r, cd::encodeDrive(200, cd::oi::RADIUS_STRAIGHT));
  r.step(1.0);
  EXPECT_NEAR(r.truePose().x, 0.2, 1e-9);
  EXPECT_NEAR(r.truePose().y, 0.0, 1e-9);
  send(r, cd::encodeDriveDirect(-100, -100));  // right, left
  r.step(1.0);
  EXPECT_NEAR(r.truePose().x, 0.1, 1e-9);
}

TEST(SimRobot, KeepsDrivingWhenTheHostFallsSilent)
{
  // Like the real Create: the last Drive runs until the host says otherwise.
  cd::SimRobot r = safeRobot();
  send(r, cd::encodeDrive(300, cd::oi::RADIUS_STRAIGHT));
  advance(r, 5.0);
  EXPECT_NEAR(r.truePose().x, 1.5, 1e-6);
  EXPECT_EQ(r.watchdogStops(), 0u);
}

TEST(SimRobot, CommandWatchdogStopsASilentHostsRobot)
{
  cd::SimParams p;
  p.command_watchdog = 0.4;
  cd::SimRobot r = safeRobot(p);
  send(r, cd::encodeDrive(300, cd::oi::RADIUS_STRAIGHT));
  for (int i = 0; i < 10; ++i)
  {
    advance(r, 0.2);
    send(r, cd::encodeDrive(300, cd::oi::RADIUS_STRAIGHT));  // a host that refreshes every 0.2 s
  }
  EXPECT_NEAR(r.truePose().x, 0.6, 1e-6);
  EXPECT_EQ(r.watchdogStops(), 0u);
  advance(r, 2.0);  // silent
  EXPECT_NEAR(r.truePose().x, 0.6 + 0.3 * 0.4, 0.3 * 0.011);
  EXPECT_EQ(r.commandedLeft(), 0.0);
  EXPECT_EQ(r.mode(), cd::OiMode::SAFE);
  EXPECT_EQ(r.watchdogStops(), 1u);
  send(r, cd::encodeDrive(100, cd::oi::RADIUS_STRAIGHT));  // the host is back
  advance(r, 0.1);
  EXPECT_NEAR(r.commandedLeft(), 0.1, 1e-9);
}

TEST(SimRobot, SpecialRadiiTurnInPlace)
{
  cd::SimParams p;
  cd::SimRobot r = safeRobot(p);
  // Counter-clockwise in place at 129 mm/s per wheel: w = 2*0.129/0.258 = 1 rad/s.
  send(r, cd::encodeDrive(129, cd::oi::RADIUS_TURN_CCW));
  r.step(0.5);
  EXPECT_NEAR(r.truePose().yaw, 0.5, 1e-9);
  EXPECT_NEAR(r.truePose().x, 0.0, 1e-12);
  send(r, cd::encodeDrive(129, cd::oi::RADIUS_TURN_CW));
  r.step(0.5);
  EXPECT_NEAR(r.truePose().yaw, 0.0, 1e-9);
}

TEST(SimRobot, ArcFollowsRadius)
{
  cd::SimRobot r = safeRobot();
  // Radius 500 mm, 200 mm/s: quarter circle (pi/2 * 0.5 m) takes 3.927 s, ends at (0.5, 0.5).
  send(r, cd::encodeDrive(200, 500));
  advance(r, M_PI / 2 * 0.5 / 0.2);
  EXPECT_NEAR(r.truePose().x, 0.5, 1e-3);
  EXPECT_NEAR(r.truePose().y, 0.5, 1e-3);
  EXPECT_NEAR(r.truePose().yaw, M_PI / 2, 1e-3);
}

TEST(SimRobot, SensorsAndQueryListReplies)
{
  cd::SimRobot r = safeRobot();
  r.setContact(cd::bumps::BUMP_LEFT);
  send(r, { 142, 7 });
  EXPECT_EQ(output(r), (Bytes{ 0x02 }));
  send(r, { 142, 0 });
  EXPECT_EQ(output(r).size(), 26u);
  send(r, { 142, 6 });
  EXPECT_EQ(output(r).size(), 52u);
  send(r, { 142, 43 });  // not a Create 1 packet: no reply
  EXPECT_TRUE(output(r).empty());
  send(r, { 149, 2, 7, 35 });
  EXPECT_EQ(output(r), (Bytes{ 0x02, 2 }));
}

TEST(SimRobot, DistanceAndAngleResetOnReadKeepingRemainder)
{
  cd::SimRobot r = safeRobot();
  send(r, cd::encodeDriveDirect(150, 150));
  r.step(0.01);  // 1.5 mm
  cd::ReplyParser p;
  ASSERT_TRUE(p.expect({ 19 }));
  send(r, { 142, 19 });
  Bytes out = output(r);
  p.feed(out.data(), out.size());
  ASSERT_TRUE(p.complete());
  EXPECT_EQ(p.state().distanceMm(), 1);
  r.step(0.01);  // another 1.5 mm: 2 reported (0.5 remainder + 1.5)
  p.expect({ 19 });
  send(r, { 142, 19 });
  out = output(r);
  p.feed(out.data(), out.size());
  EXPECT_EQ(p.state().distanceMm(), 2);
  // Reading again without motion: 0.
  p.expect({ 19 });
  send(r, { 142, 19 });
  out = output(r);
  p.feed(out.data(), out.size());
  EXPECT_EQ(p.state().distanceMm(), 0);
}

TEST(SimRobot, StreamFramesEvery15msWithValidChecksum)
{
  cd::SimRobot r = safeRobot();
  send(r, cd::encodeStream({ 7, 19, 20, 35 }));
  r.step(0.15);  // 10 frames
  const Bytes out = output(r);
  // Each frame: [19][n=10][7][b][19][hi][lo][20][hi][lo][35][mode][checksum] => 13 bytes.
  ASSERT_EQ(out.size(), 130u);
  for (size_t f = 0; f < 10; ++f)
  {
    const uint8_t* fr = out.data() + f * 13;
    EXPECT_EQ(fr[0], 19);
    EXPECT_EQ(fr[1], 10);
    uint8_t sum = 0;
    for (int i = 0; i < 13; ++i)
      sum = static_cast<uint8_t>(sum + fr[i]);
    EXPECT_EQ(sum, 0) << "frame " << f;
    EXPECT_EQ(fr[2], 7);
    EXPECT_EQ(fr[4], 19);
    EXPECT_EQ(fr[7], 20);
    EXPECT_EQ(fr[10], 35);
    EXPECT_EQ(fr[11], 2);  // Safe
  }
  cd::StreamParser p;
  p.setExpectedIds({ 7, 19, 20, 35 });
  EXPECT_EQ(p.feed(out.data(), out.size()), 10u);
  EXPECT_EQ(p.state().oiMode(), 2);
}

TEST(SimRobot, PauseAndResumeStream)
{
  cd::SimRobot r = safeRobot();
  send(r, cd::encodeStream({ 7 }));
  r.step(0.03);
  EXPECT_FALSE(output(r).empty());
  send(r, { 150, 0 });
  r.step(0.1);
  EXPECT_TRUE(output(r).empty());
  EXPECT_FALSE(r.streaming());
  send(r, { 150, 1 });
  r.step(0.031);
  EXPECT_EQ(output(r).size(), 2 * 5u);  // [19][2][7][x][ck]
}

TEST(SimRobot, SafeModeFallsBackToPassiveOnWheelDrop)
{
  cd::SimRobot r = safeRobot();
  send(r, cd::encodeDriveDirect(100, 100));
  r.step(0.1);
  r.setWheelDrops(cd::bumps::WHEEL_DROP_LEFT);
  r.step(0.01);
  EXPECT_EQ(r.mode(), cd::OiMode::PASSIVE);
  EXPECT_EQ(r.commandedLeft(), 0.0);
}

TEST(SimRobot, SafeModeCliffOnlyWhenMovingForward)
{
  cd::SimRobot r = safeRobot();
  r.setCliffs(0x02);
  r.step(0.1);  // standing still on a cliff: stays Safe
  EXPECT_EQ(r.mode(), cd::OiMode::SAFE);
  send(r, cd::encodeDrive(-100, cd::oi::RADIUS_STRAIGHT));  // backing away is allowed
  r.step(0.1);
  EXPECT_EQ(r.mode(), cd::OiMode::SAFE);
  EXPECT_LT(r.truePose().x, 0.0);
  send(r, cd::encodeDrive(100, cd::oi::RADIUS_STRAIGHT));  // forward over the edge: no
  r.step(0.01);
  EXPECT_EQ(r.mode(), cd::OiMode::PASSIVE);
  EXPECT_EQ(r.commandedLeft(), 0.0);
}

TEST(SimRobot, FullModeHasNoSafety)
{
  cd::SimRobot r = safeRobot();
  send(r, { 132 });
  r.setCliffs(0x0F);
  r.setWheelDrops(cd::bumps::WHEEL_DROP_CASTER);
  send(r, cd::encodeDriveDirect(100, 100));
  r.step(0.1);
  EXPECT_EQ(r.mode(), cd::OiMode::FULL);
  EXPECT_NEAR(r.truePose().x, 0.01, 1e-9);
}

TEST(SimRobot, WaitDistanceBlocksInputUntilCovered)
{
  cd::SimRobot r = safeRobot();
  Bytes script = cd::encodeDrive(100, cd::oi::RADIUS_STRAIGHT);
  const Bytes wait = cd::encodeWaitDistance(50);
  script.insert(script.end(), wait.begin(), wait.end());
  const Bytes stop = cd::encodeDrive(0, cd::oi::RADIUS_STRAIGHT);
  script.insert(script.end(), stop.begin(), stop.end());
  send(r, script);
  EXPECT_TRUE(r.waiting());
  // Input arriving during the wait is not executed (a Sensors request gets no reply yet).
  send(r, { 142, 35 });
  r.step(0.2);  // 20 mm
  EXPECT_TRUE(r.waiting());
  EXPECT_TRUE(output(r).empty());
  r.step(0.4);
  EXPECT_FALSE(r.waiting());
  EXPECT_NEAR(r.truePose().x, 0.05, 0.0015);
  EXPECT_EQ(r.commandedLeft(), 0.0);
  EXPECT_EQ(output(r), (Bytes{ 2 }));  // the queued request ran after the wait
}

TEST(SimRobot, WaitDistanceHangsWhenHeldBack)
{
  cd::SimRobot r = safeRobot();
  r.setContact(cd::bumps::BUMP_RIGHT);  // pressed against an obstacle
  Bytes script = cd::encodeDrive(100, cd::oi::RADIUS_STRAIGHT);
  const Bytes wait = cd::encodeWaitDistance(50);
  script.insert(script.end(), wait.begin(), wait.end());
  send(r, script);
  send(r, cd::encodeDrive(0, cd::oi::RADIUS_STRAIGHT));  // the host tries to stop it
  advance(r, 5.0);
  EXPECT_TRUE(r.waiting());
  EXPECT_DOUBLE_EQ(r.commandedLeft(), 0.1) << "a stop got through Wait Distance";
  r.setContact(0);
  r.step(1.0);
  EXPECT_FALSE(r.waiting());
  EXPECT_EQ(r.commandedLeft(), 0.0);
}

TEST(SimRobot, WaitDistanceNegative)
{
  cd::SimRobot r = safeRobot();
  Bytes script = cd::encodeDrive(-100, cd::oi::RADIUS_STRAIGHT);
  const Bytes wait = cd::encodeWaitDistance(-30);
  script.insert(script.end(), wait.begin(), wait.end());
  send(r, script);
  r.step(0.5);
  EXPECT_FALSE(r.waiting());
}

TEST(SimRobot, StreamContinuesDuringWait)
{
  cd::SimRobot r = safeRobot();
  send(r, cd::encodeStream({ 19 }));
  Bytes script = cd::encodeDrive(100, cd::oi::RADIUS_STRAIGHT);
  const Bytes wait = cd::encodeWaitDistance(100);
  script.insert(script.end(), wait.begin(), wait.end());
  send(r, script);
  r.step(0.3);
  cd::StreamParser p;
  const Bytes out = output(r);
  EXPECT_EQ(p.feed(out.data(), out.size()), 20u);
}

TEST(SimRobot, ScriptsPlayAndShow)
{
  cd::SimRobot r = safeRobot();
  Bytes script = { 152, 5 };
  const Bytes drive = cd::encodeDriveDirect(50, 50);
  script.insert(script.end(), drive.begin(), drive.end());
  send(r, script);
  EXPECT_EQ(r.commandedLeft(), 0.0);
  send(r, { 154 });
  Bytes expected = { 5 };
  expected.insert(expected.end(), drive.begin(), drive.end());
  EXPECT_EQ(output(r), expected);
  send(r, { 153 });
  EXPECT_DOUBLE_EQ(r.commandedLeft(), 0.05);
}

TEST(SimRobot, ContactSetsBumpBitsAndBlocksForwardMotion)
{
  cd::SimRobot r = safeRobot();
  send(r, cd::encodeDriveDirect(200, 200));
  r.step(0.5);
  const double x = r.truePose().x;
  r.setContact(cd::bumps::BUMP_LEFT | cd::bumps::BUMP_RIGHT);
  r.step(0.5);
  EXPECT_NEAR(r.truePose().x, x, 1e-12);
  EXPECT_EQ(r.sensorState().get(7), 0x03);
  send(r, cd::encodeDriveDirect(-200, -200));  // backing away works
  r.step(0.5);
  EXPECT_LT(r.truePose().x, x);
}

TEST(SimRobot, Create2EncodersWrap)
{
  cd::SimParams p;
  p.model = cd::Model::CREATE_2;
  cd::SimRobot r = safeRobot(p);
  EXPECT_DOUBLE_EQ(r.wheelBase(), 0.235);
  send(r, cd::encodeDriveDirect(-500, -500));
  r.step(1.0);  // -0.5 m = -1124.6 counts from 0: wraps below zero
  const int left = r.sensorState().get(43);
  EXPECT_GT(left, 60000);
  const double counts = 0.5 / (M_PI * 0.072 / 508.8);
  EXPECT_NEAR(65536 - left, counts, 1.5);
  // Create 2 specific commands are known, Create 1 scripts are not.
  send(r, { 173 });
  EXPECT_EQ(r.mode(), cd::OiMode::OFF);
}

TEST(SimRobot, SlipAndNoiseAreDeterministicForASeed)
{
  cd::SimParams p;
  p.slip_left = 0.05;
  p.slip_noise = 0.02;
  p.odom_noise = 0.05;
  p.seed = 7;
  auto run = [&](uint32_t seed)
  {
    p.seed = seed;
    cd::SimRobot r = safeRobot(p);
    send(r, cd::encodeDriveDirect(200, 200));
    send(r, cd::encodeStream({ 19 }));
    advance(r, 2.0);
    return r.truePose();
  };
  const cd::Pose2D a = run(7);
  const cd::Pose2D b = run(7);
  const cd::Pose2D c = run(8);
  EXPECT_DOUBLE_EQ(a.x, b.x);
  EXPECT_DOUBLE_EQ(a.yaw, b.yaw);
  EXPECT_NE(a.x, c.x);
  // Left wheel slips more: the robot veers left and covers less than 0.4 m.
  EXPECT_LT(a.x, 0.4);
  EXPECT_GT(a.yaw, 0.0);
}

TEST(SimRobot, InjectIntoNextFrameCorruptsIt)
{
  cd::SimRobot r = safeRobot();
  send(r, cd::encodeStream({ 7, 19, 20 }));
  r.injectIntoNextFrame({ 0xAA, 0xBB, 0xCC });
  r.step(0.045);  // 3 frames, the first one corrupted
  const Bytes out = output(r);
  cd::StreamParser p;
  p.setExpectedIds({ 7, 19, 20 });
  EXPECT_EQ(p.feed(out.data(), out.size()), 2u);
  EXPECT_GE(p.counters().corrupt_frames, 1u);
}

TEST(SimRobot, UnknownBytesAreIgnored)
{
  cd::SimRobot r = safeRobot();
  send(r, { 0x00, 0x05, 200, 131 });
  EXPECT_EQ(r.ignoredBytes(), 3u);
  EXPECT_EQ(r.mode(), cd::OiMode::SAFE);
}

TEST(SimRobot, SplitCommandsAcrossReceives)
{
  cd::SimRobot r = safeRobot();
  const Bytes d = cd::encodeDriveDirect(120, 80);
  for (uint8_t b : d)
  {
    EXPECT_EQ(r.commandedLeft(), 0.0);
    r.receive(&b, 1);
  }
  EXPECT_DOUBLE_EQ(r.commandedRight(), 0.12);
  EXPECT_DOUBLE_EQ(r.commandedLeft(), 0.08);
}

// 128 131 152 1 153 153 from a client hung create_sim: the script [153] re-queued itself for ever.
TEST(SimRobot, ScriptThatPlaysItselfDoesNotHang)
{
  auto r = std::make_shared<cd::SimRobot>();
  const Bytes input = { 128, 131, 152, 1, 153, 153 };
  ASSERT_TRUE(returnsWithin(5.0, [r, input]() { r->receive(input.data(), input.size()); }))
      << "receive() did not return";
  EXPECT_EQ(r->mode(), cd::OiMode::SAFE);
  EXPECT_FALSE(r->waiting());
  EXPECT_EQ(r->inputQueued(), 0u);
  // Start, Safe, Script, Play Script, and the script's own Play Script, which is refused.
  EXPECT_EQ(r->commands(), 5u);
  EXPECT_EQ(r->refusedCommands(), 1u);
  EXPECT_EQ(r->lastRefusal().rfind("Play Script inside a script ignored", 0), 0u) << r->lastRefusal();
  // The script is kept as defined and the robot still answers.
  send(*r, { 154, 142, 35 });
  EXPECT_EQ(output(*r), (Bytes{ 1, 153, 2 }));
}

// A script of Play Scripts played by many Play Scripts grew the input queue without bound.
TEST(SimRobot, ManyPlayScriptsStayBounded)
{
  auto r = std::make_shared<cd::SimRobot>();
  Bytes input = { 128, 131, 152, 100 };
  input.insert(input.end(), 100, 153);   // the longest script: 100 Play Scripts
  input.insert(input.end(), 1000, 153);  // played 1000 times
  ASSERT_TRUE(returnsWithin(5.0, [r, input]() { r->receive(input.data(), input.size()); }))
      << "receive() did not return";
  EXPECT_EQ(r->inputQueued(), 0u);
  EXPECT_EQ(r->refusedCommands(), 100u * 1000u);
  EXPECT_EQ(r->commands(), 3u + 1000u + 100u * 1000u);
  send(*r, { 142, 35 });
  EXPECT_EQ(output(*r), (Bytes{ 2 }));
}

// A script ending in Play Script (the OI manual's way to repeat one) plays once per Play Script
// from the host: its own Play Script is refused after its Wait, a queued host one plays it again.
TEST(SimRobot, ScriptPlaysOncePerPlayScript)
{
  cd::SimRobot r = safeRobot();
  Bytes script = cd::encodeDrive(100, cd::oi::RADIUS_STRAIGHT);
  script.insert(script.end(), { 155, 5 });  // Wait Time 0.5 s
  const Bytes stop = cd::encodeDrive(0, cd::oi::RADIUS_STRAIGHT);
  script.insert(script.end(), stop.begin(), stop.end());
  script.push_back(153);
  Bytes define = { 152, static_cast<uint8_t>(script.size()) };
  define.insert(define.end(), script.begin(), script.end());
  send(r, define);
  send(r, { 153 });
  EXPECT_TRUE(r.waiting());
  EXPECT_DOUBLE_EQ(r.commandedLeft(), 0.1);
  advance(r, 1.0);
  EXPECT_FALSE(r.waiting());
  EXPECT_EQ(r.commandedLeft(), 0.0);
  EXPECT_EQ(r.refusedCommands(), 1u);
  EXPECT_NEAR(r.truePose().x, 0.05, 0.001);
  advance(r, 1.0);
  EXPECT_NEAR(r.truePose().x, 0.05, 0.001) << "the script repeated by itself";
  // A Play Script sent during the script's Wait is held, then plays the script once more.
  send(r, { 153 });
  send(r, { 153 });
  advance(r, 0.7);
  EXPECT_TRUE(r.waiting());
  EXPECT_DOUBLE_EQ(r.commandedLeft(), 0.1);
  advance(r, 0.5);
  EXPECT_FALSE(r.waiting());
  EXPECT_EQ(r.commandedLeft(), 0.0);
  EXPECT_EQ(r.refusedCommands(), 3u);
  EXPECT_EQ(r.inputQueued(), 0u);
  EXPECT_NEAR(r.truePose().x, 0.15, 0.002);
}

// Four times packet group 100 on a Create 2 is 324 payload bytes: the length byte was clamped to
// 255 and every frame was corrupt. The request is refused and the previous stream kept.
TEST(SimRobot, StreamTooLargeForItsFrameIsRefused)
{
  cd::SimParams p;
  p.model = cd::Model::CREATE_2;
  cd::SimRobot r = safeRobot(p);
  EXPECT_EQ(r.streamPayloadLimit(), 169u);  // 172 bytes in 15 ms at 115200 baud, less 3
  send(r, { 148, 4, 100, 100, 100, 100 });
  EXPECT_EQ(r.refusedCommands(), 1u);
  EXPECT_EQ(r.lastRefusal().rfind("Stream refused: 324 payload bytes, more than the 169", 0), 0u) << r.lastRefusal();
  EXPECT_FALSE(r.streaming());
  r.step(0.1);
  EXPECT_TRUE(output(r).empty());

  // With a stream running, the previous stream continues unchanged.
  send(r, cd::encodeStream({ 7 }));
  r.step(0.03);
  output(r);
  send(r, { 148, 4, 100, 100, 100, 100 });
  EXPECT_EQ(r.refusedCommands(), 2u);
  EXPECT_TRUE(r.streaming());
  r.step(0.15);
  const Bytes out = output(r);
  EXPECT_GE(out.size(), 9u * 5u);
  EXPECT_TRUE(framesValid(out, 2));

  // Under 255 but over the frame's 15 ms: refused as well; what fits is streamed intact.
  send(r, { 148, 3, 100, 100, 100 });
  EXPECT_EQ(r.refusedCommands(), 3u);
  send(r, { 148, 2, 100, 100 });
  EXPECT_EQ(r.refusedCommands(), 3u);
  r.step(0.03);
  EXPECT_TRUE(framesValid(output(r), 2 * 81));
}

TEST(SimRobot, StreamLimitFollowsTheBaudRate)
{
  cd::SimRobot r = safeRobot();
  EXPECT_EQ(r.streamPayloadLimit(), 83u);  // Create at 57600 baud: 86 bytes in 15 ms, less 3
  send(r, { 148, 2, 6, 6 });               // 2 x (1 + 52) = 106 bytes
  EXPECT_EQ(r.refusedCommands(), 1u);
  send(r, { 129, 11 });  // Baud 115200
  EXPECT_EQ(r.streamPayloadLimit(), 169u);
  send(r, { 148, 2, 6, 6 });
  EXPECT_EQ(r.refusedCommands(), 1u);
  r.step(0.015);
  EXPECT_TRUE(framesValid(output(r), 106));
  r.powerCycle();  // back to the default rate
  EXPECT_EQ(r.streamPayloadLimit(), 83u);
}
