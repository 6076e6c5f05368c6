// Supervisor: teleop takeover and release, pairing of ray ends with points, goal bookkeeping,
// stale inputs, on stamped inputs with a fake source of poses.
#include <gtest/gtest.h>

#include <any>
#include <string>
#include <vector>

#include "sl_obstacle/supervisor.h"
#include "synthetic_clouds.h"

namespace sl_obstacle
{
namespace
{
/// Poses and driver state as a test sets them; counts the questions.
class FakeSource : public SupervisorSource
{
public:
  bool odometry = true;
  Pose2D robot;
  double robot_stamp = 0.0;  ///< s; the tests keep it fresh by setting it to now
  bool volume_known = true;
  Pose2D volume;  ///< the working-volume frame in the map frame
  std::vector<int> volume_asked;
  bool ready = true;

  bool robotPose(Pose2D& pose, double& stamp) override
  {
    pose = robot;
    stamp = robot_stamp;
    return odometry;
  }
  bool volumePose(const CloudHandle& cloud, Pose2D& pose, std::string& error) override
  {
    volume_asked.push_back(std::any_cast<int>(cloud));
    pose = volume;
    error = "no transform yet";
    return volume_known;
  }
  bool driverReady() override { return ready; }
};

Settings noMap()
{
  Settings s;
  s.world.enabled = false;
  s.decision.max_turns = 0;
  return s;
}

std::vector<const Output*> outputs(const Actions& a, Output::Kind kind)
{
  std::vector<const Output*> out;
  for (const Output& o : a.outputs)
  {
    if (o.kind == kind)
      out.push_back(&o);
  }
  return out;
}

bool hasEvent(const Actions& a, Event::Kind kind)
{
  for (const Event& e : a.events)
  {
    if (e.kind == kind)
      return true;
  }
  return false;
}

/// A cloud captured at @p stamp (handle @p id), checked and decided on at @p now.
Actions checkCloud(Supervisor& sup, const std::vector<Point>& points, int id, double stamp, double now)
{
  sup.onPoints(points, id, stamp);
  return sup.step(now);
}

/// Clouds of a wall at @p x (m ahead of the front edge), one every 0.1 s from @p now on; @return the
/// outputs and events of all, the status of the last.
Actions wall(Supervisor& sup, double x, double& now, int frames = 3)
{
  const std::vector<Point> cloud = test::render(test::Scene().wall(x));
  Actions all;
  for (int i = 0; i < frames; ++i)
  {
    now += 0.1;
    const Actions a = checkCloud(sup, cloud, 0, now, now + 0.01);
    all.outputs.insert(all.outputs.end(), a.outputs.begin(), a.outputs.end());
    all.events.insert(all.events.end(), a.events.begin(), a.events.end());
    all.status = a.status;
  }
  return all;
}

/// Horizontal free rays through both height slices of a corridor 1 m wide along +x: the map knows
/// it free.
std::vector<MapRay> freeCorridor()
{
  std::vector<MapRay> rays;
  for (double y = -0.5; y <= 0.5; y += 0.01)
  {
    for (const float z : { 0.05F, 0.13F })
    {
      rays.push_back(MapRay{ -0.4F, static_cast<float>(y), z, 2.5F, static_cast<float>(y), z, RayKind::Free });
    }
  }
  return rays;
}

TEST(Supervisor, AGoalIsSentWithItsIdAndKeptAliveByHeartbeats)
{
  FakeSource source;
  Supervisor sup(noMap(), CommandMode::ACTION, source);
  double now = 100.0;
  const Actions a = wall(sup, 0.95, now);
  const auto goals = outputs(a, Output::Kind::GOAL);
  ASSERT_EQ(goals.size(), 1U) << sup.decisions().last().text;
  EXPECT_EQ(goals[0]->goal_id, 1U);
  EXPECT_NEAR(goals[0]->distance, 0.8 - 0.15, 1e-6);
  EXPECT_EQ(a.outputs.back().kind, Output::Kind::HEARTBEAT) << "after the goal, each step";
  EXPECT_EQ(a.status, StatusKind::DECISION);
  EXPECT_EQ(outputs(sup.step(now + 0.05), Output::Kind::HEARTBEAT).size(), 1U) << "every step while it runs";
}

TEST(Supervisor, FeedbackOfTheRunningGoalDecidesOnPreemption)
{
  // Goal 1: 0.65 m. A nearer wall leaves 0.35 m at a lower speed.
  for (const unsigned feedback_id : { 0U, 1U, 7U })
  {
    FakeSource source;
    Supervisor sup(noMap(), CommandMode::ACTION, source);
    double now = 100.0;
    wall(sup, 0.95, now);
    if (feedback_id != 0U)
      sup.onGoalFeedback(feedback_id, 0.3);  // goal 7 does not exist: ignored
    const Actions a = wall(sup, 0.5, now);
    // With 0.3 m to go the goal is only re-sent slower (its remaining distance), else it is cut to 0.35 m.
    const auto goals = outputs(a, Output::Kind::GOAL);
    ASSERT_EQ(goals.size(), 1U) << "feedback from goal " << feedback_id << ": " << sup.decisions().last().text;
    EXPECT_EQ(goals[0]->goal_id, 2U);
    EXPECT_NEAR(goals[0]->distance, feedback_id == 1U ? 0.30 : 0.35, 0.01) << "feedback from goal " << feedback_id;
  }
}

TEST(Supervisor, ResultsOfReplacedGoalsAreIgnoredAndTheCurrentOneEnds)
{
  FakeSource source;
  Supervisor sup(noMap(), CommandMode::ACTION, source);
  double now = 100.0;
  wall(sup, 0.95, now);
  sup.onGoalFeedback(1, 0.65);
  ASSERT_EQ(outputs(wall(sup, 0.5, now), Output::Kind::GOAL).size(), 1U) << "goal 2 replaces goal 1";
  const Actions old = sup.onGoalResult(1, GoalEnd::CANCELLED, "pre-empted", now + 0.02);
  EXPECT_TRUE(old.outputs.empty());
  EXPECT_EQ(old.status, StatusKind::NONE) << "nothing decided for a goal we replaced";

  const Actions failed = sup.onGoalResult(2, GoalEnd::FAILED, "timeout", now + 0.03);
  ASSERT_TRUE(hasEvent(failed, Event::Kind::GOAL_FAILED));
  EXPECT_NE(failed.events[0].text.find("timeout"), std::string::npos) << failed.events[0].text;
  EXPECT_EQ(failed.status, StatusKind::DECISION);
  EXPECT_EQ(sup.decisions().last().reason, Reason::DRIVER_FAILED) << sup.decisions().last().text;
  EXPECT_TRUE(outputs(failed, Output::Kind::HEARTBEAT).empty()) << "the goal is over";
  EXPECT_EQ(sup.onGoalResult(2, GoalEnd::REACHED, "reached", now + 0.04).status, StatusKind::NONE)
      << "a goal ends once";
}

TEST(Supervisor, AStopCancelsTheGoalAndItsLateResultIsIgnored)
{
  FakeSource source;
  Supervisor sup(noMap(), CommandMode::ACTION, source);
  double now = 100.0;
  wall(sup, 0.95, now);
  const Actions stop = wall(sup, 0.1, now);  // an obstacle within the margin
  EXPECT_EQ(outputs(stop, Output::Kind::CANCEL_GOAL).size(), 1U) << sup.decisions().last().text;
  EXPECT_EQ(stop.outputs.back().kind, Output::Kind::CANCEL_GOAL) << "no heartbeat after the goal ended";
  EXPECT_EQ(sup.onGoalResult(1, GoalEnd::CANCELLED, "pre-empted", now + 0.05).status, StatusKind::NONE);
}

TEST(Supervisor, OpenLoopGoalsAreTwistsUntilTheirDistanceIsDriven)
{
  FakeSource source;
  Supervisor sup(noMap(), CommandMode::CMD_VEL, source);
  double now = 100.0;
  const Actions a = wall(sup, 0.95, now);
  ASSERT_FALSE(outputs(a, Output::Kind::TWIST).empty()) << sup.decisions().last().text;
  const double v = outputs(a, Output::Kind::TWIST)[0]->twist.linear;
  EXPECT_GT(v, 0.0);
  for (const Output* o : outputs(a, Output::Kind::TWIST))
    EXPECT_DOUBLE_EQ(o->twist.linear, v) << "the same goal at each step";
  EXPECT_TRUE(outputs(a, Output::Kind::GOAL).empty());
  const Actions fed = sup.step(now + 0.1);
  ASSERT_EQ(outputs(fed, Output::Kind::TWIST).size(), 1U) << "the watchdog is fed while it runs";
  EXPECT_DOUBLE_EQ(outputs(fed, Output::Kind::TWIST)[0]->twist.linear, v);
}

TEST(Supervisor, StaleCloudsStopTheRobot)
{
  FakeSource source;
  Supervisor sup(noMap(), CommandMode::ACTION, source);
  double now = 100.0;
  wall(sup, 0.95, now);
  const Actions a = sup.step(now + 0.6);  // stale_timeout 0.5 s
  EXPECT_EQ(sup.decisions().last().state, State::STALE) << sup.decisions().last().text;
  EXPECT_EQ(outputs(a, Output::Kind::CANCEL_GOAL).size(), 1U);
}

TEST(Supervisor, StaleOdometryStopsMapDecisions)
{
  FakeSource source;
  Supervisor sup(Settings(), CommandMode::ACTION, source);
  double now = 100.0;
  source.robot_stamp = now;
  checkCloud(sup, {}, 0, now, now);
  EXPECT_TRUE(sup.localized());
  checkCloud(sup, {}, 0, now + 0.6, now + 0.6);
  EXPECT_FALSE(sup.localized()) << "odometry older than stale_timeout";
  EXPECT_EQ(sup.decisions().last().reason, Reason::NO_ODOMETRY) << sup.decisions().last().text;
  EXPECT_NE(sup.decisions().last().text.find("older than stale_timeout"), std::string::npos)
      << sup.decisions().last().text;
  source.odometry = false;
  source.robot_stamp = now + 0.7;
  checkCloud(sup, {}, 0, now + 0.7, now + 0.7);
  EXPECT_NE(sup.decisions().last().text.find("no transform"), std::string::npos) << sup.decisions().last().text;
}

/// A map with a free corridor ahead and a cloud without obstacles, at @p now: autonomy drives.
void driveOnMap(Supervisor& sup, FakeSource& source, double& now)
{
  for (int i = 0; i < 3; ++i)
  {
    now += 0.1;
    source.robot_stamp = now;
    checkCloud(sup, {}, i, now, now);
    sup.addRays(freeCorridor(), now);
    sup.step(now, true);
  }
}

TEST(Supervisor, ACommandTakesOverFromAutonomyAndHandsBackAfterTheHold)
{
  FakeSource source;
  Settings settings;
  settings.teleop_hold = 0.3;  // below input_timeout: the turn is still commanded when it ends
  Supervisor sup(settings, CommandMode::ACTION, source);
  double now = 100.0;
  driveOnMap(sup, source, now);
  ASSERT_EQ(sup.decisions().last().command, Command::NONE) << "a goal runs: " << sup.decisions().last().text;

  // A turn in place passes the filter: the goal is cancelled and the twist sent.
  const Actions take = sup.onCommand(Velocity{ 0.0, 0.5 }, now, now);
  EXPECT_TRUE(hasEvent(take, Event::Kind::TAKEOVER));
  ASSERT_GE(take.outputs.size(), 2U);
  EXPECT_EQ(take.outputs[0].kind, Output::Kind::CANCEL_GOAL) << "autonomy's goal first";
  const auto twists = outputs(take, Output::Kind::TWIST);
  ASSERT_EQ(twists.size(), 1U);
  EXPECT_DOUBLE_EQ(twists[0]->twist.angular, 0.5);
  EXPECT_EQ(take.status, StatusKind::FILTER);
  EXPECT_TRUE(sup.teleopActive());
  EXPECT_EQ(sup.filterOutput().reason, FilterReason::PASSED) << sup.filterOutput().text;
  EXPECT_FALSE(hasEvent(sup.onCommand(Velocity{ 0.0, 0.5 }, now + 0.2, now + 0.2), Event::Kind::TAKEOVER))
      << "one takeover";

  // teleop_hold after the last command autonomy resumes: the turn is stopped first.
  EXPECT_EQ(sup.step(now + 0.45).status, StatusKind::FILTER);
  const Actions back = sup.step(now + 0.5);
  EXPECT_TRUE(hasEvent(back, Event::Kind::RESUMED));
  ASSERT_FALSE(back.outputs.empty());
  EXPECT_EQ(back.outputs[0].kind, Output::Kind::TWIST);
  EXPECT_DOUBLE_EQ(back.outputs[0].twist.angular, 0.0);
  EXPECT_EQ(back.status, StatusKind::DECISION);
  EXPECT_FALSE(sup.teleopActive());
}

TEST(Supervisor, InFilterModeCommandsAlwaysGoThroughTheFilterAndTimeOut)
{
  FakeSource source;
  Supervisor sup(Settings(), CommandMode::FILTER, source);
  double now = 100.0;
  source.robot_stamp = now;
  const Actions a = sup.onCommand(Velocity{ 0.0, -0.4 }, now, now);
  EXPECT_FALSE(hasEvent(a, Event::Kind::TAKEOVER));
  ASSERT_EQ(outputs(a, Output::Kind::TWIST).size(), 1U);
  EXPECT_DOUBLE_EQ(outputs(a, Output::Kind::TWIST)[0]->twist.angular, -0.4);
  // No command within input_timeout (0.5 s): the robot stops, once.
  source.robot_stamp = now + 0.6;
  const Actions quiet = sup.step(now + 0.6);
  EXPECT_EQ(sup.filterOutput().reason, FilterReason::INPUT_TIMEOUT);
  ASSERT_EQ(outputs(quiet, Output::Kind::TWIST).size(), 1U);
  EXPECT_DOUBLE_EQ(outputs(quiet, Output::Kind::TWIST)[0]->twist.angular, 0.0);
  EXPECT_TRUE(outputs(sup.step(now + 0.7), Output::Kind::TWIST).empty()) << "a zero twist is sent once";
  EXPECT_EQ(sup.step(now + 100.0).status, StatusKind::FILTER) << "no autonomy ever";
}

TEST(Supervisor, CloudObstaclesReachTheFilterThroughTheVolumePoseAtTheirStamp)
{
  FakeSource source;
  Supervisor sup(Settings(), CommandMode::FILTER, source);
  double now = 100.0;
  source.robot_stamp = now;
  source.volume_known = false;
  checkCloud(sup, test::render(test::Scene().wall(0.3)), 42, now, now);
  EXPECT_EQ(source.volume_asked, std::vector<int>({ 42 })) << "the filter runs on each cloud";
  const Actions early = sup.onCommand(Velocity{ 0.1, 0.0 }, now + 0.1, now + 0.1);
  EXPECT_EQ(source.volume_asked, std::vector<int>({ 42, 42 }));
  EXPECT_FALSE(hasEvent(early, Event::Kind::OBSTACLES_DROPPED)) << "odometry may come later";
  source.volume_known = true;
  sup.onCommand(Velocity{ 0.1, 0.0 }, now + 0.2, now + 0.2);
  EXPECT_EQ(source.volume_asked.size(), 3U);
  sup.onCommand(Velocity{ 0.1, 0.0 }, now + 0.3, now + 0.3);
  EXPECT_EQ(source.volume_asked.size(), 3U) << "resolved once";

  // A cloud whose pose never comes: after stale_timeout the filter uses the map only.
  source.volume_known = false;
  checkCloud(sup, test::render(test::Scene().wall(0.3)), 43, now + 0.4, now + 0.4);
  source.robot_stamp = now + 0.8;
  EXPECT_FALSE(hasEvent(sup.onCommand(Velocity{ 0.1, 0.0 }, now + 0.8, now + 0.8), Event::Kind::OBSTACLES_DROPPED));
  source.robot_stamp = now + 1.0;
  const Actions dropped = sup.onCommand(Velocity{ 0.1, 0.0 }, now + 1.0, now + 1.0);
  ASSERT_TRUE(hasEvent(dropped, Event::Kind::OBSTACLES_DROPPED));
  EXPECT_NE(dropped.events[0].text.find("no transform yet"), std::string::npos) << dropped.events[0].text;
}

TEST(Supervisor, RayEndsPairWithThePointsOfTheirStamp)
{
  FakeSource source;
  Supervisor sup(Settings(), CommandMode::ACTION, source);
  // Points first: the ray ends of the same image go in at once with them.
  ASSERT_FALSE(sup.pairPoints(1, 10.0));
  std::vector<RayInsert> in = sup.pairRays(101, 10.0);
  ASSERT_EQ(in.size(), 1U);
  EXPECT_EQ(std::any_cast<int>(in[0].rays), 101);
  ASSERT_TRUE(in[0].points);
  EXPECT_EQ(std::any_cast<int>(*in[0].points), 1);

  // Ray ends first: they wait for their points.
  EXPECT_TRUE(sup.pairRays(102, 10.1).empty());
  const auto later = sup.pairPoints(2, 10.1);
  ASSERT_TRUE(later);
  EXPECT_EQ(std::any_cast<int>(later->rays), 102);
  ASSERT_TRUE(later->points);
  EXPECT_EQ(std::any_cast<int>(*later->points), 2);
}

TEST(Supervisor, UnmatchedCloudsArePairedWithNothing)
{
  FakeSource source;
  Supervisor sup(Settings(), CommandMode::ACTION, source);
  // Ray ends whose points never come go in alone when newer ray ends arrive.
  EXPECT_TRUE(sup.pairRays(101, 10.0).empty());
  const std::vector<RayInsert> in = sup.pairRays(102, 10.1);
  ASSERT_EQ(in.size(), 1U);
  EXPECT_EQ(std::any_cast<int>(in[0].rays), 101);
  EXPECT_FALSE(in[0].points);
  // Newer points release the waiting ray ends alone, not with themselves.
  const auto newer = sup.pairPoints(3, 10.2);
  ASSERT_TRUE(newer);
  EXPECT_EQ(std::any_cast<int>(newer->rays), 102);
  EXPECT_FALSE(newer->points);
  // Older points neither release nor pair newer ray ends.
  EXPECT_TRUE(sup.pairRays(103, 10.3).empty());
  EXPECT_FALSE(sup.pairPoints(4, 10.25));
}

TEST(Supervisor, DecisionsUseTheMapTheRaysBuild)
{
  FakeSource source;
  Supervisor sup(Settings(), CommandMode::ACTION, source);
  double now = 100.0;
  source.robot_stamp = now;
  checkCloud(sup, {}, 0, now, now);
  EXPECT_NE(sup.decisions().last().command, Command::DRIVE) << "nothing known ahead";
  double t = now;
  driveOnMap(sup, source, t);
  EXPECT_EQ(sup.world()->map().state(1.0, 0.0, 0.1), CellState::Free);
  EXPECT_GT(sup.decisions().frame().free_distance, 1.0) << sup.decisions().last().text;
}

TEST(Supervisor, ABumpIsMarkedOncePerPressWhenLocalized)
{
  FakeSource source;
  Supervisor sup(Settings(), CommandMode::ACTION, source);
  EXPECT_FALSE(sup.onBumpers(true, false, 100.0)) << "no pose yet";
  EXPECT_FALSE(sup.onBumpers(false, false, 100.0));
  source.robot_stamp = 100.0;
  sup.step(100.0);
  EXPECT_TRUE(sup.onBumpers(true, false, 100.1));
  EXPECT_FALSE(sup.onBumpers(true, true, 100.2)) << "the same press";
  EXPECT_FALSE(sup.onBumpers(false, false, 100.3));
  EXPECT_TRUE(sup.onBumpers(false, true, 100.4));
}
}  // namespace
}  // namespace sl_obstacle
