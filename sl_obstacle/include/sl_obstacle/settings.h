/// @file settings.h
/// @brief All parameters of the obstacle pipeline, validated together.
#pragma once

#include "sl_obstacle/decision_maker.h"
#include "sl_obstacle/safety_filter.h"
#include "sl_obstacle/volume_checker.h"
#include "sl_obstacle/world_model.h"

namespace sl_obstacle
{
/// Analysis and decision parameters; validate() also checks the relations between the two.
struct Settings
{
  CheckerParams checker;     ///< working volume, coverage, noise rejection
  DecisionParams decision;   ///< margins, speeds, turning, staleness
  WorldParams world;         ///< local map and path checks (its height band is the volume's)
  FilterParams filter;       ///< safety filter for cmd_vel_in (footprint, margin, timeouts shared)
  double teleop_hold = 2.0;  ///< s a command on cmd_vel_in takes over from autonomy

  /// @throws std::invalid_argument when invalid, its message starting with the offending parameter's name.
  void validate() const;
};
}  // namespace sl_obstacle
