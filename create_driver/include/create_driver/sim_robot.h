/// @file sim_robot.h
/// @brief A simulated iRobot Create: Open Interface state machine plus differential-drive
/// kinematics. Pure (no I/O, no clock): bytes in, bytes out, time advanced by step().
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "create_driver/odometry.h"
#include "create_driver/oi_commands.h"
#include "create_driver/sensor_packets.h"

namespace create_driver
{
/// Parameters of the simulated robot (SI units).
struct SimParams
{
  Model model = Model::CREATE_1;
  double wheel_base = 0.0;        ///< m; 0 = model default (0.258 Create, 0.235 Create 2)
  double max_wheel_accel = 0.0;   ///< m/s^2 per wheel; 0 = wheels follow commands at once
  double slip_left = 0.0;         ///< fraction [0, 1) of left wheel travel lost on the floor
  double slip_right = 0.0;        ///< fraction [0, 1) of right wheel travel lost on the floor
  double slip_noise = 0.0;        ///< std. dev. of an extra random slip fraction, per step
  double odom_noise = 0.0;        ///< std. dev. of the relative error of reported wheel travel, per step
  uint32_t seed = 1;              ///< random seed (runs are deterministic for a seed)
  bool block_on_contact = true;   ///< while a bumper is in contact, forward motion stalls the wheels
  double stream_period = 0.015;   ///< s between stream frames (15 ms per the spec)
  double max_step = 0.005;        ///< s, longest kinematic integration step
  Pose2D initial_pose;            ///< true pose at start, world frame
  size_t max_input_queue = 4096;  ///< bytes held while a Wait command blocks input; more are dropped
  /// s; > 0 models a hardware stop outside the Create: the wheels stop when the host sent no byte
  /// for this long. 0 (default): none, like the real Create, which executes its last Drive until
  /// told otherwise.
  double command_watchdog = 0.0;
  double battery_capacity_mah = 3000.0;
  double battery_charge_mah = 2700.0;
};

/// @brief Simulated Create behind the Open Interface.
///
/// Modes Off / Passive / Safe / Full as in the spec: in Off only Start is heard; in Passive
/// actuator commands are ignored; in Safe a wheel drop, or a cliff while driving forward (or
/// backward on a tight turn), stops the wheels and falls back to Passive; Full has no safety.
/// Sensors, Query List and Stream (header 19, n-bytes, ids and data, checksum) answer from the
/// simulated state; distance (19) and angle (20) count since they were last read and keep the
/// sub-unit remainder. Wait Time / Distance / Angle / Event hold all command input until done
/// (the stream keeps running). Scripts (Create 1) are stored and played once per Play Script
/// from the host; a Play Script inside a playing script is refused, so a script that plays
/// itself cannot loop the simulator forever. A Stream request whose frame would not fit its
/// 15 ms slot (streamPayloadLimit()) is refused and the previous stream kept. Refusals are
/// counted with a reason (refusedCommands(), lastRefusal()). Unknown bytes are ignored.
class SimRobot
{
public:
  /// @brief Creates a robot in mode Off at the initial pose.
  explicit SimRobot(const SimParams& params = SimParams());

  /// @brief Bytes from the host; commands execute immediately unless a Wait holds input.
  void receive(const uint8_t* data, size_t len);
  /// @brief Advances simulated time by @p dt seconds, split into steps <= max_step. A single
  /// call advances at most 1 s (a host that stalled does not make the robot jump).
  void step(double dt);
  /// @brief Appends the bytes the robot sent since the last call, and clears them.
  void takeOutput(Bytes& out);

  /// @brief Inserts @p bytes in the middle of the next stream frame (or sends them at once when
  /// not streaming): a corrupt frame plus line noise.
  void injectIntoNextFrame(const Bytes& bytes);
  /// @brief Sends @p bytes at once, between frames.
  void injectNow(const Bytes& bytes);

  /// @brief Bumper contact, bits as packet 7 (bit 0 right, bit 1 left).
  void setContact(uint8_t bits) { contact_ = bits & bumps::BUMP_MASK; }
  /// @brief Cliff sensors: bit 0 left, bit 1 front left, bit 2 front right, bit 3 right.
  void setCliffs(uint8_t bits) { cliffs_ = bits & 0x0F; }
  /// @brief Wheel drops, bits as packet 7 (0x04 right, 0x08 left, 0x10 caster).
  void setWheelDrops(uint8_t bits) { wheel_drops_ = bits & bumps::WHEEL_DROP_MASK; }
  /// @brief Buttons (packet 18 bits).
  void setButtons(uint8_t bits) { buttons_ = bits; }
  /// @brief Moves the robot (true pose); odometry counters are not affected.
  void setPose(const Pose2D& pose) { pose_ = pose; }
  /// @brief Power cycle: mode Off, wheels stopped, stream and script cleared, input dropped.
  void powerCycle();

  /// @brief True pose in the world frame.
  const Pose2D& truePose() const { return pose_; }
  /// @brief True linear velocity over the floor, m/s.
  double trueLinearVelocity() const { return true_v_; }
  /// @brief True angular velocity, rad/s.
  double trueAngularVelocity() const { return true_w_; }
  /// @brief Current OI mode.
  OiMode mode() const { return mode_; }
  /// @brief Commanded left wheel speed, m/s.
  double commandedLeft() const { return left_cmd_; }
  /// @brief Commanded right wheel speed, m/s.
  double commandedRight() const { return right_cmd_; }
  /// @brief True while a Wait command holds command input.
  bool waiting() const { return wait_ != WaitKind::NONE; }
  /// @brief True while a non-empty stream runs unpaused.
  bool streaming() const { return mode_ != OiMode::OFF && !stream_ids_.empty() && !stream_paused_; }
  /// @brief Current contact bits.
  uint8_t contact() const { return contact_; }
  /// @brief Complete commands executed.
  uint64_t commands() const { return commands_; }
  /// @brief Bytes received.
  uint64_t bytesReceived() const { return bytes_received_; }
  /// @brief Bytes produced (replies, frames, injected bytes).
  uint64_t bytesSent() const { return bytes_sent_; }
  /// @brief Stream frames produced.
  uint64_t framesSent() const { return frames_sent_; }
  /// @brief Parameters in use.
  const SimParams& params() const { return params_; }
  /// @brief Times SimParams::command_watchdog stopped the wheels.
  uint64_t watchdogStops() const { return watchdog_stops_; }
  /// @brief Bytes ignored (unknown opcodes, Off mode, input overflow).
  uint64_t ignoredBytes() const { return ignored_bytes_; }
  /// @brief Complete commands refused (also counted in commands()): a Stream request too large
  /// for its slot, a Play Script inside a playing script.
  uint64_t refusedCommands() const { return refused_commands_; }
  /// @brief Why the last command was refused ("" if none was).
  const std::string& lastRefusal() const { return last_refusal_; }
  /// @brief Bytes in the input queue: held by a Wait, an incomplete command, or a script's rest.
  size_t inputQueued() const { return input_.size(); }
  /// @brief Largest stream payload (the frame's n-bytes: ids plus data) that fits one stream
  /// period at the current baud rate, 10 bits a byte, less header, n-bytes and checksum: 83 bytes
  /// for a Create at 57600 baud, 169 for a Create 2 at 115200 (15 ms); never over 255, the most
  /// the n-bytes field can count.
  size_t streamPayloadLimit() const;
  /// @brief Simulated time, s.
  double time() const { return time_; }
  /// @brief Wheel base in use, m.
  double wheelBase() const { return wheel_base_; }
  /// @brief Raw sensor values as they would be reported now (19/20 not consumed).
  const SensorState& sensorState();

private:
  enum class WaitKind
  {
    NONE,
    TIME,
    DISTANCE,
    ANGLE,
    EVENT
  };

  int commandLength(size_t avail) const;
  void processInput();
  void consumeInput(size_t n);
  void refuse(const std::string& reason);
  void execute(const uint8_t* cmd, size_t len);
  // The command groups execute() dispatches to.
  void executeMode(uint8_t op);
  void executeDrive(const uint8_t* cmd);  // only called in Safe or Full
  void executeSensors(const uint8_t* cmd, size_t len);
  void requestStream(const uint8_t* cmd, size_t len);
  void executeScript(const uint8_t* cmd, size_t len);
  void startWait(const uint8_t* cmd);
  void setMode(OiMode mode);
  void stopWheels();
  void setWheels(double left, double right);
  void integrate(double dt);
  void safetyCheck();
  /// SimParams::command_watchdog: stops turning wheels when the host has been silent too long.
  void hostWatchdog();
  bool waitDone() const;
  bool eventTrue(int event) const;
  void refreshState();
  void appendPacket(uint8_t id, Bytes& out);
  void emitFrame();
  void emit(const Bytes& bytes);
  void emit(const uint8_t* data, size_t len);

  SimParams params_;
  double wheel_base_;
  double m_per_count_;
  std::mt19937 rng_;
  std::normal_distribution<double> normal_{ 0.0, 1.0 };

  OiMode mode_ = OiMode::OFF;
  std::vector<uint8_t> input_;
  Bytes cmd_;
  Bytes output_;
  Bytes frame_;
  Bytes pending_garbage_;
  Bytes script_;
  size_t script_queued_ = 0;       // bytes at the front of input_ that a Play Script put there
  bool executing_script_ = false;  // the command being executed came from a script
  unsigned baud_;                  // as last set by Baud (the pty ignores it; it sizes the stream slot)
  std::vector<uint8_t> stream_ids_;
  bool stream_paused_ = false;
  double stream_phase_ = 0.0;

  double left_cmd_ = 0.0, right_cmd_ = 0.0;  // m/s commanded
  double left_act_ = 0.0, right_act_ = 0.0;  // m/s actual wheel speed
  int req_velocity_ = 0, req_radius_ = 0, req_right_ = 0, req_left_ = 0;
  Pose2D pose_;
  double true_v_ = 0.0, true_w_ = 0.0;
  double distance_acc_mm_ = 0.0;
  double angle_acc_deg_ = 0.0;
  double enc_left_ = 0.0, enc_right_ = 0.0;  // counts
  double charge_mah_;

  WaitKind wait_ = WaitKind::NONE;
  double wait_target_ = 0.0;
  double wait_progress_ = 0.0;
  int wait_event_ = 0;

  uint8_t contact_ = 0, cliffs_ = 0, wheel_drops_ = 0, buttons_ = 0;
  SensorState state_;
  double time_ = 0.0;
  uint64_t commands_ = 0, bytes_received_ = 0, bytes_sent_ = 0, frames_sent_ = 0, ignored_bytes_ = 0;
  uint64_t refused_commands_ = 0;
  std::string last_refusal_;
  double last_input_time_ = 0.0;  // simulated time of the host's newest byte
  uint64_t watchdog_stops_ = 0;
};

}  // namespace create_driver
