/// @file oi_commands.h
/// @brief Opcodes and byte encoding of iRobot Create Open Interface commands.
///
/// Multi-byte arguments are 16-bit two's complement, high byte first. Velocities are mm/s and
/// radii mm here: this is the only place (with the sensor packets) where OI units appear.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace create_driver
{
/// A byte string sent to or received from the robot.
using Bytes = std::vector<uint8_t>;

/// Which robot the Open Interface belongs to.
enum class Model : uint8_t
{
  CREATE_1,  ///< iRobot Create (2007): 57600 baud, packets 0..42, scripts and Wait commands.
  CREATE_2   ///< iRobot Create 2 / Roomba 600: 115200 baud, packets up to 107, encoders (43, 44).
};

/// Open Interface modes (values of sensor packet 35).
enum class OiMode : uint8_t
{
  OFF = 0,
  PASSIVE = 1,
  SAFE = 2,
  FULL = 3
};

/// @brief Name of a mode ("off", "passive", "safe", "full").
const char* oiModeName(OiMode mode);

/// @brief Default baud rate of a model: 57600 for the Create, 115200 for the Create 2.
unsigned defaultBaud(Model model);

/// @brief Distance between the wheels in m: 0.258 for the Create, 0.235 for the Create 2.
double defaultWheelBase(Model model);

/// @brief The model called @p name: create_1 (or create), create_2 (or roomba_600).
/// @throws std::invalid_argument starting with "model must be"
Model parseModel(const std::string& name);

namespace oi
{
/// Command opcodes (Create Open Interface v2 and Create 2 OI).
enum Opcode : uint8_t
{
  START = 128,
  BAUD = 129,
  CONTROL = 130,  ///< legacy alias of SAFE
  SAFE = 131,
  FULL = 132,
  POWER = 133,  ///< Create 2 only
  SPOT = 134,
  COVER = 135,  ///< Create 1 (Create 2: CLEAN)
  DEMO = 136,   ///< Create 1: one argument (Create 2: MAX, no argument)
  DRIVE = 137,
  LOW_SIDE_DRIVERS = 138,
  LEDS = 139,
  SONG = 140,
  PLAY_SONG = 141,
  SENSORS = 142,
  COVER_AND_DOCK = 143,
  PWM_LOW_SIDE_DRIVERS = 144,
  DRIVE_DIRECT = 145,
  DRIVE_PWM = 146,  ///< Create 2 only
  DIGITAL_OUTPUTS = 147,
  STREAM = 148,
  QUERY_LIST = 149,
  PAUSE_RESUME_STREAM = 150,
  SEND_IR = 151,
  SCRIPT = 152,
  PLAY_SCRIPT = 153,
  SHOW_SCRIPT = 154,
  WAIT_TIME = 155,
  WAIT_DISTANCE = 156,
  WAIT_ANGLE = 157,
  WAIT_EVENT = 158,
  STOP = 173  ///< Create 2 only: stops the OI (mode Off)
};

/// Special Drive radius: straight (0x8000).
constexpr int RADIUS_STRAIGHT = -32768;
/// Special Drive radius: straight, alternative value (0x7FFF).
constexpr int RADIUS_STRAIGHT_ALT = 32767;
/// Special Drive radius: turn in place clockwise (0xFFFF).
constexpr int RADIUS_TURN_CW = -1;
/// Special Drive radius: turn in place counter-clockwise (0x0001).
constexpr int RADIUS_TURN_CCW = 1;
/// Largest velocity magnitude accepted by Drive and Drive Direct, mm/s.
constexpr int MAX_VELOCITY_MM_S = 500;
/// Largest ordinary radius magnitude accepted by Drive, mm.
constexpr int MAX_RADIUS_MM = 2000;
/// First byte of every stream frame.
constexpr uint8_t STREAM_HEADER = 19;
/// Period of the sensor stream, s.
constexpr double STREAM_PERIOD_S = 0.015;

/// @brief True for the four special radius values (straight x2, turn in place x2).
bool isSpecialRadius(int radius_mm);

/// @brief Appends a 16-bit two's complement value, high byte first.
void appendInt16(Bytes& out, int value);
/// @brief Reads a signed 16-bit big-endian value.
int16_t readInt16(const uint8_t* data);
/// @brief Reads an unsigned 16-bit big-endian value.
uint16_t readUint16(const uint8_t* data);
}  // namespace oi

/// @brief Start [128]: opens the OI, mode Passive. Also returns any mode to Passive.
void appendStart(Bytes& out);
/// @brief Safe [131].
void appendSafe(Bytes& out);
/// @brief Full [132].
void appendFull(Bytes& out);
/// @brief Command that enters a mode: Start (Passive), Safe or Full. OFF encodes Stop [173].
void appendMode(Bytes& out, OiMode mode);
/// @brief Passive: the Start opcode [128], which returns the robot to Passive from any mode.
void appendPassive(Bytes& out);
/// @brief Stop [173] (Create 2): stops the OI, mode Off; the robot then ignores all but Start.
void appendStop(Bytes& out);
/// @brief Drive [137][v hi][v lo][r hi][r lo].
/// Velocity is clamped to +-500 mm/s; the special radii pass unchanged, others are clamped to
/// +-2000 mm.
void appendDrive(Bytes& out, int velocity_mm_s, int radius_mm);
/// @brief Drive Direct [145][right hi][right lo][left hi][left lo]; each clamped to +-500 mm/s.
void appendDriveDirect(Bytes& out, int right_mm_s, int left_mm_s);
/// @brief Sensors [142][packet id].
void appendSensors(Bytes& out, uint8_t packet_id);
/// @brief Query List [149][n][ids...].
void appendQueryList(Bytes& out, const std::vector<uint8_t>& packet_ids);
/// @brief Stream [148][n][ids...].
void appendStream(Bytes& out, const std::vector<uint8_t>& packet_ids);
/// @brief Pause/Resume Stream [150][0 = pause | 1 = resume].
void appendPauseResumeStream(Bytes& out, bool resume);
/// @brief Wait Distance [156][d hi][d lo], mm, signed (clamped to 16 bits).
/// The robot executes no other command until it has covered the distance.
void appendWaitDistance(Bytes& out, int distance_mm);

/// Wheel speeds in m/s.
struct WheelSpeeds
{
  double left = 0.0;
  double right = 0.0;
};

/// @brief Wheel speeds (m/s) the Create produces for a Drive command (special radii included),
/// each limited to 0.5 m/s with the ratio kept.
WheelSpeeds driveRadiusToWheels(int velocity_mm_s, int radius_mm, double wheel_base);

/// @brief Start as a new byte string (convenience for tests and tools).
Bytes encodeStart();
/// @brief Drive as a new byte string.
Bytes encodeDrive(int velocity_mm_s, int radius_mm);
/// @brief Drive Direct as a new byte string.
Bytes encodeDriveDirect(int right_mm_s, int left_mm_s);
/// @brief Stream as a new byte string.
Bytes encodeStream(const std::vector<uint8_t>& packet_ids);
/// @brief Query List as a new byte string.
Bytes encodeQueryList(const std::vector<uint8_t>& packet_ids);
/// @brief Wait Distance as a new byte string.
Bytes encodeWaitDistance(int distance_mm);

}  // namespace create_driver
