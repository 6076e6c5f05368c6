#include "create_driver/odometry.h"

#include <cmath>

namespace create_driver
{
double normalizeAngle(double a)
{
  a = std::remainder(a, 2.0 * M_PI);
  if (a <= -M_PI)
    a += 2.0 * M_PI;
  return a;
}

int encoderDelta(uint16_t now, uint16_t before)
{
  return static_cast<int16_t>(static_cast<uint16_t>(now - before));
}

Odometry::Odometry(const Params& params) : params_(params) {}

void Odometry::reset()
{
  pose_ = Pose2D();
  distance_ = 0.0;
  yaw_continuous_ = 0.0;
  have_encoders_ = false;
  history_count_ = 0;
  history_head_ = 0;
  v_ = 0.0;
  w_ = 0.0;
}

void Odometry::setPose(const Pose2D& pose)
{
  pose_ = pose;
  pose_.yaw = normalizeAngle(pose.yaw);
}

void Odometry::updateDistanceAngle(double distance_m, double angle_rad, double stamp)
{
  integrate(distance_m, angle_rad, stamp);
}

void Odometry::updateEncoders(uint16_t left, uint16_t right, double stamp)
{
  if (!have_encoders_)
  {
    have_encoders_ = true;
    last_left_ = left;
    last_right_ = right;
    integrate(0.0, 0.0, stamp);
    return;
  }
  const int dl = encoderDelta(left, last_left_);
  const int dr = encoderDelta(right, last_right_);
  last_left_ = left;
  last_right_ = right;
  updateWheels(dl * params_.encoder_m_per_count, dr * params_.encoder_m_per_count, stamp);
}

void Odometry::updateWheels(double left_m, double right_m, double stamp)
{
  integrate(0.5 * (left_m + right_m), (right_m - left_m) / params_.wheel_base, stamp);
}

void Odometry::integrate(double d, double dtheta, double stamp)
{
  const double mid = pose_.yaw + 0.5 * dtheta;
  pose_.x += d * std::cos(mid);
  pose_.y += d * std::sin(mid);
  pose_.yaw = normalizeAngle(pose_.yaw + dtheta);
  distance_ += d;
  yaw_continuous_ += dtheta;

  // Velocity over a short window of samples.
  history_[history_head_] = Sample{ stamp, distance_, yaw_continuous_ };
  history_head_ = (history_head_ + 1) % history_.size();
  if (history_count_ < history_.size())
    ++history_count_;
  const size_t newest = (history_head_ + history_.size() - 1) % history_.size();
  size_t oldest = newest;
  for (size_t k = 1; k < history_count_; ++k)
  {
    const size_t idx = (newest + history_.size() - k) % history_.size();
    if (stamp - history_[idx].stamp > params_.velocity_window)
      break;
    oldest = idx;
  }
  const double dt = history_[newest].stamp - history_[oldest].stamp;
  if (dt > 1e-6)
  {
    v_ = (history_[newest].distance - history_[oldest].distance) / dt;
    w_ = (history_[newest].yaw - history_[oldest].yaw) / dt;
  }
  else if (history_count_ <= 1)
  {
    v_ = 0.0;
    w_ = 0.0;
  }
}

}  // namespace create_driver
