#include "sl_navigation/navigator.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "validation.h"

namespace sl_navigation
{
namespace
{
constexpr double kSearchAllowance = 1.0;  // m driven beyond max_detour x the distance (short goals)
constexpr double kStuckPlace = 0.15;      // m: stuck again this near the first stuck is the same place
constexpr double kStuckAgain = 60.0;      // s within which another stuck there counts
constexpr double kTrailStep = 0.05;       // m between the trail's points
constexpr std::size_t kTrailPoints = 40;  // the trail kept: 2 m
constexpr double kBackoffDistance = 0.3;  // m reversed along the trail
constexpr double kBackoffSpeed = 0.08;    // m/s
constexpr double kBackoffTimeout = 8.0;   // s per phase of a back-off
constexpr double kBlockedRadius = 0.1;    // m, the disc taken as blocked
constexpr double kBlockedAhead = 0.12;    // m beyond the robot's disc where that disc's centre lies on the path
constexpr double kFaceGoalTime = 10.0;    // s at most to face the goal before a refusal counts
}  // namespace

void NavigatorParams::validate() const
{
  grid.validate();
  planner.validate();
  follower.validate();
  detail::requireRange("replan_period", replan_period, 0.05, 60.0);
  detail::requireRange("progress_timeout", progress_timeout, 1.0, 3600.0);
  detail::requireRange("progress_distance", progress_distance, 0.01, 10.0);
  detail::requireRange("refuse_time", refuse_time, 0.0, 60.0);
  detail::requireRange("switch_gain", switch_gain, 0.0, 10.0);
  detail::requireRange("max_detour", max_detour, 1.0, 100.0);
  detail::requireRange("stuck_time", stuck_time, 0.5, 60.0);
  detail::requireRange("look_around", look_around, 0.0, M_PI);
  detail::requireRange("refused_memory", refused_memory, 0.0, 3600.0);
  detail::requireRange("map_timeout", map_timeout, 0.1, 60.0);
  detail::requireRange("unseen_goal_distance", unseen_goal_distance, 0.0, 5.0);
  detail::requireRange("unseen_goal_time", unseen_goal_time, 1.0, 600.0);
  detail::requireRange("unseen_goal_clearance", unseen_goal_clearance, 0.0, 2.0);
}

const char* toString(NavState state)
{
  switch (state)
  {
    case NavState::IDLE:
      return "IDLE";
    case NavState::ACTIVE:
      return "ACTIVE";
    case NavState::SUCCEEDED:
      return "SUCCEEDED";
    case NavState::ABORTED:
      return "ABORTED";
    case NavState::CANCELLED:
      return "CANCELLED";
  }
  return "?";
}

namespace
{
GridParams checked(const NavigatorParams& p)
{
  p.validate();
  return p.grid;
}
}  // namespace

Navigator::Navigator(const NavigatorParams& params)
  : params_(params), grid_(checked(params)), planner_(params.planner, grid_.width()), follower_(params.follower)
{
  out_.reason = "idle: waiting for a goal";
}

bool Navigator::onMap(const OccupancyView& view, double stamp)
{
  if (!std::isfinite(stamp) || !window_.set(view))
  {
    return false;
  }
  map_time_ = stamp;
  if (!has_map_)
  {
    grid_.reset(view.origin_x + 0.5 * view.width * view.resolution,
                view.origin_y + 0.5 * view.height * view.resolution);
    has_map_ = true;
  }
  return grid_.fuse(view, stamp);
}

std::string Navigator::setGoal(const NavGoal& goal, double now)
{
  if (out_.state == NavState::ACTIVE)
  {
    end(NavState::CANCELLED, "pre-empted by a new goal");
  }
  char text[200];
  if (!std::isfinite(goal.x) || !std::isfinite(goal.y) || (goal.use_yaw && !std::isfinite(goal.yaw)))
  {
    std::snprintf(text, sizeof(text), "goal refused: not finite (x %g, y %g, yaw %g)", goal.x, goal.y, goal.yaw);
    end(NavState::ABORTED, text);
    return out_.reason;
  }
  if (has_map_ && !grid_.contains(goal.x, goal.y))
  {
    std::snprintf(text, sizeof(text),
                  "goal refused: (%.2f, %.2f) lies outside the map (%.0f x %.0f m around (%.2f, %.2f))", goal.x, goal.y,
                  params_.grid.size, params_.grid.size, grid_.originX() + 0.5 * params_.grid.size,
                  grid_.originY() + 0.5 * params_.grid.size);
    end(NavState::ABORTED, text);
    return out_.reason;
  }
  goal_ = goal;
  plan_ = Plan();
  follower_.reset();
  out_ = NavOutput();
  out_.state = NavState::ACTIVE;
  std::snprintf(text, sizeof(text), "goal (%.2f, %.2f) accepted", goal.x, goal.y);
  out_.reason = text;
  stop_pending_ = false;
  goal_time_ = now;
  plan_time_ = -std::numeric_limits<double>::infinity();
  refuse_since_ = std::numeric_limits<double>::quiet_NaN();
  best_remaining_ = std::numeric_limits<double>::infinity();
  best_distance_ = std::numeric_limits<double>::infinity();
  goal_seen_ = false;
  goal_distance_ = std::numeric_limits<double>::infinity();  // set at the first pose
  progress_time_ = now;
  has_last_pose_ = false;
  told_to_drive_ = false;
  unseen_time_ = 0.0;
  last_step_ = std::numeric_limits<double>::quiet_NaN();
  look_step_ = -1;
  backoff_phase_ = 0;
  confirm_ = Confirm::NONE;
  return std::string();
}

void Navigator::cancel(double /*now*/, const std::string& why)
{
  if (out_.state == NavState::ACTIVE)
  {
    end(NavState::CANCELLED, why);
  }
}

void Navigator::refuse(const std::string& why)
{
  end(NavState::ABORTED, why);
}

bool Navigator::noPose(double now, const std::string& why)
{
  if (out_.state != NavState::ACTIVE)
  {
    const bool stop = stop_pending_;
    stop_pending_ = false;
    return stop;
  }
  if (now - progress_time_ > params_.progress_timeout)
  {
    end(NavState::ABORTED, "goal aborted: " + why + " for longer than progress_timeout");
    stop_pending_ = false;
  }
  return true;
}

const NavOutput& Navigator::endNow(NavState state, const std::string& reason)
{
  end(state, reason);
  out_.command = true;  // the stop goes out with this step's output
  stop_pending_ = false;
  return out_;
}

void Navigator::end(NavState state, const std::string& reason)
{
  out_.state = state;
  out_.reason = reason;
  stop_pending_ = true;
  follower_.reset();
}

bool Navigator::replan(const Pose& pose, double now, bool force)
{
  pruneBlocked(now);
  planner_.update(grid_, now);
  // A goal the map puts too near an obstacle is moved at most 3/4 of goal_tolerance, so that the
  // path's end is reached with at least a quarter of it to spare.
  const double tolerance = params_.follower.goal_tolerance;
  Plan p = planner_.plan(grid_, pose.x, pose.y, goal_.x, goal_.y, 0.75 * tolerance);
  plan_time_ = now;
  plan_version_ = grid_.version();
  if (p.status == PlanStatus::OK)
  {
    bool detour = force;  // the current plan is blocked (or there is none): the new one may be longer
    if (!plan_.points.empty() && plan_.status == PlanStatus::OK)
    {
      const double kept = planner_.pathCost(grid_, plan_.points, follower_.index());
      if (!force && std::isfinite(kept) && p.cost * (1.0 + params_.switch_gain) > kept)
      {
        refuse_since_ = std::numeric_limits<double>::quiet_NaN();
        return true;  // the current plan is still passable and about as good: keep it
      }
      detour = detour || !std::isfinite(kept);
    }
    plan_ = std::move(p);
    follower_.setPath(plan_.points, goal_.yaw, goal_.use_yaw, tolerance - plan_.goal_shift);
    if (detour && !mayBeInside(now) && follower_.remaining() <= params_.max_detour * goal_distance_)
    {
      // An obstacle found on the way is no regress: progress counts along the detour from here.
      // Not toward a goal that may lie inside something (mayBeInside()): a detour there may be the
      // search for a way into it, and has to beat the shortest plan so far within progress_timeout.
      best_remaining_ = follower_.remaining();
    }
    refuse_since_ = std::numeric_limits<double>::quiet_NaN();
    confirm_ = Confirm::NONE;
    out_.plan_changed = true;
    return true;
  }
  plan_.status = p.status;
  plan_.text = p.text;
  const bool refuse_now = p.status == PlanStatus::START_OUTSIDE || p.status == PlanStatus::GOAL_OUTSIDE;
  if (std::isnan(refuse_since_))
  {
    refuse_since_ = now;
  }
  // Blocked or enclosed only counts once the robot looked toward the goal (confirmLook()): one
  // spurious cell in a doorway must not end a goal behind it.
  if (refuse_now || (confirm_ == Confirm::DONE && now - refuse_since_ >= params_.refuse_time))
  {
    end(NavState::ABORTED, std::string("goal aborted: ") + p.text);
  }
  return false;
}

void Navigator::track(const Pose& pose, double now)
{
  if (!std::isfinite(goal_distance_))
  {
    goal_distance_ = std::hypot(goal_.x - pose.x, goal_.y - pose.y);
  }
  if (has_last_pose_)
  {
    out_.travelled += std::hypot(pose.x - last_pose_.x, pose.y - last_pose_.y);
  }
  last_pose_ = pose;
  has_last_pose_ = true;
  out_.elapsed = now - goal_time_;
}

const NavOutput& Navigator::step(const Pose& pose, double now, double speed_cap)
{
  out_.plan_changed = false;
  if (has_map_)
  {
    const double body = params_.planner.robot_radius - 0.71 * params_.grid.resolution;
    grid_.markFree(pose.x, pose.y, body, now);
  }
  if (out_.state != NavState::ACTIVE)
  {
    out_.command = stop_pending_;
    out_.linear = 0.0;
    out_.angular = 0.0;
    stop_pending_ = false;
    return out_;
  }
  out_.command = true;
  out_.linear = 0.0;
  out_.angular = 0.0;
  if (!std::isfinite(pose.x) || !std::isfinite(pose.y) || !std::isfinite(pose.yaw))
  {
    out_.reason = "stopped: the robot's pose is not finite";
    return out_;
  }
  track(pose, now);
  if (!has_map_ || now - map_time_ > params_.map_timeout)
  {
    char text[160];
    std::snprintf(text, sizeof(text), "stopped: %s (map_timeout %.1f s)",
                  has_map_ ? "the local map is stale" : "waiting for the local map", params_.map_timeout);
    out_.reason = text;
    if (now - progress_time_ > params_.progress_timeout)
    {
      end(NavState::ABORTED, std::string("goal aborted: ") + text + " for longer than progress_timeout");
      stop_pending_ = false;
    }
    return out_;
  }
  const bool stale_plan = plan_.points.empty() || plan_.status != PlanStatus::OK ||
                          (grid_.version() != plan_version_ && now - plan_time_ >= params_.replan_period);
  if (stale_plan && !replan(pose, now))
  {
    if (out_.state == NavState::ACTIVE && !confirmLook(pose, now))
    {
      out_.reason = "no plan yet: " + plan_.text;
    }
    out_.command = true;
    return out_;
  }
  recordTrail(pose);
  checkStuck(pose, now);
  if (backoff_phase_ != 0 && backoff(pose, now))
  {
    return out_;
  }
  if (look_step_ >= 0 && lookAround(pose, now))
  {
    return out_;
  }
  if (out_.state != NavState::ACTIVE)
  {
    out_.command = true;
    return out_;
  }
  FollowCommand c = follower_.step(pose, window_, now, speed_cap);
  if (c.mode == FollowMode::BLOCKED && now - plan_time_ >= 0.5)
  {
    if (replan(pose, now, true))
    {
      c = follower_.step(pose, window_, now, speed_cap);
    }
    else if (out_.state != NavState::ACTIVE)
    {
      out_.command = true;
      return out_;
    }
  }
  out_.mode = c.mode;
  out_.goal_distance = c.goal_distance;
  out_.remaining = c.remaining;
  char text[320];
  if (c.mode == FollowMode::ARRIVED)
  {
    std::snprintf(text, sizeof(text), "goal reached: %.3f m from (%.2f, %.2f) after %.1f s and %.2f m",
                  std::hypot(goal_.x - pose.x, goal_.y - pose.y), goal_.x, goal_.y, out_.elapsed, out_.travelled);
    return endNow(NavState::SUCCEEDED, text);
  }
  // Nearer in a straight line is no progress toward a goal that may lie inside something: circling
  // it in search of a way in also comes nearer.
  if ((!mayBeInside(now) && c.goal_distance < best_distance_ - params_.progress_distance) ||
      c.remaining < best_remaining_ - params_.progress_distance)
  {
    best_distance_ = std::min(best_distance_, c.goal_distance);
    best_remaining_ = std::min(best_remaining_, c.remaining);
    progress_time_ = now;
  }
  else if (now - progress_time_ > params_.progress_timeout)
  {
    std::snprintf(text, sizeof(text),
                  "goal aborted: no progress for %.0f s (%.2f m of path left, %.2f m straight): unreachable from here",
                  params_.progress_timeout, c.remaining, c.goal_distance);
    return endNow(NavState::ABORTED, text);
  }
  if (goalStaysUnseen(pose, now))
  {
    std::snprintf(text, sizeof(text),
                  "goal aborted: still unseen after %.0f s within %.2f m of it (%.2f m of path left): inside or "
                  "behind something",
                  unseen_time_, params_.unseen_goal_distance, c.remaining);
    return endNow(NavState::ABORTED, text);
  }
  const double search = params_.max_detour * goal_distance_ + kSearchAllowance;
  if (out_.travelled > search)
  {
    std::snprintf(text, sizeof(text),
                  "goal aborted: %.2f m driven in search of a way, max_detour x the first straight-line distance "
                  "(%.2f m) + %.1f m (%.2f m of path left): unreachable from here",
                  out_.travelled, goal_distance_, kSearchAllowance, c.remaining);
    return endNow(NavState::ABORTED, text);
  }
  out_.linear = c.linear;
  out_.angular = c.angular;
  out_.reason = now - blocked_time_ < 3.0 ? blocked_text_ + "; " + c.text : c.text;
  told_to_drive_ = c.linear > 0.0;
  return out_;
}

Point Navigator::pathEnd() const
{
  // A goal too near an obstacle is moved a little: the plan's end is where the robot is to stop.
  const bool planned = plan_.status == PlanStatus::OK && !plan_.points.empty();
  return planned ? plan_.points.back() : Point{ goal_.x, goal_.y };
}

bool Navigator::mayBeInside(double now)
{
  const Point end = pathEnd();
  goal_seen_ = goal_seen_ || grid_.at(end.x, end.y, now) == Cell::Free;
  if (goal_seen_ || params_.unseen_goal_clearance <= 0.0)
  {
    return false;
  }
  bool near = false;
  grid_.forEachCellInDisc(end.x, end.y, params_.unseen_goal_clearance,
                          [&](int ix, int iy) { near = near || grid_.cell(ix, iy, now) == Cell::Occupied; });
  return near;
}

bool Navigator::goalStaysUnseen(const Pose& pose, double now)
{
  const double dt = std::isnan(last_step_) ? 0.0 : std::max(0.0, now - last_step_);
  last_step_ = now;
  const Point end = pathEnd();
  const bool near = std::hypot(end.x - pose.x, end.y - pose.y) <= params_.unseen_goal_distance;
  if (near && grid_.at(end.x, end.y, now) == Cell::Unknown)
  {
    unseen_time_ += dt;
  }
  return unseen_time_ >= params_.unseen_goal_time;
}

void Navigator::checkStuck(const Pose& pose, double now)
{
  const bool moved = std::hypot(pose.x - still_pose_.x, pose.y - still_pose_.y) > 0.02 ||
                     std::abs(wrapAngle(pose.yaw - still_pose_.yaw)) > 0.05;
  if (moved || !told_to_drive_)
  {
    still_pose_ = pose;
    still_since_ = now;
    return;
  }
  if (now - still_since_ >= params_.stuck_time && look_step_ < 0 && backoff_phase_ == 0)
  {
    const bool same =
        now - stuck_at_time_ < kStuckAgain && std::hypot(pose.x - stuck_at_.x, pose.y - stuck_at_.y) < kStuckPlace;
    stuck_count_ = same ? stuck_count_ + 1 : 1;
    ++stucks_;
    stuck_at_time_ = now;
    if (!same)
    {
      stuck_at_ = pose;
    }
    // The goal itself is never taken as blocked: where the refused way ends at the goal, the robot
    // backs off again and looks (progress_timeout ends a goal it never gets to).
    const Point refused = refusedPoint(pose);
    const bool way_is_goal = blocksGoal(refused);
    if ((stuck_count_ == 2 || (stuck_count_ > 2 && way_is_goal)) && startBackoff(pose, refused, now))
    {
      return;
    }
    if (stuck_count_ >= 2 && !way_is_goal && params_.refused_memory > 0.0)
    {
      blockAhead(pose, refused, now);
      return;
    }
    look_step_ = 0;
    look_base_yaw_ = pose.yaw;
    look_started_ = now;
    told_to_drive_ = false;
  }
}

bool Navigator::lookAround(const Pose& pose, double now)
{
  const double targets[3] = { look_base_yaw_ + params_.look_around, look_base_yaw_ - params_.look_around,
                              look_base_yaw_ };
  while (look_step_ >= 0 && look_step_ < 3)
  {
    const double error = wrapAngle(targets[look_step_] - pose.yaw);
    if (std::abs(error) > 0.05 && now - look_started_ < 10.0 * (look_step_ + 1))
    {
      out_.linear = 0.0;
      out_.angular = turnRate(error, params_.follower.turn_speed);
      out_.mode = FollowMode::LOOK;
      char text[160];
      std::snprintf(text, sizeof(text), "stuck for %.1f s: looking around (%d of 3, %.2f rad to go)",
                    params_.stuck_time, look_step_ + 1, error);
      out_.reason = text;
      return true;
    }
    ++look_step_;
  }
  look_step_ = -1;
  still_pose_ = pose;
  still_since_ = now;
  if (!replan(pose, now, true))
  {
    out_.linear = 0.0;
    out_.angular = 0.0;
    if (out_.state == NavState::ACTIVE)
    {
      out_.reason = "looked around; no plan yet: " + plan_.text;
    }
    return true;  // a stop this step (an ended goal also owes one)
  }
  return false;
}

bool Navigator::confirmLook(const Pose& pose, double now)
{
  if (confirm_ == Confirm::DONE)
  {
    return false;  // looked in this episode: refuse_time runs
  }
  if (confirm_ == Confirm::NONE)
  {
    confirm_ = Confirm::TURNING;
    confirm_started_ = now;
  }
  char text[360];
  const double dx = goal_.x - pose.x;
  const double dy = goal_.y - pose.y;
  const double error = wrapAngle(std::atan2(dy, dx) - pose.yaw);
  const bool far = std::hypot(dx, dy) > params_.planner.robot_radius;
  if (confirm_ == Confirm::TURNING && far && std::abs(error) > 0.1 && now - confirm_started_ < kFaceGoalTime)
  {
    out_.angular = turnRate(error, params_.follower.turn_speed);
    out_.mode = FollowMode::LOOK;
    std::snprintf(text, sizeof(text), "%s: turning toward the goal to look again (%.2f rad to go)", plan_.text.c_str(),
                  error);
    out_.reason = text;
    return true;
  }
  if (confirm_ == Confirm::TURNING)
  {
    confirm_ = Confirm::WAITING;
    confirm_started_ = now;
  }
  if (now - confirm_started_ < params_.follower.look_time)
  {
    out_.mode = FollowMode::LOOK;
    std::snprintf(text, sizeof(text), "%s: looking toward the goal before refusing it", plan_.text.c_str());
    out_.reason = text;
    return true;
  }
  confirm_ = Confirm::DONE;
  refuse_since_ = now;
  return false;
}

Point Navigator::refusedPoint(const Pose& pose) const
{
  // The first point of the path beyond the robot's disc and a margin: where the filter would not
  // let it go.
  const double reach = params_.planner.robot_radius + kBlockedAhead;
  for (std::size_t i = follower_.index(); i < plan_.points.size(); ++i)
  {
    if (std::hypot(plan_.points[i].x - pose.x, plan_.points[i].y - pose.y) >= reach)
    {
      return plan_.points[i];
    }
  }
  return Point{ goal_.x, goal_.y };
}

bool Navigator::blocksGoal(const Point& c) const
{
  // A blocked disc is occupied: the planner keeps the robot's centre lethalDistance() off it.
  return std::hypot(c.x - goal_.x, c.y - goal_.y) < kBlockedRadius + params_.planner.lethalDistance() + 0.05;
}

void Navigator::recordTrail(const Pose& pose)
{
  if (!trail_.empty() && std::hypot(pose.x - trail_.back().x, pose.y - trail_.back().y) < kTrailStep)
  {
    return;
  }
  if (trail_.size() >= kTrailPoints)
  {
    trail_.erase(trail_.begin());
  }
  trail_.push_back(Point{ pose.x, pose.y });
}

bool Navigator::startBackoff(const Pose& pose, const Point& refused, double now)
{
  // The trail point kBackoffDistance back along the way the robot came.
  if (trail_.empty())
  {
    return false;
  }
  double along = std::hypot(pose.x - trail_.back().x, pose.y - trail_.back().y);
  std::size_t i = trail_.size();
  while (i > 1 && along < kBackoffDistance)
  {
    --i;
    along += std::hypot(trail_[i].x - trail_[i - 1].x, trail_[i].y - trail_[i - 1].y);
  }
  if (along < 0.5 * kBackoffDistance)
  {
    return false;
  }
  backoff_target_ = trail_[i - 1];
  backoff_look_ = refused;
  backoff_phase_ = 1;
  backoff_started_ = now;
  ++backoffs_;
  told_to_drive_ = false;
  return true;
}

bool Navigator::backoff(const Pose& pose, double now)
{
  out_.linear = 0.0;
  out_.angular = 0.0;
  out_.mode = FollowMode::LOOK;
  const double to_target = std::hypot(backoff_target_.x - pose.x, backoff_target_.y - pose.y);
  const double away =
      std::atan2(pose.y - backoff_target_.y, pose.x - backoff_target_.x);  // heading with the target behind
  const double look = std::atan2(backoff_look_.y - pose.y, backoff_look_.x - pose.x);
  const bool timed_out = now - backoff_started_ > kBackoffTimeout;
  char text[200];
  if (backoff_phase_ == 1 && std::abs(wrapAngle(away - pose.yaw)) > 0.1 && !timed_out)
  {
    out_.angular = turnRate(wrapAngle(away - pose.yaw), params_.follower.turn_speed);
    std::snprintf(text, sizeof(text), "stuck twice here: turning so that the trail lies behind (%.2f rad to go)",
                  wrapAngle(away - pose.yaw));
  }
  else if (backoff_phase_ <= 2 && to_target > 0.04 && !(backoff_phase_ == 2 && timed_out))
  {
    if (backoff_phase_ == 1)
    {
      backoff_phase_ = 2;
      backoff_started_ = now;
    }
    // Reverse with the heading kept on the trail point behind.
    out_.linear = -std::min(kBackoffSpeed, std::sqrt(2.0 * params_.follower.acceleration * to_target));
    out_.angular = turnRate(wrapAngle(away - pose.yaw), 0.5);
    std::snprintf(text, sizeof(text), "stuck twice here: backing off along the trail, %.2f m to go", to_target);
  }
  else if (backoff_phase_ <= 3 && std::abs(wrapAngle(look - pose.yaw)) > params_.follower.look_tolerance &&
           !(backoff_phase_ == 3 && timed_out))
  {
    if (backoff_phase_ != 3)
    {
      backoff_phase_ = 3;
      backoff_started_ = now;
    }
    out_.angular = turnRate(wrapAngle(look - pose.yaw), params_.follower.turn_speed);
    std::snprintf(text, sizeof(text), "backed off: facing the refused way at (%.2f, %.2f)", backoff_look_.x,
                  backoff_look_.y);
  }
  else if (backoff_phase_ <= 4 && now - backoff_started_ < params_.follower.look_time)
  {
    if (backoff_phase_ != 4)
    {
      backoff_phase_ = 4;
      backoff_started_ = now;
    }
    std::snprintf(text, sizeof(text), "backed off: looking at the refused way at (%.2f, %.2f)", backoff_look_.x,
                  backoff_look_.y);
  }
  else
  {
    backoff_phase_ = 0;
    still_pose_ = pose;
    still_since_ = now;
    stuck_at_time_ = now;  // the next stuck in this place (within kStuckAgain) blocks the way
    if (replan(pose, now, true))
    {
      return false;
    }
    if (out_.state == NavState::ACTIVE)
    {
      out_.reason = "backed off; no plan yet: " + plan_.text;
    }
    return true;
  }
  out_.reason = text;
  return true;
}

void Navigator::blockAhead(const Pose& pose, const Point& c, double now)
{
  refused_.push_back(Refused{ Disc{ c.x, c.y, kBlockedRadius }, now + params_.refused_memory });
  stuck_count_ = 0;
  stuck_at_time_ = -std::numeric_limits<double>::infinity();
  still_pose_ = pose;
  still_since_ = now;
  told_to_drive_ = false;
  replan(pose, now, true);
  char text[200];
  std::snprintf(text, sizeof(text),
                "stuck again at (%.2f, %.2f): the way through (%.2f, %.2f) taken as blocked for %.0f s", pose.x, pose.y,
                c.x, c.y, params_.refused_memory);
  blocked_text_ = text;
  blocked_time_ = now;
  ++blocked_places_;
}

void Navigator::pruneBlocked(double now)
{
  refused_.erase(std::remove_if(refused_.begin(), refused_.end(), [now](const Refused& r) { return r.until <= now; }),
                 refused_.end());
  std::vector<Disc> discs;
  discs.reserve(refused_.size());
  for (const Refused& r : refused_)
  {
    discs.push_back(r.disc);
  }
  planner_.setBlocked(discs);
}
}  // namespace sl_navigation
