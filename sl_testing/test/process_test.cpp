// sl_testing's helpers on plain shell commands (no ROS master needed).
#include <gtest/gtest.h>

#include <string>

#include <sl_testing/child_process.h>
#include <sl_testing/process.h>

namespace sl_testing
{
namespace
{
TEST(Run, ReturnsTheExitStatusAndBothStreams)
{
  std::string out;
  EXPECT_EQ(run("sh -c 'echo out; echo err >&2; exit 3'", out), 3);
  EXPECT_NE(out.find("out\n"), std::string::npos) << out;
  EXPECT_NE(out.find("err\n"), std::string::npos) << out;
}

TEST(Run, RunShellKeepsStandardErrorApart)
{
  std::string out;
  EXPECT_EQ(runShell("echo out; echo err >&2", out), 0);
  EXPECT_EQ(out, "out\n");
}

TEST(Run, AKilledCommandIsMinusOne)
{
  std::string out;
  EXPECT_EQ(run("kill -9 $$", out), -1);
}

TEST(Child, ReadsOutputWhileRunningAndReportsTheExitStatusAfterSigint)
{
  Child child({ "sh", "-c", "echo ready; trap 'exit 5' INT; while true; do sleep 0.05; done" });
  ASSERT_TRUE(child.readUntil({ "ready" }, 30.0)) << child.output();
  EXPECT_TRUE(child.running());
  EXPECT_EQ(child.interrupt(), 5) << child.output();
  EXPECT_FALSE(child.running());
}

TEST(Child, ReadUntilGivesUpWhenTheChildEnds)
{
  Child child({ "sh", "-c", "echo something else" });
  EXPECT_FALSE(child.readUntil({ "never printed" }, 30.0));
  EXPECT_EQ(child.output(), "something else\n");
}
}  // namespace
}  // namespace sl_testing
