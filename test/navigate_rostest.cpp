// Navigation in simulation (navigate.test): goals sent to the move_base action (the first one on
// move_base_simple/goal, as rviz sends it) in the world frame. Each reachable goal must end
// SUCCEEDED with the true pose within goal_tolerance (plus the odometry's drift allowance); each
// unreachable one ABORTED within its bound. Nothing may be touched (the camera simulator's collision
// signal). Prints time, path length and mean speed while moving per goal.
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <actionlib/client/simple_action_client.h>
#include <move_base_msgs/MoveBaseAction.h>
#include <sl_msgs/NavigationStatus.h>

#include <sl_testing/wait.h>

#include "sim_watch.h"

namespace sl_bringup_test
{
namespace
{
struct GoalSpec
{
  double x, y;
  bool reachable;
};

/// "x,y,1;x,y,0" (1: reachable) -> goals.
std::vector<GoalSpec> parseGoals(const std::string& text)
{
  std::vector<GoalSpec> goals;
  std::stringstream all(text);
  std::string item;
  while (std::getline(all, item, ';'))
  {
    GoalSpec g{};
    int reach = 0;
    if (std::sscanf(item.c_str(), "%lf,%lf,%d", &g.x, &g.y, &reach) != 3)
    {
      ADD_FAILURE() << "~goals: cannot read '" << item << "' (expected x,y,reachable)";
      continue;
    }
    g.reachable = reach != 0;
    goals.push_back(g);
  }
  return goals;
}
}  // namespace

class Navigate : public SimWatch
{
public:
  void onNavStatus(const sl_msgs::NavigationStatus& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const double dt = (msg.header.stamp - nav_.header.stamp).toSec();
    if (counting_ && nav_messages_ > 0 && nav_.state == sl_msgs::NavigationStatus::ACTIVE && dt > 0.0 && dt < 1.0)
    {
      mode_time_[nav_.mode] += dt;  // the mode held since the previous status
    }
    nav_ = msg;
    ++nav_messages_;
  }

protected:
  ros::NodeHandle node_;
  void onPose(const geometry_msgs::Pose* previous, const geometry_msgs::Pose& now) override
  {
    const ros::Time t = ros::Time::now();
    if (previous != nullptr && counting_)
    {
      const double step = stepBetween(now, *previous);
      path_ += step;
      const double dt = (t - last_pose_stamp_).toSec();
      if (dt > 0.0 && dt < 0.5 && step / dt > 0.02)  // moving: faster than 2 cm/s
      {
        moving_time_ += dt;
        creep_time_ += creeping_ ? dt : 0.0;
      }
    }
    last_pose_stamp_ = t;
  }
  void onStatus(const sl_msgs::ObstacleStatus& msg) override
  {
    creeping_ = msg.reason_code == sl_msgs::ObstacleStatus::REASON_CREEPING;
  }

  /// "DRIVE 12.3 s, LOOK 4.0 s, ...; creeping 5.1 s of the moving time": where a goal's time went.
  std::string timeBreakdown() const
  {
    std::string text;
    char item[64];
    for (const auto& [mode, seconds] : mode_time_)
    {
      std::snprintf(item, sizeof(item), "%s%s %.1f s", text.empty() ? "" : ", ", mode.c_str(), seconds);
      text += item;
    }
    std::snprintf(item, sizeof(item), "; creeping %.1f s of %.1f s moving", creep_time_, moving_time_);
    return text + item;
  }

  /// Resets the per-goal figures.
  void startCounting()
  {
    std::lock_guard<std::mutex> lock(mutex_);
    path_ = 0.0;
    moving_time_ = 0.0;
    creep_time_ = 0.0;
    mode_time_.clear();
    counting_ = true;
  }

  geometry_msgs::PoseStamped goalPose(const GoalSpec& g) const
  {
    geometry_msgs::PoseStamped p;
    p.header.frame_id = "world";
    p.header.stamp = ros::Time::now();
    p.pose.position.x = g.x;
    p.pose.position.y = g.y;
    p.pose.orientation.w = 0.0;  // no heading: ignored
    return p;
  }

  double path_ = 0.0;
  double moving_time_ = 0.0;
  double creep_time_ = 0.0;           ///< moving while the filter said CREEPING
  std::map<std::string, double> mode_time_;  ///< s per navigator mode while ACTIVE
  bool creeping_ = false;
  bool counting_ = false;
  ros::Time last_pose_stamp_;
  sl_msgs::NavigationStatus nav_;
  int nav_messages_ = 0;
};

TEST_F(Navigate, ReachesEveryReachableGoalAndRefusesTheOthers)
{
  const std::vector<GoalSpec> goals = parseGoals(ros::param::param<std::string>("~goals", ""));
  ASSERT_FALSE(goals.empty()) << "~goals is empty";
  const double tolerance = privateParam("goal_tolerance", 0.10) + privateParam("drift_allowance", 0.05);
  const double reach_time = privateParam("reach_time", 120.0);
  const double refuse_time = privateParam("refuse_time", 65.0);
  const double min_speed = privateParam("min_speed", 0.0);
  ros::Subscriber nav_sub = node_.subscribe<sl_msgs::NavigationStatus>(
      "navigation_status", 50, [this](const sl_msgs::NavigationStatus::ConstPtr& m) { onNavStatus(*m); });
  ros::Publisher simple = node_.advertise<geometry_msgs::PoseStamped>("move_base_simple/goal", 1, true);
  auto client_owner =
      std::make_unique<actionlib::SimpleActionClient<move_base_msgs::MoveBaseAction>>("move_base", true);
  auto& client = *client_owner;
  ASSERT_TRUE(client.waitForServer(ros::Duration(60.0))) << "no move_base action server";
  ASSERT_TRUE(sl_testing::waitUntil(
      [&]
      {
        std::lock_guard<std::mutex> lock(mutex_);
        return nav_messages_ > 0 && have_pose_;
      },
      60.0))
      << "no navigation_status or no true_pose";
  double moving_path = 0.0, moving_time = 0.0;
  int reached = 0, reachable = 0;
  for (std::size_t i = 0; i < goals.size(); ++i)
  {
    const GoalSpec& g = goals[i];
    startCounting();
    const ros::Time start = ros::Time::now();
    bool succeeded = false;
    bool aborted = false;
    std::string why;
    if (i == 0)
    {
      simple.publish(goalPose(g));  // as rviz's "2D Nav Goal" does
      const bool ended = sl_testing::waitUntil(
          [&]
          {
            std::lock_guard<std::mutex> lock(mutex_);
            return nav_.state != sl_msgs::NavigationStatus::ACTIVE && nav_.state != sl_msgs::NavigationStatus::IDLE &&
                   nav_.header.stamp > start + ros::Duration(0.3);
          },
          g.reachable ? reach_time : refuse_time);
      std::lock_guard<std::mutex> lock(mutex_);
      succeeded = ended && nav_.state == sl_msgs::NavigationStatus::SUCCEEDED;
      aborted = ended && nav_.state == sl_msgs::NavigationStatus::ABORTED;
      why = ended ? nav_.reason : "no end within the time limit: " + nav_.reason;
    }
    else
    {
      move_base_msgs::MoveBaseGoal goal;
      goal.target_pose = goalPose(g);
      client.sendGoal(goal);
      const bool ended = client.waitForResult(ros::Duration(g.reachable ? reach_time : refuse_time));
      succeeded = ended && client.getState() == actionlib::SimpleClientGoalState::SUCCEEDED;
      aborted = ended && client.getState() == actionlib::SimpleClientGoalState::ABORTED;
      why = ended ? client.getState().getText() : "no end within the time limit";
      if (!ended)
      {
        client.cancelGoal();
      }
    }
    const double elapsed = (ros::Time::now() - start).toSec();
    std::lock_guard<std::mutex> lock(mutex_);
    counting_ = false;
    const double off = std::hypot(pose_.position.x - g.x, pose_.position.y - g.y);
    std::printf(
        "navigate goal %zu (%.2f, %.2f) %s: %s after %.1f s, path %.2f m, %.2f m/s while moving, %.3f m "
        "from the goal: %s\n",
        i, g.x, g.y, g.reachable ? "reachable" : "unreachable", succeeded ? "SUCCEEDED" : "not reached", elapsed, path_,
        moving_time_ > 0.0 ? path_ / moving_time_ : 0.0, off, why.c_str());
    std::printf("navigate goal %zu time: %s\n", i, timeBreakdown().c_str());
    if (g.reachable)
    {
      ++reachable;
      reached += succeeded ? 1 : 0;
      EXPECT_TRUE(succeeded) << "goal " << i << ": " << why;
      EXPECT_LE(off, tolerance) << "goal " << i;
      moving_path += path_;
      moving_time += moving_time_;
    }
    else
    {
      EXPECT_TRUE(aborted) << "goal " << i << " should be refused as ABORTED: " << why;
      EXPECT_LE(elapsed, refuse_time) << "goal " << i;
    }
  }
  const double speed = moving_time > 0.0 ? moving_path / moving_time : 0.0;
  std::printf("navigate: %d of %d reachable goals reached, %.2f m in %.1f s moving: %.3f m/s\n", reached, reachable,
              moving_path, moving_time, speed);
  EXPECT_GE(speed, min_speed);
  nav_sub.shutdown();
  client_owner.reset();  // its spin thread ends before the node does
  expectNoCollision();
}
}  // namespace sl_bringup_test

int main(int argc, char** argv)
{
  return sl_testing::runRostests(argc, argv, "navigate_rostest");
}
