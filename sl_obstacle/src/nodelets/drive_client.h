// The node's side of the driver's drive_distance action: goals out with their heartbeat, results
// and feedback back as the supervisor's types.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include <actionlib/client/simple_action_client.h>
#include <ros/node_handle.h>
#include <ros/publisher.h>
#include <sl_msgs/DriveDistanceAction.h>

#include "sl_obstacle/decision_maker.h"

namespace sl_obstacle
{
/// The drive_distance action client and its heartbeat publisher (drive_distance/heartbeat).
class DriveClient
{
public:
  /// Called with the id given to send() and how the goal ended (a short text in the second string).
  using ResultCallback = std::function<void(unsigned id, GoalEnd end, const std::string& what)>;
  /// Called with the id given to send() and the distance still to drive (m).
  using FeedbackCallback = std::function<void(unsigned id, double remaining)>;

  /// Connects to `drive_distance` in @p nh's namespace (without waiting).
  explicit DriveClient(ros::NodeHandle nh);

  /// True while the action server is connected.
  bool connected() const { return client_->isServerConnected(); }
  /// Sends goal @p id (@p distance m at @p speed m/s), replacing a running one.
  void send(unsigned id, double distance, double speed, const ResultCallback& on_result,
            const FeedbackCallback& on_feedback);
  /// Cancels the running goal.
  void cancel() { client_->cancelGoal(); }
  /// Keeps the running goal alive in the driver.
  void heartbeat();

private:
  using Client = actionlib::SimpleActionClient<sl_msgs::DriveDistanceAction>;
  std::unique_ptr<Client> client_;
  ros::Publisher heartbeat_pub_;
};
}  // namespace sl_obstacle
