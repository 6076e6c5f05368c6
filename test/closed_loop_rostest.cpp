// Closed loop in simulation (closed_loop_wall.test, closed_loop_leg.test): the whole system drives
// the simulated Create toward an obstacle; it must stop with its front edge at the configured
// clearance and never touch anything.
//
// Ground truth comes from the simulators, not from the system under test: create_sim's true pose
// (true_pose), the camera simulator's bumper contact (contact) and its collision of the robot's disc
// with the scene in any direction (collision), plus the driver's hazards.
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
#include <string>

#include "sim_watch.h"

namespace
{

using namespace sl_bringup_test;  // SimWatch and the pose helpers of sim_watch.h

class ClosedLoop : public SimWatch
{
protected:
  void onPose(const geometry_msgs::Pose* previous, const geometry_msgs::Pose& now) override
  {
    if (!previous)
    {
      motion_reference_ = now;
      last_motion_ = ros::Time::now();
    }
    if (stepBetween(now, motion_reference_) > 0.001 || turnBetween(now, motion_reference_) > 0.01)
    {
      motion_reference_ = now;
      last_motion_ = ros::Time::now();
    }
  }

  void onStatus(const sl_msgs::ObstacleStatus& msg) override
  {
    have_status_ = true;
    status_ = msg;
    if (msg.state == sl_msgs::ObstacleStatus::DRIVING || msg.state == sl_msgs::ObstacleStatus::SLOWING)
      ever_drove_ = true;
  }

  ros::Time last_motion_;  // last time the true pose changed by more than 1 mm / 0.01 rad
  geometry_msgs::Pose motion_reference_;
  bool have_status_ = false;
  sl_msgs::ObstacleStatus status_;
  bool ever_drove_ = false;
};

TEST_F(ClosedLoop, StopsAtClearanceWithoutContact)
{
  const double obstacle_x = privateParam("obstacle_x", 1.0);
  const double obstacle_y = privateParam("obstacle_y", 0.0);
  const double clearance = privateParam("clearance", 0.40);
  const double tolerance = privateParam("tolerance", 0.010);
  const double lateral_tolerance = privateParam("lateral_tolerance", 0.05);
  const double edge_offset = privateParam("edge_offset", 0.1675);
  const double timeout = privateParam("timeout", 150.0);
  const double start_x = privateParam("start_x", -0.1675);
  const double settle = 3.0;  // s without motion while BLOCKED: stopped for good

  // Wait for a stop: BLOCKED by an obstacle, after having driven, and no motion for `settle` s.
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout);
  bool stopped = false;
  while (ros::ok() && ros::WallTime::now() < deadline && !stopped)
  {
    ros::WallDuration(0.1).sleep();
    std::lock_guard<std::mutex> lock(mutex_);
    stopped = have_pose_ && have_status_ && ever_drove_ && status_.state == sl_msgs::ObstacleStatus::BLOCKED &&
              status_.reason_code == sl_msgs::ObstacleStatus::REASON_OBSTACLE &&
              (ros::Time::now() - last_motion_).toSec() > settle;
  }
  expectNoCollision();
  std::lock_guard<std::mutex> lock(mutex_);
  ASSERT_TRUE(have_pose_) << "no true_pose from create_sim";
  ASSERT_TRUE(have_status_) << "no obstacle_status from the obstacle node";
  ASSERT_TRUE(ever_drove_) << "the robot never drove (last decision: " << status_.reason << ")";
  ASSERT_TRUE(stopped) << "no stop BLOCKED / OBSTACLE within " << timeout << " s; last decision: " << status_.reason
                       << "; front edge at x = " << pose_.position.x + edge_offset;

  const double edge_x = pose_.position.x + edge_offset * std::cos(yawOf(pose_));
  const double stop_distance = obstacle_x - edge_x;
  const double travelled = pose_.position.x - start_x;
  const double nearest_y_world = pose_.position.y + status_.nearest_point.y;
  ROS_INFO(
      "closed loop: stopped with the front edge %.4f m from the obstacle (clearance %.3f m, error %+.1f mm) "
      "after %.3f m; the system measured %.4f m, nearest point at y = %+.4f m (world); heading %.4f rad",
      stop_distance, clearance, 1000.0 * (stop_distance - clearance), travelled, status_.nearest_distance,
      nearest_y_world, yawOf(pose_));
  EXPECT_NEAR(stop_distance, clearance, tolerance) << "front edge not at the configured clearance";
  EXPECT_GT(travelled, 0.1) << "the robot hardly moved";
  EXPECT_NEAR(yawOf(pose_), 0.0, 0.05) << "the robot did not drive straight";
  // The stop was for this obstacle: the nearest obstacle point reported lies on it.
  EXPECT_NEAR(status_.nearest_distance, stop_distance, 0.03) << "the system's distance differs from the truth";
  EXPECT_NEAR(nearest_y_world, obstacle_y, lateral_tolerance) << "the nearest obstacle point is not on the obstacle";

  // Never touched: the camera simulator's contact signal was always 0, the bumpers never fired.
  EXPECT_GT(contact_messages_, 10) << "no contact signal from the camera simulator: cannot tell";
  EXPECT_EQ(contact_bits_, 0) << "the robot touched the obstacle";
  EXPECT_GT(hazard_messages_, 0) << "no hazards from the driver";
  EXPECT_FALSE(bumped_) << "the Create's bumper fired";
}

}  // namespace

int main(int argc, char** argv)
{
  return sl_testing::runRostests(argc, argv, "closed_loop_rostest");
}
