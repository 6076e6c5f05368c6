/// @file status_codes.h
/// @brief Compile-time ties between the core's enums and the ObstacleStatus constants: status.cpp
/// copies the enum values onto the wire, so a change on either side must fail the build.
#pragma once

#include <cstdint>

#include "sl_msgs/ObstacleStatus.h"
#include "sl_obstacle/decision_maker.h"

namespace sl_obstacle
{
namespace status_codes
{
using S = sl_msgs::ObstacleStatus;

/// True when the enum value equals the message constant.
template <typename E>
constexpr bool same(E value, std::uint8_t constant)
{
  return static_cast<std::uint8_t>(value) == constant;
}

static_assert(same(State::STALE, S::STALE), "State::STALE");
static_assert(same(State::STOPPED, S::STOPPED), "State::STOPPED");
static_assert(same(State::BLOCKED, S::BLOCKED), "State::BLOCKED");
static_assert(same(State::TURNING, S::TURNING), "State::TURNING");
static_assert(same(State::SLOWING, S::SLOWING), "State::SLOWING");
static_assert(same(State::DRIVING, S::DRIVING), "State::DRIVING");
static_assert(same(State::BACKING_OFF, S::BACKING_OFF), "State::BACKING_OFF");

static_assert(same(Reason::NO_DATA, S::REASON_NO_DATA), "Reason::NO_DATA");
static_assert(same(Reason::STALE_DATA, S::REASON_STALE_DATA), "Reason::STALE_DATA");
static_assert(same(Reason::DISABLED, S::REASON_DISABLED), "Reason::DISABLED");
static_assert(same(Reason::DRIVER_UNAVAILABLE, S::REASON_DRIVER_UNAVAILABLE), "Reason::DRIVER_UNAVAILABLE");
static_assert(same(Reason::DRIVER_FAILED, S::REASON_DRIVER_FAILED), "Reason::DRIVER_FAILED");
static_assert(same(Reason::DRIVER_HAZARD, S::REASON_DRIVER_HAZARD), "Reason::DRIVER_HAZARD");
static_assert(same(Reason::LOW_COVERAGE, S::REASON_LOW_COVERAGE), "Reason::LOW_COVERAGE");
static_assert(same(Reason::OBSTACLE, S::REASON_OBSTACLE), "Reason::OBSTACLE");
static_assert(same(Reason::UNKNOWN_AHEAD, S::REASON_UNKNOWN_AHEAD), "Reason::UNKNOWN_AHEAD");
static_assert(same(Reason::TURNING, S::REASON_TURNING), "Reason::TURNING");
static_assert(same(Reason::LOOKING, S::REASON_LOOKING), "Reason::LOOKING");
static_assert(same(Reason::NO_FREE_DIRECTION, S::REASON_NO_FREE_DIRECTION), "Reason::NO_FREE_DIRECTION");
static_assert(same(Reason::WAITING_FOR_FRAME, S::REASON_WAITING_FOR_FRAME), "Reason::WAITING_FOR_FRAME");
static_assert(same(Reason::PATH_FREE, S::REASON_PATH_FREE), "Reason::PATH_FREE");
static_assert(same(Reason::SHORT_FREE_DISTANCE, S::REASON_SHORT_FREE_DISTANCE), "Reason::SHORT_FREE_DISTANCE");
static_assert(same(Reason::PARTIAL_COVERAGE, S::REASON_PARTIAL_COVERAGE), "Reason::PARTIAL_COVERAGE");
static_assert(same(Reason::NEARER_OBSTACLE, S::REASON_NEARER_OBSTACLE), "Reason::NEARER_OBSTACLE");
static_assert(same(Reason::EXTENDING, S::REASON_EXTENDING), "Reason::EXTENDING");
static_assert(same(Reason::GOAL_RUNNING, S::REASON_GOAL_RUNNING), "Reason::GOAL_RUNNING");
static_assert(same(Reason::BACKING_OFF, S::REASON_BACKING_OFF), "Reason::BACKING_OFF");
static_assert(same(Reason::NO_ODOMETRY, S::REASON_NO_ODOMETRY), "Reason::NO_ODOMETRY");
static_assert(same(Reason::CREEPING, S::REASON_CREEPING), "Reason::CREEPING");

static_assert(same(Command::NONE, S::COMMAND_NONE), "Command::NONE");
static_assert(same(Command::STOP, S::COMMAND_STOP), "Command::STOP");
static_assert(same(Command::DRIVE, S::COMMAND_DRIVE), "Command::DRIVE");
static_assert(same(Command::TURN, S::COMMAND_TURN), "Command::TURN");
}  // namespace status_codes
}  // namespace sl_obstacle
