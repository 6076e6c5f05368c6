// Rostest of obstacle_map.test: the map mode of the obstacle node against missing odometry and a
// ray cloud without its state field. The test publishes the decoder's two clouds (a dark view: no
// points, every ray free) and, later, odom -> base_link.
#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <map>
#include <mutex>
#include <string>

#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/Twist.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>
#include <sensor_msgs/PointCloud2.h>
#include <sl_testing/rostest_main.h>
#include <tf2_ros/transform_broadcaster.h>

#include "sl_msgs/ObstacleStatus.h"

namespace
{
/// A cloud in platform_edge with FLOAT32 x, y, z, sx, sy, sz (and UINT8 state if @p state) of @p n
/// rays straight ahead from 0.25 m to 1.2 m at 0.08 m height.
sensor_msgs::PointCloud2 cloud(const ros::Time& stamp, int n, bool state)
{
  sensor_msgs::PointCloud2 c;
  c.header.stamp = stamp;
  c.header.frame_id = "platform_edge";
  const char* names[6] = { "x", "y", "z", "sx", "sy", "sz" };
  for (uint32_t i = 0; i < 6; ++i)
  {
    sensor_msgs::PointField f;
    f.name = names[i];
    f.offset = 4 * i;
    f.datatype = sensor_msgs::PointField::FLOAT32;
    f.count = 1;
    c.fields.push_back(f);
  }
  c.point_step = 24;
  if (state)
  {
    sensor_msgs::PointField f;
    f.name = "state";
    f.offset = 24;
    f.datatype = sensor_msgs::PointField::UINT8;
    f.count = 1;
    c.fields.push_back(f);
    c.point_step = 25;
  }
  c.height = 1;
  c.width = static_cast<uint32_t>(n);
  c.row_step = c.point_step * c.width;
  c.data.assign(c.row_step, 0);
  for (int k = 0; k < n; ++k)
  {
    const float y = -0.2F + 0.4F * static_cast<float>(k) / static_cast<float>(n > 1 ? n - 1 : 1);
    const float v[6] = { 1.2F, 1.5F * y, 0.08F, 0.25F, 0.3F * y, 0.08F };
    std::memcpy(c.data.data() + k * c.point_step, v, sizeof(v));
    if (state)
    {
      c.data[k * c.point_step + 24] = 2;  // dark
    }
  }
  return c;
}

class ObstacleMap : public ::testing::Test
{
protected:
  void SetUp() override
  {
    points_pub_ = nh_.advertise<sensor_msgs::PointCloud2>("points", 2);
    rays_pub_ = nh_.advertise<sensor_msgs::PointCloud2>("ray_ends", 2);
    twist_sub_ = nh_.subscribe("cmd_vel", 10, &ObstacleMap::onTwist, this);  // the driver's place
    status_sub_ = nh_.subscribe("obstacle_status", 50, &ObstacleMap::onStatus, this);
    log_sub_ = nh_.subscribe("/rosout", 200, &ObstacleMap::onLog, this);
  }
  // The spinner threads may be in a callback: end the subscriptions (shutdown() waits for it)
  // before the members the callbacks write are destroyed.
  void TearDown() override
  {
    twist_sub_.shutdown();
    status_sub_.shutdown();
    log_sub_.shutdown();
  }

  void onTwist(const geometry_msgs::Twist&) {}
  void onStatus(const sl_msgs::ObstacleStatus& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    last_ = msg;
    if (statuses_++ == 0)
      joined_at_ = msg.cloud_stamp.toNSec();
    // The order of the first decision on each image's cloud and the first on the map with its rays.
    first_on_cloud_.emplace(msg.cloud_stamp.toNSec(), statuses_);
    if (!msg.map_stamp.isZero())
      first_on_map_.emplace(msg.map_stamp.toNSec(), statuses_);
  }
  void onLog(const rosgraph_msgs::Log& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (msg.msg.find("no field state") != std::string::npos)
      state_error_ = true;
  }

  /// Publishes clouds (and odometry when @p odom) for @p seconds.
  void run(double seconds, bool odom, bool with_state)
  {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
    while (ros::ok() && ros::WallTime::now() < end)
    {
      const ros::Time now = ros::Time::now();
      if (odom)
      {
        geometry_msgs::TransformStamped t;
        t.header.stamp = now;
        t.header.frame_id = "odom";
        t.child_frame_id = "base_link";
        t.transform.rotation.w = 1.0;
        tf_.sendTransform(t);
      }
      points_pub_.publish(cloud(now, 0, false));
      rays_pub_.publish(cloud(now, 64, with_state));
      ros::WallDuration(0.1).sleep();
    }
  }

  ros::NodeHandle nh_;
  ros::Publisher points_pub_, rays_pub_;
  ros::Subscriber twist_sub_, status_sub_, log_sub_;
  tf2_ros::TransformBroadcaster tf_;
  std::mutex mutex_;
  sl_msgs::ObstacleStatus last_;
  int statuses_ = 0;
  uint64_t joined_at_ = 0;  // the image of the first status seen: its cloud's status may predate us
  std::map<uint64_t, int> first_on_cloud_, first_on_map_;  // image stamp -> index of the status
  bool state_error_ = false;
};

TEST_F(ObstacleMap, StopsWithoutOdometryAndNamesAMissingField)
{
  using S = sl_msgs::ObstacleStatus;
  run(4.0, false, true);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ASSERT_GT(statuses_, 0);
    EXPECT_EQ(last_.reason_code, S::REASON_NO_ODOMETRY) << last_.reason;
    EXPECT_EQ(last_.state, S::STOPPED);
    EXPECT_NE(last_.reason.find("odom"), std::string::npos) << last_.reason;
  }
  run(4.0, true, true);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    EXPECT_NE(last_.reason_code, S::REASON_NO_ODOMETRY) << last_.reason;
    EXPECT_NE(last_.reason_code, S::REASON_STALE_DATA) << last_.reason;
  }
  run(3.0, true, false);
  std::lock_guard<std::mutex> lock(mutex_);
  EXPECT_TRUE(state_error_) << "a ray cloud without the state field must be refused by name";
}

TEST_F(ObstacleMap, DecidesAgainOnEachMapUpdateAfterTheStopCheck)
{
  // Each image's rays go into the map after the decision on its cloud; the node then decides again,
  // and that status names the image in map_stamp.
  run(3.0, true, true);
  std::lock_guard<std::mutex> lock(mutex_);
  int ordered = 0;
  for (const auto& m : first_on_map_)
  {
    const auto c = first_on_cloud_.find(m.first);
    if (c == first_on_cloud_.end() || m.first <= joined_at_)
      continue;  // its points were dropped (the rays went in alone), or it came before we subscribed
    EXPECT_LT(c->second, m.second) << "the map-updated plan came before the stop check on the cloud";
    ++ordered;
  }
  EXPECT_GE(ordered, 15) << "about 30 images were published";
}
}  // namespace

int main(int argc, char** argv)
{
  return sl_testing::runRostests(argc, argv, "obstacle_map_rostest");
}
