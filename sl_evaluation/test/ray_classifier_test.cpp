// Per-ray outcomes (doc/world_model.md section 1) on images rendered by the project's simulator,
// checked against the renderer's scene geometry.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <cstdio>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <string>

#include "sl_evaluation/evaluation.h"
#include "sl_decoder/ray_classifier.h"
#include "sl_testing/errors.h"

using namespace sl_decoder;
using namespace sl_evaluation;

namespace
{
/// Everything one rendered and classified frame produced.
struct Frame
{
  sl_sim::RenderOutput truth;
  DecodeResult result;
  std::vector<RayOutcome> rays;
  std::array<int, kRayStates> counts{};
  Eigen::Isometry3d camera = Eigen::Isometry3d::Identity();  ///< camera in the world (classifyFrom)
};

/// The default rig, simulator, decoder and classifier, shared by the tests (built once).
struct Shared
{
  sl_projector::Rig rig = sl_projector::loadRig(defaultRigFile());
  sl_sim::Renderer renderer{ rig };
  Decoder decoder{ rig };
  RayClassifier rays{ rig, decoder.config(), RayConfig() };
  cv::Mat pattern = decoder.pattern().render();
  Eigen::Isometry3d camera_in_world = sl_sim::cameraPoseInWorld(rig);
};

Shared& setup()
{
  static Shared s;
  return s;
}

/// A 4 x 4 m plane of @p albedo whose centre is @p depth m ahead of the camera (along the robot's x
/// axis; the camera sits 30 mm behind platform_edge), turned by @p yaw about the vertical and
/// @p pitch about the robot's y axis, shifted @p lateral m to the left; with the floor of room.yaml
/// when @p floor.
sl_sim::Scene planeScene(double depth, double albedo, bool floor, double yaw = 0.0, double pitch = 0.0,
                         double lateral = 0.0)
{
  std::ostringstream s;
  s << "format_version: 1\nobjects:\n";
  if (floor)
    s << "  - {type: plane, name: floor, position: [0, 0, 0], normal: [0, 0, 1], albedo: 0.35,\n"
         "     texture: {type: noise, scale: 0.08, contrast: 0.35}, floor: true}\n";
  if (depth > 0.0)
    s << "  - {type: plane, name: plane, position: [" << depth - 0.030 << ", " << lateral << ", 0.5], rpy: [0, "
      << -M_PI / 2 + pitch << ", " << yaw << "], size: [4, 4], albedo: " << albedo << "}\n";
  return sl_sim::parseScene(s.str(), "planeScene");
}

void classify(const sl_sim::Scene& scene, uint64_t seed, Frame& f)
{
  Shared& s = setup();
  s.renderer.render(scene, s.pattern, s.camera_in_world, seed, f.truth);
  s.decoder.decode(f.truth.image, f.result);
  s.rays.classify(f.truth.image, f.result, f.rays);
  f.counts = s.rays.lastCounts();
  f.camera = s.camera_in_world;
}

std::string countsText(const Frame& f)
{
  std::string text;
  for (int k = 0; k < kRayStates; ++k)
    text += std::string(k ? ", " : "") + toString(static_cast<RayState>(k)) + " " +
            std::to_string(f.counts[static_cast<size_t>(k)]);
  return text + " (C1 " + std::to_string(static_cast<int>(setup().rays.lastC1())) + ", detectable to " +
         std::to_string(setup().rays.lastDetectableDepth()).substr(0, 4) + " m)";
}

/// Primitives whose segment starts in the image (could be seen at all).
int inView()
{
  int n = 0;
  const int total = static_cast<int>(setup().decoder.pattern().array().values().size());
  for (int i = 0; i < total; ++i)
    n += setup().rays.samples(i) > 0;
  return n;
}

int count(const Frame& f, RayState state, bool in_view_only = true)
{
  int n = 0;
  for (size_t i = 0; i < f.rays.size(); ++i)
    n += f.rays[i].state == state && (!in_view_only || setup().rays.samples(static_cast<int>(i)) > 0);
  return n;
}

/**
 * Rays whose free part (or end point) goes more than @p tolerance m beyond the first surface the
 * projector ray meets in the scene, measured along the ray: the one thing a ray outcome must never do.
 * Checks floor, dark and lit rays (decoded points are the decoder's, their accuracy is tested in
 * decoder_test). Exempt: surfaces darker than min_albedo (the documented limitation) and objects
 * lower than 15 mm (sl_obstacle's floor_margin: floor to the map, like room.yaml's cable).
 */
int raysBeyondSurface(const sl_sim::Scene& scene, const Frame& f, double tolerance, const char* what)
{
  const Shared& s = setup();
  const Eigen::Vector3d origin = f.camera * s.rays.projectorCentre().cast<double>();
  int bad = 0;
  for (size_t i = 0; i < f.rays.size(); ++i)
  {
    const RayOutcome& o = f.rays[i];
    if (o.state == RayState::Unseen || o.state == RayState::Decoded)
      continue;
    const Eigen::Vector3d end = f.camera * o.end.cast<double>();
    const double along = (end - origin).norm();
    sl_sim::Ray ray;
    ray.origin = origin;
    ray.direction = (end - origin).normalized();
    sl_sim::Hit hit;
    const double surface = sl_sim::intersectScene(scene, ray, hit) ? hit.t : 1e9;
    if (hit.object >= 0)
    {
      const sl_sim::SceneObject& object = scene.objects[static_cast<size_t>(hit.object)];
      if (object.material.albedo < s.rays.config().min_albedo || (!object.floor && hit.point.z() < 0.015))
        continue;
    }
    if (along > surface + tolerance)
    {
      if (++bad <= 5)
        std::printf("  %s: primitive %zu (%d, %zu) %s ends %.3f m along the ray, the surface is at %.3f m\n", what, i,
                    static_cast<int>(i) / 64, i % 64, toString(o.state), along, surface);
    }
  }
  return bad;
}
}  // namespace

TEST(RayConfig, BadValuesThrowNamingTheField)
{
  using sl_testing::refusedNaming;
  EXPECT_EQ(sl_testing::validationError(RayConfig()), "");
  EXPECT_TRUE(refusedNaming<RayConfig>("min_albedo", [](auto& c) { c.min_albedo = 0.0; }));
  EXPECT_TRUE(refusedNaming<RayConfig>("min_albedo", [](auto& c) { c.min_albedo = 1.5; }));
  EXPECT_TRUE(refusedNaming<RayConfig>("pattern_contrast_1m", [](auto& c) { c.pattern_contrast_1m = -1.0; }));
  EXPECT_TRUE(refusedNaming<RayConfig>("light_fraction", [](auto& c) { c.light_fraction = std::nan(""); }));
  EXPECT_TRUE(refusedNaming<RayConfig>("noise_floor", [](auto& c) { c.noise_floor = 0.0; }));
  EXPECT_TRUE(refusedNaming<RayConfig>("max_range", [](auto& c) { c.max_range = -2.0; }));
  EXPECT_TRUE(refusedNaming<RayConfig>("glow_max_depth", [](auto& c) { c.glow_max_depth = -0.1; }));
  // max_range beyond the decoder's max_depth is refused by the classifier.
  RayConfig c;
  c.max_range = 3.0;
  const std::string error =
      sl_testing::invalidArgumentOf([&] { RayClassifier r(setup().rig, setup().decoder.config(), c); });
  EXPECT_EQ(error.rfind("max_range", 0), 0u) << "max_range beyond max_depth: \"" << error << "\"";
}

namespace
{
/// Classifies @p scene with seeds 1 to @p seeds, logs the counts of each ("<what>, seed <seed>:
/// <counts>; in view <n>") and runs @p check on it.
void forEachSeed(const sl_sim::Scene& scene, uint64_t seeds, const char* what,
                 const std::function<void(const Frame&, uint64_t)>& check)
{
  Frame f;
  for (uint64_t seed = 1; seed <= seeds; ++seed)
  {
    classify(scene, seed, f);
    std::printf("%s, seed %d: %s; in view %d\n", what, static_cast<int>(seed), countsText(f).c_str(), inView());
    check(f, seed);
  }
}
}  // namespace

TEST(RayClassifier, StateNames)
{
  EXPECT_STREQ(toString(RayState::Decoded), "decoded");
  EXPECT_STREQ(toString(RayState::Floor), "floor");
  EXPECT_STREQ(toString(RayState::Dark), "dark");
  EXPECT_STREQ(toString(RayState::Lit), "lit");
  EXPECT_STREQ(toString(RayState::Unseen), "unseen");
}

TEST(RayClassifier, PlaneAt3mIsDark)
{
  const sl_sim::Scene scene = planeScene(3.0, 0.8, false);
  forEachSeed(scene, 3, "plane 3 m",
              [&](const Frame& f, uint64_t seed)
              {
                EXPECT_GE(count(f, RayState::Dark), 0.9 * inView()) << seed;
                EXPECT_EQ(raysBeyondSurface(scene, f, 0.02, "plane 3 m"), 0);
              });
}

TEST(RayClassifier, PlaneAt25cmIsLitNeverDark)
{
  const sl_sim::Scene scene = planeScene(0.25, 0.8, false);
  forEachSeed(scene, 2, "plane 0.25 m",
              [&](const Frame& f, uint64_t seed)
              {
                EXPECT_GE(count(f, RayState::Lit), 0.9 * inView()) << seed;
                EXPECT_EQ(count(f, RayState::Dark, false), 0) << seed;
              });
}

/// Dark rays whose free part ends inside the image (not where the segment leaves the view).
int darkInView(const Frame& f)
{
  const sl_projector::PinholeModel& camera = setup().rig.camera;
  int n = 0;
  for (const RayOutcome& o : f.rays)
  {
    if (o.state != RayState::Dark)
      continue;
    const Eigen::Vector2d px = camera.project(o.end.cast<double>());
    n += px.x() >= 12.0 && px.y() >= 12.0 && px.x() < camera.width - 12.0 && px.y() < camera.height - 12.0;
  }
  return n;
}

TEST(RayClassifier, PlanesWhereTheRobotStopsAreNeverDark)
{
  // Where the robot stops (the camera 0.30 to 0.48 m from an obstacle) the pattern is blurred and
  // partly merged: every primitive not decoded there must still report the light (lit), never dark
  // (except where its segment leaves the image first). Planes head-on and turned, albedo down to
  // 0.15 (min_albedo is 0.1).
  for (const double depth : { 0.30, 0.33, 0.35, 0.38, 0.40, 0.43, 0.45, 0.48 })
  {
    for (const double albedo : { 0.8, 0.35, 0.15 })
    {
      const double yaw = albedo < 0.5 ? 0.2 : 0.0;
      const sl_sim::Scene scene = planeScene(depth, albedo, false, yaw, 0.0, 0.03);
      Frame f;
      for (uint64_t seed = 3; seed <= 4; ++seed)
      {
        classify(scene, seed, f);
        EXPECT_EQ(darkInView(f), 0) << "plane " << depth << " m, albedo " << albedo << ", seed " << seed << ": "
                                    << countsText(f);
        EXPECT_EQ(raysBeyondSurface(scene, f, 0.02, "near plane"), 0) << depth << " " << albedo << " " << seed;
      }
    }
  }
}

TEST(RayClassifier, FloorOnlySceneGivesFloorOnTheLowerRows)
{
  // The lower rows: floor hits nearer than 0.8 m (rows 14 and 15 of the default rig). Farther the
  // floor is lit at grazing incidence and returns a few DN at most (row 13 at 0.87 m is floor on
  // most primitives, rows 10 to 12 at 1 to 1.8 m on almost none: there they are dark).
  const sl_sim::Scene scene = planeScene(0.0, 0.0, true);
  Frame f;
  int lower = 0;
  for (int i = 0; i < static_cast<int>(setup().rig.pattern.rows * setup().rig.pattern.cols); ++i)
    lower += setup().rays.floorDepth(i) < 0.8f;
  for (uint64_t seed = 1; seed <= 3; ++seed)
  {
    classify(scene, seed, f);
    int floor = 0;
    for (int i = 0; i < static_cast<int>(f.rays.size()); ++i)
      floor += setup().rays.floorDepth(i) < 0.8f && f.rays[static_cast<size_t>(i)].state == RayState::Floor;
    std::printf("floor only, seed %d: %s; lower-row floor hits in view %d, floor %d\n", static_cast<int>(seed),
                countsText(f).c_str(), lower, floor);
    EXPECT_GT(lower, 90);
    EXPECT_GE(floor, 0.9 * lower) << seed;
    EXPECT_EQ(count(f, RayState::Lit, false), 0) << seed;
    EXPECT_EQ(raysBeyondSurface(scene, f, 0.02, "floor"), 0);
  }
}

TEST(RayClassifier, BlackSurfaceAt1mIsDark)
{
  // The documented limitation: albedo 0.02 is below min_albedo, invisible to the sensor.
  const sl_sim::Scene scene = planeScene(1.0, 0.02, false);
  Frame f;
  classify(scene, 1, f);
  std::printf("black plane 1 m: %s; in view %d\n", countsText(f).c_str(), inView());
  EXPECT_GE(count(f, RayState::Dark), 0.9 * inView());
}

TEST(RayClassifier, WhitePlaneAt700mmIsDecoded)
{
  const sl_sim::Scene scene = sl_sim::loadScene(findScene({ "plane_700" }));
  forEachSeed(scene, 2, "plane_700",
              [&](const Frame& f, uint64_t seed)
              {
                // Lit: the primitives whose segment ends on a blob cut by the image's left border.
                EXPECT_GE(f.counts[static_cast<size_t>(RayState::Decoded)], 820) << seed;
                EXPECT_LE(f.counts[static_cast<size_t>(RayState::Lit)], 60) << seed;
                EXPECT_EQ(raysBeyondSurface(scene, f, 0.02, "plane_700"), 0);
              });
}

TEST(RayClassifier, DimPlanesNeverLetAFreeRayThrough)
{
  struct Case
  {
    double depth, albedo, yaw, pitch, lateral;
    bool floor;
  };
  const Case cases[] = { { 1.0, 0.15, 0.0, 0.0, 0.0, false },
                         { 1.5, 0.2, 0.0, 0.0, 0.0, false },
                         { 1.0, 0.15, 0.5, 0.0, 0.1, true },
                         { 0.8, 0.12, -0.4, 0.3, -0.05, true },
                         { 0.6, 0.1, 0.3, 0.0, 0.0, false },
                         { 1.2, 0.2, 0.0, -0.3, 0.0, true },
                         // near, blurred: the glow and the defocused pattern of a min_albedo surface
                         { 0.27, 0.1, 0.0, 0.0, 0.0, false },
                         { 0.35, 0.1, 0.2, 0.0, 0.0, false },
                         { 0.45, 0.1, 0.0, 0.0, 0.0, true } };
  Frame f;
  for (const Case& c : cases)
  {
    const sl_sim::Scene scene = planeScene(c.depth, c.albedo, c.floor, c.yaw, c.pitch, c.lateral);
    for (uint64_t seed = 1; seed <= 3; ++seed)
    {
      classify(scene, seed, f);
      char what[96];
      std::snprintf(what, sizeof(what), "albedo %.2f at %.1f m, yaw %.1f, pitch %.1f%s, seed %d", c.albedo, c.depth,
                    c.yaw, c.pitch, c.floor ? ", floor" : "", static_cast<int>(seed));
      std::printf("%s: %s\n", what, countsText(f).c_str());
      EXPECT_EQ(raysBeyondSurface(scene, f, 0.02, what), 0) << what;
    }
  }
}

TEST(RayClassifier, RoomNeverLetsAFreeRayThroughASurface)
{
  // The demo room: floor, walls (one of albedo 0.07, below min_albedo, exempt), cable, box, chair
  // and table legs, seen from the start and from two other poses.
  const sl_sim::Scene scene = sl_sim::loadScene(findScene({ "room" }));
  Shared& s = setup();
  Frame f;
  const double poses[3][3] = { { 0.0, 0.0, 0.0 }, { 0.4, 0.1, 0.3 }, { 0.2, -0.3, -0.5 } };  // x, y, yaw
  for (const auto& pose : poses)
  {
    Eigen::Isometry3d edge = Eigen::Isometry3d::Identity();
    edge.translation() = Eigen::Vector3d(pose[0], pose[1], 0.0);
    edge.linear() = Eigen::AngleAxisd(pose[2], Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const Eigen::Isometry3d camera = sl_sim::cameraPoseInWorld(s.rig, edge);
    s.renderer.render(scene, s.pattern, camera, 5, f.truth);
    s.decoder.decode(f.truth.image, f.result);
    s.rays.classify(f.truth.image, f.result, f.rays);
    f.counts = s.rays.lastCounts();
    f.camera = camera;
    std::printf("room from (%.1f, %.1f, %.1f): %s\n", pose[0], pose[1], pose[2], countsText(f).c_str());
    EXPECT_EQ(raysBeyondSurface(scene, f, 0.02, "room"), 0);
  }
}

// The check above can fail: with a noise floor far below the real noise (0.5 DN against the 4 to 6
// DN that noise reaches), the walk trusts darkness up to 2.5 m, and rays pass through the dim plane
// (measured: 5; most others stop early, at noise).
TEST(RayClassifier, TooLowANoiseFloorLetsRaysThroughADimPlane)
{
  RayConfig optimistic;
  optimistic.noise_floor = 0.5;
  optimistic.light_fraction = 1.0;
  RayClassifier rays(setup().rig, setup().decoder.config(), optimistic);
  const sl_sim::Scene scene = planeScene(1.5, 0.2, false);
  Frame f;
  Shared& s = setup();
  s.renderer.render(scene, s.pattern, s.camera_in_world, 1, f.truth);
  s.decoder.decode(f.truth.image, f.result);
  rays.classify(f.truth.image, f.result, f.rays);
  f.camera = s.camera_in_world;
  EXPECT_GT(rays.lastDetectableDepth(), 2.5);
  EXPECT_GE(raysBeyondSurface(scene, f, 0.02, "noise floor 0.5 DN"), 3);
}

namespace
{
/// Classifies @p scene seen with platform_edge at (x, y, yaw) in the world; restores the default pose.
void classifyFrom(const sl_sim::Scene& scene, double x, double y, double yaw, uint64_t seed, Frame& f)
{
  Shared& s = setup();
  Eigen::Isometry3d edge = Eigen::Isometry3d::Identity();
  edge.translation() = Eigen::Vector3d(x, y, 0.0);
  edge.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Isometry3d saved = s.camera_in_world;
  s.camera_in_world = sl_sim::cameraPoseInWorld(s.rig, edge);
  s.renderer.render(scene, s.pattern, s.camera_in_world, seed, f.truth);
  s.decoder.decode(f.truth.image, f.result);
  s.rays.classify(f.truth.image, f.result, f.rays);
  f.counts = s.rays.lastCounts();
  f.camera = s.camera_in_world;
  s.camera_in_world = saved;
}

/// Lit rays whose suspect end lies more than @p gap m before the first surface on its projector
/// ray (inside sl_obstacle's height band): phantom obstacles where nothing is.
int phantomSuspects(const sl_sim::Scene& scene, const Frame& f, double gap,
                    double max_depth = std::numeric_limits<double>::infinity())
{
  const Shared& s = setup();
  const Eigen::Vector3d origin = f.camera * s.rays.projectorCentre().cast<double>();
  int phantoms = 0;
  for (const RayOutcome& o : f.rays)
  {
    if (o.state != RayState::Lit || !(o.depth < max_depth))
      continue;
    const Eigen::Vector3d end = f.camera * o.end.cast<double>();
    sl_sim::Ray ray;
    ray.origin = origin;
    ray.direction = (end - origin).normalized();
    sl_sim::Hit hit;
    const double surface = sl_sim::intersectScene(scene, ray, hit) ? hit.t : 1e9;
    phantoms += (end - origin).norm() < surface - gap && end.z() > 0.015 && end.z() < 0.173;
  }
  return phantoms;
}

/// Primitives whose projector ray meets the object named @p name first, and of those the ones the
/// classifier decoded or made a suspect no farther than the object (+ 0.02 m).
void seenOnObject(const sl_sim::Scene& scene, const Frame& f, const std::string& name, int& hits, int& seen)
{
  const Shared& s = setup();
  const Eigen::Vector3d origin = f.camera * s.rays.projectorCentre().cast<double>();
  hits = seen = 0;
  const int total = static_cast<int>(f.rays.size());
  for (int i = 0; i < total; ++i)
  {
    const RayOutcome& o = f.rays[static_cast<size_t>(i)];
    if (s.rays.samples(i) == 0 || o.state == RayState::Unseen)
      continue;
    sl_sim::Ray ray;
    ray.origin = origin;
    ray.direction = (f.camera * o.end.cast<double>() - origin).normalized();
    sl_sim::Hit hit;
    if (!sl_sim::intersectScene(scene, ray, hit) || scene.objects[static_cast<size_t>(hit.object)].name != name)
      continue;
    ++hits;
    const double along = (f.camera * o.end.cast<double>() - origin).norm();
    seen += o.state == RayState::Decoded || (o.state == RayState::Lit && along <= hit.t + 0.02);
  }
}
}  // namespace

TEST(RayClassifier, AWallMakesNoPhantomSuspectsInFrontOfIt)
{
  // Unexplained light (the pattern's edge cut by the image border, the dim rows stretched on the
  // floor at the foot of the wall, the glow of the floor near the robot) must not put suspects into
  // the empty space in front of a wall: each is an obstacle in the map that is not there, and the
  // robot would not drive up to the wall. Measured: 0 from each pose and seed (52, 52, 18 and 72
  // before border light and unconfirmed suspects were told apart; 3 at 0.25 m in front of the
  // camera from the first pose, seeds 2 to 12, while decoded floor points could confirm glow: the
  // closed-loop filter_wall then never started in 2 of 5 runs).
  const sl_sim::Scene scene = sl_sim::parseScene(
      "format_version: 1\nobjects:\n"
      "  - {type: plane, name: floor, position: [0, 0, 0], normal: [0, 0, 1], albedo: 0.35,\n"
      "     texture: {type: noise, scale: 0.05, contrast: 0.3}, floor: true}\n"
      "  - {type: plane, name: wall, position: [1.0, 0, 1.0], normal: [-1, 0, 0], size: [3, 2], albedo: 0.8}\n",
      "wall");
  // platform_edge poses (x, y, yaw): from 1 m away to where the robot stops and turns (0.4 to 0.55 m).
  const double poses[][3] = { { 0.0, 0.0, 0.0 }, { 0.3, 0.0, 0.0 },   { 0.5, 0.1, 0.2 },    { 0.2, -0.1, -0.3 },
                              { 0.5, 0.0, 0.0 }, { 0.55, 0.0, -0.5 }, { 0.58, 0.05, 0.35 }, { 0.45, -0.1, 0.7 } };
  Frame f;
  for (const auto& p : poses)
    for (uint64_t seed = 1; seed <= 4; ++seed)
    {
      classifyFrom(scene, p[0], p[1], p[2], seed, f);
      const int phantoms = phantomSuspects(scene, f, 0.05);
      std::printf("wall from (%.2f, %.2f, %.2f), seed %d: %s; phantom suspects %d\n", p[0], p[1], p[2],
                  static_cast<int>(seed), countsText(f).c_str(), phantoms);
      EXPECT_EQ(phantoms, 0) << p[0] << " " << p[1] << " " << p[2] << " seed " << seed;
      EXPECT_EQ(raysBeyondSurface(scene, f, 0.02, "wall"), 0);
    }
}

TEST(RayClassifier, AFarWallMakesNoPhantomSuspectsInTheGlowZone)
{
  // A bright wall beyond the decodable range (1.5 to 3.5 m) returns the pattern faint but in focus:
  // dots over dark gaps. Near the camera (glow_max_depth) that light must not pass for the glow of a
  // defocused surface (which fills the gaps, or raises the mean well above them): such suspects
  // stood 0.2 m in front of the robot in an empty corridor. Farther, at the end of the detectable
  // depth (0.6 to 0.8 m), the dots are as bright as a min_albedo surface there and stay suspects
  // (doc/limitations.md); their number is bounded. Albedo, distance, floor and heading vary.
  struct Case
  {
    double distance, albedo, yaw;
    const char* floor_albedo;
  };
  const Case cases[] = { { 1.5, 0.8, 0.0, "0.45" }, { 2.0, 0.9, 0.1, "0.3" }, { 2.5, 0.8, 0.0, "0.45" },
                         { 2.5, 0.6, -0.2, "0.6" }, { 3.0, 0.9, 0.05, "0.45" }, { 3.5, 1.0, 0.0, "0.35" } };
  const double glow_depth = setup().rays.config().glow_max_depth;
  Frame f;
  int most = 0;
  for (const Case& c : cases)
  {
    char yaml[512];
    std::snprintf(yaml, sizeof(yaml),
                  "format_version: 1\nobjects:\n"
                  "  - {type: plane, name: floor, position: [0, 0, 0], normal: [0, 0, 1], albedo: %s,\n"
                  "     texture: {type: noise, scale: 0.1, contrast: 0.3}, floor: true}\n"
                  "  - {type: plane, name: wall, position: [%.2f, 0, 1.2], normal: [-1, 0, 0], size: [6, 2.4], "
                  "albedo: %.2f}\n",
                  c.floor_albedo, c.distance, c.albedo);
    const sl_sim::Scene scene = sl_sim::parseScene(yaml, "far_wall");
    for (uint64_t seed = 1; seed <= 3; ++seed)
    {
      classifyFrom(scene, 0.0, 0.0, c.yaw, seed, f);
      const int near = phantomSuspects(scene, f, 0.05, glow_depth), all = phantomSuspects(scene, f, 0.05);
      most = std::max(most, all);
      std::printf("wall %.1f m away, albedo %.1f, yaw %.2f, floor %s, seed %d: %s; phantom suspects %d, %d of them "
                  "in the glow zone\n",
                  c.distance, c.albedo, c.yaw, c.floor_albedo, static_cast<int>(seed), countsText(f).c_str(), all, near);
      EXPECT_EQ(near, 0) << c.distance << " m, seed " << seed;
      EXPECT_EQ(raysBeyondSurface(scene, f, 0.02, "far wall"), 0);
    }
  }
  // Measured: at most 63 of the 1024 rays (the wall 2.5 m away); 40 % above that.
  EXPECT_LE(most, 88);
}

TEST(RayClassifier, ALegAfterATurnStaysAnObstacle)
{
  // The dark 22 mm leg of leg_beside_wall.yaml, 0.1 to 0.3 m in front of the robot after it turned
  // at the wall: near, blurred, hardly decodable. Its rays must be decoded or suspects at the leg,
  // and no free ray may pass through it.
  const sl_sim::Scene scene = sl_sim::parseScene(
      "format_version: 1\nobjects:\n"
      "  - {type: plane, name: floor, position: [0, 0, 0], normal: [0, 0, 1], albedo: 0.35,\n"
      "     texture: {type: noise, scale: 0.05, contrast: 0.3}, floor: true}\n"
      "  - {type: plane, name: wall, position: [1.0, 0, 1.0], normal: [-1, 0, 0], size: [4, 2], albedo: 0.7}\n"
      "  - {type: cylinder, name: leg, position: [0.60, 0.28, 0.36], radius: 0.011, height: 0.72, albedo: 0.12}\n",
      "leg_beside_wall");
  const double poses[][3] = { { 0.43, 0.0, 1.05 }, { 0.45, 0.0, 0.9 }, { 0.3, 0.05, 0.8 }, { 0.2, 0.1, 0.6 } };
  Frame f;
  for (const auto& p : poses)
  {
    classifyFrom(scene, p[0], p[1], p[2], 2, f);
    int hits = 0, seen = 0;
    seenOnObject(scene, f, "leg", hits, seen);
    std::printf("leg from (%.2f, %.2f, %.2f): %s; rays on the leg %d, decoded or suspect there %d\n", p[0], p[1], p[2],
                countsText(f).c_str(), hits, seen);
    EXPECT_EQ(raysBeyondSurface(scene, f, 0.02, "leg"), 0);
    if (hits >= 4)
    {
      EXPECT_GE(seen, hits / 2) << "the leg is hardly seen";
    }
  }
}

// Found with fuzz/decoder_rig_fuzz.cpp. Corpus camera_k3_1e6_hang.yaml: the decoder's epipolar
// index sampled every primitive's curve each 0.75 px of its length, and a strong camera distortion
// stretched the curves to millions of px, mostly outside the image: building the decoder for such a
// rig (a valid rig file) took 20 s with k3 = 1e6 and over 2.5 minutes with 1e8. The samples now stop
// at twice the image's perimeter. Corpus projector_p2_curve_int_overflow.yaml: the classifier's own
// cap was applied after converting a curve of 5e13 px to int (undefined; seen by clang's
// -fsanitize=float-cast-overflow, which `make fuzz` uses, not by g++'s).
TEST(RayClassifier, ExtremeLensesBuildInBoundedWork)
{
  const sl_projector::Rig base = sl_projector::loadRig(defaultRigFile());
  int built = 0;
  for (int lens = 0; lens < 3; ++lens)
  {
    sl_projector::Rig rig = base;
    if (lens == 0)
      rig.camera.dist = { 0.0, 0.0, 0.0, 0.0, 1e8 };
    else if (lens == 1)
      rig.camera.dist = { 0.0, 1e7, 0.0, 0.0, 0.0 };
    else
      rig.projector.dist = { 0.02, 0.0, 0.0, 2.0, 0.0 };
    ASSERT_NO_THROW(rig.validate()) << lens;
    try
    {
      Decoder decoder(rig);
      RayClassifier rays(rig, decoder.config(), RayConfig());
      const cv::Mat black(rig.camera.height, rig.camera.width, CV_8UC1, cv::Scalar(0));
      DecodeResult result;
      std::vector<RayOutcome> outcomes;
      decoder.decode(black, result);
      rays.classify(black, result, outcomes);
      EXPECT_EQ(result.valid, 0) << lens;
      EXPECT_EQ(outcomes.size(), static_cast<size_t>(rig.pattern.rows * rig.pattern.cols)) << lens;
      ++built;
    }
    catch (const std::invalid_argument& e)
    {
      // The documented refusal when the lens leaves no part of the pattern in view.
      EXPECT_NE(std::string(e.what()).find("not visible"), std::string::npos) << lens << ": " << e.what();
    }
  }
  EXPECT_GE(built, 2) << "the centre of the image keeps the pattern in view";
}
