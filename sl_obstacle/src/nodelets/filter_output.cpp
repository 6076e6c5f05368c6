#include "filter_output.h"

#include <algorithm>
#include <cmath>

namespace sl_obstacle
{
namespace
{
using S = ObstacleStatus;

/// State and reason code of the status for a filter outcome.
void stateOf(const FilterOutput& out, std::uint8_t& state, std::uint8_t& reason)
{
  switch (out.reason)
  {
    case FilterReason::PASSED:
      reason = S::REASON_PASSED;
      state = out.command.linear != 0.0 ? S::DRIVING : (out.command.angular != 0.0 ? S::TURNING : S::STOPPED);
      return;
    case FilterReason::LIMITED:
      state = S::SLOWING;
      reason = S::REASON_LIMITED;
      return;
    case FilterReason::CREEPING:
      state = S::SLOWING;
      reason = S::REASON_CREEPING;
      return;
    case FilterReason::STOPPED_OBSTACLE:
      state = S::BLOCKED;
      reason = S::REASON_STOPPED_OBSTACLE;
      return;
    case FilterReason::INPUT_TIMEOUT:
      state = S::STOPPED;
      reason = S::REASON_INPUT_TIMEOUT;
      return;
    case FilterReason::STALE_DATA:
      state = S::STALE;
      reason = S::REASON_STALE_DATA;
      return;
    case FilterReason::NO_ODOMETRY:
      state = S::STOPPED;
      reason = S::REASON_NO_ODOMETRY;
      return;
    case FilterReason::INVALID_COMMAND:
      state = S::STOPPED;
      reason = S::REASON_INVALID_COMMAND;
      return;
  }
}
}  // namespace

geometry_msgs::Point point(double x, double y, double z)
{
  geometry_msgs::Point p;
  p.x = x;
  p.y = y;
  p.z = z;
  return p;
}

void fillFilterStatus(const FilterOutput& out, const Velocity& input, ObstacleStatus& s)
{
  stateOf(out, s.state, s.reason_code);
  s.reason = out.text;
  s.blocked = out.reason == FilterReason::STOPPED_OBSTACLE;
  s.teleop = true;
  s.input_linear = input.linear;
  s.input_angular = input.angular;
  s.command_scale = out.scale;
  s.command =
      out.command.linear != 0.0 ? S::COMMAND_DRIVE : (out.command.angular != 0.0 ? S::COMMAND_TURN : S::COMMAND_STOP);
  s.command_speed = out.command.linear;
  s.command_angular_speed = out.command.angular;
  s.command_distance = out.travel;
}

void footprintMarker(const FilterOutput& out, const Pose2D& pose, double radius, visualization_msgs::Marker& m)
{
  m.type = visualization_msgs::Marker::LINE_LIST;
  m.scale.x = 0.006;
  m.color.r = out.reason == FilterReason::PASSED ? 0.1F : 1.0F;
  m.color.g = out.reason == FilterReason::STOPPED_OBSTACLE ? 0.1F : 0.8F;
  m.color.b = 0.1F;
  m.color.a = 1.0F;
  m.pose.orientation.w = 1.0;
  m.points.clear();
  const double v = out.command.linear;
  const double travel = v != 0.0 ? std::max(0.0, out.travel) : 0.0;
  const int direction = v < 0.0 ? -1 : 1;
  const double c = std::cos(pose.yaw);
  const double s = std::sin(pose.yaw);
  // The disc centre after travel t along the output's arc, in the map frame.
  const auto at = [&](double t)
  {
    const double k = out.curvature;
    const double lx = std::abs(k) < 1e-9 ? direction * t : direction * std::sin(k * t) / k;
    const double ly = std::abs(k) < 1e-9 ? 0.0 : direction * (1.0 - std::cos(k * t)) / k;
    return point(pose.x + c * lx - s * ly, pose.y + s * lx + c * ly, 0.01);
  };
  constexpr int kSteps = 20;
  for (int i = 0; i < kSteps; ++i)
  {
    m.points.push_back(at(travel * i / kSteps));
    m.points.push_back(at(travel * (i + 1) / kSteps));
  }
  const geometry_msgs::Point end = at(travel);
  constexpr int kSides = 36;
  for (int i = 0; i < kSides; ++i)
  {
    const double a0 = 2.0 * M_PI * i / kSides;
    const double a1 = 2.0 * M_PI * (i + 1) / kSides;
    m.points.push_back(point(end.x + radius * std::cos(a0), end.y + radius * std::sin(a0), 0.01));
    m.points.push_back(point(end.x + radius * std::cos(a1), end.y + radius * std::sin(a1), 0.01));
  }
}
}  // namespace sl_obstacle
