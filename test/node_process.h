// What the system tests ask about the processes that hold ROS nodes: a node's pid (its getPid on
// the master's lookupNode) and a process's resident memory (/proc/<pid>/status).
#pragma once

#include <fstream>
#include <string>

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
}  // namespace sl_bringup_test
