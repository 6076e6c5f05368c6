#include "sl_obstacle/decision_maker.h"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <stdexcept>

#include "validation.h"

namespace sl_obstacle
{
void DecisionParams::validate() const
{
  using detail::requireInRange;
  requireInRange("safety_margin", safety_margin, 0.0, 5.0);
  requireInRange("min_goal_distance", min_goal_distance, 1e-3, 5.0);
  requireInRange("slow_distance", slow_distance, 0.0, 20.0);
  requireInRange("max_speed", max_speed, 1e-3, 0.5);
  requireInRange("min_speed", min_speed, 1e-3, 0.5);
  requireInRange("min_coverage", min_coverage, 0.0, 1.0);
  requireInRange("full_speed_coverage", full_speed_coverage, 0.0, 1.0);
  requireInRange("stale_timeout", stale_timeout, 1e-3, 60.0);
  requireInRange("preempt_tolerance", preempt_tolerance, 0.0, 1.0);
  requireInRange("replan_distance", replan_distance, 0.0, 5.0);
  requireInRange("speed_tolerance", speed_tolerance, 0.0, 0.5);
  requireInRange("turn_speed", turn_speed, 1e-3, 2.0);
  requireInRange("turn_angle", turn_angle, 1e-3, 2.0 * M_PI);
  requireInRange("settle_time", settle_time, 0.0, 10.0);
  requireInRange("deceleration", deceleration, 0.0, 10.0);
  requireInRange("backoff_distance", backoff_distance, 0.01, 2.0);
  requireInRange("backoff_speed", backoff_speed, 0.01, 0.5);
  requireInRange("creep_speed", creep_speed, 0.0, 0.05);
  if (slow_distance <= safety_margin)
  {
    detail::refuse("slow_distance", "must be greater than safety_margin", slow_distance);
  }
  if (min_speed > max_speed)
  {
    detail::refuse("min_speed", "must not exceed max_speed", min_speed);
  }
  if (full_speed_coverage < min_coverage)
  {
    detail::refuse("full_speed_coverage", "must not be below min_coverage", full_speed_coverage);
  }
  if (max_turns < 0 || max_turns > 1000)
  {
    detail::refuse("max_turns", "must be in [0, 1000]", max_turns);
  }
  if (max_backoffs < 0 || max_backoffs > 100)
  {
    detail::refuse("max_backoffs", "must be in [0, 100]", max_backoffs);
  }
}

const char* toString(State state)
{
  switch (state)
  {
    case State::STALE:
      return "STALE";
    case State::STOPPED:
      return "STOPPED";
    case State::BLOCKED:
      return "BLOCKED";
    case State::TURNING:
      return "TURNING";
    case State::SLOWING:
      return "SLOWING";
    case State::DRIVING:
      return "DRIVING";
    case State::BACKING_OFF:
      return "BACKING_OFF";
  }
  return "?";
}

const char* toString(Reason reason)
{
  switch (reason)
  {
    case Reason::NO_DATA:
      return "NO_DATA";
    case Reason::STALE_DATA:
      return "STALE_DATA";
    case Reason::DISABLED:
      return "DISABLED";
    case Reason::DRIVER_UNAVAILABLE:
      return "DRIVER_UNAVAILABLE";
    case Reason::DRIVER_FAILED:
      return "DRIVER_FAILED";
    case Reason::DRIVER_HAZARD:
      return "DRIVER_HAZARD";
    case Reason::LOW_COVERAGE:
      return "LOW_COVERAGE";
    case Reason::OBSTACLE:
      return "OBSTACLE";
    case Reason::UNKNOWN_AHEAD:
      return "UNKNOWN_AHEAD";
    case Reason::TURNING:
      return "TURNING";
    case Reason::LOOKING:
      return "LOOKING";
    case Reason::NO_FREE_DIRECTION:
      return "NO_FREE_DIRECTION";
    case Reason::WAITING_FOR_FRAME:
      return "WAITING_FOR_FRAME";
    case Reason::PATH_FREE:
      return "PATH_FREE";
    case Reason::SHORT_FREE_DISTANCE:
      return "SHORT_FREE_DISTANCE";
    case Reason::PARTIAL_COVERAGE:
      return "PARTIAL_COVERAGE";
    case Reason::NEARER_OBSTACLE:
      return "NEARER_OBSTACLE";
    case Reason::EXTENDING:
      return "EXTENDING";
    case Reason::GOAL_RUNNING:
      return "GOAL_RUNNING";
    case Reason::BACKING_OFF:
      return "BACKING_OFF";
    case Reason::NO_ODOMETRY:
      return "NO_ODOMETRY";
    case Reason::CREEPING:
      return "CREEPING";
  }
  return "?";
}

const char* toString(Command command)
{
  switch (command)
  {
    case Command::NONE:
      return "NONE";
    case Command::STOP:
      return "STOP";
    case Command::DRIVE:
      return "DRIVE";
    case Command::TURN:
      return "TURN";
  }
  return "?";
}

FrameSummary summarize(const VolumeResult& result, double stamp)
{
  FrameSummary f;
  f.stamp = stamp;
  f.nearest_obstacle = result.nearest_distance;
  f.free_distance = result.free_distance;
  f.coverage = result.coverage;
  f.left_free = result.left_free;
  f.right_free = result.right_free;
  f.open_distance = result.free_distance;
  return f;
}

namespace
{
constexpr std::size_t kTextCapacity = 320;
/// After the driver failed a goal (or stopped it on a hazard), wait this long before the next one (s).
constexpr double kFailureHold = 1.0;
}  // namespace

DecisionMaker::DecisionMaker(const DecisionParams& params)
{
  decision_.text.reserve(kTextCapacity);
  cycle_text_.reserve(kTextCapacity);
  end_text_.reserve(kTextCapacity);
  setParams(params);
  reset();
}

void DecisionMaker::setParams(const DecisionParams& params)
{
  params.validate();
  params_ = params;
}

void DecisionMaker::reset()
{
  decision_.state = State::STALE;
  decision_.reason = Reason::NO_DATA;
  decision_.command = Command::STOP;
  decision_.text.assign("no cloud received yet");
  frame_ = FrameSummary();
  has_frame_ = false;
  motion_end_ = -std::numeric_limits<double>::infinity();
  end_time_ = std::numeric_limits<double>::quiet_NaN();
  goal_was_active_ = false;
  end_pending_ = false;
  end_text_.clear();
  phase_ = Phase::NONE;
  turns_done_ = 0;
  turn_dir_ = 1;
  backoffs_done_ = 0;
  backoff_sent_ = false;
  creeping_ = false;
}

void DecisionMaker::onFrame(const FrameSummary& frame)
{
  frame_ = frame;
  has_frame_ = true;
}

void DecisionMaker::onGoalEnded(GoalEnd end, double now, const std::string& what)
{
  motion_end_ = std::max(motion_end_, now);
  end_time_ = motion_end_;
  goal_was_active_ = false;
  end_kind_ = end;
  end_pending_ = true;
  end_text_.assign(what, 0, kTextCapacity - 1);
}

void DecisionMaker::set(State state, Reason reason, Command command)
{
  decision_.state = state;
  decision_.reason = reason;
  decision_.command = command;
}

void DecisionMaker::setText(const char* format, ...)
{
  char buffer[kTextCapacity];
  va_list args;
  va_start(args, format);
  std::vsnprintf(buffer, sizeof(buffer), format, args);
  va_end(args);
  decision_.text.assign(buffer);
}

double DecisionMaker::speedForFree(double free) const
{
  const double span = params_.slow_distance - params_.safety_margin;
  const double stop_distance = free - params_.safety_margin;
  const double fraction = std::min(1.0, std::max(0.0, stop_distance / span));
  const double ramp = params_.min_speed + (params_.max_speed - params_.min_speed) * fraction;
  if (params_.deceleration <= 0.0)
  {
    return ramp;
  }
  // Stop within the free distance at the driver's deceleration: v <= sqrt(2 a d).
  return std::min(ramp, std::sqrt(2.0 * params_.deceleration * std::max(0.0, stop_distance)));
}

double DecisionMaker::coverageFactor(double coverage) const
{
  if (coverage >= params_.full_speed_coverage)
  {
    return 1.0;
  }
  const double span = params_.full_speed_coverage - params_.min_coverage;
  if (span <= 0.0)
  {
    return coverage >= params_.min_coverage ? 1.0 : 0.0;
  }
  return std::min(1.0, std::max(0.0, (coverage - params_.min_coverage) / span));
}

DecisionMaker::Assessment DecisionMaker::assess(const FrameSummary& f) const
{
  Assessment a;
  if (f.nearest_obstacle - params_.safety_margin < params_.min_goal_distance)
  {
    a.kind = Assessment::OBSTACLE;
    a.reason = Reason::OBSTACLE;
    return a;
  }
  if (!f.from_map && f.coverage < params_.min_coverage)
  {
    a.kind = Assessment::LOW_COVERAGE;
    a.reason = Reason::LOW_COVERAGE;
    return a;
  }
  const double distance = f.free_distance - params_.safety_margin;
  if (!(distance >= params_.min_goal_distance))
  {
    const double open = f.open_distance - params_.safety_margin;
    if (f.from_map && params_.creep_speed > 0.0 && f.view_seen && open >= params_.min_goal_distance)
    {
      // Only cells never seen to hold anything lie ahead, and the camera sees at the margin: the
      // ring around the body it cannot see. Creep into it; the bumper is the last line.
      a.kind = Assessment::DRIVE;
      a.creep = true;
      a.distance = open;
      a.speed = std::min(params_.creep_speed, speedForFree(f.open_distance));
      a.reason = Reason::CREEPING;
      return a;
    }
    a.kind = Assessment::UNKNOWN_AHEAD;
    a.reason = Reason::UNKNOWN_AHEAD;
    return a;
  }
  const double by_distance = speedForFree(f.free_distance);
  const double factor = f.from_map ? 1.0 : coverageFactor(f.coverage);
  a.kind = Assessment::DRIVE;
  a.distance = distance;
  a.speed = params_.min_speed + (by_distance - params_.min_speed) * factor;
  if (a.speed >= params_.max_speed - 1e-9)
  {
    a.reason = Reason::PATH_FREE;
  }
  else if (factor < 1.0)
  {
    a.reason = Reason::PARTIAL_COVERAGE;
  }
  else
  {
    a.reason = Reason::SHORT_FREE_DISTANCE;
  }
  return a;
}

void DecisionMaker::describe(const Assessment& a, const FrameSummary& f)
{
  switch (a.kind)
  {
    case Assessment::OBSTACLE:
      setText("obstacle at %.3f m, closer than safety_margin %.3f m + min_goal_distance %.3f m", f.nearest_obstacle,
              params_.safety_margin, params_.min_goal_distance);
      break;
    case Assessment::LOW_COVERAGE:
      setText("coverage %.2f below min_coverage %.2f: the space ahead is unknown", f.coverage, params_.min_coverage);
      break;
    case Assessment::UNKNOWN_AHEAD:
      setText("box measured free only to %.3f m (safety_margin %.3f m, nearest obstacle %.3f m): beyond is unknown",
              f.free_distance, params_.safety_margin, f.nearest_obstacle);
      break;
    case Assessment::DRIVE:
      if (a.creep)
      {
        setText(
            "known free only to %.3f m, never-seen cells to %.3f m, the view at the margin known: creeping goal "
            "%.3f m at %.3f m/s",
            f.free_distance, f.open_distance, a.distance, a.speed);
      }
      else if (a.reason == Reason::PATH_FREE)
      {
        setText("path free for %.3f m: goal %.3f m at %.3f m/s", f.free_distance, a.distance, a.speed);
      }
      else if (a.reason == Reason::PARTIAL_COVERAGE)
      {
        setText("coverage %.2f below full_speed_coverage %.2f (free %.3f m): goal %.3f m at %.3f m/s", f.coverage,
                params_.full_speed_coverage, f.free_distance, a.distance, a.speed);
      }
      else
      {
        setText("free distance %.3f m below slow_distance %.3f m: goal %.3f m at %.3f m/s", f.free_distance,
                params_.slow_distance, a.distance, a.speed);
      }
      break;
  }
}

void DecisionMaker::drive(const Assessment& a, const FrameSummary& f)
{
  set(a.speed >= params_.max_speed - 1e-9 ? State::DRIVING : State::SLOWING, a.reason, Command::DRIVE);
  decision_.distance = a.distance;
  decision_.speed = a.speed;
  creeping_ = a.creep;
  describe(a, f);
}

void DecisionMaker::stopHere(double now)
{
  motion_end_ = std::max(motion_end_, now);
}

void DecisionMaker::startCycle(double now, Reason reason, const char* why)
{
  phase_ = Phase::SETTLE;
  phase_start_ = now;
  turns_done_ = 0;
  cycle_reason_ = reason;
  start_reason_ = reason;
  cycle_text_.assign(why);
  // Toward the freer side (from a map: the side of the freest heading); on a tie keep the previous
  // direction.
  const double difference =
      frame_.from_map && frame_.best_turn != 0.0 ? frame_.best_turn : frame_.left_free - frame_.right_free;
  if (difference > 0.01)
  {
    turn_dir_ = 1;
  }
  else if (difference < -0.01)
  {
    turn_dir_ = -1;
  }
  stopHere(now);
}

void DecisionMaker::startTurn(double now)
{
  phase_ = Phase::TURN;
  phase_start_ = now;
  turn_end_ = now + params_.turn_angle / params_.turn_speed;
}

void DecisionMaker::stepCycle(double now, const MotionState& motion)
{
  const char* side = turn_dir_ > 0 ? "left" : "right";
  decision_.blocked = true;
  if (phase_ == Phase::SETTLE)
  {
    // Blocked only by what was not known yet (the very first cloud comes before its rays are in the
    // map): a cloud taken since may show a way, a creep included, before any turn. No turn before
    // that cloud came (however late under load): the heading it shows is never looked at again
    // otherwise. Clouds that stop coming end the wait as stale data.
    const bool fresh = frame_.stamp > phase_start_;
    if (cycle_reason_ == Reason::UNKNOWN_AHEAD && fresh)
    {
      const Assessment a = assess(frame_);
      if (a.kind == Assessment::DRIVE)
      {
        phase_ = Phase::NONE;
        decision_.blocked = false;
        drive(a, frame_);
        return;
      }
    }
    if (now - phase_start_ < params_.settle_time || (cycle_reason_ == Reason::UNKNOWN_AHEAD && !fresh))
    {
      set(State::BLOCKED, cycle_reason_, Command::STOP);
      setText("%s; stopped, turning %s next", cycle_text_.c_str(), side);
      return;
    }
    startTurn(now);
  }
  if (phase_ == Phase::TURN)
  {
    if (now < turn_end_)
    {
      set(State::TURNING, Reason::TURNING, Command::TURN);
      decision_.angular_speed = turn_dir_ * params_.turn_speed;
      setText("turning %s, step %d of %d (%s)", side, turns_done_ + 1, params_.max_turns, cycle_text_.c_str());
      return;
    }
    ++turns_done_;
    phase_ = Phase::LOOK;
    look_after_ = now + params_.settle_time;
    stopHere(now);
  }
  if ((phase_ == Phase::ALIGN || phase_ == Phase::BACKOFF) && stepBackoff(now, motion))
  {
    return;
  }
  if (phase_ == Phase::LOOK)
  {
    if (frame_.stamp < look_after_)
    {
      set(State::BLOCKED, Reason::LOOKING, Command::STOP);
      setText("turn %d of %d done, waiting for a fresh cloud", turns_done_, params_.max_turns);
      return;
    }
    const Assessment a = assess(frame_);
    if (a.kind == Assessment::DRIVE)
    {
      phase_ = Phase::NONE;
      backoffs_done_ = 0;
      decision_.blocked = false;
      drive(a, frame_);
      return;
    }
    describe(a, frame_);
    cycle_reason_ = a.reason;
    cycle_text_.assign(decision_.text);
    if (turns_done_ < params_.max_turns)
    {
      if (frame_.from_map && start_reason_ == Reason::UNKNOWN_AHEAD && turns_done_ <= 2)
      {
        // Blocked by what was never seen, and one side looked at in vain: back to the first heading
        // (its rays may have reached the map only after the first look, e.g. before odometry came),
        // then on to its other side, before choosing where to go.
        if (turns_done_ == 1)
        {
          turn_dir_ = -turn_dir_;
        }
      }
      else if (frame_.from_map && frame_.best_turn != 0.0 &&
               frame_.best_turn_free - params_.safety_margin >= params_.min_goal_distance)
      {
        turn_dir_ = frame_.best_turn > 0.0 ? 1 : -1;  // the map knows a way: turn toward it
      }
      side = turn_dir_ > 0 ? "left" : "right";
      startTurn(now);
      set(State::TURNING, Reason::TURNING, Command::TURN);
      decision_.angular_speed = turn_dir_ * params_.turn_speed;
      setText("turning %s, step %d of %d (%s)", side, turns_done_ + 1, params_.max_turns, cycle_text_.c_str());
      return;
    }
    if (startBackoff(now) && stepBackoff(now, motion))
    {
      return;
    }
    phase_ = Phase::GAVE_UP;
  }
  // GAVE_UP: stay stopped until a cloud shows a way forward.
  const Assessment a = assess(frame_);
  if (a.kind == Assessment::DRIVE && frame_.stamp >= motion_end_)
  {
    phase_ = Phase::NONE;
    decision_.blocked = false;
    drive(a, frame_);
    return;
  }
  if (a.kind != Assessment::DRIVE)
  {
    describe(a, frame_);
    cycle_text_.assign(decision_.text);
  }
  set(State::STOPPED, Reason::NO_FREE_DIRECTION, Command::STOP);
  setText("no free direction after %d turns and %d back-offs (%s)", turns_done_, backoffs_done_, cycle_text_.c_str());
}

bool DecisionMaker::startBackoff(double now)
{
  if (!frame_.from_map || backoffs_done_ >= params_.max_backoffs)
  {
    return false;
  }
  creeping_ = false;
  const double enough = params_.min_goal_distance;
  if (frame_.reverse_free >= enough)
  {
    phase_ = Phase::BACKOFF;
    backoff_sent_ = false;
    return true;
  }
  if (frame_.best_reverse_free >= enough && frame_.best_reverse_turn != 0.0)
  {
    // Turn in place (sweeps nothing new) until the trail lies straight behind, then back off.
    phase_ = Phase::ALIGN;
    phase_start_ = now;
    turn_dir_ = frame_.best_reverse_turn > 0.0 ? 1 : -1;
    turn_end_ = now + std::abs(frame_.best_reverse_turn) / params_.turn_speed;
    return true;
  }
  return false;
}

bool DecisionMaker::stepBackoff(double now, const MotionState& motion)
{
  decision_.blocked = true;
  if (phase_ == Phase::ALIGN)
  {
    if (now < turn_end_)
    {
      set(State::TURNING, Reason::BACKING_OFF, Command::TURN);
      decision_.angular_speed = turn_dir_ * params_.turn_speed;
      setText("turning %s to back off along free cells (back-off %d of %d)", turn_dir_ > 0 ? "left" : "right",
              backoffs_done_ + 1, params_.max_backoffs);
      return true;
    }
    stopHere(now);
    phase_ = Phase::BACKOFF;
    backoff_sent_ = false;
  }
  if (!backoff_sent_)
  {
    if (frame_.reverse_free < params_.min_goal_distance)
    {
      phase_ = Phase::GAVE_UP;  // the aligned heading's reverse path is not free after all
      return false;
    }
    backoff_sent_ = true;
    set(State::BACKING_OFF, Reason::BACKING_OFF, Command::DRIVE);
    decision_.distance = -std::min(params_.backoff_distance, frame_.reverse_free);
    decision_.speed = params_.backoff_speed;
    setText("no free heading: backing off %.3f m along free cells (back-off %d of %d)", -decision_.distance,
            backoffs_done_ + 1, params_.max_backoffs);
    return true;
  }
  if (motion.goal_active)
  {
    set(State::BACKING_OFF, Reason::BACKING_OFF, Command::NONE);
    setText("backing off: %.3f m to go (back-off %d of %d)", std::abs(motion.goal_remaining), backoffs_done_ + 1,
            params_.max_backoffs);
    return true;
  }
  // Back-off done: look again with a fresh set of turns.
  ++backoffs_done_;
  turns_done_ = 0;
  stopHere(now);
  phase_ = Phase::LOOK;
  look_after_ = now + params_.settle_time;
  set(State::BLOCKED, Reason::LOOKING, Command::STOP);
  setText("back-off %d of %d done, waiting for a fresh cloud", backoffs_done_, params_.max_backoffs);
  return true;
}

void DecisionMaker::stepRunningGoal(double now, const MotionState& motion)
{
  const double nearest = frame_.nearest_obstacle;
  const double limit = nearest - params_.safety_margin;
  const double remaining = motion.goal_remaining;
  if (limit < params_.min_goal_distance)
  {
    stopHere(now);
    set(State::BLOCKED, Reason::OBSTACLE, Command::STOP);
    decision_.blocked = true;
    setText("obstacle at %.3f m within safety_margin %.3f m + min_goal_distance %.3f m: stopping", nearest,
            params_.safety_margin, params_.min_goal_distance);
    return;
  }
  if (creeping_)
  {
    stepCreep(now, motion);
    return;
  }
  if (limit < remaining - params_.preempt_tolerance)
  {
    const double speed = speedForFree(nearest);
    set(speed >= params_.max_speed - 1e-9 ? State::DRIVING : State::SLOWING, Reason::NEARER_OBSTACLE, Command::DRIVE);
    decision_.distance = limit;
    decision_.speed = speed;
    setText("obstacle at %.3f m nearer than planned (%.3f m to go): new goal %.3f m at %.3f m/s", nearest, remaining,
            limit, speed);
    return;
  }
  const Assessment a = assess(frame_);
  if (a.kind == Assessment::DRIVE && a.distance > remaining + params_.replan_distance && frame_.stamp >= motion_end_)
  {
    drive(a, frame_);
    decision_.reason = Reason::EXTENDING;
    setText("more free space measured (%.3f m, %.3f m to go): new goal %.3f m at %.3f m/s", frame_.free_distance,
            remaining, a.distance, a.speed);
    return;
  }
  const double speed = speedForFree(std::min(nearest, remaining + params_.safety_margin));
  if (speed < motion.goal_speed - params_.speed_tolerance && remaining >= params_.min_goal_distance)
  {
    set(State::SLOWING, Reason::SHORT_FREE_DISTANCE, Command::DRIVE);
    decision_.distance = remaining;
    decision_.speed = speed;
    setText("free distance %.3f m below slow_distance %.3f m: %.3f m to go, slowing to %.3f m/s",
            std::min(nearest, remaining + params_.safety_margin), params_.slow_distance, remaining, speed);
    return;
  }
  set(motion.goal_speed >= params_.max_speed - 1e-9 ? State::DRIVING : State::SLOWING, Reason::GOAL_RUNNING,
      Command::NONE);
  setText("driving: %.3f m to go at %.3f m/s, nearest obstacle %.3f m, coverage %.2f", remaining, motion.goal_speed,
          nearest, frame_.coverage);
}

void DecisionMaker::stepCreep(double now, const MotionState& motion)
{
  const double remaining = motion.goal_remaining;
  const Assessment a = assess(frame_);
  if (a.kind != Assessment::DRIVE)
  {
    // The creep rule no longer holds (something seen ahead, or the view at the margin unknown).
    stopHere(now);
    describe(a, frame_);
    set(State::BLOCKED, a.reason, Command::STOP);
    decision_.blocked = true;
    return;
  }
  const bool shorter = a.creep && a.distance < remaining - params_.preempt_tolerance;
  const bool longer = a.distance > remaining + params_.replan_distance;
  if ((!a.creep || shorter || longer) && frame_.stamp >= motion_end_)
  {
    drive(a, frame_);  // known free now (full goal), or a new creep goal of the open travel
    return;
  }
  set(State::SLOWING, Reason::CREEPING, Command::NONE);
  setText("creeping: %.3f m to go at %.3f m/s over never-seen cells (known free %.3f m, open %.3f m)", remaining,
          motion.goal_speed, frame_.free_distance, frame_.open_distance);
}

void DecisionMaker::stepIdle(double now, const MotionState& motion)
{
  const Assessment a = assess(frame_);
  if (a.kind == Assessment::OBSTACLE || a.kind == Assessment::UNKNOWN_AHEAD)
  {
    // Valid even for a cloud taken before the robot stopped: it can only have come closer.
    describe(a, frame_);
    if (params_.max_turns > 0)
    {
      char why[kTextCapacity];
      std::snprintf(why, sizeof(why), "%s", decision_.text.c_str());
      startCycle(now, a.reason, why);
      stepCycle(now, motion);
      return;
    }
    set(State::BLOCKED, a.reason, Command::STOP);
    decision_.blocked = true;
    return;
  }
  const bool by_driver = end_time_ == motion_end_;
  const bool failed = by_driver && (end_kind_ == GoalEnd::FAILED || end_kind_ == GoalEnd::HAZARD);
  if (frame_.stamp < motion_end_ || (failed && now - end_time_ < kFailureHold))
  {
    if (by_driver && end_kind_ == GoalEnd::FAILED)
    {
      set(State::STOPPED, Reason::DRIVER_FAILED, Command::STOP);
      setText("driver ended the goal: %s; waiting before the next goal", end_text_.c_str());
    }
    else if (by_driver && end_kind_ == GoalEnd::HAZARD)
    {
      set(State::STOPPED, Reason::DRIVER_HAZARD, Command::STOP);
      setText("driver stopped: %s; waiting before the next goal", end_text_.c_str());
    }
    else
    {
      set(State::STOPPED, Reason::WAITING_FOR_FRAME, Command::STOP);
      setText("robot stopped, waiting for a cloud taken after the stop");
    }
    return;
  }
  if (a.kind == Assessment::LOW_COVERAGE)
  {
    set(State::STOPPED, Reason::LOW_COVERAGE, Command::STOP);
    describe(a, frame_);
    return;
  }
  drive(a, frame_);
}

const Decision& DecisionMaker::step(double now, const MotionState& motion)
{
  decision_.command = Command::NONE;
  decision_.distance = 0.0;
  decision_.speed = 0.0;
  decision_.angular_speed = 0.0;
  decision_.blocked = false;

  if (goal_was_active_ && !motion.goal_active)
  {
    stopHere(now);  // the goal ended without onGoalEnded()
  }
  decide(now, motion);
  // A goal runs after this step if one was sent now, or one runs and is left alone.
  goal_was_active_ = decision_.command == Command::DRIVE || (motion.goal_active && decision_.command == Command::NONE);
  return decision_;
}

void DecisionMaker::decide(double now, const MotionState& motion)
{
  if (!params_.enabled)
  {
    phase_ = Phase::NONE;
    if (motion.goal_active)
    {
      stopHere(now);
    }
    set(State::STOPPED, Reason::DISABLED, Command::STOP);
    setText("disabled (parameter enabled is false)");
    return;
  }
  if (!has_frame_)
  {
    phase_ = Phase::NONE;
    set(State::STALE, Reason::NO_DATA, Command::STOP);
    setText("no cloud received yet");
    return;
  }
  const double age = now - frame_.stamp;
  if (age > params_.stale_timeout)
  {
    phase_ = Phase::NONE;
    if (motion.goal_active)
    {
      stopHere(now);
    }
    set(State::STALE, Reason::STALE_DATA, Command::STOP);
    setText("no cloud for %.2f s (stale_timeout %.2f s)", age, params_.stale_timeout);
    return;
  }
  if (!motion.driver_ready)
  {
    phase_ = Phase::NONE;
    set(State::STOPPED, Reason::DRIVER_UNAVAILABLE, Command::STOP);
    setText("driver not ready%s%s%s", motion.driver_detail[0] != '\0' ? " (" : "", motion.driver_detail,
            motion.driver_detail[0] != '\0' ? ")" : "");
    return;
  }
  if (end_pending_)
  {
    end_pending_ = false;
    if (end_kind_ == GoalEnd::HAZARD && params_.max_turns > 0 && phase_ == Phase::NONE)
    {
      char why[kTextCapacity];
      std::snprintf(why, sizeof(why), "driver stopped: %s", end_text_.c_str());
      startCycle(now, Reason::DRIVER_HAZARD, why);
    }
  }
  if (frame_.from_map && !motion.localized)
  {
    phase_ = Phase::NONE;
    if (motion.goal_active)
    {
      stopHere(now);
    }
    set(State::STOPPED, Reason::NO_ODOMETRY, Command::STOP);
    setText("robot pose unknown%s%s%s: the map cannot be used", motion.localization_detail[0] != '\0' ? " (" : "",
            motion.localization_detail, motion.localization_detail[0] != '\0' ? ")" : "");
    return;
  }
  if (phase_ != Phase::NONE)
  {
    stepCycle(now, motion);
    return;
  }
  if (motion.goal_active)
  {
    stepRunningGoal(now, motion);
    return;
  }
  stepIdle(now, motion);
}
}  // namespace sl_obstacle
