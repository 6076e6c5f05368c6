// Exploration on one scene (explore.test): the whole system runs the simulated Create on its own
// for ~duration seconds. Ground truth comes from the simulators and the scene file, not from the
// system under test:
//   - no contact (camera simulator) and no bumper (Create) in the whole run, and no collision of the
//     robot's disc with the scene in any direction (the camera simulator's collision signal);
//   - at least ~min_travel metres of path (where the scene leaves room to move), and at least
//     ~min_progress metres along the start heading (down a corridor);
//   - every stop before an obstacle in the middle of the robot's path (within 0.1 m of its centre
//     line) is at ~clearance +- ~tolerance of travel before the robot's disc would touch it (heights
//     up to H; early by up to 90 mm more, for what the map holds), measured by casting rays through the
//     scene from the true pose; a stop for an
//     obstacle nearer the side of the disc, which often only the map remembers, is within -30 mm
//     and +100 mm of it (the map's 2 cm cells, and the odometry since the obstacle was seen).
// It prints the path length, the floor area the robot's disc covered, the nearest approach to any
// object and the number of stops checked (also the 10-minute soak: `make soak`); in a run longer than
// 120 s, a progress line every 60 s. With ~map_png it draws the obstacle node's local maps merged
// over the run, the true path and the scene's outline into that PNG file (map_picture.h).
// Private parameters: ~scene (file), ~duration (s), ~min_travel (m), ~min_progress (m), ~clearance (m), ~tolerance (m),
// ~robot_radius (m, the disc; base_link to the front edge), ~height (m, top of the working window),
// ~map_png (file; empty: no picture), ~check_stops (bool, true: assert the stops, else only print them).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <nav_msgs/OccupancyGrid.h>
#include <sl_sim/scene.h>

#include "map_picture.h"
#include "node_process.h"
#include "sim_watch.h"

namespace
{

using namespace sl_bringup_test;  // SimWatch and the pose helpers of sim_watch.h

class Explore : public SimWatch
{
protected:
  void TearDown() override
  {
    map_sub_.shutdown();
    SimWatch::TearDown();
  }

  void onPose(const geometry_msgs::Pose* previous, const geometry_msgs::Pose& now) override
  {
    if (!previous)
      start_ = now;
    const MapPoint p = startFrame().fromWorld(now.position.x, now.position.y);
    if (trail_.empty() || std::hypot(p.x - trail_.back().x, p.y - trail_.back().y) >= 0.01)
      trail_.push_back(p);
    const double yaw0 = yawOf(start_);
    progress_ = std::max(progress_, (now.position.x - start_.position.x) * std::cos(yaw0) +
                                        (now.position.y - start_.position.y) * std::sin(yaw0));
    if (previous)
    {
      const double step = stepBetween(now, *previous);
      path_ += step;
      const double dyaw = turnBetween(now, *previous);
      const ros::WallTime t = ros::WallTime::now();
      // A stop before an obstacle is measured where the robot stands when it starts to turn away, or
      // after 0.3 s without moving.
      if (pending_stop_ && (dyaw > 1e-3 || (step <= 2e-4 && (t - last_motion_).toSec() > 0.3)))
      {
        pending_stop_ = false;
        checkStop(*previous);
      }
      if (step > 2e-4 || dyaw > 1e-3)
        last_motion_ = t;
      if (step > 2e-4 && driving_)
        drove_ = true;  // forward motion since the last stop
    }
    nearest_ = std::min(nearest_, clearanceOf(now));
    coverFootprint(now);
  }

  /// The frame of the start pose: the odometry's, which the local map uses.
  MapFrame startFrame() const { return { start_.position.x, start_.position.y, yawOf(start_) }; }

  /// The obstacle node's local map, for ~map_png (it publishes only while someone subscribes).
  void subscribeMap() { map_sub_ = ros::NodeHandle().subscribe("local_map", 2, &Explore::mapCallback, this); }

  void mapCallback(const nav_msgs::OccupancyGrid& msg)
  {
    std::lock_guard<std::mutex> lock(map_mutex_);
    try
    {
      explored_.merge(msg.info.origin.position.x, msg.info.origin.position.y, msg.info.resolution,
                      static_cast<int>(msg.info.width), static_cast<int>(msg.info.height), msg.data);
    }
    catch (const std::invalid_argument& e)
    {
      ROS_WARN_THROTTLE(10.0, "explore: local_map not merged into the picture: %s", e.what());
    }
  }

  /// The picture of ~map_png (call with mutex_ held). @p title: its first line.
  void writeMapPicture(const std::string& file, const std::string& title)
  {
    MapPictureContent content;
    content.path = trail_;
    content.title = { title, "map: the obstacle node's local maps merged (odometry frame); path: true pose" };
    std::lock_guard<std::mutex> lock(map_mutex_);
    content.outline = sceneOutline(scene_, startFrame(), pictureBox(explored_, content.path, content.margin));
    try
    {
      writePng(drawMapPicture(explored_, content), file);
      ROS_INFO("explore map picture: %s", file.c_str());
    }
    catch (const std::runtime_error& e)
    {
      ADD_FAILURE() << "~map_png: " << e.what();
    }
  }

  /// Marks the 5 cm cells under the robot's disc as covered.
  void coverFootprint(const geometry_msgs::Pose& base)
  {
    const int r = static_cast<int>(std::ceil(radius_ / kCell));
    const int cx = static_cast<int>(std::floor(base.position.x / kCell));
    const int cy = static_cast<int>(std::floor(base.position.y / kCell));
    for (int dx = -r; dx <= r; ++dx)
      for (int dy = -r; dy <= r; ++dy)
        if (std::hypot((cx + dx + 0.5) * kCell - base.position.x, (cy + dy + 0.5) * kCell - base.position.y) <= radius_)
          covered_.insert(static_cast<long>(cx + dx) * 100000L + (cy + dy));
  }

  void onStatus(const sl_msgs::ObstacleStatus& msg) override
  {
    using S = sl_msgs::ObstacleStatus;
    states_seen_ |= 1U << msg.state;
    // A trace of the decisions with the true pose, for the test's log.
    if (msg.state != last_state_ || msg.reason_code != last_reason_ || msg.command == S::COMMAND_DRIVE)
    {
      last_state_ = msg.state;
      last_reason_ = msg.reason_code;
      ROS_INFO("explore: at (%.3f, %.3f, %.1f deg): %s", pose_.position.x, pose_.position.y,
               yawOf(pose_) * 180.0 / M_PI, msg.reason.c_str());
    }
    driving_ = msg.state == S::DRIVING || msg.state == S::SLOWING;
    if (msg.state == S::BLOCKED && msg.reason_code == S::REASON_OBSTACLE && drove_)
    {
      drove_ = false;
      pending_stop_ = true;
      char detail[128];
      std::snprintf(detail, sizeof(detail), " [cloud box x %.3f, map contact %.3f]", msg.nearest_distance,
                    msg.map_obstacle_distance);
      stop_reason_ = msg.reason + detail;
    }
  }

  void checkStop(const geometry_msgs::Pose& pose)
  {
    double lateral = 0.0;
    const double d = contactDistance(pose, lateral);
    if (d < clearance_ + 0.10)
    {
      // In the middle of the path the camera sees the obstacle at the stop: the stop is exact. Near
      // the sides of the disc only the map (2 cm cells) remembers it, and a cell's width across the
      // path moves the contact along it by up to twice as much, and the odometry has drifted since the
      // map saw it: such stops may come early, never late.
      (std::abs(lateral) <= kCentre ? stop_errors_ : side_stop_errors_).push_back(d - clearance_);
      ROS_INFO("explore: stopped %.4f m before the obstacle %.3f m off the centre line (clearance %.3f): %s", d,
               lateral, clearance_, stop_reason_.c_str());
    }
  }

  /// Travel straight ahead until the robot's disc touches the scene (heights 0.02 m up to H):
  /// rays along the heading from points of the disc's front half. @p lateral: offset of the
  /// touching point from the path's centre line.
  double contactDistance(const geometry_msgs::Pose& base, double& lateral) const
  {
    const double yaw = yawOf(base);
    const Eigen::Vector3d ahead(std::cos(yaw), std::sin(yaw), 0.0);
    double best = std::numeric_limits<double>::infinity();
    lateral = 0.0;
    for (int k = -45; k <= 45; ++k)
    {
      const double a = k * M_PI / 90.0;
      for (double z = 0.02; z <= height_ + 1e-9; z += 0.03)
      {
        sl_sim::Ray ray;
        ray.origin = Eigen::Vector3d(base.position.x + radius_ * std::cos(yaw + a),
                                     base.position.y + radius_ * std::sin(yaw + a), z);
        ray.direction = ahead;
        sl_sim::Hit hit;
        if (sl_sim::intersectScene(scene_, ray, hit, 1e-6, 3.0) && !scene_.objects[hit.object].floor && hit.t < best)
        {
          best = hit.t;
          lateral = radius_ * std::sin(a);
        }
      }
    }
    return best;
  }

  /// Smallest horizontal gap between the robot's disc and the scene (rays fanned out from the centre).
  double clearanceOf(const geometry_msgs::Pose& base) const
  {
    double best = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 72; ++k)
    {
      const double a = k * M_PI / 36.0;
      for (double z = 0.02; z <= 0.10; z += 0.04)
      {
        sl_sim::Ray ray;
        ray.origin = Eigen::Vector3d(base.position.x, base.position.y, z);
        ray.direction = Eigen::Vector3d(std::cos(a), std::sin(a), 0.0);
        sl_sim::Hit hit;
        if (sl_sim::intersectScene(scene_, ray, hit, 1e-6, 2.0) && !scene_.objects[hit.object].floor)
          best = std::min(best, hit.t - radius_);
      }
    }
    return best;
  }

  static constexpr double kCell = 0.05;
  std::set<long> covered_;
  sl_sim::Scene scene_;
  double radius_ = 0.1675, height_ = 0.173, clearance_ = 0.40;
  double path_ = 0.0;
  geometry_msgs::Pose start_;  // the first true pose
  double progress_ = 0.0;      // farthest along the start heading, m
  double nearest_ = std::numeric_limits<double>::infinity();
  unsigned states_seen_ = 0;
  ros::WallTime last_motion_;
  bool driving_ = false, drove_ = false, pending_stop_ = false;
  int last_state_ = -1, last_reason_ = -1;
  std::string stop_reason_;
  static constexpr double kCentre = 0.10;  // m either side of the centre line: "in the path"
  // m a stop for an obstacle beside it may come late (measured down to -25.4 mm, hall seed 1 under
  // CI load with the sanitizer tests beside it; a lateral error counts 2.1 times there, see below);
  // ~side_late replaces it for a scene (explore.test)
  static constexpr double kSideLate = 0.030;
  // m ... or early: 0.15 m off the centre line the contact travel moves by y / sqrt(r^2 - y^2) = 2.1
  // times any lateral error, and the map's cells count from their nearest corner (measured up to
  // +79.6 mm in 18 runs).
  static constexpr double kSideEarly = 0.10;
  // m a stop for an obstacle in the path may come early beyond ~tolerance (late stops keep
  // ~tolerance): the map can hold the obstacle before the cloud does (its 2 cm cells count from their
  // nearest corner: +26.6 mm, room seed 1), or hold cells where the scene has nothing (suspects at
  // the end of the detectable depth, doc/limitations.md: +84.6 mm, room seed 3; +89.8 mm in an hour).
  static constexpr double kMapEarly = 0.09;
  std::vector<double> stop_errors_, side_stop_errors_;
  std::vector<MapPoint> trail_;  // the true path in the start pose's frame, a point every 1 cm
  std::mutex map_mutex_;         // guards explored_ (the map's callback runs beside the pose's)
  ExploredMap explored_;
  ros::Subscriber map_sub_;
};

TEST_F(Explore, MovesWhereSafeAndNeverTouches)
{
  std::string scene_file;
  ASSERT_TRUE(ros::param::get("~scene", scene_file)) << "~scene is required";
  const double duration = privateParam("duration", 60.0);
  const double min_travel = privateParam("min_travel", -1.0);
  ASSERT_GT(min_travel, 0.0) << "~min_travel must be given (m of path the scene allows)";
  const double min_progress = privateParam("min_progress", 0.0);
  const double tolerance = privateParam("tolerance", 0.010);
  const double side_late = privateParam("side_late", kSideLate);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    scene_ = sl_sim::loadScene(scene_file);
    radius_ = privateParam("robot_radius", radius_);
    height_ = privateParam("height", height_);
    clearance_ = privateParam("clearance", clearance_);
    last_motion_ = ros::WallTime::now();
  }
  const std::string map_png = ros::param::param<std::string>("~map_png", "");
  if (!map_png.empty())
    subscribeMap();
  ASSERT_TRUE(waitForSystem(60.0)) << "no true_pose from create_sim or no obstacle_status";
  // The soak: resident memory of the manager every memory_period s (empty ~memory_node: none).
  MemorySampler memory;
  const std::string memory_node = ros::param::param<std::string>("~memory_node", "");
  ASSERT_TRUE(memory.start(memory_node, privateParam("memory_period", 60.0)))
      << "no pid for ~memory_node " << memory_node;
  const ros::WallTime run = ros::WallTime::now();
  const double progress_period = 60.0;  // s between progress lines, in runs longer than 120 s
  int progress_lines = 0;
  while (ros::ok() && (ros::WallTime::now() - run).toSec() < duration)
  {
    const double elapsed = (ros::WallTime::now() - run).toSec();
    if (memory.sample(elapsed))
      ROS_INFO("explore memory: %s resident %.1f MB after %.0f s", memory_node.c_str(), memory.samples().back(),
               elapsed);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (duration > 120.0 && elapsed >= progress_period * (progress_lines + 1))
      {
        ++progress_lines;
        char rss[64] = "";
        if (!memory.samples().empty())
          std::snprintf(rss, sizeof(rss), ", resident %.1f MB", memory.samples().back());
        ROS_INFO("explore progress: %.0f / %.0f s, path %.2f m, area covered %.2f m^2%s", elapsed, duration, path_,
                 covered_.size() * kCell * kCell, rss);
      }
      if (contact_bits_ != 0 || bumped_ || colliding_messages_ > 0)
        break;
    }
    ros::WallDuration(0.1).sleep();
  }
  expectNoCollision();
  std::lock_guard<std::mutex> lock(mutex_);
  const double ran = (ros::WallTime::now() - run).toSec();
  ROS_INFO(
      "explore %s: path %.2f m in %.0f s, area covered %.2f m^2, nearest approach %.3f m, %zu + %zu stops "
      "before obstacles in the path / beside it, states 0x%x",
      scene_.name.c_str(), path_, ran, covered_.size() * kCell * kCell, nearest_, stop_errors_.size(),
      side_stop_errors_.size(), states_seen_);
  if (!map_png.empty())
  {
    char title[160];
    std::snprintf(title, sizeof(title), "%s: %.0f s, path %.1f m, area covered %.2f m^2, nearest approach %.3f m",
                  scene_.name.c_str(), ran, path_, covered_.size() * kCell * kCell, nearest_);
    writeMapPicture(map_png, title);
  }
  EXPECT_EQ(contact_bits_, 0) << "the robot touched something";
  EXPECT_FALSE(bumped_) << "a bumper fired";
  EXPECT_GT(contact_messages_, 0) << "no contact messages: the check above saw nothing";
  EXPECT_GT(nearest_, 0.0) << "the disc overlapped an object";
  EXPECT_GE(path_, min_travel) << "the robot did not move enough where the space allows";
  ROS_INFO("explore %s: %.2f m along the start heading", scene_.name.c_str(), progress_);
  EXPECT_GE(progress_, min_progress) << "the robot did not get far enough along its start heading";
  // Flat memory: after the first memory_settle samples it grows by at most memory_growth MB.
  const std::size_t settle = static_cast<std::size_t>(privateParam("memory_settle", 3.0));
  const double growth = memory.growth(settle);
  if (!std::isnan(growth))
  {
    // MB; measured 0.8 MB over an hour
    EXPECT_LE(growth, privateParam("memory_growth", 3.0)) << memory.growthText(settle);
  }
  // The stops against the ground truth: printed always, asserted unless ~check_stops is false (the
  // soak: in an hour 3 of 125 stops came 25 to 90 mm early, for map cells occupied where the scene
  // has nothing; early, never late).
  const auto range = [](const std::vector<double>& v)
  {
    char text[64] = "none";
    if (!v.empty())
      std::snprintf(text, sizeof(text), "%+.1f .. %+.1f mm", *std::min_element(v.begin(), v.end()) * 1000.0,
                    *std::max_element(v.begin(), v.end()) * 1000.0);
    return std::string(text);
  };
  ROS_INFO("explore %s: stops off the clearance: in the path %s (%zu), beside it %s (%zu)", scene_.name.c_str(),
           range(stop_errors_).c_str(), stop_errors_.size(), range(side_stop_errors_).c_str(),
           side_stop_errors_.size());
  if (!ros::param::param<bool>("~check_stops", true))
    return;
  for (const double e : stop_errors_)
  {
    EXPECT_GE(e, -tolerance) << "stop " << e << " m nearer than the clearance (obstacle in the path)";
    EXPECT_LE(e, tolerance + kMapEarly) << "stop " << e << " m early (obstacle in the path)";
  }
  for (const double e : side_stop_errors_)
  {
    EXPECT_GE(e, -side_late) << "stop " << e << " m nearer than the clearance (obstacle beside the centre line)";
    EXPECT_LE(e, kSideEarly) << "stop " << e << " m early (obstacle beside the centre line)";
  }
}

}  // namespace

int main(int argc, char** argv)
{
  return sl_testing::runRostests(argc, argv, "explore_rostest");
}
