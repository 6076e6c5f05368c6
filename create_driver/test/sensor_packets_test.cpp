#include <gtest/gtest.h>

#include <initializer_list>
#include <utility>

#include "create_driver/sensor_packets.h"

using create_driver::Bytes;
namespace cd = create_driver;

namespace
{
/// Expects packetSize(id, @p model) to be the size of each { id, size } of @p sizes.
void expectSizes(cd::Model model, std::initializer_list<std::pair<uint8_t, size_t>> sizes)
{
  for (const auto& id_size : sizes)
    EXPECT_EQ(cd::packetSize(id_size.first, model), id_size.second) << "packet " << static_cast<int>(id_size.first);
}
}  // namespace

TEST(SensorPackets, GroupSizesMatchSpec)
{
  expectSizes(cd::Model::CREATE_1, { { 0, 26 }, { 1, 10 }, { 2, 6 }, { 3, 10 }, { 4, 14 }, { 5, 12 }, { 6, 52 } });
  expectSizes(cd::Model::CREATE_2, { { 100, 80 }, { 101, 28 }, { 106, 12 }, { 107, 9 } });
}

TEST(SensorPackets, SingleSizesAndModels)
{
  expectSizes(cd::Model::CREATE_1,
              { { 7, 1 }, { 19, 2 }, { 20, 2 }, { 21, 1 }, { 22, 2 }, { 24, 1 }, { 35, 1 }, { 42, 2 } });
  // Create 2 only packets are unknown on the Create.
  expectSizes(cd::Model::CREATE_1, { { 43, 0 }, { 100, 0 } });
  expectSizes(cd::Model::CREATE_2, { { 43, 2 }, { 58, 1 }, { 59, 0 } });
  expectSizes(cd::Model::CREATE_1, { { 200, 0 } });
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
