/// @file supervisor.h
/// @brief The obstacle node's arbitration without ROS: what each input (cloud, ray cloud, command,
/// goal result, bump, control tick) makes the robot do. Times are seconds on the caller's clock.
#pragma once

#include <any>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "sl_obstacle/cloud_pairing.h"
#include "sl_obstacle/decision_maker.h"
#include "sl_obstacle/point.h"
#include "sl_obstacle/safety_filter.h"
#include "sl_obstacle/settings.h"
#include "sl_obstacle/teleop_arbiter.h"
#include "sl_obstacle/velocity_goal.h"
#include "sl_obstacle/volume_checker.h"
#include "sl_obstacle/world_model.h"

namespace sl_obstacle
{
/// How motion is commanded.
enum class CommandMode
{
  ACTION,   ///< forward motion as drive goals (the driver's drive_distance action); turns as twists
  CMD_VEL,  ///< twists only (forward goals run open loop: VelocityGoal)
  FILTER    ///< no autonomy: the outside commands pass through the safety filter (needs the map)
};

/// The mode's parameter value: "action", "cmd_vel" or "filter".
const char* toString(CommandMode mode);

/// The caller's handle of a cloud (e.g. a message pointer): the supervisor only hands it back.
using CloudHandle = std::any;

/// Ray ends to insert into the map now, with the points of the same image when they came.
using RayInsert = CloudPairing<CloudHandle, double>::Insert;

/// @brief What the supervisor asks the caller when it needs it (the nodelet answers from tf and
/// from its connections).
class SupervisorSource
{
public:
  virtual ~SupervisorSource() = default;
  /// The robot's newest pose in the map frame and its stamp (s); false when there is none.
  virtual bool robotPose(Pose2D& pose, double& stamp) = 0;
  /// The pose of the working-volume frame in the map frame at the capture time of @p cloud (a
  /// handle given to Supervisor::onPoints); false with @p error when it is not known (yet).
  virtual bool volumePose(const CloudHandle& cloud, Pose2D& pose, std::string& error) = 0;
  /// True when the motion interface takes commands (action server connected, twists subscribed).
  virtual bool driverReady() = 0;
};

/// One thing to send to the robot.
struct Output
{
  enum class Kind
  {
    CANCEL_GOAL,  ///< cancel the running drive goal
    TWIST,        ///< publish #twist
    GOAL,         ///< send the drive goal #goal_id (#distance m at #speed m/s), replacing a running one
    HEARTBEAT     ///< the running goal's decisions go on (the driver stops without them)
  };
  explicit Output(Kind k = Kind::TWIST) : kind(k) {}
  Kind kind;
  Velocity twist;         ///< TWIST
  unsigned goal_id = 0;   ///< GOAL: given back to onGoalResult() / onGoalFeedback()
  double distance = 0.0;  ///< GOAL: m, negative backwards
  double speed = 0.0;     ///< GOAL: m/s
};

/// Something worth a log line.
struct Event
{
  enum class Kind
  {
    TAKEOVER,           ///< an outside command took over from autonomy
    RESUMED,            ///< outside commands stopped for teleop_hold: autonomy resumes
    OBSTACLES_DROPPED,  ///< the cloud's obstacle points never got a pose: the filter uses the map only
    GOAL_FAILED         ///< the driver failed a goal
  };
  Kind kind = Kind::TAKEOVER;
  std::string text;  ///< a sentence with the numbers
};

/// Which status to publish after the outputs.
enum class StatusKind
{
  NONE,      ///< none (an input that decided nothing)
  DECISION,  ///< the decision maker's last decision (Supervisor::decisions().last())
  FILTER     ///< the last safety-filter step (Supervisor::filterOutput(), command())
};

/// What the caller carries out after a call, in this order: outputs, events, status.
struct Actions
{
  std::vector<Output> outputs;
  std::vector<Event> events;
  StatusKind status = StatusKind::NONE;
};

/**
 * @brief Arbitrates the obstacle node: runs the volume check, the decision maker, the local map
 * (WorldModel) and the safety filter on stamped inputs and returns what to send.
 *
 * - A cloud (points in the working-volume frame) is checked (onPoints()) and decided on (step());
 *   its ray ends go into the map after that, paired with it by stamp (CloudPairing: the caller asks
 *   pairPoints() / pairRays() which clouds to insert, converts them and gives them to addRays(),
 *   then decides on the new map with step(now, true)).
 * - With the map, outside commands (onCommand()) take over from autonomy for teleop_hold after each
 *   (always in CommandMode::FILTER) and pass through the safety filter, together with the newest
 *   cloud's obstacle points carried into the map frame and then into the robot's frame now.
 * - Drive goals are numbered: a result or feedback of a goal that was replaced or cancelled is
 *   ignored; in CommandMode::CMD_VEL they run open loop (VelocityGoal).
 * Every decision step asks the source for the robot's pose (with the map; older than stale_timeout
 * counts as unknown).
 */
class Supervisor
{
public:
  /// @throws std::invalid_argument on invalid @p settings. @p source must outlive the supervisor.
  Supervisor(const Settings& settings, CommandMode mode, SupervisorSource& source);

  /// Replaces the settings (already validated); @p new_map: the map starts empty, else it keeps its
  /// cells and takes the new clearance. The safety filter takes the new parameters.
  void setSettings(const Settings& settings, bool new_map);

  /// Checks a cloud of @p points (working-volume frame) captured at @p stamp; @p cloud is handed back
  /// to SupervisorSource::volumePose(). A gap longer than stale_timeout restarts the noise filter's
  /// history. Decide on it with step() right after (its time read after the check).
  void onPoints(const std::vector<Point>& points, const CloudHandle& cloud, double stamp);
  /// After onPoints(): the waiting ray ends of this or an older image to insert now, if any.
  std::optional<RayInsert> pairPoints(const CloudHandle& points, double stamp);
  /// New ray ends captured at @p stamp: those to insert now, in order (older ray ends whose points
  /// never came go alone; these wait when their points have not come yet).
  std::vector<RayInsert> pairRays(const CloudHandle& rays, double stamp);
  /// Inserts one image's @p rays (map frame) captured at @p stamp; decide on the new map with
  /// step(now, true) right after (no map: ignored).
  void addRays(const std::vector<MapRay>& rays, double stamp);

  /// An outside command given at @p stamp (<= @p now). Takes over from autonomy (cancels its goal).
  Actions onCommand(const Velocity& command, double stamp, double now);
  /// The driver ended goal @p goal_id with @p end (@p what: a short text); ignored for a goal that
  /// was replaced or cancelled (then nothing is to be done).
  Actions onGoalResult(unsigned goal_id, GoalEnd end, const std::string& what, double now);
  /// The driver's remaining distance (m) of goal @p goal_id.
  void onGoalFeedback(unsigned goal_id, double remaining);
  /// The bumper state at @p now. @return true when a new press was marked in the map (localized).
  bool onBumpers(bool left, bool right, double now);
  /// A decision step at @p now: after a cloud, after a map update (@p map_updated: the candidate
  /// turns are swept again) and at a steady rate (keeps goals and watchdogs fed).
  Actions step(double now, bool map_updated = false);

  /// The volume check of the newest cloud.
  const VolumeResult& volumeResult() const { return checker_.result(); }
  /// The decision maker (its last decision and frame).
  const DecisionMaker& decisions() const { return decider_; }
  /// The world model; null without the map.
  const WorldModel* world() const { return world_ ? &*world_ : nullptr; }
  /// The last safety-filter step.
  const FilterOutput& filterOutput() const { return filter_out_; }
  /// The newest outside command.
  const Velocity& command() const { return command_; }
  /// True once a cloud came.
  bool haveFrame() const { return have_frame_; }
  /// True while the robot's pose is known (map only), then pose().
  bool localized() const { return localized_; }
  /// The robot's pose in the map frame at the last decision step.
  const Pose2D& pose() const { return pose_; }
  /// True while outside commands command the robot (as of the last step).
  bool teleopActive() const { return teleop_.active(); }
  /// True when the way ahead is blocked: the filter stopped for an obstacle, or the decision says so.
  bool blocked() const;

private:
  void decide(double now, bool map_updated, Actions& a);
  bool updatePose(double now);
  bool updateTeleop(double now, Actions& a);
  void filterStep(double now, Actions& a);
  void resolveObstacles(double now, Actions& a);
  MotionState motion();
  void execute(const Decision& d, double now, Actions& a);
  void sendGoal(double distance, double speed, Actions& a);
  void cancelGoal(Actions& a);
  void twist(double linear, double angular, Actions& a);

  Settings settings_;
  CommandMode mode_;
  SupervisorSource& source_;
  VolumeChecker checker_;
  DecisionMaker decider_;
  std::optional<WorldModel> world_;     // without ~use_map: none
  std::optional<SafetyFilter> filter_;  // with the map
  VelocityGoal velocity_goal_;
  TeleopArbiter teleop_;
  CloudPairing<CloudHandle, double> pairing_;

  bool have_frame_ = false;
  double cloud_stamp_ = 0.0;
  double cloud_contact_ = 0.0;  // the newest cloud's obstacle: travel until the disc touches it
  Pose2D pose_;
  bool localized_ = false;
  const char* localization_detail_ = "no odometry yet";
  bool bumped_ = false;
  bool moving_ = false;  // the last twist was not zero

  bool goal_active_ = false;
  double goal_remaining_ = 0.0;
  double goal_speed_ = 0.0;
  unsigned goal_seq_ = 0;

  Velocity command_;
  double command_time_ = -std::numeric_limits<double>::infinity();  // none yet
  std::vector<Point2> obstacles_edge_;  // the newest cloud's obstacle points, working-volume frame
  CloudHandle obstacles_cloud_;
  double obstacles_stamp_ = 0.0;
  bool obstacles_pending_ = false;       // not yet in the map frame (no pose at the stamp yet)
  std::vector<Point2> obstacles_odom_;   // the newest resolved cloud's obstacle points, map frame
  std::vector<Point2> obstacles_robot_;  // ... in the robot's frame now
  FilterOutput filter_out_;
};
}  // namespace sl_obstacle
