// Cleaning coverage in simulation (cover.test): sim.launch with behaviour cover runs for `duration`
// seconds (or until the navigation reports the cleaning DONE). The coverage must rise above
// min_progress (coverage_progress: covered / reachable known floor), the coverage grid must come
// (nav_msgs/OccupancyGrid with covered cells), and nothing may be touched in any direction (the
// camera simulator's collision signal), nor the bumper. Prints the progress and the true path every
// 20 s, a line per minute (progress, colliding messages, nearest approach) and, at the end, the
// progress at each whole minute. With ~path_file set, the true pose goes there every 0.1 s
// ("t x y yaw" per line, s since the first pose, world frame) for measuring against the scene.
// With ~memory_node set (the soak), that node's process's resident memory is sampled every
// ~memory_period s and must grow by at most ~memory_growth MB over the second half of the run (or
// after the first ~memory_settle samples).
#include <cmath>
#include <cstdio>
#include <string>

#include <nav_msgs/OccupancyGrid.h>
#include <sl_msgs/NavigationStatus.h>
#include <std_msgs/Float32.h>

#include <sl_testing/wait.h>

#include "node_process.h"
#include "sim_watch.h"

namespace sl_bringup_test
{
class Cover : public SimWatch
{
protected:
  void onPose(const geometry_msgs::Pose* previous, const geometry_msgs::Pose& now) override
  {
    if (previous != nullptr)
    {
      path_ += stepBetween(now, *previous);
    }
    path_file_.add(ros::Time::now(), now);
  }
  void onStatus(const sl_msgs::ObstacleStatus&) override {}

  void onProgress(const std_msgs::Float32& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    progress_ = msg.data;
    best_progress_ = std::max(best_progress_, static_cast<double>(msg.data));
    ++progress_messages_;
  }
  void onGrid(const nav_msgs::OccupancyGrid& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++grid_messages_;
    grid_consistent_ =
        msg.data.size() == static_cast<std::size_t>(msg.info.width) * msg.info.height && msg.header.frame_id == "odom";
    covered_cells_ = 0;
    for (const std::int8_t v : msg.data)
    {
      covered_cells_ += v == 100 ? 1 : 0;
    }
  }
  void onNavStatus(const sl_msgs::NavigationStatus& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    reason_ = msg.reason;
    done_ = msg.mode == "DONE";
    ++nav_messages_;
  }

  ros::NodeHandle node_;
  PathFile path_file_;  // ~path_file, or none
  double path_ = 0.0;
  double progress_ = 0.0;
  double best_progress_ = 0.0;
  int progress_messages_ = 0;
  int grid_messages_ = 0;
  bool grid_consistent_ = false;
  int covered_cells_ = 0;
  std::string reason_;
  bool done_ = false;
  int nav_messages_ = 0;
};

TEST_F(Cover, CoversTheRoomWithoutTouching)
{
  const double duration = privateParam("duration", 120.0);
  const double min_progress = privateParam("min_progress", 0.0);
  std::string path_file;
  ros::param::get("~path_file", path_file);
  if (!path_file.empty())
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ASSERT_TRUE(path_file_.open(path_file)) << "cannot write ~path_file " << path_file;
  }
  ros::Subscriber progress_sub = node_.subscribe<std_msgs::Float32>(
      "coverage_progress", 10, [this](const std_msgs::Float32::ConstPtr& m) { onProgress(*m); });
  ros::Subscriber grid_sub = node_.subscribe<nav_msgs::OccupancyGrid>(
      "coverage", 2, [this](const nav_msgs::OccupancyGrid::ConstPtr& m) { onGrid(*m); });
  ros::Subscriber nav_sub = node_.subscribe<sl_msgs::NavigationStatus>(
      "navigation_status", 50, [this](const sl_msgs::NavigationStatus::ConstPtr& m) { onNavStatus(*m); });
  ASSERT_TRUE(sl_testing::waitUntil(
      [&]
      {
        std::lock_guard<std::mutex> lock(mutex_);
        return nav_messages_ > 0 && have_pose_;
      },
      60.0))
      << "no navigation_status or no true_pose";
  MemorySampler memory;
  const std::string memory_node = ros::param::param<std::string>("~memory_node", "");
  ASSERT_TRUE(memory.start(memory_node, privateParam("memory_period", 60.0)))
      << "no pid for ~memory_node " << memory_node;
  const ros::Time start = ros::Time::now();
  memory.sample(0.0);
  std::string per_minute;  // the progress at each whole minute
  for (int step = 1; step * 20.0 <= duration + 1e-9; ++step)
  {
    const bool ended = sl_testing::waitUntil(
        [&]
        {
          std::lock_guard<std::mutex> lock(mutex_);
          return done_;
        },
        20.0);
    const double elapsed = (ros::Time::now() - start).toSec();
    if (memory.sample(elapsed))
      std::printf("cover memory: %s resident %.1f MB after %.0f s\n", memory_node.c_str(), memory.samples().back(),
                  elapsed);
    std::lock_guard<std::mutex> lock(mutex_);
    std::printf("cover %5.1f s: coverage_progress %.3f, %d cells covered, true path %.2f m, min clearance %.3f m: %s\n",
                elapsed, progress_, covered_cells_, path_, min_clearance_, reason_.c_str());
    if (step % 3 == 0)
    {
      std::printf("cover minute %d: coverage_progress %.3f, %d colliding messages, nearest approach %.3f m (%s)\n",
                  step / 3, progress_, colliding_messages_, min_clearance_, nearest_object_.c_str());
      char entry[32];
      std::snprintf(entry, sizeof(entry), "%s%d %.3f", per_minute.empty() ? "" : ", ", step / 3, progress_);
      per_minute += entry;
    }
    if (ended)
    {
      break;
    }
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    std::printf("cover: best coverage_progress %.3f (floor %.3f) after %.1f s%s, true path %.2f m\n", best_progress_,
                min_progress, (ros::Time::now() - start).toSec(), done_ ? ", DONE" : "", path_);
    std::printf("cover: progress at minute %s; %d colliding messages; nearest approach %.3f m (%s)\n",
                per_minute.c_str(), colliding_messages_, min_clearance_, nearest_object_.c_str());
    EXPECT_GE(best_progress_, min_progress);
    EXPECT_GT(progress_messages_, 0) << "no coverage_progress";
    EXPECT_GT(grid_messages_, 0) << "no coverage grid";
    EXPECT_TRUE(grid_consistent_) << "the coverage grid's size or frame is wrong";
    EXPECT_GT(covered_cells_, 0) << "the coverage grid shows nothing covered";
    EXPECT_EQ(contact_bits_, 0) << "bumper contact in the simulator";
    EXPECT_FALSE(bumped_) << "the driver reported a bump";
  }
  // Flat memory (the soak): the persistent map's pages are touched as the robot finds the room, so
  // it is measured from the middle of the run on, unless ~memory_settle names the first sample.
  const double settle_sample = privateParam("memory_settle", -1.0);
  const std::size_t settle =
      settle_sample >= 0.0 ? static_cast<std::size_t>(settle_sample) : memory.samples().size() / 2;
  const double growth = memory.growth(settle);
  if (!std::isnan(growth))
  {
    std::printf("cover memory: %s\n", memory.growthText(settle).c_str());
    EXPECT_LE(growth, privateParam("memory_growth", 1.0)) << memory.growthText(settle);  // MB, as cover.test
  }
  progress_sub.shutdown();
  grid_sub.shutdown();
  nav_sub.shutdown();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    path_file_.close();
  }
  expectNoCollision();
}
}  // namespace sl_bringup_test

int main(int argc, char** argv)
{
  return sl_testing::runRostests(argc, argv, "cover_rostest");
}
