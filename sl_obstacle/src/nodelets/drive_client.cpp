#include "drive_client.h"

#include <std_msgs/Empty.h>

#include "goal_result.h"

namespace sl_obstacle
{
DriveClient::DriveClient(ros::NodeHandle nh)
  : client_(std::make_unique<Client>(nh, "drive_distance", false)),
    heartbeat_pub_(ros::NodeHandle(nh, "drive_distance").advertise<std_msgs::Empty>("heartbeat", 1))
{
}

void DriveClient::send(unsigned id, double distance, double speed, const ResultCallback& on_result,
                       const FeedbackCallback& on_feedback)
{
  sl_msgs::DriveDistanceGoal goal;
  goal.distance = distance;
  goal.speed = speed;
  client_->sendGoal(
      goal,
      [id, on_result](const actionlib::SimpleClientGoalState& state, const sl_msgs::DriveDistanceResultConstPtr& r)
      {
        std::string what;
        const GoalEnd end = goalEnd(r.get(), state.toString(), what);
        on_result(id, end, what);
      },
      Client::SimpleActiveCallback(),
      [id, on_feedback](const sl_msgs::DriveDistanceFeedbackConstPtr& feedback)
      { on_feedback(id, feedback->distance_remaining); });
}

void DriveClient::heartbeat()
{
  heartbeat_pub_.publish(std_msgs::Empty());
}
}  // namespace sl_obstacle
