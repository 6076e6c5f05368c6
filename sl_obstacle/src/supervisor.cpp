#include "sl_obstacle/supervisor.h"

#include <cstdio>

namespace sl_obstacle
{
namespace
{
std::string format(const char* text, double value)
{
  char buffer[160];
  std::snprintf(buffer, sizeof(buffer), text, value);
  return buffer;
}
}  // namespace

const char* toString(CommandMode mode)
{
  return mode == CommandMode::ACTION ? "action" : mode == CommandMode::CMD_VEL ? "cmd_vel" : "filter";
}

Supervisor::Supervisor(const Settings& settings, CommandMode mode, SupervisorSource& source)
  : settings_(settings),
    mode_(mode),
    source_(source),
    checker_(settings.checker),
    decider_(settings.decision),
    teleop_(mode == CommandMode::FILTER)
{
  if (settings.world.enabled)
  {
    world_.emplace(settings.world);
    filter_.emplace(settings.filter);
  }
}

void Supervisor::setSettings(const Settings& settings, bool new_map)
{
  checker_.setParams(settings.checker);
  decider_.setParams(settings.decision);
  if (world_ && new_map)
  {
    world_.emplace(settings.world);
  }
  else if (world_)
  {
    world_->setClearance(settings.world.clearance);
  }
  if (filter_)
  {
    filter_.emplace(settings.filter);
  }
  settings_ = settings;
}

void Supervisor::onPoints(const std::vector<Point>& points, const CloudHandle& cloud, double stamp)
{
  if (have_frame_ && stamp - cloud_stamp_ > settings_.decision.stale_timeout)
  {
    checker_.reset();  // after a gap the persistence history means nothing
  }
  have_frame_ = true;
  cloud_stamp_ = stamp;
  const VolumeResult& result = checker_.analyze(points);
  cloud_contact_ = contactTravel(points, result.obstacle_indices, settings_.world.footprint.radius);
  if (filter_)
  {
    // Kept for the filter; carried into the map frame once the pose at the stamp is known.
    obstacles_edge_.clear();
    for (const std::uint32_t i : result.obstacle_indices)
    {
      obstacles_edge_.push_back(Point2{ points[i].x, points[i].y });
    }
    obstacles_cloud_ = cloud;
    obstacles_stamp_ = stamp;
    obstacles_pending_ = true;
  }
}

std::optional<RayInsert> Supervisor::pairPoints(const CloudHandle& points, double stamp)
{
  return pairing_.onPoints(points, stamp);
}

std::vector<RayInsert> Supervisor::pairRays(const CloudHandle& rays, double stamp)
{
  std::vector<RayInsert> out;
  std::optional<CloudHandle> older;
  std::optional<RayInsert> in = pairing_.onRays(rays, stamp, older);
  if (older)
  {
    out.push_back(RayInsert{ *older, std::nullopt });  // its points never came (gated, dropped)
  }
  if (in)
  {
    out.push_back(std::move(*in));
  }
  return out;
}

void Supervisor::addRays(const std::vector<MapRay>& rays, double stamp)
{
  if (world_)
  {
    world_->addRays(rays, stamp);
  }
}

Actions Supervisor::onCommand(const Velocity& command, double stamp, double now)
{
  Actions a;
  command_ = command;
  command_time_ = stamp;
  if (teleop_.onCommand(now, settings_.teleop_hold))
  {
    cancelGoal(a);
    velocity_goal_.stop();
    a.events.push_back(
        { Event::Kind::TAKEOVER,
          format("cmd_vel_in takes over from autonomy (for %.1f s after the last command)", settings_.teleop_hold) });
  }
  decide(now, false, a);
  return a;
}

Actions Supervisor::onGoalResult(unsigned goal_id, GoalEnd end, const std::string& what, double now)
{
  Actions a;
  if (goal_id != goal_seq_ || !goal_active_)
  {
    return a;  // a goal we replaced or cancelled ourselves
  }
  goal_active_ = false;
  if (end == GoalEnd::FAILED)
  {
    a.events.push_back({ Event::Kind::GOAL_FAILED, "drive_distance goal failed (" + what + ")" });
  }
  decider_.onGoalEnded(end, now, what);
  decide(now, false, a);
  return a;
}

void Supervisor::onGoalFeedback(unsigned goal_id, double remaining)
{
  if (goal_id == goal_seq_ && goal_active_)
  {
    goal_remaining_ = remaining;
  }
}

bool Supervisor::onBumpers(bool left, bool right, double now)
{
  const bool bump = left || right;
  const bool mark = bump && !bumped_ && localized_ && world_;
  if (mark)
  {
    world_->markBump(pose_, left, right, now);
  }
  bumped_ = bump;
  return mark;
}

Actions Supervisor::step(double now, bool map_updated)
{
  Actions a;
  decide(now, map_updated, a);
  return a;
}

bool Supervisor::blocked() const
{
  return teleop_.active() ? filter_out_.reason == FilterReason::STOPPED_OBSTACLE : decider_.last().blocked;
}

void Supervisor::decide(double now, bool map_updated, Actions& a)
{
  if (mode_ == CommandMode::CMD_VEL && velocity_goal_.update(now))
  {
    decider_.onGoalEnded(GoalEnd::REACHED, now, "open-loop goal done");
  }
  if (world_ && updatePose(now))
  {
    world_->updatePose(pose_, now);
  }
  if (updateTeleop(now, a))
  {
    filterStep(now, a);
    return;
  }
  if (have_frame_)
  {
    FrameSummary cloud = summarize(checker_.result(), cloud_stamp_);
    if (world_)
    {
      cloud.nearest_obstacle = cloud_contact_;  // the map keeps the clearance on the disc's travel
    }
    decider_.onFrame(
        world_ ? withMap(cloud, world_->summarize(pose_, now, map_updated), 3.0 * settings_.world.map.resolution)
               : cloud);
  }
  const Decision& d = decider_.step(now, motion());
  execute(d, now, a);
  if (goal_active_)
  {
    // Each decision step keeps the goal alive in the driver; a frozen or dead node stops the robot.
    a.outputs.push_back(Output{ Output::Kind::HEARTBEAT });
  }
  a.status = StatusKind::DECISION;
}

bool Supervisor::updatePose(double now)
{
  Pose2D pose;
  double stamp = 0.0;
  if (!source_.robotPose(pose, stamp))
  {
    localization_detail_ = "no transform from ~odom_frame to ~robot_frame";
    return localized_ = false;
  }
  if (now - stamp > settings_.decision.stale_timeout)
  {
    localization_detail_ = "odometry transform older than stale_timeout";
    return localized_ = false;
  }
  pose_ = pose;
  return localized_ = true;
}

bool Supervisor::updateTeleop(double now, Actions& a)
{
  if (!filter_)
  {
    return false;
  }
  bool ended = false;
  const bool active = teleop_.update(now, ended);
  if (ended)
  {
    decider_.reset();  // it plans anew from here: the robot moved under teleoperation
    if (moving_)
    {
      twist(0.0, 0.0, a);
    }
    a.events.push_back(
        { Event::Kind::RESUMED, format("cmd_vel_in quiet for %.1f s: autonomy resumes", settings_.teleop_hold) });
  }
  return active;
}

void Supervisor::filterStep(double now, Actions& a)
{
  FilterInput in;
  in.now = now;
  in.command = command_;
  in.command_time = command_time_;
  in.localized = localized_;
  in.pose = pose_;
  in.cloud_time = have_frame_ ? cloud_stamp_ : -std::numeric_limits<double>::infinity();
  // The cloud's obstacles (static) seen from where the robot is now.
  resolveObstacles(now, a);
  toChild(obstacles_odom_, pose_, obstacles_robot_);
  in.obstacles = &obstacles_robot_;
  filter_out_ = filter_->filter(world_->map(), in);
  const Velocity& v = filter_out_.command;
  if (v.linear != 0.0 || v.angular != 0.0 || moving_)
  {
    twist(v.linear, v.angular, a);
  }
  a.status = StatusKind::FILTER;
}

void Supervisor::resolveObstacles(double now, Actions& a)
{
  if (!obstacles_pending_)
  {
    return;
  }
  Pose2D edge;  // the working-volume frame in the map frame at the cloud's stamp
  std::string error;
  if (!source_.volumePose(obstacles_cloud_, edge, error))
  {
    // Odometry usually arrives a few ms after the image: keep the previous points until then.
    if (now - obstacles_stamp_ > settings_.decision.stale_timeout)
    {
      a.events.push_back({ Event::Kind::OBSTACLES_DROPPED, "filter uses the map only: " + error });
      obstacles_odom_.clear();
      obstacles_pending_ = false;
    }
    return;
  }
  toParent(obstacles_edge_, edge, obstacles_odom_);
  obstacles_pending_ = false;
}

MotionState Supervisor::motion()
{
  MotionState m;
  m.driver_ready = source_.driverReady();
  if (mode_ == CommandMode::ACTION)
  {
    m.driver_detail = "drive_distance action server not connected";
    m.goal_active = goal_active_;
    m.goal_remaining = goal_remaining_;
    m.goal_speed = goal_speed_;
  }
  else
  {
    m.driver_detail = "nobody subscribes cmd_vel";
    m.goal_active = velocity_goal_.active();
    m.goal_remaining = velocity_goal_.remaining();
    m.goal_speed = velocity_goal_.speed();
  }
  m.localized = localized_;
  m.localization_detail = localization_detail_;
  return m;
}

void Supervisor::execute(const Decision& d, double now, Actions& a)
{
  switch (d.command)
  {
    case Command::NONE:
      if (mode_ == CommandMode::CMD_VEL && velocity_goal_.active())
      {
        twist(velocity_goal_.velocity(), 0.0, a);  // keeps the driver's watchdog fed
      }
      break;
    case Command::STOP:
      cancelGoal(a);
      velocity_goal_.stop();
      if (moving_)
      {
        twist(0.0, 0.0, a);
      }
      break;
    case Command::DRIVE:
      if (mode_ == CommandMode::ACTION)
      {
        if (moving_)
        {
          twist(0.0, 0.0, a);  // end a turn before the goal takes over
        }
        sendGoal(d.distance, d.speed, a);
      }
      else
      {
        velocity_goal_.start(d.distance, d.speed, now);
        twist(velocity_goal_.velocity(), 0.0, a);
      }
      break;
    case Command::TURN:
      cancelGoal(a);
      velocity_goal_.stop();
      twist(0.0, d.angular_speed, a);
      break;
  }
}

void Supervisor::sendGoal(double distance, double speed, Actions& a)
{
  goal_active_ = true;
  goal_remaining_ = distance;
  goal_speed_ = speed;
  Output o{ Output::Kind::GOAL };
  o.goal_id = ++goal_seq_;
  o.distance = distance;
  o.speed = speed;
  a.outputs.push_back(o);
}

void Supervisor::cancelGoal(Actions& a)
{
  if (!goal_active_)
  {
    return;
  }
  goal_active_ = false;
  ++goal_seq_;
  a.outputs.push_back(Output{ Output::Kind::CANCEL_GOAL });
}

void Supervisor::twist(double linear, double angular, Actions& a)
{
  Output o{ Output::Kind::TWIST };
  o.twist = Velocity{ linear, angular };
  a.outputs.push_back(o);
  moving_ = linear != 0.0 || angular != 0.0;
}
}  // namespace sl_obstacle
