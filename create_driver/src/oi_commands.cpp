#include "create_driver/oi_commands.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace create_driver
{
const char* oiModeName(OiMode mode)
{
  switch (mode)
  {
    case OiMode::OFF:
      return "off";
    case OiMode::PASSIVE:
      return "passive";
    case OiMode::SAFE:
      return "safe";
    case OiMode::FULL:
      return "full";
  }
  return "unknown";
}

unsigned defaultBaud(Model model)
{
  return model == Model::CREATE_2 ? 115200u : 57600u;
}

double defaultWheelBase(Model model)
{
  return model == Model::CREATE_2 ? 0.235 : 0.258;
}

Model parseModel(const std::string& name)
{
  if (name == "create_1" || name == "create")
    return Model::CREATE_1;
  if (name == "create_2" || name == "roomba_600")
    return Model::CREATE_2;
  throw std::invalid_argument("model must be create_1 or create_2 (got '" + name + "')");
}

namespace oi
{
bool isSpecialRadius(int radius_mm)
{
  return radius_mm == RADIUS_STRAIGHT || radius_mm == RADIUS_STRAIGHT_ALT || radius_mm == RADIUS_TURN_CW ||
         radius_mm == RADIUS_TURN_CCW;
}

void appendInt16(Bytes& out, int value)
{
  const auto v = static_cast<uint16_t>(static_cast<int16_t>(std::clamp(value, -32768, 32767)));
  out.push_back(static_cast<uint8_t>(v >> 8));
  out.push_back(static_cast<uint8_t>(v & 0xFF));
}

int16_t readInt16(const uint8_t* data)
{
  return static_cast<int16_t>(readUint16(data));
}

uint16_t readUint16(const uint8_t* data)
{
  return static_cast<uint16_t>((static_cast<uint16_t>(data[0]) << 8) | data[1]);
}
}  // namespace oi

void appendStart(Bytes& out)
{
  out.push_back(oi::START);
}

void appendSafe(Bytes& out)
{
  out.push_back(oi::SAFE);
}

void appendFull(Bytes& out)
{
  out.push_back(oi::FULL);
}

void appendPassive(Bytes& out)
{
  out.push_back(oi::START);
}

void appendStop(Bytes& out)
{
  out.push_back(oi::STOP);
}

void appendMode(Bytes& out, OiMode mode)
{
  switch (mode)
  {
    case OiMode::OFF:
      appendStop(out);
      break;
    case OiMode::PASSIVE:
      appendPassive(out);
      break;
    case OiMode::SAFE:
      appendSafe(out);
      break;
    case OiMode::FULL:
      appendFull(out);
      break;
  }
}

void appendDrive(Bytes& out, int velocity_mm_s, int radius_mm)
{
  const int v = std::clamp(velocity_mm_s, -oi::MAX_VELOCITY_MM_S, oi::MAX_VELOCITY_MM_S);
  const int r =
      oi::isSpecialRadius(radius_mm) ? radius_mm : std::clamp(radius_mm, -oi::MAX_RADIUS_MM, oi::MAX_RADIUS_MM);
  out.push_back(oi::DRIVE);
  oi::appendInt16(out, v);
  oi::appendInt16(out, r);
}

void appendDriveDirect(Bytes& out, int right_mm_s, int left_mm_s)
{
  out.push_back(oi::DRIVE_DIRECT);
  oi::appendInt16(out, std::clamp(right_mm_s, -oi::MAX_VELOCITY_MM_S, oi::MAX_VELOCITY_MM_S));
  oi::appendInt16(out, std::clamp(left_mm_s, -oi::MAX_VELOCITY_MM_S, oi::MAX_VELOCITY_MM_S));
}

WheelSpeeds driveRadiusToWheels(int velocity_mm_s, int radius_mm, double wheel_base)
{
  const double v = std::clamp(velocity_mm_s, -oi::MAX_VELOCITY_MM_S, oi::MAX_VELOCITY_MM_S) / 1000.0;
  WheelSpeeds w;
  if (radius_mm == oi::RADIUS_TURN_CCW)
  {
    w.left = -v;
    w.right = v;
  }
  else if (radius_mm == oi::RADIUS_TURN_CW)
  {
    w.left = v;
    w.right = -v;
  }
  else if (radius_mm == 0 || radius_mm < -oi::MAX_RADIUS_MM || radius_mm > oi::MAX_RADIUS_MM)
  {
    // Straight (0x8000, 0x7FFF); radii outside the specified range are treated the same way.
    w.left = v;
    w.right = v;
  }
  else
  {
    const double r = radius_mm / 1000.0;
    w.left = v * (r - 0.5 * wheel_base) / r;
    w.right = v * (r + 0.5 * wheel_base) / r;
  }
  const double largest = std::max(std::fabs(w.left), std::fabs(w.right));
  const double max_wheel = oi::MAX_VELOCITY_MM_S / 1000.0;
  if (largest > max_wheel)
  {
    w.left *= max_wheel / largest;
    w.right *= max_wheel / largest;
  }
  return w;
}

void appendSensors(Bytes& out, uint8_t packet_id)
{
  out.push_back(oi::SENSORS);
  out.push_back(packet_id);
}

namespace
{
void appendIdList(Bytes& out, uint8_t opcode, const std::vector<uint8_t>& ids)
{
  out.push_back(opcode);
  out.push_back(static_cast<uint8_t>(std::min<size_t>(ids.size(), 255)));
  out.insert(out.end(), ids.begin(), ids.begin() + static_cast<std::ptrdiff_t>(std::min<size_t>(ids.size(), 255)));
}
}  // namespace

void appendQueryList(Bytes& out, const std::vector<uint8_t>& packet_ids)
{
  appendIdList(out, oi::QUERY_LIST, packet_ids);
}

void appendStream(Bytes& out, const std::vector<uint8_t>& packet_ids)
{
  appendIdList(out, oi::STREAM, packet_ids);
}

void appendPauseResumeStream(Bytes& out, bool resume)
{
  out.push_back(oi::PAUSE_RESUME_STREAM);
  out.push_back(resume ? 1 : 0);
}

void appendWaitDistance(Bytes& out, int distance_mm)
{
  out.push_back(oi::WAIT_DISTANCE);
  oi::appendInt16(out, distance_mm);
}

Bytes encodeStart()
{
  Bytes b;
  appendStart(b);
  return b;
}

Bytes encodeDrive(int velocity_mm_s, int radius_mm)
{
  Bytes b;
  appendDrive(b, velocity_mm_s, radius_mm);
  return b;
}

Bytes encodeDriveDirect(int right_mm_s, int left_mm_s)
{
  Bytes b;
  appendDriveDirect(b, right_mm_s, left_mm_s);
  return b;
}

Bytes encodeStream(const std::vector<uint8_t>& packet_ids)
{
  Bytes b;
  appendStream(b, packet_ids);
  return b;
}

Bytes encodeQueryList(const std::vector<uint8_t>& packet_ids)
{
  Bytes b;
  appendQueryList(b, packet_ids);
  return b;
}

Bytes encodeWaitDistance(int distance_mm)
{
  Bytes b;
  appendWaitDistance(b, distance_mm);
  return b;
}

}  // namespace create_driver
