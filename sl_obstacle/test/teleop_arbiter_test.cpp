// TeleopArbiter: outside commands take over from autonomy and hand back after the hold time.
#include <gtest/gtest.h>

#include "sl_obstacle/teleop_arbiter.h"

using sl_obstacle::TeleopArbiter;

TEST(TeleopArbiter, ACommandTakesOverAndAutonomyResumesAfterTheHold)
{
  TeleopArbiter t;
  bool ended = true;
  EXPECT_FALSE(t.update(0.0, ended)) << "autonomy until a command comes";
  EXPECT_FALSE(ended);
  EXPECT_TRUE(t.onCommand(1.0, 2.0)) << "the first command takes over";
  EXPECT_TRUE(t.update(1.0, ended));
  EXPECT_FALSE(ended);
  EXPECT_FALSE(t.onCommand(2.0, 2.0)) << "a takeover is already running";
  EXPECT_TRUE(t.update(3.9, ended)) << "2 s after the last command (2.0) it still holds";
  EXPECT_FALSE(t.update(4.0, ended));
  EXPECT_TRUE(ended) << "the takeover ended: reported once";
  EXPECT_FALSE(t.update(4.1, ended));
  EXPECT_FALSE(ended);
  EXPECT_TRUE(t.onCommand(5.0, 2.0)) << "a new command takes over again";
}

TEST(TeleopArbiter, InFilterModeOutsideCommandsAlwaysCommand)
{
  TeleopArbiter t(true);
  bool ended = true;
  EXPECT_TRUE(t.update(0.0, ended)) << "no autonomy at all";
  EXPECT_FALSE(ended);
  EXPECT_FALSE(t.onCommand(1.0, 2.0)) << "nothing to take over from";
  EXPECT_TRUE(t.update(100.0, ended)) << "no hold time either";
  EXPECT_FALSE(ended);
  EXPECT_TRUE(t.active());
}
