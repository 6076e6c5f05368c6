#include "goal_result.h"

namespace sl_obstacle
{
GoalEnd goalEnd(const sl_msgs::DriveDistanceResult* result, const std::string& state, std::string& what)
{
  what = "goal ended in state " + state;
  if (result == nullptr)
  {
    return GoalEnd::FAILED;
  }
  using R = sl_msgs::DriveDistanceResult;
  GoalEnd end = GoalEnd::FAILED;
  switch (result->reason)
  {
    case R::REACHED:
      end = GoalEnd::REACHED;
      what = "reached";
      break;
    case R::PREEMPTED:
      end = GoalEnd::CANCELLED;
      what = "pre-empted";
      break;
    case R::BUMPER:
      end = GoalEnd::HAZARD;
      what = "bumper";
      break;
    case R::CLIFF:
      end = GoalEnd::HAZARD;
      what = "cliff";
      break;
    case R::WHEEL_DROP:
      end = GoalEnd::HAZARD;
      what = "wheel drop";
      break;
    case R::TIMEOUT:
      what = "timeout";
      break;
    case R::DISCONNECTED:
      what = "disconnected";
      break;
    case R::INVALID_GOAL:
      what = "invalid goal";
      break;
    case R::HEARTBEAT_LOST:
      what = "heartbeat lost";
      break;
    default:
      break;
  }
  if (!result->message.empty())
  {
    what += ": " + result->message;
  }
  return end;
}
}  // namespace sl_obstacle
