// The safety filter in the whole simulated system (filter.test, command_mode filter): this node is a
// scripted user publishing cmd_vel_in at 20 Hz, and the gate between the decoder and the obstacle
// node (it relays points and ray_ends to points_gated and ray_ends_gated while open). Ground truth
// comes from the simulators (true_pose, contact, collision) and the scene file.
//   ~scenario "wall" (a wall at ~wall_x): turning in place passes; full speed at the wall stops within
//     ~clearance +- ~tolerance and pushing on does not move it; reverse moves; with the cloud gated
//     off, forward motion stops within stale_timeout; when the user stops publishing, the robot
//     stops within input_timeout.
//   ~scenario "arcs": arcs to both sides past a thin dark leg; the robot moves and never touches.
//   ~scenario "takeover" (command_mode action): a command on cmd_vel_in takes over from autonomy
//     while the user publishes and ~teleop_hold seconds after, then autonomy drives again.
//   ~scenario "start" (a wall at ~wall_x): from a standstill, without looking around, the first
//     forward command moves the robot within 1 s (it creeps through the ring around its body that the
//     camera cannot see), then it drives on and stops at the wall at ~clearance +- ~tolerance.
//   ~scenario "dock" (corridor_closed_behind.yaml, the end wall 0.17 m behind the robot): reverse at
//     the start does not move it (nothing behind is its trail); forward moves within 1 s and drives
//     down the corridor; reverse then brings it back along its trail, never beyond the start.
// Every run: no contact, no bumper, no collision of the robot's disc in any direction.
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <thread>

#include <geometry_msgs/Twist.h>
#include <sensor_msgs/PointCloud2.h>

#include "sim_watch.h"

namespace
{

using namespace sl_bringup_test;  // SimWatch and the pose helpers of sim_watch.h
using S = sl_msgs::ObstacleStatus;

class Filter : public SimWatch
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
      const double step = stepBetween(now, *previous);
      const double turn = turnBetween(now, *previous);
      path_ += step;
      if (step > 2e-4)
        last_move_ = t;
      if (moved_at_.isZero() && stepBetween(now, move_from_) > kMoved)
        moved_at_ = t;
      min_x_ = std::min(min_x_, now.position.x);
      if (turn > 1e-3)
        last_turn_ = t;
      const double dt = (t - pose_time_).toSec();
      if (dt > 0.02)
      {
        speed_ = step / dt;
        max_speed_ = std::max(max_speed_, speed_);
        if (last_status_.reason_code == S::REASON_CREEPING)
          creep_max_ = std::max(creep_max_, speed_);
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
  double gap() const { return wall_x_ - (pose_.position.x + radius_); }

  void expectNoContact()
  {
    std::lock_guard<std::mutex> lock(mutex_);
    EXPECT_EQ(contact_bits_, 0) << "the robot touched something";
    EXPECT_FALSE(bumped_) << "a bumper fired";
    EXPECT_GT(contact_messages_, 0) << "no contact messages: the check saw nothing";
  }

  /// What a user does first: turn in place to both sides and back. The camera sees +-14 degrees
  /// and never the ring around the robot, so the sides of the path just ahead are unknown (not
  /// free) until the robot has looked at them.
  void lookAround()
  {
    command(0.0, 0.8, 1.0);
    command(0.0, -0.8, 2.0);
    command(0.0, 0.8, 1.0);
    command(0.0, 0.0, 0.5);
  }

  /// The @p motion last seen at @p last (last_move_ or last_turn_, read under the lock) ended after
  /// @p since (when @p cause happened), and the filter's status gives @p reason_code. The time it
  /// took is printed next to @p timeout (the parameter @p param); the bound asserted, timeout + 1 s (the waits after
  /// the cause are longer), only tells a stop from none: on a shared machine the messages' latency is not the filter's.
  void expectEndedWithin(const ros::Time& last, const ros::Time& since, const char* motion, const char* cause,
                         const char* param, double timeout, std::uint8_t reason_code)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const double stopped_after = (last - since).toSec();
    ROS_INFO("filter wall: %s ended %.3f s after %s (%s %.2f)", motion, stopped_after, cause, param, timeout);
    EXPECT_LE(stopped_after, timeout + 1.0) << motion << " went on after " << cause;
    EXPECT_GT(stopped_after, 0.0) << motion << " had ended before " << cause;
    EXPECT_EQ(last_status_.reason_code, reason_code) << last_status_.reason;
  }

  void runWall();
  void runArcs();
  void runTakeover();
  void runStart();
  void runDock();

  /// Publishes (v, 0) from a standstill until the robot has moved kMoved from where it stood (at most
  /// 5 s); @return the time from the first command to that motion (s; inf if it never moved).
  double timeToMove(double v)
  {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      move_from_ = pose_;
      moved_at_ = ros::Time();
    }
    const ros::Time first = ros::Time::now();
    command(v, 0.0, 5.0, [&] { return !moved_at_.isZero(); });
    std::lock_guard<std::mutex> lock(mutex_);
    return moved_at_.isZero() ? std::numeric_limits<double>::infinity() : (moved_at_ - first).toSec();
  }

  /// Waits up to @p seconds until @p done (called with mutex_ held) is true; @return done().
  template <typename Done>
  bool waitFor(double seconds, Done done)
  {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
    while (ros::ok() && ros::WallTime::now() < end)
    {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (done())
          return true;
      }
      ros::WallDuration(0.05).sleep();
    }
    std::lock_guard<std::mutex> lock(mutex_);
    return done();
  }

  ros::NodeHandle nh_;
  ros::Publisher cmd_pub_, points_pub_, rays_pub_;
  ros::Subscriber points_sub_, rays_sub_;
  std::atomic<bool> gate_open_{ true };
  ros::Time pose_time_, last_move_, last_turn_, last_command_;
  double path_ = 0.0, speed_ = 0.0, max_speed_ = 0.0;
  unsigned long long reasons_seen_ = 0;
  S last_status_;
  double wall_x_ = 1.0, radius_ = 0.1675;
  static constexpr double kMoved = 0.002;  // m from where it stood: the robot moved
  geometry_msgs::Pose move_from_;
  ros::Time moved_at_{ 1, 0 };  // not zero: nobody waits for a motion
  double min_x_ = std::numeric_limits<double>::infinity();
  double creep_max_ = 0.0;  // m/s, the highest speed while the filter said CREEPING
};

void Filter::runWall()
{
  const double clearance = privateParam("clearance", 0.40);
  const double tolerance = privateParam("tolerance", 0.010);
  const double stale_timeout = privateParam("stale_timeout", 0.5);
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
    EXPECT_GT(yawDifference(yawOf(pose_), yaw0), 0.3) << "a turn in place was held back";
  }
  command(0.0, -0.8, 2.0);
  command(0.0, 0.8, 1.0);
  command(0.0, 0.0, 0.5);
  // Full speed at the wall: the filter slows the robot (sqrt(2 a d)) and stops it at the clearance.
  const ros::Time start = ros::Time::now();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    path_ = max_speed_ = 0.0;
    reasons_seen_ = 0;
  }
  command(0.5, 0.0, 30.0,
          [&] {
            return path_ > 0.2 && (ros::Time::now() - last_move_).toSec() > 1.0 &&
                   (ros::Time::now() - start).toSec() > 3.0;
          });
  double x0 = 0.0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ROS_INFO("filter wall: stopped %.4f m before the wall (clearance %.3f), top speed %.3f m/s, path %.3f m: %s", gap(),
             clearance, max_speed_, path_, last_status_.reason.c_str());
    EXPECT_GT(path_, 0.2) << "the robot did not drive toward the wall";
    EXPECT_NEAR(gap(), clearance, tolerance) << "stop off the clearance";
    EXPECT_GT(max_speed_, 0.25) << "the filter never let the robot go fast";
    EXPECT_TRUE(reasons_seen_ & (1ULL << S::REASON_LIMITED)) << "never LIMITED on the way";
    EXPECT_EQ(last_status_.reason_code, S::REASON_STOPPED_OBSTACLE) << last_status_.reason;
    EXPECT_TRUE(last_status_.teleop);
    EXPECT_DOUBLE_EQ(last_status_.command_scale, 0.0);
    x0 = pose_.position.x;
  }
  // Pushing on does not move it.
  command(0.5, 0.0, 1.5);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    EXPECT_LT(std::abs(pose_.position.x - x0), 0.003) << "moved while stopped at the wall";
  }
  // Reverse along the trail moves.
  command(-0.15, 0.0, 2.5);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ROS_INFO("filter wall: reversed %.3f m", x0 - pose_.position.x);
    EXPECT_GT(x0 - pose_.position.x, 0.2) << "reverse along the trail did not move";
  }
  // The cloud stops while the robot drives forward: forward motion stops within stale_timeout.
  command(0.2, 0.0, 5.0, [&] { return speed_ > 0.1; });
  gate_open_ = false;
  const ros::Time gated = ros::Time::now();
  command(0.2, 0.0, 2.5);
  expectEndedWithin(last_move_, gated, "forward motion", "the cloud stopped", "stale_timeout", stale_timeout,
                    S::REASON_STALE_DATA);
  gate_open_ = true;
  // The user stops publishing while the robot turns: it stops within input_timeout.
  command(0.0, 0.6, 2.0);
  const ros::Time quiet = last_command_;
  ros::WallDuration(input_timeout + 1.5).sleep();
  expectEndedWithin(last_turn_, quiet, "turning", "the last command", "input_timeout", input_timeout,
                    S::REASON_INPUT_TIMEOUT);
}

void Filter::runArcs()
{
  // Arcs to both sides past the leg, then on toward the wall: the filter slows and stops each one
  // before the leg or the wall; turning in place always passes.
  const double legs[][3] = { { 0.3, 0.0, 3.0 }, { 0.3, 0.5, 4.0 }, { 0.0, -1.0, 1.5 },  { 0.3, -0.4, 4.0 },
                             { 0.0, 1.0, 2.0 }, { 0.3, 0.8, 4.0 }, { -0.15, 0.0, 2.0 }, { 0.3, 0.3, 4.0 } };
  lookAround();
  for (const auto& leg : legs)
    command(leg[0], leg[1], leg[2]);
  std::lock_guard<std::mutex> lock(mutex_);
  ROS_INFO("filter arcs: path %.3f m, reasons seen 0x%llx", path_, reasons_seen_);
  EXPECT_GT(path_, 0.4) << "the robot hardly moved";
  EXPECT_TRUE(reasons_seen_ & (1ULL << S::REASON_LIMITED)) << "no arc was ever limited";
}

void Filter::runTakeover()
{
  const double hold = privateParam("teleop_hold", 2.0);
  const auto autonomy_drives = [&]
  { return !last_status_.teleop && (last_status_.state == S::DRIVING || last_status_.state == S::SLOWING); };
  ASSERT_TRUE(waitFor(40.0, autonomy_drives)) << "autonomy never drove: " << last_status_.reason;
  double yaw0 = 0.0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    yaw0 = yawOf(pose_);
  }
  // The user turns the robot: the command takes over at once.
  command(0.0, 0.6, 1.5);
  const ros::Time quiet = ros::Time::now();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    EXPECT_TRUE(last_status_.teleop) << "cmd_vel_in did not take over: " << last_status_.reason;
    EXPECT_EQ(last_status_.reason_code, S::REASON_PASSED) << last_status_.reason;
    EXPECT_GT(yawDifference(yawOf(pose_), yaw0), 0.3) << "the user's turn did not happen";
  }
  // Autonomy waits teleop_hold after the last command, then decides again.
  ASSERT_TRUE(waitFor(hold + 5.0, [&] { return !last_status_.teleop; })) << "autonomy never resumed";
  const double resumed_after = (ros::Time::now() - quiet).toSec();
  ROS_INFO("filter takeover: autonomy resumed %.2f s after the last command (teleop_hold %.1f s)", resumed_after, hold);
  EXPECT_GE(resumed_after, hold - 0.2) << "autonomy took back control before teleop_hold";
  EXPECT_TRUE(waitFor(
      30.0, [&] { return last_status_.command == S::COMMAND_DRIVE || last_status_.command == S::COMMAND_TURN; }))
      << "autonomy gave no command after resuming: " << last_status_.reason;
}

void Filter::runStart()
{
  const double clearance = privateParam("clearance", 0.40);
  const double tolerance = privateParam("tolerance", 0.010);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    path_ = max_speed_ = 0.0;
    reasons_seen_ = 0;
  }
  // The first forward command, no look around: the robot moves at once, creeping.
  const double moved_after = timeToMove(0.3);
  double crept = 0.0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ROS_INFO("filter start: moved %.1f mm after %.3f s of the first forward command: %s", kMoved * 1e3, moved_after,
             last_status_.reason.c_str());
    EXPECT_TRUE(std::isfinite(moved_after)) << "the first forward command did not move the robot (5 s)";
    EXPECT_TRUE(reasons_seen_ & (1ULL << S::REASON_CREEPING)) << "never CREEPING: " << last_status_.reason;
  }
  // On toward the wall: creeping while the path crosses cells never seen (here all the way: the
  // sides of the path nearer than about 0.75 m to the camera were never in view), stopped at the
  // clearance.
  const ros::Time start = ros::Time::now();
  command(0.3, 0.0, 40.0,
          [&]
          {
            if (crept == 0.0 && last_status_.reason_code != S::REASON_CREEPING)
              crept = path_;
            return path_ > 0.2 && (ros::Time::now() - last_move_).toSec() > 1.0 &&
                   (ros::Time::now() - start).toSec() > 3.0;
          });
  std::lock_guard<std::mutex> lock(mutex_);
  ROS_INFO(
      "filter start: crept %.3f m at up to %.3f m/s, top speed %.3f m/s; stopped %.4f m before the wall "
      "(clearance %.3f) after %.1f s, path %.3f m: %s",
      crept > 0.0 ? crept : path_, creep_max_, max_speed_, gap(), clearance, (last_move_ - start).toSec(), path_,
      last_status_.reason.c_str());
  EXPECT_NEAR(gap(), clearance, tolerance) << "stop off the clearance";
  EXPECT_LE(creep_max_, 0.05 + 0.01) << "faster than creep_speed over cells never seen";
  EXPECT_EQ(last_status_.reason_code, S::REASON_STOPPED_OBSTACLE) << last_status_.reason;
}

void Filter::runDock()
{
  geometry_msgs::Pose start;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    start = pose_;
  }
  // Reverse at the start: the end wall is 0.17 m behind, and nothing behind is the robot's trail.
  command(-0.15, 0.0, 2.0);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ROS_INFO("filter dock: reverse at the start moved %.4f m: %s", stepBetween(pose_, start),
             last_status_.reason.c_str());
    EXPECT_LT(stepBetween(pose_, start), 0.003) << "reversed where the robot never was";
    EXPECT_EQ(last_status_.reason_code, S::REASON_STOPPED_OBSTACLE) << last_status_.reason;
  }
  // Forward down the corridor: moves at once.
  const double moved_after = timeToMove(0.3);
  command(0.3, 0.0, 10.0);
  double forward = 0.0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    forward = pose_.position.x - start.position.x;
    ROS_INFO("filter dock: moved after %.3f s, %.3f m down the corridor in 10 s: %s", moved_after, forward,
             last_status_.reason.c_str());
    EXPECT_TRUE(std::isfinite(moved_after)) << "the first forward command did not move the robot (5 s)";
    EXPECT_GT(forward, 0.3) << "the robot did not drive down the corridor";
    min_x_ = pose_.position.x;
  }
  // Reverse all the way: back along the trail, stopped before its end (the start).
  command(-0.15, 0.0, forward / 0.15 + 8.0);
  std::lock_guard<std::mutex> lock(mutex_);
  ROS_INFO("filter dock: reversed to %.4f m before the start (trail end 0.01 m behind it, less 0.02 m): %s",
           min_x_ - start.position.x, last_status_.reason.c_str());
  EXPECT_GE(min_x_, start.position.x - 0.01) << "reversed beyond the trail's end";
  EXPECT_LT(pose_.position.x - start.position.x, 0.05) << "did not come back along the trail";
}

TEST_F(Filter, DrivesWhereTheUserSaysExceptIntoThings)
{
  std::string scenario = "wall";
  ros::param::get("~scenario", scenario);
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
  if (scenario == "wall")
    runWall();
  else if (scenario == "arcs")
    runArcs();
  else if (scenario == "start")
    runStart();
  else if (scenario == "dock")
    runDock();
  else
    runTakeover();
  expectNoContact();
  expectNoCollision();
}

}  // namespace

int main(int argc, char** argv)
{
  return sl_testing::runRostests(argc, argv, "filter_rostest");
}
