// The room scene for a minute (room.test): the whole system runs the simulated Create in
// sl_camera/scenes/room.yaml. It must never touch anything (camera simulator's contact signal,
// the Create's bumpers), and it must really do its job meanwhile: drive, stop before an
// obstacle (BLOCKED), turn away and drive on (a goal of at least 0.1 m after a turn), or say that
// no direction is free (NO_FREE_DIRECTION).
//
// Private parameters: ~duration (s of simulated running, 60), ~min_travel (m of path, 0.3),
// ~min_turn (rad turned in total, 0.5).
#include <cmath>

#include "sim_watch.h"

namespace
{

using sl_bringup_test::yawOf;

class Room : public sl_bringup_test::SimWatch
{
protected:
  void onPose(const geometry_msgs::Pose* previous, const geometry_msgs::Pose& now) override
  {
    if (!previous)
      return;
    path_ += std::hypot(now.position.x - previous->position.x, now.position.y - previous->position.y);
    turned_ += std::abs(std::remainder(yawOf(now) - yawOf(*previous), 2.0 * M_PI));
  }

  void onStatus(const sl_obstacle::ObstacleStatus& msg) override
  {
    using S = sl_obstacle::ObstacleStatus;
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

  double path_ = 0.0, turned_ = 0.0;
  int drive_commands_ = 0;
  bool blocked_ = false, turned_after_block_ = false, drove_after_turn_ = false;
  bool gave_up_after_turn_ = false;
};

TEST_F(Room, RunsAMinuteWithoutContact)
{
  const double duration = sl_bringup_test::privateParam("duration", 60.0);
  const double min_travel = sl_bringup_test::privateParam("min_travel", 0.3);
  const double min_turn = sl_bringup_test::privateParam("min_turn", 0.5);

  // The minute starts when the system has made its first decision on a cloud.
  ASSERT_TRUE(waitForSystem(60.0)) << "no true_pose from create_sim or no obstacle_status";
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
  return sl_bringup_test::runSystemTests(argc, argv, "room_rostest");
}
