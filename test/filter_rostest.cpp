// The safety filter in the whole simulated system (filter.test, command_mode filter): this node is a
// scripted user publishing cmd_vel_in at 20 Hz, and the gate between the decoder and the obstacle
// node (it relays points and ray_ends to points_gated and ray_ends_gated while open). Ground truth
// comes from the simulators (true_pose, contact) and the scene file.
// A wall at ~wall_x: turning in place passes; full speed toward the wall never brings the disc nearer
// than ~clearance - ~tolerance; with the cloud gated off, forward motion is refused (STALE_DATA);
// when the user stops publishing, the robot stops within input_timeout. No contact, no bumper.
#include <atomic>
#include <cmath>
#include <string>
#include <thread>

#include <geometry_msgs/Twist.h>
#include <sensor_msgs/PointCloud2.h>

#include "sim_watch.h"

namespace
{

using sl_bringup_test::privateParam;
using sl_bringup_test::yawOf;
using S = sl_obstacle::ObstacleStatus;

class Filter : public sl_bringup_test::SimWatch
{
protected:
  void SetUp() override
  {
    SimWatch::SetUp();
    cmd_pub_ = nh_.advertise<geometry_msgs::Twist>("cmd_vel_in", 1);
    points_pub_ = nh_.advertise<sensor_msgs::PointCloud2>("points_gated", 2);
    rays_pub_ = nh_.advertise<sensor_msgs::PointCloud2>("ray_ends_gated", 2);
    points_sub_ = nh_.subscribe("points", 2, &Filter::relayPoints, this);
    rays_sub_ = nh_.subscribe("ray_ends", 2, &Filter::relayRays, this);
  }

  void TearDown() override
  {
    points_sub_.shutdown();
    rays_sub_.shutdown();
    SimWatch::TearDown();
  }

  void relayPoints(const sensor_msgs::PointCloud2::ConstPtr& msg)
  {
    if (gate_open_)
      points_pub_.publish(msg);
  }
  void relayRays(const sensor_msgs::PointCloud2::ConstPtr& msg)
  {
    if (gate_open_)
      rays_pub_.publish(msg);
  }

  void onPose(const geometry_msgs::Pose* previous, const geometry_msgs::Pose& now) override
  {
    const ros::Time t = ros::Time::now();
    if (previous)
    {
      const double step = std::hypot(now.position.x - previous->position.x, now.position.y - previous->position.y);
      const double turn = std::abs(std::remainder(yawOf(now) - yawOf(*previous), 2.0 * M_PI));
      path_ += step;
      if (step > 2e-4)
        last_move_ = t;
      if (turn > 1e-3)
        last_turn_ = t;
      const double dt = (t - pose_time_).toSec();
      if (dt > 0.02)
      {
        speed_ = step / dt;
        max_speed_ = std::max(max_speed_, speed_);
      }
    }
    pose_time_ = t;
  }

  void onStatus(const S& msg) override
  {
    reasons_seen_ |= 1ULL << msg.reason_code;
    last_status_ = msg;
  }

  /// Publishes (v, w) at 20 Hz for @p seconds, or until @p done (called with mutex_ held) is true.
  template <typename Done>
  void command(double v, double w, double seconds, Done done)
  {
    geometry_msgs::Twist twist;
    twist.linear.x = v;
    twist.angular.z = w;
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
    while (ros::ok() && ros::WallTime::now() < end)
    {
      cmd_pub_.publish(twist);
      last_command_ = ros::Time::now();
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (done() || contact_bits_ != 0 || bumped_)
          return;
      }
      ros::WallDuration(0.05).sleep();
    }
  }
  void command(double v, double w, double seconds)
  {
    command(v, w, seconds, [] { return false; });
  }

  /// Gap between the robot's disc and the wall x = wall_x_.
  double gap() const
  {
    return wall_x_ - (pose_.position.x + radius_);
  }

  void expectNoContact()
  {
    std::lock_guard<std::mutex> lock(mutex_);
    EXPECT_EQ(contact_bits_, 0) << "the robot touched something";
    EXPECT_FALSE(bumped_) << "a bumper fired";
    EXPECT_GT(contact_messages_, 0) << "no contact messages: the check saw nothing";
  }

  void runWall();

  ros::NodeHandle nh_;
  ros::Publisher cmd_pub_, points_pub_, rays_pub_;
  ros::Subscriber points_sub_, rays_sub_;
  std::atomic<bool> gate_open_{ true };
  ros::Time pose_time_, last_move_, last_turn_, last_command_;
  double path_ = 0.0, speed_ = 0.0, max_speed_ = 0.0;
  unsigned long long reasons_seen_ = 0;
  S last_status_;
  double wall_x_ = 1.0, radius_ = 0.1675;
};

void Filter::runWall()
{
  const double clearance = privateParam("clearance", 0.40);
  const double tolerance = privateParam("tolerance", 0.010);
  const double input_timeout = privateParam("input_timeout", 0.5);
  double yaw0 = 0.0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    yaw0 = yawOf(pose_);
  }
  // Turning in place always passes.
  command(0.0, 0.8, 1.0);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    EXPECT_GT(std::abs(std::remainder(yawOf(pose_) - yaw0, 2.0 * M_PI)), 0.3) << "a turn in place was held back";
    EXPECT_TRUE(reasons_seen_ & (1ULL << S::REASON_PASSED));
  }
  command(0.0, -0.8, 2.0);
  command(0.0, 0.8, 1.0);
  command(0.0, 0.0, 0.5);
  // Full speed toward the wall: never nearer than the clearance, never touching.
  command(0.5, 0.0, 6.0);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ROS_INFO("filter wall: %.4f m before the wall (clearance %.3f), path %.3f m, top speed %.3f m/s: %s", gap(),
             clearance, path_, max_speed_, last_status_.reason.c_str());
    EXPECT_GE(gap(), clearance - tolerance) << "the filter let the robot nearer than the clearance";
    EXPECT_TRUE(last_status_.teleop);
    EXPECT_TRUE(last_status_.reason_code == S::REASON_STOPPED_OBSTACLE || last_status_.reason_code == S::REASON_LIMITED)
        << last_status_.reason;
  }
  // The cloud stops: forward motion is refused (STALE_DATA).
  gate_open_ = false;
  double x0 = 0.0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    x0 = pose_.position.x;
  }
  command(0.3, 0.0, 1.5);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    EXPECT_EQ(last_status_.reason_code, S::REASON_STALE_DATA) << last_status_.reason;
    EXPECT_LT(pose_.position.x - x0, 0.01) << "drove forward on a stale cloud";
  }
  gate_open_ = true;
  // The user stops publishing while the robot turns: it stops within input_timeout.
  command(0.0, 0.6, 2.0);
  const ros::Time quiet = last_command_;
  ros::WallDuration(input_timeout + 1.5).sleep();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const double stopped_after = (last_turn_ - quiet).toSec();
    ROS_INFO("filter wall: turning ended %.3f s after the last command (input_timeout %.2f)", stopped_after,
             input_timeout);
    EXPECT_LE(stopped_after, input_timeout + 0.35) << "kept turning without commands";
    EXPECT_GT(stopped_after, 0.0) << "the turn never ran";
    EXPECT_EQ(last_status_.reason_code, S::REASON_INPUT_TIMEOUT) << last_status_.reason;
  }
}

TEST_F(Filter, NeverNearerThanTheClearanceAndStopsOnTimeouts)
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    wall_x_ = privateParam("wall_x", wall_x_);
    radius_ = privateParam("robot_radius", radius_);
  }
  ASSERT_TRUE(waitForSystem(60.0)) << "no true_pose from create_sim or no obstacle_status";
  // Wait for the first clouds.
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(30.0);
  while (ros::ok() && ros::WallTime::now() < deadline)
  {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!last_status_.cloud_stamp.isZero() && last_status_.data_age < 0.5)
        break;
    }
    ros::WallDuration(0.1).sleep();
  }
  ros::WallDuration(1.0).sleep();
  runWall();
  expectNoContact();
}

}  // namespace

int main(int argc, char** argv)
{
  return sl_bringup_test::runSystemTests(argc, argv, "filter_rostest");
}
