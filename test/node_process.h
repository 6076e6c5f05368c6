// What the system tests ask about the processes that hold ROS nodes: a node's pid (its getPid on
// the master's lookupNode), a process's resident memory (/proc/<pid>/status) and its samples over a
// soak (MemorySampler).
#pragma once

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <ros/master.h>
#include <ros/network.h>
#include <ros/this_node.h>
#include <xmlrpcpp/XmlRpcClient.h>

namespace sl_bringup_test
{
/// The pid of the process that holds node @p node (its getPid), or -1 when it is not registered or
/// does not answer.
inline int nodePid(const std::string& node)
{
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  args[1] = node;
  if (!ros::master::execute("lookupNode", args, result, payload, false))
    return -1;
  std::string host;
  uint32_t port = 0;
  if (payload.getType() != XmlRpc::XmlRpcValue::TypeString ||
      !ros::network::splitURI(static_cast<std::string>(payload), host, port))
    return -1;
  XmlRpc::XmlRpcClient client(host.c_str(), static_cast<int>(port), "/");
  XmlRpc::XmlRpcValue call, answer;
  call[0] = ros::this_node::getName();
  if (!client.execute("getPid", call, answer) || answer.getType() != XmlRpc::XmlRpcValue::TypeArray ||
      answer.size() < 3 || static_cast<int>(answer[0]) != 1)
    return -1;
  return static_cast<int>(answer[2]);
}

/// Resident memory of process @p pid in MB (VmRSS), or -1 when it cannot be read.
inline double residentMegabytes(int pid)
{
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string key;
  while (status >> key)
  {
    if (key == "VmRSS:")
    {
      double kb = -1.0;
      status >> kb;
      return kb < 0.0 ? -1.0 : kb / 1024.0;
    }
    status.ignore(1 << 16, '\n');
  }
  return -1.0;
}

/// Resident memory of the process holding one node, sampled every period of a long run (the soaks).
class MemorySampler
{
public:
  /// Samples the process of @p node every @p period s from elapsed time 0 (an empty @p node: never).
  /// @return false when @p node is given but its pid cannot be found.
  bool start(const std::string& node, double period)
  {
    node_ = node;
    period_ = period;
    samples_.clear();
    pid_ = node.empty() ? -1 : nodePid(node);
    return node.empty() || pid_ > 0;
  }
  /// Takes a sample when one is due at @p elapsed s. @return true when it took one.
  bool sample(double elapsed)
  {
    if (pid_ <= 0 || elapsed < period_ * samples_.size())
      return false;
    samples_.push_back(residentMegabytes(pid_));
    return true;
  }
  /// The samples so far (MB; -1 where /proc could not be read).
  const std::vector<double>& samples() const { return samples_; }
  /// The node sampled (empty: none).
  const std::string& node() const { return node_; }
  /// Growth (MB) from sample @p settle (after the warm-up) to the last one; NaN with fewer than
  /// settle + 2 samples.
  double growth(std::size_t settle) const
  {
    if (samples_.size() < settle + 2)
      return std::nan("");
    return samples_.back() - samples_[settle];
  }
  /// What growth(@p settle) measured, in words (for a check's message and the log).
  std::string growthText(std::size_t settle) const
  {
    if (samples_.size() < settle + 2)
      return node_ + ": too few memory samples";
    char text[160];
    std::snprintf(text, sizeof(text), " grew %.1f MB, from %.1f MB (sample %zu) to %.1f MB (the last of %zu)",
                  growth(settle), samples_[settle], settle, samples_.back(), samples_.size());
    return node_ + text;
  }

private:
  std::string node_;
  double period_ = 60.0;
  int pid_ = -1;
  std::vector<double> samples_;
};
}  // namespace sl_bringup_test
