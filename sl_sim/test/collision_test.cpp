// Ground-truth collision of the simulated robot's disc with the scene: every object inside it in any
// direction, by name, and the exact clearance to the nearest one.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "sl_sim/collision.h"
#include "sl_sim/contact.h"
#include "sl_sim/scene.h"

namespace sl_sim
{
namespace
{
constexpr double kR = 0.1675;  // default footprint radius; heights 0.01 .. 0.10 m

Eigen::Isometry3d robotAt(double x, double y, double yaw)
{
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(x, y, 0.0);
  t.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return t;
}

Scene scene(const std::string& objects)
{
  return parseScene(
      "objects:\n"
      "  - {type: plane, name: floor, position: [0, 0, 0], normal: [0, 0, 1], floor: true}\n" +
          objects,
      "collision_test");
}

// Brute force: the smallest horizontal distance from the z axis over a dense grid of the object's
// points (local coordinates) between the default heights. Never below the exact value.
double sampledDistance(const SceneObject& o, int n = 160)
{
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j)
      for (int k = 0; k <= n; ++k)
      {
        Eigen::Vector3d l(2.0 * i / n - 1.0, 2.0 * j / n - 1.0, 2.0 * k / n - 1.0);
        if (o.type == ObjectType::Cylinder)
        {
          if (l.x() * l.x() + l.y() * l.y() > 1.0)
            continue;
          l = Eigen::Vector3d(l.x() * o.size.x(), l.y() * o.size.x(), l.z() * o.size.z() / 2);
        }
        else
          l = l.cwiseProduct(o.size / 2);
        const Eigen::Vector3d p = o.pose * l;
        if (p.z() >= 0.01 && p.z() <= 0.10)
          best = std::min(best, p.head<2>().norm());
      }
  return best;
}
}  // namespace

TEST(Collision, BoxBehindTheRobotCollidesWhereTheBumperCannotFeelIt)
{
  // A crate whose front face reaches 10 mm into the disc straight behind the robot.
  const Scene s = scene("  - {type: box, name: crate, position: [" + std::to_string(-(kR - 0.01 + 0.05)) +
                        ", 0, 0.05], size: [0.1, 0.1, 0.1]}\n");
  EXPECT_EQ(computeContact(s, robotAt(0, 0, 0)), 0) << "the bumper covers only the front";
  const CollisionReport r = computeCollision(s, robotAt(0, 0, 0));
  EXPECT_TRUE(r.colliding);
  ASSERT_EQ(r.names.size(), 1u);
  EXPECT_EQ(r.names[0], "crate");
  EXPECT_EQ(r.objects, std::vector<int>{ 1 });
  EXPECT_NEAR(r.min_clearance, -0.01, 1e-12);
  EXPECT_EQ(r.nearest_object, 1);
  EXPECT_EQ(r.nearest_name, "crate");
}

TEST(Collision, EveryDirectionAndHeadingCollides)
{
  // A 20 mm post whose surface reaches 5 mm into the disc, at any angle around any heading.
  for (const double yaw : { 0.0, 1.0, -2.0, 3.0 })
    for (const double angle : { 0.0, M_PI / 2, -M_PI / 2, 2.4, -2.6, M_PI })
    {
      const double d = kR - 0.005 + 0.01;
      const Scene s = scene("  - {type: cylinder, name: post, position: [" + std::to_string(2.0 + d * std::cos(angle)) +
                            ", " + std::to_string(1.0 + d * std::sin(angle)) + ", 0.2], radius: 0.01, height: 0.4}\n");
      const CollisionReport r = computeCollision(s, robotAt(2.0, 1.0, yaw));
      EXPECT_TRUE(r.colliding) << "angle " << angle << " yaw " << yaw;
      EXPECT_NEAR(r.min_clearance, -0.005, 1e-6) << "angle " << angle << " yaw " << yaw;
    }
}

TEST(Collision, WallOneCentimetreFromTheEdgeIsClearance)
{
  const std::string x = std::to_string(kR + 0.01);
  for (const std::string& wall :
       { "  - {type: plane, name: wall, position: [" + x + ", 0, 1], normal: [-1, 0, 0], size: [3, 2]}\n",
         "  - {type: plane, name: wall, position: [" + x + ", 0, 1], normal: [-1, 0, 0]}\n",
         "  - {type: box, name: wall, position: [" + std::to_string(kR + 0.01 + 0.05) +
             ", 0, 1], size: [0.1, 3, 2]}\n" })
  {
    const CollisionReport r = computeCollision(scene(wall), robotAt(0, 0, 0.3));
    EXPECT_FALSE(r.colliding) << wall;
    EXPECT_TRUE(r.names.empty());
    EXPECT_NEAR(r.min_clearance, 0.01, 1e-12) << wall;
    EXPECT_EQ(r.nearest_name, "wall");
  }
  // 11 mm further on, the robot's disc reaches 1 mm into it.
  const Scene s =
      scene("  - {type: plane, name: wall, position: [" + x + ", 0, 1], normal: [-1, 0, 0], size: [3, 2]}\n");
  const CollisionReport r = computeCollision(s, robotAt(0.011, 0, 0));
  EXPECT_TRUE(r.colliding);
  EXPECT_NEAR(r.min_clearance, -0.001, 1e-12);
}

TEST(Collision, AboveOrBelowTheHeightsNeverCollides)
{
  // Right over the robot: a table top above robot_height, a flat cable below contact_min_height.
  const Scene s = scene(
      "  - {type: box, name: table_top, position: [0, 0, 0.13], size: [0.8, 0.8, 0.04]}\n"
      "  - {type: box, name: cable, position: [0, 0, 0.004], size: [1.0, 0.01, 0.008]}\n"
      "  - {type: plane, name: shelf, position: [0, 0, 0.105], normal: [0, 0, 1]}\n");
  const CollisionReport r = computeCollision(s, robotAt(0, 0, 0));
  EXPECT_FALSE(r.colliding);
  EXPECT_TRUE(std::isinf(r.min_clearance)) << "nothing reaches into the heights";
  EXPECT_EQ(r.nearest_object, -1);
  EXPECT_EQ(r.nearest_name, "");
  // Lowered into the heights they collide, reaching the robot's axis.
  const Scene low = scene("  - {type: box, name: table_top, position: [0, 0, 0.11], size: [0.8, 0.8, 0.04]}\n");
  const CollisionReport rl = computeCollision(low, robotAt(0, 0, 0));
  EXPECT_TRUE(rl.colliding);
  EXPECT_NEAR(rl.min_clearance, -kR, 1e-12);
  // Other heights move the band.
  ContactSettings tall;
  tall.robot_height = 0.2;
  EXPECT_TRUE(computeCollision(s, robotAt(0, 0, 0), tall).colliding);
  ContactSettings ground;
  ground.contact_min_height = 0.0;
  EXPECT_TRUE(computeCollision(s, robotAt(0, 0, 0), ground).colliding);
}

TEST(Collision, FloorNeverCollides)
{
  const Scene s = scene("  - {type: box, name: mat, position: [0, 0, 0.02], size: [1, 1, 0.04], floor: true}\n");
  const CollisionReport r = computeCollision(s, robotAt(0, 0, 0));
  EXPECT_FALSE(r.colliding);
  EXPECT_TRUE(std::isinf(r.min_clearance));
}

TEST(Collision, NamesEveryObjectInside)
{
  const Scene s = scene(
      "  - {type: cylinder, name: leg_a, position: [0.1, 0.1, 0.2], radius: 0.01, height: 0.4}\n"
      "  - {type: box, position: [-0.1, 0, 0.05], size: [0.05, 0.05, 0.1]}\n"
      "  - {type: cylinder, name: far_bin, position: [2, 0, 0.2], radius: 0.15, height: 0.4}\n"
      "  - {type: plane, position: [0, -0.15, 0.5], normal: [0, 1, 0], size: [1, 1]}\n");
  const CollisionReport r = computeCollision(s, robotAt(0, 0, 0));
  EXPECT_TRUE(r.colliding);
  EXPECT_EQ(r.objects, (std::vector<int>{ 1, 2, 4 }));
  EXPECT_EQ(r.names, (std::vector<std::string>{ "leg_a", "box #2", "plane #4" }));
  // The box, 75 mm behind the axis, reaches deepest.
  EXPECT_EQ(r.nearest_name, "box #2");
  EXPECT_NEAR(r.min_clearance, 0.075 - kR, 1e-12);
  EXPECT_EQ(objectName(s, 3), "far_bin");
  // Buffers are reused: a second report into the same object is a fresh one.
  CollisionReport again = r;
  computeCollision(scene("  - {type: box, name: b, position: [3, 0, 0.05], size: [0.1, 0.1, 0.1]}\n"), robotAt(0, 0, 0),
                   ContactSettings(), again);
  EXPECT_FALSE(again.colliding);
  EXPECT_TRUE(again.objects.empty());
  EXPECT_TRUE(again.names.empty());
  EXPECT_EQ(again.nearest_name, "b");
  EXPECT_NEAR(again.min_clearance, 3 - 0.05 - kR, 1e-12);
}

TEST(Collision, UprightAndLyingCylindersAreExact)
{
  // Upright 20 mm leg 0.5 m away, diagonally.
  const Scene leg = scene("  - {type: cylinder, name: leg, position: [0.3, 0.4, 0.3], radius: 0.01, height: 0.6}\n");
  EXPECT_NEAR(computeCollision(leg, robotAt(0, 0, 0)).min_clearance, 0.5 - 0.01 - kR, 1e-12);
  // A pipe across the path (axis along y) whose centre is 30 mm above robot_height: its part below
  // 0.10 m is 2 * 40 mm wide.
  const Scene pipe = scene(
      "  - {type: cylinder, name: pipe, position: [0.5, 0, 0.13], rpy: [1.5707963267948966, 0, 0], radius: 0.05, "
      "height: 1.0}\n");
  EXPECT_NEAR(computeCollision(pipe, robotAt(0, 0, 0)).min_clearance, 0.5 - 0.04 - kR, 1e-9);
  // Lying on the floor, pointing at the robot: its end cap is nearest.
  const Scene log = scene(
      "  - {type: cylinder, name: log, position: [0.8, 0, 0.05], rpy: [0, 1.5707963267948966, 0], radius: 0.05, "
      "height: 0.6}\n");
  EXPECT_NEAR(computeCollision(log, robotAt(0, 0, 0)).min_clearance, 0.5 - kR, 1e-9);
  // Nearly lying (rpy rounded as in a scene file) agrees with lying.
  const Scene nearly = scene(
      "  - {type: cylinder, name: pipe, position: [0.5, 0, 0.13], rpy: [1.5708, 0, 0], radius: 0.05, height: 1.0}\n");
  EXPECT_NEAR(computeCollision(nearly, robotAt(0, 0, 0)).min_clearance, 0.5 - 0.04 - kR, 1e-5);
}

TEST(Collision, TiltedShapesMatchDenseSampling)
{
  const std::vector<std::string> objects = {
    "{type: cylinder, position: [0.35, -0.2, 0.08], rpy: [0.7, 0.4, 0.3], radius: 0.06, height: 0.3}",
    "{type: cylinder, position: [-0.3, 0.25, 0.12], rpy: [-1.2, 0.2, 2.0], radius: 0.03, height: 0.5}",
    "{type: cylinder, position: [0.1, 0.05, 0.2], rpy: [0.9, 0.0, 0.0], radius: 0.05, height: 0.5}",
    "{type: box, position: [0.35, 0.3, 0.1], rpy: [0.5, -0.6, 0.9], size: [0.2, 0.1, 0.15]}",
    "{type: box, position: [0.0, -0.1, 0.15], rpy: [0.3, 0.2, -0.4], size: [0.1, 0.1, 0.15]}",
    "{type: plane, position: [-0.4, 0.1, 0.1], rpy: [1.1, 0.5, 0.2], size: [0.3, 0.2]}",
  };
  for (const std::string& object : objects)
  {
    const Scene s = scene("  - " + object + "\n");
    const SceneObject& o = s.objects[1];
    const double exact = horizontalDistance(o, o.pose, 0.01, 0.10);
    const double sampled = sampledDistance(o);
    // The grid's points lie inside: never nearer than the truth; within its spacing of it.
    EXPECT_LE(exact, sampled + 1e-12) << object;
    EXPECT_NEAR(exact, sampled, 0.002) << object;
    EXPECT_NEAR(computeCollision(s, robotAt(0, 0, 0)).min_clearance, exact - kR, 1e-12) << object;
  }
}

TEST(Collision, SlopedInfinitePlaneIsAStrip)
{
  // A ramp x = 1 + z: between 0.01 and 0.10 m high it is nearest at x = 1.01.
  const Scene s = scene("  - {type: plane, name: ramp, position: [1, 0, 0], normal: [-1, 0, 1]}\n");
  EXPECT_NEAR(computeCollision(s, robotAt(0, 0, 0)).min_clearance, 1.01 - kR, 1e-12);
  // Standing on it (in the strip): inside.
  EXPECT_NEAR(computeCollision(s, robotAt(1.05, 0, 0)).min_clearance, -kR, 1e-12);
}

TEST(Collision, InvalidSettingsNameTheField)
{
  ContactSettings bad;
  bad.robot_radius = -1.0;
  try
  {
    computeCollision(scene(""), robotAt(0, 0, 0), bad);
    FAIL() << "no exception";
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_EQ(std::string(e.what()).rfind("robot_radius", 0), 0u) << e.what();
  }
}

}  // namespace sl_sim
