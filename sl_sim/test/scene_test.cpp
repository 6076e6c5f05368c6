// Scene files (parsing, documented errors) and exact ray-scene intersection.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "sl_sim/scene.h"

namespace sl_sim
{
namespace
{
const std::string kScenes = SL_SIM_SCENES_DIR;

std::string errorOf(const std::string& yaml, const std::string& source = "t.yaml")
{
  try
  {
    parseScene(yaml, source);
  }
  catch (const SceneFileError& e)
  {
    return e.what();
  }
  return "(no error)";
}

Ray ray(const Eigen::Vector3d& o, const Eigen::Vector3d& d)
{
  Ray r;
  r.origin = o;
  r.direction = d;
  return r;
}
}  // namespace

TEST(SceneFile, EveryShippedSceneParses)
{
  std::vector<std::string> names = { "room",           "three_planes",   "cylinder_plane_650", "shiny_bin_586",
                                     "table_leg_20mm", "table_leg_12mm", "checkerboard_600" };
  for (int d = 450; d <= 950; d += 50)
    names.push_back("plane_" + std::to_string(d));
  for (const std::string& n : names)
  {
    SCOPED_TRACE(n);
    Scene s;
    ASSERT_NO_THROW(s = loadScene(kScenes + "/" + n + ".yaml"));
    ASSERT_FALSE(s.objects.empty());
    EXPECT_EQ(s.name, n);
    // The floor is the plane z = 0, marked as floor.
    EXPECT_EQ(s.objects[0].type, ObjectType::Plane);
    EXPECT_TRUE(s.objects[0].floor);
    EXPECT_NEAR(s.objects[0].pose.translation().z(), 0.0, 1e-12);
    EXPECT_NEAR(s.objects[0].pose.linear().col(2).z(), 1.0, 1e-12);
  }
}

TEST(SceneFile, PlaneSweepDistancesAreFromTheCamera)
{
  // A plane at D mm from the camera is x_world = D / 1000 + mount.xyz.x (-0.030 in the default rig).
  for (int d = 450; d <= 950; d += 50)
  {
    const Scene s = loadScene(kScenes + "/plane_" + std::to_string(d) + ".yaml");
    ASSERT_EQ(s.objects.size(), 2u);
    EXPECT_NEAR(s.objects[1].pose.translation().x(), d / 1000.0 - 0.030, 1e-9) << d;
    EXPECT_NEAR(s.objects[1].pose.linear().col(2).x(), -1.0, 1e-12) << d;
  }
}

TEST(SceneFile, ParsesAllObjectKindsAndMaterials)
{
  const Scene s = parseScene(R"(
format_version: 1
name: demo
objects:
  - type: plane
    name: wall
    position: [2.0, 0.0, 1.0]
    normal: [-1, 0, 0]
    size: [3.0, 2.0]
    albedo: 0.8
    texture: {type: checker, scale: 0.05, contrast: 0.4}
  - type: box
    name: crate
    position: [1.0, 0.5, 0.1]
    rpy: [0.0, 0.0, 0.5]
    size: [0.2, 0.3, 0.2]
    specular: 0.5
    shininess: 80
    texture: noise
  - type: cylinder
    position: [1.0, -0.5, 0.3]
    radius: 0.02
    height: 0.6
  - type: plane
    position: [0, 0, 0]
    normal: [0, 0, 1]
    floor: true
)",
                             "demo.yaml");
  ASSERT_EQ(s.objects.size(), 4u);
  EXPECT_EQ(s.name, "demo");
  const SceneObject& wall = s.objects[0];
  EXPECT_EQ(wall.type, ObjectType::Plane);
  EXPECT_EQ(wall.name, "wall");
  EXPECT_FALSE(wall.infinite());
  EXPECT_DOUBLE_EQ(wall.size.x(), 3.0);
  EXPECT_DOUBLE_EQ(wall.material.albedo, 0.8);
  EXPECT_EQ(wall.material.texture.type, TextureType::Checker);
  EXPECT_DOUBLE_EQ(wall.material.texture.scale, 0.05);
  // A plane given by its normal: local z = normal, local x = up x normal (to the right seen from
  // the front), local y = up.
  EXPECT_TRUE(wall.pose.linear().col(2).isApprox(Eigen::Vector3d(-1, 0, 0)));
  EXPECT_TRUE(wall.pose.linear().col(0).isApprox(Eigen::Vector3d(0, -1, 0)));
  EXPECT_TRUE(wall.pose.linear().col(1).isApprox(Eigen::Vector3d(0, 0, 1)));
  const SceneObject& crate = s.objects[1];
  EXPECT_EQ(crate.type, ObjectType::Box);
  EXPECT_TRUE(crate.size.isApprox(Eigen::Vector3d(0.2, 0.3, 0.2)));
  EXPECT_NEAR(std::atan2(crate.pose.linear()(1, 0), crate.pose.linear()(0, 0)), 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(crate.material.specular, 0.5);
  EXPECT_DOUBLE_EQ(crate.material.shininess, 80.0);
  EXPECT_EQ(crate.material.texture.type, TextureType::Noise);
  EXPECT_DOUBLE_EQ(crate.material.albedo, Material().albedo);
  const SceneObject& leg = s.objects[2];
  EXPECT_EQ(leg.type, ObjectType::Cylinder);
  EXPECT_EQ(leg.label(), "cylinder");
  EXPECT_DOUBLE_EQ(leg.size.x(), 0.02);
  EXPECT_DOUBLE_EQ(leg.size.z(), 0.6);
  const SceneObject& floor = s.objects[3];
  EXPECT_TRUE(floor.infinite());
  EXPECT_TRUE(floor.floor);
  const Eigen::AlignedBox3d fb = floor.worldBounds();
  EXPECT_DOUBLE_EQ(fb.max().z(), 0.0);
  EXPECT_TRUE(std::isinf(fb.max().x()));
  const Eigen::AlignedBox3d lb = leg.worldBounds();
  EXPECT_NEAR(lb.min().z(), 0.0, 1e-12);
  EXPECT_NEAR(lb.max().z(), 0.6, 1e-12);
  EXPECT_NEAR(lb.max().x() - lb.min().x(), 0.04, 1e-12);
}

TEST(SceneFile, ErrorsNameTheFileAndTheEntry)
{
  // The documented example.
  EXPECT_EQ(errorOf(R"(
objects:
  - {type: plane, position: [0, 0, 0], normal: [0, 0, 1]}
  - {type: box, name: table, position: [1, 0, 0.5], size: [1.0, -0.6, 0.03]}
)",
                    "room.yaml"),
            "room.yaml: objects[1] (box 'table'): size: must have 3 positive numbers");
  struct Case
  {
    std::string yaml;
    std::string expected;
  };
  const std::vector<Case> cases = {
    { "name: x\n", "t.yaml: objects: missing" },
    { "objects: []\n", "t.yaml: objects: must be a non-empty list" },
    { "objects: [\n", "t.yaml: not valid YAML" },
    { "", "t.yaml: <top level>: must be a mapping" },
    { "objects: [{type: plane, position: [0,0,0]}]\nlights: 3\n", "t.yaml: lights: unknown key" },
    { "format_version: 2\nobjects: [{type: plane, position: [0,0,0]}]\n", "t.yaml: format_version: is 2" },
    { "objects: [{type: sphere, position: [0, 0, 0]}]\n", "t.yaml: objects[0]: type: unknown type 'sphere'" },
    { "objects: [{position: [0, 0, 0]}]\n", "t.yaml: objects[0]: type: missing" },
    { "objects: [{type: box, name: b, size: [1, 1, 1]}]\n", "t.yaml: objects[0] (box 'b'): position: missing" },
    { "objects: [{type: box, position: [0, 0], size: [1, 1, 1]}]\n",
      "t.yaml: objects[0] (box): position: has 2 numbers, expected 3 numbers" },
    { "objects: [{type: box, position: [0, 0, x], size: [1, 1, 1]}]\n",
      "t.yaml: objects[0] (box): position: cannot read 'x' as a number" },
    { "objects: [{type: box, position: [0, 0, 0]}]\n", "t.yaml: objects[0] (box): size: missing" },
    { "objects: [{type: box, position: [0, 0, 0], size: [1, 1]}]\n",
      "t.yaml: objects[0] (box): size: must have 3 positive numbers" },
    { "objects: [{type: plane, name: p, position: [0, 0, 0], colour: red}]\n",
      "t.yaml: objects[0] (plane 'p'): colour: unknown key" },
    { "objects: [{type: cylinder, position: [0, 0, 0], radius: 0.1, size: [1, 1, 1]}]\n",
      "t.yaml: objects[0] (cylinder): size: unknown key" },
    { "objects: [{type: box, position: [0, 0, 0], size: [1, 1, 1], albdeo: 0.5}]\n",
      "t.yaml: objects[0] (box): albdeo: unknown key, did you mean 'albedo'? (allowed: albedo, floor, " },
    { "objects: [{type: cylinder, position: [0, 0, 0], height: 1}]\n",
      "t.yaml: objects[0] (cylinder): radius: missing" },
    { "objects: [{type: cylinder, position: [0, 0, 0], radius: -1, height: 1}]\n",
      "t.yaml: objects[0] (cylinder): radius: must be a positive number" },
    { "objects: [{type: plane, position: [0, 0, 0], normal: [0, 0, 0]}]\n",
      "t.yaml: objects[0] (plane): normal: must not be zero" },
    { "objects: [{type: plane, position: [0, 0, 0], normal: [0, 0, 1], rpy: [0, 0, 0]}]\n",
      "t.yaml: objects[0] (plane): normal: give either rpy or normal, not both" },
    { "objects: [{type: plane, position: [0, 0, 0], size: [1, 0]}]\n",
      "t.yaml: objects[0] (plane): size: must have 2 positive numbers" },
    { "objects: [{type: plane, position: [0, 0, 0], albedo: 1.5}]\n",
      "t.yaml: objects[0] (plane): albedo: must be in 0..1" },
    { "objects: [{type: plane, position: [0, 0, 0], specular: -0.1}]\n",
      "t.yaml: objects[0] (plane): specular: must be in 0..1" },
    { "objects: [{type: plane, position: [0, 0, 0], shininess: 0.5}]\n",
      "t.yaml: objects[0] (plane): shininess: must be in 1..10000" },
    { "objects: [{type: plane, position: [0, 0, 0], floor: maybe}]\n",
      "t.yaml: objects[0] (plane): floor: cannot read 'maybe' as a boolean" },
    { "objects: [{type: plane, position: [0, 0, 0], texture: marble}]\n",
      "t.yaml: objects[0] (plane): texture.type: unknown texture 'marble'" },
    { "objects: [{type: plane, position: [0, 0, 0], texture: {scale: 1}}]\n",
      "t.yaml: objects[0] (plane): texture.type: missing" },
    { "objects: [{type: plane, position: [0, 0, 0], texture: {type: checker, scale: 0}}]\n",
      "t.yaml: objects[0] (plane): texture.scale: must be a positive length" },
    { "objects: [{type: plane, position: [0, 0, 0], texture: {type: noise, contrast: 2}}]\n",
      "t.yaml: objects[0] (plane): texture.contrast: must be in 0..1" },
    { "objects: [{type: plane, position: [0, 0, 0], texture: {type: noise, grain: 2}}]\n",
      "t.yaml: objects[0] (plane): texture.grain: unknown key" },
    { "objects: [{type: box, position: [0, 0, 0], size: [1, 1, 1], texture: checkerboard}]\n",
      "t.yaml: objects[0] (box): texture.type: checkerboard is only for planes" },
    { "objects: [{type: plane, position: [0, 0, 0], size: [0.1, 0.1], texture: {type: checkerboard, cols: 9, "
      "rows: 7, square: 0.025}}]\n",
      "t.yaml: objects[0] (plane): texture: the board (cols * square by rows * square) does not fit" },
    { "objects: [{type: plane, position: [0, 0, 0], texture: {type: checkerboard, cols: 1}}]\n",
      "t.yaml: objects[0] (plane): texture.cols: must be 2..1000 squares" },
    { "objects:\n  - {type: plane, position: [0, 0, 0]}\n  - 7\n", "t.yaml: objects[1]: must be a mapping" },
  };
  for (const Case& c : cases)
  {
    const std::string e = errorOf(c.yaml);
    EXPECT_EQ(e.rfind(c.expected, 0), 0u) << "yaml:\n" << c.yaml << "\nerror: " << e << "\nexpected: " << c.expected;
  }
}

// A top-level key that is not a name threw YAML::TypedBadConversion instead of SceneFileError.
TEST(SceneFile, KeysThatAreNotNamesAreSceneFileErrors)
{
  EXPECT_THROW(parseScene("? :", "t.yaml"), SceneFileError);
  EXPECT_THROW(parseScene("[1]: 2", "t.yaml"), SceneFileError);
  // `? :` is an explicit key that is itself the mapping {~: ~}.
  EXPECT_EQ(errorOf("? :"), "t.yaml: {~: ~}: a key must be a name, not a list or a mapping (line 1)");
  EXPECT_EQ(errorOf("[1]: 2"), "t.yaml: [1]: a key must be a name, not a list or a mapping (line 1)");
  EXPECT_EQ(errorOf("objects: []\n~: 1\n"), "t.yaml: <empty key>: a key must be a name, not empty (line 2)");
  EXPECT_EQ(errorOf("? - 1\n  - 2\n: 3\n"), "t.yaml: [1, 2]: a key must be a name, not a list or a mapping (line 1)");
  EXPECT_EQ(errorOf("objects: [{type: plane, position: [0, 0, 0], [1]: 2}]\n"),
            "t.yaml: objects[0] (plane): [1]: a key must be a name, not a list or a mapping (line 1)");
  EXPECT_EQ(errorOf("objects: [{type: plane, position: [0, 0, 0], texture: {type: noise, ? : }}]\n"),
            "t.yaml: objects[0] (plane): texture.{~: ~}: a key must be a name, not a list or a mapping (line 1)");

  // Through loadScene, as sl_render and the simulator read it: the message names the file.
  const std::string path = ::testing::TempDir() + "scene_list_key.yaml";
  {
    std::ofstream out(path);
    out << "[1]: 2";
  }
  try
  {
    loadScene(path);
    ADD_FAILURE() << "no error";
  }
  catch (const SceneFileError& e)
  {
    EXPECT_EQ(std::string(e.what()), path + ": [1]: a key must be a name, not a list or a mapping (line 1)");
  }
  std::remove(path.c_str());
}

TEST(SceneFile, MissingFileIsNamed)
{
  try
  {
    loadScene("/no/such/scene.yaml");
    FAIL() << "no error";
  }
  catch (const SceneFileError& e)
  {
    EXPECT_STREQ(e.what(), "/no/such/scene.yaml: cannot open the scene file");
  }
}

TEST(SceneFile, CheckerboardInnerCornersFollowTheDocumentedLayout)
{
  const Scene s = loadScene(kScenes + "/checkerboard_600.yaml");
  const SceneObject& board = s.objects[1];
  const std::vector<Eigen::Vector3d> corners = checkerboardInnerCorners(board);
  ASSERT_EQ(corners.size(), 8u * 6u);
  // Board 9 x 7 squares of 25 mm centred at (0.570, 0, 0.0865), facing -x: local x = world -y,
  // local y = world z. Inner corner (1, 1) is one square in from the local -x, -y corner.
  const Eigen::Vector3d first = corners.front();
  EXPECT_NEAR(first.x(), 0.570, 1e-12);
  EXPECT_NEAR(first.y(), -(-4.5 * 0.025 + 0.025), 1e-12);
  EXPECT_NEAR(first.z(), 0.0865 + (-3.5 * 0.025 + 0.025), 1e-12);
  // Row-major with i fastest: the next corner is one square along local x (world -y).
  EXPECT_NEAR((corners[1] - corners[0]).norm(), 0.025, 1e-12);
  EXPECT_NEAR(corners[1].y() - corners[0].y(), -0.025, 1e-12);
  EXPECT_NEAR(corners[8].z() - corners[0].z(), 0.025, 1e-12);
  EXPECT_THROW(checkerboardInnerCorners(s.objects[0]), std::invalid_argument);
}

TEST(Intersection, Plane)
{
  SceneObject wall;
  wall.type = ObjectType::Plane;
  wall.pose.linear() << 0, 0, -1, -1, 0, 0, 0, 1, 0;  // normal -x, local x = -y, local y = z
  wall.pose.translation() = Eigen::Vector3d(2.0, 0.0, 1.0);
  Hit h;
  ASSERT_TRUE(intersectObject(wall, ray({ 0, 0.3, 1.2 }, { 1, 0, 0 }), 0.0, 1e9, h));
  EXPECT_NEAR(h.t, 2.0, 1e-12);
  EXPECT_TRUE(h.point.isApprox(Eigen::Vector3d(2.0, 0.3, 1.2)));
  EXPECT_TRUE(h.normal.isApprox(Eigen::Vector3d(-1, 0, 0)));  // towards the ray's origin
  EXPECT_NEAR(h.uv.x(), -0.3, 1e-12);
  EXPECT_NEAR(h.uv.y(), 0.2, 1e-12);
  // From behind, the normal still faces the ray (planes are two-sided).
  ASSERT_TRUE(intersectObject(wall, ray({ 3, 0, 1 }, { -1, 0, 0 }), 0.0, 1e9, h));
  EXPECT_TRUE(h.normal.isApprox(Eigen::Vector3d(1, 0, 0)));
  // Parallel, pointing away, beyond t_max: misses.
  EXPECT_FALSE(intersectObject(wall, ray({ 0, 0, 0 }, { 0, 1, 0 }), 0.0, 1e9, h));
  EXPECT_FALSE(intersectObject(wall, ray({ 0, 0, 0 }, { -1, 0, 0 }), 0.0, 1e9, h));
  EXPECT_FALSE(intersectObject(wall, ray({ 0, 0, 0 }, { 1, 0, 0 }), 0.0, 1.5, h));
  // A bounded plane misses outside its rectangle.
  wall.size = Eigen::Vector3d(1.0, 0.5, 0.0);
  EXPECT_TRUE(intersectObject(wall, ray({ 0, 0.49, 1.2 }, { 1, 0, 0 }), 0.0, 1e9, h));
  EXPECT_FALSE(intersectObject(wall, ray({ 0, 0.51, 1.0 }, { 1, 0, 0 }), 0.0, 1e9, h));
  EXPECT_FALSE(intersectObject(wall, ray({ 0, 0.0, 1.26 }, { 1, 0, 0 }), 0.0, 1e9, h));
}

TEST(Intersection, BoxAtAnyOrientation)
{
  SceneObject box;
  box.type = ObjectType::Box;
  box.size = Eigen::Vector3d(1.0, 1.0, 1.0);
  box.pose.translation() = Eigen::Vector3d(5.0, 0.0, 0.0);
  box.pose.linear() = Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  // Turned 45 degrees about z the box is the diamond |x - 5| + |y| <= sqrt(2) / 2 (for |z| <= 0.5).
  Hit h;
  ASSERT_TRUE(intersectObject(box, ray({ 0, 0.1, 0.2 }, { 1, 0, 0 }), 0.0, 1e9, h));
  EXPECT_NEAR(h.t, 5.0 - (std::sqrt(0.5) - 0.1), 1e-12);
  EXPECT_TRUE(h.normal.isApprox(Eigen::Vector3d(-1, 1, 0).normalized(), 1e-12));
  ASSERT_TRUE(intersectObject(box, ray({ 0, -0.1, 0.2 }, { 1, 0, 0 }), 0.0, 1e9, h));
  EXPECT_TRUE(h.normal.isApprox(Eigen::Vector3d(-1, -1, 0).normalized(), 1e-12));
  // Top face from above, and a miss above it.
  ASSERT_TRUE(intersectObject(box, ray({ 5, 0, 3 }, { 0, 0, -1 }), 0.0, 1e9, h));
  EXPECT_NEAR(h.t, 2.5, 1e-12);
  EXPECT_TRUE(h.normal.isApprox(Eigen::Vector3d(0, 0, 1)));
  EXPECT_EQ(h.part, 4);
  EXPECT_FALSE(intersectObject(box, ray({ 0, 0, 0.51 }, { 1, 0, 0 }), 0.0, 1e9, h));
  EXPECT_FALSE(intersectObject(box, ray({ 0, 0.8, 0 }, { 1, 0, 0 }), 0.0, 1e9, h));
  // From inside: the way out.
  ASSERT_TRUE(intersectObject(box, ray({ 5, 0, 0 }, { 0, 0, 1 }), 0.0, 1e9, h));
  EXPECT_NEAR(h.t, 0.5, 1e-12);
  EXPECT_TRUE(h.normal.isApprox(Eigen::Vector3d(0, 0, 1)));
  // Tilted about two axes: check the hit lies on the surface (a local coordinate at +-half size).
  box.pose.linear() =
      (Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  for (double y = -0.6; y <= 0.6; y += 0.05)
  {
    if (!intersectObject(box, ray({ 0, y, 0.1 }, { 1, 0.05, 0 }), 0.0, 1e9, h))
      continue;
    const Eigen::Vector3d local = box.pose.inverse() * h.point;
    EXPECT_NEAR(local.cwiseAbs().maxCoeff(), 0.5, 1e-9) << y;
    EXPECT_LT(h.normal.dot(Eigen::Vector3d(1, 0.05, 0)), 0.0);
  }
}

TEST(Intersection, Cylinder)
{
  SceneObject leg;
  leg.type = ObjectType::Cylinder;
  leg.size = Eigen::Vector3d(0.1, 0.1, 1.0);  // radius 0.1, height 1
  leg.pose.translation() = Eigen::Vector3d(2.0, 0.0, 0.5);
  Hit h;
  ASSERT_TRUE(intersectObject(leg, ray({ 0, 0, 0.3 }, { 1, 0, 0 }), 0.0, 1e9, h));
  EXPECT_NEAR(h.t, 1.9, 1e-12);
  EXPECT_TRUE(h.normal.isApprox(Eigen::Vector3d(-1, 0, 0)));
  EXPECT_EQ(h.part, 0);
  // Off-centre: the side at x = 2 - sqrt(r^2 - y^2).
  ASSERT_TRUE(intersectObject(leg, ray({ 0, 0.06, 0.3 }, { 1, 0, 0 }), 0.0, 1e9, h));
  EXPECT_NEAR(h.point.x(), 2.0 - std::sqrt(0.01 - 0.0036), 1e-12);
  EXPECT_NEAR(h.normal.norm(), 1.0, 1e-12);
  // Caps.
  ASSERT_TRUE(intersectObject(leg, ray({ 2.05, 0, 3 }, { 0, 0, -1 }), 0.0, 1e9, h));
  EXPECT_NEAR(h.t, 2.0, 1e-12);
  EXPECT_EQ(h.part, 1);
  EXPECT_TRUE(h.normal.isApprox(Eigen::Vector3d(0, 0, 1)));
  ASSERT_TRUE(intersectObject(leg, ray({ 2.0, 0.05, -1 }, { 0, 0, 1 }), 0.0, 1e9, h));
  EXPECT_EQ(h.part, 2);
  // Misses: above, beside, behind.
  EXPECT_FALSE(intersectObject(leg, ray({ 0, 0, 1.01 }, { 1, 0, 0 }), 0.0, 1e9, h));
  EXPECT_FALSE(intersectObject(leg, ray({ 0, 0.11, 0.5 }, { 1, 0, 0 }), 0.0, 1e9, h));
  EXPECT_FALSE(intersectObject(leg, ray({ 0, 0, 0.5 }, { -1, 0, 0 }), 0.0, 1e9, h));
  // Lying along y (a cable): rpy roll = pi/2.
  leg.pose.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  leg.pose.translation() = Eigen::Vector3d(1.0, 0.0, 0.1);
  ASSERT_TRUE(intersectObject(leg, ray({ 1.0, 0.3, 2.0 }, { 0, 0, -1 }), 0.0, 1e9, h));
  EXPECT_NEAR(h.point.z(), 0.2, 1e-12);
  EXPECT_FALSE(intersectObject(leg, ray({ 1.0, 0.6, 2.0 }, { 0, 0, -1 }), 0.0, 1e9, h));
}

TEST(Intersection, SceneNearestHitAndMiss)
{
  const Scene s = parseScene(R"(
objects:
  - {type: plane, name: floor, position: [0, 0, 0], normal: [0, 0, 1], floor: true}
  - {type: plane, name: wall, position: [3, 0, 1], normal: [-1, 0, 0]}
  - {type: box, name: crate, position: [1.5, 0, 0.25], size: [0.5, 0.5, 0.5]}
  - {type: cylinder, name: leg, position: [2.5, 0, 0.5], radius: 0.05, height: 1.0}
)");
  Hit h;
  ASSERT_TRUE(intersectScene(s, ray({ 0, 0, 0.2 }, { 1, 0, 0 }), h));
  EXPECT_EQ(h.object, 2);
  EXPECT_NEAR(h.t, 1.25, 1e-12);
  ASSERT_TRUE(intersectScene(s, ray({ 0, 0, 0.7 }, { 1, 0, 0 }), h));  // over the crate: the leg
  EXPECT_EQ(h.object, 3);
  ASSERT_TRUE(intersectScene(s, ray({ 0, 0.3, 0.7 }, { 1, 0, 0 }), h));  // beside the leg: the wall
  EXPECT_EQ(h.object, 1);
  EXPECT_NEAR(h.t, 3.0, 1e-12);
  ASSERT_TRUE(intersectScene(s, ray({ 0, 1, 1 }, { 0, 0, -1 }), h));
  EXPECT_EQ(h.object, 0);
  EXPECT_FALSE(intersectScene(s, ray({ 0, 0, 0.7 }, { -1, 0, 0.1 }), h));
  EXPECT_FALSE(intersectScene(s, ray({ 0, 0, 0.2 }, { 1, 0, 0 }), h, 1e-9, 1.0));
}

}  // namespace sl_sim
