// Waiting in tests: for a condition (polled while callbacks run on a spinner) or for one message.
// Never a fixed sleep: a loaded machine only makes a test slower, never wrong.
#pragma once

#include <functional>
#include <string>

#include <ros/ros.h>
#include <ros/topic.h>

namespace sl_testing
{
/// Generous default timeout for a loaded 2-core machine, s.
constexpr double kTimeout = 60.0;

/**
 * @brief Polls @p cond every @p poll_s (wall time) until it holds, @p timeout_s pass or ROS shuts down.
 * @return the last value of @p cond
 */
inline bool waitUntil(const std::function<bool()>& cond, double timeout_s = kTimeout, double poll_s = 0.01)
{
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
  while (ros::ok() && ros::WallTime::now() < end)
  {
    if (cond())
      return true;
    ros::WallDuration(poll_s).sleep();
  }
  return cond();
}

/// @brief The next message on @p topic (latched: the last one), or null after @p timeout_s.
template <typename M>
typename M::ConstPtr waitForMessage(const std::string& topic, double timeout_s = kTimeout)
{
  return ros::topic::waitForMessage<M>(topic, ros::Duration(timeout_s));
}
}  // namespace sl_testing
