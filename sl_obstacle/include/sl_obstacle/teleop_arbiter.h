/// @file teleop_arbiter.h
/// @brief Who commands the robot: autonomy, or the commands on cmd_vel_in (through the safety
/// filter) while they keep coming (ROS-free; time in seconds on the caller's clock).
#pragma once

namespace sl_obstacle
{
/**
 * @brief Arbitrates between autonomy and velocity commands from outside (teleoperation, a planner).
 *
 * In filter mode (@p always) the outside commands are the only ones. Otherwise a command takes over
 * from autonomy, and autonomy resumes `hold` seconds after the last command.
 */
class TeleopArbiter
{
public:
  /// @param always true: the outside commands always command (command_mode filter)
  explicit TeleopArbiter(bool always = false) : always_(always) {}

  /**
   * @brief A command arrived at @p now; outside commands keep control until now + @p hold.
   * @return true when this command takes over from autonomy (the caller stops autonomy's motion)
   */
  bool onCommand(double now, double hold)
  {
    commanded_ = true;
    until_ = now + hold;
    return !always_ && !active_;
  }

  /**
   * @brief Who commands at @p now.
   * @param[out] ended true once, at the first call after a takeover ended (the caller stops the
   *             robot and lets autonomy plan anew)
   * @return true while outside commands command
   */
  bool update(double now, bool& ended)
  {
    const bool active = always_ || (commanded_ && now < until_);
    ended = active_ && !active;
    active_ = active;
    return active;
  }

  /// The state of the last update().
  bool active() const { return active_; }

private:
  bool always_;
  bool commanded_ = false;
  double until_ = 0.0;
  bool active_ = false;
};
}  // namespace sl_obstacle
