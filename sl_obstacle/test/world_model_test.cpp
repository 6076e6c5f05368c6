// Tests of WorldModel (the local map fed with the sensor's ray fan, the trail, bumps) and of the
// decisions taken on it: the blind zone after a turn is refused, open space is driven, a boxed-in
// robot backs off along its trail, turning in place needs nothing, the speed obeys v <= sqrt(2 a d).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include <sl_testing/errors.h>
#include "sl_obstacle/decision_maker.h"
#include "sl_obstacle/world_model.h"

namespace sl_obstacle
{
namespace
{
using sl_testing::validationError;

const double kInf = std::numeric_limits<double>::infinity();
constexpr double kEdge = 0.1675;  // base_link -> front edge

/// A wall: the vertical plane through (x, y) with outward normal along @p normal_yaw (facing the robot).
struct Wall
{
  double x, y, normal_yaw;
};

/**
 * The pattern's fan of 16 x 64 rays from a sensor on the robot at @p robot (camera 0.03 m behind the
 * edge, 0.09 m up, +-14 degrees across, -7..+10 degrees in elevation), as the decoder reports them:
 * rays that meet a wall before @p range are Hit rays from the sensor; the others are dark (Free)
 * from 0.25 m on to @p range, or floor rays (Free from the sensor) where they meet the floor first.
 */
std::vector<MapRay> fan(const Pose2D& robot, const std::vector<Wall>& walls, double range = 1.2)
{
  const double c = std::cos(robot.yaw);
  const double s = std::sin(robot.yaw);
  const double ox = robot.x + (kEdge - 0.03) * c;
  const double oy = robot.y + (kEdge - 0.03) * s;
  const double oz = 0.09;
  std::vector<MapRay> rays;
  for (int row = 0; row < 16; ++row)
  {
    const double el = (-7.0 + 17.0 * row / 15.0) * M_PI / 180.0;
    for (int col = 0; col < 64; ++col)
    {
      const double az = robot.yaw + (-14.0 + 28.0 * col / 63.0) * M_PI / 180.0;
      const double dx = std::cos(el) * std::cos(az);
      const double dy = std::cos(el) * std::sin(az);
      const double dz = std::sin(el);
      double t = range;
      RayKind kind = RayKind::Free;
      for (const Wall& w : walls)
      {
        const double nx = std::cos(w.normal_yaw);
        const double ny = std::sin(w.normal_yaw);
        const double den = dx * nx + dy * ny;
        if (den < -1e-6)
        {
          const double tw = ((w.x - ox) * nx + (w.y - oy) * ny) / den;
          if (tw > 0.0 && tw < t)
          {
            t = tw;
            kind = RayKind::Hit;
          }
        }
      }
      bool floor = false;
      if (dz < 0.0 && -oz / dz < t)
      {
        t = -oz / dz;
        kind = RayKind::Free;
        floor = true;
      }
      const double t0 = kind == RayKind::Hit || floor ? 0.0 : 0.25;
      if (t <= t0)
      {
        continue;
      }
      rays.push_back(MapRay{ static_cast<float>(ox + t0 * dx), static_cast<float>(oy + t0 * dy),
                             static_cast<float>(oz + t0 * dz), static_cast<float>(ox + t * dx),
                             static_cast<float>(oy + t * dy), static_cast<float>(oz + t * dz), kind });
    }
  }
  return rays;
}

/// Feeds clouds while the robot drives straight from @p from by @p distance in 2 cm steps.
void driveAndLook(WorldModel& world, Pose2D& robot, double distance, const std::vector<Wall>& walls, double& now)
{
  for (double d = 0.0; d <= distance + 1e-9; d += 0.02)
  {
    Pose2D p = robot;
    p.x += d * std::cos(robot.yaw);
    p.y += d * std::sin(robot.yaw);
    world.updatePose(p, now);
    world.addRays(fan(p, walls), now);
    now += 0.1;
  }
  robot.x += distance * std::cos(robot.yaw);
  robot.y += distance * std::sin(robot.yaw);
}

/// Looks around in place, by +-k turn steps of 0.5 rad, with a cloud every 0.1 rad while turning
/// (10 Hz at 0.5 rad/s).
void scan(WorldModel& world, const Pose2D& robot, const std::vector<Wall>& walls, double& now, int k = 6)
{
  for (int i = -5 * k; i <= 5 * k; ++i)
  {
    Pose2D p = robot;
    p.yaw += i * 0.1;
    world.updatePose(p, now);
    world.addRays(fan(p, walls), now);
    now += 0.1;
  }
  world.updatePose(robot, now);
}

WorldParams params()
{
  WorldParams p;
  p.map.decay = 600.0;  // no forgetting within a test
  return p;
}

/// Decisions on the map: @p safety_margin, at most @p max_turns, no settle time.
DecisionParams mapDecisionParams(double safety_margin, int max_turns)
{
  DecisionParams p;
  p.safety_margin = safety_margin;
  p.max_turns = max_turns;
  p.settle_time = 0.0;
  return p;
}

TEST(WorldModel, OpenSpaceIsDriven)
{
  WorldModel world(params());
  Pose2D robot;
  double now = 0.0;
  driveAndLook(world, robot, 0.0, {}, now);
  // Standing start: the narrow fan sees the middle of the path from 0.25 m on; nothing around the
  // body is taken as free (start_free_radius 0), so little is known free, and the path is open
  // (never-seen cells within blind_radius) only until the sides of the path beyond blind_radius,
  // which a look around would show.
  const MapSummary& start = world.summarize(robot, now);
  EXPECT_LT(start.free, 0.40);
  EXPECT_LT(start.open, 0.40);
  EXPECT_DOUBLE_EQ(start.reverse_free, 0.0) << "no trail behind the start";
  // A look around in place shows everything but the ring within blind_radius: the path is open to
  // the sensor's range (1.2 m from the camera), though still little of it is known free.
  scan(world, robot, {}, now);
  const MapSummary& looked = world.summarize(robot, now);
  EXPECT_LT(looked.free, 0.40);
  EXPECT_GT(looked.open, 1.0);
  EXPECT_LT(looked.open, 1.25);
  // Driving through it (the decisions creep there) opens the path.
  driveAndLook(world, robot, 0.6, {}, now);
  const MapSummary& t = world.summarize(robot, now);
  EXPECT_GT(t.free, 0.7) << "0.6 m of driving through a dark (empty) view must open the path";
  EXPECT_LT(t.free, 1.25) << "nothing beyond the sensor's range is known";
  EXPECT_EQ(t.obstacle, kInf);
  // Back along the trail: 0.6 m and up to a cell of its end cap, less the lateral margin.
  EXPECT_GE(t.reverse_free, 0.6 - 0.02 - 1e-9);
  EXPECT_LE(t.reverse_free, 0.6 + 0.02 - 0.02 + 1e-9);
}

TEST(WorldModel, WallAheadStopsAtItsDistance)
{
  WorldModel world(params());
  Pose2D robot;
  double now = 0.0;
  const std::vector<Wall> walls = { { 1.2, 0.0, M_PI } };  // world x = 1.2, facing the robot
  scan(world, robot, walls, now);
  driveAndLook(world, robot, 0.5, walls, now);
  const MapSummary& s = world.summarize(robot, now);
  const double expected = 1.2 - robot.x - kEdge;  // travel until the disc touches
  EXPECT_NEAR(s.obstacle, expected, 0.05);
  EXPECT_LE(s.free, s.obstacle);
  EXPECT_GT(s.free, expected - 0.06);
}

TEST(WorldModel, CandidateHeadingsAreSweptOnRequestAndReusedBriefly)
{
  // A wall ahead, open space to the sides: the candidate turns are swept with the map, then reused
  // by the decisions in between (for up to kTurnsMaxAge), while straight ahead is always swept anew.
  WorldParams wp = params();
  wp.start_free_radius = 0.45;  // so that the headings' known-free paths differ by what the scan saw
  WorldModel world(wp);
  Pose2D robot;
  double now = 0.0;
  scan(world, robot, { { 0.9, 0.0, M_PI } }, now);
  const double t0 = now;
  const MapSummary swept = world.summarize(robot, t0, true);
  ASSERT_GT(swept.best_turn_free, swept.free + 0.2) << "the wall blocks straight ahead: some turn is better";
  // Then walls close in on every side.
  scan(world, robot, { { 0.9, 0.0, M_PI }, { 0.0, 0.5, -M_PI / 2 }, { 0.0, -0.5, M_PI / 2 }, { -0.5, 0.0, 0.0 } }, now);
  const MapSummary reused = world.summarize(robot, t0 + 0.05, false);
  EXPECT_EQ(reused.best_turn, swept.best_turn);
  EXPECT_EQ(reused.best_turn_free, swept.best_turn_free);
  EXPECT_EQ(reused.left_free, swept.left_free);
  EXPECT_EQ(reused.right_free, swept.right_free);
  EXPECT_EQ(reused.best_reverse_free, swept.best_reverse_free);
  const MapSummary fresh = world.summarize(robot, t0 + 0.05, true);
  EXPECT_LT(fresh.best_turn_free, swept.best_turn_free - 0.2) << "the walls are nearer on every side";
  const MapSummary aged = world.summarize(robot, t0 + 0.05 + WorldModel::kTurnsMaxAge + 0.01, false);
  EXPECT_EQ(aged.best_turn_free, fresh.best_turn_free) << "turns older than kTurnsMaxAge are swept again";
  EXPECT_EQ(aged.left_free, fresh.left_free);
}

TEST(WorldModel, TurnIntoTheBlindZoneIsRefused)
{
  // The robot approaches a wall straight on and stops; a leg stands to its left, never in view.
  WorldModel world(params());
  Pose2D robot;
  double now = 0.0;
  const std::vector<Wall> walls = { { 1.0, 0.0, M_PI } };
  scan(world, robot, walls, now, 1);  // a look to the sides of the path only
  driveAndLook(world, robot, 0.43, walls, now);
  Pose2D turned = robot;
  turned.yaw = 60.0 * M_PI / 180.0;
  world.updatePose(turned, now);
  const MapSummary& s = world.summarize(turned, now);
  // 0.4 m of clearance must be known-free before any goal: the near field there was never seen.
  EXPECT_LT(s.free, 0.40 + 0.05) << "free " << s.free;
  EXPECT_LT(s.unknown, 0.45);
  // Turning in place sweeps no new space.
  EXPECT_GE(sweepStraight(world.map(), world.params().footprint, turned.x, turned.y, turned.yaw, 1, 0.0, now).free,
            0.0);
}

TEST(WorldModel, BoxedInBacksOffAlongTheTrail)
{
  WorldParams wp = params();
  wp.start_free_radius = 0.2;  // nothing known behind the start
  WorldModel world(wp);
  Pose2D robot;
  double now = 0.0;
  // A dead end: walls ahead and on both sides, close. The robot came 0.35 m into it: turning round
  // and driving out forward would need the trail plus the clearance, backing out needs the trail.
  const std::vector<Wall> walls = { { 0.9, 0.0, M_PI }, { 0.0, 0.30, -M_PI / 2 }, { 0.0, -0.30, M_PI / 2 } };
  scan(world, robot, walls, now, 1);
  driveAndLook(world, robot, 0.35, walls, now);
  const MapSummary& s = world.summarize(robot, now);
  EXPECT_LT(s.best_turn_free, 0.40 + 0.05) << "no heading may be free beyond the clearance";
  EXPECT_GT(s.reverse_free, 0.3) << "the trail behind is free";
  EXPECT_LE(s.reverse_free, 0.35) << "never beyond the start: the trail ends there";

  DecisionParams dp = mapDecisionParams(0.40, 2);
  dp.slow_distance = 0.6;
  DecisionMaker decider(dp);
  FrameSummary cloud;
  cloud.coverage = 1.0;
  cloud.free_distance = s.free;
  double t = 100.0;
  bool backed_off = false;
  for (int i = 0; i < 200 && !backed_off; ++i, t += 0.1)
  {
    cloud.stamp = t;
    decider.onFrame(withMap(cloud, world.summarize(robot, now), 0.06));
    const Decision& d = decider.step(t, MotionState());
    if (d.command == Command::DRIVE)
    {
      ASSERT_LT(d.distance, 0.0) << "only a back-off is possible here: " << d.text;
      EXPECT_EQ(d.state, State::BACKING_OFF);
      EXPECT_LE(-d.distance, dp.backoff_distance + 1e-9);
      backed_off = true;
    }
  }
  EXPECT_TRUE(backed_off);
}

TEST(WorldModel, DockedAgainstAWallNeverBacksIntoIt)
{
  // The robot leaves a dock: a corridor 0.8 m wide whose end wall stands 0.17 m behind its back.
  // Even a start disc taken as free is no trail: nothing behind may be reversed into.
  const std::vector<Wall> walls = { { -kEdge - 0.17, 0.0, 0.0 }, { 0.0, 0.4, -M_PI / 2 }, { 0.0, -0.4, M_PI / 2 } };
  for (const double start_free : { 0.0, 0.45 })
  {
    WorldParams wp = params();
    wp.start_free_radius = start_free;
    wp.clearance = 0.40;
    WorldModel world(wp);
    Pose2D robot;
    double now = 0.0;
    scan(world, robot, walls, now);  // a look all around (+-3 rad)
    const MapSummary& s = world.summarize(robot, now);
    EXPECT_TRUE(world.summarize(robot, now).view_seen) << "the camera sees ahead at the clearance";
    EXPECT_DOUBLE_EQ(s.reverse_free, 0.0) << "start_free_radius " << start_free;
    EXPECT_DOUBLE_EQ(s.best_reverse_free, 0.0) << "start_free_radius " << start_free;
    // 0.3 m down the corridor, the way back is the 0.3 m driven, never more.
    driveAndLook(world, robot, 0.3, walls, now);
    const MapSummary& t = world.summarize(robot, now);
    EXPECT_GE(t.reverse_free, 0.3 - 0.02 - 1e-9) << "start_free_radius " << start_free;
    EXPECT_LE(t.reverse_free, 0.3 + 1e-9) << "start_free_radius " << start_free;
  }

  // The decisions at the dock (start_free_radius 0): never a back-off; the way out is a creep down
  // the corridor, where nothing was ever seen, while the camera sees ahead at the clearance.
  WorldParams wp = params();
  wp.clearance = 0.40;
  WorldModel world(wp);
  Pose2D robot;
  double now = 0.0;
  scan(world, robot, walls, now);
  DecisionParams dp = mapDecisionParams(0.40, 2);
  dp.min_goal_distance = 0.005;
  DecisionMaker decider(dp);
  FrameSummary cloud;
  cloud.coverage = 1.0;
  cloud.free_distance = 0.8;  // the box measured free to its depth
  bool crept = false;
  double t = 100.0;
  for (int i = 0; i < 200; ++i, t += 0.1)
  {
    cloud.stamp = t;
    decider.onFrame(withMap(cloud, world.summarize(robot, now), 0.06));
    const Decision& d = decider.step(t, MotionState());
    if (d.command == Command::DRIVE)
    {
      ASSERT_GT(d.distance, 0.0) << "no back-off toward the end wall: " << d.text;
      EXPECT_EQ(d.reason, Reason::CREEPING) << d.text;
      EXPECT_LE(d.speed, dp.creep_speed + 1e-12);
      crept = true;
    }
  }
  EXPECT_TRUE(crept);
}

TEST(WorldModel, BumpIsMarkedInFront)
{
  WorldModel world(params());
  Pose2D robot;
  double now = 0.0;
  scan(world, robot, {}, now);
  driveAndLook(world, robot, 0.6, {}, now);
  const double before = world.summarize(robot, now).obstacle;
  world.markBump(robot, false, false, now);
  const MapSummary& s = world.summarize(robot, now);
  EXPECT_EQ(before, kInf);
  EXPECT_LT(s.obstacle, 0.05);
  EXPECT_LT(s.free, 0.05);
}

TEST(WorldModel, PassingBesideAThinLegKeepsIt)
{
  // A 22 mm leg seen once (one decoded point in its 2 cm cell); the robot then stands with its body
  // 6.5 mm from the leg's surface (the cell's centre 0.185 m from the robot's): the cell lies within
  // the swept radius but not under the body, so standing there must not erase the leg. An earlier
  // version marked every centre within the swept radius free, and a later arc drove into the leg.
  WorldModel world(params());
  world.updatePose(Pose2D(), 0.0);  // the start disc (start_free_radius) lies well away from the leg
  const double leg_x = 0.61;
  const double leg_y = 0.31;
  world.addRays({ { 0.11F, 0.31F, 0.08F, 0.61F, 0.31F, 0.08F, RayKind::Hit } }, 0.0);
  ASSERT_EQ(world.map().state(leg_x, leg_y, 0.0), CellState::Occupied);
  const Pose2D beside{ leg_x, leg_y - 0.185, 0.0 };
  world.updatePose(beside, 0.1);
  EXPECT_EQ(world.map().state(leg_x, leg_y, 0.1), CellState::Occupied);
  // What lies wholly under the body is free: the centre, and 0.15 m out to either side.
  EXPECT_EQ(world.map().state(beside.x, beside.y, 0.1), CellState::Free);
  EXPECT_EQ(world.map().state(beside.x, beside.y - 0.15, 0.1), CellState::Free);
  EXPECT_EQ(world.map().state(beside.x + 0.15, beside.y, 0.1), CellState::Free);
  EXPECT_NEAR(world.bodyFreeRadius(), 0.1675 - 0.02 * M_SQRT1_2, 1e-9);
}

TEST(WorldModel, ContactTravelOfTheDisc)
{
  const std::vector<Point> points = { makePoint(0.5F, 0.0F, 0.1F), makePoint(0.45F, 0.15F, 0.1F),
                                      makePoint(0.2F, 0.4F, 0.1F) };
  const double r = 0.1675;
  EXPECT_DOUBLE_EQ(contactTravel(points, { 0 }, r), 0.5);
  // Off the centre line the disc's arc reaches the point later than the front edge would.
  EXPECT_NEAR(contactTravel(points, { 1 }, r), 0.45 + r - std::sqrt(r * r - 0.15 * 0.15), 1e-6);
  EXPECT_DOUBLE_EQ(contactTravel(points, { 0, 1 }, r), 0.5);
  EXPECT_EQ(contactTravel(points, {}, r), kInf);
}

TEST(WorldModel, BadParametersNameTheParameter)
{
  WorldParams p;
  EXPECT_NO_THROW(p.validate());
  p.start_free_radius = -1.0;
  EXPECT_THROW(p.validate(), std::invalid_argument);
  EXPECT_NE(validationError(p).find("start_free_radius"), std::string::npos) << validationError(p);
  p = WorldParams();
  p.check_distance = 5.0;  // beyond half of the 4 m map
  EXPECT_NE(validationError(p).find("check_distance"), std::string::npos) << validationError(p);
  p = WorldParams();
  p.headings = -1;
  EXPECT_NE(validationError(p).find("headings"), std::string::npos) << validationError(p);
  p = WorldParams();
  p.map.resolution = 0.0;
  EXPECT_EQ(validationError(p).rfind("map_resolution", 0), 0U) << validationError(p);
  EXPECT_THROW(WorldModel{ p }, std::invalid_argument);
}

TEST(MapDecisions, LowCoverageDoesNotStopAMapDecision)
{
  DecisionParams dp;
  dp.safety_margin = 0.4;
  DecisionMaker decider(dp);
  FrameSummary f;
  f.stamp = 1.0;
  f.from_map = true;
  f.coverage = 0.05;  // little of the far box known, but the swept path is free for 0.9 m
  f.free_distance = 0.9;
  decider.onFrame(f);
  const Decision& d = decider.step(1.0, MotionState());
  ASSERT_EQ(d.command, Command::DRIVE) << d.text;
  EXPECT_NEAR(d.distance, 0.5, 1e-9);
}

TEST(MapDecisions, SpeedObeysTheStoppingFormula)
{
  DecisionParams dp;
  dp.safety_margin = 0.1;
  dp.slow_distance = 0.15;  // the ramp alone would allow max_speed almost at once
  dp.max_speed = 0.5;
  dp.deceleration = 0.25;
  dp.min_goal_distance = 0.005;
  DecisionMaker decider(dp);
  for (const double free : { 0.12, 0.15, 0.2, 0.3, 0.5 })
  {
    decider.reset();
    FrameSummary f;
    f.stamp = 1.0;
    f.from_map = true;
    f.free_distance = free;
    decider.onFrame(f);
    const Decision& d = decider.step(1.0, MotionState());
    ASSERT_EQ(d.command, Command::DRIVE) << d.text;
    const double bound = std::sqrt(2.0 * dp.deceleration * (free - dp.safety_margin));
    EXPECT_LE(d.speed, bound + 1e-9) << "free " << free;
    EXPECT_NEAR(d.speed, std::min(dp.max_speed, bound), 1e-9) << "free " << free;
  }
}

TEST(MapDecisions, CreepFollowsItsFormula)
{
  // Known free too short for a goal: with a map, creep_speed > 0, the view ahead at the margin
  // known (view_seen) and the open travel beyond the margin plus min_goal_distance, a goal of
  // (open - margin) at v = min(creep_speed, sqrt(2 a (open - margin)), ramp); else UNKNOWN_AHEAD.
  DecisionParams dp = mapDecisionParams(0.4, 0);
  dp.min_goal_distance = 0.005;
  DecisionMaker decider(dp);
  for (const double open : { 0.403, 0.41, 0.45, 0.6, 1.2 })
  {
    for (const bool view_seen : { false, true })
    {
      decider.reset();
      FrameSummary f;
      f.stamp = 1.0;
      f.from_map = true;
      f.free_distance = 0.2;
      f.open_distance = open;
      f.view_seen = view_seen;
      decider.onFrame(f);
      const Decision& d = decider.step(1.0, MotionState());
      const bool creep = view_seen && open - 0.4 >= 0.005;
      if (!creep)
      {
        EXPECT_EQ(d.command, Command::STOP) << open << " " << view_seen << ": " << d.text;
        EXPECT_EQ(d.reason, Reason::UNKNOWN_AHEAD) << d.text;
        continue;
      }
      ASSERT_EQ(d.command, Command::DRIVE) << open << " " << view_seen << ": " << d.text;
      EXPECT_EQ(d.reason, Reason::CREEPING);
      EXPECT_EQ(d.state, State::SLOWING);
      EXPECT_NEAR(d.distance, open - 0.4, 1e-12);
      EXPECT_NEAR(d.speed, std::min(dp.creep_speed, std::sqrt(2.0 * dp.deceleration * (open - 0.4))), 1e-12);
    }
  }
  // creep_speed 0 switches it off; without a map nothing is known to be never seen.
  DecisionParams off = dp;
  off.creep_speed = 0.0;
  for (const bool from_map : { true, false })
  {
    DecisionMaker d2(from_map ? off : dp);
    FrameSummary f;
    f.stamp = 1.0;
    f.from_map = from_map;
    f.coverage = 1.0;
    f.free_distance = 0.2;
    f.open_distance = 1.2;
    f.view_seen = true;
    d2.onFrame(f);
    EXPECT_EQ(d2.step(1.0, MotionState()).reason, Reason::UNKNOWN_AHEAD) << "from_map " << from_map;
  }
}

TEST(MapDecisions, ACreepGivesWayToAFullGoalAndStopsForWhatItSees)
{
  DecisionParams dp = mapDecisionParams(0.4, 0);
  dp.min_goal_distance = 0.005;
  DecisionMaker decider(dp);
  FrameSummary f;
  f.from_map = true;
  f.free_distance = 0.2;
  f.open_distance = 1.2;
  f.view_seen = true;
  double t = 1.0;
  const auto step = [&](const MotionState& m) -> const Decision&
  {
    f.stamp = t;
    decider.onFrame(f);
    const Decision& d = decider.step(t, m);
    t += 0.1;
    return d;
  };
  ASSERT_EQ(step(MotionState()).reason, Reason::CREEPING);
  MotionState creeping;
  creeping.goal_active = true;
  creeping.goal_remaining = 0.75;
  creeping.goal_speed = dp.creep_speed;
  const Decision& going = step(creeping);
  EXPECT_EQ(going.command, Command::NONE) << going.text;
  EXPECT_EQ(going.reason, Reason::CREEPING);
  // The map now knows the path free: a full goal replaces the creep.
  f.free_distance = 1.2;
  const Decision& full = step(creeping);
  ASSERT_EQ(full.command, Command::DRIVE) << full.text;
  EXPECT_NE(full.reason, Reason::CREEPING);
  EXPECT_GT(full.speed, dp.creep_speed);

  // Creeping again; a lit (suspect) cell appears 0.42 m ahead: a shorter creep, then a stop.
  decider.reset();
  f.free_distance = 0.2;
  ASSERT_EQ(step(MotionState()).reason, Reason::CREEPING);
  f.open_distance = 0.42;
  const Decision& shorter = step(creeping);
  ASSERT_EQ(shorter.command, Command::DRIVE) << shorter.text;
  EXPECT_EQ(shorter.reason, Reason::CREEPING);
  EXPECT_NEAR(shorter.distance, 0.02, 1e-12);
  creeping.goal_remaining = 0.02;
  f.open_distance = 0.403;
  const Decision& stop = step(creeping);
  EXPECT_EQ(stop.command, Command::STOP) << stop.text;
  EXPECT_EQ(stop.reason, Reason::UNKNOWN_AHEAD);
  // The camera no longer sees ahead at the margin (something near shadows it): the creep stops.
  decider.reset();
  f.open_distance = 1.2;
  ASSERT_EQ(step(MotionState()).reason, Reason::CREEPING);
  f.view_seen = false;
  creeping.goal_remaining = 0.75;
  EXPECT_EQ(step(creeping).command, Command::STOP);
}

TEST(MapDecisions, AWayFoundWhileSettlingIsTakenOnlyWhenUnknownSpaceBlocked)
{
  // The first cloud comes before its rays are in the map: unknown ahead, the turn cycle starts. A
  // cloud taken while the robot settles shows the creep: it goes, without a turn.
  DecisionParams dp = mapDecisionParams(0.4, 12);
  dp.settle_time = 0.3;
  dp.min_goal_distance = 0.005;
  DecisionMaker decider(dp);
  FrameSummary f;
  f.from_map = true;
  f.stamp = 1.0;
  f.free_distance = 0.0;
  decider.onFrame(f);
  EXPECT_EQ(decider.step(1.0, MotionState()).reason, Reason::UNKNOWN_AHEAD);
  f.view_seen = true;
  f.open_distance = 1.2;
  decider.onFrame(f);  // the same cloud, its rays now in the map: not taken after the cycle began
  EXPECT_EQ(decider.step(1.01, MotionState()).command, Command::STOP);
  // Past settle_time, still no cloud taken since (a loaded machine): no turn away from a heading
  // nobody looked at yet.
  const Decision& waiting = decider.step(1.0 + dp.settle_time + 0.1, MotionState());
  EXPECT_EQ(waiting.command, Command::STOP) << waiting.text;
  EXPECT_EQ(waiting.reason, Reason::UNKNOWN_AHEAD);
  f.stamp = 1.1;
  decider.onFrame(f);
  const Decision& d = decider.step(1.45, MotionState());
  EXPECT_EQ(d.command, Command::DRIVE) << d.text;
  EXPECT_EQ(d.reason, Reason::CREEPING);
  // The same with a cloud that still shows nothing ahead: then it turns.
  decider.reset();
  FrameSummary u;
  u.from_map = true;
  u.stamp = 1.0;
  decider.onFrame(u);
  EXPECT_EQ(decider.step(1.0, MotionState()).command, Command::STOP);
  EXPECT_EQ(decider.step(1.0 + dp.settle_time + 0.1, MotionState()).command, Command::STOP);
  u.stamp = 1.2;
  decider.onFrame(u);
  EXPECT_EQ(decider.step(1.45, MotionState()).command, Command::TURN);
  // Blocked by an obstacle, the cycle settles and turns whatever the next cloud says.
  decider.reset();
  FrameSummary o;
  o.from_map = true;
  o.stamp = 1.0;
  o.nearest_obstacle = 0.401;
  o.free_distance = 0.401;
  decider.onFrame(o);
  EXPECT_EQ(decider.step(1.0, MotionState()).reason, Reason::OBSTACLE);
  o.stamp = 1.1;
  o.nearest_obstacle = kInf;
  o.free_distance = 1.2;
  decider.onFrame(o);
  EXPECT_EQ(decider.step(1.1, MotionState()).command, Command::STOP);
  o.stamp = 1.35;
  decider.onFrame(o);
  EXPECT_EQ(decider.step(1.35, MotionState()).command, Command::TURN);
}

TEST(MapDecisions, NeverSeenSpaceAheadIsLookedAtOnBothSides)
{
  // Unknown ahead: the turn cycle turns one step to one side, one step back (the first heading
  // again: its rays may have reached the map late) and one more (its other side), even with a
  // heading open on the first side (the way it came), and then toward that heading. Blocked by an
  // obstacle it turns toward it at once.
  for (const bool obstacle : { false, true })
  {
    DecisionParams dp = mapDecisionParams(0.4, 12);
    dp.min_goal_distance = 0.005;
    dp.settle_time = 0.1;  // a stop between the turns
    DecisionMaker decider(dp);
    FrameSummary f;
    f.from_map = true;
    f.free_distance = f.open_distance = 0.3;
    f.nearest_obstacle = obstacle ? 0.3 : kInf;
    f.best_turn = 2.0;  // far to the left, open: the way back
    f.best_turn_free = 1.0;
    std::vector<double> turns;  // signed duration of each turn, s
    bool turning = false;
    for (double t = 1.0; t < 12.0 && turns.size() < 5; t += 0.05)
    {
      f.stamp = t;
      decider.onFrame(f);
      const Decision& d = decider.step(t, MotionState());
      if (d.command == Command::TURN)
      {
        if (!turning)
        {
          turns.push_back(0.0);
        }
        turns.back() += (d.angular_speed > 0.0 ? 0.05 : -0.05);
      }
      turning = d.command == Command::TURN;
    }
    ASSERT_GE(turns.size(), 4U);
    const double step = dp.turn_angle / dp.turn_speed;
    const std::vector<double> expected =
        obstacle ? std::vector<double>{ step, step, step, step } : std::vector<double>{ step, -step, -step, step };
    for (std::size_t k = 0; k < 4; ++k)
    {
      EXPECT_NEAR(turns[k], expected[k], 0.06) << "turn " << k << (obstacle ? " (obstacle)" : " (unknown)");
    }
  }
}

TEST(MapDecisions, NoOdometryStops)
{
  DecisionMaker decider;
  FrameSummary f;
  f.stamp = 1.0;
  f.from_map = true;
  f.free_distance = 1.0;
  decider.onFrame(f);
  MotionState m;
  m.localized = false;
  m.localization_detail = "no transform";
  const Decision& d = decider.step(1.0, m);
  EXPECT_EQ(d.command, Command::STOP);
  EXPECT_EQ(d.reason, Reason::NO_ODOMETRY);
  EXPECT_NE(d.text.find("no transform"), std::string::npos);
}

TEST(MapDecisions, GivesUpAfterMaxBackoffs)
{
  DecisionParams dp = mapDecisionParams(0.4, 1);
  dp.max_backoffs = 2;
  DecisionMaker decider(dp);
  FrameSummary f;
  f.from_map = true;
  f.free_distance = 0.1;
  f.nearest_obstacle = kInf;
  f.reverse_free = 1.0;
  int backoffs = 0;
  bool gave_up = false;
  double t = 1.0;
  MotionState m;
  for (int i = 0; i < 400 && !gave_up; ++i, t += 0.1)
  {
    f.stamp = t;
    decider.onFrame(f);
    const Decision& d = decider.step(t, m);
    m.goal_active = false;
    if (d.command == Command::DRIVE)
    {
      ASSERT_LT(d.distance, 0.0);
      ++backoffs;
      m.goal_active = true;  // runs for one step
    }
    gave_up = d.reason == Reason::NO_FREE_DIRECTION;
  }
  EXPECT_TRUE(gave_up);
  EXPECT_EQ(backoffs, 2);
}
}  // namespace
}  // namespace sl_obstacle
