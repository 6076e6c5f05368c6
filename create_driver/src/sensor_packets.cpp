#include "create_driver/sensor_packets.h"

namespace create_driver
{
namespace
{
// id, size, signed, create2_only, name. Indexed by id - 7.
constexpr PacketInfo kSingles[] = {
  { 7, 1, false, false, "bumps_wheel_drops" },
  { 8, 1, false, false, "wall" },
  { 9, 1, false, false, "cliff_left" },
  { 10, 1, false, false, "cliff_front_left" },
  { 11, 1, false, false, "cliff_front_right" },
  { 12, 1, false, false, "cliff_right" },
  { 13, 1, false, false, "virtual_wall" },
  { 14, 1, false, false, "overcurrents" },
  { 15, 1, false, false, "dirt_detect" },
  { 16, 1, false, false, "unused_16" },
  { 17, 1, false, false, "ir_omni" },
  { 18, 1, false, false, "buttons" },
  { 19, 2, true, false, "distance" },
  { 20, 2, true, false, "angle" },
  { 21, 1, false, false, "charging_state" },
  { 22, 2, false, false, "voltage" },
  { 23, 2, true, false, "current" },
  { 24, 1, true, false, "temperature" },
  { 25, 2, false, false, "battery_charge" },
  { 26, 2, false, false, "battery_capacity" },
  { 27, 2, false, false, "wall_signal" },
  { 28, 2, false, false, "cliff_left_signal" },
  { 29, 2, false, false, "cliff_front_left_signal" },
  { 30, 2, false, false, "cliff_front_right_signal" },
  { 31, 2, false, false, "cliff_right_signal" },
  { 32, 1, false, false, "cargo_bay_digital_inputs" },
  { 33, 2, false, false, "cargo_bay_analog_signal" },
  { 34, 1, false, false, "charging_sources" },
  { 35, 1, false, false, "oi_mode" },
  { 36, 1, false, false, "song_number" },
  { 37, 1, false, false, "song_playing" },
  { 38, 1, false, false, "number_of_stream_packets" },
  { 39, 2, true, false, "requested_velocity" },
  { 40, 2, true, false, "requested_radius" },
  { 41, 2, true, false, "requested_right_velocity" },
  { 42, 2, true, false, "requested_left_velocity" },
  { 43, 2, false, true, "left_encoder_counts" },
  { 44, 2, false, true, "right_encoder_counts" },
  { 45, 1, false, true, "light_bumper" },
  { 46, 2, false, true, "light_bump_left_signal" },
  { 47, 2, false, true, "light_bump_front_left_signal" },
  { 48, 2, false, true, "light_bump_center_left_signal" },
  { 49, 2, false, true, "light_bump_center_right_signal" },
  { 50, 2, false, true, "light_bump_front_right_signal" },
  { 51, 2, false, true, "light_bump_right_signal" },
  { 52, 1, false, true, "ir_left" },
  { 53, 1, false, true, "ir_right" },
  { 54, 2, true, true, "left_motor_current" },
  { 55, 2, true, true, "right_motor_current" },
  { 56, 2, true, true, "main_brush_current" },
  { 57, 2, true, true, "side_brush_current" },
  { 58, 1, false, true, "stasis" },
};

std::vector<uint8_t> range(uint8_t first, uint8_t last)
{
  std::vector<uint8_t> ids;
  for (int i = first; i <= last; ++i)
    ids.push_back(static_cast<uint8_t>(i));
  return ids;
}

const std::vector<uint8_t>& members(uint8_t id)
{
  static const std::vector<uint8_t> empty;
  static const std::vector<uint8_t> g0 = range(7, 26), g1 = range(7, 16), g2 = range(17, 20), g3 = range(21, 26),
                                    g4 = range(27, 34), g5 = range(35, 42), g6 = range(7, 42), g100 = range(7, 58),
                                    g101 = range(43, 58), g106 = range(46, 51), g107 = range(54, 58);
  static std::array<std::vector<uint8_t>, packet::MAX_SINGLE_ID + 1> singles = []
  {
    std::array<std::vector<uint8_t>, packet::MAX_SINGLE_ID + 1> a;
    for (int i = 7; i <= packet::MAX_SINGLE_ID; ++i)
      a[static_cast<size_t>(i)] = { static_cast<uint8_t>(i) };
    return a;
  }();
  switch (id)
  {
    case 0:
      return g0;
    case 1:
      return g1;
    case 2:
      return g2;
    case 3:
      return g3;
    case 4:
      return g4;
    case 5:
      return g5;
    case 6:
      return g6;
    case 100:
      return g100;
    case 101:
      return g101;
    case 106:
      return g106;
    case 107:
      return g107;
    default:
      break;
  }
  if (id >= 7 && id <= packet::MAX_SINGLE_ID)
    return singles[id];
  return empty;
}
}  // namespace

const PacketInfo* singlePacketInfo(uint8_t id)
{
  if (id < 7 || id > packet::MAX_SINGLE_ID)
    return nullptr;
  return &kSingles[id - 7];
}

bool isGroupPacket(uint8_t id)
{
  return id <= 6 || id == 100 || id == 101 || id == 106 || id == 107;
}

bool isValidPacket(uint8_t id, Model model)
{
  if (id <= 6)
    return true;
  if (id == 100 || id == 101 || id == 106 || id == 107)
    return model == Model::CREATE_2;
  const PacketInfo* info = singlePacketInfo(id);
  return info != nullptr && (!info->create2_only || model == Model::CREATE_2);
}

size_t packetSize(uint8_t id, Model model)
{
  if (!isValidPacket(id, model))
    return 0;
  size_t total = 0;
  for (uint8_t m : members(id))
    total += singlePacketInfo(m)->size;
  return total;
}

const std::vector<uint8_t>& packetMembers(uint8_t id)
{
  return members(id);
}

bool decodePacket(uint8_t id, const uint8_t* data, Model model, SensorState& state)
{
  if (!isValidPacket(id, model))
    return false;
  size_t offset = 0;
  for (uint8_t m : members(id))
  {
    const PacketInfo* info = singlePacketInfo(m);
    int32_t v = 0;
    if (info->size == 2)
      v = info->is_signed ? oi::readInt16(data + offset) : oi::readUint16(data + offset);
    else
      v = info->is_signed ? static_cast<int8_t>(data[offset]) : data[offset];
    state.value[m] = v;
    state.present |= (uint64_t{ 1 } << m);
    offset += info->size;
  }
  return true;
}

bool encodePacket(uint8_t id, const SensorState& state, Model model, Bytes& out)
{
  if (!isValidPacket(id, model))
    return false;
  for (uint8_t m : members(id))
  {
    const PacketInfo* info = singlePacketInfo(m);
    const int32_t v = state.value[m];
    if (info->size == 2)
    {
      const auto u = static_cast<uint16_t>(v & 0xFFFF);
      out.push_back(static_cast<uint8_t>(u >> 8));
      out.push_back(static_cast<uint8_t>(u & 0xFF));
    }
    else
    {
      out.push_back(static_cast<uint8_t>(v & 0xFF));
    }
  }
  return true;
}

}  // namespace create_driver
