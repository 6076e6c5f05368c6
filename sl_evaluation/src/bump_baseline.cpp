#include "sl_evaluation/bump_baseline.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace sl_evaluation
{
namespace
{
constexpr double kPi = 3.14159265358979323846;
constexpr double kTurnTolerance = 0.01;  // rad: a turn this close to its target is done
constexpr double kTurnGain = 2.0;        // 1/s: the turn slows down over its last half radian
constexpr double kMinTurnSpeed = 0.3;    // rad/s: ... but not below this (or turn_speed)

void check(bool ok, const char* name, double value, const char* range)
{
  if (ok)
    return;
  std::ostringstream msg;
  msg << name << " must be in " << range << ", got " << value;
  throw std::invalid_argument(msg.str());
}
}  // namespace

void BumpBaselineConfig::validate() const
{
  check(forward_speed > 0.0 && forward_speed <= 0.5, "forward_speed", forward_speed, "(0, 0.5] m/s");
  check(back_speed > 0.0 && back_speed <= 0.5, "back_speed", back_speed, "(0, 0.5] m/s");
  check(back_distance > 0.0 && back_distance <= 0.5, "back_distance", back_distance, "(0, 0.5] m");
  check(max_back_distance >= back_distance && max_back_distance <= 1.0, "max_back_distance", max_back_distance,
        "[back_distance, 1] m");
  check(turn_speed > 0.0 && turn_speed <= 4.0, "turn_speed", turn_speed, "(0, 4] rad/s");
  check(min_turn > 0.0 && min_turn <= kPi, "min_turn", min_turn, "(0, pi] rad");
  check(max_turn >= min_turn && max_turn <= kPi, "max_turn", max_turn, "[min_turn, pi] rad");
  check(duration >= 0.0 && std::isfinite(duration), "duration", duration, "[0, inf) s");
  check(reset_interval > 0.0 && reset_interval <= 10.0, "reset_interval", reset_interval, "(0, 10] s");
}

BumpBaseline::BumpBaseline(const BumpBaselineConfig& config) : config_(config), rng_(config.seed)
{
  config_.validate();
}

const char* BumpBaseline::stateName(State state)
{
  switch (state)
  {
    case State::FORWARD:
      return "FORWARD";
    case State::BACK:
      return "BACK";
    case State::TURN:
      return "TURN";
    case State::DONE:
      return "DONE";
  }
  return "?";
}

void BumpBaseline::startBack(const BumpBaselineInput& in)
{
  state_ = State::BACK;
  ++bumps_;
  back_x_ = in.x;
  back_y_ = in.y;
  // Drawn at the contact, side first: the n-th contact of a seed always gets the same turn.
  const bool left = std::uniform_int_distribution<int>(0, 1)(rng_) == 1;
  const double angle = std::uniform_real_distribution<double>(config_.min_turn, config_.max_turn)(rng_);
  turn_target_ = left ? angle : -angle;
}

bool BumpBaseline::wantReset(double time)
{
  if (reset_ever_ && time - last_reset_ < config_.reset_interval)
    return false;
  reset_ever_ = true;
  last_reset_ = time;
  ++resets_;
  return true;
}

BumpBaselineCommand BumpBaseline::step(const BumpBaselineInput& in)
{
  BumpBaselineCommand cmd;  // stop
  if (!std::isfinite(in.time) || !std::isfinite(in.x) || !std::isfinite(in.y) || !std::isfinite(in.yaw))
    return cmd;
  if (!started_)
  {
    started_ = true;
    start_time_ = in.time;
  }
  else
  {
    travelled_ += std::hypot(in.x - last_x_, in.y - last_y_);
    if (state_ == State::TURN)
      turned_ += std::remainder(in.yaw - last_yaw_, 2.0 * kPi);
  }
  last_x_ = in.x;
  last_y_ = in.y;
  last_yaw_ = in.yaw;
  if (config_.duration > 0.0 && in.time - start_time_ >= config_.duration)
    state_ = State::DONE;

  if (state_ == State::FORWARD && (in.bumper || in.latched))
    startBack(in);
  if (state_ == State::TURN)
  {
    if (in.bumper)
      startBack(in);  // pressed while turning (the driver blocks the turn): back up again
    else if (in.latched)
    {
      cmd.reset_hazard = wantReset(in.time);  // the driver refuses turns until the latch clears
      return cmd;
    }
  }
  if (state_ == State::BACK)
  {
    const double backed = std::hypot(in.x - back_x_, in.y - back_y_);
    if (backed < config_.back_distance)
    {
      cmd.linear = -config_.back_speed;
      return cmd;
    }
    if (in.bumper || in.latched)
    {
      // Still pressed, or the latch outlived the contact: back on (up to max_back_distance) and ask
      // the driver to clear the latch once the bumper is free.
      if (backed < config_.max_back_distance)
        cmd.linear = -config_.back_speed;
      cmd.reset_hazard = !in.bumper && wantReset(in.time);
      return cmd;
    }
    state_ = State::TURN;
    turned_ = 0.0;
  }
  if (state_ == State::TURN)
  {
    const double sign = turn_target_ >= 0.0 ? 1.0 : -1.0;
    const double remaining = sign * (turn_target_ - turned_);
    if (remaining > kTurnTolerance)
    {
      const double slowest = std::min(kMinTurnSpeed, config_.turn_speed);
      cmd.angular = sign * std::clamp(kTurnGain * remaining, slowest, config_.turn_speed);
      return cmd;
    }
    state_ = State::FORWARD;
  }
  if (state_ == State::FORWARD)
    cmd.linear = config_.forward_speed;
  return cmd;  // DONE: stop
}

}  // namespace sl_evaluation
