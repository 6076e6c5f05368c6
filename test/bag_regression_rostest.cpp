// Rosbag regression (bag_wall.test, bag_leg.test): a bag recorded from the simulator is replayed
// through the decoder and the obstacle node (launch/replay.launch); the cloud of every recorded
// image and the decision taken on it must match the recorded expectations within the tolerances
// stated in the expectations file.
//
// Private parameters:
//   ~bag            the bag being replayed (read here for the image stamps)
//   ~expectations   YAML file of the expected per-frame values and the tolerances
//   ~write          when not empty: write the expectations of this run to that file instead of
//                   comparing (scripts/record_bringup_bags.sh does this after recording a bag)
//   ~timeout        wall-clock s to wait for the replay (default 300)
//
// Per frame (one recorded image): the cloud's point count, the mean and the minimum x of its points
// inside the working window (|y| <= W/2, floor_margin < z <= H, 0 < x <= max_range), and the
// obstacle node's first decision on that cloud: state, reason, blocked, nearest and free distance,
// coverage.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <sl_msgs/ObstacleStatus.h>
#include <yaml-cpp/yaml.h>

#include <sl_testing/rostest_main.h>

namespace
{

using Status = sl_msgs::ObstacleStatus;

const char* stateName(int state)
{
  static const char* names[] = { "STALE", "STOPPED", "BLOCKED", "TURNING", "SLOWING", "DRIVING" };
  return state >= 0 && state < 6 ? names[state] : "?";
}

/// The window the statistics are taken in: sl_obstacle's default working window, up to 1.2 m.
constexpr double kHalfWidth = 0.331 / 2.0, kFloor = 0.015, kHeight = 0.173, kRange = 1.2;

struct CloudStats
{
  int points = 0;         ///< all points of the cloud
  int window_points = 0;  ///< points inside the window
  double mean_x = std::numeric_limits<double>::quiet_NaN();
  double min_x = std::numeric_limits<double>::quiet_NaN();
};

struct Decision
{
  int state = -1;
  int reason = -1;
  bool blocked = false;
  double nearest = std::numeric_limits<double>::infinity();
  double free = 0.0;
  double coverage = 0.0;
};

struct Frame
{
  double stamp = 0.0;
  bool have_cloud = false, have_decision = false;
  CloudStats cloud;
  Decision decision;
};

CloudStats statsOf(const sensor_msgs::PointCloud2& cloud)
{
  CloudStats s;
  s.points = static_cast<int>(cloud.width * cloud.height);
  double sum = 0.0, min_x = std::numeric_limits<double>::infinity();
  sensor_msgs::PointCloud2ConstIterator<float> x(cloud, "x"), y(cloud, "y"), z(cloud, "z");
  for (; x != x.end(); ++x, ++y, ++z)
  {
    if (!std::isfinite(*x) || !std::isfinite(*y) || !std::isfinite(*z))
      continue;
    if (*x <= 0.0 || *x > kRange || std::abs(*y) > kHalfWidth || *z <= kFloor || *z > kHeight)
      continue;
    ++s.window_points;
    sum += *x;
    min_x = std::min(min_x, static_cast<double>(*x));
  }
  if (s.window_points > 0)
  {
    s.mean_x = sum / s.window_points;
    s.min_x = min_x;
  }
  return s;
}

/// Equal within tolerance; two infinities (no obstacle) or two NaNs (no window point) are equal.
bool near(double a, double b, double tolerance)
{
  if (std::isnan(a) || std::isnan(b))
    return std::isnan(a) && std::isnan(b);
  if (std::isinf(a) || std::isinf(b))
    return a == b;
  return std::abs(a - b) <= tolerance;
}

double yamlDouble(const YAML::Node& node)
{
  const std::string s = node.as<std::string>();
  if (s == ".inf" || s == "inf")
    return std::numeric_limits<double>::infinity();
  if (s == ".nan" || s == "nan")
    return std::numeric_limits<double>::quiet_NaN();
  return node.as<double>();
}

std::string yamlNumber(double v)
{
  if (std::isnan(v))
    return ".nan";
  if (std::isinf(v))
    return v > 0 ? ".inf" : "-.inf";
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.4f", v);
  return buffer;
}

class BagRegression : public ::testing::Test
{
protected:
  void onCloud(const sensor_msgs::PointCloud2ConstPtr& msg)
  {
    const CloudStats s = statsOf(*msg);
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = frames_.find(key(msg->header.stamp));
    if (it == frames_.end())
    {
      ++unknown_clouds_;
      return;
    }
    it->second.have_cloud = true;
    it->second.cloud = s;
  }

  void onStatus(const Status& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = frames_.find(key(msg.cloud_stamp));
    if (it == frames_.end() || it->second.have_decision)
      return;  // not a recorded frame, or not the first decision on it
    Decision& d = it->second.decision;
    it->second.have_decision = true;
    d.state = msg.state;
    d.reason = msg.reason_code;
    d.blocked = msg.blocked;
    d.nearest = msg.nearest_distance;
    d.free = msg.free_distance;
    d.coverage = msg.coverage;
  }

  void TearDown() override
  {
    // No callback may run on the fixture once it is being destroyed.
    cloud_sub_.shutdown();
    status_sub_.shutdown();
  }

  void subscribe(ros::NodeHandle& nh)
  {
    cloud_sub_ = nh.subscribe("points", 20, &BagRegression::onCloud, this);
    status_sub_ = nh.subscribe("obstacle_status", 200, &BagRegression::onStatus, this);
  }

  static int64_t key(const ros::Time& t)
  {
    return static_cast<int64_t>(t.toNSec() / 1000);  // microseconds
  }

  ros::Subscriber cloud_sub_, status_sub_;
  std::mutex mutex_;
  std::map<int64_t, Frame> frames_;
  int unknown_clouds_ = 0;
};

TEST_F(BagRegression, CloudsAndDecisionsMatchTheRecording)
{
  ros::NodeHandle nh, pnh("~");
  std::string bag_path, expectations_path, write_path;
  double timeout = 300.0;
  ASSERT_TRUE(pnh.getParam("bag", bag_path)) << "~bag is required";
  pnh.getParam("expectations", expectations_path);
  pnh.getParam("write", write_path);
  pnh.getParam("timeout", timeout);
  ASSERT_TRUE(!expectations_path.empty() || !write_path.empty()) << "~expectations or ~write is required";

  // The recorded images, in order.
  std::vector<int64_t> order;
  {
    rosbag::Bag bag;
    ASSERT_NO_THROW(bag.open(bag_path, rosbag::bagmode::Read)) << "cannot open " << bag_path;
    rosbag::View view(bag, rosbag::TopicQuery(std::vector<std::string>{ "/camera/image_raw" }));
    for (const rosbag::MessageInstance& m : view)
    {
      const sensor_msgs::ImageConstPtr image = m.instantiate<sensor_msgs::Image>();
      if (!image)
        continue;
      std::lock_guard<std::mutex> lock(mutex_);
      Frame f;
      f.stamp = image->header.stamp.toSec();
      frames_[key(image->header.stamp)] = f;
      order.push_back(key(image->header.stamp));
    }
  }
  ASSERT_GT(order.size(), 2u) << bag_path << " holds no /camera/image_raw images";
  const double last_stamp = frames_[order.back()].stamp;

  subscribe(nh);

  // Wait until every frame has its cloud and decision, or the bag's time is 3 s past its last image.
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout);
  bool complete = false;
  while (ros::ok() && ros::WallTime::now() < deadline)
  {
    ros::WallDuration(0.2).sleep();
    std::lock_guard<std::mutex> lock(mutex_);
    complete = std::all_of(frames_.begin(), frames_.end(),
                           [](const std::pair<const int64_t, Frame>& f)
                           { return f.second.have_cloud && f.second.have_decision; });
    if (complete || (!ros::Time::now().isZero() && ros::Time::now().toSec() > last_stamp + 3.0))
      break;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  int clouds = 0, decisions = 0;
  for (const auto& f : frames_)
  {
    clouds += f.second.have_cloud;
    decisions += f.second.have_decision;
  }
  ROS_INFO("bag regression: %zu images, %d clouds, %d decisions (%d clouds of other stamps)", order.size(), clouds,
           decisions, unknown_clouds_);

  if (!write_path.empty())
  {
    ASSERT_TRUE(complete) << "the replay lost frames: not writing expectations from it";
    std::ofstream out(write_path);
    ASSERT_TRUE(out.good()) << "cannot write " << write_path;
    out << "# Expected replay results of " << bag_path.substr(bag_path.find_last_of('/') + 1)
        << " (written by bag_regression_rostest: scripts/record_bringup_bags.sh).\n"
        << "# Per recorded image: the decoder's cloud (points; mean_x, min_x of the points in the working\n"
        << "# window |y| <= 0.1655, 0.015 < z <= 0.173, x <= 1.2 m) and the obstacle node's first decision on it\n"
        << "# (state, reason = sl_msgs/ObstacleStatus reason_code, blocked, nearest, free, coverage).\n"
        << "tolerances:\n"
        << "  max_lost_frames: 1        # frames whose cloud or decision may be missing (a loaded machine)\n"
        << "  points_fraction: 0.10     # |points - expected| <= this * expected + points_abs\n"
        << "  points_abs: 10\n"
        << "  distance: 0.010           # m, mean_x, min_x, nearest and free distance\n"
        << "  coverage: 0.10\n"
        << "  max_state_mismatches: 2   # frames whose state or blocked flag may differ (timing of goals); not the "
           "last\n"
        << "frames:\n";
    for (int64_t k : order)
    {
      const Frame& f = frames_.at(k);
      char stamp[32];
      std::snprintf(stamp, sizeof(stamp), "%.6f", f.stamp);
      out << "  - {stamp: " << stamp << ", points: " << f.cloud.points << ", window_points: " << f.cloud.window_points
          << ", mean_x: " << yamlNumber(f.cloud.mean_x) << ", min_x: " << yamlNumber(f.cloud.min_x)
          << ", state: " << stateName(f.decision.state) << ", reason: " << f.decision.reason
          << ", blocked: " << (f.decision.blocked ? "true" : "false") << ", nearest: " << yamlNumber(f.decision.nearest)
          << ", free: " << yamlNumber(f.decision.free) << ", coverage: " << yamlNumber(f.decision.coverage) << "}\n";
    }
    ROS_INFO("wrote %s", write_path.c_str());
    return;
  }

  YAML::Node expected;
  ASSERT_NO_THROW(expected = YAML::LoadFile(expectations_path)) << "cannot read " << expectations_path;
  const YAML::Node tol = expected["tolerances"];
  const int max_lost = tol["max_lost_frames"].as<int>();
  const double points_fraction = tol["points_fraction"].as<double>();
  const int points_abs = tol["points_abs"].as<int>();
  const double distance = tol["distance"].as<double>();
  const double coverage = tol["coverage"].as<double>();
  const int max_state_mismatches = tol["max_state_mismatches"].as<int>();

  const YAML::Node list = expected["frames"];
  ASSERT_EQ(list.size(), order.size()) << expectations_path << " was written for another bag";
  int lost = 0, state_mismatches = 0;
  for (size_t i = 0; i < order.size(); ++i)
  {
    const YAML::Node e = list[i];
    const Frame& f = frames_.at(order[i]);
    ASSERT_NEAR(e["stamp"].as<double>(), f.stamp, 1e-5)
        << "frame " << i << ": " << expectations_path << " was written for another bag";
    if (!f.have_cloud || !f.have_decision)
    {
      ++lost;
      continue;
    }
    const int points = e["points"].as<int>();
    const double allowed = points_fraction * points + points_abs;
    EXPECT_LE(std::abs(f.cloud.points - points), allowed)
        << "frame " << i << ": points " << f.cloud.points << ", expected " << points;
    const int window_points = e["window_points"].as<int>();
    EXPECT_LE(std::abs(f.cloud.window_points - window_points), points_fraction * window_points + points_abs)
        << "frame " << i << ": window points " << f.cloud.window_points << ", expected " << window_points;
    EXPECT_TRUE(near(f.cloud.mean_x, yamlDouble(e["mean_x"]), distance))
        << "frame " << i << ": mean x " << f.cloud.mean_x << ", expected " << e["mean_x"].as<std::string>();
    EXPECT_TRUE(near(f.cloud.min_x, yamlDouble(e["min_x"]), distance))
        << "frame " << i << ": min x " << f.cloud.min_x << ", expected " << e["min_x"].as<std::string>();
    EXPECT_TRUE(near(f.decision.nearest, yamlDouble(e["nearest"]), distance))
        << "frame " << i << ": nearest " << f.decision.nearest << ", expected " << e["nearest"].as<std::string>();
    EXPECT_TRUE(near(f.decision.free, yamlDouble(e["free"]), distance + 0.01))
        << "frame " << i << ": free " << f.decision.free << ", expected " << e["free"].as<std::string>();
    EXPECT_TRUE(near(f.decision.coverage, yamlDouble(e["coverage"]), coverage))
        << "frame " << i << ": coverage " << f.decision.coverage << ", expected " << e["coverage"].as<std::string>();
    const std::string state = e["state"].as<std::string>();
    // The state must match; the reason may vary while driving (re-sent, pre-empted or running
    // goal: it depends on when the goal feedback arrives), so it is only logged.
    if (state != stateName(f.decision.state) || e["blocked"].as<bool>() != f.decision.blocked)
    {
      ++state_mismatches;
      ROS_WARN("frame %zu: decision %s / reason %d / blocked %d, recorded %s / reason %d / blocked %d", i,
               stateName(f.decision.state), f.decision.reason, f.decision.blocked, state.c_str(), e["reason"].as<int>(),
               e["blocked"].as<bool>());
    }
    else if (e["reason"].as<int>() != f.decision.reason)
    {
      ROS_INFO("frame %zu: reason %d, recorded %d (same state %s)", i, f.decision.reason, e["reason"].as<int>(),
               state.c_str());
    }
  }
  EXPECT_LE(lost, max_lost) << "frames without a cloud or a decision";
  EXPECT_LE(state_mismatches, max_state_mismatches) << "decisions differ from the recording";
  // The decision on the last frame (where the recording ends: stopped before the obstacle, turning
  // away) must be the same.
  const Frame& last = frames_.at(order.back());
  if (last.have_decision)
  {
    EXPECT_STREQ(stateName(last.decision.state), list[order.size() - 1]["state"].as<std::string>().c_str());
    EXPECT_EQ(last.decision.blocked, list[order.size() - 1]["blocked"].as<bool>());
  }
}

}  // namespace

int main(int argc, char** argv)
{
  return sl_testing::runRostests(argc, argv, "bag_regression_rostest");
}
