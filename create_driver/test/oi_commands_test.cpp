// Golden-byte tests: every expected byte string below was worked out by hand from the Open
// Interface spec (opcode, then 16-bit two's complement values, high byte first).
#include <gtest/gtest.h>

#include "create_driver/oi_commands.h"

using create_driver::Bytes;
namespace cd = create_driver;

TEST(OiCommands, ModeCommands)
{
  Bytes b;
  cd::appendStart(b);
  cd::appendSafe(b);
  cd::appendFull(b);
  cd::appendPassive(b);
  cd::appendStop(b);
  EXPECT_EQ(b, (Bytes{ 128, 131, 132, 128, 173 }));
  Bytes m;
  cd::appendMode(m, cd::OiMode::PASSIVE);
  cd::appendMode(m, cd::OiMode::SAFE);
  cd::appendMode(m, cd::OiMode::FULL);
  cd::appendMode(m, cd::OiMode::OFF);
  EXPECT_EQ(m, (Bytes{ 128, 131, 132, 173 }));
}

TEST(OiCommands, DriveExampleFromIssue)
{
  // 200 mm/s = 0x00C8, 500 mm = 0x01F4.
  EXPECT_EQ(cd::encodeDrive(200, 500), (Bytes{ 137, 0, 200, 1, 244 }));
}

TEST(OiCommands, DriveNegativeValues)
{
  // -200 mm/s = 0xFF38; radius 500 mm.
  EXPECT_EQ(cd::encodeDrive(-200, 500), (Bytes{ 137, 0xFF, 0x38, 0x01, 0xF4 }));
  // 100 mm/s, radius -300 mm = 0xFED4.
  EXPECT_EQ(cd::encodeDrive(100, -300), (Bytes{ 137, 0x00, 0x64, 0xFE, 0xD4 }));
}

TEST(OiCommands, DriveSpecialRadii)
{
  EXPECT_EQ(cd::encodeDrive(-200, cd::oi::RADIUS_STRAIGHT), (Bytes{ 137, 0xFF, 0x38, 0x80, 0x00 }));
  EXPECT_EQ(cd::encodeDrive(300, cd::oi::RADIUS_STRAIGHT_ALT), (Bytes{ 137, 0x01, 0x2C, 0x7F, 0xFF }));
  EXPECT_EQ(cd::encodeDrive(100, cd::oi::RADIUS_TURN_CW), (Bytes{ 137, 0x00, 0x64, 0xFF, 0xFF }));
  EXPECT_EQ(cd::encodeDrive(100, cd::oi::RADIUS_TURN_CCW), (Bytes{ 137, 0x00, 0x64, 0x00, 0x01 }));
}

TEST(OiCommands, DriveClampsToSpecRanges)
{
  // 700 mm/s -> 500 (0x01F4); radius 5000 -> 2000 (0x07D0); -5000 -> -2000 (0xF830).
  EXPECT_EQ(cd::encodeDrive(700, 5000), (Bytes{ 137, 0x01, 0xF4, 0x07, 0xD0 }));
  EXPECT_EQ(cd::encodeDrive(-900, -5000), (Bytes{ 137, 0xFE, 0x0C, 0xF8, 0x30 }));
}

TEST(OiCommands, DriveDirectRightFirst)
{
  // Right 200 (0x00C8), left -100 (0xFF9C).
  EXPECT_EQ(cd::encodeDriveDirect(200, -100), (Bytes{ 145, 0x00, 0xC8, 0xFF, 0x9C }));
  // Clamped to +-500: 600 -> 0x01F4, -600 -> 0xFE0C.
  EXPECT_EQ(cd::encodeDriveDirect(600, -600), (Bytes{ 145, 0x01, 0xF4, 0xFE, 0x0C }));
}

TEST(OiCommands, SensorRequests)
{
  Bytes b;
  cd::appendSensors(b, 7);
  EXPECT_EQ(b, (Bytes{ 142, 7 }));
  EXPECT_EQ(cd::encodeQueryList({ 7, 19, 20 }), (Bytes{ 149, 3, 7, 19, 20 }));
  EXPECT_EQ(cd::encodeStream({ 29, 13 }), (Bytes{ 148, 2, 29, 13 }));
  Bytes p;
  cd::appendPauseResumeStream(p, false);
  cd::appendPauseResumeStream(p, true);
  EXPECT_EQ(p, (Bytes{ 150, 0, 150, 1 }));
}

TEST(OiCommands, WaitDistance)
{
  EXPECT_EQ(cd::encodeWaitDistance(500), (Bytes{ 156, 0x01, 0xF4 }));
  EXPECT_EQ(cd::encodeWaitDistance(-100), (Bytes{ 156, 0xFF, 0x9C }));
}

TEST(OiCommands, Int16Helpers)
{
  const uint8_t a[2] = { 0xFF, 0xA6 };
  EXPECT_EQ(cd::oi::readInt16(a), -90);
  EXPECT_EQ(cd::oi::readUint16(a), 65446);
  Bytes b;
  cd::oi::appendInt16(b, -32768);
  cd::oi::appendInt16(b, 40000);  // saturates
  EXPECT_EQ(b, (Bytes{ 0x80, 0x00, 0x7F, 0xFF }));
}

TEST(OiCommands, ModelDefaults)
{
  EXPECT_EQ(cd::defaultBaud(cd::Model::CREATE_1), 57600u);
  EXPECT_EQ(cd::defaultBaud(cd::Model::CREATE_2), 115200u);
  EXPECT_DOUBLE_EQ(cd::defaultWheelBase(cd::Model::CREATE_1), 0.258);
  EXPECT_DOUBLE_EQ(cd::defaultWheelBase(cd::Model::CREATE_2), 0.235);
}
