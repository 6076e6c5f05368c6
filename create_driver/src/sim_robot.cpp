#include "create_driver/sim_robot.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "create_driver/stream_parser.h"

namespace create_driver
{
namespace
{
constexpr double kRobotRadius = 0.1675;  // m, half the Create's 335 mm diameter
constexpr double kRadToDeg = 180.0 / M_PI;
constexpr size_t kMaxScript = 100;
// Header, n-bytes and checksum around a stream frame's payload.
constexpr size_t kStreamFrameOverhead = 3;
// Baud rates of the Baud command's codes 0..11.
constexpr unsigned kBaudRates[] = { 300, 600, 1200, 2400, 4800, 9600, 14400, 19200, 28800, 38400, 57600, 115200 };

int16_t clamp16(double v)
{
  return static_cast<int16_t>(std::clamp(v, -32768.0, 32767.0));
}
}  // namespace

SimRobot::SimRobot(const SimParams& params)
  : params_(params),
    wheel_base_(params.wheel_base > 0.0 ? params.wheel_base : defaultWheelBase(params.model)),
    m_per_count_(M_PI * 0.072 / 508.8),
    rng_(params.seed),
    baud_(defaultBaud(params.model)),
    pose_(params.initial_pose),
    charge_mah_(params.battery_charge_mah)
{
  input_.reserve(params.max_input_queue);
  output_.reserve(1024);
  frame_.reserve(256);
  cmd_.reserve(600);
}

void SimRobot::powerCycle()
{
  mode_ = OiMode::OFF;
  stopWheels();
  left_act_ = right_act_ = 0.0;
  input_.clear();
  script_queued_ = 0;
  baud_ = defaultBaud(params_.model);
  stream_ids_.clear();
  stream_paused_ = false;
  script_.clear();
  wait_ = WaitKind::NONE;
  distance_acc_mm_ = angle_acc_deg_ = 0.0;
}

void SimRobot::receive(const uint8_t* data, size_t len)
{
  bytes_received_ += len;
  if (len > 0)
    last_input_time_ = time_;
  const size_t room = params_.max_input_queue > input_.size() ? params_.max_input_queue - input_.size() : 0;
  const size_t take = std::min(room, len);
  input_.insert(input_.end(), data, data + take);
  ignored_bytes_ += len - take;
  processInput();
}

int SimRobot::commandLength(size_t avail) const
{
  // Returns the full length of the command at input_[0], 0 if more bytes are needed to know or to
  // complete it, -1 if the opcode is unknown on this model.
  const uint8_t op = input_[0];
  const bool c1 = params_.model == Model::CREATE_1;
  auto need = [&](size_t n) { return avail >= n ? static_cast<int>(n) : 0; };
  switch (op)
  {
    case oi::START:
    case oi::CONTROL:
    case oi::SAFE:
    case oi::FULL:
    case oi::SPOT:
    case oi::COVER:
    case oi::COVER_AND_DOCK:
      return 1;
    case oi::POWER:
      return c1 ? -1 : 1;
    case oi::DEMO:
      return c1 ? need(2) : 1;
    case oi::BAUD:
    case oi::LOW_SIDE_DRIVERS:
    case oi::PLAY_SONG:
    case oi::SENSORS:
    case oi::DIGITAL_OUTPUTS:
    case oi::PAUSE_RESUME_STREAM:
      return need(2);
    case oi::LEDS:
    case oi::PWM_LOW_SIDE_DRIVERS:
      return need(4);
    case oi::DRIVE:
    case oi::DRIVE_DIRECT:
      return need(5);
    case oi::DRIVE_PWM:
      return c1 ? -1 : need(5);
    case oi::SONG:
      return avail >= 3 ? need(3 + 2 * static_cast<size_t>(input_[2])) : 0;
    case oi::STREAM:
    case oi::QUERY_LIST:
      return avail >= 2 ? need(2 + static_cast<size_t>(input_[1])) : 0;
    case oi::SEND_IR:
    case oi::WAIT_TIME:
    case oi::WAIT_EVENT:
      return c1 ? need(2) : -1;
    case oi::SCRIPT:
      return c1 ? (avail >= 2 ? need(2 + static_cast<size_t>(input_[1])) : 0) : -1;
    case oi::PLAY_SCRIPT:
    case oi::SHOW_SCRIPT:
      return c1 ? 1 : -1;
    case oi::WAIT_DISTANCE:
    case oi::WAIT_ANGLE:
      return c1 ? need(3) : -1;
    case 162:  // Scheduling LEDs
      return c1 ? -1 : need(3);
    case 163:  // Digit LEDs raw
    case 164:  // Digit LEDs ASCII
      return c1 ? -1 : need(5);
    case 165:  // Buttons
      return c1 ? -1 : need(2);
    case 167:  // Schedule
      return c1 ? -1 : need(16);
    case 168:  // Set day/time
      return c1 ? -1 : need(4);
    case oi::STOP:
      return c1 ? -1 : 1;
    default:
      return -1;
  }
}

void SimRobot::processInput()
{
  size_t pos = 0;
  while (pos < input_.size() && wait_ == WaitKind::NONE)
  {
    if (mode_ == OiMode::OFF && input_[pos] != oi::START)
    {
      // Off: the robot only listens for Start.
      ++ignored_bytes_;
      ++pos;
      continue;
    }
    // commandLength() looks at input_ from index 0: compact first.
    if (pos > 0)
    {
      consumeInput(pos);
      pos = 0;
    }
    const int len = commandLength(input_.size());
    if (len < 0)
    {
      ++ignored_bytes_;
      ++pos;
      continue;
    }
    if (len == 0)
      break;  // incomplete command: wait for more bytes
    // A command that starts in a played script's bytes is part of the script.
    executing_script_ = script_queued_ > 0;
    // Copy out: execute() may modify input_ (Play Script).
    cmd_.assign(input_.begin(), input_.begin() + len);
    consumeInput(static_cast<size_t>(len));
    execute(cmd_.data(), cmd_.size());
    executing_script_ = false;
  }
  if (pos > 0)
    consumeInput(pos);
}

void SimRobot::consumeInput(size_t n)
{
  input_.erase(input_.begin(), input_.begin() + static_cast<std::ptrdiff_t>(n));
  script_queued_ -= std::min(n, script_queued_);
}

void SimRobot::refuse(const std::string& reason)
{
  ++refused_commands_;
  last_refusal_ = reason;
}

size_t SimRobot::streamPayloadLimit() const
{
  const double slot_bytes = std::floor(baud_ / 10.0 * params_.stream_period);
  const double payload = slot_bytes - static_cast<double>(kStreamFrameOverhead);
  return payload <= 0.0 ? 0 : std::min<size_t>(255, static_cast<size_t>(payload));
}

void SimRobot::setMode(OiMode mode)
{
  if (mode == OiMode::PASSIVE || mode == OiMode::OFF)
    stopWheels();
  mode_ = mode;
}

void SimRobot::stopWheels()
{
  left_cmd_ = right_cmd_ = 0.0;
  req_velocity_ = req_radius_ = req_right_ = req_left_ = 0;
}

void SimRobot::setWheels(double left, double right)
{
  left_cmd_ = left;
  right_cmd_ = right;
  req_left_ = static_cast<int>(std::lround(left * 1000.0));
  req_right_ = static_cast<int>(std::lround(right * 1000.0));
}

void SimRobot::execute(const uint8_t* cmd, size_t len)
{
  ++commands_;
  const uint8_t op = cmd[0];
  switch (op)
  {
    case oi::START:
    case oi::CONTROL:
    case oi::SAFE:
    case oi::FULL:
    case oi::POWER:
    case oi::SPOT:
    case oi::COVER:
    case oi::DEMO:
    case oi::COVER_AND_DOCK:
    case oi::STOP:
      executeMode(op);
      break;
    case oi::DRIVE:
    case oi::DRIVE_DIRECT:
    case oi::DRIVE_PWM:
      if (mode_ == OiMode::SAFE || mode_ == OiMode::FULL)
        executeDrive(cmd);
      break;
    case oi::SENSORS:
    case oi::QUERY_LIST:
    case oi::STREAM:
    case oi::PAUSE_RESUME_STREAM:
      executeSensors(cmd, len);
      break;
    case oi::SCRIPT:
    case oi::PLAY_SCRIPT:
    case oi::SHOW_SCRIPT:
      executeScript(cmd, len);
      break;
    case oi::WAIT_TIME:
    case oi::WAIT_DISTANCE:
    case oi::WAIT_ANGLE:
    case oi::WAIT_EVENT:
      startWait(cmd);
      break;
    case oi::BAUD:
      // The pty has no baud rate; the rate only sizes the stream slot.
      if (cmd[1] < sizeof(kBaudRates) / sizeof(kBaudRates[0]))
        baud_ = kBaudRates[cmd[1]];
      break;
    default:
      // Songs, LEDs, low side drivers, outputs, IR, Create 2 schedule/LED/button commands:
      // accepted and ignored.
      break;
  }
  if (wait_ != WaitKind::NONE && waitDone())
    wait_ = WaitKind::NONE;
}

void SimRobot::executeMode(uint8_t op)
{
  switch (op)
  {
    case oi::START:
      setMode(OiMode::PASSIVE);
      break;
    case oi::CONTROL:
    case oi::SAFE:
      setMode(OiMode::SAFE);
      break;
    case oi::FULL:
      setMode(OiMode::FULL);
      break;
    case oi::STOP:
      setMode(OiMode::OFF);
      stream_ids_.clear();
      break;
    default:
      // Built-in behaviours (Power, Spot, Cover, Demo, Cover and Dock) are not simulated; like the
      // real robot the OI goes to Passive.
      setMode(OiMode::PASSIVE);
      break;
  }
}

void SimRobot::executeDrive(const uint8_t* cmd)
{
  switch (cmd[0])
  {
    case oi::DRIVE:
    {
      const int v = std::clamp<int>(oi::readInt16(cmd + 1), -oi::MAX_VELOCITY_MM_S, oi::MAX_VELOCITY_MM_S);
      const int r = oi::readInt16(cmd + 3);
      const WheelSpeeds w = driveRadiusToWheels(v, r, wheel_base_);
      setWheels(w.left, w.right);
      req_velocity_ = v;
      req_radius_ = r;
      break;
    }
    case oi::DRIVE_DIRECT:
    {
      const int right = std::clamp<int>(oi::readInt16(cmd + 1), -oi::MAX_VELOCITY_MM_S, oi::MAX_VELOCITY_MM_S);
      const int left = std::clamp<int>(oi::readInt16(cmd + 3), -oi::MAX_VELOCITY_MM_S, oi::MAX_VELOCITY_MM_S);
      setWheels(left / 1000.0, right / 1000.0);
      req_velocity_ = (left + right) / 2;
      req_radius_ = 0;
      break;
    }
    default:  // Drive PWM
    {
      const int right = std::clamp<int>(oi::readInt16(cmd + 1), -255, 255);
      const int left = std::clamp<int>(oi::readInt16(cmd + 3), -255, 255);
      setWheels(0.5 * left / 255.0, 0.5 * right / 255.0);
      break;
    }
  }
}

void SimRobot::executeSensors(const uint8_t* cmd, size_t len)
{
  switch (cmd[0])
  {
    case oi::SENSORS:
      if (isValidPacket(cmd[1], params_.model))
      {
        frame_.clear();
        appendPacket(cmd[1], frame_);
        emit(frame_);
      }
      break;
    case oi::QUERY_LIST:
      frame_.clear();
      for (size_t i = 2; i < len; ++i)
        if (isValidPacket(cmd[i], params_.model))
          appendPacket(cmd[i], frame_);
      emit(frame_);
      break;
    case oi::STREAM:
      requestStream(cmd, len);
      break;
    default:  // Pause/Resume Stream
      if (stream_paused_ && cmd[1] != 0)
        stream_phase_ = 0.0;
      stream_paused_ = cmd[1] == 0;
      break;
  }
}

void SimRobot::requestStream(const uint8_t* cmd, size_t len)
{
  // The frame's n-bytes counts ids and data. Over 255 it cannot be sent at all (the length
  // byte was clamped and every frame was corrupt); over the slot a real robot's frames
  // overrun each other. Either way the request is refused and the previous stream kept.
  size_t payload = 0;
  for (size_t i = 2; i < len; ++i)
    if (isValidPacket(cmd[i], params_.model))
      payload += 1 + packetSize(cmd[i], params_.model);
  const size_t limit = streamPayloadLimit();
  if (payload > limit)
  {
    refuse("Stream refused: " + std::to_string(payload) + " payload bytes, more than the " + std::to_string(limit) +
           " that fit a " + std::to_string(std::lround(params_.stream_period * 1000.0)) + " ms frame at " +
           std::to_string(baud_) + " baud; the previous stream continues");
    return;
  }
  stream_ids_.clear();
  for (size_t i = 2; i < len; ++i)
    if (isValidPacket(cmd[i], params_.model))
      stream_ids_.push_back(cmd[i]);
  stream_paused_ = false;
  stream_phase_ = 0.0;
}

void SimRobot::executeScript(const uint8_t* cmd, size_t len)
{
  switch (cmd[0])
  {
    case oi::SCRIPT:
      script_.assign(cmd + 2, cmd + std::min(len, 2 + kMaxScript));
      break;
    case oi::PLAY_SCRIPT:
      // Once per Play Script from the host. Played from inside a script it would re-queue the
      // script for ever (128 131 152 1 153 153 hung create_sim), so it is refused there.
      if (executing_script_)
      {
        refuse("Play Script inside a script ignored: a script plays once per Play Script from the host");
        break;
      }
      input_.insert(input_.begin(), script_.begin(), script_.end());
      script_queued_ = script_.size();
      break;
    default:  // Show Script
      frame_.clear();
      frame_.push_back(static_cast<uint8_t>(script_.size()));
      frame_.insert(frame_.end(), script_.begin(), script_.end());
      emit(frame_);
      break;
  }
}

void SimRobot::startWait(const uint8_t* cmd)
{
  switch (cmd[0])
  {
    case oi::WAIT_TIME:
      wait_ = WaitKind::TIME;
      wait_target_ = cmd[1] / 10.0;
      wait_progress_ = 0.0;
      break;
    case oi::WAIT_DISTANCE:
      wait_ = WaitKind::DISTANCE;
      wait_target_ = oi::readInt16(cmd + 1);
      wait_progress_ = 0.0;
      break;
    case oi::WAIT_ANGLE:
      wait_ = WaitKind::ANGLE;
      wait_target_ = oi::readInt16(cmd + 1);
      wait_progress_ = 0.0;
      break;
    default:  // Wait Event
      wait_ = WaitKind::EVENT;
      wait_event_ = static_cast<int8_t>(cmd[1]);
      break;
  }
}

bool SimRobot::eventTrue(int event) const
{
  const uint8_t b7 = static_cast<uint8_t>(contact_ | wheel_drops_);
  switch (event)
  {
    case 1:
      return (b7 & bumps::WHEEL_DROP_MASK) != 0;
    case 2:
      return (b7 & bumps::WHEEL_DROP_CASTER) != 0;
    case 3:
      return (b7 & bumps::WHEEL_DROP_LEFT) != 0;
    case 4:
      return (b7 & bumps::WHEEL_DROP_RIGHT) != 0;
    case 5:
      return (b7 & bumps::BUMP_MASK) != 0;
    case 6:
      return (b7 & bumps::BUMP_LEFT) != 0;
    case 7:
      return (b7 & bumps::BUMP_RIGHT) != 0;
    case 10:
      return cliffs_ != 0;
    case 11:
      return (cliffs_ & 0x01) != 0;
    case 12:
      return (cliffs_ & 0x02) != 0;
    case 13:
      return (cliffs_ & 0x04) != 0;
    case 14:
      return (cliffs_ & 0x08) != 0;
    case 16:
      return (buttons_ & buttons::CREATE1_ADVANCE) != 0;
    case 17:
      return (buttons_ & buttons::CREATE1_PLAY) != 0;
    case 22:
      return mode_ == OiMode::PASSIVE;
    default:
      return false;  // virtual wall, wall, home base, digital inputs: never present here
  }
}

bool SimRobot::waitDone() const
{
  switch (wait_)
  {
    case WaitKind::NONE:
      return true;
    case WaitKind::TIME:
      return wait_progress_ >= wait_target_;
    case WaitKind::DISTANCE:
    case WaitKind::ANGLE:
      return wait_target_ >= 0.0 ? wait_progress_ >= wait_target_ : wait_progress_ <= wait_target_;
    case WaitKind::EVENT:
      return wait_event_ >= 0 ? eventTrue(wait_event_) : !eventTrue(-wait_event_);
  }
  return true;
}

void SimRobot::step(double dt)
{
  if (!(dt > 0.0))
    return;
  dt = std::min(dt, 1.0);  // a stalled host does not make the robot jump
  while (dt > 1e-12)
  {
    const double h = std::min(dt, params_.max_step);
    dt -= h;
    time_ += h;
    integrate(h);
    safetyCheck();
    hostWatchdog();
    if (wait_ != WaitKind::NONE)
    {
      if (wait_ == WaitKind::TIME)
        wait_progress_ += h;
      if (waitDone())
      {
        wait_ = WaitKind::NONE;
        processInput();
      }
    }
    stream_phase_ += h;
    if (stream_phase_ >= params_.stream_period - 1e-9)
    {
      stream_phase_ = std::min(stream_phase_ - params_.stream_period, params_.stream_period);
      if (streaming())
        emitFrame();
    }
  }
  if (!pending_garbage_.empty() && !streaming())
  {
    emit(pending_garbage_);
    pending_garbage_.clear();
  }
}

void SimRobot::integrate(double h)
{
  // Wheel dynamics.
  auto approach = [&](double current, double target)
  {
    if (params_.max_wheel_accel <= 0.0)
      return target;
    const double step = params_.max_wheel_accel * h;
    return current + std::clamp(target - current, -step, step);
  };
  left_act_ = approach(left_act_, left_cmd_);
  right_act_ = approach(right_act_, right_cmd_);

  double dl = left_act_ * h;
  double dr = right_act_ * h;
  if (params_.block_on_contact && contact_ != 0 && dl + dr > 0.0)
  {
    dl = 0.0;  // pushing against the obstacle: the wheels stall
    dr = 0.0;
  }
  // Reported wheel travel (what the robot's odometry sees), with noise.
  double dl_rep = dl;
  double dr_rep = dr;
  if (params_.odom_noise > 0.0)
  {
    dl_rep *= 1.0 + params_.odom_noise * normal_(rng_);
    dr_rep *= 1.0 + params_.odom_noise * normal_(rng_);
  }
  // True travel over the floor, with slip.
  auto slip = [&](double base)
  {
    double s = base;
    if (params_.slip_noise > 0.0)
      s += std::fabs(params_.slip_noise * normal_(rng_));
    return std::clamp(s, 0.0, 1.0);
  };
  const double dl_true = dl * (1.0 - slip(params_.slip_left));
  const double dr_true = dr * (1.0 - slip(params_.slip_right));

  const double d = 0.5 * (dl_true + dr_true);
  const double dth = (dr_true - dl_true) / wheel_base_;
  const double mid = pose_.yaw + 0.5 * dth;
  pose_.x += d * std::cos(mid);
  pose_.y += d * std::sin(mid);
  pose_.yaw = normalizeAngle(pose_.yaw + dth);
  true_v_ = d / h;
  true_w_ = dth / h;

  const double d_rep_mm = 500.0 * (dl_rep + dr_rep);
  const double dth_rep_deg = (dr_rep - dl_rep) / wheel_base_ * kRadToDeg;
  distance_acc_mm_ += d_rep_mm;
  angle_acc_deg_ += dth_rep_deg;
  enc_left_ += dl_rep / m_per_count_;
  enc_right_ += dr_rep / m_per_count_;
  if (wait_ == WaitKind::DISTANCE)
    wait_progress_ += d_rep_mm;
  else if (wait_ == WaitKind::ANGLE)
    wait_progress_ += dth_rep_deg;

  // Battery: a quiescent draw plus the motors.
  const double current_ma = 200.0 + 1500.0 * (std::fabs(left_act_) + std::fabs(right_act_));
  charge_mah_ = std::max(0.0, charge_mah_ - current_ma * h / 3600.0);
}

void SimRobot::safetyCheck()
{
  if (mode_ != OiMode::SAFE)
    return;
  if (wheel_drops_ != 0)
  {
    setMode(OiMode::PASSIVE);
    return;
  }
  if (cliffs_ != 0)
  {
    const double v = 0.5 * (left_cmd_ + right_cmd_);
    const double w = (right_cmd_ - left_cmd_) / wheel_base_;
    const bool forward = v > 1e-6;
    const bool tight_backward = v < -1e-6 && std::fabs(w) > 1e-9 && std::fabs(v / w) < kRobotRadius;
    const bool in_place = std::fabs(v) <= 1e-6 && std::fabs(w) > 1e-9;
    if (forward || tight_backward || in_place)
      setMode(OiMode::PASSIVE);
  }
}

void SimRobot::hostWatchdog()
{
  if (params_.command_watchdog > 0.0 && time_ - last_input_time_ > params_.command_watchdog &&
      (left_cmd_ != 0.0 || right_cmd_ != 0.0))
  {
    stopWheels();
    ++watchdog_stops_;
  }
}

void SimRobot::refreshState()
{
  SensorState& s = state_;
  s.set(packet::BUMPS_WHEEL_DROPS, contact_ | wheel_drops_);
  s.set(packet::WALL, 0);
  s.set(packet::CLIFF_LEFT, (cliffs_ & 0x01) ? 1 : 0);
  s.set(packet::CLIFF_FRONT_LEFT, (cliffs_ & 0x02) ? 1 : 0);
  s.set(packet::CLIFF_FRONT_RIGHT, (cliffs_ & 0x04) ? 1 : 0);
  s.set(packet::CLIFF_RIGHT, (cliffs_ & 0x08) ? 1 : 0);
  s.set(packet::BUTTONS, buttons_);
  s.set(packet::CHARGING_STATE, 0);
  const double frac = params_.battery_capacity_mah > 0.0 ? charge_mah_ / params_.battery_capacity_mah : 0.0;
  s.set(packet::VOLTAGE, static_cast<int32_t>(14000.0 + 3000.0 * frac));
  s.set(packet::CURRENT, -static_cast<int32_t>(200.0 + 1500.0 * (std::fabs(left_act_) + std::fabs(right_act_))));
  s.set(packet::TEMPERATURE, 25);
  s.set(packet::BATTERY_CHARGE, static_cast<int32_t>(charge_mah_));
  s.set(packet::BATTERY_CAPACITY, static_cast<int32_t>(params_.battery_capacity_mah));
  for (uint8_t i = 0; i < 4; ++i)
    s.set(static_cast<uint8_t>(packet::CLIFF_LEFT_SIGNAL + i), (cliffs_ >> i) & 1 ? 20 : 1500);
  s.set(packet::OI_MODE, static_cast<int32_t>(mode_));
  s.set(packet::NUM_STREAM_PACKETS, static_cast<int32_t>(stream_ids_.size()));
  s.set(packet::REQUESTED_VELOCITY, req_velocity_);
  s.set(packet::REQUESTED_RADIUS, req_radius_);
  s.set(packet::REQUESTED_RIGHT_VELOCITY, req_right_);
  s.set(packet::REQUESTED_LEFT_VELOCITY, req_left_);
  s.set(packet::LEFT_ENCODER_COUNTS, static_cast<int32_t>(static_cast<int64_t>(std::floor(enc_left_)) & 0xFFFF));
  s.set(packet::RIGHT_ENCODER_COUNTS, static_cast<int32_t>(static_cast<int64_t>(std::floor(enc_right_)) & 0xFFFF));
  s.set(packet::DISTANCE, static_cast<int32_t>(std::trunc(distance_acc_mm_)));
  s.set(packet::ANGLE, static_cast<int32_t>(std::trunc(angle_acc_deg_)));
}

const SensorState& SimRobot::sensorState()
{
  refreshState();
  return state_;
}

void SimRobot::appendPacket(uint8_t id, Bytes& out)
{
  refreshState();
  for (uint8_t m : packetMembers(id))
  {
    // Reading distance or angle resets them; the fraction below one unit is kept.
    if (m == packet::DISTANCE)
    {
      const int16_t r = clamp16(std::trunc(distance_acc_mm_));
      state_.set(packet::DISTANCE, r);
      distance_acc_mm_ -= r;
    }
    else if (m == packet::ANGLE)
    {
      const int16_t r = clamp16(std::trunc(angle_acc_deg_));
      state_.set(packet::ANGLE, r);
      angle_acc_deg_ -= r;
    }
  }
  encodePacket(id, state_, params_.model, out);
}

void SimRobot::emitFrame()
{
  frame_.clear();
  frame_.push_back(oi::STREAM_HEADER);
  frame_.push_back(0);
  for (uint8_t id : stream_ids_)
  {
    frame_.push_back(id);
    appendPacket(id, frame_);
  }
  // Fits: Stream requests over streamPayloadLimit() (<= 255) are refused.
  frame_[1] = static_cast<uint8_t>(frame_.size() - 2);
  frame_.push_back(streamChecksum(frame_.data(), frame_.size()));
  ++frames_sent_;
  if (!pending_garbage_.empty())
  {
    const size_t half = frame_.size() / 2;
    emit(frame_.data(), half);
    emit(pending_garbage_);
    emit(frame_.data() + half, frame_.size() - half);
    pending_garbage_.clear();
    return;
  }
  emit(frame_);
}

void SimRobot::injectIntoNextFrame(const Bytes& bytes)
{
  pending_garbage_.insert(pending_garbage_.end(), bytes.begin(), bytes.end());
}

void SimRobot::injectNow(const Bytes& bytes)
{
  emit(bytes);
}

void SimRobot::emit(const Bytes& bytes)
{
  emit(bytes.data(), bytes.size());
}

void SimRobot::emit(const uint8_t* data, size_t len)
{
  output_.insert(output_.end(), data, data + len);
  bytes_sent_ += len;
}

void SimRobot::takeOutput(Bytes& out)
{
  out.insert(out.end(), output_.begin(), output_.end());
  output_.clear();
}

}  // namespace create_driver
