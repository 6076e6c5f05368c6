#include <gtest/gtest.h>

#include "create_driver/link_supervisor.h"

namespace cd = create_driver;
using Action = cd::LinkSupervisor::Action;

namespace
{
cd::LinkParams params()
{
  cd::LinkParams p;
  p.initial_backoff = 0.25;
  p.max_backoff = 2.0;
  p.start_timeout = 3.0;
  p.frame_timeout = 1.0;
  return p;
}
}  // namespace

TEST(LinkSupervisor, ConnectsAndRuns)
{
  cd::LinkSupervisor s(params());
  EXPECT_EQ(s.state(), cd::LinkState::DISCONNECTED);
  EXPECT_EQ(s.tick(0.0), Action::OPEN);
  EXPECT_EQ(s.state(), cd::LinkState::CONNECTING);
  s.openSucceeded(0.0);
  EXPECT_EQ(s.state(), cd::LinkState::STARTING);
  EXPECT_EQ(s.tick(1.0), Action::NONE);
  s.validFrame(1.0);
  EXPECT_EQ(s.state(), cd::LinkState::RUNNING);
  EXPECT_EQ(s.connects(), 1u);
  EXPECT_EQ(s.tick(1.5), Action::NONE);
}

TEST(LinkSupervisor, ExponentialBackoffIsCapped)
{
  cd::LinkSupervisor s(params());
  double t = 0.0;
  std::vector<double> delays;
  for (int i = 0; i < 6; ++i)
  {
    ASSERT_EQ(s.tick(t), Action::OPEN);
    s.openFailed(t, "no such device");
    delays.push_back(s.nextAttempt() - t);
    // No new attempt before the delay has passed.
    EXPECT_EQ(s.tick(t + delays.back() * 0.5), Action::NONE);
    t = s.nextAttempt();
  }
  EXPECT_DOUBLE_EQ(delays[0], 0.25);
  EXPECT_DOUBLE_EQ(delays[1], 0.5);
  EXPECT_DOUBLE_EQ(delays[2], 1.0);
  EXPECT_DOUBLE_EQ(delays[3], 2.0);
  EXPECT_DOUBLE_EQ(delays[4], 2.0);
  EXPECT_EQ(s.failedAttempts(), 6u);
  EXPECT_EQ(s.lastError(), "no such device");
}

TEST(LinkSupervisor, SilenceWhileRunningReconnects)
{
  cd::LinkSupervisor s(params());
  s.tick(0.0);
  s.openSucceeded(0.0);
  s.validFrame(0.1);
  EXPECT_EQ(s.tick(1.0), Action::NONE);
  EXPECT_EQ(s.tick(1.2), Action::CLOSE);  // 1.1 s without a frame
  EXPECT_EQ(s.state(), cd::LinkState::DISCONNECTED);
  EXPECT_EQ(s.disconnects(), 1u);
  // Backoff was reset by RUNNING: retry after the initial delay.
  EXPECT_DOUBLE_EQ(s.nextAttempt(), 1.2 + 0.25);
  EXPECT_EQ(s.tick(1.3), Action::NONE);
  EXPECT_EQ(s.tick(1.5), Action::OPEN);
}

TEST(LinkSupervisor, NoFrameAfterStartReconnects)
{
  cd::LinkSupervisor s(params());
  s.tick(0.0);
  s.openSucceeded(0.0);
  EXPECT_EQ(s.tick(2.9), Action::NONE);
  EXPECT_EQ(s.tick(3.1), Action::CLOSE);
  EXPECT_EQ(s.connects(), 0u);
}

TEST(LinkSupervisor, IoErrorReconnectsAndCountsConnects)
{
  cd::LinkSupervisor s(params());
  s.tick(0.0);
  s.openSucceeded(0.0);
  s.validFrame(0.05);
  s.ioError(0.5, "EOF");
  EXPECT_EQ(s.state(), cd::LinkState::DISCONNECTED);
  EXPECT_EQ(s.lastError(), "EOF");
  EXPECT_EQ(s.tick(0.8), Action::OPEN);
  s.openSucceeded(0.8);
  s.validFrame(0.85);
  EXPECT_EQ(s.connects(), 2u);
  EXPECT_EQ(s.disconnects(), 1u);
  // The first error drops the link; a second one while disconnected is ignored.
  s.ioError(0.9, "late");
  s.ioError(0.9, "late");
  EXPECT_EQ(s.disconnects(), 2u);
}

TEST(LinkSupervisor, StateNames)
{
  EXPECT_STREQ(cd::linkStateName(cd::LinkState::RUNNING), "running");
  EXPECT_STREQ(cd::linkStateName(cd::LinkState::DISCONNECTED), "disconnected");
}
