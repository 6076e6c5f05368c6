#include "sl_navigation/path_follower.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "validation.h"

namespace sl_navigation
{
namespace
{
constexpr double kSweepStep = 0.025;       // m between the discs swept along the path
constexpr double kLookSpacing = 0.2;       // m of travel for each two looks
constexpr double kReturnTolerance = 0.15;  // rad: after a look, the turn back ends this near the path
constexpr double kRefused = 0.01;          // m/s: a filter's limit below this refused the command

double hypot2(const Point& a, const Point& b)
{
  return std::hypot(a.x - b.x, a.y - b.y);
}
}  // namespace

double wrapAngle(double a)
{
  a = std::remainder(a, 2.0 * M_PI);
  return a <= -M_PI ? a + 2.0 * M_PI : a;
}

double turnRate(double error, double max_rate)
{
  const double w = std::clamp(2.0 * error, -max_rate, max_rate);
  return std::abs(w) < 0.2 ? std::copysign(0.2, error) : w;
}

const char* toString(FollowMode mode)
{
  switch (mode)
  {
    case FollowMode::DRIVE:
      return "DRIVE";
    case FollowMode::ROTATE:
      return "ROTATE";
    case FollowMode::LOOK:
      return "LOOK";
    case FollowMode::BLOCKED:
      return "BLOCKED";
    case FollowMode::ARRIVED:
      return "ARRIVED";
  }
  return "?";
}

void FollowerParams::validate() const
{
  detail::requireRange("max_speed", max_speed, 0.01, 0.5);
  detail::requireRange("min_speed", min_speed, 0.0, max_speed);
  detail::requireRange("max_angular_speed", max_angular, 0.05, 4.0);
  detail::requireRange("turn_speed", turn_speed, 0.05, 4.0);
  detail::requireRange("acceleration", acceleration, 0.01, 5.0);
  detail::requireRange("deceleration", deceleration, 0.01, 5.0);
  detail::requireRange("clearance", clearance, 0.0, 2.0);
  detail::requireRange("swept_radius", swept_radius, 0.01, 2.0);
  detail::requireRange("lookahead", lookahead, 0.05, 3.0);
  detail::requireRange("rotate_threshold", rotate_threshold, 0.05, M_PI);
  detail::requireRange("look_distance", look_distance, 0.0, 5.0);
  detail::requireRange("look_min_distance", look_min_distance, 0.0, 5.0);
  detail::requireRange("look_tolerance", look_tolerance, 0.01, 1.0);
  detail::requireRange("view_angle", view_angle, 0.0, M_PI);
  detail::requireRange("look_time", look_time, 0.0, 30.0);
  detail::requireRange("goal_tolerance", goal_tolerance, 0.01, 2.0);
  detail::requireRange("yaw_tolerance", yaw_tolerance, 0.0, M_PI);
}

bool ExecWindow::set(const OccupancyView& v)
{
  if (!validLayout(v))
  {
    return false;
  }
  data_.assign(v.data, v.data + static_cast<std::size_t>(v.width) * v.height);
  width_ = v.width;
  height_ = v.height;
  resolution_ = v.resolution;
  origin_x_ = v.origin_x;
  origin_y_ = v.origin_y;
  return true;
}

std::int8_t ExecWindow::at(double x, double y) const
{
  const double fx = (x - origin_x_) / resolution_;
  const double fy = (y - origin_y_) / resolution_;
  if (!(fx >= 0.0 && fy >= 0.0 && fx < width_ && fy < height_))
  {
    return -1;
  }
  return data_[static_cast<std::size_t>(fy) * width_ + static_cast<std::size_t>(fx)];
}

PathFollower::PathFollower(const FollowerParams& params) : params_(params), tolerance_(params.goal_tolerance)
{
  params_.validate();
}

void PathFollower::reset()
{
  path_.clear();
  along_.clear();
  index_ = 0;
  offset_ = 0.0;
  speed_ = 0.0;
  facing_ = false;
  returning_ = false;
  looking_ = false;
  looks_.clear();
  last_time_ = std::numeric_limits<double>::quiet_NaN();
}

void PathFollower::setPath(const std::vector<Point>& path, double goal_yaw, bool use_yaw, double tolerance)
{
  tolerance_ = tolerance > 0.0 && tolerance < params_.goal_tolerance ? tolerance : params_.goal_tolerance;
  path_ = path;
  if (path_.size() == 1)
  {
    path_.push_back(path_.front());
  }
  along_.assign(path_.size(), 0.0);
  for (std::size_t i = 1; i < path_.size(); ++i)
  {
    along_[i] = along_[i - 1] + hypot2(path_[i], path_[i - 1]);
  }
  index_ = 0;
  offset_ = 0.0;
  goal_yaw_ = goal_yaw;
  use_yaw_ = use_yaw;
  facing_ = false;
}

void PathFollower::project(const Pose& pose)
{
  // The nearest point on the segments from the current one on, within 3 m of path: never backwards.
  double best = std::numeric_limits<double>::infinity();
  const std::size_t first = index_;
  for (std::size_t i = first; i + 1 < path_.size() && along_[i] <= along_[first] + 3.0; ++i)
  {
    const Point& a = path_[i];
    const Point& b = path_[i + 1];
    const double len = along_[i + 1] - along_[i];
    double t = 0.0;
    if (len > 1e-9)
    {
      t = ((pose.x - a.x) * (b.x - a.x) + (pose.y - a.y) * (b.y - a.y)) / (len * len);
      t = std::clamp(t, 0.0, 1.0);
    }
    const double d = std::hypot(a.x + t * (b.x - a.x) - pose.x, a.y + t * (b.y - a.y) - pose.y);
    if (d < best - 1e-9 && (i > index_ || t * len >= offset_ - 1e-9))
    {
      best = d;
      index_ = i;
      offset_ = t * len;
    }
  }
}

Point PathFollower::pointAhead(double distance) const
{
  const double target = along_[index_] + offset_ + distance;
  std::size_t i = index_;
  while (i + 1 < path_.size() && along_[i + 1] < target)
  {
    ++i;
  }
  if (i + 1 >= path_.size())
  {
    return path_.back();
  }
  const double len = along_[i + 1] - along_[i];
  const double t = len > 1e-9 ? (target - along_[i]) / len : 0.0;
  return { path_[i].x + t * (path_[i + 1].x - path_[i].x), path_[i].y + t * (path_[i + 1].y - path_[i].y) };
}

double PathFollower::remaining() const
{
  return path_.empty() ? 0.0 : along_.back() - along_[index_] - offset_;
}

PathFollower::Sweep PathFollower::sweep(const Pose& pose, const ExecWindow& w) const
{
  Sweep s;
  const double r = params_.swept_radius;
  const double res = w.resolution();
  const double horizon = std::min(remaining(), std::max(params_.look_distance, 1.5));
  const int cells = static_cast<int>(std::ceil(r / res)) + 1;
  // Two looks (one to each side) per kLookSpacing of travel: looking again where the robot stands
  // would not show what the last two looks did not.
  const auto near = [&](const Pose& q) { return std::hypot(q.x - pose.x, q.y - pose.y) < kLookSpacing; };
  const bool may_look = std::count_if(looks_.begin(), looks_.end(), near) < 2;
  for (double t = kSweepStep; t <= horizon + 1e-9; t += kSweepStep)
  {
    const Point c = pointAhead(t);
    for (int dy = -cells; dy <= cells; ++dy)
    {
      for (int dx = -cells; dx <= cells; ++dx)
      {
        const double x = c.x + dx * res;
        const double y = c.y + dy * res;
        if (std::hypot(x - c.x, y - c.y) > r || std::hypot(x - pose.x, y - pose.y) <= r)
        {
          continue;  // outside this disc, or under the robot now (it may always leave)
        }
        const std::int8_t v = w.at(x, y);
        if (v >= 100 && t < s.obstacle)
        {
          s.obstacle = t;
        }
        else if (v != 0 && v < 100)
        {
          s.unknown = std::min(s.unknown, t);
          if (may_look && t < s.look && lookable(pose, { x, y }, w))
          {
            s.look = t;
            s.look_at = { x, y };
          }
        }
      }
    }
    if (s.obstacle < std::numeric_limits<double>::infinity())
    {
      break;
    }
  }
  s.free = std::min({ s.obstacle, s.unknown, horizon }) - kSweepStep;
  s.free = std::max(0.0, s.free);
  return s;
}

bool PathFollower::lookable(const Pose& pose, const Point& p, const ExecWindow& w) const
{
  const double d = std::hypot(p.x - pose.x, p.y - pose.y);
  const double bearing = wrapAngle(std::atan2(p.y - pose.y, p.x - pose.x) - pose.yaw);
  return d >= params_.look_min_distance && d <= params_.look_distance && std::abs(bearing) > params_.view_angle &&
         !looked(p) && inSight(pose, p, w);
}

bool PathFollower::inSight(const Pose& pose, const Point& p, const ExecWindow& w) const
{
  // An obstacle between would hide the cell: looking would not show it (a door's frame, a wall's end).
  const double d = std::hypot(p.x - pose.x, p.y - pose.y);
  const int n = static_cast<int>(d / w.resolution());
  for (int k = 1; k < n; ++k)
  {
    const double f = static_cast<double>(k) / n;
    if (w.at(pose.x + f * (p.x - pose.x), pose.y + f * (p.y - pose.y)) >= 100)
    {
      return false;
    }
  }
  return true;
}

bool PathFollower::looked(const Point& p) const
{
  for (const Pose& q : looks_)
  {
    const double d = std::hypot(p.x - q.x, p.y - q.y);
    const double bearing = wrapAngle(std::atan2(p.y - q.y, p.x - q.x) - q.yaw);
    if (d >= params_.look_min_distance && d <= params_.look_distance && std::abs(bearing) <= params_.view_angle)
    {
      return true;
    }
  }
  return false;
}

void PathFollower::endLook(const Pose& pose)
{
  looks_.push_back(pose);
  looking_ = false;
  facing_ = false;
  returning_ = true;  // turn back toward the path in place
}

bool PathFollower::lookAt(const Pose& pose, const Sweep& s, const ExecWindow& window, double now)
{
  const std::int8_t target = looking_ ? window.at(look_target_.x, look_target_.y) : -1;
  if (looking_ && (target == 0 || target >= 100))
  {
    endLook(pose);  // seen meanwhile: a look all the same
  }
  if (!looking_ && (!std::isfinite(s.look) || s.obstacle <= s.look))
  {
    facing_ = false;
    return false;
  }
  if (!looking_)
  {
    looking_ = true;  // one target until the look ends: turning toward it brings others out of view
    look_target_ = s.look_at;
  }
  const double error = wrapAngle(std::atan2(look_target_.y - pose.y, look_target_.x - pose.x) - pose.yaw);
  if (std::abs(error) > params_.look_tolerance)
  {
    facing_ = false;
    rotateTo(error, FollowMode::LOOK);
    return true;
  }
  if (!facing_)
  {
    facing_ = true;
    facing_since_ = now;
  }
  if (now - facing_since_ >= params_.look_time)
  {
    endLook(pose);  // what is in view now is seen as well as the camera can see it
    return false;
  }
  out_.mode = FollowMode::LOOK;
  out_.linear = 0.0;
  out_.angular = 0.0;
  speed_ = 0.0;
  return true;
}

void PathFollower::rotateTo(double error, FollowMode mode)
{
  out_.mode = mode;
  out_.linear = 0.0;
  speed_ = 0.0;
  out_.angular = turnRate(error, params_.turn_speed);
}

void PathFollower::drive(const Pose& pose, const Sweep& s, double dt, double speed_cap)
{
  const Point target = pointAhead(params_.lookahead);
  const double dist = std::max(1e-3, std::hypot(target.x - pose.x, target.y - pose.y));
  const double alpha = wrapAngle(std::atan2(target.y - pose.y, target.x - pose.x) - pose.yaw);
  // After a look, turn back in place: an arc back to the path would sweep the unseen side. So too
  // when the filter refused the last arc outright (what it crosses within the clearance is unknown
  // or occupied): facing the path brings the arc into the camera's narrow view, where turning at
  // the arc's own slow rate would take seconds to.
  returning_ = (returning_ || speed_cap < kRefused) && std::abs(alpha) > kReturnTolerance;
  if (returning_ || std::abs(alpha) > params_.rotate_threshold)
  {
    rotateTo(alpha, FollowMode::ROTATE);
    return;
  }
  const double curvature = 2.0 * std::sin(alpha) / dist;
  const double a = params_.deceleration;
  double v = params_.max_speed;
  const double margin = std::min(s.obstacle, 10.0) - kSweepStep - params_.clearance;
  v = std::min(v, margin > 0.0 ? std::sqrt(2.0 * a * margin) : 0.0);
  v = std::min(v, speed_cap + params_.acceleration * dt);
  v = std::max(v, params_.min_speed);  // not blocked (step() checked): the filter decides
  v = std::min(
      v, std::sqrt(2.0 * a * std::max(0.0, out_.goal_distance - 0.5 * tolerance_)) + params_.min_speed);
  if (std::abs(curvature) > 1e-6)
  {
    v = std::min(v, params_.max_angular / std::abs(curvature));
  }
  v = std::min(v, speed_ + params_.acceleration * dt);
  speed_ = v;
  out_.mode = FollowMode::DRIVE;
  out_.linear = v;
  out_.angular = v * curvature;
}

const FollowCommand& PathFollower::step(const Pose& pose, const ExecWindow& window, double now, double speed_cap)
{
  const double dt = std::isnan(last_time_) ? 0.1 : std::clamp(now - last_time_, 0.0, 0.5);
  last_time_ = now;
  out_ = FollowCommand();
  if (path_.empty())
  {
    out_.mode = FollowMode::ARRIVED;
    out_.text = "no path";
    return out_;
  }
  project(pose);
  out_.remaining = remaining();
  out_.goal_distance = std::hypot(path_.back().x - pose.x, path_.back().y - pose.y);
  char text[200];
  if (out_.goal_distance <= tolerance_)
  {
    const double yaw_error = wrapAngle(goal_yaw_ - pose.yaw);
    if (use_yaw_ && params_.yaw_tolerance > 0.0 && std::abs(yaw_error) > params_.yaw_tolerance)
    {
      rotateTo(yaw_error, FollowMode::ROTATE);
      std::snprintf(text, sizeof(text), "at the goal (%.3f m): turning %.2f rad to its heading", out_.goal_distance,
                    yaw_error);
    }
    else
    {
      out_.mode = FollowMode::ARRIVED;
      speed_ = 0.0;
      std::snprintf(text, sizeof(text), "arrived: %.3f m from the goal", out_.goal_distance);
    }
    out_.text = text;
    return out_;
  }
  const Sweep s = sweep(pose, window);
  out_.free_travel = s.free;
  out_.obstacle_travel = s.obstacle;
  if (s.obstacle <= params_.clearance + kSweepStep)
  {
    out_.mode = FollowMode::BLOCKED;
    speed_ = 0.0;
    std::snprintf(text, sizeof(text), "obstacle on the path %.2f m ahead (clearance %.2f m): stopped", s.obstacle,
                  params_.clearance);
    out_.text = text;
    return out_;
  }
  if (lookAt(pose, s, window, now))
  {
    std::snprintf(text, sizeof(text), "path unknown at (%.2f, %.2f), out of view: looking", look_target_.x,
                  look_target_.y);
    out_.text = text;
    return out_;
  }
  drive(pose, s, dt, speed_cap);
  std::snprintf(text, sizeof(text), "%s: %.2f m/s, %.2f rad/s; %.2f m known free, %.2f m of path left",
                toString(out_.mode), out_.linear, out_.angular, s.free, out_.remaining);
  out_.text = text;
  return out_;
}
}  // namespace sl_navigation
