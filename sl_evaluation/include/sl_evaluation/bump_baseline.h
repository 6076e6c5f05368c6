#pragma once
/// @file bump_baseline.h
/// @brief The bump-and-turn baseline of the cleaning-coverage benchmark (ROS-free): drive straight
/// until the bumper touches, back up a little by odometry, turn a random angle, drive straight again.
/// A benchmark reference that drives the (simulated) Create directly, not a product mode.

#include <cmath>
#include <cstdint>
#include <random>
#include <string>

namespace sl_evaluation
{

/// @brief Settings of BumpBaseline. Defaults: the kinematic baseline of sl_navigation's coverage
/// tests (0.3 m/s forward, back 0.05 m at 0.1 m/s, turn 0.5..pi rad either way at 1 rad/s).
struct BumpBaselineConfig
{
  double forward_speed = 0.3;      ///< m/s, in (0, 0.5]: straight ahead until the bumper touches
  double back_speed = 0.1;         ///< m/s, in (0, 0.5]: backing up after a contact
  double back_distance = 0.05;     ///< m, in (0, 0.5]: how far to back up (odometry)
  double max_back_distance = 0.3;  ///< m, in [back_distance, 1]: backing goes on up to this while the
                                   ///< bumper is still pressed or the driver's hazard latch is still set
  double turn_speed = 1.0;         ///< rad/s, in (0, 4]: turning in place
  double min_turn = 0.5;           ///< rad, in (0, pi]: smallest random turn
  double max_turn = M_PI;          ///< rad, in [min_turn, pi]: largest random turn
  std::uint32_t seed = 1;          ///< random seed of the turns (angle and side): runs repeat
  double duration = 0.0;           ///< s, >= 0: stop after this long since the first step; 0: never
  double reset_interval = 0.5;     ///< s, in (0, 10]: at most one reset_hazard request this often

  /// @brief Throws std::invalid_argument, starting with the parameter's name, for a value out of range.
  void validate() const;
};

/// @brief What the policy sees at one step: odometry pose and the driver's hazards.
struct BumpBaselineInput
{
  double time = 0.0;     ///< s, any monotonic clock
  double x = 0.0;        ///< m, odometry position
  double y = 0.0;        ///< m
  double yaw = 0.0;      ///< rad, odometry heading
  bool bumper = false;   ///< a bump sensor pressed (left or right)
  bool latched = false;  ///< the driver's hazard latch is set (it blocks forward motion and turns)
};

/// @brief What to send at one step.
struct BumpBaselineCommand
{
  double linear = 0.0;        ///< m/s, cmd_vel linear.x
  double angular = 0.0;       ///< rad/s, cmd_vel angular.z
  bool reset_hazard = false;  ///< call the driver's reset_hazard (the latch outlived the contact)
};

/**
 * @brief Bump-and-turn state machine: FORWARD until the bumper touches (or the driver latches a
 * hazard), BACK back_distance by odometry, TURN a random angle in [min_turn, max_turn] to a random
 * side (std::mt19937 seeded with seed: the same seed gives the same sequence of turns), FORWARD.
 *
 * The driver (create_driver) latches a bump: it stops the wheels and refuses forward motion and
 * turns in place until a backing-away command runs with the bumper released (the latch then clears
 * itself) or reset_hazard succeeds. So BACK goes on past back_distance (up to max_back_distance)
 * while the bumper is pressed or the latch is set, asking for reset_hazard once the bumper is free;
 * a TURN that finds the latch set asks for reset_hazard, and one that finds the bumper pressed backs
 * up again (counted as a new bump). Steps with a non-finite pose command a stop and change nothing.
 */
class BumpBaseline
{
public:
  /// @brief The phases of the baseline.
  enum class State
  {
    FORWARD,
    BACK,
    TURN,
    DONE  ///< duration elapsed: stopped for good
  };

  /// @brief Validates @p config (throws std::invalid_argument naming the parameter).
  explicit BumpBaseline(const BumpBaselineConfig& config);

  /// @brief One control step: the command to send now.
  BumpBaselineCommand step(const BumpBaselineInput& in);

  /// @brief Current phase.
  State state() const { return state_; }
  /// @brief Contacts so far (entries into BACK).
  int bumps() const { return bumps_; }
  /// @brief reset_hazard requests so far.
  int resets() const { return resets_; }
  /// @brief Signed angle of the current (or last) turn, rad (positive: counter-clockwise).
  double turnTarget() const { return turn_target_; }
  /// @brief Odometry path length so far, m.
  double travelled() const { return travelled_; }
  /// @brief Name of a state ("FORWARD", "BACK", "TURN", "DONE").
  static const char* stateName(State state);

private:
  void startBack(const BumpBaselineInput& in);
  bool wantReset(double time);

  BumpBaselineConfig config_;
  std::mt19937 rng_;
  State state_ = State::FORWARD;
  bool started_ = false;
  double start_time_ = 0.0;
  double last_x_ = 0.0, last_y_ = 0.0, last_yaw_ = 0.0;  // previous valid pose
  double back_x_ = 0.0, back_y_ = 0.0;                   // where the current BACK started
  double turn_target_ = 0.0;                             // rad, signed
  double turned_ = 0.0;                                  // rad, signed, accumulated odometry
  double last_reset_ = 0.0;
  bool reset_ever_ = false;
  int bumps_ = 0;
  int resets_ = 0;
  double travelled_ = 0.0;
};

}  // namespace sl_evaluation
