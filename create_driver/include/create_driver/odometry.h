/// @file odometry.h
/// @brief Planar odometry from the Create's distance/angle packets or the Create 2's encoders.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace create_driver
{
/// A planar pose: position in m, heading in rad (counter-clockwise, REP 103).
struct Pose2D
{
  double x = 0.0;
  double y = 0.0;
  double yaw = 0.0;
};

/// @brief Wraps an angle into (-pi, pi].
double normalizeAngle(double a);

/// @brief Signed difference of two 16-bit wrapping counters (now - before), in (-32768, 32767].
int encoderDelta(uint16_t now, uint16_t before);

/// Geometry of the robot for Odometry.
struct OdometryParams
{
  double wheel_base = 0.258;                                      ///< m, distance between the wheels
  double encoder_m_per_count = 3.14159265358979 * 0.072 / 508.8;  ///< Create 2: 72 mm wheel, 508.8 counts/rev
  double velocity_window = 0.1;                                   ///< s, time span of the velocity estimate
};

/// @brief Dead-reckoning integrator.
///
/// Increments are integrated along the arc (mid-point heading). Besides the pose it keeps the
/// signed path length (distance()) and the unwrapped heading (yawContinuous()) used by the
/// distance controller, and a velocity estimate over a short window of updates.
class Odometry
{
public:
  /// Geometry of the robot (see OdometryParams).
  using Params = OdometryParams;

  /// @brief Creates an integrator at the origin.
  explicit Odometry(const Params& params = Params());

  /// @brief Back to the origin; forgets the encoder baseline and the velocity history.
  void reset();

  /// @brief Sets the pose (path length and unwrapped heading are kept).
  void setPose(const Pose2D& pose);

  /// @brief Forgets the encoder baseline: the next encoder update only sets it (after a
  /// reconnect, when the robot may have been power-cycled).
  void resetEncoderBaseline() { have_encoders_ = false; }

  /// @brief Integrates a distance/angle increment (packets 19 and 20, converted to m and rad).
  /// @param stamp time of the measurement, s (any monotonic origin)
  void updateDistanceAngle(double distance_m, double angle_rad, double stamp);

  /// @brief Integrates absolute encoder counts (packets 43/44), handling the 16-bit wrap.
  /// The first call after construction/reset only stores the baseline.
  void updateEncoders(uint16_t left, uint16_t right, double stamp);

  /// @brief Integrates wheel travel increments in m.
  void updateWheels(double left_m, double right_m, double stamp);

  /// @brief Current pose; yaw in (-pi, pi].
  const Pose2D& pose() const { return pose_; }
  /// @brief Signed path length since construction/reset, m (backwards counts negative).
  double distance() const { return distance_; }
  /// @brief Heading without wrapping, rad.
  double yawContinuous() const { return yaw_continuous_; }
  /// @brief Linear velocity estimate, m/s.
  double linearVelocity() const { return v_; }
  /// @brief Angular velocity estimate, rad/s.
  double angularVelocity() const { return w_; }
  /// @brief Geometry in use.
  const Params& params() const { return params_; }

private:
  void integrate(double d, double dtheta, double stamp);

  struct Sample
  {
    double stamp, distance, yaw;
  };

  Params params_;
  Pose2D pose_;
  double distance_ = 0.0;
  double yaw_continuous_ = 0.0;
  bool have_encoders_ = false;
  uint16_t last_left_ = 0;
  uint16_t last_right_ = 0;
  std::array<Sample, 32> history_{};
  size_t history_count_ = 0;
  size_t history_head_ = 0;
  double v_ = 0.0;
  double w_ = 0.0;
};

}  // namespace create_driver
