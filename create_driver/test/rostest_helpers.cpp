#include "rostest_helpers.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace test_helpers
{
bool diagValue(const diagnostic_msgs::DiagnosticArray& array, const std::string& status_suffix, const std::string& key,
               double* value)
{
  for (const auto& st : array.status)
  {
    if (st.name.size() < status_suffix.size() ||
        st.name.compare(st.name.size() - status_suffix.size(), status_suffix.size(), status_suffix) != 0)
      continue;
    for (const auto& kv : st.values)
      if (kv.key == key)
      {
        *value = std::stod(kv.value);
        return true;
      }
  }
  return false;
}

bool System::waitRunning(double timeout_s)
{
  return waitUntil(
      [&]
      {
        const auto m = mode.get();
        return mode.count() > 0 && m.link_state == create_driver::Mode::LINK_RUNNING &&
               m.mode == create_driver::Mode::SAFE && status.count() > 0 && pose.count() > 0;
      },
      timeout_s);
}

bool System::waitWheelsStopped(double timeout_s)
{
  return waitUntil([&] { return status.count() > 0 && wheels() == 0.0; }, timeout_s);
}

bool System::driveUntil(double linear, double angular, const std::function<bool()>& cond, double timeout_s)
{
  geometry_msgs::Twist t;
  t.linear.x = linear;
  t.angular.z = angular;
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
  ros::WallTime next_pub = ros::WallTime::now();
  while (ros::ok() && ros::WallTime::now() < end)
  {
    if (cond())
      return true;
    if (ros::WallTime::now() >= next_pub)
    {
      cmd_pub.publish(t);
      next_pub = ros::WallTime::now() + ros::WallDuration(0.1);
    }
    ros::WallDuration(0.01).sleep();
  }
  return cond();
}

double System::maxWheelOver(uint64_t n, const std::function<void()>& each_tick)
{
  // Every message counts (the hook), not only those a poll happens to see.
  double worst = 0.0;
  uint64_t seen = 0;
  status.setHook(
      [&](const create_driver::SimStatus& s)
      {
        worst = std::max(worst, std::max(std::fabs(s.left_wheel_velocity), std::fabs(s.right_wheel_velocity)));
        ++seen;
      });
  const uint64_t target = status.count() + n;
  waitUntil(
      [&]
      {
        if (each_tick)
          each_tick();
        return status.count() >= target;
      });
  status.setHook({});
  // Wheels that "stayed stopped" because the simulator went quiet prove nothing.
  if (seen < n)
  {
    ADD_FAILURE() << "maxWheelOver: only " << seen << " of " << n << " simulator status messages arrived";
    return std::numeric_limits<double>::infinity();
  }
  return worst;
}

bool System::diag(const std::string& status_suffix, const std::string& key, double* value)
{
  return waitUntil([&] { return diagnostics.count() > 0 && diagValue(diagnostics.get(), status_suffix, key, value); });
}

}  // namespace test_helpers
