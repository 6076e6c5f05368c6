// What the closed-loop system tests (closed_loop, room, explore, filter, ...) and the bump-and-turn
// baseline watch while the simulation runs. Ground truth comes from the simulators, not from the
// system under test: create_sim's true pose (true_pose), the camera simulator's bumper contact
// (contact) and its ground-truth collision of the robot's disc with the scene in any direction
// (collision), plus the driver's hazards and the obstacle node's decisions (obstacle_status).
#pragma once

#include <cmath>
#include <cstdio>
#include <deque>
#include <limits>
#include <mutex>
#include <set>
#include <string>

#include <geometry_msgs/PoseStamped.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sl_msgs/Collision.h>
#include <sl_msgs/Hazards.h>
#include <sl_msgs/ObstacleStatus.h>
#include <std_msgs/UInt8.h>

#include <sl_testing/rostest_main.h>

namespace sl_bringup_test
{

/// A private parameter of the test node, or @p fallback.
inline double privateParam(const std::string& name, double fallback)
{
  double v = fallback;
  ros::param::get("~" + name, v);
  return v;
}

/// Yaw of a pose that only turns about z, rad.
inline double yawOf(const geometry_msgs::Pose& p)
{
  return 2.0 * std::atan2(p.orientation.z, p.orientation.w);
}

/// |@p a - @p b| of two yaws, wrapped to [0, pi], rad.
inline double yawDifference(double a, double b)
{
  return std::abs(std::remainder(a - b, 2.0 * M_PI));
}

/// How far the robot turned from pose @p b to pose @p a, in [0, pi], rad.
inline double turnBetween(const geometry_msgs::Pose& a, const geometry_msgs::Pose& b)
{
  return yawDifference(yawOf(a), yawOf(b));
}

/// Distance between the positions of two poses in the x-y plane, m.
inline double stepBetween(const geometry_msgs::Pose& a, const geometry_msgs::Pose& b)
{
  return std::hypot(a.position.x - b.position.x, a.position.y - b.position.y);
}

/**
 * The true path as scripts/cover_truth.py reads it: "t x y yaw" per line (t in s since the origin,
 * world frame), at most one line per 0.1 s. The origin is the first line's time unless set before.
 * Not thread-safe: call under the caller's lock.
 */
class PathFile
{
public:
  PathFile() = default;
  PathFile(const PathFile&) = delete;
  PathFile& operator=(const PathFile&) = delete;
  ~PathFile() { close(); }

  /// Opens (truncates) @p file. @return false when it cannot be written.
  bool open(const std::string& file)
  {
    close();
    out_ = std::fopen(file.c_str(), "w");
    return out_ != nullptr;
  }
  /// Times of later lines count from @p origin.
  void setOrigin(const ros::Time& origin) { origin_ = origin; }
  /// Writes @p pose at @p now unless the last line is less than 0.1 s old (nothing when not open).
  void add(const ros::Time& now, const geometry_msgs::Pose& pose)
  {
    if (out_ == nullptr || (!last_.isZero() && (now - last_).toSec() < 0.1))
      return;
    if (origin_.isZero())
      origin_ = now;
    last_ = now;
    std::fprintf(out_, "%.2f %.4f %.4f %.4f\n", (now - origin_).toSec(), pose.position.x, pose.position.y, yawOf(pose));
  }
  /// Closes the file (flushing it); later add() calls write nothing.
  void close()
  {
    if (out_ != nullptr)
      std::fclose(out_);
    out_ = nullptr;
  }

private:
  std::FILE* out_ = nullptr;
  ros::Time origin_, last_;
};

/**
 * Base fixture: subscribes the five topics, keeps the latest true pose, counts contact, collision
 * and hazard messages and their onsets, ORs the contact bits, latches a bumper, and keeps the objects
 * collided with and the minimum clearance. Subclasses see every pose and decision in onPose() and
 * onStatus(), which run with mutex_ held, as must every read of the members. In the default mode
 * (Collisions::kFail) every test ends with expectNoCollision() (TearDown() runs it for a test that
 * stopped before); in Collisions::kCount, for a robot that collides by design (the bump-and-turn
 * baseline), collisions are only counted. A failed test also reports the last changes of the
 * decision (state, reason, command and text, kTrailLength of them), so that a CI log alone tells
 * what the robot was doing.
 */
class SimWatch : public ::testing::Test
{
protected:
  /// What a collision does to the test.
  enum class Collisions
  {
    kFail,   ///< fails it: expectNoCollision() ends every test
    kCount,  ///< nothing: it is only counted (no expectNoCollision() in TearDown(), no error log)
  };

  explicit SimWatch(Collisions collisions = Collisions::kFail) : collisions_(collisions) {}

  void SetUp() override
  {
    pose_sub_ = nh_.subscribe("true_pose", 100, &SimWatch::poseCallback, this);
    contact_sub_ = nh_.subscribe("contact", 50, &SimWatch::contactCallback, this);
    collision_sub_ = nh_.subscribe("collision", 100, &SimWatch::collisionCallback, this);
    hazards_sub_ = nh_.subscribe("hazards", 50, &SimWatch::hazardsCallback, this);
    status_sub_ = nh_.subscribe("obstacle_status", 100, &SimWatch::statusCallback, this);
  }

  void TearDown() override
  {
    if (!collision_checked_ && collisions_ == Collisions::kFail)
      expectNoCollision();
    if (HasFailure())
    {
      std::lock_guard<std::mutex> lock(mutex_);
      // A counting fixture may watch a system without an obstacle node (the baseline): no trail then.
      if (collisions_ == Collisions::kFail || !trail_.empty())
      {
        std::string text;
        for (const std::string& line : trail_)
          text += "\n  " + line;
        ADD_FAILURE() << "the last " << trail_.size() << " changes of decision (s since the first; state/reason "
                      << "codes of ObstacleStatus, command, distance):" << text;
      }
    }
    // No callback may run on the fixture once it is being destroyed.
    pose_sub_.shutdown();
    contact_sub_.shutdown();
    collision_sub_.shutdown();
    hazards_sub_.shutdown();
    status_sub_.shutdown();
  }

  /// A new true pose; @p previous is null for the first one. pose_ is updated after the call.
  virtual void onPose(const geometry_msgs::Pose* previous, const geometry_msgs::Pose& now) = 0;
  /// A decision of the obstacle node.
  virtual void onStatus(const sl_msgs::ObstacleStatus& msg) = 0;

  /// Waits up to @p seconds for the system: a true pose and a decision. Call without mutex_ held.
  /// @return true when both arrived.
  bool waitForSystem(double seconds)
  {
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(seconds);
    while (ros::ok() && ros::WallTime::now() < deadline)
    {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (have_pose_ && status_messages_ > 0)
          return true;
      }
      ros::WallDuration(0.1).sleep();
    }
    std::lock_guard<std::mutex> lock(mutex_);
    return have_pose_ && status_messages_ > 0;
  }

  /**
   * The end of every closed-loop test (call without mutex_ held): the camera simulator's
   * ground-truth collision signal came, was still coming at the last true pose, and never found an
   * object inside the robot's disc. Prints the minimum clearance over the run and its object.
   */
  void expectNoCollision()
  {
    std::lock_guard<std::mutex> lock(mutex_);
    collision_checked_ = true;
    std::string objects;
    for (const std::string& name : collided_with_)
      objects += (objects.empty() ? "" : ", ") + name;
    ROS_INFO("min clearance %.4f m (%s) at (%.3f, %.3f); %d collision messages, %d colliding%s%s", min_clearance_,
             nearest_object_.c_str(), min_clearance_pose_.position.x, min_clearance_pose_.position.y,
             collision_messages_, colliding_messages_, objects.empty() ? "" : ": ", objects.c_str());
    EXPECT_GT(collision_messages_, 0) << "no collision message from the camera simulator: cannot tell";
    EXPECT_EQ(colliding_messages_, 0) << "the robot's disc overlapped " << objects;
    if (collision_messages_ > 0 && have_pose_)
    {
      EXPECT_LE((last_pose_time_ - last_collision_time_).toSec(), 5.0)
          << "the collision signal stopped before the true pose did";
    }
  }

  std::mutex mutex_;
  int status_messages_ = 0;
  bool have_pose_ = false;
  geometry_msgs::Pose pose_;
  // Contact, collision and hazard messages count (in the members below) only while counting_: always,
  // unless a subclass watches a window of the run (the baseline: from its first command). An onset is
  // a message with contact, a bump or a collision after one without (which may precede the window).
  bool counting_ = true;
  int contact_messages_ = 0;
  int contact_bits_ = 0;  // OR of every contact message
  int contact_onsets_ = 0;
  int hazard_messages_ = 0;
  bool bumped_ = false;
  int bump_onsets_ = 0;  // of bump_left or bump_right
  int collision_messages_ = 0;
  int colliding_messages_ = 0;           // messages with colliding = true
  int collision_onsets_ = 0;             // episodes of them
  std::set<std::string> collided_with_;  // the objects they named
  // <= 0 from a colliding message on (Collision.msg): then -min_clearance_ is the deepest overlap.
  double min_clearance_ = std::numeric_limits<double>::infinity();
  std::string nearest_object_;              // of min_clearance_
  geometry_msgs::Pose min_clearance_pose_;  // the true pose when it came

private:
  void poseCallback(const geometry_msgs::PoseStamped& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    onPose(have_pose_ ? &pose_ : nullptr, msg.pose);
    have_pose_ = true;
    pose_ = msg.pose;
    last_pose_time_ = ros::Time::now();
  }

  void contactCallback(const std_msgs::UInt8& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const bool onset = msg.data != 0 && !in_contact_;
    in_contact_ = msg.data != 0;
    if (!counting_)
      return;
    ++contact_messages_;
    contact_onsets_ += onset ? 1 : 0;
    if (msg.data != 0 && contact_bits_ == 0 && collisions_ == Collisions::kFail)
      ROS_ERROR("contact %d at (%.3f, %.3f)", msg.data, pose_.position.x, pose_.position.y);
    contact_bits_ |= msg.data;
  }

  void collisionCallback(const sl_msgs::Collision& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    last_collision_time_ = ros::Time::now();
    const bool onset = msg.colliding && !colliding_;
    colliding_ = msg.colliding;
    if (!counting_)
      return;
    ++collision_messages_;
    if (msg.colliding)
    {
      if (colliding_messages_ == 0 && collisions_ == Collisions::kFail)
        ROS_ERROR("collision with %s (clearance %.4f m) at (%.3f, %.3f)",
                  msg.objects.empty() ? "?" : msg.objects.front().c_str(), msg.min_clearance, pose_.position.x,
                  pose_.position.y);
      ++colliding_messages_;
      collision_onsets_ += onset ? 1 : 0;
      collided_with_.insert(msg.objects.begin(), msg.objects.end());
    }
    if (msg.min_clearance < min_clearance_)
    {
      min_clearance_ = msg.min_clearance;
      nearest_object_ = msg.nearest_object;
      min_clearance_pose_ = pose_;
    }
  }

  void hazardsCallback(const sl_msgs::Hazards& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const bool bump = msg.bump_left || msg.bump_right;
    const bool onset = bump && !bumping_;
    bumping_ = bump;
    if (!counting_)
      return;
    ++hazard_messages_;
    bump_onsets_ += onset ? 1 : 0;
    bumped_ = bumped_ || bump;
  }

  void statusCallback(const sl_msgs::ObstacleStatus& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++status_messages_;
    onStatus(msg);
    remember(msg);
  }

  /// Keeps a line for a decision whose state, reason or command differs from the previous one.
  void remember(const sl_msgs::ObstacleStatus& msg)
  {
    if (first_status_.isZero())
      first_status_ = msg.header.stamp;
    const bool same = !trail_.empty() && msg.state == last_state_ && msg.reason_code == last_reason_ &&
                      (msg.command == last_command_ || msg.command == sl_msgs::ObstacleStatus::COMMAND_NONE);
    last_state_ = msg.state;
    last_reason_ = msg.reason_code;
    last_command_ = msg.command;
    if (same)
      return;
    char line[240];
    std::snprintf(line, sizeof(line), "%7.2f %d/%-2d cmd %d %+.3f: %.150s", (msg.header.stamp - first_status_).toSec(),
                  msg.state, msg.reason_code, msg.command, msg.command_distance, msg.reason.c_str());
    trail_.emplace_back(line);
    if (trail_.size() > kTrailLength)
      trail_.pop_front();
  }

  static constexpr size_t kTrailLength = 40;
  std::deque<std::string> trail_;
  ros::Time first_status_;
  int last_state_ = -1, last_reason_ = -1, last_command_ = -1;

  ros::NodeHandle nh_;
  ros::Subscriber pose_sub_, contact_sub_, collision_sub_, hazards_sub_, status_sub_;
  const Collisions collisions_;
  bool collision_checked_ = false;
  ros::Time last_pose_time_, last_collision_time_;
  bool in_contact_ = false, bumping_ = false, colliding_ = false;  // the last message's, for the onsets
};

}  // namespace sl_bringup_test
