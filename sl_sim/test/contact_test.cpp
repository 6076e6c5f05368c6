// Bumper contact of the simulated robot with the scene.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "sl_sim/contact.h"
#include "sl_sim/scene.h"

namespace sl_sim
{
namespace
{
constexpr double kR = 0.1675;  // default footprint radius

Eigen::Isometry3d robotAt(double x, double y, double yaw)
{
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(x, y, 0.0);
  t.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return t;
}

// A 10 cm cube standing on the floor whose nearest face is `gap` beyond the footprint at `angle`
// (rad, 0 ahead, positive left) from a robot at the origin heading +x.
Scene cubeAt(double angle, double gap, double height = 0.1, double bottom = 0.0)
{
  const double d = kR + gap + 0.05;
  SceneObject floor;
  floor.type = ObjectType::Plane;
  floor.floor = true;
  SceneObject cube;
  cube.type = ObjectType::Box;
  cube.size = Eigen::Vector3d(0.1, 0.1, height);
  cube.pose.linear() = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  cube.pose.translation() = Eigen::Vector3d(d * std::cos(angle), d * std::sin(angle), bottom + height / 2);
  Scene s;
  s.objects = { floor, cube };
  return s;
}
}  // namespace

TEST(Contact, NothingNearMeansNoBump)
{
  EXPECT_EQ(computeContact(cubeAt(0.0, 0.01), robotAt(0, 0, 0)), 0);
  EXPECT_EQ(computeContact(cubeAt(0.0, 1.0), robotAt(0, 0, 0)), 0);
}

TEST(Contact, StraightAheadPressesBothBumpers)
{
  std::vector<ContactPoint> points;
  EXPECT_EQ(computeContact(cubeAt(0.0, -0.005), robotAt(0, 0, 0), ContactSettings(), &points), kBumpLeft | kBumpRight);
  ASSERT_FALSE(points.empty());
  for (const ContactPoint& p : points)
  {
    EXPECT_LE(std::abs(p.angle), 0.35);
    EXPECT_LE(p.distance, kR + 1e-9);
    EXPECT_EQ(p.object, 1);
  }
  // Within +-20 degrees both, beyond one side.
  EXPECT_EQ(computeContact(cubeAt(0.30, -0.003), robotAt(0, 0, 0)), kBumpLeft | kBumpRight);
  // (A face 1 mm inside the footprint touches it over +-6 degrees around its direction.)
  EXPECT_EQ(computeContact(cubeAt(0.5, -0.001), robotAt(0, 0, 0)), kBumpLeft);
  EXPECT_EQ(computeContact(cubeAt(-0.5, -0.001), robotAt(0, 0, 0)), kBumpRight);
  EXPECT_EQ(computeContact(cubeAt(1.2, -0.003), robotAt(0, 0, 0)), kBumpLeft);
  EXPECT_EQ(computeContact(cubeAt(-1.2, -0.003), robotAt(0, 0, 0)), kBumpRight);
}

TEST(Contact, BehindTheBumperIsNotSensed)
{
  EXPECT_EQ(computeContact(cubeAt(M_PI, -0.01), robotAt(0, 0, 0)), 0);
  EXPECT_EQ(computeContact(cubeAt(-2.5, -0.01), robotAt(0, 0, 0)), 0);
}

TEST(Contact, SidesFollowTheRobotsHeading)
{
  // The cube is ahead-left of the world x axis; turned left by 90 degrees it is ahead-right.
  const Scene s = cubeAt(0.6, -0.004);
  EXPECT_EQ(computeContact(s, robotAt(0, 0, 0)), kBumpLeft);
  EXPECT_EQ(computeContact(s, robotAt(0, 0, M_PI / 2)), kBumpRight);
  EXPECT_EQ(computeContact(s, robotAt(0, 0, 0.6)), kBumpLeft | kBumpRight);
  // Moved away from it: nothing.
  EXPECT_EQ(computeContact(s, robotAt(-0.1, 0, 0.6)), 0);
}

TEST(Contact, LowAndHighObjectsAndTheFloorDoNotTouch)
{
  // A flat cable (8 mm) is driven over; a 2 cm step is not.
  EXPECT_EQ(computeContact(cubeAt(0.0, -0.05, 0.008), robotAt(0, 0, 0)), 0);
  EXPECT_EQ(computeContact(cubeAt(0.0, -0.05, 0.02), robotAt(0, 0, 0)), kBumpLeft | kBumpRight);
  // A table top at 70 cm passes over the robot.
  EXPECT_EQ(computeContact(cubeAt(0.0, -0.05, 0.03, 0.70), robotAt(0, 0, 0)), 0);
  // An object hanging down to 8 cm touches the 10 cm high robot.
  EXPECT_EQ(computeContact(cubeAt(0.0, -0.05, 0.3, 0.08), robotAt(0, 0, 0)), kBumpLeft | kBumpRight);
  // A tilted "floor" object is never a contact, the same plane not marked as floor is.
  Scene s = loadScene(SL_SIM_SCENES_DIR "/plane_700.yaml");
  s.objects[1].pose.translation().x() = kR - 0.01;
  EXPECT_EQ(computeContact(s, robotAt(0, 0, 0)), kBumpLeft | kBumpRight);
  s.objects[1].floor = true;
  EXPECT_EQ(computeContact(s, robotAt(0, 0, 0)), 0);
}

TEST(Contact, ThinLegAndInsideSolid)
{
  Scene s = parseScene(R"(
objects:
  - {type: plane, position: [0, 0, 0], normal: [0, 0, 1], floor: true}
  - {type: cylinder, name: leg, position: [0.16, 0.02, 0.36], radius: 0.006, height: 0.72}
)");
  EXPECT_EQ(computeContact(s, robotAt(0, 0, 0)), kBumpLeft | kBumpRight);
  EXPECT_EQ(computeContact(s, robotAt(-0.02, 0, 0)), 0);
  // A robot whose axis is inside a solid (spawned in a box) is in contact.
  const Scene box = parseScene("objects: [{type: box, position: [0, 0, 0.1], size: [1, 1, 0.2]}]\n");
  EXPECT_EQ(computeContact(box, robotAt(0, 0, 0)), kBumpLeft | kBumpRight);
}

TEST(Contact, SettingsAreValidated)
{
  ContactSettings c;
  EXPECT_NO_THROW(c.validate());
  c.robot_radius = 0.0;
  EXPECT_THROW(c.validate(), std::invalid_argument);
  c = ContactSettings();
  c.robot_height = 0.005;
  try
  {
    c.validate();
    FAIL();
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_EQ(std::string(e.what()).rfind("robot_height:", 0), 0u);
  }
  // A larger radius reaches a cube the default one does not.
  c = ContactSettings();
  c.robot_radius = kR + 0.02;
  EXPECT_EQ(computeContact(cubeAt(0.0, 0.01), robotAt(0, 0, 0), c), kBumpLeft | kBumpRight);
}

}  // namespace sl_sim
