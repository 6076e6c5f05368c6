// The driver's drive_distance result as the decision maker's GoalEnd, with a short text.
#pragma once

#include <string>

#include <sl_msgs/DriveDistanceResult.h>

#include "sl_obstacle/decision_maker.h"

namespace sl_obstacle
{
/// How a drive_distance goal ended: from the driver's result @p result (null when none came) and
/// the action's final state @p state (its text, for a goal without result). @p what gets a short
/// description ("reached", "bumper", "timeout: <the driver's message>").
GoalEnd goalEnd(const sl_msgs::DriveDistanceResult* result, const std::string& state, std::string& what);
}  // namespace sl_obstacle
