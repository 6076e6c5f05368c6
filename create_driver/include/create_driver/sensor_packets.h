/// @file sensor_packets.h
/// @brief Open Interface sensor packet table (ids, sizes, signedness), decoding and encoding.
///
/// Single packets 7..58 and the group packets 0..6, 100, 101, 106, 107 are known. Packets 43..58
/// and groups 100..107 exist on the Create 2 only. Values are kept raw (OI units: mm, mm/s,
/// degrees, mV, mA, mAh, counts) in SensorState; conversion to SI happens in the caller.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "create_driver/oi_commands.h"

namespace create_driver
{
/// Sensor packet ids.
namespace packet
{
constexpr uint8_t GROUP_0 = 0;  ///< 7..26
constexpr uint8_t GROUP_1 = 1;  ///< 7..16
constexpr uint8_t GROUP_2 = 2;  ///< 17..20
constexpr uint8_t GROUP_3 = 3;  ///< 21..26
constexpr uint8_t GROUP_4 = 4;  ///< 27..34
constexpr uint8_t GROUP_5 = 5;  ///< 35..42
constexpr uint8_t GROUP_6 = 6;  ///< 7..42
constexpr uint8_t BUMPS_WHEEL_DROPS = 7;
constexpr uint8_t WALL = 8;
constexpr uint8_t CLIFF_LEFT = 9;
constexpr uint8_t CLIFF_FRONT_LEFT = 10;
constexpr uint8_t CLIFF_FRONT_RIGHT = 11;
constexpr uint8_t CLIFF_RIGHT = 12;
constexpr uint8_t VIRTUAL_WALL = 13;
constexpr uint8_t OVERCURRENTS = 14;
constexpr uint8_t DIRT_DETECT = 15;  ///< Create 2; unused on the Create
constexpr uint8_t UNUSED_16 = 16;
constexpr uint8_t IR_OMNI = 17;
constexpr uint8_t BUTTONS = 18;
constexpr uint8_t DISTANCE = 19;  ///< mm since last read, signed
constexpr uint8_t ANGLE = 20;     ///< degrees since last read, signed, counter-clockwise positive
constexpr uint8_t CHARGING_STATE = 21;
constexpr uint8_t VOLTAGE = 22;           ///< mV
constexpr uint8_t CURRENT = 23;           ///< mA, signed (negative: discharging)
constexpr uint8_t TEMPERATURE = 24;       ///< degrees C, signed
constexpr uint8_t BATTERY_CHARGE = 25;    ///< mAh
constexpr uint8_t BATTERY_CAPACITY = 26;  ///< mAh
constexpr uint8_t WALL_SIGNAL = 27;
constexpr uint8_t CLIFF_LEFT_SIGNAL = 28;
constexpr uint8_t CLIFF_FRONT_LEFT_SIGNAL = 29;
constexpr uint8_t CLIFF_FRONT_RIGHT_SIGNAL = 30;
constexpr uint8_t CLIFF_RIGHT_SIGNAL = 31;
constexpr uint8_t CARGO_BAY_DIGITAL_INPUTS = 32;
constexpr uint8_t CARGO_BAY_ANALOG_SIGNAL = 33;
constexpr uint8_t CHARGING_SOURCES = 34;
constexpr uint8_t OI_MODE = 35;
constexpr uint8_t SONG_NUMBER = 36;
constexpr uint8_t SONG_PLAYING = 37;
constexpr uint8_t NUM_STREAM_PACKETS = 38;
constexpr uint8_t REQUESTED_VELOCITY = 39;
constexpr uint8_t REQUESTED_RADIUS = 40;
constexpr uint8_t REQUESTED_RIGHT_VELOCITY = 41;
constexpr uint8_t REQUESTED_LEFT_VELOCITY = 42;
constexpr uint8_t LEFT_ENCODER_COUNTS = 43;   ///< Create 2, unsigned, wraps at 65535
constexpr uint8_t RIGHT_ENCODER_COUNTS = 44;  ///< Create 2, unsigned, wraps at 65535
constexpr uint8_t LIGHT_BUMPER = 45;
constexpr uint8_t LIGHT_BUMP_LEFT_SIGNAL = 46;
constexpr uint8_t LIGHT_BUMP_RIGHT_SIGNAL = 51;
constexpr uint8_t IR_LEFT = 52;
constexpr uint8_t IR_RIGHT = 53;
constexpr uint8_t LEFT_MOTOR_CURRENT = 54;
constexpr uint8_t RIGHT_MOTOR_CURRENT = 55;
constexpr uint8_t MAIN_BRUSH_CURRENT = 56;
constexpr uint8_t SIDE_BRUSH_CURRENT = 57;
constexpr uint8_t STASIS = 58;
constexpr uint8_t GROUP_100 = 100;  ///< 7..58 (Create 2)
constexpr uint8_t GROUP_101 = 101;  ///< 43..58 (Create 2)
constexpr uint8_t GROUP_106 = 106;  ///< 46..51 (Create 2)
constexpr uint8_t GROUP_107 = 107;  ///< 54..58 (Create 2)
constexpr uint8_t MAX_SINGLE_ID = 58;
}  // namespace packet

/// Bits of packet 7 (bumps and wheel drops).
namespace bumps
{
constexpr uint8_t BUMP_RIGHT = 0x01;
constexpr uint8_t BUMP_LEFT = 0x02;
constexpr uint8_t WHEEL_DROP_RIGHT = 0x04;
constexpr uint8_t WHEEL_DROP_LEFT = 0x08;
constexpr uint8_t WHEEL_DROP_CASTER = 0x10;  ///< Create 1 only
constexpr uint8_t BUMP_MASK = BUMP_RIGHT | BUMP_LEFT;
constexpr uint8_t WHEEL_DROP_MASK = WHEEL_DROP_RIGHT | WHEEL_DROP_LEFT | WHEEL_DROP_CASTER;
}  // namespace bumps

/// Bits of packet 18 (buttons).
namespace buttons
{
constexpr uint8_t CREATE1_PLAY = 0x01;
constexpr uint8_t CREATE1_ADVANCE = 0x04;
constexpr uint8_t CREATE2_CLEAN = 0x01;
constexpr uint8_t CREATE2_SPOT = 0x02;
constexpr uint8_t CREATE2_DOCK = 0x04;
}  // namespace buttons

/// Description of one single (non-group) sensor packet.
struct PacketInfo
{
  uint8_t id;         ///< packet id
  uint8_t size;       ///< data bytes
  bool is_signed;     ///< two's complement (2-byte and 1-byte signed packets)
  bool create2_only;  ///< present on the Create 2 only
  const char* name;   ///< short name
};

/// @brief Table entry of a single packet (7..58), or nullptr for groups and unknown ids.
const PacketInfo* singlePacketInfo(uint8_t id);

/// @brief True if @p id is a group packet (0..6, 100, 101, 106, 107).
bool isGroupPacket(uint8_t id);

/// @brief True if @p id (single or group) exists on @p model.
[[nodiscard]] bool isValidPacket(uint8_t id, Model model);

/// @brief Number of data bytes of a packet (single or group), 0 if unknown on @p model.
size_t packetSize(uint8_t id, Model model);

/// @brief Single packet ids contained in a packet, in wire order (itself for a single packet).
/// Empty for unknown ids. Points into a static table.
const std::vector<uint8_t>& packetMembers(uint8_t id);

/// @brief Raw sensor values, one per single packet id, as last committed.
///
/// A value keeps its last decoded content until a newer frame or reply containing that packet is
/// committed; @c present tells which packets the latest update contained.
struct SensorState
{
  std::array<int32_t, packet::MAX_SINGLE_ID + 1> value{};  ///< raw value per single packet id
  uint64_t present = 0;  ///< bit i set when packet i was part of the latest committed update

  /// @brief Raw value of a single packet.
  int32_t get(uint8_t id) const { return id <= packet::MAX_SINGLE_ID ? value[id] : 0; }
  /// @brief Sets the raw value of a single packet (used by the simulator and tests).
  void set(uint8_t id, int32_t v)
  {
    if (id <= packet::MAX_SINGLE_ID)
      value[id] = v;
  }
  /// @brief True if the latest update contained packet @p id.
  bool has(uint8_t id) const { return id <= packet::MAX_SINGLE_ID && ((present >> id) & 1u) != 0; }

  /// @brief Right bumper pressed (packet 7 bit 0).
  bool bumpRight() const { return (value[packet::BUMPS_WHEEL_DROPS] & bumps::BUMP_RIGHT) != 0; }
  /// @brief Left bumper pressed (packet 7 bit 1).
  bool bumpLeft() const { return (value[packet::BUMPS_WHEEL_DROPS] & bumps::BUMP_LEFT) != 0; }
  /// @brief Right wheel dropped (packet 7 bit 2).
  bool wheelDropRight() const { return (value[packet::BUMPS_WHEEL_DROPS] & bumps::WHEEL_DROP_RIGHT) != 0; }
  /// @brief Left wheel dropped (packet 7 bit 3).
  bool wheelDropLeft() const { return (value[packet::BUMPS_WHEEL_DROPS] & bumps::WHEEL_DROP_LEFT) != 0; }
  /// @brief Caster dropped (packet 7 bit 4, Create 1 only).
  bool wheelDropCaster() const { return (value[packet::BUMPS_WHEEL_DROPS] & bumps::WHEEL_DROP_CASTER) != 0; }
  /// @brief Left cliff sensor (packet 9).
  bool cliffLeft() const { return value[packet::CLIFF_LEFT] != 0; }
  /// @brief Front left cliff sensor (packet 10).
  bool cliffFrontLeft() const { return value[packet::CLIFF_FRONT_LEFT] != 0; }
  /// @brief Front right cliff sensor (packet 11).
  bool cliffFrontRight() const { return value[packet::CLIFF_FRONT_RIGHT] != 0; }
  /// @brief Right cliff sensor (packet 12).
  bool cliffRight() const { return value[packet::CLIFF_RIGHT] != 0; }
  /// @brief Any of the four cliff sensors.
  bool anyCliff() const { return cliffLeft() || cliffFrontLeft() || cliffFrontRight() || cliffRight(); }
  /// @brief Any wheel drop (including the Create 1 caster).
  bool anyWheelDrop() const { return (value[packet::BUMPS_WHEEL_DROPS] & bumps::WHEEL_DROP_MASK) != 0; }
  /// @brief Either bumper.
  bool anyBump() const { return (value[packet::BUMPS_WHEEL_DROPS] & bumps::BUMP_MASK) != 0; }
  /// @brief Distance since the previous report, mm (packet 19).
  int distanceMm() const { return value[packet::DISTANCE]; }
  /// @brief Angle since the previous report, degrees, counter-clockwise positive (packet 20).
  int angleDeg() const { return value[packet::ANGLE]; }
  /// @brief OI mode (packet 35): 0 off, 1 passive, 2 safe, 3 full.
  int oiMode() const { return value[packet::OI_MODE]; }
};

/// @brief Decodes the data of packet @p id (single or group) into @p state.
/// @param data  exactly packetSize(id, model) bytes
/// @return false if @p id is unknown on @p model (state unchanged)
bool decodePacket(uint8_t id, const uint8_t* data, Model model, SensorState& state);

/// @brief Appends the data bytes of packet @p id (single or group) from @p state.
/// Values are truncated to the packet width. Unknown ids append nothing.
/// @return false if @p id is unknown on @p model
bool encodePacket(uint8_t id, const SensorState& state, Model model, Bytes& out);

}  // namespace create_driver
