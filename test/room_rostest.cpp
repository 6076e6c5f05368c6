// The room scene for a minute (room.test): the whole system runs the simulated Create in
// sl_camera/scenes/room.yaml. It must never touch anything (camera simulator's contact signal,
// the Create's bumpers), and it must really do its job meanwhile: drive, stop before an
// obstacle (BLOCKED), turn away and drive on (a goal of at least 0.1 m after a turn).
//
// Private parameters: ~duration (s of simulated running, 60), ~min_travel (m of path, 0.3),
// ~min_turn (rad turned in total, 0.5).
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

double yawOf(const geometry_msgs::Pose& p)
{
  return 2.0 * std::atan2(p.orientation.z, p.orientation.w);
}

class Room : public ::testing::Test
{
protected:
  void SetUp() override
  {
    pose_sub_ = nh_.subscribe("true_pose", 100, &Room::onPose, this);
    contact_sub_ = nh_.subscribe("contact", 50, &Room::onContact, this);
    hazards_sub_ = nh_.subscribe("hazards", 50, &Room::onHazards, this);
    status_sub_ = nh_.subscribe("obstacle_status", 100, &Room::onStatus, this);
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
    std::lock_guard<std::mutex> lock(mutex_);
    if (have_pose_)
    {
      path_ += std::hypot(msg.pose.position.x - pose_.position.x, msg.pose.position.y - pose_.position.y);
      turned_ += std::abs(std::remainder(yawOf(msg.pose) - yawOf(pose_), 2.0 * M_PI));
    }
    have_pose_ = true;
    pose_ = msg.pose;
  }

  void onContact(const std_msgs::UInt8& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++contact_messages_;
    if (msg.data != 0 && contact_bits_ == 0)
      ROS_ERROR("contact %d at (%.3f, %.3f)", msg.data, pose_.position.x, pose_.position.y);
    contact_bits_ |= msg.data;
  }

  void onHazards(const create_driver::Hazards& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++hazard_messages_;
    bumped_ = bumped_ || msg.bump_left || msg.bump_right;
  }

  void onStatus(const sl_obstacle::ObstacleStatus& msg)
  {
    using S = sl_obstacle::ObstacleStatus;
    std::lock_guard<std::mutex> lock(mutex_);
    ++statuses_;
    if (msg.state == S::BLOCKED && msg.reason_code == S::REASON_OBSTACLE && !blocked_)
      ROS_INFO("room: stopped before an obstacle: %s", msg.reason.c_str());
    blocked_ = blocked_ || (msg.state == S::BLOCKED && msg.reason_code == S::REASON_OBSTACLE);
    if (msg.state == S::TURNING && blocked_)
      turned_after_block_ = true;
    if (msg.command == S::COMMAND_DRIVE && msg.command_distance >= 0.1 && turned_after_block_ && !drove_after_turn_)
    {
      drove_after_turn_ = true;
      ROS_INFO("room: driving again after turning away: %s", msg.reason.c_str());
    }
    // The other legitimate end of a turn cycle: every direction is blocked or unmeasured (the
    // sensor sees 0.35..1.2 m; in a corner facing far or dark walls nothing within reach is free).
    if (msg.reason_code == S::REASON_NO_FREE_DIRECTION && turned_after_block_ && !gave_up_after_turn_)
    {
      gave_up_after_turn_ = true;
      ROS_INFO("room: no free direction after turning away: %s", msg.reason.c_str());
    }
    if (msg.command == S::COMMAND_DRIVE)
      ++drive_commands_;
  }

  ros::NodeHandle nh_;
  ros::Subscriber pose_sub_, contact_sub_, hazards_sub_, status_sub_;
  std::mutex mutex_;
  bool have_pose_ = false;
  geometry_msgs::Pose pose_;
  double path_ = 0.0, turned_ = 0.0;
  int contact_messages_ = 0, contact_bits_ = 0, hazard_messages_ = 0, statuses_ = 0, drive_commands_ = 0;
  bool bumped_ = false, blocked_ = false, turned_after_block_ = false, drove_after_turn_ = false;
  bool gave_up_after_turn_ = false;
};

TEST_F(Room, RunsAMinuteWithoutContact)
{
  double duration = 60.0, min_travel = 0.3, min_turn = 0.5;
  ros::param::get("~duration", duration);
  ros::param::get("~min_travel", min_travel);
  ros::param::get("~min_turn", min_turn);

  // The minute starts when the system has made its first decision on a cloud.
  const ros::WallTime start_deadline = ros::WallTime::now() + ros::WallDuration(60.0);
  while (ros::ok() && ros::WallTime::now() < start_deadline)
  {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (have_pose_ && statuses_ > 0)
        break;
    }
    ros::WallDuration(0.1).sleep();
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ASSERT_TRUE(have_pose_) << "no true_pose from create_sim";
    ASSERT_GT(statuses_, 0) << "no obstacle_status";
  }
  // The minute; then, if the first turn cycle has not ended yet (drove on, or no free direction),
  // up to 40 s more for it, still without contact.
  const ros::Time start = ros::Time::now();
  while (ros::ok())
  {
    ros::WallDuration(0.2).sleep();
    std::lock_guard<std::mutex> lock(mutex_);
    if (contact_bits_ != 0 || bumped_)
      break;  // failed already
    const double elapsed = (ros::Time::now() - start).toSec();
    if (elapsed >= duration + 40.0 || (elapsed >= duration && (drove_after_turn_ || gave_up_after_turn_)))
      break;
  }

  std::lock_guard<std::mutex> lock(mutex_);
  ROS_INFO("room: %.1f s, path %.3f m, turned %.2f rad, %d drive commands, blocked %d, turned away %d, drove on %d, "
           "no free direction %d, contact %d, bumper %d; at (%.3f, %.3f, %.2f rad)",
           (ros::Time::now() - start).toSec(), path_, turned_, drive_commands_, blocked_, turned_after_block_,
           drove_after_turn_, gave_up_after_turn_, contact_bits_, bumped_, pose_.position.x, pose_.position.y, yawOf(pose_));
  EXPECT_GT(contact_messages_, 100) << "no contact signal from the camera simulator: cannot tell";
  EXPECT_EQ(contact_bits_, 0) << "the robot touched something";
  EXPECT_GT(hazard_messages_, 0) << "no hazards from the driver";
  EXPECT_FALSE(bumped_) << "the Create's bumper fired";
  EXPECT_GT(path_, min_travel) << "the robot hardly drove";
  EXPECT_GT(turned_, min_turn) << "the robot hardly turned";
  EXPECT_TRUE(blocked_) << "the robot never stopped before an obstacle";
  EXPECT_TRUE(turned_after_block_) << "the robot never turned away from an obstacle";
  EXPECT_TRUE(drove_after_turn_ || gave_up_after_turn_)
      << "after turning away the robot neither drove on nor reported that no direction is free";
}

}  // namespace

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "room_rostest");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const int result = RUN_ALL_TESTS();
  spinner.stop();
  ros::shutdown();
  return result;
}
