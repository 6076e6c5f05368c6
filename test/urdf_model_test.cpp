// sl_bringup_test: the robot description generated from a rig file (scripts/bringup_make_urdf.py,
// urdf/create.urdf.in) is a valid URDF whose camera mount and projector pose are exactly the rig
// file's, and invalid rig files (unknown keys too) are refused with the key named. No ROS master needed.
#include <array>
#include <cmath>
#include <fstream>
#include <memory>
#include <string>

#include <gtest/gtest.h>
#include <ros/package.h>
#include <sl_testing/process.h>
#include <urdf/model.h>
#include <yaml-cpp/yaml.h>

namespace
{

struct GeneratorRun
{
  int status = -1;
  std::string out;  // stdout
  std::string err;  // stderr
};

std::string readFile(const std::string& path)
{
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// Runs the generator on @p rig_file.
GeneratorRun generate(const std::string& rig_file)
{
  const std::string err_file = testing::TempDir() + "/bringup_make_urdf.err";
  const std::string command =
      "/usr/bin/python3 " SL_BRINGUP_SCRIPTS_DIR "/bringup_make_urdf.py '" + rig_file + "' 2> '" + err_file + "'";
  GeneratorRun run;
  run.status = sl_testing::runShell(command, run.out);
  run.err = readFile(err_file);
  return run;
}

std::string writeRig(const std::string& name, const std::string& text)
{
  const std::string path = testing::TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

/// Row-major rotation matrix of a URDF rotation.
std::array<double, 9> matrixOf(const urdf::Rotation& r)
{
  const double x = r.x, y = r.y, z = r.z, w = r.w;
  return { 1 - 2 * (y * y + z * z), 2 * (x * y - z * w),     2 * (x * z + y * w),
           2 * (x * y + z * w),     1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
           2 * (x * z - y * w),     2 * (y * z + x * w),     1 - 2 * (x * x + y * y) };
}

/// Row-major R = Rz(yaw) Ry(pitch) Rx(roll).
std::array<double, 9> matrixOfRpy(double roll, double pitch, double yaw)
{
  urdf::Rotation r;
  r.setFromRPY(roll, pitch, yaw);
  return matrixOf(r);
}

std::string rigText(const std::string& parent, const std::array<double, 3>& xyz, const std::array<double, 3>& rpy,
                    const std::array<double, 9>& rotation, const std::array<double, 3>& translation)
{
  char text[1024];
  std::snprintf(text, sizeof(text),
                "format_version: 1\n"
                "projector_pose:\n"
                "  rotation: [%.12g, %.12g, %.12g, %.12g, %.12g, %.12g, %.12g, %.12g, %.12g]\n"
                "  translation: [%.12g, %.12g, %.12g]\n"
                "mount:\n"
                "  parent_frame: %s\n"
                "  xyz: [%.12g, %.12g, %.12g]\n"
                "  rpy: [%.12g, %.12g, %.12g]\n",
                rotation[0], rotation[1], rotation[2], rotation[3], rotation[4], rotation[5], rotation[6], rotation[7],
                rotation[8], translation[0], translation[1], translation[2], parent.c_str(), xyz[0], xyz[1], xyz[2],
                rpy[0], rpy[1], rpy[2]);
  return text;
}

void expectPose(const urdf::Model& model, const std::string& joint, const std::string& parent,
                const std::array<double, 3>& xyz, const std::array<double, 9>& rotation)
{
  const urdf::JointConstSharedPtr j = model.getJoint(joint);
  ASSERT_TRUE(j) << "no joint " << joint;
  EXPECT_EQ(j->type, urdf::Joint::FIXED) << joint;
  EXPECT_EQ(j->parent_link_name, parent) << joint;
  const urdf::Pose& p = j->parent_to_joint_origin_transform;
  EXPECT_NEAR(p.position.x, xyz[0], 1e-9) << joint;
  EXPECT_NEAR(p.position.y, xyz[1], 1e-9) << joint;
  EXPECT_NEAR(p.position.z, xyz[2], 1e-9) << joint;
  const std::array<double, 9> m = matrixOf(p.rotation);
  for (int i = 0; i < 9; ++i)
    EXPECT_NEAR(m[i], rotation[i], 1e-7) << joint << " rotation element " << i;
}

TEST(RobotModel, DefaultRigGivesTheMountAndProjectorPose)
{
  const std::string rig_file = ros::package::getPath("sl_projector") + "/config/default_rig.yaml";
  const GeneratorRun run = generate(rig_file);
  ASSERT_EQ(run.status, 0) << run.err;
  urdf::Model model;
  ASSERT_TRUE(model.initString(run.out)) << "not a valid URDF";
  EXPECT_EQ(model.getRoot()->name, "base_link");
  for (const char* link : { "base_link", "platform_edge", "sensor_mast_link", "camera_link", "camera_optical_frame",
                            "projector_optical_frame", "left_wheel_link", "right_wheel_link", "caster_link" })
    EXPECT_TRUE(model.getLink(link)) << "no link " << link;

  const YAML::Node rig = YAML::LoadFile(rig_file);
  expectPose(model, "platform_edge_joint", "base_link", { 0.1675, 0.0, 0.0 }, matrixOfRpy(0, 0, 0));
  const YAML::Node mount = rig["mount"];
  expectPose(model, "camera_joint", mount["parent_frame"].as<std::string>(),
             { mount["xyz"][0].as<double>(), mount["xyz"][1].as<double>(), mount["xyz"][2].as<double>() },
             matrixOfRpy(mount["rpy"][0].as<double>(), mount["rpy"][1].as<double>(), mount["rpy"][2].as<double>()));
  expectPose(model, "camera_optical_joint", "camera_link", { 0, 0, 0 }, matrixOfRpy(-M_PI / 2, 0, -M_PI / 2));
  const YAML::Node pose = rig["projector_pose"];
  std::array<double, 9> rotation;
  for (int i = 0; i < 9; ++i)
    rotation[i] = pose["rotation"][i].as<double>();
  expectPose(
      model, "projector_joint", "camera_optical_frame",
      { pose["translation"][0].as<double>(), pose["translation"][1].as<double>(), pose["translation"][2].as<double>() },
      rotation);
}

TEST(RobotModel, AnyRotationRoundTrips)
{
  // General rotations, and pitch at +-90 degrees (gimbal lock: roll and yaw are not unique there).
  const std::array<std::array<double, 3>, 5> cases = {
    { { 0.3, -0.4, 1.2 }, { -2.9, 0.1, -3.0 }, { 0.0, M_PI / 2, 0.7 }, { 0.5, -M_PI / 2, 0.0 }, { 0.0, 0.0, 0.0 } }
  };
  int k = 0;
  for (const auto& rpy : cases)
  {
    const std::array<double, 9> rotation = matrixOfRpy(rpy[0], rpy[1], rpy[2]);
    const std::string file =
        writeRig("rot" + std::to_string(k++) + ".yaml",
                 rigText("base_link", { 0.1, -0.02, 0.3 }, { 0.01, -0.2, 0.3 }, rotation, { -0.05, 0.01, 0.002 }));
    const GeneratorRun run = generate(file);
    ASSERT_EQ(run.status, 0) << run.err;
    urdf::Model model;
    ASSERT_TRUE(model.initString(run.out));
    expectPose(model, "projector_joint", "camera_optical_frame", { -0.05, 0.01, 0.002 }, rotation);
    expectPose(model, "camera_joint", "base_link", { 0.1, -0.02, 0.3 }, matrixOfRpy(0.01, -0.2, 0.3));
  }
}

TEST(RobotModel, InvalidRigFilesAreRefusedNamingTheKey)
{
  const std::array<double, 9> identity = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
  struct Case
  {
    std::string text, expected;
  };
  const Case cases[] = {
    { "format_version: 1\nprojector_pose: {rotation: [1,0,0,0,1,0,0,0,1], translation: [0.05,0,0]}\n",
      "mount: missing" },
    { rigText("camera_mast", { 0, 0, 0.1 }, { 0, 0, 0 }, identity, { 0.05, 0, 0 }), "mount.parent_frame" },
    { rigText("platform_edge", { 0, 0, 0.1 }, { 0, 0, 0 }, { 1, 0, 0, 0, 1, 0, 0, 0.5, 1 }, { 0.05, 0, 0 }),
      "projector_pose.rotation: is not orthonormal" },
    { rigText("platform_edge", { 0, 0, 0.1 }, { 0, 0, 0 }, { 1, 0, 0, 0, 1, 0, 0, 0, -1 }, { 0.05, 0, 0 }),
      "projector_pose.rotation: has determinant -1" },
    { rigText("platform_edge", { 0, 0, 0.1 }, { 0, 0, 0 }, identity, { 55.2, -4, 11.6 }),
      "projector_pose.translation" },
    { "format_version: 1\nmount: {xyz: [0, 0], rpy: [0, 0, 0]}\nprojector_pose: {rotation: [1,0,0,0,1,0,0,0,1], "
      "translation: [0.05,0,0]}\n",
      "mount.xyz: expected a list of 3 numbers" },
    { "format_version: 1\nmount: {xyz: [0, 0, .nan], rpy: [0, 0, 0]}\n", "mount.xyz" },
    { "mount: [unclosed\n", "bringup_make_urdf" },
    // Keys the rig reader (sl_rig) does not know, at each level, as it refuses them.
    { rigText("platform_edge", { 0, 0, 0.1 }, { 0, 0, 0 }, identity, { 0.05, 0, 0 }) + "mount_offset: 0.1\n",
      "mount_offset: unknown key (allowed: camera, depth_tables, format_version, mount, "
      "pattern, projector, projector_pose)" },
    { "format_version: 1\nmount: {xyz: [0, 0, 0.1], rpy: [0, 0, 0], parnet_frame: base_link}\n",
      "mount.parnet_frame: unknown key, did you mean 'parent_frame'?" },
    { "format_version: 1\npattern: {rosw: 3}\n", "pattern.rosw: unknown key, did you mean 'rows'?" },
    { "format_version: 1\ncamera: {width: 752, skew: 0}\n",
      "camera.skew: unknown key (allowed: D, K, f_number, focus_distance, height, pixel_pitch, width)" },
    { "format_version: 1\ndepth_tables: {rational: {a: [], b: [], d: [], rms: []}}\n",
      "depth_tables.rational.d: unknown key (allowed: a, b, c, rms)" },  // a, b and c tie: no hint
    { "format_version: 1\nprojector_pose: [1, 2]\n", "projector_pose: must be a mapping" },
  };
  int k = 0;
  for (const Case& c : cases)
  {
    const std::string file = writeRig("bad" + std::to_string(k++) + ".yaml", c.text);
    const GeneratorRun run = generate(file);
    EXPECT_EQ(run.status, 1) << c.text;
    EXPECT_TRUE(run.out.empty()) << c.text;
    EXPECT_NE(run.err.find(file), std::string::npos) << "the message does not name the file: " << run.err;
    EXPECT_NE(run.err.find(c.expected), std::string::npos) << "expected '" << c.expected << "' in: " << run.err;
  }
  const GeneratorRun missing = generate(testing::TempDir() + "/no_such_rig.yaml");
  EXPECT_EQ(missing.status, 1);
  EXPECT_NE(missing.err.find("no_such_rig.yaml"), std::string::npos) << missing.err;
}

}  // namespace
