#include <gtest/gtest.h>

#include "create_driver/sensor_packets.h"

using create_driver::Bytes;
namespace cd = create_driver;

TEST(SensorPackets, GroupSizesMatchSpec)
{
  const auto c1 = cd::Model::CREATE_1;
  const auto c2 = cd::Model::CREATE_2;
  EXPECT_EQ(cd::packetSize(0, c1), 26u);
  EXPECT_EQ(cd::packetSize(1, c1), 10u);
  EXPECT_EQ(cd::packetSize(2, c1), 6u);
  EXPECT_EQ(cd::packetSize(3, c1), 10u);
  EXPECT_EQ(cd::packetSize(4, c1), 14u);
  EXPECT_EQ(cd::packetSize(5, c1), 12u);
  EXPECT_EQ(cd::packetSize(6, c1), 52u);
  EXPECT_EQ(cd::packetSize(100, c2), 80u);
  EXPECT_EQ(cd::packetSize(101, c2), 28u);
  EXPECT_EQ(cd::packetSize(106, c2), 12u);
  EXPECT_EQ(cd::packetSize(107, c2), 9u);
}

TEST(SensorPackets, SingleSizesAndModels)
{
  const auto c1 = cd::Model::CREATE_1;
  EXPECT_EQ(cd::packetSize(7, c1), 1u);
  EXPECT_EQ(cd::packetSize(19, c1), 2u);
  EXPECT_EQ(cd::packetSize(20, c1), 2u);
  EXPECT_EQ(cd::packetSize(21, c1), 1u);
  EXPECT_EQ(cd::packetSize(22, c1), 2u);
  EXPECT_EQ(cd::packetSize(24, c1), 1u);
  EXPECT_EQ(cd::packetSize(35, c1), 1u);
  EXPECT_EQ(cd::packetSize(42, c1), 2u);
  // Create 2 only packets are unknown on the Create.
  EXPECT_EQ(cd::packetSize(43, c1), 0u);
  EXPECT_EQ(cd::packetSize(100, c1), 0u);
  EXPECT_EQ(cd::packetSize(43, cd::Model::CREATE_2), 2u);
  EXPECT_EQ(cd::packetSize(58, cd::Model::CREATE_2), 1u);
  EXPECT_EQ(cd::packetSize(59, cd::Model::CREATE_2), 0u);
  EXPECT_EQ(cd::packetSize(200, c1), 0u);
}

TEST(SensorPackets, DecodeSignedAndUnsigned)
{
  cd::SensorState s;
  // Angle -90 degrees = 0xFFA6; voltage 15000 mV = 0x3A98; temperature -5 = 0xFB.
  const uint8_t angle[2] = { 0xFF, 0xA6 };
  ASSERT_TRUE(cd::decodePacket(20, angle, cd::Model::CREATE_1, s));
  EXPECT_EQ(s.angleDeg(), -90);
  const uint8_t volt[2] = { 0x3A, 0x98 };
  ASSERT_TRUE(cd::decodePacket(22, volt, cd::Model::CREATE_1, s));
  EXPECT_EQ(s.get(22), 15000);
  const uint8_t temp[1] = { 0xFB };
  ASSERT_TRUE(cd::decodePacket(24, temp, cd::Model::CREATE_1, s));
  EXPECT_EQ(s.get(24), -5);
  // Encoder counts are unsigned: 0xFFFF = 65535.
  const uint8_t enc[2] = { 0xFF, 0xFF };
  ASSERT_TRUE(cd::decodePacket(43, enc, cd::Model::CREATE_2, s));
  EXPECT_EQ(s.get(43), 65535);
  EXPECT_FALSE(cd::decodePacket(43, enc, cd::Model::CREATE_1, s));
}

TEST(SensorPackets, BumpAndWheelDropBits)
{
  cd::SensorState s;
  const uint8_t b = 0x1A;  // caster drop, left wheel drop, left bump
  ASSERT_TRUE(cd::decodePacket(7, &b, cd::Model::CREATE_1, s));
  EXPECT_TRUE(s.bumpLeft());
  EXPECT_FALSE(s.bumpRight());
  EXPECT_TRUE(s.wheelDropLeft());
  EXPECT_FALSE(s.wheelDropRight());
  EXPECT_TRUE(s.wheelDropCaster());
  EXPECT_TRUE(s.anyBump());
  EXPECT_TRUE(s.anyWheelDrop());
  EXPECT_FALSE(s.anyCliff());
  EXPECT_TRUE(s.has(7));
  EXPECT_FALSE(s.has(8));
}

TEST(SensorPackets, GroupZeroRoundTrip)
{
  cd::SensorState in;
  in.set(7, 0x03);
  in.set(9, 1);
  in.set(12, 1);
  in.set(18, 4);
  in.set(19, -123);
  in.set(20, 45);
  in.set(21, 2);
  in.set(22, 16000);
  in.set(23, -1500);
  in.set(24, 31);
  in.set(25, 2500);
  in.set(26, 3000);
  Bytes data;
  ASSERT_TRUE(cd::encodePacket(0, in, cd::Model::CREATE_1, data));
  ASSERT_EQ(data.size(), 26u);
  // Distance is at offset 12 (after the twelve 1-byte packets 7..18): -123 = 0xFF85.
  EXPECT_EQ(data[12], 0xFF);
  EXPECT_EQ(data[13], 0x85);
  cd::SensorState out;
  ASSERT_TRUE(cd::decodePacket(0, data.data(), cd::Model::CREATE_1, out));
  for (int id = 7; id <= 26; ++id)
  {
    EXPECT_EQ(out.get(static_cast<uint8_t>(id)), in.get(static_cast<uint8_t>(id))) << "packet " << id;
    EXPECT_TRUE(out.has(static_cast<uint8_t>(id)));
  }
  EXPECT_TRUE(out.bumpLeft() && out.bumpRight() && out.cliffLeft() && out.cliffRight());
  EXPECT_FALSE(out.has(27));
}

TEST(SensorPackets, Members)
{
  EXPECT_EQ(cd::packetMembers(2), (std::vector<uint8_t>{ 17, 18, 19, 20 }));
  EXPECT_EQ(cd::packetMembers(19), (std::vector<uint8_t>{ 19 }));
  EXPECT_TRUE(cd::packetMembers(99).empty());
  EXPECT_TRUE(cd::isGroupPacket(6));
  EXPECT_FALSE(cd::isGroupPacket(7));
}
