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
#include <string>

#include <std_msgs/String.h>

#include <sl_testing/wait.h>

#include "sim_watch.h"  // SimWatch, privateParam, stepBetween, PathFile; runRostests

namespace sl_bringup_test
{
/// SimWatch in Collisions::kCount mode, counting (counting_) from the baseline's first status
/// (start()) to the end of `duration`; plus the true path and the baseline's own status.
class Baseline : public SimWatch
{
protected:
  Baseline() : SimWatch(Collisions::kCount)
  {
    counting_ = false;  // from start() on
  }

  void SetUp() override
  {
    SimWatch::SetUp();
    baseline_sub_ = nh_.subscribe("bump_baseline/status", 50, &Baseline::onBaselineStatus, this);
  }
  void TearDown() override
  {
    baseline_sub_.shutdown();
    SimWatch::TearDown();
    std::lock_guard<std::mutex> lock(mutex_);
    path_file_.close();
  }

  /// Counting and recording from now on (call with mutex_ held).
  void start()
  {
    started_ = true;
    counting_ = true;
    start_ = ros::Time::now();
    path_file_.setOrigin(start_);
  }

  void onPose(const geometry_msgs::Pose* previous, const geometry_msgs::Pose& now) override
  {
    if (!counting_)
      return;
    if (previous != nullptr)
      path_ += stepBetween(now, *previous);
    ++poses_;
    path_file_.add(ros::Time::now(), now);
  }
  /// The baseline has no obstacle node.
  void onStatus(const sl_msgs::ObstacleStatus&) override {}

  void onBaselineStatus(const std_msgs::String& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!started_)
      start();
    if (counting_)
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
                  path_, bump_onsets_, contact_onsets_, baseline_bumps_, baseline_resets_, collision_messages_,
                  colliding_messages_, collision_onsets_, colliding_messages_ > 0 ? -min_clearance_ : 0.0,
                  objects.empty() ? "-" : objects.c_str());
    return text;
  }

  ros::NodeHandle nh_;
  ros::Subscriber baseline_sub_;
  PathFile path_file_;  // ~path_file, or none
  bool started_ = false;
  ros::Time start_;
  int poses_ = 0;
  double path_ = 0.0;
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
      counting_ = false;  // the counts and the path end here
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
