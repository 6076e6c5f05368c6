// The bump-and-turn baseline of the cleaning-coverage benchmark (baseline.test): a benchmark
// reference, not a product mode, so contacts and collisions are counted, not refused. From the
// baseline's first status (its first command) for `duration` s: the true pose goes to ~path_file
// every 0.1 s ("t x y yaw" per line, s since that start, world frame; as cover_rostest, for
// scripts/cover_truth.py); counted are the driver's bumper contacts (onsets of bump_left or
// bump_right on hazards), the camera simulator's contact onsets and its colliding messages
// (collision: the robot's disc overlaps the scene in any direction). A line a minute and one
// summary line at the end ("baseline <scene> seed <n>: ..."). Fails only when the run does not
// happen (no pose, no collision signal, no status, no movement).
#include <algorithm>
#include <cstdio>
#include <set>
#include <string>

#include <geometry_msgs/PoseStamped.h>
#include <sl_msgs/Collision.h>
#include <sl_msgs/Hazards.h>
#include <std_msgs/String.h>
#include <std_msgs/UInt8.h>

#include <sl_testing/wait.h>

#include "sim_watch.h"  // privateParam, stepBetween, PathFile; runRostests

namespace sl_bringup_test
{
class Baseline : public ::testing::Test
{
protected:
  void SetUp() override
  {
    pose_sub_ = nh_.subscribe("true_pose", 100, &Baseline::onPose, this);
    contact_sub_ = nh_.subscribe("contact", 50, &Baseline::onContact, this);
    collision_sub_ = nh_.subscribe("collision", 100, &Baseline::onCollision, this);
    hazards_sub_ = nh_.subscribe("hazards", 50, &Baseline::onHazards, this);
    status_sub_ = nh_.subscribe("bump_baseline/status", 50, &Baseline::onStatus, this);
  }
  void TearDown() override
  {
    pose_sub_.shutdown();
    contact_sub_.shutdown();
    collision_sub_.shutdown();
    hazards_sub_.shutdown();
    status_sub_.shutdown();
    std::lock_guard<std::mutex> lock(mutex_);
    path_file_.close();
  }

  /// Counting and recording from now on (call with mutex_ held).
  void start()
  {
    started_ = true;
    start_ = ros::Time::now();
    path_file_.setOrigin(start_);
  }

  void onPose(const geometry_msgs::PoseStamped& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!started_ || stopped_)
    {
      pose_ = msg.pose;
      have_pose_ = true;
      return;
    }
    path_ += stepBetween(msg.pose, pose_);
    pose_ = msg.pose;
    ++poses_;
    path_file_.add(ros::Time::now(), msg.pose);
  }
  void onContact(const std_msgs::UInt8& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const bool now = msg.data != 0;
    if (started_ && !stopped_ && now && !contact_)
      ++contact_onsets_;
    contact_ = now;
  }
  void onCollision(const sl_msgs::Collision& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (started_ && !stopped_)
    {
      ++collision_messages_;
      if (msg.colliding)
      {
        ++colliding_messages_;
        collision_onsets_ += colliding_ ? 0 : 1;
        collided_with_.insert(msg.objects.begin(), msg.objects.end());
        deepest_ = std::min(deepest_, static_cast<double>(msg.min_clearance));
      }
    }
    colliding_ = msg.colliding;
  }
  void onHazards(const sl_msgs::Hazards& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const bool now = msg.bump_left || msg.bump_right;
    if (started_ && !stopped_ && now && !bumper_)
      ++bumper_onsets_;
    bumper_ = now;
  }
  void onStatus(const std_msgs::String& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!started_)
      start();
    if (!stopped_)
    {
      status_ = msg.data;
      std::sscanf(msg.data.c_str(), "%*s bumps %d resets %d", &baseline_bumps_, &baseline_resets_);
    }
  }

  /// One line of figures (call with mutex_ held).
  std::string figures() const
  {
    std::string objects;
    for (const std::string& name : collided_with_)
      objects += (objects.empty() ? "" : ",") + name;
    char text[600];
    std::snprintf(text, sizeof(text),
                  "true path %.2f m; bumper contacts %d (driver hazards; sim contact onsets %d, baseline bumps %d, "
                  "reset_hazard calls %d); collision messages %d, colliding %d in %d episodes, deepest %.3f m (%s)",
                  path_, bumper_onsets_, contact_onsets_, baseline_bumps_, baseline_resets_, collision_messages_,
                  colliding_messages_, collision_onsets_, colliding_messages_ > 0 ? -deepest_ : 0.0,
                  objects.empty() ? "-" : objects.c_str());
    return text;
  }

  ros::NodeHandle nh_;
  ros::Subscriber pose_sub_, contact_sub_, collision_sub_, hazards_sub_, status_sub_;
  std::mutex mutex_;
  PathFile path_file_;  // ~path_file, or none
  bool started_ = false, stopped_ = false;
  ros::Time start_;
  bool have_pose_ = false;
  geometry_msgs::Pose pose_;
  int poses_ = 0;
  double path_ = 0.0;
  bool contact_ = false, bumper_ = false, colliding_ = false;
  int contact_onsets_ = 0, bumper_onsets_ = 0;
  int collision_messages_ = 0, colliding_messages_ = 0, collision_onsets_ = 0;
  double deepest_ = 0.0;  // most negative min_clearance of a colliding message, m
  std::set<std::string> collided_with_;
  std::string status_;
  int baseline_bumps_ = 0, baseline_resets_ = 0;
};

TEST_F(Baseline, DrivesAndRecords)
{
  const double duration = privateParam("duration", 600.0);
  const int seed = static_cast<int>(privateParam("seed", 0.0));
  std::string scene = "?", path_file;
  ros::param::get("~scene", scene);
  ros::param::get("~path_file", path_file);
  ASSERT_GT(duration, 0.0) << "~duration must be > 0 s";
  if (!path_file.empty())
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ASSERT_TRUE(path_file_.open(path_file)) << "cannot write ~path_file " << path_file;
  }
  ASSERT_TRUE(sl_testing::waitUntil(
      [&]
      {
        std::lock_guard<std::mutex> lock(mutex_);
        return started_ && have_pose_;
      },
      90.0))
      << "no status from bump_baseline (it starts at the driver's first odometry and hazards) or no true_pose";
  const ros::WallTime wall_start = ros::WallTime::now();
  for (int minute = 1; minute * 60.0 < duration + 60.0; ++minute)
  {
    const double until = std::min(minute * 60.0, duration);
    sl_testing::waitUntil(
        [&]
        {
          std::lock_guard<std::mutex> lock(mutex_);
          return (ros::Time::now() - start_).toSec() >= until;
        },
        until + 60.0, 0.05);
    std::lock_guard<std::mutex> lock(mutex_);
    if (until >= duration)
      stopped_ = true;  // the counts and the path end here
    std::printf("baseline %5.1f s: %s; %s\n", (ros::Time::now() - start_).toSec(), figures().c_str(), status_.c_str());
    std::fflush(stdout);
    if (until >= duration)
      break;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  const double elapsed = (ros::Time::now() - start_).toSec();
  const double wall = (ros::WallTime::now() - wall_start).toSec();
  std::printf("baseline %s seed %d: %.1f s (%.1f s wall, true_pose %.1f Hz); %s; path file %s\n", scene.c_str(), seed,
              elapsed, wall, poses_ / std::max(elapsed, 1e-9), figures().c_str(),
              path_file.empty() ? "-" : path_file.c_str());
  std::fflush(stdout);
  EXPECT_GT(poses_, 0) << "no true_pose during the run";
  EXPECT_GT(collision_messages_, 0) << "no collision message from the camera simulator: cannot tell";
  EXPECT_GT(path_, 0.1) << "the robot did not move";
}
}  // namespace sl_bringup_test

int main(int argc, char** argv)
{
  return sl_testing::runRostests(argc, argv, "baseline_rostest");
}
