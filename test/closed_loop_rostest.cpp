// Closed loop in simulation (closed_loop_wall.test, closed_loop_leg.test): the whole system drives
// the simulated Create toward an obstacle; it must stop with its front edge at the configured
// clearance and never touch anything.
//
// Ground truth comes from the simulators, not from the system under test: create_sim's true pose
// (true_pose) and the camera simulator's bumper contact (contact), plus the driver's hazards.
//
// Private parameters of the test node:
//   ~obstacle_x     world x of the obstacle surface the robot faces (m)
//   ~obstacle_y     world y of the obstacle (m); the nearest obstacle point the system reports must
//                   lie within ~lateral_tolerance of it (checks that this obstacle stopped the robot)
//   ~clearance      expected distance front edge -> obstacle at the stop (obstacle's safety_margin)
//   ~tolerance      allowed |stop distance - clearance| (m)
//   ~edge_offset    base_link -> platform_edge along x (m)
//   ~start_x        world x of base_link at the start (sim.launch's x)
//   ~timeout        s to wait for the stop
#include <cmath>
#include <mutex>

#include <create_driver/Hazards.h>
#include <geometry_msgs/PoseStamped.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sl_obstacle/ObstacleStatus.h>
#include <std_msgs/UInt8.h>

namespace
{

double param(const std::string& name, double fallback)
{
  double v = fallback;
  ros::param::get("~" + name, v);
  return v;
}

/// Everything the test watches, filled by the callbacks.
struct Observed
{
  std::mutex mutex;
  bool have_pose = false;
  geometry_msgs::Pose pose;
  ros::Time last_motion;  // last time the true pose changed by more than 1 mm / 0.01 rad
  geometry_msgs::Pose motion_reference;
  int contact_messages = 0;
  int contact_bits = 0;  // OR of every contact message
  int hazard_messages = 0;
  bool bumped = false;
  bool have_status = false;
  sl_obstacle::ObstacleStatus status;
  bool ever_drove = false;
};

double yawOf(const geometry_msgs::Pose& p)
{
  return 2.0 * std::atan2(p.orientation.z, p.orientation.w);
}

class ClosedLoop : public ::testing::Test
{
protected:
  void SetUp() override
  {
    pose_sub_ = nh_.subscribe("true_pose", 50, &ClosedLoop::onPose, this);
    contact_sub_ = nh_.subscribe("contact", 50, &ClosedLoop::onContact, this);
    hazards_sub_ = nh_.subscribe("hazards", 50, &ClosedLoop::onHazards, this);
    status_sub_ = nh_.subscribe("obstacle_status", 50, &ClosedLoop::onStatus, this);
  }

  void TearDown() override
  {
    // No callback may run on the fixture once it is being destroyed.
    pose_sub_.shutdown();
    contact_sub_.shutdown();
    hazards_sub_.shutdown();
    status_sub_.shutdown();
  }

  void onPose(const geometry_msgs::PoseStamped& msg)
  {
    std::lock_guard<std::mutex> lock(o_.mutex);
    if (!o_.have_pose)
    {
      o_.motion_reference = msg.pose;
      o_.last_motion = ros::Time::now();
    }
    o_.have_pose = true;
    o_.pose = msg.pose;
    const double dx = msg.pose.position.x - o_.motion_reference.position.x;
    const double dy = msg.pose.position.y - o_.motion_reference.position.y;
    const double dyaw = std::remainder(yawOf(msg.pose) - yawOf(o_.motion_reference), 2.0 * M_PI);
    if (std::hypot(dx, dy) > 0.001 || std::abs(dyaw) > 0.01)
    {
      o_.motion_reference = msg.pose;
      o_.last_motion = ros::Time::now();
    }
  }

  void onContact(const std_msgs::UInt8& msg)
  {
    std::lock_guard<std::mutex> lock(o_.mutex);
    ++o_.contact_messages;
    o_.contact_bits |= msg.data;
  }

  void onHazards(const create_driver::Hazards& msg)
  {
    std::lock_guard<std::mutex> lock(o_.mutex);
    ++o_.hazard_messages;
    o_.bumped = o_.bumped || msg.bump_left || msg.bump_right;
  }

  void onStatus(const sl_obstacle::ObstacleStatus& msg)
  {
    std::lock_guard<std::mutex> lock(o_.mutex);
    o_.have_status = true;
    o_.status = msg;
    if (msg.state == sl_obstacle::ObstacleStatus::DRIVING || msg.state == sl_obstacle::ObstacleStatus::SLOWING)
      o_.ever_drove = true;
  }

  ros::NodeHandle nh_;
  ros::Subscriber pose_sub_, contact_sub_, hazards_sub_, status_sub_;
  Observed o_;
};

TEST_F(ClosedLoop, StopsAtClearanceWithoutContact)
{
  const double obstacle_x = param("obstacle_x", 1.0);
  const double obstacle_y = param("obstacle_y", 0.0);
  const double clearance = param("clearance", 0.40);
  const double tolerance = param("tolerance", 0.010);
  const double lateral_tolerance = param("lateral_tolerance", 0.05);
  const double edge_offset = param("edge_offset", 0.1675);
  const double timeout = param("timeout", 150.0);
  const double start_x = param("start_x", -0.1675);
  const double settle = 3.0;  // s without motion while BLOCKED: stopped for good

  // Wait for a stop: BLOCKED by an obstacle, after having driven, and no motion for `settle` s.
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout);
  bool stopped = false;
  while (ros::ok() && ros::WallTime::now() < deadline && !stopped)
  {
    ros::WallDuration(0.1).sleep();
    std::lock_guard<std::mutex> lock(o_.mutex);
    stopped = o_.have_pose && o_.have_status && o_.ever_drove &&
              o_.status.state == sl_obstacle::ObstacleStatus::BLOCKED &&
              o_.status.reason_code == sl_obstacle::ObstacleStatus::REASON_OBSTACLE &&
              (ros::Time::now() - o_.last_motion).toSec() > settle;
  }
  std::lock_guard<std::mutex> lock(o_.mutex);
  ASSERT_TRUE(o_.have_pose) << "no true_pose from create_sim";
  ASSERT_TRUE(o_.have_status) << "no obstacle_status from the obstacle node";
  ASSERT_TRUE(o_.ever_drove) << "the robot never drove (last decision: " << o_.status.reason << ")";
  ASSERT_TRUE(stopped) << "no stop BLOCKED / OBSTACLE within " << timeout << " s; last decision: " << o_.status.reason
                       << "; front edge at x = " << o_.pose.position.x + edge_offset;

  const double edge_x = o_.pose.position.x + edge_offset * std::cos(yawOf(o_.pose));
  const double stop_distance = obstacle_x - edge_x;
  const double travelled = o_.pose.position.x - start_x;
  ROS_INFO("closed loop: stopped with the front edge %.4f m from the obstacle (clearance %.3f m, error %+.1f mm) "
           "after %.3f m; the system measured %.4f m; heading %.4f rad",
           stop_distance, clearance, 1000.0 * (stop_distance - clearance), travelled, o_.status.nearest_distance,
           yawOf(o_.pose));
  EXPECT_NEAR(stop_distance, clearance, tolerance) << "front edge not at the configured clearance";
  EXPECT_GT(travelled, 0.1) << "the robot hardly moved";
  EXPECT_NEAR(yawOf(o_.pose), 0.0, 0.05) << "the robot did not drive straight";
  // The stop was for this obstacle: the nearest obstacle point reported lies on it.
  EXPECT_NEAR(o_.status.nearest_distance, stop_distance, 0.03) << "the system's distance differs from the truth";
  const double nearest_y_world = o_.pose.position.y + o_.status.nearest_point.y;
  EXPECT_NEAR(nearest_y_world, obstacle_y, lateral_tolerance) << "the nearest obstacle point is not on the obstacle";

  // Never touched: the camera simulator's contact signal was always 0, the bumpers never fired.
  EXPECT_GT(o_.contact_messages, 10) << "no contact signal from the camera simulator: cannot tell";
  EXPECT_EQ(o_.contact_bits, 0) << "the robot touched the obstacle";
  EXPECT_GT(o_.hazard_messages, 0) << "no hazards from the driver";
  EXPECT_FALSE(o_.bumped) << "the Create's bumper fired";
}

}  // namespace

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "closed_loop_rostest");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const int result = RUN_ALL_TESTS();
  spinner.stop();
  ros::shutdown();
  return result;
}
