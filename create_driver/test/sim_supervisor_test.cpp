// SimSupervisor: the create_sim node's pty reopening, publication schedule, refusal and watchdog
// reports, and garbage bytes, on a synthetic clock.
#include <gtest/gtest.h>
#include <sl_testing/errors.h>

#include <string>

#include "create_driver/sim_supervisor.h"

using create_driver::Bytes;
namespace cd = create_driver;

namespace
{
std::string refusal(const cd::SimNodeConfig& c)
{
  return sl_testing::invalidArgumentOf([&] { c.validate(); });
}

bool startsWith(const std::string& s, const std::string& prefix)
{
  return s.rfind(prefix, 0) == 0;
}

void send(cd::SimSupervisor& s, const Bytes& bytes)
{
  s.robot().receive(bytes.data(), bytes.size());
}
}  // namespace

TEST(SimSupervisor, ConfigValidationNamesTheParameter)
{
  EXPECT_EQ(refusal(cd::SimNodeConfig()), "");
  cd::SimNodeConfig c;
  c.robot.wheel_base = 0.0;
  EXPECT_TRUE(startsWith(refusal(c), "wheel_base")) << refusal(c);
  c = cd::SimNodeConfig();
  c.robot.slip_right = 1.0;
  EXPECT_TRUE(startsWith(refusal(c), "slip_right")) << refusal(c);
  c = cd::SimNodeConfig();
  c.robot.command_watchdog = 0.01;
  EXPECT_TRUE(startsWith(refusal(c), "command_watchdog")) << refusal(c);
  c = cd::SimNodeConfig();
  c.rate = 20.0;
  EXPECT_TRUE(startsWith(refusal(c), "rate")) << refusal(c);
  c = cd::SimNodeConfig();
  c.publish_rate = c.rate + 1.0;
  EXPECT_TRUE(startsWith(refusal(c), "publish_rate")) << refusal(c);
  c = cd::SimNodeConfig();
  c.garbage_bytes = 5000;
  EXPECT_TRUE(startsWith(refusal(c), "garbage_bytes")) << refusal(c);
  c = cd::SimNodeConfig();
  c.reopen_delay = -1.0;
  EXPECT_TRUE(startsWith(refusal(c), "reopen_delay")) << refusal(c);
}

TEST(SimSupervisor, ReopenClosesAtOnceAndOpensAfterTheDelay)
{
  cd::SimSupervisor s(cd::SimNodeConfig(), 10.0);
  EXPECT_FALSE(s.ptyActions(10.0).close);
  s.requestReopen();
  cd::PtyActions a = s.ptyActions(10.0);
  EXPECT_TRUE(a.close);
  EXPECT_FALSE(a.open);
  a = s.ptyActions(10.4);
  EXPECT_FALSE(a.close || a.open);
  a = s.ptyActions(10.5);
  EXPECT_FALSE(a.close);
  EXPECT_TRUE(a.open);
  a = s.ptyActions(11.0);
  EXPECT_FALSE(a.close || a.open) << "once";

  cd::SimNodeConfig c;
  c.reopen_delay = 0.0;
  cd::SimSupervisor at_once(c, 10.0);
  at_once.requestReopen();
  a = at_once.ptyActions(10.0);
  EXPECT_TRUE(a.close && a.open);
}

TEST(SimSupervisor, PoseAtThePublishRateAndStatusAtItsPeriod)
{
  cd::SimSupervisor s(cd::SimNodeConfig(), 10.0);
  EXPECT_DOUBLE_EQ(s.nextStep(), 10.005);
  Bytes out;
  int poses = 0;
  int statuses = 0;
  for (int i = 0; i < 200; ++i)  // 1 s at 200 Hz
  {
    const cd::SimStepActions a = s.step(10.0 + 0.005 * i, out);
    poses += a.publish_pose ? 1 : 0;
    statuses += a.publish_status ? 1 : 0;
  }
  EXPECT_EQ(poses, 50);
  EXPECT_EQ(statuses, 10);
  EXPECT_DOUBLE_EQ(s.nextStep(), 10.0 + 0.005 * 199 + 0.005);
}

TEST(SimSupervisor, NoBurstOfPosesAfterAStall)
{
  cd::SimSupervisor s(cd::SimNodeConfig(), 10.0);
  Bytes out;
  s.step(10.0, out);
  int poses = 0;
  for (int i = 0; i < 4; ++i)  // the host stalled for 1 s, then 4 steps
    poses += s.step(11.0 + 0.005 * i, out).publish_pose ? 1 : 0;
  EXPECT_LE(poses, 3);
  EXPECT_GE(poses, 1);
}

TEST(SimSupervisor, RefusalsReportedWithANewReasonOnce)
{
  cd::SimSupervisor s(cd::SimNodeConfig(), 10.0);
  Bytes out;
  send(s, { cd::oi::START });
  EXPECT_FALSE(s.step(10.01, out).refusal);
  // Two copies of group 6 (52 bytes each) do not fit the 15 ms slot of a Create at 57600 baud.
  const Bytes too_large = { cd::oi::STREAM, 2, 6, 6 };
  send(s, too_large);
  cd::SimStepActions a = s.step(10.02, out);
  EXPECT_TRUE(a.refusal);
  EXPECT_TRUE(a.new_refusal_reason);
  EXPECT_EQ(s.robot().refusedCommands(), 1u);
  EXPECT_FALSE(s.step(10.03, out).refusal) << "reported once";
  send(s, too_large);
  a = s.step(10.04, out);
  EXPECT_TRUE(a.refusal);
  EXPECT_FALSE(a.new_refusal_reason) << "the same reason (logged throttled)";
}

TEST(SimSupervisor, HardwareStopReportedOnce)
{
  cd::SimNodeConfig c;
  c.robot.command_watchdog = 0.1;
  cd::SimSupervisor s(c, 10.0);
  Bytes out;
  send(s, { cd::oi::START, cd::oi::SAFE, cd::oi::DRIVE_DIRECT, 0, 100, 0, 100 });
  int stops = 0;
  for (int i = 1; i <= 60; ++i)  // 0.3 s without a byte
    stops += s.step(10.0 + 0.005 * i, out).watchdog_stop ? 1 : 0;
  EXPECT_EQ(stops, 1);
  EXPECT_EQ(s.robot().commandedLeft(), 0.0);
}

TEST(SimSupervisor, GarbageFollowsTheSeedAndStartsWithAHeader)
{
  cd::SimNodeConfig c;
  c.garbage_bytes = 40;
  cd::SimSupervisor a(c, 10.0);
  cd::SimSupervisor b(c, 10.0);
  c.robot.seed = 7;
  cd::SimSupervisor other(c, 10.0);
  Bytes out_a, out_b, out_other;
  EXPECT_EQ(a.injectGarbage(), 40u);
  b.injectGarbage();
  other.injectGarbage();
  a.step(10.01, out_a);  // not streaming: the bytes leave at once
  b.step(10.01, out_b);
  other.step(10.01, out_other);
  ASSERT_EQ(out_a.size(), 40u);
  EXPECT_EQ(out_a[0], cd::oi::STREAM_HEADER);
  EXPECT_EQ(out_a, out_b);
  EXPECT_NE(out_a, out_other);
}
